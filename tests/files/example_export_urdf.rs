//! The `export_urdf` example solves through the one solve path: the model's own obstacles are
//! part of the solve, so its fixed URDF is the command line's (`ccrkit export urdf`) byte for
//! byte. (It once solved with an empty scene and dropped them.)
//!
//! The example's binary is built by `cargo test` (or `cargo build --release --example
//! export_urdf`) next to this test's folder.

use crate::common::cli::{ccrkit_in, root, scratch};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The example's binary: `target/<profile>/examples/export_urdf`, beside `deps/` where this
/// test runs from.
fn example() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    let profile = exe
        .parent()
        .and_then(Path::parent)
        .expect("target/<profile>/deps");
    let bin = profile
        .join("examples")
        .join(format!("export_urdf{}", std::env::consts::EXE_SUFFIX));
    assert!(
        bin.exists(),
        "{} is not built: run the whole `cargo test --release` (it builds the examples) or \
         `cargo build --release --example export_urdf` first",
        bin.display()
    );
    bin
}

fn fixed_urdf(dir: &Path) -> String {
    let f = std::fs::read_dir(dir)
        .expect("output folder")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.to_string_lossy().ends_with("-fixed.urdf"))
        .unwrap_or_else(|| panic!("no *-fixed.urdf in {}", dir.display()));
    std::fs::read_to_string(f).expect("fixed URDF")
}

/// `ccrkit export urdf MODEL --method geometric --mode fixed --cables` into `dir`.
fn cli_fixed(model: &Path, dir: &Path) -> String {
    std::fs::create_dir_all(dir).expect("dir");
    let out = dir.join("robot-fixed.urdf");
    let o = ccrkit_in(
        &root(),
        &[
            "export".as_ref(),
            "urdf".as_ref(),
            model.as_os_str(),
            "--method".as_ref(),
            "geometric".as_ref(),
            "--mode".as_ref(),
            "fixed".as_ref(),
            "--cables".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(out).expect("CLI URDF")
}

#[test]
fn export_urdf_example_keeps_the_models_obstacles() {
    let dir = scratch("example-export-urdf");
    let case1 = std::fs::read_to_string(root().join("models/paper/case1.toml")).expect("case 1");
    // The wall the bent robot presses against (models/scenes/wall.toml), in the model file.
    let wall = "\n[[obstacles]]\nname = \"wall\"\nshape = \"box\"\n\
                position = [0.055, 0.0, 0.10]\nhalf_extents = [0.005, 0.15, 0.12]\n";
    let model = dir.join("case1-wall.toml");
    std::fs::write(&model, format!("{case1}{wall}")).expect("model");
    let out = dir.join("example");
    let run = Command::new(example())
        .arg(&out)
        .arg(&model)
        .output()
        .expect("example runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let with_wall = cli_fixed(&model, &dir.join("cli-wall"));
    let free = cli_fixed(
        &root().join("models/paper/case1.toml"),
        &dir.join("cli-free"),
    );
    assert_ne!(with_wall, free, "the wall must change the solved shape");
    assert_eq!(
        fixed_urdf(&out),
        with_wall,
        "the example's shape is the command line's, obstacles included"
    );
}
