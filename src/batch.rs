//! Batches of solves of one model: many rows of cable inputs, solved in parallel blocks,
//! warm-started along the rows, a failed row recorded and never aborting the batch.
//!
//! This is what the Python package's `solve_batch` runs with the GIL released, and what an
//! inverse or calibration loop (hardware `predict`) reuses: the rows are the inputs, the
//! model's own actuation is ignored.
//!
//! Rows are cut into blocks of [`BatchOptions::chunk`] consecutive rows. Inside a block each
//! row starts from the last solved shape of the block (when `warm_start`); blocks are solved
//! in parallel (rayon). The block boundaries depend only on `chunk`, never on the number of
//! threads, so a batch gives bit-identical results on 1 or N threads, and a sweep cut into
//! pieces whose lengths are multiples of `chunk` (e.g. mapped over a Dask cluster) gives the
//! same rows as one batch.
//!
//! Files: `batch.rs` (the inputs, options, row records and [`solve_batch`]) ·
//! `batch/blocks.rs` (the block loop every batch runs on, shared with hardware `predict` and
//! the calibration).

use crate::error::{SolveError, Status};
use crate::method::run::SolveRequest;
use crate::method::MethodKind;
use crate::model::actuation::{Actuation, CableDrive, Shortening};
use crate::model::Model;
use crate::shape::{DiskFrame, Shape};

mod blocks;

pub(crate) use blocks::{Blocks, RowFailure, Solved};

/// Most rows one batch may hold.
pub const MAX_ROWS: usize = 100_000_000;
/// Largest block of warm-started rows.
pub const MAX_CHUNK: usize = 1_000_000;
/// Most threads a batch may ask for.
pub const MAX_THREADS: usize = 1024;
/// Default rows per block.
pub const DEFAULT_CHUNK: usize = 64;

/// The inputs of every row: `rows × cables` values, row-major, one column per cable in robot
/// order. Shortenings in metres, tensions in newtons; NaN: the cable gets no input of that
/// kind in that row (a cable with neither is free).
#[derive(Debug, Clone, PartialEq)]
pub struct BatchInputs {
    rows: usize,
    cables: usize,
    shorten: Option<Vec<f64>>,
    tension: Option<Vec<f64>>,
    insertion: Option<Vec<f64>>,
    rotation: Option<Vec<f64>>,
}

impl BatchInputs {
    /// Check the sizes: `shorten` and `tension` (at least one) hold `rows × cables` values.
    pub fn new(
        rows: usize,
        cables: usize,
        shorten: Option<Vec<f64>>,
        tension: Option<Vec<f64>>,
    ) -> Result<Self, SolveError> {
        let invalid = |field: &str, reason: String| SolveError::InvalidInput {
            field: field.into(),
            reason,
        };
        if shorten.is_none() && tension.is_none() {
            return Err(invalid(
                "shorten",
                "a batch needs `shorten` or `tension` (or both)".into(),
            ));
        }
        if rows > MAX_ROWS {
            return Err(invalid(
                "rows",
                format!("at most {MAX_ROWS} rows, got {rows}"),
            ));
        }
        for (field, v) in [("shorten", &shorten), ("tension", &tension)] {
            if let Some(v) = v {
                if v.len() != rows * cables {
                    return Err(invalid(
                        field,
                        format!(
                            "needs {rows} rows × {cables} cables = {} values, got {}",
                            rows * cables,
                            v.len()
                        ),
                    ));
                }
            }
        }
        Ok(BatchInputs {
            rows,
            cables,
            shorten,
            tension,
            insertion: None,
            rotation: None,
        })
    }

    /// The same rows through the model's port: `insertion` \[m\] and `rotation` \[rad\], one
    /// value per row each (NaN: the row gives none: full insertion, no rotation). Checked for
    /// their sizes here and for their ranges by each row's solve (a robot without a port
    /// refuses them by name).
    pub fn with_port(
        mut self,
        insertion: Option<Vec<f64>>,
        rotation: Option<Vec<f64>>,
    ) -> Result<Self, SolveError> {
        for (field, v) in [("insertion", &insertion), ("rotation", &rotation)] {
            if let Some(v) = v {
                if v.len() != self.rows {
                    return Err(SolveError::InvalidInput {
                        field: field.into(),
                        reason: format!("needs one value per row ({}), got {}", self.rows, v.len()),
                    });
                }
            }
        }
        self.insertion = insertion;
        self.rotation = rotation;
        Ok(self)
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The actuation of row `r` (every cable's inputs replaced by the row's).
    pub fn actuation(&self, r: usize) -> Actuation {
        let at = |v: &Option<Vec<f64>>, c: usize| {
            v.as_ref()
                .map(|v| v[r * self.cables + c])
                .filter(|x| !x.is_nan())
        };
        Actuation {
            cables: (0..self.cables)
                .map(|c| CableDrive {
                    shorten: at(&self.shorten, c).map(Shortening::Length),
                    tension: at(&self.tension, c),
                    capstan: 0.0,
                })
                .collect(),
            insertion: self
                .insertion
                .as_ref()
                .map(|v| v[r])
                .filter(|x| !x.is_nan()),
            rotation: self.rotation.as_ref().map(|v| v[r]).filter(|x| !x.is_nan()),
        }
    }
}

/// How a batch runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BatchOptions {
    /// Threads (`None`: rayon's global pool, one per core).
    pub threads: Option<usize>,
    /// Start each row from the previous solved row of its block.
    pub warm_start: bool,
    /// Rows per block (warm starts never cross a block boundary).
    pub chunk: usize,
    /// Keep every row's disk frames.
    pub keep_disks: bool,
}

impl Default for BatchOptions {
    fn default() -> Self {
        BatchOptions {
            threads: None,
            warm_start: true,
            chunk: DEFAULT_CHUNK,
            keep_disks: false,
        }
    }
}

impl BatchOptions {
    fn check(&self) -> Result<(), SolveError> {
        if !(1..=MAX_CHUNK).contains(&self.chunk) {
            return Err(SolveError::InvalidInput {
                field: "chunk".into(),
                reason: format!("must be from 1 to {MAX_CHUNK}, got {}", self.chunk),
            });
        }
        if let Some(t) = self.threads.filter(|t| !(1..=MAX_THREADS).contains(t)) {
            return Err(SolveError::InvalidInput {
                field: "threads".into(),
                reason: format!("must be from 1 to {MAX_THREADS}, got {t}"),
            });
        }
        Ok(())
    }
}

/// One solved (or failed) row.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchRow {
    /// Outcome.
    pub status: Status,
    /// The error's message when the row failed.
    pub error: Option<String>,
    /// Tip position \[m\] (NaN when the row failed).
    pub tip: [f64; 3],
    /// Iterations (of the failed solve too, when it says).
    pub iterations: usize,
    /// Final residual (NaN when the method did not say).
    pub residual: f64,
    /// The report's `converged`.
    pub converged: bool,
    /// Tension of every cable \[N\] (NaN where the method computes none, or on failure).
    pub tensions: Vec<f64>,
    /// Disk frames, when [`BatchOptions::keep_disks`] and the row solved.
    pub disks: Option<Vec<DiskFrame>>,
    /// The estimated tip distance from the converged reference rod \[m\], when the request
    /// asks for estimates ([`SolveRequest::estimate`]); `None` otherwise, on failure, or
    /// where the model part is unknown ([`crate::method::estimate`]).
    pub error_estimate_m: Option<f64>,
}

impl BatchRow {
    fn solved(s: &Shape, keep_disks: bool) -> Self {
        BatchRow {
            status: Status::Ok,
            error: None,
            tip: s.tip().into(),
            iterations: s.report.iterations,
            residual: s.report.residual,
            converged: s.report.converged,
            tensions: s
                .cables
                .iter()
                .map(|c| c.tension.unwrap_or(f64::NAN))
                .collect(),
            disks: keep_disks.then(|| s.disks.clone()),
            error_estimate_m: s.report.error_estimate.as_ref().and_then(|e| e.bound_m),
        }
    }

    fn failed(status: Status, error: String, cables: usize, e: Option<&SolveError>) -> Self {
        let (iterations, residual) = e.map_or((0, f64::NAN), SolveError::iterations_residual);
        BatchRow {
            status,
            error: Some(error),
            tip: [f64::NAN; 3],
            iterations,
            residual,
            converged: false,
            tensions: vec![f64::NAN; cables],
            disks: None,
            error_estimate_m: None,
        }
    }
}

/// A solved batch: one row per input row, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct Batch {
    /// The method.
    pub method: MethodKind,
    /// The rows.
    pub rows: Vec<BatchRow>,
}

impl Batch {
    /// How many rows have each status.
    pub fn count(&self, status: Status) -> usize {
        self.rows.iter().filter(|r| r.status == status).count()
    }
}

/// Solve every row of `inputs` on `model` (its robot and scene; its actuation is replaced by
/// each row's) with the request's method, settings, extra obstacles and continuation steps
/// (`steps` applies to the rows that start cold). Errors only for a request or options that
/// cannot run at all; a row that fails is recorded with its [`Status`].
pub fn solve_batch(
    model: &Model,
    request: &SolveRequest,
    inputs: &BatchInputs,
    opts: &BatchOptions,
) -> Result<Batch, SolveError> {
    opts.check()?;
    if let Some(w) = request.warm_from {
        return Err(SolveError::InvalidInput {
            field: "warm_from".into(),
            reason: format!("a batch warm-starts along its rows; --warm-from {w} is not used"),
        });
    }
    if inputs.cables != model.robot.cables.len() {
        return Err(SolveError::InvalidInput {
            field: "shorten".into(),
            reason: format!(
                "rows give {} cables, the robot `{}` has {}",
                inputs.cables,
                model.robot.name,
                model.robot.cables.len()
            ),
        });
    }
    let solver = request.solver()?;
    let scene = request.scene_for(model);
    let blocks = Blocks {
        solver: &solver,
        scene: &scene,
        chunk: opts.chunk,
        warm_start: opts.warm_start,
        retry_cold: false,
    };
    let cables = inputs.cables;
    let run = || -> Vec<BatchRow> {
        blocks.run(
            &model.robot,
            inputs.rows,
            &|r| inputs.actuation(r),
            None,
            &|r, out: &Solved| match &out.result {
                Ok(s) if request.estimate => {
                    let act = inputs.actuation(r);
                    match solver.estimate(&model.robot, &act, &scene, s) {
                        Ok(e) => {
                            let mut s = s.clone();
                            s.report.error_estimate = Some(e);
                            BatchRow::solved(&s, opts.keep_disks)
                        }
                        Err(e) => BatchRow::failed(e.status(), e.to_string(), cables, Some(&e)),
                    }
                }
                Ok(s) => BatchRow::solved(s, opts.keep_disks),
                Err(RowFailure::Error(e)) => {
                    BatchRow::failed(e.status(), e.to_string(), cables, Some(e))
                }
                Err(RowFailure::Panic(msg)) => {
                    BatchRow::failed(Status::Panicked, format!("panic: {msg}"), cables, None)
                }
            },
        )
    };
    let rows = match opts.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| SolveError::InvalidInput {
                field: "threads".into(),
                reason: format!("cannot start {n} threads: {e}"),
            })?
            .install(run),
        None => run(),
    };
    Ok(Batch {
        method: request.method,
        rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::MethodKind;

    fn case1() -> Model {
        Model::from_file("models/paper/case1.toml").expect("case 1")
    }

    /// Rows of case I's shortenings scaled from 50 % to 100 %.
    fn rows(model: &Model, n: usize) -> Vec<f64> {
        let mut v = Vec::new();
        for r in 0..n {
            let f = 0.5 + 0.5 * r as f64 / (n - 1) as f64;
            for c in 0..model.robot.cables.len() {
                let s = model.actuation.shortening_length(&model.robot, c);
                v.push(f * s.expect("case 1 gives shortenings"));
            }
        }
        v
    }

    #[test]
    fn rows_equal_single_solves_and_bad_rows_do_not_abort() {
        let model = case1();
        let n = 6;
        let mut short = rows(&model, n);
        short[2 * 2] = f64::INFINITY; // row 2: invalid
        short[4 * 2 + 1] = 10.0; // row 4: longer than the cable, infeasible
        let inputs = BatchInputs::new(n, 2, Some(short.clone()), None).expect("inputs");
        let req = SolveRequest::new(MethodKind::Energy);
        let opts = BatchOptions {
            warm_start: false,
            chunk: 4,
            ..Default::default()
        };
        let b = solve_batch(&model, &req, &inputs, &opts).expect("batch");
        let status: Vec<&str> = b.rows.iter().map(|r| r.status.name()).collect();
        assert_eq!(
            status,
            ["ok", "ok", "invalid_input", "ok", "infeasible", "ok"]
        );
        // A cold row is exactly the one solve path's answer for that actuation.
        for r in [0, 3, 5] {
            let mut m = model.clone();
            m.actuation = inputs.actuation(r);
            let s = req.run(&m).expect("single").shape;
            assert_eq!(b.rows[r].tip, <[f64; 3]>::from(s.tip()));
            assert_eq!(b.rows[r].iterations, s.report.iterations);
        }
        assert!(b.rows[2].tip[0].is_nan());
        assert!(b.rows[2]
            .error
            .as_deref()
            .unwrap_or("")
            .contains("cables[0].shorten"));
    }

    /// Rows through a port: each row's insertion and rotation reach its solve (a row equals
    /// the single solve at them; NaN is none: full insertion, no rotation), a bad length is
    /// named, a robot without a port refuses them in the row by name.
    #[test]
    fn rows_through_a_port_carry_their_insertion_and_rotation() {
        let model = Model::from_file("models/soft/lung_rod.toml").expect("lung rod");
        let (n, k) = (4, 3);
        let tension: Vec<f64> = (0..n).flat_map(|_| [0.6, 0.3, 0.2]).collect();
        let ins = vec![0.03, 0.06, f64::NAN, 0.11];
        let rot = vec![-1.0, f64::NAN, 0.5, 2.0];
        let inputs = BatchInputs::new(n, k, None, Some(tension.clone()))
            .and_then(|b| b.with_port(Some(ins.clone()), Some(rot.clone())))
            .expect("inputs");
        assert_eq!(inputs.actuation(0).insertion, Some(0.03));
        assert_eq!(inputs.actuation(1).rotation, None);
        assert_eq!(inputs.actuation(2).insertion, None);
        let req = SolveRequest::new(MethodKind::Energy);
        let opts = BatchOptions {
            warm_start: false,
            ..Default::default()
        };
        let b = solve_batch(&model, &req, &inputs, &opts).expect("batch");
        for r in 0..n {
            let mut a = model.actuation.clone();
            for (c, t) in a.cables.iter_mut().zip(&tension[r * k..]) {
                c.tension = Some(*t);
            }
            a.insertion = (!ins[r].is_nan()).then_some(ins[r]);
            a.rotation = (!rot[r].is_nan()).then_some(rot[r]);
            let s = req
                .solver()
                .and_then(|sv| sv.solve(&model.robot, &a, &model.scene, None))
                .expect("single");
            assert_eq!(b.rows[r].tip, <[f64; 3]>::from(s.tip()), "row {r}");
        }
        let e = BatchInputs::new(n, k, None, Some(tension))
            .and_then(|b| b.with_port(Some(vec![0.05; 3]), None))
            .expect_err("one insertion per row");
        assert!(e.to_string().contains("insertion"), "{e}");
        let plain = case1();
        let inputs = BatchInputs::new(1, 2, Some(vec![0.001, 0.0]), None)
            .and_then(|b| b.with_port(Some(vec![0.05]), None))
            .expect("inputs");
        let b = solve_batch(&plain, &req, &inputs, &opts).expect("batch");
        assert_eq!(b.rows[0].status.name(), "invalid_input");
        assert!(b.rows[0]
            .error
            .as_deref()
            .unwrap_or("")
            .contains("insertion"));
    }

    #[test]
    fn rows_carry_the_single_solves_estimate_when_asked() {
        let model = case1();
        let n = 3;
        let inputs = BatchInputs::new(n, 2, Some(rows(&model, n)), None).expect("inputs");
        let req = SolveRequest::new(MethodKind::Energy).with_estimate(true);
        let opts = BatchOptions {
            warm_start: false,
            ..Default::default()
        };
        let b = solve_batch(&model, &req, &inputs, &opts).expect("batch");
        for (r, row) in b.rows.iter().enumerate() {
            let mut m = model.clone();
            m.actuation = inputs.actuation(r);
            let single = req.run(&m).expect("single").shape.report.error_estimate;
            let want = single.and_then(|e| e.bound_m).expect("a bound");
            let got = row.error_estimate_m.expect("asked for");
            assert!(
                (got - want).abs() <= 1e-9 * want.max(1e-12),
                "row {r}: {got} vs {want}"
            );
        }
        let plain = solve_batch(
            &model,
            &SolveRequest::new(MethodKind::Energy),
            &inputs,
            &opts,
        );
        assert!(plain
            .expect("batch")
            .rows
            .iter()
            .all(|r| r.error_estimate_m.is_none()));
    }

    #[test]
    fn threads_and_warm_starts_do_not_change_rows_beyond_tolerance() {
        let model = case1();
        let n = 10;
        let inputs = BatchInputs::new(n, 2, Some(rows(&model, n)), None).expect("inputs");
        // Chord lengths: ≈ 9 Newton iterations cold, so a warm start shows in the count.
        let req = SolveRequest::new(MethodKind::Energy)
            .with_settings(crate::method::Settings::new().with("length", "chord"));
        let warm = |threads| BatchOptions {
            threads: Some(threads),
            chunk: 3,
            ..Default::default()
        };
        let one = solve_batch(&model, &req, &inputs, &warm(1)).expect("1 thread");
        let two = solve_batch(&model, &req, &inputs, &warm(2)).expect("2 threads");
        assert_eq!(one, two, "blocks are fixed by chunk, not by threads");
        let cold = BatchOptions {
            warm_start: false,
            ..warm(2)
        };
        let c = solve_batch(&model, &req, &inputs, &cold).expect("cold");
        for (w, c) in one.rows.iter().zip(&c.rows) {
            assert_eq!(w.status, Status::Ok);
            let d = (0..3)
                .map(|i| (w.tip[i] - c.tip[i]).abs())
                .fold(0.0, f64::max);
            assert!(d < 1e-8, "warm and cold tips differ by {d} m");
        }
        // Warm rows (not first in their block) need fewer iterations in total.
        let iters = |b: &Batch| b.rows.iter().map(|r| r.iterations).sum::<usize>();
        assert!(iters(&one) < iters(&c), "{} vs {}", iters(&one), iters(&c));
    }

    #[test]
    fn sizes_and_options_are_checked() {
        let model = case1();
        let req = SolveRequest::new(MethodKind::Energy);
        assert!(BatchInputs::new(2, 2, Some(vec![0.0; 3]), None).is_err());
        assert!(BatchInputs::new(2, 2, None, None).is_err());
        let three = BatchInputs::new(1, 3, Some(vec![0.0; 3]), None).expect("sizes");
        let e = solve_batch(&model, &req, &three, &BatchOptions::default());
        assert!(matches!(e, Err(SolveError::InvalidInput { ref field, .. }) if field == "shorten"));
        let ok = BatchInputs::new(1, 2, Some(vec![0.0; 2]), None).expect("sizes");
        for opts in [
            BatchOptions {
                chunk: 0,
                ..Default::default()
            },
            BatchOptions {
                threads: Some(0),
                ..Default::default()
            },
        ] {
            assert!(solve_batch(&model, &req, &ok, &opts).is_err());
        }
        let unknown = req.with_settings(crate::method::Settings::new().with("rk4-steps", "3"));
        let e = solve_batch(&model, &unknown, &ok, &BatchOptions::default());
        assert!(
            matches!(e, Err(SolveError::InvalidInput { ref field, .. }) if field == "rk4-steps")
        );
    }
}
