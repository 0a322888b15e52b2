//! Convergence of the SQP loop next to obstacles: with the contact curvature in the Hessian
//! the residual falls superlinearly.

use super::{dot, Sqp};
use crate::method::energy::Energy;
use crate::model::scene::Scene;
use crate::model::Model;

/// The residual history of the energy solve of case I in `scene`.
fn history(scene: &str) -> Vec<f64> {
    let dir = env!("CARGO_MANIFEST_DIR");
    let mut model = Model::from_file(format!("{dir}/models/paper/case1.toml")).expect("case 1");
    model.scene = Scene::from_file(format!("{dir}/models/scenes/{scene}.toml")).expect("scene");
    let set = Energy::default();
    let prob = set
        .setup(&model.robot, &model.actuation, &model.scene)
        .expect("problem");
    let sol = set.newton(&prob, None).expect("converges");
    assert!(!sol.contacts.is_empty(), "{scene}: no contact");
    sol.history
}

/// Steps from `r_k` to `r_{k+1}` with `r_{k+1} ≤ r_k^1.5` (superlinear; a linear rate would
/// need `r_{k+1} ≤ c r_k`) over the final iterations: after the last residual above `from`,
/// while above `floor`. Returns how many steps were checked.
fn assert_superlinear(h: &[f64], from: f64, floor: f64) -> usize {
    let start = h.iter().rposition(|&r| r >= from).map_or(0, |i| i + 1);
    let mut steps = 0;
    for w in h[start..].windows(2) {
        if w[0] > floor {
            assert!(w[1] <= w[0].powf(1.5), "{:e} → {:e} in {h:?}", w[0], w[1]);
            steps += 1;
        }
    }
    steps
}

/// The wall: a disk rim against a box face; quadratic to round-off.
#[test]
fn wall_converges_superlinearly() {
    let h = history("wall");
    assert!(assert_superlinear(&h, 1e-2, 0.0) >= 3, "{h:?}");
    assert!(*h.last().expect("iterations") <= 1e-10, "{h:?}");
    assert!(h.len() <= 10, "{} iterations: {h:?}", h.len());
}

/// The pillar: two disk rims against a cylinder; superlinear down to round-off, and to
/// ~1e-12 since a pair near touching is queried from its old normal (no EPA
/// answer, whose normal was off by ~1e-5 rad: the old floor of a few 1e-10). Five iterations
/// since the step guard knows the exact distance to the cylinder (`energy/step_guard.rs`).
#[test]
fn pillar_converges_superlinearly() {
    let h = history("pillar");
    assert!(assert_superlinear(&h, 1e-1, 1e-10) >= 2, "{h:?}");
    assert!(*h.last().expect("iterations") <= 1e-12, "{h:?}");
    assert!(h.len() <= 6, "{} iterations: {h:?}", h.len());
}

/// The penalty that makes the Hessian with contact curvature positive definite
/// (`newton/curved.rs`) leaves the step's QP solution unchanged: every penalized contact row
/// the step keeps pressing (multiplier > 0 after [`Sqp::unpenalize`]) is met by the step,
/// `c + aᵀd = 0`, also for a pair not yet touching (`c ≠ 0`). Random dense scene 5 of
/// `tests/contact/dense_scenes.rs` (written to `tests/data/dense_scene5.json`) has such pairs: with
/// the Hessian term alone a disk 0.44 mm short of a sphere was closed by 16 µm per step.
#[test]
fn penalized_rows_the_step_keeps_are_met() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let mut model = Model::from_file(format!("{dir}/models/paper/case1.toml")).expect("case 1");
    model.scene = Scene::from_file(format!("{dir}/tests/data/dense_scene5.json")).expect("scene 5");
    let set = Energy::default();
    let prob = set
        .setup(&model.robot, &model.actuation, &model.scene)
        .expect("problem");
    let mut sqp = Sqp::new(&prob, set.start_point(&prob, None));
    let (mut apart, mut iterations) = (0, 0);
    for it in 0..=set.max_iterations {
        sqp.linearize();
        let r = sqp.residuals();
        if r.feas.max(r.gap).max(r.stat) <= 1e-6 {
            iterations = it;
            break;
        }
        sqp.factor().expect("factor");
        let lam = sqp.dual_step().expect("step");
        let nc = sqp.cable_rows.len();
        for &(row, _) in &sqp.penalty {
            let p = &sqp.pairs[row - nc];
            let c = sqp.clearance - p.dist;
            let met = c - dot(&p.grad, &sqp.dxi);
            if lam[row] > 0.0 {
                assert!(
                    met.abs() <= 1e-12 + 1e-9 * c.abs(),
                    "it {it}: c {c:e}, c + aᵀd {met:e}"
                );
                apart += usize::from(c.abs() > 1e-6);
            }
        }
        let alpha = sqp.line_search(&lam);
        sqp.take_step(alpha, &lam);
    }
    assert!(
        apart > 0,
        "no penalized pressing row off its face: the case is not exercised"
    );
    assert!((1..=13).contains(&iterations), "{iterations} iterations");
}
