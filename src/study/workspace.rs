//! Workspace sweeps: Halton samples of the driven cables' inputs, solved in parallel blocks,
//! shardable and mergeable.

use super::stability::{actuation_for, max_input};
use super::{natural_input, num, outcome, study_method, Input, Status, StudyError};
use crate::method::MethodKind;
use crate::model::scene::Scene;
use crate::model::Model;
use crate::progress::ProgressHandle;
use crate::shape::Shape;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::time::Instant;

/// A share of a sweep: blocks of [`WorkspaceOptions::chunk`] consecutive samples, block `j`
/// belonging to shard `j % count`. Every block is solved the same way in every sharding, so
/// merged shards equal the unsharded run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
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
    /// Input sampled (`None`: the method's [`natural_input`](super::natural_input)).
    pub input: Option<Input>,
    /// Largest shortening sampled (fraction).
    pub max_fraction: f64,
    /// Largest tension sampled, as a multiple of the file's (1 N when it gives none).
    pub tension_factor: f64,
    /// This run's share.
    pub shard: Option<Shard>,
    /// Samples per block (warm starts stay inside a block).
    pub chunk: usize,
    /// Where progress goes (one step per sample solved).
    pub progress: ProgressHandle,
}

impl Default for WorkspaceOptions {
    fn default() -> Self {
        WorkspaceOptions {
            samples: 1000,
            method: MethodKind::DEFAULT.name().into(),
            input: None,
            max_fraction: 0.10,
            tension_factor: 3.0,
            shard: None,
            chunk: 32,
            progress: ProgressHandle::none(),
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
    pub status: Status,
    /// Iterations.
    pub iterations: usize,
    /// Tip \[m\] when `ok`.
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
    /// Wall time of the sweep \[s\].
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
    super::stability::check_ranges(opts.max_fraction, opts.tension_factor)?;
    let kind: MethodKind = opts.method.parse()?;
    let input = opts.input.unwrap_or_else(|| natural_input(kind));
    let solver = study_method(kind, input)?;
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
    crate::counts::STUDY_SAMPLES.check(opts.samples)?;
    let chunk = crate::counts::STUDY_CHUNK.check(opts.chunk)?;
    let blocks: Vec<usize> = (0..opts.samples.div_ceil(chunk))
        .filter(|j| opts.shard.is_none_or(|s| j % s.count == s.index))
        .collect();
    let count: usize = blocks
        .iter()
        .map(|j| chunk.min(opts.samples - j * chunk))
        .sum();
    let bar = &opts.progress;
    bar.start(&opts.method, Some(count as u64));
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
                bar.advance(1);
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
    bar.finish();
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

/// The number in a workspace CSV's column `column` (as [`workspace_csv`] writes them, read
/// back by `ccrkit view --sweep` and `ccrkit study merge`), or why `text` is not one: every
/// column has a range, by its name — `sample` a whole number below the most samples
/// ([`crate::counts::STUDY_SAMPLES`]), `iterations` a whole number up to the most iterations,
/// `<cable>_shortening_fraction` within ±1 (of the cable), `<cable>_tension_n` within
/// [`crate::model::bounds::TENSION`], the tip's `tip_x_m`… within ±[`crate::shape::MAX_EXTENT`]
/// (where a shape lies), any other number within ±1e9 — so no `NaN` or `1e308` reaches a page's
/// colour scale or a merged file. An empty value is not a number (a failed sample's tip is
/// the caller's to allow).
pub fn sweep_value(column: &str, text: &str) -> Result<f64, String> {
    let (lo, hi, whole, what) =
        column_range(column).unwrap_or((-1e9, 1e9, false, "a number of this column"));
    let v = text.trim();
    match v.parse::<f64>() {
        Ok(x) if x.is_finite() && (lo..=hi).contains(&x) && (!whole || x.fract() == 0.0) => Ok(x),
        _ => Err(format!(
            "`{v}` is not {what}: {} from {lo:e} to {hi:e}",
            if whole { "a whole number" } else { "a number" }
        )),
    }
}

/// The range of a workspace number column, by its name ([`sweep_value`]): lowest, highest,
/// whole numbers only, what it holds; `None` for a column that is not one of them.
fn column_range(column: &str) -> Option<(f64, f64, bool, &'static str)> {
    Some(match column {
        "sample" => (
            0.0,
            crate::counts::STUDY_SAMPLES.max as f64,
            true,
            "a sample index",
        ),
        "iterations" => (
            0.0,
            crate::method::settings::MAX_ITERATIONS as f64,
            true,
            "an iteration count",
        ),
        "tip_x_m" | "tip_y_m" | "tip_z_m" => {
            let e = crate::shape::MAX_EXTENT;
            (-e, e, false, "a tip coordinate [m] (where a shape lies)")
        }
        c if c.ends_with("_shortening_fraction") => (-1.0, 1.0, false, "a fraction of the cable"),
        c if c.ends_with("_tension_n") => {
            let t = crate::model::bounds::TENSION;
            (t.lo, t.hi, false, "a tension [N]")
        }
        _ => return None,
    })
}

/// True when `column` holds numbers in every workspace CSV (its values are checked by
/// [`sweep_value`] whatever they are; another column is text when any value is not a number).
pub fn sweep_column_is_numeric(column: &str) -> bool {
    column_range(column).is_some()
}

/// One row of a workspace CSV checked column by column ([`sweep_value`]: a workspace number
/// column, or any value that reads as a number; a failed sample's tip is empty): the error
/// names the column.
fn check_sweep_row(header: &[&str], fields: &[&str]) -> Result<(), String> {
    if fields.len() != header.len() {
        return Err(format!(
            "{} fields, the header has {}",
            fields.len(),
            header.len()
        ));
    }
    for (c, v) in header.iter().zip(fields) {
        let tip = c.starts_with("tip_");
        let number = sweep_column_is_numeric(c) || v.trim().parse::<f64>().is_ok();
        if number && !(tip && v.trim().is_empty()) {
            sweep_value(c, v).map_err(|e| format!("column `{c}`: {e}"))?;
        }
    }
    Ok(())
}

/// Merge workspace CSVs (shards of one sweep): same header required, every row's values in
/// their columns' ranges ([`sweep_value`]), rows sorted by sample index, a sample present twice
/// is an error.
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
        let names: Vec<&str> = h.split(',').map(str::trim).collect();
        for (ln, l) in lines.enumerate() {
            if l.is_empty() {
                continue;
            }
            let at =
                |e: String| StudyError::Invalid(format!("input {} line {}: {e}", f + 1, ln + 2));
            let fields: Vec<&str> = l.split(',').collect();
            check_sweep_row(&names, &fields).map_err(at)?;
            let idx = fields
                .first()
                .and_then(|x| x.parse::<usize>().ok())
                .ok_or_else(|| at("no sample index".into()))?;
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
