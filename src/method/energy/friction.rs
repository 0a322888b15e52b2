//! Capstan friction along displacement-driven cables (`hardware.friction` in a sequence of
//! rows; [`crate::model::actuation::CableDrive::capstan`]).
//!
//! # Derivation
//!
//! A cable of tension `T(s)` running along the curve `p_c(s)` with unit tangent `t` loads the
//! backbone with `(T t)'` per length (the normal force `T t'` where it is bent, the friction
//! `T' t` along it) and, where it is tied, with `−T t`. Their virtual work in a virtual motion
//! `δp_c` that holds the base fixed is, integrating by parts,
//!
//! ```text
//! δW = ∫ (T t)' · δp_c ds − T_end t_end · δp_c,end = −∫ T(s) δ|p_c'| ds,
//! ```
//!
//! the tension times the local change of path length: for a frictionless cable (`T` const) it is
//! `−T δL_c`, the model's `λ_c ∇L_c`. With friction the cable slides through the holes (of
//! the disks, or along the continuous routing of the path measure) and by Coulomb's law the
//! friction per length is `μ` times the normal force `T |t'|`, against the sliding: the capstan
//! (Euler–Eytelwein) law `T' = −a T |t'|`, i.e. `T(θ) = T_a e^{−a θ}` with `θ(s) = ∫₀ˢ |t'|` the
//! wrap angle from the base, `T_a` the tension at the actuator and `a = μ s` (`s = +1` while the
//! cable is pulled in and slides toward the actuator: the tension falls toward the tie; `−1`
//! while it is paid out: it rises). This is the friction model of tendon-driven continuum
//! robots in Kato, Okumura, Kose, Takagi & Hata, "Extended kinematic mapping of
//! tendon-driven continuum robot for neuroendoscopy", IROS 2014 (tension decaying
//! exponentially with the accumulated bending angle), also in Rucker & Webster (IEEE T-RO 2011,
//! §VII: friction lowers the tension along the path).
//!
//! In the energy model's straight-routed sub-arcs the cable tangent turns with the backbone
//! (`w = v + u × r` keeps its direction when `r` lies in the bending plane; for a cable off that
//! plane the backbone's bending angle is the leading term, `O(κ r)` smaller effects are left
//! out), so the wrap across sub-arc `j` is `θ_j = ℓ_j |(κx, κy)_j|`, and the cable's local
//! stretch rate `|w|` is constant along a straight-routed sub-arc. The virtual work of cable `c`
//! is then `−T_a Σ_j w_cj δL_cj` with the mean tension factor over sub-arc `j`
//!
//! ```text
//! w_cj = e^{−a Θ_j} φ(a θ_j),   Θ_j = Σ_{i<j} θ_i,   φ(x) = (1 − e^{−x}) / x   (φ(0) = 1),
//! ```
//!
//! exact for the constant curvature of the sub-arc (`(1/θ_j) ∫₀^{θ_j} e^{−a (Θ_j + ϑ)} dϑ`).
//! Equilibrium is therefore `∇E + Σ_c λ_c Σ_j w_cj ∇L_cj = 0` with `λ_c = T_a` the actuator
//! tension, and the cable length is still what the actuator and the compliance allow:
//! `L_c − t_c − λ_c/k_c ≤ 0 ⊥ λ_c ≥ 0` (the lumped compliance `1/k` sits at the actuator, it
//! stretches with `T_a`). The weights depend on the shape: the system is not the stationarity
//! of an energy (friction is not conservative) and its Jacobian is not symmetric.
//!
//! # Solution: lagged weights
//!
//! With the weights `w^k` frozen at the strains `ξ^k`, the system is the KKT system of the
//! model's convex problem with every cable's quadrature weights scaled by `w^k_cj` (its
//! weighted length `L̃_c = Σ_j w^k_cj L_cj`) and the target shifted by `L̃_c(ξ^k) − L_c(ξ^k)`:
//! `L̃_c(ξ) − L̃_c(ξ^k) + L_c(ξ^k) − t_c − λ_c/k_c ≤ 0`. It is solved warm from `ξ^k`; the
//! weights are updated at the result and the pass repeated until the true residual (the
//! stationarity with the new weights, `|Σ_c λ_c Σ_j (w^{k+1}_cj − w^k_cj) ∇L_cj|∞` scaled as
//! the solver's, and the true length error) is below [`FRICTION_TOLERANCE`]. At the fixed point
//! `ξ^{k+1} = ξ^k` the shifted constraint is the true one.
//!
//! # Newton polish
//!
//! The lagged passes are a fixed-point (Picard) iteration `x^{k+1} = G(x^k)`; near a fixed
//! point they converge linearly with the rate `ρ(G')`, the spectral radius of its Jacobian, and
//! only when `ρ < 1` (Ostrowski's theorem: Ortega & Rheinboldt, *Iterative Solution of
//! Nonlinear Equations in Several Variables*, 1970, 10.1.3). `G'` is `−K̃⁻¹ M` on the taut
//! cables' tangent space (`K̃` the lagged problem's Hessian, `M = Σ_c λ_c Σ_j ∇L_cj ∇w_cjᵀ` of
//! `Problem::friction_jacobian`): a change `Δθ` of wrap changes the weights by `a Δθ` and the
//! generalized force by `λ a Δθ ∇L`, against a bending stiffness `EI/ℓ`, so `ρ` grows like
//! `μ λ r ℓ / EI`. With compliant tendons `λ` stays a few newtons and `ρ` ≈ 0.02–0.5; with
//! rigid tendons pulling against each other (the nominal v4's `all3_same_dir180_hold` rows: the
//! three distal tendons taut at 110–150 N, compressing the backbone) `ρ` ≈ 0.8 to ≥ 1, and the
//! passes creep or wander (`tests/hardware/hardware_friction.rs`).
//!
//! Full Newton steps on the friction equilibrium (`[∇E + Σ_c λ_c Σ_j w_cj ∇L_cj; L_c − t_c −
//! λ_c/k_c]` with the non-symmetric matrix of `Problem::friction_jacobian`, the taut set held
//! fixed) converge quadratically from close enough whatever `ρ` (Dennis & Schnabel, *Numerical
//! Methods for Unconstrained Optimization and Nonlinear Equations*, 1983, Thm 5.2.1), provided
//! the taut set is the solution's: with it fixed the complementarity becomes equations, as an
//! SQP method's once its active set is identified (Nocedal & Wright, *Numerical Optimization*,
//! 2nd ed., §18.1). So the polish is tried after pass 0 and again whenever the taut set is the
//! one of the previous pass (settled) and the residual has fallen below `POLISH_RETRY` (0.1) times
//! the one a failed polish started from (at most one try per tenfold gain, a few per row). A
//! step that does not halve the residual, makes a tension negative or stretches a slack cable
//! hands back to the lagged passes, which bring the iterate closer. A row the passes end at
//! pass 0 or 1, or without a polish, is computed as before to the bit; a row they would have
//! ended later may now end earlier by a polish, at another point within [`FRICTION_TOLERANCE`].
//! A solve without friction (`a = 0` for every cable) never enters this file: it is today's
//! model to the bit. The tip Jacobian
//! of a solve with friction comes from the full, non-symmetric linearization
//! (`Problem::friction_jacobian`); its stability is not reported.

use super::lengths::Work;
use super::newton::Solution;
use super::problem::{NodeRow, Problem, Target};
use super::Energy;
use crate::error::SolveError;
use crate::method::Method;
use crate::model::actuation::{Actuation, Input, LengthMeasure};
use crate::shape::TipJacobian;
use nalgebra::{DMatrix, DVector};
use std::borrow::Cow;

/// Residual \[m\] (length, and stationarity expressed as a length) at which the friction
/// passes stop: 1 nm, a thousandth of a micrometre of tip (the data's unit is the mm).
pub const FRICTION_TOLERANCE: f64 = 1e-9;

/// Most friction passes (each a warm Newton solve) before the solve reports non-convergence.
pub const MAX_FRICTION_PASSES: usize = 60;

/// Most full Newton steps of one polish ([`Problem::friction_newton`]).
const POLISH_STEPS: usize = 8;

/// A polish that failed is tried again from the same taut set only once the lagged passes have
/// brought the residual below this fraction of the residual it was tried at (module docs).
const POLISH_RETRY: f64 = 0.1;

/// The signed capstan coefficient of every cable, `None` when no cable has friction.
pub(super) fn coefficients(act: &Actuation) -> Option<Vec<f64>> {
    act.cables
        .iter()
        .any(|d| d.capstan != 0.0)
        .then(|| act.cables.iter().map(|d| d.capstan).collect())
}

/// `φ(x) = (1 − e^{−x}) / x`, `φ(0) = 1` (module docs).
pub fn mean_factor(x: f64) -> f64 {
    if x == 0.0 {
        1.0
    } else {
        -(-x).exp_m1() / x
    }
}

/// `φ'(x) = (e^{−x}(1 + x) − 1) / x²` (series `−1/2 + x/3 − x²/8` near 0).
pub fn mean_factor_slope(x: f64) -> f64 {
    if x.abs() < 1e-4 {
        -0.5 + x / 3.0 - x * x / 8.0
    } else {
        ((-x).exp() * (1.0 + x) - 1.0) / (x * x)
    }
}

/// Mean tension factors `w_cj` (module docs) of every cable over the sub-arcs it reaches, for
/// the strains `xi` and signed coefficients `a`.
pub(super) fn weights(prob: &Problem, a: &[f64], xi: &[f64]) -> Vec<Vec<f64>> {
    prob.robot
        .cables
        .iter()
        .zip(a)
        .map(|(cable, &ac)| {
            let n = prob.first[cable.ends_at];
            if ac == 0.0 {
                return vec![1.0; n];
            }
            let mut wrap = 0.0;
            (0..n)
                .map(|j| {
                    let th = prob.ell[j] * xi[4 * j].hypot(xi[4 * j + 1]);
                    let w = (-ac * wrap).exp() * mean_factor(ac * th);
                    wrap += th;
                    w
                })
                .collect()
        })
        .collect()
}

/// `base` with every cable's quadrature weights on sub-arc `j` scaled by `w[c][j]`.
fn scaled(base: &[NodeRow], w: &[Vec<f64>]) -> Vec<NodeRow> {
    base.iter()
        .zip(w)
        .map(|(row, wc)| {
            row.iter()
                .zip(wc)
                .map(|(nodes, &f)| {
                    let mut out = *nodes;
                    for nd in out.iter_mut() {
                        nd[4] *= f;
                    }
                    out
                })
                .collect()
        })
        .collect()
}

impl Energy {
    /// Solve `prob` (built with the unscaled routing samples `base` and the true targets) with
    /// capstan friction `a` per cable by lagged weights (module docs), from `start`. Returns
    /// the lagged problem of the last pass (its weighted samples and shifted targets) and its
    /// solution, with the Newton iterations of every pass.
    pub(super) fn solve_with_friction<'a>(
        &'a self,
        mut prob: Problem<'a>,
        base: &'a [NodeRow],
        a: &[f64],
        start: (Vec<f64>, Vec<f64>),
    ) -> Result<(Problem<'a>, Solution), SolveError> {
        if self.cable_length != LengthMeasure::Path {
            return Err(SolveError::Unsupported {
                method: self.name().into(),
                reason: "capstan friction (`hardware.friction`) is modelled with the path cable \
                         length only (`--set length=path`)"
                    .into(),
            });
        }
        prob.want_sensitivity = false;
        let nc = prob.robot.cables.len();
        let targets = prob.targets.clone();
        let (mut xi, mut lam) = start;
        let mut w = weights(&prob, a, &xi);
        let (mut len, mut lenw) = (vec![0.0; nc], vec![0.0; nc]);
        let mut iterations = 0;
        let mut resid = f64::INFINITY;
        // The taut set of the previous pass, and the residual of the last polish tried from
        // it ("Newton polish": retried once the taut set has settled).
        let mut prev_taut: Vec<usize> = vec![];
        let mut polished_at = f64::INFINITY;
        for pass in 0..MAX_FRICTION_PASSES {
            // The lagged problem at ξ^k: weighted samples, shifted targets.
            prob.nodes = Cow::Borrowed(base);
            prob.lengths(&xi, &mut len);
            prob.nodes = Cow::Owned(scaled(base, &w));
            prob.lengths(&xi, &mut lenw);
            for c in 0..nc {
                if let Target::Length(t) = targets[c] {
                    prob.targets[c] = Target::Length(t + lenw[c] - len[c]);
                }
            }
            let sol = self
                .newton_from(&prob, (xi, lam), None)
                .map_err(|e| match e {
                    SolveError::NotConverged {
                        method,
                        section,
                        iterations: it,
                        residual,
                        detail,
                    } => SolveError::NotConverged {
                        method,
                        section,
                        iterations: iterations + it,
                        residual,
                        detail: format!("{detail} (capstan friction pass {pass})"),
                    },
                    e => e,
                })?;
            iterations += sol.iterations;
            xi = sol.xi.clone();
            lam = sol.lam.clone();
            let w_new = weights(&prob, a, &xi);
            resid = self.friction_residual(&mut prob, base, &targets, &w, &w_new, &xi, &lam);
            w = w_new;
            let mut sol = sol;
            let taut: Vec<usize> = (0..nc).filter(|&c| lam[c] > 0.0).collect();
            if taut != prev_taut {
                polished_at = f64::INFINITY;
            }
            let settled = taut == prev_taut && resid < POLISH_RETRY * polished_at;
            prev_taut = taut;
            if resid > FRICTION_TOLERANCE && (pass == 0 || settled) {
                polished_at = resid;
                if let Some((x, l, r, steps)) = prob.friction_newton(base, a, &xi, &lam) {
                    (xi, lam, resid) = (x, l, r);
                    iterations += steps;
                    w = weights(&prob, a, &xi);
                    sol.xi.clone_from(&xi);
                    sol.lam.clone_from(&lam);
                }
            }
            if resid <= FRICTION_TOLERANCE {
                if self.sensitivity {
                    sol.sensitivity.jacobian = prob.friction_jacobian(&FrictionPoint {
                        base,
                        a,
                        w: &w,
                        xi: &xi,
                        lam: &lam,
                    });
                }
                let sol = Solution {
                    iterations,
                    residual: sol.residual.max(resid),
                    ..sol
                };
                return Ok((prob, sol));
            }
        }
        Err(SolveError::NotConverged {
            method: self.name().into(),
            section: None,
            iterations,
            residual: resid,
            detail: format!(
                "capstan friction: {MAX_FRICTION_PASSES} passes of lagged weights did not \
                 settle (residual = max(length error [m], r̄·|Σ λ Δw ∇L|∞/(EI ℓ)))"
            ),
        })
    }

    /// The true residual at `xi` after a pass with weights `w_old` (module docs): the length
    /// error against the true targets, and the stationarity change `Σ_c λ_c Σ_j (w_new − w_old)
    /// ∇L_cj` as a length (the lagged stationarity is solved to the solver's tolerance). Leaves
    /// `prob` the true problem: unscaled samples `base`, the true `targets`.
    #[allow(clippy::too_many_arguments)]
    fn friction_residual<'a>(
        &self,
        prob: &mut Problem<'a>,
        base: &'a [NodeRow],
        targets: &[Target],
        w_old: &[Vec<f64>],
        w_new: &[Vec<f64>],
        xi: &[f64],
        lam: &[f64],
    ) -> f64 {
        let nc = targets.len();
        prob.targets.copy_from_slice(targets);
        let dw: Vec<Vec<f64>> = w_new
            .iter()
            .zip(w_old)
            .map(|(n, o)| n.iter().zip(o).map(|(a, b)| a - b).collect())
            .collect();
        prob.nodes = Cow::Owned(scaled(base, &dw));
        let mut work = Work::new(prob);
        prob.evaluate(xi, &vec![0.0; nc], &mut work, false);
        let mut stat = 0.0f64;
        for i in 0..prob.nvar() {
            let g: f64 = (0..nc).map(|c| lam[c] * work.grad[c][i]).sum();
            stat = stat.max(g.abs());
        }
        prob.nodes = Cow::Borrowed(base);
        let mut len = vec![0.0; nc];
        prob.lengths(xi, &mut len);
        let mut feas = 0.0f64;
        for c in 0..nc {
            if let Target::Length(_) = targets[c] {
                let gap = prob.cable_gap(c, len[c], lam[c]);
                feas = feas.max(if lam[c] > 0.0 {
                    gap.abs()
                } else {
                    gap.max(0.0)
                });
            }
        }
        feas.max(stat * prob.stat_scale)
    }
}

/// A point of the friction equilibrium: the unscaled samples `base`, the capstan exponents
/// `a` (`μ s` per cable, module docs), the weights `w` at `xi`, the strains `xi` and the multipliers `lam`.
#[derive(Clone, Copy)]
struct FrictionPoint<'b> {
    base: &'b [NodeRow],
    a: &'b [f64],
    w: &'b [Vec<f64>],
    xi: &'b [f64],
    lam: &'b [f64],
}

impl<'a> Problem<'a> {
    /// Full Newton steps on the friction equilibrium (module docs, "Newton polish") from `xi`,
    /// `lam` with the taut set fixed; `Some((ξ, λ, residual, steps))` once the residual is
    /// below [`FRICTION_TOLERANCE`], `None` when a step does not reduce it, makes a tension
    /// negative, or pulls a slack cable taut (the caller goes on with lagged passes).
    fn friction_newton(
        &mut self,
        base: &[NodeRow],
        a: &[f64],
        xi: &[f64],
        lam: &[f64],
    ) -> Option<(Vec<f64>, Vec<f64>, f64, usize)> {
        if !self.frame_forces.is_empty() || self.world.is_some() {
            return None;
        }
        let (mut xi, mut lam) = (xi.to_vec(), lam.to_vec());
        let mut prev = f64::INFINITY;
        for step in 0..POLISH_STEPS {
            let w = weights(self, a, &xi);
            let (r, resid) = self.friction_equations(base, &w, &xi, &lam)?;
            if resid <= FRICTION_TOLERANCE {
                return Some((xi, lam, resid, step));
            }
            if resid >= 0.5 * prev {
                return None;
            }
            prev = resid;
            let at = FrictionPoint {
                base,
                a,
                w: &w,
                xi: &xi,
                lam: &lam,
            };
            let (m, taut) = self.friction_kkt(&at);
            let d = m.lu().solve(&(-r))?;
            let nv = self.nvar();
            for i in 0..nv {
                xi[i] += d[i];
            }
            for (k, &c) in taut.iter().enumerate() {
                lam[c] += d[nv + k];
                if lam[c] < 0.0 {
                    return None;
                }
            }
        }
        None
    }

    /// The friction equilibrium's equations at `xi`, `lam` (weights `w` at `xi`): the vector
    /// `[∇E + Σ_c λ_c Σ_j w_cj ∇L_cj; L_c − t_c − λ_c/k_c (taut c)]` and the residual (the
    /// stationarity as a length, the length errors, a slack cable's excess length); `None`
    /// when a slack cable would be stretched.
    fn friction_equations(
        &mut self,
        base: &[NodeRow],
        w: &[Vec<f64>],
        xi: &[f64],
        lam: &[f64],
    ) -> Option<(DVector<f64>, f64)> {
        let (nv, nc) = (self.nvar(), self.robot.cables.len());
        let wgt: Vec<f64> = (0..nc)
            .map(|c| self.cable_weight(c, lam[c].max(0.0)))
            .collect();
        let true_nodes = std::mem::replace(&mut self.nodes, Cow::Owned(scaled(base, w)));
        let mut work = Work::new(self);
        self.evaluate(xi, &wgt, &mut work, false);
        self.nodes = true_nodes;
        let mut len = vec![0.0; nc];
        self.lengths(xi, &mut len);
        let taut: Vec<usize> = (0..nc)
            .filter(|&c| matches!(self.targets[c], Target::Length(_)) && lam[c] > 0.0)
            .collect();
        let mut r = DVector::zeros(nv + taut.len());
        let mut stat = 0.0f64;
        let mut ge = vec![0.0; nv];
        self.energy_gradient(xi, &mut ge);
        for i in 0..nv {
            let g = ge[i] + (0..nc).map(|c| wgt[c] * work.grad[c][i]).sum::<f64>();
            r[i] = g;
            stat = stat.max(g.abs());
        }
        let mut feas = 0.0f64;
        for c in 0..nc {
            if let Target::Length(_) = self.targets[c] {
                let gap = self.cable_gap(c, len[c], lam[c]);
                if let Some(k) = taut.iter().position(|&t| t == c) {
                    r[nv + k] = gap;
                    feas = feas.max(gap.abs());
                } else if gap > FRICTION_TOLERANCE {
                    return None;
                }
            }
        }
        Some((r, feas.max(stat * self.stat_scale)))
    }

    /// The non-symmetric KKT matrix of [`Problem::friction_jacobian`] at `xi`, `lam` (weights
    /// `w` at `xi`), with the taut cables (`λ > 0`) as rows.
    fn friction_kkt(&mut self, at: &FrictionPoint) -> (DMatrix<f64>, Vec<usize>) {
        let FrictionPoint {
            base,
            a,
            w,
            xi,
            lam,
        } = *at;
        let (nv, nc) = (self.nvar(), self.robot.cables.len());
        let wgt: Vec<f64> = (0..nc)
            .map(|c| self.cable_weight(c, lam[c].max(0.0)))
            .collect();
        // Unweighted gradients ∇L_c (block j = ∇L_cj) from the true samples.
        let mut plain = Work::new(self);
        self.evaluate(xi, &wgt, &mut plain, false);
        // H̃: the Hessian of the lagged problem (weighted samples).
        let true_nodes = std::mem::replace(&mut self.nodes, Cow::Owned(scaled(base, w)));
        let mut work = Work::new(self);
        self.path_hessian(xi, &wgt, &mut work);
        self.nodes = true_nodes;
        let taut: Vec<usize> = (0..nc)
            .filter(|&c| matches!(self.targets[c], Target::Length(_)) && lam[c] > 0.0)
            .collect();
        let k = taut.len();
        let mut m = DMatrix::zeros(nv + k, nv + k);
        for b in 0..self.nsub {
            for i in 0..4 {
                for j in 0..4 {
                    m[(4 * b + i, 4 * b + j)] = work.hess[b * 16 + i * 4 + j];
                }
            }
        }
        // ∂θ_i/∂(κx, κy).
        let dtheta: Vec<[f64; 2]> = (0..self.nsub)
            .map(|i| {
                let (kx, ky) = (xi[4 * i], xi[4 * i + 1]);
                let n = kx.hypot(ky);
                if n > 0.0 {
                    [self.ell[i] * kx / n, self.ell[i] * ky / n]
                } else {
                    [0.0, 0.0]
                }
            })
            .collect();
        for (r, &c) in taut.iter().enumerate() {
            let ac = a[c];
            let g = &plain.grad[c];
            let nj = self.first[self.robot.cables[c].ends_at];
            let mut wrap = 0.0;
            for j in 0..nj {
                let th = self.ell[j] * xi[4 * j].hypot(xi[4 * j + 1]);
                // Column (G̃) and row (A) of cable c.
                for q in 0..4 {
                    m[(4 * j + q, nv + r)] = w[c][j] * g[4 * j + q];
                    m[(nv + r, 4 * j + q)] = g[4 * j + q];
                }
                if ac != 0.0 {
                    let here = ac * (-ac * wrap).exp() * mean_factor_slope(ac * th);
                    for i in 0..=j {
                        let dw = if i < j { -ac * w[c][j] } else { here };
                        for q in 0..4 {
                            let f = lam[c] * g[4 * j + q] * dw;
                            m[(4 * j + q, 4 * i)] += f * dtheta[i][0];
                            m[(4 * j + q, 4 * i + 1)] += f * dtheta[i][1];
                        }
                    }
                }
                wrap += th;
            }
            m[(nv + r, nv + r)] = -self.compliance[c];
        }
        (m, taut)
    }

    /// The tip Jacobian in the shortenings of a solve with capstan friction at its fixed point
    /// `xi`, `lam` (`self` the true problem: unscaled samples `base`, true targets; `w` the
    /// weights at `xi`). Linearizing `∇E + Σ_c λ_c Σ_j w_cj ∇L_cj = 0` and `L_c − t_c − λ_c/k_c
    /// = 0` (taut cables) with `dt_c = −dδ_c`:
    ///
    /// ```text
    /// [H̃ + M   G̃ ] [dξ]   [ 0   ]      H̃ = K + Σ_c λ_c Σ_j w_cj ∇²L_cj,  G̃_c = Σ_j w_cj ∇L_cj,
    /// [A      −C ] [dλ] = [−e_c ],     M = Σ_c λ_c Σ_j ∇L_cj ∇w_cjᵀ,     A_c = ∇L_c,  C = diag(1/k),
    /// ```
    ///
    /// with `∂w_cj/∂θ_i = −a w_cj` (`i < j`), `a e^{−aΘ_j} φ'(aθ_j)` (`i = j`), and `∂θ_i/∂κ =
    /// ℓ_i κ/|κ|` (0 on a straight sub-arc). Dense LU (the system is not symmetric). `None` with
    /// dead loads or obstacles (their curvature is not added here), or when singular.
    fn friction_jacobian(&mut self, at: &FrictionPoint) -> Option<TipJacobian> {
        if !self.frame_forces.is_empty() || self.world.is_some() {
            return None;
        }
        let (nv, nc) = (self.nvar(), self.robot.cables.len());
        let (m, taut) = self.friction_kkt(at);
        let k = taut.len();
        let lu = m.lu();
        let mut which = vec![];
        let mut dxis = vec![];
        for c in 0..nc {
            if !matches!(self.targets[c], Target::Length(_)) {
                continue;
            }
            let mut b = DVector::zeros(nv + k);
            if let Some(r) = taut.iter().position(|&t| t == c) {
                b[nv + r] = -1.0;
            }
            let x = lu.solve(&b)?;
            which.push((c, Input::Shortening));
            dxis.push(x.rows(0, nv).iter().copied().collect());
        }
        self.tip_columns(at.xi, &which, &dxis)
    }
}

#[cfg(test)]
mod tests {
    use super::mean_factor;

    /// `φ(x) = (1 − e^{−x})/x` is the mean of `e^{−ϑ}` over `[0, x]` (midpoint rule, 10⁵
    /// intervals), for both signs, and tends to 1 − x/2 near 0.
    #[test]
    fn mean_factor_is_the_mean_of_the_exponential() {
        for x in [-1.3, -0.2, 1e-9, 0.05, 0.7, 2.5] {
            let n = 100_000;
            let h = x / n as f64;
            let mean: f64 = (0..n).map(|i| (-(i as f64 + 0.5) * h).exp()).sum::<f64>() / n as f64;
            assert!((mean_factor(x) - mean).abs() < 1e-9, "{x}");
        }
        assert_eq!(mean_factor(0.0), 1.0);
        assert!((mean_factor(1e-6) - (1.0 - 0.5e-6)).abs() < 1e-12);
    }
}
