//! The clearance of a shape: the smallest distance between any robot feature and any obstacle.
//!
//! # Growing query bound (exact, cheaper)
//!
//! parry3d's closest-points query against a triangle mesh prunes its bounding-volume tree with
//! the query's bound: with an infinite bound it visits every triangle (≈ 0.5 ms for one
//! segment in the 3840-triangle tube of `models/plan/vessel.toml`), with a bound of a few
//! millimetres well under a microsecond. So the features are queried in passes with a finite
//! bound `b` (first twice the scene's clearance, at least 1 mm; ×2 per pass): within a pass
//! each feature–obstacle pair is queried with the bound `min(b, best so far)`, which returns
//! its exact closest points when they are within it. A pass that finds any pair within `b`
//! has found the minimum (every pair closer than the answer was within the bound it was
//! queried with); a pass that finds none proves every distance exceeds `b`, and the next
//! pass grows it. The bound stays finite: the distance from a feature's point to an
//! obstacle is at most its distance to the farthest corner of the obstacle's bounding box,
//! and the last pass, beyond that bound for the first feature's point, uses parry's unbounded
//! query. Same answer, same order
//! (ties keep the earlier feature) as one unbounded pass.

use crate::contact::features;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;
use nalgebra::Vector3;
use parry3d::query::ClosestPoints;
use parry3d::shape::Shape as PShape;

/// The smallest distance between the robot and the obstacles, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct Clearance {
    /// Signed distance \[m\] (negative: penetration depth, for convex obstacles).
    pub distance: f64,
    /// Obstacle name.
    pub obstacle: String,
    /// Robot feature: `disk K`, `backbone J` (between backbone samples J and J+1) or
    /// `cable NAME K` (chord from disk K−1 to K).
    pub feature: String,
}

/// A robot feature: label, parry shape, bounding box (min, max), pose, a point of it.
struct Feature {
    label: String,
    shape: Box<dyn PShape>,
    lo: Vector3<f64>,
    hi: Vector3<f64>,
    pose: parry3d::math::Pose,
    centre: Vector3<f64>,
}

/// Robot features of `shape` as parry shapes with their poses and bounding boxes.
fn features_of(robot: &Robot, shape: &Shape) -> Vec<Feature> {
    let mut out: Vec<Feature> = Vec::new();
    let r = robot.disk_radius;
    let ext = Vector3::repeat(r + robot.disk_thickness);
    for (k, d) in shape.disks.iter().enumerate() {
        out.push(Feature {
            label: format!("disk {k}"),
            shape: Box::new(features::disk(robot)),
            lo: d.position - ext,
            hi: d.position + ext,
            pose: features::disk_pose(&d.rotation, &d.position),
            centre: d.position,
        });
    }
    let rb = robot.backbone.radius();
    let id = parry3d::math::Pose::IDENTITY;
    for (j, w) in shape.backbone.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        out.push(Feature {
            label: format!("backbone {j}"),
            shape: Box::new(features::backbone(&a, &b, rb)),
            lo: a.inf(&b) - Vector3::repeat(rb),
            hi: a.sup(&b) + Vector3::repeat(rb),
            pose: id,
            centre: 0.5 * (a + b),
        });
    }
    for c in &shape.cables {
        for (k, w) in c.points.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            out.push(Feature {
                label: format!("cable {} {}", c.name, k + 1),
                shape: Box::new(features::chord(&a, &b)),
                lo: a.inf(&b),
                hi: a.sup(&b),
                pose: id,
                centre: 0.5 * (a + b),
            });
        }
    }
    out
}

/// The largest distance from `p` to the bounding box of obstacle `k`: at least the distance
/// from `p` to the obstacle.
fn far_corner(scene: &Scene, k: usize, p: &Vector3<f64>) -> f64 {
    let (lo, hi) = &scene.obstacles[k].aabb;
    let far = Vector3::from_fn(|a, _| (p[a] - lo[a]).abs().max((p[a] - hi[a]).abs()));
    far.norm()
}

/// Smallest signed distance between any feature of `shape` and any obstacle of `scene`
/// (parry3d; `None` for an empty scene), in the passes of the module docs.
pub fn clearance(robot: &Robot, shape: &Shape, scene: &Scene) -> Option<Clearance> {
    if scene.is_empty() {
        return None;
    }
    let feats = features_of(robot, shape);
    let far = feats.first().map_or(0.0, |f| {
        (0..scene.obstacles.len())
            .map(|k| far_corner(scene, k, &f.centre))
            .fold(f64::INFINITY, f64::min)
    });
    let mut cap = 2.0 * scene.clearance.max(5e-4);
    loop {
        // The last pass (beyond every obstacle's far corner) is unbounded.
        let last = cap > far;
        let best = pass(&feats, scene, if last { f64::MAX } else { cap });
        if best.distance.is_finite() || last {
            return Some(best);
        }
        cap *= 2.0;
    }
}

/// One pass over every feature–obstacle pair with the query bound `min(cap, best so far)`.
fn pass(feats: &[Feature], scene: &Scene, cap: f64) -> Clearance {
    let mut best = Clearance {
        distance: f64::INFINITY,
        obstacle: String::new(),
        feature: String::new(),
    };
    for f in feats {
        for (k, o) in scene.obstacles.iter().enumerate() {
            let bound = cap.min(best.distance);
            if scene.bounds_gap(k, &f.lo, &f.hi) > bound {
                continue;
            }
            let g = &*f.shape;
            let mut d =
                match parry3d::query::closest_points(&f.pose, g, &o.parry_pose, &*o.shape, bound) {
                    Ok(ClosestPoints::Disjoint) => continue,
                    Ok(ClosestPoints::WithinMargin(a, b)) => (a - b).length(),
                    Ok(ClosestPoints::Intersecting) => 0.0,
                    Err(_) => parry3d::query::distance(&f.pose, g, &o.parry_pose, &*o.shape)
                        .map_or(0.0, |d| d.distance),
                };
            if d <= 0.0 {
                if let Ok(Some(ct)) =
                    parry3d::query::contact(&f.pose, g, &o.parry_pose, &*o.shape, 0.0)
                {
                    d = ct.dist.min(0.0);
                }
            }
            if d < best.distance {
                best = Clearance {
                    distance: d,
                    obstacle: o.name.clone(),
                    feature: f.label.clone(),
                };
            }
        }
    }
    best
}
