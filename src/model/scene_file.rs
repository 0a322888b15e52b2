//! Reading a scene file (format: [`super::scene`]): TOML, or JSON for a file named
//! `*.json`, parsed into one typed form ([`FileScene`]), then every obstacle checked (errors
//! name `obstacles[k].field`) and built into its parry shape, pose and bounds. A TOML scene of
//! the plain shape is read straight from the parser's events ([`scene_toml`]).

use super::mesh::Free;
use super::scene::{Obstacle, ObstacleKind, Scene};
use crate::contact::field_cache::FieldCache;
use crate::error::ModelError;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use parry3d::math::{Pose, Vector as PVec};
use parry3d::shape::{Ball, Capsule, Cuboid, Cylinder, SharedShape};
use serde::Deserialize;
use std::path::Path;

#[path = "scene_toml.rs"]
mod scene_toml;

impl Scene {
    /// Read a scene file (`clearance` and `[[obstacles]]`); mesh paths are relative to it.
    /// A file named `*.json` is read as JSON with the same fields and checks
    /// ([`crate::model::scene`]).
    pub fn from_file(path: impl AsRef<Path>) -> Result<Scene, ModelError> {
        Self::from_file_as(path.as_ref(), "scene file")
    }

    /// [`Scene::from_file`], the file listed in [`Scene::files`] as `role` (what it is to the
    /// run that reads it, e.g. `scene file named in the model`).
    pub fn from_file_as(path: &Path, role: &str) -> Result<Scene, ModelError> {
        let text = super::read::read_text(path, "scene file")?;
        let json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let parsed = if json {
            parse_json(&text)
        } else {
            parse_toml(&text)
        };
        let file: FileScene = parsed.map_err(|reason| ModelError::Parse {
            path: path.display().to_string(),
            reason: reason.trim_end().to_string(),
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let mut scene = Scene::from_parts(file.clearance, &file.obstacles, dir, "")?;
        scene
            .files
            .insert(0, (role.to_string(), path.to_path_buf()));
        Ok(scene)
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
        let mut files = Vec::new();
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
            if let ObstacleKind::Mesh { path, .. } = &ob.kind {
                files.push((format!("mesh file of obstacle `{}`", ob.name), path.clone()));
            }
            out.push(ob);
        }
        Ok(Scene {
            clearance,
            obstacles: out,
            files,
        })
    }
}

/// A TOML scene: the plain shape of a scene file in one pass over the parser's events
/// ([`scene_toml`], 18.3 M instead of 34.6 M instructions for 1000 obstacles), anything else
/// — and every error, with its message — through `toml::from_str`, which builds a document
/// tree before serde reads it. Both give the same [`FileScene`] wherever the first gives one.
fn parse_toml(text: &str) -> Result<FileScene, String> {
    match scene_toml::plain_scene(text) {
        Some(file) => Ok(file),
        None => toml::from_str(text).map_err(|e| e.to_string()),
    }
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

/// A rotation as a file writes it: `{ rpy = [roll, pitch, yaw] }` or
/// `{ quaternion = [w, x, y, z] }` (obstacles, the port).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub(crate) enum FileRotation {
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
    /// A mesh's free side: `inside` (a lumen) or `outside` (an organ); absent: a surface.
    pub(super) free: Option<String>,
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

/// A file's rotation (roll–pitch–yaw or a quaternion, normalized); identity if none. `name`
/// turns `rotation.rpy` / `rotation.quaternion` into the field's full name for errors.
pub(crate) fn quaternion(
    r: Option<&FileRotation>,
    name: &dyn Fn(&str) -> String,
) -> Result<UnitQuaternion<f64>, ModelError> {
    Ok(match r {
        None => UnitQuaternion::identity(),
        Some(FileRotation::Rpy(r)) => {
            if r.iter().any(|x| !x.is_finite()) {
                return Err(ModelError::invalid(name("rotation.rpy"), "must be finite"));
            }
            UnitQuaternion::from_euler_angles(r[0], r[1], r[2])
        }
        Some(FileRotation::Quaternion(q)) => {
            let n = (q.iter().map(|x| x * x).sum::<f64>()).sqrt();
            if !n.is_finite() || n < 1e-9 {
                return Err(ModelError::invalid(
                    name("rotation.quaternion"),
                    "must be a finite, non-zero [w, x, y, z]",
                ));
            }
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]))
        }
    })
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
            Some(n) => {
                super::name::check_name(at.name("name"), n)?;
                n.clone()
            }
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
            field: Default::default(),
            field_cache: FieldCache::from_env(),
        })
    }

    /// The rotation as written (roll–pitch–yaw or a quaternion, normalized); identity if none.
    fn rotation(&self, at: Field) -> Result<UnitQuaternion<f64>, ModelError> {
        quaternion(self.rotation.as_ref(), &|n| at.name(n))
    }

    /// Refuses a size given that this shape does not have (it would be silently ignored).
    fn only(&self, at: Field, names: &[&str]) -> Result<(), ModelError> {
        let given = [
            ("radius", self.radius.is_some()),
            ("half_extents", self.half_extents.is_some()),
            ("half_height", self.half_height.is_some()),
            ("path", self.path.is_some()),
            ("scale", self.scale.is_some()),
            ("free", self.free.is_some()),
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
        self.only(at, &["path", "scale", "free"])?;
        let free = match self.free.as_deref() {
            None => None,
            Some("inside") => Some(Free::Inside),
            Some("outside") => Some(Free::Outside),
            Some(other) => {
                return Err(ModelError::invalid(
                    at.name("free"),
                    format!("`{other}`: use inside (a lumen) or outside (an organ to avoid)"),
                ))
            }
        };
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
        let cannot = |reason: String| {
            ModelError::invalid(
                at.name("path"),
                format!("cannot load mesh `{}`: {reason}", full.display()),
            )
        };
        let (verts, tris) = crate::model::mesh::load(&full).map_err(|e| cannot(e.to_string()))?;
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
        // A solid: closed and wound outward (after the scale, which may mirror it).
        let tris = match free {
            None => tris,
            Some(_) => super::mesh_check::solid(&verts, &tris).map_err(|e| {
                ModelError::invalid(
                    at.name("free"),
                    format!("mesh `{}` is not a solid: {e}", full.display()),
                )
            })?,
        };
        let tm = super::mesh::trimesh(&verts, &tris, free).map_err(|e| {
            ModelError::invalid(
                at.name("path"),
                format!("mesh `{}` is not usable: {e}", full.display()),
            )
        })?;
        Ok((
            ObstacleKind::Mesh {
                path: full,
                vertices: verts,
                triangles: tris,
                free,
            },
            SharedShape::new(tm),
            pose,
        ))
    }
}
