//! ccrkit's errors as Python exceptions: one base, `ccrkit.SolveError`, and one subclass per
//! kind of the core's errors. Every instance carries `kind`, `field` and `reason` (the field or
//! thing the error names, and why), plus the kind's own attributes (`cable`, `section`,
//! `method`, `iterations`, `residual`, `obstacle`, `path`, and the inverse problems' `target`,
//! `closest`, `distance`, `samples`); absent ones are `None`.

use ccrkit::export::ExportError as CoreExportError;
use ccrkit::{ModelError as CoreModelError, SolveError as CoreSolveError};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;

create_exception!(
    ccrkit,
    SolveError,
    PyException,
    "Every ccrkit error. Attributes: kind, field, reason (and the kind's own: cable, section, \
     method, iterations, residual, obstacle, path; None where absent)."
);
create_exception!(
    ccrkit,
    InvalidInput,
    SolveError,
    "An input is not valid (field: the input or setting, reason: why)."
);
create_exception!(
    ccrkit,
    ModelError,
    InvalidInput,
    "A model or scene file cannot be read, parsed or used (field: the file's field, path)."
);
create_exception!(
    ccrkit,
    Infeasible,
    SolveError,
    "No shape of the robot reaches the actuation (field: the cable, section)."
);
create_exception!(
    ccrkit,
    NotConverged,
    SolveError,
    "An iterative solver stopped without meeting its tolerance (method, iterations, residual)."
);
create_exception!(
    ccrkit,
    Obstructed,
    SolveError,
    "An obstacle makes the shape impossible (field: the obstacle, section)."
);
create_exception!(
    ccrkit,
    Unsupported,
    SolveError,
    "The method cannot represent this robot, load or obstacle (field: the method)."
);
create_exception!(
    ccrkit,
    ContactBudget,
    Unsupported,
    "The scene has more distinct obstacles within reach of the robot than a solve may query \
     (field: `obstacles`, reason: the message, with the count, the limit and what to do)."
);
create_exception!(
    ccrkit,
    Unreachable,
    SolveError,
    "reach found no actuation putting the tip on the target (target, closest: the closest tip \
     found, distance [m]; result: that closest answer as a ccrkit.Reach, when raised by reach)."
);
create_exception!(
    ccrkit,
    NoPath,
    SolveError,
    "plan found no clear path to the goal (samples drawn, reason)."
);
create_exception!(
    ccrkit,
    ExportError,
    SolveError,
    "An export cannot be written (field: the option or disk, path)."
);

/// Attributes of one error, set on the exception instance.
#[derive(Default)]
struct Attrs {
    kind: &'static str,
    field: Option<String>,
    reason: String,
    cable: Option<String>,
    section: Option<usize>,
    method: Option<String>,
    iterations: Option<usize>,
    residual: Option<f64>,
    obstacle: Option<String>,
    path: Option<String>,
    target: Option<[f64; 3]>,
    closest: Option<[f64; 3]>,
    distance: Option<f64>,
    samples: Option<usize>,
}

fn raise<T: pyo3::PyTypeInfo>(py: Python<'_>, msg: String, a: Attrs) -> PyErr {
    let err = PyErr::new::<T, _>(msg);
    let value = err.value(py);
    let set = || -> PyResult<()> {
        let d = PyDict::new(py);
        d.set_item("kind", a.kind)?;
        d.set_item("field", a.field)?;
        d.set_item("reason", a.reason)?;
        d.set_item("cable", a.cable)?;
        d.set_item("section", a.section)?;
        d.set_item("method", a.method)?;
        d.set_item("iterations", a.iterations)?;
        d.set_item("residual", a.residual)?;
        d.set_item("obstacle", a.obstacle)?;
        d.set_item("path", a.path)?;
        d.set_item("target", a.target.map(|v| v.to_vec()))?;
        d.set_item("closest", a.closest.map(|v| v.to_vec()))?;
        d.set_item("distance", a.distance)?;
        d.set_item("samples", a.samples)?;
        for (k, v) in d.iter() {
            value.setattr(k.cast::<pyo3::types::PyString>()?, v)?;
        }
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// The Python exception of a core solve error.
pub fn solve_error(py: Python<'_>, e: &CoreSolveError) -> PyErr {
    let msg = e.to_string();
    let kind = e.kind();
    match e.clone() {
        CoreSolveError::InvalidInput { field, reason } => raise::<InvalidInput>(
            py,
            msg,
            Attrs {
                kind,
                field: Some(field),
                reason,
                ..Default::default()
            },
        ),
        CoreSolveError::Infeasible {
            cable,
            section,
            reason,
        } => raise::<Infeasible>(
            py,
            msg,
            Attrs {
                kind,
                field: Some(cable.clone()),
                reason,
                cable: Some(cable),
                section: Some(section),
                ..Default::default()
            },
        ),
        CoreSolveError::NotConverged {
            method,
            section,
            iterations,
            residual,
            detail,
        } => raise::<NotConverged>(
            py,
            msg,
            Attrs {
                kind,
                field: Some(method.clone()),
                reason: detail,
                method: Some(method),
                section,
                iterations: Some(iterations),
                residual: Some(residual),
                ..Default::default()
            },
        ),
        CoreSolveError::Obstructed {
            obstacle,
            section,
            reason,
        } => raise::<Obstructed>(
            py,
            msg,
            Attrs {
                kind,
                field: Some(obstacle.clone()),
                reason,
                obstacle: Some(obstacle),
                section: Some(section),
                ..Default::default()
            },
        ),
        CoreSolveError::Unsupported { method, reason } => raise::<Unsupported>(
            py,
            msg,
            Attrs {
                kind,
                field: Some(method.clone()),
                reason,
                method: Some(method),
                ..Default::default()
            },
        ),
        CoreSolveError::Unreachable {
            target,
            closest,
            distance,
            reason,
        } => raise::<Unreachable>(
            py,
            msg,
            Attrs {
                kind,
                field: Some("tip".into()),
                reason,
                target: Some(target),
                closest: Some(closest),
                distance: Some(distance),
                ..Default::default()
            },
        ),
        CoreSolveError::ContactBudget { .. } => raise::<ContactBudget>(
            py,
            msg.clone(),
            Attrs {
                kind,
                field: Some("obstacles".into()),
                reason: msg,
                ..Default::default()
            },
        ),
        CoreSolveError::NoPath { samples, reason } => raise::<NoPath>(
            py,
            msg,
            Attrs {
                kind,
                field: Some("plan".into()),
                reason,
                samples: Some(samples),
                ..Default::default()
            },
        ),
        // A kind this build of the extension does not know yet (the core's errors are
        // non-exhaustive): the base class, with the kind's name and the message.
        _ => raise::<SolveError>(
            py,
            msg.clone(),
            Attrs {
                kind,
                reason: msg,
                ..Default::default()
            },
        ),
    }
}

/// The Python exception of a model-file error.
pub fn model_error(py: Python<'_>, e: &CoreModelError) -> PyErr {
    let msg = e.to_string();
    let (field, reason, path) = match e.clone() {
        CoreModelError::Io { path, reason } => (None, reason, Some(path)),
        CoreModelError::Parse { path, reason } => (None, reason, Some(path)),
        CoreModelError::Invalid { field, reason } => (Some(field), reason, None),
        // A kind this build does not know yet (non-exhaustive): the message is the reason.
        _ => (None, msg.clone(), None),
    };
    raise::<ModelError>(
        py,
        msg,
        Attrs {
            kind: "model",
            field,
            reason,
            path,
            ..Default::default()
        },
    )
}

/// The Python exception of an export error (a bad option is an `InvalidInput`).
pub fn export_error(py: Python<'_>, e: &CoreExportError) -> PyErr {
    let msg = e.to_string();
    let attrs = |field: Option<String>, reason: String, path: Option<String>| Attrs {
        kind: "export",
        field,
        reason,
        path,
        ..Default::default()
    };
    match e.clone() {
        CoreExportError::InvalidOption { option, reason } => raise::<InvalidInput>(
            py,
            msg,
            Attrs {
                kind: "invalid_input",
                ..attrs(Some(option), reason, None)
            },
        ),
        CoreExportError::Io { path, reason } => {
            raise::<ExportError>(py, msg, attrs(None, reason, Some(path)))
        }
        CoreExportError::ShapeMismatch { robot, reason } => {
            raise::<ExportError>(py, msg, attrs(Some(robot), reason, None))
        }
        CoreExportError::BadDiskFrame { disk, reason } => {
            raise::<ExportError>(py, msg, attrs(Some(format!("disk {disk}")), reason, None))
        }
        CoreExportError::Urdf { reason } => {
            raise::<ExportError>(py, msg, attrs(None, reason, None))
        }
        CoreExportError::Input { field, reason } => raise::<InvalidInput>(
            py,
            msg,
            Attrs {
                kind: "invalid_input",
                ..attrs(Some(field), reason, None)
            },
        ),
    }
}

/// An output a call may not write (onto one of its inputs, or twice): an `InvalidInput` whose
/// `field` is the argument that named it, `path` the file, `reason` why (`crate::files`).
pub fn write_error(py: Python<'_>, argument: &str, e: &ccrkit::output::WriteError) -> PyErr {
    raise::<InvalidInput>(
        py,
        e.to_string(),
        Attrs {
            kind: "invalid_input",
            field: Some(argument.to_string()),
            reason: e.reason(),
            path: Some(e.path().to_string()),
            ..Default::default()
        },
    )
}

/// An `InvalidInput` raised by the bindings themselves (array shapes, argument types).
pub fn invalid(py: Python<'_>, field: &str, reason: impl Into<String>) -> PyErr {
    solve_error(
        py,
        &CoreSolveError::InvalidInput {
            field: field.into(),
            reason: reason.into(),
        },
    )
}

/// Register the exception types in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SolveError", py.get_type::<SolveError>())?;
    m.add("InvalidInput", py.get_type::<InvalidInput>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("Infeasible", py.get_type::<Infeasible>())?;
    m.add("NotConverged", py.get_type::<NotConverged>())?;
    m.add("Obstructed", py.get_type::<Obstructed>())?;
    m.add("Unsupported", py.get_type::<Unsupported>())?;
    m.add("ExportError", py.get_type::<ExportError>())?;
    m.add("ContactBudget", py.get_type::<ContactBudget>())?;
    m.add("Unreachable", py.get_type::<Unreachable>())?;
    m.add("NoPath", py.get_type::<NoPath>())?;
    Ok(())
}
