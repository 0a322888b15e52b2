//! The unloaded path's solve (module docs, "Unloaded rod"; `unloaded.rs`): with every tension
//! given, one pass; with length-controlled cables, Newton on their tensions, each iteration
//! one pass that also gives the lengths' tension Jacobian in closed form.
//!
//! # The lengths' Jacobian, and why Newton on the tensions converges
//!
//! The strains at each point minimise `Φ(z; τ) = ½ (v − e3)ᵀ Kse (v − e3) + ½ uᵀ Kbt u +
//! Σ τ_i |ṗ_i|` (`unloaded.rs`), point by point. So `ψ(τ) = ∫ min_z Φ ds` is a minimum of
//! functions affine in `τ`, hence concave, and by the envelope theorem its gradient is the
//! path lengths, `∂ψ/∂τ_i = ∫ |ṗ_i| ds = ℓ_i`. Its Hessian, the lengths' Jacobian, follows
//! from differentiating the balance `F(z; τ) = 0`: `∂z/∂τ_j = −K⁻¹ b_j`, `b_j = ∂F/∂τ_j =
//! [t_j; r_j × t_j]`, which is also `∂|ṗ_j|/∂z`, so
//!
//! ```text
//! ∂ℓ_i/∂τ_j = −∫ b_iᵀ K⁻¹ b_j ds        (symmetric, negative semidefinite)
//! ```
//!
//! integrated by the pass's own Gauss points: the exact derivative of the discrete lengths
//! (up to the strains' Newton tolerance; checked against central differences in
//! `tests/methods/cosserat_unloaded.rs`). The length equations `k_ℓ (ℓ − t − τ/k) = 0` (the
//! shooting rows, `Problem::length_row`) are the stationarity of the concave
//! `ψ(τ) − τ·t − ½ Σ τ_i²/k_i`, so Newton's step on them is an ascent direction of a concave
//! function with a unique maximiser: halving it until the residual falls converges, from the
//! straight rod (`τ = 0`) too. A tension that comes out negative is the slack active set's
//! business (`solve.rs`), as for shooting. Two or three iterations from a cold start on the
//! paper cases, each one pass: no base wrench to shoot for, no variational pass.
//!
//! # Stability without a pass
//!
//! With no external load the rod's configuration is its strain field alone (clamped base,
//! free tip, nothing outside pulls on it: every strain field is a shape), and its potential
//! energy under fixed tensions is `E[z] = ∫ Φ(z(s); τ, s) ds` — the backbone's strain energy
//! and the actuators' `τ_i ℓ_i`, each `ℓ_i = ∫ |ṗ_i| ds` a local function of the strains.
//! `Φ` is the sum of a positive definite quadratic and, for `τ ≥ 0`, the convex `τ_i |ṗ_i|`
//! (a norm of a function affine in `z`), so its Hessian `K` is positive definite at every
//! point and the second variation `∫ δzᵀ K δz ds` is positive for every `δz ≠ 0`: the answer
//! is a strict minimum, stable (`report.stable = Some(true)`), for every tension. The
//! focal-point test along the rod (`jacobian.rs`) must then find no focal point, and it
//! does: its compliance `C(s)` of the base part is `∫₀ˢ Adᵀ K⁻¹ Ad dσ` here, a sum of
//! positive definite terms (checked against it on random robots in
//! `tests/methods/cosserat_unloaded.rs`). Under displacement control the tensions are the
//! length constraints' multipliers, the Lagrangian's Hessian is the same `K`, positive
//! definite on every perturbation and so on the constraints' tangent space too; a compliant
//! cable adds `k δℓ² ≥ 0`. Cables guided along the rod cannot buckle it, however hard they
//! pull (a duct-guided prestressing tendon does not buckle its column; the same force as a
//! dead tip load does, `tests/methods/cosserat_stability.rs`). The check therefore costs
//! nothing here; shooting's focal-point pass costs one variational pass.

use super::problem::{LoadCase, Problem};
use super::shooting::{Fail, Newton, Setup};
use super::unloaded::{Sens, Unloaded};
use super::MAX_CABLES;
use crate::model::actuation::Drive;
use nalgebra::{DMatrix, DVector};

/// Halvings of a Newton step before the unloaded solve gives up (and the rod shoots).
const MAX_HALVINGS: usize = 12;

impl Problem<'_> {
    /// The unloaded solve (no external load): the given tensions and, for length-controlled
    /// cables (`setup.unknown`), Newton on theirs from `x0`'s (module docs); the base wrench
    /// `x = [n(0), m(0)/L, τ_unknown]` from the last pass, the Newton iterations, and as the
    /// residual the larger of the length rows' and the largest balance residual at a point.
    /// A note says which path was taken.
    pub(super) fn solve_unloaded(
        &self,
        x0: &DVector<f64>,
        setup: &Setup,
        notes: &mut Vec<String>,
    ) -> Result<(Newton, usize), Fail> {
        let nu = setup.unknown.len();
        let mut x = DVector::zeros(6 + nu);
        for j in 0..nu {
            x[6 + j] = x0[6 + j];
        }
        let mut sens = [[0.0; MAX_CABLES]; MAX_CABLES];
        let fail = |iterations, residual, detail: &str| Fail {
            iterations,
            residual,
            detail: detail.into(),
        };
        let unsettled = "the strains of the unloaded rod did not settle at some point";
        let (mut un, mut f) = self
            .unloaded_lengths(&x, setup, &mut sens)
            .ok_or_else(|| fail(0, f64::NAN, unsettled))?;
        let mut iterations = 0;
        while f.amax() > self.set.tolerance {
            if iterations == self.set.max_iterations {
                let detail = "Newton on the unloaded rod's tensions did not converge";
                return Err(fail(iterations, f.amax(), detail));
            }
            iterations += 1;
            let jac = DMatrix::from_fn(nu, nu, |i, j| {
                let (ci, cj) = (setup.unknown[i], setup.unknown[j]);
                let own = if i == j { self.compliance[ci] } else { 0.0 };
                self.kl[ci] * (sens[ci][cj] - own)
            });
            let Some(step) = jac.lu().solve(&-&f) else {
                let detail = "singular length Jacobian on the unloaded rod";
                return Err(fail(iterations, f.amax(), detail));
            };
            let mut alpha = 1.0;
            let mut halvings = 0;
            loop {
                let mut xt = x.clone();
                for j in 0..nu {
                    xt[6 + j] += alpha * step[j];
                }
                let mut st = [[0.0; MAX_CABLES]; MAX_CABLES];
                match self.unloaded_lengths(&xt, setup, &mut st) {
                    Some((ut, ft)) if ft.norm() < f.norm() => {
                        (x, un, f, sens) = (xt, ut, ft, st);
                        break;
                    }
                    _ if halvings == MAX_HALVINGS => {
                        let detail = "line search failed on the unloaded rod's tensions";
                        return Err(fail(iterations, f.amax(), detail));
                    }
                    _ => {
                        alpha *= 0.5;
                        halvings += 1;
                    }
                }
            }
        }
        let steps: usize = self.nsteps[1..].iter().sum();
        notes.push(match nu {
            0 => format!(
                "unloaded: strains from the tendons' balance, {steps} Magnus steps, no shooting"
            ),
            _ => format!(
                "unloaded: strains from the tendons' balance, {steps} Magnus steps, \
                 {iterations} Newton iterations on {nu} cable tensions, no shooting"
            ),
        });
        for i in 0..3 {
            x[i] = un.n0[i];
            x[3 + i] = un.ms[i];
        }
        Ok((
            Newton {
                x,
                iterations,
                residual: f.amax().max(un.residual),
                jac: None,
            },
            0,
        ))
    }

    /// One unloaded pass at the tensions of `x`: the pass, the length rows of the unknown
    /// cables, and (into `sens`, when there are unknowns) the lengths' tension Jacobian.
    fn unloaded_lengths(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        sens: &mut Sens,
    ) -> Option<(Unloaded, DVector<f64>)> {
        let ld = LoadCase::new(self.tensions(x, setup, 1.0), 1.0);
        let mut asked = [false; MAX_CABLES];
        for &c in &setup.unknown {
            asked[c] = true;
        }
        let want = !setup.unknown.is_empty();
        let un = self.unloaded_pass(&ld, None, want.then_some((sens, asked)))?;
        let f = DVector::from_fn(setup.unknown.len(), |j, _| {
            let c = setup.unknown[j];
            self.length_row(c, un.shot.len[c], x[6 + j], 1.0)
        });
        Some((un, f))
    }

    /// True when the answer `x` of the unloaded path is proven stable (module docs,
    /// "Stability without a pass"): every tension finite and non-negative (the slack active
    /// set has made a negative unknown tension slack before an answer is returned).
    pub(super) fn convex_stable(&self, x: &DVector<f64>, setup: &Setup) -> bool {
        let tau = self.tensions(x, setup, 1.0);
        tau[..self.robot.cables.len()]
            .iter()
            .all(|t| t.is_finite() && *t >= 0.0)
    }

    /// Leave the unloaded path for shooting (its Newton on the tensions failed): the rest
    /// lengths again by shooting's quadrature, so targets and lengths agree.
    pub(super) fn shoot_instead(&mut self) {
        self.fast = false;
        if self
            .modes
            .iter()
            .any(|m| matches!(m, Drive::Shorten { .. }))
        {
            let zero = LoadCase::new([0.0; MAX_CABLES], 0.0);
            let origin = nalgebra::Vector3::zeros();
            self.len0 = self.pass(&origin, &origin, &zero, None).len;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::cosserat::Cosserat;
    use crate::method::Method;
    use crate::model::actuation::Input;
    use crate::model::Model;

    /// The closed-form lengths' Jacobian (module docs) against central differences of the
    /// pass's lengths, on case III (a cable tied at an inner disk: the strains jump there),
    /// full and inextensible: the same to 1e-6 of its largest entry, symmetric, and with a
    /// negative diagonal (more tension, shorter path).
    #[test]
    fn lengths_jacobian_is_the_central_difference_of_the_lengths() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/models/paper/case3.toml");
        let model = Model::from_file(path).expect("case III");
        for set in [Cosserat::full(), Cosserat::kirchhoff()] {
            let set = set.with_control(Input::Shortening);
            let (prob, _) = set
                .problem(&model.robot, &model.actuation)
                .expect("problem");
            assert!(
                prob.fast,
                "case III under displacement control takes the unloaded path"
            );
            let nc = model.robot.cables.len();
            let mut tau = [0.0; MAX_CABLES];
            for (c, t) in tau.iter_mut().enumerate().take(nc) {
                *t = 1.0 + 0.5 * c as f64;
            }
            let mut sens = [[0.0; MAX_CABLES]; MAX_CABLES];
            let all = [true; MAX_CABLES];
            let ld = LoadCase::new(tau, 1.0);
            prob.unloaded_pass(&ld, None, Some((&mut sens, all)))
                .expect("pass");
            let biggest = (0..nc)
                .flat_map(|i| (0..nc).map(move |j| (i, j)))
                .map(|(i, j)| sens[i][j].abs())
                .fold(0.0, f64::max);
            let h = 1e-3;
            for j in 0..nc {
                let lengths = |d: f64| {
                    let mut t = tau;
                    t[j] += d;
                    let pass = prob.unloaded_pass(&LoadCase::new(t, 1.0), None, None);
                    pass.expect("pass").shot.len
                };
                let (up, down) = (lengths(h), lengths(-h));
                for i in 0..nc {
                    let central = (up[i] - down[i]) / (2.0 * h);
                    let err = (sens[i][j] - central).abs();
                    assert!(
                        err <= 1e-6 * biggest,
                        "{} ∂ℓ{i}/∂τ{j}: {:e} vs {central:e}",
                        set.name(),
                        sens[i][j]
                    );
                    assert!((sens[i][j] - sens[j][i]).abs() <= 1e-9 * biggest);
                }
                assert!(sens[j][j] < 0.0);
            }
        }
    }
}
