//! The 6-unknown QP step of [`super::qp::qp_step6`] solved exactly: a dual active-set method
//! (Goldfarb & Idnani, "A numerically stable dual method for solving strictly convex quadratic
//! programs", *Math. Programming* 27, 1983), each inner solve the equality-constrained KKT
//! system of the current active set.
//!
//! `min ½ xᵀ P x + gᵀ x  s.t.  E x = e,  G x ≤ h` with `P` positive definite (the caller clamps
//! its eigenvalues). The method starts at the minimizer under the equalities alone (dual
//! feasible: no inequality multiplier yet) and adds one violated inequality `p` at a time.
//! With `N` the active rows, `(x, u)` the current point and multipliers
//! (`P x + g + Nᵀ u = 0`, `N x = b_N`), raising the new multiplier `t` moves them along
//! `[P Nᵀ; N 0] [z; r] = [−a_p; 0]` (`x + t z`, `u + t r`), which keeps the active rows and
//! the stationarity; `a_pᵀ z = −zᵀ P z < 0` unless `a_p` depends on `N` (`z = 0`). The step is
//! the smaller of the full step (`p` met with equality: `t = (a_pᵀ x − h_p) / zᵀ P z`) and the
//! partial step at which an active inequality's multiplier reaches 0 (that row is dropped and
//! `p` pursued further). When `a_p` depends on `N` and no active inequality's multiplier falls
//! (`r ≥ 0`), `a_p = −Nᵀ r` proves `G x ≤ h, E x = e` infeasible (Farkas). Each iteration
//! raises the dual objective strictly, so no active set repeats and the method ends in
//! finitely many steps (Goldfarb & Idnani, Thm 1). At the end the point is solved again from
//! the final active set's KKT system, so it is the exact minimizer to rounding.

use super::qp::QpStep;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

/// What [`qp6_active_set`] found.
#[derive(Debug, Clone)]
pub enum Qp6 {
    /// The minimizer with its multipliers (and the active inequality rows).
    Solved(QpStep, Vec<usize>),
    /// The constraints admit no point (a Farkas certificate was met).
    Infeasible,
    /// The equality rows are dependent, a KKT solve failed, or the iteration limit was met:
    /// no claim either way.
    Undecided,
}

/// Two rows whose Gram–Schmidt remainder (row-normalized) has `ρ² ≤` this are dependent: the
/// threshold of [`crate::numeric::kkt::RANK_TOL`].
const DEPENDENT: f64 = crate::numeric::kkt::RANK_TOL;

/// Solve the QP (see the module docs); `p` must be symmetric positive definite.
pub fn qp6_active_set(
    p: &Matrix6<f64>,
    g: &Vector6<f64>,
    eq_rows: &[Vector6<f64>],
    eq_rhs: &[f64],
    in_rows: &[Vector6<f64>],
    in_rhs: &[f64],
) -> Qp6 {
    let ne = eq_rows.len();
    if ne > 6 || !independent(eq_rows) {
        return Qp6::Undecided;
    }
    let mut active: Vec<usize> = vec![];
    let Some((mut x, y0)) = kkt_solve(p, g, eq_rows, eq_rhs, in_rows, in_rhs, &active) else {
        return Qp6::Undecided;
    };
    // Whether `x` is still the solve on the current active set (nothing added yet).
    let mut fresh = true;
    // Multipliers of the active inequalities, in the order of `active`.
    let mut u: Vec<f64> = vec![];
    for _ in 0..10 * (in_rows.len() + 1) + 20 {
        // The most violated inequality, relative to the size of its terms.
        let worst = (0..in_rows.len())
            .filter(|i| !active.contains(i))
            .map(|i| {
                let ax = in_rows[i].dot(&x);
                let scale = in_rows[i].abs().dot(&x.abs()) + in_rhs[i].abs();
                (
                    i,
                    (ax - in_rhs[i]) / in_rows[i].norm(),
                    ax - in_rhs[i] > 1e-13 * scale,
                )
            })
            .filter(|&(_, _, violated)| violated)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((ip, _, _)) = worst else {
            // Primal feasible and dual feasible: the minimizer. Solve it once more from the
            // final active set, so it carries no accumulated rounding.
            if fresh {
                return finish(x, &y0, ne, in_rows.len(), &active);
            }
            return match kkt_solve(p, g, eq_rows, eq_rhs, in_rows, in_rhs, &active) {
                Some((x, y)) => finish(x, &y, ne, in_rows.len(), &active),
                None => Qp6::Undecided,
            };
        };
        let a_p = in_rows[ip];
        let mut t_p = 0.0;
        fresh = false;
        // Pursue `p` until it is met (added) or proved unreachable.
        loop {
            let rows: Vec<Vector6<f64>> = eq_rows
                .iter()
                .copied()
                .chain(active.iter().map(|&i| in_rows[i]))
                .collect();
            let dependent = !independent_of(&rows, &a_p);
            let zero_rhs = vec![0.0; rows.len()];
            let Some((z, r)) = kkt_dir(p, &a_p, &rows, &zero_rhs) else {
                return Qp6::Undecided;
            };
            let viol = a_p.dot(&x) - in_rhs[ip];
            let curv = -a_p.dot(&z);
            let t_full = if dependent || curv <= 0.0 {
                f64::INFINITY
            } else {
                (viol / curv).max(0.0)
            };
            let mut t_part = f64::INFINITY;
            let mut drop = None;
            for (k, &uk) in u.iter().enumerate() {
                let rk = r[ne + k];
                if rk < 0.0 {
                    let t = uk / -rk;
                    if t < t_part {
                        t_part = t;
                        drop = Some(k);
                    }
                }
            }
            if t_full.is_infinite() && t_part.is_infinite() {
                return Qp6::Infeasible;
            }
            let t = t_full.min(t_part);
            if !dependent {
                x += z * t;
            }
            for (uk, rk) in u.iter_mut().zip(&r[ne..]) {
                *uk += t * rk;
            }
            t_p += t;
            match drop {
                Some(k) if t_part < t_full => {
                    active.remove(k);
                    u.remove(k);
                }
                _ => {
                    active.push(ip);
                    u.push(t_p);
                    break;
                }
            }
        }
    }
    Qp6::Undecided
}

/// The QP's step from the final active set's KKT solve; multipliers of inactive rows are 0.
fn finish(x: Vector6<f64>, y: &[f64], ne: usize, ni: usize, active: &[usize]) -> Qp6 {
    if x.iter().any(|v| !v.is_finite()) || y.iter().any(|v| !v.is_finite()) {
        return Qp6::Undecided;
    }
    let mut mu = vec![0.0; ni];
    for (k, &i) in active.iter().enumerate() {
        mu[i] = y[ne + k].max(0.0);
    }
    Qp6::Solved(
        QpStep {
            x,
            lambda_eq: y[..ne].to_vec(),
            mu,
        },
        active.to_vec(),
    )
}

/// The minimizer of `½ xᵀ P x + gᵀ x` with the equalities and the active inequalities held
/// with equality, and their multipliers (`P x + g + Nᵀ y = 0`): the KKT system by LU with full
/// pivoting. `None` when singular or not finite.
fn kkt_solve(
    p: &Matrix6<f64>,
    g: &Vector6<f64>,
    eq_rows: &[Vector6<f64>],
    eq_rhs: &[f64],
    in_rows: &[Vector6<f64>],
    in_rhs: &[f64],
    active: &[usize],
) -> Option<(Vector6<f64>, Vec<f64>)> {
    let rows: Vec<Vector6<f64>> = eq_rows
        .iter()
        .copied()
        .chain(active.iter().map(|&i| in_rows[i]))
        .collect();
    let rhs: Vec<f64> = eq_rhs
        .iter()
        .copied()
        .chain(active.iter().map(|&i| in_rhs[i]))
        .collect();
    kkt_dir(p, g, &rows, &rhs)
}

/// Solve `[P Nᵀ; N 0] [x; y] = [−a; b]` (rows of `N`: `rows`) by LU with full pivoting.
fn kkt_dir(
    p: &Matrix6<f64>,
    a: &Vector6<f64>,
    rows: &[Vector6<f64>],
    b: &[f64],
) -> Option<(Vector6<f64>, Vec<f64>)> {
    let m = rows.len();
    let kkt = DMatrix::from_fn(6 + m, 6 + m, |i, j| match (i < 6, j < 6) {
        (true, true) => p[(i, j)],
        (true, false) => rows[j - 6][i],
        (false, true) => rows[i - 6][j],
        (false, false) => 0.0,
    });
    let rhs = DVector::from_iterator(6 + m, a.iter().map(|v| -v).chain(b.iter().copied()));
    let sol = kkt.full_piv_lu().solve(&rhs)?;
    if sol.iter().any(|v| !v.is_finite()) {
        return None;
    }
    Some((
        Vector6::from_iterator(sol.iter().take(6).copied()),
        sol.iter().skip(6).copied().collect(),
    ))
}

/// Whether the rows are linearly independent (modified Gram–Schmidt on the normalized rows).
fn independent(rows: &[Vector6<f64>]) -> bool {
    (0..rows.len()).all(|k| independent_of(&rows[..k], &rows[k]))
}

/// Whether `a` is independent of `rows` (which must be independent): its normalized
/// Gram–Schmidt remainder against them has `ρ² > DEPENDENT`.
fn independent_of(rows: &[Vector6<f64>], a: &Vector6<f64>) -> bool {
    let mut basis: Vec<Vector6<f64>> = Vec::with_capacity(rows.len());
    for r in rows {
        let mut v = *r / r.norm();
        for q in &basis {
            v -= q * q.dot(&v);
        }
        let n = v.norm();
        if n > 0.0 {
            basis.push(v / n);
        }
    }
    let s = a.norm();
    if s == 0.0 {
        return false;
    }
    let mut v = *a / s;
    for q in &basis {
        v -= q * q.dot(&v);
    }
    v.norm_squared() > DEPENDENT
}
