//! Signed distances to a solid mesh: a closed mesh whose scene declares its free side
//! (`free = "inside"` for a lumen, `"outside"` for an organ; `model/mesh_check.rs`), built as
//! parry's oriented mesh whose inside is the obstacle region ([`crate::model::mesh::trimesh`]).
//!
//! parry's contact query against a mesh is the closest triangle's: unsigned, so a robot feature
//! that has passed through a thin wall looks as clear as one on the free side. Here:
//!
//! * a feature apart from the surface (parry's distance `d > 0`) is on one side; its witness
//!   point's side is parry's pseudo-normal test (exact for a closed, consistently oriented,
//!   manifold mesh). On the free side the distance is `d`, exactly;
//! * a feature across the surface (`d ≤ 0`) or wholly on the obstacle side is given the depth
//!   it must move along the wall's normal `n` (the closest triangle's, pointing to the free
//!   side) to clear the wall's plane through the closest surface point `w`:
//!   `s = min over the feature's points x of n · (x − w) = n · (x* − w)`, `x*` the feature's
//!   support point along `−n` — exact for a flat wall, continuous from across to beyond, and
//!   never above `−|d|`. Its witness is `x*`, its gradient direction `n` (the envelope theorem
//!   on the plane's distance).
//!
//! A feature wholly on the obstacle side farther from the surface than the query's margin is
//! not returned (as any pair beyond the margin): the robot is one connected body from a base on
//! the free side (checked first, [`super::broad::check_base`]), so such a robot has another
//! feature across the wall, which is.

use super::nvec;
use parry3d::math::{Pose as PPose, Vector as PVec};
use parry3d::query::{Contact as PContact, PointQueryWithLocation};
use parry3d::shape::{Shape as PShape, TriMesh};

/// The solid mesh of an obstacle's shape: an oriented parry mesh with pseudo-normals (a mesh
/// with a declared free side); `None` for any other shape (surfaces included).
pub(crate) fn solid(shape: &dyn PShape) -> Option<&TriMesh> {
    shape
        .as_trimesh()
        .filter(|m| m.pseudo_normals_if_oriented().is_some())
}

/// Whether `shape` is a mesh without a declared free side (a surface) that is nevertheless
/// closed ([`crate::model::mesh_check::closed`]): a feature across it is across for good, as
/// across a solid's wall. Linear in the triangles; asked only of a mesh a start crosses.
pub(crate) fn closed_surface(shape: &dyn PShape) -> bool {
    shape
        .as_trimesh()
        .filter(|m| m.pseudo_normals_if_oriented().is_none())
        .is_some_and(|m| crate::model::mesh_check::closed(m.vertices().len(), m.indices()))
}

/// Whether the world point `p` lies in the obstacle region of the solid `mesh` at `pose`
/// (behind the pseudo-normal of its closest surface point).
pub(crate) fn in_obstacle(mesh: &TriMesh, pose: &PPose, p: PVec) -> bool {
    mesh.project_local_point_and_get_location(pose.inverse_transform_point(p), false)
        .0
        .is_inside
}

/// The signed contact of feature `g` at `gpose` with the solid `mesh` at `opose`, from parry's
/// unsigned one `ct` (module docs).
pub(crate) fn signed(
    ct: PContact,
    g: &dyn PShape,
    gpose: &PPose,
    mesh: &TriMesh,
    opose: &PPose,
) -> PContact {
    if ct.dist > 0.0 && !in_obstacle(mesh, opose, ct.point1) {
        return ct;
    }
    across(ct.point2, ct.point1, -ct.dist.abs(), g, gpose, mesh, opose)
}

/// The depth of a feature across or beyond the wall near the surface point `near` (world),
/// no more than `cap`; `fallback` is the robot's witness when the feature has no support map.
fn across(
    near: PVec,
    fallback: PVec,
    cap: f64,
    g: &dyn PShape,
    gpose: &PPose,
    mesh: &TriMesh,
    opose: &PPose,
) -> PContact {
    let local = opose.inverse_transform_point(near);
    let (proj, (tri, _)) = mesh.project_local_point_and_get_location(local, false);
    let w = opose.transform_point(proj.point);
    // The triangle's normal points to the free side (parry's outside of the oriented mesh).
    let n = mesh
        .triangle_normal(tri)
        .map(|n| opose.transform_vector(n))
        .filter(|n| nvec(*n).norm() > 0.5);
    let Some(n) = n else {
        // No normal (cannot happen for a checked solid): the unsigned depth, negated.
        return PContact::new(
            fallback,
            w,
            (w - fallback).normalize(),
            (fallback - w).normalize(),
            cap,
        );
    };
    let x = g
        .as_support_map()
        .map_or(fallback, |sm| sm.support_point(gpose, -n));
    let s = n.dot(x - w).min(cap);
    PContact::new(x, w, -n, n, s).with_subshapes(0, tri)
}

/// The signed contact of a feature that parry finds intersecting the solid's surface but for
/// which its contact query gave no answer (EPA failed on a barely overlapping pair): the depth
/// across the wall near the surface point closest to the centre of the feature's bounds.
pub(crate) fn intersecting(
    g: &dyn PShape,
    gpose: &PPose,
    mesh: &TriMesh,
    opose: &PPose,
) -> PContact {
    let c = g.compute_aabb(gpose).center();
    let near = opose.transform_point(
        mesh.project_local_point_and_get_location(opose.inverse_transform_point(c), false)
            .0
            .point,
    );
    across(near, c, 0.0, g, gpose, mesh, opose)
}

/// The most face contacts [`face_contacts`] returns for one feature.
pub(crate) const MAX_FACES: usize = 8;

/// The face contacts of feature `g` at `gpose` with the solid `mesh` at `opose`: every
/// triangle facing the way `towards` does (the feature's closest contact's normal, within
/// 60°) whose plane the feature lies beyond by `|s| ≤ within` (across it for `s < 0`: the depth
/// of [`signed`]) and whose point nearest the feature's lowest point is inside its face, or
/// beyond it across concave edges only and behind the wall (below), each with that distance,
/// closest first, one per plane (normals apart by more than ~1e-4 rad), at most
/// [`MAX_FACES`]. Facing the same way keeps out the far side of a thin wall.
///
/// Why: the distance to a mesh is the smallest of the distances to its triangles, so on the
/// free side `d ≥ c` holds exactly when `d_t ≥ c` holds for every triangle `t`. Where the wall
/// is concave (a lumen seen from inside, a crease), the feature settles where two or three
/// faces hold it; one constraint on the closest triangle alone switches between them from one
/// iterate to the next and never settles. With the faces as constraints of their own, each is
/// smooth and the solver can hold all of them.
///
/// Each is exact in closed form (no GJK): with `n` the face's unit normal towards the free
/// side, `x*` the feature's support point along `−n` and `s = n · (x* − a)` its height over
/// the plane, the projection `y = x* − s n` lying in the triangle makes `s` the distance from
/// the convex feature to the triangle (no point of the feature is lower than `x*`, and `y` is
/// a point of the triangle at that height), with witnesses `x*` and `y`.
///
/// A face whose `y` lies beyond its triangle keeps its plane as a constraint when every edge
/// `y` lies beyond is concave seen from the free side ([`face_side`]) and `y` lies in the
/// obstacle region (parry's pseudo-normal test): near a concave edge the free side is the
/// intersection of its two faces' half-spaces, so the plane beyond the edge runs behind the
/// neighbour's face and cuts off no free space there, and `y` behind the wall says it still
/// does where the feature is (past a convex edge further on the plane would come out into the
/// free side: such a face is left out). Its `s` is then the height over that plane, at most
/// the distance to the triangle: the constraint holds the feature no closer than the wall
/// does. Why: a feature pressing on a concave faceted wall touches two or three faces at
/// points apart on it (a disk's rim meets neighbouring faces at support points ~0.5 mm
/// apart), so one face's `y` lies over its neighbour until the feature has slid across; with
/// the inside test alone the faces entered the step one per iteration and alternated (the
/// paper's case I in a 100 mm sphere of 100 × 128 quads: 48 iterations, 37 with them).
pub(crate) fn face_contacts(
    gpose: &PPose,
    g: &dyn PShape,
    opose: &PPose,
    mesh: &TriMesh,
    within: f64,
    towards: PVec,
) -> Vec<(u32, super::Witness)> {
    use parry3d::bounding_volume::BoundingVolume;
    let Some(sm) = g.as_support_map() else {
        return vec![];
    };
    let rel = gpose.inv_mul(opose).inverse();
    let reach = g.compute_aabb(&rel).loosened(within);
    let towards = opose.inverse_transform_vector(towards);
    let mut found: Vec<(f64, u32, PVec, PVec, PVec, bool)> = mesh
        .bvh()
        .leaves(|node| node.aabb().intersects(&reach))
        .filter_map(|t| {
            let tri = mesh.triangle(t);
            let n = mesh.triangle_normal(t).filter(|n| n.dot(towards) > 0.5)?;
            let x = sm.support_point(&rel, -n);
            let s = n.dot(x - tri.a);
            if s.is_nan() || s.abs() > within {
                return None;
            }
            let y = x - s * n;
            match face_side(mesh, t, &tri, n, y) {
                Side::Inside => Some((s, t, n, x, y, true)),
                Side::AcrossConcave => Some((s, t, n, x, y, false)),
                Side::Outside => None,
            }
        })
        .collect();
    found.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut normals: Vec<PVec> = vec![];
    let mut out = vec![];
    for (s, t, n, x, y, inside) in found {
        if out.len() == MAX_FACES {
            break;
        }
        if normals.iter().any(|m| n.dot(*m) > 1.0 - 5e-9) {
            continue;
        }
        // Beyond its triangle: kept only behind the wall (asked of the few kept faces only).
        if !inside
            && !mesh
                .project_local_point_and_get_location(y, false)
                .0
                .is_inside
        {
            continue;
        }
        normals.push(n);
        out.push((
            t,
            super::Witness {
                robot: super::nvec(opose.transform_point(x)),
                obstacle: super::nvec(opose.transform_point(y)),
                normal: super::nvec(opose.transform_vector(n)),
                dist: s,
            },
        ));
    }
    out
}

/// Where a point on a face's plane lies against the face ([`face_side`]).
enum Side {
    /// Strictly inside the triangle.
    Inside,
    /// Beyond it, across concave edges only.
    AcrossConcave,
    /// Beyond a convex (or flat, or unknown) edge.
    Outside,
}

/// Where `y` (on the plane of triangle `t` = `tri`, unit normal `n` towards the free side)
/// lies against the triangle: inside it (on the inner side of each edge by more than
/// round-off), beyond it across concave edges only, or beyond a convex one.
///
/// An edge `e` (from `p` to `q` in the triangle's winding, the triangle on its left seen from
/// the free side) is concave seen from the free side when the neighbour across it bends
/// towards the free side: `(n × n_b) · e < 0`, `n_b` the neighbour's unit normal. parry's edge
/// pseudo-normal is `m = n + n_b` (the sum of the two faces' normals), so with `m̂ = m / |m|`,
/// `n_b = 2 (m̂ · n) m̂ − n` (the reflection of `n` about `m̂`; `m̂ · n = m̂ · n_b`). A flat
/// edge (`n_b = n`) counts as convex: the plane is the neighbour's own, which stands for it.
fn face_side(mesh: &TriMesh, t: u32, tri: &parry3d::shape::Triangle, n: PVec, y: PVec) -> Side {
    let scale = (tri.b - tri.a).length() + (tri.c - tri.b).length() + (tri.a - tri.c).length();
    let eps = 1e-12 * scale * scale;
    let edges = mesh
        .pseudo_normals_if_oriented()
        .and_then(|pn| pn.edges_pseudo_normal.get(t as usize));
    let mut side = Side::Inside;
    for (e, (p, q)) in [(tri.a, tri.b), (tri.b, tri.c), (tri.c, tri.a)]
        .into_iter()
        .enumerate()
    {
        if n.dot((q - p).cross(y - p)) > eps {
            continue;
        }
        let Some(m) = edges.map(|m| m[e]).filter(|m| m.length() > 0.0) else {
            return Side::Outside;
        };
        let m = m.normalize();
        let nb = 2.0 * m.dot(n) * m - n;
        if n.cross(nb).dot(q - p) >= 0.0 {
            return Side::Outside;
        }
        side = Side::AcrossConcave;
    }
    side
}

#[cfg(test)]
#[path = "solid_tests.rs"]
mod tests;

/// parry's closest contact of feature `g` with the triangles of `mesh` within `margin`
/// (what `parry3d::query::contact` against the whole mesh answers: the smallest distance; of
/// triangles at exactly that distance, the first one reached), found by branch and bound over
/// parry's tree: nodes are visited nearer child first ([`parry3d::partitioning::Bvh::find_best`])
/// and only while their lower bound — the larger of the gap between their box and the
/// feature's and, when apart, the gap from their bounding ball — is below the best distance
/// found so far; a triangle there gets a lower bound too (the gap between the feature's extent
/// along the triangle's normal and the triangle's plane, and its bounding ball's gap), and is
/// queried by parry's triangle query only when that bound is below the best. Every triangle
/// closer than the answer has bounds below it all the way down, so it is queried: the answer
/// is the closest triangle's, exactly. Near the wall the best distance is small at once and
/// only the triangles under the feature are reached.
///
/// `hint`, a triangle near the answer (the one a nearby state found), starts the search from
/// its own distance `p` instead of the margin: the search then admits only costs up to
/// `p` (the next float above it, so a triangle tied with it is still found), which every
/// triangle the cold search could return meets. Nodes are visited in the same order (their
/// order does not depend on the best so far, only whether they are pruned does), and a
/// node or triangle pruned here holds nothing at or below `p`, so the same triangle is
/// reached first among those of the smallest distance: the answer is the cold search's, to
/// the bit, and far fewer nodes are opened. Any triangle (or none, or an index out of range)
/// may be given. The contact's `subshape2` is the triangle.
pub(crate) fn closest_triangle(
    gpose: &PPose,
    g: &dyn PShape,
    opose: &PPose,
    mesh: &TriMesh,
    margin: f64,
    hint: Option<u32>,
) -> Option<PContact> {
    use parry3d::partitioning::BvhLeafCost;
    use parry3d::query::{DefaultQueryDispatcher, QueryDispatcher};
    /// A triangle's contact, ranked by its distance.
    struct Found(PContact);
    impl BvhLeafCost for Found {
        fn cost(&self) -> f64 {
            self.0.dist
        }
    }
    let sm = g.as_support_map()?;
    // The feature in the mesh's frame, composed as parry's composite query composes it, and
    // each triangle queried as it queries it (triangle first), so the answers agree.
    let rel = gpose.inv_mul(opose).inverse();
    let fbox = g.compute_aabb(&rel);
    // Round-off of parry's own distance: a bound this close to the best is not trusted.
    let slack = |lb: f64| lb - 1e-9 * (1.0 + lb.abs());
    // A capsule's or a segment's axis (in the mesh's frame) and radius: its distance to a point
    // and its extent along a direction in closed form (parry's answers, to round-off), as the
    // bounds below ask them hundreds of times per query.
    let core = g
        .as_capsule()
        .map(|c| (c.segment.a, c.segment.b, c.radius))
        .or_else(|| g.as_segment().map(|s| (s.a, s.b, 0.0)))
        .map(|(a, b, r)| (rel.transform_point(a), rel.transform_point(b), r));
    // The feature's distance to the point `c` (0 inside it).
    let to_point = |c: PVec| match core {
        Some((a, b, r)) => {
            let ab = b - a;
            let l2 = ab.length_squared();
            let t = if l2 > 0.0 {
                ((c - a).dot(ab) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            ((c - (a + t * ab)).length() - r).max(0.0)
        }
        None => g.distance_to_point(&rel, c, true),
    };
    // The feature's extent `(min, max)` of `n · x` along the unit vector `n`.
    let extent = |n: PVec| match core {
        Some((a, b, r)) => {
            let (x, y) = (n.dot(a), n.dot(b));
            (x.min(y) - r, x.max(y) + r)
        }
        None => (
            n.dot(sm.support_point(&rel, -n)),
            n.dot(sm.support_point(&rel, n)),
        ),
    };
    // The ball `(c, radius)`'s gap from the feature, when the two are apart (a lower bound on
    // the distance of anything in it); `f64::MIN` (no bound) when they meet.
    let ball = |c: PVec, radius: f64| {
        let gap = to_point(c) - radius;
        if gap < 0.0 {
            f64::MIN
        } else {
            gap
        }
    };
    let node_bound = |node: &parry3d::partitioning::BvhNode, best: f64| {
        let b = node.aabb();
        let gap = (b.mins - fbox.maxs)
            .max(fbox.mins - b.maxs)
            .max(PVec::ZERO)
            .length();
        // (Boxes apart: everything in the node is at least `gap` away.)
        if gap > 0.0 && slack(gap) >= best {
            return f64::MAX;
        }
        // Boxes that meet bound nothing below (a triangle across the feature has a negative
        // distance); the ball does when it is apart.
        let ball = ball(b.center(), b.half_extents().length());
        if gap > 0.0 {
            slack(gap.max(ball))
        } else {
            slack(ball)
        }
    };
    let leaf = |t: u32, best: f64| {
        let tri = mesh.triangle(t);
        let c = (tri.a + tri.b + tri.c) / 3.0;
        let radius = [tri.a, tri.b, tri.c]
            .iter()
            .map(|v| (*v - c).length())
            .fold(0.0, f64::max);
        let mut lb = ball(c, radius);
        if let Some(n) = tri.normal() {
            let p = n.dot(tri.a);
            let (lo, hi) = extent(n);
            lb = lb.max(lo - p).max(p - hi);
        }
        if slack(lb) >= best {
            return None;
        }
        match DefaultQueryDispatcher.contact(&rel, &tri, g, margin) {
            Ok(Some(ct)) => Some(Found(ct)),
            _ => None,
        }
    };
    // Every contact parry returns is within `margin`; the search admits exactly those.
    let limit = margin + 1e-12 * (1.0 + margin.abs());
    let start = hint
        .filter(|t| (*t as usize) < mesh.indices().len())
        .and_then(|t| leaf(t, limit))
        .map_or(limit, |Found(ct)| limit.min(ct.dist.next_up()));
    let (t, Found(ct)) = mesh.bvh().find_best(start, node_bound, leaf)?;
    let mut ct = ct;
    ct.subshape1 = t;
    let mut ct = ct.flipped();
    ct.transform_by_mut(gpose, opose);
    Some(ct)
}
