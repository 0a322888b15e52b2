//! Real robots: hardware data, prediction, friction, round-off and the calibration's choice of a
//! parameter set on train only.
//!
//! One test crate per concept, one module per topic: `cargo test --release --test hardware <module>::`.

#[path = "../common/mod.rs"]
mod common;

mod calibrate_default;
mod hardware;
mod hardware_friction;
mod hardware_roundoff;
mod hardware_select;
