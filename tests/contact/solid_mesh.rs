//! Meshes as solids through the scene file and the solvers: a closed mesh declares its free
//! side; the distances to it are signed; every defect is refused by name.

use crate::common;

use ccrkit::mesh::to_obj;
use ccrkit::prelude::*;
use ccrkit::reach::clearance;
use nalgebra::Vector3;
use std::time::Instant;

/// The box `lo..hi` as 12 outward triangles.
fn box_mesh(lo: [f64; 3], hi: [f64; 3]) -> String {
    let v: Vec<Vector3<f64>> = (0..8)
        .map(|i: usize| Vector3::from_fn(|a, _| if (i >> a) & 1 == 0 { lo[a] } else { hi[a] }))
        .collect();
    let quads = [
        [0u32, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let t: Vec<[u32; 3]> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    to_obj(&v, &t)
}

/// A scene of one mesh obstacle written as `name.obj` (text `mesh`) with the obstacle's extra
/// lines `extra`.
fn scene(name: &str, mesh: &str, extra: &str) -> Result<Scene, ModelError> {
    common::scene_file("solid_mesh", &format!("{name}.obj"), mesh);
    let body = format!(
        "[[obstacles]]\nname = \"{name}\"\nshape = \"mesh\"\npath = \"{name}.obj\"\n{extra}"
    );
    Scene::from_file(common::scene_file(
        "solid_mesh",
        &format!("{name}.toml"),
        &body,
    ))
}

/// The paper's case-1 robot (180 mm, disks 12 mm) straight, unactuated.
fn straight() -> Model {
    let mut m = common::paper(1);
    m.actuation = m.actuation.scaled(0.0);
    m
}

#[test]
fn a_straight_robot_in_a_box_lumen_keeps_the_closed_form_clearance() {
    let model = straight();
    let lumen = scene(
        "lumen",
        &box_mesh([-0.03, -0.025, -0.05], [0.03, 0.025, 0.25]),
        "free = \"inside\"\n",
    )
    .unwrap();
    let solver = SolveRequest::new(MethodKind::Energy).solver().unwrap();
    let t = Instant::now();
    let shape = solver
        .solve(&model.robot, &model.actuation, &lumen, None)
        .unwrap();
    eprintln!("energy in the lumen: {:?}", t.elapsed());
    let c = clearance(&model.robot, &shape, &lumen).unwrap();
    // The disks' rims (12 mm) against the side walls 25 mm away.
    assert!((c.distance - (0.025 - 0.012)).abs() < 1e-9, "{c:?}");
}

#[test]
fn a_robot_through_the_end_of_a_lumen_is_beyond_the_wall() {
    let model = straight();
    let mesh = box_mesh([-0.03, -0.03, -0.01], [0.03, 0.03, 0.1]);
    let lumen = scene("short_lumen", &mesh, "free = \"inside\"\n").unwrap();
    let surface = scene("short_surface", &mesh, "").unwrap();
    let solver = SolveRequest::new(MethodKind::Geometric).solver().unwrap();
    let free = solver
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)
        .unwrap();
    // The tip is 80 mm beyond the end wall: the last disk's distance as a solid is its depth.
    let signed = clearance(&model.robot, &free, &lumen).unwrap();
    let unsigned = clearance(&model.robot, &free, &surface).unwrap();
    // As a surface only the disk across the end wall is seen (half its thickness); as the
    // solid, the tip's depth beyond it.
    assert!((unsigned.distance + 0.001).abs() < 1e-9, "{unsigned:?}");
    // The last backbone piece ends 80 mm beyond the wall; its radius is 1.5 mm.
    assert!((signed.distance + 0.0815).abs() < 1e-9, "{signed:?}");
}

#[test]
fn an_organ_is_avoided_from_outside() {
    let model = straight();
    // A block beside the robot, 10 mm from the disks' rims.
    let organ = scene(
        "organ",
        &box_mesh([0.022, -0.02, 0.05], [0.06, 0.02, 0.15]),
        "free = \"outside\"\n",
    )
    .unwrap();
    let solver = SolveRequest::new(MethodKind::Geometric).solver().unwrap();
    let shape = solver
        .solve(&model.robot, &model.actuation, &organ, None)
        .unwrap();
    let c = clearance(&model.robot, &shape, &organ).unwrap();
    assert!((c.distance - 0.010).abs() < 1e-9, "{c:?}");
}

#[test]
fn a_base_outside_the_lumen_is_refused_by_name() {
    let model = straight();
    let lumen = scene(
        "far_lumen",
        &box_mesh([0.1, 0.1, 0.1], [0.2, 0.2, 0.2]),
        "free = \"inside\"\n",
    )
    .unwrap();
    let solver = SolveRequest::new(MethodKind::Energy).solver().unwrap();
    let e = solver
        .solve(&model.robot, &model.actuation, &lumen, None)
        .unwrap_err();
    assert!(
        matches!(e, SolveError::Obstructed { section: 0, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("obstacle side"), "{e}");
}

#[test]
fn each_bad_solid_is_refused_naming_the_field_and_the_defect() {
    let cube = box_mesh([0.0; 3], [0.1; 3]);
    // Drop the last triangle: a hole.
    let open: String = {
        let lines: Vec<&str> = cube.lines().collect();
        lines[..lines.len() - 1].join("\n")
    };
    let cases: [(&str, String, &str, &[&str]); 4] = [
        (
            "open",
            open.clone(),
            "free = \"inside\"\n",
            &["obstacles[0].free", "not closed", "open.obj"],
        ),
        (
            "side",
            cube.clone(),
            "free = \"both\"\n",
            &["obstacles[0].free", "both"],
        ),
        (
            "flipped",
            cube.replacen("f 1 3 4", "f 1 4 3", 1),
            "free = \"outside\"\n",
            &["obstacles[0].free", "inconsistent orientation"],
        ),
        (
            "degenerate",
            cube.replacen("f 1 3 4", "f 1 3 3", 1),
            "",
            &["obstacles[0].path", "degenerate"],
        ),
    ];
    for (name, mesh, extra, what) in cases {
        let msg = scene(name, &mesh, extra).expect_err(name).to_string();
        for w in what {
            assert!(msg.contains(w), "{name}: `{msg}` does not name `{w}`");
        }
    }
    // An open surface without `free` stays a surface.
    scene("open_surface", &open, "").unwrap();
    // `free` belongs to meshes only.
    common::scene_refused_naming(
        "solid_mesh",
        "ball.toml",
        "[[obstacles]]\nshape = \"sphere\"\nradius = 0.01\nfree = \"inside\"\n",
        &["obstacles[0].free"],
    );
}

/// A straight robot whose last 80 mm lie beyond the end wall of a lumen: no method hands out
/// a shape; the energy model names the obstacle and says the start crosses it, before its
/// first step.
#[test]
fn a_start_across_the_wall_is_refused() {
    let model = straight();
    let lumen = scene(
        "end_lumen",
        &box_mesh([-0.03, -0.03, -0.01], [0.03, 0.03, 0.1]),
        "free = \"inside\"\n",
    )
    .unwrap();
    for kind in [MethodKind::Energy, MethodKind::Geometric] {
        let solver = SolveRequest::new(kind).solver().unwrap();
        let t = Instant::now();
        let r = solver.solve(&model.robot, &model.actuation, &lumen, None);
        eprintln!("{kind:?}: {r:?} in {:?}", t.elapsed());
        let e = r.expect_err("no shape across the wall");
        if kind == MethodKind::Energy {
            assert!(
                matches!(&e, SolveError::Obstructed { obstacle, .. } if obstacle == "end_lumen"),
                "{e}"
            );
            assert!(e.to_string().contains("the start crosses"), "{e}");
            // Refused before the first step, not after the last iteration.
            assert!(
                e.to_string().contains("across the wall of this solid mesh"),
                "{e}"
            );
        }
    }
}

/// The same box as a surface (no `free`): closed, so the start across its end wall is refused
/// before the first step too (it took 60 iterations before, 20–30 s on a 25 000-triangle
/// sphere); the box without its bottom face is open (a feature could slide off its edge), so
/// it is not refused at once.
#[test]
fn a_start_across_a_closed_surface_is_refused_at_once() {
    let model = straight();
    let closed = box_mesh([-0.03, -0.03, -0.01], [0.03, 0.03, 0.1]);
    let surface = scene("end_surface", &closed, "").unwrap();
    let solver = SolveRequest::new(MethodKind::Energy).solver().unwrap();
    let e = solver
        .solve(&model.robot, &model.actuation, &surface, None)
        .expect_err("no shape across the surface");
    assert!(
        matches!(&e, SolveError::Obstructed { obstacle, .. } if obstacle == "end_surface"),
        "{e}"
    );
    assert!(
        e.to_string().contains("across this closed surface mesh"),
        "{e}"
    );
    // The bottom face (z = −0.01, the first two triangles) left out: a hole.
    let open: String = closed
        .lines()
        .filter(|l| !l.starts_with("f ") || !l.ends_with("1 3 4") && !l.ends_with("1 4 2"))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_eq!(open.lines().count() + 2, closed.lines().count(), "{open}");
    let surface = scene("end_open", &open, "").unwrap();
    let r = solver.solve(&model.robot, &model.actuation, &surface, None);
    eprintln!("open: {r:?}");
    assert!(
        !r.is_err_and(|e| e.to_string().contains("closed surface")),
        "an open surface is not closed"
    );
}
