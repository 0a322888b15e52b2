//! The clearance of reach and plan reads the body as the solve's contact code does: the
//! backbone as capsules of the body radius (`robot.collision_radius`), no disks on a rod
//! without spacer disks, no cable chords for cables inside the rod, and, through a port,
//! nothing of what lies inside the port. Closed forms: a box beside or behind a straight rod.

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::reach::Space;
use ccrkit::Model;

/// A straight soft rod (6 mm, tendon inside at 2 mm, no spacer disks) with `body` added to
/// `[robot]`, a box `obstacle` and `port` appended.
fn rod(body: &str, obstacle: &str, port: &str) -> Model {
    let text = format!(
        "name = \"rod\"\n[robot]\nsections = 12\nsection_length = 0.01\ntendons = \"inside\"\n\
         spacer_disks = false\n{body}\n\
         backbone = {{ youngs_modulus = 2e6, poisson_ratio = 0.45, diameter = 0.006 }}\n\
         [[cables]]\nname = \"A\"\nradius = 0.002\nangles = {{ straight = 0.0 }}\n\
         [[obstacles]]\nname = \"box\"\nshape = \"box\"\n{obstacle}\n{port}"
    );
    Model::from_toml_str(&text).expect("model parses")
}

fn clearance(m: &Model) -> f64 {
    let space = Space::new(m, &SolveRequest::new(MethodKind::Energy), false).expect("space");
    let shape = space
        .solve(&space.clamp(&vec![0.0; space.dim()]), None)
        .expect("solves");
    space.clearance(&shape).expect("an obstacle").distance
}

/// A box whose face is 4 mm from the straight rod's axis: clear by 4 mm less the body radius
/// (the backbone's 3 mm, or the collision radius), never by the tendon inside the rod (2 mm
/// from the axis, towards the box) nor by the stations, which are no disks; a 5 mm body
/// overlaps the box (a negative clearance).
#[test]
fn the_clearance_is_the_body_radius_from_the_axis() {
    let wall = "position = [0.014, 0.0, 0.09]\nhalf_extents = [0.01, 0.02, 0.03]";
    for (body, r) in [("", 0.003), ("collision_radius = 0.001", 0.001)] {
        let d = clearance(&rod(body, wall, ""));
        assert!(
            (d - (0.004 - r)).abs() < 1e-9,
            "body radius {r}: clearance {d}"
        );
    }
    let d = clearance(&rod("collision_radius = 0.005", wall, ""));
    assert!(
        d < 0.0,
        "a 5 mm body overlaps the box 4 mm away: clearance {d}"
    );
}

/// Through a port, the part of the robot inside the port meets nothing: a box behind the port
/// on its axis, 10 mm below the port, is 10 mm less the body radius from the robot beyond it
/// (the capsule that starts at the port), however far the straight part behind reaches into it.
#[test]
fn what_lies_inside_the_port_meets_nothing() {
    let behind = "position = [0.0, 0.0, -0.05]\nhalf_extents = [0.01, 0.01, 0.04]";
    let port = "[port]\ninsertion = 0.06\nlimits = { insertion = [0.02, 0.12] }";
    let d = clearance(&rod("", behind, port));
    assert!((d - (0.01 - 0.003)).abs() < 1e-9, "clearance {d}");
}
