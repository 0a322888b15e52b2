//! The sequential-QP (Newton–KKT) loop of the energy model (derivation in the docs of
//! [`super`]), cut by role: [`Sqp::linearize`] (lengths, gradients, contact pairs at the
//! iterate), [`Sqp::residuals`], [`Sqp::factor`] (block Cholesky of the Lagrangian Hessian),
//! [`Sqp::dual_step`] (the step's QP in its dual), [`Sqp::line_search`] (ℓ1 merit) and
//! [`Sqp::failure`] (which named error a run that did not converge ends in).

use super::contacts::{self, Feat, Kin, Pair, World};
use super::lengths::Work;
use super::problem::{Problem, Target};
use super::sensitivity::Sensitivity;
use super::Energy;
use crate::error::SolveError;
use crate::method::warm::WarmState;
use crate::method::Method;
use crate::model::actuation::LengthMeasure;
use crate::numeric::dense::chol_factor;
use crate::numeric::qp::nonneg_qp;
use crate::shape::{Contact, Shape};

/// What [`Energy::newton`] found.
pub(super) struct Solution {
    pub xi: Vec<f64>,
    /// Cable multipliers (tensions) \[N\].
    pub lam: Vec<f64>,
    /// Active contacts with their reactions \[N\].
    pub contacts: Vec<Contact>,
    pub iterations: usize,
    pub residual: f64,
    /// Stability and tip Jacobian from the converged KKT system (`sensitivity.rs`).
    pub sensitivity: Sensitivity,
}

/// Residual \[m\] at which a solution with active contacts has converged: parry's distances and
/// normals on smooth pairs (a disk rim against a cylinder or a tube) carry ~1e-9 m of noise.
const CONTACT_RESIDUAL: f64 = 1e-8;

/// A full Newton step that moves no point of the robot by more than this \[m\] ends a solve
/// with active contacts (see [`Energy::newton`]).
const CONTACT_STEP: f64 = 1e-7;

/// Noise of parry's signed distances near touching \[m\]: a merit decrease predicted below
/// `penalty × CONTACT_NOISE` cannot be checked, so the full step is taken.
const CONTACT_NOISE: f64 = 1e-9;

/// Residuals of one iterate: cable lengths (equal if taut, not longer if slack) \[m\],
/// contacts (no penetration; touching where the reaction is positive) \[m\], stationarity
/// as a length (`r̄ |∇ℒ|∞ / (EI ℓ)`).
struct Residuals {
    feas: f64,
    gap: f64,
    stat: f64,
}

/// State of one SQP run: the iterate, its linearization and the scratch of the step.
struct Sqp<'p, 'a> {
    prob: &'p Problem<'a>,
    world: Option<&'p World<'a>>,
    clearance: f64,
    /// Rows of the constraint set that never changes: the displacement-driven cables.
    cable_rows: Vec<usize>,
    xi: Vec<f64>,
    lam: Vec<f64>,
    w: Work,
    /// Weights of the constraint Hessians: multipliers of taut cables, input tensions.
    wgt: Vec<f64>,
    /// Frames at the iterate (with obstacles or loads).
    kin: Option<Kin>,
    /// Feature–obstacle pairs at the iterate, their multipliers from the last step, and the
    /// robot's distance to the obstacles.
    pairs: Vec<Pair>,
    mu: Vec<f64>,
    mu_prev: Vec<((usize, Feat), f64)>,
    clear: f64,
    dxi: Vec<f64>,
    trial: Vec<f64>,
    trial_len: Vec<f64>,
    /// Chords: exact Hessian (second-order AD) instead of Gauss–Newton.
    exact: bool,
    /// The last line search found no decrease.
    stalled: bool,
    /// Bound on how far the last full step moved any point \[m\] (∞ after a damped step).
    last_move: f64,
}

impl Energy {
    /// Sequential QP (Newton–KKT) on the whole robot (module docs). Returns the strains, the
    /// cable multipliers, the active contacts with theirs, iterations and the final residual.
    pub(super) fn newton(
        &self,
        prob: &Problem,
        warm: Option<&Shape>,
    ) -> Result<Solution, SolveError> {
        let mut sqp = Sqp::new(prob, self.start_point(prob, warm));
        let tol = self.tolerance;
        let mut resid = f64::INFINITY;
        for it in 0..=self.max_iterations {
            sqp.linearize();
            let r = sqp.residuals();
            // Chords: Gauss–Newton while it contracts fast, the exact Hessian once it slows.
            let now = r.feas.max(r.stat);
            if prob.set.cable_length == LengthMeasure::Chord
                && !sqp.exact
                && now > tol
                && (sqp.stalled || (it >= 4 && now > 0.3 * resid))
            {
                sqp.exact = true;
                prob.evaluate(&sqp.xi, &sqp.wgt, &mut sqp.w, true);
            }
            resid = r.feas.max(r.stat).max(r.gap);
            if !resid.is_finite() {
                break;
            }
            // With contacts, parry's distances on smooth pairs carry ~1e-9 m of noise.
            // With active contacts, parry's normals on smooth pairs carry noise that keeps
            // the stationarity residual from falling below ~1e-6: there the solution has
            // converged once a full Newton step moves no point of the robot by more than
            // CONTACT_STEP (a bound: Σ ℓ_j (|δu_j| (L − s_j) + |δε_j|)).
            let in_contact = sqp.mu.iter().any(|&m| m > 0.0);
            let ctol = if in_contact {
                tol.max(CONTACT_RESIDUAL)
            } else {
                tol
            };
            let settled = in_contact && sqp.last_move <= CONTACT_STEP;
            if r.feas <= tol && r.gap <= ctol && (r.stat <= ctol || settled) {
                self.check_stretch(prob, &sqp.xi, &sqp.lam)?;
                return Ok(sqp.solution(it, resid));
            }
            if it == self.max_iterations {
                break;
            }
            sqp.factor().map_err(|section| SolveError::NotConverged {
                method: self.name().into(),
                section: Some(section),
                iterations: it,
                residual: resid,
                detail: "Hessian block cannot be made positive definite".into(),
            })?;
            let lam_new = sqp.dual_step().ok_or_else(|| SolveError::NotConverged {
                method: self.name().into(),
                section: None,
                iterations: it,
                residual: resid,
                detail: "the step's QP (cable and contact multipliers) did not converge".into(),
            })?;
            let alpha = sqp.line_search(&lam_new);
            sqp.take_step(alpha, &lam_new);
        }
        Err(self.failure(&sqp, resid))
    }

    /// The start: the strains and multipliers of a warm shape of this method and layout, else
    /// strains fitted to the disk frames of any other shape with as many disks, else straight.
    fn start_point(&self, prob: &Problem, warm: Option<&Shape>) -> (Vec<f64>, Vec<f64>) {
        let nc = prob.robot.cables.len();
        let nv = prob.nvar();
        let mut xi = vec![0.0; nv];
        let mut lam = vec![0.0; nc];
        let state = warm
            .filter(|w| w.method == self.name())
            .and_then(|w| match &w.report.warm {
                Some(WarmState::Energy(e)) => Some(e),
                _ => None,
            })
            .filter(|e| {
                e.strains.len() == nv
                    && e.multipliers.len() == nc
                    && e.strains
                        .iter()
                        .chain(&e.multipliers)
                        .all(|v| v.is_finite())
            });
        if let Some(st) = state {
            xi.copy_from_slice(&st.strains);
            for c in 0..nc {
                if matches!(prob.targets[c], Target::Length(_)) {
                    lam[c] = st.multipliers[c].max(0.0);
                }
            }
        } else if let Some(w) = warm.filter(|w| w.disks.len() == prob.robot.sections() + 1) {
            // Another method's shape (or another discretization): its disk frames.
            prob.strains_from_disks(&w.disks, &mut xi);
        }
        (xi, lam)
    }

    /// The named error of a run that did not converge: a compressed backbone (target out of
    /// reach), a start that crosses an obstacle, or plain non-convergence with the residual.
    fn failure(&self, sqp: &Sqp, resid: f64) -> SolveError {
        let prob = sqp.prob;
        if let Err(e) = self.check_stretch(prob, &sqp.xi, &sqp.lam) {
            return e;
        }
        // Still inside an obstacle: the start crossed it (the straight robot through a wall,
        // or a tube it does not fit).
        let clearance = sqp.clearance;
        if let Some(p) = sqp
            .pairs
            .iter()
            .filter(|p| p.dist < clearance - CONTACT_RESIDUAL)
            .min_by(|a, b| a.dist.total_cmp(&b.dist))
        {
            let c = sqp.world.map(|wd| wd.contact(p, 0.0));
            return SolveError::Obstructed {
                obstacle: c.as_ref().map(|c| c.obstacle.clone()).unwrap_or_default(),
                section: c.and_then(|c| c.section.or(c.disk)).unwrap_or(0),
                reason: format!(
                    "after {} iterations the {} still lies {:.3e} m inside the clearance: the \
                     start crosses the obstacle; start from a shape that is clear of it (e.g. \
                     the geometric method's, `--warm-from geometric`)",
                    self.max_iterations,
                    match p.feat {
                        Feat::Backbone(_) => "backbone",
                        Feat::Disk(_) => "disk",
                        Feat::Cable(..) => "cable",
                    },
                    clearance - p.dist
                ),
            };
        }
        SolveError::NotConverged {
            method: self.name().into(),
            section: None,
            iterations: self.max_iterations,
            residual: resid,
            detail: "residual = max(length error [m], contact gap [m], r̄·|∇ℒ|∞/(EI ℓ))".into(),
        }
    }

    /// A solution that compresses the backbone below `min_stretch` means the cable lengths
    /// cannot be reached by bending: name the most loaded cable.
    fn check_stretch(&self, prob: &Problem, xi: &[f64], lam: &[f64]) -> Result<(), SolveError> {
        let (jmin, smin) = (0..prob.nsub)
            .map(|j| (j, 1.0 + xi[4 * j + 3]))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, 1.0));
        let bad = smin.is_nan() || smin < self.min_stretch || xi.iter().any(|v| !v.is_finite());
        if !bad {
            return Ok(());
        }
        let c = (0..lam.len())
            .max_by(|&a, &b| lam[a].total_cmp(&lam[b]))
            .unwrap_or(0);
        Err(SolveError::Infeasible {
            cable: prob
                .robot
                .cables
                .get(c)
                .map(|c| c.name.clone())
                .unwrap_or_default(),
            section: prob.section_of(jmin),
            reason: format!(
                "the cable lengths need an axial stretch 1+ε = {smin:.3} < {} of the backbone",
                self.min_stretch
            ),
        })
    }
}

impl<'p, 'a> Sqp<'p, 'a> {
    fn new(prob: &'p Problem<'a>, (xi, lam): (Vec<f64>, Vec<f64>)) -> Self {
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
            trial_len: vec![0.0; nc],
            exact: false,
            stalled: false,
            last_move: f64::INFINITY,
        }
    }

    /// Lengths, gradients (and chord Hessians) at the iterate, its frames and contact pairs
    /// with the last step's multipliers, and the gradient of the objective part (energy,
    /// tension potentials, dead loads).
    fn linearize(&mut self) {
        let prob = self.prob;
        let nc = prob.robot.cables.len();
        self.wgt = (0..nc)
            .map(|c| match prob.targets[c] {
                Target::Length(_) => self.lam[c],
                Target::Tension(t) => t,
                Target::Free => 0.0,
            })
            .collect();
        prob.evaluate(&self.xi, &self.wgt, &mut self.w, self.exact);
        self.kin = prob
            .needs_frames()
            .then(|| contacts::kinematics(&self.xi, &prob.ell, true));
        self.clear = f64::INFINITY;
        if let (Some(wd), Some(k)) = (self.world, &self.kin) {
            (self.pairs, self.clear) = wd.pairs(k);
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
        for i in 0..prob.nvar() {
            w.gobj[i] = prob.k[i] * self.xi[i];
        }
        for c in 0..nc {
            if let Target::Tension(t) = prob.targets[c] {
                for i in 0..prob.nvar() {
                    w.gobj[i] += t * w.grad[c][i];
                }
            }
        }
        prob.add_load_gradient(self.kin.as_ref(), &mut w.gobj);
    }

    fn residuals(&self) -> Residuals {
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
    fn solution(mut self, iterations: usize, residual: f64) -> Solution {
        let world = self.world;
        let pressing: Vec<(&Pair, f64)> = self
            .pairs
            .iter()
            .zip(&self.mu)
            .filter(|(_, &m)| m > 0.0)
            .map(|(p, &m)| (p, m))
            .collect();
        let sensitivity = if pressing.is_empty() || self.prob.set.contact_sensitivity {
            self.prob.sensitivity(
                &self.xi,
                &self.wgt,
                &self.lam,
                &pressing,
                self.kin.as_ref(),
                &mut self.w,
            )
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
            sensitivity,
        }
    }

    /// Factor the Lagrangian Hessian blocks in place (shifted towards the energy block where
    /// one is not positive definite); `Err(section)` if a block cannot be made so.
    fn factor(&mut self) -> Result<(), usize> {
        let prob = self.prob;
        let nb = prob.nb;
        let w = &mut self.w;
        if prob.set.cable_length == LengthMeasure::Path {
            prob.path_hessian(&self.xi, &self.wgt, w);
        }
        w.raw.copy_from_slice(&w.hess);
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
                    return Err(b * nb / 4 / prob.m + 1);
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
    /// z = H⁻¹ ∇f and y_r = H⁻¹ a_r the step is −z − Σ λ_r y_r (into `dxi`), where λ ≥ 0
    /// minimizes ½ λᵀ (S + C) λ − qᵀ λ, S = [a_rᵀ y_s], q_r = c_r − a_rᵀ z, C the diagonal of
    /// the cables' compliances `1/k` (a compliant row `a·d + c − λ/k ≤ 0` is the primal QP
    /// with a stretch `s` costing `½ k s²`; eliminating `s = λ/k` puts `1/k` on the dual's
    /// diagonal). Returns the new multipliers (cables, then contacts); `None` if the QP cycles.
    fn dual_step(&mut self) -> Option<Vec<f64>> {
        let prob = self.prob;
        let nrow = self.cable_rows.len() + self.pairs.len();
        self.w.z.copy_from_slice(&self.w.gobj);
        prob.block_solve(&self.w.hess, &mut self.w.z);
        let mut ys = std::mem::take(&mut self.w.y);
        ys.resize_with(nrow, Vec::new);
        for (r, y) in ys.iter_mut().enumerate() {
            let (a, sign, _) = self.row(r);
            y.clear();
            y.extend(a.iter().map(|v| sign * v));
            prob.block_solve(&self.w.hess, y);
        }
        let mut s_mat = vec![0.0; nrow * nrow];
        let mut q = vec![0.0; nrow];
        let mut lam_new = vec![0.0; nrow];
        for r in 0..nrow {
            let (a, sign, c) = self.row(r);
            q[r] = c - sign * dot(a, &self.w.z);
            for s in 0..nrow {
                s_mat[r * nrow + s] = sign * dot(a, &ys[s]);
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
        }
        self.w.y = ys;
        ok.then_some(lam_new)
    }

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

    /// The ℓ1 merit `E + V + Σ T L + Σ ½ k (L − t)₊² + pen · violation` (the compliant
    /// cables' springs, [`Problem::spring_energy`]).
    fn merit(&self, x: &[f64], kin: Option<&Kin>, len: &[f64], ps: &[Pair], pen: f64) -> f64 {
        let prob = self.prob;
        let mut f = prob.energy(x) + prob.load_potential(kin) + prob.spring_energy(len);
        for c in 0..prob.robot.cables.len() {
            if let Target::Tension(t) = prob.targets[c] {
                f += t * len[c];
            }
        }
        f + pen * self.violation(len, ps)
    }

    /// Backtracking on the ℓ1 merit along `dxi` (every pair re-queried at the trial point);
    /// the step length, 0 if no decrease was found (sets `stalled`).
    fn line_search(&mut self, lam_new: &[f64]) -> f64 {
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
        let mut alpha: f64 = 1.0;
        for _ in 0..40 {
            for i in 0..prob.nvar() {
                self.trial[i] = self.xi[i] + alpha * self.dxi[i];
            }
            let stretch_ok = (0..prob.nsub).all(|j| self.trial[4 * j + 3] > -1.0 + 1e-3);
            // No point may move farther than the robot's distance to the obstacles, or
            // than half the pair margin when closer: features near an obstacle are held
            // by their linearized constraints, the others cannot reach one, so nothing
            // passes through an obstacle between two iterates (distances to open meshes
            // are unsigned: a jump through a wall would look clear).
            let kin_trial = prob
                .needs_frames()
                .then(|| contacts::kinematics(&self.trial, &prob.ell, false));
            let (trial_pairs, trial_clear) = match (self.world, &kin_trial) {
                (Some(wd), Some(k)) if stretch_ok => wd.pairs(k),
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
            if stretch_ok && near_enough {
                prob.lengths(&self.trial, &mut self.trial_len);
                let phi = self.merit(
                    &self.trial,
                    kin_trial.as_ref(),
                    &self.trial_len,
                    &trial_pairs,
                    pen,
                );
                if phi.is_finite()
                    && (tiny || phi <= phi0 + 1e-4 * alpha * dphi.min(0.0) + 1e-14 * phi0.abs())
                {
                    self.stalled = false;
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

    /// Move by `alpha · dxi` and adopt the step's multipliers (contacts keyed by feature and
    /// obstacle, for the next linearization).
    fn take_step(&mut self, alpha: f64, lam_new: &[f64]) {
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

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
