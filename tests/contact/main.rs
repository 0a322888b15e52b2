//! Obstacles and contact: scene obstacles of every kind, dense random scenes, and each method's
//! contact steps.
//!
//! One test crate per concept, one module per topic: `cargo test --release --test contact <module>::`.

#[path = "../common/mod.rs"]
mod common;

mod airway;
mod concave_lumen;
mod dense_scenes;
mod energy_contact_convergence;
mod field_cache;
mod generated_scenes;
mod geometric_contact;
mod obstacles;
mod rod_contact;
mod rod_warm;
mod shear_contact;
mod solid_mesh;
