//! Deploy through a port: a robot that starts 60 mm out of its port, a block on the port axis
//! in front of it, and a target behind the block (`models/port/behind_block.toml`). `reach`
//! finds the least-effort insertion, rotation and cable shortenings that put the tip on the
//! target keeping 1 mm clear of the block, and the example prints what it did.
//!
//! `cargo run --release --example port_reach`

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::reach::{reach, ReachOptions, Space, Target};
use ccrkit::Model;

fn main() -> anyhow::Result<()> {
    let root = env!("CARGO_MANIFEST_DIR");
    let model = Model::from_file(format!("{root}/models/port/behind_block.toml"))?;
    let req = SolveRequest::new(MethodKind::Energy);
    let space = Space::new(&model, &req, false)?;
    // The target: behind the block (farther out along the port axis than its far face), off
    // to one side, where a robot inserted 160 mm, turned by 2 rad and bent by cable A ends.
    let made = space.solve(&[0.007, 0.0, 0.16, 2.0], None)?;
    let tip = made.tip();
    let far_face = 0.118 + 0.008;
    println!(
        "target [{:.2}, {:.2}, {:.2}] mm: {:.1} mm beyond the block's far face",
        tip.x * 1e3,
        tip.y * 1e3,
        tip.z * 1e3,
        (tip.z - far_face) * 1e3
    );
    // Straight in, the robot runs into the block.
    let straight = space.solve(&[0.0, 0.0, 0.16, 0.0], None)?;
    if let Some(c) = space.clearance(&straight) {
        println!(
            "inserted straight to 160 mm: {} is {:.1} mm from `{}` (into it)",
            c.feature,
            c.distance * 1e3,
            c.obstacle
        );
    }
    let start = space.solve(&ccrkit::plan::actuation_of(&model, &model.actuation), None)?;
    println!(
        "start: insertion {:.1} mm, rotation 0 rad, cables slack; tip at {:.1} mm from the target",
        model.actuation.insertion.unwrap_or(0.0) * 1e3,
        (start.tip() - tip).norm() * 1e3
    );
    let t0 = std::time::Instant::now();
    let r = reach(
        &model,
        &req,
        &Target { tip, tangent: None },
        &ReachOptions::default(),
    )?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let r = r.require_reached()?;
    println!(
        "reached in {ms:.0} ms ({} solves): tip error {:.1e} m, clearance {:.2} mm",
        r.solves,
        r.tip_error_m,
        r.min_clearance_m.unwrap_or(f64::INFINITY) * 1e3
    );
    println!(
        "  inserted {:.2} mm (from {:.0} mm), turned {:.3} rad ({:.1}°)",
        r.insertion.unwrap_or(f64::NAN) * 1e3,
        model.actuation.insertion.unwrap_or(0.0) * 1e3,
        r.rotation.unwrap_or(f64::NAN),
        r.rotation.unwrap_or(f64::NAN).to_degrees()
    );
    for c in &r.actuation {
        println!(
            "  cable {}: shortened {:.3} mm{}",
            c.cable,
            c.shorten * 1e3,
            c.tension
                .map(|t| format!(", tension {t:.2} N"))
                .unwrap_or_default()
        );
    }
    println!(
        "  effort {:.3e} m² (Σ u² + scaled insertion and rotation)",
        r.effort_m2
    );
    Ok(())
}
