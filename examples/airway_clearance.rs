//! What one whole-shape clearance costs in a generated airway of about 10⁵ triangles (seed 3,
//! 4 generations, 1.5 mm cell: `free = "inside"`, the catheter through its port in the
//! trachea): the shapes of seeded reachable targets ([`airway_tasks::Setup::tasks`]), each
//! one's `reach::clearance` timed (the grid prepared first) and compared with the dense check
//! on the exact triangles (`airway_tasks::dense_clearance`).
//!
//! `cargo run --release --example airway_clearance [SHAPES] [REPEATS]`; its instruction count,
//! the setup left out: `valgrind --tool=callgrind --toggle-collect='*airway_clearance*timed*'
//! target/release/examples/airway_clearance 8 1`; the grid's certified bounds alone
//! (`reach::clearance_bounds`, printed beside each): `--toggle-collect='*airway_clearance*bounded*'`

#[path = "common/airway_tasks.rs"]
mod airway_tasks;

use airway_tasks::{dense_clearance, Setup};
use anyhow::Result;
use ccrkit::anatomy::AirwayOptions;
use ccrkit::reach::{clearance, clearance_bounds, ClearanceBounds};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

/// The airway of the clearance row: seed 3, 4 generations, 1.5 mm cell (about 10⁵ triangles).
pub fn options() -> AirwayOptions {
    AirwayOptions {
        seed: 3,
        generations: 4,
        cell: Some(0.0015),
        ..AirwayOptions::default()
    }
}

/// One clearance, in a function of its own so callgrind can count only it.
#[inline(never)]
fn timed(
    robot: &ccrkit::Robot,
    shape: &ccrkit::Shape,
    scene: &ccrkit::Scene,
) -> Option<ccrkit::reach::Clearance> {
    clearance(robot, shape, scene)
}

/// The grid's bounds on one clearance, in a function of its own for callgrind.
#[inline(never)]
fn bounded(
    robot: &ccrkit::Robot,
    shape: &ccrkit::Shape,
    scene: &ccrkit::Scene,
) -> Option<ClearanceBounds> {
    clearance_bounds(robot, shape, scene)
}

fn main() -> Result<()> {
    let arg = |k: usize, d: usize| std::env::args().nth(k).map_or(Ok(d), |s| s.parse());
    let (count, repeats) = (arg(1, 16)?, arg(2, 200)?);
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/airway_clearance");
    let setup = Setup::from_options(&options(), &dir)?;
    let space = setup.space()?;
    let scene = &space.scene;
    let t0 = Instant::now();
    let _ = scene.obstacles[0].field();
    println!(
        "{} triangles; grid prepared in {:.2?}",
        setup.airway.triangles.len(),
        t0.elapsed()
    );
    let tasks = setup.tasks(&space, 5, count, 0, 400 * count);
    let robot = &space.robot;
    let (mut total, mut grid_total) = (std::time::Duration::ZERO, std::time::Duration::ZERO);
    for task in &tasks {
        let shape = space.solve(&task.u, None)?;
        let t0 = Instant::now();
        let mut c = None;
        for _ in 0..repeats {
            c = black_box(timed(robot, black_box(&shape), scene));
        }
        let each = t0.elapsed() / repeats as u32;
        total += each;
        let t0 = Instant::now();
        let mut b = None;
        for _ in 0..repeats {
            b = black_box(bounded(robot, black_box(&shape), scene));
        }
        let grid = t0.elapsed() / repeats as u32;
        grid_total += grid;
        let b = b.ok_or_else(|| anyhow::anyhow!("no bounds"))?;
        let c = c.ok_or_else(|| anyhow::anyhow!("no clearance"))?;
        println!(
            "  grid bounds [{:.4}, {:.4}] mm, {grid:.2?}",
            1e3 * b.lower,
            1e3 * b.upper
        );
        println!(
            "generation {} ({} backbone points, {} disks, {} cables): clearance {:.4} mm ({}), dense check {:.4} mm, {each:.2?}",
            task.generation,
            shape.backbone.len(),
            shape.disks.len(),
            shape.cables.len(),
            1e3 * c.distance,
            c.feature,
            1e3 * dense_clearance(&setup, &shape)
        );
    }
    let n = tasks.len().max(1) as u32;
    println!(
        "{} shapes: mean {:.2?} per clearance, {:.2?} per grid bounds",
        tasks.len(),
        total / n,
        grid_total / n
    );
    Ok(())
}
