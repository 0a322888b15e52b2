//! The Lagrangian Hessian with the curvature of dead loads and pressing contacts
//! (`energy/curvature.rs`), factored in semiseparable form.
//!
//! Against a convex obstacle `−μ ∇²d` is negative along the surface (`−μ Jᵀ G J`), so the
//! Hessian can be indefinite on the whole space while it is positive definite on the null
//! space of the active constraints (a stable equilibrium). Adding `ρ_r a_r a_rᵀ` for the
//! pressing contacts' rows (`a_r = −∇d`) makes it positive definite for `ρ` large enough
//! (Debreu's lemma; Nocedal & Wright, *Numerical Optimization*, 2nd ed., §17.3, the augmented
//! Lagrangian Hessian). The term added to the step's QP is the penalty on the linearized
//! row, `½ ρ (c + aᵀd)²` (`c` the row's value, `≤ 0` when satisfied): Hessian `ρ a aᵀ`,
//! gradient `ρ c a` ([`Sqp::add_penalty_gradient`]). It vanishes on the face `c + aᵀd = 0`
//! and is `≥ 0` elsewhere, so where the unpenalized QP's solution `d*` has the row active
//! the penalized objective is `≥` the unpenalized one on the feasible set and equal at `d*`:
//! the same step. Its stationarity `(H + ρ a aᵀ) d + ρ c a + a λ' = −g` is
//! `H d + a (λ' + ρ (c + aᵀd)) = −g`, so the multiplier is `λ = λ' + ρ (c + aᵀd)`
//! ([`Sqp::unpenalize`]), `= λ'` on the active face. The Hessian term alone (`½ ρ (aᵀd)²`)
//! is exact only for a row at `c = 0`: for a pressing pair not yet touching (`c < 0`) the
//! step would need `λ' = λ + ρ c`, negative once `λ < ρ |c|`; the dual holds it at 0 and the
//! step closes only `λ / ρ` of the gap (random dense scene 5 of `tests/contact/dense_scenes.rs`
//! with the step guard's exact distances: a disk 0.44 mm short of a sphere closed by 16 µm
//! per iteration, 40 iterations instead of 12). Only where no `ρ` makes the Hessian
//! positive definite is the energy's `K` added (a damped step, as for the blocks).

use super::{dot, Sqp};
use crate::method::energy::curvature::LowRank;
use nalgebra::DMatrix;

/// Gap \[m\] beyond which a solid mesh's pressing pair leaves its curvature `−μ ∇²d` out of
/// the Hessian.
///
/// A pair still apart gets its multiplier from the step's linearization, not from a touch, and
/// a faceted wall's distance curvature at it is that of the edge or vertex its witness is on
/// now (differenced from the mesh's normals), not of the face it will touch. Approaching a
/// concave faceted wall (paper case I inside a meshed sphere of 100 mm) the step's QP gave a
/// disk 6 mm from the wall a multiplier, that curvature made the Hessian indefinite beyond what
/// the penalty repairs, the fallback's shift grew the next multipliers with it (about ×10 per
/// iteration, to 1e7) and the steps shortened. Left out, such an iterate's Hessian is the
/// energy's and the touching contacts'; a pair within `CURVED_GAP` keeps its curvature, and at
/// a converged answer every pressing pair touches (gap ≤ 1e-8 m), so the last iterations are
/// Newton's as before and the answer the same. Measured (cases I–III in spheres of 60 × 80 to
/// 200 × 256 quads, radius 95–110 mm): 37 → 24 iterations in the 25 344-triangle sphere, no
/// other case more than one iteration apart; with 0 three lumens that ran out of iterations
/// converge but every other case takes more (31 in the 25k sphere). Smooth obstacles (boxes,
/// cylinders, balls) keep every pressing pair's exact curvature: left out there, the committed
/// wall and pillar lose their superlinear last iterations (the pillar ends at 6.5e-11, not
/// 1e-12; `newton/tests.rs`).
const CURVED_GAP: f64 = 1e-5;

impl Sqp<'_, '_> {
    /// Factor `H` with the curvature of loads and pressing contacts into `curved`; `None`
    /// when there is no such curvature or no shift makes it positive definite (a start deep
    /// inside an obstacle): the blocks are factored instead, as without it.
    pub(super) fn factor_curved(&mut self) -> Option<()> {
        let prob = self.prob;
        self.curved = None;
        self.penalty.clear();
        let kin = self.kin.as_ref().filter(|k| k.m_int.len() == prob.nsub)?;
        // A solid mesh's pairs pressing within `CURVED_GAP` of touching only (its docs).
        let clearance = self.clearance;
        let pressing: Vec<_> = super::iterate::pressing(&self.pairs, &self.mu)
            .into_iter()
            .filter(|(p, _)| p.triangle.is_none() || p.dist - clearance < CURVED_GAP)
            .collect();
        let (loads, low) = prob.curvature_terms(kin, &pressing)?;
        // Built once: each try below adds only its penalty term (the same matrix as a whole
        // build with that term last, `CurvatureParts`).
        let parts = prob.curvature_parts(&self.xi, kin, &loads, &low);
        let kmax = prob.k.iter().cloned().fold(0.0, f64::max);
        // Rows of the pressing contacts in the step's QP, unit gradients.
        let rows: Vec<(usize, Vec<f64>)> = (0..self.pairs.len())
            .filter(|&k| self.mu[k] > 0.0)
            .map(|k| {
                let g = &self.pairs[k].grad;
                let n = dot(g, g).sqrt();
                (self.cable_rows.len() + k, g.iter().map(|v| v / n).collect())
            })
            .collect();
        let mut rho = 0.0;
        let mut pen: Option<LowRank> = None;
        loop {
            let ss = parts.semisep(pen.as_slice(), &self.w.raw);
            if let Some(f) = ss.factor() {
                self.curved = Some(f);
                // ρ_r for the raw gradient: ρ â âᵀ = (ρ / |∇d|²) ∇d ∇dᵀ.
                let nc = self.cable_rows.len();
                self.penalty = rows
                    .iter()
                    .map(|(r, _)| {
                        let g = &self.pairs[r - nc].grad;
                        (*r, rho / dot(g, g))
                    })
                    .filter(|_| rho > 0.0)
                    .collect();
                return Some(());
            }
            if rows.is_empty() || rho >= 1e4 * kmax {
                break;
            }
            rho = if rho == 0.0 { 1e-4 * kmax } else { 10.0 * rho };
            pen = Some(LowRank {
                w: rows.iter().map(|(_, a)| a.clone()).collect(),
                m: DMatrix::identity(rows.len(), rows.len()) * rho,
            });
        }
        // Damped: the energy's K added.
        self.penalty.clear();
        let mut ss = parts.semisep(&[], &self.w.raw);
        let nb = prob.nb;
        let mut shift = 0.0;
        loop {
            let add = if shift == 0.0 { 1e-8 } else { 9.0 * shift };
            shift += add;
            if shift > 1e8 {
                return None;
            }
            for b in 0..prob.nblocks {
                for i in 0..nb {
                    ss.diag[b * nb * nb + i * nb + i] += add * prob.k[b * nb + i];
                }
            }
            if let Some(f) = ss.factor() {
                self.curved = Some(f);
                return Some(());
            }
        }
    }

    /// Add the penalty's gradient `Σ ρ_r c_r a_r` to `z` (module docs), `c_r` the value of
    /// penalized row `r` and `a_r` its gradient in the step's QP.
    pub(super) fn add_penalty_gradient(&self, z: &mut [f64]) {
        for &(r, rho) in &self.penalty {
            let p = &self.pairs[r - self.cable_rows.len()];
            // The contact row: gradient −∇d, value clearance − d.
            let s = -rho * (self.clearance - p.dist);
            for (zi, gi) in z.iter_mut().zip(&p.grad) {
                *zi += s * gi;
            }
        }
    }

    /// The multipliers of the unpenalized step from those of the penalized one (module docs):
    /// `λ_r = λ'_r + ρ_r (c_r + a_rᵀ d)` for each penalized row, `a_r` its gradient in the
    /// step's QP and `c_r` its value.
    pub(super) fn unpenalize(&self, lam: &mut [f64]) {
        for &(r, rho) in &self.penalty {
            let p = &self.pairs[r - self.cable_rows.len()];
            // The contact row: gradient −∇d, value clearance − d.
            let c = self.clearance - p.dist;
            lam[r] = (lam[r] + rho * (c - dot(&p.grad, &self.dxi))).max(0.0);
        }
    }
}
