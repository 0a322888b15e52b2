//! The adversarial suites: the built binary under a wall-time budget on generated command lines,
//! files, robots, settings and self-contact — no panic, no hang, no non-finite number, every
//! failure named.
//!
//! One test crate per concept, one module per topic: `cargo test --release --test adversarial <module>::`.

#[path = "../common/mod.rs"]
mod common;

mod adversarial_actuation_files;
mod adversarial_cli;
mod adversarial_counts;
mod adversarial_files;
mod adversarial_floats;
mod adversarial_lies;
mod adversarial_outputs;
mod adversarial_plan_files;
mod adversarial_robots;
mod adversarial_self_contact;
mod adversarial_settings;
