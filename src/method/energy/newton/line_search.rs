//! Backtracking on the ℓ1 merit along the Newton–KKT step ([`Sqp::line_search`]), with
//! the guard that no feature passes through an obstacle between two iterates.

// Index loops mirror the variable layout.
#![allow(clippy::needless_range_loop)]

use super::{dot, Sqp, CONTACT_NOISE};
use crate::method::energy::contacts::{self, Kin, Pair};
use crate::method::energy::problem::Target;
use std::cell::OnceCell;

/// The fraction of the pair margin beyond the clearance (half the longest section) a line
/// search's trial may take a feature deeper into an obstacle than the iterate's deepest pair
/// ([`Sqp::depth_allowed`]).
const PENETRATION_STEP: f64 = 0.5;

impl<'p, 'a> Sqp<'p, 'a> {
    /// Summed violation of the constraints at lengths `len` and pairs `ps` \[m\] (compliant
    /// cables are springs in the merit, not constraints).
    fn violation(&self, len: &[f64], ps: &[Pair]) -> f64 {
        let mut v = 0.0;
        for &c in &self.cable_rows {
            if !self.prob.is_spring(c) {
                v += self.prob.cable_gap(c, len[c], 0.0).max(0.0);
            }
        }
        for p in ps {
            v += (self.clearance - p.dist).max(0.0);
        }
        v
    }

    /// The smooth part of the merit, `E + V + Σ T L + Σ ½ k (L − t)₊²` (the compliant
    /// cables' springs, [`Problem::spring_energy`]).
    fn smooth_merit(&self, x: &[f64], kin: Option<&Kin>, len: &[f64]) -> f64 {
        let prob = self.prob;
        let mut f = prob.energy(x) + prob.load_potential(kin) + prob.spring_energy(len);
        for c in 0..prob.robot.cables.len() {
            if let Target::Tension(t) = prob.targets[c] {
                f += t * len[c];
            }
        }
        f
    }

    /// The ℓ1 merit: [`Sqp::smooth_merit`] `+ pen · violation`.
    fn merit(&self, x: &[f64], kin: Option<&Kin>, len: &[f64], ps: &[Pair], pen: f64) -> f64 {
        self.smooth_merit(x, kin, len) + pen * self.violation(len, ps)
    }

    /// Whether a trial with pairs `ps` (and distance `clear` beyond them) stays within the
    /// depth a step may take a feature into an obstacle: no deeper than the iterate's deepest
    /// pair or [`PENETRATION_STEP`] of the pair margin beyond the clearance, whichever is
    /// more. A feature that ends inside a convex obstacle is seen by the merit (the step
    /// guard's rule 3), but only while it has not crossed the obstacle's middle: beyond it the
    /// distance is to the far face, the normal turns over and the iterations push the feature
    /// through. A cold soft rod's first Newton step put its backbone 13.5 mm into a 20 mm
    /// wall, where the iterations never settled; halved to this depth, the step ends near the
    /// face and the next steps hold the pair by its linearized constraint.
    fn depth_allowed(&self, ps: &[Pair], clear: f64) -> bool {
        let Some(wd) = self.world else {
            return true;
        };
        let deepest = |ps: &[Pair], clear: f64| ps.iter().map(|p| p.dist).fold(clear, f64::min);
        let now = self.clearance - deepest(&self.pairs, self.clear);
        let allowed = now.max(PENETRATION_STEP * (wd.margin() - self.clearance));
        self.clearance - deepest(ps, clear) <= allowed
    }

    /// Backtracking on the ℓ1 merit along `dxi` (every pair re-queried at the trial point);
    /// the step length, 0 if no decrease was found (sets `stalled`).
    pub(super) fn line_search(&mut self, lam_new: &[f64]) -> f64 {
        let prob = self.prob;
        let pen = 2.0 * lam_new.iter().cloned().fold(0.0, f64::max) + 1e-3;
        let phi0 = self.merit(&self.xi, self.kin.as_ref(), &self.w.len, &self.pairs, pen);
        let springs: f64 = self
            .cable_rows
            .iter()
            .map(|&c| prob.spring_tension(c, self.w.len[c]) * dot(&self.w.grad[c], &self.dxi))
            .sum();
        let dphi =
            dot(&self.w.gobj, &self.dxi) + springs - pen * self.violation(&self.w.len, &self.pairs);
        // Near the solution the merit changes below round-off (or below the noise of
        // parry's distances, with contacts): take the full step.
        let noise = if self.pairs.is_empty() {
            0.0
        } else {
            pen * CONTACT_NOISE
        };
        let tiny = dphi.abs() <= 1e-12 * phi0.abs() + noise;
        // A merit difference resolves no better than twice the cable lengths' round-off in it
        // (`Problem::merit_roundoff`): a step whose predicted decrease and actual change both
        // lie below that is judged by the residuals.
        let floor = 2.0 * prob.merit_roundoff(&self.w.len, pen);
        let within = |phi: f64| dphi.abs() <= floor && phi - phi0 <= floor;
        let armijo = |alpha: f64| phi0 + 1e-4 * alpha * dphi.min(0.0) + 1e-14 * phi0.abs();
        let mut alpha: f64 = 1.0;
        for _ in 0..40 {
            for i in 0..prob.nvar() {
                self.trial[i] = self.xi[i] + alpha * self.dxi[i];
            }
            let stretch_ok = (0..prob.nsub).all(|j| self.trial[4 * j + 3] > -1.0 + 1e-3);
            if !stretch_ok {
                alpha *= 0.5;
                continue;
            }
            let kin_trial = prob.needs_frames().then(|| prob.kin(&self.trial, false));
            // The lengths and the smooth part of the merit, once asked for.
            let smooth: OnceCell<f64> = OnceCell::new();
            let merit = |ps: &[Pair]| {
                let smooth = *smooth.get_or_init(|| {
                    let mut len = self.trial_len.borrow_mut();
                    prob.lengths(&self.trial, &mut len);
                    self.smooth_merit(&self.trial, kin_trial.as_ref(), &len)
                });
                smooth + pen * self.violation(&self.trial_len.borrow(), ps)
            };
            let bound = armijo(alpha);
            // The trial is rejected once the merit with the pairs found so far fails both
            // tests of acceptance below: the violation is a sum of non-negative terms and
            // rounded addition is monotone, as are `+ smooth` and `· pen > 0`, so the merit of
            // a prefix of the pairs is at most the full merit, which fails them too, whatever
            // the pairs left (and whatever the step guard would say: acceptance needs both). A
            // trial that is not given up computes every pair in the same order, so what is
            // accepted is unchanged to the bit.
            let rejects = |ps: &[Pair]| {
                let phi = merit(ps);
                !tiny && phi > bound && (dphi.abs() > floor || phi - phi0 > floor)
            };
            let (trial_pairs, trial_clear) = match (self.world, &kin_trial) {
                (Some(wd), Some(k)) => {
                    let stop = contacts::Stop {
                        clearance: self.clearance,
                        rejects: &rejects,
                    };
                    match wd.pairs_until(k, &self.pairs, Some(stop)) {
                        Some(found) => found,
                        None => {
                            alpha *= 0.5;
                            continue;
                        }
                    }
                }
                _ => (vec![], f64::INFINITY),
            };
            // No feature may pass through an obstacle between two iterates (distances to
            // open meshes are unsigned: a jump through a wall would look clear): either no
            // point moves farther than the robot's distance to the obstacles (or half the
            // pair margin when closer; features near an obstacle are held by their
            // linearized constraints), or every feature–obstacle pair passes the tests of
            // `energy/step_guard.rs` (distances, separating planes).
            let near_enough = match (self.world, &self.kin, &kin_trial) {
                (Some(wd), Some(k0), Some(k1)) => {
                    wd.max_move(k0, k1) <= self.clear.max(0.5 * wd.margin())
                        || wd.step_is_clear(
                            (k0, &self.pairs, self.clear),
                            (k1, &trial_pairs, trial_clear),
                        )
                }
                _ => true,
            };
            if near_enough && self.depth_allowed(&trial_pairs, trial_clear) {
                let phi = merit(&trial_pairs);
                if phi.is_finite() && (tiny || phi <= bound || within(phi)) {
                    self.stalled = false;
                    // `take_step` moves to this very trial point (same operations).
                    self.next_pairs = kin_trial.is_some().then_some((trial_pairs, trial_clear));
                    return alpha;
                }
            }
            alpha *= 0.5;
        }
        // No decrease along this direction (round-off level, or a poor Gauss–Newton model):
        // stay, and let the next iteration use the exact Hessian.
        self.stalled = true;
        0.0
    }
}
