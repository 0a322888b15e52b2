//! The files of one Python call, checked as the command line's runs are
//! (`ccrkit::output::RunFiles`, the one check): a call on a model reads the model's files —
//! the file `Model.load` read, the scene file it names, the scenes `with_scene` added, every
//! mesh they name (`ccrkit::Model::files`) — and an output onto one of them, or two outputs of
//! the call on one file, is refused before any work. The writes themselves are the library's
//! (`ccrkit::output::write_file`: atomic, folders created).

use crate::errors::write_error;
use ccrkit::output::RunFiles;
use pyo3::prelude::*;
use std::path::PathBuf;

/// What `Model.with_scene` files are to a call (in its refusals).
pub const WITH_SCENE: &str = "scene file added by `with_scene`";

/// Claim `outputs` (each `(role, path)`, given by the argument `argument`) for a call on
/// `model`: an `InvalidInput` naming `argument` when one is a file of the model or two are one
/// file.
pub fn claim(
    py: Python<'_>,
    model: &ccrkit::Model,
    argument: &str,
    outputs: &[(String, PathBuf)],
) -> PyResult<()> {
    let mut run = RunFiles::new();
    run.read(&model.files())
        .and_then(|()| run.outputs(outputs))
        .map_err(|e| write_error(py, argument, &e))
}
