use super::*;
use crate::contact::field::tests::{points, tube};
use crate::model::mesh::{trimesh, Free};

const NODES: usize = 1 << 16;

fn mesh(free: Free, scale: f64) -> TriMesh {
    let (v, t) = tube();
    let v: Vec<_> = v.into_iter().map(|x| x * scale).collect();
    trimesh(&v, &t, Some(free)).expect("a solid")
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("ccrkit-field-cache-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The checksum recomputed after a mutation, so that only the other checks can refuse it.
fn resum(b: &mut [u8]) {
    let n = b.len() - 8;
    let sum = xxh3_64(&b[..n]);
    b[n..].copy_from_slice(&sum.to_le_bytes());
}

#[test]
fn a_cached_grid_answers_as_the_cold_one_to_the_bit() {
    for free in [Free::Inside, Free::Outside] {
        let m = mesh(free, 1.0);
        let d = dir(&format!("same-{}", free.name()));
        let (cold, o1) = load_or_build(&m, NODES, Some(&d));
        let path = d.join(Key::of(&m, NODES).file_name());
        assert_eq!(o1, FieldOrigin::Written(path.clone()));
        let (warm, o2) = load_or_build(&m, NODES, Some(&d));
        assert_eq!(o2, FieldOrigin::Loaded(path));
        assert_eq!(
            warm,
            SolidField::build(&m, NODES),
            "the same grid as a build"
        );
        for p in points(&m, 2000, 0xCAC4E) {
            let (a, b) = (cold.point_bounds(p), warm.point_bounds(p));
            assert_eq!(a.0.to_bits(), b.0.to_bits());
            assert_eq!(a.1.to_bits(), b.1.to_bits());
        }
        let _ = std::fs::remove_dir_all(&d);
    }
}

#[test]
fn the_key_follows_the_mesh_the_side_and_the_budget() {
    let a = Key::of(&mesh(Free::Inside, 1.0), NODES);
    assert_eq!(a, Key::of(&mesh(Free::Inside, 1.0), NODES));
    assert_ne!(a.mesh, Key::of(&mesh(Free::Outside, 1.0), NODES).mesh);
    assert_ne!(a.mesh, Key::of(&mesh(Free::Inside, 1.001), NODES).mesh);
    let b = Key::of(&mesh(Free::Inside, 1.0), 2 * NODES);
    assert_eq!((a.mesh == b.mesh, a.params == b.params), (true, false));
}

/// Every kind of bad file is refused by name, ignored, and replaced by a good one.
#[test]
fn a_corrupt_truncated_or_lying_file_is_refused_and_rebuilt() {
    let m = mesh(Free::Inside, 1.0);
    let key = Key::of(&m, NODES);
    let good = encode(&SolidField::build(&m, NODES), key);
    let other = mesh(Free::Inside, 1.001);
    let foreign = encode(&SolidField::build(&other, NODES), Key::of(&other, NODES));
    let total = Grid::of(&m, NODES).total();
    type Mutation = Box<dyn Fn(&mut Vec<u8>)>;
    let cases: Vec<(&str, Mutation, &str)> = vec![
        ("truncated", Box::new(|b| b.truncate(b.len() / 2)), "size"),
        ("empty", Box::new(|b| b.clear()), "size"),
        ("grown", Box::new(|b| b.extend_from_slice(&[0; 8])), "size"),
        (
            "a value's byte",
            Box::new(|b| b[HEADER + 400] ^= 0x10),
            "checksum",
        ),
        (
            "the magic",
            Box::new(|b| {
                b[0] = b'X';
                resum(b)
            }),
            "magic",
        ),
        (
            "the version",
            Box::new(|b| {
                b[8] = 9;
                resum(b)
            }),
            "version",
        ),
        (
            "the side flag",
            Box::new(|b| {
                b[12] = 7;
                resum(b)
            }),
            "far side",
        ),
        (
            "the mesh hash",
            Box::new(|b| {
                b[16] ^= 1;
                resum(b)
            }),
            "another mesh",
        ),
        (
            "the params hash",
            Box::new(|b| {
                b[24] ^= 1;
                resum(b)
            }),
            "grid parameters",
        ),
        (
            "the spacing",
            Box::new(|b| {
                b[56] ^= 1;
                resum(b)
            }),
            "place",
        ),
        (
            "a huge count",
            Box::new(|b| {
                b[64..72].copy_from_slice(&u64::MAX.to_le_bytes());
                resum(b)
            }),
            "place",
        ),
        (
            "a NaN value",
            Box::new(|b| {
                b[HEADER..HEADER + 4].copy_from_slice(&f32::NAN.to_le_bytes());
                resum(b)
            }),
            "not finite",
        ),
        (
            "every value 1 mm off",
            Box::new(move |b| {
                for k in 0..total {
                    let at = HEADER + 4 * k;
                    let v = f32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]);
                    let w = if v > 0.0 { v + 1e-3 } else { v - 1e-3 };
                    b[at..at + 4].copy_from_slice(&w.to_le_bytes());
                }
                resum(b)
            }),
            "exact signed distance",
        ),
    ];
    let d = dir("corrupt");
    let path = d.join(key.file_name());
    for (what, mutate, words) in cases {
        let mut b = good.clone();
        mutate(&mut b);
        crate::output::write_file(&path, &b).expect("writes");
        let (f, origin) = load_or_build(&m, NODES, Some(&d));
        let FieldOrigin::Rebuilt { reason, .. } = &origin else {
            panic!("{what}: {origin:?}");
        };
        assert!(reason.contains(words), "{what}: {reason}");
        assert_eq!(f, SolidField::build(&m, NODES), "{what}");
        assert_eq!(
            std::fs::read(&path).expect("reads"),
            good,
            "{what}: rewritten"
        );
    }
    // Another mesh's good file under this mesh's name.
    crate::output::write_file(&path, &foreign).expect("writes");
    let (_, origin) = load_or_build(&m, NODES, Some(&d));
    assert!(matches!(origin, FieldOrigin::Rebuilt { .. }), "{origin:?}");
    let (_, origin) = load_or_build(&m, NODES, Some(&d));
    assert_eq!(origin, FieldOrigin::Loaded(path));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_unwritable_cache_builds_and_says_why() {
    let m = mesh(Free::Outside, 1.0);
    let d = dir("unwritable");
    std::fs::create_dir_all(d.parent().expect("parent")).expect("dir");
    // A file where the folder should be.
    std::fs::write(&d, b"not a folder").expect("writes");
    let (f, origin) = load_or_build(&m, NODES, Some(&d));
    assert!(
        matches!(origin, FieldOrigin::NotWritten { .. }),
        "{origin:?}"
    );
    assert_eq!(f, SolidField::build(&m, NODES));
    let _ = std::fs::remove_file(&d);
}
