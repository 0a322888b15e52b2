//! URDF export of a solved [`Shape`]: a fixed snapshot, or an articulated chain whose joint
//! values (SRDF `group_state` + JSON) reproduce the solved disk frames.
//!
//! Units are metres and radians; every frame is the disk frame of [`DiskFrame`] (z along the disk
//! normal, x at hole angle 0). Links and joints:
//!
//! * `base_link` — the robot's base frame; `base_to_disk_0` (fixed) places `disk_0` where the
//!   shape puts it (the identity for every current method).
//! * **fixed mode** ([`UrdfMode::Fixed`], a snapshot for collision checking): one link per disk,
//!   `disk_{k-1}_to_disk_k` fixed joints whose `origin` is the solved relative transform
//!   `T_{k-1}⁻¹ T_k`: `xyz = R_{k-1}ᵀ (p_k − p_{k−1})`, `rpy = rpy(R_{k−1}ᵀ R_k)`.
//! * **articulated mode** ([`UrdfMode::Articulated`], for planners): section `i` (between disks
//!   `i−1` and `i`) is six joints, which together can represent *any* rigid motion of the disk
//!   (the geometric method tilts disks, and the backbone chord need not lie on the disk normal):
//!
//!   | joint | type | axis | child link | meaning |
//!   |---|---|---|---|---|
//!   | `section_i_bend_x` | revolute | x | `section_i_bend_x_link` | first bending angle `a` of the chord |
//!   | `section_i_bend_y` | revolute | y | `section_i_chord` | second bending angle `b`; the chord now runs along z |
//!   | `section_i_extension` | prismatic | z, origin `z = l0` | `section_i_chord_end` | chord length minus the nominal `l0` |
//!   | `section_i_tilt_x` | revolute | x | `section_i_tilt_x_link` | disk tilt against the chord |
//!   | `section_i_tilt_y` | revolute | y | `section_i_tilt_y_link` | disk tilt against the chord |
//!   | `section_i_twist` | revolute | z | `disk_i` | disk twist about the chord |
//!
//!   So `T_{i−1}⁻¹ T_i = Rx(a) Ry(b) · Trans(0, 0, l0 + e) · Rx(α) Ry(β) Rz(γ)`.
//!   A twist joint is always present (also for straight routing, where it is ~0): a planner
//!   then sees the same chain for every routing, and helically routed cables do twist disks.
//!   The extension is a prismatic joint rather than a fixed offset so that the URDF's *kinematic
//!   structure* depends only on the robot, and the shape lives entirely in the joint values
//!   (the geometric method keeps chords at `l0`, so `e ≈ 0`; rod models with extension differ).
//!   Limits: bends and tilts ±π/2, twist ±π, extension ±l0/2, each widened to contain the
//!   solved value; `effort` and `velocity` are a nominal 1 (the chain is kinematic).
//!   The SRDF holds group `backbone` (chain `base_link` → `disk_n`), the `group_state` named
//!   after the model with the solved values, and `disable_collisions` (reason `Adjacent`) for
//!   the pairs among `disk_{i−1}`, `section_i_chord`, `disk_i` and `section_{i+1}_chord`
//!   that touch by construction.
//!   Note: the paper's geometric method keeps each chord on the previous disk's normal (its
//!   tangent term is zero), so its shapes have `a = b ≈ 0` and live in the tilts and twist.
//!
//! **Joint-value extraction** ([`SectionJoints::from_frames`]). With `t = R_{i−1}ᵀ(p_i − p_{i−1})`,
//! `c = |t|`, `u = t/c`: `Rx(a) Ry(b) ẑ = (sin b, −sin a cos b, cos a cos b)`, so
//! `a = atan2(−u_y, u_z)`, then `v = Rx(−a) u = (sin b, 0, cos b)` gives `b = atan2(v_x, v_z)`;
//! `e = c − l0`. The disk's rotation relative to the chord frame is
//! `D = (Rx(a) Ry(b))ᵀ R_{i−1}ᵀ R_i = Rx(α) Ry(β) Rz(γ)`; `α = atan2(−D₁₂, D₂₂)`, then
//! `M = Rx(−α) D = Ry(β) Rz(γ)` gives `γ = atan2(M₁₀, M₁₁)` and `β = atan2(M₀₂, M₂₂)`.
//! Each angle after the first is read from the *residual* rotation (entries of unit size),
//! never as a ratio of two small numbers, so the decomposition stays accurate to rounding even
//! at its singularities (`b = ±π/2`: the chord perpendicular to the disk normal; `β = ±π/2`):
//! there the first angle is arbitrary and the later ones absorb it. URDF `rpy` origins are
//! decomposed the same way ([`rpy_from_rotation`]). A zero-length chord gets `a = b = 0`.
//!
//! **Geometry.** Every disk link carries the disk as a cylinder (radius `disk_radius`, length
//! `disk_thickness`, centred on the disk frame) for both visual and collision; the backbone of
//! section `i` is a cylinder of the backbone diameter spanning the solved chord (on `disk_i` in
//! fixed mode, on `section_i_chord` in articulated mode, where it follows the bending joints).
//! With [`UrdfOptions::cables`] the cable chords between consecutive holes are thin cylinders on
//! `disk_i`, drawn as the solved shape routes them (in articulated mode they are exact at the
//! solved joint values and decorative elsewhere). Materials: `ccrkit_disk`, `ccrkit_backbone`,
//! `ccrkit_cable`.

use super::ExportError;
use crate::model::robot::Robot;
use crate::shape::{DiskFrame, Shape};
use nalgebra::{Matrix3, Rotation3, Vector3};
use serde::Serialize;
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// Name of the root link.
pub const BASE_LINK: &str = "base_link";
/// Name of the SRDF planning group (the chain `base_link` → last disk).
pub const GROUP_NAME: &str = "backbone";
/// Cable chords are drawn with this fraction of the backbone diameter…
const CABLE_DIAMETER_FRACTION: f64 = 0.25;
/// …but at least this diameter \[m\].
const CABLE_MIN_DIAMETER: f64 = 2e-4;
/// Largest accepted deviation of a disk rotation from orthonormality (‖RᵀR − I‖∞).
const ORTHONORMAL_TOL: f64 = 1e-6;
/// Cylinders shorter than this are not drawn \[m\].
const MIN_CYLINDER_LENGTH: f64 = 1e-12;

/// How the shape becomes a URDF.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum UrdfMode {
    /// One link per disk, fixed joints at the solved relative poses (a snapshot).
    Fixed,
    /// Six joints per section; the solved shape is a set of joint values.
    Articulated,
}

impl FromStr for UrdfMode {
    type Err = ExportError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "fixed" => Ok(UrdfMode::Fixed),
            "articulated" => Ok(UrdfMode::Articulated),
            other => Err(ExportError::InvalidOption {
                option: "mode".into(),
                reason: format!("unknown mode `{other}`; known: fixed, articulated"),
            }),
        }
    }
}

impl std::fmt::Display for UrdfMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            UrdfMode::Fixed => "fixed",
            UrdfMode::Articulated => "articulated",
        })
    }
}

/// Options of [`export_urdf`].
#[derive(Debug, Clone, PartialEq)]
pub struct UrdfOptions {
    /// Fixed snapshot or articulated chain.
    pub mode: UrdfMode,
    /// Draw the cables as thin cylinders between consecutive holes.
    pub cables: bool,
    /// Robot name in the URDF and name of the SRDF `group_state` (default: the robot's name).
    pub name: Option<String>,
}

impl Default for UrdfOptions {
    fn default() -> Self {
        UrdfOptions {
            mode: UrdfMode::Articulated,
            cables: false,
            name: None,
        }
    }
}

/// One joint value of the solved shape.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointValue {
    /// Joint name in the URDF.
    pub name: String,
    /// Value \[rad\] for revolute joints, \[m\] for prismatic ones.
    pub value: f64,
}

/// The six joint values of one articulated section (see the module docs for the chain).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionJoints {
    /// Chord bending about x \[rad\].
    pub bend_x: f64,
    /// Chord bending about y \[rad\].
    pub bend_y: f64,
    /// Chord length minus the nominal section length \[m\].
    pub extension: f64,
    /// Disk tilt about the chord frame's x \[rad\].
    pub tilt_x: f64,
    /// Disk tilt about y \[rad\].
    pub tilt_y: f64,
    /// Disk twist about z \[rad\].
    pub twist: f64,
}

impl SectionJoints {
    /// Joint values taking disk frame `prev` to disk frame `next` for a section of nominal
    /// length `l0` (derivation in the module docs).
    pub fn from_frames(prev: &DiskFrame, next: &DiskFrame, l0: f64) -> SectionJoints {
        let t = prev.rotation.transpose() * (next.position - prev.position);
        let c = t.norm();
        let (bend_x, bend_y) = if c > 0.0 {
            let u = t / c;
            let a = (-u.y).atan2(u.z);
            let v = rot_x(-a) * u;
            (a, v.x.atan2(v.z))
        } else {
            (0.0, 0.0)
        };
        let chord = rot_x(bend_x) * rot_y(bend_y);
        let d = chord.transpose() * prev.rotation.transpose() * next.rotation;
        let alpha = (-d[(1, 2)]).atan2(d[(2, 2)]);
        let m = rot_x(-alpha) * d;
        let gamma = m[(1, 0)].atan2(m[(1, 1)]);
        let beta = m[(0, 2)].atan2(m[(2, 2)]);
        SectionJoints {
            bend_x,
            bend_y,
            extension: c - l0,
            tilt_x: alpha,
            tilt_y: beta,
            twist: gamma,
        }
    }
}

/// The result of [`export_urdf`]: the URDF (as urdf-rs data and text) and, in articulated
/// mode, the solved joint values as SRDF and JSON.
#[derive(Debug, Clone)]
pub struct UrdfExport {
    /// The robot as urdf-rs data.
    pub robot: urdf_rs::Robot,
    /// URDF text.
    pub urdf: String,
    /// Mode it was written in.
    pub mode: UrdfMode,
    /// Movable joints with their solved values, base to tip (empty in fixed mode).
    pub joint_values: Vec<JointValue>,
    /// SRDF text: group `backbone` (chain `base_link` → tip) and the `group_state` named after
    /// the model holding the solved values (articulated mode only).
    pub srdf: Option<String>,
    /// JSON text with the same joint values (articulated mode only).
    pub json: Option<String>,
}

impl UrdfExport {
    /// Write the URDF to `urdf_path` and, when present, the SRDF next to it (same stem,
    /// `.srdf`) and the joint values (same stem, `.joints.json`). Returns the paths written.
    pub fn write_files(&self, urdf_path: &Path) -> Result<Vec<PathBuf>, ExportError> {
        let mut written = Vec::new();
        write_file(urdf_path, &self.urdf)?;
        written.push(urdf_path.to_path_buf());
        if let Some(srdf) = &self.srdf {
            let p = urdf_path.with_extension("srdf");
            write_file(&p, srdf)?;
            written.push(p);
        }
        if let Some(json) = &self.json {
            let p = urdf_path.with_extension("joints.json");
            write_file(&p, json)?;
            written.push(p);
        }
        Ok(written)
    }
}

fn write_file(path: &Path, text: &str) -> Result<(), ExportError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| ExportError::Io {
            path: dir.display().to_string(),
            reason: e.to_string(),
        })?;
    }
    std::fs::write(path, text).map_err(|e| ExportError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Export `shape` (a solved shape of `robot`) as URDF; see the module docs for the layout.
pub fn export_urdf(
    shape: &Shape,
    robot: &Robot,
    opts: &UrdfOptions,
) -> Result<UrdfExport, ExportError> {
    check(shape, robot)?;
    let name = opts.name.clone().unwrap_or_else(|| robot.name.clone());
    let n = robot.sections();
    let disks = &shape.disks;
    let mut links = vec![empty_link(BASE_LINK)];
    let mut joints = vec![fixed_joint(
        "base_to_disk_0",
        BASE_LINK,
        &disk_link_name(0),
        &disks[0].position,
        &disks[0].rotation,
    )];
    links.push(disk_link(robot, shape, 0, opts, None));
    let mut values = Vec::new();
    for i in 1..=n {
        let (prev, next) = (&disks[i - 1], &disks[i]);
        let t = prev.rotation.transpose() * (next.position - prev.position);
        match opts.mode {
            UrdfMode::Fixed => {
                let back = next.rotation.transpose() * (prev.position - next.position);
                joints.push(fixed_joint(
                    &format!("disk_{}_to_disk_{}", i - 1, i),
                    &disk_link_name(i - 1),
                    &disk_link_name(i),
                    &t,
                    &(prev.rotation.transpose() * next.rotation),
                ));
                links.push(disk_link(robot, shape, i, opts, Some(back)));
            }
            UrdfMode::Articulated => {
                let l0 = robot.section_length(i);
                let q = SectionJoints::from_frames(prev, next, l0);
                let sec = format!("section_{i}");
                let bend_x_link = format!("{sec}_bend_x_link");
                let chord_link = format!("{sec}_chord");
                let chord_end = format!("{sec}_chord_end");
                let tilt_x_link = format!("{sec}_tilt_x_link");
                let tilt_y_link = format!("{sec}_tilt_y_link");
                let disk = disk_link_name(i);
                let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
                let bend = (-FRAC_PI_2, FRAC_PI_2);
                let revolute = urdf_rs::JointType::Revolute;
                let specs = [
                    JointSpec::new("bend_x", &bend_x_link, revolute.clone(), x, q.bend_x, bend),
                    JointSpec::new("bend_y", &chord_link, revolute.clone(), y, q.bend_y, bend),
                    JointSpec {
                        offset_z: l0,
                        ..JointSpec::new(
                            "extension",
                            &chord_end,
                            urdf_rs::JointType::Prismatic,
                            z,
                            q.extension,
                            (-0.5 * l0, 0.5 * l0),
                        )
                    },
                    JointSpec::new("tilt_x", &tilt_x_link, revolute.clone(), x, q.tilt_x, bend),
                    JointSpec::new("tilt_y", &tilt_y_link, revolute.clone(), y, q.tilt_y, bend),
                    JointSpec::new("twist", &disk, revolute, z, q.twist, (-PI, PI)),
                ];
                let mut parent = disk_link_name(i - 1);
                for spec in specs {
                    let jname = format!("{sec}_{}", spec.what);
                    let (lo, hi) = spec.limits;
                    joints.push(urdf_rs::Joint {
                        name: jname.clone(),
                        joint_type: spec.joint_type,
                        origin: pose([0.0, 0.0, spec.offset_z], [0.0; 3]),
                        parent: urdf_rs::LinkName { link: parent },
                        child: urdf_rs::LinkName {
                            link: spec.child.to_string(),
                        },
                        axis: urdf_rs::Axis {
                            xyz: urdf_rs::Vec3(spec.axis),
                        },
                        // Limits always contain the solved value.
                        limit: limit(lo.min(spec.value), hi.max(spec.value)),
                        calibration: None,
                        dynamics: None,
                        mimic: None,
                        safety_controller: None,
                    });
                    values.push(JointValue {
                        name: jname,
                        value: spec.value,
                    });
                    parent = spec.child.to_string();
                }
                links.push(empty_link(&bend_x_link));
                let mut chord = empty_link(&chord_link);
                let c = t.norm();
                if c > MIN_CYLINDER_LENGTH {
                    add_cylinder(
                        &mut chord,
                        &format!("{sec}_backbone"),
                        &Vector3::zeros(),
                        &Vector3::new(0.0, 0.0, c),
                        robot.backbone.radius(),
                        &backbone_material(),
                        true,
                    );
                }
                links.push(chord);
                links.push(empty_link(&chord_end));
                links.push(empty_link(&tilt_x_link));
                links.push(empty_link(&tilt_y_link));
                links.push(disk_link(robot, shape, i, opts, None));
            }
        }
    }
    let urdf_robot = urdf_rs::Robot {
        name: name.clone(),
        version: None,
        links,
        joints,
        materials: vec![disk_material(), backbone_material(), cable_material()],
    };
    let urdf = urdf_rs::write_to_string(&urdf_robot).map_err(|e| ExportError::Urdf {
        reason: e.to_string(),
    })?;
    let (srdf, json) = match opts.mode {
        UrdfMode::Fixed => (None, None),
        UrdfMode::Articulated => (
            Some(srdf_text(&name, &disk_link_name(n), &values, n)),
            Some(json_text(&name, &shape.method, &values)?),
        ),
    };
    Ok(UrdfExport {
        robot: urdf_robot,
        urdf,
        mode: opts.mode,
        joint_values: values,
        srdf,
        json,
    })
}

/// One movable joint of an articulated section; its parent is the previous joint's child.
struct JointSpec<'a> {
    what: &'static str,
    child: &'a str,
    joint_type: urdf_rs::JointType,
    axis: [f64; 3],
    /// Origin offset along the parent's z \[m\].
    offset_z: f64,
    value: f64,
    limits: (f64, f64),
}

impl<'a> JointSpec<'a> {
    fn new(
        what: &'static str,
        child: &'a str,
        joint_type: urdf_rs::JointType,
        axis: [f64; 3],
        value: f64,
        limits: (f64, f64),
    ) -> Self {
        JointSpec {
            what,
            child,
            joint_type,
            axis,
            offset_z: 0.0,
            value,
            limits,
        }
    }
}

/// Check that the shape fits the robot and every frame is finite and a rotation.
fn check(shape: &Shape, robot: &Robot) -> Result<(), ExportError> {
    let n = robot.sections();
    if shape.disks.len() != n + 1 {
        return Err(ExportError::ShapeMismatch {
            robot: robot.name.clone(),
            reason: format!(
                "shape has {} disk frames, robot has {} disks",
                shape.disks.len(),
                n + 1
            ),
        });
    }
    for (k, d) in shape.disks.iter().enumerate() {
        if !d
            .position
            .iter()
            .chain(d.rotation.iter())
            .all(|v| v.is_finite())
        {
            return Err(ExportError::BadDiskFrame {
                disk: k,
                reason: "non-finite position or rotation".into(),
            });
        }
        let err = (d.rotation.transpose() * d.rotation - Matrix3::identity()).amax();
        if err > ORTHONORMAL_TOL || d.rotation.determinant() <= 0.0 {
            return Err(ExportError::BadDiskFrame {
                disk: k,
                reason: format!(
                    "rotation is not a proper rotation (|RᵀR − I| = {err:.1e}, det = {:.3})",
                    d.rotation.determinant()
                ),
            });
        }
    }
    Ok(())
}

/// URDF roll-pitch-yaw of a rotation: `R = Rz(yaw) Ry(pitch) Rx(roll)` (fixed axes x, y, z).
///
/// `yaw = atan2(R₁₀, R₀₀)`, then `M = Rz(−yaw) R = Ry(pitch) Rx(roll)` gives
/// `roll = atan2(−M₁₂, M₁₁)` and `pitch = atan2(−M₂₀, M₀₀)`: accurate to rounding also at
/// `pitch = ±π/2`, where yaw is arbitrary and roll absorbs it. Returns `[roll, pitch, yaw]`.
pub fn rpy_from_rotation(r: &Matrix3<f64>) -> [f64; 3] {
    let yaw = r[(1, 0)].atan2(r[(0, 0)]);
    let m = rot_z(-yaw) * r;
    let roll = (-m[(1, 2)]).atan2(m[(1, 1)]);
    let pitch = (-m[(2, 0)]).atan2(m[(0, 0)]);
    [roll, pitch, yaw]
}

/// Rotation of URDF `rpy = [roll, pitch, yaw]`: `Rz(yaw) Ry(pitch) Rx(roll)`.
pub fn rotation_from_rpy(rpy: [f64; 3]) -> Matrix3<f64> {
    rot_z(rpy[2]) * rot_y(rpy[1]) * rot_x(rpy[0])
}

fn rot_x(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::x_axis(), a).into_inner()
}
fn rot_y(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::y_axis(), a).into_inner()
}
fn rot_z(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), a).into_inner()
}

fn disk_link_name(k: usize) -> String {
    format!("disk_{k}")
}

fn pose(xyz: [f64; 3], rpy: [f64; 3]) -> urdf_rs::Pose {
    // `+ 0.0` turns −0 into 0 (cosmetic: the text then reads `0`, not `-0`).
    urdf_rs::Pose {
        xyz: urdf_rs::Vec3(xyz.map(|v| v + 0.0)),
        rpy: urdf_rs::Vec3(rpy.map(|v| v + 0.0)),
    }
}

/// A number as XML attribute text that parses back to the same `f64` (shortest round trip;
/// scientific notation for tiny magnitudes instead of 20 leading zeros).
fn num(v: f64) -> String {
    let v = v + 0.0;
    if v != 0.0 && v.abs() < 1e-4 {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

fn limit(lower: f64, upper: f64) -> urdf_rs::JointLimit {
    urdf_rs::JointLimit {
        lower,
        upper,
        // Nominal: the exported chain is kinematic; planners need finite values here.
        effort: 1.0,
        velocity: 1.0,
        acceleration: f64::INFINITY,
        deceleration: f64::INFINITY,
        jerk: f64::INFINITY,
    }
}

fn fixed_joint(
    name: &str,
    parent: &str,
    child: &str,
    xyz: &Vector3<f64>,
    rot: &Matrix3<f64>,
) -> urdf_rs::Joint {
    urdf_rs::Joint {
        name: name.into(),
        joint_type: urdf_rs::JointType::Fixed,
        origin: pose([xyz.x, xyz.y, xyz.z], rpy_from_rotation(rot)),
        parent: urdf_rs::LinkName {
            link: parent.into(),
        },
        child: urdf_rs::LinkName { link: child.into() },
        axis: urdf_rs::Axis {
            xyz: urdf_rs::Vec3([0.0, 0.0, 1.0]),
        },
        limit: limit(0.0, 0.0),
        calibration: None,
        dynamics: None,
        mimic: None,
        safety_controller: None,
    }
}

fn empty_link(name: &str) -> urdf_rs::Link {
    urdf_rs::Link {
        name: name.into(),
        inertial: zero_inertial(),
        visual: vec![],
        collision: vec![],
    }
}

fn zero_inertial() -> urdf_rs::Inertial {
    urdf_rs::Inertial {
        origin: pose([0.0; 3], [0.0; 3]),
        mass: urdf_rs::Mass { value: 0.0 },
        inertia: urdf_rs::Inertia {
            ixx: 0.0,
            ixy: 0.0,
            ixz: 0.0,
            iyy: 0.0,
            iyz: 0.0,
            izz: 0.0,
        },
    }
}

fn material(name: &str, rgba: [f64; 4]) -> urdf_rs::Material {
    urdf_rs::Material {
        name: name.into(),
        color: Some(urdf_rs::Color {
            rgba: urdf_rs::Vec4(rgba),
        }),
        texture: None,
    }
}
fn disk_material() -> urdf_rs::Material {
    material("ccrkit_disk", [0.85, 0.65, 0.2, 1.0])
}
fn backbone_material() -> urdf_rs::Material {
    material("ccrkit_backbone", [0.25, 0.25, 0.3, 1.0])
}
fn cable_material() -> urdf_rs::Material {
    material("ccrkit_cable", [0.1, 0.35, 0.9, 1.0])
}

/// Add a cylinder (visual, and collision when `collide`) from `a` to `b` in the link frame.
fn add_cylinder(
    link: &mut urdf_rs::Link,
    name: &str,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    radius: f64,
    mat: &urdf_rs::Material,
    collide: bool,
) {
    let d = b - a;
    let length = d.norm();
    if length <= MIN_CYLINDER_LENGTH {
        return;
    }
    // URDF cylinders lie along their local z.
    let rot = Rotation3::rotation_between(&Vector3::z(), &d)
        .map(|r| r.into_inner())
        .unwrap_or_else(|| rot_x(PI));
    let mid = (a + b) / 2.0;
    let origin = pose([mid.x, mid.y, mid.z], rpy_from_rotation(&rot));
    let geometry = urdf_rs::Geometry::Cylinder { radius, length };
    link.visual.push(urdf_rs::Visual {
        name: Some(name.into()),
        origin: origin.clone(),
        geometry: geometry.clone(),
        material: Some(mat.clone()),
    });
    if collide {
        link.collision.push(urdf_rs::Collision {
            name: Some(name.into()),
            origin,
            geometry,
        });
    }
}

/// Link of disk `k`: the disk cylinder, the backbone of section `k` when `backbone_to_prev`
/// (the previous disk's position in this disk's frame) is given, and the cable chords.
fn disk_link(
    robot: &Robot,
    shape: &Shape,
    k: usize,
    opts: &UrdfOptions,
    backbone_to_prev: Option<Vector3<f64>>,
) -> urdf_rs::Link {
    let name = disk_link_name(k);
    let mut link = empty_link(&name);
    let m = robot.loads.disk_mass.max(0.0);
    let (r, h) = (robot.disk_radius, robot.disk_thickness);
    link.inertial.mass.value = m;
    link.inertial.inertia.ixx = m * (3.0 * r * r + h * h) / 12.0;
    link.inertial.inertia.iyy = link.inertial.inertia.ixx;
    link.inertial.inertia.izz = m * r * r / 2.0;
    let half = Vector3::new(0.0, 0.0, h / 2.0);
    add_cylinder(&mut link, &name, &-half, &half, r, &disk_material(), true);
    if let Some(prev) = backbone_to_prev {
        add_cylinder(
            &mut link,
            &format!("section_{k}_backbone"),
            &Vector3::zeros(),
            &prev,
            robot.backbone.radius(),
            &backbone_material(),
            true,
        );
    }
    if opts.cables && k >= 1 {
        let (prev, here) = (&shape.disks[k - 1], &shape.disks[k]);
        let radius =
            (robot.backbone.diameter * CABLE_DIAMETER_FRACTION).max(CABLE_MIN_DIAMETER) / 2.0;
        for cable in robot.cables.iter().filter(|c| c.reaches_section(k)) {
            let a = cable.hole(k);
            let hole_prev = prev.position + prev.rotation * cable.hole(k - 1);
            let b = here.rotation.transpose() * (hole_prev - here.position);
            add_cylinder(
                &mut link,
                &format!("cable_{}_section_{k}", cable.name),
                &a,
                &b,
                radius,
                &cable_material(),
                true,
            );
        }
    }
    link
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

/// SRDF: the planning group, the solved state, and collisions between touching neighbours off.
fn srdf_text(name: &str, tip: &str, values: &[JointValue], n: usize) -> String {
    let name = xml_escape(name);
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str(&format!("<robot name=\"{name}\">\n"));
    s.push_str(&format!("  <group name=\"{GROUP_NAME}\">\n"));
    s.push_str(&format!(
        "    <chain base_link=\"{BASE_LINK}\" tip_link=\"{tip}\"/>\n"
    ));
    s.push_str("  </group>\n");
    s.push_str(&format!(
        "  <group_state name=\"{name}\" group=\"{GROUP_NAME}\">\n"
    ));
    for v in values {
        s.push_str(&format!(
            "    <joint name=\"{}\" value=\"{}\"/>\n",
            xml_escape(&v.name),
            num(v.value)
        ));
    }
    s.push_str("  </group_state>\n");
    // The backbone of section i touches disk i-1, disk i and the backbone of section i+1 by
    // construction; cable chords (on disk i) touch disk i-1.
    for i in 1..=n {
        let mut pairs = vec![
            (format!("disk_{}", i - 1), format!("section_{i}_chord")),
            (format!("section_{i}_chord"), format!("disk_{i}")),
            (format!("disk_{}", i - 1), format!("disk_{i}")),
        ];
        if i < n {
            pairs.push((
                format!("section_{i}_chord"),
                format!("section_{}_chord", i + 1),
            ));
        }
        for (a, b) in pairs {
            s.push_str(&format!(
                "  <disable_collisions link1=\"{a}\" link2=\"{b}\" reason=\"Adjacent\"/>\n"
            ));
        }
    }
    s.push_str("</robot>\n");
    s
}

#[derive(Serialize)]
struct JointsJson<'a> {
    robot: &'a str,
    method: &'a str,
    group: &'a str,
    group_state: &'a str,
    units: &'a str,
    joints: &'a [JointValue],
}

fn json_text(name: &str, method: &str, values: &[JointValue]) -> Result<String, ExportError> {
    serde_json::to_string_pretty(&JointsJson {
        robot: name,
        method,
        group: GROUP_NAME,
        group_state: name,
        units: "rad for revolute joints, m for prismatic (section_*_extension)",
        joints: values,
    })
    .map_err(|e| ExportError::Urdf {
        reason: format!("joint values as JSON: {e}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOL: f64 = 1e-12;

    fn angle_between(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
        // ‖A − B‖_F = 2√2 sin(θ/2): accurate for small angles.
        let s = (a - b).norm() / (2.0 * 2f64.sqrt());
        2.0 * s.min(1.0).asin()
    }

    #[test]
    fn rpy_round_trips_including_gimbal_lock() {
        let cases = [
            [0.1, 0.2, 0.3],
            [-2.0, 1.2, 3.0],
            [0.4, FRAC_PI_2, -0.7],
            [0.4, -FRAC_PI_2, 1.1],
            [0.3, FRAC_PI_2 - 1e-9, 0.2],
            [3.0, -1e-8, -3.1],
        ];
        for rpy in cases {
            let r = rotation_from_rpy(rpy);
            let back = rotation_from_rpy(rpy_from_rotation(&r));
            assert!(angle_between(&r, &back) < TOL, "{rpy:?}");
        }
    }

    #[test]
    fn section_joints_reproduce_relative_pose() {
        let prev = DiskFrame {
            s: 0.0,
            position: Vector3::new(0.01, -0.02, 0.03),
            rotation: Rotation3::new(Vector3::new(0.3, -0.2, 0.9)).into_inner(),
        };
        for (w, t) in [
            (
                Vector3::new(0.2, 0.1, 1.4),
                Vector3::new(0.004, -0.003, 0.019),
            ),
            (Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.0, 0.0, 0.02)),
            (Vector3::new(-0.5, 0.7, -2.0), Vector3::new(0.02, 0.0, 0.0)),
            (
                Vector3::new(0.0, FRAC_PI_2, 0.0),
                Vector3::new(0.0, -0.01, -0.01),
            ),
        ] {
            let next = DiskFrame {
                s: 0.02,
                position: prev.position + prev.rotation * t,
                rotation: prev.rotation * Rotation3::new(w).into_inner(),
            };
            let q = SectionJoints::from_frames(&prev, &next, 0.02);
            let chord = rot_x(q.bend_x) * rot_y(q.bend_y);
            let rel_p = chord * Vector3::new(0.0, 0.0, 0.02 + q.extension);
            let rel_r = chord * rot_x(q.tilt_x) * rot_y(q.tilt_y) * rot_z(q.twist);
            let p = prev.position + prev.rotation * rel_p;
            let r = prev.rotation * rel_r;
            assert!((p - next.position).norm() < TOL, "{t:?}");
            assert!(angle_between(&r, &next.rotation) < TOL, "{w:?}");
        }
    }
}
