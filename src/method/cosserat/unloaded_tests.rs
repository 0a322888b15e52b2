//! Tests of the unloaded and loaded passes' point solves (`unloaded.rs`): the remainder bound
//! a point is taken on, and the Magnus step.

use super::*;
use crate::method::cosserat::Cosserat;
use crate::method::Method;
use crate::model::Model;

/// The remainder bound ([`At::quadratic`]) against the balance evaluated again: on case
/// I's first section, from the strains there moved by a range of sizes, a point taken
/// after one evaluation has a balance no larger than the residual returned and the
/// evaluation's rounding, and within the tolerance (evaluated at
/// the strains returned, which then need no step) and its `|ṗ_c|` moved to first order
/// within 1e-12 of the evaluated ones; and some sizes that take two evaluations without
/// the bound are taken on it.
#[test]
fn a_point_taken_on_the_remainder_bound_meets_it() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/models/paper/case1.toml");
    let model = Model::from_file(path).expect("case I");
    for set in [Cosserat::full(), Cosserat::kirchhoff()] {
        let (prob, _) = set
            .problem(&model.robot, &model.actuation)
            .expect("problem");
        let mut tau = [0.0; MAX_CABLES];
        for (c, t) in tau.iter_mut().enumerate().take(prob.robot.cables.len()) {
            *t = 2.0 + c as f64;
        }
        let ld = LoadCase::new(tau, 1.0);
        let zero = Vector3::zeros();
        let (s, sec) = (0.5 * prob.robot.disk_s[1], 1);
        let straight = Strains { v: E3, u: zero };
        let mut plain = At::new([false; MAX_CABLES]);
        let found = prob.strains_at(s, sec, &ld, straight, (&zero, &zero), &mut plain);
        let (z, _) = found.expect("strains");
        let mut taken = 0;
        for size in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7] {
            let mut start = z;
            start.u += Vector3::new(1.0, -2.0, 0.5) * size;
            start.v += Vector3::new(-0.5, 1.0, 0.2) * (1e-3 * size);
            let mut at = At::new([false; MAX_CABLES]);
            at.quadratic = true;
            let before = prob.work.get();
            let got = prob.strains_at(s, sec, &ld, start, (&zero, &zero), &mut at);
            let (zq, bound) = got.expect("strains");
            if prob.work.get() - before != 1 {
                continue;
            }
            // Without the bound the same start takes a second evaluation?
            let mut checked = At::new([false; MAX_CABLES]);
            let before = prob.work.get();
            prob.strains_at(s, sec, &ld, start, (&zero, &zero), &mut checked);
            let on_bound = prob.work.get() - before >= 2;
            // One evaluation from there: the balance there, ≤ the tolerance if it ends.
            let mut again = At::new([false; MAX_CABLES]);
            let before = prob.work.get();
            let got = prob.strains_at(s, sec, &ld, zq, (&zero, &zero), &mut again);
            let (_, residual) = got.expect("strains");
            assert_eq!(prob.work.get() - before, 1, "{} size {size}", set.name());
            // (Plus the evaluation's rounding: `Kse (v − e3)` with `v ≈ e3`.)
            let floor = 4.0 * f64::EPSILON * (prob.kse.amax() + tau.iter().sum::<f64>());
            assert!(
                residual <= bound + floor,
                "{residual:e} > {bound:e} + {floor:e}"
            );
            assert!(residual <= set.tolerance, "{residual:e}");
            for c in 0..prob.robot.cables.len() {
                let gap = (at.lr[c] - again.lr[c]).abs();
                assert!(
                    gap <= 1e-12,
                    "{} size {size}: |ṗ| off by {gap:e}",
                    set.name()
                );
            }
            taken += usize::from(on_bound);
        }
        assert!(taken >= 1, "{}: no size taken on the bound", set.name());
    }
}

#[test]
fn magnus_is_exact_for_a_constant_twist() {
    // A helix: constant v, u. Ten small steps equal one big one (the exponential's group law).
    let z = Strains {
        v: Vector3::new(0.01, -0.02, 1.03),
        u: Vector3::new(3.0, -1.0, 2.0),
    };
    let (p1, r1) = magnus_step(0.5, &z, &z);
    let (mut p, mut r) = (Vector3::zeros(), Matrix3::identity());
    for _ in 0..10 {
        let (dp, dr) = magnus_step(0.05, &z, &z);
        p += r * dp;
        r *= dr;
    }
    assert!((p - p1).norm() < 1e-14, "{p} vs {p1}");
    assert!((r - r1).norm() < 1e-14);
    assert!((r1.transpose() * r1 - Matrix3::identity()).norm() < 1e-14);
}
