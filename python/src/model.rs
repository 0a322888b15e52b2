//! `ccrkit.Model`: a parsed, validated model file, kept with its text so that it pickles.

use crate::errors::{export_error, invalid, model_error, solve_error};
use crate::files::{claim, WITH_SCENE};
use crate::inverse::{Plan, PlanArgs, Reach};
use crate::shape::Shape;
use ccrkit::batch::BatchInputs;
use ccrkit::export::{export_urdf, UrdfExport, UrdfMode, UrdfOptions};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::plan::PlanOptions;
use ccrkit::reach::ReachOptions;
use ccrkit::Scene;
use numpy::{AllowTypeChange, PyArray1, PyArrayLike1};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyString, PyTuple};
use std::path::{Path, PathBuf};

/// A robot with its file's actuation and obstacles. Build it with `Model.load(path)` or
/// `Model.from_toml(text, base_dir=None)`; it is immutable (`with_scene` returns a new one)
/// and pickles (its TOML text, base directory and added scene files travel).
#[pyclass(frozen, module = "ccrkit._native", name = "Model")]
pub struct Model {
    pub(crate) inner: ccrkit::Model,
    text: String,
    dir: PathBuf,
    source: Option<PathBuf>,
    scenes: Vec<PathBuf>,
}

fn absolute(py: Python<'_>, p: &Path) -> PyResult<PathBuf> {
    std::path::absolute(p).map_err(|e| invalid(py, "path", format!("`{}`: {e}", p.display())))
}

impl Model {
    fn build(
        py: Python<'_>,
        text: String,
        dir: PathBuf,
        source: Option<PathBuf>,
        scenes: Vec<PathBuf>,
    ) -> PyResult<Model> {
        let mut inner =
            ccrkit::Model::from_toml_in(&text, &dir).map_err(|e| model_error(py, &e))?;
        inner.source = source.clone();
        for s in &scenes {
            inner
                .scene
                .merge(Scene::from_file_as(s, WITH_SCENE).map_err(|e| model_error(py, &e))?);
        }
        Ok(Model {
            inner,
            text,
            dir,
            source,
            scenes,
        })
    }

    /// The actuation given by `shorten` / `tension` (one value per cable, NaN: none), or the
    /// file's when both are `None`.
    pub(crate) fn actuation(
        &self,
        py: Python<'_>,
        shorten: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
        tension: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
    ) -> PyResult<ccrkit::Actuation> {
        if shorten.is_none() && tension.is_none() {
            return Ok(self.inner.actuation.clone());
        }
        let k = self.inner.robot.cables.len();
        let vec =
            |a: Option<PyArrayLike1<'_, f64, AllowTypeChange>>| a.map(|a| a.as_array().to_vec());
        let inputs =
            BatchInputs::new(1, k, vec(shorten), vec(tension)).map_err(|e| solve_error(py, &e))?;
        Ok(inputs.actuation(0))
    }
}

/// Settings given as Python keyword arguments: `sub_arcs=8` is `sub-arcs=8`; booleans are
/// `true`/`false`; every other value is its `str()`.
pub fn settings_from(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Settings> {
    let mut s = Settings::new();
    if let Some(d) = kwargs {
        for (k, v) in d.iter() {
            let name: String = k.extract()?;
            let value = if v.is_instance_of::<PyBool>() {
                if v.is_truthy()? { "true" } else { "false" }.to_string()
            } else if let Ok(t) = v.cast::<PyString>() {
                t.to_string()
            } else {
                v.str()?.to_string()
            };
            // Python spells `sub-arcs` as the keyword `sub_arcs`: the registry's name.
            s.push(name.replace('_', "-"), value);
        }
    }
    Ok(s)
}

/// The method named `name`, or `InvalidInput` naming the known ones.
/// The method named (`None`: the library's default, `MethodKind::DEFAULT`).
pub fn method_kind(py: Python<'_>, name: Option<&str>) -> PyResult<MethodKind> {
    match name {
        None => Ok(MethodKind::DEFAULT),
        Some(name) => name.parse::<MethodKind>().map_err(|e| solve_error(py, &e)),
    }
}

#[pymethods]
impl Model {
    /// Read and validate a model file (TOML); relative scene and mesh paths resolve against
    /// its folder.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Model> {
        let path = absolute(py, &path)?;
        // Read once, capped as every model file, and parsed as the command line does, so
        // errors name the file; the text kept is the text checked, and `from_toml_in(text,
        // dir)` rebuilds the same model when unpickled.
        let (inner, text) =
            ccrkit::Model::from_file_with_text(&path).map_err(|e| model_error(py, &e))?;
        let dir = path.parent().unwrap_or(Path::new("/")).to_path_buf();
        Ok(Model {
            inner,
            text,
            dir,
            source: Some(path),
            scenes: Vec::new(),
        })
    }

    /// Parse and validate model text; relative scene and mesh paths resolve against
    /// `base_dir` (default: the current directory).
    #[staticmethod]
    #[pyo3(signature = (text, base_dir=None))]
    fn from_toml(py: Python<'_>, text: String, base_dir: Option<PathBuf>) -> PyResult<Model> {
        let dir = absolute(py, &base_dir.unwrap_or_else(|| PathBuf::from(".")))?;
        Model::build(py, text, dir, None, Vec::new())
    }

    /// This model with the obstacles of a scene file added.
    fn with_scene(&self, py: Python<'_>, path: PathBuf) -> PyResult<Model> {
        let mut scenes = self.scenes.clone();
        scenes.push(absolute(py, &path)?);
        Model::build(
            py,
            self.text.clone(),
            self.dir.clone(),
            self.source.clone(),
            scenes,
        )
    }

    /// Robot name.
    #[getter]
    fn name(&self) -> String {
        self.inner.robot.name.clone()
    }

    /// Cable names, in robot order (the columns of `shorten` / `tension`).
    #[getter]
    fn cables(&self) -> Vec<String> {
        self.inner
            .robot
            .cables
            .iter()
            .map(|c| c.name.clone())
            .collect()
    }

    /// Number of sections n (disks 0..=n).
    #[getter]
    fn sections(&self) -> usize {
        self.inner.robot.sections()
    }

    /// Undeformed straight-chord length of every cable [m] (shortening fractions are of it).
    #[getter]
    fn cable_lengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let r = &self.inner.robot;
        PyArray1::from_vec(
            py,
            (0..r.cables.len())
                .map(|c| r.undeformed_chord_length(c))
                .collect(),
        )
    }

    /// The file's shortening of every cable [m] (NaN where it gives none).
    #[getter]
    fn shorten<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let (r, a) = (&self.inner.robot, &self.inner.actuation);
        PyArray1::from_vec(
            py,
            (0..r.cables.len())
                .map(|c| a.shortening_length(r, c).unwrap_or(f64::NAN))
                .collect(),
        )
    }

    /// The file's tension of every cable [N] (NaN where it gives none).
    #[getter]
    fn tension<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let a = &self.inner.actuation;
        PyArray1::from_vec(
            py,
            (0..self.inner.robot.cables.len())
                .map(|c| a.tension(c).unwrap_or(f64::NAN))
                .collect(),
        )
    }

    /// Number of obstacles (the file's and the added scenes').
    #[getter]
    fn obstacles(&self) -> Vec<String> {
        self.inner
            .scene
            .obstacles
            .iter()
            .map(|o| o.name.clone())
            .collect()
    }

    /// The file the model was read from, if any.
    #[getter]
    fn source(&self) -> Option<PathBuf> {
        self.source.clone()
    }

    /// Solve the shape with `method` (see `ccrkit.methods()`). `shorten` [m] and `tension` [N]
    /// (one value per cable, NaN: none) replace the file's actuation when either is given;
    /// `insertion` [m] and `rotation` [rad] replace the port's (a model with a `[port]`; the
    /// shape's `insertion` and `rotation` give them back).
    /// `steps` reaches the actuation in that many warm-started steps; `warm_from` starts from
    /// another method's shape; `estimate=True` adds the answer's estimated distance from the
    /// converged rod (`Shape.error_estimate`; `energy`: no extra solve). Every other keyword is a setting
    /// of the method by name (`sub_arcs=8`, `length="chord"`); a setting the method does not
    /// take is refused.
    /// `method="auto"` picks the cheapest model and resolution whose estimated error is within
    /// `tolerance` [m] (default 1e-4); what it chose is in `report["auto"]`.
    /// `check_unique=True` solves the input again along other paths and says whether the answer
    /// is the only equilibrium found (`report["unique"]`, as `ccrkit solve --check unique`).
    #[pyo3(signature = (method=None, shorten=None, tension=None, *, insertion=None, rotation=None, steps=1, warm_from=None, estimate=false, tolerance=None, check_unique=false, **settings))]
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &self,
        py: Python<'_>,
        method: Option<&str>,
        shorten: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
        tension: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
        insertion: Option<f64>,
        rotation: Option<f64>,
        steps: usize,
        warm_from: Option<&str>,
        estimate: bool,
        tolerance: Option<f64>,
        check_unique: bool,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Shape> {
        let auto = match (method, tolerance) {
            (Some("auto"), t) => Some(t.unwrap_or(1e-4)),
            (_, None) => None,
            (_, Some(_)) => {
                return Err(crate::errors::invalid(
                    py,
                    "tolerance",
                    "is the tolerance of method=\"auto\"".to_string(),
                ))
            }
        };
        let request = SolveRequest {
            auto,
            method: if auto.is_some() {
                MethodKind::DEFAULT
            } else {
                method_kind(py, method)?
            },
            settings: settings_from(settings)?,
            extra_scene: None,
            warm_from: warm_from.map(|w| method_kind(py, Some(w))).transpose()?,
            steps,
            repeat: 1,
            estimate,
            check_unique,
        };
        let mut actuation = self.actuation(py, shorten, tension)?;
        if insertion.is_some() {
            actuation.insertion = insertion;
        }
        if rotation.is_some() {
            actuation.rotation = rotation;
        }
        let model = &self.inner;
        let solved = py.detach(|| {
            let mut m = model.clone();
            m.actuation = actuation;
            let solved = request.run(&m)?;
            // The CLI's --json text: the same writer as `ccrkit solve --json`.
            let json = serde_json::to_string_pretty(&request.json(&m, &solved.shape)).ok();
            Ok::<_, ccrkit::SolveError>((solved, json))
        });
        let (solved, json) = solved.map_err(|e| solve_error(py, &e))?;
        let mut shape = Shape::new(solved.shape);
        shape.json = json;
        Ok(shape)
    }

    /// Write `shape` (solved on this model) as URDF to `path`, with the SRDF and the joint
    /// values as JSON next to it in `articulated` mode. Returns the paths written. None of
    /// them may be one of the model's files, nor two of them one file (`crate::files`).
    #[pyo3(signature = (path, shape, mode="articulated", cables=false, name=None))]
    fn export_urdf(
        &self,
        py: Python<'_>,
        path: PathBuf,
        shape: &Shape,
        mode: &str,
        cables: bool,
        name: Option<String>,
    ) -> PyResult<Vec<PathBuf>> {
        let mode: UrdfMode = mode.parse().map_err(|e| export_error(py, &e))?;
        let outputs: Vec<(String, PathBuf)> = UrdfExport::paths(mode, &path)
            .into_iter()
            .enumerate()
            .map(|(k, (role, p))| match k {
                0 => (format!("{role} (`path`)"), p),
                _ => (format!("{role} (beside `path`)"), p),
            })
            .collect();
        claim(py, &self.inner, "path", &outputs)?;
        let opts = UrdfOptions { mode, cables, name };
        let export = export_urdf(&shape.inner, &self.inner.robot, &opts)
            .map_err(|e| export_error(py, &e))?;
        export.write_files(&path).map_err(|e| export_error(py, &e))
    }

    /// The least-effort actuation (Σ shorten² [m²]) within the model's `[limits]` that puts
    /// the tip on `tip` [m] (and the tip tangent along `tangent`, normalized, if given),
    /// keeping every feature `margin` [m] (default: the scene's `clearance`) clear of the
    /// model's obstacles, or touching them with `allow_contact`; `ccrkit reach`. Raises
    /// `Unreachable` (closest tip, distance, and the closest answer as `result`) when not
    /// reached, unless `require=False`. Other keywords are the method's settings.
    #[pyo3(signature = (tip, tangent=None, *, method=None, margin=None, allow_contact=false, tolerance=1e-7, starts=16, max_iterations=60, require=true, **settings))]
    #[allow(clippy::too_many_arguments)]
    fn reach(
        &self,
        py: Python<'_>,
        tip: PyArrayLike1<'_, f64, AllowTypeChange>,
        tangent: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
        method: Option<&str>,
        margin: Option<f64>,
        allow_contact: bool,
        tolerance: f64,
        starts: usize,
        max_iterations: usize,
        require: bool,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Reach> {
        let request =
            SolveRequest::new(method_kind(py, method)?).with_settings(settings_from(settings)?);
        let opts = ReachOptions {
            allow_contact,
            tolerance,
            max_iterations,
            starts,
            margin,
        };
        crate::inverse::reach(py, &self.inner, tip, tangent, request, opts, require)
    }

    /// A path of actuations from `from_actuation` (default: the file's) to `to_tip` [m] or
    /// `to_actuation` [m] along which every feature keeps `margin` (default: the scene's
    /// `clearance`) from the model's obstacles; `ccrkit plan`. RRT-Connect with `seed`, or a
    /// query of the roadmap file `roadmap` (`ccrkit roadmap build`). Raises `NoPath` when
    /// none is found. Other keywords are the method's settings.
    #[pyo3(signature = (to_tip=None, to_actuation=None, from_actuation=None, *, method=None, seed=1, margin=None, max_samples=5000, roadmap=None, **settings))]
    #[allow(clippy::too_many_arguments)]
    fn plan(
        &self,
        py: Python<'_>,
        to_tip: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
        to_actuation: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
        from_actuation: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
        method: Option<&str>,
        seed: u64,
        margin: Option<f64>,
        max_samples: usize,
        roadmap: Option<PathBuf>,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Plan> {
        let request =
            SolveRequest::new(method_kind(py, method)?).with_settings(settings_from(settings)?);
        let opts = PlanOptions {
            seed,
            margin,
            max_samples,
            ..PlanOptions::default()
        };
        let args = PlanArgs {
            to_tip,
            to_actuation,
            from_actuation,
            roadmap,
            opts,
        };
        crate::inverse::plan(py, &self.inner, request, args)
    }

    /// A roadmap for repeated `plan(roadmap=…)` queries, as `ccrkit roadmap build`: its JSON
    /// text, also written to `out` when given (not one of the model's files: `crate::files`,
    /// checked before building). `shard=(k, N)` builds only shard `k` of `N`
    /// (every shard samples the same nodes; `ccrkit.merge_roadmaps` joins them into the
    /// roadmap one build gives — e.g. one shard per Dask worker). Other keywords are the
    /// method's settings. Releases the GIL.
    #[pyo3(signature = (out=None, *, method=None, samples=400, expand=400, spread=0.1, neighbours=8, seed=1, margin=None, shard=None, **settings))]
    #[allow(clippy::too_many_arguments)]
    fn build_roadmap(
        &self,
        py: Python<'_>,
        out: Option<PathBuf>,
        method: Option<&str>,
        samples: usize,
        expand: usize,
        spread: f64,
        neighbours: usize,
        seed: u64,
        margin: Option<f64>,
        shard: Option<(usize, usize)>,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<String> {
        if let Some(out) = &out {
            claim(
                py,
                &self.inner,
                "out",
                &[("`out` file".into(), out.clone())],
            )?;
        }
        let request =
            SolveRequest::new(method_kind(py, method)?).with_settings(settings_from(settings)?);
        let shard = match shard {
            Some((index, count)) if index < count => {
                Some(ccrkit::plan::roadmap::Shard { index, count })
            }
            Some((k, n)) => {
                return Err(invalid(
                    py,
                    "shard",
                    format!("expected (k, N) with 0 <= k < N, got ({k}, {n})"),
                ))
            }
            None => None,
        };
        let opts = ccrkit::plan::roadmap::BuildOptions {
            samples,
            expand,
            spread,
            neighbours,
            seed,
            margin,
            shard,
            ..Default::default()
        };
        crate::inverse::build_roadmap(py, &self.inner, request, opts, out)
    }

    /// Pickling: the TOML text, its base directory, the source file and the added scenes.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let restore = py.get_type::<Model>().getattr("_restore")?;
        let args = (
            self.text.clone(),
            self.dir.clone(),
            self.source.clone(),
            self.scenes.clone(),
        );
        PyTuple::new(py, [restore, args.into_pyobject(py)?.into_any()])
    }

    /// Rebuild a pickled model (not meant to be called directly).
    #[staticmethod]
    fn _restore(
        py: Python<'_>,
        text: String,
        dir: PathBuf,
        source: Option<PathBuf>,
        scenes: Vec<PathBuf>,
    ) -> PyResult<Model> {
        Model::build(py, text, dir, source, scenes)
    }

    fn __repr__(&self) -> String {
        format!(
            "Model(name={:?}, sections={}, cables={:?}, obstacles={})",
            self.inner.robot.name,
            self.inner.robot.sections(),
            self.cables(),
            self.inner.scene.obstacles.len()
        )
    }
}
