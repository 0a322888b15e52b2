//! `ccrkit._native`: the Python bindings of ccrkit, a thin shell over the core crate. Every
//! solve goes through the core's one solve path (`SolveRequest`) or its batch
//! (`ccrkit::batch`), methods and settings through its registry (`MethodKind`); this crate
//! only converts arguments and results and maps errors to Python exceptions.

mod errors;
mod files;
mod inverse;
mod model;
mod shape;

use ccrkit::batch::{solve_batch as core_batch, BatchInputs, BatchOptions};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use model::{method_kind, settings_from, Model};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike1, PyArrayLike2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use shape::Shape;

/// Every registered method: a list of dicts with `name`, `summary`, `inputs`,
/// `default_input`, `obstacles`, `loads` (`gravity`, `tip_force`, `tip_moment`),
/// `contact_unit` and `settings` (dicts with `name`, `values`, `default`, `help`).
#[pyfunction]
fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let out = PyList::empty(py);
    for k in MethodKind::ALL {
        let i = k.info();
        let d = PyDict::new(py);
        d.set_item("name", i.name)?;
        d.set_item("summary", i.summary)?;
        d.set_item(
            "inputs",
            i.inputs.iter().map(|x| x.name()).collect::<Vec<_>>(),
        )?;
        d.set_item("default_input", i.default_input.name())?;
        d.set_item("obstacles", i.obstacles)?;
        let loads = PyDict::new(py);
        loads.set_item("gravity", i.loads.gravity)?;
        loads.set_item("tip_force", i.loads.tip_force)?;
        loads.set_item("tip_moment", i.loads.tip_moment)?;
        d.set_item("loads", loads)?;
        d.set_item("contact_unit", i.contact_unit)?;
        let settings = PyList::empty(py);
        for s in i.settings {
            let sd = PyDict::new(py);
            sd.set_item("name", s.name)?;
            sd.set_item("values", s.values.to_string())?;
            sd.set_item("default", s.default)?;
            sd.set_item("help", s.help)?;
            settings.append(sd)?;
        }
        d.set_item("settings", settings)?;
        out.append(d)?;
    }
    Ok(out)
}

/// A (rows, cables) array as row-major values, or `InvalidInput` naming the argument.
fn rows_of(
    py: Python<'_>,
    name: &str,
    a: Option<PyArrayLike2<'_, f64, AllowTypeChange>>,
    cables: usize,
) -> PyResult<Option<(usize, Vec<f64>)>> {
    let Some(a) = a else { return Ok(None) };
    let v = a.as_array();
    let (n, k) = v.dim();
    if k != cables {
        return Err(errors::invalid(
            py,
            name,
            format!("has {k} columns, the robot has {cables} cables"),
        ));
    }
    Ok(Some((n, v.iter().copied().collect())))
}

/// The native batch: rows solved by `ccrkit::batch::solve_batch` with the GIL released.
/// Returns a dict of arrays; `ccrkit.solve_batch` wraps it in a `Batch`.
#[pyfunction]
#[pyo3(signature = (model, shorten=None, tension=None, method=None, threads=None, warm_start=true, chunk=64, full=false, steps=1, insertion=None, rotation=None, estimate=false, **settings))]
#[allow(clippy::too_many_arguments)]
fn _solve_batch<'py>(
    py: Python<'py>,
    model: &Model,
    shorten: Option<PyArrayLike2<'_, f64, AllowTypeChange>>,
    tension: Option<PyArrayLike2<'_, f64, AllowTypeChange>>,
    method: Option<&str>,
    threads: Option<usize>,
    warm_start: bool,
    chunk: usize,
    full: bool,
    steps: usize,
    insertion: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
    rotation: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
    estimate: bool,
    settings: Option<&Bound<'_, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let k = model.inner.robot.cables.len();
    let s = rows_of(py, "shorten", shorten, k)?;
    let t = rows_of(py, "tension", tension, k)?;
    let rows = match (&s, &t) {
        (Some((a, _)), Some((b, _))) if a != b => {
            return Err(errors::invalid(
                py,
                "tension",
                format!("has {b} rows, `shorten` has {a}"),
            ))
        }
        (Some((n, _)), _) | (None, Some((n, _))) => *n,
        (None, None) => 0,
    };
    let vec = |a: Option<PyArrayLike1<'_, f64, AllowTypeChange>>| a.map(|a| a.as_array().to_vec());
    let inputs = BatchInputs::new(rows, k, s.map(|x| x.1), t.map(|x| x.1))
        .and_then(|b| b.with_port(vec(insertion), vec(rotation)))
        .map_err(|e| errors::solve_error(py, &e))?;
    let request = SolveRequest {
        steps,
        estimate,
        ..SolveRequest::new(method_kind(py, method)?).with_settings(settings_from(settings)?)
    };
    let opts = BatchOptions {
        threads,
        warm_start,
        chunk,
        keep_disks: full,
    };
    let m = &model.inner;
    let batch = py
        .detach(|| core_batch(m, &request, &inputs, &opts))
        .map_err(|e| errors::solve_error(py, &e))?;
    let d = batch_dict(py, &batch, k, m.robot.sections() + 1, full)?;
    // Each row's insertion and rotation as solved (a row without them: full insertion, no
    // rotation; NaN for a model without a port).
    let (len, port) = (m.robot.length(), m.robot.port.is_some());
    let per_row = |f: &dyn Fn(&ccrkit::Actuation) -> f64| -> Vec<f64> {
        (0..inputs.rows())
            .map(|r| {
                if port {
                    f(&inputs.actuation(r))
                } else {
                    f64::NAN
                }
            })
            .collect()
    };
    d.set_item(
        "insertion",
        PyArray1::from_vec(py, per_row(&|a| a.insertion.unwrap_or(len))),
    )?;
    d.set_item(
        "rotation",
        PyArray1::from_vec(py, per_row(&|a| a.rotation.unwrap_or(0.0))),
    )?;
    Ok(d)
}

fn batch_dict<'py>(
    py: Python<'py>,
    b: &ccrkit::batch::Batch,
    k: usize,
    disks: usize,
    full: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let n = b.rows.len();
    let flat = |f: &dyn Fn(&ccrkit::batch::BatchRow) -> Vec<f64>| -> Vec<f64> {
        b.rows.iter().flat_map(f).collect()
    };
    let d = PyDict::new(py);
    d.set_item("method", b.method.name())?;
    let tips = PyArray1::from_vec(py, flat(&|r| r.tip.to_vec())).reshape([n, 3])?;
    d.set_item("tips", tips)?;
    let status: Vec<&str> = b.rows.iter().map(|r| r.status.name()).collect();
    d.set_item("status", status)?;
    let errs: Vec<Option<&str>> = b.rows.iter().map(|r| r.error.as_deref()).collect();
    d.set_item("errors", errs)?;
    let it: Vec<i64> = b.rows.iter().map(|r| r.iterations as i64).collect();
    d.set_item("iterations", PyArray1::from_vec(py, it))?;
    d.set_item(
        "residual",
        PyArray1::from_vec(py, b.rows.iter().map(|r| r.residual).collect()),
    )?;
    d.set_item(
        "converged",
        PyArray1::from_vec(py, b.rows.iter().map(|r| r.converged).collect()),
    )?;
    let tensions = PyArray1::from_vec(py, flat(&|r| r.tensions.clone())).reshape([n, k])?;
    d.set_item("tensions", tensions)?;
    let estimates = b
        .rows
        .iter()
        .map(|r| r.error_estimate_m.unwrap_or(f64::NAN));
    d.set_item(
        "error_estimate",
        PyArray1::from_vec(py, estimates.collect()),
    )?;
    if full {
        let mut pos = vec![f64::NAN; n * disks * 3];
        let mut rot = vec![f64::NAN; n * disks * 9];
        for (r, row) in b.rows.iter().enumerate() {
            for (j, f) in row.disks.iter().flatten().enumerate().take(disks) {
                for i in 0..3 {
                    pos[(r * disks + j) * 3 + i] = f.position[i];
                    for c in 0..3 {
                        rot[(r * disks + j) * 9 + 3 * i + c] = f.rotation[(i, c)];
                    }
                }
            }
        }
        d.set_item(
            "disk_positions",
            PyArray1::from_vec(py, pos).reshape([n, disks, 3])?,
        )?;
        d.set_item(
            "disk_rotations",
            PyArray1::from_vec(py, rot).reshape([n, disks, 3, 3])?,
        )?;
    }
    Ok(d)
}

/// The native module; `ccrkit/__init__.py` re-exports it with the Python-side `Batch`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Model>()?;
    m.add_class::<Shape>()?;
    m.add_class::<inverse::Reach>()?;
    m.add_class::<inverse::Plan>()?;
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(_solve_batch, m)?)?;
    m.add_function(wrap_pyfunction!(inverse::merge_roadmaps, m)?)?;
    // The method used when none is named (the core's `MethodKind::DEFAULT`).
    m.add("DEFAULT_METHOD", ccrkit::method::MethodKind::DEFAULT.name())?;
    // Every outcome of a solve (the core's `Status`): what a batch row's `status` holds.
    let statuses: Vec<&str> = ccrkit::error::Status::ALL
        .iter()
        .map(|s| s.name())
        .collect();
    m.add("STATUSES", pyo3::types::PyTuple::new(m.py(), statuses)?)?;
    errors::register(m)?;
    Ok(())
}
