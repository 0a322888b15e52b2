//! Self-contact of a solved shape: the robot's parts (disks and backbone capsules) in order
//! along the arc, a broad phase over their bounds, and the narrow test of one pair (module docs
//! of [`crate::check`] say which pairs may not touch and why).

use crate::robot::Robot;
use crate::shape::Shape;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use parry3d::bounding_volume::Aabb;
use parry3d::math::{Pose, Vector as PVec};
use parry3d::partitioning::{Bvh, BvhBuildStrategy};
use parry3d::shape::{Capsule, Cylinder, SharedShape};

/// Relative penetration depth tolerated before two parts of the robot are said to overlap
/// (of min(disk thickness, backbone diameter)).
pub const SELF_CONTACT_TOL: f64 = 1e-3;
/// Most backbone segments tested; denser polylines are thinned evenly (every k-th sample).
pub const MAX_BACKBONE_SEGMENTS: usize = 100_000;

/// Two parts of the robot that overlap.
#[derive(Debug, Clone, PartialEq)]
pub struct SelfContact {
    /// What overlaps, e.g. `disks 3 and 7` or `the backbone at s = 0.051 m and s = 0.163 m`.
    pub what: String,
    /// Section of the first part (1-based; 0 for the base disk).
    pub section: usize,
    /// Penetration depth \[m\].
    pub depth: f64,
}

/// One part in the broad phase: a shape, its pose, and where it sits along the arc.
struct Part {
    shape: SharedShape,
    /// The shape shrunk by the tolerance (the overlap test).
    shrunk: SharedShape,
    pose: Pose,
    /// Arc-length interval along the solved backbone polyline (disks: where they sit on it,
    /// assuming a uniform stretch).
    s: (f64, f64),
    /// Section (1-based) the part starts in; 0 for the base disk.
    section: usize,
    /// `Some(k)` for disk k, `None` for a backbone segment.
    disk: Option<usize>,
}

fn disk_pose(rotation: &Matrix3<f64>, position: &Vector3<f64>) -> Pose {
    // Parry's cylinder axis is its local y; a disk's normal is its frame's z.
    let y_to_z = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
    let m = rotation * y_to_z;
    // A solver's frame is a rotation to roundoff: its quaternion in closed form (Shepperd),
    // a tenth of the cost of the iterative nearest rotation, which stays for any other matrix.
    let q = if (m.transpose() * m - Matrix3::identity()).amax() < 1e-9 && m.determinant() > 0.0 {
        UnitQuaternion::new_normalize(
            UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m)).into_inner(),
        )
    } else {
        UnitQuaternion::from_matrix(&m)
    };
    Isometry3::from_parts(Translation3::from(*position), q).into()
}

fn parts(robot: &Robot, shape: &Shape, tol: f64) -> Vec<Part> {
    let pts = &shape.backbone;
    let total: f64 = pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    // Polyline arc per metre of undeformed backbone (1 for an inextensible rod).
    let scale = if total > 0.0 {
        total / robot.length()
    } else {
        1.0
    };
    let mut out: Vec<Part> = Vec::new();
    if robot.has_disks() {
        let (ht, r) = (robot.disk_thickness / 2.0, robot.disk_radius);
        let disk = SharedShape::new(Cylinder::new(ht, r));
        let disk_shrunk = SharedShape::new(Cylinder::new(ht - tol, r - tol));
        out.extend(shape.disks.iter().enumerate().map(|(k, d)| Part {
            shape: disk.clone(),
            shrunk: disk_shrunk.clone(),
            pose: disk_pose(&d.rotation, &d.position),
            s: (d.s * scale, d.s * scale),
            section: k,
            disk: Some(k),
        }));
    }
    if pts.len() < 2 {
        return out;
    }
    // Segments shorter than an eighth of the backbone diameter add no resolution the check
    // can use, only pairs: a chord of length ℓ lies within ℓ²κ/8 of the arc, 0.3 µm at
    // ℓ = d/8 = 0.125 mm and κ = 160 /m (8 % strain at the surface of a 1 mm backbone, past
    // nitinol's limit), below the tolerance; while each segment's bounds overlap ~8ρ/ℓ of its
    // neighbours' and a grid cell (a disk's size) holds them all, so a dense polyline made the
    // check quadratic (energy at 64 sub-arcs × 64 samples, 36 865 points: 95 s). Thinned to
    // about d/8 (every k-th sample); the default outputs' segments are millimetres long and
    // stay as they are.
    let segments = (pts.len() - 1) as f64;
    let fine = 0.125 * robot.backbone.diameter * segments / total;
    let fine = if fine.is_finite() && fine >= 1.0 {
        (fine as usize).min(pts.len() - 1)
    } else {
        1
    };
    let stride = (pts.len() - 1)
        .div_ceil(MAX_BACKBONE_SEGMENTS)
        .max(fine)
        .max(1);
    let mut idx: Vec<usize> = (0..pts.len()).step_by(stride).collect();
    if idx.last() != Some(&(pts.len() - 1)) {
        idx.push(pts.len() - 1);
    }
    let rho = robot.body_radius();
    let mut s = 0.0;
    for w in idx.windows(2) {
        let (a, b) = (pts[w[0]], pts[w[1]]);
        let len = (b - a).norm();
        let (pa, pb) = (PVec::new(a.x, a.y, a.z), PVec::new(b.x, b.y, b.z));
        out.push(Part {
            shape: SharedShape::new(Capsule::new(pa, pb, rho)),
            shrunk: SharedShape::new(Capsule::new(pa, pb, rho - tol)),
            pose: Pose::IDENTITY,
            s: (s, s + len),
            // The disks' arc positions ascend: how many lie at or before s, in log time.
            section: robot
                .disk_s
                .partition_point(|&x| x * scale <= s)
                .clamp(1, robot.sections()),
            disk: None,
        });
        s += len;
    }
    out
}

/// The parts of `shape` in order along the arc (by where they start; a disk before a segment
/// starting at the same place), and the tolerance.
fn ordered_parts(robot: &Robot, shape: &Shape) -> Option<(Vec<Part>, f64)> {
    if shape.disks.len() != robot.disk_s.len() {
        return None;
    }
    // The body's diameter (the backbone's unless the model gives a collision radius).
    let d = 2.0 * robot.body_radius();
    let thinnest = if robot.has_disks() {
        robot.disk_thickness.min(d)
    } else {
        d
    };
    let tol = SELF_CONTACT_TOL * thinnest;
    let mut parts = parts(robot, shape, tol);
    // Stable: disks come first in `parts`, so they stay before segments at the same s.
    parts.sort_by(|a, b| a.s.0.total_cmp(&b.s.0));
    Some((parts, tol))
}

/// The overlap depth of parts `a` and `b` if they may not touch and overlap deeper than `tol`.
fn overlap(robot: &Robot, pa: &Part, pb: &Part, tol: f64) -> Option<f64> {
    let gap = (pb.s.0 - pa.s.1).max(pa.s.0 - pb.s.1).max(0.0);
    let needed = match (pa.disk, pb.disk) {
        (Some(_), Some(_)) => 0.0,
        (None, None) => std::f64::consts::PI * 2.0 * robot.body_radius(),
        _ => std::f64::consts::PI * robot.disk_radius,
    };
    if gap < needed || (pa.disk.is_some() && pa.disk == pb.disk) {
        return None;
    }
    // GJK's boolean test on the shrunk shapes decides (robust also for coaxial disks, where
    // EPA's penetration depth can fail); EPA's depth, when it has one, is reported.
    let hit = parry3d::query::intersection_test(&pa.pose, &*pa.shrunk, &pb.pose, &*pb.shrunk)
        .is_ok_and(|x| x.intersecting);
    if !hit {
        return None;
    }
    Some(
        match parry3d::query::contact(&pa.pose, &*pa.shape, &pb.pose, &*pb.shape, 0.0) {
            Ok(Some(c)) => (-c.dist).max(tol),
            _ => tol,
        },
    )
}

/// Part `a`'s deepest overlap with any of `later` (indices after `a`, increasing; the first
/// of equal depths), as the reported record.
fn deepest(
    robot: &Robot,
    parts: &[Part],
    a: usize,
    later: impl Iterator<Item = usize>,
    tol: f64,
) -> Option<SelfContact> {
    let mut worst: Option<(f64, usize)> = None;
    for b in later {
        if let Some(depth) = overlap(robot, &parts[a], &parts[b], tol) {
            if worst.is_none_or(|(w, _)| depth > w) {
                worst = Some((depth, b));
            }
        }
    }
    worst.map(|(depth, b)| SelfContact {
        what: describe(&parts[a], &parts[b]),
        section: parts[a].section,
        depth,
    })
}

/// The first part along the arc that overlaps a later part it may not touch, with its deepest
/// such overlap (see the module docs of [`crate::check`] for which pairs are tested). Parts
/// whose axis-aligned bounds are disjoint are never tested (parry's bounding-volume hierarchy),
/// and the search stops at the first part found overlapping: n log n in the number of parts
/// for a shape clear of itself or one coiled through itself many times alike. Gives the same
/// answer as [`self_contact_exhaustive`].
pub fn self_contact(robot: &Robot, shape: &Shape) -> Option<SelfContact> {
    let (parts, tol) = ordered_parts(robot, shape)?;
    let boxes: Vec<Aabb> = parts
        .iter()
        .map(|p| p.shape.compute_aabb(&p.pose))
        .collect();
    let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes);
    let mut later = Vec::new();
    for (a, bounds) in boxes.iter().enumerate() {
        later.clear();
        later.extend(
            bvh.intersect_aabb(bounds)
                .map(|b| b as usize)
                .filter(|&b| b > a),
        );
        later.sort_unstable();
        if let Some(c) = deepest(robot, &parts, a, later.iter().copied(), tol) {
            return Some(c);
        }
    }
    None
}

/// [`self_contact`] by testing every pair of parts, no broad phase: quadratic in the number
/// of parts, the oracle the broad phase is tested against.
pub fn self_contact_exhaustive(robot: &Robot, shape: &Shape) -> Option<SelfContact> {
    let (parts, tol) = ordered_parts(robot, shape)?;
    (0..parts.len()).find_map(|a| deepest(robot, &parts, a, a + 1..parts.len(), tol))
}

fn describe(a: &Part, b: &Part) -> String {
    match (a.disk, b.disk) {
        (Some(i), Some(j)) => format!("disks {i} and {j}"),
        (Some(i), None) | (None, Some(i)) => {
            let s = if a.disk.is_none() { a.s.0 } else { b.s.0 };
            format!("disk {i} and the backbone {s:.4} m along it")
        }
        (None, None) => format!("the backbone {:.4} m and {:.4} m along it", a.s.0, b.s.0),
    }
}
