//! What a mesh must be before ccrkit queries it: finite vertices, triangles whose indices are in
//! range and that span an area, a bounded size; and, for a mesh declared a solid (`free =
//! "inside"` or `"outside"`), closed and consistently oriented, so that its inside is defined.
//!
//! # When a mesh is a solid
//!
//! Every edge of a closed, consistently oriented, manifold triangle mesh is used by exactly two
//! triangles, once in each direction. Then the mesh bounds a volume, the sign of the enclosed
//! volume `Σ det(v₀, v₁, v₂) / 6` says whether the triangles wind outward (positive) or inward,
//! and the angle-weighted pseudo-normals at the closest point decide inside or outside for any
//! point (Bærentzen & Aanæs, IEEE TVCG 11(3), 2005) — what parry's oriented [`TriMesh`] query
//! does. A mesh that fails any of these gets a named [`MeshError`], never a guess:
//! an edge used once ([`MeshError::NotClosed`]), by three or more triangles
//! ([`MeshError::NonManifold`]), twice in the same direction ([`MeshError::Inconsistent`]),
//! or a volume that is zero to round-off ([`MeshError::NoVolume`]). A closed mesh wound
//! inward is turned outward (its triangles reversed): the winding of a closed mesh decides
//! nothing once the free side is declared.
//!
//! [`TriMesh`]: parry3d::shape::TriMesh

use nalgebra::Vector3;
use rayon::prelude::*;

/// Most triangles in one mesh (about the 256 MiB file cap of a binary STL).
pub const MAX_TRIANGLES: usize = 5_000_000;

/// Why a mesh cannot be used; the reason in a model error names the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The file's extension is not one ccrkit reads.
    #[error("unknown mesh format: use .stl, .obj or .ply")]
    Format,
    /// The file could not be read or parsed.
    #[error("{format}: {reason}")]
    Read {
        /// STL, OBJ or PLY.
        format: &'static str,
        /// What the reader said.
        reason: String,
    },
    /// No triangles.
    #[error("the mesh has no triangles")]
    Empty,
    /// More triangles than [`MAX_TRIANGLES`].
    #[error("{count} triangles, more than the {limit} ccrkit reads")]
    TooLarge {
        /// Triangles in the file.
        count: usize,
        /// [`MAX_TRIANGLES`].
        limit: usize,
    },
    /// A vertex with a coordinate that is not a finite number.
    #[error("vertex {vertex} is not finite")]
    NonFinite {
        /// Vertex index (0-based).
        vertex: usize,
    },
    /// A triangle names a vertex that does not exist.
    #[error("triangle {triangle} names vertex {index}, but there are {vertices} vertices")]
    IndexOutOfRange {
        /// Triangle index (0-based).
        triangle: usize,
        /// The index it names.
        index: u64,
        /// Vertices in the mesh.
        vertices: usize,
    },
    /// A triangle with a repeated vertex or no area.
    #[error("triangle {triangle} is degenerate (a repeated vertex or zero area)")]
    Degenerate {
        /// Triangle index (0-based).
        triangle: usize,
    },
    /// A solid's edge used by one triangle only: the mesh has a hole.
    #[error("not closed: {boundary_edges} edges have one triangle only, e.g. between vertices {} and {} (a solid mesh must be closed; leave `free` out to use it as a surface)", edge.0, edge.1)]
    NotClosed {
        /// How many such edges.
        boundary_edges: usize,
        /// One of them (vertex indices).
        edge: (u32, u32),
    },
    /// A solid's edge shared by three or more triangles.
    #[error("not manifold: the edge between vertices {} and {} is shared by {triangles} triangles", edge.0, edge.1)]
    NonManifold {
        /// The edge (vertex indices).
        edge: (u32, u32),
        /// How many triangles share it.
        triangles: usize,
    },
    /// Two triangles run along a shared edge in the same direction: their normals disagree on
    /// which side is inside.
    #[error("inconsistent orientation: two triangles run along the edge from vertex {} to {} in the same direction, so its inside is ambiguous", edge.0, edge.1)]
    Inconsistent {
        /// The edge (vertex indices, in the direction both triangles take).
        edge: (u32, u32),
    },
    /// A closed mesh that encloses no volume (to round-off).
    #[error("encloses no volume ({volume:e} m³ for a bounding box of {bounds:e} m³): its inside is ambiguous")]
    NoVolume {
        /// The enclosed volume.
        volume: f64,
        /// The volume of its bounding box.
        bounds: f64,
    },
    /// A mesh file could not be written.
    #[error("cannot write {format}: {reason}")]
    Write {
        /// STL or OBJ.
        format: &'static str,
        /// What the file system said.
        reason: String,
    },
}

/// Check a mesh as read: not empty, not too large, finite vertices, every index in range,
/// every triangle with three distinct vertices and an area above round-off of its size.
pub fn basic(vertices: &[Vector3<f64>], triangles: &[[u32; 3]]) -> Result<(), MeshError> {
    if triangles.is_empty() {
        return Err(MeshError::Empty);
    }
    if triangles.len() > MAX_TRIANGLES {
        return Err(MeshError::TooLarge {
            count: triangles.len(),
            limit: MAX_TRIANGLES,
        });
    }
    if let Some(vertex) = vertices
        .iter()
        .position(|v| !v.iter().all(|x| x.is_finite()))
    {
        return Err(MeshError::NonFinite { vertex });
    }
    for (triangle, t) in triangles.iter().enumerate() {
        if let Some(&index) = t.iter().find(|&&i| i as usize >= vertices.len()) {
            return Err(MeshError::IndexOutOfRange {
                triangle,
                index: u64::from(index),
                vertices: vertices.len(),
            });
        }
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let size = e1.norm_squared().max(e2.norm_squared());
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || e1.cross(&e2).norm() <= 1e-12 * size {
            return Err(MeshError::Degenerate { triangle });
        }
    }
    Ok(())
}

/// The triangles of a solid, wound outward: the mesh must be closed, manifold and
/// consistently oriented, and enclose a volume (module docs). Triangles reversed when the
/// mesh was wound inward.
pub fn solid(
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
) -> Result<Vec<[u32; 3]>, MeshError> {
    edges(vertices.len(), triangles)?;
    let volume = enclosed_volume(vertices, triangles);
    let (lo, hi) = vertices.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), v| (lo.inf(v), hi.sup(v)),
    );
    let bounds = (hi - lo).product();
    if volume.abs() <= 1e-9 * bounds || volume == 0.0 {
        return Err(MeshError::NoVolume { volume, bounds });
    }
    Ok(if volume > 0.0 {
        triangles.to_vec()
    } else {
        triangles.iter().map(|t| [t[0], t[2], t[1]]).collect()
    })
}

/// Whether the triangles form a closed surface: every edge used by exactly two triangles,
/// once in each direction (what [`solid`] asks of a mesh before its volume). Such a surface
/// separates space, so a robot body across it cannot come back without passing through it.
pub(crate) fn closed(vertices: usize, triangles: &[[u32; 3]]) -> bool {
    edges(vertices, triangles).is_ok()
}

/// The one of `a` and `b` with the smaller directed edge.
fn earlier<T>(a: Option<((u32, u32), T)>, b: Option<((u32, u32), T)>) -> Option<((u32, u32), T)> {
    match (a, b) {
        (Some(x), Some(y)) => Some(if y.0 < x.0 { y } else { x }),
        (x, y) => x.or(y),
    }
}

/// What one vertex's outgoing edges say about the edge check: the first defect in the order
/// of directed edges `(a, b)`, how many edges have no partner, and the first of those.
#[derive(Default)]
struct EdgeSummary {
    defect: Option<((u32, u32), MeshError)>,
    boundary: usize,
    first_boundary: Option<((u32, u32), (u32, u32))>,
}

impl EdgeSummary {
    /// Both summaries as one: the earlier defect and boundary edge, the counts summed.
    fn join(self, other: EdgeSummary) -> EdgeSummary {
        EdgeSummary {
            defect: earlier(self.defect, other.defect),
            boundary: self.boundary + other.boundary,
            first_boundary: earlier(self.first_boundary, other.first_boundary),
        }
    }
}

/// Every edge used by exactly two triangles, once in each direction (module docs), or the
/// defect of the smallest directed edge `(a, b)` that has one (a mesh with a hole: how many
/// edges have one triangle, and the smallest). The directed edges are grouped by their first
/// vertex (counted, then placed: no hashing), each vertex's list sorted, and every edge's
/// reverse counted in its end's list by binary search, vertices in parallel.
fn edges(vertices: usize, triangles: &[[u32; 3]]) -> Result<(), MeshError> {
    for (triangle, t) in triangles.iter().enumerate() {
        if let Some(&index) = t.iter().find(|&&i| i as usize >= vertices) {
            return Err(MeshError::IndexOutOfRange {
                triangle,
                index: u64::from(index),
                vertices,
            });
        }
    }
    // `start[a]..start[a + 1]`: the ends of the edges leaving vertex `a` in `to`.
    let mut start = vec![0usize; vertices + 1];
    for t in triangles {
        for &a in t {
            start[a as usize + 1] += 1;
        }
    }
    for a in 0..vertices {
        start[a + 1] += start[a];
    }
    let mut fill = start.clone();
    let mut to = vec![0u32; 3 * triangles.len()];
    for t in triangles {
        for k in 0..3 {
            let a = t[k] as usize;
            to[fill[a]] = t[(k + 1) % 3];
            fill[a] += 1;
        }
    }
    let mut lists: Vec<&mut [u32]> = Vec::with_capacity(vertices);
    let mut rest = &mut to[..];
    for a in 0..vertices {
        let (list, tail) = rest.split_at_mut(start[a + 1] - start[a]);
        lists.push(list);
        rest = tail;
    }
    lists.par_iter_mut().for_each(|l| l.sort_unstable());
    drop(lists);
    let list = |a: usize| &to[start[a]..start[a + 1]];
    let count = |l: &[u32], b: u32| l.partition_point(|&x| x <= b) - l.partition_point(|&x| x < b);
    let summary = (0..vertices)
        .into_par_iter()
        .with_min_len(1024)
        .map(|a| {
            let mut s = EdgeSummary::default();
            let out = list(a);
            let a = a as u32;
            let mut i = 0;
            while i < out.len() {
                let b = out[i];
                let ab = count(&out[i..], b);
                i += ab;
                let ba = count(list(b as usize), a);
                let (lo, hi) = (a.min(b), a.max(b));
                if ab + ba > 2 {
                    let e = MeshError::NonManifold {
                        edge: (lo, hi),
                        triangles: ab + ba,
                    };
                    s.defect = Some(((a, b), e));
                    break;
                }
                if ab == 2 {
                    s.defect = Some(((a, b), MeshError::Inconsistent { edge: (a, b) }));
                    break;
                }
                if ba == 0 {
                    s.boundary += 1;
                    s.first_boundary.get_or_insert(((a, b), (lo, hi)));
                }
            }
            s
        })
        .reduce(EdgeSummary::default, EdgeSummary::join);
    if let Some((_, e)) = summary.defect {
        return Err(e);
    }
    match summary.first_boundary {
        Some((_, edge)) => Err(MeshError::NotClosed {
            boundary_edges: summary.boundary,
            edge,
        }),
        None => Ok(()),
    }
}

/// The signed volume a closed mesh encloses, `Σ det(v₀, v₁, v₂) / 6` (positive when the
/// triangles wind outward) \[m³\]; taken about the first vertex, so far-off meshes keep their
/// digits.
pub fn enclosed_volume(vertices: &[Vector3<f64>], triangles: &[[u32; 3]]) -> f64 {
    let Some(o) = vertices.first() else {
        return 0.0;
    };
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize] - o);
            a.dot(&b.cross(&c))
        })
        .sum::<f64>()
        / 6.0
}

/// The box `[lo, hi]³` as its 8 corners and 12 outward triangles: the closed mesh the tests
/// of meshes, solids and fields start from.
#[cfg(test)]
pub(crate) fn test_box(lo: f64, hi: f64) -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
    let v = (0..8)
        .map(|i| {
            let bit = |b: usize| if (i >> b) & 1 == 1 { hi } else { lo };
            Vector3::new(bit(0), bit(1), bit(2))
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let t = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    (v, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube `[0, 1]³`.
    pub(crate) fn cube() -> (Vec<Vector3<f64>>, Vec<[u32; 3]>) {
        test_box(0.0, 1.0)
    }

    #[test]
    fn the_cube_is_a_solid_of_unit_volume_either_way_wound() {
        let (v, t) = cube();
        assert!((enclosed_volume(&v, &t) - 1.0).abs() < 1e-15);
        assert_eq!(solid(&v, &t).unwrap(), t);
        let inward: Vec<[u32; 3]> = t.iter().map(|t| [t[0], t[2], t[1]]).collect();
        assert_eq!(solid(&v, &inward).unwrap(), t);
        basic(&v, &t).unwrap();
    }

    #[test]
    fn each_defect_is_named() {
        let (v, t) = cube();
        let open = &t[..11];
        assert!(matches!(
            solid(&v, open),
            Err(MeshError::NotClosed {
                boundary_edges: 3,
                ..
            })
        ));
        let mut flipped = t.clone();
        flipped[0] = [t[0][0], t[0][2], t[0][1]];
        assert!(matches!(
            solid(&v, &flipped),
            Err(MeshError::Inconsistent { .. })
        ));
        let mut fin = t.clone();
        fin.push([0, 2, 7]);
        assert!(matches!(
            solid(&v, &fin),
            Err(MeshError::NonManifold { triangles: 3, .. })
        ));
        // Two triangles back to back: closed, consistent, no volume.
        let flat = [[0u32, 1, 2], [0, 2, 1]];
        assert!(matches!(solid(&v, &flat), Err(MeshError::NoVolume { .. })));
        assert!(matches!(
            basic(&v, &[[0, 1, 9]]),
            Err(MeshError::IndexOutOfRange { index: 9, .. })
        ));
        assert!(matches!(
            basic(&v, &[[0, 1, 1]]),
            Err(MeshError::Degenerate { triangle: 0 })
        ));
        // Three collinear vertices.
        let line = vec![Vector3::zeros(), Vector3::x(), 2.0 * Vector3::x()];
        assert!(matches!(
            basic(&line, &[[0, 1, 2]]),
            Err(MeshError::Degenerate { triangle: 0 })
        ));
        let mut nan = v.clone();
        nan[3].y = f64::NAN;
        assert!(matches!(
            basic(&nan, &t),
            Err(MeshError::NonFinite { vertex: 3 })
        ));
        assert!(matches!(basic(&v, &[]), Err(MeshError::Empty)));
    }
}
