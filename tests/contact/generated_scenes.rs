//! The generated scenes beside a robot's path (`ccrkit_test_support::scenes::near_path`, the
//! set `examples/scene_speed.rs` measures speed on): each obstacle is where the generator says,
//! its distance from the path point it was placed beside measured by parry's point projection
//! on the obstacle as the scene file reads it (an independent check of the generator's
//! rotations and support extents); and the set holds every kind, pressed on.

use crate::common::scenes::near_path;
use ccrkit::model::scene::Scene;
use ccrkit::prelude::*;
use parry3d::math::Vector as PVec;

#[test]
fn generated_obstacles_lie_at_their_placed_gap_from_the_path() {
    let model = Model::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/models/paper/case1.toml"
    ))
    .unwrap();
    let free = SolveRequest::new(MethodKind::Geometric)
        .solver()
        .unwrap()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    let path: Vec<[f64; 3]> = free.disks.iter().map(|d| d.position.into()).collect();
    let dir = std::env::temp_dir().join(format!("ccrkit-generated-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (mut kinds, mut worst) = (std::collections::BTreeMap::new(), 0.0f64);
    for seed in 0..200 {
        let (text, placed) = near_path(&path, seed);
        let file = dir.join(format!("gen_{seed}.toml"));
        std::fs::write(&file, &text).unwrap();
        let scene = Scene::from_file(&file).unwrap();
        assert_eq!(scene.obstacles.len(), placed.len());
        assert!((1..=3).contains(&placed.len()));
        for (o, p) in scene.obstacles.iter().zip(&placed) {
            assert!(o.name.starts_with(p.kind), "{} {}", o.name, p.kind);
            assert!(p.anchor >= path.len() / 2 && p.anchor < path.len());
            let a = path[p.anchor];
            let proj = o
                .shape
                .project_point(&o.parry_pose, PVec::new(a[0], a[1], a[2]), true);
            assert!(!proj.is_inside, "seed {seed}: {} holds its anchor", o.name);
            let q = proj.point;
            let d = ((q.x - a[0]).powi(2) + (q.y - a[1]).powi(2) + (q.z - a[2]).powi(2)).sqrt();
            worst = worst.max((d - p.gap).abs());
            assert!((0.004..=0.018).contains(&p.gap));
            *kinds.entry(p.kind).or_insert(0) += 1;
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!("kinds {kinds:?}, |distance − placed gap| ≤ {worst:.1e} m");
    assert!(worst < 1e-12, "{worst}");
    assert!(
        kinds.len() == 3 && kinds.values().all(|&n| n > 50),
        "{kinds:?}"
    );
}

/// Paper case I, the literal method's solver, its shape without obstacles and that shape's
/// disk centres (the path the scene generator places obstacles near).
fn case1_free() -> (Model, Solver, Shape, Vec<[f64; 3]>) {
    let model = Model::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/models/paper/case1.toml"
    ))
    .unwrap();
    let solver = SolveRequest::new(MethodKind::Geometric).solver().unwrap();
    let free = solver
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    let path: Vec<[f64; 3]> = free.disks.iter().map(|d| d.position.into()).collect();
    (model, solver, free, path)
}

/// The scenes of `scene_speed` (seeds 1–60; 37 and 42 put a wall through the base disk before
/// the generator kept its obstacles off it) are valid inputs: the literal method is never
/// refused as obstructed in section 0 (the broad phase's base-disk check, independent of the
/// generator's).
#[test]
fn generated_scenes_leave_the_base_disk_free() {
    let (model, solver, _, path) = case1_free();
    let dir = std::env::temp_dir().join(format!("ccrkit-base-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for seed in 1..=60 {
        let file = dir.join(format!("gen_{seed}.toml"));
        std::fs::write(&file, near_path(&path, seed).0).unwrap();
        let scene = Scene::from_file(&file).unwrap();
        let answer = solver.solve(&model.robot, &model.actuation, &scene, None);
        if let Err(e) = &answer {
            assert!(!e.to_string().contains("section 0"), "seed {seed}: {e}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A generated scene whose search judged every taut set by its lowest certified candidate and
/// found none with every cable pulling (seed 52: `NotConverged`, section 9) is solved by a
/// higher certified minimum that passes the pull-only check. Checked on the answer's own
/// geometry, not the solver's: each cable's path through the disks is no longer than its
/// length less its shortening (taut ones equal to it, to 1e-9 m), every contact presses
/// (multiplier ≥ 0) and is at the clearance; seeds 1 and 13, solved before, hold the same
/// checks. (Seeds 5, 16 and 57 still fail: not one of their certified candidates, the lowest
/// of its set or not, has every cable pulling.)
#[test]
fn every_taut_set_minimum_is_judged_not_only_the_lowest() {
    let (model, solver, free, path) = case1_free();
    // Case I's cables run straight and parallel to the backbone when unbent: their rest length
    // is the robot's.
    let rest = free.disks.last().unwrap().s;
    let dir = std::env::temp_dir().join(format!("ccrkit-pulling-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for seed in [1, 13, 52] {
        let file = dir.join(format!("gen_{seed}.toml"));
        std::fs::write(&file, near_path(&path, seed).0).unwrap();
        let scene = Scene::from_file(&file).unwrap();
        let shape = solver
            .solve(&model.robot, &model.actuation, &scene, None)
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert!(shape.report.converged, "seed {seed}");
        for c in &shape.cables {
            let len: f64 = c.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
            let short = c.shortening.unwrap();
            let excess = len - (rest - short);
            assert!(
                excess <= 1e-9,
                "seed {seed}: cable {} stretched by {excess}",
                c.name
            );
            if !c.slack {
                assert!(
                    excess.abs() <= 1e-9,
                    "seed {seed}: taut {} off by {excess}",
                    c.name
                );
            }
        }
        assert!(!shape.contacts.is_empty(), "seed {seed}: no contact");
        for k in &shape.contacts {
            assert!(k.multiplier >= 0.0, "seed {seed}: {k:?}");
            assert!(k.distance.abs() <= 1e-9, "seed {seed}: {k:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The literal method's runs that circle a kink beside an obstacle are given up
/// (`MAX_KINK_CROSSINGS`), and its contact steps take the exact Newton–KKT step on the QP's
/// active set where that solves the SQP's own QP: generated scene 13 (the most Newton
/// iterations of seeds 1–20) took 620 iterations before, three runs of sections 6 and 7 spending
/// their 40 on a tangent kink they never reached, and takes 446 now. The count is deterministic
/// (the search is); the bound leaves room for rounding to move a line search. The answer is
/// checked on its own geometry as above: contacts press at the clearance, no cable stretched.
#[test]
fn kink_circling_runs_are_given_up() {
    let (model, solver, free, path) = case1_free();
    let rest = free.disks.last().unwrap().s;
    let dir = std::env::temp_dir().join(format!("ccrkit-kink-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("gen_13.toml");
    std::fs::write(&file, near_path(&path, 13).0).unwrap();
    let scene = Scene::from_file(&file).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let shape = solver
        .solve(&model.robot, &model.actuation, &scene, None)
        .unwrap();
    assert!(shape.report.converged);
    let it = shape.report.iterations;
    assert!(it <= 470, "{it} Newton iterations (620 before)");
    for c in &shape.cables {
        let len: f64 = c.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        assert!(len - (rest - c.shortening.unwrap()) <= 1e-9, "{}", c.name);
    }
    assert!(!shape.contacts.is_empty());
    for k in &shape.contacts {
        assert!(k.multiplier >= 0.0 && k.distance.abs() <= 1e-9, "{k:?}");
    }
}
