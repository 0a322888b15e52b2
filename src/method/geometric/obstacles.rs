//! Obstacles seen by one section: the robot features (backbone capsule, disk cylinder, cable
//! chords), their pairs with nearby obstacles, and each pair's distance linearized in the
//! section's variables.

use super::problem::Pose;
use crate::contact::features::{self, Touching};
use crate::contact::parry::SEPARATION_SHIFT;
use crate::contact::primitives::{closed_witness, Convex};
use crate::contact::sat;
use crate::contact::Witness;
use crate::contact::{nvec, pvec};
use crate::model::robot::Robot;
use crate::model::scene::{aabb_ball_distance, aabb_gap, Scene};
use crate::shape::Contact;
use nalgebra::{Matrix3, Vector3, Vector6};
use parry3d::math::Pose as PPose;
use parry3d::shape::{Cylinder, Shape as PShape};

/// Slack on [`SectionWorld::pairs_within`]'s lower bound \[m\]: a pair is left unqueried
/// only when the bound exceeds the distance asked for by this much, far above parry's GJK
/// tolerance and the rounding of the bound, so the skipped query could not have answered
/// otherwise.
const PRUNE_SLACK: f64 = 1e-6;

/// `Σ max(0, clearance − d)` over the pairs: how far they are inside the clearance \[m\].
pub(super) fn penetration_of(pairs: &[Pair], clearance: f64) -> f64 {
    pairs.iter().map(|p| (clearance - p.dist).max(0.0)).sum()
}

/// `max(0, max (clearance − d))` over the pairs: the deepest one inside the clearance \[m\].
pub(super) fn worst_gap(pairs: &[Pair], clearance: f64) -> f64 {
    pairs
        .iter()
        .map(|p| clearance - p.dist)
        .fold(0.0f64, f64::max)
}

/// When [`SectionWorld::pairs_within_into`] may stop querying: a rule on the pairs found so
/// far, monotone in them (true of some ⇒ true of more).
type StopRule<'r> = &'r dyn Fn(&[Pair]) -> bool;

/// A robot feature of one section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Feature {
    /// The backbone segment of the section, a capsule of the backbone radius.
    Backbone,
    /// The disk at the section's end, a thin cylinder.
    Disk,
    /// The straight chord of a cable (its index) in the section.
    Cable(usize),
}

/// One robot feature near one obstacle, linearized at the current pose.
pub(super) struct Pair {
    pub(super) obstacle: usize,
    pub(super) feature: Feature,
    /// Signed distance \[m\].
    pub(super) dist: f64,
    /// ∂dist/∂(dp, dω) in the section's variables.
    pub(super) grad: Vector6<f64>,
    pub(super) point_robot: Vector3<f64>,
    pub(super) point_obstacle: Vector3<f64>,
    /// Unit normal from the obstacle towards the robot.
    pub(super) normal: Vector3<f64>,
}

impl Pair {
    pub(super) fn to_contact(
        &self,
        world: Option<&SectionWorld>,
        section: usize,
        mu: f64,
    ) -> Contact {
        let feature = match self.feature {
            Feature::Backbone => Touching::Backbone { section },
            Feature::Disk => Touching::Disk { disk: section },
            Feature::Cable(c) => Touching::Cable {
                name: world.map_or("", |w| &w.cable_names[c]),
                section,
            },
        };
        let w = Witness {
            robot: self.point_robot,
            obstacle: self.point_obstacle,
            normal: self.normal,
            dist: self.dist,
        };
        let obstacle = world.map_or(String::new(), |w| w.name(self.obstacle));
        features::record(obstacle, feature, &w, mu)
    }
}

/// What section `i` sees of the scene: the obstacles the broad phase kept, and the fixed
/// geometry of disk `i−1` in the base frame.
pub(super) struct SectionWorld {
    pub(super) names: Vec<String>,
    pub(super) shapes: Vec<(parry3d::shape::SharedShape, PPose)>,
    /// Each solid mesh's signed-distance grid (`contact/field.rs`).
    fields: Vec<Option<std::sync::Arc<crate::contact::field::SolidField>>>,
    /// Each obstacle's bounding box in its own frame (min and max corners), for
    /// [`SectionWorld::pairs_within`]'s lower bound.
    boxes: Vec<(Vector3<f64>, Vector3<f64>)>,
    pub(super) cable_names: Vec<String>,
    pub(super) r_prev: Matrix3<f64>,
    pub(super) x_prev: Vector3<f64>,
    /// (cable, hole at disk i−1 in the base frame, hole at disk i in its disk frame).
    pub(super) holes: Vec<(usize, Vector3<f64>, Vector3<f64>)>,
    pub(super) backbone_radius: f64,
    pub(super) disk_radius: f64,
    pub(super) half_thickness: f64,
    pub(super) clearance: f64,
    /// Pairs farther apart than this are left out of the step \[m\].
    pub(super) margin: f64,
}

impl SectionWorld {
    pub(super) fn new(
        robot: &Robot,
        scene: &Scene,
        relevant: &[usize],
        i: usize,
        r_prev: &Matrix3<f64>,
        x_prev: &Vector3<f64>,
    ) -> Option<SectionWorld> {
        if relevant.is_empty() {
            return None;
        }
        let l = robot.section_length(i);
        let margin = 0.5 * l + scene.clearance;
        let reach = l + robot.disk_radius + robot.disk_thickness + scene.clearance + margin;
        // Only the robot-level survivors are tested again (was: every obstacle of the scene
        // tested, then a quadratic `relevant.contains` filter).
        let near = scene.near_among(relevant, x_prev, reach);
        if near.is_empty() {
            return None;
        }
        Some(SectionWorld {
            names: near
                .iter()
                .map(|&k| scene.obstacles[k].name.clone())
                .collect(),
            shapes: near
                .iter()
                .map(|&k| {
                    (
                        scene.obstacles[k].shape.clone(),
                        scene.obstacles[k].parry_pose,
                    )
                })
                .collect(),
            fields: near
                .iter()
                .map(|&k| scene.obstacles[k].field_shared())
                .collect(),
            boxes: near
                .iter()
                .map(|&k| {
                    let b = scene.obstacles[k].shape.compute_local_aabb();
                    (nvec(b.mins), nvec(b.maxs))
                })
                .collect(),
            cable_names: robot.cables.iter().map(|c| c.name.clone()).collect(),
            r_prev: *r_prev,
            x_prev: *x_prev,
            holes: robot
                .cables
                .iter()
                .enumerate()
                .filter(|(_, c)| c.reaches_section(i))
                .map(|(k, c)| (k, x_prev + r_prev * c.hole(i - 1), c.hole(i)))
                .collect(),
            backbone_radius: robot.body_radius(),
            disk_radius: robot.disk_radius,
            half_thickness: robot.disk_thickness / 2.0,
            clearance: scene.clearance,
            margin,
        })
    }

    pub(super) fn name(&self, k: usize) -> String {
        self.names[k].clone()
    }

    /// Total penetration below the clearance over the pairs at this pose \[m\]: the sum over
    /// every pair within the margin of `max(0, clearance − d)`. `scratch` holds the pairs
    /// between calls (the line search's trials reuse it); a call that does not give up leaves
    /// in it the pairs within the margin, [`SectionWorld::pairs_into`]'s at this pose with the
    /// same `near` to the bit (Newton takes them for its next iterate when the trial is
    /// accepted). `near`: the pairs of a pose a moment ago (the line search's iterate), whose
    /// normals start the exact queries of pairs touching or overlapping now
    /// ([`SectionWorld::pairs_within_into`]).
    ///
    /// `rejects` may end the queries early (`None`): it is asked of the penetration of the
    /// pairs found so far — before the first query, then after each pair found closer than the
    /// margin — and must be monotone in it (true of a value ⇒ true of every larger one). The
    /// penetration is a rounded sum of the non-negative terms `max(0, clearance − d)` in the
    /// order of the pairs, and rounded addition is monotone, so the sum over a prefix of the
    /// pairs is at most the sum over all of them: a rule true of a prefix is true of the
    /// whole. A call that does not give up returns the sum over every pair, to the bit (the
    /// same queries in the same order).
    pub(super) fn penetration(
        &self,
        pose: &Pose,
        scratch: &mut Vec<Pair>,
        rejects: &dyn Fn(f64) -> bool,
        near: &[Pair],
    ) -> Option<f64> {
        let clearance = self.clearance;
        let stop = |found: &[Pair]| rejects(penetration_of(found, clearance));
        self.pairs_within_into(pose, self.margin, scratch, Some(&stop), near)
            .then(|| penetration_of(scratch, clearance))
    }

    /// Every feature–obstacle pair within the margin at this pose, linearized.
    pub(super) fn pairs(&self, pose: &Pose) -> Vec<Pair> {
        self.pairs_within(pose, self.margin)
    }

    /// [`SectionWorld::pairs`] into `out` (cleared first; Newton reuses one buffer).
    pub(super) fn pairs_into(&self, pose: &Pose, out: &mut Vec<Pair>) {
        self.pairs_within_into(pose, self.margin, out, None, &[]);
    }

    /// A lower bound on the distance between obstacle `k` and a feature (0 or less when they
    /// may overlap; a pair is pruned only for a positive bound): the obstacle lies in
    /// its bounding box (its own frame), the feature in its bounding ball and in its bounding
    /// box in that frame, so the distance is at least the larger of the (closed-form)
    /// distances from the box to the ball and between the two boxes.
    fn distance_bound(&self, k: usize, hull: &Convex) -> f64 {
        let opose = &self.shapes[k].1;
        let to_local = |p: &Vector3<f64>| nvec(opose.inverse_transform_point(pvec(p)));
        let (c, radius, lo, hi) = match *hull {
            Convex::Segment(a, b, r) => {
                let (la, lb) = (to_local(&a), to_local(&b));
                let pad = Vector3::repeat(r);
                let half = 0.5 * (lb - la).norm();
                (
                    0.5 * (la + lb),
                    half + r,
                    la.inf(&lb) - pad,
                    la.sup(&lb) + pad,
                )
            }
            Convex::Disk(rot, x, rd, ht) => {
                let n = rot.column(2).into_owned();
                let lc = to_local(&x);
                let ln = to_local(&(x + n)) - lc;
                // Half extent of a disk (axis n, radius rd, half thickness ht) along e_i.
                let e = Vector3::from_fn(|i, _| {
                    rd * (1.0 - ln[i] * ln[i]).max(0.0).sqrt() + ht * ln[i].abs()
                });
                (lc, rd.hypot(ht), lc - e, lc + e)
            }
        };
        let obstacle_box = &self.boxes[k];
        (aabb_ball_distance(obstacle_box, &c) - radius).max(aabb_gap(obstacle_box, &lo, &hi))
    }

    /// The feature–obstacle pairs within the margin at this pose whose distance may be at most
    /// `limit` (≤ the margin), linearized. A pair whose [`SectionWorld::distance_bound`]
    /// exceeds `limit + PRUNE_SLACK` is not queried: parry would find it beyond the margin
    /// (`limit` = margin: the same answer, None) or farther than `limit` (where a caller
    /// asking for less than the margin does not read it).
    ///
    /// With `n` the unit normal from the robot point `a` towards the obstacle, moving `a` by
    /// `δa` changes the distance by `−n·δa`. Points carried by the new disk move as
    /// `δa = R δp − R Q [ℓ]× δω` (ℓ: the point in the disk frame), points on a segment from a
    /// fixed end to a moving end by the fraction `t` of that.
    fn pairs_within(&self, pose: &Pose, limit: f64) -> Vec<Pair> {
        let mut out = vec![];
        self.pairs_within_into(pose, limit, &mut out, None, &[]);
        out
    }

    /// [`SectionWorld::pairs_within`] into `out` (cleared first), so that callers that query
    /// often reuse one buffer. With a `stop` rule, the queries end (false; `out` then holds
    /// part of the pairs) as soon as it is true of the pairs found so far: it is asked before
    /// the first query and after each pair closer than `limit` is found. Without one, or if it
    /// never fires (true), `out` is what `pairs_within` gives.
    ///
    /// `near` (empty for none): the pairs of a pose a moment ago. A pair touching or
    /// overlapping a box or cylinder now that was near touching there
    /// ([`SEPARATION_SHIFT`]) takes its exact witness from that normal
    /// ([`sat::near_witness`]: the feature moved clear along it, the separating-axis maximum),
    /// without parry's EPA and shifted GJK; where that does not decide, parry's route as
    /// without `near`. The answers agree with that route's to round-off where both decide
    /// (`near_pairs_match_the_pairs_without_them`).
    fn pairs_within_into(
        &self,
        pose: &Pose,
        limit: f64,
        out: &mut Vec<Pair>,
        stop: Option<StopRule<'_>>,
        near: &[Pair],
    ) -> bool {
        let r = &self.r_prev;
        let x0 = self.x_prev + r * pose.p;
        let ri = r * pose.q;
        let identity = PPose::IDENTITY;
        out.clear();
        let backbone = features::backbone(&self.x_prev, &x0, self.backbone_radius);
        let disk = Cylinder::new(self.half_thickness, self.disk_radius);
        let disk_pose = features::disk_pose(&ri, &x0);
        // Cable j's hole at disk i (the chord from its hole at disk i−1, `self.holes[j].1`).
        let hole = |j: usize| x0 + ri * self.holes[j].2;
        let far = limit + PRUNE_SLACK;
        let mut stopped = stop.is_some_and(|rule| rule(out));
        for (k, (shape, opose)) in self.shapes.iter().enumerate() {
            let mut push = |feature: Feature, g: &dyn PShape, gpose: &PPose| {
                if stopped {
                    return;
                }
                let hull = match feature {
                    Feature::Backbone => Convex::Segment(self.x_prev, x0, self.backbone_radius),
                    Feature::Disk => Convex::Disk(ri, x0, self.disk_radius, self.half_thickness),
                    Feature::Cable(j) => Convex::Segment(self.holes[j].1, hole(j), 0.0),
                };
                if self.distance_bound(k, &hull) > far {
                    return;
                }
                // A box face (the wall) or a ball decides the distance in closed form where it
                // can.
                let closed = closed_witness(&**shape, opose, &hull, self.margin);
                // The separating-axis witness's robot point is exact (a disk's side on a
                // cylinder's side: the crossing of the two lines, not a rim point the normal
                // suggests); a box face's is the disk's support point, placed as parry's is.
                // Apart from a box or cylinder: the exact witness without parry's; touching or
                // overlapping, from the pair's normal a moment ago where it was near.
                let apart = match closed {
                    Some(_) => None,
                    None => sat::apart_witness(&**shape, opose, &hull)
                        .or_else(|| self.near_witness(k, feature, &hull, near)),
                };
                let (w, exact) = match (closed, apart) {
                    (Some(decided), _) => (decided, false),
                    (None, Some(e)) => ((e.dist <= self.margin).then_some(e), true),
                    (None, None) => {
                        let rough = features::witness(
                            g,
                            gpose,
                            &**shape,
                            opose,
                            self.margin,
                            self.fields[k].as_deref(),
                        )
                        .map(|w| w.0);
                        match rough.map(|w| (exact_witness(&**shape, opose, &hull, &w), w)) {
                            Some((Some(e), _)) => (Some(e), true),
                            Some((None, w)) => (Some(w), false),
                            None => (None, false),
                        }
                    }
                };
                let Some(w) = w else {
                    return;
                };
                // `n` from the robot towards the obstacle.
                let (mut a, po, n, dist) = (w.robot, w.obstacle, -w.normal, w.dist);
                if feature == Feature::Disk && !exact {
                    let (rd, ht) = (self.disk_radius, self.half_thickness);
                    a = features::disk_support(&ri, &x0, &w.normal, rd, ht).unwrap_or(a);
                }
                let rn = r.transpose() * n;
                let qrn = pose.q.transpose() * rn;
                let (gp, gw) = match feature {
                    Feature::Backbone => {
                        let t = features::segment_fraction(&a, &self.x_prev, &x0);
                        (-t * rn, Vector3::zeros())
                    }
                    Feature::Disk => {
                        let l = ri.transpose() * (a - x0);
                        (-rn, qrn.cross(&l))
                    }
                    Feature::Cable(j) => {
                        let (_, hp, h) = self.holes[j];
                        let hc = hole(j);
                        let t = features::segment_fraction(&a, &hp, &hc);
                        (-t * rn, t * qrn.cross(&h))
                    }
                };
                out.push(Pair {
                    obstacle: k,
                    feature,
                    dist,
                    grad: Vector6::new(gp.x, gp.y, gp.z, gw.x, gw.y, gw.z),
                    point_robot: a,
                    point_obstacle: po,
                    normal: -n,
                });
                stopped = dist < limit && stop.is_some_and(|rule| rule(out));
            };
            push(Feature::Backbone, &backbone, &identity);
            push(Feature::Disk, &disk, &disk_pose);
            for (j, (_, hp, _)) in self.holes.iter().enumerate() {
                let hc = hole(j);
                if (hc - hp).norm() > 0.0 {
                    push(Feature::Cable(j), &features::chord(hp, &hc), &identity);
                }
            }
        }
        if stopped {
            return false;
        }
        // Feature::Cable holds the index into `holes`; report the cable's own index.
        for p in out.iter_mut() {
            if let Feature::Cable(j) = p.feature {
                p.feature = Feature::Cable(self.holes[j].0);
            }
        }
        true
    }
}

impl SectionWorld {
    /// The exact witness of obstacle `k` and `feature` (the hole index for a cable, as in
    /// [`SectionWorld::pairs_within_into`]'s loop) whose convex set is `hull`, from the same
    /// pair's normal among `near` where it was within [`SEPARATION_SHIFT`]
    /// ([`sat::near_witness`]); `None` without one or where that does not decide.
    fn near_witness(
        &self,
        k: usize,
        feature: Feature,
        hull: &Convex,
        near: &[Pair],
    ) -> Option<Witness> {
        let reported = match feature {
            Feature::Cable(j) => Feature::Cable(self.holes[j].0),
            f => f,
        };
        let hint = near
            .iter()
            .find(|p| p.obstacle == k && p.feature == reported && p.dist < SEPARATION_SHIFT)?;
        let (shape, opose) = &self.shapes[k];
        let (o, f) = (
            sat::obstacle_support(&**shape, opose)?,
            sat::feature_support(hull)?,
        );
        sat::near_witness(&f, &o, (&hint.normal, hint.dist))
    }
}

/// parry's witness `w` of a feature against a box or cylinder made exact where a box edge or
/// corner or a cylinder's rim or side decides it (`contact/sat.rs`: its normal otherwise
/// chatters at ~1e-6 rad near touching); `None` where that does not decide.
fn exact_witness(shape: &dyn PShape, opose: &PPose, hull: &Convex, w: &Witness) -> Option<Witness> {
    sat::obstacle_support(shape, opose)
        .zip(sat::feature_support(hull))
        .and_then(|(o, f)| sat::sat_witness(&f, &o, w))
}

/// Up to 300 random section worlds of `robot` next to `scene`, each with a pose whose features
/// are within the margin (separated, touching and penetrating pairs): the sample the unit tests
/// of the contact queries and of their curvature draw from.
#[cfg(test)]
pub(super) fn random_section_worlds(
    robot: &Robot,
    scene: &Scene,
    rng: &mut crate::numeric::test_rng::Rng,
) -> Vec<(SectionWorld, Pose)> {
    use crate::numeric::so3::exp_so3;
    let mut rnd = |a: f64, b: f64| rng.range(a, b);
    let relevant: Vec<usize> = (0..scene.obstacles.len()).collect();
    let mut out = vec![];
    for _ in 0..300 {
        let r_prev = exp_so3(&Vector3::new(
            rnd(-0.6, 0.6),
            rnd(-0.6, 0.6),
            rnd(-3.2, 3.2),
        ));
        let x_prev = Vector3::new(rnd(0.0, 0.05), rnd(0.0, 0.09), rnd(0.06, 0.13));
        let i = 1 + (rnd(0.0, 8.99) as usize);
        let Some(w) = SectionWorld::new(robot, scene, &relevant, i, &r_prev, &x_prev) else {
            continue;
        };
        let l = robot.section_length(i);
        let w_rot = Vector3::new(rnd(-0.5, 0.5), rnd(-0.5, 0.5), rnd(-0.5, 0.5));
        let pose = Pose {
            p: exp_so3(&(0.5 * w_rot)) * Vector3::new(0.0, 0.0, l),
            q: exp_so3(&w_rot),
        };
        out.push((w, pose));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;

    /// The pruned queries change nothing: over random section poses next to the wall and the
    /// pillar (separated, touching and penetrating), the pairs within the margin are the
    /// unpruned ones bit for bit (`limit = ∞` prunes nothing), the penetration is their sum,
    /// and every bound is below parry's distance of the pair.
    #[test]
    fn pruned_pairs_equal_the_unpruned_ones() {
        let robot = Model::from_file("models/paper/case1.toml").unwrap().robot;
        let mut rng = crate::numeric::test_rng::Rng(0x2545_f491_4f6c_dd1d);
        let (mut kept, mut pruned, mut touching) = (0, 0, 0);
        for scene in ["wall", "pillar"] {
            let scene = Scene::from_file(format!("models/scenes/{scene}.toml")).unwrap();
            for (w, pose) in random_section_worlds(&robot, &scene, &mut rng) {
                let all = w.pairs_within(&pose, f64::INFINITY);
                let near = w.pairs(&pose);
                let key = |p: &Pair| (p.obstacle, p.feature, p.dist.to_bits(), p.grad);
                let all_keys: Vec<_> = all.iter().map(key).collect();
                assert_eq!(all_keys, near.iter().map(key).collect::<Vec<_>>());
                let pen = penetration_of(&all, w.clearance);
                // Equal values; a sum with no term is −0.0 where the unpruned one adds +0.0
                // terms (the merit adds it to Σ|c|, so the merit is the same to the bit).
                assert_eq!(
                    Some(pen),
                    w.penetration(&pose, &mut vec![], &|_| false, &[])
                );
                // A stop rule gives up exactly when the whole sum meets it, else changes nothing
                // (to the bit: the sum without a rule).
                let full = w.penetration(&pose, &mut vec![], &|_| false, &[]);
                for t in [0.0, 0.5 * pen, pen, 2.0 * pen + 1e-9] {
                    let stopped = w.penetration(&pose, &mut vec![], &|p| p >= t, &[]);
                    if pen >= t {
                        assert_eq!(stopped, None, "{pen} {t}");
                    } else {
                        assert_eq!(stopped.map(f64::to_bits), full.map(f64::to_bits), "{t}");
                    }
                }
                kept += all.len();
                touching += all.iter().filter(|p| p.dist < 1e-3).count();
                // Pruned from the penetration: pairs beyond the clearance.
                pruned += all.len() - w.pairs_within(&pose, w.clearance).len();
                let x0 = w.x_prev + w.r_prev * pose.p;
                for p in &all {
                    let hull = match p.feature {
                        Feature::Backbone => Convex::Segment(w.x_prev, x0, w.backbone_radius),
                        Feature::Disk => {
                            Convex::Disk(w.r_prev * pose.q, x0, w.disk_radius, w.half_thickness)
                        }
                        _ => continue,
                    };
                    // A bound on the unsigned distance (0 for overlapping shapes).
                    let bound = w.distance_bound(p.obstacle, &hull);
                    assert!(
                        bound <= p.dist.max(0.0) + 1e-12,
                        "{:?}: {bound} > {}",
                        p.feature,
                        p.dist
                    );
                }
            }
        }
        // The sample reaches every regime.
        assert!(
            kept > 200 && pruned > 50 && touching > 20,
            "{kept} {pruned} {touching}"
        );
    }

    /// The pairs queried with the pairs of a pose a moment ago (`near`, the line search's
    /// iterate) are those queried without them: over random section poses next to the wall
    /// and the pillar, each moved a little (up to ~0.3 mm and 5 mrad) from a pose whose pairs
    /// are the hints, the same pairs in the same order, distances to 1e-12 m, normals and
    /// gradients to 1e-9; and the touching or overlapping pairs of a box or cylinder
    /// (parry's EPA and shifted GJK without hints) mostly take the hinted route.
    #[test]
    fn near_pairs_match_the_pairs_without_them() {
        use crate::numeric::so3::exp_so3;
        let robot = Model::from_file("models/paper/case1.toml").unwrap().robot;
        let mut rng = crate::numeric::test_rng::Rng(0x6e65_6172_5f70_6169);
        let (mut compared, mut hinted, mut better) = (0, 0, 0);
        for scene in ["wall", "pillar"] {
            let scene = Scene::from_file(format!("models/scenes/{scene}.toml")).unwrap();
            for (w, pose) in random_section_worlds(&robot, &scene, &mut rng) {
                let before = w.pairs(&pose);
                let dp = Vector3::from_fn(|_, _| rng.range(-2e-4, 2e-4));
                let dq = Vector3::from_fn(|_, _| rng.range(-3e-3, 3e-3));
                let moved = Pose {
                    p: pose.p + dp,
                    q: pose.q * exp_so3(&dq),
                };
                let cold = w.pairs(&moved);
                let mut warm = vec![];
                assert!(w.pairs_within_into(&moved, w.margin, &mut warm, None, &before));
                assert_eq!(cold.len(), warm.len());
                for (c, h) in cold.iter().zip(&warm) {
                    assert_eq!((c.obstacle, c.feature), (h.obstacle, h.feature));
                    assert!((c.dist - h.dist).abs() < 1e-12, "{} {}", c.dist, h.dist);
                    compared += 1;
                    if (c.normal - h.normal).amax() >= 1e-9 {
                        // parry's answer where its route's maximum did not decide: the hinted
                        // normal is the better one by the support maps.
                        let phi = support_value(&w, &moved, h);
                        let (cn, hn) = (c.normal, h.normal);
                        assert!((phi(&hn) - h.dist).abs() < 1e-12, "{hn:?} {}", h.dist);
                        assert!(phi(&cn) <= h.dist + 1e-13, "{cn:?} {hn:?}");
                        assert!((cn - hn).amax() < 1e-4, "{cn:?} {hn:?}");
                        better += 1;
                        continue;
                    }
                    assert!((c.grad - h.grad).amax() < 1e-9, "{:?} {:?}", c.grad, h.grad);
                    let was_near = before.iter().any(|b| {
                        (b.obstacle, b.feature) == (c.obstacle, c.feature)
                            && b.dist < SEPARATION_SHIFT
                    });
                    hinted += usize::from(was_near && c.dist <= 1e-9);
                }
            }
        }
        eprintln!("compared {compared}, hinted {hinted}, better than parry's {better}");
        assert!(compared > 200 && hinted > 20, "{compared} {hinted}");
    }

    /// The separating-axis value `m ↦ m̂·(s_F(−m̂) − s_O(m̂))` of pair `p` at `pose` by parry's
    /// support maps (`sat::tests::separation`, independent of the solver under test): the
    /// signed distance at the pair's normal, no more anywhere.
    fn support_value<'a>(
        w: &'a SectionWorld,
        pose: &Pose,
        p: &Pair,
    ) -> impl Fn(&Vector3<f64>) -> f64 + 'a {
        let x0 = w.x_prev + w.r_prev * pose.p;
        let ri = w.r_prev * pose.q;
        let (g, gpose): (Box<dyn PShape>, PPose) = match p.feature {
            Feature::Backbone => (
                Box::new(features::backbone(&w.x_prev, &x0, w.backbone_radius)),
                PPose::IDENTITY,
            ),
            Feature::Disk => (
                Box::new(Cylinder::new(w.half_thickness, w.disk_radius)),
                features::disk_pose(&ri, &x0),
            ),
            Feature::Cable(c) => {
                let (_, hp, h) = *w.holes.iter().find(|h| h.0 == c).unwrap();
                (
                    Box::new(features::chord(&hp, &(x0 + ri * h))),
                    PPose::IDENTITY,
                )
            }
        };
        let (shape, opose) = (&w.shapes[p.obstacle].0, w.shapes[p.obstacle].1);
        move |m: &Vector3<f64>| sat::tests::separation(&*g, &gpose, &**shape, &opose, m)
    }
}
