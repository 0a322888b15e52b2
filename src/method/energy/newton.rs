//! The sequential-QP (Newton–KKT) loop of the energy model (derivation in the docs of
//! [`super`]), cut by role: [`Sqp::linearize`] (lengths, gradients, contact pairs at the
//! iterate), [`Sqp::residuals`], [`Sqp::factor`] (block Cholesky of the Lagrangian Hessian),
//! [`Sqp::dual_step`] (the step's QP in its dual), [`Sqp::line_search`] (ℓ1 merit) and
//! [`Energy::failure`] (which named error a run that did not converge ends in). The loop,
//! its start and its end are here; the iterate (`newton/iterate.rs`), the step
//! (`newton/step.rs`) and the line search (`newton/line_search.rs`) in files of their own.

mod curved;
mod iterate;
mod line_search;
mod shear_step;
mod step;
#[cfg(test)]
mod tests;

use super::contacts::{Feat, Kin, Pair, PairKey, World};
use super::lengths::Work;
use super::problem::{Problem, Target};
use super::sensitivity::Sensitivity;
use super::Energy;
use crate::error::SolveError;
use crate::method::warm::{EnergyHessian, WarmState};
use crate::method::Method;
use crate::model::actuation::LengthMeasure;
use crate::numeric::semisep::SemiSepFactor;
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
    /// The residual at every iteration (read by the convergence tests).
    #[cfg_attr(not(test), allow(dead_code))]
    pub history: Vec<f64>,
    /// Stability and tip Jacobian from the converged KKT system (`sensitivity.rs`).
    pub sensitivity: Sensitivity,
    /// The Hessian blocks built for the sensitivity, for the next warm start.
    pub hessian: Option<EnergyHessian>,
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
    mu_prev: Vec<(PairKey, f64)>,
    clear: f64,
    dxi: Vec<f64>,
    trial: Vec<f64>,
    /// Cable lengths at the line search's trial point (filled when its merit is asked for).
    trial_len: std::cell::RefCell<Vec<f64>>,
    /// The factored Hessian with the curvature of loads and contacts, when there is some
    /// ([`Sqp::factor`]).
    curved: Option<SemiSepFactor>,
    /// Rows of the step's QP penalized in `curved` and their `ρ` (`newton/curved.rs`).
    penalty: Vec<(usize, f64)>,
    /// The residual at every iteration so far.
    history: Vec<f64>,
    /// Chords: exact Hessian (second-order AD) instead of Gauss–Newton.
    exact: bool,
    /// The last line search found no decrease.
    stalled: bool,
    /// Bound on how far the last full step moved any point \[m\] (∞ after a damped step).
    last_move: f64,
    /// The pairs and clearance the line search found at the accepted step, for the next
    /// linearization (the same point: only the gradients are missing).
    next_pairs: Option<(Vec<Pair>, f64)>,
    /// The Hessian blocks a warm start brought (the last ones of the solve it comes from),
    /// for the first [`Sqp::factor`] when its strains and weights are theirs.
    warm_hessian: Option<EnergyHessian>,
}

impl Energy {
    /// Sequential QP (Newton–KKT) on the whole robot (module docs). Returns the strains, the
    /// cable multipliers, the active contacts with theirs, iterations and the final residual.
    pub(super) fn newton(
        &self,
        prob: &Problem,
        warm: Option<&Shape>,
    ) -> Result<Solution, SolveError> {
        self.start_shear(prob, warm);
        self.newton_from(prob, self.start_point(prob, warm), warm)
    }

    /// [`Energy::newton`] from the strains and cable multipliers `start`; `warm` (the shape
    /// `start` came from, if any) may bring the Hessian blocks of its last iteration.
    pub(super) fn newton_from(
        &self,
        prob: &Problem,
        start: (Vec<f64>, Vec<f64>),
        warm: Option<&Shape>,
    ) -> Result<Solution, SolveError> {
        let mut sqp = Sqp::new(prob, start);
        sqp.warm_hessian = warm_hessian(warm, &sqp.xi).filter(|_| !self.shear);
        let tol = self.tolerance;
        let mut resid = f64::INFINITY;
        // Whether the start keeps the clearance: a run that ends inside it then did not settle
        // (rather than starting across an obstacle).
        let mut start_clear = true;
        for it in 0..=self.max_iterations {
            // The shear's Newton step on its own equilibrium at the iterate (`energy/shear.rs`,
            // `newton/shear_step.rs`), then the SQP's linearization at fixed shear.
            let shear_move = sqp.shear_and_linearize();
            // A start across a solid mesh's wall cannot come back (module docs): refused now.
            if it == 0 {
                if let Some(e) = self.across_solid(&sqp) {
                    return Err(e);
                }
                start_clear = !sqp
                    .pairs
                    .iter()
                    .any(|p| p.dist < sqp.clearance - CONTACT_RESIDUAL);
            }
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
            resid = r.feas.max(r.stat).max(r.gap).max(shear_move);
            sqp.history.push(resid);
            if !resid.is_finite() {
                break;
            }
            // With contacts, parry's distances on smooth pairs carry ~1e-9 m of noise.
            // With active contacts the Hessian carries their curvature and Newton converges
            // quadratically to the tolerance, except where parry's normals on smooth pairs
            // carry noise (a disk rim against a cylinder: ~1e-5 rad) that keeps the
            // stationarity residual from falling below ~1e-6: there the solution has
            // converged once a full Newton step moves no point of the robot by more than
            // CONTACT_STEP (a bound: Σ ℓ_j (|δu_j| (L − s_j) + |δε_j|)).
            let in_contact = sqp.mu.iter().any(|&m| m > 0.0);
            let ctol = if in_contact {
                tol.max(CONTACT_RESIDUAL)
            } else {
                tol
            };
            let settled = in_contact && sqp.last_move <= CONTACT_STEP;
            if r.feas <= tol && r.gap <= ctol && (r.stat <= tol || settled) && shear_move <= tol {
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
            let Some(lam_new) = sqp.dual_step() else {
                // Still inside an obstacle: that is the named reason (a start that crosses it).
                return Err(self.obstructed(&sqp, it, start_clear).unwrap_or_else(|| {
                    SolveError::NotConverged {
                        method: self.name().into(),
                        section: None,
                        iterations: it,
                        residual: resid,
                        detail: "the step's QP (cable and contact multipliers) did not converge"
                            .into(),
                    }
                }));
            };
            // A step that is not finite (an ill-conditioned KKT system far from any
            // equilibrium) would carry the iterate with it even at a step length of zero
            // (`0 · NaN`): the run ends on the last finite iterate, whose stretch or residual
            // names the failure.
            if !(sqp.dxi.iter().chain(&lam_new).all(|v| v.is_finite())) {
                break;
            }
            let alpha = sqp.line_search(&lam_new);
            sqp.take_step(alpha, &lam_new);
        }
        Err(self.failure(&sqp, resid, start_clear))
    }

    /// The start: the strains and multipliers of a warm shape of this method and layout, else
    /// strains fitted to the disk frames of any other shape with as many disks, else straight.
    pub(super) fn start_point(&self, prob: &Problem, warm: Option<&Shape>) -> (Vec<f64>, Vec<f64>) {
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
                    && e.sub_arcs.len() + 1 == prob.first.len()
                    && e.sub_arcs
                        .iter()
                        .zip(prob.first.windows(2))
                        .all(|(m, w)| *m == w[1] - w[0])
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
    fn failure(&self, sqp: &Sqp, resid: f64, start_clear: bool) -> SolveError {
        let prob = sqp.prob;
        if let Err(e) = self.check_stretch(prob, &sqp.xi, &sqp.lam) {
            return e;
        }
        if let Some(e) = self.obstructed(sqp, self.max_iterations, start_clear) {
            return e;
        }
        SolveError::NotConverged {
            method: self.name().into(),
            section: None,
            iterations: self.max_iterations,
            residual: resid,
            detail: "residual = max(length error [m], contact gap [m], r̄·|∇ℒ|∞/(EI ℓ))".into(),
        }
    }

    /// [`SolveError::Obstructed`] when the iterate, after `iterations`, still lies inside an
    /// obstacle and the start did too (`start_clear` false): the start crossed it (the
    /// straight robot through a wall, or a tube it does not fit). From a clear start, the same
    /// state is [`SolveError::NotConverged`]: the iterations did not settle against the
    /// obstacle, which says so.
    fn obstructed(&self, sqp: &Sqp, iterations: usize, start_clear: bool) -> Option<SolveError> {
        let clearance = sqp.clearance;
        let p = sqp
            .pairs
            .iter()
            .filter(|p| p.dist < clearance - CONTACT_RESIDUAL)
            .min_by(|a, b| a.dist.total_cmp(&b.dist))?;
        let c = sqp.world.map(|wd| wd.contact(p, 0.0));
        let obstacle = c.as_ref().map(|c| c.obstacle.clone()).unwrap_or_default();
        let section = c.and_then(|c| c.section.or(c.disk)).unwrap_or(0);
        let feature = match p.feat {
            Feat::Backbone(_) => "backbone",
            Feat::Disk(_) => "disk",
            Feat::Cable(..) => "cable",
        };
        let depth = clearance - p.dist;
        if start_clear {
            return Some(SolveError::NotConverged {
                method: self.name().into(),
                section: Some(section),
                iterations,
                residual: sqp.history.last().copied().unwrap_or(depth),
                detail: format!(
                    "the iterations did not settle against `{obstacle}`: the {feature} still \
                     lies {depth:.3e} m inside the clearance, from a start clear of it"
                ),
            });
        }
        Some(SolveError::Obstructed {
            obstacle,
            section,
            reason: format!(
                "after {iterations} iterations the {feature} still lies {depth:.3e} m inside \
                 the clearance: the start crosses the obstacle; start from a shape that is \
                 clear of it (e.g. the geometric method's, `--warm-from geometric`)"
            ),
        })
    }

    /// [`SolveError::Obstructed`] when a feature of the start lies across or beyond the wall of
    /// a solid mesh (a negative signed distance): every iterate would keep it there, as the
    /// start that crosses any obstacle ([`Energy::obstructed`]), so the solve is refused before
    /// its first step rather than after its last.
    ///
    /// The same for a closed surface mesh (no `free` declared, every edge shared by two
    /// triangles: [`crate::contact::solid::closed_surface`]) that a feature of the start
    /// crosses (a negative unsigned distance: it meets the surface's both sides), which every
    /// iterate would keep crossing, and whose 60 iterations of queries took 20–30 s on a
    /// 25 000-triangle mesh before ending in the same error.
    fn across_solid(&self, sqp: &Sqp) -> Option<SolveError> {
        let scene = sqp.world?.scene;
        let deepest = |wall: &dyn Fn(usize) -> bool| {
            sqp.pairs
                .iter()
                .filter(|p| p.dist < -CONTACT_RESIDUAL && wall(p.obstacle))
                .min_by(|a, b| a.dist.total_cmp(&b.dist))
        };
        let shape = |k: usize| &*scene.obstacles[k].shape;
        let (p, wall) = match deepest(&|k| crate::contact::solid::solid(shape(k)).is_some()) {
            Some(p) => (p, "the wall of this solid mesh"),
            None => {
                // Each crossed surface's edges checked once.
                let mut crossed: Vec<usize> = sqp
                    .pairs
                    .iter()
                    .filter(|p| p.dist < -CONTACT_RESIDUAL)
                    .map(|p| p.obstacle)
                    .collect();
                crossed.sort_unstable();
                crossed.dedup();
                crossed.retain(|&k| crate::contact::solid::closed_surface(shape(k)));
                let p = deepest(&|k| crossed.binary_search(&k).is_ok())?;
                (p, "this closed surface mesh")
            }
        };
        let c = sqp.world.map(|wd| wd.contact(p, 0.0));
        Some(SolveError::Obstructed {
            obstacle: scene.obstacles[p.obstacle].name.clone(),
            section: c.and_then(|c| c.section.or(c.disk)).unwrap_or(0),
            reason: format!(
                "the start's {} lies {:.3e} m across {wall}: the start \
                 crosses the obstacle; start from a shape that is clear of it (e.g. the \
                 geometric method's, `--warm-from geometric`)",
                match p.feat {
                    Feat::Backbone(_) => "backbone",
                    Feat::Disk(_) => "disk",
                    Feat::Cable(..) => "cable",
                },
                -p.dist
            ),
        })
    }

    /// A solution that compresses the backbone below `min_stretch` means the cable lengths
    /// cannot be reached by bending: name the most loaded cable.
    fn check_stretch(&self, prob: &Problem, xi: &[f64], lam: &[f64]) -> Result<(), SolveError> {
        let (jmin, smin) = (0..prob.nsub)
            .map(|j| (j, 1.0 + xi[4 * j + 3]))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, 1.0));
        if xi.iter().any(|v| !v.is_finite()) {
            return Err(SolveError::NotConverged {
                method: self.name().into(),
                section: Some(prob.section_of(jmin)),
                iterations: self.max_iterations,
                residual: f64::INFINITY,
                detail: "the strains left the finite numbers".into(),
            });
        }
        if smin >= self.min_stretch {
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

/// The Hessian blocks carried by a warm shape of this method, if any, when the start `xi`
/// is that shape's strains.
fn warm_hessian(warm: Option<&Shape>, xi: &[f64]) -> Option<EnergyHessian> {
    match &warm?.report.warm {
        Some(WarmState::Energy(e)) if e.strains == xi => e.hessian.clone(),
        _ => None,
    }
}

/// The routing fingerprint of [`EnergyHessian::routing`]: sub-arc lengths, then per cable
/// the disk it ends at, its hole radii and angles.
fn routing(prob: &Problem) -> Vec<f64> {
    let cables = &prob.robot.cables;
    let n = prob.ell.len()
        + cables
            .iter()
            .map(|c| 1 + c.radius.len() + c.angle.len())
            .sum::<usize>();
    let mut out = Vec::with_capacity(n);
    out.extend_from_slice(&prob.ell);
    for cable in cables {
        out.push(cable.ends_at as f64);
        out.extend_from_slice(&cable.radius);
        out.extend_from_slice(&cable.angle);
    }
    out
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
