//! The parry3d bridge: parry poses and vectors from nalgebra ones, a contact query that stays
//! on GJK near touching (EPA recovery for barely overlapping shapes), and the polish of GJK's
//! witness points by alternating projections.

use nalgebra::{Matrix3, Vector3};
use parry3d::math::{Pose as PPose, Vector as PVec};
use parry3d::query::Contact as PContact;
use parry3d::shape::Shape as PShape;

/// Robot features within this of an obstacle are queried again moved this far away \[m\].
pub(crate) const SEPARATION_SHIFT: f64 = 1e-3;

/// Two candidates closer than this to the clearance count as touching \[m\].
pub(crate) const CONTACT_TOL: f64 = 1e-9;

/// Rotation taking parry's cylinder axis (local y) to the disk normal (local z).
pub(crate) fn y_to_z() -> Matrix3<f64> {
    Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0)
}

/// A parry pose from an orthonormal rotation and a translation.
pub(crate) fn ppose(r: &Matrix3<f64>, t: &Vector3<f64>) -> PPose {
    let iso = nalgebra::Isometry3::from_parts(
        nalgebra::Translation3::from(*t),
        // `r` is orthonormal (products of rotations, re-orthonormalized): the direct
        // conversion, not `from_matrix`'s iterative fit (10 % of a contact solve's time).
        nalgebra::UnitQuaternion::from_rotation_matrix(
            &nalgebra::Rotation3::from_matrix_unchecked(*r),
        ),
    );
    iso.into()
}

/// parry vector from nalgebra.
pub(crate) fn pvec(v: &Vector3<f64>) -> PVec {
    PVec::new(v.x, v.y, v.z)
}

/// nalgebra vector from parry.
pub(crate) fn nvec(v: PVec) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

/// `x` raised past the round-off of the distance queries that produced it (1e-9 relative,
/// 1e-12 m absolute): as a query's margin, a bound of `x` that is sure to admit a distance
/// found equal to `x`.
pub(crate) fn past_roundoff(x: f64) -> f64 {
    x * (1.0 + 1e-9) + 1e-12
}

/// Signed distance, witness points and normal (`normal1`, from the robot feature `g` towards
/// the obstacle) of one feature–obstacle pair, or `None` beyond `margin`.
///
/// Near touching, parry switches between GJK (separated) and EPA (penetrating), whose normals
/// for smooth shapes differ by ~1e-5: Newton iterates then chatter at ~1e-7 m and never
/// converge. So a pair closer than [`SEPARATION_SHIFT`] is queried again with the feature moved
/// `shift` away along the normal, where GJK alone answers: the signed distance is the max over
/// directions m of (−h_B(−m) − h_A(m)), so the shifted answer minus `shift` is at least as
/// close to the true value as the first one.
///
/// A solid mesh's distance is signed by the side of the wall the feature is on
/// ([`super::solid`]), without the shift (its triangles are flat); its signed-distance grid
/// `field`, when given, skips the query of a feature it proves beyond `margin` and narrows the
/// query to the feature's upper bound (same answer, fewer triangles).
pub(crate) fn query(
    gpose: &PPose,
    g: &dyn PShape,
    opose: &PPose,
    shape: &dyn PShape,
    margin: f64,
    field: Option<&super::field::SolidField>,
) -> Option<PContact> {
    query_hinted((g, gpose), (shape, opose), (margin, field, None))
}

/// [`query`] with the triangle of a solid mesh that a nearby state found closest, `hint`,
/// which starts the closest-triangle search ([`super::solid::closest_triangle`]: the same
/// answer, to the bit, from fewer nodes). For a solid mesh the contact's `subshape2` is the
/// triangle of its witness.
pub(crate) fn query_hinted(
    (g, gpose): (&dyn PShape, &PPose),
    (shape, opose): (&dyn PShape, &PPose),
    (margin, field, hint): (f64, Option<&super::field::SolidField>, Option<u32>),
) -> Option<PContact> {
    // A solid mesh: parry's closest triangle, signed by the side the feature is on.
    if let Some(mesh) = super::solid::solid(shape) {
        // The ball-bounded grid bounds first; the finer ones only when those do not decide.
        let bounds = field.and_then(|f| {
            f.feature_bounds(g, gpose, opose, false)
                .filter(|b| b.0 > margin || b.0 > 0.0 && b.1 <= margin)
                .or_else(|| f.feature_bounds(g, gpose, opose, true))
        });
        let free = bounds.is_some_and(|b| b.0 > 0.0);
        let margin = match bounds {
            // Wholly on the free side and beyond the margin: parry would find nothing.
            Some((lo, _)) if lo > margin => return None,
            // Wholly on the free side: its closest triangle is within its upper bound, so
            // parry's answer with that margin is the same (module docs of `field.rs`).
            Some((lo, hi)) if lo > 0.0 => margin.min(past_roundoff(hi)),
            _ => margin,
        };
        let closest = if field.is_some() {
            super::solid::closest_triangle(gpose, g, opose, mesh, (margin, hint), free)
        } else {
            parry3d::query::contact(gpose, g, opose, shape, margin).ok()?
        };
        return match closest {
            // Wholly on the free side by the grid: its witness is too (no side test).
            Some(ct) if free && ct.dist > 0.0 => Some(ct),
            Some(ct) => Some(super::solid::signed(ct, g, gpose, mesh, opose)),
            // Wholly on the free side by the grid: apart from the surface.
            None if free => None,
            None if parry3d::query::intersection_test(gpose, g, opose, shape)
                .ok()?
                .intersecting =>
            {
                Some(super::solid::intersecting(g, gpose, mesh, opose))
            }
            None => None,
        };
    }
    let mut exact = true;
    let ct = match parry3d::query::contact(gpose, g, opose, shape, margin).ok()? {
        Some(ct) => ct,
        // `None` also means that EPA failed on shapes that barely overlap (seen for a disk on
        // a cylinder at 1e-12 m): then find the normal from a copy of the feature moved clear
        // along an axis.
        None if parry3d::query::intersection_test(gpose, g, opose, shape)
            .ok()?
            .intersecting =>
        {
            exact = false;
            let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
            let clear = 2.0 * SEPARATION_SHIFT;
            let mut ct = axes.iter().flat_map(|a| [*a, -a]).find_map(|dir| {
                let moved =
                    PPose::from_parts(gpose.translation + pvec(&(clear * dir)), gpose.rotation);
                match parry3d::query::contact(&moved, g, opose, shape, margin + clear) {
                    Ok(Some(c)) if c.dist > 0.0 => Some(c),
                    _ => None,
                }
            })?;
            ct.dist = 0.0;
            ct
        }
        None => return None,
    };
    if ct.dist >= SEPARATION_SHIFT {
        return Some(ct);
    }
    let shift = SEPARATION_SHIFT + (-ct.dist).max(0.0);
    match shifted(gpose, g, opose, shape, margin, &nvec(ct.normal1), shift) {
        Ok(Some(c2)) => Some(c2),
        // Without the GJK answer, the first one only if it was a real one.
        _ if exact => Some(ct),
        _ => None,
    }
}

/// The contact of the feature moved `shift` away along `-n0` (`n0` from the feature towards
/// the obstacle), brought back: distance minus `shift`, the feature's point moved back.
fn shifted(
    gpose: &PPose,
    g: &dyn PShape,
    opose: &PPose,
    shape: &dyn PShape,
    margin: f64,
    n0: &Vector3<f64>,
    shift: f64,
) -> Result<Option<PContact>, parry3d::query::Unsupported> {
    let moved = PPose::from_parts(gpose.translation - pvec(&(shift * n0)), gpose.rotation);
    Ok(
        parry3d::query::contact(&moved, g, opose, shape, margin + shift)?.map(|mut c2| {
            c2.dist -= shift;
            c2.point1 += pvec(&(shift * n0));
            c2
        }),
    )
}

/// [`query`] for a pair that was near touching ([`SEPARATION_SHIFT`]) a moment ago, at
/// distance `dist0` with normal `normal0` (from the obstacle towards the robot): the feature
/// is moved clear along that normal at once, where GJK alone answers, without the first query
/// (and the EPA it runs when the two barely overlap). The shifted answer is the same as
/// [`query`]'s up to GJK's tolerance: moving a convex feature by `shift` along a direction
/// `ε` off the contact normal changes the signed distance by `shift` to within
/// `shift (1 − cos ε)`, and the witness is polished afterwards as any other.
/// `Some(None)` beyond `margin` (the move changes the distance by at most `shift`); `None` when
/// this cannot answer (a non-convex obstacle, the moved feature still overlaps, an unsupported
/// pair): use [`query`].
pub(crate) fn query_near(
    gpose: &PPose,
    g: &dyn PShape,
    opose: &PPose,
    shape: &dyn PShape,
    margin: f64,
    (normal0, dist0): (&Vector3<f64>, f64),
) -> Option<Option<PContact>> {
    // Convex obstacles only: a mesh's distance is unsigned, its old normal may point through it.
    if !shape.is_convex() {
        return None;
    }
    let shift = SEPARATION_SHIFT + (-dist0).max(0.0);
    let c = match shifted(gpose, g, opose, shape, margin, &-normal0, shift) {
        // GJK answered (the moved feature is clear of the obstacle).
        Ok(Some(c)) if c.dist + shift > 0.0 => c,
        Ok(None) => return Some(None),
        _ => return None,
    };
    // Where the normal has turned, once more along the new one (as `query` moves the feature
    // along its first answer's normal): the shifted answer's error grows with the angle.
    let n1 = nvec(c.normal1);
    if (n1 + normal0).norm() <= NORMAL_KEPT {
        return Some(Some(c));
    }
    let shift = SEPARATION_SHIFT + (-c.dist).max(0.0);
    match shifted(gpose, g, opose, shape, margin, &n1, shift) {
        Ok(Some(c2)) if c2.dist + shift > 0.0 => Some(Some(c2)),
        _ => Some(Some(c)),
    }
}

/// [`query_near`] moves the feature along the new normal again when it differs from the old
/// one by more than this \[rad\].
const NORMAL_KEPT: f64 = 1e-6;

/// Closest points of one feature–obstacle pair.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Witness {
    /// On the robot feature.
    pub robot: Vector3<f64>,
    /// On the obstacle.
    pub obstacle: Vector3<f64>,
    /// Unit normal from the obstacle towards the robot.
    pub normal: Vector3<f64>,
    /// Signed distance \[m\].
    pub dist: f64,
}

/// Polish a GJK answer by alternating projections between the feature and the obstacle.
///
/// GJK's witness points are good to ~1e-6 m at centimetres (the distance is stationary in
/// them, so it is far better), which makes the normal — the direction of the gradient — off by
/// ~5e-5. Projecting back and forth between the two convex sets converges to the closest pair,
/// whose difference is the exact normal. Near touching the feature is moved
/// [`SEPARATION_SHIFT`] away along the normal first (as in [`query`]) and moved back after.
/// `None` when the polish cannot improve (overlap, a mesh obstacle, degenerate gap); the
/// caller keeps GJK's answer. `rough.normal` points from the obstacle to the robot.
pub(crate) fn polish(
    g: &dyn PShape,
    gpose: &PPose,
    shape: &dyn PShape,
    opose: &PPose,
    rough: &Witness,
) -> Option<Witness> {
    let (a, po, n, dist) = (&rough.robot, &rough.obstacle, &rough.normal, rough.dist);
    if dist < -SEPARATION_SHIFT || shape.as_composite_shape().is_some() {
        return None;
    }
    let shift = if dist < SEPARATION_SHIFT {
        SEPARATION_SHIFT
    } else {
        0.0
    };
    let sigma = n * shift;
    let moved = PPose::from_parts(gpose.translation + pvec(&sigma), gpose.rotation);
    let mut xs = a + sigma;
    let mut po = *po;
    for _ in 0..4 {
        let pf = g.project_point(&moved, pvec(&po), false);
        if pf.is_inside {
            return None;
        }
        xs = nvec(pf.point);
        let pr = shape.project_point(opose, pvec(&xs), false);
        if pr.is_inside {
            return None;
        }
        po = nvec(pr.point);
    }
    let gap = xs - po;
    let len = gap.norm();
    if len < 0.1 * SEPARATION_SHIFT.max(dist) {
        return None;
    }
    Some(Witness {
        robot: xs - sigma,
        obstacle: po,
        normal: gap / len,
        dist: len - shift,
    })
}
