//! `energy` pressing on a concave faceted wall from inside (a sphere meshed as a lumen): the
//! robot settles where two or three faces hold it, which one constraint on the closest
//! triangle alone never reached (it switched faces from one iterate to the next until the
//! iterations ran out). Checked against independent facts: every contact on the sphere, every
//! disk inside it, the mesh's clearance from the shape ≥ 0; outside, against the same sphere
//! as a primitive.

use crate::common;
use ccrkit_test_support::scenes::uv_sphere_obj;

use ccrkit::prelude::*;
use ccrkit::reach::clearance;
use nalgebra::Vector3;

/// The scene of one meshed sphere (`stacks` × `slices`), free side `free`, written as `name`.
fn sphere_scene(
    name: &str,
    r: f64,
    c: Vector3<f64>,
    (stacks, slices): (usize, usize),
    free: &str,
) -> Scene {
    common::scene_file(
        "concave_lumen",
        &format!("{name}.obj"),
        &uv_sphere_obj(r, [c.x, c.y, c.z], stacks, slices),
    );
    let body = format!(
        "[[obstacles]]\nname = \"{name}\"\nshape = \"mesh\"\npath = \"{name}.obj\"\n\
         free = \"{free}\"\n"
    );
    Scene::from_file(common::scene_file(
        "concave_lumen",
        &format!("{name}.toml"),
        &body,
    ))
    .expect("sphere scene")
}

#[test]
fn the_robot_settles_on_a_concave_faceted_wall_held_by_several_faces() {
    // The paper's case-1 robot: straight it fits the sphere (R = 100 mm about z = 90 mm);
    // bent freely its tip would reach 115 mm from the centre, so disk 9 presses on the wall.
    let model = common::paper(1);
    let (r, c) = (0.1, Vector3::new(0.0, 0.0, 0.09));
    let scene = sphere_scene("cavity", r, c, (60, 80), "inside");
    let shape = held(&model, &scene, r, c);
    assert!(
        shape.contacts.len() >= 2,
        "held by several faces: {:?}",
        shape.contacts
    );
}

/// A face whose point under the feature lies beyond its triangle across concave edges, behind
/// the wall, is a constraint too (`contact::solid::face_contacts`): the faces a disk presses on
/// enter the step together instead of one per iteration. Before, case I in the 25k-triangle
/// sphere took 48 iterations (the faces alternating), and case II in a 98 mm sphere of 50 × 64
/// quads ran its 60 iterations to an error; the counts are deterministic.
#[test]
fn faces_beyond_concave_edges_enter_the_step_together() {
    let (r, c) = (0.1, Vector3::new(0.0, 0.0, 0.09));
    let scene = sphere_scene("lumen_25k", r, c, (100, 128), "inside");
    let shape = held(&common::paper(1), &scene, r, c);
    assert!(
        shape.report.iterations <= 40,
        "{} iterations",
        shape.report.iterations
    );
    let (r, c) = (0.098, Vector3::new(0.0, 0.004, 0.088));
    let scene = sphere_scene("lumen_98", r, c, (50, 64), "inside");
    let shape = held(&common::paper(2), &scene, r, c);
    assert!(
        shape.report.iterations <= 25,
        "{} iterations",
        shape.report.iterations
    );
}

/// `model` solved by `energy` inside the meshed sphere `scene` (radius `r` about `c`): every
/// contact touching and pressing on the sphere's facets, every disk inside the sphere, and
/// the mesh's clearance from the shape ≥ 0.
fn held(model: &Model, scene: &Scene, r: f64, c: Vector3<f64>) -> Shape {
    let shape = SolveRequest::new(MethodKind::Energy)
        .solver()
        .expect("solver")
        .solve(&model.robot, &model.actuation, scene, None)
        .expect("settles against the wall");
    let contacts = &shape.contacts;
    eprintln!(
        "tip {:?}, {} contacts, {} iterations",
        shape.tip() * 1e3,
        contacts.len(),
        shape.report.iterations
    );
    assert!(!contacts.is_empty(), "pressing on the wall");
    // The facets' vertices lie on the sphere, their points inside it by less than 3e-4 m at
    // these resolutions (60 × 80 quads of 100 mm, 50 × 64 of 98 mm); a face's plane beyond
    // its triangle would put the point outside.
    for ct in contacts {
        let from_centre = (Vector3::from(ct.point_obstacle) - c).norm();
        assert!(
            from_centre <= r + 1e-12 && from_centre >= r - 3e-4,
            "a contact on the sphere's facets: {from_centre}"
        );
        assert!(ct.distance.abs() <= 1e-9, "touching: {}", ct.distance);
        assert!(ct.multiplier > 0.0, "pressing: {}", ct.multiplier);
    }
    // Each disk's point farthest from the centre: its offset along the disk's axis `a` grown
    // by half the thickness, and across it grown by the disk radius.
    for (k, d) in shape.disks.iter().enumerate() {
        let a = d.rotation.column(2).into_owned();
        let off = d.position - c;
        let axial = off.dot(&a);
        let across = (off - axial * a).norm() + model.robot.disk_radius;
        let along = axial.abs() + 0.5 * model.robot.disk_thickness;
        let rim = (along * along + across * across).sqrt();
        assert!(rim <= r + 1e-9, "disk {k} inside the sphere: {rim}");
    }
    let clear = clearance(&model.robot, &shape, scene).expect("near the wall");
    assert!(
        clear.distance >= -1e-9,
        "clear of the wall: {}",
        clear.distance
    );
    shape
}

#[test]
fn a_faceted_sphere_seen_from_outside_agrees_with_the_sphere() {
    // The same robot's tip pressing on a ball of 30 mm beside its bend: the faceted ball
    // against parry's exact ball. Frictionless, the facets' normals (off the sphere's by up
    // to half a facet's angle) push the tip sideways, where the robot is soft (~3EI/L³ ≈
    // 2.3 N/m against a 0.09 N reaction): 0.3 mm at 60 × 80 facets, 0.02 mm at 100 × 128.
    let model = common::paper(1);
    let c = Vector3::new(0.07735, 0.11064, 0.10);
    let faceted = sphere_scene("organ", 0.03, c, (100, 128), "outside");
    let body = format!(
        "[[obstacles]]\nname = \"organ\"\nshape = \"sphere\"\nradius = 0.03\n\
         position = [{}, {}, {}]\n",
        c.x, c.y, c.z
    );
    let ball = Scene::from_file(common::scene_file("concave_lumen", "ball.toml", &body))
        .expect("ball scene");
    let solver = SolveRequest::new(MethodKind::Energy)
        .solver()
        .expect("solver");
    let a = solver
        .solve(&model.robot, &model.actuation, &faceted, None)
        .expect("faceted");
    let b = solver
        .solve(&model.robot, &model.actuation, &ball, None)
        .expect("ball");
    let gap = (a.tip() - b.tip()).norm();
    eprintln!("faceted vs exact ball: tip {gap:.3e} m");
    assert!(!a.contacts.is_empty() && !b.contacts.is_empty());
    assert!(gap <= 5e-5, "faceted vs exact: {gap}");
}
