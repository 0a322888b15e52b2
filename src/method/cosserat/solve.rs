//! The `Method` entry of the rod: the slack active set over length-controlled cables around
//! the shooting solve, and the assembly of the shape from the converged pass.

use super::inextensible::{slack_start, Group};
use super::problem::{LoadCase, Problem, Trace};
use super::shooting::{Newton, Setup};
use super::warm::Warm;
use super::{Cosserat, RodModel, MAX_CABLES};
use crate::error::SolveError;
use crate::method::warm::WarmState;
use crate::method::{Method, MethodKind, SolveInput};
use crate::model::actuation::Drive;
use crate::numeric::so3::gram_schmidt;
use crate::shape::{CablePath, DiskFrame, Shape, SolveReport};
use nalgebra::{DVector, Vector3};

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
        let (prob, mut notes) = self.problem(robot, act)?;
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
        // Active set over slack cables.
        let mut total_it = 0usize;
        let max_rounds = 2 * nc + 3;
        let mut prev: Option<(DVector<f64>, Setup)> = None;
        for _round in 0..max_rounds {
            let unknown: Vec<usize> = length_cables
                .iter()
                .copied()
                .filter(|&c| !slack[c])
                .collect();
            let setup = Setup {
                unknown,
                slack: slack.clone(),
            };
            let mut x0 = DVector::zeros(6 + setup.unknown.len());
            match &prev {
                // Carry the base wrench and the tensions of cables still unknown.
                Some((xp, ps)) => {
                    for i in 0..6 {
                        x0[i] = xp[i];
                    }
                    for (j, &c) in setup.unknown.iter().enumerate() {
                        if let Some(pj) = ps.unknown.iter().position(|&q| q == c) {
                            x0[6 + j] = xp[6 + pj].max(0.0);
                        }
                    }
                }
                None => warm.start(&prob, &setup, &mut x0),
            }
            // A predicted start (new shortenings) gets a fresh exact Jacobian there instead.
            let jac0 = if prev.is_none() && !warm.predicted {
                warm.jac.as_ref()
            } else {
                None
            };
            let solved = match prob.fast {
                true => prob.solve_unloaded(&mut notes),
                false => prob.solve_with_continuation(&x0, &setup, jac0),
            };
            let (sol, load_steps) = solved.map_err(|e| SolveError::NotConverged {
                method: name.clone(),
                section: None,
                iterations: total_it + e.iterations,
                residual: e.residual,
                detail: e.detail,
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
            if !self.update_active_set(&prob, &x, &setup, &length_cables, &groups, &mut slack) {
                // The focal-point pass also gives the exact Jacobian at the answer, a better
                // warm start than Newton's last (Broyden-updated) one. Skipped on request
                // (`stability = skip`): `stable` stays `None`, meaning not checked.
                let (stable, jac) = if self.check_stability {
                    let (stable, exact) = prob.focal_stable(&x, &setup);
                    if stable.is_none() {
                        notes.push(prob.undecided_stability(exact.is_some()));
                    }
                    (stable, exact.or(jac))
                } else {
                    notes.push("stability not checked (stability = skip)".into());
                    (None, jac)
                };
                let mut shape = self.build_shape(&prob, &x, &setup, total_it, res, notes);
                shape.report.stable = stable;
                let targets = setup.unknown.iter().map(|&c| prob.target(c, 1.0)).collect();
                shape.report.warm = jac.map(|jacobian| WarmState::Rod {
                    jacobian,
                    unknown: setup.unknown.clone(),
                    targets,
                });
                return Ok(shape);
            }
            prev = Some((x, setup));
        }
        Err(SolveError::NotConverged {
            method: name,
            section: None,
            iterations: total_it,
            residual: f64::NAN,
            detail: "slack active set did not settle".into(),
        })
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
            let shot = prob.pass(&n0, &m0, &LoadCase { tau, lam: 1.0 }, None);
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
        let ld = LoadCase { tau, lam: 1.0 };
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
        // cable was length-driven, else here (one unloaded pass, the same quadrature).
        let computed =
            (0..robot.cables.len()).any(|c| matches!(prob.modes[c], Drive::Shorten { .. }));
        let len0 = if computed {
            prob.len0
        } else {
            let zero = LoadCase {
                tau: [0.0; MAX_CABLES],
                lam: 0.0,
            };
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
