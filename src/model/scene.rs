//! Obstacles around the robot: parry3d shapes with poses, read from model or scene files.
//!
//! ```toml
//! clearance = 0.0005            # every robot feature keeps this distance \[m\] (default 0)
//! [[obstacles]]
//! name = "wall"                 # optional (default: obstacle<k>)
//! shape = "box"                 # sphere | box | capsule | cylinder | mesh
//! position = [0.09, 0.0, 0.1]
//! rotation = { rpy = [0.0, 0.0, 0.0] }   # or { quaternion = [w, x, y, z] }; default identity
//! half_extents = [0.005, 0.05, 0.05]      # box
//! # radius = 0.01                          # sphere, capsule, cylinder
//! # half_height = 0.02                     # capsule, cylinder: along their local z axis
//! # path = "meshes/vessel.obj"; scale = 1.0 (or [sx, sy, sz])   # mesh (STL, OBJ or PLY)
//! # free = "inside"                      # a closed mesh: a lumen (or "outside": an organ)
//! ```
//!
//! The same scene as JSON, in a file named `*.json`: the same fields, defaults and checks,
//! read straight into the same typed form (a scene exported by another program, or one of
//! thousands of obstacles, where JSON parses in half the instructions of TOML; user's
//! guide, obstacles). A JSON parse error is prefixed with the path of the field
//! (`obstacles[3].radius: invalid type: string "a", expected f64 at line 9 column 20`).
//!
//! ```json
//! {"clearance": 0.0005,
//!  "obstacles": [{"name": "wall", "shape": "box", "position": [0.09, 0.0, 0.1],
//!                 "rotation": {"rpy": [0.0, 0.0, 0.0]}, "half_extents": [0.005, 0.05, 0.05]}]}
//! ```
//!
//! Obstacles live in a robot file (`[[obstacles]]`, `clearance`), in a scene file referenced
//! by the robot file (`scene = "scenes/wall.toml"`, relative to the robot file) or passed with
//! `--scene`. Capsules and cylinders are given along their local **z** axis (the robot's
//! convention) and turned into parry's y-axis shapes here. Distances use parry3d-f64.

//!
//! Reading and checking a scene file is `scene_file.rs` ([`Scene::from_file`]); this file is
//! what a scene is and the broad-phase queries on it.

use crate::contact::field::{nodes_for, SolidField};
pub use crate::contact::field_cache::{FieldCache, FieldOrigin};
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Vector3};
use parry3d::math::Pose;
use parry3d::shape::SharedShape;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

/// What an obstacle is, with its sizes (kept for drawing and export).
#[derive(Debug, Clone, PartialEq)]
pub enum ObstacleKind {
    /// A ball.
    Sphere {
        /// Radius \[m\].
        radius: f64,
    },
    /// A box.
    Box {
        /// Half extents \[m\].
        half_extents: Vector3<f64>,
    },
    /// A capsule along local z.
    Capsule {
        /// Radius \[m\].
        radius: f64,
        /// Half length of the axis segment \[m\].
        half_height: f64,
    },
    /// A cylinder along local z.
    Cylinder {
        /// Radius \[m\].
        radius: f64,
        /// Half height \[m\].
        half_height: f64,
    },
    /// A triangle mesh (vertices already scaled, in the obstacle frame).
    Mesh {
        /// Source file.
        path: PathBuf,
        /// Vertices \[m\].
        vertices: Vec<Vector3<f64>>,
        /// Triangles (a solid's wound outward).
        triangles: Vec<[u32; 3]>,
        /// Which side is free, for a closed mesh declared a solid; `None`: a surface
        /// (unsigned distances).
        free: Option<crate::model::mesh::Free>,
    },
}

/// A solid's grid and how it came.
pub(crate) type PreparedField = (Arc<SolidField>, FieldOrigin);

/// One obstacle.
#[derive(Clone)]
pub struct Obstacle {
    /// Name (unique in the scene).
    pub name: String,
    /// Shape and sizes.
    pub kind: ObstacleKind,
    /// Pose in the robot's base frame.
    pub pose: Isometry3<f64>,
    /// The parry shape (in its own frame; `parry_pose` places it).
    pub shape: SharedShape,
    /// Pose handed to parry (includes the z → y axis turn of capsules and cylinders).
    pub parry_pose: Pose,
    /// Axis-aligned bounds in the base frame: (min, max).
    pub aabb: (Vector3<f64>, Vector3<f64>),
    /// A solid mesh's signed-distance grid, built (or read from the cache) on first use and
    /// shared by every copy of the obstacle (`contact/field.rs`), with how it came.
    pub(crate) field: Arc<OnceLock<Option<PreparedField>>>,
    /// Where that grid is cached (`contact/field_cache.rs`).
    pub(crate) field_cache: FieldCache,
}

impl std::fmt::Debug for Obstacle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Obstacle")
            .field("name", &self.name)
            .field("kind", &self.kind)
            .field("pose", &self.pose)
            .finish()
    }
}

/// Obstacles near the robot.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// Minimum distance every robot feature keeps from every obstacle \[m\].
    pub clearance: f64,
    /// The obstacles.
    pub obstacles: Vec<Obstacle>,
    /// The files this scene was read from, each with what it was ([`Scene::files`]).
    pub(crate) files: Vec<(String, PathBuf)>,
}

impl Scene {
    /// A scene with no obstacles.
    pub fn empty() -> Self {
        Scene::default()
    }
    /// True when there are no obstacles.
    pub fn is_empty(&self) -> bool {
        self.obstacles.is_empty()
    }

    /// The same obstacles seen from another frame: every obstacle's pose premultiplied by
    /// `iso` (`iso` maps this scene's frame into the new one). The parry shapes are shared,
    /// not copied; each bound is the shape's own in its new pose.
    pub fn transformed(&self, iso: &Isometry3<f64>) -> Scene {
        Scene {
            clearance: self.clearance,
            obstacles: self.obstacles.iter().map(|o| o.transformed(iso)).collect(),
            files: self.files.clone(),
        }
    }

    /// The same scene with every obstacle's grid cached in `cache`
    /// ([`Obstacle::with_field_cache`]).
    pub fn with_field_cache(&self, cache: &FieldCache) -> Scene {
        Scene {
            clearance: self.clearance,
            obstacles: self
                .obstacles
                .iter()
                .map(|o| o.with_field_cache(cache.clone()))
                .collect(),
            files: self.files.clone(),
        }
    }

    /// Append another scene's obstacles (the larger clearance wins).
    pub fn merge(&mut self, other: Scene) {
        self.clearance = self.clearance.max(other.clearance);
        self.obstacles.extend(other.obstacles);
        self.files.extend(other.files);
    }

    /// The files this scene was read from, each with what it was to the scene: the scene
    /// file itself (`scene file`, or `scene file named in the model`) and every mesh file an
    /// obstacle names (`mesh file of obstacle `NAME``), as the paths that were opened (relative
    /// ones joined to their file's folder). A run lists them among its inputs, so that none
    /// is overwritten by one of its outputs ([`crate::output::RunFiles::read`]). Empty for a
    /// scene built in code.
    pub fn files(&self) -> &[(String, PathBuf)] {
        &self.files
    }

    /// Broad phase: indices of the obstacles whose bounds come within `radius` of `center`.
    pub fn near(&self, center: &Vector3<f64>, radius: f64) -> Vec<usize> {
        self.obstacles
            .iter()
            .enumerate()
            .filter(|(_, o)| aabb_ball_distance(&o.aabb, center) <= radius)
            .map(|(k, _)| k)
            .collect()
    }

    /// Distance from `center` to the axis-aligned bounds of obstacle `k` (0 inside them,
    /// infinite for an index out of range): a lower bound on the distance to the obstacle.
    pub fn bounds_distance(&self, k: usize, center: &Vector3<f64>) -> f64 {
        self.obstacles
            .get(k)
            .map_or(f64::INFINITY, |o| aabb_ball_distance(&o.aabb, center))
    }

    /// Distance between the axis-aligned box `lo..hi` and the bounds of obstacle `k` (0 when
    /// they overlap, infinite for an index out of range): a lower bound on the distance from
    /// anything inside the box to the obstacle.
    pub fn bounds_gap(&self, k: usize, lo: &Vector3<f64>, hi: &Vector3<f64>) -> f64 {
        self.obstacles
            .get(k)
            .map_or(f64::INFINITY, |o| aabb_gap(&o.aabb, lo, hi))
    }

    /// Broad phase on a subset: the indices in `among` (e.g. an earlier [`Scene::near`]
    /// result) whose bounds come within `radius` of `center`. Linear in `among.len()`, so a
    /// per-section test costs nothing when the robot-level test kept no obstacle.
    pub fn near_among(&self, among: &[usize], center: &Vector3<f64>, radius: f64) -> Vec<usize> {
        among
            .iter()
            .copied()
            .filter(|&k| {
                self.obstacles
                    .get(k)
                    .is_some_and(|o| aabb_ball_distance(&o.aabb, center) <= radius)
            })
            .collect()
    }

    /// The indices of `among` without exact duplicates: an obstacle with the same geometry
    /// to the bit as an earlier one in `among` ([`Obstacle::same_geometry`]; names aside) is
    /// left out, the first of each group kept, the order kept. Exact for every contact
    /// constraint: duplicates give the same constraint twice, the same feasible set and the
    /// same minimizers, so a solve that queries one copy is the solve of the scene with one
    /// (to the bit). Linear in `among.len()` (hashing; equal hashes compared in full).
    pub fn distinct(&self, among: Vec<usize>) -> Vec<usize> {
        use std::collections::hash_map::{DefaultHasher, HashMap};
        use std::hash::Hasher;
        if among.len() < 2 {
            return among;
        }
        let mut groups: HashMap<u64, Vec<usize>> = HashMap::with_capacity(among.len());
        let mut out = Vec::with_capacity(among.len());
        for k in among {
            let Some(o) = self.obstacles.get(k) else {
                continue;
            };
            let mut h = DefaultHasher::new();
            o.geometry_words().for_each(|w| h.write_u64(w));
            let group = groups.entry(h.finish()).or_default();
            if group.iter().any(|&j| self.obstacles[j].same_geometry(o)) {
                continue;
            }
            group.push(k);
            out.push(k);
        }
        out
    }

    /// How many obstacles are exact duplicates of an earlier one ([`Scene::distinct`]).
    pub fn exact_duplicates(&self) -> usize {
        let n = self.obstacles.len();
        n - self.distinct((0..n).collect()).len()
    }
}

/// Distance from the point `c` to the box `aabb` (min and max corners; 0 inside it).
pub(crate) fn aabb_ball_distance(aabb: &(Vector3<f64>, Vector3<f64>), c: &Vector3<f64>) -> f64 {
    let mut d2 = 0.0;
    for k in 0..3 {
        let v = if c[k] < aabb.0[k] {
            aabb.0[k] - c[k]
        } else if c[k] > aabb.1[k] {
            c[k] - aabb.1[k]
        } else {
            0.0
        };
        d2 += v * v;
    }
    d2.sqrt()
}

/// Distance between the box `aabb` (min and max corners) and the box `lo..hi` (0 when they
/// overlap).
pub(crate) fn aabb_gap(
    aabb: &(Vector3<f64>, Vector3<f64>),
    lo: &Vector3<f64>,
    hi: &Vector3<f64>,
) -> f64 {
    let mut d2 = 0.0;
    for a in 0..3 {
        let g = (aabb.0[a] - hi[a]).max(lo[a] - aabb.1[a]).max(0.0);
        d2 += g * g;
    }
    d2.sqrt()
}

impl Obstacle {
    /// The signed-distance grid of a solid mesh (built or read from the cache on the first
    /// call, then shared); `None` for any other shape. A solid of at least
    /// [`MIN_CACHED_TRIANGLES`](crate::contact::field_cache::MIN_CACHED_TRIANGLES) triangles
    /// is cached in [`Obstacle::field_cache`]'s folder; a refused or unwritable cache file is
    /// noted for the front end (`contact::field_cache::take_notes`).
    pub fn field(&self) -> Option<&SolidField> {
        self.field
            .get_or_init(|| {
                let mesh = crate::contact::solid::solid(&*self.shape)?;
                let tris = mesh.num_triangles();
                let dir = match &self.field_cache {
                    FieldCache::Dir(d)
                        if tris >= crate::contact::field_cache::MIN_CACHED_TRIANGLES =>
                    {
                        Some(d.as_path())
                    }
                    _ => None,
                };
                let (f, origin) =
                    crate::contact::field_cache::load_or_build(mesh, nodes_for(tris), dir);
                crate::contact::field_cache::note(&origin, &self.name);
                Some((Arc::new(f), origin))
            })
            .as_ref()
            .map(|(f, _)| &**f)
    }

    /// How [`Obstacle::field`]'s grid came (built, read from the cache, ...); `None` before
    /// its first use and for any shape but a solid mesh.
    pub fn field_origin(&self) -> Option<&FieldOrigin> {
        self.field.get()?.as_ref().map(|(_, o)| o)
    }

    /// Where this obstacle's grid is cached (from the environment when the scene was read:
    /// [`FieldCache::from_env`]).
    pub fn field_cache(&self) -> &FieldCache {
        &self.field_cache
    }

    /// The same obstacle with its grid cached in `cache`, its grid not yet made: the copy
    /// prepares its own on first use.
    pub fn with_field_cache(&self, cache: FieldCache) -> Obstacle {
        Obstacle {
            field: Default::default(),
            field_cache: cache,
            ..self.clone()
        }
    }

    /// [`Obstacle::field`], shared.
    pub(crate) fn field_shared(&self) -> Option<Arc<SolidField>> {
        self.field();
        self.field.get()?.as_ref().map(|(f, _)| f.clone())
    }

    /// Polylines on the obstacle's surface in the base frame, for drawing.
    pub fn wireframe(&self) -> Vec<Vec<Vector3<f64>>> {
        let circle = |r: f64, z: f64, axis: usize| -> Vec<Vector3<f64>> {
            (0..=32)
                .map(|j| {
                    let a = j as f64 / 32.0 * std::f64::consts::TAU;
                    let (c, s) = (r * a.cos(), r * a.sin());
                    let v = match axis {
                        0 => Vector3::new(z, c, s),
                        1 => Vector3::new(c, z, s),
                        _ => Vector3::new(c, s, z),
                    };
                    self.pose * Point3::from(v)
                })
                .map(|p| p.coords)
                .collect()
        };
        let line = |a: Vector3<f64>, b: Vector3<f64>| {
            vec![
                (self.pose * Point3::from(a)).coords,
                (self.pose * Point3::from(b)).coords,
            ]
        };
        match &self.kind {
            ObstacleKind::Sphere { radius } => (0..3).map(|ax| circle(*radius, 0.0, ax)).collect(),
            ObstacleKind::Box { half_extents: h } => {
                let mut out = vec![];
                for (i, j) in [(0usize, 1usize), (0, 2), (1, 2)] {
                    let k = 3 - i - j;
                    for si in [-1.0, 1.0] {
                        for sj in [-1.0, 1.0] {
                            let mut a = Vector3::zeros();
                            a[i] = si * h[i];
                            a[j] = sj * h[j];
                            let mut b = a;
                            a[k] = -h[k];
                            b[k] = h[k];
                            out.push(line(a, b));
                        }
                    }
                }
                out
            }
            ObstacleKind::Cylinder {
                radius,
                half_height,
            }
            | ObstacleKind::Capsule {
                radius,
                half_height,
            } => {
                let mut out = vec![
                    circle(*radius, -half_height, 2),
                    circle(*radius, *half_height, 2),
                ];
                for j in 0..8 {
                    let a = j as f64 / 8.0 * std::f64::consts::TAU;
                    let (c, s) = (radius * a.cos(), radius * a.sin());
                    out.push(line(
                        Vector3::new(c, s, -half_height),
                        Vector3::new(c, s, *half_height),
                    ));
                }
                out
            }
            ObstacleKind::Mesh {
                vertices,
                triangles,
                ..
            } => {
                // At most ~600 triangle outlines, evenly picked, keep the picture readable.
                let step = (triangles.len() / 600).max(1);
                triangles
                    .iter()
                    .step_by(step)
                    .map(|t| {
                        [t[0], t[1], t[2], t[0]]
                            .iter()
                            .map(|&i| (self.pose * Point3::from(vertices[i as usize])).coords)
                            .collect()
                    })
                    .collect()
            }
        }
    }

    /// True when `other` has the same geometry to the bit: the same kind, sizes (mesh
    /// vertices and triangles) and pose; names and mesh paths aside.
    pub fn same_geometry(&self, other: &Obstacle) -> bool {
        self.geometry_words().eq(other.geometry_words())
    }

    /// The obstacle's geometry as words: a kind tag, the sizes' and the pose's bits (a mesh:
    /// its vertex and triangle counts, then every vertex and triangle).
    fn geometry_words(&self) -> Box<dyn Iterator<Item = u64> + '_> {
        let t = &self.pose.translation.vector;
        let q = &self.pose.rotation.coords;
        let pose = [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(f64::to_bits);
        let (tag, sizes): (u64, Vec<f64>) = match &self.kind {
            ObstacleKind::Sphere { radius } => (0, vec![*radius]),
            ObstacleKind::Box { half_extents: h } => (1, vec![h.x, h.y, h.z]),
            ObstacleKind::Capsule {
                radius,
                half_height,
            } => (2, vec![*radius, *half_height]),
            ObstacleKind::Cylinder {
                radius,
                half_height,
            } => (3, vec![*radius, *half_height]),
            ObstacleKind::Mesh {
                vertices,
                triangles,
                free,
                ..
            } => {
                let side = free.map_or(0, |f| 1 + f as u64);
                let head = [4, vertices.len() as u64, triangles.len() as u64, side];
                let v = vertices
                    .iter()
                    .flat_map(|v| [v.x, v.y, v.z].map(f64::to_bits));
                let t = triangles.iter().flat_map(|t| t.map(u64::from));
                return Box::new(head.into_iter().chain(pose).chain(v).chain(t));
            }
        };
        Box::new(
            std::iter::once(tag)
                .chain(pose)
                .chain(sizes.into_iter().map(f64::to_bits)),
        )
    }

    /// The obstacle posed by `iso` after its own pose (see [`Scene::transformed`]).
    pub fn transformed(&self, iso: &Isometry3<f64>) -> Obstacle {
        let pose = iso * self.pose;
        let by: Pose = (*iso).into();
        let parry_pose = by * self.parry_pose;
        let a = self.shape.compute_aabb(&parry_pose);
        Obstacle {
            pose,
            parry_pose,
            aabb: (
                Vector3::new(a.mins.x, a.mins.y, a.mins.z),
                Vector3::new(a.maxs.x, a.maxs.y, a.maxs.z),
            ),
            ..self.clone()
        }
    }

    /// Rotation of the obstacle as a matrix.
    pub fn rotation(&self) -> Matrix3<f64> {
        Rotation3::from(self.pose.rotation).into_inner()
    }
}
