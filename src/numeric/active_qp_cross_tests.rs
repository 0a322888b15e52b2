//! The exact 6-unknown QP step (`qp6_active_set`, a dual active set) against its KKT
//! conditions and against clarabel's interior point, on seeded random QPs: generic ones,
//! degenerate ones (duplicated inequality rows, rows active at the minimizer with a zero
//! multiplier, a row that is a combination of others) and infeasible ones (which it must call
//! infeasible, and clarabel must not solve).

use super::{qp6_active_set, Qp6};
use crate::numeric::qp::{clamped_hessian, qp_step6_clarabel};
use crate::numeric::test_rng::Rng;
use nalgebra::{Matrix6, Vector6};

fn vec6(rng: &mut Rng, s: f64) -> Vector6<f64> {
    Vector6::from_fn(|_, _| rng.range(-s, s))
}

/// A QP: P, g, equality rows and right-hand sides, inequality rows and right-hand sides.
type Qp = (
    Matrix6<f64>,
    Vector6<f64>,
    Vec<Vector6<f64>>,
    Vec<f64>,
    Vec<Vector6<f64>>,
    Vec<f64>,
);

/// A random QP feasible at a random point `x0` (slacks ≥ 0, some exactly 0); `kind` 1 adds
/// degeneracy, 2 makes it infeasible.
fn random_qp(rng: &mut Rng, kind: u32) -> Qp {
    let b = Matrix6::from_fn(|_, _| rng.range(-1.0, 1.0));
    let scale = 10f64.powf(rng.range(-2.0, 2.0));
    let h = (b * b.transpose() + Matrix6::identity() * rng.range(1e-3, 1.0)) * scale;
    let g = vec6(rng, 1.0);
    let x0 = vec6(rng, 0.01);
    let ne = (rng.next() * 4.0) as usize;
    let ni = 1 + (rng.next() * 6.0) as usize;
    let eq: Vec<Vector6<f64>> = (0..ne).map(|_| vec6(rng, 1.0)).collect();
    let e: Vec<f64> = eq.iter().map(|r| r.dot(&x0)).collect();
    let mut gi: Vec<Vector6<f64>> = (0..ni).map(|_| vec6(rng, 1.0)).collect();
    let mut hi: Vec<f64> = gi
        .iter()
        .map(|r| {
            r.dot(&x0)
                + if rng.next() < 0.3 {
                    0.0
                } else {
                    rng.range(0.0, 0.01)
                }
        })
        .collect();
    match kind {
        1 => {
            // A duplicated row, and a row that is the sum of two others with the sum of their
            // right-hand sides (implied, never binding alone).
            gi.push(gi[0]);
            hi.push(hi[0]);
            if ni >= 2 {
                gi.push(gi[0] + gi[1]);
                hi.push(hi[0] + hi[1]);
            }
        }
        2 => {
            // a·x ≤ a·x0 − δ and −a·x ≤ −a·x0 − δ: no x meets both.
            let a = vec6(rng, 1.0);
            let delta = rng.range(1e-6, 1e-2);
            gi.push(a);
            hi.push(a.dot(&x0) - delta);
            gi.push(-a);
            hi.push(-a.dot(&x0) - delta);
        }
        _ => {}
    }
    (h, g, eq, e, gi, hi)
}

/// The KKT conditions of the solved QP, to rounding relative to the problem's size.
fn check_kkt(qp: &Qp, x: &Vector6<f64>, lam: &[f64], mu: &[f64], case: usize) {
    check_kkt_to(qp, x, lam, mu, case, 1e-14);
}

/// [`check_kkt`] with the rows' feasibility and complementarity to `tol` (a minimizer solved
/// from another of its active sets rounds otherwise).
fn check_kkt_to(qp: &Qp, x: &Vector6<f64>, lam: &[f64], mu: &[f64], case: usize, tol: f64) {
    let (h, g, eq, e, gi, hi) = qp;
    let mut stat = h * x + g;
    for (r, l) in eq.iter().zip(lam) {
        stat += r * *l;
    }
    for (r, m) in gi.iter().zip(mu) {
        stat += r * *m;
    }
    let size = (h * x).amax() + g.amax() + 1.0;
    assert!(
        stat.amax() <= 1e-11 * size,
        "case {case}: stationarity {}",
        stat.amax()
    );
    for (r, v) in eq.iter().zip(e) {
        assert!((r.dot(x) - v).abs() <= tol, "case {case}: equality");
    }
    for ((r, v), m) in gi.iter().zip(hi).zip(mu) {
        let s = r.dot(x) - v;
        assert!(s <= tol, "case {case}: inequality violated by {s}");
        assert!(*m >= 0.0, "case {case}: multiplier {m}");
        assert!(
            (m * s).abs() <= tol * (1.0 + m),
            "case {case}: complementarity"
        );
    }
}

#[test]
fn active_set_qp_matches_kkt_and_clarabel() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut solved, mut infeasible, mut worst) = (0, 0, 0.0f64);
    for case in 0..360 {
        let kind = (case % 3) as u32;
        let qp = random_qp(&mut rng, kind);
        let (h, g, eq, e, gi, hi) = &qp;
        let hp = clamped_hessian(h, 1e-10);
        let ipm = qp_step6_clarabel(&hp, g, eq, e, gi, hi);
        match qp6_active_set(&hp, g, eq, e, gi, hi) {
            Qp6::Solved(step, active) => {
                assert_ne!(kind, 2, "case {case}: an infeasible QP was solved");
                check_kkt(&qp, &step.x, &step.lambda_eq, &step.mu, case);
                for (i, m) in step.mu.iter().enumerate() {
                    assert!(*m == 0.0 || active.contains(&i), "case {case}: inactive μ");
                }
                let ipm = ipm.unwrap_or_else(|| panic!("case {case}: clarabel failed"));
                let d = (step.x - ipm.x).amax() / (1e-3 + step.x.amax());
                worst = worst.max(d);
                assert!(d < 1e-5, "case {case}: differs from clarabel by {d}");
                solved += 1;
            }
            Qp6::Infeasible => {
                assert_eq!(kind, 2, "case {case}: a feasible QP called infeasible");
                assert!(ipm.is_none(), "case {case}: clarabel solved it");
                infeasible += 1;
            }
            Qp6::Undecided => panic!("case {case}: undecided with independent equalities"),
        }
    }
    assert_eq!((solved, infeasible), (240, 120));
    eprintln!("largest relative difference from clarabel: {worst:.1e}");
}

/// Dependent equality rows: no claim (the caller falls back to clarabel), not a guess.
#[test]
fn dependent_equalities_are_undecided() {
    let mut rng = Rng(7);
    let a = vec6(&mut rng, 1.0);
    let r = qp6_active_set(
        &Matrix6::identity(),
        &vec6(&mut rng, 1.0),
        &[a, 2.0 * a],
        &[0.1, 0.2],
        &[vec6(&mut rng, 1.0)],
        &[0.0],
    );
    assert!(matches!(r, Qp6::Undecided), "{r:?}");
}

/// min ½|x|² − x₀ s.t. x₀ ≤ 0.25: x₀ = 0.25, multiplier 0.75 exactly (closed form).
#[test]
fn one_active_bound_in_closed_form() {
    let mut g = Vector6::zeros();
    g[0] = -1.0;
    let mut row = Vector6::zeros();
    row[0] = 1.0;
    let Qp6::Solved(s, active) = qp6_active_set(
        &Matrix6::identity(),
        &g,
        &[],
        &[],
        &[row, -row],
        &[0.25, 1.0],
    ) else {
        panic!("not solved");
    };
    assert_eq!(active, vec![0]);
    assert!((s.x[0] - 0.25).abs() < 1e-15 && (s.mu[0] - 0.75).abs() < 1e-15);
    assert_eq!(s.mu[1], 0.0);
}

/// The warm start changes nothing but the work: on the random QPs (generic, degenerate,
/// infeasible), started from the cold solve's own active set, from that set reversed, from a
/// random subset of the rows and from a guess with a repeated or out-of-range row, the answer
/// is the cold one to rounding (the KKT conditions, and the same minimizer) and an infeasible
/// QP stays infeasible; from its own active set it takes the one-solve path and returns that
/// set, and wherever it ends on the cold solve's set its answer is the cold one to the bit.
#[test]
fn warm_start_gives_the_cold_answer() {
    use super::qp6_warm;
    let mut rng = Rng(0x51_7cc1_b727_220a);
    let (mut same_set, mut checked, mut different) = (0, 0, 0);
    for case in 0..360 {
        let kind = (case % 3) as u32;
        let qp = random_qp(&mut rng, kind);
        let (h, g, eq, e, gi, hi) = &qp;
        let hp = clamped_hessian(h, 1e-10);
        let cold = qp6_active_set(&hp, g, eq, e, gi, hi);
        let subset: Vec<usize> = (0..gi.len()).filter(|_| rng.next() < 0.4).collect();
        let (own, reversed) = match &cold {
            Qp6::Solved(_, a) => (a.clone(), a.iter().rev().copied().collect()),
            _ => (vec![], vec![]),
        };
        let guesses = [own.clone(), reversed, subset, vec![0, 0], vec![gi.len()]];
        for guess in guesses {
            let warm = qp6_warm(&hp, g, (eq, e), (gi, hi), &guess);
            match (&cold, &warm) {
                (Qp6::Solved(c, ca), Qp6::Solved(w, active)) => {
                    if ca == active {
                        // The same set: the same bits.
                        assert_eq!((c.x, &c.mu), (w.x, &w.mu), "case {case}");
                    } else {
                        // Another set of the same minimizer (a duplicated row in place of
                        // its twin, a row held at a zero multiplier): the same point.
                        assert!(w.mu.iter().all(|m| *m >= 0.0), "case {case}");
                        different += 1;
                    }
                    check_kkt_to(&qp, &w.x, &w.lambda_eq, &w.mu, case, 1e-12);
                    let d = (c.x - w.x).amax() / (1e-3 + c.x.amax());
                    assert!(d < 1e-9, "case {case}: warm differs from cold by {d}");
                    if guess == own && !own.is_empty() {
                        assert_eq!(active, &own, "case {case}");
                        same_set += 1;
                    }
                    checked += 1;
                }
                (Qp6::Infeasible, Qp6::Infeasible) => {}
                _ => panic!("case {case}: cold {cold:?}, warm {warm:?} from {guess:?}"),
            }
        }
    }
    eprintln!("{checked} warm solves, {different} on another set of the same minimizer");
    assert!(same_set > 100 && checked > 1000, "{same_set} {checked}");
}
