//! Plan in a generated airway: a seeded airway tree (`ccrkit::anatomy`, 4 generations, about
//! 75 000 triangles) as a lumen, the two-segment catheter of
//! `models/anatomy/airway_catheter.toml` (3 mm wide) coming out of a bronchoscope parked
//! 25 mm above the carina (the port), a target two generations below the trachea (one when
//! no draw reaches two; `examples/common/airway_tasks.rs`: the tip of a clear forward solve); `reach` finds the
//! least-effort insertion, rotation and cable shortenings to it, `plan` a path there from the
//! retracted catheter (cables at rest, shallowest insertion). Every waypoint is then checked
//! by the independent dense check against the exact triangles (`dense_clearance`).
//!
//! `cargo run --release --example airway [OUT_DIR] [SEED]` (default `target/airway`, seed 1)
//! writes `airway.stl`, `scene.toml`, `plan.json` and `airway.html` (the airway
//! semi-transparent, the catheter inserting, turning and bending along the plan: a slider and
//! a play button).

#[path = "common/airway_tasks.rs"]
mod airway_tasks;

use airway_tasks::{plan_dense_clearance, Setup, GENERATIONS};
use anyhow::{bail, Result};
use ccrkit::anatomy::tasks::branch_of;
use ccrkit::export::view::View;
use ccrkit::plan::{plan, Goal, PlanOptions};
use ccrkit::reach::{reach_in, ReachOptions, Target};
use ccrkit::Shape;
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "target/airway".into()));
    let seed: u64 = args.next().map_or(Ok(1), |s| s.parse())?;
    let t0 = Instant::now();
    let setup = Setup::new(seed, GENERATIONS, &out)?;
    println!(
        "airway seed {seed}: {} branches, {} triangles ({:.2} s)",
        setup.airway.branches.len(),
        setup.airway.triangles.len(),
        t0.elapsed().as_secs_f64()
    );
    let space = setup.space()?;
    // A target two generations below the trachea (the first clear forward solve there among
    // 3000 draws), else one generation below.
    let t1 = Instant::now();
    let mut tasks = setup.tasks(&space, seed, 1, 2, 3000);
    if tasks.is_empty() {
        tasks = setup.tasks(&space, seed, 1, 1, 400);
    }
    let Some(task) = tasks.first() else {
        bail!("no clear forward solve beyond the trachea among 3400 draws");
    };
    println!(
        "target: generation {} ({:.2} s of forward draws, the signed-distance grid built on the first)",
        task.generation,
        t1.elapsed().as_secs_f64()
    );
    let t2 = Instant::now();
    let target = Target {
        tip: task.tip,
        tangent: None,
    };
    let answer = reach_in(&space, &setup.model, &target, &ReachOptions::default())?;
    let answer = answer.require_reached()?;
    println!(
        "reach: tip error {:.1e} m, insertion {:.1} mm, rotation {:.2} rad, clearance {:.2} mm, {} solves, {:.2} s",
        answer.tip_error_m,
        answer.insertion.unwrap_or(f64::NAN) * 1e3,
        answer.rotation.unwrap_or(f64::NAN),
        answer.min_clearance_m.unwrap_or(f64::INFINITY) * 1e3,
        answer.solves,
        t2.elapsed().as_secs_f64()
    );
    let start = setup.retracted(&space);
    let p = plan(
        &setup.model,
        &setup.request,
        Some(start),
        &Goal::Actuation(answer.u.clone()),
        &PlanOptions::default(),
        None,
    )?;
    println!(
        "plan (cold, from the retracted catheter): {} waypoints, {:.2} s, {} samples, {} solves; clearance {:.2} mm measured, {:.2} mm certified",
        p.waypoints.len(),
        p.stats.time_s,
        p.stats.samples,
        p.stats.checks.solves,
        p.min_clearance_m * 1e3,
        p.certified_clearance_m * 1e3
    );
    let t3 = Instant::now();
    let dense = plan_dense_clearance(&setup, &p);
    let last = &p.waypoints[p.waypoints.len() - 1].shape;
    let branch = branch_of(&setup.airway, &last.tip()).map(|b| setup.airway.branches[b].generation);
    println!(
        "dense check of every waypoint against the exact triangles: smallest clearance {:.3} mm ({:.2} s); the tip ends in generation {}",
        dense * 1e3,
        t3.elapsed().as_secs_f64(),
        branch.map_or("none".into(), |g| g.to_string())
    );
    ccrkit::output::write_file(
        out.join("plan.json"),
        serde_json::to_string_pretty(&p.to_json())?,
    )?;
    let scene = setup.request.scene_for(&setup.model);
    let mut view = View::new(
        "airway: insert, turn and bend to a target",
        &setup.model.robot,
        &scene,
    );
    let shapes: Vec<Shape> = p.waypoints.iter().map(|w| w.shape.clone()).collect();
    view.add_path("plan", &shapes)?;
    view.write(&out.join("airway.html"))?;
    println!(
        "wrote {}/{{airway.stl, scene.toml, plan.json, airway.html}} ({:.1} s in all, {:.1} s of the main thread's CPU)",
        out.display(),
        t0.elapsed().as_secs_f64(),
        airway_tasks::cpu_seconds(t0)
    );
    if dense < 0.0 {
        bail!("a waypoint is not clear of the wall by the dense check");
    }
    Ok(())
}
