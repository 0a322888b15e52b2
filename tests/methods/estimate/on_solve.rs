//! `--estimate` (`SolveRequest::with_estimate`) on `energy` answers: the discretization part
//! read from the answer alone (no extra solve) where it applies, against the true
//! discretization error (the same model at 32 sub-arcs); elsewhere an extra solve, with the
//! reason in the estimate.

use ccrkit::method::estimate::A_PRIORI;
use ccrkit::prelude::*;
use ccrkit::study::random::random_model;

/// `energy` at `k` sub-arcs, estimated or not.
fn energy(model: &Model, k: usize, estimate: bool) -> Option<ccrkit::Shape> {
    SolveRequest::new(MethodKind::Energy)
        .with_settings(Settings::new().with("sub-arcs", k))
        .with_estimate(estimate)
        .run(model)
        .ok()
        .map(|s| s.shape)
}

/// On seeded random robots not calibrated on, every estimated `energy` answer is read from
/// its own strains (no fallback, no failure), and its discretization part bounds the distance
/// to the refined solve in ≥ 99 % of answers (the study: 100 % against the converged rod).
#[test]
fn energy_estimates_need_no_extra_solve_and_bound_the_refined_error() {
    let (mut held, mut total) = (0, 0);
    for seed in 4000..4040 {
        let model = random_model(seed).expect("valid by construction");
        let Some(fine) = energy(&model, 32, false) else {
            continue;
        };
        for k in [1, 2, 4] {
            let Some(shape) = energy(&model, k, true) else {
                continue;
            };
            let e = shape.report.error_estimate.as_ref().expect("asked for");
            assert_eq!(e.against, A_PRIORI, "seed {seed}, {k} sub-arcs: {e:?}");
            assert!(e.fallback.is_empty() && e.failed.is_empty(), "{e:?}");
            let disc = e.discretization_m.expect("read from the answer");
            let truth = shape.tip_distance(&fine);
            total += 1;
            if truth <= disc.max(1e-9) {
                held += 1;
            } else {
                println!("seed {seed}, {k} sub-arcs: error {truth:.3e} m > estimate {disc:.3e} m");
            }
        }
    }
    println!("the a-priori part bounds the refined error in {held} of {total} answers");
    assert!(total >= 100, "only {total} answers");
    assert!(100 * held >= 99 * total, "{held} of {total}");
}

/// Where the a-priori part does not apply, the estimate says why and measures it by an extra
/// solve: with contacts (paper case I pressed on the wall), and with chord cable lengths.
#[test]
fn fallbacks_name_their_reason() {
    let case1 = Model::from_file("models/paper/case1.toml").expect("case I");
    let case2 = Model::from_file("models/paper/case2.toml").expect("case II");
    let wall = Scene::from_file("models/scenes/wall.toml").expect("the wall");
    let cases = [
        (&case1, Some(wall), Settings::new(), "energy with contacts"),
        (
            &case2,
            None,
            Settings::new().with("length", "chord"),
            "energy with chord cable lengths",
        ),
    ];
    for (model, scene, s, why) in cases {
        let shape = SolveRequest::new(MethodKind::Energy)
            .with_settings(s)
            .with_scene(scene)
            .with_estimate(true)
            .run(model)
            .expect("solves")
            .shape;
        let e = shape.report.error_estimate.expect("asked for");
        assert!(e.fallback.contains(why), "{e:?}");
        assert_eq!(e.against, "sub-arcs=3", "{e:?}");
        assert!(e.discretization_m.is_some() && e.failed.is_empty(), "{e:?}");
    }
}

/// Through a port the estimate is read from the answer alone too.
#[test]
fn port_answers_are_estimated_a_priori() {
    let port = Model::from_file("models/port/behind_block.toml").expect("port model");
    let shape = SolveRequest::new(MethodKind::Energy)
        .with_estimate(true)
        .run(&port)
        .expect("solves")
        .shape;
    assert!(shape.contacts.is_empty(), "the block is not touched");
    let e = shape.report.error_estimate.expect("asked for");
    assert_eq!(e.against, A_PRIORI, "{e:?}");
    assert!(e.fallback.is_empty(), "{e:?}");
}
