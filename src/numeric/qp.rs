//! Small convex QP steps with inequalities: [`qp_step6`] (a dual active set, clarabel where
//! that makes no claim), and [`nonneg_qp`] (a
//! bound-constrained dense QP by a primal active set, the dual of the energy model's steps).
//!
//! `min ½ xᵀ H x + gᵀ x  s.t.  E x = e,  G x ≤ h` for 6 unknowns — the SQP step of a section
//! problem when obstacle constraints are near-active. `H` is made positive definite first
//! (eigenvalues clamped to at least `reg`), as clarabel needs a convex objective and an SQP step
//! must descend. Equality-only steps do not come here: they use the dense nalgebra KKT step
//! ([`crate::numeric::kkt::kkt_step6`]), which is ~100× cheaper.

use crate::numeric::active_qp::{qp6_warm, Qp6};
use crate::numeric::dense::small_solve;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolution, DefaultSolver, IPSolver, NonnegativeConeT,
    SecondOrderConeT, SolverStatus, SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, DVector, Matrix6, SymmetricEigen, Vector3, Vector6};

/// Solution of [`qp_step6`].
#[derive(Debug, Clone)]
pub struct QpStep {
    /// Step.
    pub x: Vector6<f64>,
    /// Multipliers of the equalities (convention: ∇f + Eᵀλ − … = 0 as clarabel's `z`).
    pub lambda_eq: Vec<f64>,
    /// Multipliers of the inequalities (≥ 0).
    pub mu: Vec<f64>,
}

/// Solve the QP; `None` when it is infeasible or clarabel reports anything but (almost)
/// solved. Exact to rounding by the dual active set of
/// [`qp6_active_set`](crate::numeric::active_qp::qp6_active_set) (the
/// interior point cost half of a contact solve and left its steps accurate to ~1e-7 only);
/// clarabel ([`qp_step6_clarabel`]) where that method makes no claim (dependent equality
/// rows, a failed KKT solve).
///
/// It starts from a guess of the active inequalities (`guess`: rows of `in_rows`, the last
/// step's; empty for none: [`qp6_warm`]) and returns with the step the active set it ends on
/// (empty from clarabel), the next guess. The same step whatever the guess, to the bit where
/// the dual method ends on the same set (a wrong guess costs one KKT solve).
pub fn qp_step6(
    h: &Matrix6<f64>,
    g: &Vector6<f64>,
    (eq_rows, eq_rhs): (&[Vector6<f64>], &[f64]),
    (in_rows, in_rhs): (&[Vector6<f64>], &[f64]),
    reg: f64,
    guess: &[usize],
) -> Option<(QpStep, Vec<usize>)> {
    let hp = clamped_hessian(h, reg);
    match qp6_warm(&hp, g, (eq_rows, eq_rhs), (in_rows, in_rhs), guess) {
        Qp6::Solved(step, active) => Some((step, active)),
        Qp6::Infeasible => None,
        Qp6::Undecided => {
            qp_step6_clarabel(&hp, g, eq_rows, eq_rhs, in_rows, in_rhs).map(|s| (s, vec![]))
        }
    }
}

/// `h` made positive definite: its eigenvalues replaced by their magnitudes, at least `reg`
/// (an SQP step must descend, and both QP solvers need a convex objective).
pub fn clamped_hessian(h: &Matrix6<f64>, reg: f64) -> Matrix6<f64> {
    let e = SymmetricEigen::new(*h);
    let mut d = e.eigenvalues;
    for v in d.iter_mut() {
        *v = v.abs().max(reg);
    }
    e.eigenvectors * Matrix6::from_diagonal(&d) * e.eigenvectors.transpose()
}

/// [`qp_step6`] by clarabel's interior point alone, on the Hessian `hp` already made positive
/// definite ([`clamped_hessian`]): accurate to its tolerances, ~1e-8 to 1e-7 on a step; `None`
/// if clarabel reports anything but (almost) solved.
pub fn qp_step6_clarabel(
    hp: &Matrix6<f64>,
    g: &Vector6<f64>,
    eq_rows: &[Vector6<f64>],
    eq_rhs: &[f64],
    in_rows: &[Vector6<f64>],
    in_rhs: &[f64],
) -> Option<QpStep> {
    // P: upper triangle, column-major CSC.
    let (mut colptr, mut rowval, mut nzval) = (vec![0usize], vec![], vec![]);
    for j in 0..6 {
        for i in 0..=j {
            rowval.push(i);
            nzval.push(0.5 * (hp[(i, j)] + hp[(j, i)]));
        }
        colptr.push(rowval.len());
    }
    let p = CscMatrix::new(6, 6, colptr, rowval, nzval);
    let m = eq_rows.len() + in_rows.len();
    let rows: Vec<&Vector6<f64>> = eq_rows.iter().chain(in_rows.iter()).collect();
    let (mut colptr, mut rowval, mut nzval) = (vec![0usize], vec![], vec![]);
    for j in 0..6 {
        for (i, r) in rows.iter().enumerate() {
            if r[j] != 0.0 {
                rowval.push(i);
                nzval.push(r[j]);
            }
        }
        colptr.push(rowval.len());
    }
    let a = CscMatrix::new(m, 6, colptr, rowval, nzval);
    let b: Vec<f64> = eq_rhs.iter().chain(in_rhs.iter()).copied().collect();
    let mut cones: Vec<SupportedConeT<f64>> = vec![];
    if !eq_rows.is_empty() {
        cones.push(ZeroConeT(eq_rows.len()));
    }
    if !in_rows.is_empty() {
        cones.push(NonnegativeConeT(in_rows.len()));
    }
    let sol = clarabel_solve(&p, g.as_slice(), &a, &b, &cones, 1e-12)?;
    if sol.x.iter().any(|v| !v.is_finite()) {
        return None;
    }
    Some(QpStep {
        x: Vector6::from_row_slice(&sol.x),
        lambda_eq: sol.z[..eq_rows.len()].to_vec(),
        mu: sol.z[eq_rows.len()..].to_vec(),
    })
}

/// Solve the dense QP `min ½ xᵀ H x + gᵀ x  s.t.  E x = e,  G x ≤ h` of any (small) size;
/// `H` must be symmetric positive semidefinite (only its upper triangle is read).
/// `None` when clarabel reports anything but (almost) solved — an infeasible QP included.
/// Used by the inverse problems ([`crate::reach`]) whose unknowns are the cable inputs.
///
/// First the equality-constrained minimizer is found from its KKT system
/// `[H Eᵀ; E 0] [x; y] = [−g; e]` ([`eq_qp`]); when it keeps every inequality it is the QP's
/// minimizer (a convex problem whose KKT conditions hold with zero inequality multipliers,
/// Nocedal & Wright, *Numerical Optimization*, 2nd ed., Thm 16.4), exact to rounding and
/// ~100× cheaper than an interior-point solve. Otherwise (or when that KKT matrix is singular)
/// clarabel solves the whole QP.
pub fn qp_dense(
    h: &DMatrix<f64>,
    g: &[f64],
    eq: (&DMatrix<f64>, &[f64]),
    ineq: (&DMatrix<f64>, &[f64]),
) -> Option<Vec<f64>> {
    if let Some(x) = eq_qp(h, g, eq) {
        let keeps = (0..ineq.0.nrows()).all(|i| {
            let gx: f64 = (0..x.len()).map(|j| ineq.0[(i, j)] * x[j]).sum();
            gx <= ineq.1[i]
        });
        if keeps {
            return Some(x);
        }
    }
    qp_clarabel(h, g, eq, ineq)
}

/// The minimizer of `½ xᵀ H x + gᵀ x` subject to `E x = e` only, from the KKT system (LU with
/// full pivoting; `H` read from its upper triangle). `None` when the KKT matrix is singular
/// (`H` not positive definite on the null space of `E`, or `E` without full row rank) or the
/// answer is not finite.
pub fn eq_qp(h: &DMatrix<f64>, g: &[f64], eq: (&DMatrix<f64>, &[f64])) -> Option<Vec<f64>> {
    let (n, me) = (g.len(), eq.0.nrows());
    let kkt = DMatrix::from_fn(n + me, n + me, |i, j| match (i < n, j < n) {
        (true, true) => h[(i.min(j), i.max(j))],
        (true, false) => eq.0[(j - n, i)],
        (false, true) => eq.0[(i - n, j)],
        (false, false) => 0.0,
    });
    let rhs = DVector::from_iterator(n + me, g.iter().map(|v| -v).chain(eq.1.iter().copied()));
    let sol = kkt.full_piv_lu().solve(&rhs)?;
    let x: Vec<f64> = sol.iter().take(n).copied().collect();
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// [`qp_dense`] by clarabel alone.
fn qp_clarabel(
    h: &DMatrix<f64>,
    g: &[f64],
    eq: (&DMatrix<f64>, &[f64]),
    ineq: (&DMatrix<f64>, &[f64]),
) -> Option<Vec<f64>> {
    let n = g.len();
    let (mut colptr, mut rowval, mut nzval) = (vec![0usize], vec![], vec![]);
    for j in 0..n {
        for i in 0..=j {
            rowval.push(i);
            nzval.push(h[(i, j)]);
        }
        colptr.push(rowval.len());
    }
    let p = CscMatrix::new(n, n, colptr, rowval, nzval);
    let (me, mi) = (eq.0.nrows(), ineq.0.nrows());
    let (mut colptr, mut rowval, mut nzval) = (vec![0usize], vec![], vec![]);
    for j in 0..n {
        for i in 0..me + mi {
            let v = if i < me {
                eq.0[(i, j)]
            } else {
                ineq.0[(i - me, j)]
            };
            if v != 0.0 {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    let a = CscMatrix::new(me + mi, n, colptr, rowval, nzval);
    let b: Vec<f64> = eq.1.iter().chain(ineq.1.iter()).copied().collect();
    let mut cones: Vec<SupportedConeT<f64>> = vec![];
    if me > 0 {
        cones.push(ZeroConeT(me));
    }
    if mi > 0 {
        cones.push(NonnegativeConeT(mi));
    }
    let sol = clarabel_solve(&p, g, &a, &b, &cones, 1e-14)?;
    sol.x.iter().all(|v| v.is_finite()).then_some(sol.x)
}

/// Minimize `½ λᵀ S λ − qᵀ λ` over `λ ≥ 0` (`S`: `n × n`, symmetric positive semidefinite,
/// row-major): the dual of one step's QP. A primal active set on the bounds: on the free set
/// `F` solve `S_FF λ_F = q_F`; if that leaves the bounds, move to the first bound met and fix
/// it there, else free the fixed bound with the most negative gradient `(S λ − q)_i`; done
/// when none is negative. `lam` holds the start (projected on `λ ≥ 0`) and the result. When
/// the free rows are dependent (two contacts at one joint, cables sharing a path), a ridge
/// from 1e-12 of the largest diagonal up makes them solvable and they share the load; it is
/// not used otherwise, since even 1e-12 moves the step by more than the last Newton
/// corrections. `false` if it cycles.
#[allow(clippy::needless_range_loop)]
pub fn nonneg_qp(s: &[f64], q: &[f64], n: usize, lam: &mut [f64]) -> bool {
    if n == 0 {
        return true;
    }
    let big = (0..n).map(|i| s[i * n + i].abs()).fold(0.0, f64::max);
    let mut ridge = 0.0;
    for l in lam.iter_mut() {
        *l = if l.is_finite() { l.max(0.0) } else { 0.0 };
    }
    let mut free: Vec<bool> = lam.iter().map(|&l| l > 0.0).collect();
    // A bound freed because its gradient was negative must come out positive; in round-off
    // (nearly dependent rows) it may not: then it stays fixed (its gradient is ~0 anyway).
    let mut blocked = vec![false; n];
    let mut last_added: Option<usize> = None;
    let mut x = vec![0.0; n];
    let (mut sub, mut rhs, mut idx) = (vec![], vec![], vec![]);
    for _ in 0..20 * n + 50 {
        idx.clear();
        idx.extend((0..n).filter(|&i| free[i]));
        let k = idx.len();
        x.fill(0.0);
        if k > 0 {
            loop {
                sub.clear();
                rhs.clear();
                for &a in &idx {
                    rhs.push(q[a]);
                    for &b in &idx {
                        sub.push(s[a * n + b] + if a == b { ridge } else { 0.0 });
                    }
                }
                if small_solve(&mut sub, &mut rhs, k).is_some() {
                    break;
                }
                // Dependent rows: a ridge (it perturbs the multipliers, so only when needed).
                ridge = if ridge == 0.0 {
                    1e-12 * big
                } else {
                    100.0 * ridge
                };
                if !(ridge > 0.0 && ridge < big) {
                    return false;
                }
            }
            for (t, &a) in idx.iter().enumerate() {
                x[a] = rhs[t];
            }
        }
        if idx.iter().all(|&a| x[a] >= 0.0) {
            lam.copy_from_slice(&x);
            let mut best: Option<(usize, f64)> = None;
            for i in (0..n).filter(|&i| !free[i] && !blocked[i]) {
                let (mut g, mut scale) = (-q[i], q[i].abs());
                for j in 0..n {
                    g += s[i * n + j] * lam[j];
                    scale += (s[i * n + j] * lam[j]).abs();
                }
                if g < -1e-12 * scale && best.is_none_or(|(_, b)| g < b) {
                    best = Some((i, g));
                }
            }
            match best {
                Some((i, _)) => {
                    free[i] = true;
                    last_added = Some(i);
                }
                None => return true,
            }
        } else {
            if let Some(i) = last_added.take() {
                if x[i] < 0.0 {
                    free[i] = false;
                    blocked[i] = true;
                    continue;
                }
            }
            let mut alpha = 1.0;
            let mut hit = None;
            for &a in &idx {
                if x[a] < 0.0 {
                    let r = lam[a] / (lam[a] - x[a]);
                    if r < alpha {
                        alpha = r;
                        hit = Some(a);
                    }
                }
            }
            for &a in &idx {
                lam[a] += alpha * (x[a] - lam[a]);
                if lam[a] <= 0.0 || Some(a) == hit {
                    lam[a] = 0.0;
                    free[a] = false;
                }
            }
        }
    }
    false
}

/// The smallest `s` such that `target = Σ_k (a_k e1_k + b_k e2_k)` with `a_k² + b_k² ≤ (s w_k)²`:
/// how far `target` is from the Minkowski sum of the discs `{a e1_k + b e2_k : |(a, b)| ≤ w_k}`
/// (`s ≤ 1`: inside). A second-order cone program (min s over the cones `(w_k s, a_k, b_k)`),
/// solved by clarabel; `None` if it reports anything but (almost) solved, e.g. when the discs
/// do not span `target`.
///
/// Used to certify a kink where several norm-like terms vanish together: the multiplier of
/// their common constraint must split into one subgradient per term.
pub fn disc_sum_scale(
    target: &Vector3<f64>,
    discs: &[(Vector3<f64>, Vector3<f64>, f64)],
) -> Option<f64> {
    match discs {
        [a, b] => super::disc_split::two_disc_scale(target, a, b)
            .or_else(|| disc_sum_scale_socp(target, discs)),
        _ => disc_sum_scale_socp(target, discs),
    }
}

/// [`disc_sum_scale`] as a second-order cone program, solved by clarabel.
pub(crate) fn disc_sum_scale_socp(
    target: &Vector3<f64>,
    discs: &[(Vector3<f64>, Vector3<f64>, f64)],
) -> Option<f64> {
    let n = 1 + 2 * discs.len();
    let m = 3 + 3 * discs.len();
    // Column-major entries of A (rows: 3 equalities, then 3 per cone).
    let mut cols: Vec<Vec<(usize, f64)>> = vec![vec![]; n];
    for (k, (e1, e2, w)) in discs.iter().enumerate() {
        for i in 0..3 {
            cols[1 + 2 * k].push((i, e1[i]));
            cols[2 + 2 * k].push((i, e2[i]));
        }
        let r = 3 + 3 * k;
        cols[0].push((r, -w));
        cols[1 + 2 * k].push((r + 1, -1.0));
        cols[2 + 2 * k].push((r + 2, -1.0));
    }
    let (mut colptr, mut rowval, mut nzval) = (vec![0usize], vec![], vec![]);
    for col in &mut cols {
        col.sort_by_key(|e| e.0);
        for &(i, v) in col.iter() {
            rowval.push(i);
            nzval.push(v);
        }
        colptr.push(rowval.len());
    }
    let a = CscMatrix::new(m, n, colptr, rowval, nzval);
    let p = CscMatrix::zeros((n, n));
    let mut q = vec![0.0; n];
    q[0] = 1.0;
    let mut b = vec![0.0; m];
    b[..3].copy_from_slice(target.as_slice());
    let mut cones: Vec<SupportedConeT<f64>> = vec![ZeroConeT(3)];
    cones.extend(discs.iter().map(|_| SecondOrderConeT(3)));
    let sol = clarabel_solve(&p, &q, &a, &b, &cones, 1e-12)?;
    sol.x[0].is_finite().then_some(sol.x[0])
}

/// Clarabel on `min ½ xᵀ P x + qᵀ x  s.t.  A x + s = b, s ∈ cones` (`P` upper triangle) with
/// the tolerances a Newton step needs: duality gap `gap_abs` absolute and 1e-12 relative,
/// feasibility 1e-12. Its solution when clarabel reports solved or almost solved, else `None`
/// (the callers check the entries they use for finiteness).
fn clarabel_solve(
    p: &CscMatrix<f64>,
    q: &[f64],
    a: &CscMatrix<f64>,
    b: &[f64],
    cones: &[SupportedConeT<f64>],
    gap_abs: f64,
) -> Option<DefaultSolution<f64>> {
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(gap_abs)
        .tol_gap_rel(1e-12)
        .tol_feas(1e-12)
        .build()
        .ok()?;
    let mut solver = DefaultSolver::new(p, q, a, b, cones, settings).ok()?;
    solver.solve();
    matches!(
        solver.solution.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    )
    .then_some(solver.solution)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// min ½|x|² − x₀ s.t. x₀ ≤ 0.25: the bound is active, multiplier 0.75.
    #[test]
    fn active_bound_and_its_multiplier() {
        let h = Matrix6::identity();
        let mut g = Vector6::zeros();
        g[0] = -1.0;
        let mut row = Vector6::zeros();
        row[0] = 1.0;
        let (s, active) = qp_step6(&h, &g, (&[], &[]), (&[row], &[0.25]), 1e-12, &[]).unwrap();
        assert!((s.x[0] - 0.25).abs() < 1e-8);
        assert!((s.mu[0] - 0.75).abs() < 1e-7);
        assert_eq!(active, vec![0]);
        // Warm from that set: the same step, to the bit.
        let (w, _) = qp_step6(&h, &g, (&[], &[]), (&[row], &[0.25]), 1e-12, &active).unwrap();
        assert_eq!((w.x, w.mu), (s.x, s.mu));
    }

    /// min ½|x|² s.t. x₀ + x₁ = 1, x₀ ≤ 0.2: x = (0.2, 0.8) (closed form).
    #[test]
    fn dense_qp_with_equality_and_bound() {
        let h = DMatrix::identity(2, 2);
        let e = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let gi = DMatrix::from_row_slice(1, 2, &[1.0, 0.0]);
        let x = qp_dense(&h, &[0.0, 0.0], (&e, &[1.0]), (&gi, &[0.2])).unwrap();
        assert!(
            (x[0] - 0.2).abs() < 1e-9 && (x[1] - 0.8).abs() < 1e-9,
            "{x:?}"
        );
    }

    /// The fast path (inequalities inactive) and clarabel agree, and both match the closed
    /// form: min ½ xᵀ diag(1, 2, 4) x − (1, 1, 1)ᵀ x s.t. x₀ + x₁ + x₂ = 1, x₀ ≤ 10 has
    /// x_i = (1 + y)/h_i with y from Σ x_i = 1: (1 + y) · 1.75 = 1.
    #[test]
    fn inactive_inequalities_take_the_kkt_solve() {
        let h = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 2.0, 4.0]));
        let e = DMatrix::from_row_slice(1, 3, &[1.0, 1.0, 1.0]);
        let gi = DMatrix::from_row_slice(1, 3, &[1.0, 0.0, 0.0]);
        let g = [-1.0, -1.0, -1.0];
        let fast = qp_dense(&h, &g, (&e, &[1.0]), (&gi, &[10.0])).unwrap();
        let ipm = qp_clarabel(&h, &g, (&e, &[1.0]), (&gi, &[10.0])).unwrap();
        let c = 1.0 / 1.75;
        for (i, hi) in [1.0, 2.0, 4.0].iter().enumerate() {
            assert!((fast[i] - c / hi).abs() < 1e-15, "{fast:?}");
            assert!((ipm[i] - c / hi).abs() < 1e-8, "{ipm:?}");
        }
        // A singular KKT system (H = 0 with no equalities) is left to clarabel.
        assert!(eq_qp(
            &DMatrix::zeros(2, 2),
            &[1.0, 0.0],
            (&DMatrix::zeros(0, 2), &[])
        )
        .is_none());
    }

    /// The active set's answer satisfies the KKT conditions of `min ½ λᵀSλ − qᵀλ, λ ≥ 0`:
    /// λ ≥ 0, gradient `Sλ − q` ≥ 0, zero where λ > 0.
    #[test]
    fn nonneg_qp_meets_kkt_conditions() {
        let n = 4;
        let b = [
            1.0, 0.3, -0.2, 0.5, -0.4, 1.2, 0.1, 0.0, 0.2, -0.3, 0.9, 0.4, 0.0, 0.6, -0.5, 1.1,
        ];
        let mut s = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                s[i * n + j] = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum();
            }
        }
        for q in [
            [1.0, -2.0, 0.5, 0.3],
            [-1.0, -1.0, -1.0, -1.0],
            [2.0, 1.0, 3.0, -0.1],
        ] {
            let mut lam = vec![0.0; n];
            assert!(nonneg_qp(&s, &q, n, &mut lam));
            for i in 0..n {
                let g: f64 = (0..n).map(|j| s[i * n + j] * lam[j]).sum::<f64>() - q[i];
                assert!(lam[i] >= 0.0 && g > -1e-12, "{q:?} {i}: λ {} g {g}", lam[i]);
                assert!(
                    lam[i] == 0.0 || g.abs() < 1e-12,
                    "{q:?} {i}: complementarity"
                );
            }
        }
    }

    /// Two discs, normal to x and to y (both contain z), weight 1: (0.5, 0.5, 1) splits best
    /// as (0, 0.5, 0.5) + (0.5, 0, 0.5), scale √0.5 (the two norms cross); (0, 2, 0.1) needs
    /// its y from the first disc alone, scale 2 (one end); one disc normal to x cannot reach
    /// x at all.
    #[test]
    fn disc_sum_scale_closed_forms() {
        let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
        let s = disc_sum_scale(&Vector3::new(0.5, 0.5, 1.0), &[(y, z, 1.0), (x, z, 1.0)]).unwrap();
        assert!((s - 0.5f64.sqrt()).abs() < 1e-7, "{s}");
        let s = disc_sum_scale(&Vector3::new(0.0, 2.0, 0.1), &[(y, z, 1.0), (x, z, 1.0)]).unwrap();
        assert!((s - 2.0).abs() < 1e-12, "{s}");
        let s = disc_sum_scale(&Vector3::new(0.0, 0.6, 0.8), &[(y, z, 2.0)]).unwrap();
        assert!((s - 0.5).abs() < 1e-7, "{s}");
        assert!(disc_sum_scale(&x, &[(y, z, 1.0)]).is_none_or(|s| s > 1e3));
    }
}
