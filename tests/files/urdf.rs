//! URDF export: round trip through urdf-rs, forward kinematics of the exported chain against
//! the solved disk frames, and the external checkers (`check_urdf`, Python `yourdfpy`).
//!
//! The FK here is written from the URDF spec, independently of the exporter: for each joint,
//! `T_child = T_parent · Trans(xyz) · Rz(yaw) Ry(pitch) Rx(roll) · motion(axis, q)`.

use ccrkit::export::{export_urdf, ExportError, UrdfExport, UrdfMode, UrdfOptions};
use ccrkit::shape::{DiskFrame, Shape, SolveReport};
use ccrkit::{method_by_name, Model, Robot, Scene};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::urdf_scripts;
use crate::common::urdf_scripts::python;

/// Largest accepted disk position error of the exported chain [m].
const POSITION_TOL: f64 = 1e-9;
/// Largest accepted disk rotation error of the exported chain [rad].
const ROTATION_TOL: f64 = 1e-9;
/// Tolerance of the URDF text round trip (numbers are written shortest-round-trip: exact).
const ROUND_TRIP_TOL: f64 = 0.0;

const CASES: [&str; 3] = [
    "models/paper/case1.toml",
    "models/paper/case2.toml",
    "models/paper/case3.toml",
];

fn solve_case(path: &str) -> (Robot, Shape) {
    let model = Model::from_file(Path::new(env!("CARGO_MANIFEST_DIR")).join(path))
        .unwrap_or_else(|e| panic!("{path}: {e}"));
    let method = method_by_name("geometric").expect("geometric method");
    let shape = method
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap_or_else(|e| panic!("{path}: {e}"));
    (model.robot, shape)
}

/// A hand-made shape of case 1's robot with large, arbitrary tilts, twists and chords that are
/// neither along the disk normal nor of length l0 (stands in for a shape next to an obstacle),
/// and a base disk that is not at the origin.
fn synthetic() -> (Robot, Shape) {
    let (robot, _) = solve_case(CASES[0]);
    let mut pos = Vector3::new(0.003, -0.002, 0.001);
    let mut rot = Rotation3::new(Vector3::new(0.05, -0.1, 0.7)).into_inner();
    let mut disks = vec![DiskFrame {
        s: 0.0,
        position: pos,
        rotation: rot,
    }];
    for i in 1..=robot.sections() {
        let f = i as f64;
        // Relative motion of disk i in disk i-1's frame: tilt, twist, chord off the normal.
        let mut w = Vector3::new(
            0.3 * (1.3 * f).sin(),
            -0.25 * (0.7 * f).cos(),
            0.4 * f - 1.5,
        );
        let mut dir = Vector3::new(0.35 * (2.1 * f).cos(), 0.3 * (1.7 * f).sin(), 1.0);
        match i {
            // The chord perpendicular to the disk normal: bend_y = π/2, bend_x arbitrary.
            5 => dir = Vector3::new(1.0, 0.0, 0.0),
            // Chord on the normal, disk turned by exactly π/2 about y: tilt_y = π/2.
            7 => {
                dir = Vector3::z();
                w = Vector3::new(0.0, std::f64::consts::FRAC_PI_2, 0.0);
            }
            _ => {}
        }
        let len = robot.section_length(i) * (1.0 + 0.05 * (3.0 * f).sin());
        pos += rot * (dir.normalize() * len);
        rot *= Rotation3::new(w).into_inner();
        disks.push(DiskFrame {
            s: robot.disk_s[i],
            position: pos,
            rotation: rot,
        });
    }
    let shape = Shape {
        method: "hand-made".into(),
        backbone: disks.iter().map(|d| d.position).collect(),
        disks,
        cables: vec![],
        contacts: vec![],
        port: None,
        report: SolveReport::default(),
    };
    (robot, shape)
}

fn all_shapes() -> Vec<(String, Robot, Shape)> {
    let mut v: Vec<_> = CASES
        .iter()
        .map(|c| {
            let (r, s) = solve_case(c);
            (c.to_string(), r, s)
        })
        .collect();
    let (r, s) = synthetic();
    v.push(("synthetic".into(), r, s));
    let (r, s) = next_to_wall();
    v.push(("case 1 against a wall".into(), r, s));
    let (r, s) = through_port();
    v.push(("case 2 through a port".into(), r, s));
    v
}

/// Case 2 deployed through a turned port, 0.113 m of its 0.18 m out and turned by 2.1 rad:
/// the articulated export starts with the port's prismatic and revolute joints.
fn through_port() -> (Robot, Shape) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("models/paper/case2.toml")).expect("case 2");
    let text = format!(
        "{text}\n[port]\nposition = [0.02, -0.01, 0.05]\norientation = {{ rpy = [0.4, -0.3, 1.2] }}\n\
         insertion = 0.113\nrotation = 2.1\n"
    );
    let model = Model::from_toml_str(&text).expect("case 2 with a port");
    let method = method_by_name("geometric").expect("geometric method");
    let shape = method
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .expect("case 2 through a port");
    assert!(shape.port.is_some());
    (model.robot, shape)
}

/// Case 1 solved next to `models/scenes/wall.toml`: disks 8 and 9 rest on the wall.
fn next_to_wall() -> (Robot, Shape) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let model = Model::from_file(root.join("models/paper/case1.toml")).expect("case 1");
    let scene = Scene::from_file(root.join("models/scenes/wall.toml")).expect("wall scene");
    let method = method_by_name("geometric").expect("geometric method");
    let shape = method
        .solve(&model.robot, &model.actuation, &scene, None)
        .expect("case 1 against the wall");
    assert!(!shape.contacts.is_empty(), "the wall must be touched");
    (model.robot, shape)
}

fn export(robot: &Robot, shape: &Shape, mode: UrdfMode) -> UrdfExport {
    let opts = UrdfOptions {
        mode,
        cables: true,
        name: None,
    };
    export_urdf(shape, robot, &opts).unwrap_or_else(|e| panic!("export {mode}: {e}"))
}

// ---------- a small, independent URDF forward kinematics ----------

type Pose = (Vector3<f64>, Matrix3<f64>);

fn rpy_matrix(rpy: &[f64; 3]) -> Matrix3<f64> {
    let r = |axis: Unit<Vector3<f64>>, a: f64| Rotation3::from_axis_angle(&axis, a).into_inner();
    r(Vector3::z_axis(), rpy[2]) * r(Vector3::y_axis(), rpy[1]) * r(Vector3::x_axis(), rpy[0])
}

/// Poses of every link in the frame of the root link, at joint values `q` (missing: 0).
fn forward_kinematics(urdf: &urdf_rs::Robot, q: &HashMap<String, f64>) -> HashMap<String, Pose> {
    let children: HashMap<&str, Vec<&urdf_rs::Joint>> =
        urdf.joints.iter().fold(HashMap::new(), |mut m, j| {
            m.entry(j.parent.link.as_str()).or_default().push(j);
            m
        });
    let is_child: std::collections::HashSet<&str> =
        urdf.joints.iter().map(|j| j.child.link.as_str()).collect();
    let roots: Vec<&str> = urdf
        .links
        .iter()
        .map(|l| l.name.as_str())
        .filter(|n| !is_child.contains(n))
        .collect();
    assert_eq!(roots, vec!["base_link"], "exactly one root, base_link");
    let mut poses = HashMap::new();
    let mut stack = vec![("base_link", (Vector3::zeros(), Matrix3::identity()))];
    while let Some((link, (p, r))) = stack.pop() {
        poses.insert(link.to_string(), (p, r));
        for j in children.get(link).into_iter().flatten() {
            let (xyz, rpy) = (&j.origin.xyz.0, &j.origin.rpy.0);
            let mut pj = p + r * Vector3::new(xyz[0], xyz[1], xyz[2]);
            let mut rj = r * rpy_matrix(rpy);
            let value = q.get(&j.name).copied().unwrap_or(0.0);
            let axis = Vector3::new(j.axis.xyz[0], j.axis.xyz[1], j.axis.xyz[2]);
            match j.joint_type {
                urdf_rs::JointType::Fixed => {}
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                    rj *=
                        Rotation3::from_axis_angle(&Unit::new_normalize(axis), value).into_inner();
                }
                urdf_rs::JointType::Prismatic => pj += rj * axis.normalize() * value,
                ref other => panic!("joint {} of unsupported type {other:?}", j.name),
            }
            stack.push((j.child.link.as_str(), (pj, rj)));
        }
    }
    poses
}

/// `name="…"`-style attribute of one XML tag.
fn attr(tag: &str, name: &str) -> Option<String> {
    let key = format!("{name}=\"");
    let start = tag.find(&key)? + key.len();
    let end = tag[start..].find('"')? + start;
    Some(tag[start..end].to_string())
}

/// Joint values of the SRDF's group_state `state`.
fn srdf_state(srdf: &str, state: &str) -> HashMap<String, f64> {
    let open = srdf
        .find(&format!("<group_state name=\"{state}\""))
        .unwrap_or_else(|| panic!("group_state `{state}` in SRDF"));
    let body = &srdf[open..srdf[open..].find("</group_state>").expect("closed") + open];
    body.split("<joint ")
        .skip(1)
        .map(|t| {
            let name = attr(t, "name").expect("joint name");
            let value = attr(t, "value").expect("joint value").parse().expect("f64");
            (name, value)
        })
        .collect()
}

fn rotation_angle(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    // ‖A − B‖_F = 2√2 sin(θ/2), accurate for small θ (unlike acos of the trace).
    2.0 * ((a - b).norm() / (2.0 * 2f64.sqrt())).min(1.0).asin()
}

/// Largest disk position and rotation errors of the exported chain at its stored values.
fn fk_errors(robot: &Robot, shape: &Shape, ex: &UrdfExport) -> (f64, f64) {
    let parsed = urdf_rs::read_from_string(&ex.urdf).expect("URDF parses");
    let q = match &ex.srdf {
        Some(srdf) => srdf_state(srdf, &robot.name),
        None => HashMap::new(),
    };
    assert_eq!(q.len(), ex.joint_values.len());
    let poses = forward_kinematics(&parsed, &q);
    let (mut ep, mut er) = (0.0f64, 0.0f64);
    for (k, d) in shape.disks.iter().enumerate() {
        let (p, r) = poses
            .get(&format!("disk_{k}"))
            .unwrap_or_else(|| panic!("link disk_{k}"));
        ep = ep.max((p - d.position).norm());
        er = er.max(rotation_angle(r, &d.rotation));
    }
    (ep, er)
}

#[test]
fn forward_kinematics_reproduces_solved_disks() {
    for (name, robot, shape) in all_shapes() {
        for mode in [UrdfMode::Fixed, UrdfMode::Articulated] {
            let ex = export(&robot, &shape, mode);
            let (ep, er) = fk_errors(&robot, &shape, &ex);
            println!("{name:<26} {mode:<11}: max disk position error {ep:.2e} m, rotation error {er:.2e} rad");
            assert!(ep <= POSITION_TOL, "{name} {mode}: position error {ep:e}");
            assert!(er <= ROTATION_TOL, "{name} {mode}: rotation error {er:e}");
        }
    }
}

fn same_pose(a: &urdf_rs::Pose, b: &urdf_rs::Pose, what: &str) {
    for k in 0..3 {
        assert!((a.xyz[k] - b.xyz[k]).abs() <= ROUND_TRIP_TOL, "{what} xyz");
        assert!((a.rpy[k] - b.rpy[k]).abs() <= ROUND_TRIP_TOL, "{what} rpy");
    }
}

#[test]
fn synthetic_shape_reaches_both_decomposition_singularities() {
    let (robot, shape) = synthetic();
    let ex = export(&robot, &shape, UrdfMode::Articulated);
    let value = |name: &str| {
        ex.joint_values
            .iter()
            .find(|v| v.name == name)
            .map(|v| v.value)
            .unwrap_or_else(|| panic!("joint {name}"))
    };
    let half_pi = std::f64::consts::FRAC_PI_2;
    assert!((value("section_5_bend_y") - half_pi).abs() < 1e-12);
    assert!((value("section_7_tilt_y") - half_pi).abs() < 1e-12);
}

#[test]
fn urdf_round_trip_keeps_every_origin() {
    for (name, robot, shape) in all_shapes() {
        for mode in [UrdfMode::Fixed, UrdfMode::Articulated] {
            let ex = export(&robot, &shape, mode);
            let text = urdf_rs::write_to_string(&ex.robot).expect("writes");
            assert_eq!(text, ex.urdf);
            let back = urdf_rs::read_from_string(&text).expect("reads back");
            assert_eq!(back.name, ex.robot.name);
            assert_eq!(back.links.len(), ex.robot.links.len(), "{name}");
            assert_eq!(back.joints.len(), ex.robot.joints.len(), "{name}");
            for (a, b) in ex.robot.joints.iter().zip(&back.joints) {
                let w = format!("{name} {mode} joint {}", a.name);
                assert_eq!(a.name, b.name);
                assert_eq!(a.joint_type, b.joint_type, "{w}");
                assert_eq!(a.parent.link, b.parent.link, "{w}");
                assert_eq!(a.child.link, b.child.link, "{w}");
                assert_eq!(a.axis.xyz, b.axis.xyz, "{w}");
                if a.joint_type != urdf_rs::JointType::Fixed {
                    assert_eq!(a.limit.lower, b.limit.lower, "{w}");
                    assert_eq!(a.limit.upper, b.limit.upper, "{w}");
                }
                same_pose(&a.origin, &b.origin, &w);
            }
            for (a, b) in ex.robot.links.iter().zip(&back.links) {
                assert_eq!(a.name, b.name);
                assert_eq!(a.visual.len(), b.visual.len(), "{}", a.name);
                assert_eq!(a.collision.len(), b.collision.len(), "{}", a.name);
                for (va, vb) in a.visual.iter().zip(&b.visual) {
                    same_pose(&va.origin, &vb.origin, &format!("{} visual", a.name));
                    assert_eq!(
                        va.material.as_ref().map(|m| &m.name),
                        vb.material.as_ref().map(|m| &m.name)
                    );
                }
                for (ca, cb) in a.collision.iter().zip(&b.collision) {
                    same_pose(&ca.origin, &cb.origin, &format!("{} collision", a.name));
                }
            }
        }
    }
}

#[test]
fn articulated_chain_has_six_limited_joints_per_section_and_geometry() {
    let (robot, shape) = solve_case(CASES[1]);
    let ex = export(&robot, &shape, UrdfMode::Articulated);
    let n = robot.sections();
    assert_eq!(ex.joint_values.len(), 6 * n);
    let movable: Vec<_> = ex
        .robot
        .joints
        .iter()
        .filter(|j| j.joint_type != urdf_rs::JointType::Fixed)
        .collect();
    assert_eq!(movable.len(), 6 * n);
    for (j, v) in movable.iter().zip(&ex.joint_values) {
        assert_eq!(j.name, v.name);
        assert!(
            j.limit.lower <= v.value && v.value <= j.limit.upper,
            "{}",
            j.name
        );
        assert!(j.limit.lower < j.limit.upper, "{}", j.name);
    }
    for k in 0..=n {
        let disk = ex
            .robot
            .links
            .iter()
            .find(|l| l.name == format!("disk_{k}"))
            .expect("disk link");
        match &disk.collision[0].geometry {
            urdf_rs::Geometry::Cylinder { radius, length } => {
                assert_eq!(*radius, robot.disk_radius);
                assert_eq!(*length, robot.disk_thickness);
            }
            g => panic!("disk geometry {g:?}"),
        }
    }
    let srdf = ex.srdf.as_deref().expect("srdf");
    assert!(srdf.contains("<chain base_link=\"base_link\" tip_link=\"disk_9\"/>"));
    // Every link the SRDF names exists in the URDF.
    for tag in srdf.split("<disable_collisions ").skip(1) {
        for key in ["link1", "link2"] {
            let link = attr(tag, key).expect("link attribute");
            assert!(ex.robot.links.iter().any(|l| l.name == link), "{link}");
        }
    }
    let json: serde_json::Value =
        serde_json::from_str(ex.json.as_deref().expect("json")).expect("JSON parses");
    let state = srdf_state(srdf, &robot.name);
    for j in json["joints"].as_array().expect("joints") {
        let name = j["name"].as_str().expect("name");
        assert_eq!(j["value"].as_f64(), state.get(name).copied(), "{name}");
    }
}

/// World end points and radius of every cylinder visual, by visual name, at the stored joint
/// values.
fn cylinder_ends(
    ex: &UrdfExport,
    state: &str,
) -> HashMap<String, (Vector3<f64>, Vector3<f64>, f64)> {
    let parsed = urdf_rs::read_from_string(&ex.urdf).expect("parses");
    let q = ex
        .srdf
        .as_deref()
        .map(|s| srdf_state(s, state))
        .unwrap_or_default();
    let poses = forward_kinematics(&parsed, &q);
    let mut ends = HashMap::new();
    for link in &parsed.links {
        let (p, r) = poses[&link.name];
        for v in &link.visual {
            if let urdf_rs::Geometry::Cylinder { radius, length } = v.geometry {
                let o = &v.origin;
                let c = p + r * Vector3::new(o.xyz[0], o.xyz[1], o.xyz[2]);
                let axis = r * rpy_matrix(&o.rpy.0) * Vector3::z() * (length / 2.0);
                // Visuals are `NAME_visual`, collisions `NAME_collision` (MuJoCo wants
                // unique names): key the cylinder by NAME.
                let name = v.name.clone().expect("visuals are named");
                let name = name
                    .strip_suffix("_visual")
                    .unwrap_or_else(|| panic!("visual `{name}` does not end in _visual"));
                ends.insert(name.to_string(), (c - axis, c + axis, radius));
            }
        }
    }
    ends
}

/// The backbone cylinders span the solved chords and the cable cylinders join the solved holes.
#[test]
fn geometry_spans_backbone_chords_and_cable_holes() {
    let (robot, shape) = solve_case(CASES[2]);
    let same_segment = |(a, b): (Vector3<f64>, Vector3<f64>), p: Vector3<f64>, q: Vector3<f64>| {
        ((a - p).norm() + (b - q).norm()).min((a - q).norm() + (b - p).norm())
    };
    for mode in [UrdfMode::Fixed, UrdfMode::Articulated] {
        let ex = export(&robot, &shape, mode);
        let ends = cylinder_ends(&ex, &robot.name);
        let (mut worst, mut cables_drawn) = (0.0f64, 0);
        for k in 1..=robot.sections() {
            let (a, b, radius) = ends[&format!("section_{k}_backbone")];
            assert_eq!(radius, robot.backbone.radius());
            let d = &shape.disks;
            worst = worst.max(same_segment((a, b), d[k - 1].position, d[k].position));
            for cable in &shape.cables {
                if let Some(&(a, b, _)) = ends.get(&format!("cable_{}_section_{k}", cable.name)) {
                    worst = worst.max(same_segment((a, b), cable.points[k - 1], cable.points[k]));
                    cables_drawn += 1;
                } else {
                    assert!(
                        cable.points.len() <= k,
                        "cable {} section {k} drawn",
                        cable.name
                    );
                }
            }
        }
        assert!(cables_drawn > 0, "no cable chords drawn");
        println!(
            "{mode}: largest cylinder end-point error {worst:.2e} m ({cables_drawn} cable chords)"
        );
        assert!(worst <= POSITION_TOL, "{mode}: {worst:e}");
    }
}

#[test]
fn bad_inputs_are_named_errors() {
    let (robot, mut shape) = solve_case(CASES[0]);
    let opts = UrdfOptions::default();
    shape.disks[3].rotation[(0, 0)] += 0.1;
    match export_urdf(&shape, &robot, &opts) {
        Err(ExportError::BadDiskFrame { disk: 3, .. }) => {}
        other => panic!("expected BadDiskFrame for disk 3, got {other:?}"),
    }
    shape.disks.pop();
    assert!(matches!(
        export_urdf(&shape, &robot, &opts),
        Err(ExportError::ShapeMismatch { .. })
    ));
    assert!(matches!(
        "snapshot".parse::<UrdfMode>(),
        Err(ExportError::InvalidOption { .. })
    ));
}

// ---------- external tools: check_urdf (urdfdom) and yourdfpy ----------

fn require_tools() -> bool {
    std::env::var("CCRKIT_REQUIRE_URDF_TOOLS").is_ok_and(|v| v == "1")
}

/// Why a tool is unusable, or `None` when it runs.
fn missing_check_urdf() -> Option<String> {
    match Command::new("check_urdf").arg("--help").output() {
        Ok(_) => None,
        Err(e) => Some(format!(
            "`check_urdf` not runnable ({e}); install liburdfdom-tools (.ci/install-urdf-tools.sh)"
        )),
    }
}

fn missing_yourdfpy() -> Option<String> {
    match Command::new(python())
        .args(["-c", "import yourdfpy"])
        .output()
    {
        Ok(o) if o.status.success() => None,
        Ok(o) => {
            Some(format!(
            "{} cannot import yourdfpy ({}); `pip install yourdfpy` (.ci/install-urdf-tools.sh)",
            python(),
            String::from_utf8_lossy(&o.stderr).trim().lines().last().unwrap_or("")
        ))
        }
        Err(e) => Some(format!("{} not runnable ({e})", python())),
    }
}

fn skip_or_fail(reason: &str) {
    if require_tools() {
        panic!("CCRKIT_REQUIRE_URDF_TOOLS=1 but {reason}");
    }
    println!("SKIPPED: {reason}");
    eprintln!("SKIPPED: {reason}");
}

fn out_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("urdf-test");
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

#[test]
fn check_urdf_accepts_exports() {
    if let Some(why) = missing_check_urdf() {
        return skip_or_fail(&why);
    }
    let dir = out_dir();
    for (name, robot, shape) in all_shapes() {
        for mode in [UrdfMode::Fixed, UrdfMode::Articulated] {
            let stem = format!("{}-{mode}", name.replace(['/', '.'], "_"));
            let path = dir.join(format!("{stem}.urdf"));
            export(&robot, &shape, mode)
                .write_files(&path)
                .expect("writes");
            let out = Command::new("check_urdf")
                .arg(&path)
                .output()
                .expect("check_urdf runs");
            let text = String::from_utf8_lossy(&out.stdout).to_string()
                + &String::from_utf8_lossy(&out.stderr);
            assert!(
                out.status.success() && text.contains("Successfully Parsed XML"),
                "check_urdf rejected {}:\n{text}",
                path.display()
            );
        }
    }
}

#[test]
fn yourdfpy_forward_kinematics_matches_ours() {
    if let Some(why) = missing_yourdfpy() {
        return skip_or_fail(&why);
    }
    let dir = out_dir();
    for (name, robot, shape) in all_shapes() {
        for mode in [UrdfMode::Fixed, UrdfMode::Articulated] {
            let stem = format!("{}-{mode}-py", name.replace(['/', '.'], "_"));
            let path = dir.join(format!("{stem}.urdf"));
            let ex = export(&robot, &shape, mode);
            ex.write_files(&path).expect("writes");
            // Our FK of every disk, for the script to compare against.
            let parsed = urdf_rs::read_from_string(&ex.urdf).expect("parses");
            let q = ex
                .srdf
                .as_deref()
                .map(|s| srdf_state(s, &robot.name))
                .unwrap_or_default();
            let poses = forward_kinematics(&parsed, &q);
            let ours = urdf_scripts::disks_json(
                (0..shape.disks.len()).map(|k| poses[&format!("disk_{k}")]),
            );
            let label = format!("{name:<26} {mode:<11}");
            urdf_scripts::check_with_script("urdf_fk.py", &path, &ex, &robot.name, &ours, &label);
        }
    }
}

#[test]
fn cli_exports_urdf_and_names_bad_mode() {
    let exe = env!("CARGO_BIN_EXE_ccrkit");
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join(CASES[0]);
    let dir = out_dir().join("cli");
    let out = dir.join("case1.urdf");
    let run = |mode: &str| {
        Command::new(exe)
            .args(["export", "urdf"])
            .arg(&model)
            .args(["--method", "geometric", "--mode", mode, "--cables", "--out"])
            .arg(&out)
            .output()
            .expect("ccrkit runs")
    };
    let ok = run("articulated");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    for ext in ["urdf", "srdf", "joints.json"] {
        assert!(out.with_extension(ext).is_file(), "{ext} written");
    }
    let urdf = urdf_rs::read_file(&out).expect("URDF reads");
    assert!(urdf.joints.iter().any(|j| j.name == "section_9_twist"));
    let bad = run("snapshot");
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("invalid option `mode`"));
}
