//! The way in to the obstacles: the given loads raised from zero in steps that cannot carry a
//! disk through an obstacle, contacts joining as the disks meet the scene (module docs of
//! `contact.rs`, "Approach").
//!
//! A cold start at full load lands wherever the free rod goes, which may be through a thin wall
//! (the paper's case I free rod puts disk 8 beyond the wall scene's 10 mm box) or through an
//! open mesh, where no query can tell the side any more. So the loads are scaled by a factor
//! `λ_s` raised from 0 (the straight rod) to 1, and a step from shape A to shape B is taken only
//! if every disk not in contact moved at most its distance at A plus [`STEP_DEPTH`]: no disk
//! can then pass an obstacle, and one that enters does so by at most `STEP_DEPTH`, where the
//! signed distance is still that of the side it came from (the shared query's shifted GJK
//! answers up to `SEPARATION_SHIFT`, 1 mm). A disk's move is bounded by
//! `|Δp| + r_disk |ΔR|_F` (as `energy/contacts.rs`). At each accepted factor the contact active
//! set is settled (drop a pulling contact, add the deepest entering disk) before the next step.
//! The same guard as the energy model's step guard, applied to load steps instead of Newton
//! steps.

use super::contact::Touch;
use super::problem::{Problem, Trace};
use super::shooting::{Fail, Setup};
use crate::error::SolveError;
use nalgebra::{DVector, Matrix3, Vector3};

/// The deepest a disk may enter an obstacle in one load step \[m\] (module docs).
pub(super) const STEP_DEPTH: f64 = 5e-4;

/// Smallest load step before the approach gives up.
const MIN_STEP: f64 = 1.0 / 4096.0;

/// The disks' frames of a pass.
type Frames = Vec<(Vector3<f64>, Matrix3<f64>)>;

/// Where the approach ended: the unknowns and the active contacts at full load, the load steps
/// and Newton iterations it took.
pub(super) struct Approach {
    pub(super) x: DVector<f64>,
    /// The unknowns' layout at `x`.
    pub(super) setup: Setup,
    pub(super) contacts: Vec<Touch>,
    pub(super) steps: usize,
    pub(super) iterations: usize,
}

impl Problem<'_> {
    /// Raise the loads from zero to full (module docs) for the cables `unknown` (taut,
    /// length-controlled) and `slack`, settling the contacts at each step.
    pub(super) fn approach(&self, unknown: &[usize], slack: &[bool]) -> Result<Approach, Fail> {
        let setup_of = |contacts: &[Touch]| Setup {
            unknown: unknown.to_vec(),
            slack: slack.to_vec(),
            contacts: contacts.to_vec(),
        };
        let mut x = DVector::zeros(6 + unknown.len());
        let mut active: Vec<Touch> = vec![];
        let mut at = self.frames(&x, &setup_of(&active), 0.0);
        let (mut lam, mut dl) = (0.0f64, 1.0f64);
        let (mut steps, mut iterations) = (0usize, 0usize);
        let mut last = Fail {
            iterations: 0,
            residual: f64::NAN,
            detail: String::new(),
        };
        while lam < 1.0 {
            if dl < MIN_STEP || self.over_budget() {
                last.iterations = iterations;
                last.detail = format!(
                    "approach to the obstacles stalled at load factor {lam:.4} ({})",
                    last.detail
                );
                return Err(last);
            }
            let l1 = (lam + dl).min(1.0);
            match self.settle_at(l1, &x, &active, &at, &setup_of) {
                Ok((xn, an, frames, it)) => {
                    iterations += it;
                    steps += 1;
                    (x, active, at, lam) = (xn, an, frames, l1);
                    dl = (2.0 * dl).min(1.0);
                }
                Err(e) => {
                    iterations += e.iterations;
                    last = e;
                    dl *= 0.5;
                }
            }
        }
        Ok(Approach {
            x,
            setup: setup_of(&active),
            contacts: active,
            steps,
            iterations,
        })
    }

    /// [`Problem::approach`] as the start of the solve: its failure the named
    /// `NotConverged` of method `name`, a note in `notes`.
    pub(super) fn approach_start(
        &self,
        unknown: Vec<usize>,
        slack: &[bool],
        name: &str,
        notes: &mut Vec<String>,
    ) -> Result<Approach, SolveError> {
        // A straight start with a disk deep in an obstacle is named, not stalled on.
        let straight = Setup {
            unknown: unknown.clone(),
            slack: slack.to_vec(),
            contacts: vec![],
        };
        let at = self.frames(&DVector::zeros(6 + unknown.len()), &straight, 0.0);
        if let Some(err) = self.world.as_ref().and_then(|w| w.start_inside(&at)) {
            return Err(err);
        }
        let a = self
            .approach(&unknown, slack)
            .map_err(|e| SolveError::NotConverged {
                method: name.to_string(),
                section: None,
                iterations: e.iterations,
                residual: e.residual,
                detail: e.detail,
            })?;
        notes.push(format!(
            "approach to the obstacles: {} load steps, {} contacts",
            a.steps,
            a.contacts.len()
        ));
        Ok(a)
    }

    /// The contacts settled at load factor `lam` from the accepted state `(x, active)` with
    /// disk frames `at`: the unknowns, the active set, the frames and the iterations, or a
    /// failure (Newton did not converge, or a disk moved farther than the guard allows).
    fn settle_at(
        &self,
        lam: f64,
        x: &DVector<f64>,
        active: &[Touch],
        at: &Frames,
        setup_of: &dyn Fn(&[Touch]) -> Setup,
    ) -> Result<(DVector<f64>, Vec<Touch>, Frames, usize), Fail> {
        let Some(world) = self.world.as_ref() else {
            return Err(Fail {
                iterations: 0,
                residual: f64::NAN,
                detail: "no obstacles to approach".into(),
            });
        };
        let mut active = active.to_vec();
        let mut x = x.clone();
        let mut iterations = 0;
        let mut prev = setup_of(&active);
        let rounds = 4 * self.robot.sections() + 4;
        for _ in 0..rounds {
            let setup = setup_of(&active);
            let mut x0 = DVector::zeros(setup.first_contact() + setup.contacts.len());
            super::solve::carry(&x, &prev, &setup, &mut x0);
            let sol = self.newton(&x0, &setup, lam, None).map_err(|mut e| {
                e.iterations += iterations;
                e
            })?;
            iterations += sol.iterations;
            let frames = self.frames(&sol.x, &setup, lam);
            if let Some(k) = world.guard(at, &frames, &active) {
                return Err(Fail {
                    iterations,
                    residual: sol.residual,
                    detail: format!("disk {k} would move through an obstacle"),
                });
            }
            let mut next = active.clone();
            if !self.update_contacts_at(&sol.x, &setup, &mut next, lam) {
                return Ok((sol.x, active, frames, iterations));
            }
            (x, prev, active) = (sol.x, setup, next);
        }
        Err(Fail {
            iterations,
            residual: f64::NAN,
            detail: "contact active set did not settle".into(),
        })
    }

    /// The disk frames of the pass at `x`.
    fn frames(&self, x: &DVector<f64>, setup: &Setup, lam: f64) -> Frames {
        let (n0, m0) = self.base_wrench(x);
        let mut trace = Trace::default();
        self.pass(&n0, &m0, &self.load_case(x, setup, lam), Some(&mut trace));
        trace.disks
    }
}
