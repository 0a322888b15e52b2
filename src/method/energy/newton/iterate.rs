//! One iterate of the SQP loop: the start of a run ([`Sqp::new`]), the linearization at
//! the iterate ([`Sqp::linearize`]), its residuals ([`Sqp::residuals`]) and the converged
//! result ([`Sqp::solution`]).

// Index loops mirror the variable layout.
#![allow(clippy::needless_range_loop)]

use super::{Residuals, Solution, Sqp};
use crate::method::energy::contacts::Pair;
use crate::method::energy::lengths::Work;
use crate::method::energy::problem::{Problem, Target};
use crate::method::energy::sensitivity::Sensitivity;
use crate::method::warm::EnergyHessian;
use crate::model::actuation::LengthMeasure;

impl<'p, 'a> Sqp<'p, 'a> {
    pub(super) fn new(prob: &'p Problem<'a>, (xi, lam): (Vec<f64>, Vec<f64>)) -> Self {
        let nc = prob.robot.cables.len();
        let nv = prob.nvar();
        let world = prob.world.as_ref();
        Sqp {
            prob,
            world,
            clearance: world.map_or(0.0, |wd| wd.clearance()),
            cable_rows: (0..nc)
                .filter(|&c| matches!(prob.targets[c], Target::Length(_)))
                .collect(),
            xi,
            lam,
            w: Work::new(prob),
            wgt: vec![0.0; nc],
            kin: None,
            pairs: vec![],
            mu: vec![],
            mu_prev: vec![],
            clear: f64::INFINITY,
            dxi: vec![0.0; nv],
            trial: vec![0.0; nv],
            trial_len: std::cell::RefCell::new(vec![0.0; nc]),
            curved: None,
            penalty: vec![],
            history: vec![],
            exact: false,
            stalled: false,
            last_move: f64::INFINITY,
            next_pairs: None,
            warm_hessian: None,
        }
    }

    /// Lengths, gradients (and chord Hessians) at the iterate, its frames and contact pairs
    /// with the last step's multipliers, and the gradient of the objective part (energy,
    /// tension potentials, dead loads).
    pub(super) fn linearize(&mut self) {
        let prob = self.prob;
        let nc = prob.robot.cables.len();
        self.wgt = (0..nc).map(|c| prob.cable_weight(c, self.lam[c])).collect();
        prob.evaluate(&self.xi, &self.wgt, &mut self.w, self.exact);
        self.kin = prob.needs_frames().then(|| prob.kin(&self.xi, true));
        self.clear = f64::INFINITY;
        if let (Some(wd), Some(k)) = (self.world, &self.kin) {
            (self.pairs, self.clear) = match self.next_pairs.take() {
                // The line search's pairs at this very point (same frames to the bit).
                Some((mut pairs, clear)) => {
                    wd.add_gradients(k, &mut pairs);
                    (pairs, clear)
                }
                None => wd.pairs(k),
            };
        }
        self.mu = self
            .pairs
            .iter()
            .map(|p| {
                self.mu_prev
                    .iter()
                    .find(|(k, _)| *k == p.key())
                    .map_or(0.0, |(_, m)| *m)
            })
            .collect();
        let w = &mut self.w;
        prob.energy_gradient(&self.xi, &mut w.gobj);
        for c in 0..nc {
            if let Target::Tension(t) = prob.targets[c] {
                for i in 0..prob.nvar() {
                    w.gobj[i] += t * w.grad[c][i];
                }
            }
        }
        prob.add_load_gradient(self.kin.as_ref(), &mut w.gobj);
    }

    pub(super) fn residuals(&self) -> Residuals {
        let (prob, w) = (self.prob, &self.w);
        let mut feas = 0.0f64;
        for &c in &self.cable_rows {
            let r = prob.cable_gap(c, w.len[c], self.lam[c]);
            feas = feas.max(if self.lam[c] > 0.0 {
                r.abs()
            } else {
                r.max(0.0)
            });
        }
        let mut gap = 0.0f64;
        for (p, &m) in self.pairs.iter().zip(&self.mu) {
            let r = self.clearance - p.dist;
            gap = gap.max(if m > 0.0 { r.abs() } else { r.max(0.0) });
        }
        let mut stat = 0.0f64;
        for i in 0..prob.nvar() {
            let mut g = w.gobj[i];
            for &c in &self.cable_rows {
                g += self.lam[c] * w.grad[c][i];
            }
            for (p, &m) in self.pairs.iter().zip(&self.mu) {
                g -= m * p.grad[i];
            }
            stat = stat.max(g.abs());
        }
        Residuals {
            feas,
            gap,
            stat: stat * prob.stat_scale,
        }
    }

    /// The converged result: the iterate and its pressing contacts.
    pub(super) fn solution(mut self, iterations: usize, residual: f64) -> Solution {
        let world = self.world;
        let pressing = pressing(&self.pairs, &self.mu);
        let mut hessian = None;
        let wanted = self.prob.want_sensitivity
            && (pressing.is_empty() || self.prob.set.contact_sensitivity);
        let sensitivity = if wanted {
            let s = self.prob.sensitivity(
                &self.xi,
                &self.wgt,
                &self.lam,
                &pressing,
                self.kin.as_ref(),
                &mut self.w,
            );
            // `w.hess` now holds `K + Σ w_c ∇²L_c` at the solution (path lengths); the
            // scratch ends with this solve, so the blocks are moved, not copied.
            // With curvature stiffening the energy block depends on the strains and `β`, which
            // the warm state does not record: no blocks to reuse.
            if self.prob.set.cable_length == LengthMeasure::Path && self.prob.stiffening == 0.0 {
                hessian = Some(EnergyHessian {
                    blocks: std::mem::take(&mut self.w.hess),
                    weights: std::mem::take(&mut self.wgt),
                    stiffness: self.prob.k.clone(),
                    routing: super::routing(self.prob),
                });
            }
            s
        } else {
            Sensitivity {
                stable: None,
                jacobian: None,
            }
        };
        let contacts = self
            .pairs
            .iter()
            .zip(&self.mu)
            .filter(|(_, &m)| m > 0.0)
            .filter_map(|(p, &m)| world.map(|wd| wd.contact(p, m)))
            .collect();
        Solution {
            xi: self.xi,
            lam: self.lam,
            contacts,
            iterations,
            residual,
            history: self.history,
            sensitivity,
            hessian,
        }
    }
}

/// The pressing contacts (multiplier > 0) with their multipliers; a free function so that the
/// caller may keep borrowing the iterate's other fields.
pub(super) fn pressing<'q>(pairs: &'q [Pair], mu: &[f64]) -> Vec<(&'q Pair, f64)> {
    pairs
        .iter()
        .zip(mu)
        .filter(|(_, &m)| m > 0.0)
        .map(|(p, &m)| (p, m))
        .collect()
}
