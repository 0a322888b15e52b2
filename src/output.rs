//! Every file ccrkit writes goes through [`write_with`] (text and bytes through [`write_file`]):
//!
//! - **atomically**: the content goes to a temporary file in the destination's folder, is
//!   flushed to disk, and is renamed over the destination only when complete, so an interrupted
//!   run leaves the old file (or none), never a truncated one;
//! - **folders created**: a missing parent folder of an output is created (every command,
//!   every output alike);
//! - **never over an input**: a command lists the files it reads and the files it will write in
//!   one [`RunFiles`], which refuses, before any work, an output that is one of the run's inputs
//!   (the same path once canonicalized, through symbolic links, or the same file through a hard
//!   link: same device and inode) or that another output of the run already claims.
//!
//! A destination that is a symbolic link is replaced by the new file (the link, not its
//! target, is renamed over). New files get mode 0644 on Unix; a replaced file keeps its mode.

use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why an output was not written. Every variant reads `cannot write `PATH`: REASON`, and
/// converts to the `Io { path, reason }` of the crate's other error types with that reason.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum WriteError {
    /// The output is a file this run reads.
    #[error("cannot write `{path}`: {}", self.reason())]
    Clobbers {
        /// What the output is (e.g. `--out file`).
        output: String,
        /// The output's path as given.
        path: String,
        /// What the input is (e.g. `model file`).
        input: String,
        /// The input's path as given.
        input_path: String,
    },
    /// Two outputs of one run are the same file.
    #[error("cannot write `{path}`: {}", self.reason())]
    Twice {
        /// What the output is.
        output: String,
        /// The output's path as given.
        path: String,
        /// The other output claiming the same file.
        other: String,
    },
    /// The operating system refused (a folder could not be made, the disk is full, …).
    #[error("cannot write `{path}`: {reason}")]
    Io {
        /// The path.
        path: String,
        /// What the operating system said.
        reason: String,
    },
}

impl WriteError {
    /// The output's path as given.
    pub fn path(&self) -> &str {
        match self {
            WriteError::Clobbers { path, .. }
            | WriteError::Twice { path, .. }
            | WriteError::Io { path, .. } => path,
        }
    }

    /// Why it was not written.
    pub fn reason(&self) -> String {
        match self {
            WriteError::Clobbers {
                output,
                input,
                input_path,
                ..
            } => format!(
                "the {output} is the {input} of this run (`{input_path}`) and would be overwritten: refused"
            ),
            WriteError::Twice { output, other, .. } => format!(
                "the {output} is the same file as the {other} of this run: refused (give another path)"
            ),
            WriteError::Io { reason, .. } => reason.clone(),
        }
    }
}

macro_rules! into_io {
    ($t:ty, $($v:tt)+) => {
        impl From<WriteError> for $t {
            fn from(e: WriteError) -> Self {
                $($v)+ {
                    path: e.path().to_string(),
                    reason: e.reason(),
                }
            }
        }
    };
}
into_io!(crate::error::ModelError, crate::error::ModelError::Io);
into_io!(crate::export::ExportError, crate::export::ExportError::Io);
into_io!(crate::study::StudyError, crate::study::StudyError::Io);
#[cfg(feature = "plot")]
into_io!(crate::plot::PlotError, crate::plot::PlotError);

/// The files of one run: what it reads and what it has claimed to write (see the module docs).
#[derive(Debug, Default, Clone)]
pub struct RunFiles {
    inputs: Vec<(String, PathBuf)>,
    outputs: Vec<(String, PathBuf)>,
}

impl RunFiles {
    /// No files yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Record `path` as read by this run, as its `role` (e.g. `model file`, `--scene file`).
    pub fn input(&mut self, role: &str, path: &Path) -> &mut Self {
        self.inputs.push((role.to_string(), path.to_path_buf()));
        self
    }

    /// Claim `path` as written by this run, as its `role` (e.g. `--out file`): refused when it
    /// is an input of the run or already claimed by another output. `-` (standard output) is
    /// never a file and always accepted.
    pub fn output(&mut self, role: &str, path: &Path) -> Result<(), WriteError> {
        if path.as_os_str() == "-" {
            return Ok(());
        }
        if let Some((input, p)) = self.inputs.iter().find(|(_, p)| same_file(path, p)) {
            return Err(WriteError::Clobbers {
                output: role.to_string(),
                path: path.display().to_string(),
                input: input.clone(),
                input_path: p.display().to_string(),
            });
        }
        if let Some((other, _)) = self.outputs.iter().find(|(_, p)| same_file(path, p)) {
            return Err(WriteError::Twice {
                output: role.to_string(),
                path: path.display().to_string(),
                other: other.clone(),
            });
        }
        self.outputs.push((role.to_string(), path.to_path_buf()));
        Ok(())
    }

    /// Record `files` (each `(role, path)`) as read by this run — the files a model or a scene
    /// was read from ([`crate::Model::files`], [`crate::Scene::files`]), known only once it is
    /// loaded — refused when one of them is an output the run has already claimed. A command
    /// claims its outputs first, loads, then calls this before it writes anything.
    pub fn read(&mut self, files: &[(String, PathBuf)]) -> Result<(), WriteError> {
        for (role, path) in files {
            if let Some((output, p)) = self.outputs.iter().find(|(_, o)| same_file(o, path)) {
                return Err(WriteError::Clobbers {
                    output: output.clone(),
                    path: p.display().to_string(),
                    input: role.clone(),
                    input_path: path.display().to_string(),
                });
            }
            self.inputs.push((role.clone(), path.clone()));
        }
        Ok(())
    }

    /// [`RunFiles::output`] for each `(role, path)` in turn.
    pub fn outputs<S: AsRef<str>, P: AsRef<Path>>(
        &mut self,
        list: &[(S, P)],
    ) -> Result<(), WriteError> {
        list.iter()
            .try_for_each(|(r, p)| self.output(r.as_ref(), p.as_ref()))
    }
}

/// Whether `a` and `b` name one file: the same file on disk when both exist (same device and
/// inode: hard links, symbolic links, `..`), else the same path once its folder is
/// canonicalized.
pub fn same_file(a: &Path, b: &Path) -> bool {
    if let Ok(true) = same_file::is_same_file(a, b) {
        return true;
    }
    match (a.exists(), b.exists()) {
        (true, true) => false,
        _ => resolved(a) == resolved(b),
    }
}

/// `path` with its folder canonicalized where it exists (its last part kept as written), made
/// absolute otherwise.
fn resolved(path: &Path) -> PathBuf {
    if let Ok(p) = path.canonicalize() {
        return p;
    }
    let parent = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match (parent.canonicalize(), path.file_name()) {
        (Ok(d), Some(name)) => d.join(name),
        _ => lexical(path),
    }
}

/// `path` made absolute with `.` and `..` folded in (for a folder that does not exist yet).
fn lexical(path: &Path) -> PathBuf {
    use std::path::Component;
    let abs = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

/// Write `bytes` to `path` atomically, its folder created (see the module docs); the
/// atomic twin of `std::fs::write`.
pub fn write_file(path: impl AsRef<Path>, bytes: impl AsRef<[u8]>) -> Result<(), WriteError> {
    write_with(path.as_ref(), |tmp| {
        std::fs::write(tmp, bytes.as_ref()).map_err(|e| e.to_string())
    })
}

/// Write `path` atomically by having `fill` write a temporary file in the same folder, with the
/// same extension (for writers that choose a format by it), which then replaces `path`. The
/// one place every output of ccrkit is written.
pub fn write_with(
    path: &Path,
    fill: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), WriteError> {
    let io = |reason: String| WriteError::Io {
        path: path.display().to_string(),
        reason,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir).map_err(|e| WriteError::Io {
        path: dir.display().to_string(),
        reason: format!("cannot create the folder: {e}"),
    })?;
    let suffix = path
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    let tmp = tempfile::Builder::new()
        .prefix(".ccrkit-")
        .suffix(&suffix)
        .tempfile_in(dir)
        .map_err(|e| io(format!("cannot create a temporary file beside it: {e}")))?;
    fill(tmp.path()).map_err(io)?;
    tmp.as_file().sync_all().map_err(|e| io(e.to_string()))?;
    set_mode(tmp.path(), path).map_err(|e| io(e.to_string()))?;
    tmp.persist(path).map_err(|e| io(e.error.to_string()))?;
    Ok(())
}

/// The new file's mode: the replaced file's, or 0644 (a temporary file is made 0600).
#[cfg(unix)]
fn set_mode(tmp: &Path, dest: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    let perm = match std::fs::metadata(dest) {
        Ok(m) if m.is_file() => m.permissions(),
        _ => std::fs::Permissions::from_mode(0o644),
    };
    std::fs::set_permissions(tmp, perm)
}

/// Other platforms keep the temporary file's permissions.
#[cfg(not(unix))]
fn set_mode(_tmp: &Path, _dest: &Path) -> std::io::Result<()> {
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("ccrkit-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("dir");
        d
    }

    #[test]
    fn an_interrupted_write_leaves_the_old_file_whole() {
        let d = dir("atomic");
        let p = d.join("a.txt");
        write_file(&p, b"old").expect("writes");
        let e = write_with(&p, |tmp| {
            std::fs::write(tmp, b"half").map_err(|e| e.to_string())?;
            Err("interrupted".into())
        });
        assert!(matches!(e, Err(WriteError::Io { .. })), "{e:?}");
        assert_eq!(std::fs::read(&p).expect("reads"), b"old");
        let left: Vec<_> = std::fs::read_dir(&d).expect("lists").collect();
        assert_eq!(left.len(), 1, "no temporary file left behind");
    }

    #[test]
    fn a_missing_folder_is_created() {
        let d = dir("mkdir");
        let p = d.join("x/y/z.json");
        write_file(&p, b"{}").expect("writes");
        assert_eq!(std::fs::read(&p).expect("reads"), b"{}");
    }

    #[cfg(unix)]
    #[test]
    fn links_and_dot_dot_name_the_same_file() {
        let d = dir("links");
        let m = d.join("m.toml");
        std::fs::write(&m, "x").expect("writes");
        std::fs::create_dir_all(d.join("sub")).expect("dir");
        std::os::unix::fs::symlink(&m, d.join("sym.toml")).expect("symlink");
        std::fs::hard_link(&m, d.join("hard.toml")).expect("hard link");
        let mut run = RunFiles::new();
        run.input("model file", &m);
        for out in ["sym.toml", "hard.toml", "sub/../m.toml", "m.toml"] {
            let e = run.clone().output("--out file", &d.join(out));
            assert!(
                matches!(e, Err(WriteError::Clobbers { .. })),
                "{out}: {e:?}"
            );
        }
        run.output("--out file", &d.join("new/a.urdf"))
            .expect("new");
        let e = run.output("--srdf", &d.join("new/../new/a.urdf"));
        assert!(matches!(e, Err(WriteError::Twice { .. })), "{e:?}");
        run.output("stdout", Path::new("-")).expect("stdout");
        run.output("stdout", Path::new("-")).expect("stdout twice");
    }

    /// Files learnt only once a model is loaded (its scene and mesh files) are checked against
    /// the outputs claimed before, whether they exist yet or not, through `..` and links.
    #[cfg(unix)]
    #[test]
    fn files_read_after_the_outputs_are_claimed_are_checked_against_them() {
        let d = dir("read");
        std::fs::create_dir_all(d.join("meshes")).expect("dir");
        let mesh = d.join("meshes/wall.stl");
        std::fs::write(&mesh, "solid").expect("writes");
        std::os::unix::fs::symlink(&mesh, d.join("link.stl")).expect("symlink");
        let read = |p: PathBuf| vec![("mesh file of obstacle `w`".to_string(), p)];
        for out in ["meshes/wall.stl", "link.stl", "meshes/../meshes/wall.stl"] {
            let mut run = RunFiles::new();
            run.output("--out file", &d.join(out)).expect("claimed");
            let e = run.read(&read(d.join("meshes/./wall.stl")));
            match e {
                Err(WriteError::Clobbers { input, output, .. }) => {
                    assert_eq!(input, "mesh file of obstacle `w`");
                    assert_eq!(output, "--out file");
                }
                other => panic!("{out}: {other:?}"),
            }
        }
        // Neither exists yet: the same path once its folder is resolved.
        let mut run = RunFiles::new();
        run.output("--out file", &d.join("meshes/../new.toml"))
            .expect("claimed");
        assert!(run.read(&read(d.join("new.toml"))).is_err());
        assert!(run.read(&read(d.join("other.toml"))).is_ok());
        // And an output claimed after the read is refused too.
        let e = run.output("--json file", &d.join("other.toml"));
        assert!(matches!(e, Err(WriteError::Clobbers { .. })), "{e:?}");
    }
}
