//! The paper's case-1 robot pressing against a wall (`models/scenes/wall.toml`): solve with the
//! obstacle-aware geometric method in `--steps`-style continuation and with the energy model,
//! print the contacts, and draw shape, wall and contact points to
//! `target/obstacle_wall{,_energy}.{png,svg}` (or OUT_DIR).
//!
//! `cargo run --release --example obstacle_wall [OUT_DIR]`

mod common;

fn main() -> anyhow::Result<()> {
    // Four steps: each warm start is close enough that no Newton step jumps through the wall.
    common::run("wall", "obstacle_wall", "wall", 4)
}
