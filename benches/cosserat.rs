//! Cosserat rod solve times on the paper cases: cold start, and warm start from a solution of
//! a slightly different actuation (tensions 2 % lower; under displacement control,
//! shortenings 2 % lower), at the default settings (3 RK4 steps
//! per section, more where a route bends: the resolution that keeps the tip within 0.01 mm of
//! the converged rod). `CCRKIT_BENCH_STEPS=N` sets the base steps per section instead. With no
//! external load the default takes the unloaded path (under displacement control, Newton on
//! the tensions); `displacement-shooting` rows shoot instead. `loaded`: lateral gravity and a
//! tip force, shooting on the external moment (the default) against `loaded-shooting` on
//! Rucker–Webster's equations at the default steps and (`loaded-shooting-as-close`) at the
//! steps that come as close to the converged rod as the default. `lung`: the 24-section soft lung rod, unloaded path against
//! shooting.

use ccrkit::actuation::{Input, Shortening};
use ccrkit::method::cosserat::Cosserat;
use ccrkit::{Method, Model, Scene};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

fn paper(n: usize) -> Model {
    Model::from_file(format!(
        "{}/models/paper/case{n}.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("paper model")
}

fn steps() -> usize {
    std::env::var("CCRKIT_BENCH_STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(Cosserat::default().steps_per_section)
}

fn bench(c: &mut Criterion) {
    let scene = Scene::empty();
    let m = Cosserat::full().with_steps(steps());
    for n in 1..=3 {
        let model = paper(n);
        let (robot, act) = (&model.robot, &model.actuation);
        let mut near = act.clone();
        for d in &mut near.cables {
            d.tension = d.tension.map(|t| 0.98 * t);
        }
        let warm = m.solve(robot, &near, &scene, None).expect("solves");
        c.bench_function(&format!("cosserat/case{n}/cold"), |b| {
            b.iter(|| black_box(m.solve(robot, act, &scene, None).expect("solves")))
        });
        c.bench_function(&format!("cosserat/case{n}/warm"), |b| {
            b.iter(|| black_box(m.solve(robot, act, &scene, Some(&warm)).expect("solves")))
        });
        // Displacement control: warm from the solution for shortenings 2 % lower.
        let md = m.clone().with_control(Input::Shortening);
        let mut near = act.clone();
        for d in &mut near.cables {
            d.shorten = d.shorten.map(|s| match s {
                Shortening::Length(x) => Shortening::Length(0.98 * x),
                Shortening::Fraction(x) => Shortening::Fraction(0.98 * x),
            });
        }
        let warm = md.solve(robot, &near, &scene, None).expect("solves");
        c.bench_function(&format!("cosserat/case{n}/displacement/cold"), |b| {
            b.iter(|| black_box(md.solve(robot, act, &scene, None).expect("solves")))
        });
        c.bench_function(&format!("cosserat/case{n}/displacement/warm"), |b| {
            b.iter(|| black_box(md.solve(robot, act, &scene, Some(&warm)).expect("solves")))
        });
        // The same cold solve shooting (`solver = shooting`): the unloaded path's Newton on the
        // tensions against shooting for base wrench and tensions.
        let shoot = md.clone().with_unloaded(false);
        c.bench_function(
            &format!("cosserat/case{n}/displacement-shooting/cold"),
            |b| b.iter(|| black_box(shoot.solve(robot, act, &scene, None).expect("solves"))),
        );
        // Loaded (lateral gravity on a nitinol backbone, a tip force; force control): shooting
        // on the external moment (`loaded.rs`, the default) against shooting on
        // Rucker–Webster's equations (`solver = shooting`), both cold with the stability test.
        let mut loaded = model.clone();
        loaded.robot.backbone.density = 6450.0;
        loaded.robot.loads.gravity = nalgebra::Vector3::new(0.0, -9.81, 0.0);
        loaded.robot.loads.tip_force = nalgebra::Vector3::new(0.05, 0.0, 0.0);
        let (lr, la) = (&loaded.robot, &loaded.actuation);
        c.bench_function(&format!("cosserat/case{n}/loaded/cold"), |b| {
            b.iter(|| black_box(m.solve(lr, la, &scene, None).expect("solves")))
        });
        let shoot = m.clone().with_unloaded(false);
        c.bench_function(&format!("cosserat/case{n}/loaded-shooting/cold"), |b| {
            b.iter(|| black_box(shoot.solve(lr, la, &scene, None).expect("solves")))
        });
        // Shooting on the strain rates as close to the converged rod as the default loaded
        // path (0.012 / 0.003 / 0.009 µm at the tip): 6 / 7 / 16 RK4 steps per section
        // (`docs/guide/performance.md`).
        let close = shoot.clone().with_steps([6, 7, 16][n - 1]);
        c.bench_function(
            &format!("cosserat/case{n}/loaded-shooting-as-close/cold"),
            |b| b.iter(|| black_box(close.solve(lr, la, &scene, None).expect("solves"))),
        );
    }
}

/// The soft lung rod at 24 stations, tension-driven and unloaded (`tests/support/src/soft.rs`):
/// the unloaded path (`solver=auto`, the default) against shooting, both without the stability
/// test (`stability=skip`) and with it.
fn lung(c: &mut Criterion) {
    let scene = Scene::empty();
    let text = ccrkit_test_support::soft::lung_rod_toml(24, [1.5, 2.5, 0.7]);
    let model = Model::from_toml_str(&text).expect("lung rod");
    let (robot, act) = (&model.robot, &model.actuation);
    for (name, unloaded) in [("unloaded", true), ("shooting", false)] {
        for check in [false, true] {
            let m = Cosserat {
                check_stability: check,
                ..Cosserat::full().with_unloaded(unloaded)
            };
            let tag = if check { "check" } else { "skip" };
            c.bench_function(&format!("cosserat/lung24/{name}/stability-{tag}"), |b| {
                b.iter(|| black_box(m.solve(robot, act, &scene, None).expect("solves")))
            });
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = bench, lung
}
criterion_main!(benches);
