//! Timing next to large meshes: the paper's case-1 robot inside a closed bent tube (the
//! vessel's, capped) of about 25 000 or 100 000 triangles, as a lumen (`free = "inside"`):
//! one cold energy solve and whole-shape clearances, each timed.
//!
//! `cargo run --release --example lumen_timing [TRIANGLES] [clearance]` (with `clearance`, no
//! solve: the clearance of the shape solved without obstacles)

use anyhow::Result;
use ccrkit::mesh::{to_obj, BentTube};
use ccrkit::prelude::*;
use ccrkit::reach::clearance;
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<()> {
    let n: usize = std::env::args().nth(1).map_or(Ok(25_000), |s| s.parse())?;
    let only_clearance = std::env::args().nth(2).as_deref() == Some("clearance");
    let segments = if n > 50_000 { 64 } else { 32 };
    let rings = n / (2 * segments);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = root.join("target/lumen_timing");
    std::fs::create_dir_all(&dir)?;
    let (v, t) = BentTube {
        bend_radius: 0.11,
        tube_radius: 0.02,
        theta0: -0.1,
        theta1: 1.8,
        rings,
        segments,
    }
    .capped();
    ccrkit::output::write_file(dir.join("lumen.obj"), to_obj(&v, &t))?;
    for free in ["free = \"inside\"\n", ""] {
        ccrkit::output::write_file(
            dir.join("lumen.toml"),
            format!("[[obstacles]]\nname = \"lumen\"\nshape = \"mesh\"\npath = \"lumen.obj\"\nrotation = {{ rpy = [0.0, 0.0, 0.964] }}\n{free}"),
        )?;
        let t0 = Instant::now();
        let scene = Scene::from_file(dir.join("lumen.toml"))?;
        let load = t0.elapsed();
        // The solid's signed-distance grid, built once (the first query would otherwise).
        let t0 = Instant::now();
        let _ = scene.obstacles[0].field();
        let prepare = t0.elapsed();
        let model = Model::from_file(root.join("models/paper/case1.toml"))?;
        let solver = SolveRequest::new(MethodKind::Energy).solver()?;
        let t0 = Instant::now();
        let r =
            (!only_clearance).then(|| solver.solve(&model.robot, &model.actuation, &scene, None));
        let solve = t0.elapsed();
        let shape = match &r {
            Some(Ok(s)) => s.clone(),
            _ => SolveRequest::new(MethodKind::Energy).solver()?.solve(
                &model.robot,
                &model.actuation,
                &Scene::empty(),
                None,
            )?,
        };
        let t0 = Instant::now();
        let reps = 200;
        let mut c = None;
        for _ in 0..reps {
            c = clearance(&model.robot, &shape, &scene);
        }
        let clear = t0.elapsed() / reps;
        println!(
            "{} triangles, {}: load {load:?}, grid {prepare:?}, cold energy solve {solve:?} ({}), clearance {clear:?} ({c:?})",
            t.len(),
            if free.is_empty() { "surface" } else { "lumen" },
            match &r {
                None => "not run".to_string(),
                Some(Ok(_)) => "ok".to_string(),
                Some(Err(e)) => format!("{e}"),
            }
        );
    }
    Ok(())
}
