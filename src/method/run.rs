//! The one way in: robot + actuation + scene + method + settings → shape. Every front end —
//! the command line, Python, batches, studies, reach and plan, hardware predictions and the
//! calibration, the examples — states what to solve as a [`SolveRequest`] and solves it
//! either whole ([`SolveRequest::run`] on a [`Model`]: its robot, actuation and obstacles) or
//! through the request's [`Solver`] ([`SolveRequest::solver`]: any robot, actuation and
//! scene, many times). Either way a scene, a setting, a warm start or a step count means the
//! same thing everywhere, and every shape handed out has passed the output check
//! ([`crate::check::output`]: finite, not through itself).
//!
//! ```
//! use ccrkit::prelude::*;
//!
//! let model = Model::from_file("models/paper/case1.toml")?;
//! let request = SolveRequest::new(MethodKind::DEFAULT)
//!     .with_settings(Settings::new().with("sub-arcs", 6));
//! let solved = request.run(&model)?;
//! println!("tip {:?} m in {:.1} ms", solved.shape.tip(), solved.median_time_s * 1e3);
//!
//! // The same request on other actuations of the robot: one solver, warm starts.
//! let solver = request.solver()?;
//! let half = solver.solve(&model.robot, &model.actuation.scaled(0.5), &model.scene, None)?;
//! assert!(half.report.converged);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::{Method, MethodKind, Settings, Solver};
use crate::error::SolveError;
use crate::model::actuation::Drive;
use crate::model::scene::Scene;
use crate::model::Model;
use crate::shape::{CableDriveJson, DrivenBy, Shape, ShapeJson};
use std::time::Instant;

/// Most repeated solves one request may ask for (timing medians).
pub const MAX_REPEAT: usize = 100_000;
/// Most continuation steps one request may ask for.
pub const MAX_STEPS: usize = 10_000;

/// What to solve: a method with its settings, the obstacles added to the model's own, an
/// optional start from another method's shape, continuation steps and timing repeats.
#[derive(Debug, Clone)]
pub struct SolveRequest {
    /// The method.
    pub method: MethodKind,
    /// Its settings (refused by name when it does not take one).
    pub settings: Settings,
    /// Obstacles added to the model's scene.
    pub extra_scene: Option<Scene>,
    /// Start from the shape this method finds (solved with the settings it takes).
    pub warm_from: Option<MethodKind>,
    /// Reach the actuation in this many warm-started steps (≥ 1).
    pub steps: usize,
    /// Solve this many times and report the median time (≥ 1).
    pub repeat: usize,
    /// Estimate each answer's distance from the converged reference rod
    /// ([`crate::method::estimate`]: `energy` a priori, else one extra solve), into `report.error_estimate`.
    pub estimate: bool,
    /// `auto` with this tolerance \[m\]: the cheapest model and resolution whose estimated
    /// error is within it ([`crate::method::auto`]); `method` is then not used.
    pub auto: Option<f64>,
    /// Check whether the answer is the only equilibrium found along other paths and from the
    /// other model's answer ([`crate::method::unique`]: a few extra solves), into
    /// `report.unique`.
    pub check_unique: bool,
}

/// A solved request.
#[derive(Debug, Clone)]
pub struct Solved {
    /// The shape; `report.solve_time_s` is the median over the repeats.
    pub shape: Shape,
    /// The obstacles it was solved with (the model's and the request's).
    pub scene: Scene,
    /// Median wall time of one solve \[s\] (the warm-start solve excluded).
    pub median_time_s: f64,
    /// Obstacles within reach that exactly duplicate another and were merged (the contact
    /// broad phase queries one of each group).
    pub merged_duplicates: usize,
}

impl SolveRequest {
    /// One solve of `method` with its defaults.
    pub fn new(method: MethodKind) -> Self {
        SolveRequest {
            method,
            settings: Settings::new(),
            extra_scene: None,
            warm_from: None,
            steps: 1,
            repeat: 1,
            estimate: false,
            auto: None,
            check_unique: false,
        }
    }

    /// `auto`: the cheapest model and resolution whose estimated tip distance from the
    /// converged rod is within `tolerance` \[m\] for the robot, input and scene solved
    /// ([`crate::method::auto`]).
    pub fn auto(tolerance: f64) -> Self {
        SolveRequest {
            auto: Some(tolerance),
            ..SolveRequest::new(MethodKind::DEFAULT)
        }
    }

    /// This request settled for `model`: an `auto` request becomes the request of the method
    /// and resolution it chooses for the model's own actuation and scene (for the commands
    /// that solve many actuations at one choice: reach, plan, predict, batches); any other is
    /// itself.
    pub fn resolved(&self, model: &Model) -> Result<SolveRequest, SolveError> {
        let Some(t) = self.auto else {
            return Ok(self.clone());
        };
        let scene = self.scene_for(model);
        let shape = super::auto::choose(&model.robot, &model.actuation, &scene, t, &self.settings)?;
        let settled = super::auto::settled(&shape, &self.settings).ok_or_else(|| {
            SolveError::InvalidInput {
                field: "method".into(),
                reason: "auto's choice is not on the registry's ladder (a bug in ccrkit)".into(),
            }
        })?;
        Ok(SolveRequest {
            method: settled.method,
            settings: settled.settings,
            auto: None,
            ..self.clone()
        })
    }

    /// Builder: estimate each answer's error ([`SolveRequest::estimate`]).
    pub fn with_estimate(mut self, on: bool) -> Self {
        self.estimate = on;
        self
    }

    /// Builder: check whether the answer is the only equilibrium found
    /// ([`SolveRequest::check_unique`]).
    pub fn with_unique_check(mut self, on: bool) -> Self {
        self.check_unique = on;
        self
    }

    /// Builder: settings.
    pub fn with_settings(mut self, settings: Settings) -> Self {
        self.settings = settings;
        self
    }

    /// Builder: obstacles added to the model's scene.
    pub fn with_scene(mut self, scene: Option<Scene>) -> Self {
        self.extra_scene = scene;
        self
    }

    /// The scene of a solve of `model`: its own obstacles and the request's.
    pub fn scene_for(&self, model: &Model) -> Scene {
        let mut sc = model.scene.clone();
        if let Some(extra) = &self.extra_scene {
            sc.merge(extra.clone());
        }
        sc
    }

    /// Check everything that can be checked before solving — bounds of `steps` and `repeat`,
    /// the combination of options, and the settings (each taken by the method, or refused) —
    /// and build the method: the [`Solver`] every solve of this request goes through.
    pub fn solver(&self) -> Result<Solver, SolveError> {
        if self.auto.is_some() {
            return Err(SolveError::InvalidInput {
                field: "method".into(),
                reason: "auto chooses for one robot, input and scene: solve with `run`, or \
                         settle the choice first (`SolveRequest::resolved`)"
                    .into(),
            });
        }
        if !(1..=MAX_STEPS).contains(&self.steps) {
            return Err(SolveError::InvalidInput {
                field: "steps".into(),
                reason: format!("must be from 1 to {MAX_STEPS}, got {}", self.steps),
            });
        }
        if !(1..=MAX_REPEAT).contains(&self.repeat) {
            return Err(SolveError::InvalidInput {
                field: "repeat".into(),
                reason: format!("must be from 1 to {MAX_REPEAT}, got {}", self.repeat),
            });
        }
        if let (Some(w), true) = (self.warm_from, self.steps > 1) {
            return Err(SolveError::InvalidInput {
                field: "warm_from".into(),
                reason: format!(
                    "--warm-from {w} and --steps {} cannot be combined",
                    self.steps
                ),
            });
        }
        Ok(Solver::new(self.method.build(&self.settings)?, self.steps)
            .with_settings(self.settings.clone()))
    }

    /// The warm-start method: `warm_from` with those of the request's settings it takes.
    fn warm_method(&self, kind: MethodKind) -> Result<Box<dyn Method>, SolveError> {
        let mut s = Settings::new();
        for (k, v) in self.settings.iter() {
            if kind.check_setting(k).is_ok() {
                s.push(k, v);
            }
        }
        kind.build(&s)
    }

    /// The JSON of `shape` solved by this request on `model`, with the model's name and the
    /// input that drove the solve (the method's `control`, its settings, each cable's drive).
    pub fn json(&self, model: &Model, shape: &Shape) -> ShapeJson {
        let method = MethodKind::from_name(&shape.method).unwrap_or(self.method);
        let control = method.input_with(&self.settings);
        let drives = method
            .drives(&model.robot, &model.actuation, control)
            .unwrap_or_default();
        let cables = model
            .robot
            .cables
            .iter()
            .zip(drives.iter().map(Some).chain(std::iter::repeat(None)))
            .map(|(c, d)| {
                let (drive, shorten_m, tension_n) = match d {
                    Some(Drive::Shorten { length, .. }) => ("shorten", Some(*length), None),
                    Some(Drive::Tension(t)) => ("tension", None, Some(*t)),
                    _ => ("free", None, None),
                };
                CableDriveJson {
                    name: c.name.clone(),
                    drive: drive.into(),
                    shorten_m,
                    tension_n,
                }
            })
            .collect();
        let mut j = shape.to_json();
        j.model = Some(model.robot.name.clone());
        j.input = Some(DrivenBy {
            control: control.name().into(),
            settings: self
                .settings
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
            cables,
            insertion: shape.port.as_ref().map(|p| p.insertion),
            rotation: shape.port.as_ref().map(|p| p.rotation),
        });
        j
    }

    /// Solve `model` (its robot, actuation and obstacles, and the request's obstacles): the
    /// shape (checked at the output boundary), the scene it was solved in, the median time.
    pub fn run(&self, model: &Model) -> Result<Solved, SolveError> {
        if let Some(t) = self.auto {
            if self.check_unique {
                return Err(SolveError::InvalidInput {
                    field: "check_unique".into(),
                    reason: "auto chooses among methods: check the method it chose \
                             (`SolveRequest::resolved`, then `check_unique`)"
                        .into(),
                });
            }
            return self.run_auto(model, t);
        }
        let solver = self.solver()?;
        let scene = self.scene_for(model);
        let warm = match self.warm_from {
            Some(kind) => {
                Some(
                    self.warm_method(kind)?
                        .solve(&model.robot, &model.actuation, &scene, None)?,
                )
            }
            None => None,
        };
        // Readied for the robot once; every repeat pays its share of that time.
        let t = Instant::now();
        let prepared = solver.prepare(&model.robot)?;
        let setup = t.elapsed().as_secs_f64() / self.repeat as f64;
        // Checked once below, outside the timed repeats.
        let (times, last) = timed(self.repeat, || {
            prepared.solve_unchecked(&model.actuation, &scene, warm.as_ref())
        });
        let mut shape = last?;
        let median_time_s = times[times.len() / 2] + setup;
        shape.report.solve_time_s = median_time_s;
        // Exact duplicates within reach were merged by the broad phase: say so.
        let merged_duplicates = if scene.obstacles.len() > 1 {
            crate::contact::broad::within_reach(&model.robot, &scene).1
        } else {
            0
        };
        if merged_duplicates > 0 {
            shape.report.notes.push(format!(
                "{merged_duplicates} obstacles within reach are exact duplicates of another \
                 and were merged (a contact names the first of each group)"
            ));
        }
        // The output boundary: no non-finite number, no robot passing through itself.
        crate::check::output(&model.robot, &shape)?;
        if self.estimate {
            shape.report.error_estimate =
                Some(solver.estimate(&model.robot, &model.actuation, &scene, &shape)?);
        }
        if self.check_unique {
            shape.report.unique = Some(super::unique::check(self, model, &scene, &shape)?);
        }
        Ok(Solved {
            shape,
            scene,
            median_time_s,
            merged_duplicates,
        })
    }
}

impl SolveRequest {
    /// [`SolveRequest::run`] of an `auto` request: the choice and every solve it took, timed
    /// as one (the median of `repeat` runs).
    fn run_auto(&self, model: &Model, tolerance: f64) -> Result<Solved, SolveError> {
        let scene = self.scene_for(model);
        let (times, last) = timed(self.repeat.clamp(1, MAX_REPEAT), || {
            super::auto::choose(
                &model.robot,
                &model.actuation,
                &scene,
                tolerance,
                &self.settings,
            )
        });
        let mut shape = last?;
        let median_time_s = times[times.len() / 2];
        // `choose` hands out its answer through the output check already.
        shape.report.solve_time_s = median_time_s;
        Ok(Solved {
            shape,
            scene,
            median_time_s,
            merged_duplicates: 0,
        })
    }
}

/// Run `solve` `repeats` times (at least once), stopping at the first failure: the wall times
/// of the runs, sorted (never empty), and the last answer.
pub(crate) fn timed<T>(
    repeats: usize,
    solve: impl Fn() -> Result<T, SolveError>,
) -> (Vec<f64>, Result<T, SolveError>) {
    let mut times = Vec::with_capacity(repeats.max(1));
    loop {
        let t = Instant::now();
        let r = solve();
        times.push(t.elapsed().as_secs_f64());
        if r.is_err() || times.len() >= repeats.max(1) {
            times.sort_by(f64::total_cmp);
            return (times, r);
        }
    }
}
