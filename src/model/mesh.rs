//! Triangle meshes from STL (binary or ASCII), Wavefront OBJ and PLY (ASCII or binary) files,
//! read by maintained crates made for each format (`stl_io`, `tobj`, `ply-rs-bw`) from bytes
//! already read with a size cap ([`super::read::MAX_MESH_BYTES`]); then checked
//! ([`super::mesh_check`]): finite, indices in range, no degenerate triangle, at most
//! [`mesh_check::MAX_TRIANGLES`]. Only vertices and triangles are kept (polygons fanned into
//! triangles; normals, texture coordinates, colours and materials ignored), and vertices equal
//! to the bit are merged, so that triangles that share a corner share its index whatever the
//! format (an STL lists every corner of every triangle; an OBJ's objects each have their own).
//!
//! Whether a mesh is a solid (closed, with an inside) is asked of it only when the scene
//! declares which side is free ([`Free`], [`mesh_check::solid`]).

use super::mesh_check::{self, MeshError};
use foldhash::fast::FixedState;
use nalgebra::Vector3;
use parry3d::math::Vector as PVec;
use parry3d::shape::{TriMesh, TriMeshFlags};
use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;

/// Vertices and triangles (indices into the vertices).
pub type MeshData = (Vec<Vector3<f64>>, Vec<[u32; 3]>);

/// Which side of a closed mesh the robot may be on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Free {
    /// The enclosed volume is free (a lumen: an airway, a vessel); everything outside is wall.
    Inside,
    /// The enclosed volume is an obstacle (an organ to avoid).
    Outside,
}

impl Free {
    /// The word a scene file writes (`inside`, `outside`).
    pub fn name(self) -> &'static str {
        match self {
            Free::Inside => "inside",
            Free::Outside => "outside",
        }
    }
}

/// Vertices and triangles of a mesh file, checked ([`mesh_check::basic`]), or why it cannot
/// be read. The format is chosen by the extension (`.stl`, `.obj`, `.ply`, any case).
pub fn load(path: &Path) -> Result<MeshData, MeshError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let format = match ext.as_deref() {
        Some("stl") => "STL",
        Some("obj") => "OBJ",
        Some("ply") => "PLY",
        _ => return Err(MeshError::Format),
    };
    let bytes =
        super::read::read_capped(path, super::read::MAX_MESH_BYTES, "mesh file").map_err(|e| {
            MeshError::Read {
                format,
                reason: match e {
                    crate::error::ModelError::Io { reason, .. } => reason,
                    other => other.to_string(),
                },
            }
        })?;
    let (v, t) = parse(format, bytes)?;
    mesh_check::basic(&v, &t)?;
    Ok((v, t))
}

/// Parse the bytes of a mesh file in `format` (`STL`, `OBJ` or `PLY`), vertices merged.
pub fn parse(format: &'static str, bytes: Vec<u8>) -> Result<MeshData, MeshError> {
    let read = |reason: String| MeshError::Read { format, reason };
    match format {
        // Merged as read.
        "STL" => stl(bytes).map_err(read),
        "OBJ" => obj(&bytes).map_err(read).map(|(v, t)| merge(v, t)),
        "PLY" => ply(&bytes).map_err(read).map(|(v, t)| merge(v, t)),
        _ => Err(MeshError::Format),
    }
}

/// An STL file by `stl_io`. A file whose size is exactly that of a binary STL with the
/// triangle count of its header is binary even when its 80-byte header starts with `solid`
/// (as some exporters write it), so the header's first bytes are blanked before `stl_io`
/// guesses; any other file is given to `stl_io` as it is (ASCII when it starts with
/// `solid `). A binary header's count is never trusted beyond the bytes present.
fn stl(mut bytes: Vec<u8>) -> Result<MeshData, String> {
    let count = bytes
        .get(80..84)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64);
    let binary = count.is_some_and(|n| bytes.len() as u64 == 84 + 50 * n);
    if binary {
        bytes[..5].copy_from_slice(b"\0\0\0\0\0");
    } else if !bytes.starts_with(b"solid") {
        return Err(format!(
            "neither a binary STL ({} bytes, not 84 + 50 × the {} triangles of its header) nor an ASCII STL (starts with `solid `)",
            bytes.len(),
            count.map_or("missing".into(), |n| n.to_string())
        ));
    }
    // `stl_io`'s triangles, their corners merged here once (its own indexed read hashes every
    // corner with SipHash, and the corners were merged again after it).
    let cap = (bytes.len() / 50).min(super::mesh_check::MAX_TRIANGLES + 1);
    let mut cursor = Cursor::new(bytes);
    let reader = stl_io::create_stl_reader(&mut cursor).map_err(|e| e.to_string())?;
    let mut merged = Merged::with_capacity(cap);
    for t in reader {
        let t = t.map_err(|e| e.to_string())?;
        let mut tri = [0u32; 3];
        for (id, v) in tri.iter_mut().zip(&t.vertices) {
            let p = Vector3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
            *id = merged.index(p)?;
        }
        merged.triangles.push(tri);
    }
    Ok((merged.vertices, merged.triangles))
}

/// Vertices equal to the bit merged as they come (the first kept, in order), with the
/// triangles naming them: one hash map (foldhash, fixed seed) sized up front.
struct Merged {
    index: HashMap<[u64; 3], u32, FixedState>,
    vertices: Vec<Vector3<f64>>,
    triangles: Vec<[u32; 3]>,
}

impl Merged {
    /// Room for about `triangles` triangles of a closed mesh (half as many vertices).
    fn with_capacity(triangles: usize) -> Merged {
        Merged {
            index: HashMap::with_capacity_and_hasher(triangles / 2 + 4, FixedState::default()),
            vertices: Vec::with_capacity(triangles / 2 + 4),
            triangles: Vec::with_capacity(triangles),
        }
    }

    /// The index of the vertex `p` (a new one when no earlier vertex has its bits).
    fn index(&mut self, p: Vector3<f64>) -> Result<u32, String> {
        let next = u32::try_from(self.vertices.len())
            .map_err(|_| format!("more than {} vertices", u32::MAX))?;
        let id = *self
            .index
            .entry([p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .or_insert(next);
        if id == next {
            self.vertices.push(p);
        }
        Ok(id)
    }
}

/// A Wavefront OBJ file by `tobj` (faces fanned into triangles, every object's vertices in one
/// list; points, lines and materials ignored).
fn obj(bytes: &[u8]) -> Result<MeshData, String> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut Cursor::new(bytes), &opts, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| e.to_string())?;
    let (mut v, mut t) = (vec![], vec![]);
    for m in models {
        let base = v.len() as u64;
        let m = m.mesh;
        v.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vector3::new(p[0], p[1], p[2])),
        );
        for tri in m.indices.chunks_exact(3) {
            t.push(try_indices(
                [tri[0], tri[1], tri[2]].map(|i| base + u64::from(i)),
            )?);
        }
    }
    Ok((v, t))
}

/// A PLY file (ASCII or binary) by `ply-rs-bw`: the `vertex` element's `x`, `y`, `z` and the
/// `face` element's `vertex_indices` (or `vertex_index`) lists, fanned into triangles.
fn ply(bytes: &[u8]) -> Result<MeshData, String> {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Property};
    let ply = Parser::<DefaultElement>::new()
        .read_ply(&mut Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let num = |p: Option<&Property>, what: &str| -> Result<f64, String> {
        match p {
            Some(Property::Float(x)) => Ok(f64::from(*x)),
            Some(Property::Double(x)) => Ok(*x),
            Some(Property::Int(x)) => Ok(f64::from(*x)),
            Some(Property::Short(x)) => Ok(f64::from(*x)),
            _ => Err(format!("a vertex has no number `{what}`")),
        }
    };
    let mut v = vec![];
    for e in ply.payload.get("vertex").map_or(&[][..], |x| &x[..]) {
        v.push(Vector3::new(
            num(e.get("x"), "x")?,
            num(e.get("y"), "y")?,
            num(e.get("z"), "z")?,
        ));
    }
    let mut t = vec![];
    for (k, e) in ply
        .payload
        .get("face")
        .map_or(&[][..], |x| &x[..])
        .iter()
        .enumerate()
    {
        let ids: Vec<i64> = match e.get("vertex_indices").or_else(|| e.get("vertex_index")) {
            Some(Property::ListInt(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListUInt(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListShort(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListUShort(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListUChar(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            Some(Property::ListChar(l)) => l.iter().map(|&i| i64::from(i)).collect(),
            _ => return Err(format!("face {k} has no integer list `vertex_indices`")),
        };
        if ids.len() < 3 {
            return Err(format!("face {k} has {} vertices, fewer than 3", ids.len()));
        }
        let id = |i: i64| u64::try_from(i).map_err(|_| format!("face {k} names vertex {i}"));
        for j in 1..ids.len() - 1 {
            t.push(try_indices([id(ids[0])?, id(ids[j])?, id(ids[j + 1])?])?);
        }
    }
    Ok((v, t))
}

/// Three indices as `u32`, or why not (a mesh this large is refused anyway).
fn try_indices(ids: [u64; 3]) -> Result<[u32; 3], String> {
    let one = |i: u64| u32::try_from(i).map_err(|_| format!("vertex index {i} is too large"));
    Ok([one(ids[0])?, one(ids[1])?, one(ids[2])?])
}

/// Vertices equal to the bit merged (the first kept, in order), triangles re-indexed; an
/// index out of range is kept out of range (for [`mesh_check::basic`] to name).
fn merge(v: Vec<Vector3<f64>>, t: Vec<[u32; 3]>) -> MeshData {
    let mut index: HashMap<[u64; 3], u32, FixedState> =
        HashMap::with_capacity_and_hasher(v.len(), FixedState::default());
    let mut verts = Vec::with_capacity(v.len());
    let map: Vec<u32> = v
        .iter()
        .map(|p| {
            *index
                .entry([p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
                .or_insert_with(|| {
                    verts.push(*p);
                    (verts.len() - 1) as u32
                })
        })
        .collect();
    let tris = t
        .iter()
        .map(|tri| tri.map(|i| map.get(i as usize).copied().unwrap_or(i)))
        .collect();
    (verts, tris)
}

/// The parry mesh of an obstacle: a surface as given (`free` absent), or a solid whose
/// obstacle region is what parry's oriented mesh calls inside: the enclosed volume of an organ
/// (`outside` free: triangles as given, outward), the space around a lumen (`inside` free:
/// triangles reversed, so their normals point into the lumen, its free side). The contact
/// queries sign a solid's distances from its pseudo-normals (`contact::parry`).
pub fn trimesh(
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
    free: Option<Free>,
) -> Result<TriMesh, parry3d::shape::TriMeshBuilderError> {
    let pv: Vec<PVec> = vertices.iter().map(|v| PVec::new(v.x, v.y, v.z)).collect();
    match free {
        None => TriMesh::new(pv, triangles.to_vec()),
        Some(free) => {
            let tris = match free {
                Free::Outside => triangles.to_vec(),
                Free::Inside => triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
            };
            TriMesh::with_flags(pv, tris, TriMeshFlags::ORIENTED)
        }
    }
}

/// Write a mesh as Wavefront OBJ text.
pub fn to_obj(vertices: &[Vector3<f64>], triangles: &[[u32; 3]]) -> String {
    let mut s = String::new();
    for v in vertices {
        s += &format!("v {:.9} {:.9} {:.9}\n", v.x, v.y, v.z);
    }
    for t in triangles {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    s
}

/// A mesh as binary STL bytes (`stl_io`; coordinates in `f32`, each triangle's normal from
/// its winding).
pub fn to_stl(vertices: &[Vector3<f64>], triangles: &[[u32; 3]]) -> Vec<u8> {
    let f = |p: &Vector3<f64>| stl_io::Vector::new([p.x as f32, p.y as f32, p.z as f32]);
    let tris: Vec<stl_io::Triangle> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let n = (b - a)
                .cross(&(c - a))
                .try_normalize(0.0)
                .unwrap_or_default();
            stl_io::Triangle {
                normal: f(&n),
                vertices: [f(&a), f(&b), f(&c)],
            }
        })
        .collect();
    let mut bytes = Vec::with_capacity(84 + 50 * tris.len());
    // Writing into memory cannot fail.
    let _ = stl_io::write_stl(&mut bytes, tris.iter());
    bytes
}

/// Write a mesh to `path` (atomically, [`crate::output::write_file`]): binary STL (`.stl`) or Wavefront OBJ (`.obj`), by the extension.
pub fn write(
    path: &Path,
    vertices: &[Vector3<f64>],
    triangles: &[[u32; 3]],
) -> Result<(), MeshError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    let (format, bytes) = match ext.as_deref() {
        Some("stl") => ("STL", to_stl(vertices, triangles)),
        Some("obj") => ("OBJ", to_obj(vertices, triangles).into_bytes()),
        _ => {
            return Err(MeshError::Write {
                format: "mesh",
                reason: format!("{}: ccrkit writes .stl or .obj", path.display()),
            })
        }
    };
    crate::output::write_file(path, &bytes).map_err(|e| MeshError::Write {
        format,
        reason: e.to_string(),
    })
}

/// A bent tube: a section of a torus surface whose centreline is the arc
/// `c(θ) = (R (1 − cos θ), 0, R sin θ)` in the x–z plane, starting at the origin along +z and
/// bending towards +x with radius `bend_radius` (R), for θ from `theta0` to `theta1` \[rad\];
/// the wall is the circle of radius `tube_radius` around it, with `rings` circles along the arc
/// and `segments` vertices on each (at least 2 and 3 are used). Deterministic, so the files it
/// writes through [`to_obj`] can be regenerated bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BentTube {
    /// Radius of the centreline's arc \[m\].
    pub bend_radius: f64,
    /// Radius of the wall around the centreline \[m\].
    pub tube_radius: f64,
    /// Arc angle where the tube starts \[rad\].
    pub theta0: f64,
    /// Arc angle where the tube ends \[rad\].
    pub theta1: f64,
    /// Circles of vertices along the arc.
    pub rings: usize,
    /// Vertices on each circle.
    pub segments: usize,
}

impl BentTube {
    /// The centreline's point at arc angle `th`.
    fn centre(&self, th: f64) -> Vector3<f64> {
        let r = self.bend_radius;
        Vector3::new(r * (1.0 - th.cos()), 0.0, r * th.sin())
    }

    /// Rings and segments as meshed (at least 2 and 3).
    fn counts(&self) -> (usize, usize) {
        (self.rings.max(2), self.segments.max(3))
    }

    /// The wall alone, open at both ends: `2 (rings − 1) segments` triangles.
    pub fn open(&self) -> MeshData {
        let (rings, segments) = self.counts();
        let mut verts = Vec::with_capacity(rings * segments);
        for k in 0..rings {
            let th = self.theta0 + (self.theta1 - self.theta0) * k as f64 / (rings - 1) as f64;
            // In-plane normal (away from the bend centre) and the bend's binormal.
            let e1 = Vector3::new(-th.cos(), 0.0, th.sin());
            let e2 = Vector3::new(0.0, 1.0, 0.0);
            for j in 0..segments {
                let phi = j as f64 / segments as f64 * std::f64::consts::TAU;
                verts.push(self.centre(th) + self.tube_radius * (phi.cos() * e1 + phi.sin() * e2));
            }
        }
        let mut tris = Vec::with_capacity(2 * (rings - 1) * segments);
        for k in 0..rings - 1 {
            for j in 0..segments {
                let id = |k: usize, j: usize| (k * segments + j % segments) as u32;
                tris.push([id(k, j), id(k + 1, j), id(k + 1, j + 1)]);
                tris.push([id(k, j), id(k + 1, j + 1), id(k, j + 1)]);
            }
        }
        (verts, tris)
    }

    /// The tube closed at both ends by flat caps (a fan about each end ring's centre): a
    /// closed, consistently wound solid ([`mesh_check::solid`]) of `2 rings × segments`
    /// triangles — a lumen with `free = "inside"`.
    pub fn capped(&self) -> MeshData {
        let (rings, segments) = self.counts();
        let (mut v, mut t) = self.open();
        v.push(self.centre(self.theta0));
        v.push(self.centre(self.theta1));
        let (c0, c1) = ((v.len() - 2) as u32, (v.len() - 1) as u32);
        let id = |k: usize, j: usize| (k * segments + j % segments) as u32;
        for j in 0..segments {
            t.push([c0, id(0, j), id(0, j + 1)]);
            t.push([c1, id(rings - 1, j + 1), id(rings - 1, j)]);
        }
        (v, t)
    }
}

#[cfg(test)]
#[path = "mesh_tests.rs"]
mod tests;
