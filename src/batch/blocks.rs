//! The one block loop of every batch of solves ([`Blocks`]): rows cut into blocks, blocks
//! in parallel, warm starts along a block, an optional cold retry, panics caught. The batch's
//! inputs, options, row records and [`super::solve_batch`] live in `batch.rs`.

use crate::error::SolveError;
use crate::method::{PreparedSolver, Solver};
use crate::model::actuation::Actuation;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;
use rayon::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Why a row of [`Blocks::run`] has no shape.
#[derive(Debug, Clone)]
pub(crate) enum RowFailure {
    /// The method's error (of the last attempt).
    Error(SolveError),
    /// The method panicked (a bug in ccrkit), with the panic's message.
    Panic(String),
}

/// One row as [`Blocks::run`] solved it.
#[derive(Debug)]
pub(crate) struct Solved {
    /// The shape, or why there is none.
    pub(crate) result: Result<Shape, RowFailure>,
    /// Iterations of every attempt (a failed one counts when its error says).
    pub(crate) iterations: usize,
}

/// The one block loop of every batch of solves (Python's `solve_batch`, hardware `predict`
/// and the calibration's passes): rows cut into blocks of `chunk`, blocks in parallel
/// (rayon), rows of a block in order, each started from the last solved row of its block.
pub(crate) struct Blocks<'a> {
    /// The request's solver (its continuation steps start a cold row; every shape passes the
    /// output check).
    pub(crate) solver: &'a Solver,
    /// The scene every row is solved in.
    pub(crate) scene: &'a Scene,
    /// Rows per block (≥ 1).
    pub(crate) chunk: usize,
    /// Start a row from the last solved row of its block.
    pub(crate) warm_start: bool,
    /// Retry a row whose warm-started solve failed once more, cold.
    pub(crate) retry_cold: bool,
}

impl Blocks<'_> {
    /// Solve `rows` rows of `robot`, row `r` with actuation `act(r)`; `warm[r]`, when given,
    /// starts row `r` instead of the previous row. `out(r, row)` turns each solved row into the
    /// caller's result (rows in order).
    pub(crate) fn run<T: Send>(
        &self,
        robot: &Robot,
        rows: usize,
        act: &(dyn Fn(usize) -> Actuation + Sync),
        warm: Option<&[Option<Shape>]>,
        out: &(dyn Fn(usize, &Solved) -> T + Sync),
    ) -> Vec<T> {
        // What depends on the robot alone (the energy model's routing samples and undeformed
        // cable lengths) is computed once for every row and shared by the threads, not once
        // per row. A robot the method cannot be readied for fails every row with that error.
        let prepared = catch_unwind(AssertUnwindSafe(|| self.solver.prepare(robot)));
        let prepared = match prepared {
            Ok(Ok(p)) => Ok(p),
            Ok(Err(e)) => Err(RowFailure::Error(e)),
            Err(p) => Err(RowFailure::Panic(panic_message(&*p))),
        };
        let starts: Vec<usize> = (0..rows).step_by(self.chunk.max(1)).collect();
        starts
            .par_iter()
            .flat_map_iter(|&start| {
                let end = (start + self.chunk.max(1)).min(rows);
                let mut last: Option<Shape> = None;
                let mut block = Vec::with_capacity(end - start);
                for r in start..end {
                    let from = warm
                        .and_then(|w| w.get(r).and_then(Option::as_ref))
                        .or(last.as_ref().filter(|_| self.warm_start));
                    let solved = match &prepared {
                        Ok(p) => self.row(p, &act(r), from),
                        Err(e) => Solved {
                            result: Err(e.clone()),
                            iterations: 0,
                        },
                    };
                    block.push(out(r, &solved));
                    if let Ok(s) = solved.result {
                        last = Some(s);
                    }
                }
                block
            })
            .collect()
    }

    /// One row from `warm` (cold with continuation steps when `None`), retried cold once when
    /// asked; a panic of the method is caught and reported.
    fn row(&self, solver: &PreparedSolver<'_>, act: &Actuation, warm: Option<&Shape>) -> Solved {
        let attempt = |w: Option<&Shape>| match catch_unwind(AssertUnwindSafe(|| {
            solver.solve(act, self.scene, w)
        })) {
            Ok(Ok(s)) => (s.report.iterations, Ok(s)),
            Ok(Err(e)) => (failed_iterations(&e), Err(RowFailure::Error(e))),
            Err(p) => (0, Err(RowFailure::Panic(panic_message(&*p)))),
        };
        let (mut iterations, mut result) = attempt(warm);
        if self.retry_cold && warm.is_some() && matches!(result, Err(RowFailure::Error(_))) {
            let (it, r) = attempt(None);
            iterations += it;
            result = r;
        }
        Solved { result, iterations }
    }
}

/// The message of a caught panic.
fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Iterations a failed solve reports (0 when its error does not say).
fn failed_iterations(e: &SolveError) -> usize {
    match e {
        SolveError::NotConverged { iterations, .. } => *iterations,
        _ => 0,
    }
}
