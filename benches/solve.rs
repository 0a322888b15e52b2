//! Criterion benchmarks: one full solve per paper case and method.
//!
//! `cargo bench --bench solve`

use ccrkit::{method_by_name, Model, Scene};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

fn paper_cases(c: &mut Criterion) {
    let scene = Scene::empty();
    for method in ["geometric", "geometric-squared"] {
        let m = method_by_name(method).expect("method");
        for case in 1..=3 {
            let model = Model::from_file(format!("models/paper/case{case}.toml")).expect("model");
            c.bench_function(&format!("{method}/case{case}"), |b| {
                b.iter(|| {
                    m.solve(
                        black_box(&model.robot),
                        black_box(&model.actuation),
                        &scene,
                        None,
                    )
                    .expect("solve")
                })
            });
        }
    }
}

/// The literal method next to an obstacle: case I in the wall scene.
fn wall_scene(c: &mut Criterion) {
    let m = method_by_name("geometric").expect("method");
    let model = Model::from_file("models/paper/case1.toml").expect("model");
    let scene = Scene::from_file("models/scenes/wall.toml").expect("scene");
    c.bench_function("geometric/case1-wall", |b| {
        b.iter(|| {
            m.solve(
                black_box(&model.robot),
                black_box(&model.actuation),
                &scene,
                None,
            )
            .expect("solve")
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = paper_cases, wall_scene
}
criterion_main!(benches);
