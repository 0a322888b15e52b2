//! A feature's certified interval from a solid's signed-distance grid alone, corner by corner:
//! what a search needs to decide whether a shape keeps a margin, without a triangle.
//!
//! Around a point `p` in a cell with corners `v`, the signed distance `φ` is 1-Lipschitz, so
//! `lo_v − |p − v| ≤ φ(p) ≤ up_v + |p − v|` for each corner (`lo_v`, `up_v` the node's stored
//! bounds, `up_v = lo_v` for an exact node, `lo_v + LOOSE h` for a loose one, plus the `f32`
//! value's rounding), and the best of the eight on each side holds
//! ([`SolidField::point_interval`]). A feature's interval ([`SolidField::feature_interval`])
//! takes points of it:
//!
//! * below: every point of a capsule is within `r` of its axis, and every axis point within
//!   `δ` of a sample (samples `2δ` apart), so `min φ ≥ min_samples lo − δ − r`; a disk by the
//!   square pattern of its mid-plane of [`SolidField::feature_bounds`] (refined);
//! * above: for an axis sample `p` of a capsule the capsule's point `r` towards the surface
//!   point closest to `p` is within `φ(p) − r` of the surface, so the smallest distance of any
//!   point of the capsule is at most `φ(p) − r` when that is positive (and when it is not,
//!   the ball about `p` reaches the surface: some point of the capsule is on it or beyond); a
//!   disk's centre and rim points are points of it.

use super::field::SolidField;
use parry3d::math::{Pose as PPose, Vector as PVec};
use parry3d::shape::Shape as PShape;

impl SolidField {
    /// Lower and upper bounds on the signed distance at `p` (mesh frame), corner by corner
    /// (module docs): each within the distance from `p` to its nearest node of the true value
    /// at exact nodes, never looser than [`SolidField::point_bounds`]' `h √3/2`.
    pub fn point_interval(&self, p: [f64; 3]) -> (f64, f64) {
        let Some((i, _)) = self.cell(p) else {
            return self.point_bounds(p);
        };
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (d, k) in self.corners(i) {
            let r = self.node_distance(p, i, d);
            let v = f64::from(self.lo[k]);
            lo = lo.max(v - r);
            // The f32 value was rounded down by less than one of its units.
            hi = hi.min(v + self.loose_up(k) + v.abs() * f64::from(f32::EPSILON) + r);
        }
        // Round-off of the node's place and of the distance, far below the grid's error.
        let eps = |x: f64| 1e-12 * (1.0 + x.abs());
        (lo - eps(lo), hi + eps(hi))
    }

    /// Bounds on the smallest signed distance of any point of the robot feature `g` at
    /// `gpose` (world) from the surface of this field's mesh at `opose`, from the grid alone
    /// (module docs): below, at most the feature's smallest signed distance `m`; above, a
    /// value `u` with `m ≤ max(u, 0)` (a capsule whose sample is within its radius of the
    /// surface has a point on it or beyond). A capsule's axis is sampled at most `h/2` apart.
    /// `None` for a shape this does not know.
    pub(crate) fn feature_interval(
        &self,
        g: &dyn PShape,
        gpose: &PPose,
        opose: &PPose,
    ) -> Option<(f64, f64)> {
        let local = |p: PVec| {
            let q = opose.inverse_transform_point(gpose.transform_point(p));
            [q.x, q.y, q.z]
        };
        if let Some(c) = g.as_capsule() {
            let (a, b) = (local(c.segment.a), local(c.segment.b));
            return Some(self.segment_interval(a, b, c.radius));
        }
        if let Some(s) = g.as_segment() {
            return Some(self.segment_interval(local(s.a), local(s.b), 0.0));
        }
        if let Some(c) = g.as_ball() {
            let (lo, hi) = self.point_interval(local(PVec::ZERO));
            return Some((lo - c.radius, hi - c.radius));
        }
        let cyl = g.as_cylinder()?;
        let r = cyl.radius;
        let (lo, _) = self.feature_bounds(g, gpose, opose, true)?;
        let rim = |a: f64| local(PVec::new(r * a.cos(), 0.0, r * a.sin()));
        let hi = (0..8)
            .map(|k| {
                self.point_interval(rim(k as f64 * std::f64::consts::FRAC_PI_4))
                    .1
            })
            .fold(self.point_interval(local(PVec::ZERO)).1, f64::min);
        Some((lo, hi))
    }

    /// [`SolidField::feature_interval`] of the capsule of radius `r` about `a`–`b` (mesh
    /// frame).
    fn segment_interval(&self, a: [f64; 3], b: [f64; 3], r: f64) -> (f64, f64) {
        let (lo, hi, half) = self.sweep(a, b, 2.0, 256.0, |p| self.point_interval(p));
        (lo - half - r, hi - r)
    }
}

#[cfg(test)]
#[path = "field_interval_tests.rs"]
mod tests;
