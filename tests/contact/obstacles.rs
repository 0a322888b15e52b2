//! Obstacles in the geometric section solver and the energy model, checked independently:
//! penetration recomputed with parry3d from the output disk frames and backbone polyline
//! (backbone capsules, disk cylinders, cable chords),
//! contact points projected on the obstacle and robot surfaces, exact equality with the free
//! shape when nothing is in reach, named errors for impossible scenes, scene-file validation.

use ccrkit::method::energy::{cable_lengths, elastic_energy, Energy};
use ccrkit::method::geometric::Geometric;
use ccrkit::method::solve_stepped;
use ccrkit::{Method, Model, Scene, Shape, SolveError};
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use parry3d::math::{Pose, Vector as PVec};
use parry3d::shape::{Capsule, Cylinder, Segment, Shape as PShape};
use proptest::prelude::*;
use std::path::PathBuf;

use crate::common::scenes;

use crate::common;
use crate::common::cli::root;

/// Deepest allowed penetration of any robot feature into any obstacle [m].
const PENETRATION_TOL: f64 = 1e-6;
/// Distance of a reported contact point from the surface it lies on [m].
const SURFACE_TOL: f64 = 1e-6;

fn case1() -> Model {
    Model::from_file(root().join("models/paper/case1.toml")).expect("case 1")
}

fn case1_text() -> String {
    std::fs::read_to_string(root().join("models/paper/case1.toml")).expect("case 1 text")
}

/// Case 1 with extra `[[obstacles]]` text.
fn case1_with(obstacles: &str) -> Model {
    Model::from_toml_str(&format!("{}\n{obstacles}", case1_text())).expect("model with obstacles")
}

fn pv(v: &Vector3<f64>) -> PVec {
    PVec::new(v.x, v.y, v.z)
}

fn pose(r: &Matrix3<f64>, t: &Vector3<f64>) -> Pose {
    Isometry3::from_parts(Translation3::from(*t), UnitQuaternion::from_matrix(r)).into()
}

/// Parry's cylinder axis is local y; the disk normal is local z.
fn y_to_z() -> Matrix3<f64> {
    Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0)
}

/// Every robot feature of a shape as (label, parry shape, pose).
fn features(model: &Model, shape: &Shape) -> Vec<(String, Box<dyn PShape>, Pose)> {
    let robot = &model.robot;
    let mut out: Vec<(String, Box<dyn PShape>, Pose)> = vec![];
    for (k, d) in shape.disks.iter().enumerate() {
        out.push((
            format!("disk {k}"),
            Box::new(Cylinder::new(robot.disk_thickness / 2.0, robot.disk_radius)),
            pose(&(d.rotation * y_to_z()), &d.position),
        ));
    }
    // The backbone polyline the method reports (disk centres for the section solver, sub-arc
    // ends for the energy model).
    for k in 1..shape.backbone.len() {
        out.push((
            format!("backbone {k}"),
            Box::new(Capsule::new(
                pv(&shape.backbone[k - 1]),
                pv(&shape.backbone[k]),
                robot.backbone.radius(),
            )),
            Pose::IDENTITY,
        ));
    }
    for c in &shape.cables {
        for k in 1..c.points.len() {
            if (c.points[k] - c.points[k - 1]).norm() > 0.0 {
                out.push((
                    format!("cable {} {k}", c.name),
                    Box::new(Segment::new(pv(&c.points[k - 1]), pv(&c.points[k]))),
                    Pose::IDENTITY,
                ));
            }
        }
    }
    out
}

/// Smallest signed distance between any feature and any obstacle, and where.
fn min_distance(model: &Model, shape: &Shape, scene: &Scene) -> (f64, String) {
    let mut best = (f64::INFINITY, String::new());
    for (label, g, gp) in features(model, shape) {
        for o in &scene.obstacles {
            if let Ok(Some(ct)) = parry3d::query::contact(&gp, &*g, &o.parry_pose, &*o.shape, 1.0) {
                if ct.dist < best.0 {
                    best = (ct.dist, format!("{label} / {}", o.name));
                }
            }
        }
    }
    best
}

/// No penetration, and every contact's points lie on the obstacle and on the robot.
pub(super) fn assert_valid(model: &Model, shape: &Shape, scene: &Scene) {
    let (d, where_) = min_distance(model, shape, scene);
    assert!(d >= -PENETRATION_TOL, "penetration {d:.3e} m at {where_}");
    let feats = features(model, shape);
    for c in &shape.contacts {
        let o = scene
            .obstacles
            .iter()
            .find(|o| o.name == c.obstacle)
            .expect("contact names a scene obstacle");
        let q = PVec::new(
            c.point_obstacle[0],
            c.point_obstacle[1],
            c.point_obstacle[2],
        );
        let proj = o.shape.project_point(&o.parry_pose, q, false);
        let off = (proj.point - q).length();
        assert!(
            off <= SURFACE_TOL,
            "contact point {:?} is {off:.3e} m off `{}`",
            c.point_obstacle,
            o.name
        );
        let r = PVec::new(c.point_robot[0], c.point_robot[1], c.point_robot[2]);
        let on_robot = feats
            .iter()
            .map(|(_, g, gp)| (g.project_point(gp, r, false).point - r).length())
            .fold(f64::INFINITY, f64::min);
        assert!(
            on_robot <= SURFACE_TOL,
            "robot contact point {:?} is {on_robot:.3e} m off every robot feature",
            c.point_robot
        );
    }
}

fn geometric() -> Geometric {
    Geometric::literal()
}

#[test]
fn obstacles_out_of_reach_give_exactly_the_free_shape() {
    let model = case1();
    let free = geometric()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    let far = case1_with(
        r#"
[[obstacles]]
name = "far-ball"
shape = "sphere"
position = [1.0, 1.0, 1.0]
radius = 0.05
[[obstacles]]
name = "far-box"
shape = "box"
position = [-0.5, 0.0, 0.1]
half_extents = [0.01, 0.01, 0.01]
"#,
    );
    assert_eq!(far.scene.obstacles.len(), 2);
    let s = geometric()
        .solve(&far.robot, &far.actuation, &far.scene, None)
        .unwrap();
    assert!(s.contacts.is_empty());
    for (a, b) in s.disks.iter().zip(&free.disks) {
        for k in 0..3 {
            assert_eq!(a.position[k].to_bits(), b.position[k].to_bits());
        }
    }
}

#[test]
fn a_wall_where_the_free_tip_would_be_stops_the_robot_there() {
    let model = case1();
    let free = geometric()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    let face = free.tip().x - 0.008;
    let walled = case1_with(&format!(
        r#"
[[obstacles]]
name = "wall"
shape = "box"
position = [{}, 0.0, 0.1]
half_extents = [0.005, 0.15, 0.12]
"#,
        face + 0.005
    ));
    let s = solve_stepped(
        &geometric(),
        &walled.robot,
        &walled.actuation,
        &walled.scene,
        2,
    )
    .expect("the robot presses on the wall");
    assert!(!s.contacts.is_empty(), "no contact reported");
    for c in &s.contacts {
        assert_eq!(c.obstacle, "wall");
        assert!((c.point_obstacle[0] - face).abs() < SURFACE_TOL);
        assert!(c.multiplier >= 0.0);
    }
    assert!(s.tip().x < free.tip().x);
    assert_valid(&walled, &s, &walled.scene);
}

#[test]
fn the_pillar_scene_converges_with_contacts_on_a_smooth_obstacle() {
    // Regression: disk-against-cylinder contacts chattered at ~1e-7 m (GJK vs EPA normals)
    // and no candidate was ever certified ("did not converge in section 5").
    let model = case1();
    let scene = Scene::from_file(root().join("models/scenes/pillar.toml")).unwrap();
    let s = geometric()
        .solve(&model.robot, &model.actuation, &scene, None)
        .expect("pillar solves");
    assert!(!s.contacts.is_empty());
    assert_valid(&model, &s, &scene);
}

#[test]
fn the_wall_scene_file_gives_contacts_on_the_last_disks() {
    let model = case1();
    let scene = Scene::from_file(root().join("models/scenes/wall.toml")).unwrap();
    let s = geometric()
        .solve(&model.robot, &model.actuation, &scene, None)
        .unwrap();
    let disks: Vec<usize> = s.contacts.iter().filter_map(|c| c.disk).collect();
    assert_eq!(disks, vec![8, 9]);
    assert_valid(&model, &s, &scene);
}

#[test]
fn the_base_inside_an_obstacle_is_obstructed_at_section_0() {
    let m = case1_with(
        r#"
[[obstacles]]
name = "blob"
shape = "sphere"
position = [0.0, 0.0, 0.0]
radius = 0.005
"#,
    );
    match geometric().solve(&m.robot, &m.actuation, &m.scene, None) {
        Err(SolveError::Obstructed {
            obstacle, section, ..
        }) => {
            assert_eq!(obstacle, "blob");
            assert_eq!(section, 0);
        }
        other => panic!("expected Obstructed at section 0, got {other:?}"),
    }
}

#[test]
fn a_robot_boxed_in_too_tightly_gives_a_named_error() {
    // A closed box of 28 mm x 28 mm x 17 mm around the base: disk 1 (radius 12 mm, 20 mm from
    // the base) fits nowhere inside.
    let mut text = String::new();
    for (name, p, h) in [
        ("px", [0.024, 0.0, 0.0], [0.01, 0.05, 0.05]),
        ("nx", [-0.024, 0.0, 0.0], [0.01, 0.05, 0.05]),
        ("py", [0.0, 0.024, 0.0], [0.05, 0.01, 0.05]),
        ("ny", [0.0, -0.024, 0.0], [0.05, 0.01, 0.05]),
        ("lid", [0.0, 0.0, 0.025], [0.05, 0.05, 0.01]),
        ("floor", [0.0, 0.0, -0.012], [0.05, 0.05, 0.01]),
    ] {
        text += &format!(
            "[[obstacles]]\nname = \"{name}\"\nshape = \"box\"\nposition = {p:?}\nhalf_extents = {h:?}\n"
        );
    }
    let m = case1_with(&text);
    match geometric().solve(&m.robot, &m.actuation, &m.scene, None) {
        Err(SolveError::Obstructed { .. })
        | Err(SolveError::Infeasible { .. })
        | Err(SolveError::NotConverged { .. }) => {}
        other => panic!("expected a named error, got {other:?}"),
    }
}

#[test]
fn the_committed_vessel_mesh_is_what_the_generator_writes() {
    let text = std::fs::read_to_string(root().join("models/meshes/vessel.obj")).unwrap();
    let body: String = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    let (v, t) = ccrkit::mesh::BentTube {
        bend_radius: 0.11,
        tube_radius: 0.02,
        theta0: -0.1,
        theta1: 1.8,
        rings: 61,
        segments: 32,
    }
    .open();
    assert_eq!(body, ccrkit::mesh::to_obj(&v, &t));
    let scene = Scene::from_file(root().join("models/scenes/vessel.toml")).unwrap();
    assert_eq!(scene.obstacles[0].name, "vessel");
}

#[test]
fn near_among_only_tests_the_given_obstacles() {
    let m = case1_with(
        r#"
[[obstacles]]
name = "a"
shape = "sphere"
position = [0.0, 0.0, 0.1]
radius = 0.01
[[obstacles]]
name = "b"
shape = "sphere"
position = [0.0, 0.0, 0.12]
radius = 0.01
"#,
    );
    let c = Vector3::new(0.0, 0.0, 0.1);
    assert_eq!(m.scene.near(&c, 0.05), vec![0, 1]);
    assert_eq!(m.scene.near_among(&[1], &c, 0.05), vec![1]);
    assert_eq!(m.scene.near_among(&[], &c, 0.05), Vec::<usize>::new());
    assert_eq!(m.scene.near_among(&[7], &c, 0.05), Vec::<usize>::new());
}

// ---- scene-file validation: one test per rule, each naming the field ----

/// `body` written as `name.toml` in the test's own temporary folder.
fn scene_file(name: &str, body: &str) -> PathBuf {
    common::scene_file("obstacles", &format!("{name}.toml"), body)
}

/// The TOML scene `body` (written as `name.toml`) is refused with an error naming each of
/// `what`.
fn refused_naming(name: &str, body: &str, what: &[&str]) {
    common::scene_refused_naming("obstacles", &format!("{name}.toml"), body, what);
}

#[test]
fn unknown_shape_is_rejected() {
    refused_naming(
        "shape",
        "[[obstacles]]\nshape = \"cone\"\nradius = 0.01\n",
        &["obstacles[0].shape", "cone"],
    );
}

#[test]
fn missing_size_is_rejected() {
    refused_naming(
        "missing",
        "[[obstacles]]\nshape = \"sphere\"\n",
        &["obstacles[0].radius"],
    );
    refused_naming(
        "missing-he",
        "[[obstacles]]\nshape = \"box\"\n",
        &["obstacles[0].half_extents"],
    );
}

#[test]
fn negative_size_is_rejected() {
    refused_naming(
        "neg",
        "[[obstacles]]\nshape = \"sphere\"\nradius = -0.01\n",
        &["obstacles[0].radius"],
    );
    refused_naming(
        "neg-he",
        "[[obstacles]]\nshape = \"box\"\nhalf_extents = [0.01, -0.02, 0.01]\n",
        &["obstacles[0].half_extents[1]"],
    );
    refused_naming(
        "neg-hh",
        "[[obstacles]]\nshape = \"cylinder\"\nradius = 0.01\nhalf_height = 0.0\n",
        &["obstacles[0].half_height"],
    );
}

#[test]
fn bad_quaternion_is_rejected() {
    refused_naming("quat", "[[obstacles]]\nshape = \"sphere\"\nradius = 0.01\nrotation = { quaternion = [0.0, 0.0, 0.0, 0.0] }\n", &["obstacles[0].rotation.quaternion"]);
}

#[test]
fn a_mesh_that_does_not_load_names_the_file() {
    refused_naming(
        "mesh",
        "[[obstacles]]\nshape = \"mesh\"\npath = \"no-such-vessel.obj\"\n",
        &["obstacles[0].path", "no-such-vessel.obj"],
    );
}

#[test]
fn duplicate_names_are_rejected() {
    refused_naming("dup", "[[obstacles]]\nname = \"x\"\nshape = \"sphere\"\nradius = 0.01\n[[obstacles]]\nname = \"x\"\nshape = \"sphere\"\nradius = 0.02\n", &["obstacles[1].name"]);
}

#[test]
fn unknown_fields_are_rejected() {
    refused_naming(
        "unknown",
        "[[obstacles]]\nshape = \"sphere\"\nradius = 0.01\ncolour = \"red\"\n",
        &["colour"],
    );
    refused_naming("unknown-top", "gravity = 9.81\n", &["gravity"]);
    refused_naming(
        "wrong-size",
        "[[obstacles]]\nshape = \"sphere\"\nradius = 0.01\nhalf_height = 0.01\n",
        &["obstacles[0].half_height"],
    );
}

// ---- random scenes ----

fn obstacle_strategy() -> impl Strategy<Value = String> {
    (
        prop::bool::ANY,
        -0.06f64..0.12,
        -0.06f64..0.14,
        0.03f64..0.19,
        0.004f64..0.02,
        0.004f64..0.02,
        0.004f64..0.02,
    )
        .prop_map(|(ball, x, y, z, a, b, c)| {
            if ball {
                format!("shape = \"sphere\"\nposition = [{x}, {y}, {z}]\nradius = {a}\n")
            } else {
                format!(
                    "shape = \"box\"\nposition = [{x}, {y}, {z}]\nhalf_extents = [{a}, {b}, {c}]\n"
                )
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Random spheres and boxes around the robot's reach: either a shape without penetration
    /// whose contacts lie on both surfaces, or a named error — never a wrong shape.
    #[test]
    fn random_scenes_never_give_a_penetrating_shape(obs in prop::collection::vec(obstacle_strategy(), 1..4)) {
        let text: String = obs.iter().map(|o| format!("[[obstacles]]\n{o}")).collect();
        let m = case1_with(&text);
        match solve_stepped(&geometric(), &m.robot, &m.actuation, &m.scene, 2) {
            Ok(s) => assert_valid(&m, &s, &m.scene),
            Err(SolveError::Obstructed { .. })
            | Err(SolveError::Infeasible { .. })
            | Err(SolveError::NotConverged { .. }) => {}
            Err(e) => panic!("unexpected error kind: {e}"),
        }
    }
}

/// Case 1 with both cables at 0 % and a ball that the straight robot would graze on the side
/// opposite both cables (at this angle [rad]); bending away from it slackens both.
fn slack_robot_next_to_a_ball() -> (Model, f64) {
    let text = case1_text()
        .replace("shorten_percent = 4.0", "shorten_percent = 0.0")
        .replace("shorten_percent = 3.0", "shorten_percent = 0.0");
    let a = 240f64.to_radians();
    let m = Model::from_toml_str(&format!(
        "{text}\n[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\nposition = [{}, {}, 0.1]\nradius = 0.01\n",
        0.02 * a.cos(),
        0.02 * a.sin()
    ))
    .unwrap();
    (m, a)
}

#[test]
#[ignore = "open: the slack face now runs, but section 5 is not certified (NotConverged)"]
fn an_obstacle_in_the_way_of_a_slack_section_bends_it_away() {
    // Regression: with every cable slack the section only tried the straight pose, and when
    // an obstacle blocked it the section was reported infeasible. Both cables at 0 %: the
    // straight robot would graze a ball on the side opposite both cables (240°), and bending
    // towards 60° slackens both.
    let (m, _) = slack_robot_next_to_a_ball();
    let s = geometric()
        .solve(&m.robot, &m.actuation, &m.scene, None)
        .expect("the slack robot bends away from the ball");
    assert!(!s.contacts.is_empty());
    assert_valid(&m, &s, &m.scene);
}

/// The scene the section solver cannot certify yet (above): a ball pushing on unactuated
/// (slack-at-zero) cables' robot. The whole-robot model bends away from it, the cables keep
/// their lengths or go slack, and the contact carries a positive reaction.
#[test]
fn energy_bends_a_slack_robot_away_from_an_obstacle() {
    let (m, a) = slack_robot_next_to_a_ball();
    let s = Energy::default()
        .solve(&m.robot, &m.actuation, &m.scene, None)
        .expect("the slack robot bends away from the ball");
    assert!(!s.contacts.is_empty());
    assert!(s.contacts.iter().all(|c| c.multiplier > 0.0));
    assert_valid(&m, &s, &m.scene);
    assert_lengths_met(&m, &s);
    // Away from the ball: the tip moves towards +60°.
    let tip = s.tip();
    assert!(tip.x * a.cos() + tip.y * a.sin() < 0.0, "tip {tip:?}");
}

#[test]
fn the_robot_in_the_vessel_presses_on_its_wall_without_crossing_it() {
    let model = case1();
    let scene = Scene::from_file(root().join("models/scenes/vessel.toml")).unwrap();
    let s = geometric()
        .solve(&model.robot, &model.actuation, &scene, None)
        .expect("the vessel scene solves");
    assert!(s.contacts.len() >= 3, "contacts: {:?}", s.contacts);
    assert_valid(&model, &s, &scene);
    // Unsigned distances cannot tell inside from outside: check each disk centre lies inside
    // the tube (closer to its centre line than the 20 mm radius), in the tube's frame.
    let (bend, radius) = (0.11, 0.02);
    let tube = &scene.obstacles[0];
    for (k, d) in s.disks.iter().enumerate() {
        let p = tube.pose.inverse() * nalgebra::Point3::from(d.position);
        let q = p.coords - Vector3::new(bend, 0.0, 0.0);
        let th = q.z.atan2(-q.x).clamp(-0.1, 1.8);
        let c = Vector3::new(bend * (1.0 - th.cos()), 0.0, bend * th.sin());
        assert!((p.coords - c).norm() < radius, "disk {k} left the tube");
    }
}

// ---- the energy model ----

/// Strains of an energy shape (its warm-start state minus the cable multipliers).
fn strains<'a>(shape: &'a Shape, model: &Model) -> &'a [f64] {
    let st = shape
        .report
        .warm
        .as_ref()
        .and_then(|w| w.strains())
        .expect("energy state");
    assert_eq!(st.len() % 4, 0, "{} cables", model.robot.cables.len());
    st
}

/// The energy model keeps the cable lengths with obstacles too: taut cables at their target.
fn assert_lengths_met(model: &Model, shape: &Shape) {
    let e = Energy::default();
    let xi = strains(shape, model);
    let len = cable_lengths(&model.robot, &e, xi).unwrap();
    let len0 = cable_lengths(&model.robot, &e, &vec![0.0; xi.len()]).unwrap();
    for (c, cable) in shape.cables.iter().enumerate() {
        let target = len0[c] - model.actuation.shortening_length(&model.robot, c).unwrap();
        let t = cable.tension.unwrap();
        assert!(len[c] <= target + 1e-9, "cable {c} longer than its length");
        if t > 0.0 {
            assert!(
                (len[c] - target).abs() <= 1e-9,
                "taut cable {c} off its length"
            );
        }
    }
}

#[test]
fn energy_obstacles_out_of_reach_or_clear_leave_the_free_shape() {
    let model = case1();
    let free = Energy::default()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    // Beyond reach: not even queried, the same iterations.
    let far = case1_with(
        "[[obstacles]]\nshape = \"sphere\"\nposition = [1.0, 1.0, 1.0]\nradius = 0.05\n",
    );
    let s = Energy::default()
        .solve(&far.robot, &far.actuation, &far.scene, None)
        .unwrap();
    assert_eq!(s.disks, free.disks);
    // Within reach but clear of the free shape (on the other side): same shape, no contact.
    let clear = case1_with(
        "[[obstacles]]\nshape = \"sphere\"\nposition = [-0.05, -0.05, 0.1]\nradius = 0.02\n",
    );
    let s = Energy::default()
        .solve(&clear.robot, &clear.actuation, &clear.scene, None)
        .unwrap();
    assert!(s.contacts.is_empty());
    for (a, b) in s.disks.iter().zip(&free.disks) {
        assert!((a.position - b.position).norm() < 1e-9);
    }
    assert_valid(&clear, &s, &clear.scene);
}

#[test]
fn energy_presses_on_the_wall_with_a_reaction_in_newtons() {
    let model = case1();
    let scene = Scene::from_file(root().join("models/scenes/wall.toml")).unwrap();
    let free = Energy::default()
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    let s = Energy::default()
        .solve(&model.robot, &model.actuation, &scene, None)
        .expect("the wall scene solves");
    assert!(!s.contacts.is_empty(), "no contact");
    for c in &s.contacts {
        assert_eq!(c.obstacle, "wall");
        assert!(c.multiplier > 0.0);
        // The wall's face is at x = 50 mm.
        assert!((c.point_obstacle[0] - 0.05).abs() < SURFACE_TOL);
    }
    assert!(free.tip().x > 0.05, "the free robot would cross the wall");
    assert_valid(&model, &s, &scene);
    assert_lengths_met(&model, &s);
}

/// The contact multiplier is a force: by the envelope theorem it is the rate at which the
/// optimal elastic energy grows with the clearance, `∂E*/∂c = Σ μ` (the cable lengths do not
/// depend on `c`). Checked by central differences of two more solves.
#[test]
fn energy_contact_multiplier_is_the_price_of_clearance() {
    let model = case1();
    let with = |c: f64| {
        let mut scene = Scene::from_file(root().join("models/scenes/wall.toml")).unwrap();
        scene.clearance = c;
        Energy::default()
            .solve(&model.robot, &model.actuation, &scene, None)
            .expect("wall with clearance")
    };
    let (c0, h) = (0.0005, 2e-5);
    let s = with(c0);
    let mu: f64 = s.contacts.iter().map(|c| c.multiplier).sum();
    assert!(mu > 0.0);
    let e =
        |sh: &Shape| elastic_energy(&model.robot, &Energy::default(), strains(sh, &model)).unwrap();
    let de = (e(&with(c0 + h)) - e(&with(c0 - h))) / (2.0 * h);
    eprintln!("wall, clearance 0.5 mm: dE*/dc = {de:.6} N, contact multipliers {mu:.6} N");
    assert!(
        (de - mu).abs() <= 1e-3 * mu,
        "dE*/dc = {de:.6} N, contact multipliers sum to {mu:.6} N"
    );
}

#[test]
fn energy_handles_smooth_obstacles_without_penetration() {
    let model = case1();
    let scene = Scene::from_file(root().join("models/scenes/pillar.toml")).unwrap();
    let s = Energy::default()
        .solve(&model.robot, &model.actuation, &scene, None)
        .expect("pillar solves");
    assert!(!s.contacts.is_empty());
    assert_valid(&model, &s, &scene);
    assert_lengths_met(&model, &s);
}

#[test]
fn energy_in_the_vessel_needs_a_start_inside_it() {
    let model = case1();
    let scene = Scene::from_file(root().join("models/scenes/vessel.toml")).unwrap();
    // The straight robot crosses the bent tube's wall: a named error, not a shape.
    match Energy::default().solve(&model.robot, &model.actuation, &scene, None) {
        Err(SolveError::Obstructed { obstacle, .. }) => assert_eq!(obstacle, "vessel"),
        other => panic!("expected Obstructed by the vessel, got {other:?}"),
    }
    // From the section solver's shape, which never leaves the tube, it solves.
    let start = geometric()
        .solve(&model.robot, &model.actuation, &scene, None)
        .unwrap();
    let s = Energy::default()
        .solve(&model.robot, &model.actuation, &scene, Some(&start))
        .expect("energy from inside the tube");
    assert_valid(&model, &s, &scene);
    assert_lengths_met(&model, &s);
    let (bend, radius) = (0.11, 0.02);
    let tube = &scene.obstacles[0];
    for (k, p) in s.backbone.iter().enumerate() {
        let p = tube.pose.inverse() * nalgebra::Point3::from(*p);
        let q = p.coords - Vector3::new(bend, 0.0, 0.0);
        let th = q.z.atan2(-q.x).clamp(-0.1, 1.8);
        let c = Vector3::new(bend * (1.0 - th.cos()), 0.0, bend * th.sin());
        assert!(
            (p.coords - c).norm() < radius,
            "backbone point {k} left the tube"
        );
    }
}

#[test]
fn energy_base_inside_an_obstacle_is_obstructed_at_section_0() {
    let m = case1_with(
        "[[obstacles]]\nname = \"blob\"\nshape = \"sphere\"\nposition = [0.0, 0.0, 0.0]\nradius = 0.005\n",
    );
    match Energy::default().solve(&m.robot, &m.actuation, &m.scene, None) {
        Err(SolveError::Obstructed {
            obstacle, section, ..
        }) => {
            assert_eq!(obstacle, "blob");
            assert_eq!(section, 0);
        }
        other => panic!("expected Obstructed at section 0, got {other:?}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// The energy model on random spheres and boxes: a shape without penetration that keeps
    /// the cable lengths, or a named error.
    #[test]
    fn energy_random_scenes_never_give_a_penetrating_shape(obs in prop::collection::vec(obstacle_strategy(), 1..4)) {
        let text: String = obs.iter().map(|o| format!("[[obstacles]]\n{o}")).collect();
        let m = case1_with(&text);
        match Energy::default().solve(&m.robot, &m.actuation, &m.scene, None) {
            Ok(s) => {
                assert_valid(&m, &s, &m.scene);
                assert_lengths_met(&m, &s);
            }
            Err(SolveError::Obstructed { .. })
            | Err(SolveError::Infeasible { .. })
            | Err(SolveError::NotConverged { .. }) => {}
            Err(e) => panic!("unexpected error kind: {e}"),
        }
    }
}

// ---- large scenes (1000 obstacles parsed and prepared in milliseconds) ----

#[test]
fn a_generated_scene_of_1000_obstacles_is_read_whole_with_exact_bounds() {
    let scene = Scene::from_file(scene_file("s1000", &scenes::scene_text(1000, 7))).unwrap();
    assert_eq!(scene.obstacles.len(), 1000);
    for (k, o) in scene.obstacles.iter().enumerate() {
        assert_eq!(o.name, format!("o{k}"));
        let c = o.pose.translation.vector;
        // Every bound holds the obstacle's centre; a sphere's bound is centre ± radius.
        assert!(
            (0..3).all(|a| o.aabb.0[a] <= c[a] && c[a] <= o.aabb.1[a]),
            "{}",
            o.name
        );
        if let ccrkit::model::scene::ObstacleKind::Sphere { radius } = o.kind {
            for a in 0..3 {
                assert!((o.aabb.0[a] - (c[a] - radius)).abs() < 1e-12);
                assert!((o.aabb.1[a] - (c[a] + radius)).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn a_repeated_name_after_1000_obstacles_is_named() {
    let text = scenes::scene_text(1000, 7)
        + "[[obstacles]]\nname = \"o3\"\nshape = \"sphere\"\nradius = 0.01\n";
    refused_naming("dup1000", &text, &["obstacles[1000].name", "o3"]);
}
