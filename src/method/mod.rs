//! Shape methods, all behind one trait, and the one registry of them ([`MethodKind`]).
//!
//! | name | module | input | what it is |
//! |---|---|---|---|
//! | `geometric` | [`geometric`] | shortening | the paper's section solver, literal (sum of angles) |
//! | `geometric-squared` | [`geometric`] | shortening | same sections, squared angles (a discrete bending energy) |
//! | `energy` | [`energy`] | shortening (or tension) | whole robot: constant-strain sub-arcs, elastic energy, total cable lengths |
//! | `cosserat` | [`cosserat`] | tension (or shortening) | Rucker–Webster rod with shear and extension, shooting |
//! | `kirchhoff` | [`cosserat`] | tension (or shortening) | the same rod, inextensible and unshearable |
//! | `constant-curvature` | [`constant_curvature`] | shortening (or tension) | closed-form arc for straight, parallel cables |
//!
//! Everything the rest of ccrkit (command line, studies, Python, reach and plan) needs to know
//! about a method — its name, the inputs it takes, whether it handles obstacles and loads, its
//! settings and their resolution ladder — is read from [`MethodKind::info`]; a method is built
//! from its kind and [`Settings`] by [`MethodKind::build`]. Adding a method is one module plus
//! one arm in each `match` of this file (see `CONTRIBUTING.md`).

pub mod auto;
pub mod constant_curvature;
pub mod cosserat;
pub mod energy;
pub mod estimate;
pub mod geometric;
pub mod output;
mod port;
mod registry;
pub mod run;
pub mod settings;
pub mod solver;
pub mod unique;
pub mod warm;

use crate::error::SolveError;
use crate::model::actuation::Actuation;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;
use std::time::Instant;

pub use registry::{LoadSupport, MethodInfo, MethodKind};
pub use settings::{Configure, SettingInfo, Settings};
pub use solver::{PreparedSolver, Solver};
pub use warm::WarmState;

/// A way to compute a robot's shape: the trait a **method implementor** writes
/// (`CONTRIBUTING.md`, "Adding a method").
///
/// Users do not call it: they solve through [`SolveRequest`](run::SolveRequest) and its
/// [`Solver`], which build the method from the registry, validate every setting and pass
/// every shape through the output check ([`crate::check::output`]). A method implements
/// [`Method::solve_supported`], its own work, and inherits the contract every solve keeps
/// (the registry's support check and the timing, in [`Method::solve`]).
pub trait Method: Configure + Send + Sync {
    /// Which registered method this is.
    fn kind(&self) -> MethodKind;
    /// The name used on the command line and in outputs.
    fn name(&self) -> &str {
        self.kind().name()
    }
    /// Solve for the shape. `warm` is a previous shape of the same robot to start from (any
    /// method's: its disk frames; the same method's also carries [`WarmState`]). What the
    /// method does not model is refused by name before any work
    /// ([`MethodKind::check_support`]), and `report.solve_time_s` is the time of this call.
    /// The robot and the settings are checked first ([`Robot::check`],
    /// [`Configure::check`]), however they were built. No output check: that is the
    /// [`Solver`]'s.
    fn solve(
        &self,
        robot: &Robot,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        self.check()?;
        robot.check()?;
        let input = SolveInput {
            robot,
            act,
            scene,
            warm,
        };
        checked_and_timed(self.kind(), input, |i| self.solve_supported(i))
    }
    /// The method's own work behind [`Method::solve`], which has already refused what the
    /// method does not model ([`MethodKind::check_support`]) and fills in
    /// `report.solve_time_s`. Call [`Method::solve`], not this.
    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError>;

    /// This method readied for `robot`: what depends on the robot and the settings alone
    /// (e.g. the energy model's routing samples) is computed once, so repeated solves of the
    /// same robot ([`SolveRequest`](run::SolveRequest) repeats, continuation steps) skip it.
    /// A robot with a port is readied per solve for the robot beyond the port (which changes
    /// with the insertion, `method/port.rs`); otherwise this is [`Method::prepare_fixed`].
    /// Methods implement [`Method::prepare_fixed`], not this. The robot and the settings
    /// are checked here, once for every solve of the prepared method (as in [`Method::solve`]).
    fn prepare<'a>(&'a self, robot: &'a Robot) -> Result<Box<dyn Prepared + 'a>, SolveError> {
        self.check()?;
        robot.check()?;
        if robot.port.is_some() {
            return Ok(Box::new(port::PortPrepared {
                method: self,
                robot,
            }));
        }
        self.prepare_fixed(robot)
    }

    /// The method's own readying for a robot without a port (see [`Method::prepare`]). The
    /// default readies nothing.
    fn prepare_fixed<'a>(&'a self, robot: &'a Robot) -> Result<Box<dyn Prepared + 'a>, SolveError> {
        Ok(Box::new(Unprepared {
            method: self,
            robot,
        }))
    }
}

/// What one solve is asked: a robot under an actuation in a scene, and optionally a previous
/// shape of the same robot to start from (see [`Method::solve`]).
#[derive(Clone, Copy)]
pub struct SolveInput<'a> {
    /// The robot.
    pub robot: &'a Robot,
    /// Its actuation.
    pub act: &'a Actuation,
    /// The obstacles.
    pub scene: &'a Scene,
    /// A previous shape to start from.
    pub warm: Option<&'a Shape>,
}

/// A method readied for one robot ([`Method::prepare`]): solves that robot for any
/// actuation and scene, as [`Method::solve`] does and under the same contract (for method
/// implementors; users hold a [`PreparedSolver`]).
pub trait Prepared: Send + Sync {
    /// Which registered method this is.
    fn kind(&self) -> MethodKind;
    /// The robot it was readied for.
    fn robot(&self) -> &Robot;
    /// Solve the prepared robot (same contract as [`Method::solve`]).
    fn solve(
        &self,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        let input = SolveInput {
            robot: self.robot(),
            act,
            scene,
            warm,
        };
        checked_and_timed(self.kind(), input, |i| self.solve_supported(i))
    }
    /// The prepared method's own work behind [`Prepared::solve`] (as
    /// [`Method::solve_supported`]; `input.robot` is [`Prepared::robot`]). Call
    /// [`Prepared::solve`], not this.
    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError>;
}

/// The contract of every solve, written once for [`Method::solve`] and [`Prepared::solve`]:
/// an obstacle, load or cable property that `kind` does not model is refused by name before
/// any work ([`MethodKind::check_support`]: never silently left out of a shape); a robot with
/// a port is solved beyond its port and placed in the scene (`method/port.rs`), a robot
/// without one refuses an insertion or a rotation by name; and the shape's
/// `report.solve_time_s` is the wall time of the whole call, `solve` included.
fn checked_and_timed(
    kind: MethodKind,
    input: SolveInput<'_>,
    solve: impl FnOnce(SolveInput<'_>) -> Result<Shape, SolveError>,
) -> Result<Shape, SolveError> {
    let start = Instant::now();
    let mut shape = match &input.robot.port {
        Some(p) => port::solve_through(kind, p, input, solve)?,
        None => {
            input.act.port_command(input.robot)?;
            kind.check_support(input.robot, input.scene)?;
            solve(input)?
        }
    };
    shape.report.solve_time_s = start.elapsed().as_secs_f64();
    Ok(shape)
}

/// [`Method::prepare`] of a method with nothing to prepare.
struct Unprepared<'a, M: ?Sized> {
    method: &'a M,
    robot: &'a Robot,
}

impl<M: Method + ?Sized> Prepared for Unprepared<'_, M> {
    fn kind(&self) -> MethodKind {
        self.method.kind()
    }
    fn robot(&self) -> &Robot {
        self.robot
    }
    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError> {
        self.method.solve_supported(input)
    }
}

/// For method implementors and their tests (users set [`SolveRequest::steps`](run::SolveRequest::steps)):
/// solve along a path of actuations, every displacement and tension scaled by `k/steps` for
/// `k = 1..=steps`, each solve warm-started from the previous shape (the 2-D obstacle work of
/// Ashwin et al. 2021 steps the cable displacement ~1 mm at a time). `steps = 1` is one solve.
/// The report of the returned shape sums the iterations of every step.
pub fn solve_stepped(
    method: &dyn Method,
    robot: &Robot,
    act: &Actuation,
    scene: &Scene,
    steps: usize,
) -> Result<Shape, SolveError> {
    solve_stepped_prepared(&*method.prepare(robot)?, act, scene, steps)
}

/// [`solve_stepped`] on a method already [prepared](Method::prepare) for the robot.
pub fn solve_stepped_prepared(
    method: &dyn Prepared,
    act: &Actuation,
    scene: &Scene,
    steps: usize,
) -> Result<Shape, SolveError> {
    let steps = steps.max(1);
    let mut shape: Option<Shape> = None;
    let mut iterations = 0;
    for k in 1..=steps {
        let a = act.scaled(k as f64 / steps as f64);
        let s = method.solve(&a, scene, shape.as_ref())?;
        iterations += s.report.iterations;
        shape = Some(s);
    }
    let mut s = shape.ok_or_else(|| SolveError::InvalidInput {
        field: "steps".into(),
        reason: "no step was solved".into(),
    })?;
    s.report.iterations = iterations;
    Ok(s)
}

/// Names of every registered method, in registry order.
pub const METHOD_NAMES: &[&str] = &registry::NAMES;

/// Build a method with default settings from its command-line name: the implementor-level
/// [`Method`], without the output check (users: `SolveRequest::new(name.parse()?)`).
pub fn method_by_name(name: &str) -> Result<Box<dyn Method>, SolveError> {
    name.parse::<MethodKind>()?.build(&Settings::new())
}
