//! The methods, one at a time: the paper's geometric solver, the energy model, the Cosserat rod,
//! compliance, stiffening and friction, the method registry and its settings, typed inputs, the
//! entry port, soft rods (cables inside the rod, tubes, no spacer disks) and the cable report.
//!
//! One test crate per concept, one module per topic: `cargo test --release --test methods <module>::`.

#[path = "../common/mod.rs"]
mod common;

mod adaptive;
mod auto;
mod cable_report;
mod compliance;
mod cosserat;
mod cosserat_compliance;
mod cosserat_loaded;
mod cosserat_refs;
mod cosserat_stability;
mod cosserat_unloaded;
mod energy;
mod energy_sensitivity;
mod energy_warm;
mod estimate;
mod friction;
mod geometric;
mod geometric_feasibility;
mod geometric_many_cables;
mod geometric_random;
mod geometric_tips;
mod port;
mod port_sweep;
mod registry;
mod registry_ranges;
mod rod_body;
mod shear;
mod stiffening;
mod typed_inputs;
mod unique;
