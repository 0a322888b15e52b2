//! Where the integration tests find things and run the binary: the repository root, the
//! paper cases, a scratch folder per test and process, and one run of the built `ccrkit`.
//! Depends on std only (`tests/common/mod.rs` declares it as `common::cli`; the adversarial
//! harness re-exports it).
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The path of paper case `n` (1, 2 or 3), as a command-line argument.
pub fn paper_path(n: usize) -> String {
    root()
        .join(format!("models/paper/case{n}.toml"))
        .display()
        .to_string()
}

/// A scratch folder `ccrkit-NAME-PID` in the system's temporary folder, created.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ccrkit-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// The built `ccrkit` run with `args` in `dir` to its end, its output captured.
pub fn ccrkit_in<S: AsRef<OsStr>>(dir: &Path, args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ccrkit"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("ccrkit runs")
}
