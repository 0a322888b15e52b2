//! A solid mesh's signed-distance grid: bounds on the signed distance anywhere in microseconds,
//! so that exact queries against the triangles are asked only where they can decide something.
//!
//! The grid is built once per mesh ([`SolidField::build`], `field_build.rs`) in the mesh's own
//! frame, over its bounds padded by two cells, with spacing `h` chosen from a node budget
//! ([`nodes_for`]). Each node holds a lower bound on the signed distance to the surface
//! (positive on the free side, in metres, stored as `f32` rounded down) and whether it is
//! exact:
//!
//! * every node within `h` of the surface (and a few more) is projected on the mesh by parry
//!   (exact distance, side by the pseudo-normals): exact;
//! * any other node `v` is farther than `h` from the surface. Let `D` be its distance to the
//!   nearest node within `h` of the surface (a Euclidean distance transform). The surface
//!   point `s` closest to `v` has a cell corner `b` within `h √3/2 < h` of it, so `b` is such a
//!   node and `|v − s| ≥ |v − b| − h √3/2 ≥ D − h √3/2`; and `|v − s| ≤ D + h`. Its side is that
//!   of a neighbour (no surface crosses an edge from a node farther than `h` from it): the sign
//!   spreads from the projected nodes. It stores `max(h, D − h √3/2)` signed as a lower bound,
//!   with the upper bound `LOOSE · h` above it.
//!
//! Between nodes the signed distance `φ` is 1-Lipschitz, so for `x` in a cell with corners `v`
//! and trilinear weights `w_v`: `φ(x) ≥ Σ w_v φ(v) − Σ w_v |x − v| ≥ Σ w_v lo_v − h √3/2`
//! (`Σ w_v |x − v|` is at most `h √3/2` by Jensen), and the same above with the upper bounds.
//! Outside the grid, the distance to the mesh's bounds and to the far corner bound it.
//!
//! A robot feature (a capsule, a segment, a disk) is bounded through points of its core: a
//! segment sampled every `h` (each point within `h/2` of a sample), a disk through its centre
//! and the ball about it (or, refined, a square pattern of points on its mid-plane).

use parry3d::math::{Pose as PPose, Vector as PVec};
use parry3d::shape::Shape as PShape;

/// Upper bound above a loose node's stored lower bound, in cells: `1 + √3/2`.
pub(crate) const LOOSE: f64 = 1.0 + 0.866_025_403_784_438_7;

/// Half the diagonal of a cell, in cells: the interpolation's error bound.
const HALF_DIAG: f64 = 0.866_025_403_784_438_7;

/// The grid nodes for a mesh of `triangles` triangles: 32 per triangle, within
/// `[2¹⁶, 2²³]` (the largest grid is 32 MiB of values).
pub fn nodes_for(triangles: usize) -> usize {
    triangles.saturating_mul(32).clamp(1 << 16, 1 << 23)
}

/// The signed-distance grid of one solid mesh (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SolidField {
    /// The grid's first node (mesh frame) \[m\].
    pub(crate) origin: [f64; 3],
    /// Node spacing \[m\].
    pub(crate) h: f64,
    /// Nodes along each axis (x fastest in `lo`).
    pub(crate) n: [usize; 3],
    /// Lower bound on the signed distance at each node (free side positive) \[m\].
    pub(crate) lo: Vec<f32>,
    /// One bit per node: not exact (its upper bound is `lo + LOOSE h`).
    pub(crate) loose: Vec<u64>,
    /// The mesh's bounds (mesh frame): min, max \[m\].
    pub(crate) bounds: [[f64; 3]; 2],
    /// Whether the space beyond the mesh's bounds is free (an organ) or obstacle (a lumen).
    pub(crate) far_free: bool,
}

impl SolidField {
    /// Lower and upper bounds on the signed distance (free side positive) at `p` (mesh frame).
    pub fn point_bounds(&self, p: [f64; 3]) -> (f64, f64) {
        let Some((i, t)) = self.cell(p) else {
            return self.beyond(p);
        };
        let (mut lo, mut slack) = (0.0, 0.0);
        for (d, k) in self.corners(i) {
            let w = if d[0] == 1 { t[0] } else { 1.0 - t[0] }
                * if d[1] == 1 { t[1] } else { 1.0 - t[1] }
                * if d[2] == 1 { t[2] } else { 1.0 - t[2] };
            let v = f64::from(self.lo[k]);
            lo += w * v;
            // The f32 value was rounded down by less than one of its units.
            slack += w * (self.loose_up(k) + v.abs() * f64::from(f32::EPSILON));
        }
        let e = HALF_DIAG * self.h;
        (lo - e, lo + slack + e)
    }

    /// The cell holding `p` (mesh frame): its first node along each axis and `p`'s place in
    /// it in cells (each in `[0, 1]`); `None` beyond the grid.
    pub(super) fn cell(&self, p: [f64; 3]) -> Option<([usize; 3], [f64; 3])> {
        let mut i = [0usize; 3];
        let mut t = [0.0; 3];
        for a in 0..3 {
            let u = (p[a] - self.origin[a]) / self.h;
            let last = (self.n[a] - 1) as f64;
            if !(0.0..=last).contains(&u) {
                return None;
            }
            i[a] = (u.floor() as usize).min(self.n[a] - 2);
            t[a] = u - i[a] as f64;
        }
        Some((i, t))
    }

    /// The eight corners of the cell whose first node is `i`, by bits (x = 1, y = 2, z = 4):
    /// each one's step from `i` along each axis and its index in `lo`.
    pub(super) fn corners(&self, i: [usize; 3]) -> impl Iterator<Item = ([usize; 3], usize)> {
        let (sy, sz) = (self.n[0], self.n[0] * self.n[1]);
        let base = i[0] + i[1] * sy + i[2] * sz;
        (0..8).map(move |c| {
            let d = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
            (d, base + d[0] + d[1] * sy + d[2] * sz)
        })
    }

    /// The distance from `p` (mesh frame) to the node `i + d`.
    pub(super) fn node_distance(&self, p: [f64; 3], i: [usize; 3], d: [usize; 3]) -> f64 {
        let mut r2 = 0.0;
        for a in 0..3 {
            let x = p[a] - (self.origin[a] + (i[a] + d[a]) as f64 * self.h);
            r2 += x * x;
        }
        r2.sqrt()
    }

    /// How far above its stored lower bound node `k`'s true value may be, beside the `f32`
    /// value's rounding: `LOOSE h` for a loose node, 0 for an exact one.
    pub(super) fn loose_up(&self, k: usize) -> f64 {
        if self.loose[k / 64] >> (k % 64) & 1 == 1 {
            LOOSE * self.h
        } else {
            0.0
        }
    }

    /// Bounds beyond the grid: the distance to the mesh's bounds below, to their far corner
    /// above, on the far side's sign.
    fn beyond(&self, p: [f64; 3]) -> (f64, f64) {
        let (mut near, mut far) = (0.0f64, 0.0f64);
        for ((x, lo), hi) in p.iter().zip(self.bounds[0]).zip(self.bounds[1]) {
            let g = (lo - x).max(x - hi).max(0.0);
            near += g * g;
            let f = (x - lo).abs().max((x - hi).abs());
            far += f * f;
        }
        let (near, far) = (near.sqrt(), far.sqrt());
        if self.far_free {
            (near, far)
        } else {
            (-far, -near)
        }
    }

    /// Bounds on the signed distance of the robot feature `g` at `gpose` (world) from the
    /// surface of this field's mesh at `opose`: below, the smallest signed distance of any
    /// point of the feature (its clearance when on the free side); above, that of some point
    /// of it. `refine` samples a disk's mid-plane instead of bounding it by its ball. `None`
    /// for a shape this does not know (a caller then queries exactly).
    pub(crate) fn feature_bounds(
        &self,
        g: &dyn PShape,
        gpose: &PPose,
        opose: &PPose,
        refine: bool,
    ) -> Option<(f64, f64)> {
        let local = |p: PVec| {
            let q = opose.inverse_transform_point(gpose.transform_point(p));
            [q.x, q.y, q.z]
        };
        let segment = |a, b, r| {
            let (lo, hi) = self.segment(a, b, r);
            if refine {
                (lo.max(self.segment_below(a, b, r)), hi)
            } else {
                (lo, hi)
            }
        };
        if let Some(c) = g.as_capsule() {
            return Some(segment(local(c.segment.a), local(c.segment.b), c.radius));
        }
        if let Some(s) = g.as_segment() {
            return Some(segment(local(s.a), local(s.b), 0.0));
        }
        if let Some(c) = g.as_ball() {
            let (lo, hi) = self.point_bounds(local(PVec::ZERO));
            return Some((lo - c.radius, hi - c.radius));
        }
        let cyl = g.as_cylinder()?;
        let (r, hh) = (cyl.radius, cyl.half_height);
        let c = local(PVec::ZERO);
        let (lo, hi) = self.point_bounds(c);
        // Points of the disk: its centre and eight points of its rim.
        let rim = |a: f64| local(PVec::new(r * a.cos(), 0.0, r * a.sin()));
        let hi = (0..8)
            .map(|k| {
                self.point_bounds(rim(k as f64 * std::f64::consts::FRAC_PI_4))
                    .1
            })
            .fold(hi, f64::min);
        if !refine {
            return Some((lo - r.hypot(hh), hi));
        }
        // A square pattern of spacing `s` on the mid-plane covering the disk: every point of
        // the disk within `s/√2` of one in-plane, `√(s²/2 + hh²)` of one in space.
        let m = (r / self.h).ceil().clamp(1.0, 8.0);
        let s = r / m;
        let cover = (0.5 * s * s + hh * hh).sqrt();
        let mut low = f64::INFINITY;
        let m = m as i32;
        for i in -m..=m {
            for j in -m..=m {
                let (x, z) = (f64::from(i) * s, f64::from(j) * s);
                if x.hypot(z) > r + s {
                    continue;
                }
                low = low.min(self.point_bounds(local(PVec::new(x, 0.0, z))).0);
            }
        }
        Some(((low - cover).max(lo - r.hypot(hh)), hi))
    }

    /// A lower bound on the signed distance at `p` (mesh frame) from the cell's corners one by
    /// one: `φ(p) ≥ lo_v − |p − v|` for each (1-Lipschitz), the largest of the eight. It is at
    /// least [`SolidField::point_bounds`]' lower bound (`max ≥ Σ w_v (lo_v − |p − v|)`, and
    /// `Σ w_v |p − v| ≤ h √3/2`), and much closer to the truth near a node.
    pub fn point_below(&self, p: [f64; 3]) -> f64 {
        let Some((i, _)) = self.cell(p) else {
            return self.beyond(p).0;
        };
        let mut best = f64::NEG_INFINITY;
        for (d, k) in self.corners(i) {
            best = best.max(f64::from(self.lo[k]) - self.node_distance(p, i, d));
        }
        // Round-off of the node's place and of the distance, far below the grid's error.
        best - 1e-12 * (1.0 + best.abs())
    }

    /// A lower bound for the capsule of radius `r` about the segment `a`–`b` (mesh frame) from
    /// [`SolidField::point_below`] at samples a quarter cell apart (each point of the segment
    /// within an eighth of a cell of one).
    fn segment_below(&self, a: [f64; 3], b: [f64; 3], r: f64) -> f64 {
        let (lo, _, half) = self.sweep(a, b, 4.0, 256.0, |p| (self.point_below(p), f64::INFINITY));
        lo - half - r
    }

    /// Bounds for the capsule of radius `r` about the segment `a`–`b` (mesh frame).
    fn segment(&self, a: [f64; 3], b: [f64; 3], r: f64) -> (f64, f64) {
        let (lo, hi, half) = self.sweep(a, b, 1.0, 64.0, |p| self.point_bounds(p));
        (lo - half - r, hi - r)
    }

    /// The smallest of `point`'s lower and of its upper values at evenly spaced samples of the
    /// segment `a`–`b` (mesh frame), `per_cell` samples a cell apart (between 1 and `cap`
    /// steps, ends included), and half the spacing: every point of the segment lies within it
    /// of a sample.
    pub(super) fn sweep(
        &self,
        a: [f64; 3],
        b: [f64; 3],
        per_cell: f64,
        cap: f64,
        point: impl Fn([f64; 3]) -> (f64, f64),
    ) -> (f64, f64, f64) {
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let steps = (per_cell * len / self.h).ceil().clamp(1.0, cap);
        let half = 0.5 * len / steps;
        let steps = steps as usize;
        let (mut lo, mut hi) = (f64::INFINITY, f64::INFINITY);
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let p = [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]];
            let (l, u) = point(p);
            lo = lo.min(l);
            hi = hi.min(u);
        }
        (lo, hi, half)
    }
}

#[cfg(test)]
#[path = "field_tests.rs"]
pub(crate) mod tests;
