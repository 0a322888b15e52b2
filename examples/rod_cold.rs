//! The rod (`--method cosserat`) from a cold start beside the generated scenes of paper case I's
//! path (`ccrkit_test_support::scenes::near_path`, seeds `FIRST..FIRST+N`), against `energy`:
//! per scene the rod's outcome (converged with its Newton iterations, or the error it names),
//! its tip distance from `energy`'s answer, and a summary (converged count, median and worst
//! iterations). Each scene is written to `OUT/gen_SEED.toml` so one can be solved alone:
//! `ccrkit solve models/paper/case1.toml --method cosserat --scene OUT/gen_5.toml`.
//!
//! `cargo run --release --example rod_cold -- [--first 0] [--scenes 16] [--out DIR]`

use anyhow::{bail, Context, Result};
use ccrkit::prelude::*;
use ccrkit::{Scene, Shape};
use ccrkit_test_support::scenes::near_path;
use std::path::PathBuf;

fn solve(
    m: &Model,
    sc: &Scene,
    kind: MethodKind,
    warm: Option<&Shape>,
) -> Result<Shape, SolveError> {
    let settings = match kind {
        MethodKind::Geometric => Settings::new(),
        _ => Settings::new().with("control", "displacement"),
    };
    SolveRequest::new(kind)
        .with_settings(settings)
        .solver()?
        .solve(&m.robot, &m.actuation, sc, warm)
}

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let (mut first, mut n, mut out) = (0u64, 16u64, PathBuf::from("target/rod_cold"));
    while let Some(a) = args.next() {
        let v = args.next().with_context(|| format!("{a} needs a value"))?;
        match a.as_str() {
            "--first" => first = v.parse().context("--first: an integer")?,
            "--scenes" => n = v.parse().context("--scenes: a count")?,
            "--out" => out = v.into(),
            _ => bail!("unknown option {a} (--first, --scenes, --out)"),
        }
    }
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let m = Model::from_file(root.join("models/paper/case1.toml"))?;
    let free = solve(&m, &Scene::empty(), MethodKind::Geometric, None)?;
    let path: Vec<[f64; 3]> = free.disks.iter().map(|d| d.position.into()).collect();
    let mut iters = vec![];
    for seed in first..first + n {
        let file = out.join(format!("gen_{seed}.toml"));
        std::fs::write(&file, near_path(&path, seed).0)?;
        let sc = Scene::from_file(&file)?;
        let energy = solve(&m, &sc, MethodKind::Energy, None).or_else(|_| {
            let start = solve(&m, &sc, MethodKind::Geometric, None)?;
            solve(&m, &sc, MethodKind::Energy, Some(&start))
        });
        let rod = solve(&m, &sc, MethodKind::Cosserat, None);
        let vs = |s: &Shape| match &energy {
            Ok(e) => format!("{:.4} mm from energy", (s.tip() - e.tip()).norm() * 1e3),
            Err(_) => "energy failed".into(),
        };
        match &rod {
            Ok(s) => {
                iters.push(s.report.iterations);
                println!(
                    "seed {seed}: converged, {} iterations, {} contacts, {}",
                    s.report.iterations,
                    s.contacts.len(),
                    vs(s)
                );
            }
            Err(e) => println!("seed {seed}: {e}"),
        }
    }
    iters.sort_unstable();
    println!(
        "converged {} of {n}; iterations median {}, worst {}",
        iters.len(),
        iters
            .get(iters.len() / 2)
            .map_or("-".into(), |v| v.to_string()),
        iters.last().map_or("-".into(), |v| v.to_string()),
    );
    Ok(())
}
