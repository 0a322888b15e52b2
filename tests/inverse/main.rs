//! The inverse problems: reach (least-effort actuation to a tip) and plan (collision-free paths,
//! roadmaps).
//!
//! One test crate per concept, one module per topic: `cargo test --release --test inverse <module>::`.

#[path = "../common/mod.rs"]
mod common;

mod airway_plan;
mod insertion_column;
mod plan;
mod plan_port;
mod plan_tension;
mod reach;
mod reach_body;
mod reach_port;
mod reach_random;
mod reach_tension;
mod roadmap_shards;
