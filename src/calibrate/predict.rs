//! Batch prediction: solve every row of a [`Dataset`] in-process, in order, each row
//! warm-started from the previous one, chunks of rows in parallel (rayon), and report the
//! marker in the measurement frame ([`crate::model::hardware::Hardware::measured_tip`]). Each
//! cable's direction of motion (for the backlash) is taken from the rows in file order,
//! before they are cut into chunks ([`crate::model::hardware::directions`]).
//!
//! The rows run on the one block loop of [`crate::batch`] (Python's `solve_batch` runs on it
//! too). Chunks are cut at fixed row counts ([`PredictOptions::chunk`]), not per thread, so the
//! result does not depend on the number of threads: the first row of a chunk starts cold (from
//! the straight robot), every other row from the previous row's shape. A warm-started solve
//! that fails is retried cold once; a row that still fails gets its error as status, and the
//! next row starts from the last shape that solved.

use super::data::Dataset;
use crate::batch::{Blocks, RowFailure, Solved};
use crate::error::{SolveError, Status};
use crate::method::run::SolveRequest;
use crate::method::{MethodKind, Solver};
use crate::model::hardware::directions;
use crate::model::scene::Scene;
use crate::model::Model;
use crate::progress::ProgressHandle;
use crate::shape::Shape;
use nalgebra::Vector3;

/// Default rows per chunk.
pub const DEFAULT_CHUNK: usize = 64;

/// How to predict.
#[derive(Debug, Clone)]
pub struct PredictOptions {
    /// Method and settings (and extra obstacles). `steps`, `warm_from` and `repeat` other than
    /// their defaults are refused by name: every row starts from the previous one.
    pub request: SolveRequest,
    /// Rows per chunk solved in sequence (≥ 1).
    pub chunk: usize,
    /// Where progress goes (one step per row predicted).
    pub progress: ProgressHandle,
}

/// One predicted row.
#[derive(Debug, Clone)]
pub struct RowPrediction {
    /// Marker in the measurement frame \[m\] (`Err` when the row did not solve).
    pub tip: Result<Vector3<f64>, SolveError>,
    /// Solver iterations spent on the row (both attempts when a warm start failed; a failed
    /// attempt counts when its error says).
    pub iterations: usize,
}

impl RowPrediction {
    /// How the row ended (`ok`, `not_converged`, `infeasible`, ...).
    pub fn status(&self) -> Status {
        Status::of(&self.tip)
    }
}

/// What [`Rows::solve_all`] makes of row `i`: its shape or error, and its iterations.
pub(crate) type RowMap<'a, T> = dyn Fn(usize, Result<&Shape, &SolveError>, usize) -> T + Sync + 'a;

/// A method ready to solve rows of one model.
pub(crate) struct Rows {
    pub(crate) solver: Solver,
    pub(crate) scene: Scene,
    pub(crate) chunk: usize,
}

impl Rows {
    /// Check the options against the model and data and build the method.
    pub(crate) fn new(
        model: &Model,
        data: &Dataset,
        opts: &PredictOptions,
    ) -> Result<Self, SolveError> {
        let r = &opts.request;
        for (field, bad) in [
            ("steps", r.steps != 1),
            ("warm_from", r.warm_from.is_some()),
            ("repeat", r.repeat != 1),
        ] {
            if bad {
                return Err(SolveError::InvalidInput {
                    field: field.into(),
                    reason: "predict warm-starts every row from the previous one; it takes no steps, warm-from or repeat".into(),
                });
            }
        }
        crate::counts::PREDICT_CHUNK.check(opts.chunk)?;
        let n = model.robot.cables.len();
        if data.columns.len() != n {
            return Err(SolveError::InvalidInput {
                field: "columns".into(),
                reason: format!(
                    "the data gives {} cable columns ({}) for a model with {n} cables",
                    data.columns.len(),
                    data.columns.join(",")
                ),
            });
        }
        Ok(Rows {
            solver: r.solver()?,
            scene: r.scene_for(model),
            chunk: opts.chunk,
        })
    }

    /// Every row of `commands` (with each cable's direction of motion `dirs[i]`, for the
    /// backlash; empty: none) for `model` (the robot `new` was checked against; its
    /// parameters may differ) on the one block loop of [`crate::batch`]: chunks in parallel,
    /// each row warm-started from the previous solved row of its chunk (or from `warm[i]`
    /// when given), a failed warm start retried cold once. `out(i, row)` maps each row; a
    /// panic of the method is passed on (a bug in ccrkit, not a row status).
    pub(crate) fn solve_all<T: Send>(
        &self,
        model: &Model,
        commands: &[Vec<f64>],
        dirs: &[Vec<f64>],
        warm: Option<&[Option<Shape>]>,
        bar: &ProgressHandle,
        out: &RowMap<'_, T>,
    ) -> Vec<T> {
        let blocks = Blocks {
            solver: &self.solver,
            scene: &self.scene,
            chunk: self.chunk,
            warm_start: true,
            retry_cold: true,
        };
        blocks.run(
            &model.robot,
            commands.len(),
            &|i| {
                let d = dirs.get(i).map_or(&[][..], Vec::as_slice);
                model.hardware.actuation_moving(&commands[i], d)
            },
            warm,
            &|i, row: &Solved| {
                bar.advance(1);
                match &row.result {
                    Ok(s) => out(i, Ok(s), row.iterations),
                    Err(RowFailure::Error(e)) => out(i, Err(e), row.iterations),
                    Err(RowFailure::Panic(msg)) => std::panic::resume_unwind(Box::new(msg.clone())),
                }
            },
        )
    }
}

/// Predict every row of `data` with `model`: the marker in the measurement frame per row, in
/// row order (module docs). Only the tip is read, so the energy model's tip Jacobian and
/// stability are not computed (`sensitivity = off`, unless the settings give it): the tips
/// are the same to the bit.
pub fn predict(
    model: &Model,
    data: &Dataset,
    opts: &PredictOptions,
) -> Result<Vec<RowPrediction>, SolveError> {
    let mut opts = opts.clone();
    let r = &mut opts.request;
    if r.method == MethodKind::Energy && r.settings.get("sensitivity").is_none() {
        r.settings.push("sensitivity", "off");
    }
    let opts = &opts;
    let rows = Rows::new(model, data, opts)?;
    let bar = &opts.progress;
    bar.start("predict", Some(data.len() as u64));
    let dirs = directions(&data.commands);
    let out = rows.solve_all(
        model,
        &data.commands,
        &dirs,
        None,
        bar,
        &|_, r, iterations| RowPrediction {
            tip: r
                .map(|s| model.hardware.measured_tip(s))
                .map_err(Clone::clone),
            iterations,
        },
    );
    bar.finish();
    Ok(out)
}

/// Write predictions as CSV: `tip_x, tip_y, tip_z` in the data's unit (`unit` metres per unit),
/// then `status`; a row that did not solve has empty tip fields.
pub fn write_csv(rows: &[RowPrediction], unit: f64) -> String {
    let mut s = String::from("tip_x,tip_y,tip_z,status\n");
    for r in rows {
        match &r.tip {
            Ok(t) => s.push_str(&format!(
                "{},{},{},ok\n",
                t.x / unit,
                t.y / unit,
                t.z / unit
            )),
            Err(e) => s.push_str(&format!(",,,{}\n", e.kind())),
        }
    }
    s
}
