//! [`Solver`]: a [`SolveRequest`](super::run::SolveRequest) checked and its method built, the
//! one way every front end (the command line, Python, batches, studies, reach and plan, the
//! hardware predictions and the calibration) turns robot + actuation + scene into a shape.
//!
//! Every shape a solver returns has passed the same two gates: before any work, what the
//! method does not model is refused by name ([`MethodKind::check_support`], in
//! [`Method::solve`]); after it, the output boundary ([`crate::check::output`]: every number
//! finite, the robot not through itself). A failed gate is an error, never a shape.

use super::estimate::ErrorEstimate;
use super::{solve_stepped_prepared, Method, MethodKind, Prepared, Settings, SolveInput};
use crate::error::SolveError;
use crate::model::actuation::Actuation;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;

/// A checked request with its method built: solves any robot, each shape through the output
/// check. Made by [`SolveRequest::solver`](super::run::SolveRequest::solver).
///
/// ```
/// use ccrkit::prelude::*;
///
/// let model = Model::from_file("models/paper/case1.toml")?;
/// let solver = SolveRequest::new(MethodKind::DEFAULT).solver()?;
/// // Half the file's actuation, then the whole of it started from the half.
/// let half = solver.solve(&model.robot, &model.actuation.scaled(0.5), &model.scene, None)?;
/// let full = solver.solve(&model.robot, &model.actuation, &model.scene, Some(&half))?;
/// assert!(full.tip().z < half.tip().z);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Solver {
    method: Box<dyn Method>,
    steps: usize,
    settings: Settings,
}

impl Solver {
    /// `method` solving a cold start in `steps` continuation steps (≥ 1; checked by the
    /// request that builds it).
    pub(crate) fn new(method: Box<dyn Method>, steps: usize) -> Self {
        Solver {
            method,
            steps: steps.max(1),
            settings: Settings::new(),
        }
    }

    /// The settings the method was built with (what [`Solver::estimate`] reads its
    /// resolution from).
    pub(crate) fn with_settings(mut self, settings: Settings) -> Self {
        self.settings = settings;
        self
    }

    /// The settings the method was built with.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// How far `shape` (this solver's answer for `robot`, `act`, `scene`) is from the
    /// converged reference rod: the discretization part read from the answer (`energy`) or
    /// measured by an extra solve at the companion resolution, and the model's left-out
    /// strains ([`crate::method::estimate`]).
    pub fn estimate(
        &self,
        robot: &Robot,
        act: &Actuation,
        scene: &Scene,
        shape: &Shape,
    ) -> Result<ErrorEstimate, SolveError> {
        super::estimate::estimate(&super::estimate::Answer {
            kind: self.kind(),
            settings: &self.settings,
            robot,
            act,
            scene,
            shape,
        })
    }

    /// The method.
    pub fn kind(&self) -> MethodKind {
        self.method.kind()
    }

    /// The method's name.
    pub fn name(&self) -> &str {
        self.method.name()
    }

    /// The shape of `robot` under `act` in `scene`, started from `warm` (a previous shape of
    /// the same robot, any method's) or, without one, from the straight robot in the
    /// request's continuation steps. Checked at the output boundary (module docs).
    pub fn solve(
        &self,
        robot: &Robot,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        let shape = self.solve_unchecked(SolveInput {
            robot,
            act,
            scene,
            warm,
        })?;
        crate::check::output(robot, &shape)?;
        Ok(shape)
    }

    /// [`Solver::solve`] without the output check: for timing loops that check the shape they
    /// keep once ([`crate::check::output`]), never for a shape handed to anyone.
    pub(crate) fn solve_unchecked(&self, input: SolveInput<'_>) -> Result<Shape, SolveError> {
        let SolveInput {
            robot,
            act,
            scene,
            warm,
        } = input;
        match warm {
            Some(w) => self.method.solve(robot, act, scene, Some(w)),
            None if self.steps > 1 => {
                solve_stepped_prepared(&*self.method.prepare(robot)?, act, scene, self.steps)
            }
            None => self.method.solve(robot, act, scene, None),
        }
    }

    /// This solver readied for `robot`: what depends on the robot and the settings alone is
    /// computed once ([`Method::prepare`]), for many solves of the same robot.
    pub fn prepare<'a>(&'a self, robot: &'a Robot) -> Result<PreparedSolver<'a>, SolveError> {
        Ok(PreparedSolver {
            prepared: self.method.prepare(robot)?,
            robot,
            steps: self.steps,
        })
    }
}

impl std::fmt::Debug for Solver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solver")
            .field("method", &self.kind())
            .field("steps", &self.steps)
            .finish()
    }
}

/// A [`Solver`] readied for one robot ([`Solver::prepare`]): solves that robot for any
/// actuation and scene, each shape through the output check.
pub struct PreparedSolver<'a> {
    prepared: Box<dyn Prepared + 'a>,
    robot: &'a Robot,
    steps: usize,
}

impl PreparedSolver<'_> {
    /// The robot it was readied for.
    pub fn robot(&self) -> &Robot {
        self.robot
    }

    /// As [`Solver::solve`], for the prepared robot.
    pub fn solve(
        &self,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        let shape = self.solve_unchecked(act, scene, warm)?;
        crate::check::output(self.robot, &shape)?;
        Ok(shape)
    }

    /// [`PreparedSolver::solve`] without the output check (see [`Solver::solve_unchecked`]).
    pub(crate) fn solve_unchecked(
        &self,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        match warm {
            Some(w) => self.prepared.solve(act, scene, Some(w)),
            None => solve_stepped_prepared(&*self.prepared, act, scene, self.steps),
        }
    }
}
