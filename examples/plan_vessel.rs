//! A two-segment tendon robot (FTDCR v4 layout, `models/plan/two_segment.toml`) inside the
//! bent tube of `models/meshes/vessel.obj` (`models/plan/vessel.toml`, 1 mm margin): from the
//! least-effort shape whose tip lies on the tube's centre line to a tip 5 mm off it, planned
//! with RRT-Connect (cold) and with a roadmap. Writes the path's figure, the plan as JSON and
//! the trajectory (joint values of the articulated URDF export) to OUT_DIR (default
//! `target/plan_vessel`).
//!
//! `cargo run --release --example plan_vessel [OUT_DIR]`

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plan::roadmap::{build, BuildOptions};
use ccrkit::plan::{plan, Goal, PlanOptions};
use ccrkit::plot::{plot_rows, Row};
use ccrkit::reach::{reach, ReachOptions, Target};
use ccrkit::{Model, Scene};
use nalgebra::Vector3;
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/plan_vessel".into()),
    );
    std::fs::create_dir_all(&out)?;
    let root = env!("CARGO_MANIFEST_DIR");
    let model = Model::from_file(format!("{root}/models/plan/two_segment.toml"))?;
    let scene = Scene::from_file(format!("{root}/models/plan/vessel.toml"))?;
    let req = SolveRequest::new(MethodKind::Energy).with_scene(Some(scene.clone()));
    // The tube's centre line at the robot's length: (R (1 − cos θ), 0, R sin θ), θ = L / R.
    let (r, l) = (0.11, model.robot.length());
    let th = l / r;
    let on_axis = Vector3::new(r * (1.0 - th.cos()), 0.0, r * th.sin());
    let start = reach(
        &model,
        &req,
        &Target {
            tip: on_axis,
            tangent: None,
        },
        &ReachOptions::default(),
    )?
    .require_reached()?;
    println!(
        "start: tip on the centre line, clearance {:.2} mm, {} solves",
        start.min_clearance_m.unwrap_or(f64::NAN) * 1e3,
        start.solves
    );
    let goal = on_axis + Vector3::new(0.0, 0.005, 0.0);
    let opts = PlanOptions::default();
    let p = plan(&model, &req, Some(start.u.clone()), &Goal::Tip(goal), &opts)?;
    println!(
        "plan (cold, RRT-Connect): {} waypoints, clearance {:.2} mm measured, {:.2} mm certified, {} solves, {:.0} ms",
        p.waypoints.len(),
        p.min_clearance_m * 1e3,
        p.certified_clearance_m * 1e3,
        p.stats.checks.solves,
        p.stats.time_s * 1e3
    );
    std::fs::write(
        out.join("plan.json"),
        serde_json::to_string_pretty(&p.to_json())?,
    )?;
    std::fs::write(out.join("trajectory.csv"), p.trajectory_csv(&model)?)?;
    let rm = build(&model, &req, &BuildOptions::default())?;
    println!(
        "roadmap: {} nodes, {} edges, {:.2} s",
        rm.nodes.len(),
        rm.edges.len(),
        rm.build_time_s
    );
    let q = rm.query(&model, &req, Some(start.u.clone()), &Goal::Tip(goal), &opts)?;
    println!(
        "plan (roadmap): {} waypoints, clearance {:.2} mm, {:.0} ms",
        q.waypoints.len(),
        q.min_clearance_m * 1e3,
        q.stats.time_s * 1e3
    );
    let n = p.waypoints.len();
    let picks = [0, n / 3, 2 * n / 3, n - 1];
    let shapes: Vec<(&ccrkit::Shape, String)> = picks
        .iter()
        .map(|&k| (&p.waypoints[k].shape, format!("waypoint {k}")))
        .collect();
    let fig = out.join("plan_vessel.svg");
    plot_rows(
        &[Row {
            title: format!(
                "{}: path inside the tube (margin {} mm)",
                model.robot.name,
                p.margin_m * 1e3
            ),
            robot: &model.robot,
            shapes,
            scene: Some(&scene),
        }],
        &fig,
    )?;
    plot_rows(
        &[Row {
            title: format!("{}: path inside the tube", model.robot.name),
            robot: &model.robot,
            shapes: picks
                .iter()
                .map(|&k| (&p.waypoints[k].shape, format!("waypoint {k}")))
                .collect(),
            scene: Some(&scene),
        }],
        &out.join("plan_vessel.png"),
    )?;
    println!(
        "wrote {}/{{plan.json, trajectory.csv, plan_vessel.svg, plan_vessel.png}}",
        out.display()
    );
    Ok(())
}
