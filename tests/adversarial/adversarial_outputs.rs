//! Outputs that would clobber inputs: every command's output named as one of the same run's
//! inputs — directly, through a symbolic or a hard link, or as another output of the run — is
//! refused by name before any work, and the input is left byte for byte as it was.

use crate::common::adversarial_harness::cli::ccrkit_in;
use crate::common::adversarial_harness::{root, scratch};
use std::path::{Path, PathBuf};

/// A scratch folder holding a copy of paper case 1 (`M.toml`), the wall scene (`wall.toml`), a
/// copy of it named `scene.svg`, a plan file (`plan.json`) and two rows of hardware data (`d.csv`).
fn fixtures(name: &str) -> PathBuf {
    let dir = scratch(&format!("outputs-{name}"));
    let copy = |from: &str, to: &str| {
        std::fs::copy(root().join(from), dir.join(to)).expect("copy fixture");
    };
    copy("models/paper/case1.toml", "M.toml");
    copy("models/scenes/wall.toml", "wall.toml");
    copy("models/scenes/wall.toml", "scene.svg");
    copy("models/hardware/ftdcr_v4.toml", "v4.toml");
    std::fs::write(dir.join("plan.json"), "{\"waypoints\": []}").expect("plan");
    let data = std::fs::read_to_string(
        root().join("models/hardware/data/v4/tdcr_sysid_20260511-183002_train.csv"),
    )
    .expect("hardware data");
    let rows: Vec<&str> = data.lines().take(3).collect();
    std::fs::write(dir.join("d.csv"), rows.join("\n")).expect("data");
    dir
}

/// Run `args` in `dir`: it must exit 1 with an error naming the refusal (`says`), and every file
/// of `dir` must be unchanged.
fn refused(dir: &Path, args: &[&str], says: &str) {
    let before = snapshot(dir);
    let out = ccrkit_in(dir, args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert!(
        err.contains("cannot write") && err.contains(says),
        "{args:?}: {err}"
    );
    assert_eq!(snapshot(dir), before, "{args:?} changed a file");
}

/// Every file of `dir` with its bytes, sorted by name.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .expect("lists")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_file())
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).expect("reads"),
            )
        })
        .collect();
    v.sort();
    v
}

const OVER: &str = "would be overwritten";

#[test]
fn an_output_onto_an_input_of_the_same_run_is_refused_by_name() {
    let dir = fixtures("inputs");
    refused(&dir, &["view", "M.toml", "--out", "M.toml"], OVER);
    let cases: &[&[&str]] = &[
        &["export", "urdf", "M.toml", "--out", "M.toml"],
        &[
            "export", "urdf", "M.toml", "--mode", "fixed", "--out", "M.toml",
        ],
        &["solve", "--json", "M.toml", "M.toml"],
        &[
            "solve",
            "M.toml",
            "--plot",
            "scene.svg",
            "--scene",
            "scene.svg",
        ],
        &[
            "view",
            "M.toml",
            "--scene",
            "wall.toml",
            "--out",
            "wall.toml",
        ],
        &[
            "view",
            "M.toml",
            "--plan",
            "plan.json",
            "--out",
            "plan.json",
        ],
        &["view", "M.toml", "--out", "./sub/../M.toml"],
        &[
            "compare",
            "M.toml",
            "--plot",
            "scene.svg",
            "--scene",
            "scene.svg",
        ],
        &["reach", "M.toml", "--tip", "0,0,0.1", "--json", "M.toml"],
        &["plan", "M.toml", "--to-tip", "0,0,0.1", "--json", "M.toml"],
        &[
            "plan",
            "M.toml",
            "--to-actuation",
            "plan.json",
            "--trajectory",
            "plan.json",
        ],
        &[
            "roadmap",
            "build",
            "M.toml",
            "--scene",
            "wall.toml",
            "--out",
            "wall.toml",
        ],
        &["predict", "v4.toml", "--data", "d.csv", "--out", "d.csv"],
        &["predict", "v4.toml", "--data", "d.csv", "--out", "v4.toml"],
        &[
            "calibrate",
            "v4.toml",
            "--data",
            "d.csv",
            "--out",
            "v4.toml",
        ],
        &["study", "merge", "d.csv", "d.csv"],
    ];
    for args in cases {
        refused(&dir, args, OVER);
    }
}

#[cfg(unix)]
#[test]
fn links_to_an_input_are_the_input() {
    let dir = fixtures("links");
    std::os::unix::fs::symlink(dir.join("M.toml"), dir.join("sym.toml")).expect("symlink");
    std::fs::hard_link(dir.join("d.csv"), dir.join("hard.csv")).expect("hard link");
    refused(&dir, &["view", "M.toml", "--out", "sym.toml"], OVER);
    refused(&dir, &["solve", "sym.toml", "--json", "M.toml"], OVER);
    refused(
        &dir,
        &["predict", "v4.toml", "--data", "d.csv", "--out", "hard.csv"],
        OVER,
    );
}

/// `--out a.srdf` in articulated mode would put the URDF and the SRDF on one file: refused
/// before either is written (the URDF was lost and `wrote a.srdf` printed twice).
#[test]
fn two_outputs_of_one_run_on_one_file_are_refused() {
    let dir = fixtures("twice");
    refused(
        &dir,
        &["export", "urdf", "M.toml", "--out", "a.srdf"],
        "same file as the URDF",
    );
    refused(
        &dir,
        &["solve", "M.toml", "--json", "s.svg", "--plot", "s.svg"],
        "same file",
    );
    assert!(!dir.join("a.srdf").exists() && !dir.join("s.svg").exists());
    // Fixed mode writes the URDF alone: `a.srdf` is then a fine name.
    let out = ccrkit_in(
        &dir,
        &[
            "export", "urdf", "M.toml", "--mode", "fixed", "--out", "a.srdf",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Every output creates its missing folders alike (`export` did, `view` refused them), and
/// leaves no temporary file beside it.
#[test]
fn every_output_creates_its_folder_and_leaves_no_temporary_file() {
    let dir = fixtures("folders");
    for (args, file) in [
        (
            vec!["view", "M.toml", "--out", "new1/v.html"],
            "new1/v.html",
        ),
        (
            vec!["solve", "M.toml", "--json", "new2/s.json"],
            "new2/s.json",
        ),
        (
            vec!["export", "urdf", "M.toml", "--out", "new3/a.urdf"],
            "new3/a.urdf",
        ),
        (
            vec!["solve", "M.toml", "--plot", "new4/s.svg"],
            "new4/s.svg",
        ),
    ] {
        let out = ccrkit_in(&dir, &args);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let p = dir.join(file);
        assert!(p.metadata().expect("written").len() > 0, "{file}");
        let folder = p.parent().expect("folder");
        for e in std::fs::read_dir(folder).expect("lists") {
            let name = e.expect("entry").file_name().to_string_lossy().into_owned();
            assert!(!name.starts_with(".ccrkit-"), "{name} left in {folder:?}");
        }
    }
}
