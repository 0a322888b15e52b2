//! Replaying waypoints through a port on one exported URDF: the articulated export's joint
//! values at each waypoint (the port's prismatic `port_insertion` and revolute `port_rotation`
//! joints first, then six joints per section), set in yourdfpy, pybullet and MuJoCo, put every
//! disk where the solver put it at that waypoint, to 1e-9 m and 1e-9 rad (pybullet: the chain
//! it parsed; its own `getLinkState` answers in single precision, checked to 1e-6).
//!
//! The clients come from `.ci/install-urdf-tools.sh` (yourdfpy, pybullet) and
//! `.ci/install-mujoco.sh`; without one its replay prints a note and passes unless
//! `CCRKIT_REQUIRE_URDF_TOOLS=1` (yourdfpy, pybullet) or `CCRKIT_REQUIRE_MUJOCO=1` (MuJoCo).

use ccrkit::export::{export_urdf, UrdfExport, UrdfMode, UrdfOptions};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::model::actuation::Shortening;
use ccrkit::{Model, Shape};
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::urdf_scripts::python;

const TOL: f64 = 1e-9;
/// pybullet's own forward kinematics (`getLinkState`) comes back in single precision from the
/// PyPI build (a link at 0.0123456789012345 m reads 0.012345679104328156): ~10 ulps of f32
/// (ε = 1.2e-7) at the robots' 0.2 m scale and unit rotations. The chain pybullet parsed
/// (double precision) is checked at [`TOL`].
const F32_TOL: f64 = 1e-6;

/// Waypoints through the port: (insertion [m], rotation [rad], input scale of every cable).
const CASE2_WAYPOINTS: [(f64, f64, f64); 6] = [
    (0.18, 0.0, 1.0),
    (0.16, 0.8, 1.0),
    (0.14, 2.1, 0.7),
    (0.12, -1.3, 0.5),
    (0.16, 3.0, 0.0),
    (0.10, -2.9, 0.4),
];
const ROD_WAYPOINTS: [(f64, f64, f64); 6] = [
    (0.12, 0.0, 1.0),
    (0.10, 0.9, 1.5),
    (0.08, 2.5, 2.0),
    (0.05, -1.0, 3.0),
    (0.03, -3.0, 1.0),
    (0.11, 1.7, 0.0),
];

/// Case 2 through a turned port (displacement-driven, energy) and the soft lung rod (three
/// tendons inside the rod, tension-driven, energy), solved at each waypoint.
fn waypoint_shapes() -> Vec<(String, Model, Vec<Shape>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let case2 = std::fs::read_to_string(root.join("models/paper/case2.toml")).expect("case 2");
    let case2 = format!(
        "{case2}\n[port]\nposition = [0.02, -0.01, 0.05]\norientation = {{ rpy = [0.4, -0.3, 1.2] }}\n"
    );
    let case2 = Model::from_toml_str(&case2).expect("case 2 with a port");
    let mut rod = Model::from_file(root.join("models/soft/lung_rod.toml")).expect("lung rod");
    for (c, t) in rod.actuation.cables.iter_mut().zip([0.6, 0.3, 0.2]) {
        c.tension = Some(t);
    }
    let mut out = vec![];
    for (name, model, points) in [
        ("case2-port", case2, CASE2_WAYPOINTS),
        ("lung-rod", rod, ROD_WAYPOINTS),
    ] {
        let solver = SolveRequest::new(MethodKind::DEFAULT)
            .solver()
            .expect("a solver");
        let shapes = points
            .iter()
            .map(|&(d, psi, scale)| {
                let mut a = model.actuation.clone();
                a.insertion = Some(d);
                a.rotation = Some(psi);
                for c in &mut a.cables {
                    c.tension = c.tension.map(|t| t * scale);
                    c.shorten = c.shorten.map(|s| match s {
                        Shortening::Length(x) => Shortening::Length(x * scale),
                        Shortening::Fraction(x) => Shortening::Fraction(x * scale),
                    });
                }
                solver
                    .solve(&model.robot, &a, &model.scene, None)
                    .unwrap_or_else(|e| panic!("{name} at d = {d}, ψ = {psi}: {e}"))
            })
            .collect();
        out.push((name.to_string(), model, shapes));
    }
    out
}

fn export(model: &Model, shape: &Shape) -> UrdfExport {
    let opts = UrdfOptions {
        mode: UrdfMode::Articulated,
        cables: false,
        name: None,
    };
    export_urdf(shape, &model.robot, &opts).expect("exports")
}

/// A joint's kinematics as the URDF gives them (name, type, parent, child, origin, axis,
/// limits), to compare the exports of two waypoints.
fn kinematics(ex: &UrdfExport) -> Vec<String> {
    ex.robot
        .joints
        .iter()
        .map(|j| {
            format!(
                "{} {:?} {} {} {:?} {:?} {:?} [{}, {}]",
                j.name,
                j.joint_type,
                j.parent.link,
                j.child.link,
                j.origin.xyz.0,
                j.origin.rpy.0,
                j.axis.xyz.0,
                j.limit.lower,
                j.limit.upper
            )
        })
        .collect()
}

/// One URDF serves every waypoint: the exports at all waypoints have the same joints, origins,
/// axes and limits (the shape lives in the joint values alone), the port's two base joints
/// first, their values the waypoint's insertion and rotation.
#[test]
fn one_urdf_holds_every_waypoint_and_the_port_joints_carry_insertion_and_rotation() {
    for (name, model, shapes) in waypoint_shapes() {
        let first = kinematics(&export(&model, &shapes[0]));
        for (k, s) in shapes.iter().enumerate() {
            let ex = export(&model, s);
            assert_eq!(kinematics(&ex), first, "{name} waypoint {k}");
            let port = s.port.as_ref().expect("solved through the port");
            let v = &ex.joint_values;
            assert_eq!(v[0].name, "port_insertion");
            assert_eq!(v[1].name, "port_rotation");
            assert_eq!(v[0].value, port.insertion, "{name} waypoint {k}");
            assert_eq!(v[1].value, port.rotation, "{name} waypoint {k}");
        }
    }
}

fn tool_missing(tool: &str) -> Option<String> {
    let module = tool;
    match Command::new(python())
        .args(["-c", &format!("import {module}")])
        .output()
    {
        Ok(o) if o.status.success() => None,
        Ok(_) => Some(format!(
            "{} cannot import {module}; install it (.ci/install-{}.sh)",
            python(),
            if tool == "mujoco" {
                "mujoco"
            } else {
                "urdf-tools"
            }
        )),
        Err(e) => Some(format!("{} not runnable ({e})", python())),
    }
}

fn required(tool: &str) -> bool {
    let var = if tool == "mujoco" {
        "CCRKIT_REQUIRE_MUJOCO"
    } else {
        "CCRKIT_REQUIRE_URDF_TOOLS"
    };
    std::env::var(var).is_ok_and(|v| v == "1")
}

fn out_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("urdf-replay");
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// The waypoints as `tests/scripts/urdf_replay.py` reads them: each one's joint values and
/// solved disk frames (scene frame = `base_link`).
fn waypoints_json(model: &Model, shapes: &[Shape]) -> String {
    let list: Vec<_> = shapes
        .iter()
        .map(|s| {
            let joints: serde_json::Map<String, serde_json::Value> = export(model, s)
                .joint_values
                .iter()
                .map(|j| (j.name.clone(), j.value.into()))
                .collect();
            let disks: Vec<_> = s
                .disks
                .iter()
                .enumerate()
                .map(|(k, d)| {
                    let r = d.rotation;
                    serde_json::json!({
                        "link": format!("disk_{k}"),
                        "position": [d.position.x, d.position.y, d.position.z],
                        "rotation": [[r[(0, 0)], r[(0, 1)], r[(0, 2)]],
                                     [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
                                     [r[(2, 0)], r[(2, 1)], r[(2, 2)]]],
                    })
                })
                .collect();
            serde_json::json!({ "joints": joints, "disks": disks })
        })
        .collect();
    serde_json::to_string(&list).expect("json")
}

fn replay(tool: &str, tol: f64) {
    let module = tool.split('-').next().unwrap_or(tool);
    if let Some(why) = tool_missing(module) {
        assert!(!required(tool), "{tool} is required but {why}");
        println!("SKIPPED: {why}");
        eprintln!("SKIPPED: {why}");
        return;
    }
    let dir = out_dir();
    for (name, model, shapes) in waypoint_shapes() {
        let urdf = dir.join(format!("{name}-{tool}.urdf"));
        export(&model, &shapes[0])
            .write_files(&urdf)
            .expect("writes");
        let wp = urdf.with_extension("waypoints.json");
        std::fs::write(&wp, waypoints_json(&model, &shapes)).expect("writes waypoints");
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/urdf_replay.py");
        let out = Command::new(python())
            .arg(script)
            .arg(&urdf)
            .arg(&wp)
            .args(["--tool", tool, "--tol", &tol.to_string()])
            .output()
            .expect("python runs");
        let stdout = String::from_utf8_lossy(&out.stdout);
        println!("{name:<11} {}", stdout.trim());
        assert!(
            out.status.success(),
            "{tool} does not replay {name}:\n{stdout}\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn yourdfpy_replays_waypoints_through_the_port() {
    replay("yourdfpy", TOL);
}

#[test]
fn pybullet_replays_waypoints_through_the_port() {
    replay("pybullet", TOL);
    replay("pybullet-engine", F32_TOL);
}

#[test]
fn mujoco_replays_waypoints_through_the_port() {
    replay("mujoco", TOL);
}

/// The masses MuJoCo needs keep the robot's: through a port the links sum to the closed form
/// (case 2: n + 1 PLA disks and the nitinol rod; the lung rod without spacer disks: its rod,
/// ρ·A·L, ρ = 1100 kg/m³), and every moving link has mass.
#[test]
fn port_links_and_rod_stations_carry_the_robots_mass() {
    use ccrkit::export::DEFAULT_BACKBONE_DENSITY;
    use std::f64::consts::PI;
    for (name, model, shapes) in waypoint_shapes() {
        let r = &model.robot;
        let expected = if r.has_disks() {
            let disk = 1240.0 * PI * r.disk_radius.powi(2) * r.disk_thickness;
            (r.sections() as f64 + 1.0) * disk
                + DEFAULT_BACKBONE_DENSITY * r.backbone.area() * r.length()
        } else {
            1100.0 * PI * 0.003_f64.powi(2) * 0.12
        };
        let ex = export(&model, &shapes[2]);
        let total: f64 = ex.robot.links.iter().map(|l| l.inertial.mass.value).sum();
        assert!(
            (total - expected).abs() <= 1e-12 * expected,
            "{name}: {total} kg vs {expected} kg"
        );
        let moving: Vec<&str> = ex
            .robot
            .joints
            .iter()
            .filter(|j| !matches!(j.joint_type, urdf_rs::JointType::Fixed))
            .map(|j| j.child.link.as_str())
            .collect();
        for l in &ex.robot.links {
            if moving.contains(&l.name.as_str()) {
                assert!(
                    l.inertial.mass.value > 0.0,
                    "{name}: {} is massless",
                    l.name
                );
            }
        }
    }
}
