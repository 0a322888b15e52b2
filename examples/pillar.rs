//! The paper's case-1 robot pressing against a horizontal pillar (`models/scenes/pillar.toml`),
//! wrapping against it: solve with the obstacle-aware geometric method in `--steps`-style
//! continuation and with the energy model, print the contacts, and draw shape, pillar and
//! contact points to `target/pillar{,_energy}.{png,svg}` (or OUT_DIR).
//!
//! `cargo run --release --example pillar [OUT_DIR]`

mod common;

fn main() -> anyhow::Result<()> {
    // Four steps: each warm start is close enough that no Newton step jumps through the pillar.
    common::run("pillar", "pillar", "pillar", 4)
}
