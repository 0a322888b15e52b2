//! The port: insertion `d` and rotation `ψ` in the model, every method, and the shape.

use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{Model, Scene, Shape, SolveError};
use nalgebra::{Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};

/// A three-cable robot (two straight, one helical per metre), `extra` appended (e.g. a port).
fn robot_text(cables: &str, extra: &str) -> String {
    format!(
        "name = \"port-test\"\n[robot]\nsections = 8\nsection_length = 0.015\ndisk_radius = 0.008\n\
         disk_thickness = 0.0015\nbackbone = {{ youngs_modulus = 5e10, poisson_ratio = 0.3, diameter = 0.001 }}\n\
         {cables}\n{extra}\n"
    )
}

const ONE_CABLE: &str = "[[cables]]\nname = \"A\"\nradius = 0.005\nangles = { straight = 0.0 }\nshorten = 0.002\ntension = 1.0\n";

const PORT: &str =
    "[port]\nposition = [0.01, -0.02, 0.03]\norientation = { rpy = [0.3, -0.2, 0.5] }\n";

fn model(text: &str) -> Model {
    Model::from_toml_str(text).expect("model parses")
}

fn solve(m: &Model, kind: MethodKind, settings: &Settings) -> Result<Shape, SolveError> {
    SolveRequest::new(kind)
        .with_settings(settings.clone())
        .solver()?
        .solve(&m.robot, &m.actuation, &m.scene, None)
}

fn port_pose() -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(0.01, -0.02, 0.03),
        UnitQuaternion::from_euler_angles(0.3, -0.2, 0.5),
    )
}

/// Constant curvature through a port: the shape is the arc of length `d` at the port, turned
/// by `ψ`, with the robot's first `L − d` straight behind the port (closed form: one straight
/// cable at radius r shortened by Δ turns the exposed arc by θ = Δ/r towards the cable).
#[test]
fn constant_curvature_through_a_port_is_the_arc_of_length_d() {
    let (r, delta, len) = (0.005, 0.002, 0.12);
    for (d, psi) in [
        (0.12, 0.0),
        (0.07, 0.4),
        (0.0301, -2.0),
        (0.015, 1.0),
        (0.004, 3.0),
    ] {
        let text = robot_text(
            ONE_CABLE,
            &format!("{PORT}insertion = {d}\nrotation = {psi}\n"),
        );
        let m = model(&text);
        let s = solve(&m, MethodKind::ConstantCurvature, &Settings::new()).expect("solves");
        let theta = delta / r;
        let kappa = theta / d;
        let arc = |a: f64| {
            Vector3::new(
                (1.0 - (kappa * a).cos()) / kappa,
                0.0,
                (kappa * a).sin() / kappa,
            )
        };
        let frame = port_pose() * Isometry3::rotation(Vector3::z() * psi);
        let tip = (frame * Point3::from(arc(d))).coords;
        assert!(
            (s.tip() - tip).norm() < 1e-12,
            "d {d} ψ {psi}: tip {:?} vs {:?}",
            s.tip(),
            tip
        );
        for (k, disk) in s.disks.iter().enumerate() {
            let sk = k as f64 * 0.015;
            let local = if sk <= len - d {
                Vector3::new(0.0, 0.0, sk - (len - d))
            } else {
                arc(sk - (len - d))
            };
            let want = (frame * Point3::from(local)).coords;
            assert!((disk.position - want).norm() < 1e-12, "d {d} disk {k}");
        }
        let st = s.port.as_ref().expect("port state");
        assert_eq!((st.insertion, st.rotation), (d, psi));
    }
}

/// Rotation ψ turns every point of the shape about the port axis, exactly, for every method
/// that solves the robot (no gravity: the robot beyond the port is the same problem).
#[test]
fn rotation_turns_the_shape_about_the_port_axis_for_every_method() {
    let cables = format!(
        "{ONE_CABLE}[[cables]]\nname = \"B\"\nradius = 0.005\nangles = {{ helix = {{ start = 2.0, per_metre = 8.0 }} }}\nshorten = 0.001\ntension = 0.5\n"
    );
    for kind in MethodKind::ALL {
        let at = |psi: f64| {
            let m = model(&robot_text(
                &cables,
                &format!("{PORT}insertion = 0.08\nrotation = {psi}\n"),
            ));
            solve(&m, kind, &Settings::new())
        };
        let (s0, s1) = match (at(0.0), at(0.9)) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(e), _) | (_, Err(e)) => {
                assert!(matches!(e, SolveError::Unsupported { .. }), "{kind}: {e}");
                continue;
            }
        };
        let pose = port_pose();
        let turn = pose * Isometry3::rotation(Vector3::z() * 0.9) * pose.inverse();
        for (a, b) in s0.disks.iter().zip(&s1.disks) {
            let want = (turn * Point3::from(a.position)).coords;
            assert!(
                (b.position - want).norm() < 1e-12,
                "{kind}: {:e}",
                (b.position - want).norm()
            );
        }
    }
}

/// A full insertion through a port at the origin is the robot without a port.
#[test]
fn full_insertion_at_the_origin_is_the_fixed_robot() {
    let cables = format!(
        "{ONE_CABLE}[[cables]]\nname = \"B\"\nradius = 0.005\nangles = {{ helix = {{ start = 2.0, per_metre = 8.0 }} }}\nshorten = 0.001\ntension = 0.5\n"
    );
    let fixed = model(&robot_text(&cables, ""));
    let ported = model(&robot_text(&cables, "[port]\n"));
    for kind in MethodKind::ALL {
        let (a, b) = match (
            solve(&fixed, kind, &Settings::new()),
            solve(&ported, kind, &Settings::new()),
        ) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(e), Err(_)) => {
                assert!(matches!(e, SolveError::Unsupported { .. }), "{kind}: {e}");
                continue;
            }
            (a, b) => panic!("{kind}: {:?} vs {:?}", a.err(), b.err()),
        };
        let d = a.rms_distance(&b).expect("same disks");
        assert!(d < 1e-12, "{kind}: {d:e}");
    }
}

#[test]
fn a_robot_without_a_port_refuses_insertion_and_rotation_by_name() {
    let m = model(&robot_text(ONE_CABLE, ""));
    for (act, field) in [
        (m.actuation.clone().with_insertion(0.05), "insertion"),
        (m.actuation.clone().with_rotation(0.1), "rotation"),
    ] {
        let e = SolveRequest::new(MethodKind::Energy)
            .solver()
            .unwrap()
            .solve(&m.robot, &act, &Scene::empty(), None)
            .unwrap_err();
        match e {
            SolveError::InvalidInput { field: f, reason } => {
                assert_eq!(f, field);
                assert!(reason.contains("port"), "{reason}");
            }
            other => panic!("{other}"),
        }
    }
}

#[test]
fn port_tables_are_checked_naming_the_field() {
    let bad = [
        ("[port]\ninsertion = 0.2\n", "port.insertion"),
        ("[port]\ninsertion = -0.01\n", "port.insertion"),
        ("[port]\nrotation = 1e9\n", "port.rotation"),
        ("[port]\nposition = [0.0, 1e9, 0.0]\n", "port.position[1]"),
        (
            "[port]\norientation = { quaternion = [0, 0, 0, 0] }\n",
            "port.orientation.quaternion",
        ),
        (
            "[port]\nlimits = { insertion = [0.05, 0.01] }\n",
            "port.limits.insertion",
        ),
        (
            "[port]\nlimits = { insertion = [0.0, 0.5] }\n",
            "port.limits.insertion[1]",
        ),
        (
            "[port]\nlimits = { rotation = [1.0, -1.0] }\n",
            "port.limits.rotation",
        ),
    ];
    for (extra, field) in bad {
        let e = Model::from_toml_str(&robot_text(ONE_CABLE, extra)).unwrap_err();
        assert_eq!(e.field(), Some(field), "{extra}: {e}");
    }
    let e = Model::from_toml_str(&robot_text(ONE_CABLE, "[port]\ndepth = 1\n")).unwrap_err();
    assert!(e.to_string().contains("depth"), "{e}");
}

#[test]
fn shape_json_carries_the_port() {
    let m = model(&robot_text(
        ONE_CABLE,
        &format!("{PORT}insertion = 0.05\nrotation = 0.7\n"),
    ));
    let s = solve(&m, MethodKind::Energy, &Settings::new()).expect("solves");
    let text = s.to_json_string();
    let back = Shape::from_json_str(&text).expect("reads");
    let (a, b) = (s.port.as_ref().unwrap(), back.port.as_ref().unwrap());
    assert_eq!(
        (a.insertion, a.rotation, a.first_disk),
        (b.insertion, b.rotation, b.first_disk)
    );
    let r = Rotation3::from(a.pose.rotation);
    let rb = Rotation3::from(b.pose.rotation);
    assert!((r.matrix() - rb.matrix()).norm() < 1e-12);
    assert_eq!(a.first_disk, 5);
}
