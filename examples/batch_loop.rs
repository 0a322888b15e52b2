//! The first `ROWS` rows of `benches/batch.rs` (case I, energy, 100 × 100 shortening grid,
//! warm-started along blocks of 64), solved by a plain Rust loop over `Method::solve`
//! (`loop`) or by `ccrkit::batch::solve_batch` on one thread (`batch`). A target for
//! callgrind: the difference of two row counts is the per-solve instruction count, which
//! `python/bench/callgrind_batch.sh` compares with the Python package's `solve_batch`.
//!
//! `cargo run --release --example batch_loop -- ROWS loop|batch`

use anyhow::{bail, Context, Result};
use ccrkit::batch::{solve_batch, BatchInputs, BatchOptions};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Model, Scene, Shape};

const SIDE: usize = 100;
const CHUNK: usize = 64;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let rows: usize = args.get(1).context("ROWS")?.parse()?;
    let mode = args.get(2).map(String::as_str).unwrap_or("loop");
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model = Model::from_file(root.join("models/paper/case1.toml"))?;
    let base: Vec<f64> = (0..2)
        .map(|c| model.actuation.shortening_length(&model.robot, c))
        .collect::<Option<_>>()
        .context("case 1 gives shortenings")?;
    let f = |i: usize| 0.2 + 0.8 * i as f64 / (SIDE - 1) as f64;
    let grid: Vec<f64> = (0..rows)
        .flat_map(|r| [base[0] * f(r / SIDE), base[1] * f(r % SIDE)])
        .collect();
    let inputs = BatchInputs::new(rows, 2, Some(grid), None)?;
    let request = SolveRequest::new(MethodKind::Energy);
    let mut iterations = 0;
    match mode {
        "loop" => {
            let method = request.solver()?;
            let scene = Scene::empty();
            for start in (0..rows).step_by(CHUNK) {
                let mut last: Option<Shape> = None;
                for r in start..(start + CHUNK).min(rows) {
                    let s =
                        method.solve(&model.robot, &inputs.actuation(r), &scene, last.as_ref())?;
                    iterations += s.report.iterations;
                    last = Some(s);
                }
            }
        }
        "batch" => {
            let opts = BatchOptions {
                threads: Some(1),
                chunk: CHUNK,
                ..Default::default()
            };
            let b = solve_batch(&model, &request, &inputs, &opts)?;
            iterations = b.rows.iter().map(|r| r.iterations).sum();
        }
        other => bail!("mode `{other}`: expected loop or batch"),
    }
    println!("{rows} rows, {iterations} iterations");
    Ok(())
}
