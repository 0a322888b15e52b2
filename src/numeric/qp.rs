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
use nalgebra::{Matrix6, SymmetricEigen, Vector6};

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
}
