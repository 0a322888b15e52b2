//! The readers: every format of one closed box gives the same mesh; each bad file is named.

use super::*;

/// The cube `[0, 1]³` as 12 outward triangles: corners and triangles.
fn cube() -> MeshData {
    super::mesh_check::test_box(0.0, 1.0)
}

/// The triangles of a mesh as corner coordinates (what two readers must agree on, whatever
/// order they number the vertices in).
fn corners((v, t): &MeshData) -> Vec<[[u64; 3]; 3]> {
    let mut c: Vec<[[u64; 3]; 3]> = t
        .iter()
        .map(|t| t.map(|i| [v[i as usize].x, v[i as usize].y, v[i as usize].z].map(f64::to_bits)))
        .collect();
    c.sort_unstable();
    c
}

fn binary_stl((v, t): &MeshData, header: &[u8]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b[..header.len()].copy_from_slice(header);
    b.extend((t.len() as u32).to_le_bytes());
    for tri in t {
        b.extend([0f32; 3].iter().flat_map(|x| x.to_le_bytes()));
        for &i in tri {
            let p = v[i as usize];
            b.extend(
                [p.x, p.y, p.z]
                    .iter()
                    .flat_map(|&x| (x as f32).to_le_bytes()),
            );
        }
        b.extend([0u8; 2]);
    }
    b
}

fn ascii_stl((v, t): &MeshData) -> Vec<u8> {
    let mut s = String::from("solid cube\n");
    for tri in t {
        s += "facet normal 0 0 0\nouter loop\n";
        for &i in tri {
            let p = v[i as usize];
            s += &format!("vertex {} {} {}\n", p.x, p.y, p.z);
        }
        s += "endloop\nendfacet\n";
    }
    (s + "endsolid cube\n").into_bytes()
}

fn ascii_ply((v, t): &MeshData) -> Vec<u8> {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        v.len(),
        t.len()
    );
    for p in v {
        s += &format!("{} {} {}\n", p.x, p.y, p.z);
    }
    for tri in t {
        s += &format!("3 {} {} {}\n", tri[0], tri[1], tri[2]);
    }
    s.into_bytes()
}

fn binary_ply((v, t): &MeshData) -> Vec<u8> {
    let mut b = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\nelement face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        v.len(),
        t.len()
    )
    .into_bytes();
    for p in v {
        b.extend([p.x, p.y, p.z].iter().flat_map(|x| x.to_le_bytes()));
    }
    for tri in t {
        b.push(3);
        b.extend(tri.iter().flat_map(|i| i.to_le_bytes()));
    }
    b
}

#[test]
fn every_format_reads_the_same_closed_box() {
    let want = cube();
    let files: [(&'static str, Vec<u8>); 6] = [
        ("STL", binary_stl(&want, b"binary")),
        // A binary STL whose header starts with `solid`, as some exporters write it.
        ("STL", binary_stl(&want, b"solid cube")),
        ("STL", ascii_stl(&want)),
        ("OBJ", to_obj(&want.0, &want.1).into_bytes()),
        ("PLY", ascii_ply(&want)),
        ("PLY", binary_ply(&want)),
    ];
    for (k, (format, bytes)) in files.into_iter().enumerate() {
        let got = parse(format, bytes).unwrap_or_else(|e| panic!("{k} {format}: {e}"));
        assert_eq!(got.0.len(), 8, "{k} {format}: vertices merged");
        assert_eq!(corners(&got), corners(&want), "{k} {format}");
        mesh_check::basic(&got.0, &got.1).unwrap();
        let solid = mesh_check::solid(&got.0, &got.1).unwrap();
        assert!((mesh_check::enclosed_volume(&got.0, &solid) - 1.0).abs() < 1e-12);
    }
}

#[test]
fn obj_polygons_are_fanned() {
    let (v, t) = parse(
        "OBJ",
        b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n".to_vec(),
    )
    .unwrap();
    assert_eq!((v.len(), t.len()), (4, 2));
}

#[test]
fn each_bad_file_is_named() {
    let read = |format: &'static str, bytes: &[u8]| -> MeshError {
        parse(format, bytes.to_vec())
            .and_then(|(v, t)| mesh_check::basic(&v, &t).map(|_| (v, t)))
            .expect_err(format)
    };
    // A binary STL whose header promises more triangles than the file holds.
    let mut short = binary_stl(&cube(), b"x");
    short.truncate(short.len() - 10);
    let e = read("STL", &short);
    assert!(matches!(e, MeshError::Read { format: "STL", .. }), "{e}");
    assert!(e.to_string().contains("neither a binary STL"), "{e}");
    let e = read(
        "STL",
        b"solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 0\n",
    );
    assert!(matches!(e, MeshError::Read { format: "STL", .. }), "{e}");
    let e = read("OBJ", b"v 0 0 0\nv 1 0 0\nf 1 2 9\n");
    assert!(
        matches!(
            e,
            MeshError::Read { format: "OBJ", .. } | MeshError::IndexOutOfRange { .. }
        ),
        "{e}"
    );
    let e = read("OBJ", b"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(
        matches!(
            e,
            MeshError::NonFinite { vertex: 0 } | MeshError::Read { .. }
        ),
        "{e}"
    );
    let e = read("OBJ", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    assert!(matches!(e, MeshError::Degenerate { triangle: 0 }), "{e}");
    let e = read("OBJ", b"# nothing\n");
    assert!(matches!(e, MeshError::Empty), "{e}");
    let e = read(
        "PLY",
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
    );
    assert!(matches!(e, MeshError::Read { format: "PLY", .. }), "{e}");
    let e = read("PLY", b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    assert!(
        matches!(e, MeshError::IndexOutOfRange { index: 7, .. }),
        "{e}"
    );
    assert!(matches!(
        load(Path::new("mesh.vtk")),
        Err(MeshError::Format)
    ));
}

/// The capped tube is a solid whose volume is the torus section's, `π r² R Δθ`, to the
/// facets' (inscribed polygons': `n/(2π) sin(2π/n)` of the disk) and the caps' accuracy.
#[test]
fn the_capped_tube_is_a_solid_of_the_torus_volume() {
    let (r_bend, r, th) = (0.11, 0.02, 1.9);
    let (v, t) = BentTube {
        bend_radius: r_bend,
        tube_radius: r,
        theta0: -0.1,
        theta1: 1.8,
        rings: 400,
        segments: 64,
    }
    .capped();
    mesh_check::basic(&v, &t).unwrap();
    let solid = mesh_check::solid(&v, &t).unwrap();
    let n = 64.0;
    let polygon = n / std::f64::consts::TAU * (std::f64::consts::TAU / n).sin();
    let want = std::f64::consts::PI * r * r * polygon * r_bend * th;
    let got = mesh_check::enclosed_volume(&v, &solid);
    assert!((got / want - 1.0).abs() < 1e-4, "{got} vs {want}");
}

/// The edge check of a solid as it was first written: every directed edge counted in a hash
/// map, then read in sorted order — the first defect, else every edge with one triangle.
fn edges_by_map(t: &[[u32; 3]]) -> Result<(), MeshError> {
    let mut directed: std::collections::HashMap<(u32, u32), usize> = Default::default();
    for t in t {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    let mut seen: Vec<(u32, u32)> = directed.keys().copied().collect();
    seen.sort_unstable();
    let mut boundary = (0, (0, 0));
    for &(a, b) in &seen {
        let (ab, ba) = (
            directed[&(a, b)],
            directed.get(&(b, a)).copied().unwrap_or(0),
        );
        let edge = (a.min(b), a.max(b));
        if ab + ba > 2 {
            return Err(MeshError::NonManifold {
                edge,
                triangles: ab + ba,
            });
        }
        if ab == 2 {
            return Err(MeshError::Inconsistent { edge: (a, b) });
        }
        if ba == 0 {
            if boundary.0 == 0 {
                boundary.1 = edge;
            }
            boundary.0 += 1;
        }
    }
    match boundary {
        (0, _) => Ok(()),
        (n, edge) => Err(MeshError::NotClosed {
            boundary_edges: n,
            edge,
        }),
    }
}

/// The solid check (edges grouped by vertex, no hashing, in parallel) names the same defect
/// as a hash map of directed edges read in order, on a closed tube and on copies of it with
/// triangles removed, flipped, repeated or added across it, drawn at random.
#[test]
fn the_edge_check_agrees_with_a_map_of_directed_edges() {
    let (v, t) = BentTube {
        bend_radius: 0.11,
        tube_radius: 0.02,
        theta0: -0.1,
        theta1: 1.8,
        rings: 40,
        segments: 12,
    }
    .capped();
    let mut rng = crate::numeric::test_rng::Rng(17);
    let mut kinds = [0usize; 4];
    for case in 0..200 {
        let mut t = t.clone();
        for _ in 0..case % 4 {
            let k = (rng.next() * t.len() as f64) as usize;
            match (rng.next() * 4.0) as usize {
                0 => {
                    t.remove(k);
                }
                1 => t[k] = [t[k][0], t[k][2], t[k][1]],
                2 => t.push(t[k]),
                _ => t.push([t[k][0], t[k][1], (rng.next() * v.len() as f64) as u32]),
            }
        }
        let want = edges_by_map(&t);
        let got = mesh_check::solid(&v, &t).map(|_| ());
        kinds[match &want {
            Ok(()) => 0,
            Err(MeshError::NotClosed { .. }) => 1,
            Err(MeshError::NonManifold { .. }) => 2,
            Err(_) => 3,
        }] += 1;
        assert_eq!(got, want, "case {case}");
    }
    // Every outcome was drawn.
    assert!(kinds.iter().all(|&k| k > 0), "{kinds:?}");
}
