//! Every count a user can set — command-line flags, model fields, Python arguments, method
//! settings — with its limit, in one table ([`COUNTS`]), so that no count runs unbounded: an
//! absurd value (`reach --starts 1000000000` once ran past two minutes) is refused by name
//! before any work. The user's guide prints the same table (`docs/guide/errors.md`; a test
//! holds the two equal).
//!
//! Counts checked elsewhere (model fields at parse time, `steps` and `repeat` in
//! [`crate::method::run::SolveRequest::solver`], batch rows and chunks in [`crate::batch`]) keep
//! their own constants; the table names those constants, so it cannot drift from them.

use crate::error::SolveError;

/// One user-settable count and its accepted range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Count {
    /// The field as errors name it (the option's name in the library and in Python).
    pub field: &'static str,
    /// Where a user sets it (command-line flag, model field or setting).
    pub set_by: &'static str,
    /// Least accepted value.
    pub min: usize,
    /// Largest accepted value.
    pub max: usize,
}

impl Count {
    /// `v` if it is in `min..=max`, else `InvalidInput` naming the field, the range and `v`.
    pub fn check(&self, v: usize) -> Result<usize, SolveError> {
        if (self.min..=self.max).contains(&v) {
            return Ok(v);
        }
        Err(SolveError::InvalidInput {
            field: self.field.into(),
            reason: format!(
                "must be a whole number from {} to {} ({}), got {v}",
                self.min, self.max, self.set_by
            ),
        })
    }
}

const fn count(field: &'static str, set_by: &'static str, min: usize, max: usize) -> Count {
    Count {
        field,
        set_by,
        min,
        max,
    }
}

/// Starts of the least-effort search (10 000 starts took 16 s on FTDCR v4).
pub const REACH_STARTS: Count = count("starts", "reach --starts", 1, 1000);
/// Gauss–Newton iterations per start of the least-effort search.
pub const REACH_ITERATIONS: Count = count(
    "max_iterations",
    "reach, ReachOptions.max_iterations",
    1,
    10_000,
);
/// Uniform samples of a roadmap.
pub const ROADMAP_SAMPLES: Count = count("samples", "roadmap build --samples", 1, 100_000);
/// Expansion samples of a roadmap.
pub const ROADMAP_EXPAND: Count = count("expand", "roadmap build --expand", 0, 100_000);
/// Neighbours each roadmap node tries.
pub const ROADMAP_NEIGHBOURS: Count = count("neighbours", "roadmap build --neighbours", 1, 256);
/// Shards of one roadmap build (`k/N`: N), in a build's options and in a shard file read back
/// (a merge keeps one flag per shard).
pub const ROADMAP_SHARDS: Count = count("shard", "roadmap build --shard k/N", 1, 10_000);
/// Samples of the planner before it gives up.
pub const PLAN_SAMPLES: Count = count("max_samples", "plan --max-samples", 1, 1_000_000);
/// Shortcut edge checks of the planner.
pub const PLAN_SHORTCUTS: Count = count("shortcuts", "PlanOptions.shortcuts", 0, 100_000);
/// Levenberg–Marquardt iterations of a calibration.
pub const FIT_ITERATIONS: Count = count("max_iterations", "calibrate --max-iterations", 1, 10_000);
/// Rows solved in sequence per parallel chunk of `predict`.
pub const PREDICT_CHUNK: Count = count("chunk", "predict --chunk", 1, crate::batch::MAX_CHUNK);
/// Solves per setting of the speed–accuracy study.
pub const STUDY_REPEATS: Count = count("repeats", "study speed-accuracy --repeats", 1, 1000);
/// Random robots of the `auto` study (each one a converged reference and every rung solved).
pub const STUDY_AUTO_ROBOTS: Count = count("robots", "study auto --robots", 1, 100_000);
/// Timed runs per solve of the `auto` study.
pub const STUDY_AUTO_REPEATS: Count = count("repeats", "study auto --repeats", 1, 1000);
/// Grid points per axis of the stability study (the sweep solves 4 grid² points per method).
pub const STUDY_GRID: Count = count("grid", "study stability --grid", 2, 500);
/// Samples of the workspace study.
pub const STUDY_SAMPLES: Count = count("samples", "study workspace --samples", 1, 10_000_000);
/// Samples per block of the workspace study.
pub const STUDY_CHUNK: Count = count(
    "chunk",
    "study workspace --chunk",
    1,
    crate::batch::MAX_CHUNK,
);

/// Every count a user can set, with its range: the ones above and those checked where they
/// are read (their constants named here).
pub const COUNTS: &[Count] = &[
    count(
        "robot.sections",
        "model file",
        1,
        crate::model::MAX_SECTIONS,
    ),
    count("cables", "model file", 1, crate::model::bounds::MAX_CABLES),
    count("steps", "solve --steps", 1, crate::method::run::MAX_STEPS),
    count(
        "repeat",
        "solve --repeat",
        1,
        crate::method::run::MAX_REPEAT,
    ),
    count(
        "max-iterations",
        "--set max-iterations=N",
        1,
        crate::method::settings::MAX_ITERATIONS,
    ),
    count("rows", "Python solve_batch", 0, crate::batch::MAX_ROWS),
    count(
        "chunk",
        "Python solve_batch chunk",
        1,
        crate::batch::MAX_CHUNK,
    ),
    count(
        "threads",
        "Python solve_batch threads",
        1,
        crate::batch::MAX_THREADS,
    ),
    count(
        "data rows",
        "predict / calibrate --data",
        1,
        crate::calibrate::data::MAX_ROWS,
    ),
    REACH_STARTS,
    REACH_ITERATIONS,
    ROADMAP_SAMPLES,
    ROADMAP_EXPAND,
    ROADMAP_NEIGHBOURS,
    ROADMAP_SHARDS,
    PLAN_SAMPLES,
    PLAN_SHORTCUTS,
    FIT_ITERATIONS,
    PREDICT_CHUNK,
    STUDY_REPEATS,
    STUDY_AUTO_ROBOTS,
    STUDY_AUTO_REPEATS,
    STUDY_GRID,
    STUDY_SAMPLES,
    STUDY_CHUNK,
];
