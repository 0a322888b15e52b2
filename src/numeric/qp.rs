//! Small convex QP steps with inequalities, solved by clarabel.
//!
//! `min ½ xᵀ H x + gᵀ x  s.t.  E x = e,  G x ≤ h` for 6 unknowns — the SQP step of a section
//! problem when obstacle constraints are near-active. `H` is made positive definite first
//! (eigenvalues clamped to at least `reg`), as clarabel needs a convex objective and an SQP step
//! must descend. Equality-only steps do not come here: they use the dense nalgebra KKT step
//! ([`crate::numeric::kkt::kkt_step6`]), which is ~100× cheaper.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus,
    SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, Matrix6, SymmetricEigen, Vector6};

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

/// Solve the dense QP `min ½ xᵀ H x + gᵀ x  s.t.  E x = e,  G x ≤ h` of any (small) size with
/// clarabel; `H` must be symmetric positive semidefinite (only its upper triangle is read).
/// `None` when clarabel reports anything but (almost) solved — an infeasible QP included.
/// Used by the inverse problems ([`crate::reach`]) whose unknowns are the cable inputs.
pub fn qp_dense(
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
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-14)
        .tol_gap_rel(1e-12)
        .tol_feas(1e-12)
        .build()
        .ok()?;
    let mut solver = DefaultSolver::new(&p, g, &a, &b, &cones, settings).ok()?;
    solver.solve();
    let sol = &solver.solution;
    if !matches!(
        sol.status,
        SolverStatus::Solved | SolverStatus::AlmostSolved
    ) || sol.x.iter().any(|v| !v.is_finite())
    {
        return None;
    }
    Some(sol.x.clone())
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
}
