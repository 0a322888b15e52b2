//! `ccrkit.Shape`: a solved shape, read as numpy arrays (metres, base frame).

use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

/// A solved robot. Arrays are float64 in metres, base frame; `to_json()` is the command
/// line's `ccrkit solve --json` text. Immutable; pickles through its JSON (solver warm-start
/// state is not kept).
#[pyclass(frozen, module = "ccrkit._native", name = "Shape")]
pub struct Shape {
    pub(crate) inner: ccrkit::Shape,
    /// The CLI's `--json` text (with the model's name and the input that drove the solve),
    /// when the shape came from `Model.solve`.
    pub(crate) json: Option<String>,
}

impl Shape {
    pub fn new(inner: ccrkit::Shape) -> Self {
        Shape { inner, json: None }
    }
}

fn points<'py>(
    py: Python<'py>,
    pts: impl ExactSizeIterator<Item = [f64; 3]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = pts.len();
    let flat: Vec<f64> = pts.flat_map(|p| p.into_iter()).collect();
    PyArray1::from_vec(py, flat).reshape([n, 3])
}

fn json_loads<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

#[pymethods]
impl Shape {
    /// Method that produced it.
    #[getter]
    fn method(&self) -> String {
        self.inner.method.clone()
    }

    /// Disk centres, (n+1, 3) [m].
    #[getter]
    fn disk_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points(py, self.inner.disks.iter().map(|d| d.position.into()))
    }

    /// Disk orientations, (n+1, 3, 3): `[d, i, j]` is row i, column j of disk d's rotation
    /// (columns: the disk's x, y, z axes in the base frame; z is the disk normal).
    #[getter]
    fn disk_rotations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let n = self.inner.disks.len();
        let mut flat = Vec::with_capacity(9 * n);
        for d in &self.inner.disks {
            for i in 0..3 {
                for j in 0..3 {
                    flat.push(d.rotation[(i, j)]);
                }
            }
        }
        PyArray1::from_vec(py, flat).reshape([n, 3, 3])
    }

    /// Arc length of every disk along the undeformed backbone, (n+1,) [m].
    #[getter]
    fn disk_s<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.inner.disks.iter().map(|d| d.s).collect())
    }

    /// Insertion through the model's port [m] (`None` without a port).
    #[getter]
    fn insertion(&self) -> Option<f64> {
        self.inner.port.as_ref().map(|p| p.insertion)
    }

    /// Rotation about the model's port axis [rad] (`None` without a port).
    #[getter]
    fn rotation(&self) -> Option<f64> {
        self.inner.port.as_ref().map(|p| p.rotation)
    }

    /// Tip (last disk) position, (3,) [m].
    #[getter]
    fn tip<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let t = self.inner.tip();
        PyArray1::from_vec(py, vec![t.x, t.y, t.z])
    }

    /// Dense backbone samples, (m, 3) [m].
    #[getter]
    fn backbone<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points(py, self.inner.backbone.iter().map(|p| (*p).into()))
    }

    /// Cable name → hole positions at the disks it passes, (k_c, 3) [m], in robot order.
    #[getter]
    fn cable_paths<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for c in &self.inner.cables {
            d.set_item(&c.name, points(py, c.points.iter().map(|p| (*p).into()))?)?;
        }
        Ok(d)
    }

    /// Tension of every cable [N] in robot order (NaN where the method computes none).
    #[getter]
    fn tensions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let t = self
            .inner
            .cables
            .iter()
            .map(|c| c.tension.unwrap_or(f64::NAN));
        PyArray1::from_vec(py, t.collect())
    }

    /// Path-length change of every cable \[m\] in robot order (its shortening, whatever
    /// drove the solve: a tension-driven solve reports the shortening that drives the same
    /// shape back; NaN where the method computes none).
    #[getter]
    fn shortenings<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let u = self
            .inner
            .cables
            .iter()
            .map(|c| c.shortening.unwrap_or(f64::NAN));
        PyArray1::from_vec(py, u.collect())
    }

    /// Whether each cable is slack somewhere, in robot order.
    #[getter]
    fn slack(&self) -> Vec<bool> {
        self.inner.cables.iter().map(|c| c.slack).collect()
    }

    /// Contacts with obstacles: dicts with `obstacle`, `feature`, `disk`, `section`,
    /// `point_robot`, `point_obstacle`, `normal` ((3,) arrays [m]), `distance` [m] and
    /// `reaction` (the multiplier, in the method's `contact_unit`, see `ccrkit.methods()`).
    #[getter]
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for c in &self.inner.contacts {
            let d = PyDict::new(py);
            d.set_item("obstacle", &c.obstacle)?;
            d.set_item("feature", &c.feature)?;
            d.set_item("disk", c.disk)?;
            d.set_item("section", c.section)?;
            d.set_item("point_robot", PyArray1::from_slice(py, &c.point_robot))?;
            d.set_item(
                "point_obstacle",
                PyArray1::from_slice(py, &c.point_obstacle),
            )?;
            d.set_item("normal", PyArray1::from_slice(py, &c.normal))?;
            d.set_item("distance", c.distance)?;
            d.set_item("reaction", c.multiplier)?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// The solver's report as a dict, the `report` object of `to_json()`: `converged`,
    /// `iterations`, `residual`, `solve_time_s`, and where the method gives them `sections`,
    /// `base_wrench`, `notes`, `stable` (True / False; absent: unknown) and `jacobian`.
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.inner.report)
            .map_err(|e| crate::errors::invalid(py, "report", e.to_string()))?;
        json_loads(py, &text)
    }

    /// True when every tolerance was met.
    #[getter]
    fn converged(&self) -> bool {
        self.inner.report.converged
    }

    /// Whether the shape is a verified stable equilibrium (None: the method cannot tell).
    #[getter]
    fn stable(&self) -> Option<bool> {
        self.inner.report.stable
    }

    /// The estimated tip distance from the converged reference rod [m], when the solve was
    /// asked for it (`estimate=True`) and the model part is known; the parts are in
    /// `report["error_estimate"]`.
    #[getter]
    fn error_estimate(&self) -> Option<f64> {
        self.inner
            .report
            .error_estimate
            .as_ref()
            .and_then(|e| e.bound_m)
    }

    /// Tip sensitivities, where the method computes them: a dict with `inputs` (list of
    /// `(cable, "shortening" | "tension")`), `position` and `tangent`, each (3, k) arrays
    /// (column j: ∂p_tip/∂u_j, ∂t_tip/∂u_j); else None.
    #[getter]
    fn jacobian<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(j) = &self.inner.report.jacobian else {
            return Ok(None);
        };
        let k = j.position.len();
        let cols = |v: &[[f64; 3]]| -> PyResult<Bound<'py, PyArray2<f64>>> {
            let mut flat = vec![0.0; 3 * k];
            for (c, p) in v.iter().enumerate() {
                for (i, x) in p.iter().enumerate() {
                    flat[i * k + c] = *x;
                }
            }
            PyArray1::from_vec(py, flat).reshape([3, k])
        };
        let d = PyDict::new(py);
        d.set_item("inputs", j.inputs.clone())?;
        d.set_item("position", cols(&j.position)?)?;
        d.set_item("tangent", cols(&j.tangent)?)?;
        Ok(Some(d))
    }

    /// The command line's `--json` text for this shape (pretty-printed).
    fn to_json(&self) -> String {
        self.json
            .clone()
            .unwrap_or_else(|| self.inner.to_json_string())
    }

    /// Pickling: through the JSON text (floats round-trip exactly).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let restore = py.get_type::<Shape>().getattr("from_json")?;
        let args = (self.to_json(),).into_pyobject(py)?;
        PyTuple::new(py, [restore, args.into_any()])
    }

    /// A shape from `to_json()` text (warm-start state is not kept).
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Shape> {
        let shape =
            ccrkit::Shape::from_json_str(text).map_err(|e| crate::errors::model_error(py, &e))?;
        let mut shape = Shape::new(shape);
        // The text read is the shape's JSON (the pickled one included): keep it verbatim.
        shape.json = Some(text.to_string());
        Ok(shape)
    }

    fn __repr__(&self) -> String {
        let t = self.inner.tip() * 1e3;
        format!(
            "Shape(method={:?}, disks={}, tip=[{:.3}, {:.3}, {:.3}] mm, converged={})",
            self.inner.method,
            self.inner.disks.len(),
            t.x,
            t.y,
            t.z,
            self.inner.report.converged
        )
    }
}
