//! Criterion benchmarks of `--method energy` on the paper cases: cold starts (from the
//! straight robot) and warm starts (from the solution of a 10 % and of a 2 % smaller
//! actuation).
//!
//! `cargo bench --bench energy`

use ccrkit::actuation::LengthMeasure;
use ccrkit::method::energy::Energy;
use ccrkit::{Method, Model, Scene, Shortening};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

fn paper_cases(c: &mut Criterion) {
    let scene = Scene::empty();
    for (tag, method) in [
        ("path", Energy::default()),
        (
            "chord",
            Energy::default().with_cable_length(LengthMeasure::Chord),
        ),
    ] {
        for case in 1..=3 {
            let model = Model::from_file(format!("models/paper/case{case}.toml")).expect("model");
            c.bench_function(&format!("energy-{tag}/case{case}/cold"), |b| {
                b.iter(|| {
                    method
                        .solve(
                            black_box(&model.robot),
                            black_box(&model.actuation),
                            &scene,
                            None,
                        )
                        .expect("solve")
                })
            });
            // Warm from the solution of a 10 % and a 2 % smaller actuation (a warm start
            // should never be slower than the cold one).
            for (name, frac) in [("warm", 0.9), ("warm-2pct", 0.98)] {
                let mut before = model.actuation.clone();
                for (ci, d) in before.cables.iter_mut().enumerate() {
                    if let Some(f) = model.actuation.shortening_fraction(&model.robot, ci) {
                        d.shorten = Some(Shortening::Fraction(frac * f));
                    }
                }
                let prev = method
                    .solve(&model.robot, &before, &scene, None)
                    .expect("previous");
                c.bench_function(&format!("energy-{tag}/case{case}/{name}"), |b| {
                    b.iter(|| {
                        method
                            .solve(
                                black_box(&model.robot),
                                black_box(&model.actuation),
                                &scene,
                                Some(&prev),
                            )
                            .expect("solve")
                    })
                });
            }
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(2));
    targets = paper_cases
}
criterion_main!(benches);
