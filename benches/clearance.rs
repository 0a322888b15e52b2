//! One whole-shape clearance (`reach::clearance`, the query `reach` and `plan` make of every
//! shape) in a generated airway of about 10⁵ triangles (seed 3, 4 generations, 1.5 mm cell,
//! `free = "inside"`): the catheter through its port in the trachea, at the shapes of seeded
//! reachable targets, one shape per iteration in turn. The grid is prepared before timing.
//!
//! Two rows: `clearance/airway_1e5`, the exact clearance (the triangles queried: what a plan
//! or an answer reports), and `clearance/airway_1e5_grid`, the grid's certified bounds on it
//! (`reach::clearance_bounds`, no triangle queried: what the search's margin tests ask first).
//!
//! `cargo bench --bench clearance`

#[path = "../examples/common/airway_tasks.rs"]
mod airway_tasks;

use airway_tasks::Setup;
use ccrkit::anatomy::AirwayOptions;
use ccrkit::reach::{clearance, clearance_bounds};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::PathBuf;

fn bench(c: &mut Criterion) {
    let opts = AirwayOptions {
        seed: 3,
        generations: 4,
        cell: Some(0.0015),
        ..AirwayOptions::default()
    };
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/bench_clearance");
    let setup = Setup::from_options(&opts, &dir).expect("the airway is generated");
    let space = setup.space().expect("the catheter's space");
    let _ = space.scene.obstacles[0].field();
    let shapes: Vec<_> = setup
        .tasks(&space, 5, 8, 0, 3200)
        .iter()
        .map(|t| space.solve(&t.u, None).expect("a target's shape"))
        .collect();
    assert!(!shapes.is_empty(), "no clear shape drawn");
    let mut k = 0;
    c.bench_function("clearance/airway_1e5", |b| {
        b.iter(|| {
            k = (k + 1) % shapes.len();
            clearance(&space.robot, black_box(&shapes[k]), &space.scene)
        })
    });
    c.bench_function("clearance/airway_1e5_grid", |b| {
        b.iter(|| {
            k = (k + 1) % shapes.len();
            clearance_bounds(&space.robot, black_box(&shapes[k]), &space.scene)
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
