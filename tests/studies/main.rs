//! The studies: compare, speed–accuracy, stability and workspace.
//!
//! One test crate per concept, one module per topic: `cargo test --release --test studies <module>::`.

#[path = "../common/mod.rs"]
mod common;

mod auto;
mod study;
