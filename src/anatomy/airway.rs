//! The branching tree of a generated airway: each branch a curved centreline with one radius.
//!
//! The laws, from the airway literature:
//! - **Diameters** halve in cross-section area... more precisely, a parent's diameter splits
//!   between its two children by Murray's law `d₀³ = d₁³ + d₂³` (Murray 1926; the basis of
//!   Kitaoka, Takaki & Suki, J. Appl. Physiol. 87(6), 1999). With equal flow to both children
//!   (`asymmetry = 0`) this is Weibel's regular dichotomy, `dₙ = d₀ · 2^(−n/3)` (Weibel,
//!   *Morphometry of the Human Lung*, 1963); an `asymmetry` `a` sends the fraction `½ + a` of
//!   the flow to the major child, `d_major = d₀ (½ + a)^(1/3)`, `d_minor = d₀ (½ − a)^(1/3)`,
//!   the flow-split form of Horsfield's asymmetric branching (Horsfield et al., J. Appl.
//!   Physiol. 31(2), 1971; Kitaoka 1999).
//! - **Lengths**: a branch is about three diameters long (`L/d ≈ 3`, Weibel 1963, Table of
//!   generations 1–16), drawn within ±20 %; the trachea is 120 mm long and 18 mm wide (Weibel).
//! - **Branching angles** minimise the work of the flow (Murray 1926, as used by Kitaoka 1999):
//!   `cos θ₁ = (d₀⁴ + d₁⁴ − d₂⁴) / (2 d₀² d₁²)`, so 37.5° for each child of a symmetric
//!   bifurcation; the plane of each bifurcation is turned about 90° (±30°, drawn) from its
//!   parent's (Weibel 1963; Horsfield 1971).
//! - **Curvature**: each child leaves along the bisector of its parent's and its own direction
//!   and bends into its own direction (a quadratic Bézier centreline with a drawn sideways
//!   offset of up to 10 % of its length), so the tubes are curved, not straight cylinders.
//!
//! A child that would come within a wall's thickness of a branch other than its parent and
//! sibling is redrawn in other planes (12 tries), and left out with its subtree when none
//! fits: real airways fill space without crossing (Kitaoka 1999 do the same by rules).

use nalgebra::{Unit, UnitQuaternion, Vector3};
use rand_core::{Rng, SeedableRng};
use rand_xorshift::XorShiftRng;

/// Points sampled along each branch's centreline.
pub const CENTRELINE_POINTS: usize = 9;

/// What to generate.
#[derive(Debug, Clone, PartialEq)]
pub struct AirwayOptions {
    /// Seed of every random choice: the same seed gives the same airway, bit for bit.
    pub seed: u64,
    /// Generations below the trachea (generation 0): 5 (the default) gives up to 63 branches.
    pub generations: u32,
    /// Diameter of the trachea \[m\] (Weibel: 0.018).
    pub trachea_diameter: f64,
    /// Length of the trachea \[m\] (Weibel: 0.12).
    pub trachea_length: f64,
    /// Length over diameter of every other branch (Weibel: about 3).
    pub length_ratio: f64,
    /// Flow-split asymmetry `a` in `[0, 0.4]` (0: Weibel's symmetric dichotomy).
    pub asymmetry: f64,
    /// Grid cell of the meshing \[m\]; `None`: a quarter of the smallest diameter.
    pub cell: Option<f64>,
}

impl Default for AirwayOptions {
    fn default() -> Self {
        AirwayOptions {
            seed: 1,
            generations: 5,
            trachea_diameter: 0.018,
            trachea_length: 0.12,
            length_ratio: 3.0,
            asymmetry: 0.0,
            cell: None,
        }
    }
}

/// One tube of the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Branch {
    /// 0 for the trachea, its parent's plus one below.
    pub generation: u32,
    /// Index of the parent branch (`None` for the trachea).
    pub parent: Option<usize>,
    /// Centreline points from the start (the parent's end) to the end \[m\].
    pub centreline: Vec<Vector3<f64>>,
    /// Inner radius of the lumen \[m\].
    pub radius: f64,
}

impl Branch {
    /// The unit direction of the centreline at its end.
    pub fn end_direction(&self) -> Vector3<f64> {
        let n = self.centreline.len();
        (self.centreline[n - 1] - self.centreline[n - 2]).normalize()
    }
    /// The centreline's end \[m\].
    pub fn end(&self) -> Vector3<f64> {
        self.centreline[self.centreline.len() - 1]
    }
    /// Distance from `p` to the centreline polyline \[m\].
    pub fn axis_distance(&self, p: &Vector3<f64>) -> f64 {
        self.centreline
            .windows(2)
            .map(|w| point_segment(p, &w[0], &w[1]))
            .fold(f64::INFINITY, f64::min)
    }
}

/// Distance from `p` to the segment `a`–`b`.
pub fn point_segment(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + t * ab)).norm()
}

/// Smallest distance between two polylines, by sampling each segment of `a` densely against
/// the segments of `b` (accurate to a sixteenth of a segment: enough to keep tubes apart).
fn polyline_gap(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> f64 {
    let mut best = f64::INFINITY;
    for w in a.windows(2) {
        for k in 0..=16 {
            let p = w[0] + (w[1] - w[0]) * (k as f64 / 16.0);
            for v in b.windows(2) {
                best = best.min(point_segment(&p, &v[0], &v[1]));
            }
        }
    }
    best
}

/// Uniform in `[lo, hi)`.
fn uniform(rng: &mut XorShiftRng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * ((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
}

/// A unit vector perpendicular to `t`.
fn perpendicular(t: &Vector3<f64>) -> Vector3<f64> {
    let helper = if t.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    t.cross(&helper).normalize()
}

/// The quadratic Bézier centreline from `p` leaving along `start` and ending at `q`.
fn bezier(p: Vector3<f64>, start: Vector3<f64>, q: Vector3<f64>) -> Vec<Vector3<f64>> {
    let c = p + start * ((q - p).norm() * 0.5);
    (0..CENTRELINE_POINTS)
        .map(|k| {
            let s = k as f64 / (CENTRELINE_POINTS - 1) as f64;
            p * (1.0 - s) * (1.0 - s) + c * (2.0 * s * (1.0 - s)) + q * (s * s)
        })
        .collect()
}

/// Murray's optimal angle of the child of diameter `d1` from its parent `d0` when its
/// sibling has `d2` \[rad\].
pub fn murray_angle(d0: f64, d1: f64, d2: f64) -> f64 {
    ((d0.powi(4) + d1.powi(4) - d2.powi(4)) / (2.0 * d0 * d0 * d1 * d1))
        .clamp(-1.0, 1.0)
        .acos()
}

/// The branches of the airway `opts` describes, the trachea first, parents before children;
/// the trachea starts at the origin and runs along +z. Options are checked by the caller
/// ([`super::generate`]).
pub fn tree(opts: &AirwayOptions) -> Vec<Branch> {
    let mut rng = XorShiftRng::seed_from_u64(opts.seed);
    let d0 = opts.trachea_diameter;
    let end = Vector3::new(0.0, 0.0, opts.trachea_length);
    let side = perpendicular(&Vector3::z()) * uniform(&mut rng, 0.0, 0.03) * opts.trachea_length;
    let mut branches = vec![Branch {
        generation: 0,
        parent: None,
        centreline: bezier(Vector3::zeros(), (end + side).normalize(), end),
        radius: d0 / 2.0,
    }];
    // The reference direction of each branch's bifurcation plane, turned ~90° per generation.
    let mut plane = vec![Vector3::x()];
    let mut k = 0;
    while k < branches.len() {
        if branches[k].generation < opts.generations {
            let (kids, normal) = children(&branches, k, &plane[k], opts, &mut rng);
            for kid in kids.into_iter().flatten() {
                branches.push(kid);
                plane.push(normal);
            }
        }
        k += 1;
    }
    branches
}

/// The two children of branch `k` (either `None` when it does not fit), and the plane
/// normal they were placed with.
fn children(
    branches: &[Branch],
    k: usize,
    parent_plane: &Vector3<f64>,
    opts: &AirwayOptions,
    rng: &mut XorShiftRng,
) -> ([Option<Branch>; 2], Vector3<f64>) {
    let parent = &branches[k];
    let t = parent.end_direction();
    let dp = 2.0 * parent.radius;
    let q = 0.5 + opts.asymmetry;
    let (d1, d2) = (dp * q.cbrt(), dp * (1.0 - q).cbrt());
    let (a1, a2) = (murray_angle(dp, d1, d2), murray_angle(dp, d2, d1));
    let mut best: Option<(f64, [Branch; 2], Vector3<f64>)> = None;
    for _ in 0..12 {
        let turn = uniform(rng, 60f64.to_radians(), 120f64.to_radians());
        let rot = UnitQuaternion::from_axis_angle(&Unit::new_normalize(t), turn);
        // The in-plane direction: the parent's plane reference turned about the axis.
        let e = rot * (parent_plane - t * t.dot(parent_plane));
        let e = if e.norm() > 1e-9 {
            e.normalize()
        } else {
            perpendicular(&t)
        };
        let kids = [(d1, a1, 1.0), (d2, a2, -1.0)].map(|(d, angle, sign)| {
            let dir = t * angle.cos() + e * (sign * angle.sin());
            let len = opts.length_ratio * d * uniform(rng, 0.8, 1.2);
            let off = perpendicular(&dir) * (len * uniform(rng, -0.1, 0.1));
            let q = parent.end() + dir * len + off;
            Branch {
                generation: parent.generation + 1,
                parent: Some(k),
                centreline: bezier(parent.end(), (t + dir).normalize(), q),
                radius: d / 2.0,
            }
        });
        let gap = kids
            .iter()
            .map(|kid| clearance(branches, k, kid))
            .fold(f64::INFINITY, f64::min);
        if best.as_ref().is_none_or(|b| gap > b.0) {
            best = Some((gap, kids, e));
        }
        if gap > 0.0 {
            break;
        }
    }
    let Some((_, kids, e)) = best else {
        return ([None, None], *parent_plane);
    };
    let normal = t.cross(&e);
    let keep = kids.map(|kid| (clearance(branches, k, &kid) > 0.0).then_some(kid));
    (keep, normal)
}

/// How far `kid` (a child of branch `k`) keeps from every branch but its parent and its
/// sibling, beyond both walls and a wall's thickness (a third of the smaller radius) \[m\].
///
/// The smallest of the branches' values, by branch and bound: a branch whose centreline's
/// bounding ball is farther than the smallest value yet (every sampled gap is at least the
/// distance between the balls, less a round-off margin) cannot lower it and is not sampled —
/// the same minimum as sampling every branch, bit for bit; without it the pairs' sampling
/// (all pairs, up to twelve tries per child) ran past five minutes at 12 generations.
fn clearance(branches: &[Branch], k: usize, kid: &Branch) -> f64 {
    let (kc, kr) = bounding_ball(&kid.centreline);
    let mut best = f64::INFINITY;
    for (j, b) in branches.iter().enumerate() {
        if j == k || b.parent == Some(k) {
            continue;
        }
        let wall = kid.radius.min(b.radius) / 3.0;
        let tubes = kid.radius + b.radius + wall;
        let (bc, br) = bounding_ball(&b.centreline);
        let below = (kc - bc).norm() - kr - br - tubes;
        if below - 1e-9 * (1.0 + below.abs()) > best {
            continue;
        }
        let gap = polyline_gap(&kid.centreline, &b.centreline) - kid.radius - b.radius - wall;
        best = best.min(gap);
    }
    best
}

/// A ball holding every point of `line` (so every segment): the mean point, the farthest
/// point's distance.
fn bounding_ball(line: &[Vector3<f64>]) -> (Vector3<f64>, f64) {
    let c = line.iter().sum::<Vector3<f64>>() / line.len().max(1) as f64;
    let r = line.iter().map(|p| (p - c).norm()).fold(0.0, f64::max);
    (c, r)
}
