//! Model files (TOML): robot + actuation (+ scene), parsed and validated at the boundary.
//!
//! ```toml
//! name = "paper-case-1"
//! [robot]
//! sections = 9                  # n; disks are numbered 0..=n
//! section_length = 0.020        # l0 \[m\] (or section_lengths = [...])
//! disk_radius = 0.012           # \[m\]
//! disk_thickness = 0.002        # \[m\]
//! backbone = { youngs_modulus = 1.1e9, poisson_ratio = 0.3, diameter = 0.003 }
//! [[cables]]
//! name = "A"
//! radius = 0.008                # hole radius \[m\]: one number, or one per disk it passes
//! angles = { straight = 0.0 }   # or { helix = { start, per_metre } } [rad, rad/m]
//!                               # or { helix = { start, per_disk } } or [a0, ..., a_end]
//! ends_at = 9                   # disk where the cable is tied (default: last)
//! shorten_percent = 4.0         # or shorten = 0.0072 \[m\]
//! tension = 4.16925             # \[N\]
//! stiffness = 4000.0            # optional: cable + actuator axial stiffness k \[N/m\] (EA / free length)
//! pretension = 0.5              # optional, needs stiffness: tension at zero command, straight \[N\]
//! [hardware]                    # optional: a real robot's gains, offsets and frames
//! gain = 1.0                    # see [`hardware`] for every field
//! [port]                        # optional: deployed through a port (see [`port`])
//! position = [0.0, 0.0, 0.0]    # [m]; orientation = { rpy = [...] }
//! insertion = 0.1               # [m] out of the port; rotation = 0.0 [rad]
//! ```
//!
//! Every rule is checked with an error naming the field ([`ModelError::Invalid`]); unknown
//! fields are rejected by the parser ([`ModelError::Parse`], whose message names them).

pub mod actuation;
pub mod bounds;
/// A solid mesh's signed-distance grid cached on disk, keyed by the mesh's content.
pub use crate::contact::field_cache;
mod file;
mod file_cable;
pub mod hardware;
pub mod limits;
pub mod mesh;
pub mod mesh_check;
pub mod name;
pub mod port;
pub mod read;
pub mod robot;
mod robot_check;
pub mod routing;
pub mod scene;
mod scene_file;

use crate::error::ModelError;
use actuation::Actuation;
use file::FileModel;
use robot::Robot;
use scene::Scene;
use std::path::{Path, PathBuf};

/// Largest number of sections accepted (guards against absurd allocations).
pub const MAX_SECTIONS: usize = 10_000;

/// A parsed, validated model file.
#[derive(Debug, Clone)]
pub struct Model {
    /// The robot.
    pub robot: Robot,
    /// Cable inputs from the file.
    pub actuation: Actuation,
    /// Obstacles (from `[[obstacles]]` and a referenced `scene` file).
    pub scene: Scene,
    /// Gains, offsets and frames of a real robot (identity when the file has no `[hardware]`).
    pub hardware: hardware::Hardware,
    /// Actuation limits per cable (`[limits.NAME]`; documented defaults otherwise).
    pub limits: limits::Limits,
    /// Where the file was read from (for resolving relative paths).
    pub source: Option<PathBuf>,
}

impl Model {
    /// Read and validate a model file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Model, ModelError> {
        Self::from_file_with_text(path).map(|(m, _)| m)
    }

    /// [`Model::from_file`] and the text it parsed, read once with the model file's cap
    /// ([`read::MAX_TEXT_BYTES`]): a front end that keeps a model as its text (Python pickles
    /// it so) keeps exactly the text that was checked.
    pub fn from_file_with_text(path: impl AsRef<Path>) -> Result<(Model, String), ModelError> {
        let path = path.as_ref();
        let text = read::read_text(path, "model file")?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut m = Self::from_toml_named(&text, &path.display().to_string(), dir)?;
        m.source = Some(path.to_path_buf());
        Ok((m, text))
    }

    /// The files this model was read from, each with what it was: the model file (when read
    /// by [`Model::from_file`]), then its scene's ([`Scene::files`]: a scene file it names,
    /// the mesh files its obstacles name). A run lists them among its inputs
    /// ([`crate::output::RunFiles::read`]).
    pub fn files(&self) -> Vec<(String, PathBuf)> {
        let own = self
            .source
            .iter()
            .map(|p| ("model file".to_string(), p.clone()));
        own.chain(self.scene.files().iter().cloned()).collect()
    }

    /// Parse and validate model text (relative mesh and scene paths resolve against the
    /// current directory).
    pub fn from_toml_str(text: &str) -> Result<Model, ModelError> {
        Self::from_toml_named(text, "<string>", Path::new("."))
    }

    /// Parse and validate model text whose relative mesh and scene paths resolve against
    /// `dir` (a model kept as text, e.g. sent to another process, that was read from `dir`).
    pub fn from_toml_in(text: &str, dir: &Path) -> Result<Model, ModelError> {
        Self::from_toml_named(text, "<string>", dir)
    }

    fn from_toml_named(text: &str, path: &str, dir: &Path) -> Result<Model, ModelError> {
        let file: FileModel = toml::from_str(text).map_err(|e| ModelError::Parse {
            path: path.to_string(),
            reason: e.to_string().trim_end().to_string(),
        })?;
        file.validate(dir)
    }
}
