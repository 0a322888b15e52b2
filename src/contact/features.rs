//! The robot's features as parry shapes, the witness of one feature–obstacle pair, and the
//! contact record a shape reports.

use super::{nvec, polish, ppose, pvec, query, query_near, y_to_z, Witness};
use crate::model::robot::Robot;
use crate::shape::Contact;
use nalgebra::{Matrix3, Vector3};
use parry3d::math::Pose as PPose;
use parry3d::shape::{Capsule, Cylinder, Segment, Shape as PShape, ShapeType};

/// Which parts of a robot's body meet the world, and the radius of its backbone there: the
/// one reading of [`crate::model::robot::Body`] that every list of contact features makes
/// (the energy method's contacts, reach's and plan's clearance).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyParts {
    /// Spacer disks take part (cylinders of the disk radius and thickness).
    pub disks: bool,
    /// Cable runs between disks take part (chords): cables through spacer disks, not cables
    /// inside the rod (the body covers them).
    pub cables: bool,
    /// Radius of the backbone's capsules: [`Robot::body_radius`] \[m\].
    pub radius: f64,
}

impl BodyParts {
    /// The parts of `robot` that meet the world.
    pub fn of(robot: &Robot) -> BodyParts {
        BodyParts {
            disks: robot.has_disks(),
            cables: robot.body.cables_exposed(),
            radius: robot.body_radius(),
        }
    }
}

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
    field: Option<&super::field::SolidField>,
) -> Option<(Witness, f64)> {
    witness_of(
        g,
        gpose,
        shape,
        opose,
        query(gpose, g, opose, shape, margin, field)?,
    )
}

/// [`witness`] from what a nearby state found for the same pair (a line search's trial and
/// its iterate), with the triangle of a solid mesh its witness lies on: `near`, the
/// `(normal, distance)` of a pair that was near touching there (normal from the obstacle
/// towards the robot), asks [`query_near`] first; `hint`, the triangle found there, starts
/// the closest-triangle search ([`super::parry::query_hinted`]: the same answer).
pub(crate) fn witness_near(
    (g, gpose): (&dyn PShape, &PPose),
    (shape, opose): (&dyn PShape, &PPose),
    margin: f64,
    (near, hint): (Option<(&Vector3<f64>, f64)>, Option<u32>),
    field: Option<&super::field::SolidField>,
) -> Option<(Witness, f64, Option<u32>)> {
    let ct = match near.and_then(|n| query_near(gpose, g, opose, shape, margin, n)) {
        Some(answer) => answer?,
        None => super::parry::query_hinted((g, gpose), (shape, opose), (margin, field, hint))?,
    };
    let triangle = super::solid::solid(shape).map(|_| ct.subshape2);
    let (w, dist) = witness_of(g, gpose, shape, opose, ct)?;
    Some((w, dist, triangle))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::parry::SEPARATION_SHIFT;
    use crate::numeric::test_rng::Rng;
    use parry3d::shape::{Ball, Cuboid};

    /// The tests' generator with the vectors and rotations drawn here.
    struct Gen(Rng);
    impl Gen {
        fn range(&mut self, a: f64, b: f64) -> f64 {
            self.0.range(a, b)
        }
        fn vec(&mut self, s: f64) -> Vector3<f64> {
            Vector3::new(self.range(-s, s), self.range(-s, s), self.range(-s, s))
        }
        fn rot(&mut self) -> Matrix3<f64> {
            nalgebra::Rotation3::new(self.vec(3.0)).into_inner()
        }
    }

    /// The obstacles of the scenes (box, ball, capsule, cylinder) at random poses.
    fn obstacle(k: usize, gen: &mut Gen) -> (Box<dyn PShape>, PPose) {
        let shape: Box<dyn PShape> = match k % 4 {
            0 => Box::new(Cuboid::new(pvec(&Vector3::new(0.01, 0.02, 0.015)))),
            1 => Box::new(Ball::new(0.015)),
            2 => Box::new(Capsule::new_y(0.02, 0.008)),
            _ => Box::new(Cylinder::new(0.04, 0.015)),
        };
        (shape, ppose(&gen.rot(), &gen.vec(0.01)))
    }

    /// The robot's features (disk, backbone capsule, cable chord) at a random place, with the
    /// bounding ball `energy/contacts.rs` gives each.
    fn feature(k: usize, gen: &mut Gen) -> (Box<dyn PShape>, PPose, (Vector3<f64>, f64)) {
        let (a, b) = (gen.vec(0.05), gen.vec(0.05));
        let (a, b) = (a, a + (b - a).normalize() * 0.005);
        let mid = 0.5 * (a + b);
        match k % 3 {
            0 => {
                let (rd, ht) = (0.012, 0.001);
                let x = gen.vec(0.05);
                let shape = Box::new(Cylinder::new(ht, rd));
                (
                    shape,
                    disk_pose(&gen.rot(), &x),
                    (x, (rd * rd + ht * ht).sqrt()),
                )
            }
            1 => (
                Box::new(backbone(&a, &b, 0.0015)),
                PPose::IDENTITY,
                (mid, 0.0025 + 0.0015),
            ),
            _ => (Box::new(chord(&a, &b)), PPose::IDENTITY, (mid, 0.0025)),
        }
    }

    /// `ball_gap` never exceeds parry's distance, and a pair it puts beyond a margin is one
    /// the query drops too (what `energy/contacts.rs` relies on to skip the query).
    #[test]
    fn ball_gap_bounds_the_distance() {
        let mut gen = Gen(Rng(0x9E37_79B9_7F4A_7C15));
        let margin = 0.01;
        let mut pruned = 0;
        for k in 0..400 {
            let (o, opose) = obstacle(k, &mut gen);
            let (g, gpose, (c, r)) = feature(k / 4, &mut gen);
            let gap = ball_gap(&*o, &opose, &c, r).expect("a simple shape");
            let d = parry3d::query::distance(&gpose, &*g, &opose, &*o)
                .expect("supported")
                .distance;
            assert!(gap <= d + 1e-12, "{k}: gap {gap} > distance {d}");
            if gap > margin {
                pruned += 1;
                assert!(
                    witness(&*g, &gpose, &*o, &opose, margin, None).is_none(),
                    "{k}"
                );
            }
        }
        assert!(pruned > 50, "{pruned}");
    }

    /// `witness_near` from a normal off by up to 1e-3 rad and an old distance gives a distance
    /// as good as `witness`'s (checked against the exact distance to a ball, elsewhere
    /// against the shapes' separation along the normals), for pairs overlapping, touching and
    /// near touching.
    #[test]
    fn near_witness_is_the_witness() {
        let mut gen = Gen(Rng(0xD1B5_4A32_D192_ED03));
        let margin = 0.01;
        let mut checked = 0;
        // Largest error (near, query) from an early step's normal and from a late one's.
        let mut worst = [(0.0f64, 0.0f64); 2];
        for k in 0..300 {
            let (o, opose) = obstacle(k, &mut gen);
            let (g, gpose, _) = feature(k / 4, &mut gen);
            let Ok(Some(ct)) = parry3d::query::contact(&gpose, &*g, &opose, &*o, 1.0) else {
                continue;
            };
            if ct.dist <= 0.0 {
                continue;
            }
            // Move the feature towards the obstacle to a gap of `target` (negative: overlap).
            let target = [-5e-5, 0.0, 1e-6, 2e-4][k % 4];
            let n = -nvec(ct.normal1);
            let t = gpose.translation + pvec(&(n * (target - ct.dist)));
            let pose = PPose::from_parts(t, gpose.rotation);
            let Some((want, _)) = witness(&*g, &pose, &*o, &opose, margin, None) else {
                continue;
            };
            // A normal off by up to ~1e-3 rad (an early Newton step) or ~1e-6 rad (a late one).
            let eps = if k % 2 == 0 { 1e-3 } else { 1e-6 };
            let hint = (want.normal + gen.vec(eps)).normalize();
            let old = want.dist + gen.range(-1e-5, 1e-5);
            let near = (Some((&hint, old)), None);
            let (got, ..) = witness_near((&*g, &pose), (&*o, &opose), margin, near, None)
                .expect("near pair found");
            // Both shapes' separation along a direction (support functions) is a lower bound
            // on the signed distance that only the contact normal attains.
            let sep = |n: &Vector3<f64>| {
                let (gs, os) = (g.as_support_map().unwrap(), o.as_support_map().unwrap());
                n.dot(&nvec(gs.support_point(&pose, pvec(&-n))))
                    - n.dot(&nvec(os.support_point(&opose, pvec(n))))
            };
            // The reference: against a ball the exact distance (the feature's distance to the
            // centre, projected in closed form, minus the radius); elsewhere the best
            // separation along either answer's normal.
            let best = if k % 4 == 1 {
                let c = nvec(opose.translation);
                g.distance_to_point(&pose, pvec(&c), true) - 0.015
            } else {
                sep(&got.normal).max(sep(&want.normal))
            };
            // Against the reference: a shift along a wrong direction would be off by ~1e-3 m;
            // parry's own answers carry up to ~1e-6 m on overlapping pairs (a capsule 5e-5 m
            // into a box), ~4e-7 m on curved ones.
            let (eg, ew) = ((got.dist - best).abs(), (want.dist - best).abs());
            assert!(eg <= 1e-5, "{k}: off by {eg:e} m (the query by {ew:e} m)");
            if k % 4 == 1 {
                assert!(eg <= 1e-9, "{k}: off by {eg:e} m from the exact distance");
            }
            let r = usize::from(eps < 1e-4);
            worst[r] = (worst[r].0.max(eg), worst[r].1.max(ew));
            assert!(want.dist.abs() < SEPARATION_SHIFT);
            checked += 1;
        }
        assert!(checked > 100, "{checked}");
        eprintln!(
            "largest error near / query: early {:?}, late {:?}",
            worst[0], worst[1]
        );
        // Overall no worse than the query's own answers, to GJK's noise on curved pairs.
        for (near, query) in worst {
            assert!(near <= 2.0 * query + 1e-8, "{near:e} vs {query:e}");
        }
    }
}
