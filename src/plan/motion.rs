//! How far the robot's features can move along one sub-interval of an edge, for a robot
//! deployed through a port: the bound [`super::edge`] certifies clearances with, split into a
//! part that holds under the Lipschitz estimate and a part that holds exactly.
//!
//! # The bound
//!
//! Along an edge the actuation `x = [u, d, ψ]` moves on a straight line, so the rotation
//! `ψ(t)` is linear in the parameter `t`. Every shape is placed by `T_port · Rz(ψ)`
//! ([`crate::method`]'s port), so a feature point is `p(t) = Q(ψ(t)) q(t)` with `Q(ψ)` the
//! turn by `ψ` about the port axis and `q(t) = Q(−ψ(t)) p(t)` the *de-rotated* shape. For a
//! sub-interval with end shapes `a` (rotation `ψ_a`) and `b` (`ψ_b`), a point's distance
//! from its place in `a` is
//!
//! ```text
//! |Q(ψ(t)) q(t) − Q(ψ_a) q_a| ≤ |q(t) − q_a| + |(Q(ψ(t)) − Q(ψ_a)) q_a|
//!                             ≤ |q(t) − q_a| + r⊥(q_a) |ψ(t) − ψ_a|
//! ```
//!
//! (a turn by `α` moves a point at distance `r⊥` from the axis by the chord `2 r⊥ sin(α/2) ≤
//! r⊥ α`), and likewise from its place in `b`. Summed, with `|ψ(t) − ψ_a| + |ψ_b − ψ(t)| =
//! |ψ_b − ψ_a|` on a straight edge:
//!
//! ```text
//! δ_a(t) + δ_b(t) ≤ κ D_q + R |ψ_b − ψ_a|
//! ```
//!
//! where `D_q` bounds the motion between the de-rotated end shapes `q_a`, `q_b` (the motion
//! bound of [`crate::reach::motion_bound`], with `b` turned back to `ψ_a` and the backbone
//! matched by arc as below), `κ` is the Lipschitz factor [`super::edge::KAPPA`] applied to
//! that part only, and `R` is the largest distance of any feature point of either end shape
//! from the port axis (disks: centre plus `ρ = √(r² + (t/2)²)`; segments and capsules: their
//! farther end, distance to a line being convex). **The rotation's part is exact:** without
//! loads the de-rotated shape does not depend on `ψ` (a rigid turn about the port axis), so an
//! edge along `ψ` alone has `D_q = 0` and its bound `(c_a + c_b − R |Δψ|)/2` holds with no
//! estimate at all. With gravity or a tip load the shape in the port frame changes with `ψ`
//! and that change is in `D_q`.
//!
//! # Insertion: matching the backbone by arc, and a turning cap
//!
//! Inserting changes how the backbone is sampled (the part behind the port is one straight
//! piece; the part beyond is sampled by the method), so the two end shapes' backbone samples
//! are not the same material points. Both polylines are matched by arc: each is parametrized
//! by its cumulative length over its total, `τ ∈ [0, 1]`, and their distance is taken at every
//! breakpoint of either (the difference of two polylines on the union of their breakpoints is
//! linear on each piece, and a norm of a linear function is largest at a piece's ends, so this
//! is the largest distance over all `τ`). Disks are material points and are matched by index.
//!
//! Why `κ = 2` also covers insertion: a material point beyond the port moves, as `d` grows,
//! along the robot's own backbone (the robot slides out of the port and follows its shape,
//! changed slowly by the longer bending part); over an insertion change `|Δd|` its path turns
//! by at most `k_max |Δd|`, `k_max` the largest curvature of the end shapes. A path whose
//! tangent stays within an angle `α` of its first tangent has length at most `chord / cos α`,
//! so with `k_max |Δd| ≤ π/3` ([`MAX_TURN`]) the path is at most twice its chord, and the chord
//! is at most `D_q`: `δ_a + δ_b ≤ 2 D_q`. A sub-interval that inserts further than that is
//! not certified whatever its clearances and is bisected ([`Motion::certifiable`]). Behind the
//! port the robot only translates along the axis (`δ_a + δ_b` equals the chord: `κ = 1`
//! would do). The cables' part stays an estimate, as without a port; the tests re-check
//! every planned path on finer interpolations by independent solves.
//!
//! `k_max` is measured from consecutive disks, `θ_k / (s_{k+1} − s_k)` with `θ_k` the angle
//! between their frames.
//!
//! # Material crossing the port: a one-sided bound
//!
//! A clearance counts only what lies beyond the port (what is inside it meets nothing,
//! [`crate::reach::clearance`]). When the insertion changes along a sub-interval, the material
//! that crosses the port lies beyond it at the deeper end only, so its distance at the
//! shallower end was never measured: the two-sided `max(c_a − δ_a, c_b − δ_b)` has only the
//! deeper end's term, and with `δ_a + δ_b ≤ κ D_q + R |Δψ|` each of `δ_a`, `δ_b` is at most
//! that sum. A sub-interval whose insertion changes is therefore certified by
//!
//! ```text
//! min((c_a + c_b − κ D_q − R |Δψ|)/2, c_deep − κ D_q − R |Δψ|)
//! ```
//!
//! with `c_deep` the clearance of the end inserted further ([`Motion::certified`]). Without
//! this, an end with the whole robot inside the port (clearance `+∞`: nothing beyond) certified
//! any edge out of it: a soft rod retracted fully while bending was certified 6.6 mm clear on
//! an edge along which independent solves measure 6.46 mm
//! (`plan_tension::an_edge_out_of_the_port_is_certified_by_its_deeper_end`).

use crate::model::robot::Robot;
use crate::numeric::so3::angle_between;
use crate::shape::Shape;
use nalgebra::{Isometry3, Matrix3, Vector3};

/// Largest turn \[rad\] of the backbone over the insertion change of one certified
/// sub-interval (module docs: `1/cos(π/3) = 2 = κ`).
pub const MAX_TURN: f64 = std::f64::consts::FRAC_PI_3;

/// The motion between the end shapes of one sub-interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// Bound on the motion that holds under the Lipschitz estimate (multiplied by `κ`) \[m\].
    pub estimated: f64,
    /// Bound on the motion that holds exactly (the rotation's: `R |Δψ|`) \[m\].
    pub exact: f64,
    /// False when the sub-interval inserts further than [`MAX_TURN`] allows.
    pub certifiable: bool,
    /// The insertion of the second end less the first's \[m\] (0 without a port): material
    /// crosses the port when it is not 0 (module docs, "Material crossing the port").
    pub insertion_change: f64,
}

impl Motion {
    /// The clearance certified between ends of clearance `c0`, `c1` with Lipschitz factor
    /// `kappa` (`−∞` when not [`Motion::certifiable`]); when the insertion changes, also at
    /// most the deeper end's clearance less the whole motion (module docs, "Material crossing
    /// the port").
    pub fn certified(&self, c0: f64, c1: f64, kappa: f64) -> f64 {
        if !self.certifiable {
            return f64::NEG_INFINITY;
        }
        let travel = kappa * self.estimated + self.exact;
        let both = 0.5 * (c0 + c1 - travel);
        if self.insertion_change == 0.0 {
            return both;
        }
        let deep = if self.insertion_change > 0.0 { c1 } else { c0 };
        both.min(deep - travel)
    }
}

/// The motion between shapes `a` and `b` of `robot` (module docs); without a port, the
/// plain [`crate::reach::motion_bound`], all of it estimated.
pub fn motion(robot: &Robot, a: &Shape, b: &Shape) -> Motion {
    let (Some(pa), Some(pb)) = (&a.port, &b.port) else {
        return Motion {
            estimated: crate::reach::motion_bound(robot, a, b),
            exact: 0.0,
            certifiable: true,
            insertion_change: 0.0,
        };
    };
    let rho = robot.disk_radius.hypot(robot.disk_thickness / 2.0);
    // Turn b back to a's rotation about the port axis: Q = T Rz(ψa − ψb) T⁻¹.
    let t = pa.pose;
    let q: Isometry3<f64> =
        t * Isometry3::rotation(Vector3::z() * (pa.rotation - pb.rotation)) * t.inverse();
    let qr: Matrix3<f64> = q.rotation.to_rotation_matrix().into_inner();
    let disks = a.disks.iter().zip(&b.disks).map(|(x, y)| {
        let yp = q.transform_point(&y.position.into()).coords;
        (yp - x.position).norm() + rho * angle_between(&x.rotation, &(qr * y.rotation))
    });
    let bb_b: Vec<Vector3<f64>> = b
        .backbone
        .iter()
        .map(|p| q.transform_point(&(*p).into()).coords)
        .collect();
    let estimated = disks
        .chain(std::iter::once(by_arc(&a.backbone, &bb_b)))
        .fold(0.0, f64::max);
    let inv = t.inverse();
    let radial = |p: &Vector3<f64>| {
        let l = inv.transform_point(&(*p).into());
        l.x.hypot(l.y)
    };
    let r = [a, b]
        .iter()
        .flat_map(|s| {
            s.disks
                .iter()
                .map(|f| radial(&f.position) + rho)
                .chain(s.backbone.iter().map(radial))
        })
        .fold(0.0, f64::max);
    let k_max = curvature(robot, a).max(curvature(robot, b));
    Motion {
        estimated,
        exact: r * (pb.rotation - pa.rotation).abs(),
        certifiable: k_max * (pb.insertion - pa.insertion).abs() <= MAX_TURN,
        insertion_change: pb.insertion - pa.insertion,
    }
}

/// The largest curvature between consecutive disks \[1/m\] (module docs).
fn curvature(robot: &Robot, s: &Shape) -> f64 {
    s.disks
        .windows(2)
        .zip(robot.disk_s.windows(2))
        .map(|(f, ds)| {
            let h = (ds[1] - ds[0]).abs();
            if h > 0.0 {
                angle_between(&f[0].rotation, &f[1].rotation) / h
            } else {
                0.0
            }
        })
        .fold(0.0, f64::max)
}

/// Cumulative length of a polyline over its total: its breakpoints in `[0, 1]`.
fn arc_params(p: &[Vector3<f64>]) -> Vec<f64> {
    let mut acc = Vec::with_capacity(p.len());
    let mut s = 0.0;
    acc.push(0.0);
    for w in p.windows(2) {
        s += (w[1] - w[0]).norm();
        acc.push(s);
    }
    if s > 0.0 {
        acc.iter_mut().for_each(|x| *x /= s);
    } else {
        // A polyline of one point: every breakpoint at 0.
        acc.iter_mut().for_each(|x| *x = 0.0);
    }
    acc
}

/// The polyline `p` (breakpoints `tau`) at parameter `x ∈ [0, 1]`.
fn at(p: &[Vector3<f64>], tau: &[f64], x: f64) -> Vector3<f64> {
    let i = tau.partition_point(|t| *t <= x);
    if i == 0 {
        return p[0];
    }
    if i >= p.len() {
        return p[p.len() - 1];
    }
    let (t0, t1) = (tau[i - 1], tau[i]);
    let f = if t1 > t0 { (x - t0) / (t1 - t0) } else { 0.0 };
    p[i - 1] + f * (p[i] - p[i - 1])
}

/// The largest distance between two polylines matched by arc (module docs) \[m\]; 0 when
/// either is empty.
fn by_arc(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return 0.0;
    }
    let (ta, tb) = (arc_params(a), arc_params(b));
    ta.iter()
        .chain(&tb)
        .map(|&x| (at(a, &ta, x) - at(b, &tb, x)).norm())
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Inserting, the deeper end's clearance bounds the certificate: an end with nothing
    /// beyond the port (`+∞`) certifies nothing by itself; without an insertion change the
    /// two-sided mean.
    #[test]
    fn crossing_material_is_bounded_by_the_deeper_end() {
        let m = |dd: f64| Motion {
            estimated: 0.001,
            exact: 0.0005,
            certifiable: true,
            insertion_change: dd,
        };
        let inf = f64::INFINITY;
        let travel = 2.0 * 0.001 + 0.0005;
        let close = |a: f64, b: f64| assert!((a - b).abs() < 1e-15, "{a} vs {b}");
        close(m(0.0).certified(0.010, 0.020, 2.0), 0.5 * (0.030 - travel));
        close(m(-0.1).certified(0.010, inf, 2.0), 0.010 - travel);
        close(m(0.1).certified(inf, 0.010, 2.0), 0.010 - travel);
        close(m(0.1).certified(0.010, 0.020, 2.0), 0.5 * (0.030 - travel));
        assert_eq!(m(-0.1).certified(inf, 0.010, 2.0), inf);
    }

    #[test]
    fn by_arc_is_the_largest_distance_over_a_fine_grid() {
        // Two polylines with different breakpoints: the breakpoint maximum is the grid's.
        let a: Vec<Vector3<f64>> = (0..5)
            .map(|i| Vector3::new(i as f64 * 0.01, (i as f64 * 0.7).sin() * 0.01, 0.0))
            .collect();
        let b: Vec<Vector3<f64>> = (0..8)
            .map(|i| Vector3::new(i as f64 * 0.006, 0.002, (i as f64 * 0.3).cos() * 0.004))
            .collect();
        let (ta, tb) = (arc_params(&a), arc_params(&b));
        let grid = (0..=20000)
            .map(|k| k as f64 / 20000.0)
            .map(|x| (at(&a, &ta, x) - at(&b, &tb, x)).norm())
            .fold(0.0, f64::max);
        let bp = by_arc(&a, &b);
        assert!(bp >= grid - 1e-15, "{bp} < {grid}");
        assert!(bp - grid < 1e-6, "{bp} vs {grid}");
    }
}
