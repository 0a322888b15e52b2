//! What goes in and out through files: scene and shape JSON, bad input files, the CLI's outputs,
//! URDF/SRDF exports (checked by yourdfpy and MuJoCo when installed), the HTML view, the export
//! example and the baseline scripts.
//!
//! One test crate per concept, one module per topic: `cargo test --release --test files <module>::`.

#[path = "../common/mod.rs"]
mod common;

mod bad_input;
mod baseline_cmp;
mod cli_outputs;
mod example_export_urdf;
mod scene_json;
mod shape_json;
mod urdf;
mod urdf_mujoco;
mod urdf_replay;
mod view;
mod xml_names;
