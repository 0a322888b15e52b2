//! Small convex QP steps with inequalities, solved by clarabel.
//!
//! `min ½ xᵀ H x + gᵀ x  s.t.  E x = e,  G x ≤ h` for 6 unknowns — the SQP step of a section
//! problem when obstacle constraints are near-active. `H` is made positive definite first
//! (eigenvalues clamped to at least `reg`), as clarabel needs a convex objective and an SQP step
//! must descend. Equality-only steps do not come here: they use the dense nalgebra KKT step
//! ([`crate::numeric::kkt::kkt_step6`]), which is ~100× cheaper.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT,
    SolverStatus, SupportedConeT, ZeroConeT,
};
use nalgebra::{Matrix6, SymmetricEigen, Vector3, Vector6};

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

/// Solve the QP; `None` if clarabel reports anything but (almost) solved.
pub fn qp_step6(
    h: &Matrix6<f64>,
    g: &Vector6<f64>,
    eq_rows: &[Vector6<f64>],
    eq_rhs: &[f64],
    in_rows: &[Vector6<f64>],
    in_rhs: &[f64],
    reg: f64,
) -> Option<QpStep> {
    let e = SymmetricEigen::new(*h);
    let mut d = e.eigenvalues;
    for v in d.iter_mut() {
        *v = v.abs().max(reg);
    }
    let hp = e.eigenvectors * Matrix6::from_diagonal(&d) * e.eigenvectors.transpose();
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
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-12)
        .tol_gap_rel(1e-12)
        .tol_feas(1e-12)
        .build()
        .ok()?;
    let mut solver = DefaultSolver::new(&p, g.as_slice(), &a, &b, &cones, settings).ok()?;
    solver.solve();
    let sol = &solver.solution;
    if !matches!(
        sol.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    ) {
        return None;
    }
    if sol.x.iter().any(|v| !v.is_finite()) {
        return None;
    }
    Some(QpStep {
        x: Vector6::from_row_slice(&sol.x),
        lambda_eq: sol.z[..eq_rows.len()].to_vec(),
        mu: sol.z[eq_rows.len()..].to_vec(),
    })
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
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-12)
        .tol_gap_rel(1e-12)
        .tol_feas(1e-12)
        .build()
        .ok()?;
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).ok()?;
    solver.solve();
    let sol = &solver.solution;
    if !matches!(
        sol.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    ) || !sol.x[0].is_finite()
    {
        return None;
    }
    Some(sol.x[0])
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
        let s = qp_step6(&h, &g, &[], &[], &[row], &[0.25], 1e-12).unwrap();
        assert!((s.x[0] - 0.25).abs() < 1e-8);
        assert!((s.mu[0] - 0.75).abs() < 1e-7);
    }

    /// Two discs, normal to x and to y (both contain z), weight 1: (0.5, 0.5, 1) splits best
    /// as (0, 0.5, 0.5) + (0.5, 0, 0.5), scale √0.5; one disc normal to x cannot reach x at all.
    #[test]
    fn disc_sum_scale_closed_forms() {
        let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
        let s = disc_sum_scale(&Vector3::new(0.5, 0.5, 1.0), &[(y, z, 1.0), (x, z, 1.0)]).unwrap();
        assert!((s - 0.5f64.sqrt()).abs() < 1e-7, "{s}");
        let s = disc_sum_scale(&Vector3::new(0.0, 0.6, 0.8), &[(y, z, 2.0)]).unwrap();
        assert!((s - 0.5).abs() < 1e-7, "{s}");
        assert!(disc_sum_scale(&x, &[(y, z, 1.0)]).is_none_or(|s| s > 1e3));
    }
}
