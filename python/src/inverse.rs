//! `Model.reach` and `Model.plan`: thin wrappers over `ccrkit::reach::reach` and
//! `ccrkit::plan::plan` (with or without a `Roadmap`), numpy in and out. Their `to_json()` is the
//! command line's `ccrkit reach --json` / `ccrkit plan --json` text (same writer).

use crate::errors::{export_error, invalid, model_error, solve_error};
use crate::shape::Shape;
use ccrkit::method::run::SolveRequest;
use ccrkit::plan::roadmap::Roadmap;
use ccrkit::plan::{Goal, PlanOptions};
use ccrkit::reach::{ReachOptions, Target};
use nalgebra::Vector3;
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyList;
use std::path::PathBuf;

/// A vector of three finite numbers named `field`.
fn vec3(
    py: Python<'_>,
    field: &str,
    a: PyArrayLike1<'_, f64, AllowTypeChange>,
) -> PyResult<Vector3<f64>> {
    let v = a.as_array().to_vec();
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err(invalid(
            py,
            field,
            format!("needs three finite numbers X, Y, Z, got {v:?}"),
        ));
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}

/// One shortening per cable \[m\], then for a robot with a port (`port`) optionally its
/// insertion \[m\] and rotation \[rad\] (default: the model file's), named `field`.
fn actuation(
    py: Python<'_>,
    field: &str,
    a: PyArrayLike1<'_, f64, AllowTypeChange>,
    model: &ccrkit::Model,
) -> PyResult<Vec<f64>> {
    let cables = model.robot.cables.len();
    let mut v = a.as_array().to_vec();
    let port = model.robot.port.is_some();
    let fits = v.len() == cables || port && v.len() == cables + 2;
    if !fits {
        let want = if port {
            format!(
                "{cables} (one per cable) or {} (then insertion [m] and rotation [rad])",
                cables + 2
            )
        } else {
            format!("{cables}, one per cable")
        };
        return Err(invalid(
            py,
            field,
            format!("has {} values, wants {want}", v.len()),
        ));
    }
    if port && v.len() == cables {
        let here = ccrkit::plan::actuation_of(model, &model.actuation);
        v.extend_from_slice(&here[cables..]);
    }
    Ok(v)
}

/// The `j`-th unknown of every waypoint, `None` when the plan has no such unknown (no port).
fn column(plan: &ccrkit::plan::Plan, j: usize) -> Option<Vec<f64>> {
    (plan.waypoints.iter().all(|n| n.u.len() > j))
        .then(|| plan.waypoints.iter().map(|n| n.u[j]).collect())
}

/// The answer of `Model.reach`: the least-effort actuation (Σ shorten² \[m²\]) within the
/// model's limits that puts the tip on the target, or the closest one found
/// (`reached == False`). Arrays are float64, SI units.
#[pyclass(frozen, module = "ccrkit._native", name = "Reach")]
pub struct Reach {
    inner: ccrkit::reach::Reach,
    json: String,
}

#[pymethods]
impl Reach {
    /// True when the tip (and tangent) are on target within the tolerance, clear of the
    /// obstacles (unless contact is allowed) and within the tension limits.
    #[getter]
    fn reached(&self) -> bool {
        self.inner.reached
    }
    /// (3,) target tip \[m\].
    #[getter]
    fn target<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.inner.target.tip.as_slice())
    }
    /// (3,) tip of the answer's shape \[m\].
    #[getter]
    fn tip<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.inner.shape.tip().as_slice())
    }
    /// Distance from the tip to the target \[m\].
    #[getter]
    fn tip_error_m(&self) -> f64 {
        self.inner.tip_error_m
    }
    /// Angle between the tip tangent and the target tangent \[rad\], if one was given.
    #[getter]
    fn tangent_error_rad(&self) -> Option<f64> {
        self.inner.tangent_error_rad
    }
    /// (cables,) shortenings \[m\], in `Model.cables` order.
    #[getter]
    fn shorten<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let k = self.inner.actuation.len().min(self.inner.u.len());
        PyArray1::from_slice(py, &self.inner.u[..k])
    }
    /// Insertion of the answer \[m\] (None without a port).
    #[getter]
    fn insertion(&self) -> Option<f64> {
        self.inner.insertion
    }
    /// Rotation of the answer \[rad\] (None without a port).
    #[getter]
    fn rotation(&self) -> Option<f64> {
        self.inner.rotation
    }
    /// (cables,) tensions of the answer's shape \[N\] (NaN where the method computes none).
    #[getter]
    fn tensions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let t: Vec<f64> = self
            .inner
            .actuation
            .iter()
            .map(|c| c.tension.unwrap_or(f64::NAN))
            .collect();
        PyArray1::from_vec(py, t)
    }
    /// The effort Σ shorten² \[m²\].
    #[getter]
    fn effort_m2(&self) -> f64 {
        self.inner.effort_m2
    }
    /// Clearance of the answer from the obstacles \[m\] (None without obstacles).
    #[getter]
    fn min_clearance_m(&self) -> Option<f64> {
        self.inner.min_clearance_m
    }
    /// The answer's shape, solved as `ccrkit solve` does.
    #[getter]
    fn shape(&self) -> Shape {
        Shape::new(self.inner.shape.clone())
    }
    /// SQP iterations over every start.
    #[getter]
    fn iterations(&self) -> usize {
        self.inner.iterations
    }
    /// Starts tried.
    #[getter]
    fn starts(&self) -> usize {
        self.inner.starts
    }
    /// Forward solves spent.
    #[getter]
    fn solves(&self) -> usize {
        self.inner.solves
    }
    /// `exact` (the method's Jacobian) or `finite-differences`.
    #[getter]
    fn sensitivities(&self) -> &'static str {
        self.inner.sensitivities
    }
    /// Why the target was not reached (empty when reached).
    #[getter]
    fn reason(&self) -> String {
        self.inner.reason.clone()
    }
    /// The command line's `ccrkit reach --json` text.
    fn to_json(&self) -> String {
        self.json.clone()
    }
    fn __repr__(&self) -> String {
        format!(
            "Reach(reached={}, tip_error_m={:.3e}, shorten={:?})",
            if self.inner.reached { "True" } else { "False" },
            self.inner.tip_error_m,
            self.inner.u
        )
    }
}

/// `Model.reach`: see the stub. Raises `Unreachable` (with the closest answer as `result`)
/// when `require` and not reached.
#[allow(clippy::too_many_arguments)]
pub fn reach(
    py: Python<'_>,
    model: &ccrkit::Model,
    tip: PyArrayLike1<'_, f64, AllowTypeChange>,
    tangent: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
    request: SolveRequest,
    opts: ReachOptions,
    require: bool,
) -> PyResult<Reach> {
    let tip = vec3(py, "tip", tip)?;
    // Normalized as `ccrkit reach --tangent` does.
    let tangent = match tangent {
        None => None,
        Some(t) => {
            let t = vec3(py, "tangent", t)?;
            if t.norm() == 0.0 {
                return Err(invalid(py, "tangent", "must not be zero"));
            }
            Some(t.normalize())
        }
    };
    let r = py
        .detach(|| {
            request.solver()?;
            ccrkit::reach::reach(model, &request, &Target { tip, tangent }, &opts)
        })
        .map_err(|e| solve_error(py, &e))?;
    let json = serde_json::to_string_pretty(&r.to_json())
        .map_err(|e| invalid(py, "reach", e.to_string()))?;
    let out = Reach { inner: r, json };
    if require && !out.inner.reached {
        let err = solve_error(
            py,
            &out.inner.clone().require_reached().err().unwrap_or(
                ccrkit::SolveError::InvalidInput {
                    field: "tip".into(),
                    reason: "not reached".into(),
                },
            ),
        );
        err.value(py).setattr("result", Py::new(py, out)?)?;
        return Err(err);
    }
    Ok(out)
}

/// The answer of `Model.plan`: waypoints of actuations along which every feature keeps the
/// margin from every obstacle (each edge validated, see `ccrkit plan`). Arrays are float64,
/// SI units.
#[pyclass(frozen, module = "ccrkit._native", name = "Plan")]
pub struct Plan {
    inner: ccrkit::plan::Plan,
    robot: ccrkit::Model,
    json: String,
}

#[pymethods]
impl Plan {
    /// (waypoints, cables) shortenings \[m\], in `cables` order: the inputs, or in tension
    /// space the path-length changes the tensions made.
    #[getter]
    fn shorten<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.per_cable(py, |a| a.shorten)
    }
    /// (waypoints, cables) tensions \[N\], in `cables` order: the inputs in tension space,
    /// else the tensions the shortenings made (NaN where the method reports none).
    #[getter]
    fn tensions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.per_cable(py, |a| a.tension.unwrap_or(f64::NAN))
    }
    /// The space planned in: `"shortening"` or `"tension"` (chosen by the method and its
    /// `control` setting, as for `reach`).
    #[getter]
    fn space(&self) -> &'static str {
        self.inner.input.name()
    }
    /// (waypoints,) insertions \[m\] through the port (None without a port).
    #[getter]
    fn insertion<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        column(&self.inner, self.inner.cables.len()).map(|v| PyArray1::from_vec(py, v))
    }
    /// (waypoints,) rotations \[rad\] about the port axis (None without a port).
    #[getter]
    fn rotation<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        column(&self.inner, self.inner.cables.len() + 1).map(|v| PyArray1::from_vec(py, v))
    }
    /// (waypoints, 3) tips \[m\].
    #[getter]
    fn tips<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let w = &self.inner.waypoints;
        let flat: Vec<f64> = w
            .iter()
            .flat_map(|n| n.shape.tip().iter().copied().collect::<Vec<_>>())
            .collect();
        PyArray1::from_vec(py, flat).reshape([w.len(), 3])
    }
    /// (waypoints,) measured clearance of each waypoint's shape \[m\] (inf without obstacles).
    #[getter]
    fn clearances<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(
            py,
            self.inner.waypoints.iter().map(|n| n.clearance).collect(),
        )
    }
    /// The waypoints' shapes.
    #[getter]
    fn shapes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let l = PyList::empty(py);
        for n in &self.inner.waypoints {
            l.append(Py::new(py, Shape::new(n.shape.clone()))?)?;
        }
        Ok(l)
    }
    /// Cable names (columns of `shorten`).
    #[getter]
    fn cables(&self) -> Vec<String> {
        self.inner.cables.clone()
    }
    /// Margin kept \[m\].
    #[getter]
    fn margin_m(&self) -> f64 {
        self.inner.margin_m
    }
    /// Smallest clearance measured along the path \[m\].
    #[getter]
    fn min_clearance_m(&self) -> f64 {
        self.inner.min_clearance_m
    }
    /// Smallest clearance certified by the edge validation \[m\].
    #[getter]
    fn certified_clearance_m(&self) -> f64 {
        self.inner.certified_clearance_m
    }
    /// Seed used.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.seed
    }
    /// Planner statistics (the `statistics` object of `to_json()`).
    #[getter]
    fn statistics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.inner.stats)
            .map_err(|e| invalid(py, "statistics", e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
    }
    /// The command line's `ccrkit plan --json` text.
    fn to_json(&self) -> String {
        self.json.clone()
    }
    /// The command line's `ccrkit plan --trajectory` text: joint values of the articulated
    /// URDF export, one CSV row per waypoint.
    fn trajectory_csv(&self, py: Python<'_>) -> PyResult<String> {
        self.inner
            .trajectory_csv(&self.robot)
            .map_err(|e| export_error(py, &e))
    }
    fn __repr__(&self) -> String {
        format!(
            "Plan(planner={:?}, waypoints={}, min_clearance_m={:.3e})",
            self.inner.stats.planner,
            self.inner.waypoints.len(),
            self.inner.min_clearance_m
        )
    }
}

impl Plan {
    /// One value per waypoint and cable of each waypoint's cable entries (the plan JSON's).
    fn per_cable<'py>(
        &self,
        py: Python<'py>,
        value: impl Fn(&ccrkit::reach::CableActuation) -> f64,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let p = &self.inner;
        let flat: Vec<f64> = p
            .waypoints
            .iter()
            .flat_map(|n| ccrkit::reach::CableActuation::of(&p.cables, p.input, &n.u, &n.shape))
            .map(|a| value(&a))
            .collect();
        PyArray1::from_vec(py, flat).reshape([p.waypoints.len(), p.cables.len()])
    }
}

/// The arguments of `Model.plan` other than the request.
pub struct PlanArgs<'a> {
    pub to_tip: Option<PyArrayLike1<'a, f64, AllowTypeChange>>,
    pub to_actuation: Option<PyArrayLike1<'a, f64, AllowTypeChange>>,
    pub from_actuation: Option<PyArrayLike1<'a, f64, AllowTypeChange>>,
    pub roadmap: Option<PathBuf>,
    pub opts: PlanOptions,
}

/// `Model.plan`: see the stub.
pub fn plan(
    py: Python<'_>,
    model: &ccrkit::Model,
    request: SolveRequest,
    a: PlanArgs<'_>,
) -> PyResult<Plan> {
    let goal = match (a.to_tip, a.to_actuation) {
        (Some(t), None) => Goal::Tip(vec3(py, "to_tip", t)?),
        (None, Some(u)) => Goal::Actuation(actuation(py, "to_actuation", u, model)?),
        _ => {
            return Err(invalid(
                py,
                "goal",
                "give exactly one goal: to_tip=[x, y, z] or to_actuation=[…]",
            ))
        }
    };
    let start = a
        .from_actuation
        .map(|u| actuation(py, "from_actuation", u, model))
        .transpose()?;
    let roadmap = a
        .roadmap
        .map(|p| Roadmap::load(&p))
        .transpose()
        .map_err(|e| model_error(py, &e))?;
    let opts = a.opts;
    let p = py
        .detach(|| {
            request.solver()?;
            ccrkit::plan::plan(model, &request, start, &goal, &opts, roadmap.as_ref())
        })
        .map_err(|e| solve_error(py, &e))?;
    let json = serde_json::to_string_pretty(&p.to_json())
        .map_err(|e| invalid(py, "plan", e.to_string()))?;
    Ok(Plan {
        inner: p,
        robot: model.clone(),
        json,
    })
}

/// `Model.build_roadmap`: the roadmap (or one shard of it) as JSON text, also written to
/// `out` when given; see the stub.
pub fn build_roadmap(
    py: Python<'_>,
    model: &ccrkit::Model,
    request: SolveRequest,
    opts: ccrkit::plan::roadmap::BuildOptions,
    out: Option<PathBuf>,
) -> PyResult<String> {
    let r = py
        .detach(|| ccrkit::plan::roadmap::build(model, &request, &opts))
        .map_err(|e| solve_error(py, &e))?;
    save_text(py, &r, out)
}

/// The roadmap's JSON text, written to `out` (atomically) when given.
fn save_text(py: Python<'_>, r: &Roadmap, out: Option<PathBuf>) -> PyResult<String> {
    if let Some(p) = &out {
        r.save(p).map_err(|e| model_error(py, &e))?;
    }
    r.to_json("roadmap").map_err(|e| model_error(py, &e))
}

/// The roadmap the shards `parts` (JSON texts of `Model.build_roadmap(shard=(k, N))`, all N
/// of them, any order) make together: the roadmap one build gives, edge for edge
/// (`ccrkit roadmap merge`). Written to `out` when given; returns its JSON text.
#[pyfunction]
#[pyo3(signature = (parts, out=None))]
pub fn merge_roadmaps(
    py: Python<'_>,
    parts: Vec<String>,
    out: Option<PathBuf>,
) -> PyResult<String> {
    let loaded = parts
        .iter()
        .enumerate()
        .map(|(k, t)| Roadmap::from_json(t, &format!("parts[{k}]")))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| model_error(py, &e))?;
    let r = ccrkit::plan::roadmap_shard::merge(loaded).map_err(|e| model_error(py, &e))?;
    save_text(py, &r, out)
}
