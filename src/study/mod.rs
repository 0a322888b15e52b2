//! Studies: speed against accuracy, stability maps over an actuation plane, and workspace
//! sweeps at scale (sharded, mergeable). The engine behind `ccrkit study` and the examples.
//!
//! * [`speed_accuracy`]: every registered method ([`MethodKind::ALL`]) at each of its resolution
//!   settings ([`MethodInfo::resolutions`](crate::method::MethodInfo)) — median solve time over a few repeats and the error against a converged
//!   Cosserat reference driven by the same kind of input: [`reference()`] (full rod, 80 RK4 steps
//!   per section, force control with the file's tensions) for force-driven methods, and
//!   [`reference_displacement`] (the same rod driven by the file's cable displacements, lengths
//!   along the routed path) for displacement-driven ones — the paper's cases give both inputs,
//!   and they do not describe the same shape, so each model is judged on its own input.
//!   `auto` adds one row per tolerance ([`AUTO_TOLERANCES`]): its choice, timed with its whole
//!   search, judged against the rod driven by the input it chose; the chart marks them.
//! * [`stability`]: a grid over the inputs of two cables, each method solved cold and with
//!   continuation along the rows (warm start from the previous grid point of the row);
//!   every point is `ok` or a named failure ([`Status`]; a shape with a non-finite number or
//!   through itself is refused at the output check, as everywhere).
//! * [`workspace`]: low-discrepancy (Halton) samples of the cables' inputs, solved in parallel
//!   in fixed chunks (warm-started from the nearest solved sample of the chunk), shardable with
//!   [`Shard`]; [`merge_csv`] joins shards into the CSV of the unsharded run, byte for byte.
//!
//! All outputs are SI: shortening as a fraction of the cable's length, tension in N,
//! positions in m, times in s.
//!
//!
//! Measured numbers live in the user's guide (`docs/guide/`, with the commands that regenerate
//! them), not here.

mod auto;
pub mod compare;
#[cfg(feature = "plot")]
pub mod figures;
pub mod random;
mod speed_accuracy;
mod stability;
mod workspace;

pub use crate::error::Status;
pub use crate::model::actuation::Input;
pub use auto::{
    auto_study, auto_study_csv, summarize, AutoStudyOptions, AutoStudyRow, AutoSummary,
};
pub use compare::{compare, Comparison, ComparisonRow};
pub use speed_accuracy::*;
pub use stability::*;
pub use workspace::*;

use crate::error::SolveError;
use crate::method::cosserat::Cosserat;
use crate::method::run::SolveRequest;
use crate::method::{MethodKind, Settings, Solver};
use crate::shape::Shape;

/// A study failure (a solve that the study cannot do without, a file, a figure).
/// Non-exhaustive: the `plot` feature adds `StudyError::Plot`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StudyError {
    /// A solve the study needs (the reference) failed.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// Reading or writing a file.
    #[error("`{path}`: {reason}")]
    Io {
        /// Path.
        path: String,
        /// Why.
        reason: String,
    },
    /// A figure could not be drawn.
    #[cfg(feature = "plot")]
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    /// A CSV that cannot be merged, or bad study options.
    #[error("{0}")]
    Invalid(String),
}

/// Write a text file atomically ([`crate::output`]), naming the path on failure.
pub fn write_text(path: &std::path::Path, text: &str) -> Result<(), StudyError> {
    Ok(crate::output::write_file(path, text.as_bytes())?)
}

/// The registered methods named in study options (an unknown name is an error).
pub fn method_kinds(names: &[String]) -> Result<Vec<MethodKind>, StudyError> {
    names
        .iter()
        .map(|n| n.parse::<MethodKind>().map_err(StudyError::from))
        .collect()
}

/// Every registered method's name (the default method list of the studies).
pub fn all_method_names() -> Vec<String> {
    MethodKind::ALL
        .iter()
        .map(|k| k.name().to_string())
        .collect()
}

/// The input a method reads naturally (its default `control`): tension for the rods,
/// shortening for the others.
pub fn natural_input(method: MethodKind) -> Input {
    method.info().default_input
}

/// A method in its default settings, driven by `input` where it accepts both inputs: the
/// [`Solver`] of that request, so every study solve passes the output check.
pub fn study_method(method: MethodKind, input: Input) -> Result<Solver, SolveError> {
    SolveRequest::new(method)
        .with_settings(method.driven_by(input))
        .solver()
}

/// The converged reference of the speed–accuracy study: full Cosserat rod, 80 RK4 steps per
/// section, force control, shooting tolerance 1e-11 N.
pub fn reference() -> Cosserat {
    Cosserat {
        tolerance: 1e-11,
        ..Cosserat::full().with_steps(80).with_control(Input::Tension)
    }
}

/// The converged reference for displacement-driven methods: the same rod as [`reference()`]
/// driven by the model's cable displacements (lengths along the routed path).
pub fn reference_displacement() -> Cosserat {
    Cosserat {
        tolerance: 1e-11,
        ..Cosserat::full()
            .with_steps(80)
            .with_control(Input::Shortening)
    }
}

/// Outcome of one solve in a study.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// How it ended.
    pub status: Status,
    /// Iterations (of the shape, or of a `NotConverged` error; 0 otherwise).
    pub iterations: usize,
    /// Residual (of the shape, or of a `NotConverged` error; NaN when unknown).
    pub residual: f64,
    /// The shape, when `ok`.
    pub shape: Option<Shape>,
}

/// Classify a solve result. A study's solves go through a [`Solver`], so a shape here has
/// passed the output check; a shape from anywhere else with a non-finite number is still
/// the failure that check makes of it ([`crate::check::finite`]), never `ok`.
pub fn outcome(r: Result<Shape, SolveError>) -> Outcome {
    let r = r.and_then(|s| crate::check::finite(&s).map(|()| s));
    let status = Status::of(&r);
    match r {
        Ok(s) => Outcome {
            status,
            iterations: s.report.iterations,
            residual: s.report.residual,
            shape: Some(s),
        },
        Err(e) => {
            let (iterations, residual) = e.iterations_residual();
            Outcome {
                status,
                iterations,
                residual,
                shape: None,
            }
        }
    }
}

/// A number for CSV: shortest round-trip form, empty when not finite.
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        String::new()
    }
}

/// Settings of a registered method's resolution entry.
fn resolution_settings(pairs: &[(&str, &str)]) -> Settings {
    let mut s = Settings::new();
    for (k, v) in pairs {
        s.push(*k, *v);
    }
    s
}
