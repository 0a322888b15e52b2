//! Calibration: fit named parameters ([`super::params`]) to measured tips by
//! Levenberg–Marquardt on the benchmark's metric.
//!
//! **Residual.** For parameters `x` every row is solved (warm-started, see below) and the
//! marker `s_i(x)` taken in the measurement frame; the residual is the mean-offset-aligned
//! error `r_i = s_i − mean_j(s_j − m_j) − m_i` (3 per row), so `½|r|²` is `N/2` times the
//! squared RMSE the data README reports. The alignment absorbs the base position; the fitted
//! model's `base_position` is moved by the final mean offset, so its predictions need no
//! alignment on the training data.
//!
//! **Jacobian** (`calibrate/jacobian.rs`): from the solver's exact tip sensitivities where the
//! method reports them (energy), else forward differences of warm-started solves.
//!
//! **Step.** Marquardt's scaled damping (Marquardt 1963; Nocedal & Wright, *Numerical
//! Optimization*, 2nd ed., §10.3): `(JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr` in scaled variables
//! `x/scale`, the trial point projected onto the parameters' bounds (compliance and
//! backlash ≥ 0, gain ≥ 10⁻³: a projected Levenberg–Marquardt step, Kanzow, Yamashita &
//! Fukushima 2004, *J. Comput. Appl. Math.* 172; without it a parameter at its bound whose
//! free step points outside — a backlash of 0 the data would make negative — rejects every
//! step, whatever the damping); a step that lowers the cost is taken and `λ /= 3`, else `λ *= 4`. A trial at which
//! any row fails to solve counts as a rise. Stops when the relative decrease of the cost falls
//! below [`FitOptions::tolerance`], or `λ` exceeds 10¹⁰ (no descent left), or after
//! [`FitOptions::max_iterations`].
//!
//! **Uncertainty.** `cov = σ² (JᵀJ)⁻¹`, `σ² = |r|² / (3N − 3 − p)` (3 degrees of freedom per
//! file go to the alignment): the standard errors of a least-squares fit with independent,
//! equal-variance residuals (Nocedal & Wright §10.3). The residuals here are correlated
//! along a pattern (hysteresis), so these are lower bounds.
//!
//! Why hand-written rather than the `levenberg-marquardt` crate: it is built on nalgebra 0.34
//! (ccrkit is on 0.35: a second copy of nalgebra to compile and convert between), and this fit
//! needs a trial that fails (a row that does not solve) to be a rejected step, the cost per
//! iteration for the report, and the warm starts carried between evaluations; the p × p
//! damped solve (p ≤ 9 by default) is nalgebra's Cholesky.

use super::data::Dataset;
use super::params::{default_names, parse_all, Param};
use super::predict::{PredictOptions, Rows};
use super::{aligned_errors, ErrorStats};
use crate::error::SolveError;
use crate::model::hardware::directions;
use crate::model::Model;
use crate::progress::ProgressHandle;
use crate::shape::Shape;
use nalgebra::{DVector, Vector3};

/// How to fit.
#[derive(Debug, Clone)]
pub struct FitOptions {
    /// Method, settings, chunking, progress (as for predict).
    pub predict: PredictOptions,
    /// Parameter names (empty: [`default_names`]).
    pub params: Vec<String>,
    /// Most LM iterations.
    pub max_iterations: usize,
    /// Stop when an iteration lowers the cost by less than this fraction.
    pub tolerance: f64,
}

impl FitOptions {
    /// Defaults around `predict`: the default parameters, 30 iterations, tolerance 10⁻⁴ (on
    /// FTDCR v4 the last 10⁻⁴ → 10⁻⁵ iterations move the train RMSE by ≈ 0.03 mm).
    pub fn new(predict: PredictOptions) -> Self {
        FitOptions {
            predict,
            params: Vec::new(),
            max_iterations: 30,
            tolerance: 1e-4,
        }
    }

    /// Refuse a tolerance that is not a positive number or an iteration count outside
    /// [`crate::counts::FIT_ITERATIONS`], naming the field — before any row is solved, so a
    /// selection over many candidates fails once, at once, instead of once per candidate.
    pub fn check(&self) -> Result<(), SolveError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(SolveError::InvalidInput {
                field: "tolerance".into(),
                reason: format!("must be > 0, got {}", self.tolerance),
            });
        }
        crate::counts::FIT_ITERATIONS.check(self.max_iterations)?;
        Ok(())
    }
}

/// One fitted parameter.
#[derive(Debug, Clone)]
pub struct Fitted {
    /// Name.
    pub name: String,
    /// Unit (`-` or `m`).
    pub unit: &'static str,
    /// Value before the fit.
    pub initial: f64,
    /// Fitted value.
    pub value: f64,
    /// Standard error (module docs), `NaN` never: `None` when `JᵀJ` is singular.
    pub sigma: Option<f64>,
}

/// One LM iteration.
#[derive(Debug, Clone, Copy)]
pub struct Iteration {
    /// Iteration (0: the start).
    pub iteration: usize,
    /// Aligned tip RMSE \[m\] after it.
    pub rmse: f64,
    /// Damping used by the accepted step.
    pub lambda: f64,
    /// Full passes over the data so far (residual and Jacobian evaluations).
    pub passes: usize,
}

/// The outcome of [`calibrate`].
#[derive(Debug, Clone)]
pub struct FitReport {
    /// Fitted parameters.
    pub params: Vec<Fitted>,
    /// Cost per iteration.
    pub history: Vec<Iteration>,
    /// Aligned errors on the rows used, before and after.
    pub before: ErrorStats,
    /// After.
    pub after: ErrorStats,
    /// Rows used; rows left out because they did not solve at the start.
    pub rows_used: usize,
    /// Rows left out.
    pub rows_excluded: usize,
    /// Why the fit stopped.
    pub stop: String,
    /// The fitted model (base position moved by the remaining mean offset).
    pub model: Model,
    /// Wall time of the fit \[s\] (a report, not a result: it varies with the machine's load).
    pub seconds: f64,
}

/// The residual at one point: every row's shape, the aligned residuals, the mean offset.
pub(super) struct Eval {
    pub(super) shapes: Vec<Option<Shape>>,
    pub(super) r: DVector<f64>,
    pub(super) mean_offset: Vector3<f64>,
}

/// The fit's state: the rows used, their commands and measured tips, the parameters.
pub(super) struct Fitter<'a> {
    pub(super) rows: Rows,
    pub(super) base: &'a Model,
    pub(super) params: Vec<Param>,
    pub(super) commands: Vec<Vec<f64>>,
    /// Each used row's direction of motion per cable (from the whole file, in order).
    pub(super) dirs: Vec<Vec<f64>>,
    pub(super) tips: Vec<Vector3<f64>>,
    pub(super) bar: ProgressHandle,
    pub(super) passes: usize,
}

impl Fitter<'_> {
    pub(super) fn model_at(&self, x: &DVector<f64>) -> Model {
        let mut m = self.base.clone();
        for (p, v) in self.params.iter().zip(x.iter()) {
            p.set(&mut m, v * p.scale());
        }
        m
    }

    /// `x` (scaled) with every parameter moved to its nearest admissible value.
    fn project(&self, mut x: DVector<f64>) -> DVector<f64> {
        for (p, v) in self.params.iter().zip(x.iter_mut()) {
            *v = p.project(*v * p.scale()) / p.scale();
        }
        x
    }

    /// Residuals at `x` (`None` if a row fails or a value lies outside the model).
    pub(super) fn eval(
        &mut self,
        x: &DVector<f64>,
        warm: Option<&[Option<Shape>]>,
    ) -> Option<Eval> {
        let inside = self
            .params
            .iter()
            .zip(x.iter())
            .all(|(p, v)| p.admissible(v * p.scale()));
        if !inside {
            return None;
        }
        let m = self.model_at(x);
        self.passes += 1;
        let out = self.rows.solve_all(
            &m,
            &self.commands,
            &self.dirs,
            warm,
            &ProgressHandle::none(),
            &|_, r, _| r.ok().cloned(),
        );
        let mut shapes = Vec::with_capacity(out.len());
        let mut sim = Vec::with_capacity(out.len());
        for r in out {
            let s = r?;
            sim.push(m.hardware.measured_tip(&s));
            shapes.push(Some(s));
        }
        let n = sim.len();
        let off = (0..n).map(|i| sim[i] - self.tips[i]).sum::<Vector3<f64>>() / n as f64;
        let mut r = DVector::zeros(3 * n);
        for (i, (p, m)) in sim.iter().zip(&self.tips).enumerate() {
            r.fixed_rows_mut::<3>(3 * i).copy_from(&(p - off - m));
        }
        Some(Eval {
            shapes,
            r,
            mean_offset: off,
        })
    }
}

fn rmse(r: &DVector<f64>) -> f64 {
    (r.norm_squared() / (r.len() / 3).max(1) as f64).sqrt()
}

/// Fit `opts.params` of `model` to the measured tips of `data` (module docs).
pub fn calibrate(
    model: &Model,
    data: &Dataset,
    opts: &FitOptions,
) -> Result<FitReport, SolveError> {
    let clock = std::time::Instant::now();
    // A rotation vector is defined modulo 2π along its axis: started from |θ| > π (a tilt of
    // 1e4 rad is a valid model file) the fit wandered to meaningless values (−1367 ± 2e4 rad)
    // and near 2π its standard errors blew up (exp's Jacobian is singular there). The same
    // rotation with |θ| ≤ π (`Hardware::canonical_base_rotation`) starts the fit instead;
    // every prediction is unchanged.
    let canonical;
    let model = if model.hardware.base_rotation.norm() > std::f64::consts::PI {
        let mut m = model.clone();
        m.hardware.base_rotation = m.hardware.canonical_base_rotation();
        canonical = m;
        &canonical
    } else {
        model
    };
    let (mut f, used) = Fitter::new(model, data, opts)?;
    let x0 = DVector::from_iterator(
        f.params.len(),
        f.params.iter().map(|p| p.get(model) / p.scale()),
    );
    let start = f.eval(&x0, None).ok_or_else(|| SolveError::InvalidInput {
        field: "data".into(),
        reason: "a row that solved cold failed when solved in sequence".into(),
    })?;
    let before = ErrorStats::of(&aligned_errors_of(&start.r)).unwrap_or(ErrorStats {
        n: 0,
        rmse: 0.0,
        mean: 0.0,
        median: 0.0,
        max: 0.0,
    });
    let (x, cur, history, stop) = f.levenberg_marquardt(x0.clone(), start, opts)?;
    f.bar.finish();
    let params = f.uncertainties(&x0, &x, &cur)?;
    let mut fitted_model = f.model_at(&x);
    fitted_model.hardware.base_position -= cur.mean_offset;
    let after = ErrorStats::of(&aligned_errors_of(&cur.r)).unwrap_or(before);
    Ok(FitReport {
        params,
        history,
        before,
        after,
        rows_used: used,
        rows_excluded: data.len() - used,
        stop,
        model: fitted_model,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

impl<'a> Fitter<'a> {
    /// Check the options and data, and keep the rows that solve at the start (the others are
    /// left out and counted); the number of rows kept.
    pub(super) fn new(
        model: &'a Model,
        data: &Dataset,
        opts: &FitOptions,
    ) -> Result<(Self, usize), SolveError> {
        let names = if opts.params.is_empty() {
            default_names(&model.robot)
        } else {
            opts.params.clone()
        };
        let params = parse_all(&names, &model.robot)?;
        let tips = data.tips.clone().ok_or_else(|| SolveError::InvalidInput {
            field: "data".into(),
            reason: "has no tip_x, tip_y, tip_z columns to fit to".into(),
        })?;
        opts.check()?;
        let rows = Rows::new(model, data, &opts.predict)?;
        let dirs = directions(&data.commands);
        let first = rows.solve_all(
            model,
            &data.commands,
            &dirs,
            None,
            &ProgressHandle::none(),
            &|_, r, _| r.is_ok(),
        );
        let used: Vec<usize> = (0..first.len()).filter(|&i| first[i]).collect();
        if used.len() < params.len() + 2 {
            return Err(SolveError::InvalidInput {
                field: "data".into(),
                reason: format!(
                    "{} of {} rows solve at the start; fitting {} parameters needs at least {} \
                     solved rows",
                    used.len(),
                    first.len(),
                    params.len(),
                    params.len() + 2
                ),
            });
        }
        let bar = opts.predict.progress.clone();
        bar.start("calibrate", Some(opts.max_iterations as u64));
        let f = Fitter {
            rows,
            base: model,
            params,
            commands: used.iter().map(|&i| data.commands[i].clone()).collect(),
            dirs: used.iter().map(|&i| dirs[i].clone()).collect(),
            tips: used.iter().map(|&i| tips[i]).collect(),
            bar,
            passes: 0,
        };
        Ok((f, used.len()))
    }

    /// Marquardt's damped Gauss–Newton iterations from `x` (module docs): the final point, its
    /// evaluation, the cost per iteration and why it stopped.
    fn levenberg_marquardt(
        &mut self,
        mut x: DVector<f64>,
        mut cur: Eval,
        opts: &FitOptions,
    ) -> Result<(DVector<f64>, Eval, Vec<Iteration>, String), SolveError> {
        let mut history = vec![Iteration {
            iteration: 0,
            rmse: rmse(&cur.r),
            lambda: 0.0,
            passes: self.passes,
        }];
        let mut lambda = 1e-3;
        let mut stop = format!("{} iterations", opts.max_iterations);
        let mut jac = self.jacobian(&x, &cur)?;
        for it in 1..=opts.max_iterations {
            let a = jac.transpose() * &jac;
            let g = jac.transpose() * &cur.r;
            let cost = cur.r.norm_squared();
            let mut accepted = None;
            while lambda <= 1e10 {
                let mut m = a.clone();
                for k in 0..m.nrows() {
                    m[(k, k)] += lambda * a[(k, k)].max(1e-12);
                }
                let Some(ch) = m.cholesky() else {
                    lambda *= 4.0;
                    continue;
                };
                let xt = self.project(&x - ch.solve(&g));
                match self.eval(&xt, Some(&cur.shapes)) {
                    Some(e) if e.r.norm_squared() < cost => {
                        accepted = Some((xt, e));
                        break;
                    }
                    _ => lambda *= 4.0,
                }
            }
            let Some((xt, e)) = accepted else {
                stop = "no descent left (damping above 1e10)".into();
                break;
            };
            let rel = (cost - e.r.norm_squared()) / cost.max(f64::MIN_POSITIVE);
            x = xt;
            cur = e;
            history.push(Iteration {
                iteration: it,
                rmse: rmse(&cur.r),
                lambda,
                passes: self.passes,
            });
            self.bar.advance(1);
            self.bar
                .note(|| format!("calibrate rmse {:.3} mm", 1e3 * rmse(&cur.r)));
            lambda = (lambda / 3.0).max(1e-9);
            if rel < opts.tolerance {
                stop = format!("cost fell by {rel:.1e} < {:.0e}", opts.tolerance);
                break;
            }
            jac = self.jacobian(&x, &cur)?;
        }
        Ok((x, cur, history, stop))
    }

    /// The fitted parameters with their standard errors at the final point `x` (started at
    /// `x0`; module docs, "Uncertainty").
    fn uncertainties(
        &mut self,
        x0: &DVector<f64>,
        x: &DVector<f64>,
        cur: &Eval,
    ) -> Result<Vec<Fitted>, SolveError> {
        let jac = self.jacobian(x, cur)?;
        let dof = (cur.r.len() as f64 - 3.0 - x.len() as f64).max(1.0);
        let s2 = cur.r.norm_squared() / dof;
        let cov = (jac.transpose() * &jac).try_inverse();
        Ok(self
            .params
            .iter()
            .enumerate()
            .map(|(k, p)| Fitted {
                name: p.name.clone(),
                unit: p.unit(),
                initial: x0[k] * p.scale(),
                value: x[k] * p.scale(),
                sigma: cov
                    .as_ref()
                    .map(|c| (s2 * c[(k, k)]).max(0.0).sqrt() * p.scale())
                    .filter(|s| s.is_finite()),
            })
            .collect())
    }
}

/// Per-row error norms of an aligned residual vector.
fn aligned_errors_of(r: &DVector<f64>) -> Vec<f64> {
    let n = r.len() / 3;
    let sim: Vec<Vector3<f64>> = (0..n)
        .map(|i| r.fixed_rows::<3>(3 * i).into_owned())
        .collect();
    // Already aligned: the mean of `sim` is zero, so aligning again changes nothing.
    aligned_errors(&sim, &vec![Vector3::zeros(); n])
}

/// The text of a model file with `[hardware]` replaced by `model`'s, each cable's
/// `stiffness` set to `model`'s where it has one and the backbone's `stiffening` where it is
/// positive (comments are lost; `header` is written
/// first as comment lines).
pub fn fitted_toml(original: &str, model: &Model, header: &str) -> Result<String, SolveError> {
    let mut t: toml::Table = toml::from_str(original).map_err(|e| SolveError::InvalidInput {
        field: "model".into(),
        reason: format!("cannot re-read the model text: {e}"),
    })?;
    t.insert(
        "hardware".into(),
        toml::Value::Table(model.hardware.to_toml()),
    );
    // Fitted cable stiffnesses go to their cables (file order = robot order).
    if let Some(toml::Value::Array(cables)) = t.get_mut("cables") {
        for (fc, c) in cables.iter_mut().zip(&model.robot.cables) {
            if let (toml::Value::Table(fc), Some(k)) = (fc, c.stiffness) {
                fc.insert("stiffness".into(), toml::Value::Float(k));
            }
        }
    }
    // A fitted curvature stiffening goes to the backbone.
    let beta = model.robot.backbone.stiffening;
    if beta > 0.0 {
        if let Some(toml::Value::Table(bb)) = t
            .get_mut("robot")
            .and_then(|r| r.as_table_mut())
            .and_then(|r| r.get_mut("backbone"))
        {
            bb.insert("stiffening".into(), toml::Value::Float(beta));
        }
    }
    let body = toml::to_string(&t).map_err(|e| SolveError::InvalidInput {
        field: "model".into(),
        reason: format!("cannot write TOML: {e}"),
    })?;
    let mut out: String = header.lines().map(|l| format!("# {l}\n")).collect();
    out.push_str(&body);
    Ok(out)
}
