//! The Newton–KKT step of the SQP loop: the factored Lagrangian Hessian ([`Sqp::factor`]),
//! the step's QP in its dual ([`Sqp::dual_step`]) and the move to the next iterate
//! ([`Sqp::take_step`]).

// Index loops mirror the variable layout.
#![allow(clippy::needless_range_loop)]

use super::dot;
use super::Sqp;
use crate::model::actuation::LengthMeasure;
use crate::numeric::dense::chol_factor;
use crate::numeric::qp::nonneg_qp;

impl<'p, 'a> Sqp<'p, 'a> {
    /// Factor the Lagrangian Hessian: its blocks in place (shifted towards the energy block
    /// where one is not positive definite), or, with dead loads or pressing contacts, the
    /// blocks plus their curvature in semiseparable form (`energy/curvature.rs`; shifted as a
    /// whole). `Err(section)` if a block cannot be made positive definite.
    pub(super) fn factor(&mut self) -> Result<(), usize> {
        let prob = self.prob;
        let nb = prob.nb;
        let w = &mut self.w;
        if prob.set.cable_length == LengthMeasure::Path {
            // A warm start's first Hessian is the last one of the solve it comes from when
            // strains, weights, stiffness and cable routing are those (the same numbers, not rebuilt) and there
            // is no curvature stiffening (whose block the warm state does not record).
            match self.warm_hessian.take() {
                Some(h)
                    if h.blocks.len() == w.hess.len()
                        && h.weights == self.wgt
                        && h.stiffness == prob.k
                        && h.routing == super::routing(prob)
                        && prob.stiffening == 0.0 =>
                {
                    w.hess.copy_from_slice(&h.blocks);
                }
                _ => prob.path_hessian(&self.xi, &self.wgt, w),
            }
        }
        w.raw.copy_from_slice(&w.hess);
        if self.factor_curved().is_some() {
            return Ok(());
        }
        let w = &mut self.w;
        for b in 0..prob.nblocks {
            let rng = b * nb * nb..(b + 1) * nb * nb;
            if chol_factor(&mut w.hess[rng.clone()], nb) {
                continue;
            }
            let mut shift = 1e-8;
            loop {
                let blk = &mut w.hess[rng.clone()];
                blk.copy_from_slice(&w.raw[rng.clone()]);
                for i in 0..nb {
                    blk[i * nb + i] += shift * prob.k[b * nb + i];
                }
                if chol_factor(blk, nb) {
                    break;
                }
                shift *= 10.0;
                if shift > 1e8 {
                    return Err(prob.section_of(b * nb / 4));
                }
            }
        }
        Ok(())
    }

    /// Constraint row `r` of the step's QP: gradient, sign, value (`≤ 0` when satisfied).
    /// Cables first (length − target, the rigid part: a compliant cable's `−λ/k` is on the
    /// dual's diagonal), then contacts (clearance − distance, gradient negated).
    fn row(&self, r: usize) -> (&[f64], f64, f64) {
        if r < self.cable_rows.len() {
            let c = self.cable_rows[r];
            (
                &self.w.grad[c],
                1.0,
                self.prob.cable_gap(c, self.w.len[c], 0.0),
            )
        } else {
            let p = &self.pairs[r - self.cable_rows.len()];
            (&p.grad, -1.0, self.clearance - p.dist)
        }
    }

    /// The QP of this step in its dual: rows a_r, values c_r ≤ 0 ([`Sqp::row`]). With
    /// z = H⁻¹ ∇f (∇f with the penalty's gradient, `newton/curved.rs`) and y_r = H⁻¹ a_r (a_r with the row's sign) the step is −z − Σ λ_r y_r (into `dxi`), where λ ≥ 0
    /// minimizes ½ λᵀ (S + C) λ − qᵀ λ, S = [a_rᵀ y_s], q_r = c_r − a_rᵀ z, C the diagonal of
    /// the cables' compliances `1/k` (a compliant row `a·d + c − λ/k ≤ 0` is the primal QP
    /// with a stretch `s` costing `½ k s²`; eliminating `s = λ/k` puts `1/k` on the dual's
    /// diagonal). Returns the new multipliers (cables, then contacts); `None` if the QP cycles.
    pub(super) fn dual_step(&mut self) -> Option<Vec<f64>> {
        let prob = self.prob;
        let nrow = self.cable_rows.len() + self.pairs.len();
        // The objective's gradient, with the penalty's where contact rows are penalized.
        let mut z = std::mem::take(&mut self.w.z);
        z.copy_from_slice(&self.w.gobj);
        self.add_penalty_gradient(&mut z);
        self.w.z = z;
        let mut ys = std::mem::take(&mut self.w.y);
        ys.resize_with(nrow, Vec::new);
        for (r, y) in ys.iter_mut().enumerate() {
            let (a, sign, _) = self.row(r);
            y.clear();
            y.extend(a.iter().map(|v| sign * v));
        }
        // With the semiseparable factor `H = L Lᵀ` the forward sweeps alone give
        // `w = L⁻¹ (∇f, â_r)`: `S_rs = w_r · w_s`, `q_r = c_r − w_r · w_z`, and the step is one
        // backward sweep, `−L⁻ᵀ (w_z + Σ λ_r w_r)`. The blocks solve in full.
        let curved = self.curved.as_ref();
        for x in std::iter::once(&mut self.w.z).chain(ys.iter_mut()) {
            match curved {
                Some(f) => f.forward(x),
                None => prob.block_solve(&self.w.hess, x),
            }
        }
        let mut s_mat = vec![0.0; nrow * nrow];
        let mut q = vec![0.0; nrow];
        let mut lam_new = vec![0.0; nrow];
        for r in 0..nrow {
            let (a, sign, c) = self.row(r);
            if curved.is_some() {
                q[r] = c - dot(&ys[r], &self.w.z);
                for s in r..nrow {
                    let v = dot(&ys[r], &ys[s]);
                    s_mat[r * nrow + s] = v;
                    s_mat[s * nrow + r] = v;
                }
            } else {
                q[r] = c - sign * dot(a, &self.w.z);
                for s in 0..nrow {
                    s_mat[r * nrow + s] = sign * dot(a, &ys[s]);
                }
            }
            lam_new[r] = if r < self.cable_rows.len() {
                s_mat[r * nrow + r] += prob.compliance[self.cable_rows[r]];
                self.lam[self.cable_rows[r]]
            } else {
                self.mu[r - self.cable_rows.len()]
            };
        }
        let ok = nonneg_qp(&s_mat, &q, nrow, &mut lam_new);
        if ok {
            for i in 0..prob.nvar() {
                let mut d = -self.w.z[i];
                for r in 0..nrow {
                    d -= lam_new[r] * ys[r][i];
                }
                self.dxi[i] = d;
            }
            if let Some(f) = curved {
                f.backward(&mut self.dxi);
            }
            self.unpenalize(&mut lam_new);
        }
        self.w.y = ys;
        ok.then_some(lam_new)
    }

    /// Move by `alpha · dxi` and adopt the step's multipliers (contacts keyed by feature and
    /// obstacle, for the next linearization).
    pub(super) fn take_step(&mut self, alpha: f64, lam_new: &[f64]) {
        self.last_move = if alpha == 1.0 {
            self.prob.move_bound(&self.dxi)
        } else {
            f64::INFINITY
        };
        for i in 0..self.prob.nvar() {
            self.xi[i] += alpha * self.dxi[i];
        }
        self.lam.fill(0.0);
        for (r, &c) in self.cable_rows.iter().enumerate() {
            self.lam[c] = lam_new[r];
        }
        self.mu_prev.clear();
        for (k, p) in self.pairs.iter().enumerate() {
            let m = lam_new[self.cable_rows.len() + k];
            if m > 0.0 {
                self.mu_prev.push((p.key(), m));
            }
        }
    }
}
