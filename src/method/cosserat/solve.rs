//! The `Method` entry of the rod: the slack active set over length-controlled cables around
//! the shooting solve, and the assembly of the shape from the converged pass.

use super::contact::{RodWorld, Touch};
use super::inextensible::{slack_start, Group};
use super::problem::{LoadCase, Problem, Trace};
use super::shooting::{Fail, Newton, Setup};
use super::warm::Warm;
use super::{Cosserat, RodModel, MAX_CABLES};
use crate::error::SolveError;
use crate::method::warm::WarmState;
use crate::method::{Method, MethodKind, SolveInput};
use crate::model::actuation::Drive;
use crate::numeric::so3::gram_schmidt;
use crate::shape::{CablePath, DiskFrame, Shape, SolveReport};
use nalgebra::{DMatrix, DVector, Vector3};

impl Method for Cosserat {
    fn kind(&self) -> MethodKind {
        match self.model {
            RodModel::Full => MethodKind::Cosserat,
            RodModel::Kirchhoff => MethodKind::Kirchhoff,
        }
    }

    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError> {
        let (robot, act, warm) = (input.robot, input.act, input.warm);
        let name = self.name().to_string();
        let (mut prob, mut notes) = self.problem(robot, act)?;
        // Obstacles within reach: contacts at the disks (`contact.rs`), always by shooting.
        prob.world = RodWorld::new(robot, input.scene)?;
        // A warm shape's contacts start the active set when its reactions are forces (a
        // rod's or the energy model's; the geometric methods' are in rad/m).
        let in_newtons = |w: &Shape| {
            MethodKind::from_name(&w.method).is_some_and(|k| k.info().contact_unit == "N")
        };
        let (mut pushes, push_f, push_m) = match (&prob.world, warm) {
            (Some(world), Some(w)) if in_newtons(w) => world.warm_contacts(&w.contacts),
            _ => (vec![], Vector3::zeros(), Vector3::zeros()),
        };
        if prob.world.is_some() {
            prob.fast = false;
            prob.loaded = false;
        }
        pushes.sort_by_key(|p| (p.touch.disk, p.touch.obstacle));
        let mut active: Vec<Touch> = pushes.iter().map(|p| p.touch).collect();
        let nc = robot.cables.len();
        let length_cables: Vec<usize> = (0..nc)
            .filter(|&c| matches!(prob.modes[c], Drive::Shorten { .. }))
            .collect();
        let mut slack = vec![false; nc];
        let mut warm = Warm::read(warm, self.name(), prob.len_l, &length_cables, &mut slack);
        // Inextensible rod: balanced cable groups prove some shortenings infeasible and need
        // one cable slack (`inextensible.rs`).
        let groups = prob.balanced_groups();
        prob.check_inextensible(&groups)?;
        for g in &groups {
            if g.cables.iter().all(|&c| !slack[c]) {
                slack[slack_start(&prob, g)] = true;
            }
        }
        // Active sets over slack cables and contacts.
        let mut total_it = 0usize;
        let contact_rounds = match prob.world {
            Some(_) => 4 * robot.sections() + 4,
            None => 0,
        };
        let max_rounds = 2 * nc + 3 + contact_rounds;
        let mut prev: Option<(DVector<f64>, Setup)> = None;
        let mut last_res = f64::NAN;
        let mut retried = false;
        for _round in 0..max_rounds {
            // Cold next to obstacles: raise the loads in steps no disk can cross an obstacle
            // in (`approach.rs`); a warm shape is trusted to start clear of them.
            if prob.world.is_some() && prev.is_none() && (input.warm.is_none() || retried) {
                let unknown = length_cables.iter().copied().filter(|&c| !slack[c]);
                let a = prob.approach_start(unknown.collect(), &slack, &name, &mut notes)?;
                total_it += a.iterations;
                active.clone_from(&a.contacts);
                prev = Some((a.x, a.setup));
            }
            let unknown: Vec<usize> = length_cables
                .iter()
                .copied()
                .filter(|&c| !slack[c])
                .collect();
            let setup = Setup {
                unknown,
                slack: slack.clone(),
                contacts: active.clone(),
            };
            let mut x0 = DVector::zeros(setup.first_contact() + setup.contacts.len());
            match &prev {
                Some((xp, ps)) => carry(xp, ps, &setup, &mut x0),
                None => {
                    warm.start(&prob, &setup, &mut x0);
                    warm.with_contacts(&prob, (&push_f, &push_m), &mut x0);
                    let c0 = setup.first_contact();
                    for (i, p) in pushes.iter().enumerate() {
                        x0[c0 + i] = p.force;
                    }
                }
            }
            // A predicted start (new shortenings) gets a fresh exact Jacobian there instead.
            let jac0 = if prev.is_none() && !warm.predicted {
                warm.jac.as_ref()
            } else {
                None
            };
            let cold = input.warm.is_none() && prev.is_none();
            let solved = self.solve_round(&mut prob, &x0, &setup, (jac0, cold), &mut notes);
            // A warm start beside obstacles that Newton cannot take (nor its load steps from
            // zero, with the warm contacts held: they stall at load factor 0) is dropped for
            // the cold start's approach, so a warm start converges wherever a cold one does.
            if solved.is_err() && warm_failed_once(&prob, input.warm, &prev, &mut retried) {
                total_it += solved.err().map_or(0, |e| e.iterations);
                notes.push("warm start did not converge: approached from the straight rod".into());
                continue;
            }
            let (sol, load_steps) = solved.map_err(|e| SolveError::NotConverged {
                method: name.clone(),
                section: None,
                iterations: total_it + e.iterations,
                residual: e.residual,
                detail: match setup.contacts.len() {
                    0 => e.detail,
                    n => format!("{} ({n} contacts active)", e.detail),
                },
            })?;
            if load_steps > 0 {
                notes.push(format!("continuation: {load_steps} load steps"));
            }
            let Newton {
                x,
                iterations: it,
                residual: res,
                jac,
            } = sol;
            total_it += it;
            last_res = res;
            if self.update_active_set(&prob, &x, &setup, &length_cables, &groups, &mut slack)
                || prob.update_contacts(&x, &setup, &mut active)
            {
                prev = Some((x, setup));
                continue;
            }
            let (stable, jac) = self.stability(&prob, &x, &setup, jac, &mut notes);
            let mut shape = self.build_shape(&prob, &x, &setup, total_it, res, notes);
            shape.report.stable = stable;
            if prob.world.is_some() {
                prob.contacts_of(&x, &setup, &mut shape)?;
            }
            let targets = setup.unknown.iter().map(|&c| prob.target(c, 1.0)).collect();
            // (A Jacobian with contact columns would not fit the next solve's start.)
            shape.report.warm =
                jac.filter(|_| setup.contacts.is_empty())
                    .map(|jacobian| WarmState::Rod {
                        jacobian,
                        unknown: setup.unknown.clone(),
                        targets,
                    });
            return Ok(shape);
        }
        let contacts = prob.world.is_some();
        Err(unsettled(name, total_it, last_res, max_rounds, contacts))
    }
}

impl Cosserat {
    /// One active set's solve by the problem's path — unloaded (no shooting), loaded (shooting
    /// on the base moment) or shooting on the strain rates with continuation — falling back to
    /// shooting when a faster path's Newton does not settle (a note says so). `cold`: no warm
    /// shape and no previous active set started it; `jac0`: the warm Jacobian, if any.
    fn solve_round(
        &self,
        prob: &mut Problem<'_>,
        x0: &DVector<f64>,
        setup: &Setup,
        (jac0, cold): (Option<&DMatrix<f64>>, bool),
        notes: &mut Vec<String>,
    ) -> Result<(Newton, usize), Fail> {
        let mut solved = if prob.fast {
            prob.solve_unloaded(x0, setup, notes)
        } else if prob.loaded {
            prob.solve_loaded(x0, setup, (cold, self.check_stability), notes)
        } else {
            prob.solve_with_continuation(x0, setup, jac0)
        };
        // The loaded path's Newton on the base moment did not settle: shoot instead.
        if prob.loaded && solved.is_err() {
            prob.loaded = false;
            notes.push("loaded: the base moment did not settle; shooting instead".into());
            solved = prob.solve_with_continuation(x0, setup, jac0);
        }
        // The unloaded path's Newton on tensions did not settle: shoot instead.
        if prob.fast && solved.is_err() && !setup.unknown.is_empty() {
            prob.shoot_instead();
            notes.push("unloaded: tensions did not settle; shooting instead".into());
            solved = prob.solve_with_continuation(x0, setup, jac0);
        }
        solved
    }

    /// The answer's stability and the Jacobian its warm start carries (module docs of
    /// `unloaded_solve.rs`, "Stability", and `jacobian.rs`): `jac` is Newton's last.
    fn stability(
        &self,
        prob: &Problem,
        x: &DVector<f64>,
        setup: &Setup,
        jac: Option<DMatrix<f64>>,
        notes: &mut Vec<String>,
    ) -> (Option<bool>, Option<DMatrix<f64>>) {
        // The unloaded rod's energy is strictly convex in its strains: stable with no
        // pass (`unloaded_solve.rs`, "Stability"). Elsewhere the focal-point pass, which
        // also gives the exact Jacobian at the answer, a better warm start than Newton's
        // last (Broyden-updated) one. Skipped on request (`stability = skip`): `stable`
        // stays `None`, meaning not checked.
        if !self.check_stability {
            notes.push("stability not checked (stability = skip)".into());
            (None, jac)
        } else if prob.fast && prob.convex_stable(x, setup) {
            notes.push(
                "stable: the unloaded rod's energy is strictly convex in its strains \
                 (no focal-point pass)"
                    .into(),
            );
            (Some(true), jac)
        } else if let Some(stable) = prob.loaded_focal.get().filter(|_| prob.loaded) {
            notes.push(
                "stability: focal-point test on the Jacobi fields the loaded solve's passes \
                 carried (no extra pass)"
                    .into(),
            );
            (Some(stable), jac)
        } else {
            let (stable, exact) = prob.focal_stable(x, setup);
            if stable.is_none() {
                notes.push(prob.undecided_stability(exact.is_some()));
            }
            (stable, exact.or(jac))
        }
    }
}

/// Whether a failed first round of a warm start beside obstacles is retried once from the
/// cold start's approach (`retried` set when so).
fn warm_failed_once(
    prob: &Problem,
    warm: Option<&Shape>,
    prev: &Option<(DVector<f64>, Setup)>,
    retried: &mut bool,
) -> bool {
    let retry = prob.world.is_some() && warm.is_some() && prev.is_none() && !*retried;
    *retried |= retry;
    retry
}

/// The `NotConverged` of active sets that did not settle in `rounds` rounds.
fn unsettled(
    method: String,
    iterations: usize,
    residual: f64,
    rounds: usize,
    contacts: bool,
) -> SolveError {
    SolveError::NotConverged {
        method,
        section: None,
        iterations,
        residual,
        detail: match contacts {
            true => format!(
                "the active sets of slack cables and contacts did not settle in {rounds} rounds"
            ),
            false => "slack active set did not settle".into(),
        },
    }
}

/// The start of the next active-set round from the last one's answer `xp` (set `ps`): its
/// base wrench, and the tensions and contact forces of cables and contacts still unknown.
pub(super) fn carry(xp: &DVector<f64>, ps: &Setup, setup: &Setup, x0: &mut DVector<f64>) {
    for i in 0..6 {
        x0[i] = xp[i];
    }
    for (j, &c) in setup.unknown.iter().enumerate() {
        if let Some(pj) = ps.unknown.iter().position(|&q| q == c) {
            x0[6 + j] = xp[6 + pj].max(0.0);
        }
    }
    let (c0, p0) = (setup.first_contact(), ps.first_contact());
    for (j, t) in setup.contacts.iter().enumerate() {
        if let Some(pj) = ps.contacts.iter().position(|q| q == t) {
            x0[c0 + j] = xp[p0 + pj].max(0.0);
        }
    }
}

impl Cosserat {
    /// Complementarity at a converged `x`: the taut cable with the most negative tension
    /// becomes slack; else every slack cable whose path comes out longer than its length
    /// becomes taut; a balanced group of the inextensible rod that this would make all taut
    /// (`inextensible.rs`) slackens instead its previously taut member of least tension.
    /// True if the set changed.
    fn update_active_set(
        &self,
        prob: &Problem,
        x: &DVector<f64>,
        setup: &Setup,
        length_cables: &[usize],
        groups: &[Group],
        slack: &mut [bool],
    ) -> bool {
        let tau = prob.tensions(x, setup, 1.0);
        let mut changed = false;
        let neg = setup
            .unknown
            .iter()
            .copied()
            .filter(|&c| tau[c] < 0.0)
            .min_by(|&a, &b| tau[a].total_cmp(&tau[b]));
        if let Some(c) = neg {
            slack[c] = true;
            changed = true;
        } else if setup.slack.iter().any(|&b| b) {
            let n0 = Vector3::new(x[0], x[1], x[2]);
            let m0 = Vector3::new(x[3], x[4], x[5]) * prob.len_l;
            let shot = prob.pass(&n0, &m0, &prob.load_case(x, setup, 1.0), None);
            for &c in length_cables {
                let tol_len = 10.0 * self.tolerance / prob.kl[c];
                if setup.slack[c] && shot.len[c] > prob.target(c, 1.0) + tol_len {
                    slack[c] = false;
                    changed = true;
                }
            }
            for g in groups {
                if g.cables.iter().all(|&c| !slack[c]) {
                    let keep = g.cables.iter().copied().filter(|&c| !setup.slack[c]);
                    if let Some(c) = keep.min_by(|&a, &b| tau[a].total_cmp(&tau[b])) {
                        slack[c] = true;
                    }
                }
            }
        }
        changed
    }

    fn build_shape(
        &self,
        prob: &Problem,
        x: &DVector<f64>,
        setup: &Setup,
        iterations: usize,
        residual: f64,
        notes: Vec<String>,
    ) -> Shape {
        let robot = prob.robot;
        let n0 = Vector3::new(x[0], x[1], x[2]);
        let m0 = Vector3::new(x[3], x[4], x[5]) * prob.len_l;
        let tau = prob.tensions(x, setup, 1.0);
        let ld = prob.load_case(x, setup, 1.0);
        // The converged point was the last one integrated (Newton returns right after it):
        // reuse its geometry; integrate again only if it was another point.
        let mut trace = prob.last.take();
        let mut probe = Trace::default();
        probe.start(&n0, &m0, &ld);
        let same = trace.key == probe.key && trace.fast == prob.fast;
        if !same || trace.disks.len() != robot.sections() + 1 {
            prob.pass(&n0, &m0, &ld, Some(&mut probe));
            trace = probe;
        }
        // Undeformed lengths, for the shortenings reported: computed by the solve when a
        // cable was length-driven, by the unloaded or loaded path beside its lengths, else
        // here (one pass at zero load, the same quadrature).
        let computed =
            (0..robot.cables.len()).any(|c| matches!(prob.modes[c], Drive::Shorten { .. }));
        let len0 = if computed {
            prob.len0
        } else if trace.rest.len() == robot.cables.len() {
            let mut len0 = [0.0; MAX_CABLES];
            len0[..trace.rest.len()].copy_from_slice(&trace.rest);
            len0
        } else {
            let zero = LoadCase::new([0.0; MAX_CABLES], 0.0);
            let mut unloaded = Trace::default();
            prob.pass(
                &Vector3::zeros(),
                &Vector3::zeros(),
                &zero,
                Some(&mut unloaded),
            )
            .len
        };
        let disks: Vec<DiskFrame> = trace
            .disks
            .iter()
            .enumerate()
            .map(|(k, (p, r))| DiskFrame {
                s: robot.disk_s[k],
                position: *p,
                rotation: gram_schmidt(r),
            })
            .collect();
        let cables = robot
            .cables
            .iter()
            .enumerate()
            .map(|(c, cable)| {
                let points = (0..=cable.ends_at)
                    .map(|k| disks[k].position + disks[k].rotation * cable.hole(k))
                    .collect();
                let slack =
                    setup.slack[c] || matches!(prob.modes[c], Drive::Tension(t) if t == 0.0);
                CablePath {
                    name: cable.name.clone(),
                    points,
                    slack,
                    // One tension along a frictionless cable: slack everywhere or nowhere.
                    slack_sections: if slack {
                        (1..=cable.ends_at).collect()
                    } else {
                        vec![]
                    },
                    tension: Some(tau[c]),
                    // The displacement under which this shape is the answer: the path change
                    // plus the stretch `τ/k − T₀/k` of a compliant cable.
                    shortening: trace
                        .len
                        .get(c)
                        .map(|l| len0[c] - l + tau[c] * prob.compliance[c] - prob.pre_stretch[c]),
                }
            })
            .collect();
        Shape {
            method: self.name().into(),
            disks,
            backbone: trace.backbone,
            cables,
            contacts: vec![],
            port: None,
            report: SolveReport {
                converged: true,
                iterations,
                residual,
                solve_time_s: 0.0, // filled in by `Method::solve`
                base_wrench: Some([n0.x, n0.y, n0.z, m0.x, m0.y, m0.z]),
                notes,
                ..SolveReport::default()
            },
        }
    }
}
