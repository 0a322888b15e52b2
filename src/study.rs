//! Studies: speed against accuracy, stability maps over an actuation plane, and workspace
//! sweeps at scale (sharded, mergeable). The engine behind `ccrkit study` and the examples.
//!
//! * [`speed_accuracy`]: every method of [`METHOD_NAMES`] at each of its resolution settings
//!   ([`variants`]) — median solve time over a few repeats and the error against a converged
//!   Cosserat reference driven by the same kind of input: [`reference`] (full rod, 80 RK4 steps
//!   per section, force control with the file's tensions) for force-driven methods, and
//!   [`reference_displacement`] (the same rod driven by the file's cable displacements, lengths
//!   along the routed path) for displacement-driven ones — the paper's cases give both inputs,
//!   and they do not describe the same shape, so each model is judged on its own input.
//!   A method added to [`METHOD_NAMES`] later (e.g. `energy`) joins with its default settings
//!   unless [`variants`] lists settings for it.
//! * [`stability`]: a grid over the inputs of two cables, each method solved cold and with
//!   continuation along the rows (warm start from the previous grid point of the row);
//!   every point is `ok` or a named failure ([`crate::SolveError::kind`], or `nan` when a
//!   method returned a shape with a non-finite coordinate — a bug to report).
//! * [`workspace`]: low-discrepancy (Halton) samples of the cables' inputs, solved in parallel
//!   in fixed chunks (warm-started from the nearest solved sample of the chunk), shardable with
//!   [`Shard`]; [`merge_csv`] joins shards into the CSV of the unsharded run, byte for byte.
//!
//! All outputs are SI: shortening as a fraction of the cable's length, tension in N,
//! positions in m, times in s.
//!
//! # Numbers (2-core machine shared with other builds; times are indicative)
//!
//! Speed–accuracy, case II (`ccrkit study speed-accuracy models/paper/case2.toml --out DIR`):
//! geometric 25–37 ms at 2.9 mm RMS (8.2 mm tip) from the rod — a model difference, not a
//! resolution one; geometric-squared 0.56 ms at 4.0 mm RMS; Cosserat RK4 2/3/4/8/12/20 steps
//! per section 0.13/0.14/0.18/0.26/0.37/0.60 ms at 2.6e-7/4.8e-8/1.5e-8/8e-10/1.5e-10/3e-11 m
//! RMS (all on the Pareto front); adaptive RK45 1e-3/1e-5 stall at 2.6e-7 m; Kirchhoff sits at
//! 2.9e-5 m (its inextensibility) whatever its resolution; constant curvature does not apply
//! (helical cable).
//!
//! Stability (`ccrkit study stability FILE --out DIR`, shortening 0–18 %, tension 0–10×):
//! case I converges everywhere for every method; the literal geometric method fails
//! (`not_converged`) on 3/400 (case II) and 97/400 (case III, 73 with continuation) points
//! of a 20×20 grid, in bands (A or B near 9.5 % and 11.4 % on case III), first at
//! (A, B) = (0, 0.95 %) on case III; the squared variant and both rods converge everywhere.
//! Pushed further on case I (shortening to 40 %, tension to 40×): geometric-squared fails only
//! at the (40 %, 40 %) corner, the rods stop converging above ≈ 72 N on one cable (≈ 17× the
//! file's, a bending angle κL ≈ 24 rad), constant curvature never fails.
//!
//! Workspace throughput, case I, 2000 samples, 2 threads: constant curvature ≈ 48 000
//! solves/s, Kirchhoff ≈ 2100, Cosserat ≈ 1400, geometric-squared ≈ 960, geometric ≈ 73.

pub mod figures;

use crate::actuation::{Actuation, Shortening};
use crate::error::SolveError;
use crate::method::constant_curvature::ConstantCurvature;
use crate::method::cosserat::{Control, Cosserat};
use crate::method::{method_by_name, Method, METHOD_NAMES};
use crate::model::Model;
use crate::scene::Scene;
use crate::shape::Shape;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use nalgebra::Vector3;
use rayon::prelude::*;
use std::io::IsTerminal;
use std::time::Instant;

/// A study failure (a solve that the study cannot do without, a file, a figure).
#[derive(Debug, thiserror::Error)]
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
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    /// A CSV that cannot be merged, or bad study options.
    #[error("{0}")]
    Invalid(String),
}

/// Write a text file, naming the path on failure.
pub fn write_text(path: &std::path::Path, text: &str) -> Result<(), StudyError> {
    std::fs::write(path, text).map_err(|e| StudyError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Which input a study varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// Shortening, as a fraction of the cable's undeformed length.
    Shortening,
    /// Tension [N].
    Tension,
}

impl Input {
    /// Name used in CSV files (`shortening_fraction` or `tension_n`).
    pub fn csv_name(self) -> &'static str {
        match self {
            Input::Shortening => "shortening_fraction",
            Input::Tension => "tension_n",
        }
    }
    /// Axis label.
    pub fn label(self, cable: &str) -> String {
        match self {
            Input::Shortening => format!("{cable} shortening [%]"),
            Input::Tension => format!("{cable} tension [N]"),
        }
    }
}

/// The input a method reads naturally: tension for the rods, shortening for the others
/// (including methods added later).
pub fn natural_input(method: &str) -> Input {
    match method {
        "cosserat" | "kirchhoff" => Input::Tension,
        _ => Input::Shortening,
    }
}

/// A method in its default settings, driven by `input` (rods and constant curvature switch
/// their control mode; other methods read what they read).
pub fn study_method(name: &str, input: Input) -> Result<Box<dyn Method>, SolveError> {
    let control = match input {
        Input::Shortening => Control::Displacement,
        Input::Tension => Control::Force,
    };
    Ok(match name {
        "cosserat" => Box::new(Cosserat::full().with_control(control)),
        "kirchhoff" => Box::new(Cosserat::kirchhoff().with_control(control)),
        "constant-curvature" => Box::new(ConstantCurvature { control }),
        other => method_by_name(other)?,
    })
}

/// One method at one resolution setting.
pub struct Variant {
    /// Method name (as in [`METHOD_NAMES`]).
    pub method: String,
    /// Setting label (e.g. `rk4 12/section`, `adaptive 1e-6`, `default`).
    pub setting: String,
    /// The configured solver.
    pub solver: Box<dyn Method>,
}

/// RK4 steps per section examined for the rods.
pub const RK4_STEPS: &[usize] = &[2, 3, 4, 6, 8, 12, 20];
/// Adaptive RK45 tolerances examined for the rods.
pub const ADAPTIVE_TOLS: &[f64] = &[1e-3, 1e-5, 1e-7];

/// The resolution settings of a method for [`speed_accuracy`]. This is the hook for new
/// methods: a name without an entry here is studied with its default settings.
pub fn variants(name: &str) -> Result<Vec<Variant>, SolveError> {
    let v = |setting: String, solver: Box<dyn Method>| Variant {
        method: name.to_string(),
        setting,
        solver,
    };
    Ok(match name {
        "cosserat" | "kirchhoff" => {
            let base = if name == "cosserat" {
                Cosserat::full()
            } else {
                Cosserat::kirchhoff()
            }
            .with_control(Control::Force);
            let mut out: Vec<Variant> = RK4_STEPS
                .iter()
                .map(|&k| {
                    v(
                        format!("rk4 {k}/section"),
                        Box::new(base.clone().with_steps(k)),
                    )
                })
                .collect();
            out.extend(ADAPTIVE_TOLS.iter().map(|&t| {
                v(
                    format!("adaptive {t:e}"),
                    Box::new(base.clone().with_adaptive(Some(t))),
                )
            }));
            out
        }
        "constant-curvature" => vec![
            v(
                "displacement".into(),
                Box::new(ConstantCurvature::displacement()),
            ),
            v("force".into(), Box::new(ConstantCurvature::force())),
        ],
        other => vec![v("default".into(), method_by_name(other)?)],
    })
}

/// The converged reference of the speed–accuracy study: full Cosserat rod, 80 RK4 steps per
/// section, force control, shooting tolerance 1e-11 N.
pub fn reference() -> Cosserat {
    Cosserat {
        tolerance: 1e-11,
        ..Cosserat::full().with_steps(80).with_control(Control::Force)
    }
}

/// The converged reference for displacement-driven methods: the same rod as [`reference`]
/// driven by the model's cable displacements (lengths along the routed path).
pub fn reference_displacement() -> Cosserat {
    Cosserat {
        tolerance: 1e-11,
        ..Cosserat::full()
            .with_steps(80)
            .with_control(Control::Displacement)
    }
}

/// True when a study variant takes cable displacements as its input (and is judged against
/// [`reference_displacement`]); false for force-driven variants.
pub fn displacement_driven(method: &str, setting: &str) -> bool {
    match method {
        "cosserat" | "kirchhoff" => false,
        "constant-curvature" => setting != "force",
        _ => true,
    }
}

/// True when every coordinate of a shape is finite.
pub fn shape_is_finite(s: &Shape) -> bool {
    s.disks.iter().all(|d| {
        d.position.iter().all(|x| x.is_finite()) && d.rotation.iter().all(|x| x.is_finite())
    }) && s.backbone.iter().all(|p| p.iter().all(|x| x.is_finite()))
}

/// Outcome of one solve in a study.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// `ok`, a [`SolveError::kind`], or `nan` (a shape with a non-finite coordinate: a bug).
    pub status: String,
    /// Iterations (of the shape, or of a `NotConverged` error; 0 otherwise).
    pub iterations: usize,
    /// Residual (of the shape, or of a `NotConverged` error; NaN when unknown).
    pub residual: f64,
    /// The shape, when `ok`.
    pub shape: Option<Shape>,
}

/// Classify a solve result.
pub fn outcome(r: Result<Shape, SolveError>) -> Outcome {
    match r {
        Ok(s) if !shape_is_finite(&s) => Outcome {
            status: "nan".into(),
            iterations: s.report.iterations,
            residual: s.report.residual,
            shape: None,
        },
        Ok(s) => Outcome {
            status: "ok".into(),
            iterations: s.report.iterations,
            residual: s.report.residual,
            shape: Some(s),
        },
        Err(e) => {
            let (iterations, residual) = match &e {
                SolveError::NotConverged {
                    iterations,
                    residual,
                    ..
                } => (*iterations, *residual),
                _ => (0, f64::NAN),
            };
            Outcome {
                status: e.kind().into(),
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

fn progress_bar(len: u64, show: bool, msg: &str) -> ProgressBar {
    let bar = if show && std::io::stderr().is_terminal() {
        ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr())
    } else {
        ProgressBar::hidden()
    };
    if let Ok(style) =
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({per_sec}, eta {eta})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(msg.to_string());
    bar
}

// ───────────────────────────── speed against accuracy ─────────────────────────────

/// One row of the speed–accuracy study.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedAccuracyRow {
    /// Method name.
    pub method: String,
    /// Setting label.
    pub setting: String,
    /// `ok` or the failure kind.
    pub status: String,
    /// Median wall time of one solve [s] (NaN on failure).
    pub median_time_s: f64,
    /// Tip distance to the reference [m] (NaN on failure).
    pub tip_error_m: f64,
    /// RMS distance of the disk positions to the reference [m] (NaN on failure).
    pub rms_error_m: f64,
    /// Iterations of one solve.
    pub iterations: usize,
    /// Which reference the errors are measured against: `force` ([`reference`]) or
    /// `displacement` ([`reference_displacement`]).
    pub reference: String,
}

/// Options of [`speed_accuracy`].
#[derive(Debug, Clone)]
pub struct SpeedAccuracyOptions {
    /// Solves per setting; the median time is reported.
    pub repeats: usize,
    /// Methods to study (default: every name in [`METHOD_NAMES`]).
    pub methods: Vec<String>,
}

impl Default for SpeedAccuracyOptions {
    fn default() -> Self {
        SpeedAccuracyOptions {
            repeats: 5,
            methods: METHOD_NAMES.iter().map(|s| s.to_string()).collect(),
        }
    }
}

/// Time every variant of every method on the model's actuation and measure its error against
/// [`reference`]. Methods that cannot solve the model get a row with the failure kind. The
/// solves run one at a time (timings are not disturbed by parallel work of the study itself).
pub fn speed_accuracy(
    model: &Model,
    opts: &SpeedAccuracyOptions,
) -> Result<Vec<SpeedAccuracyRow>, StudyError> {
    let scene = Scene::empty();
    let reference = reference().solve(&model.robot, &model.actuation, &scene, None)?;
    // Without displacement inputs the displacement-driven methods fail anyway.
    let reference_disp = reference_displacement()
        .solve(&model.robot, &model.actuation, &scene, None)
        .ok();
    let mut rows = vec![];
    for name in &opts.methods {
        for v in variants(name)? {
            let mut times = vec![];
            let mut last = None;
            for _ in 0..opts.repeats.max(1) {
                let t = Instant::now();
                let r = v.solver.solve(&model.robot, &model.actuation, &scene, None);
                times.push(t.elapsed().as_secs_f64());
                let failed = r.is_err();
                last = Some(r);
                if failed {
                    break;
                }
            }
            times.sort_by(f64::total_cmp);
            let o = outcome(last.unwrap_or_else(|| {
                Err(SolveError::InvalidInput {
                    field: "repeats".into(),
                    reason: "no solve ran".into(),
                })
            }));
            let by_disp = displacement_driven(&v.method, &v.setting);
            let refer = if by_disp {
                reference_disp.as_ref()
            } else {
                Some(&reference)
            };
            let (tip, rms) = match (&o.shape, refer) {
                (Some(s), Some(r)) => (s.tip_distance(r), s.rms_distance(r).unwrap_or(f64::NAN)),
                _ => (f64::NAN, f64::NAN),
            };
            rows.push(SpeedAccuracyRow {
                method: v.method.clone(),
                setting: v.setting.clone(),
                median_time_s: if o.shape.is_some() {
                    times[times.len() / 2]
                } else {
                    f64::NAN
                },
                tip_error_m: tip,
                rms_error_m: rms,
                iterations: o.iterations,
                status: o.status,
                reference: if by_disp { "displacement" } else { "force" }.into(),
            });
        }
    }
    Ok(rows)
}

/// Which points are on the Pareto front when both coordinates are minimized: a point is on
/// the front when no other point is at least as good in both and strictly better in one.
/// Points with a non-finite coordinate are never on it.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(x, y)| {
            x.is_finite()
                && y.is_finite()
                && !points.iter().any(|&(a, b)| {
                    a.is_finite() && b.is_finite() && a <= x && b <= y && (a < x || b < y)
                })
        })
        .collect()
}

/// Pareto flags of speed–accuracy rows (time against RMS error).
pub fn speed_accuracy_front(rows: &[SpeedAccuracyRow]) -> Vec<bool> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.median_time_s, r.rms_error_m))
        .collect();
    pareto_front(&pts)
}

/// CSV of the speed–accuracy rows:
/// `method,setting,status,median_time_s,tip_error_m,rms_error_m,iterations,pareto`.
pub fn speed_accuracy_csv(rows: &[SpeedAccuracyRow]) -> String {
    let front = speed_accuracy_front(rows);
    let mut s = String::from(
        "method,setting,status,median_time_s,tip_error_m,rms_error_m,iterations,pareto,reference\n",
    );
    for (r, f) in rows.iter().zip(front) {
        s += &format!(
            "{},{},{},{},{},{},{},{},{}\n",
            r.method,
            r.setting,
            r.status,
            num(r.median_time_s),
            num(r.tip_error_m),
            num(r.rms_error_m),
            r.iterations,
            f,
            r.reference
        );
    }
    s
}

// ───────────────────────────── stability maps ─────────────────────────────

/// Options of [`stability`].
#[derive(Debug, Clone)]
pub struct StabilityOptions {
    /// Grid points per axis (from 0 to the maximum, inclusive).
    pub grid: usize,
    /// Largest shortening swept (fraction of the cable length).
    pub max_fraction: f64,
    /// Largest tension swept, as a multiple of the file's tension (1 N when it gives none).
    pub tension_factor: f64,
    /// Input swept: `None` = each method's [`natural_input`].
    pub input: Option<Input>,
    /// Methods (default: every name in [`METHOD_NAMES`]).
    pub methods: Vec<String>,
    /// Show a progress bar on a terminal.
    pub progress: bool,
}

impl Default for StabilityOptions {
    fn default() -> Self {
        StabilityOptions {
            grid: 40,
            max_fraction: 0.18,
            tension_factor: 10.0,
            input: None,
            methods: METHOD_NAMES.iter().map(|s| s.to_string()).collect(),
            progress: false,
        }
    }
}

/// One grid point of a stability map.
#[derive(Debug, Clone)]
pub struct StabilityPoint {
    /// Method name.
    pub method: String,
    /// Warm-started from the previous point of the row.
    pub continuation: bool,
    /// Input swept.
    pub input: Input,
    /// Column index (first cable's input).
    pub ia: usize,
    /// Row index (second cable's input).
    pub ib: usize,
    /// First cable's input (fraction or N).
    pub a: f64,
    /// Second cable's input (fraction or N).
    pub b: f64,
    /// Outcome.
    pub status: String,
    /// Iterations.
    pub iterations: usize,
    /// Residual.
    pub residual: f64,
    /// Tip [m] when `ok`.
    pub tip: Option<Vector3<f64>>,
}

/// Result of [`stability`].
#[derive(Debug, Clone)]
pub struct Stability {
    /// Names of the two swept cables.
    pub cables: [String; 2],
    /// Grid size per axis.
    pub grid: usize,
    /// Every point, per method, mode, row, column.
    pub points: Vec<StabilityPoint>,
}

/// The first two cables with an input in the model.
pub fn swept_cables(model: &Model) -> Result<[usize; 2], StudyError> {
    let driven: Vec<usize> = (0..model.robot.cables.len())
        .filter(|&c| model.actuation.cables.get(c).is_some_and(|d| !d.is_free()))
        .collect();
    if driven.len() < 2 {
        return Err(StudyError::Invalid(format!(
            "the stability study sweeps two cables with inputs; `{}` has {}",
            model.robot.name,
            driven.len()
        )));
    }
    Ok([driven[0], driven[1]])
}

fn max_input(model: &Model, c: usize, input: Input, max_fraction: f64, factor: f64) -> f64 {
    match input {
        Input::Shortening => max_fraction,
        Input::Tension => factor * model.actuation.tension(c).unwrap_or(1.0),
    }
}

/// An actuation with only the listed cables driven.
pub fn actuation_for(model: &Model, input: Input, values: &[(usize, f64)]) -> Actuation {
    let mut act = Actuation::free(&model.robot);
    for &(c, v) in values {
        if let Some(d) = act.cables.get_mut(c) {
            match input {
                Input::Shortening => d.shorten = Some(Shortening::Fraction(v)),
                Input::Tension => d.tension = Some(v),
            }
        }
    }
    act
}

/// Sweep the inputs of the first two driven cables (the others free) over a grid, for every
/// method, cold and with continuation along each row. Rows run in parallel (rayon).
pub fn stability(model: &Model, opts: &StabilityOptions) -> Result<Stability, StudyError> {
    let [ca, cb] = swept_cables(model)?;
    let n = opts.grid.max(2);
    let total = (opts.methods.len() * 2 * n * n) as u64;
    let bar = progress_bar(total, opts.progress, "stability");
    let scene = Scene::empty();
    let mut points = vec![];
    for name in &opts.methods {
        let input = opts.input.unwrap_or_else(|| natural_input(name));
        let solver = study_method(name, input)?;
        let amax = max_input(model, ca, input, opts.max_fraction, opts.tension_factor);
        let bmax = max_input(model, cb, input, opts.max_fraction, opts.tension_factor);
        let value = |k: usize, max: f64| max * k as f64 / (n - 1) as f64;
        for continuation in [false, true] {
            let rows: Vec<Vec<StabilityPoint>> = (0..n)
                .into_par_iter()
                .map(|ib| {
                    let b = value(ib, bmax);
                    let mut warm: Option<Shape> = None;
                    (0..n)
                        .map(|ia| {
                            let a = value(ia, amax);
                            let act = actuation_for(model, input, &[(ca, a), (cb, b)]);
                            let w = if continuation { warm.as_ref() } else { None };
                            let o = outcome(solver.solve(&model.robot, &act, &scene, w));
                            bar.inc(1);
                            let tip = o.shape.as_ref().map(|s| s.tip());
                            if let Some(s) = o.shape {
                                warm = Some(s);
                            }
                            StabilityPoint {
                                method: name.clone(),
                                continuation,
                                input,
                                ia,
                                ib,
                                a,
                                b,
                                status: o.status,
                                iterations: o.iterations,
                                residual: o.residual,
                                tip,
                            }
                        })
                        .collect()
                })
                .collect();
            points.extend(rows.into_iter().flatten());
        }
    }
    bar.finish_and_clear();
    Ok(Stability {
        cables: [
            model.robot.cables[ca].name.clone(),
            model.robot.cables[cb].name.clone(),
        ],
        grid: n,
        points,
    })
}

/// CSV of a stability study:
/// `method,continuation,input,a,b,status,iterations,residual,tip_x_m,tip_y_m,tip_z_m`
/// (`a`, `b`: the first and second swept cable's input, fraction or N).
pub fn stability_csv(st: &Stability) -> String {
    let mut s = String::from(
        "method,continuation,input,a,b,status,iterations,residual,tip_x_m,tip_y_m,tip_z_m\n",
    );
    for p in &st.points {
        let t = p.tip.unwrap_or(Vector3::repeat(f64::NAN));
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{},{}\n",
            p.method,
            p.continuation,
            p.input.csv_name(),
            num(p.a),
            num(p.b),
            p.status,
            p.iterations,
            num(p.residual),
            num(t.x),
            num(t.y),
            num(t.z)
        );
    }
    s
}

/// Per method and mode: how many points converged, and the smallest input norm (a/a_max,
/// b/b_max, max-norm) at which a point failed — where the method stops converging.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilitySummary {
    /// Method.
    pub method: String,
    /// Continuation or cold.
    pub continuation: bool,
    /// Points that converged.
    pub ok: usize,
    /// Points in all.
    pub total: usize,
    /// Failures by kind.
    pub failures: Vec<(String, usize)>,
    /// The failed point closest to the origin (max-norm of the grid indices), as (a, b).
    pub first_failure: Option<(f64, f64)>,
}

/// Summaries of a stability study, one per method and mode.
pub fn stability_summary(st: &Stability) -> Vec<StabilitySummary> {
    let mut out: Vec<StabilitySummary> = vec![];
    // Grid indices of each summary's first failure (max-norm, then sum).
    let mut first: Vec<Option<(usize, usize)>> = vec![];
    for p in &st.points {
        let idx = match out
            .iter()
            .position(|s| s.method == p.method && s.continuation == p.continuation)
        {
            Some(i) => i,
            None => {
                out.push(StabilitySummary {
                    method: p.method.clone(),
                    continuation: p.continuation,
                    ok: 0,
                    total: 0,
                    failures: vec![],
                    first_failure: None,
                });
                first.push(None);
                out.len() - 1
            }
        };
        let s = &mut out[idx];
        s.total += 1;
        if p.status == "ok" {
            s.ok += 1;
            continue;
        }
        match s.failures.iter_mut().find(|(k, _)| *k == p.status) {
            Some(f) => f.1 += 1,
            None => s.failures.push((p.status.clone(), 1)),
        }
        let key = |(a, b): (usize, usize)| (a.max(b), a + b);
        if first[idx].is_none_or(|f| key((p.ia, p.ib)) < key(f)) {
            first[idx] = Some((p.ia, p.ib));
            s.first_failure = Some((p.a, p.b));
        }
    }
    out
}

// ───────────────────────────── workspace sweeps ─────────────────────────────

/// A share of a sweep: blocks of [`WorkspaceOptions::chunk`] consecutive samples, block `j`
/// belonging to shard `j % count`. Every block is solved the same way in every sharding, so
/// merged shards equal the unsharded run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard (0-based).
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = StudyError;
    /// Parse `k/N` (0 ≤ k < N).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || StudyError::Invalid(format!("shard `{s}`: expected k/N with 0 <= k < N"));
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = k.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

/// Options of [`workspace`].
#[derive(Debug, Clone)]
pub struct WorkspaceOptions {
    /// Samples in the whole sweep (all shards).
    pub samples: usize,
    /// Method name.
    pub method: String,
    /// Input sampled (`None`: the method's [`natural_input`]).
    pub input: Option<Input>,
    /// Largest shortening sampled (fraction).
    pub max_fraction: f64,
    /// Largest tension sampled, as a multiple of the file's (1 N when it gives none).
    pub tension_factor: f64,
    /// This run's share.
    pub shard: Option<Shard>,
    /// Samples per block (warm starts stay inside a block).
    pub chunk: usize,
    /// Progress bar on a terminal.
    pub progress: bool,
}

impl Default for WorkspaceOptions {
    fn default() -> Self {
        WorkspaceOptions {
            samples: 1000,
            method: "geometric".into(),
            input: None,
            max_fraction: 0.10,
            tension_factor: 3.0,
            shard: None,
            chunk: 32,
            progress: false,
        }
    }
}

/// One solved sample.
#[derive(Debug, Clone)]
pub struct WorkspaceSample {
    /// Index in the whole sweep.
    pub index: usize,
    /// Input of every sampled cable (fraction or N).
    pub inputs: Vec<f64>,
    /// Outcome status.
    pub status: String,
    /// Iterations.
    pub iterations: usize,
    /// Tip [m] when `ok`.
    pub tip: Option<Vector3<f64>>,
}

/// Result of [`workspace`].
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Method.
    pub method: String,
    /// Input sampled.
    pub input: Input,
    /// Names of the sampled cables.
    pub cables: Vec<String>,
    /// The samples of this shard, by index.
    pub samples: Vec<WorkspaceSample>,
    /// Wall time of the sweep [s].
    pub elapsed_s: f64,
}

impl Workspace {
    /// Solves per second of wall time.
    pub fn throughput(&self) -> f64 {
        self.samples.len() as f64 / self.elapsed_s.max(1e-12)
    }
}

/// Radical inverse of `i` in base `b` (van der Corput), the Halton sequence's coordinate.
pub fn radical_inverse(mut i: usize, b: usize) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f /= b as f64;
        r += f * (i % b) as f64;
        i /= b;
    }
    r
}

const PRIMES: [usize; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

/// Solve `samples` Halton points of the driven cables' inputs (every cable with an input in
/// the file; others free), this shard's blocks only, blocks in parallel.
pub fn workspace(model: &Model, opts: &WorkspaceOptions) -> Result<Workspace, StudyError> {
    let input = opts.input.unwrap_or_else(|| natural_input(&opts.method));
    let solver = study_method(&opts.method, input)?;
    let cables: Vec<usize> = (0..model.robot.cables.len())
        .filter(|&c| model.actuation.cables.get(c).is_some_and(|d| !d.is_free()))
        .collect();
    if cables.is_empty() || cables.len() > PRIMES.len() {
        return Err(StudyError::Invalid(format!(
            "workspace sampling needs 1 to {} cables with inputs, `{}` has {}",
            PRIMES.len(),
            model.robot.name,
            cables.len()
        )));
    }
    let maxes: Vec<f64> = cables
        .iter()
        .map(|&c| max_input(model, c, input, opts.max_fraction, opts.tension_factor))
        .collect();
    let chunk = opts.chunk.max(1);
    let blocks: Vec<usize> = (0..opts.samples.div_ceil(chunk))
        .filter(|j| opts.shard.is_none_or(|s| j % s.count == s.index))
        .collect();
    let count: usize = blocks
        .iter()
        .map(|j| chunk.min(opts.samples - j * chunk))
        .sum();
    let bar = progress_bar(count as u64, opts.progress, &opts.method);
    let scene = Scene::empty();
    let start = Instant::now();
    let solved: Vec<Vec<WorkspaceSample>> = blocks
        .par_iter()
        .map(|&j| {
            let mut done: Vec<(Vec<f64>, Shape)> = vec![];
            let mut out = vec![];
            for i in j * chunk..((j + 1) * chunk).min(opts.samples) {
                let inputs: Vec<f64> = (0..cables.len())
                    .map(|k| maxes[k] * radical_inverse(i, PRIMES[k]))
                    .collect();
                let values: Vec<(usize, f64)> =
                    cables.iter().copied().zip(inputs.iter().copied()).collect();
                let act = actuation_for(model, input, &values);
                // Warm start: the nearest solved sample of this block (relative input distance).
                let warm = done
                    .iter()
                    .min_by(|(x, _), (y, _)| {
                        let d = |v: &Vec<f64>| {
                            v.iter()
                                .zip(&inputs)
                                .zip(&maxes)
                                .map(|((p, q), m)| ((p - q) / m.max(1e-300)).powi(2))
                                .sum::<f64>()
                        };
                        d(x).total_cmp(&d(y))
                    })
                    .map(|(_, s)| s);
                let o = outcome(solver.solve(&model.robot, &act, &scene, warm));
                bar.inc(1);
                let tip = o.shape.as_ref().map(|s| s.tip());
                if let Some(s) = o.shape {
                    done.push((inputs.clone(), s));
                }
                out.push(WorkspaceSample {
                    index: i,
                    inputs,
                    status: o.status,
                    iterations: o.iterations,
                    tip,
                });
            }
            out
        })
        .collect();
    bar.finish_and_clear();
    Ok(Workspace {
        method: solver.name().to_string(),
        input,
        cables: cables
            .iter()
            .map(|&c| model.robot.cables[c].name.clone())
            .collect(),
        samples: solved.into_iter().flatten().collect(),
        elapsed_s: start.elapsed().as_secs_f64(),
    })
}

/// CSV of a workspace sweep: `sample,<cable>_<input>...,tip_x_m,tip_y_m,tip_z_m,status,iterations`,
/// rows by sample index. Deterministic: the same samples give the same bytes.
pub fn workspace_csv(ws: &Workspace) -> String {
    let mut s = String::from("sample");
    for c in &ws.cables {
        s += &format!(",{c}_{}", ws.input.csv_name());
    }
    s += ",tip_x_m,tip_y_m,tip_z_m,status,iterations\n";
    let mut samples: Vec<&WorkspaceSample> = ws.samples.iter().collect();
    samples.sort_by_key(|x| x.index);
    for x in samples {
        s += &x.index.to_string();
        for v in &x.inputs {
            s += &format!(",{}", num(*v));
        }
        let t = x.tip.unwrap_or(Vector3::repeat(f64::NAN));
        s += &format!(
            ",{},{},{},{},{}\n",
            num(t.x),
            num(t.y),
            num(t.z),
            x.status,
            x.iterations
        );
    }
    s
}

/// Merge workspace CSVs (shards of one sweep): same header required, rows sorted by sample
/// index, a sample present twice is an error.
pub fn merge_csv(texts: &[String]) -> Result<String, StudyError> {
    let mut header: Option<&str> = None;
    let mut rows: Vec<(usize, &str)> = vec![];
    for (f, t) in texts.iter().enumerate() {
        let mut lines = t.lines();
        let h = lines
            .next()
            .ok_or_else(|| StudyError::Invalid(format!("input {} is empty", f + 1)))?;
        match header {
            None => header = Some(h),
            Some(h0) if h0 != h => {
                return Err(StudyError::Invalid(format!(
                    "input {} has header `{h}`, expected `{h0}`",
                    f + 1
                )))
            }
            _ => {}
        }
        for (ln, l) in lines.enumerate() {
            if l.is_empty() {
                continue;
            }
            let idx = l
                .split(',')
                .next()
                .and_then(|x| x.parse::<usize>().ok())
                .ok_or_else(|| {
                    StudyError::Invalid(format!("input {} line {}: no sample index", f + 1, ln + 2))
                })?;
            rows.push((idx, l));
        }
    }
    rows.sort_by_key(|r| r.0);
    if let Some(w) = rows.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(StudyError::Invalid(format!(
            "sample {} appears in more than one input",
            w[0].0
        )));
    }
    let mut out = format!("{}\n", header.unwrap_or("sample"));
    for (_, l) in rows {
        out += l;
        out.push('\n');
    }
    Ok(out)
}
