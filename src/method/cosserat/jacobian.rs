//! The exact shooting Jacobian and the rod's stability, read from one variational pass
//! (module docs, "Jacobian: variational equations" and "Stability"): the pass itself
//! ([`Problem::residual_jac`], [`Problem::focal_stable`]), the focal-point test at each disk,
//! and the test diagnostics comparing the variational Jacobian with central differences.
//! The tangent equations the pass integrates live in `variational.rs`.

use super::problem::{LoadCase, Problem};
use super::shooting::Setup;
use super::variational::Var;
use super::{rot_of, v3, Cosserat, JacobianCheck, RodModel, State, E3};
use crate::error::SolveError;
use crate::model::actuation::{Actuation, Drive};
use crate::model::robot::Robot;
use crate::numeric::so3::vee_skew;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector3};

/// Residual, exact Jacobian, tip, and "no focal point found" of one variational pass.
type JacPass = (DVector<f64>, DMatrix<f64>, Vector3<f64>, bool);

impl Problem<'_> {
    /// The focal-point test at one disk `s` (module docs, "Stability"): with the 6 Jacobi
    /// fields of the base wrench, `U = ∂(p, θ)(s)/∂(n₀, m₀)` (`θ`: spatial rotation,
    /// `δR Rᵀ = θ̂`) and `W = ∂(n, m)(s)/∂(n₀, m₀)` (after the tip's point loads at the tip),
    /// true when `W` is regular and the compliance `C = U W⁻¹` of the base part `[0, s]` to a
    /// wrench at `s` is positive definite (its symmetric part: `C` is symmetric up to the
    /// integration error, the fields spanning a Lagrangian plane).
    pub(super) fn no_focal_point(&self, k: usize, y: &State, ld: &LoadCase, vr: &Var) -> bool {
        let tip = k == self.robot.sections();
        let r = rot_of(y);
        let w = v3(y, 12);
        let u = v3(y, 15);
        let v = match self.set.model {
            RodModel::Full => w,
            RodModel::Kirchhoff => E3,
        };
        let mut um = Matrix6::zeros();
        let mut wm = Matrix6::zeros();
        for d in 0..6 {
            let ty = vr.y[d];
            let dr_m = Matrix3::from_column_slice(&ty.as_slice()[3..12]);
            let om = dr_m * r.transpose();
            let dth = vee_skew(&om) * 0.5;
            let (dn, dm) = if tip {
                let e = vr.resid[d];
                (
                    Vector3::new(e[0], e[1], e[2]),
                    Vector3::new(e[3], e[4], e[5]) * self.len_l,
                )
            } else {
                let dw = v3(&ty, 12);
                let dn = match self.set.model {
                    RodModel::Full => {
                        dr_m * self.kse.component_mul(&(w - E3)) + r * self.kse.component_mul(&dw)
                    }
                    RodModel::Kirchhoff => dw,
                };
                let du = v3(&ty, 15);
                let mut dm = dr_m * self.kbt.component_mul(&u) + r * self.kbt.component_mul(&du);
                // The cables passing `s` are cut with the rod: the momentum conjugate to
                // `(p, θ)` is the wrench of rod and cables, `n + Σ τ R t`,
                // `m + Σ τ (R r) × (R t)` (what the tip's tie forces add at `L`).
                let dv = match self.set.model {
                    RodModel::Full => dw,
                    RodModel::Kirchhoff => Vector3::zeros(),
                };
                let mut dn = dn;
                for (c, cable) in self.robot.cables.iter().enumerate() {
                    let tau = ld.tau[c];
                    if cable.ends_at <= k || tau == 0.0 {
                        continue;
                    }
                    let rp = self.eval_route(c, self.robot.disk_s[k], k);
                    let pd = u.cross(&rp.r) + rp.dr + v;
                    let nrm = pd.norm();
                    let t = pd / nrm;
                    let dpd = du.cross(&rp.r) + dv;
                    let dt = (dpd - t * t.dot(&dpd)) / nrm;
                    let f = r * t * tau;
                    let df = (dr_m * t + r * dt) * tau;
                    dn += df;
                    dm += (dr_m * rp.r).cross(&f) + (r * rp.r).cross(&df);
                }
                (dn, dm)
            };
            let col_u = [ty[0], ty[1], ty[2], dth.x, dth.y, dth.z];
            let col_w = [dn.x, dn.y, dn.z, dm.x, dm.y, dm.z];
            for i in 0..6 {
                um[(i, d)] = col_u[i];
                wm[(i, d)] = col_w[i];
            }
        }
        self.compliance_psd(&um, &wm)
    }

    /// The focal-point test's verdict from the Jacobi fields' `U` and `W` (6×6, columns any
    /// basis of the base wrench's directions: `C = U W⁻¹` does not depend on it): true when
    /// `W` is regular and the symmetric part of `C` is positive semidefinite.
    pub(super) fn compliance_psd(&self, um: &Matrix6<f64>, wm: &Matrix6<f64>) -> bool {
        let Some(wi) = wm.try_inverse() else {
            return false;
        };
        // In units of length per force: `∂(p, L θ)/∂(n, m/L)`, then relative to its largest
        // entry; the inextensible rod's straight state has a zero eigenvalue (an axial force
        // moves nothing), so the test is "no eigenvalue below −1e-9".
        let mut c = um * wi;
        let l = self.len_l;
        for i in 0..3 {
            for j in 0..3 {
                c[(3 + i, j)] *= l;
                c[(i, 3 + j)] *= l;
                c[(3 + i, 3 + j)] *= l * l;
            }
        }
        let sym = (c + c.transpose()) * 0.5;
        let top = sym.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if !(top.is_finite() && top > 0.0) {
            return false;
        }
        // Positive definite (a Cholesky factor exists) is the common verdict and costs a
        // tenth of the eigenvalues; they decide only the rest (semidefinite or not).
        let scaled = sym / top;
        if nalgebra::Cholesky::new(scaled).is_some() {
            return true;
        }
        let eig = nalgebra::SymmetricEigen::new(scaled).eigenvalues;
        eig.iter().all(|&e| e >= -1e-9)
    }

    /// `Some(true)` when the converged `x` has no focal point along the rod with its tensions
    /// held (module docs, "Stability"), `Some(false)` when it has one and every tension is
    /// given (force control), `None` where the test cannot decide: no variational pass
    /// (adaptive steps, point loads at inner disks), or a focal point under displacement
    /// control (fixed cable lengths can still hold a shape that fixed tensions cannot). The
    /// same pass gives the exact shooting Jacobian at `x` (second item), which warm starts
    /// carry.
    pub(super) fn focal_stable(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
    ) -> (Option<bool>, Option<DMatrix<f64>>) {
        let Some((f, jac, _, ok)) = self.jac_pass(x, setup, 1.0, true) else {
            return (None, None);
        };
        if !f[0].is_finite() {
            return (None, None);
        }
        let stable = match (ok, setup.unknown.is_empty()) {
            (true, _) => Some(true),
            (false, true) => Some(false),
            (false, false) => None,
        };
        (stable, Some(jac))
    }

    /// The report's note when [`Self::focal_stable`] leaves `stable` undecided (`None`), so an
    /// unchecked answer never looks like a checked one: `passed` says whether the variational
    /// pass ran (then a focal point under displacement control is why), else why it could not.
    pub(super) fn undecided_stability(&self, passed: bool) -> String {
        let why = if passed {
            "a focal point under displacement control (fixed cable lengths may hold a shape \
             fixed tensions cannot)"
        } else if self.set.adaptive.is_some() {
            "the focal-point test needs fixed RK4 steps, not `--adaptive`"
        } else {
            "no variational pass here (point loads at inner disks: a contact, a disk weight or a \
             tensioned cable ending before the tip)"
        };
        format!("stability not decided: {why}")
    }

    /// Residual, exact Jacobian (variational equations integrated with the state in the same
    /// RK4 pass) and tip; `None` where [`Self::var_ok`] says no.
    ///
    /// Columns: `x = [n(0), m(0)/L, τ_unknown]`. The start tangents follow from
    /// `v(0) = e3 + Kse⁻¹ n(0)`, `u(0) = Kbt⁻¹ m(0)` (`R(0) = I`; Kirchhoff: the state is `n`).
    pub(super) fn residual_jac(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> Option<(DVector<f64>, DMatrix<f64>, Vector3<f64>)> {
        self.jac_pass(x, setup, lam, false)
            .map(|(f, j, tip, _)| (f, j, tip))
    }

    /// [`Self::residual_jac`], and with `focal` the focal-point test along the same pass
    /// (last item: no focal point found).
    fn jac_pass(&self, x: &DVector<f64>, setup: &Setup, lam: f64, focal: bool) -> Option<JacPass> {
        let tau = self.tensions(x, setup, lam);
        if !self.var_ok(setup, &tau, lam) {
            return None;
        }
        let k = x.len();
        let mut var = Var::new(self, k);
        var.focal = focal;
        for (j, &c) in setup.unknown.iter().enumerate() {
            var.tcab[6 + j] = c;
            var.tg.tcab[6 + j] = c;
        }
        let n0 = Vector3::new(x[0], x[1], x[2]);
        let m0 = Vector3::new(x[3], x[4], x[5]) * self.len_l;
        let ld = LoadCase::new(tau, lam);
        let shot = self.shoot(&n0, &m0, &ld, None, Some(&mut var));
        let mut f = DVector::zeros(k);
        let mut jac = DMatrix::zeros(k, k);
        for i in 0..6 {
            f[i] = shot.resid[i];
            for d in 0..k {
                jac[(i, d)] = var.resid[d][i];
            }
        }
        for (j, &c) in setup.unknown.iter().enumerate() {
            f[6 + j] = self.length_row(c, shot.len[c], x[6 + j], lam);
            for d in 0..k {
                jac[(6 + j, d)] = self.kl[c] * var.len[d][c];
            }
            jac[(6 + j, 6 + j)] -= self.kl[c] * self.compliance[c];
        }
        if f.iter().chain(jac.iter()).any(|v| !v.is_finite()) {
            f.fill(f64::NAN);
        }
        Some((f, jac, shot.tip, var.focal_ok))
    }
}

impl Cosserat {
    /// Diagnostic for tests: at the cold start point of a solve (global-balance guess, every
    /// length-controlled cable taut, its tension `tension_guess`), the shooting residual
    /// `F(x)`, its Jacobian from the variational equations, and central differences of `F`
    /// (step `1e-4·max(|x_j|, EI/L²)`: the full rod's `n = R Kse (v − e3)` cancels ~4 digits,
    /// so smaller steps measure rounding). `Ok(None)` where the variational Jacobian is not
    /// available (adaptive steps, point loads at inner disks).
    #[doc(hidden)]
    pub fn shooting_jacobians(
        &self,
        robot: &Robot,
        act: &Actuation,
        tension_guess: f64,
        rel_step: f64,
    ) -> Result<Option<JacobianCheck>, SolveError> {
        let (prob, _) = self.problem(robot, act)?;
        let (setup, x) = cold_start(&prob, robot, tension_guess);
        let Some((f, jv, _)) = prob.residual_jac(&x, &setup, 1.0) else {
            return Ok(None);
        };
        let jc = central_jacobian(&prob, &setup, &x, rel_step);
        Ok(Some((f, jv, jc)))
    }

    /// Diagnostic for tests: the start point `x` of [`Self::shooting_jacobians`] (every
    /// length-controlled cable taut at `tension_guess`, global-balance base wrench) and the
    /// central-difference Jacobian of the shooting residual there, for any robot (also where
    /// the variational one is not available, e.g. cables tied at inner disks).
    #[doc(hidden)]
    pub fn shooting_jacobian_fd(
        &self,
        robot: &Robot,
        act: &Actuation,
        tension_guess: f64,
        rel_step: f64,
    ) -> Result<(DVector<f64>, DMatrix<f64>), SolveError> {
        let (prob, _) = self.problem(robot, act)?;
        let (setup, x) = cold_start(&prob, robot, tension_guess);
        let jc = central_jacobian(&prob, &setup, &x, rel_step);
        Ok((x, jc))
    }
}

/// The cold start point of the test diagnostics: every length-controlled cable taut at
/// `tension_guess`, the base wrench from global balance.
fn cold_start(prob: &Problem<'_>, robot: &Robot, tension_guess: f64) -> (Setup, DVector<f64>) {
    let unknown: Vec<usize> = (0..robot.cables.len())
        .filter(|&c| matches!(prob.modes[c], Drive::Shorten { .. }))
        .collect();
    let setup = Setup {
        slack: vec![false; robot.cables.len()],
        unknown,
        contacts: vec![],
    };
    let mut x = DVector::zeros(6 + setup.unknown.len());
    for j in 0..setup.unknown.len() {
        x[6 + j] = tension_guess;
    }
    prob.balance_guess(&mut x, &setup, 1.0);
    (setup, x)
}

/// Central differences of the shooting residual at `x`, step `rel_step·max(|x_j|, fscale)`.
fn central_jacobian(
    prob: &Problem<'_>,
    setup: &Setup,
    x: &DVector<f64>,
    rel_step: f64,
) -> DMatrix<f64> {
    let mut jc = DMatrix::zeros(x.len(), x.len());
    for col in 0..x.len() {
        let h = rel_step * x[col].abs().max(prob.fscale);
        let mut xp = x.clone();
        xp[col] += h;
        let fp = prob.residual(&xp, setup, 1.0);
        xp[col] -= 2.0 * h;
        let fm = prob.residual(&xp, setup, 1.0);
        jc.set_column(col, &((fp - fm) / (2.0 * h)));
    }
    jc
}
