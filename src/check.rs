//! Checks on a solved shape at the output boundary, independent of the method that made it:
//! every number finite, and the robot not passing through itself.
//!
//! The one solve path ([`crate::method::Solver`], behind [`crate::method::run::SolveRequest`])
//! applies [`output`] to every shape it hands out — single solves, batch rows, study points,
//! reach and plan, hardware predictions, calibration passes — so no caller gets a non-finite
//! number or a backbone or disks that interpenetrate (99.99 % shortening under `energy` once
//! curled the robot through itself with no word).
//!
//! **Self-contact** is tested with parry3d on the shape's own geometry, not on any method's
//! internal state:
//! - every pair of disks (cylinders of the robot's radius and thickness at the solved frames),
//!   adjacent ones included: rigid disks may touch, not overlap;
//! - backbone against backbone: the polyline of `Shape::backbone` as capsules of the backbone
//!   radius ρ = d/2, for pairs of segments more than π d apart along the arc. On a circle of
//!   radius r ≥ ρ (the tightest bend a tube of radius ρ can take without overlapping itself)
//!   two points s apart lie 2r sin(s/2r) apart, which is ≥ d once s ≥ π d/2 (sin(πx/2) ≥ x on
//!   [0, 1]); so two segments that far apart and closer than d overlap — the backbone crosses
//!   itself. The π d gap (twice the bound) keeps discretization of the polyline from counting;
//! - each disk against backbone segments more than π R along the arc from it (a curve leaving
//!   a disk along its normal returns to the disk's plane only after half a turn).
//!
//! An overlap deeper than tol = [`SELF_CONTACT_TOL`] × min(disk thickness, backbone diameter) is
//! reported: the parts shrunk by tol intersect (GJK's boolean test, robust also where EPA's
//! penetration depth fails, e.g. for coaxial disks); the depth given is EPA's where it has one,
//! else tol (a lower bound). A broad phase (uniform grid over axis-aligned bounds) keeps the cost near linear
//! in the number of disks and samples, and a backbone sampled more finely than d/8 is thinned
//! to about that spacing (see `parts`).

use crate::error::SolveError;
use crate::robot::Robot;
use crate::shape::Shape;
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use parry3d::bounding_volume::BoundingVolume;
use parry3d::math::{Pose, Vector as PVec};
use parry3d::shape::{Capsule, Cylinder, SharedShape};
use std::collections::{HashMap, HashSet};

/// Relative penetration depth tolerated before two parts of the robot are said to overlap
/// (of min(disk thickness, backbone diameter)).
pub const SELF_CONTACT_TOL: f64 = 1e-3;
/// Most backbone segments tested; denser polylines are thinned evenly (every k-th sample).
pub const MAX_BACKBONE_SEGMENTS: usize = 100_000;

/// Both checks; the first failure as a [`SolveError`] (`NotConverged` for a non-finite number,
/// `Obstructed` by `self` for a self-contact).
pub fn output(robot: &Robot, shape: &Shape) -> Result<(), SolveError> {
    finite(shape)?;
    if let Some(c) = self_contact(robot, shape) {
        return Err(SolveError::Obstructed {
            obstacle: "self".into(),
            section: c.section,
            reason: format!(
                "{} overlap by {:.3e} m: the shape passes through itself (ccrkit does not model self-contact; reduce the actuation)",
                c.what, c.depth
            ),
        });
    }
    Ok(())
}

/// The first half of [`output`], which needs no robot: every number of `shape` finite, else
/// `NotConverged` naming the first field that is not.
pub fn finite(shape: &Shape) -> Result<(), SolveError> {
    match first_non_finite(shape) {
        None => Ok(()),
        Some(field) => Err(SolveError::NotConverged {
            method: shape.method.clone(),
            section: None,
            iterations: shape.report.iterations,
            residual: shape.report.residual,
            detail: format!("the result holds a non-finite number at `{field}`"),
        }),
    }
}

/// A method's result passed through [`output`], so a shape through itself or a non-finite
/// one counts as the failure it is.
pub fn checked(robot: &Robot, result: Result<Shape, SolveError>) -> Result<Shape, SolveError> {
    let shape = result?;
    output(robot, &shape)?;
    Ok(shape)
}

/// The first field of `shape` holding a NaN or an infinity (a dotted path such as
/// `disks[3].position`), if any.
pub fn first_non_finite(shape: &Shape) -> Option<String> {
    let bad = |xs: &[f64]| xs.iter().any(|x| !x.is_finite());
    for (k, d) in shape.disks.iter().enumerate() {
        if bad(&[d.s]) || bad(d.position.as_slice()) || bad(d.rotation.as_slice()) {
            return Some(format!("disks[{k}]"));
        }
    }
    if let Some(k) = shape.backbone.iter().position(|p| bad(p.as_slice())) {
        return Some(format!("backbone[{k}]"));
    }
    for c in &shape.cables {
        if c.points.iter().any(|p| bad(p.as_slice())) || c.tension.is_some_and(|t| !t.is_finite()) {
            return Some(format!("cables[{}]", c.name));
        }
    }
    for (k, c) in shape.contacts.iter().enumerate() {
        let nums = [c.distance, c.multiplier];
        if bad(&nums) || bad(&c.point_robot) || bad(&c.point_obstacle) || bad(&c.normal) {
            return Some(format!("contacts[{k}]"));
        }
    }
    let r = &shape.report;
    if bad(&[r.residual, r.solve_time_s]) {
        return Some("report.residual".into());
    }
    for s in &r.sections {
        if bad(&[s.residual, s.objective]) {
            return Some(format!("report.sections[{}]", s.section));
        }
    }
    if r.base_wrench.is_some_and(|w| bad(&w)) {
        return Some("report.base_wrench".into());
    }
    if let Some(j) = &r.jacobian {
        if j.position.iter().chain(&j.tangent).any(|v| bad(v)) {
            return Some("report.jacobian".into());
        }
    }
    None
}

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
    let q = UnitQuaternion::from_matrix(&(rotation * y_to_z));
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
            section: robot
                .disk_s
                .iter()
                .filter(|&&x| x * scale <= s)
                .count()
                .clamp(1, robot.sections()),
            disk: None,
        });
        s += len;
    }
    out
}

/// Candidate pairs whose axis-aligned bounds share a cell of a uniform grid.
fn broad_phase(parts: &[Part]) -> Vec<(usize, usize)> {
    let boxes: Vec<_> = parts
        .iter()
        .map(|p| p.shape.compute_aabb(&p.pose))
        .collect();
    let cell = boxes
        .iter()
        .map(|b| (b.maxs - b.mins).max_element())
        .fold(0.0_f64, f64::max)
        .max(1e-12);
    let key = |x: f64| (x / cell).floor() as i64;
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (k, b) in boxes.iter().enumerate() {
        for i in key(b.mins.x)..=key(b.maxs.x) {
            for j in key(b.mins.y)..=key(b.maxs.y) {
                for l in key(b.mins.z)..=key(b.maxs.z) {
                    grid.entry((i, j, l)).or_default().push(k);
                }
            }
        }
    }
    let mut pairs = HashSet::new();
    for members in grid.values() {
        for (x, &a) in members.iter().enumerate() {
            for &b in &members[x + 1..] {
                if boxes[a].intersects(&boxes[b]) {
                    pairs.insert((a.min(b), a.max(b)));
                }
            }
        }
    }
    let mut pairs: Vec<_> = pairs.into_iter().collect();
    pairs.sort_unstable();
    pairs
}

/// The deepest overlap between two parts of the robot that may not touch, if any deeper than
/// the tolerance (see the module docs for which pairs are tested).
pub fn self_contact(robot: &Robot, shape: &Shape) -> Option<SelfContact> {
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
    let parts = parts(robot, shape, tol);
    let mut worst: Option<SelfContact> = None;
    for (a, b) in broad_phase(&parts) {
        let (pa, pb) = (&parts[a], &parts[b]);
        let gap = (pb.s.0 - pa.s.1).max(pa.s.0 - pb.s.1).max(0.0);
        let needed = match (pa.disk, pb.disk) {
            (Some(_), Some(_)) => 0.0,
            (None, None) => std::f64::consts::PI * d,
            _ => std::f64::consts::PI * robot.disk_radius,
        };
        if gap < needed || (pa.disk.is_some() && pa.disk == pb.disk) {
            continue;
        }
        // GJK's boolean test on the shrunk shapes decides (robust also for coaxial disks,
        // where EPA's penetration depth can fail); EPA's depth, when it has one, is reported.
        let overlap =
            parry3d::query::intersection_test(&pa.pose, &*pa.shrunk, &pb.pose, &*pb.shrunk)
                .is_ok_and(|x| x.intersecting);
        if !overlap {
            continue;
        }
        let depth = match parry3d::query::contact(&pa.pose, &*pa.shape, &pb.pose, &*pb.shape, 0.0) {
            Ok(Some(c)) => (-c.dist).max(tol),
            _ => tol,
        };
        if worst.as_ref().is_none_or(|w| depth > w.depth) {
            worst = Some(SelfContact {
                what: describe(pa, pb),
                section: pa.section,
                depth,
            });
        }
    }
    worst
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
