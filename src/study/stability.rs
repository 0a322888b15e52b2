//! Stability maps: where each method converges over a grid of two cables' inputs, cold and
//! with continuation along the rows.

use super::{
    all_method_names, method_kinds, natural_input, num, outcome, study_method, Input, Status,
    StudyError,
};
use crate::model::actuation::{Actuation, Shortening};
use crate::model::scene::Scene;
use crate::model::Model;
use crate::progress::ProgressHandle;
use crate::shape::Shape;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Options of [`stability`].
#[derive(Debug, Clone)]
pub struct StabilityOptions {
    /// Grid points per axis (from 0 to the maximum, inclusive).
    pub grid: usize,
    /// Largest shortening swept (fraction of the cable length).
    pub max_fraction: f64,
    /// Largest tension swept, as a multiple of the file's tension (1 N when it gives none).
    pub tension_factor: f64,
    /// Input swept: `None` = each method's [`natural_input`](super::natural_input).
    pub input: Option<Input>,
    /// Methods (default: every registered method).
    pub methods: Vec<String>,
    /// Where progress goes (one step per grid point solved).
    pub progress: ProgressHandle,
}

impl Default for StabilityOptions {
    fn default() -> Self {
        StabilityOptions {
            grid: 40,
            max_fraction: 0.18,
            tension_factor: 10.0,
            input: None,
            methods: all_method_names(),
            progress: ProgressHandle::none(),
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
    pub status: Status,
    /// Iterations.
    pub iterations: usize,
    /// Residual.
    pub residual: f64,
    /// Tip \[m\] when `ok`.
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

pub(super) fn max_input(
    model: &Model,
    c: usize,
    input: Input,
    max_fraction: f64,
    factor: f64,
) -> f64 {
    match input {
        Input::Shortening => max_fraction,
        Input::Tension => factor * model.actuation.tension(c).unwrap_or(1.0),
    }
}

/// The sweep's ranges, checked before any solve (before this, `--max-percent nan` printed `NaN`,
/// `1e308` and `--tension-factor inf` ran without end): the largest shortening a fraction in
/// (0, 1), the tension factor in (0, 1000].
pub(super) fn check_ranges(max_fraction: f64, factor: f64) -> Result<(), StudyError> {
    if !(max_fraction > 0.0 && max_fraction < 1.0) {
        return Err(StudyError::Invalid(format!(
            "invalid option `max-percent`: must lie in (0, 100), got {}",
            max_fraction * 100.0
        )));
    }
    if !(factor > 0.0 && factor <= 1e3) {
        return Err(StudyError::Invalid(format!(
            "invalid option `tension-factor`: must lie in (0, 1000], got {factor}"
        )));
    }
    Ok(())
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
    check_ranges(opts.max_fraction, opts.tension_factor)?;
    let [ca, cb] = swept_cables(model)?;
    let n = crate::counts::STUDY_GRID.check(opts.grid)?;
    let kinds = method_kinds(&opts.methods)?;
    let total = (kinds.len() * 2 * n * n) as u64;
    let bar = &opts.progress;
    bar.start("stability", Some(total));
    let scene = Scene::empty();
    let mut points = vec![];
    for kind in kinds {
        let name = kind.name().to_string();
        let input = opts.input.unwrap_or_else(|| natural_input(kind));
        let solver = study_method(kind, input)?;
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
                            bar.advance(1);
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
    bar.finish();
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
    /// The input swept.
    pub input: Input,
    /// Points that converged.
    pub ok: usize,
    /// Points in all.
    pub total: usize,
    /// Failures by kind.
    pub failures: Vec<(String, usize)>,
    /// The failed point closest to the origin (max-norm of the grid indices), as (a, b).
    pub first_failure: Option<(f64, f64)>,
}

impl StabilitySummary {
    /// One console line: method, mode, converged points, failures by kind, and the first
    /// failure as the inputs of the swept `cables` (percent shortening or newtons).
    pub fn line(&self, cables: &[String; 2]) -> String {
        let fails: Vec<String> = self
            .failures
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect();
        let mode = if self.continuation {
            "continuation"
        } else {
            "cold"
        };
        let failed = if fails.is_empty() {
            String::new()
        } else {
            format!(", failed: {}", fails.join(", "))
        };
        let value = |x: f64| match self.input {
            Input::Shortening => format!("{:.2} %", 100.0 * x),
            Input::Tension => format!("{x:.3} N"),
        };
        let first = self
            .first_failure
            .map(|(a, b)| {
                format!(
                    ", first failure at {} {}, {} {}",
                    cables[0],
                    value(a),
                    cables[1],
                    value(b)
                )
            })
            .unwrap_or_default();
        format!(
            "{:<20} {:<13} {:>5}/{:<5} ok{failed}{first}",
            self.method, mode, self.ok, self.total
        )
    }
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
                    input: p.input,
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
        if p.status.is_ok() {
            s.ok += 1;
            continue;
        }
        match s.failures.iter_mut().find(|(k, _)| *k == p.status.name()) {
            Some(f) => f.1 += 1,
            None => s.failures.push((p.status.name().to_string(), 1)),
        }
        let key = |(a, b): (usize, usize)| (a.max(b), a + b);
        if first[idx].is_none_or(|f| key((p.ia, p.ib)) < key(f)) {
            first[idx] = Some((p.ia, p.ib));
            s.first_failure = Some((p.a, p.b));
        }
    }
    out
}
