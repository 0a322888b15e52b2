//! Obstacle cost of the geometric section solver and of the energy model on the paper's case-1
//! robot: no obstacles, 1000 obstacles out of reach (broad phase only), 1000 small obstacles in
//! reach but clear of the shape (broad + narrow phase), and pressing on one wall or a pillar
//! (contacts active), and the energy model next to a 25 344-triangle mesh from outside and
//! inside (`energy_organ_25k`, `energy_lumen_25k`); and the literal method beside seeded generated scenes (`near_path`, as
//! `examples/scene_speed.rs`): the scenes of seeds 1–20 that take the median and the most
//! Newton iterations.
//!
//! `cargo bench --bench obstacles`

use ccrkit::method::energy::Energy;
use ccrkit::method::geometric::Geometric;
use ccrkit::{Method, Model, Scene};
use ccrkit_test_support::scenes::{near_path, uv_sphere_obj};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Case 1 with `n` spheres of radius `r` at deterministic pseudo-random places in a shell of
/// radii `r0..r1` around the base, below the plane `z = zmax`.
fn scattered(n: usize, r: f64, r0: f64, r1: f64, zmax: f64) -> Model {
    let mut text = std::fs::read_to_string(root().join("models/paper/case1.toml")).unwrap();
    let mut seed: u64 = 0x2545_F491_4F6C_DD1D;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for k in 0..n {
        let (u, v, w) = (rnd(), rnd(), rnd());
        let th = u * std::f64::consts::TAU;
        let z = zmax - v * (r1 + zmax);
        let rad = r0 + w * (r1 - r0);
        let rho = (rad * rad - z * z).max(0.0).sqrt();
        text += &format!(
            "[[obstacles]]\nname = \"s{k}\"\nshape = \"sphere\"\nposition = [{}, {}, {z}]\nradius = {r}\n",
            rho * th.cos(),
            rho * th.sin()
        );
    }
    Model::from_toml_str(&text).unwrap()
}

fn bench(c: &mut Criterion) {
    let model = Model::from_file(root().join("models/paper/case1.toml")).unwrap();
    let far = scattered(1000, 0.01, 1.0, 2.0, 2.0);
    // In reach of the robot-level ball (~0.2 m) but below the base, clear of every shape.
    let near = scattered(1000, 0.001, 0.05, 0.19, -0.03);
    let wall = Scene::from_file(root().join("models/scenes/wall.toml")).unwrap();
    let g = Geometric::literal();
    // One solve of each, with per-section iterations, for the report.
    for (name, scene) in [
        ("empty", &Scene::empty()),
        ("1000 out of reach", &far.scene),
        ("1000 in reach", &near.scene),
        ("wall", &wall),
    ] {
        match g.solve(&model.robot, &model.actuation, scene, None) {
            Ok(s) => {
                let its: Vec<usize> = s.report.sections.iter().map(|r| r.iterations).collect();
                eprintln!(
                    "{name}: {} contacts, iterations per section {its:?}",
                    s.contacts.len()
                );
            }
            Err(e) => eprintln!("{name}: {e}"),
        }
    }
    let mut grp = c.benchmark_group("obstacles_case1");
    grp.sample_size(20);
    grp.bench_function("empty", |b| {
        b.iter(|| black_box(g.solve(&model.robot, &model.actuation, &Scene::empty(), None)))
    });
    grp.bench_function("1000_out_of_reach", |b| {
        b.iter(|| black_box(g.solve(&model.robot, &model.actuation, &far.scene, None)))
    });
    grp.bench_function("1000_in_reach", |b| {
        b.iter(|| black_box(g.solve(&model.robot, &model.actuation, &near.scene, None)))
    });
    grp.bench_function("wall", |b| {
        b.iter(|| black_box(g.solve(&model.robot, &model.actuation, &wall, None)))
    });
    // The broad phase alone: what 1000 obstacles add to a solve before any narrow phase.
    let origin = nalgebra::Vector3::zeros();
    grp.bench_function("broad_phase_1000_out_of_reach", |b| {
        b.iter(|| black_box(far.scene.near(black_box(&origin), 0.2)))
    });
    grp.bench_function("broad_phase_1000_in_reach", |b| {
        b.iter(|| black_box(near.scene.near(black_box(&origin), 0.2)))
    });
    // The energy model, cold starts.
    let pillar = Scene::from_file(root().join("models/scenes/pillar.toml")).unwrap();
    let e = Energy::default();
    for (name, scene) in [
        ("empty", &Scene::empty()),
        ("1000_out_of_reach", &far.scene),
        ("1000_in_reach", &near.scene),
        ("wall", &wall),
        ("pillar", &pillar),
    ] {
        match e.solve(&model.robot, &model.actuation, scene, None) {
            Ok(s) => eprintln!(
                "energy {name}: {} contacts, {} iterations",
                s.contacts.len(),
                s.report.iterations
            ),
            Err(err) => eprintln!("energy {name}: {err}"),
        }
        grp.bench_function(format!("energy_{name}"), |b| {
            b.iter(|| black_box(e.solve(&model.robot, &model.actuation, scene, None)))
        });
    }
    // Next to a 25 344-triangle mesh (a UV sphere of 100 × 128 quads), cold starts: case I's
    // disk 9 pressing on a ball of 30 mm from outside (`free = "outside"`), and on the sphere
    // of 100 mm it lies in (`free = "inside"`). The mesh is read and its grid made before.
    let dir = root().join("target/bench_obstacles");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, r, centre, free) in [
        ("organ_25k", 0.03, [0.07735, 0.11064, 0.10], "outside"),
        ("lumen_25k", 0.1, [0.0, 0.0, 0.09], "inside"),
    ] {
        std::fs::write(
            dir.join(format!("{name}.obj")),
            uv_sphere_obj(r, centre, 100, 128),
        )
        .unwrap();
        let body = format!(
            "[[obstacles]]\nname = \"{name}\"\nshape = \"mesh\"\npath = \"{name}.obj\"\nfree = \"{free}\"\n"
        );
        let file = dir.join(format!("{name}.toml"));
        std::fs::write(&file, body).unwrap();
        let scene = Scene::from_file(&file).unwrap();
        let _ = scene.obstacles[0].field();
        let s = e
            .solve(&model.robot, &model.actuation, &scene, None)
            .unwrap();
        eprintln!(
            "energy {name}: {} contacts, {} iterations",
            s.contacts.len(),
            s.report.iterations
        );
        grp.bench_function(format!("energy_{name}"), |b| {
            b.iter(|| black_box(e.solve(&model.robot, &model.actuation, &scene, None)))
        });
    }
    grp.finish();
    generated(c, &model, &g);
}

/// The literal method beside the generated scenes of seeds 1–20 (paper case I pressing on a
/// wall, box or pillar turned so a face, edge, corner or rim is nearest): the converged scene
/// with the median and the one with the most Newton iterations, chosen by one solve each.
fn generated(c: &mut Criterion, model: &Model, g: &Geometric) {
    let free = g
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    let path: Vec<[f64; 3]> = free.disks.iter().map(|d| d.position.into()).collect();
    let dir = std::env::temp_dir().join(format!("ccrkit-bench-generated-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut solved: Vec<(usize, u64, Scene)> = (1..=20u64)
        .filter_map(|seed| {
            let file = dir.join(format!("gen_{seed}.toml"));
            std::fs::write(&file, near_path(&path, seed).0).ok()?;
            let scene = Scene::from_file(&file).ok()?;
            let s = g.solve(&model.robot, &model.actuation, &scene, None).ok()?;
            Some((s.report.iterations, seed, scene))
        })
        .collect();
    std::fs::remove_dir_all(&dir).ok();
    solved.sort_by_key(|s| s.0);
    let Some(worst) = solved.last() else {
        return;
    };
    let median = &solved[solved.len() / 2];
    eprintln!(
        "generated: {} of 20 converged; median gen_{} ({} iterations), worst gen_{} ({} iterations)",
        solved.len(),
        median.1,
        median.0,
        worst.1,
        worst.0
    );
    let mut grp = c.benchmark_group("obstacles_generated");
    grp.sample_size(20);
    for (name, (_, _, scene)) in [("geometric_median", median), ("geometric_worst", worst)] {
        grp.bench_function(name, |b| {
            b.iter(|| black_box(g.solve(&model.robot, &model.actuation, scene, None)))
        });
    }
    grp.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
