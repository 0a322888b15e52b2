//! Inverse problems: reach on the paper robot (energy) without obstacles
//! and next to the wall, through a port (insertion, rotation and cables: the `port_reach`
//! example's target behind the block; the soft lung rod in tension space); a cold RRT-Connect plan and a roadmap query around a ball blocking
//! the straight path (case 1), and a cold plan and roadmap queries inside the vessel
//! (two-segment robot), one of whose straight actuation path leaves the tube.
//!
//! `cargo bench --bench reach`

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plan::roadmap::{build, BuildOptions};
use ccrkit::plan::{plan, read_actuation, Goal, PlanOptions};
use ccrkit::reach::{reach, ReachOptions, Space, Target};
use ccrkit::{Model, Scene};
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::Vector3;
use std::hint::black_box;
use std::time::Duration;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn case1() -> Model {
    Model::from_file(format!("{ROOT}/models/paper/case1.toml")).unwrap()
}

fn energy() -> SolveRequest {
    SolveRequest::new(MethodKind::Energy)
}

fn tip_of(model: &Model, u: &[f64]) -> Vector3<f64> {
    Space::new(model, &energy(), false)
        .unwrap()
        .solve(u, None)
        .unwrap()
        .tip()
}

fn bench_reach(c: &mut Criterion) {
    let model = case1();
    let target = Target {
        tip: tip_of(&model, &[0.006, 0.002]),
        tangent: None,
    };
    let opts = ReachOptions::default();
    c.bench_function("reach/case1_free", |b| {
        b.iter(|| {
            let r = reach(&model, &energy(), black_box(&target), &opts).unwrap();
            assert!(r.reached);
        })
    });
    // Next to the wall: the tip of cable A alone at 3.25 mm (3.2 mm clear of the wall),
    // reached keeping a 1 mm margin.
    let wall = Scene::from_file(format!("{ROOT}/models/scenes/wall.toml")).unwrap();
    let req = energy().with_scene(Some(wall));
    let target = Target {
        tip: tip_of(&model, &[0.00325, 0.0]),
        tangent: None,
    };
    let opts = ReachOptions {
        margin: Some(0.001),
        ..ReachOptions::default()
    };
    c.bench_function("reach/case1_wall", |b| {
        b.iter(|| {
            let r = reach(&model, &req, black_box(&target), &opts).unwrap();
            assert!(r.reached);
        })
    });
    // Through a port: the `port_reach` example (inserted 160 mm, turned 2 rad, cable A at
    // 7 mm makes the target behind the block), from the file's start.
    let port = Model::from_file(format!("{ROOT}/models/port/behind_block.toml")).unwrap();
    let space = Space::new(&port, &energy(), false).unwrap();
    let target = Target {
        tip: space.solve(&[0.007, 0.0, 0.16, 2.0], None).unwrap().tip(),
        tangent: None,
    };
    let opts = ReachOptions::default();
    c.bench_function("reach/port_behind_block", |b| {
        b.iter(|| {
            let r = reach(&port, &energy(), black_box(&target), &opts).unwrap();
            assert!(r.reached);
        })
    });
    // The soft lung rod in tension space: tensions (1, 2, 0.5) N at insertion 80 mm, turned
    // 0.5 rad, as in `tests/inverse/reach_tension.rs`.
    let lung = Model::from_file(format!("{ROOT}/models/soft/lung_rod.toml")).unwrap();
    let force = energy().with_settings(ccrkit::method::Settings::new().with("control", "force"));
    let space = Space::new(&lung, &force, false).unwrap();
    let target = Target {
        tip: space
            .solve(&[1.0, 2.0, 0.5, 0.08, 0.5], None)
            .unwrap()
            .tip(),
        tangent: None,
    };
    c.bench_function("reach/lung_rod_tension", |b| {
        b.iter(|| {
            let r = reach(&lung, &force, black_box(&target), &opts).unwrap();
            assert!(r.reached);
        })
    });
}

const BALL: &str = "[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\nposition = [0.064, 0.111, 0.104]\nradius = 0.012\n";

fn bench_plan(c: &mut Criterion) {
    let text = std::fs::read_to_string(format!("{ROOT}/models/paper/case1.toml")).unwrap();
    let model = Model::from_toml_str(&format!("clearance = 0.0005\n{text}\n{BALL}")).unwrap();
    let (from, to) = (vec![0.014, 0.0], vec![0.0, 0.014]);
    let opts = PlanOptions::default();
    let mut g = c.benchmark_group("plan");
    g.sample_size(20).measurement_time(Duration::from_secs(10));
    g.bench_function("ball_detour_cold", |b| {
        b.iter(|| {
            plan(
                &model,
                &energy(),
                Some(from.clone()),
                &Goal::Actuation(to.clone()),
                &opts,
                None,
            )
            .unwrap()
        })
    });
    let rm = build(&model, &energy(), &BuildOptions::default()).unwrap();
    g.bench_function("ball_detour_roadmap_query", |b| {
        b.iter(|| {
            plan(
                &model,
                &energy(),
                Some(from.clone()),
                &Goal::Actuation(to.clone()),
                &opts,
                Some(&rm),
            )
            .unwrap()
        })
    });
    // Inside the vessel: the example's query (`models/plan/vessel_*.json`), whose straight
    // actuation path leaves the tube.
    let model = Model::from_file(format!("{ROOT}/models/plan/two_segment.toml")).unwrap();
    let scene = Scene::from_file(format!("{ROOT}/models/plan/vessel.toml")).unwrap();
    let req = energy().with_scene(Some(scene));
    let read = |f: &str| {
        read_actuation(
            std::path::Path::new(&format!("{ROOT}/models/plan/{f}")),
            &model,
        )
        .unwrap()
    };
    let (s, t) = (read("vessel_start.json"), read("vessel_goal.json"));
    g.sample_size(10);
    g.bench_function("vessel_cold", |b| {
        b.iter(|| {
            plan(
                &model,
                &req,
                Some(s.clone()),
                &Goal::Actuation(t.clone()),
                &opts,
                None,
            )
            .unwrap()
        })
    });
    // The same query through a roadmap (default build: 400 uniform + 400 expansion samples),
    // and 28 seeded random feasible queries (every pair of 8 admissible uniform samples, as in
    // tests/inverse/plan.rs vessel_queries_succeed) through it: queries/s = 28 / time per iteration.
    let rm = build(&model, &req, &BuildOptions::default()).unwrap();
    g.bench_function("vessel_roadmap_query", |b| {
        b.iter(|| {
            plan(
                &model,
                &req,
                Some(s.clone()),
                &Goal::Actuation(t.clone()),
                &opts,
                Some(&rm),
            )
            .unwrap()
        })
    });
    let ends = admissible(&Space::new(&model, &req, false).unwrap(), 7, 8);
    g.bench_function("vessel_roadmap_28_random_queries", |b| {
        b.iter(|| {
            for i in 0..ends.len() {
                for j in i + 1..ends.len() {
                    plan(
                        &model,
                        &req,
                        Some(ends[i].clone()),
                        &Goal::Actuation(ends[j].clone()),
                        &opts,
                        Some(&rm),
                    )
                    .unwrap();
                }
            }
        })
    });
    g.finish();
}

/// `n` seeded uniform samples of the limits box that keep the margin.
fn admissible(space: &Space, seed: u64, n: usize) -> Vec<Vec<f64>> {
    use rand_core::{Rng, SeedableRng};
    let mut ck = ccrkit::plan::Checker::new(space, space.margin);
    let mut rng = rand_xorshift::XorShiftRng::seed_from_u64(seed);
    let mut out = Vec::new();
    while out.len() < n {
        let u: Vec<f64> = (0..space.dim())
            .map(|c| {
                let f = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
                space.lo[c] + f * (space.hi[c] - space.lo[c])
            })
            .collect();
        if ck.node(&u, None).is_some() {
            out.push(u);
        }
    }
    out
}

criterion_group!(benches, bench_reach, bench_plan);
criterion_main!(benches);
