//! How well `auto` ([`crate::method::auto`]) keeps its promise: on seeded random robots
//! ([`super::random`]) and tolerances, the answer's true tip distance from the converged rod
//! (80 RK4 steps per section, shooting to 1e-11 N, the same inputs) against the tolerance and
//! against the answer's own estimate, and its cost against the cheapest rung of the ladders
//! that met the tolerance in truth (found by hindsight: every rung solved and measured).

use super::random::random_model;
use super::{num, StudyError};
use crate::error::SolveError;
use crate::method::run::SolveRequest;
use crate::method::{MethodKind, Settings};
use crate::progress::ProgressHandle;
use crate::shape::Shape;
use std::time::Instant;

/// Options of [`auto_study`].
#[derive(Debug, Clone)]
pub struct AutoStudyOptions {
    /// Random robots, seeds `first_seed..first_seed + robots`.
    pub robots: u64,
    /// The first seed.
    pub first_seed: u64,
    /// Tolerances asked of `auto` \[m\].
    pub tolerances: Vec<f64>,
    /// Timed runs per solve (the median is the cost).
    pub repeats: usize,
    /// Where progress goes (one step per robot).
    pub progress: ProgressHandle,
}

impl Default for AutoStudyOptions {
    fn default() -> Self {
        AutoStudyOptions {
            robots: 200,
            first_seed: 0,
            tolerances: vec![1e-4, 1e-3],
            repeats: 3,
            progress: ProgressHandle::none(),
        }
    }
}

/// One robot at one tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct AutoStudyRow {
    /// The robot's seed.
    pub seed: u64,
    /// The tolerance \[m\].
    pub tolerance: f64,
    /// What `auto` chose (`energy sub-arcs=2`), or the failure.
    pub chosen: String,
    /// Whether its estimate met the tolerance.
    pub met: bool,
    /// Its true tip distance from the converged rod \[m\].
    pub true_error: f64,
    /// Its estimate \[m\] (discretization + model, the model part 0 where unknown).
    pub estimate: f64,
    /// Solves `auto` ran (answers and estimates; 0 when it failed).
    pub solves: usize,
    /// Median wall time of `auto` (every solve it ran) \[s\].
    pub cost_s: f64,
    /// The cheapest rung whose answer was within the tolerance in truth, or empty.
    pub hindsight: String,
    /// Median wall time of that one solve \[s\] (NaN without one).
    pub hindsight_cost_s: f64,
}

/// The median wall time of `f` over `repeats` runs, and its last result.
fn timed<T>(repeats: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let t = Instant::now();
    let mut last = f();
    let mut times = vec![t.elapsed().as_secs_f64()];
    for _ in 1..repeats {
        let t = Instant::now();
        last = f();
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], last)
}

/// Every rung of the ladders `auto` walks, solved once each: (label, cost, tip error).
fn rungs(model: &crate::Model, truth: &Shape, repeats: usize) -> Vec<(String, f64, f64)> {
    let mut out = vec![];
    for kind in [MethodKind::Energy, MethodKind::Cosserat] {
        let name = if kind == MethodKind::Energy {
            "sub-arcs"
        } else {
            "rk4-steps"
        };
        for (_, pairs) in kind.info().resolutions {
            let Some((_, n)) = pairs.iter().find(|(k, _)| *k == name) else {
                continue;
            };
            let request = SolveRequest::new(kind).with_settings(
                Settings::new()
                    .with("control", "displacement")
                    .with(name, n),
            );
            let (cost, r) = timed(repeats, || request.run(model));
            if let Ok(s) = r {
                out.push((
                    format!("{kind} {name}={n}"),
                    cost,
                    s.shape.tip_distance(truth),
                ));
            }
        }
    }
    out
}

/// The options refused by name before any work: the robots and repeats within their counts
/// ([`crate::counts`]), the last seed a `u64`, and each tolerance a positive length asked once
/// (the same tolerance twice would count each robot twice).
fn check(opts: &AutoStudyOptions) -> Result<std::ops::Range<u64>, SolveError> {
    let robots = usize::try_from(opts.robots).unwrap_or(usize::MAX);
    crate::counts::STUDY_AUTO_ROBOTS.check(robots)?;
    crate::counts::STUDY_AUTO_REPEATS.check(opts.repeats)?;
    let bad = |field: &str, reason: String| SolveError::InvalidInput {
        field: field.into(),
        reason,
    };
    let end = opts.first_seed.checked_add(opts.robots).ok_or_else(|| {
        bad(
            "first_seed",
            format!(
                "{} robots from seed {} run past the largest seed {}",
                opts.robots,
                opts.first_seed,
                u64::MAX
            ),
        )
    })?;
    if opts.tolerances.is_empty() {
        return Err(bad("tolerances", "name at least one tolerance".into()));
    }
    for (k, &t) in opts.tolerances.iter().enumerate() {
        crate::model::bounds::TIP_DISTANCE.check("tolerances", t)?;
        if opts.tolerances[..k].contains(&t) {
            return Err(bad(
                "tolerances",
                format!("{t} m is asked twice (each robot would count twice)"),
            ));
        }
    }
    Ok(opts.first_seed..end)
}

/// The study (module docs): one row per robot with a converged reference and tolerance.
/// Options out of range are refused by name before any solve ([`SolveError::InvalidInput`]).
pub fn auto_study(opts: &AutoStudyOptions) -> Result<Vec<AutoStudyRow>, StudyError> {
    let seeds = check(opts)?;
    let bar = &opts.progress;
    bar.start("auto", Some(opts.robots));
    let mut rows = vec![];
    for seed in seeds {
        bar.advance(1);
        let model = random_model(seed).map_err(|e| StudyError::Invalid(e.to_string()))?;
        let reference = SolveRequest::new(MethodKind::Cosserat).with_settings(
            Settings::new()
                .with("control", "displacement")
                .with("rk4-steps", 80)
                .with("tolerance", 1e-11),
        );
        let Ok(truth) = reference.run(&model) else {
            continue;
        };
        let ladder = rungs(&model, &truth.shape, opts.repeats);
        for &t in &opts.tolerances {
            let (cost, r) = timed(opts.repeats, || SolveRequest::auto(t).run(&model));
            let hind = ladder
                .iter()
                .filter(|(_, _, e)| *e <= t)
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let (hindsight, hindsight_cost_s) =
                hind.map_or((String::new(), f64::NAN), |h| (h.0.clone(), h.1));
            let row = match r {
                Ok(s) => {
                    let a = s.shape.report.auto.clone();
                    let e = s.shape.report.error_estimate.clone();
                    AutoStudyRow {
                        seed,
                        tolerance: t,
                        chosen: a
                            .as_ref()
                            .map_or_else(String::new, |a| format!("{} {}", a.method, a.setting)),
                        solves: a.as_ref().map_or(0, |a| a.solves),
                        met: a.is_some_and(|a| a.met),
                        true_error: s.shape.tip_distance(&truth.shape),
                        estimate: e.map_or(f64::NAN, |e| e.known_parts_m()),
                        cost_s: cost,
                        hindsight,
                        hindsight_cost_s,
                    }
                }
                Err(e) => AutoStudyRow {
                    seed,
                    tolerance: t,
                    chosen: format!("error: {}", e.kind()),
                    met: false,
                    solves: 0,
                    true_error: f64::NAN,
                    estimate: f64::NAN,
                    cost_s: cost,
                    hindsight,
                    hindsight_cost_s,
                },
            };
            rows.push(row);
        }
    }
    bar.finish();
    Ok(rows)
}

/// The study's verdict at one tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct AutoSummary {
    /// The tolerance \[m\].
    pub tolerance: f64,
    /// Answers (robots with a reference).
    pub answers: usize,
    /// Fraction of answers whose true error is within the tolerance.
    pub within: f64,
    /// Fraction of answers whose estimate bounds their true error.
    pub bounded: f64,
    /// Median of auto's cost over the hindsight-cheapest cost (answers that have one; NaN
    /// when none has: no rung was within the tolerance in truth).
    pub median_cost_ratio: f64,
}

/// One summary per tolerance of `rows`.
pub fn summarize(rows: &[AutoStudyRow]) -> Vec<AutoSummary> {
    let mut tols: Vec<f64> = rows.iter().map(|r| r.tolerance).collect();
    tols.sort_by(f64::total_cmp);
    tols.dedup();
    tols.into_iter()
        .map(|t| {
            let at: Vec<&AutoStudyRow> = rows.iter().filter(|r| r.tolerance == t).collect();
            let n = at.len().max(1) as f64;
            let within = at.iter().filter(|r| r.true_error <= t).count() as f64 / n;
            let bounded = at
                .iter()
                .filter(|r| r.true_error <= r.estimate.max(1e-9))
                .count() as f64
                / n;
            let mut ratios: Vec<f64> = at
                .iter()
                .map(|r| r.cost_s / r.hindsight_cost_s)
                .filter(|x| x.is_finite())
                .collect();
            ratios.sort_by(f64::total_cmp);
            AutoSummary {
                tolerance: t,
                answers: at.len(),
                within,
                bounded,
                median_cost_ratio: ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN),
            }
        })
        .collect()
}

/// CSV of the rows:
/// `seed,tolerance_m,chosen,met,solves,true_error_m,estimate_m,cost_s,hindsight,hindsight_cost_s`
/// (a choice with a comma, `energy sub-arcs=4, shear=on`, in quotes).
pub fn auto_study_csv(rows: &[AutoStudyRow]) -> String {
    let mut s = String::from(
        "seed,tolerance_m,chosen,met,solves,true_error_m,estimate_m,cost_s,hindsight,\
         hindsight_cost_s\n",
    );
    let quoted = |t: &str| {
        if t.contains(',') {
            format!("\"{t}\"")
        } else {
            t.to_string()
        }
    };
    for r in rows {
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{}\n",
            r.seed,
            num(r.tolerance),
            quoted(&r.chosen),
            r.met,
            r.solves,
            num(r.true_error),
            num(r.estimate),
            num(r.cost_s),
            quoted(&r.hindsight),
            num(r.hindsight_cost_s)
        );
    }
    s
}
