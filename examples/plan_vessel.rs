//! A two-segment tendon robot (FTDCR v4 layout, `models/plan/two_segment.toml`) inside the
//! bent tube of `models/meshes/vessel.obj` (`models/plan/vessel.toml`, 1 mm margin), planned
//! cold with RRT-Connect between two actuations inside the tube (`models/plan/vessel_start.json`,
//! `vessel_goal.json`: admissible seeded uniform samples of the limits box) whose straight
//! actuation path leaves the tube — the planner must find a detour (checked here: the straight
//! edge is refused). Then the same query through a roadmap (uniform samples, of which about 1
//! in 200 lies inside the tube, then Gaussian expansion samples around those: see
//! `ccrkit::plan::roadmap`).
//! Writes the path's figure, the plan as JSON and the trajectory (joint values of the
//! articulated URDF export) to OUT_DIR (default `target/plan_vessel`).
//!
//! `cargo run --release --example plan_vessel [OUT_DIR]`

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plan::roadmap::{build, BuildOptions};
use ccrkit::plan::{plan, read_actuation, Checker, EdgeCheck, Goal, PlanOptions};
use ccrkit::plot::{plot_rows, Row};
use ccrkit::reach::Space;
use ccrkit::{Model, Scene};
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
    let dir = PathBuf::from(format!("{root}/models/plan"));
    let start = read_actuation(&dir.join("vessel_start.json"), &model)?;
    let goal = read_actuation(&dir.join("vessel_goal.json"), &model)?;
    // The straight actuation path: refused (it leaves the tube).
    let space = Space::new(&model, &req, false)?;
    let mut ck = Checker::new(&space, space.margin);
    let (a, b) = (ck.node(&start, None), ck.node(&goal, None));
    let (Some(a), Some(b)) = (a, b) else {
        anyhow::bail!("start or goal is not clear of the tube by the margin");
    };
    let straight = ck.edge(&a, &b);
    println!(
        "start tip {:.2?} mm, goal tip {:.2?} mm, straight actuation path: {}",
        (a.shape.tip() * 1e3).as_slice(),
        (b.shape.tip() * 1e3).as_slice(),
        if straight == EdgeCheck::Blocked {
            "leaves the tube (refused)"
        } else {
            "clear"
        }
    );
    let opts = PlanOptions::default();
    let p = plan(
        &model,
        &req,
        Some(start.clone()),
        &Goal::Actuation(goal.clone()),
        &opts,
        None,
    )?;
    println!(
        "plan (cold, RRT-Connect): {} waypoints, clearance {:.2} mm measured, {:.2} mm certified, {} samples, {} solves, {:.0} ms",
        p.waypoints.len(),
        p.min_clearance_m * 1e3,
        p.certified_clearance_m * 1e3,
        p.stats.samples,
        p.stats.checks.solves,
        p.stats.time_s * 1e3
    );
    ccrkit::output::write_file(
        out.join("plan.json"),
        serde_json::to_string_pretty(&p.to_json())?,
    )?;
    ccrkit::output::write_file(out.join("trajectory.csv"), p.trajectory_csv(&model)?)?;
    let rm = build(&model, &req, &BuildOptions::default())?;
    println!(
        "roadmap: {} nodes, {} edges, {:.2} s",
        rm.nodes.len(),
        rm.edges.len(),
        rm.build_time_s
    );
    match plan(
        &model,
        &req,
        Some(start.clone()),
        &Goal::Actuation(goal.clone()),
        &opts,
        Some(&rm),
    ) {
        Ok(q) => println!(
            "plan (roadmap): {} waypoints, clearance {:.2} mm, {:.0} ms",
            q.waypoints.len(),
            q.min_clearance_m * 1e3,
            q.stats.time_s * 1e3
        ),
        Err(e) => println!("plan (roadmap): {e}"),
    }
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
