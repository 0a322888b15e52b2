//! Triangle meshes from STL (binary or ASCII) and Wavefront OBJ files.
//!
//! Small, dependency-free readers: vertices and triangles only (OBJ polygons are fanned into
//! triangles; normals, texture coordinates and materials are ignored). Identical STL vertices
//! are merged so parry's mesh topology sees a connected surface.

use nalgebra::Vector3;
use std::collections::HashMap;
use std::path::Path;

/// Vertices and triangles (indices into the vertices).
pub type MeshData = (Vec<Vector3<f64>>, Vec<[u32; 3]>);

/// Vertices and triangles of a mesh file, or why it cannot be read.
pub fn load(path: &Path) -> Result<MeshData, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    if !matches!(ext.as_deref(), Some("stl" | "obj")) {
        return Err("unknown mesh format: use .stl or .obj".into());
    }
    let bytes =
        super::read::read_capped(path, super::read::MAX_MESH_BYTES, "mesh file").map_err(|e| {
            match e {
                crate::error::ModelError::Io { reason, .. } => reason,
                other => other.to_string(),
            }
        })?;
    let (v, t) = match ext.as_deref() {
        Some("stl") => stl(&bytes)?,
        Some("obj") => obj(&String::from_utf8_lossy(&bytes))?,
        _ => return Err("unknown mesh format: use .stl or .obj".into()),
    };
    if t.is_empty() {
        return Err("the mesh has no triangles".into());
    }
    if v.iter().any(|p| !p.iter().all(|x| x.is_finite())) {
        return Err("the mesh has non-finite vertices".into());
    }
    Ok((v, t))
}

fn stl(bytes: &[u8]) -> Result<MeshData, String> {
    let mut soup: Vec<[Vector3<f64>; 3]> = vec![];
    let binary_len = bytes
        .get(80..84)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    match binary_len {
        Some(n) if bytes.len() == 84 + 50 * n => {
            for k in 0..n {
                let base = 84 + 50 * k + 12;
                let f = |o: usize| {
                    let b = &bytes[base + 4 * o..base + 4 * o + 4];
                    f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64
                };
                soup.push([
                    Vector3::new(f(0), f(1), f(2)),
                    Vector3::new(f(3), f(4), f(5)),
                    Vector3::new(f(6), f(7), f(8)),
                ]);
            }
        }
        _ => {
            let text = String::from_utf8_lossy(bytes);
            if !text.trim_start().starts_with("solid") {
                return Err("neither a binary STL (size does not match its triangle count) nor an ASCII STL".into());
            }
            let mut cur: Vec<Vector3<f64>> = vec![];
            for (ln, line) in text.lines().enumerate() {
                let mut it = line.split_whitespace();
                if it.next() == Some("vertex") {
                    let xs: Result<Vec<f64>, _> = it.map(str::parse::<f64>).collect();
                    let xs = xs.map_err(|e| format!("line {}: {e}", ln + 1))?;
                    if xs.len() != 3 {
                        return Err(format!("line {}: a vertex needs 3 numbers", ln + 1));
                    }
                    cur.push(Vector3::new(xs[0], xs[1], xs[2]));
                    if cur.len() == 3 {
                        soup.push([cur[0], cur[1], cur[2]]);
                        cur.clear();
                    }
                }
            }
        }
    }
    // Merge identical vertices.
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let mut verts = vec![];
    let mut tris = vec![];
    for tri in soup {
        let mut ids = [0u32; 3];
        for (k, p) in tri.iter().enumerate() {
            let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
            ids[k] = *index.entry(key).or_insert_with(|| {
                verts.push(*p);
                (verts.len() - 1) as u32
            });
        }
        if ids[0] != ids[1] && ids[1] != ids[2] && ids[0] != ids[2] {
            tris.push(ids);
        }
    }
    Ok((verts, tris))
}

fn obj(text: &str) -> Result<MeshData, String> {
    let mut verts = vec![];
    let mut tris = vec![];
    for (ln, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let xs: Result<Vec<f64>, _> = it.take(3).map(str::parse::<f64>).collect();
                let xs = xs.map_err(|e| format!("line {}: {e}", ln + 1))?;
                if xs.len() != 3 {
                    return Err(format!("line {}: a vertex needs 3 numbers", ln + 1));
                }
                verts.push(Vector3::new(xs[0], xs[1], xs[2]));
            }
            Some("f") => {
                let mut ids = vec![];
                for tok in it {
                    let first = tok.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|e| format!("line {}: face index `{tok}`: {e}", ln + 1))?;
                    let idx = if i < 0 { verts.len() as i64 + i } else { i - 1 };
                    if idx < 0 || idx as usize >= verts.len() {
                        return Err(format!("line {}: face index {i} out of range", ln + 1));
                    }
                    ids.push(idx as u32);
                }
                if ids.len() < 3 {
                    return Err(format!("line {}: a face needs 3 vertices", ln + 1));
                }
                for k in 1..ids.len() - 1 {
                    tris.push([ids[0], ids[k], ids[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok((verts, tris))
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

/// A bent tube (a section of a torus surface, open at both ends) as a triangle mesh: the
/// centreline is the arc `c(θ) = (R (1 − cos θ), 0, R sin θ)` in the x–z plane, starting at the
/// origin along +z and bending towards +x with radius `bend_radius` (R), for θ from `theta0` to
/// `theta1` \[rad\]; the wall is the circle of radius `tube_radius` around it, with `rings`
/// circles along the arc and `segments` vertices on each. Deterministic, so the file it writes
/// through [`to_obj`] can be regenerated bit for bit.
pub fn bent_tube(
    bend_radius: f64,
    tube_radius: f64,
    theta0: f64,
    theta1: f64,
    rings: usize,
    segments: usize,
) -> MeshData {
    let rings = rings.max(2);
    let segments = segments.max(3);
    let mut verts = Vec::with_capacity(rings * segments);
    for k in 0..rings {
        let th = theta0 + (theta1 - theta0) * k as f64 / (rings - 1) as f64;
        let c = Vector3::new(bend_radius * (1.0 - th.cos()), 0.0, bend_radius * th.sin());
        // In-plane normal (away from the bend centre) and the bend's binormal.
        let e1 = Vector3::new(-th.cos(), 0.0, th.sin());
        let e2 = Vector3::new(0.0, 1.0, 0.0);
        for j in 0..segments {
            let phi = j as f64 / segments as f64 * std::f64::consts::TAU;
            verts.push(c + tube_radius * (phi.cos() * e1 + phi.sin() * e2));
        }
    }
    let mut tris = Vec::with_capacity(2 * (rings - 1) * segments);
    let id = |k: usize, j: usize| (k * segments + j % segments) as u32;
    for k in 0..rings - 1 {
        for j in 0..segments {
            tris.push([id(k, j), id(k + 1, j), id(k + 1, j + 1)]);
            tris.push([id(k, j), id(k + 1, j + 1), id(k, j + 1)]);
        }
    }
    (verts, tris)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obj_quads_are_fanned_and_ascii_stl_vertices_merged() {
        let (v, t) = obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
        assert_eq!((v.len(), t.len()), (4, 2));
        let stl_text = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
        let (v, t) = stl(stl_text.as_bytes()).unwrap();
        assert_eq!((v.len(), t.len()), (4, 2));
        assert!(obj("v 0 0 0\nf 1 2 3\n").is_err());
    }
}
