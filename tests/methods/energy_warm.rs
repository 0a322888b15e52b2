//! Warm starts of the energy model are never worse than cold ones: on the paper cases a solve
//! started from the solution of a nearby actuation (2 % and 10 % smaller shortenings) takes no
//! more Newton iterations than the same solve from the straight robot, and reaches the same
//! shape. (Speed itself is measured by `cargo bench --bench energy`, pairs `cold` / `warm-2pct`.)
//! A method prepared once for a robot ([`Method::prepare`]: the routing samples computed
//! once) solves exactly as the one-off solve does.

use crate::common::paper;
use ccrkit::method::energy::Energy;
use ccrkit::method::WarmState;
use ccrkit::{Method, Scene, Shape};

#[test]
fn warm_starts_take_no_more_iterations_than_cold() {
    let scene = Scene::empty();
    let method = Energy::default();
    for case in 1..=3 {
        let model = paper(case);
        let cold = method
            .solve(&model.robot, &model.actuation, &scene, None)
            .expect("cold solve");
        for frac in [0.98, 0.9] {
            let before = method
                .solve(&model.robot, &model.actuation.scaled(frac), &scene, None)
                .expect("previous solve");
            let warm = method
                .solve(&model.robot, &model.actuation, &scene, Some(&before))
                .expect("warm solve");
            println!(
                "case {case}, warm from {frac}: cold {} iterations, warm {}",
                cold.report.iterations, warm.report.iterations
            );
            assert!(
                warm.report.iterations <= cold.report.iterations,
                "case {case} from {frac}: warm {} > cold {} iterations",
                warm.report.iterations,
                cold.report.iterations
            );
            let (a, b) = (cold.tip(), warm.tip());
            assert!((a - b).norm() < 1e-9, "case {case}: tips {a} vs {b}");
        }
    }
}

/// Solves through [`Method::prepare`] (reused across actuations, warm starts and scenes) are
/// bit for bit those of [`Method::solve`].
#[test]
fn prepared_solves_equal_one_off_solves() {
    let wall = Scene::from_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/models/scenes/wall.toml"
    ))
    .expect("wall");
    for case in 1..=3 {
        let model = paper(case);
        let method = Energy::default();
        let prepared = method.prepare(&model.robot).expect("prepare");
        let mut prev = None;
        for frac in [0.5, 0.98, 1.0] {
            let act = model.actuation.scaled(frac);
            for scene in [Scene::empty(), wall.clone()] {
                if case > 1 && !scene.is_empty() {
                    continue;
                }
                // Warm from the last obstacle-free shape (which may cross the wall: cold there).
                let warm = if scene.is_empty() {
                    prev.as_ref()
                } else {
                    None
                };
                let a = method.solve(&model.robot, &act, &scene, warm);
                let b = prepared.solve(&act, &scene, warm);
                let (a, b) = (a.expect("one-off"), b.expect("prepared"));
                assert_eq!(a.disks, b.disks, "case {case} at {frac}");
                assert_eq!(a.report.iterations, b.report.iterations);
                assert_eq!(a.report.residual, b.report.residual);
                if scene.is_empty() {
                    prev = Some(b);
                }
            }
        }
    }
}

/// `shape` with its energy warm state's Hessian blocks dropped (a warm start from it rebuilds
/// them); panics if `shape` kept none (`what` names it).
fn without_hessian(shape: &Shape, what: &str) -> Shape {
    let mut stripped = shape.clone();
    match &mut stripped.report.warm {
        Some(WarmState::Energy(e)) => {
            assert!(e.hessian.is_some(), "{what}: no Hessian kept");
            e.hessian = None;
        }
        other => panic!("{what}: warm state {other:?}"),
    }
    stripped
}

/// A warm start takes its first Hessian from the blocks its shape carries (the last ones of
/// that solve) instead of rebuilding them: the same numbers, so the warm solve equals, to the
/// bit, the one from the same shape without them (paper cases, from 2 % less shortening).
#[test]
fn carried_hessian_is_the_rebuilt_one() {
    let scene = Scene::empty();
    let method = Energy::default();
    for case in 1..=3 {
        let model = paper(case);
        let before = method
            .solve(&model.robot, &model.actuation.scaled(0.98), &scene, None)
            .expect("previous solve");
        let stripped = without_hessian(&before, &format!("case {case}"));
        let with = method
            .solve(&model.robot, &model.actuation, &scene, Some(&before))
            .expect("warm solve");
        let without = method
            .solve(&model.robot, &model.actuation, &scene, Some(&stripped))
            .expect("warm solve without the blocks");
        assert_eq!(with.disks, without.disks, "case {case}");
        assert_eq!(with.report.iterations, without.report.iterations);
        assert_eq!(with.report.residual, without.report.residual);
    }
}

/// A warm state carries Hessian blocks built with its robot's cable routing: two robots that
/// differ only in one cable's hole angles have the same strains, weights and stiffness, and
/// the other robot's blocks must not be taken. Robot B warm-started from robot A's solve equals,
/// to 1e-12 m, B warm-started from the same state without the blocks (which rebuilds them), and
/// ends where B's cold solve ends (to the solver's tolerance).
#[test]
fn warm_hessian_of_another_routing_is_rebuilt() {
    let scene = Scene::empty();
    let method = Energy::default();
    let a = paper(2);
    let mut b = a.clone();
    for angle in &mut b.robot.cables[0].angle {
        *angle += 0.3;
    }
    let from_a = method
        .solve(&a.robot, &a.actuation, &scene, None)
        .expect("robot A");
    let stripped = without_hessian(&from_a, "robot A");
    let with = method
        .solve(&b.robot, &b.actuation, &scene, Some(&from_a))
        .expect("B warm from A");
    let rebuilt = method
        .solve(&b.robot, &b.actuation, &scene, Some(&stripped))
        .expect("B warm from A without the blocks");
    let cold = method
        .solve(&b.robot, &b.actuation, &scene, None)
        .expect("B cold");
    let gap = |x: &ccrkit::Shape, y: &ccrkit::Shape| {
        x.disks
            .iter()
            .zip(&y.disks)
            .map(|(p, q)| (p.position - q.position).norm())
            .fold(0.0, f64::max)
    };
    assert!(
        gap(&with, &rebuilt) <= 1e-12,
        "{:e} m",
        gap(&with, &rebuilt)
    );
    assert_eq!(with.report.iterations, rebuilt.report.iterations);
    assert!(
        gap(&with, &cold) <= 1e-8,
        "{:e} m from cold",
        gap(&with, &cold)
    );
}
