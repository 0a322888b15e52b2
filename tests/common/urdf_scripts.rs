//! Running the Python URDF checkers (`tests/scripts/urdf_fk.py` with yourdfpy,
//! `tests/scripts/urdf_mujoco.py` with MuJoCo) on an export: shared by the file tests `urdf`
//! and `urdf_mujoco`.
#![allow(dead_code)]

use ccrkit::export::UrdfExport;
use nalgebra::{Matrix3, Vector3};
use std::path::Path;
use std::process::Command;

/// The Python interpreter: `$PYTHON`, else `python3` (as in the `.ci/install-*.sh` scripts).
pub fn python() -> String {
    std::env::var("PYTHON").unwrap_or_else(|_| "python3".into())
}

/// The disk poses as the scripts read them: a list of `{"link": "disk_k", "position" [m],
/// "rotation" (row-major 3×3)}` in the frame of `base_link`, disk 0 first.
pub fn disks_json(poses: impl IntoIterator<Item = (Vector3<f64>, Matrix3<f64>)>) -> String {
    let list: Vec<_> = poses
        .into_iter()
        .enumerate()
        .map(|(k, (p, r))| {
            serde_json::json!({
                "link": format!("disk_{k}"),
                "position": [p.x, p.y, p.z],
                "rotation": [[r[(0,0)], r[(0,1)], r[(0,2)]],
                             [r[(1,0)], r[(1,1)], r[(1,2)]],
                             [r[(2,0)], r[(2,1)], r[(2,2)]]],
            })
        })
        .collect();
    serde_json::to_string(&list).expect("json")
}

/// Runs `tests/scripts/SCRIPT URDF EXPECTED` on the export written at `urdf` (its joint values: the
/// SRDF group state `robot_name` when the export has an SRDF, i.e. is articulated), with
/// `expected` (from [`disks_json`]) written beside it; prints the script's verdict after
/// `label` and fails with its output unless it exits 0.
pub fn check_with_script(
    script: &str,
    urdf: &Path,
    ex: &UrdfExport,
    robot_name: &str,
    expected: &str,
    label: &str,
) {
    let expected_path = urdf.with_extension("disks.json");
    std::fs::write(&expected_path, expected).expect("writes expected disks");
    let mut cmd = Command::new(python());
    cmd.arg(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/scripts")
            .join(script),
    )
    .arg(urdf)
    .arg(&expected_path);
    if ex.srdf.is_some() {
        cmd.arg("--srdf")
            .arg(urdf.with_extension("srdf"))
            .arg("--state")
            .arg(robot_name);
    }
    let out = cmd.output().expect("python runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{label}: {}", stdout.trim());
    assert!(
        out.status.success(),
        "{script} differs or refuses {label}:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
