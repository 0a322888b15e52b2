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
//!
//! # A hint from a nearby shape (exact, cheaper still)
//!
//! Along an edge of a plan consecutive shapes are close, and so is their closest
//! feature–obstacle pair. [`clearance_hinted`] first measures the distance `d` of the hinted
//! pair (the closest pair of the previous shape: a feature index and an obstacle index), with
//! the same growing bound; the clearance is at most `d`, so one pass with the bound
//! `d (1 + 10⁻⁹) + 10⁻¹²` finds it, each feature queried with a bound near the answer instead of
//! the passes' coarse ones. The hint changes only the cost: the pass is the same in-order pass
//! (same answer, same ties) and, should it find nothing, the growing passes go on from there.
//! Labels are formatted for the closest pair only.

use crate::contact::features;
use crate::contact::parry::past_roundoff;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;
use nalgebra::Vector3;
use parry3d::query::ClosestPoints;
use parry3d::shape::Shape as PShape;

/// The smallest distance between the robot and the obstacles, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct Clearance {
    /// Signed distance \[m\] (negative: penetration depth, for convex obstacles; for a solid
    /// mesh, the depth of a feature across or beyond its wall).
    pub distance: f64,
    /// Obstacle name.
    pub obstacle: String,
    /// Robot feature: `disk K`, `backbone J` (between backbone samples J and J+1) or
    /// `cable NAME K` (chord from disk K−1 to K).
    pub feature: String,
}

/// Which robot feature (see [`Clearance::feature`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Label {
    Disk(usize),
    Backbone(usize),
    /// Cable index, chord index (from 1).
    Cable(usize, usize),
}

impl Label {
    fn text(self, shape: &Shape) -> String {
        match self {
            Label::Disk(k) => format!("disk {k}"),
            Label::Backbone(j) => format!("backbone {j}"),
            Label::Cable(c, k) => format!("cable {} {k}", shape.cables[c].name),
        }
    }
}

/// A robot feature: label, parry shape, bounding box (min, max), pose, a point of it.
pub(super) struct Feature {
    label: Label,
    pub(super) shape: Box<dyn PShape>,
    lo: Vector3<f64>,
    hi: Vector3<f64>,
    pub(super) pose: parry3d::math::Pose,
    centre: Vector3<f64>,
}

/// Robot features of `shape` as parry shapes with their poses and bounding boxes: the parts of
/// the body that meet the world ([`features::BodyParts`], as the methods' contact code reads
/// them: spacer disks when it has them, the backbone as capsules of the body radius, cable
/// chords only for cables outside the rod), and, through a port, only beyond it (the disks,
/// backbone and cables behind the port lie inside it, where no solve has contact either).
pub(super) fn features_of(robot: &Robot, shape: &Shape) -> Vec<Feature> {
    let mut out: Vec<Feature> = Vec::new();
    let parts = features::BodyParts::of(robot);
    // The first disk beyond the port; a backbone piece lies in the port when both its ends
    // do (port-frame z ≤ 0).
    let first = shape.port.as_ref().map_or(0, |p| p.first_disk);
    let behind = |x: &Vector3<f64>| {
        shape.port.as_ref().is_some_and(|p| {
            let (o, a) = (p.pose.translation.vector, p.pose.rotation * Vector3::z());
            a.dot(&(x - o)) <= 1e-12
        })
    };
    let r = robot.disk_radius;
    let ext = Vector3::repeat(r + robot.disk_thickness);
    for (k, d) in shape.disks.iter().enumerate().filter(|_| parts.disks) {
        if k < first {
            continue;
        }
        out.push(Feature {
            label: Label::Disk(k),
            shape: Box::new(features::disk(robot)),
            lo: d.position - ext,
            hi: d.position + ext,
            pose: features::disk_pose(&d.rotation, &d.position),
            centre: d.position,
        });
    }
    let rb = parts.radius;
    let id = parry3d::math::Pose::IDENTITY;
    for (j, w) in shape.backbone.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        if behind(&a) && behind(&b) {
            continue;
        }
        out.push(Feature {
            label: Label::Backbone(j),
            shape: Box::new(features::backbone(&a, &b, rb)),
            lo: a.inf(&b) - Vector3::repeat(rb),
            hi: a.sup(&b) + Vector3::repeat(rb),
            pose: id,
            centre: 0.5 * (a + b),
        });
    }
    for (c, cable) in shape.cables.iter().enumerate().filter(|_| parts.cables) {
        for (k, w) in cable.points.windows(2).enumerate() {
            // The chord from disk k to k + 1: beyond the port when disk k + 1 is.
            if k + 1 < first {
                continue;
            }
            let (a, b) = (w[0], w[1]);
            out.push(Feature {
                label: Label::Cable(c, k + 1),
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
    clearance_hinted(robot, shape, scene, None).map(|(c, _)| c)
}

/// The closest pair of a clearance: feature index (disks, backbone segments, cable chords, in
/// that order) and obstacle index — a hint for [`clearance_hinted`].
pub type ClosestPair = (usize, usize);

/// [`clearance`], starting from the hinted pair (module docs: same answer, cheaper when the
/// hint is the closest pair of a nearby shape), with the closest pair found. A hint out of
/// range is ignored.
pub fn clearance_hinted(
    robot: &Robot,
    shape: &Shape,
    scene: &Scene,
    hint: Option<ClosestPair>,
) -> Option<(Clearance, ClosestPair)> {
    if scene.is_empty() {
        return None;
    }
    let feats = features_of(robot, shape);
    let far = feats.first().map_or(0.0, |f| {
        (0..scene.obstacles.len())
            .map(|k| far_corner(scene, k, &f.centre))
            .fold(f64::INFINITY, f64::min)
    });
    let bounds = grid_bounds(&feats, scene);
    // A grid's upper bound of a feature wholly on a solid's free side bounds the answer: the
    // first pass within it finds it.
    let within = bounds
        .iter()
        .filter(|b| b.0 > 0.0)
        .map(|b| past_roundoff(b.1))
        .fold(f64::INFINITY, f64::min);
    let start = (2.0 * scene.clearance.max(5e-4)).min(within);
    let mut cap = start;
    if let Some((f, k)) = hint.filter(|&(f, k)| f < feats.len() && k < scene.obstacles.len()) {
        // The hinted pair's own distance, by the same growing bound, started at the pair's
        // grid upper bound when it has a positive one (its distance is at most that: found by
        // the first query instead of after a few doublings from `start`).
        let upper = bounds[f * scene.obstacles.len() + k].1;
        let first = if upper > 0.0 && upper.is_finite() {
            past_roundoff(upper)
        } else {
            start
        };
        if let Some(d) = pair_grown(&feats[f], scene, k, first) {
            cap = past_roundoff(d.max(0.0));
        }
    }
    loop {
        // The last pass (beyond every obstacle's far corner) is unbounded.
        let last = cap > far;
        let best = pass(&feats, scene, if last { f64::MAX } else { cap }, &bounds);
        if let Some((d, f, k)) = best {
            let c = Clearance {
                distance: d,
                obstacle: scene.obstacles[k].name.clone(),
                feature: feats[f].label.text(shape),
            };
            return Some((c, (f, k)));
        }
        if last {
            // Nothing within an unbounded query: only when every query failed outright.
            return Some((
                Clearance {
                    distance: f64::INFINITY,
                    obstacle: String::new(),
                    feature: String::new(),
                },
                (0, 0),
            ));
        }
        cap *= 2.0;
    }
}

/// The clearance of `shape` when it is below `cap` \[m\] (the same distance, obstacle and
/// feature as [`clearance`]) with its closest pair, `None` when every feature–obstacle
/// distance is at least `cap` — proved by the grid's lower bounds without a query, or by one
/// pass whose queries are bounded by `cap` (module docs: a pass that finds a pair within its
/// bound has found the minimum). Also `None` for an empty scene. What a margin test needs:
/// the exact depth of a shape too close, nothing more for a clear one.
pub fn clearance_below(
    robot: &Robot,
    shape: &Shape,
    scene: &Scene,
    cap: f64,
) -> Option<(Clearance, ClosestPair)> {
    clearance_below_hinted(robot, shape, scene, cap, None)
}

/// [`clearance_below`], starting from a hinted closest pair (the same answer): the hinted
/// pair's distance, when below `cap`, bounds the one pass's queries instead of `cap` (module
/// docs, "A hint from a nearby shape"). A hint out of range is ignored.
pub fn clearance_below_hinted(
    robot: &Robot,
    shape: &Shape,
    scene: &Scene,
    cap: f64,
    hint: Option<ClosestPair>,
) -> Option<(Clearance, ClosestPair)> {
    if !cap.is_finite() {
        return clearance_hinted(robot, shape, scene, hint).filter(|c| c.0.distance < cap);
    }
    if scene.is_empty() {
        return None;
    }
    let feats = features_of(robot, shape);
    let bounds = grid_bounds(&feats, scene);
    let mut bound = cap;
    if let Some((f, k)) = hint.filter(|&(f, k)| f < feats.len() && k < scene.obstacles.len()) {
        // Some pair's distance: the clearance is at most it, so a pass within it finds it.
        if let Some(d) = pair(&feats[f], scene, k, cap) {
            bound = bound.min(past_roundoff(d.max(0.0)));
        }
    }
    let (d, f, k) = pass(&feats, scene, bound, &bounds)?;
    let c = Clearance {
        distance: d,
        obstacle: scene.obstacles[k].name.clone(),
        feature: feats[f].label.text(shape),
    };
    (d < cap).then_some((c, (f, k)))
}

/// The feature of `shape` at index `f` of a [`ClosestPair`] (`None` when out of range).
pub(crate) fn label_of(robot: &Robot, shape: &Shape, f: usize) -> Option<Label> {
    features_of(robot, shape).get(f).map(|x| x.label)
}

/// The signed distance between the feature `label` of `shape` and obstacle `k` (exact, as
/// [`clearance`] measures it; `None` when `shape` has no such feature or `k` is out of
/// range): the distance of one pair — the clearance's active piece, whose change along a
/// small step is the clearance's (one-sided) derivative while that pair stays the closest.
pub(crate) fn pair_distance(
    robot: &Robot,
    shape: &Shape,
    scene: &Scene,
    label: Label,
    k: usize,
) -> Option<f64> {
    if k >= scene.obstacles.len() {
        return None;
    }
    let feats = features_of(robot, shape);
    let f = feats.iter().find(|f| f.label == label)?;
    Some(pair_grown(f, scene, k, 2.0 * scene.clearance.max(5e-4)).unwrap_or(f64::INFINITY))
}

/// The distance of one feature–obstacle pair by a growing bound from `start` (×2 per query),
/// finite up to the far corner of the obstacle's box from the feature's point, unbounded
/// beyond it; `None` only when even the unbounded query fails.
pub(super) fn pair_grown(f: &Feature, scene: &Scene, k: usize, start: f64) -> Option<f64> {
    let far = far_corner(scene, k, &f.centre);
    let mut b = start;
    loop {
        let last = b > far;
        if let Some(d) = pair(f, scene, k, if last { f64::MAX } else { b }) {
            return Some(d);
        }
        if last {
            return None;
        }
        b *= 2.0;
    }
}

/// Distance between feature `f` and obstacle `k` when within `bound` (`None` beyond it);
/// signed for an intersecting pair (parry's contact depth).
fn pair(f: &Feature, scene: &Scene, k: usize, bound: f64) -> Option<f64> {
    let o = &scene.obstacles[k];
    let g = &*f.shape;
    // A solid mesh: the signed distance of `contact/solid.rs` (negative across or beyond the
    // wall). A feature farther than the bound from the surface is wholly on one side: on the
    // obstacle side its depth is below every bound, so it is measured whatever the bound
    // (its bounds say nothing: a lumen's obstacle region is everything outside them).
    if let Some(mesh) = crate::contact::solid::solid(&*o.shape) {
        let query =
            |b: f64| crate::contact::query(&f.pose, g, &o.parry_pose, &*o.shape, b, o.field());
        // Not below zero once a negative distance is the best so far (features across the
        // wall are within it; those beyond it are measured below).
        return match query(bound.max(0.0)) {
            Some(c) => Some(c.dist),
            // Wholly on the free side by the grid: beyond the bound.
            None if o
                .field()
                .and_then(|fd| fd.feature_bounds(g, &f.pose, &o.parry_pose, false))
                .is_some_and(|(lo, _)| lo > 0.0) =>
            {
                None
            }
            None if crate::contact::solid::in_obstacle(
                mesh,
                &o.parry_pose,
                crate::contact::pvec(&f.centre),
            ) =>
            {
                // Finite (parry loosens boxes by it): no point of the feature is farther from
                // the surface than the far corner of its bounds from the feature's centre plus
                // the feature's size. The centre (a point of the feature) is within |φ(c)| of
                // the surface, at most the grid's −lo there: a bound that keeps the tree walk
                // near the feature instead of over the whole mesh (the same closest triangle).
                let corner = far_corner(scene, k, &f.centre) + (f.hi - f.lo).norm();
                let near = o.field().map_or(f64::INFINITY, |fd| {
                    let c = o
                        .parry_pose
                        .inverse_transform_point(crate::contact::pvec(&f.centre));
                    let (lo, _) = fd.point_bounds([c.x, c.y, c.z]);
                    past_roundoff(lo.abs())
                });
                query(corner.min(near)).map(|c| c.dist)
            }
            None => None,
        };
    }
    if scene.bounds_gap(k, &f.lo, &f.hi) > bound {
        return None;
    }
    let mut d = match parry3d::query::closest_points(&f.pose, g, &o.parry_pose, &*o.shape, bound) {
        Ok(ClosestPoints::Disjoint) => return None,
        Ok(ClosestPoints::WithinMargin(a, b)) => (a - b).length(),
        Ok(ClosestPoints::Intersecting) => 0.0,
        Err(_) => parry3d::query::distance(&f.pose, g, &o.parry_pose, &*o.shape)
            .map_or(0.0, |d| d.distance),
    };
    if d <= 0.0 {
        if let Ok(Some(ct)) = parry3d::query::contact(&f.pose, g, &o.parry_pose, &*o.shape, 0.0) {
            d = ct.dist.min(0.0);
        }
    }
    Some(d)
}

/// Lower and upper bounds on each feature–obstacle pair's distance from a solid mesh's
/// signed-distance grid (`contact/field.rs`), `(−∞, ∞)` where there is none; indexed
/// `feature × obstacles + obstacle`.
fn grid_bounds(feats: &[Feature], scene: &Scene) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(feats.len() * scene.obstacles.len());
    for f in feats {
        for o in &scene.obstacles {
            let b = o.field().and_then(|fd| {
                let coarse = fd.feature_bounds(&*f.shape, &f.pose, &o.parry_pose, false)?;
                Some(coarse)
            });
            out.push(b.unwrap_or((f64::NEG_INFINITY, f64::INFINITY)));
        }
    }
    out
}

/// One pass over every feature–obstacle pair with the query bound `min(cap, best so far)`:
/// the smallest distance found, its feature and obstacle (`None`: none within the bound); ties
/// go to the earlier feature, then obstacle. Pairs are queried in the order of their grid
/// lower bounds `bounds` ([`grid_bounds`]), so the best so far falls fast, and a pair whose
/// lower bound is above it (and above zero: a feature wholly on a solid's free side) is not
/// queried at all (its distance is at least that bound).
fn pass(
    feats: &[Feature],
    scene: &Scene,
    cap: f64,
    bounds: &[(f64, f64)],
) -> Option<(f64, usize, usize)> {
    let nk = scene.obstacles.len();
    let mut order: Vec<usize> = (0..bounds.len()).collect();
    order.sort_by(|&a, &b| bounds[a].0.total_cmp(&bounds[b].0).then(a.cmp(&b)));
    let mut best: Option<(f64, usize, usize)> = None;
    for j in order {
        let (i, k) = (j / nk, j % nk);
        let bound = cap.min(best.map_or(f64::INFINITY, |b| b.0));
        if bounds[j].0 > bound.max(0.0) {
            break;
        }
        if let Some(d) = pair(&feats[i], scene, k, bound) {
            let better = best.is_none_or(|b| d < b.0 || (d == b.0 && (i, k) < (b.1, b.2)));
            if better {
                best = Some((d, i, k));
            }
        }
    }
    best
}
