//! Exports in MuJoCo: every link has a physical mass and inertia (totals
//! against closed forms), names are unique, and MuJoCo loads the URDF and its forward
//! kinematics at the SRDF joint values puts every disk where the solver did, to 1e-9 m.
//!
//! MuJoCo comes from `pip install mujoco` (`.ci/install-mujoco.sh`); without it the MuJoCo
//! test prints a note and passes unless `CCRKIT_REQUIRE_MUJOCO=1`.

use ccrkit::export::{export_urdf, UrdfMode, UrdfOptions, DEFAULT_BACKBONE_DENSITY};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::{Model, Robot, Shape};
use std::collections::HashSet;
use std::f64::consts::PI;
use std::path::Path;
use std::process::Command;

use crate::common::urdf_scripts;
use crate::common::urdf_scripts::python;

fn shapes() -> Vec<(String, Robot, Shape)> {
    let mut out = vec![];
    for n in 1..=3 {
        let model = Model::from_file(format!("models/paper/case{n}.toml")).expect("case");
        for k in [
            MethodKind::Geometric,
            MethodKind::Energy,
            MethodKind::Cosserat,
        ] {
            if let Ok(s) = SolveRequest::new(k).run(&model) {
                out.push((format!("case{n}-{k}"), model.robot.clone(), s.shape));
            }
        }
    }
    assert!(out.len() >= 6, "{} shapes", out.len());
    out
}

fn opts(mode: UrdfMode) -> UrdfOptions {
    UrdfOptions {
        mode,
        cables: true,
        name: None,
    }
}

#[test]
fn every_link_has_mass_and_the_totals_match_closed_forms() {
    for (name, robot, shape) in shapes() {
        // Independent totals: n + 1 solid PLA disks (no disk_mass in the paper files) and n
        // nitinol rods of l0 (no backbone density either).
        assert_eq!(robot.loads.disk_mass, 0.0);
        let n = robot.sections() as f64;
        let r = robot.disk_radius;
        let disk = 1240.0 * PI * r * r * robot.disk_thickness;
        let rod = DEFAULT_BACKBONE_DENSITY * robot.backbone.area() * robot.length();
        let expected = (n + 1.0) * disk + rod;
        for mode in [UrdfMode::Fixed, UrdfMode::Articulated] {
            let ex = export_urdf(&shape, &robot, &opts(mode)).expect("exports");
            let mut total = 0.0;
            let mut names = HashSet::new();
            for l in &ex.robot.links {
                let m = l.inertial.mass.value;
                total += m;
                let i = &l.inertial.inertia;
                if l.name != "base_link" {
                    assert!(m > 0.0, "{name} {mode} {}: mass {m}", l.name);
                    let (a, b, c) = (i.ixx, i.iyy, i.izz);
                    assert!(a > 0.0 && b > 0.0 && c > 0.0, "{name} {}", l.name);
                    // A real body's principal moments obey the triangle inequality (MuJoCo
                    // checks it); on the diagonal it holds within rounding.
                    assert!(a + b >= c * (1.0 - 1e-9), "{name} {}", l.name);
                    assert!(a + c >= b * (1.0 - 1e-9), "{name} {}", l.name);
                    assert!(b + c >= a * (1.0 - 1e-9), "{name} {}", l.name);
                }
                for v in &l.visual {
                    assert!(names.insert(v.name.clone()), "repeated {:?}", v.name);
                }
                for c in &l.collision {
                    assert!(names.insert(c.name.clone()), "repeated {:?}", c.name);
                }
            }
            assert!(
                (total - expected).abs() <= 1e-12 * expected,
                "{name} {mode}: total mass {total} kg, expected {expected} kg"
            );
        }
    }
}

#[test]
fn mujoco_loads_exports_and_its_kinematics_match_the_solved_disks() {
    let ok = Command::new(python())
        .args(["-c", "import mujoco"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        let why = format!(
            "{} cannot import mujoco; `pip install mujoco` (.ci/install-mujoco.sh)",
            python()
        );
        assert!(
            std::env::var("CCRKIT_REQUIRE_MUJOCO").as_deref() != Ok("1"),
            "CCRKIT_REQUIRE_MUJOCO=1 but {why}"
        );
        println!("SKIPPED: {why}");
        return;
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("urdf-mujoco");
    std::fs::create_dir_all(&dir).expect("dir");
    for (name, robot, shape) in shapes() {
        for mode in [UrdfMode::Fixed, UrdfMode::Articulated] {
            let path = dir.join(format!("{name}-{mode}.urdf"));
            let ex = export_urdf(&shape, &robot, &opts(mode)).expect("exports");
            ex.write_files(&path).expect("writes");
            // The solved disks themselves, not our own FK of the URDF.
            let solved =
                urdf_scripts::disks_json(shape.disks.iter().map(|d| (d.position, d.rotation)));
            let label = format!("{name:<22} {mode:<11}");
            urdf_scripts::check_with_script(
                "urdf_mujoco.py",
                &path,
                &ex,
                &robot.name,
                &solved,
                &label,
            );
        }
    }
}
