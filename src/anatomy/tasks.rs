//! Tasks in a generated airway: where a port goes (the trachea's entrance), points of the lumen
//! at a chosen generation, and which branch a point is in — each point checked inside by the
//! triangles themselves (ray parity), not by the tree that made them.

use super::{Airway, Branch};
use nalgebra::Vector3;
use rand_core::{Rng, SeedableRng};
use rand_xorshift::XorShiftRng;

/// A point of the lumen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LumenPoint {
    /// Where \[m\].
    pub point: Vector3<f64>,
    /// The branch it was drawn in.
    pub branch: usize,
    /// That branch's generation.
    pub generation: u32,
}

/// The port at the trachea's entrance: a position on the trachea's axis `depth` \[m\] in from
/// its start, and the axis (the trachea's start direction), so a robot inserted through it
/// runs down the trachea.
pub fn entrance(airway: &Airway, depth: f64) -> (Vector3<f64>, Vector3<f64>) {
    let c = &airway.branches[0].centreline;
    let axis = (c[1] - c[0]).normalize();
    (c[0] + axis * depth, axis)
}

/// The deepest branch whose tube (within its radius of its centreline) holds `p`.
pub fn branch_of(airway: &Airway, p: &Vector3<f64>) -> Option<usize> {
    airway
        .branches
        .iter()
        .enumerate()
        .filter(|(_, b)| b.axis_distance(p) < b.radius)
        .max_by_key(|(_, b)| b.generation)
        .map(|(k, _)| k)
}

/// Whether `p` is inside the closed mesh: the parity of the triangles a ray from `p` crosses
/// (along a fixed, irrational direction, so it meets no edge of a grid-made mesh exactly).
pub fn inside_mesh(vertices: &[Vector3<f64>], triangles: &[[u32; 3]], p: &Vector3<f64>) -> bool {
    let dir = Vector3::new(0.5773, 0.5791, 0.5755).normalize();
    let mut crossings = 0usize;
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        // Möller–Trumbore.
        let (e1, e2) = (b - a, c - a);
        let h = dir.cross(&e2);
        let det = e1.dot(&h);
        if det.abs() < 1e-300 {
            continue;
        }
        let s = p - a;
        let u = s.dot(&h) / det;
        if !(0.0..=1.0).contains(&u) {
            continue;
        }
        let q = s.cross(&e1);
        let v = dir.dot(&q) / det;
        if v < 0.0 || u + v > 1.0 {
            continue;
        }
        if e2.dot(&q) / det > 0.0 {
            crossings += 1;
        }
    }
    crossings % 2 == 1
}

/// `count` points of the lumen in branches of generation `generation`, drawn from `seed`:
/// along the middle 60 % of a branch, at most half its radius from the centreline, and inside
/// the mesh by [`inside_mesh`] (a draw outside is dropped; at most `4 · count` draws). Empty
/// when the airway has no such generation.
pub fn lumen_points(airway: &Airway, generation: u32, count: usize, seed: u64) -> Vec<LumenPoint> {
    let pool: Vec<(usize, &Branch)> = airway
        .branches
        .iter()
        .enumerate()
        .filter(|(_, b)| b.generation == generation)
        .collect();
    let mut rng = XorShiftRng::seed_from_u64(seed);
    let mut u = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let mut out = vec![];
    if pool.is_empty() {
        return out;
    }
    for _ in 0..4 * count {
        if out.len() == count {
            break;
        }
        let (k, b) = pool[((u() * pool.len() as f64) as usize).min(pool.len() - 1)];
        let s = 0.2 + 0.6 * u();
        let n = b.centreline.len() - 1;
        let x = s * n as f64;
        let i = (x as usize).min(n - 1);
        let on = b.centreline[i] + (b.centreline[i + 1] - b.centreline[i]) * (x - i as f64);
        let jitter = Vector3::new(u() - 0.5, u() - 0.5, u() - 0.5) * b.radius;
        let p = on + jitter;
        if b.axis_distance(&p) <= 0.5 * b.radius
            && inside_mesh(&airway.vertices, &airway.triangles, &p)
        {
            out.push(LumenPoint {
                point: p,
                branch: k,
                generation,
            });
        }
    }
    out
}
