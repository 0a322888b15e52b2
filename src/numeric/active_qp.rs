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
use nalgebra::{Matrix6, Vector6};

/// What [`qp6_active_set`] found.
#[derive(Debug, Clone)]
pub enum Qp6 {
    /// The minimizer with its multipliers (and the active inequality rows, which the tests
    /// check against the multipliers).
    Solved(QpStep, #[cfg_attr(not(test), allow(dead_code))] Vec<usize>),
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
    let Some((mut x, y0)) = kkt_solve(p, g, (eq_rows, eq_rhs), (in_rows, in_rhs), &active) else {
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
            .filter_map(|i| violation(&in_rows[i], in_rhs[i], &x).map(|v| (i, v)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((ip, _)) = worst else {
            // Primal feasible and dual feasible: the minimizer. Solve it once more from the
            // final active set, so it carries no accumulated rounding; its rows in their
            // order in `in_rows`, so the bits depend on the set alone ([`qp6_warm`]).
            if fresh {
                return finish(x, &y0, ne, in_rows.len(), &active);
            }
            active.sort_unstable();
            return match kkt_solve(p, g, (eq_rows, eq_rhs), (in_rows, in_rhs), &active) {
                Some((x, y)) => finish(x, &y, ne, in_rows.len(), &active),
                None => Qp6::Undecided,
            };
        };
        let a_p = in_rows[ip];
        let mut t_p = 0.0;
        fresh = false;
        // Pursue `p` until it is met (added) or proved unreachable.
        loop {
            // More than 6 rows: `kkt_dir` declines them (Undecided, as before this check).
            let Some((rows, nr)) = stacked(eq_rows, active.iter().map(|&i| in_rows[i])) else {
                return Qp6::Undecided;
            };
            let rows = &rows[..nr];
            let dependent = !independent_of(rows, &a_p);
            let Some((z, r)) = kkt_dir(p, &a_p, rows, &[0.0; 6][..nr]) else {
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

/// How far `x` violates the inequality `row·x ≤ rhs`, relative to the row's length, when it
/// does by more than rounding (1e-13 of the size of its terms); `None` when it holds.
fn violation(row: &Vector6<f64>, rhs: f64, x: &Vector6<f64>) -> Option<f64> {
    let ax = row.dot(x);
    let scale = row.abs().dot(&x.abs()) + rhs.abs();
    (ax - rhs > 1e-13 * scale).then(|| (ax - rhs) / row.norm())
}

/// [`qp6_active_set`] started from a guess of the active inequalities (`guess`: rows of
/// `in_rows`, the last Newton step's active set): the equalities and the guessed rows held
/// with equality, one KKT solve. When that point meets every other inequality (to the
/// rounding [`qp6_active_set`] allows) and the guessed rows' multipliers are ≥ 0, it meets the
/// KKT conditions of the QP — stationarity and the held rows by the solve, primal and dual
/// feasibility by the checks, complementarity as the other rows' multipliers are 0 — which,
/// `P` being positive definite, only its one minimizer does (Nocedal & Wright, *Numerical
/// Optimization*, 2nd ed., Thm 16.4): the dual method's answer, at the cost of one of its
/// solves, and to the bit: both solve the final set's system with its rows in their order in
/// `in_rows`. Otherwise (an empty, repeated, out-of-range or dependent guess, a failed solve, a
/// violated row or a negative multiplier) the dual method from the start.
pub fn qp6_warm(
    p: &Matrix6<f64>,
    g: &Vector6<f64>,
    (eq_rows, eq_rhs): (&[Vector6<f64>], &[f64]),
    (in_rows, in_rhs): (&[Vector6<f64>], &[f64]),
    guess: &[usize],
) -> Qp6 {
    let ne = eq_rows.len();
    // More than 6 rows: not a guess (`kkt_dir` takes 6 rows at most).
    let mut sorted: arrayvec::ArrayVec<usize, 6> = guess.iter().take(6).copied().collect();
    sorted.sort_unstable();
    let valid = !guess.is_empty() && ne + guess.len() <= 6;
    let guess = &sorted[..];
    let valid = valid
        && guess
            .iter()
            .enumerate()
            .all(|(k, &i)| i < in_rows.len() && !guess[..k].contains(&i));
    let solved = valid
        .then(|| stacked(eq_rows, guess.iter().map(|&i| in_rows[i])))
        .flatten()
        .filter(|(rows, nr)| independent(&rows[..*nr]))
        .and_then(|_| kkt_solve(p, g, (eq_rows, eq_rhs), (in_rows, in_rhs), guess));
    if let Some((x, y)) = solved {
        let feasible = (0..in_rows.len())
            .filter(|i| !guess.contains(i))
            .all(|i| violation(&in_rows[i], in_rhs[i], &x).is_none());
        let pressing = y[ne..ne + guess.len()].iter().all(|&u| u >= 0.0);
        if feasible && pressing {
            return finish(x, &y, ne, in_rows.len(), guess);
        }
    }
    qp6_active_set(p, g, eq_rows, eq_rhs, in_rows, in_rhs)
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
/// pivoting. `None` when singular or not finite. The multipliers are the first
/// `eq_rows.len() + active.len()` entries of `y` ([`kkt_dir`]).
fn kkt_solve(
    p: &Matrix6<f64>,
    g: &Vector6<f64>,
    (eq_rows, eq_rhs): (&[Vector6<f64>], &[f64]),
    (in_rows, in_rhs): (&[Vector6<f64>], &[f64]),
    active: &[usize],
) -> Option<(Vector6<f64>, [f64; 6])> {
    // More than 6 rows: `kkt_dir` declines them (None).
    let (rows, nr) = stacked(eq_rows, active.iter().map(|&i| in_rows[i]))?;
    let (rhs, _) = stacked(eq_rhs, active.iter().map(|&i| in_rhs[i]))?;
    kkt_dir(p, g, &rows[..nr], &rhs[..nr])
}

/// `first` followed by `rest` in a stack array, with their count; `None` beyond 6 (the most
/// rows [`kkt_dir`] takes: [`KKT_MAX`] − 6).
fn stacked<T: Copy + Default>(
    first: &[T],
    rest: impl Iterator<Item = T>,
) -> Option<([T; 6], usize)> {
    let mut out = [T::default(); 6];
    let mut n = 0;
    for v in first.iter().copied().chain(rest) {
        *out.get_mut(n)? = v;
        n += 1;
    }
    Some((out, n))
}

/// Solve `[P Nᵀ; N 0] [x; y] = [−a; b]` (rows of `N`: `rows`) by LU with full pivoting
/// ([`full_piv_solve`], on the stack: nalgebra's heap `DMatrix` LU was 13 % of a literal
/// solve next to the wall). `None` when singular, not finite, or larger than
/// [`KKT_MAX`]. `y` is returned on the stack, its first `rows.len()` entries (the rest 0).
fn kkt_dir(
    p: &Matrix6<f64>,
    a: &Vector6<f64>,
    rows: &[Vector6<f64>],
    b: &[f64],
) -> Option<(Vector6<f64>, [f64; 6])> {
    let m = rows.len();
    let n = 6 + m;
    if n > KKT_MAX {
        return None;
    }
    // By columns (`kkt[j][i]` is entry (i, j)), as `full_piv_solve` takes it.
    let mut kkt = [[0.0; KKT_MAX]; KKT_MAX];
    for (j, col) in kkt.iter_mut().enumerate().take(n) {
        for (i, v) in col.iter_mut().enumerate().take(n) {
            *v = match (i < 6, j < 6) {
                (true, true) => p[(i, j)],
                (true, false) => rows[j - 6][i],
                (false, true) => rows[i - 6][j],
                (false, false) => 0.0,
            };
        }
    }
    let mut sol = [0.0; KKT_MAX];
    for (i, v) in sol.iter_mut().enumerate().take(n) {
        *v = if i < 6 { -a[i] } else { b[i - 6] };
    }
    full_piv_solve(&mut kkt, &mut sol, n)?;
    if sol[..n].iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut y = [0.0; 6];
    y[..m].copy_from_slice(&sol[6..n]);
    Some((Vector6::from_iterator(sol.iter().take(6).copied()), y))
}

/// The full-pivot search of [`full_piv_solve`]: nalgebra's scan `if |v| > best { take v }`
/// from the leading entry of the remaining block over its columns in order, rows within
/// each (the first entry of largest magnitude; a NaN is never taken).
///
/// It is run one column at a time: the column's part of the scan leaves `best` at the same
/// recurrence's value `m` (the fold in [`Pivot::scan`]), and if `m` is above `best` the entry
/// the scan took last is the column's first entry of magnitude `m` (an earlier one would
/// have been taken, and none after it exceeds `m`). So the pivot is the scan's, with the row
/// index looked for only in the columns that raise `best`.
struct Pivot {
    best: f64,
    row: usize,
    col: usize,
}

impl Pivot {
    /// A scan not yet started.
    fn new() -> Pivot {
        Pivot {
            best: 0.0,
            row: usize::MAX,
            col: usize::MAX,
        }
    }

    /// Continue the scan down `seg`, rows `row0..` of column `col` (the first call's first
    /// entry is the block's leading one, where the scan starts).
    fn scan(&mut self, seg: &[f64], row0: usize, col: usize) {
        if self.row == usize::MAX {
            let Some(first) = seg.first() else {
                return;
            };
            (self.best, self.row, self.col) = (first.abs(), row0, col);
        }
        let m = seg.iter().fold(self.best, |m, x| {
            let v = x.abs();
            if v > m {
                v
            } else {
                m
            }
        });
        if m > self.best {
            if let Some(k) = seg.iter().position(|x| x.abs() == m) {
                (self.best, self.row, self.col) = (m, row0 + k, col);
            }
        }
    }
}

/// The largest KKT system [`kkt_dir`] solves: 6 unknowns and 6 rows. The method never asks
/// for more: the equality rows are independent (checked on entry, at most 6) and a row joins
/// the active set only when independent of those already in it. (A larger array, 18 × 18, cost
/// 7 % more instructions on the wall in its zero fill.)
const KKT_MAX: usize = 12;

/// Solve `A x = b` for the leading `n × n` block of `a` (stored by columns) in place (`b` becomes
/// `x`) by Gaussian elimination with full pivoting, `None` when `A` is singular (a zero
/// pivot). The same operations in the same order as nalgebra's `FullPivLU::new(..).solve(..)`
/// (pivot: the first entry of largest magnitude, columns scanned in order; the multipliers
/// scaled by the pivot's reciprocal; the triangular solves column by column), so the answer
/// is the same to the bit (`tests::stack_lu_equals_nalgebra_bit_for_bit`) without its heap
/// matrices.
#[allow(clippy::needless_range_loop)]
fn full_piv_solve(
    a: &mut [[f64; KKT_MAX]; KKT_MAX],
    b: &mut [f64; KKT_MAX],
    n: usize,
) -> Option<()> {
    // `a` is stored by columns, `a[c][r]` being entry (r, c): the pivot search (columns in
    // order, rows within each) and the elimination's inner loops (down a column) then run over
    // contiguous memory. Each entry sees the same operations in the same order as with rows
    // stored by rows, so the bits are the same.
    // Indices below `n ≤ KKT_MAX`: the bounds checks fold away.
    let n = n.min(KKT_MAX);
    if n == 0 {
        return Some(());
    }
    let (mut row_swap, mut col_swap) = ([0usize; KKT_MAX], [0usize; KKT_MAX]);
    // The first pivot: the scan over the whole matrix ([`Pivot`]).
    let mut pivot = Pivot::new();
    for (cc, col) in a.iter().enumerate().take(n) {
        pivot.scan(&col[..n], 0, cc);
    }
    for i in 0..n {
        let (r, c) = (pivot.row, pivot.col);
        row_swap[i] = r;
        col_swap[i] = c;
        let diag = a[c][r];
        if diag == 0.0 {
            // The rest is zero: singular (nalgebra stops here too).
            for k in i + 1..n {
                row_swap[k] = k;
                col_swap[k] = k;
            }
            break;
        }
        if c != i {
            a.swap(i, c);
        }
        if r != i {
            for col in a.iter_mut().take(n) {
                col.swap(i, r);
            }
        }
        let inv = 1.0 / diag;
        for rr in i + 1..n {
            a[i][rr] *= inv;
        }
        // The update leaves rows and columns i + 1.. as the next pivot's scan reads them, in
        // its order (columns in order, rows within each): each column is scanned as soon as
        // it is updated, and nothing changes them in between.
        let (left, right) = a.split_at_mut(i + 1);
        let pivot_col = &left[i];
        pivot = Pivot::new();
        for (k, col) in right.iter_mut().take(n - i - 1).enumerate() {
            let pk = -col[i];
            for rr in i + 1..n {
                col[rr] += pk * pivot_col[rr];
            }
            pivot.scan(&col[i + 1..n], i + 1, i + 1 + k);
        }
    }
    if a[n - 1][n - 1] == 0.0 {
        return None;
    }
    for i in 0..n {
        b.swap(i, row_swap[i]);
    }
    for i in 0..n - 1 {
        let coeff = -b[i];
        for r in i + 1..n {
            b[r] += coeff * a[i][r];
        }
    }
    for i in (0..n).rev() {
        let coeff = b[i] / a[i][i];
        b[i] = coeff;
        for r in 0..i {
            b[r] += -coeff * a[i][r];
        }
    }
    for i in (0..n).rev() {
        b.swap(i, col_swap[i]);
    }
    Some(())
}

/// Whether the rows are linearly independent (modified Gram–Schmidt on the normalized rows).
fn independent(rows: &[Vector6<f64>]) -> bool {
    (0..rows.len()).all(|k| independent_of(&rows[..k], &rows[k]))
}

/// Whether `a` is independent of `rows` (which must be independent): its normalized
/// Gram–Schmidt remainder against them has `ρ² > DEPENDENT`.
/// At most 6 rows (both callers check; more cannot be independent in 6 unknowns).
fn independent_of(rows: &[Vector6<f64>], a: &Vector6<f64>) -> bool {
    debug_assert!(rows.len() <= 6);
    let (mut basis, mut nb) = ([Vector6::zeros(); 6], 0);
    for r in rows.iter().take(6) {
        let mut v = *r / r.norm();
        for q in &basis[..nb] {
            v -= q * q.dot(&v);
        }
        let n = v.norm();
        if n > 0.0 {
            basis[nb] = v / n;
            nb += 1;
        }
    }
    let s = a.norm();
    if s == 0.0 {
        return false;
    }
    let mut v = *a / s;
    for q in &basis[..nb] {
        v -= q * q.dot(&v);
    }
    v.norm_squared() > DEPENDENT
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// The stack LU is nalgebra's full-pivot LU to the bit on random KKT systems of every size
    /// (6 unknowns, 0 to 6 rows), including repeated entries (pivot ties), a singular system
    /// (a repeated row, both `None`) and badly scaled ones.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn pivot_scan_by_columns_equals_the_entry_scan() {
        // Few magnitudes (ties everywhere), signed zeros and NaNs, blocks of every size.
        let values = [0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.0, f64::NAN];
        let mut rng = crate::numeric::test_rng::Rng(0x5851_f42d_4c95_7f2d);
        for trial in 0..5000 {
            let (n, i) = (1 + trial % KKT_MAX, trial % 3);
            let i = i.min(n - 1);
            let mut a = [[0.0; KKT_MAX]; KKT_MAX];
            for col in a.iter_mut().take(n) {
                for v in col.iter_mut().take(n) {
                    *v = values[rng.range(0.0, 7.99) as usize];
                }
            }
            // nalgebra's scan, entry by entry.
            let (mut best, mut r, mut c) = (a[i][i].abs(), i, i);
            for cc in i..n {
                for rr in i..n {
                    if a[cc][rr].abs() > best {
                        (best, r, c) = (a[cc][rr].abs(), rr, cc);
                    }
                }
            }
            let mut pivot = Pivot::new();
            for (cc, col) in a.iter().enumerate().take(n).skip(i) {
                pivot.scan(&col[i..n], i, cc);
            }
            assert_eq!((pivot.row, pivot.col), (r, c), "trial {trial}");
            assert_eq!(pivot.best.to_bits(), best.to_bits(), "trial {trial}");
        }
    }

    #[test]
    fn stack_lu_equals_nalgebra_bit_for_bit() {
        let mut rng = crate::numeric::test_rng::Rng(0x9e37_79b9_7f4a_7c15);
        let (mut solved, mut singular) = (0, 0);
        for trial in 0..3000 {
            let m = trial % 7;
            let n = 6 + m;
            let scale = 10f64.powf(rng.range(-6.0, 6.0));
            let mut p = Matrix6::from_fn(|_, _| rng.range(-1.0, 1.0));
            p = p * p.transpose() * scale + Matrix6::identity() * 1e-10;
            if trial % 11 == 0 {
                p[(1, 1)] = p[(0, 0)];
            }
            if trial % 5 == 0 {
                // Not symmetric: the stack LU must read its columns as columns.
                p[(0, 1)] += 0.3 * scale;
            }
            let mut rows: Vec<Vector6<f64>> = (0..m)
                .map(|_| Vector6::from_fn(|_, _| rng.range(-1.0, 1.0).round() * 0.5))
                .collect();
            if m >= 2 && trial % 13 == 0 {
                rows[1] = rows[0];
            }
            let a = Vector6::from_fn(|_, _| rng.range(-1.0, 1.0));
            let b: Vec<f64> = (0..m).map(|_| rng.range(-1.0, 1.0)).collect();
            let kkt = DMatrix::from_fn(n, n, |i, j| match (i < 6, j < 6) {
                (true, true) => p[(i, j)],
                (true, false) => rows[j - 6][i],
                (false, true) => rows[i - 6][j],
                (false, false) => 0.0,
            });
            let rhs = DVector::from_iterator(n, a.iter().map(|v| -v).chain(b.iter().copied()));
            let reference = kkt.clone().full_piv_lu().solve(&rhs);
            let mut st = [[0.0; KKT_MAX]; KKT_MAX];
            let mut sol = [0.0; KKT_MAX];
            for i in 0..n {
                sol[i] = rhs[i];
                for j in 0..n {
                    st[j][i] = kkt[(i, j)];
                }
            }
            match (reference, full_piv_solve(&mut st, &mut sol, n)) {
                (Some(x), Some(())) => {
                    solved += 1;
                    for i in 0..n {
                        assert_eq!(x[i].to_bits(), sol[i].to_bits(), "trial {trial} entry {i}");
                    }
                }
                (None, None) => singular += 1,
                (x, y) => panic!("trial {trial}: nalgebra {x:?}, stack {y:?}"),
            }
        }
        assert!(solved > 2500 && singular > 10, "{solved} {singular}");
    }
}

/// Seeded cross-checks against independent solvers (kept in their own file for length).
#[cfg(test)]
#[path = "active_qp_cross_tests.rs"]
mod against_clarabel;
