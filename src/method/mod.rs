//! Shape methods, all behind one trait.
//!
//! | name | file | input | what it is |
//! |---|---|---|---|
//! | `geometric` | [`geometric`] | displacement | the paper's section solver, literal (sum of angles) |
//! | `geometric-squared` | [`geometric`] | displacement | same sections, squared angles (a discrete bending energy) |
//! | `energy` | [`energy`] | displacement | whole robot: constant-strain sub-arcs, elastic energy, total cable lengths |
//! | `cosserat` | [`cosserat`] | tension (or displacement) | Rucker–Webster rod with shear and extension, shooting |
//! | `kirchhoff` | [`cosserat`] | tension (or displacement) | the same rod, inextensible and unshearable |
//! | `constant-curvature` | [`constant_curvature`] | displacement (or tension) | closed-form arc for straight, parallel cables |

pub mod constant_curvature;
pub(crate) mod contact;
pub mod cosserat;
pub mod energy;
pub mod geometric;

use crate::actuation::Actuation;
use crate::error::SolveError;
use crate::robot::Robot;
use crate::scene::Scene;
use crate::shape::Shape;

/// A way to compute a robot's shape.
pub trait Method: Send + Sync {
    /// The name used on the command line and in outputs.
    fn name(&self) -> &str;
    /// Solve for the shape. `warm` is a previous shape of the same robot to start from.
    fn solve(
        &self,
        robot: &Robot,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError>;
}

/// Solve along a path of actuations: every displacement and tension scaled by `k/steps` for
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
    let steps = steps.max(1);
    let mut shape: Option<Shape> = None;
    let mut iterations = 0;
    for k in 1..=steps {
        let a = act.scaled(k as f64 / steps as f64);
        let s = method.solve(robot, &a, scene, shape.as_ref())?;
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

/// Names accepted by [`method_by_name`].
pub const METHOD_NAMES: &[&str] = &[
    "geometric",
    "geometric-squared",
    "cosserat",
    "kirchhoff",
    "energy",
    "constant-curvature",
];

/// Build a method with default settings from its command-line name.
pub fn method_by_name(name: &str) -> Result<Box<dyn Method>, SolveError> {
    match name {
        "geometric" => Ok(Box::new(geometric::Geometric::literal())),
        "geometric-squared" => Ok(Box::new(geometric::Geometric::squared())),
        "energy" => Ok(Box::new(energy::Energy::default())),
        "cosserat" => Ok(Box::new(cosserat::Cosserat::full())),
        "kirchhoff" => Ok(Box::new(cosserat::Cosserat::kirchhoff())),
        "constant-curvature" => Ok(Box::new(
            constant_curvature::ConstantCurvature::displacement(),
        )),
        other => Err(SolveError::InvalidInput {
            field: "method".into(),
            reason: format!(
                "unknown method `{other}`; known: {}",
                METHOD_NAMES.join(", ")
            ),
        }),
    }
}
