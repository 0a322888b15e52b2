//! Speed on scenes nobody tuned for: paper case I next to seeded generated scenes (walls,
//! pillars and boxes at random poses beside the upper half of its free path, the body pressing
//! on them; `ccrkit_test_support::scenes::near_path`) and the committed scenes (`wall`,
//! `pillar`) as a subset, solved by every method that takes obstacles. Per method: how many
//! converged, the median and the worst solve time and Newton iterations, and which scene is the
//! worst. Every scene is written to `OUT/` (default `target/scene_speed`) so that the worst one
//! can be measured alone, e.g.
//! `valgrind --tool=callgrind target/release/ccrkit solve models/paper/case1.toml --method geometric --scene OUT/gen_17.toml`.
//!
//! `cargo run --release --example scene_speed -- [--scenes 60] [--seed 1] [--out DIR]`

use anyhow::{bail, Context, Result};
use ccrkit::prelude::*;
use ccrkit::Scene;
use ccrkit_test_support::scenes::near_path;
use std::path::PathBuf;

/// The methods that take obstacles.
const METHODS: [MethodKind; 3] = [
    MethodKind::Geometric,
    MethodKind::GeometricSquared,
    MethodKind::Energy,
];

/// One solve: scene (with the error when it failed), converged, time \[s\], Newton iterations.
struct Row {
    scene: String,
    converged: bool,
    time: f64,
    iterations: usize,
}

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let (mut n, mut seed, mut out) = (60usize, 1u64, PathBuf::from("target/scene_speed"));
    while let Some(a) = args.next() {
        let v = args.next().with_context(|| format!("{a} needs a value"))?;
        match a.as_str() {
            "--scenes" => n = v.parse().context("--scenes: a count")?,
            "--seed" => seed = v.parse().context("--seed: an integer")?,
            "--out" => out = v.into(),
            _ => bail!("unknown option {a} (--scenes, --seed, --out)"),
        }
    }
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model = Model::from_file(root.join("models/paper/case1.toml"))?;
    let free = SolveRequest::new(MethodKind::Geometric).solver()?.solve(
        &model.robot,
        &model.actuation,
        &Scene::empty(),
        None,
    )?;
    let path: Vec<[f64; 3]> = free.disks.iter().map(|d| d.position.into()).collect();
    let mut scenes = vec![];
    for name in ["wall", "pillar"] {
        scenes.push((
            name.to_string(),
            root.join(format!("models/scenes/{name}.toml")),
        ));
    }
    for k in 0..n as u64 {
        let (text, _) = near_path(&path, seed.wrapping_add(k));
        let file = out.join(format!("gen_{}.toml", seed.wrapping_add(k)));
        ccrkit::output::write_file(&file, text)?;
        scenes.push((format!("gen_{}", seed.wrapping_add(k)), file));
    }
    println!(
        "paper case I, {} scenes (wall, pillar and {n} generated from seed {seed}), files in {}",
        scenes.len(),
        out.display()
    );
    println!("| method | converged | median time [ms] | worst time [ms] (scene) | median iterations | worst iterations (scene) | wall [ms] / iterations |");
    println!("|---|---|---|---|---|---|---|");
    let mut failures = vec![];
    for method in METHODS {
        let solver = SolveRequest::new(method).solver()?;
        let mut rows = vec![];
        for (name, file) in &scenes {
            let scene = Scene::from_file(file)?;
            // The fastest of three runs: the solve's own cost, not the machine's noise.
            let mut best: Option<Row> = None;
            for _ in 0..3 {
                let row = match solver.solve(&model.robot, &model.actuation, &scene, None) {
                    Ok(s) => Row {
                        scene: name.clone(),
                        converged: s.report.converged,
                        time: s.report.solve_time_s,
                        iterations: s.report.iterations,
                    },
                    Err(e) => Row {
                        scene: format!("{name}: {e}"),
                        converged: false,
                        time: f64::NAN,
                        iterations: 0,
                    },
                };
                if best
                    .as_ref()
                    .is_none_or(|b| row.time.total_cmp(&b.time).is_lt())
                {
                    best = Some(row);
                }
            }
            rows.extend(best);
        }
        print_method(method, &rows);
        failures.extend(
            rows.into_iter()
                .filter(|r| !r.converged)
                .map(|r| (method, r.scene)),
        );
    }
    for (method, why) in failures {
        let short: String = why.chars().take(160).collect();
        println!("{} failed on {short}", method.name());
    }
    Ok(())
}

/// The median of sorted values.
fn median(v: &[f64]) -> f64 {
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// One table row of a method over the scenes it converged on.
fn print_method(method: MethodKind, rows: &[Row]) {
    let ok: Vec<&Row> = rows.iter().filter(|r| r.converged).collect();
    if ok.is_empty() {
        println!("| {} | 0/{} | | | | | |", method.name(), rows.len());
        return;
    }
    let mut times: Vec<f64> = ok.iter().map(|r| r.time * 1e3).collect();
    times.sort_by(f64::total_cmp);
    let mut its: Vec<f64> = ok.iter().map(|r| r.iterations as f64).collect();
    its.sort_by(f64::total_cmp);
    let slow = ok.iter().max_by(|a, b| a.time.total_cmp(&b.time)).unwrap();
    let most = ok.iter().max_by_key(|r| r.iterations).unwrap();
    let wall = rows.iter().find(|r| r.scene == "wall");
    let wall = wall.map_or("—".into(), |w| {
        format!("{:.3} / {}", w.time * 1e3, w.iterations)
    });
    println!(
        "| {} | {}/{} | {:.3} | {:.3} ({}) | {} | {} ({}) | {wall} |",
        method.name(),
        ok.len(),
        rows.len(),
        median(&times),
        slow.time * 1e3,
        slow.scene,
        median(&its),
        most.iterations,
        most.scene,
    );
}
