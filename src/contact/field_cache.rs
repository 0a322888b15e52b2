//! A solid's signed-distance grid kept on disk, keyed by the mesh's content, so a mesh is
//! prepared once per machine rather than once per process.
//!
//! The key is two xxh3 hashes (`xxhash-rust`): of the mesh as parry holds it (every vertex's
//! bits, every triangle's indices, oriented or not: the scale, the free side and the file
//! format are all in it) and of the grid's parameters (the node budget, this format's and the
//! build's versions). The file, `<mesh>-<params>.field` (hexadecimal) in the cache folder
//! ([`FieldCache`]), is written atomically ([`crate::output::write_file`]):
//!
//! | bytes | field |
//! |---|---|
//! | 8 | magic `CCRKFLD\0` |
//! | 4 | format version ([`FORMAT_VERSION`]), little endian as everything after |
//! | 4 | the far side is free (0 or 1) |
//! | 8 + 8 | the mesh's hash, the parameters' hash |
//! | 24 + 8 + 24 + 48 | origin, spacing, nodes along x, y, z, the mesh's bounds |
//! | 4 per node | lower bounds (`f32`) |
//! | 8 per 64 nodes | loose bits |
//! | 8 | xxh3 of every byte before |
//!
//! Nothing in a file is believed that can be checked: the grid's place (origin, spacing,
//! counts, bounds) is derived from the mesh again and must match to the bit, so the file's
//! size is known before it is read and a header cannot make it allocate; the magic, version,
//! both hashes and the checksum must match; every value must be finite, with the far side's
//! sign; and 128 nodes (half of them exact) are projected on the triangles again, each value
//! within its stated bounds of the exact signed distance. A file that fails any of these is
//! named ([`CacheError`]), ignored and replaced by a fresh build. What the checks cannot see
//! is a deliberate, consistent lie about a few nodes: the cache folder is the user's own.

use super::field::{SolidField, LOOSE};
use super::field_build::Grid;
use parry3d::math::Vector as PVec;
use parry3d::query::PointQueryWithLocation;
use parry3d::shape::TriMesh;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use xxhash_rust::xxh3::{xxh3_64, Xxh3};

/// The cache file format's version.
pub const FORMAT_VERSION: u32 = 1;
/// The build's version: raised whenever [`SolidField::build`] would answer differently.
const BUILD_VERSION: u32 = 1;
const MAGIC: [u8; 8] = *b"CCRKFLD\0";
const HEADER: usize = 136;
/// Nodes projected again when a file is read (half of them exact ones).
const SPOT: usize = 128;
/// The environment variable naming the cache folder (`off`: no cache).
pub const CACHE_ENV: &str = "CCRKIT_CACHE_DIR";
/// Solids with fewer triangles are built, not cached (a build under about 0.1 s).
pub const MIN_CACHED_TRIANGLES: usize = 10_000;

/// Where prepared grids are kept.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FieldCache {
    /// Built in every process, never written.
    Off,
    /// Read from and written to this folder.
    Dir(PathBuf),
}

impl FieldCache {
    /// The folder `fields` inside `$CCRKIT_CACHE_DIR` (`off` or empty: [`FieldCache::Off`]);
    /// without it, inside the user's cache folder: `$XDG_CACHE_HOME/ccrkit`,
    /// `$HOME/.cache/ccrkit` or `%LOCALAPPDATA%\ccrkit`, the first that is set and absolute.
    pub fn from_env() -> FieldCache {
        let var = |k: &str| {
            std::env::var_os(k)
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
        };
        if let Some(v) = std::env::var_os(CACHE_ENV) {
            if v.is_empty() || v == "off" {
                return FieldCache::Off;
            }
            return FieldCache::Dir(PathBuf::from(v).join("fields"));
        }
        let base = var("XDG_CACHE_HOME")
            .filter(|p| p.is_absolute())
            .or_else(|| var("HOME").map(|h| h.join(".cache")))
            .or_else(|| var("LOCALAPPDATA"))
            .filter(|p| p.is_absolute());
        base.map_or(FieldCache::Off, |b| {
            FieldCache::Dir(b.join("ccrkit").join("fields"))
        })
    }
}

/// How an obstacle's grid came to be.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FieldOrigin {
    /// Built here (no cache, or a mesh too small to cache).
    Built,
    /// Read from this cache file.
    Loaded(PathBuf),
    /// Built here and written to this cache file (none was there).
    Written(PathBuf),
    /// The cache file was refused for `reason`, and a fresh build written over it.
    Rebuilt {
        /// The cache file.
        path: PathBuf,
        /// Why it was refused ([`CacheError`]'s words).
        reason: String,
    },
    /// Built here; the cache file could not be written (`reason`).
    NotWritten {
        /// The cache file.
        path: PathBuf,
        /// The write's error.
        reason: String,
    },
}

/// Why a cache file was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CacheError {
    /// The file could not be read.
    #[error("cannot be read: {0}")]
    Io(String),
    /// Its size is not the one this mesh's grid has.
    #[error("size: {found} bytes, this mesh's grid has {expected}")]
    Size {
        /// Bytes expected.
        expected: u64,
        /// Bytes found.
        found: u64,
    },
    /// A header field differs from what it must be.
    #[error("header: {0}")]
    Header(&'static str),
    /// The checksum does not match the bytes.
    #[error("checksum: the bytes changed after they were written")]
    Checksum,
    /// A node's value is not finite or on the wrong side of a loose bound.
    #[error("node {0}: value not finite or not a bound")]
    Value(usize),
    /// A node's value is not within its bounds of the exact signed distance.
    #[error("node {node}: stored {stored} m, exact signed distance {exact} m")]
    SpotCheck {
        /// The node.
        node: usize,
        /// Its stored lower bound \[m\].
        stored: f64,
        /// The exact signed distance \[m\].
        exact: f64,
    },
}

/// The two hashes a file is named by: the mesh's and the grid parameters'.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Key {
    /// xxh3 of the mesh's vertices, triangles and orientation.
    pub mesh: u64,
    /// xxh3 of the node budget and the versions.
    pub params: u64,
}

impl Key {
    /// The key of `mesh`'s grid with `nodes` nodes.
    pub fn of(mesh: &TriMesh, nodes: usize) -> Key {
        let mut h = Xxh3::new();
        let oriented = mesh.pseudo_normals_if_oriented().is_some();
        h.update(&[u8::from(oriented)]);
        h.update(&(mesh.vertices().len() as u64).to_le_bytes());
        let mut buf = Vec::with_capacity(1 << 16);
        for v in mesh.vertices() {
            for x in [v.x, v.y, v.z] {
                buf.extend_from_slice(&x.to_bits().to_le_bytes());
            }
            if buf.len() >= 1 << 16 {
                h.update(&buf);
                buf.clear();
            }
        }
        for t in mesh.indices() {
            for i in t {
                buf.extend_from_slice(&i.to_le_bytes());
            }
            if buf.len() >= 1 << 16 {
                h.update(&buf);
                buf.clear();
            }
        }
        h.update(&buf);
        let mut p = Vec::new();
        p.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        p.extend_from_slice(&BUILD_VERSION.to_le_bytes());
        p.extend_from_slice(&(nodes as u64).to_le_bytes());
        p.extend_from_slice(&LOOSE.to_bits().to_le_bytes());
        Key {
            mesh: h.digest(),
            params: xxh3_64(&p),
        }
    }

    /// The cache file's name.
    pub fn file_name(&self) -> String {
        format!("{:016x}-{:016x}.field", self.mesh, self.params)
    }
}

/// The bytes of a cache file holding `f` under `key`.
pub fn encode(f: &SolidField, key: Key) -> Vec<u8> {
    let mut b = Vec::with_capacity(HEADER + 4 * f.lo.len() + 8 * f.loose.len() + 8);
    b.extend_from_slice(&MAGIC);
    b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    b.extend_from_slice(&u32::from(f.far_free).to_le_bytes());
    b.extend_from_slice(&key.mesh.to_le_bytes());
    b.extend_from_slice(&key.params.to_le_bytes());
    let words = f
        .origin
        .iter()
        .chain([&f.h])
        .map(|x| x.to_bits())
        .chain(f.n.iter().map(|&n| n as u64))
        .chain(f.bounds.iter().flatten().map(|x| x.to_bits()));
    for w in words {
        b.extend_from_slice(&w.to_le_bytes());
    }
    debug_assert_eq!(b.len(), HEADER);
    for v in &f.lo {
        b.extend_from_slice(&v.to_le_bytes());
    }
    for w in &f.loose {
        b.extend_from_slice(&w.to_le_bytes());
    }
    let sum = xxh3_64(&b);
    b.extend_from_slice(&sum.to_le_bytes());
    b
}

/// The size of the file of a grid with `total` nodes.
fn file_size(total: usize) -> usize {
    HEADER + 4 * total + 8 * total.div_ceil(64) + 8
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    let mut w = [0u8; 8];
    w.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(w)
}

/// The grid in `bytes` if it is the one of `mesh` with `nodes` nodes under `key`, checked
/// (module docs).
pub fn decode(
    bytes: &[u8],
    key: Key,
    mesh: &TriMesh,
    nodes: usize,
) -> Result<SolidField, CacheError> {
    let g = Grid::of(mesh, nodes);
    let total = g.total();
    let size = file_size(total);
    if bytes.len() != size {
        return Err(CacheError::Size {
            expected: size as u64,
            found: bytes.len() as u64,
        });
    }
    let (body, sum) = bytes.split_at(size - 8);
    if xxh3_64(body) != u64_at(sum, 0) {
        return Err(CacheError::Checksum);
    }
    if body[..8] != MAGIC {
        return Err(CacheError::Header("not a ccrkit field file (magic)"));
    }
    if body[8..12] != FORMAT_VERSION.to_le_bytes() {
        return Err(CacheError::Header("another format version"));
    }
    let far_free = match body[12..16] {
        [0, 0, 0, 0] => false,
        [1, 0, 0, 0] => true,
        _ => return Err(CacheError::Header("far side neither 0 nor 1")),
    };
    if u64_at(body, 16) != key.mesh {
        return Err(CacheError::Header("made for another mesh"));
    }
    if u64_at(body, 24) != key.params {
        return Err(CacheError::Header("made with other grid parameters"));
    }
    let w: Vec<u64> = (0..13).map(|k| u64_at(body, 32 + 8 * k)).collect();
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let placed = w[..3] == bits(&g.origin)[..]
        && w[3] == g.h.to_bits()
        && w[4..7] == g.n.map(|n| n as u64)[..]
        && w[7..13] == bits(g.bounds.as_flattened())[..];
    if !placed {
        return Err(CacheError::Header("the grid's place is not this mesh's"));
    }
    let values = &body[HEADER..HEADER + 4 * total];
    let loose: Vec<u64> = body[HEADER + 4 * total..]
        .chunks_exact(8)
        .map(|c| u64_at(c, 0))
        .collect();
    let h32 = super::field_build::down(g.h);
    // Decoded and checked in one pass (in parallel it cost more than it saved).
    let mut lo: Vec<f32> = Vec::with_capacity(total);
    for (k, c) in values.chunks_exact(4).enumerate() {
        let v = f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
        let is_loose = loose[k / 64] >> (k % 64) & 1 == 1;
        // A loose node is at least `h` from the surface: its bound is at least `h` there.
        if !v.is_finite() || (is_loose && v.abs() < h32) {
            return Err(CacheError::Value(k));
        }
        lo.push(v);
    }
    if (lo[0] > 0.0) != far_free {
        return Err(CacheError::Header(
            "far side's sign is not its first node's",
        ));
    }
    let f = SolidField {
        origin: g.origin,
        h: g.h,
        n: g.n,
        lo,
        loose,
        bounds: g.bounds,
        far_free,
    };
    spot_check(&f, mesh, u64_at(sum, 0))?;
    Ok(f)
}

/// [`SPOT`] nodes projected on `mesh` again: each stored value within its bounds of the exact
/// signed distance (half the nodes the first exact one from a random start).
fn spot_check(f: &SolidField, mesh: &TriMesh, seed: u64) -> Result<(), CacheError> {
    let total = f.lo.len();
    let mut s = seed | 1;
    let is_loose = |k: usize| f.loose[k / 64] >> (k % 64) & 1 == 1;
    let nodes: Vec<usize> = (0..SPOT)
        .map(|i| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let k = (s % total as u64) as usize;
            if i % 2 == 1 {
                return k;
            }
            (k..total).chain(0..k).find(|&j| !is_loose(j)).unwrap_or(k)
        })
        .collect();
    // Projected in parallel; the first node (in the drawn order) that fails is named.
    let failed = nodes.par_iter().find_map_first(|&k| {
        let (x, y, z) = (k % f.n[0], (k / f.n[0]) % f.n[1], k / (f.n[0] * f.n[1]));
        let p = PVec::new(
            f.origin[0] + x as f64 * f.h,
            f.origin[1] + y as f64 * f.h,
            f.origin[2] + z as f64 * f.h,
        );
        let (proj, _) = mesh.project_local_point_and_get_location(p, false);
        let d = (p - proj.point).length();
        let exact = if proj.is_inside { -d } else { d };
        let stored = f64::from(f.lo[k]);
        let up = if is_loose(k) { LOOSE * f.h } else { 0.0 };
        let tol = 1e-9 * (f.h + d) + stored.abs() * f64::from(f32::EPSILON);
        (exact < stored - tol || exact > stored + up + tol).then_some(CacheError::SpotCheck {
            node: k,
            stored,
            exact,
        })
    });
    failed.map_or(Ok(()), Err)
}

/// The grid of the solid `mesh` with `nodes` nodes: read from `dir` when a good file is there,
/// else built and written there (module docs); and how it came.
pub fn load_or_build(
    mesh: &TriMesh,
    nodes: usize,
    dir: Option<&Path>,
) -> (SolidField, FieldOrigin) {
    let Some(dir) = dir else {
        return (SolidField::build(mesh, nodes), FieldOrigin::Built);
    };
    let key = Key::of(mesh, nodes);
    let path = dir.join(key.file_name());
    let refused = match read(&path, key, mesh, nodes) {
        Ok(Some(f)) => return (f, FieldOrigin::Loaded(path)),
        Ok(None) => None,
        Err(e) => Some(e.to_string()),
    };
    let f = SolidField::build(mesh, nodes);
    let origin = match crate::output::write_file(&path, encode(&f, key)) {
        Err(e) => FieldOrigin::NotWritten {
            path,
            reason: e.to_string(),
        },
        Ok(()) => match refused {
            Some(reason) => FieldOrigin::Rebuilt { path, reason },
            None => FieldOrigin::Written(path),
        },
    };
    (f, origin)
}

/// The checked grid in the file at `path`; `None` when there is no file.
fn read(
    path: &Path,
    key: Key,
    mesh: &TriMesh,
    nodes: usize,
) -> Result<Option<SolidField>, CacheError> {
    use std::io::Read;
    let file = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(CacheError::Io(e.to_string())),
    };
    let expected = file_size(Grid::of(mesh, nodes).total()) as u64;
    let found = file
        .metadata()
        .map_err(|e| CacheError::Io(e.to_string()))?
        .len();
    if found != expected {
        return Err(CacheError::Size { expected, found });
    }
    let mut bytes = Vec::with_capacity(expected as usize);
    file.take(expected)
        .read_to_end(&mut bytes)
        .map_err(|e| CacheError::Io(e.to_string()))?;
    decode(&bytes, key, mesh, nodes).map(Some)
}

static NOTES: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Record a warning about the cache for the front end to print ([`take_notes`]).
pub(crate) fn note(origin: &FieldOrigin, mesh: &str) {
    let text = match origin {
        FieldOrigin::Rebuilt { path, reason } => format!(
            "the cached grid of mesh `{mesh}` ({}) was refused ({reason}) and rebuilt",
            path.display()
        ),
        FieldOrigin::NotWritten { path, reason } => format!(
            "the grid of mesh `{mesh}` could not be cached at {} ({reason})",
            path.display()
        ),
        _ => return,
    };
    if let Ok(mut n) = NOTES.lock() {
        n.push(text);
    }
}

/// The cache's warnings since the last call (a refused file, a file that could not be
/// written), for a front end to print; the library prints nothing.
pub fn take_notes() -> Vec<String> {
    NOTES
        .lock()
        .map(|mut n| std::mem::take(&mut *n))
        .unwrap_or_default()
}

#[cfg(test)]
#[path = "field_cache_tests.rs"]
mod tests;
