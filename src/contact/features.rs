//! The robot's features as parry shapes, the witness of one feature–obstacle pair, and the
//! contact record a shape reports.

use super::{nvec, polish, ppose, pvec, query, query_near, y_to_z, Witness};
use crate::model::robot::Robot;
use crate::shape::Contact;
use nalgebra::{Matrix3, Vector3};
use parry3d::math::Pose as PPose;
use parry3d::shape::{Capsule, Cylinder, Segment, Shape as PShape, ShapeType};

/// A backbone piece from `a` to `b`: a capsule of the backbone radius `radius`.
pub(crate) fn backbone(a: &Vector3<f64>, b: &Vector3<f64>, radius: f64) -> Capsule {
    Capsule::new(pvec(a), pvec(b), radius)
}

/// A disk of the robot: a cylinder of the disk radius and thickness, axis along parry's local
/// y (placed by [`disk_pose`]).
pub(crate) fn disk(robot: &Robot) -> Cylinder {
    Cylinder::new(robot.disk_thickness / 2.0, robot.disk_radius)
}

/// The parry pose of a disk with frame `r` (normal: its z axis) centred at `x`.
pub(crate) fn disk_pose(r: &Matrix3<f64>, x: &Vector3<f64>) -> PPose {
    ppose(&(r * y_to_z()), x)
}

/// A cable chord from hole `a` to hole `b`.
pub(crate) fn chord(a: &Vector3<f64>, b: &Vector3<f64>) -> Segment {
    Segment::new(pvec(a), pvec(b))
}

/// The closest points, normal (from the obstacle towards the robot) and signed distance of
/// feature `g` at `gpose` and obstacle `shape` at `opose`, or `None` beyond `margin`: parry's
/// answer ([`query`]) polished by alternating projections ([`polish`]) where that improves it;
/// with parry's own distance, before the polish.
pub(crate) fn witness(
    g: &dyn PShape,
    gpose: &PPose,
    shape: &dyn PShape,
    opose: &PPose,
    margin: f64,
) -> Option<(Witness, f64)> {
    witness_of(
        g,
        gpose,
        shape,
        opose,
        query(gpose, g, opose, shape, margin)?,
    )
}

/// [`witness`] of a pair that was near touching a moment ago with `(normal, distance)` `near`
/// (normal from the obstacle towards the robot): parry's answer from [`query_near`], else
/// from [`query`].
pub(crate) fn witness_near(
    g: &dyn PShape,
    gpose: &PPose,
    shape: &dyn PShape,
    opose: &PPose,
    margin: f64,
    near: (&Vector3<f64>, f64),
) -> Option<(Witness, f64)> {
    let ct = match query_near(gpose, g, opose, shape, margin, near) {
        Some(answer) => answer?,
        None => query(gpose, g, opose, shape, margin)?,
    };
    witness_of(g, gpose, shape, opose, ct)
}

/// The polished witness of parry's contact `ct` and parry's distance.
fn witness_of(
    g: &dyn PShape,
    gpose: &PPose,
    shape: &dyn PShape,
    opose: &PPose,
    ct: parry3d::query::Contact,
) -> Option<(Witness, f64)> {
    let rough = Witness {
        robot: nvec(ct.point1),
        obstacle: nvec(ct.point2),
        normal: -nvec(ct.normal1),
        dist: ct.dist,
    };
    Some((
        polish(g, gpose, shape, opose, &rough).unwrap_or(rough),
        ct.dist,
    ))
}

/// A lower bound on the distance from anything inside the ball `(center, radius)` to
/// `shape` at `pose`: the distance from the centre to the solid shape minus the radius (a
/// point of the ball is at most `radius` from the centre, and the distance to a set is
/// 1-Lipschitz), for the shapes whose point distance parry computes in closed form (ball,
/// box, capsule, cylinder); `None` for the others. Tighter than the distance to the shape's
/// axis-aligned bounds for a rotated shape (a tilted cylinder's bounds hold much empty space).
pub(crate) fn ball_gap(
    shape: &dyn PShape,
    pose: &PPose,
    center: &Vector3<f64>,
    radius: f64,
) -> Option<f64> {
    match shape.shape_type() {
        ShapeType::Ball | ShapeType::Cuboid | ShapeType::Capsule | ShapeType::Cylinder => {
            Some(shape.distance_to_point(pose, pvec(center), true) - radius)
        }
        _ => None,
    }
}

/// The point of a disk (frame `r`, centre `x`, radius `radius`, half thickness `half`)
/// farthest along `−normal` (`normal` from the obstacle towards the robot): the witness on the
/// rim exactly, where the iterative query places it to ~1e-6 only. `None` when the normal is
/// along the disk axis (a face touches; the query's point stands).
pub(crate) fn disk_support(
    r: &Matrix3<f64>,
    x: &Vector3<f64>,
    normal: &Vector3<f64>,
    radius: f64,
    half: f64,
) -> Option<Vector3<f64>> {
    let u = -(r.transpose() * normal);
    let uxy = (u.x * u.x + u.y * u.y).sqrt();
    (uxy > 1e-6).then(|| {
        let l = Vector3::new(radius * u.x / uxy, radius * u.y / uxy, half * u.z.signum());
        x + r * l
    })
}

/// The fraction `t ∈ [0, 1]` along the segment `a → b` of the point closest to `p` (1 for a
/// segment of zero length).
pub(crate) fn segment_fraction(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let d = b - a;
    if d.norm_squared() > 0.0 {
        ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// The robot feature of a reported contact.
pub(crate) enum Touching<'a> {
    /// The backbone in a section (1-based).
    Backbone { section: usize },
    /// A disk (1-based).
    Disk { disk: usize },
    /// The chord of the named cable in a section.
    Cable { name: &'a str, section: usize },
}

/// The contact a shape reports: obstacle `obstacle` touching `feature` at the witness `w`,
/// with multiplier (normal reaction) `mu`.
pub(crate) fn record(obstacle: String, feature: Touching, w: &Witness, mu: f64) -> Contact {
    let arr = |v: &Vector3<f64>| [v.x, v.y, v.z];
    let (feature, disk, section) = match feature {
        Touching::Backbone { section } => ("backbone".to_string(), None, Some(section)),
        Touching::Disk { disk } => ("disk".to_string(), Some(disk), None),
        Touching::Cable { name, section } => (format!("cable:{name}"), None, Some(section)),
    };
    Contact {
        obstacle,
        feature,
        disk,
        section,
        point_robot: arr(&w.robot),
        point_obstacle: arr(&w.obstacle),
        normal: arr(&w.normal),
        distance: w.dist,
        multiplier: mu,
    }
}
