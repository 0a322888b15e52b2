//! Criterion benchmarks of batch solves: 10 000 energy solves of paper case I over a 100 × 100
//! grid of cable shortenings (20–100 % of the file's, row-major, so consecutive rows are
//! neighbours), warm-started along blocks of 64 rows — as a plain Rust loop over
//! `Method::solve`, and through `ccrkit::batch::solve_batch` on 1 and 2 threads. The Python
//! package's `solve_batch` runs the latter; `python/bench/bench_batch.py` times it from Python
//! on the same rows.
//!
//! `cargo bench --bench batch`

use ccrkit::batch::{solve_batch, BatchInputs, BatchOptions};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Model, Scene, Shape};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

/// Grid side: 100 × 100 = 10 000 rows.
const SIDE: usize = 100;
const CHUNK: usize = 64;

/// The rows (shortenings [m], row-major): cable A scaled by `0.2 + 0.8 i/99`, B by `… j/99`.
fn grid(model: &Model) -> Vec<f64> {
    let base: Vec<f64> = (0..2)
        .map(|c| {
            model
                .actuation
                .shortening_length(&model.robot, c)
                .expect("case 1 gives shortenings")
        })
        .collect();
    let f = |i: usize| 0.2 + 0.8 * i as f64 / (SIDE - 1) as f64;
    let mut v = Vec::with_capacity(2 * SIDE * SIDE);
    for i in 0..SIDE {
        for j in 0..SIDE {
            v.push(base[0] * f(i));
            v.push(base[1] * f(j));
        }
    }
    v
}

fn batch(c: &mut Criterion) {
    let model = Model::from_file("models/paper/case1.toml").expect("model");
    let rows = SIDE * SIDE;
    let inputs = BatchInputs::new(rows, 2, Some(grid(&model)), None).expect("inputs");
    let request = SolveRequest::new(MethodKind::Energy);
    let method = request.solver().expect("energy");
    let scene = Scene::empty();
    let mut g = c.benchmark_group("batch-case1-energy-10000");
    g.sample_size(10);
    g.bench_function("rust-loop", |b| {
        b.iter(|| {
            let mut n = 0;
            for start in (0..rows).step_by(CHUNK) {
                let mut last: Option<Shape> = None;
                for r in start..(start + CHUNK).min(rows) {
                    let act = inputs.actuation(r);
                    let s = method
                        .solve(&model.robot, &act, &scene, last.as_ref())
                        .expect("solves");
                    n += s.report.iterations;
                    last = Some(s);
                }
            }
            black_box(n)
        })
    });
    for threads in [1, 2] {
        let opts = BatchOptions {
            threads: Some(threads),
            chunk: CHUNK,
            ..Default::default()
        };
        g.bench_function(format!("solve_batch-{threads}-threads"), |b| {
            b.iter(|| solve_batch(&model, &request, black_box(&inputs), &opts).expect("batch"))
        });
    }
    g.finish();
}

criterion_group!(benches, batch);
criterion_main!(benches);
