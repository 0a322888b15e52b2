//! Speed against accuracy: every method at each of its resolution settings, timed and
//! measured against a converged rod driven by the same kind of input.

use super::{
    all_method_names, method_kinds, num, outcome, reference, reference_displacement,
    resolution_settings, Input, Status, StudyError,
};
use crate::error::SolveError;
use crate::method::run::{timed, SolveRequest};
use crate::method::{MethodKind, Settings, Solver};
use crate::model::scene::Scene;
use crate::model::Model;
use crate::progress::ProgressHandle;
use crate::shape::Shape;

/// One method at one resolution setting.
pub struct Variant {
    /// Method name.
    pub method: String,
    /// Setting label (e.g. `rk4 12/section`, `adaptive 1e-5`, `default`).
    pub setting: String,
    /// The input that drives it.
    pub input: Input,
    /// The configured solver.
    pub solver: Solver,
}

/// The resolution settings of a method for [`speed_accuracy`], from the registry.
pub fn variants(kind: MethodKind) -> Result<Vec<Variant>, SolveError> {
    kind.info()
        .resolutions
        .iter()
        .map(|(label, pairs)| {
            let s = resolution_settings(pairs);
            Ok(Variant {
                method: kind.name().to_string(),
                setting: label.to_string(),
                input: kind.input_with(&s),
                solver: SolveRequest::new(kind).with_settings(s).solver()?,
            })
        })
        .collect()
}

/// One row of the speed–accuracy study.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedAccuracyRow {
    /// Method name.
    pub method: String,
    /// Setting label.
    pub setting: String,
    /// How the solve ended.
    pub status: Status,
    /// Median wall time of one solve \[s\] (NaN on failure).
    pub median_time_s: f64,
    /// Tip distance to the reference \[m\] (NaN on failure).
    pub tip_error_m: f64,
    /// RMS distance of the disk positions to the reference \[m\] (NaN on failure).
    pub rms_error_m: f64,
    /// Iterations of one solve.
    pub iterations: usize,
    /// Which reference the errors are measured against: `force` ([`reference()`]) or
    /// `displacement` ([`reference_displacement`]).
    pub reference: String,
}

/// Options of [`speed_accuracy`].
#[derive(Debug, Clone)]
pub struct SpeedAccuracyOptions {
    /// Solves per setting; the median time is reported.
    pub repeats: usize,
    /// Methods to study (default: every registered method and [`AUTO`]); [`AUTO`] adds a row
    /// per tolerance of [`AUTO_TOLERANCES`].
    pub methods: Vec<String>,
    /// Where progress goes (one step per method variant; the note names the variant).
    pub progress: ProgressHandle,
}

impl Default for SpeedAccuracyOptions {
    fn default() -> Self {
        SpeedAccuracyOptions {
            repeats: 5,
            methods: all_method_names()
                .into_iter()
                .chain([AUTO.to_string()])
                .collect(),
            progress: ProgressHandle::none(),
        }
    }
}

/// Time every variant of every method on the model's actuation and measure its error against
/// [`reference()`]. Methods that cannot solve the model get a row with the failure kind. The
/// solves run one at a time (timings are not disturbed by parallel work of the study itself).
pub fn speed_accuracy(
    model: &Model,
    opts: &SpeedAccuracyOptions,
) -> Result<Vec<SpeedAccuracyRow>, StudyError> {
    crate::counts::STUDY_REPEATS.check(opts.repeats)?;
    let scene = Scene::empty();
    let checked = |rod: crate::method::cosserat::Cosserat| Solver::new(Box::new(rod), 1);
    let reference = checked(reference()).solve(&model.robot, &model.actuation, &scene, None)?;
    // Without displacement inputs the displacement-driven methods fail anyway.
    let reference_disp = checked(reference_displacement())
        .solve(&model.robot, &model.actuation, &scene, None)
        .ok();
    let refs = (&reference, reference_disp.as_ref());
    let (want_auto, names): (Vec<String>, Vec<String>) =
        opts.methods.iter().cloned().partition(|m| m == AUTO);
    let all = method_kinds(&names)?
        .into_iter()
        .map(variants)
        .collect::<Result<Vec<_>, _>>()?;
    let autos: &[f64] = if want_auto.is_empty() {
        &[]
    } else {
        &AUTO_TOLERANCES
    };
    let bar = &opts.progress;
    bar.start(
        "speed-accuracy",
        Some((all.iter().map(Vec::len).sum::<usize>() + autos.len()) as u64),
    );
    let mut rows = vec![];
    for v in all.iter().flatten() {
        bar.note(|| format!("{} {}", v.method, v.setting));
        bar.advance(1);
        let (times, last) = timed(opts.repeats, || {
            v.solver.solve_unchecked(crate::method::SolveInput {
                robot: &model.robot,
                act: &model.actuation,
                scene: &scene,
                warm: None,
            })
        });
        let by_disp = v.input == Input::Shortening;
        rows.push(row(
            model, &v.method, &v.setting, times, last, by_disp, refs,
        ));
    }
    for &t in autos {
        bar.note(|| format!("auto {:.3} mm", t * 1e3));
        bar.advance(1);
        let settings = Settings::new();
        let (times, last) = timed(opts.repeats, || {
            crate::method::auto::choose(&model.robot, &model.actuation, &scene, t, &settings)
        });
        // The choice's input decides which rod it is judged against.
        let chosen = last
            .as_ref()
            .ok()
            .and_then(|s| crate::method::auto::settled(s, &settings));
        let by_disp = chosen
            .as_ref()
            .is_some_and(|r| r.method.input_with(&r.settings) == Input::Shortening);
        let setting = match (&last, &chosen) {
            (Ok(s), Some(_)) => format!(
                "tol {} mm: {} {}",
                t * 1e3,
                s.method,
                s.report.auto.as_ref().map_or("", |a| a.setting.as_str())
            ),
            _ => format!("tol {} mm", t * 1e3),
        };
        rows.push(row(model, AUTO, &setting, times, last, by_disp, refs));
    }
    bar.finish();
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

/// The pseudo-method name that adds `auto`'s choices to the study (one row per tolerance of
/// [`AUTO_TOLERANCES`]), timed with the search it runs (estimates included).
pub const AUTO: &str = "auto";

/// The tolerances \[m\] at which `auto` is studied: 1 mm, 0.1 mm, 0.01 mm.
pub const AUTO_TOLERANCES: [f64; 3] = [1e-3, 1e-4, 1e-5];

/// One row: the answer checked, its errors against the rod driven by the same input.
fn row(
    model: &Model,
    method: &str,
    setting: &str,
    times: Vec<f64>,
    last: Result<Shape, SolveError>,
    by_disp: bool,
    (force, disp): (&Shape, Option<&Shape>),
) -> SpeedAccuracyRow {
    let o = outcome(crate::check::checked(&model.robot, last));
    let refer = if by_disp { disp } else { Some(force) };
    let (tip, rms) = match (&o.shape, refer) {
        (Some(s), Some(r)) => (s.tip_distance(r), s.rms_distance(r).unwrap_or(f64::NAN)),
        _ => (f64::NAN, f64::NAN),
    };
    SpeedAccuracyRow {
        method: method.to_string(),
        setting: setting.to_string(),
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
    }
}

/// Pareto flags of speed–accuracy rows (time against RMS error), one front per reference:
/// errors measured against the force-driven and the displacement-driven rod are different
/// quantities, so a row is on the front of the rows judged against the same reference.
pub fn speed_accuracy_front(rows: &[SpeedAccuracyRow]) -> Vec<bool> {
    let mut flags = vec![false; rows.len()];
    let mut refs: Vec<&str> = rows.iter().map(|r| r.reference.as_str()).collect();
    refs.sort_unstable();
    refs.dedup();
    for reference in refs {
        let idx: Vec<usize> = (0..rows.len())
            .filter(|&i| rows[i].reference == reference)
            .collect();
        let pts: Vec<(f64, f64)> = idx
            .iter()
            .map(|&i| (rows[i].median_time_s, rows[i].rms_error_m))
            .collect();
        for (k, on) in pareto_front(&pts).into_iter().enumerate() {
            flags[idx[k]] = on;
        }
    }
    flags
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
