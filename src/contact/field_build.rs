//! Building a [`SolidField`] (the argument is in `field.rs`): the nodes near the surface
//! projected on the mesh by parry in parallel, a separable Euclidean distance transform
//! (Felzenszwalb and Huttenlocher, 2012) from those within a cell of the surface, the sign
//! of the rest filled row by row from the projected nodes.

use super::field::{SolidField, LOOSE};
use parry3d::math::Vector as PVec;
use parry3d::query::PointQueryWithLocation;
use parry3d::shape::TriMesh;
use rayon::prelude::*;

/// Where a mesh's grid lies: what [`SolidField::build`] derives from the mesh and the node
/// budget alone, before any distance (a cached grid must match it to the bit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Grid {
    /// The first node (mesh frame) \[m\].
    pub origin: [f64; 3],
    /// Node spacing \[m\].
    pub h: f64,
    /// Nodes along each axis.
    pub n: [usize; 3],
    /// The mesh's bounds: min, max \[m\].
    pub bounds: [[f64; 3]; 2],
}

impl Grid {
    /// The grid of `mesh` with about `nodes` nodes: its bounds padded by two cells.
    pub fn of(mesh: &TriMesh, nodes: usize) -> Grid {
        let b = mesh.local_aabb();
        let (lo, hi) = (
            [b.mins.x, b.mins.y, b.mins.z],
            [b.maxs.x, b.maxs.y, b.maxs.z],
        );
        let ext = [0, 1, 2].map(|a| (hi[a] - lo[a]).max(1e-9));
        // Spacing from the budget over the bounds padded by two cells (fixed point, twice).
        let mut h = (ext[0] * ext[1] * ext[2] / nodes.max(8) as f64).cbrt();
        for _ in 0..2 {
            let v: f64 = (0..3).map(|a| ext[a] + 4.0 * h).product();
            h = (v / nodes.max(8) as f64).cbrt();
        }
        let n = [0, 1, 2].map(|a| ((ext[a] + 4.0 * h) / h).ceil() as usize + 1);
        let origin = [0, 1, 2].map(|a| lo[a] - 2.0 * h);
        Grid {
            origin,
            h,
            n,
            bounds: [lo, hi],
        }
    }

    /// The number of nodes.
    pub fn total(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }
}

/// `f32` at or below `x`.
pub(crate) fn down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x {
        f.next_down()
    } else {
        f
    }
}

impl SolidField {
    /// The grid of the solid `mesh` (parry's oriented mesh: its inside is the obstacle region)
    /// with about `nodes` nodes.
    pub fn build(mesh: &TriMesh, nodes: usize) -> SolidField {
        let Grid {
            origin,
            h,
            n,
            bounds: [lo, hi],
        } = Grid::of(mesh, nodes);
        let total = n[0] * n[1] * n[2];
        let node = |k: usize| {
            let (x, y, z) = (k % n[0], (k / n[0]) % n[1], k / (n[0] * n[1]));
            PVec::new(
                origin[0] + x as f64 * h,
                origin[1] + y as f64 * h,
                origin[2] + z as f64 * h,
            )
        };
        // Every node within `h` of a triangle is in the triangle's bounds loosened by `h`.
        let mut near = vec![0u64; total.div_ceil(64)];
        let pad = h * (1.0 + 1e-9);
        for t in mesh.triangles() {
            let (mut a, mut c) = ([0usize; 3], [0usize; 3]);
            for ax in 0..3 {
                let (vmin, vmax) = [t.a, t.b, t.c].iter().fold((f64::MAX, f64::MIN), |m, v| {
                    (m.0.min(v[ax]), m.1.max(v[ax]))
                });
                a[ax] = (((vmin - pad - origin[ax]) / h).ceil().max(0.0)) as usize;
                c[ax] = (((vmax + pad - origin[ax]) / h).floor() as usize).min(n[ax] - 1);
            }
            for z in a[2]..=c[2] {
                for y in a[1]..=c[1] {
                    for x in a[0]..=c[0] {
                        let k = x + n[0] * (y + n[1] * z);
                        near[k / 64] |= 1 << (k % 64);
                    }
                }
            }
        }
        let marked: Vec<usize> = near
            .iter()
            .enumerate()
            .filter(|(_, w)| **w != 0)
            .flat_map(|(i, &w)| {
                (0..64)
                    .filter(move |b| w >> b & 1 == 1)
                    .map(move |b| 64 * i + b)
            })
            .collect();
        // Projected within 2h (a bounded search of parry's tree); a node farther is left to
        // the transform like any node not marked.
        let exact: Vec<Option<(f64, bool)>> = marked
            .par_iter()
            .map(|&k| {
                let p = node(k);
                mesh.project_local_point_and_get_location_with_max_dist(p, false, 2.0 * h)
                    .map(|(proj, _)| ((p - proj.point).length(), proj.is_inside))
            })
            .collect();
        // Signed values: the projected nodes exact, the others from the transform.
        let mut value = vec![f64::NAN; total];
        let mut source = vec![false; total];
        for (&k, e) in marked.iter().zip(&exact) {
            match e {
                Some((d, inside)) => {
                    value[k] = if *inside { -d } else { *d };
                    source[k] = *d <= h;
                }
                None => near[k / 64] &= !(1 << (k % 64)),
            }
        }
        let dist = distance_transform(&source, n);
        // The side beyond the mesh's bounds, from the grid's first node (two cells beyond).
        let far = if mesh
            .project_local_point_and_get_location(node(0), false)
            .0
            .is_inside
        {
            -1.0
        } else {
            1.0
        };
        spread_sign(&mut value, n, far);
        // Every node not projected within 2h is loose (the last word's spare bits clear).
        let mut loose: Vec<u64> = near.iter().map(|w| !w).collect();
        if total % 64 != 0 {
            if let Some(last) = loose.last_mut() {
                *last &= (1u64 << (total % 64)) - 1;
            }
        }
        let lo_v: Vec<f32> = (0..total)
            .into_par_iter()
            .with_min_len(4096)
            .map(|k| {
                if near[k / 64] >> (k % 64) & 1 == 1 {
                    return down(value[k]);
                }
                let d = dist[k].sqrt() * h;
                // Lower bound max(h, D − h√3/2) on the free side; −(D + h) on the other.
                if value[k] > 0.0 {
                    down(h.max(d - (LOOSE - 1.0) * h))
                } else {
                    down(-(d + h))
                }
            })
            .collect();
        let corner = far > 0.0;
        SolidField {
            origin,
            h,
            n,
            lo: lo_v,
            loose,
            bounds: [lo, hi],
            far_free: corner,
        }
    }
}

/// Squared distances (in cells) from every node to the nearest `source` node; infinite when
/// there is none.
fn distance_transform(source: &[bool], n: [usize; 3]) -> Vec<f64> {
    let plane = n[0] * n[1];
    let big = 1e18;
    // Along z first, by two sweeps over whole planes (contiguous).
    let mut d: Vec<f64> = source.iter().map(|&s| if s { 0.0 } else { big }).collect();
    for z in 1..n[2] {
        let (prev, cur) = d.split_at_mut(z * plane);
        let prev = &prev[(z - 1) * plane..];
        for (c, p) in cur[..plane].iter_mut().zip(prev) {
            *c = c.min(p + 1.0);
        }
    }
    for z in (0..n[2].saturating_sub(1)).rev() {
        let (cur, next) = d.split_at_mut((z + 1) * plane);
        let cur = &mut cur[z * plane..];
        for (c, p) in cur.iter_mut().zip(&next[..plane]) {
            *c = c.min(p + 1.0);
        }
    }
    for v in d.iter_mut() {
        if *v < big {
            *v *= *v;
        }
    }
    // Then along x and y inside each plane, planes in parallel.
    d.par_chunks_mut(plane).for_each(|p| {
        let mut line = vec![0.0; n[0].max(n[1])];
        let mut out = vec![0.0; n[0].max(n[1])];
        let (mut v, mut z) = (Vec::new(), Vec::new());
        for y in 0..n[1] {
            let row = &mut p[y * n[0]..(y + 1) * n[0]];
            line[..n[0]].copy_from_slice(row);
            lower_envelope(&line[..n[0]], &mut out[..n[0]], &mut v, &mut z);
            row.copy_from_slice(&out[..n[0]]);
        }
        for x in 0..n[0] {
            for y in 0..n[1] {
                line[y] = p[x + y * n[0]];
            }
            lower_envelope(&line[..n[1]], &mut out[..n[1]], &mut v, &mut z);
            for y in 0..n[1] {
                p[x + y * n[0]] = out[y];
            }
        }
    });
    d
}

/// One line of the separable transform: `out[q] = min_p f[p] + (q − p)²` by the lower
/// envelope of parabolas (values of `1e18` and above count as none).
/// `v` and `z` are scratch (the envelope's parabolas and their bounds).
fn lower_envelope(f: &[f64], out: &mut [f64], v: &mut Vec<usize>, z: &mut Vec<f64>) {
    let n = f.len();
    v.clear();
    z.clear();
    for q in 0..n {
        if f[q] >= 1e18 {
            continue;
        }
        let fq = f[q] + (q * q) as f64;
        loop {
            let Some(&p) = v.last() else {
                v.push(q);
                z.push(f64::NEG_INFINITY);
                break;
            };
            let s = (fq - (f[p] + (p * p) as f64)) / (2.0 * (q as f64 - p as f64));
            if s <= *z.last().unwrap_or(&f64::NEG_INFINITY) {
                v.pop();
                z.pop();
                continue;
            }
            v.push(q);
            z.push(s);
            break;
        }
    }
    if v.is_empty() {
        out.fill(1e18);
        return;
    }
    let mut k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while k + 1 < v.len() && z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        let dq = q as f64 - p as f64;
        *o = dq * dq + f[p];
    }
}

/// The side of every node not projected (`NaN`), as a magnitude-free `±1`. A node not
/// projected is farther than `h` from the surface, so no surface crosses an edge from it: it
/// has the side of any projected neighbour, and a run of them along a row has the side of the
/// projected node at either end; a row with none has the side of its ends, which are beyond
/// the mesh's bounds: `far`. Rows in parallel; a run between two nodes on the surface itself
/// (value 0, no side) takes a side from its other neighbours afterwards.
fn spread_sign(value: &mut [f64], n: [usize; 3], far: f64) {
    value.par_chunks_mut(n[0]).with_min_len(64).for_each(|row| {
        let len = row.len();
        let mut start = None;
        for x in 0..=len {
            if x < len && row[x].is_nan() {
                start.get_or_insert(x);
                continue;
            }
            let Some(s) = start.take() else {
                continue;
            };
            let left = if s > 0 { row[s - 1] } else { 0.0 };
            let right = if x < len { row[x] } else { 0.0 };
            let side = if s == 0 && x == len {
                far
            } else if left != 0.0 {
                left.signum()
            } else if right != 0.0 {
                right.signum()
            } else {
                continue;
            };
            row[s..x].fill(side);
        }
    });
    let mut left: Vec<usize> = (0..value.len()).filter(|&k| value[k].is_nan()).collect();
    while !left.is_empty() {
        let before = left.len();
        left.retain(|&k| {
            let (x, y, z) = (k % n[0], (k / n[0]) % n[1], k / (n[0] * n[1]));
            let (sy, sz) = (n[0], n[0] * n[1]);
            let near = [
                (x > 0).then(|| k - 1),
                (x + 1 < n[0]).then(|| k + 1),
                (y > 0).then(|| k - sy),
                (y + 1 < n[1]).then(|| k + sy),
                (z > 0).then(|| k - sz),
                (z + 1 < n[2]).then(|| k + sz),
            ];
            let side = near
                .into_iter()
                .flatten()
                .map(|j| value[j])
                .find(|v| !v.is_nan() && *v != 0.0);
            match side {
                Some(v) => {
                    value[k] = v.signum();
                    false
                }
                None => true,
            }
        });
        if left.len() == before {
            // Nothing next to them has a side (nodes walled in by nodes on the surface).
            left.iter().for_each(|&k| value[k] = far);
            break;
        }
    }
}
