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
//! # path = "meshes/vessel.obj"; scale = 1.0 (or [sx, sy, sz])   # mesh (STL or OBJ)
//! ```
//!
//! The same scene as JSON, in a file named `*.json`: the same fields, defaults and checks,
//! read straight into the same typed form (a scene exported by another program, or one of
//! thousands of obstacles, where JSON parses several times faster than TOML; README,
//! "Large scenes"). A JSON parse error is prefixed with the path of the field
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

use crate::error::ModelError;
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use parry3d::math::{Pose, Vector as PVec};
use parry3d::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape, TriMesh};
use serde::Deserialize;
use std::path::{Path, PathBuf};

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
        /// Triangles.
        triangles: Vec<[u32; 3]>,
    },
}

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

    /// Read a scene file (`clearance` and `[[obstacles]]`); mesh paths are relative to it.
    /// A file named `*.json` is read as JSON with the same fields and checks (module docs).
    pub fn from_file(path: impl AsRef<Path>) -> Result<Scene, ModelError> {
        let path = path.as_ref();
        let text = super::read::read_text(path, "scene file")?;
        let json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let parsed = if json {
            parse_json(&text)
        } else {
            toml::from_str(&text).map_err(|e| e.to_string())
        };
        let file: FileScene = parsed.map_err(|reason| ModelError::Parse {
            path: path.display().to_string(),
            reason: reason.trim_end().to_string(),
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        Scene::from_parts(file.clearance, &file.obstacles, dir, "")
    }

    /// Build from parsed file parts; `prefix` is prepended to field names in errors.
    pub(crate) fn from_parts(
        clearance: Option<f64>,
        obstacles: &[FileObstacle],
        dir: &Path,
        prefix: &str,
    ) -> Result<Scene, ModelError> {
        let clearance = match clearance {
            None => 0.0,
            Some(c) => super::bounds::CLEARANCE.check(&format!("{prefix}clearance"), c)?,
        };
        let mut out: Vec<Obstacle> = Vec::with_capacity(obstacles.len());
        // Names seen so far: a hash set keeps a scene of thousands of obstacles linear.
        let mut names = std::collections::HashSet::with_capacity(obstacles.len());
        for (k, o) in obstacles.iter().enumerate() {
            let at = Field { prefix, k };
            let ob = o.build(at, dir)?;
            if !names.insert(ob.name.clone()) {
                return Err(ModelError::invalid(
                    at.name("name"),
                    format!("two obstacles are named `{}`", ob.name),
                ));
            }
            out.push(ob);
        }
        Ok(Scene {
            clearance,
            obstacles: out,
        })
    }

    /// Append another scene's obstacles (the larger clearance wins).
    pub fn merge(&mut self, other: Scene) {
        self.clearance = self.clearance.max(other.clearance);
        self.obstacles.extend(other.obstacles);
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
        self.obstacles.get(k).map_or(f64::INFINITY, |o| {
            let mut d2 = 0.0;
            for a in 0..3 {
                let g = (o.aabb.0[a] - hi[a]).max(lo[a] - o.aabb.1[a]).max(0.0);
                d2 += g * g;
            }
            d2.sqrt()
        })
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
}

fn aabb_ball_distance(aabb: &(Vector3<f64>, Vector3<f64>), c: &Vector3<f64>) -> f64 {
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

/// A JSON scene: serde_json into the same typed [`FileScene`] as TOML (no intermediate
/// value tree). On an error the text is parsed once more with `serde_path_to_error` (which
/// allocates every key, so not on the path that succeeds), to prefix the message with the
/// path of the field that failed (`obstacles[3].radius: invalid type …`).
fn parse_json(text: &str) -> Result<FileScene, String> {
    let plain = match serde_json::from_str(text) {
        Ok(file) => return Ok(file),
        Err(e) => e.to_string(),
    };
    let mut de = serde_json::Deserializer::from_str(text);
    match serde_path_to_error::deserialize::<_, FileScene>(&mut de) {
        Err(e) if e.path().to_string() != "." => Err(format!("{}: {}", e.path(), e.inner())),
        // At the top level, or after the value (trailing text): the plain message.
        _ => Err(plain),
    }
}

/// A scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileScene {
    clearance: Option<f64>,
    #[serde(default)]
    obstacles: Vec<FileObstacle>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
enum FileRotation {
    Rpy([f64; 3]),
    Quaternion([f64; 4]),
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum FileScale {
    Uniform(f64),
    PerAxis([f64; 3]),
}

/// One `[[obstacles]]` entry as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FileObstacle {
    name: Option<String>,
    shape: String,
    #[serde(default)]
    position: Option<[f64; 3]>,
    rotation: Option<FileRotation>,
    radius: Option<f64>,
    half_extents: Option<[f64; 3]>,
    half_height: Option<f64>,
    path: Option<String>,
    scale: Option<FileScale>,
}

/// Where obstacle `k` stands in its file (`{prefix}obstacles[{k}]`); field names are
/// formatted only when an error needs one.
#[derive(Clone, Copy)]
struct Field<'a> {
    prefix: &'a str,
    k: usize,
}

impl Field<'_> {
    fn name(&self, n: &str) -> String {
        format!("{}obstacles[{}].{n}", self.prefix, self.k)
    }
}

/// A size: present and inside [`super::bounds::OBSTACLE_SIZE`].
fn size(at: Field, n: &str, v: Option<f64>) -> Result<f64, ModelError> {
    match v {
        None => Err(ModelError::invalid(at.name(n), "missing")),
        Some(x) if super::bounds::OBSTACLE_SIZE.accepts(x) => Ok(x),
        Some(x) => super::bounds::OBSTACLE_SIZE.check(&at.name(n), x),
    }
}

/// An obstacle's shape as ccrkit keeps it, the parry shape, and the pose handed to parry.
type Built = (ObstacleKind, SharedShape, Isometry3<f64>);

impl FileObstacle {
    fn build(&self, at: Field, dir: &Path) -> Result<Obstacle, ModelError> {
        let name = match &self.name {
            Some(n) if n.trim().is_empty() => {
                return Err(ModelError::invalid(at.name("name"), "must not be empty"))
            }
            Some(n) => n.clone(),
            None => format!("obstacle{}", at.k),
        };
        let p = self.position.unwrap_or([0.0; 3]);
        let coordinate = super::bounds::COORDINATE;
        if !p.iter().all(|x| coordinate.accepts(*x)) {
            coordinate.check3(&at.name("position"), p)?;
        }
        let pose = Isometry3::from_parts(Translation3::new(p[0], p[1], p[2]), self.rotation(at)?);
        let (kind, shape, parry_iso) = match self.shape.as_str() {
            "sphere" => {
                self.only(at, &["radius"])?;
                let r = size(at, "radius", self.radius)?;
                (
                    ObstacleKind::Sphere { radius: r },
                    SharedShape::new(Ball::new(r)),
                    pose,
                )
            }
            "box" => self.cuboid(at, pose)?,
            "capsule" | "cylinder" => self.round(at, pose)?,
            "mesh" => self.mesh(at, dir, pose)?,
            other => {
                return Err(ModelError::invalid(
                    at.name("shape"),
                    format!("unknown shape `{other}`: use sphere, box, capsule, cylinder or mesh"),
                ))
            }
        };
        let parry_pose: Pose = parry_iso.into();
        let a = shape.compute_aabb(&parry_pose);
        let aabb = (
            Vector3::new(a.mins.x, a.mins.y, a.mins.z),
            Vector3::new(a.maxs.x, a.maxs.y, a.maxs.z),
        );
        Ok(Obstacle {
            name,
            kind,
            pose,
            shape,
            parry_pose,
            aabb,
        })
    }

    /// The rotation as written (roll–pitch–yaw or a quaternion, normalized); identity if none.
    fn rotation(&self, at: Field) -> Result<UnitQuaternion<f64>, ModelError> {
        Ok(match &self.rotation {
            None => UnitQuaternion::identity(),
            Some(FileRotation::Rpy(r)) => {
                if r.iter().any(|x| !x.is_finite()) {
                    return Err(ModelError::invalid(
                        at.name("rotation.rpy"),
                        "must be finite",
                    ));
                }
                UnitQuaternion::from_euler_angles(r[0], r[1], r[2])
            }
            Some(FileRotation::Quaternion(q)) => {
                let n = (q.iter().map(|x| x * x).sum::<f64>()).sqrt();
                if !n.is_finite() || n < 1e-9 {
                    return Err(ModelError::invalid(
                        at.name("rotation.quaternion"),
                        "must be a finite, non-zero [w, x, y, z]",
                    ));
                }
                UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]))
            }
        })
    }

    /// Refuses a size given that this shape does not have (it would be silently ignored).
    fn only(&self, at: Field, names: &[&str]) -> Result<(), ModelError> {
        let given = [
            ("radius", self.radius.is_some()),
            ("half_extents", self.half_extents.is_some()),
            ("half_height", self.half_height.is_some()),
            ("path", self.path.is_some()),
            ("scale", self.scale.is_some()),
        ];
        for (n, g) in given {
            if g && !names.contains(&n) {
                return Err(ModelError::invalid(
                    at.name(n),
                    format!("not a size of a {}", self.shape),
                ));
            }
        }
        Ok(())
    }

    fn cuboid(&self, at: Field, pose: Isometry3<f64>) -> Result<Built, ModelError> {
        self.only(at, &["half_extents"])?;
        let he = self
            .half_extents
            .ok_or_else(|| ModelError::invalid(at.name("half_extents"), "missing"))?;
        for (i, h) in he.iter().enumerate() {
            if !super::bounds::OBSTACLE_SIZE.accepts(*h) {
                size(at, &format!("half_extents[{i}]"), Some(*h))?;
            }
        }
        Ok((
            ObstacleKind::Box {
                half_extents: Vector3::new(he[0], he[1], he[2]),
            },
            SharedShape::new(Cuboid::new(PVec::new(he[0], he[1], he[2]))),
            pose,
        ))
    }

    /// A capsule or a cylinder: along our local z, turned onto parry's local y.
    fn round(&self, at: Field, pose: Isometry3<f64>) -> Result<Built, ModelError> {
        self.only(at, &["radius", "half_height"])?;
        let r = size(at, "radius", self.radius)?;
        let h = size(at, "half_height", self.half_height)?;
        let z_to_y =
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -std::f64::consts::FRAC_PI_2);
        let iso = pose * z_to_y;
        Ok(if self.shape == "capsule" {
            (
                ObstacleKind::Capsule {
                    radius: r,
                    half_height: h,
                },
                SharedShape::new(Capsule::new_y(h, r)),
                iso,
            )
        } else {
            (
                ObstacleKind::Cylinder {
                    radius: r,
                    half_height: h,
                },
                SharedShape::new(Cylinder::new(h, r)),
                iso,
            )
        })
    }

    /// A triangle mesh read from `path` (relative to `dir`), scaled, every vertex in range.
    fn mesh(&self, at: Field, dir: &Path, pose: Isometry3<f64>) -> Result<Built, ModelError> {
        self.only(at, &["path", "scale"])?;
        let rel = self
            .path
            .as_ref()
            .ok_or_else(|| ModelError::invalid(at.name("path"), "missing"))?;
        let full = dir.join(rel);
        let scale = match &self.scale {
            None => Vector3::new(1.0, 1.0, 1.0),
            Some(FileScale::Uniform(s)) => Vector3::new(*s, *s, *s),
            Some(FileScale::PerAxis(s)) => Vector3::new(s[0], s[1], s[2]),
        };
        for k in 0..3 {
            super::bounds::MESH_SCALE.check(&at.name("scale"), scale[k])?;
        }
        let (verts, tris) = crate::model::mesh::load(&full).map_err(|reason| {
            ModelError::invalid(
                at.name("path"),
                format!("cannot load mesh `{}`: {reason}", full.display()),
            )
        })?;
        let verts: Vec<Vector3<f64>> = verts.iter().map(|v| v.component_mul(&scale)).collect();
        if let Some(v) = verts
            .iter()
            .find(|v| v.amax() > super::bounds::COORDINATE.hi)
        {
            return Err(ModelError::invalid(
                at.name("scale"),
                format!(
                    "a scaled vertex lies at {:e} m, beyond the {:e} m ccrkit accepts",
                    v.amax(),
                    super::bounds::COORDINATE.hi
                ),
            ));
        }
        let pv: Vec<PVec> = verts.iter().map(|v| PVec::new(v.x, v.y, v.z)).collect();
        let tm = TriMesh::new(pv, tris.clone()).map_err(|e| {
            ModelError::invalid(
                at.name("path"),
                format!("mesh `{}` is not usable: {e:?}", full.display()),
            )
        })?;
        Ok((
            ObstacleKind::Mesh {
                path: full,
                vertices: verts,
                triangles: tris,
            },
            SharedShape::new(tm),
            pose,
        ))
    }
}

impl Obstacle {
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

    /// Rotation of the obstacle as a matrix.
    pub fn rotation(&self) -> Matrix3<f64> {
        Rotation3::from(self.pose.rotation).into_inner()
    }
}
