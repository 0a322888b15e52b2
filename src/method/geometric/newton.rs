//! Newton–KKT on one face from one start (an SQP with clarabel's QP when obstacles are near),
//! with an ℓ1-merit line search.

use super::contact_curvature::Pressed;
use super::faces::{Candidate, Rejected, Step};
use super::obstacles::{penetration_of, worst_gap, Feature, Pair};
use super::problem::{Pose, SectionData};
use super::{Geometric, Objective};
use crate::contact::CONTACT_TOL;
use crate::numeric::ad::D2;
use crate::numeric::kkt::{kkt_step, kkt_step6, kkt_step6_gs, multipliers};
use crate::numeric::qp::qp_step6;
use crate::shape::Contact;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};
use std::cmp::Ordering::Less;

/// Newton step size at which a candidate with active contacts has converged [m or rad]. Was
/// 1e-7 (clarabel's interior-point steps and parry's unpolished GJK noise): candidates stopped
/// with steps of up to 1e-7 and stationarity up to 8e-6 (wall, pillar), ~1e-9 m from the
/// minimum. With the exact QP step ([`crate::numeric::active_qp`]) and polished witnesses the
/// polish converges on to the free tolerance: on the wall and the pillar every certified
/// contact candidate ends with a step ≤ 1e-11 and stationarity ≤ 7e-10. Since the
/// step carries the contact curvature (`contact_curvature.rs`) the last steps converge
/// quadratically (wall, disk 8: 1.7e-5 → 2.0e-10 → 1.3e-15, was 1.2e-5 → 1.1e-7 → 9.6e-10 →
/// 8.5e-12).
pub(super) const CONTACT_STEP_TOL: f64 = 1e-11;

/// [`CONTACT_STEP_TOL`] before that exact step, kept by `geometric-squared`: with 1e-11 its pillar
/// solve found no certified candidate in section 5 (not measured further; the squared
/// objective is not the paper's method).
/// The literal method falls back to it in a section near obstacles where no candidate
/// converged at 1e-11 ([`SectionData::loose_contacts`]): found by `tests/adversarial/adversarial_files.rs`
/// (the pillar turned by 1e5 rad solved before the tightening and not after). The
/// contact curvature did not make it unneeded: on the 40 turned pillars of
/// `tests/contact/geometric_contact.rs` the failing candidates chatter with steps of 1e-8–1e-6 at a
/// residual of 1e-13 — the noise of parry's distance and normal for the disk against the
/// pillar's side, not a slow step — and without the retry 34 of 40 fail (39 without the
/// curvature; with the closed-form derivatives next to obstacles 7 of 40 with it, 36 without).
const FORMER_CONTACT_STEP_TOL: f64 = 1e-7;

/// Stationarity a candidate with active contacts must meet, relative to (1 + largest contact
/// multiplier): the contact normals carry the same noise.
pub(super) const CONTACT_STAT_TOL: f64 = 1e-6;

/// Consecutive line searches cut below 1e-3 of the step after which a run is given up as
/// stalled (it is a kink of a term this face keeps non-zero, or no minimum on this face). Was
/// 3; 2 measured: the same certified answers on every case of
/// `tests/methods/geometric_tips.rs` (and the same `NotConverged` count in `geometric_random.rs`) with
/// 12–14 % fewer Newton iterations on the paper cases; 1 loses a random robot. The former
/// search ([`SectionData::former_search`]) keeps [`FORMER_MAX_SHORT_STEPS`].
const MAX_SHORT_STEPS: usize = 2;

/// Settled contact iterations (constraints and gaps met, a pressing contact, a step at most
/// [`FORMER_CONTACT_STEP_TOL`]) after which a run whose steps rose [`NOISE_FLOOR_RISES`] times
/// among them is at its noise floor (see [`NoiseFloor`]).
const NOISE_FLOOR_RUN: usize = 4;

/// Rises of the step within a settled run that tell noise from convergence (a converging
/// Newton's steps only fall).
const NOISE_FLOOR_RISES: usize = 2;

/// Whether a contact run has reached the noise floor of its contact normals: settled, with
/// steps no larger than [`FORMER_CONTACT_STEP_TOL`] that no longer fall but rise and fall.
///
/// Where a box edge or corner, or a cylinder's side, meets a disk's rim, the pair's normal
/// comes from parry's GJK and its polish, good to ~1e-9 (`contact/parry.rs`): the step, which
/// balances the contact force (~40 rad/m) against the bending, then chatters at 1e-8–1e-7 and
/// never reaches [`CONTACT_STEP_TOL`]. Such a run used to spend its 40 iterations and fail; the
/// section then searched every taut set twice more, the last time accepting steps of
/// [`FORMER_CONTACT_STEP_TOL`] (`loose_contacts`) — 1115 and 1375 Newton iterations in two
/// sections of one generated scene (`examples/scene_speed.rs`), 60× the committed wall's
/// instructions. The run is now certified where the loose retry would accept it, as soon as its
/// steps show noise instead of convergence; a run converging quadratically (the wall, the
/// pillar: 1.7e-5 → 2.0e-10 → 1.3e-15) reaches the tight tolerance first, and one converging
/// linearly never rises, so neither is changed.
#[derive(Default)]
struct NoiseFloor {
    /// Settled iterations in a row.
    run: usize,
    /// Rises of the step among them.
    rises: usize,
    /// The last step's size.
    last: f64,
}

impl NoiseFloor {
    /// Record an iteration (`settled`: constraints and gaps met with a pressing contact) with
    /// step size `dx`; true once the run is at its noise floor.
    fn at(&mut self, settled: bool, dx: f64) -> bool {
        if !settled || dx > FORMER_CONTACT_STEP_TOL {
            *self = NoiseFloor::default();
            return false;
        }
        if self.run > 0 && dx > self.last {
            self.rises += 1;
        }
        self.run += 1;
        self.last = dx;
        self.run >= NOISE_FLOOR_RUN && self.rises >= NOISE_FLOOR_RISES
    }
}

/// Consecutive Newton steps next to obstacles that each carry a term this face keeps non-zero
/// through its kink ([`crosses_kink`]) after which a run is given up: it is heading for that
/// kink, whose minimum belongs to the face where the term is zero (searched by its own runs).
///
/// Near a minimum of the face the term's angle is bounded away from zero while the steps
/// shrink to nothing, so a full step cannot flip the term's direction there: a run flipping it
/// at every step is not converging on this face. Measured on the 62 scenes of
/// `examples/scene_speed.rs` (paper case I): every run that was certified flipped a term on at
/// most 9 steps in a row (large early steps across a large angle), while runs circling a kink
/// (angles 1e-4–1e-3 rad, the line search cut to 1e-2 of the step, the merit hardly falling,
/// the short-step rule [`MAX_SHORT_STEPS`] never firing) flipped it at every step until their
/// 40 iterations were spent — 3 such runs of generated scene 13 spent 120 of its 530.
const MAX_KINK_CROSSINGS: usize = 12;

/// Whether the full step `dx` from `pose` carries the solved direction of a term this face
/// keeps non-zero through its undeformed direction: the direction's components normal to the
/// undeformed one (`e1`, `e2`: `sin` of the angle times the unit direction of the tilt) point
/// opposite ways before and after the step.
fn crosses_kink(data: &SectionData, pose: &Pose, dx: &Vector6<f64>, face: u32) -> bool {
    let full = pose.retract(dx, 1.0);
    data.terms.iter().enumerate().any(|(t, term)| {
        let image = |p: &Pose| if term.tangent { p.p } else { p.q * term.dir };
        let (a, b) = (image(pose), image(&full));
        face & (1 << t) == 0
            && term.e1.dot(&a) * term.e1.dot(&b) + term.e2.dot(&a) * term.e2.dot(&b) < 0.0
    })
}

/// A line search that ends below this step length is short (see [`MAX_SHORT_STEPS`]).
const SHORT_STEP: f64 = 1e-3;

/// The stall count of the former search.
const FORMER_MAX_SHORT_STEPS: usize = 3;

impl Geometric {
    /// Newton–KKT (SQP when obstacles are near) on one face from one start; returns a
    /// certified candidate or why not.
    ///
    /// Obstacle pairs within the margin enter each step as linearized inequalities
    /// `d_j + ∇d_j·dx ≥ clearance`; such steps are convex QPs solved exactly by a dual active set
    /// ([`crate::numeric::active_qp`]; clarabel where it makes no claim), steps without
    /// near pairs are the dense equality-only Newton–KKT step. The Lagrangian Hessian carries
    /// the contact curvature `−μ ∇²d` of every pair that pressed at the last step
    /// (`contact_curvature.rs`), so the contact steps converge quadratically. The line search uses the ℓ1
    /// merit `F + ρ (Σ|c| + Σ max(0, clearance − d_j))`.
    ///
    /// In the body:
    /// - one buffer each for the constraints, their rows and values, the multipliers, the pairs
    ///   and a trial's constraints and pairs serves every iteration and trial (room for the
    ///   most constraints a face has, 7 at a degenerate vertex);
    /// - the derivatives are closed-form, or dual numbers where `gram_schmidt` is off (its doc);
    /// - a run whose kept-non-zero term reaches its kink belongs to a face where it is zero;
    /// - at a converged point the active contacts join the equalities for the second-order
    ///   check; at a vertex whose rows are dependent (an unshortened taut cable on its
    ///   degenerate face, `degenerate.rs`), the multipliers that certify it, if any;
    /// - the merit at the iterate takes the penetration of the pairs at hand (was queried
    ///   again);
    /// - a short step that would end the run ends it whatever the merit below it does: near
    ///   obstacles (where each trial queries the contacts) the search stops at the first short
    ///   step (same outcome, same iterations; the free path is left as it was);
    /// - a trial that only a tiny step would accept stops querying the pairs once the merit
    ///   with those found so far is not below `m0` (`SectionWorld::penetration`'s rule: the
    ///   merit is monotone in the penetration, as `+ Σ|c|`, `· ρ > 0` and `+ F` round
    ///   monotonically), for the full merit is not below it either, or not a number;
    /// - an accepted trial was queried last and in full (its merit is finite), to the margin:
    ///   its pairs are the next iterate's, what `pairs_into` answers there to the bit
    ///   (`SectionWorld::penetration`'s doc), and are not queried again.
    pub(super) fn newton(
        &self,
        data: &SectionData,
        start: &Pose,
        face: u32,
        active: &[usize],
        squared: bool,
    ) -> Result<(Candidate, usize), Rejected> {
        let mut pose = *start;
        let world = data.world.as_ref();
        let mut lambda: Option<Vec<f64>> = None;
        let mut last_res = f64::INFINITY;
        let mut short_steps = 0;
        let max_short = if data.former_search.get() {
            FORMER_MAX_SHORT_STEPS
        } else {
            MAX_SHORT_STEPS
        };
        let mut rows: Vec<Vector6<f64>> = Vec::with_capacity(6);
        let (mut c, mut cv, mut pairs) = (Vec::with_capacity(8), Vec::with_capacity(8), Vec::new());
        let (mut trial_cons, mut trial_pairs) = (Vec::with_capacity(8), Vec::new());
        let mut lam = Vec::with_capacity(8);
        let mut pressed = Pressed::default();
        let mut pairs_at_hand = false;
        let mut floor = NoiseFloor::default();
        let mut qp_active = QpActive::new();
        let mut kink_streak = 0;
        for it in 1..=self.max_iterations {
            let reject = |residual: f64| {
                Err(Rejected {
                    iterations: it,
                    residual,
                    escape: None,
                })
            };
            let f = if data.world.is_some() && !data.gram_schmidt {
                data.eval::<D2<6>>(&pose, face, active, squared, &mut c)
            } else {
                data.eval_d2(&pose, face, active, squared, &mut c)
            };
            if !f.v.is_finite() || c.iter().any(|x| !x.v.is_finite()) {
                return reject(last_res);
            }
            let g = Vector6::from_row_slice(&f.g);
            rows_and_values(&c, &mut rows, &mut cv);
            let mut h = lagrangian_hessian(&f, &c, &g, &rows, lambda.as_deref(), &mut lam);
            if h.iter().any(|x| !x.is_finite()) {
                return reject(last_res);
            }
            if !squared && it > 1 && self.runs_into_kink(data, &pose, face) {
                return reject(cv.iter().fold(0.0f64, |m, x| m.max(x.abs())));
            }
            pairs.clear();
            if let Some(w) = world {
                if pairs_at_hand {
                    std::mem::swap(&mut pairs, &mut trial_pairs);
                } else {
                    w.pairs_into(&pose, &mut pairs);
                }
                w.add_pressed_curvature(&pose, &pairs, &pressed, &mut h);
            }
            let clearance = world.map_or(0.0, |w| w.clearance);
            let (step, mu) = if pairs.is_empty() {
                (self.step(&h, &g, &rows, &cv, data.gram_schmidt), vec![])
            } else {
                match self.contact_step(&h, &g, &rows, &cv, &pairs, data, &mut qp_active) {
                    Some(s) => s,
                    None => return reject(last_res),
                }
            };
            let res = cv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let worst_gap = worst_gap(&pairs, clearance);
            last_res = res.max(worst_gap);
            let mu_max = mu.iter().fold(0.0f64, |m, x| m.max(*x));
            let in_contact = mu_max > 1e-10;
            let step_tol = self.step_tolerance(data, in_contact);
            let settled = res <= self.tolerance && worst_gap <= CONTACT_TOL;
            let at_floor = floor.at(settled && in_contact, step.dx.amax());
            if settled && (step.dx.amax() <= step_tol || at_floor) {
                let run = (pose, face, active, squared);
                return self.converged(
                    data,
                    run,
                    step,
                    (&pairs, &mu),
                    (&g, &rows),
                    (res, last_res, it),
                );
            }
            kink_streak =
                if world.is_some() && !squared && crosses_kink(data, &pose, &step.dx, face) {
                    kink_streak + 1
                } else {
                    0
                };
            if kink_streak >= MAX_KINK_CROSSINGS {
                return reject(last_res);
            }
            let amax = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let rho = 2.0 * amax(&step.lambda).max(amax(&lam)).max(amax(&mu)) + 1.0;
            let merit = |f: f64, c: &[f64], pen: f64| {
                f + rho * (c.iter().map(|x| x.abs()).sum::<f64>() + pen)
            };
            let pen0 = world.map_or(0.0, |w| penetration_of(&pairs, w.clearance));
            let m0 = merit(f.v, &cv, pen0);
            let floor = if world.is_some() && short_steps + 1 >= max_short {
                SHORT_STEP
            } else {
                0.0
            };
            let (next, alpha) = line_search(&pose, &step.dx, m0, floor, |trial, tiny| {
                let ft = data.eval::<f64>(trial, face, active, squared, &mut trial_cons);
                let Some(w) = world else {
                    return merit(ft, &trial_cons, 0.0);
                };
                let rejects =
                    |pen: f64| !tiny && merit(ft, &trial_cons, pen).partial_cmp(&m0) != Some(Less);
                w.penetration(trial, &mut trial_pairs, &rejects, &pairs)
                    .map_or(f64::NAN, |pen| merit(ft, &trial_cons, pen))
            });
            short_steps = if alpha < SHORT_STEP {
                short_steps + 1
            } else {
                0
            };
            match next {
                Some(p) if short_steps < max_short => {
                    pose = p;
                    pairs_at_hand = true;
                }
                _ => return reject(last_res),
            }
            lambda = Some(step.lambda);
            pressed = Pressed::of(&pairs, &mu);
        }
        Err(Rejected {
            iterations: self.max_iterations,
            residual: last_res,
            escape: None,
        })
    }

    /// A run settled at `pose` (`run`: pose, face, active set, objective): its pressing pairs
    /// as contacts, its multipliers (at a vertex of seven rows, the vertex's own), its
    /// stationarity, certified ([`Geometric::certify`]); rejected where a contact pulls, with
    /// the run's residual `last_res` (constraints and gaps).
    fn converged(
        &self,
        data: &SectionData,
        (pose, face, active, squared): (Pose, u32, &[usize], bool),
        step: Step,
        (pairs, mu): (&[Pair], &[f64]),
        (g, rows): (&Vector6<f64>, &[Vector6<f64>]),
        (res, last_res, it): (f64, f64, usize),
    ) -> Result<(Candidate, usize), Rejected> {
        let world = data.world.as_ref();
        let mu_max = mu.iter().fold(0.0f64, |m, x| m.max(*x));
        let in_contact = mu_max > 1e-10;
        let contacts: Vec<Contact> = (0..pairs.len())
            .filter(|&j| mu.get(j).copied().unwrap_or(0.0) > 1e-10)
            .map(|j| pairs[j].to_contact(world, data.section, mu[j]))
            .collect();
        if mu.iter().any(|m| *m < -1e-9) {
            return Err(Rejected {
                iterations: it,
                residual: last_res,
                escape: None,
            });
        }
        let lambda = if rows.len() == 7 && pairs.is_empty() {
            data.vertex_multipliers(face, active, g, rows)
                .unwrap_or(step.lambda)
        } else {
            step.lambda
        };
        let stat = stationarity(g, rows, &lambda, pairs, mu);
        self.certify(
            data,
            pose,
            face,
            active,
            squared,
            &lambda,
            (stat, stationarity_tolerance(in_contact, mu_max)),
            step.min_reduced_eigenvalue,
            res,
            it,
            contacts,
        )
    }

    /// The Newton step size at which a run has converged: 1e-11, or with active contacts
    /// [`CONTACT_STEP_TOL`] — [`FORMER_CONTACT_STEP_TOL`] for `geometric-squared` (by the
    /// method, not by the run's objective: the literal method's squared start runs converge
    /// like its own) and on the literal method's last retry ([`SectionData::loose_contacts`]).
    fn step_tolerance(&self, data: &SectionData, in_contact: bool) -> f64 {
        let former = self.objective == Objective::Squared || data.loose_contacts.get();
        match (in_contact, former) {
            (true, false) => CONTACT_STEP_TOL,
            (true, true) => FORMER_CONTACT_STEP_TOL,
            (false, _) => 1e-11,
        }
    }

    /// Whether Newton ran a term that this face keeps non-zero into its kink.
    fn runs_into_kink(&self, data: &SectionData, pose: &Pose, face: u32) -> bool {
        (0..data.terms.len())
            .any(|t| face & (1 << t) == 0 && data.term_angle(pose, t) < 10.0 * self.zero_angle)
    }

    /// One step with obstacle pairs near: a convex QP with the pairs as linearized
    /// inequalities, then, once feasible to 1e-8, an exact Newton–KKT polish with the active
    /// contacts as equalities (its rows split as `data.gram_schmidt` says). Before that, for the
    /// literal method, the same exact step on the QP's active contacts replaces the QP's step
    /// wherever it solves the SQP's own QP ([`newton_solves_qp`]; the QP clamps the whole
    /// Hessian positive definite). Returns the step and the pairs' multipliers (≥ 0 when pressing).
    /// The QP starts from the pairs its last solve in this run ended active on (`qp_active`,
    /// updated): the same step, usually in one KKT solve instead of one per row added.
    #[allow(clippy::too_many_arguments)]
    fn contact_step(
        &self,
        h: &Matrix6<f64>,
        g: &Vector6<f64>,
        rows: &[Vector6<f64>],
        cv: &[f64],
        pairs: &[Pair],
        data: &SectionData,
        qp_active: &mut QpActive,
    ) -> Option<(Step, Vec<f64>)> {
        let clearance = data.world.as_ref().map_or(0.0, |w| w.clearance);
        let in_rows: Vec<Vector6<f64>> = pairs.iter().map(|p| -p.grad).collect();
        let in_rhs: Vec<f64> = pairs.iter().map(|p| p.dist - clearance).collect();
        let eq_rhs: Vec<f64> = cv.iter().map(|x| -x).collect();
        let guess = qp_active.rows_in(pairs);
        let (q, active) = qp_step6(h, g, (rows, &eq_rhs), (&in_rows, &in_rhs), 1e-10, &guess)?;
        qp_active.keep(pairs, &active);
        let res0 = cv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let gap0 = pairs
            .iter()
            .map(|p| clearance - p.dist)
            .fold(0.0f64, f64::max);
        let polish = res0 <= 1e-8 && gap0 <= 1e-8;
        // Polish: with the active contacts identified, an exact Newton–KKT step on them as
        // equalities converges quadratically (multiplier of dist ≥ c is −λ).
        let mu_max = q.mu.iter().fold(1.0f64, |m, x| m.max(*x));
        let act: Vec<usize> = (0..pairs.len())
            .filter(|&j| q.mu[j] > 1e-9 * mu_max)
            .collect();
        if polish || self.objective == Objective::Literal {
            let mut all = rows.to_vec();
            let mut cc = cv.to_vec();
            for &j in &act {
                all.push(pairs[j].grad);
                cc.push(pairs[j].dist - clearance);
            }
            let st = self.step(h, g, &all, &cc, data.gram_schmidt);
            let mut mu = vec![0.0; pairs.len()];
            for (k, &j) in act.iter().enumerate() {
                mu[j] = -st.lambda[rows.len() + k];
            }
            if polish || newton_solves_qp(&st, &mu, &act, pairs, clearance) {
                return Some((
                    Step {
                        dx: st.dx,
                        lambda: st.lambda[..rows.len()].to_vec(),
                        min_reduced_eigenvalue: st.min_reduced_eigenvalue,
                    },
                    mu,
                ));
            }
        }
        Some((
            Step {
                dx: q.x,
                lambda: q.lambda_eq,
                min_reduced_eigenvalue: f64::NAN,
            },
            q.mu,
        ))
    }

    /// One Newton–KKT step: the allocation-free 6×6 kernel, or the general one when the
    /// constraint rows are redundant (its multiplier system is singular). `gram_schmidt`:
    /// split the rows by Gram–Schmidt ([`kkt_step6_gs`], same step in exact arithmetic,
    /// cheaper); `geometric-squared` next to obstacles keeps the eigen split its recorded tips
    /// were solved with (see [`SectionData::gram_schmidt`]).
    pub(super) fn step(
        &self,
        h: &Matrix6<f64>,
        g: &Vector6<f64>,
        rows: &[Vector6<f64>],
        c: &[f64],
        gram_schmidt: bool,
    ) -> Step {
        let fast = if gram_schmidt {
            kkt_step6_gs(h, g, rows, c, 1e-10)
        } else {
            kkt_step6(h, g, rows, c, 1e-10)
        };
        if let Some(s) = fast {
            return Step {
                dx: s.dx,
                lambda: s.lambda[..rows.len()].to_vec(),
                min_reduced_eigenvalue: s.min_reduced_eigenvalue,
            };
        }
        let hd = DMatrix::from_fn(6, 6, |r, col| h[(r, col)]);
        let gd = DVector::from_row_slice(g.as_slice());
        let ad = DMatrix::from_fn(rows.len(), 6, |r, col| rows[r][col]);
        let s = kkt_step(&hd, &gd, &ad, &DVector::from_row_slice(c), 1e-10);
        Step {
            dx: Vector6::from_row_slice(s.dx.as_slice()),
            lambda: s.lambda.as_slice().to_vec(),
            min_reduced_eigenvalue: s.min_reduced_eigenvalue,
        }
    }
}

/// Whether the exact Newton–KKT step `st` on the QP's active contacts `act` held as equalities
/// (multipliers `mu`) solves the SQP's own QP — the one with the Lagrangian Hessian `H` itself
/// rather than `H` clamped positive definite: its reduced Hessian on that face is positive
/// definite (not modified), every held contact pushes (`μ ≥ 0`) and every other pair's
/// linearized gap keeps the clearance. Then `st` meets the QP's KKT conditions with a
/// positive definite reduced Hessian, a strict local minimizer of it, the SQP step of
/// Nocedal & Wright (*Numerical Optimization*, 2nd ed., §18.1: once the active set is
/// identified, SQP is Newton's method on the KKT system, quadratically convergent, Thm 18.4).
/// The clamped QP's step differs from it wherever `H` is indefinite off that face — the
/// Lagrangian of the literal angles with `|p| = l0` almost always is — and converged only
/// linearly (rate ~½, the step halving for 10 iterations in a generated scene's contact runs,
/// `examples/scene_speed.rs`).
fn newton_solves_qp(st: &Step, mu: &[f64], act: &[usize], pairs: &[Pair], clearance: f64) -> bool {
    let eig = st.min_reduced_eigenvalue;
    if eig.is_nan() || eig <= 0.0 || act.iter().any(|&j| mu[j] < 0.0) {
        return false;
    }
    pairs.iter().enumerate().all(|(j, p)| {
        act.contains(&j) || {
            let lin = p.dist + p.grad.dot(&st.dx) - clearance;
            lin >= -1e-13 * (p.dist.abs() + p.grad.abs().dot(&st.dx.abs()) + clearance.abs())
        }
    })
}

/// The pairs (obstacle, feature) a run's last contact QP ended active on, in its order: the
/// next QP's guess ([`qp_step6`]). Pairs are found afresh at each iterate, so they are
/// named, not numbered.
struct QpActive(Vec<(usize, Feature)>);

impl QpActive {
    fn new() -> QpActive {
        QpActive(Vec::new())
    }

    /// The guess as rows of `pairs`: the named pairs still among them, in order.
    fn rows_in(&self, pairs: &[Pair]) -> Vec<usize> {
        self.0
            .iter()
            .filter_map(|&(o, f)| pairs.iter().position(|p| p.obstacle == o && p.feature == f))
            .collect()
    }

    /// Remember the pairs of rows `active` of `pairs`.
    fn keep(&mut self, pairs: &[Pair], active: &[usize]) {
        self.0.clear();
        self.0.extend(
            active
                .iter()
                .map(|&j| (pairs[j].obstacle, pairs[j].feature)),
        );
    }
}

/// The constraints' gradient rows and values, into the run's buffers.
fn rows_and_values(c: &[D2<6>], rows: &mut Vec<Vector6<f64>>, cv: &mut Vec<f64>) {
    rows.clear();
    rows.extend(c.iter().map(|cj| Vector6::from_row_slice(&cj.g)));
    cv.clear();
    cv.extend(c.iter().map(|cj| cj.v));
}

/// Hessian of the Lagrangian `∇²F + Σ λ_j ∇²c_j` with the previous step's multipliers, or, on
/// the first iteration, the least-squares multipliers of `∇F + Aᵀλ = 0`; returns the Hessian,
/// the multipliers into `lam` (the run's buffer).
fn lagrangian_hessian(
    f: &D2<6>,
    c: &[D2<6>],
    g: &Vector6<f64>,
    rows: &[Vector6<f64>],
    lambda: Option<&[f64]>,
    lam: &mut Vec<f64>,
) -> Matrix6<f64> {
    lam.clear();
    match lambda {
        Some(l) => lam.extend_from_slice(l),
        None => {
            let a = DMatrix::from_fn(c.len(), 6, |r, col| rows[r][col]);
            lam.extend_from_slice(
                multipliers(&DVector::from_row_slice(g.as_slice()), &a).as_slice(),
            );
        }
    }
    let mut h = Matrix6::from_fn(|r, col| f.h[r][col]);
    for (j, cj) in c.iter().enumerate() {
        h += Matrix6::from_fn(|r, col| cj.h[r][col]) * lam[j];
    }
    h
}

/// Backtracking from the full step: the first of 20 halvings whose merit is finite and below
/// `m0` (or whose step is below 1e-8); returns it (None if none) and the last step length.
/// Step lengths below `floor` are not tried (None, with that length). `merit_at` is told
/// whether the step is below 1e-8 (any finite merit accepts it); otherwise it may answer NaN
/// for a trial whose merit it has proved not below `m0` (rejected the same).
fn line_search(
    pose: &Pose,
    dx: &Vector6<f64>,
    m0: f64,
    floor: f64,
    mut merit_at: impl FnMut(&Pose, bool) -> f64,
) -> (Option<Pose>, f64) {
    let mut alpha = 1.0;
    for _ in 0..20 {
        if alpha < floor {
            return (None, alpha);
        }
        let trial = pose.retract(dx, alpha);
        let tiny = dx.amax() * alpha < 1e-8;
        let mt = merit_at(&trial, tiny);
        if mt.is_finite() && (mt < m0 || tiny) {
            return (Some(trial), alpha);
        }
        alpha *= 0.5;
    }
    (None, alpha)
}

/// `|∇F + Σ λ_j ∇c_j − Σ μ_k ∇d_k|_∞`, the stationarity of the Lagrangian.
fn stationarity(
    g: &Vector6<f64>,
    rows: &[Vector6<f64>],
    lambda: &[f64],
    pairs: &[Pair],
    mu: &[f64],
) -> f64 {
    let mut kkt_res = *g;
    for (r, l) in rows.iter().zip(lambda) {
        kkt_res += r * *l;
    }
    for (p, m) in pairs.iter().zip(mu) {
        kkt_res -= p.grad * *m;
    }
    kkt_res.amax()
}

/// The stationarity a converged run must meet: 1e-7, or with active contacts
/// [`CONTACT_STAT_TOL`] relative to the largest contact multiplier `mu_max`.
fn stationarity_tolerance(in_contact: bool, mu_max: f64) -> f64 {
    if in_contact {
        CONTACT_STAT_TOL * (1.0 + mu_max)
    } else {
        1e-7
    }
}

#[cfg(test)]
mod tests {
    use super::NoiseFloor;

    /// Whether a run of settled steps is taken for its noise floor, and at which step.
    fn first_floor(steps: &[f64]) -> Option<usize> {
        let mut f = NoiseFloor::default();
        steps.iter().position(|&dx| f.at(true, dx))
    }

    /// Converging runs are never at their floor — quadratic (the wall's last steps) or linear
    /// with any rate — and a chattering run (section 7 of a generated scene: steps of
    /// 1e-8–1e-7 that rise and fall) is, at its fourth settled step with two rises; a step
    /// above the former tolerance or an unsettled iteration starts the count again.
    #[test]
    fn noise_floor_tells_chatter_from_convergence() {
        assert_eq!(first_floor(&[1.7e-5, 2.0e-10, 1.3e-15]), None);
        for rate in [0.9, 0.5, 0.1] {
            let linear: Vec<f64> = (0..40).map(|k| 1e-7 * f64::powi(rate, k)).collect();
            assert_eq!(first_floor(&linear), None, "{rate}");
        }
        let chatter = [8.3e-8, 6.5e-8, 2.5e-8, 6.6e-8, 1.8e-8, 3.9e-8, 2.7e-8];
        assert_eq!(first_floor(&chatter), Some(5));
        assert_eq!(
            first_floor(&[6.6e-8, 1.8e-8, 3.9e-8, 2e-7, 2.7e-8, 4e-8, 1e-8]),
            None
        );
        let mut f = NoiseFloor::default();
        for dx in [5e-8, 1e-8, 4e-8, 1e-8] {
            assert!(!f.at(false, dx));
        }
    }
}
