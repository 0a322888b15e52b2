//! The paper's geometric section solver (Mahapatra & Ghosal), generalized to N cables.
//!
//! # The literal method (`geometric`)
//!
//! The robot is solved one section at a time, base to tip (paper §2, steps 1–4, read as in
//! the user's guide, `docs/guide/paper.md`). Section `i` lies between disks `i−1` and `i`.
//! Everything is written in the frame of the **solved** disk `i−1` (origin at its backbone
//! point, z along its normal, x at hole angle 0). In that frame the unknown is the rigid pose
//! of disk `i`:
//! backbone point `p` and rotation `Q`, so hole `c` of disk `i` sits at `p + Q h_c(i)` with
//! `h_c(k) = r_c(k) (cos φ_c(k), sin φ_c(k), 0)`. A rigid disk keeps `|x_c − x_0| = r` and the
//! angle θ between holes (the last three constraints of eq. 2) by construction, and the paper's
//! frame `T` (steps 1–3, with `sign(θ)`) is the same rigid frame, so crossed-over cables need no
//! special case.
//!
//! The "undeformed" disk `i` (step 4) is disk `i` in its undeformed pose relative to disk
//! `i−1`: `p = l0 ẑ`, `Q = I`. Eq. 1, one coupler angle per displacement-driven cable plus the
//! tangent angle, is then
//!
//! ```text
//! F(p, Q) = Σ_c ang(h_c(i), Q h_c(i)) + ang(ẑ, p),    ang(a, b) = atan2(|a × b|, a · b)
//! ```
//!
//! subject to (eq. 2) `|p| = l0` and, for each cable, `|p + Q h_c(i) − h_c(i−1)| ≤ l_c^i` where
//! `l_c^i = (1 − Δ_c) |H_c(i) − H_c(i−1)|` is a uniform fraction of the cable's **undeformed
//! straight chord** between its two holes (reading 1 of the guide). The paper writes the cable
//! constraint as an equality; cables pull but cannot push, so ccrkit treats it as `≤`: a cable
//! whose chord comes out shorter than its length is reported slack.
//!
//! ## The kink
//!
//! Each angle is a cone at 0 (like a norm), and at the optimum one or more angles are exactly
//! zero. A smooth NLP solver stalls there. This solver enumerates **faces**: for each set `Z`
//! of terms that may vanish, it minimizes the other terms with the zero terms as equalities
//! `w_t = 0` (`w_t`: the two components of the solved direction orthogonal to the undeformed one,
//! so `|w_t| = sin ang_t`), by Newton–KKT with exact second derivatives (`numeric::ad`)
//! from several starts. A candidate is **certified** when it is feasible, stationary, has a
//! positive semi-definite reduced Hessian, every zero term's multiplier lies inside that term's
//! subgradient ball (`|μ_t| ≤ weight_t`), every other term is non-zero, and every taut cable's
//! multiplier is ≥ 0 (it pulls). The lowest certified candidate is returned, and the report
//! says which terms are zero in each section.
//!
//! ## Degenerate hole patterns
//!
//! When all driven holes of a disk are collinear with its centre (one cable, two cables with
//! coinciding holes as in case III at disks 7–9, or two opposite holes), the rotation of the disk
//! about that line changes neither the objective nor a constraint. It is fixed as reading 7 of the
//! guide says: the disk normal is the incoming backbone chord made orthogonal to the hole
//! direction. Cables sharing a hole on both disks of a section share one segment constraint with
//! the tighter length; the other is slack there. Sections past every driven cable's end carry no
//! load and continue straight.
//!
//! ## Stability (`report.stable`)
//!
//! The paper's method has no energy, so "stable" is read from the certificate: every section's
//! pose is a certified local minimum of its own problem (feasible, stationary, subgradient and
//! pull-only conditions, reduced Hessian positive semi-definite). When, in every section, the
//! reduced Hessian is positive definite (smallest eigenvalue above `1e-8`, or nothing free at a
//! vertex) each pose is a strict local minimum — a small disturbance of any disk is undone by
//! re-solving — and `stable` is `true`. A singular reduced Hessian somewhere leaves it unknown
//! (`None`); `false` never occurs, since saddles are rejected by the certificate.
//!
//! # The squared variant (`geometric-squared`)
//!
//! Same sections and constraints, objective `Σ ang²` — a discrete bending energy, smooth, so one
//! face suffices. Not the paper's method; offered as a named option.

//!
//! # Files
//!
//! `mod.rs` the settings and the section loop (base to tip) · `problem.rs` the eq. 1–2 section
//! problem and its derivatives · `derivatives.rs` their closed forms · `faces.rs` the taut-set and face search and the certificate · `bound.rs` a lower bound on a face's objective (faces it proves infeasible are skipped) ·
//! `degenerate.rs` faces where an unshortened cable's row is redundant · `feasibility.rs` proofs that no pose exists · `newton.rs` Newton–KKT on one face · `contact_curvature.rs` the second derivative of a contact distance · `starts.rs` the starting poses · `obstacles.rs` the obstacles one section sees.

mod bound;
mod contact_curvature;
mod degenerate;
mod derivatives;
mod faces;
mod feasibility;
mod newton;
mod obstacles;
mod problem;
mod starts;

use crate::contact::broad;
use crate::error::SolveError;
use crate::method::output::{cable_paths, chord_shortening};
use crate::method::settings::Configure;
use crate::method::{Method, MethodKind, SolveInput};
use crate::model::actuation::{Drive, Input};
use crate::numeric::so3::orthonormalize;
use crate::shape::{DiskFrame, Shape, SolveReport};
use faces::SectionSolution;
pub use faces::{MAX_ENUMERATED_CABLES, SECTION_BUDGET};
use nalgebra::{Matrix3, Vector3};
use obstacles::SectionWorld;
use problem::{Pose, SectionData};

/// Which objective the sections minimize.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Objective {
    /// The paper's: sum of the coupler angles and the tangent angle (eq. 1).
    Literal,
    /// Sum of squared angles (a discrete bending energy).
    Squared,
}

/// Settings of the geometric section solver.
#[derive(Debug, Clone)]
pub struct Geometric {
    /// Objective.
    pub objective: Objective,
    /// Newton iterations per candidate.
    pub max_iterations: usize,
    /// Constraint residual a candidate must reach \[m\].
    pub tolerance: f64,
    /// An angle at or below this is "zero" (on a kink) \[rad\].
    pub zero_angle: f64,
}

impl Geometric {
    /// The paper's literal method.
    pub fn literal() -> Self {
        Geometric {
            objective: Objective::Literal,
            max_iterations: 40,
            tolerance: 1e-12,
            zero_angle: 1e-7,
        }
    }
    /// The squared-angle variant.
    pub fn squared() -> Self {
        Geometric {
            objective: Objective::Squared,
            ..Self::literal()
        }
    }
}

impl Configure for Geometric {
    fn set(&mut self, name: &str, value: &str) -> Result<(), SolveError> {
        let range = self.kind().setting(name)?.values;
        match name {
            "max-iterations" => self.max_iterations = range.count(name, value)?,
            "tolerance" => self.tolerance = range.real(name, value)?,
            "zero-angle" => self.zero_angle = range.real(name, value)?,
            _ => return Err(self.kind().unapplied(name)),
        }
        Ok(())
    }

    fn check(&self) -> Result<(), SolveError> {
        let range = |name| self.kind().setting(name).map(|s| s.values);
        range("max-iterations")?.check_count("max-iterations", self.max_iterations)?;
        range("tolerance")?.check_real("tolerance", self.tolerance)?;
        range("zero-angle")?.check_real("zero-angle", self.zero_angle)?;
        Ok(())
    }
}

impl Method for Geometric {
    fn kind(&self) -> MethodKind {
        match self.objective {
            Objective::Literal => MethodKind::Geometric,
            Objective::Squared => MethodKind::GeometricSquared,
        }
    }

    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError> {
        let (robot, act, scene, warm) = (input.robot, input.act, input.scene, input.warm);
        let n = robot.sections();
        let mut notes = vec![
            "cable segment length after actuation = (1 - shortening) x undeformed straight chord between holes".to_string(),
        ];
        // Displacement fraction per cable (None: free).
        let drives = self.kind().drives(robot, act, Input::Shortening)?;
        let frac: Vec<Option<f64>> = drives
            .iter()
            .map(|d| match d {
                Drive::Shorten { fraction, .. } => Some(*fraction),
                _ => None,
            })
            .collect();

        let mut rot = Matrix3::identity();
        let mut pos = Vector3::zeros();
        let mut disks = vec![DiskFrame {
            s: 0.0,
            position: pos,
            rotation: rot,
        }];
        let mut sections = Vec::with_capacity(n);
        let mut slack_sections: Vec<Vec<usize>> = vec![vec![]; robot.cables.len()];
        let mut prev_rel: Option<Pose> = None;
        let (mut total_it, mut worst) = (0usize, 0.0f64);
        let relevant = broad::robot_obstacles(robot, scene)?;
        let warm_rel = warm.filter(|w| w.disks.len() == n + 1).map(relative_poses);
        let mut contacts = vec![];
        let mut strict = true;
        // The search is deterministic: a section whose problem and start (the previous
        // section's relative pose) equal the last solved section's, bit for bit, has the same
        // certified answer. Uniform robots with straight cables repeat from the third section on.
        let mut repeat: Option<(SectionData, Option<Pose>, SectionSolution)> = None;
        let mut reused = vec![];
        for i in 1..=n {
            let mut data = SectionData::new(robot, &frac, i)?;
            data.world = SectionWorld::new(robot, scene, &relevant, i, &rot, &pos);
            data.gram_schmidt = relevant.is_empty() || self.objective == Objective::Literal;
            let warm_i = warm_rel.as_ref().map(|w| w[i - 1]);
            let sol = match repeat
                .as_ref()
                .filter(|(d, p, _)| warm_i.is_none() && *p == prev_rel && d.same_problem(&data))
            {
                Some((_, _, s)) => {
                    reused.push(i);
                    s.reused_as(i)
                }
                None => {
                    let s = self.solve_section(&data, i, prev_rel.as_ref(), warm_i.as_ref())?;
                    repeat = Some((data, prev_rel, s.clone()));
                    s
                }
            };
            contacts.extend(sol.contacts.iter().cloned());
            strict &= sol.strict;
            total_it += sol.report.iterations;
            worst = worst.max(sol.report.residual);
            for &c in &sol.slack {
                slack_sections[c].push(i);
            }
            pos += rot * sol.pose.p;
            rot = orthonormalize(&(rot * sol.pose.q));
            disks.push(DiskFrame {
                s: robot.disk_s[i],
                position: pos,
                rotation: rot,
            });
            prev_rel = Some(sol.pose);
            sections.push(sol.report);
        }
        if !reused.is_empty() {
            notes.push(format!(
                "sections {reused:?} pose exactly the problem of the section before them, from the same start: its certified pose is reused (0 iterations)"
            ));
        }
        let mut cables = cable_paths(robot, &disks, &slack_sections);
        for (c, path) in cables.iter_mut().enumerate() {
            path.shortening = Some(chord_shortening(robot, c, &path.points));
        }
        let backbone = disks.iter().map(|d| d.position).collect();
        Ok(Shape {
            method: self.name().into(),
            disks,
            backbone,
            cables,
            contacts,
            port: None,
            report: SolveReport {
                converged: true,
                iterations: total_it,
                residual: worst,
                solve_time_s: 0.0, // filled in by `Method::solve`
                sections,
                base_wrench: None,
                notes,
                stable: strict.then_some(true),
                jacobian: None,
                error_estimate: None,
                auto: None,
                unique: None,
                warm: None,
            },
        })
    }
}

/// Relative poses (disk i in the frame of disk i−1) of a solved shape, as warm starts.
fn relative_poses(shape: &Shape) -> Vec<Pose> {
    shape
        .disks
        .windows(2)
        .map(|w| Pose {
            p: w[0].rotation.transpose() * (w[1].position - w[0].position),
            q: w[0].rotation.transpose() * w[1].rotation,
        })
        .collect()
}
