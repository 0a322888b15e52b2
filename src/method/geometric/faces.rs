//! Faces and certification: the taut-set search (cables pull, they do not push), the faces
//! (sets of angle terms that vanish) on each taut set, and the certificate a candidate must
//! carry to be accepted.

use super::bound::{skip_enabled, LENGTH_SLACK};
use super::problem::{Pose, SectionData};
use super::starts::nudge;
use super::{Geometric, Objective};
use crate::contact::CONTACT_TOL;
use crate::error::SolveError;
use crate::method::Method;
use crate::numeric::qp::disc_sum_scale;
use crate::numeric::so3::exp_so3;
use crate::shape::{Contact, SectionReport};
use nalgebra::{Vector3, Vector6};
use std::f64::consts::FRAC_PI_2;

/// The accepted solution of one section.
#[derive(Clone)]
pub(super) struct SectionSolution {
    /// Whether the pose is a strict local minimum of the section problem (see
    /// [`STRICT_EIGENVALUE`]).
    pub(super) strict: bool,
    pub(super) pose: Pose,
    pub(super) slack: Vec<usize>,
    pub(super) report: SectionReport,
    pub(super) contacts: Vec<Contact>,
}

/// A converged, certified candidate.
#[derive(Clone)]
pub(super) struct Candidate {
    pub(super) pose: Pose,
    pub(super) objective: f64,
    pub(super) residual: f64,
    /// Multipliers of the active cable constraints (≥ 0 when the cable pulls).
    pub(super) cable_lambda: Vec<f64>,
    pub(super) face: u32,
    /// Active contacts with their multipliers.
    pub(super) contacts: Vec<Contact>,
    /// Smallest eigenvalue of the reduced Hessian (∞ at a vertex, where nothing is free).
    pub(super) min_eig: f64,
}

/// A Newton–KKT step.
pub(super) struct Step {
    pub(super) dx: Vector6<f64>,
    pub(super) lambda: Vec<f64>,
    pub(super) min_reduced_eigenvalue: f64,
}

/// A Newton run done: its face, its start, and the escape (start, face) it asked for.
type RunDone = (u32, Pose, Option<(Pose, u32)>);

/// What the pull-only check says of a candidate.
pub(super) enum TautMove {
    Accept,
    Drop(usize),
    Add(usize),
}

/// Why a Newton run on one face was not accepted.
pub(super) struct Rejected {
    pub(super) iterations: usize,
    pub(super) residual: f64,
    /// A stationary pose that failed only a zero term's subgradient bound, and the face
    /// without that term, where the minimum lies.
    pub(super) escape: Option<Box<(Pose, u32)>>,
}

/// A certified candidate whose reduced Hessian's smallest eigenvalue exceeds this is a strict
/// local minimum of its section problem (the certificate itself accepts ≥ −1e-8).
pub(super) const STRICT_EIGENVALUE: f64 = 1e-8;

/// Escape runs (see [`Rejected::escape`]) per taut set.
const MAX_ESCAPES: usize = 8;

/// How far an escape start moves a term off its kink \[rad\].
const ESCAPE_ANGLE: f64 = 1e-4;

/// Two starts of one face closer than this (position relative to the section length, rotation
/// entries absolute) are the same run; escapes from one stationary pose reached from several
/// starts differ by rounding (~1e-16). Exact equality only near obstacles, whose candidates
/// converge only to the contact noise.
const SAME_START: f64 = 1e-12;

/// What a section's search has spent and seen so far.
pub(super) struct Tally {
    /// Newton iterations over every start and face.
    pub(super) iterations: usize,
    /// Certified candidates.
    pub(super) count: usize,
    /// Smallest residual of a rejected Newton run.
    pub(super) closest: f64,
    /// Every certified candidate with its taut set, the lowest of a set or not: where no
    /// set's lowest passes the pull-only check, [`Geometric::lowest_pulling`] looks here.
    pub(super) certified: Vec<(Candidate, Vec<usize>)>,
}

impl Tally {
    /// Whether the section's Newton iteration budget ([`SECTION_BUDGET`]) is spent.
    fn exhausted(&self) -> bool {
        self.iterations >= SECTION_BUDGET
    }
}

/// Newton iterations one section may spend over all taut sets, faces and starts: bounds every
/// run (a 16-cable section needs ~2 300). Spent: `NotConverged`, saying so.
pub const SECTION_BUDGET: usize = 20_000;

/// Driven cable constraints in one section up to which, when the active-set path fails, every
/// taut set of at most 5 cables is tried (`Σ C(m, k)`, k ≤ 5: 637 sets at 10). Above it only the
/// active-set path runs, and a failure is `NotConverged` naming this limit.
pub const MAX_ENUMERATED_CABLES: usize = 10;

impl SectionSolution {
    /// This solution as the answer of section `i` that repeats its problem exactly: same pose,
    /// certificate and slack set, no iterations spent.
    pub(super) fn reused_as(&self, i: usize) -> SectionSolution {
        let mut s = self.clone();
        s.report.section = i;
        s.report.iterations = 0;
        s
    }
}

impl Geometric {
    /// Solve section `i`: the lowest certified pose over the taut sets and faces.
    pub(super) fn solve_section(
        &self,
        data: &SectionData,
        i: usize,
        prev: Option<&Pose>,
        warm: Option<&Pose>,
    ) -> Result<SectionSolution, SolveError> {
        if data.cons.is_empty() {
            return unloaded_section(data, i);
        }
        let squared = self.objective == Objective::Squared;
        let mut tally = Tally {
            iterations: 0,
            count: 0,
            closest: f64::INFINITY,
            certified: vec![],
        };
        let mut found = None;
        // The quick search (small nudges, runs given up after 2 short line searches); when it
        // finds nothing, the former search (see `SectionData::former_search`) with a budget
        // of its own: a 16-cable robot that the former search solves failed the quick one.
        // Near obstacles too since contact candidates converge to 1e-11 (`CONTACT_STEP_TOL`):
        // same tips to 8e-13 m on wall and pillar; `geometric-squared` keeps the former one.
        // A section near obstacles where neither certified a pose at 1e-11 is searched once
        // more with the former search at the former contact tolerance (`loose_contacts`).
        let near = data.world.is_some();
        for (former, loose) in [(false, false), (true, false), (true, true)] {
            if loose && (!near || squared) {
                break;
            }
            data.loose_contacts.set(loose);
            data.former_search.set(former || (squared && near));
            let spent = tally.iterations;
            tally.iterations = 0;
            let mut starts = self.starts(data, prev, &mut tally.iterations);
            if let Some(w) = warm {
                starts.insert(0, nudge(w, data));
            }
            found = self.search_taut_sets(data, &starts, squared, &mut tally);
            tally.iterations += spent;
            if found.is_some() || (squared && near) {
                break;
            }
        }
        let Some((best, taut)) = found.or_else(|| self.lowest_pulling(data, &tally)) else {
            return Err(self.section_failure(data, i, &tally));
        };
        let angles = data.term_angles(&best.pose);
        let zero_terms = data
            .terms
            .iter()
            .enumerate()
            .filter(|(t, _)| best.face & (1 << t) != 0 || angles[*t] <= self.zero_angle)
            .map(|(_, t)| t.label.clone())
            .collect();
        let mut slack: Vec<usize> = data.always_slack.clone();
        for j in 0..data.cons.len() {
            if !taut.contains(&j) {
                slack.extend(data.cons[j].cables.iter().copied());
            }
        }
        slack.sort_unstable();
        Ok(SectionSolution {
            strict: best.min_eig > STRICT_EIGENVALUE,
            contacts: best.contacts.clone(),
            pose: best.pose,
            report: SectionReport {
                section: i,
                iterations: tally.iterations,
                residual: best.residual,
                objective: best.objective,
                zero_terms,
                slack: slack.iter().map(|&c| data.names[c].clone()).collect(),
                candidates: tally.count,
            },
            slack,
        })
    }

    /// Cables pull, they do not push: the taut set T must give a certified pose whose taut
    /// multipliers are ≥ 0 and where no other cable's chord exceeds its length. Fast path: a
    /// primal active set from the cables the straight pose violates; if it cycles or fails,
    /// every taut set (small: cables reaching one section), lowest valid.
    fn search_taut_sets(
        &self,
        data: &SectionData,
        starts: &[Pose],
        squared: bool,
        tally: &mut Tally,
    ) -> Option<(Candidate, Vec<usize>)> {
        let straight = Pose::straight(data.l0);
        let max_taut = 5 - usize::from(data.gauge.is_some());
        let mut taut: Vec<usize> = (0..data.cons.len())
            .filter(|&j| data.chord(&straight, j) > data.cons[j].length)
            .collect();
        let mut seen: Vec<Vec<usize>> = vec![];
        while taut.len() <= max_taut && !seen.contains(&taut) && !tally.exhausted() {
            seen.push(taut.clone());
            let Some(best) = self.best_on_taut_set(data, &taut, starts, squared, tally) else {
                break;
            };
            match self.taut_set_move(data, &taut, &best) {
                TautMove::Accept => return Some((best, taut)),
                TautMove::Drop(k) => {
                    taut.remove(k);
                }
                TautMove::Add(j) => {
                    taut.push(j);
                    taut.sort_unstable();
                }
            }
        }
        let mut accepted: Option<(Candidate, Vec<usize>)> = None;
        let m = data.cons.len();
        if m > MAX_ENUMERATED_CABLES {
            return None;
        }
        for mask in 0u32..(1 << m) {
            if tally.exhausted() {
                return None;
            }
            let set: Vec<usize> = (0..m).filter(|j| mask & (1 << j) != 0).collect();
            if set.len() > max_taut || seen.contains(&set) {
                continue;
            }
            let Some(best) = self.best_on_taut_set(data, &set, starts, squared, tally) else {
                continue;
            };
            if matches!(self.taut_set_move(data, &set, &best), TautMove::Accept)
                && accepted
                    .as_ref()
                    .is_none_or(|(a, _)| best.objective < a.objective)
            {
                accepted = Some((best, set));
            }
        }
        accepted
    }

    /// The error when no taut set gave an accepted pose. Infeasibility is only claimed where
    /// it is proved (`feasibility.rs`, before the search); a search that finds nothing is
    /// not a proof, so this is a non-convergence with its iterations and closest residual.
    fn section_failure(&self, data: &SectionData, i: usize, tally: &Tally) -> SolveError {
        let near = data
            .world
            .as_ref()
            .map(|w| format!(", keeping clear of {}", w.names.join(", ")))
            .unwrap_or_default();
        let limit = if tally.exhausted() {
            format!("the section's budget of {SECTION_BUDGET} Newton iterations is spent; ")
        } else if data.cons.len() > MAX_ENUMERATED_CABLES {
            format!(
                "{} driven cables reach this section, more than the {MAX_ENUMERATED_CABLES} whose taut sets are all tried; ",
                data.cons.len()
            )
        } else {
            String::new()
        };
        SolveError::NotConverged {
            method: self.name().into(),
            section: Some(i),
            iterations: tally.iterations,
            residual: tally.closest,
            detail: format!(
                "{limit}no taut set and face of the section problem gave a certified minimum ({} certified candidates were rejected by the pull-only check{near}); the actuation is not proved infeasible",
                tally.count
            ),
        }
    }

    /// Lowest certified candidate over every face with this taut set (the straight pose, the
    /// exact minimum F = 0, when no cable is taut).
    pub(super) fn best_on_taut_set(
        &self,
        data: &SectionData,
        taut: &[usize],
        starts: &[Pose],
        squared: bool,
        tally: &mut Tally,
    ) -> Option<Candidate> {
        let n_terms = data.terms.len();
        // All cables slack: the straight pose, unless an obstacle is in its way — then the
        // angles are minimized against the obstacles alone, like any other taut set (was:
        // give up, so a robot pushed off its minimal bend by an obstacle was "infeasible").
        let straight_blocked = data.world.as_ref().is_some_and(|w| {
            w.pairs(&Pose::straight(data.l0))
                .iter()
                .any(|p| p.dist < w.clearance - CONTACT_TOL)
        });
        if taut.is_empty() && !straight_blocked {
            tally.count += 1;
            return Some(Candidate {
                pose: Pose::straight(data.l0),
                objective: 0.0,
                residual: 0.0,
                cable_lambda: vec![],
                face: (1 << n_terms) - 1,
                contacts: vec![],
                min_eig: f64::INFINITY,
            });
        }
        let fixed = 1 + taut.len() + usize::from(data.gauge.is_some());
        let faces: Vec<u32> = if squared {
            vec![0]
        } else {
            data.faces(fixed, taut)
        };
        let mut runs: Vec<(u32, Pose)> = faces
            .iter()
            .flat_map(|&face| starts.iter().map(move |s| (face, *s)))
            .collect();
        // Faces the one-constraint-at-a-time bound proves infeasible (`bound.rs`): no run on
        // them can converge, so none yields a candidate or an escape; skipping them leaves the
        // answer unchanged. (A finite bound above the best candidate does not let a face be
        // skipped: its runs' escapes reach the face without zeros, which no bound prices.)
        let slack = LENGTH_SLACK.max(1e3 * self.tolerance);
        let infeasible: Vec<u32> = if squared || !skip_enabled() {
            vec![]
        } else {
            faces
                .iter()
                .copied()
                .filter(|&f| data.face_lower_bound(f, taut, slack).is_infinite())
                .collect()
        };
        let mut best: Option<Candidate> = None;
        let mut escapes = 0;
        let mut k = 0;
        let mut done: Vec<RunDone> = vec![];
        let tol = if data.world.is_none() {
            SAME_START
        } else {
            0.0
        };
        while k < runs.len() && !tally.exhausted() {
            let (face, start) = runs[k];
            k += 1;
            if infeasible.contains(&face) {
                continue;
            }
            // A run from the start of an earlier run on the same face repeats it (typically
            // escapes from one stationary pose reached from several starts): its candidate
            // could not replace the earlier one (`best` moves only 1e-12 lower), so only its
            // escape bookkeeping is replayed, which keeps MAX_ESCAPES counting as before.
            if let Some((_, _, again)) = done
                .iter()
                .find(|(f, s, _)| *f == face && s.within(&start, tol * data.l0, tol))
            {
                if let Some((pose, smaller)) = *again {
                    if escapes < MAX_ESCAPES && faces.contains(&smaller) {
                        escapes += 1;
                        runs.push((smaller, pose));
                    }
                }
                continue;
            }
            let outcome = self.newton(data, &start, face, taut, squared);
            done.push((
                face,
                start,
                outcome
                    .as_ref()
                    .err()
                    .and_then(|r| r.escape.as_deref().copied()),
            ));
            match outcome {
                Ok((cand, it)) => {
                    tally.iterations += it;
                    tally.count += 1;
                    tally.certified.push((cand.clone(), taut.to_vec()));
                    if best
                        .as_ref()
                        .is_none_or(|b| cand.objective < b.objective - 1e-12)
                    {
                        best = Some(cand);
                    }
                }
                Err(r) => {
                    tally.iterations += r.iterations;
                    tally.closest = tally.closest.min(r.residual);
                    // A stationary pose whose zero term's multiplier leaves the subgradient
                    // ball: the minimum lies just off that kink, on the face without it.
                    if let Some((pose, smaller)) = r.escape.map(|e| *e) {
                        if escapes < MAX_ESCAPES && faces.contains(&smaller) {
                            escapes += 1;
                            runs.push((smaller, pose));
                        }
                    }
                }
            }
        }
        best
    }

    /// Where every search ended without an accepted pose: the lowest certified candidate of
    /// any taut set that passes the pull-only check, though not the lowest of its set.
    ///
    /// The search judges a taut set by its lowest certified candidate alone. Beside obstacles
    /// a set has several certified minima (the body pressed on either side of an edge, or
    /// clear of it), and the lowest may ask a taut cable to push or stretch a slack one where a
    /// higher one does neither: such a pose is a certified minimum of its face with every
    /// cable pulling, which is what the section's answer must be. Asked only after the
    /// searches fail, so no section they solve changes.
    fn lowest_pulling(&self, data: &SectionData, tally: &Tally) -> Option<(Candidate, Vec<usize>)> {
        tally
            .certified
            .iter()
            .filter(|(c, set)| matches!(self.taut_set_move(data, set, c), TautMove::Accept))
            .min_by(|a, b| a.0.objective.total_cmp(&b.0.objective))
            .cloned()
    }

    /// Pull-only check of a candidate: drop the taut cable that would push most, or add the
    /// slack cable whose chord exceeds its length most, or accept.
    pub(super) fn taut_set_move(
        &self,
        data: &SectionData,
        taut: &[usize],
        best: &Candidate,
    ) -> TautMove {
        let neg = best
            .cable_lambda
            .iter()
            .enumerate()
            .filter(|(_, &l)| l < -1e-9)
            .min_by(|a, b| a.1.total_cmp(b.1));
        if let Some((k, _)) = neg {
            return TautMove::Drop(k);
        }
        let over = (0..data.cons.len())
            .filter(|j| !taut.contains(j))
            .map(|j| (j, data.chord(&best.pose, j) - data.cons[j].length))
            .filter(|&(_, e)| e > 1e-10)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match over {
            Some((j, _)) => TautMove::Add(j),
            None => TautMove::Accept,
        }
    }
}

impl Geometric {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn certify(
        &self,
        data: &SectionData,
        pose: Pose,
        face: u32,
        active: &[usize],
        squared: bool,
        lambda: &[f64],
        (stationarity, stat_tol): (f64, f64),
        min_eig: f64,
        residual: f64,
        it: usize,
        contacts: Vec<Contact>,
    ) -> Result<(Candidate, usize), Rejected> {
        let reject = Err(Rejected {
            iterations: it,
            residual,
            escape: None,
        });
        let escape = |moved: Pose, smaller: u32| {
            Err(Rejected {
                iterations: it,
                residual,
                escape: Some(Box::new((moved, smaller))),
            })
        };
        if stationarity > stat_tol || min_eig < -1e-8 || min_eig.is_nan() {
            return reject;
        }
        let angles = data.term_angles(&pose);
        let mut row = 1 + active.len();
        let mut objective = 0.0;
        let fixed_rotation = data.rotation_fixed(face);
        // The face's equations also hold where its terms are π (at −dir; Q's axial part at any
        // rotation by π), and Newton converges there (a straight cable at its shortest reach:
        // Q ĥ = −ĥ on "coupler zero", its π left out; found by `bound.rs`'s skip test).
        let off_face = (0..data.terms.len())
            .any(|t| face & (1 << t) != 0 && !(fixed_rotation && t > 0) && angles[t] > FRAC_PI_2)
            || (fixed_rotation && pose.q.trace() < 1.0);
        if off_face {
            return reject;
        }
        for (t, term) in data.terms.iter().enumerate() {
            if fixed_rotation && !term.tangent {
                if t == 1 {
                    // The rotation multiplier must split into one subgradient per coupler:
                    // v_t ⊥ ĥ_t with |v_t| ≤ weight_t (the subdifferential of weight·|ω × ĥ|).
                    let target = Vector3::new(lambda[row], lambda[row + 1], lambda[row + 2]);
                    let discs: Vec<_> = data.terms[1..]
                        .iter()
                        .map(|k| (k.e1, k.e2, k.weight))
                        .collect();
                    if disc_sum_scale(&target, &discs).is_none_or(|s| s > 1.0 + 1e-7) {
                        // Off Q = I along the rotation the multiplier asks for.
                        let moved = Pose {
                            p: pose.p,
                            q: pose.q * exp_so3(&(target.normalize() * ESCAPE_ANGLE)),
                        };
                        return escape(moved, face & 1);
                    }
                    row += 3;
                }
            } else if face & (1 << t) != 0 {
                let mu = (lambda[row].powi(2) + lambda[row + 1].powi(2)).sqrt();
                if mu > term.weight * (1.0 + 1e-9) {
                    // Moving this term's direction off the kink along its multiplier lowers
                    // F at first order by (|μ| − weight)·ε: the minimum is on the face
                    // without this term, ESCAPE_ANGLE away is a start for it.
                    let m = (term.e1 * lambda[row] + term.e2 * lambda[row + 1]) / mu;
                    let moved = if term.tangent {
                        let l = pose.p.norm();
                        Pose {
                            p: (pose.p + m * (l * ESCAPE_ANGLE)).normalize() * l,
                            q: pose.q,
                        }
                    } else {
                        let v = pose.q * term.dir;
                        let axis = v.cross(&m);
                        Pose {
                            p: pose.p,
                            q: exp_so3(&(axis.normalize() * ESCAPE_ANGLE)) * pose.q,
                        }
                    };
                    return escape(moved, face & !(1 << t));
                }
                row += 2;
            } else {
                if !squared && angles[t] <= self.zero_angle {
                    return reject;
                }
                objective += term.weight
                    * if squared {
                        angles[t] * angles[t]
                    } else {
                        angles[t]
                    };
            }
        }
        let cable_lambda = (0..active.len()).map(|k| lambda[1 + k]).collect();
        Ok((
            Candidate {
                pose,
                objective,
                residual,
                cable_lambda,
                face,
                contacts,
                min_eig,
            },
            it,
        ))
    }
}

/// A section no driven cable reaches carries no load and continues straight (an error if an
/// obstacle is in the way).
fn unloaded_section(data: &SectionData, i: usize) -> Result<SectionSolution, SolveError> {
    let l0 = data.l0;
    if let Some(w) = &data.world {
        if let Some(pair) = w
            .pairs(&Pose::straight(l0))
            .into_iter()
            .find(|p| p.dist < w.clearance - CONTACT_TOL)
        {
            return Err(SolveError::Obstructed {
                obstacle: w.name(pair.obstacle),
                section: i,
                reason: "a section without driven cables continues straight, and straight runs into this obstacle".into(),
            });
        }
    }
    Ok(SectionSolution {
        strict: true,
        contacts: vec![],
        pose: Pose::straight(l0),
        slack: data.always_slack.clone(),
        report: SectionReport {
            section: i,
            iterations: 0,
            residual: 0.0,
            objective: 0.0,
            zero_terms: data.terms.iter().map(|t| t.label.clone()).collect(),
            slack: data
                .always_slack
                .iter()
                .map(|&c| data.names[c].clone())
                .collect(),
            candidates: 1,
        },
    })
}
