//! URDF export of a solved [`Shape`]: a fixed snapshot, or an articulated chain whose joint
//! values (SRDF `group_state` + JSON) reproduce the solved disk frames.
//!
//! Units are metres and radians; every frame is the disk frame of [`DiskFrame`](crate::shape::DiskFrame) (z along the disk
//! normal, x at hole angle 0). Links and joints:
//!
//! * `base_link` — the robot's base frame (the scene frame); `base_to_disk_0` (fixed) places
//!   `disk_0` where the shape puts it (the identity for a robot without a port).
//! * **a robot deployed through a port** ([`crate::model::port`]), articulated mode: two base
//!   joints come first, so a URDF client replays insertion and rotation: `port` (fixed, the
//!   port frame `T_port`) → `port_link` → `port_insertion` (prismatic along z, value `d` \[m\],
//!   limits `[0, L]`) → `port_insertion_link` → `port_rotation` (revolute about z, value `ψ`,
//!   limits `[−π, π]`, each widened to contain the value) → `port_rotation_link` →
//!   `base_to_disk_0` (fixed, `Tz(−L)`). Disk 0 is then at `T_port · Tz(d) · Rz(ψ) · Tz(−L)
//!   = T_port · Rz(ψ) · Tz(d − L)`, where the solve put it; the sections behind the port are
//!   straight sections of the chain (their joint values zero but for rounding). In fixed mode
//!   `base_to_disk_0` places disk 0 directly.
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
//! `disk_thickness`, centred on the disk frame) for both visual and collision (a rod without
//! spacer disks has none); the backbone of section `i` is a cylinder of the body's diameter
//! (the collision radius, else the backbone's) spanning the solved chord (on `disk_i` in
//! fixed mode, on `section_i_chord` in articulated mode, where it follows the bending joints).
//! With [`UrdfOptions::cables`] the cable chords between consecutive holes are thin cylinders on
//! `disk_i`, drawn as the solved shape routes them (in articulated mode they are exact at the
//! solved joint values and decorative elsewhere). Materials: `ccrkit_disk`, `ccrkit_backbone`,
//! `ccrkit_cable`.

mod frames;
mod inertia;
mod links;
mod srdf;

pub use frames::{rotation_from_rpy, rpy_from_rotation, SectionJoints};
pub use inertia::{DEFAULT_BACKBONE_DENSITY, DEFAULT_DISK_DENSITY};

use super::ExportError;
use crate::model::robot::Robot;
use crate::shape::Shape;
use links::{
    add_cylinder, backbone_material, cable_material, disk_link, disk_link_name, disk_material,
    empty_link, fixed_joint, limit, mass_link, pose,
};
use nalgebra::{Matrix3, Vector3};
use serde::Serialize;
use srdf::{json_text, srdf_text};
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// Name of the root link.
pub const BASE_LINK: &str = "base_link";
/// The port frame's link (a shape solved through a port, articulated mode).
pub const PORT_LINK: &str = "port_link";
/// The link after the insertion joint.
pub const PORT_INSERTION_LINK: &str = "port_insertion_link";
/// The link after the rotation joint.
pub const PORT_ROTATION_LINK: &str = "port_rotation_link";
/// Name of the SRDF planning group (the chain `base_link` → last disk).
pub const GROUP_NAME: &str = "backbone";
/// Cable chords are drawn with this fraction of the backbone diameter…
pub(super) const CABLE_DIAMETER_FRACTION: f64 = 0.25;
/// …but at least this diameter \[m\].
pub(super) const CABLE_MIN_DIAMETER: f64 = 2e-4;
/// Cylinders shorter than this are not drawn \[m\].
pub(super) const MIN_CYLINDER_LENGTH: f64 = 1e-12;

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
    /// `.srdf`) and the joint values (same stem, `.joints.json`), each atomically
    /// ([`crate::output`]). Two of them on one file (`--out a.srdf`) are refused before any is
    /// written. Returns the paths written.
    pub fn write_files(&self, urdf_path: &Path) -> Result<Vec<PathBuf>, ExportError> {
        let paths = UrdfExport::paths(self.mode, urdf_path);
        crate::output::RunFiles::new().outputs(&paths)?;
        let texts = [Some(&self.urdf), self.srdf.as_ref(), self.json.as_ref()];
        for ((_, p), text) in paths.iter().zip(texts.into_iter().flatten()) {
            crate::output::write_file(p, text.as_bytes())?;
        }
        Ok(paths.into_iter().map(|(_, p)| p).collect())
    }

    /// The files [`UrdfExport::write_files`] writes in `mode` for `urdf_path`, each with its
    /// role: the URDF, then in articulated mode the SRDF and the joint values.
    pub fn paths(mode: UrdfMode, urdf_path: &Path) -> Vec<(&'static str, PathBuf)> {
        let mut v = vec![("URDF", urdf_path.to_path_buf())];
        if mode == UrdfMode::Articulated {
            v.push(("SRDF", urdf_path.with_extension("srdf")));
            v.push(("joint values", urdf_path.with_extension("joints.json")));
        }
        v
    }
}

/// Every name written into the XML is one XML can hold ([`crate::model::name::check_name`]):
/// the robot's (or the option's) and the cables' (in link names). The XML writers escape
/// `& < > " '`; a control character or noncharacter cannot be escaped in XML 1.0.
fn check_names(name: &str, robot: &Robot) -> Result<(), ExportError> {
    let named = |field: String, s: &str| {
        crate::model::name::check_name(field.clone(), s).map_err(|e| ExportError::Input {
            field,
            reason: match e {
                crate::ModelError::Invalid { reason, .. } => reason,
                e => e.to_string(),
            },
        })
    };
    named("name".into(), name)?;
    for (i, c) in robot.cables.iter().enumerate() {
        named(format!("cables[{i}].name"), &c.name)?;
    }
    Ok(())
}

/// Export `shape` (a solved shape of `robot`) as URDF; see the module docs for the layout.
pub fn export_urdf(
    shape: &Shape,
    robot: &Robot,
    opts: &UrdfOptions,
) -> Result<UrdfExport, ExportError> {
    check(shape, robot)?;
    let name = opts.name.clone().unwrap_or_else(|| robot.name.clone());
    check_names(&name, robot)?;
    let n = robot.sections();
    let disks = &shape.disks;
    let articulated = opts.mode == UrdfMode::Articulated;
    let mut links = vec![empty_link(BASE_LINK)];
    let mut joints = vec![];
    let mut values = Vec::new();
    match (&shape.port, articulated) {
        (Some(p), true) => port_joints(robot, p, &mut links, &mut joints, &mut values),
        _ => joints.push(fixed_joint(
            "base_to_disk_0",
            BASE_LINK,
            &disk_link_name(0),
            &disks[0].position,
            &disks[0].rotation,
        )),
    }
    // Share of a disk's mass on each link whose origin is its centre (see `inertia`).
    let port = shape.port.is_some();
    let share = |k: usize| {
        if articulated {
            1.0 / inertia::shares_at_disk(k, n, port) as f64
        } else {
            1.0
        }
    };
    links.push(disk_link(robot, shape, 0, opts, None, share(0)));
    for i in 1..=n {
        match opts.mode {
            UrdfMode::Fixed => {
                let (prev, next) = (&disks[i - 1], &disks[i]);
                let t = prev.rotation.transpose() * (next.position - prev.position);
                let back = next.rotation.transpose() * (prev.position - next.position);
                joints.push(fixed_joint(
                    &format!("disk_{}_to_disk_{}", i - 1, i),
                    &disk_link_name(i - 1),
                    &disk_link_name(i),
                    &t,
                    &(prev.rotation.transpose() * next.rotation),
                ));
                links.push(disk_link(robot, shape, i, opts, Some(back), share(i)));
            }
            UrdfMode::Articulated => {
                articulated_section(robot, shape, opts, i, &mut links, &mut joints, &mut values)
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

/// The port's two joints (articulated mode, a shape solved through a port): `port`
/// (fixed, the port frame in the scene frame), `port_insertion` (prismatic along the port
/// axis, value `d`), `port_rotation` (revolute about it, value `ψ`) and `base_to_disk_0`
/// (fixed, `Tz(−L)`): disk 0 at `T_port · Tz(d) · Rz(ψ) · Tz(−L)`, where the shape has it.
fn port_joints(
    robot: &Robot,
    p: &crate::shape::PortState,
    links: &mut Vec<urdf_rs::Link>,
    joints: &mut Vec<urdf_rs::Joint>,
    values: &mut Vec<JointValue>,
) {
    let r = p.pose.rotation.to_rotation_matrix().into_inner();
    joints.push(fixed_joint(
        "port",
        BASE_LINK,
        PORT_LINK,
        &p.pose.translation.vector,
        &r,
    ));
    links.push(empty_link(PORT_LINK));
    let len = robot.length();
    // Both joints turn or slide about the port's z axis.
    let (z, prismatic, revolute) = (
        [0.0, 0.0, 1.0],
        urdf_rs::JointType::Prismatic,
        urdf_rs::JointType::Revolute,
    );
    let (slide, turn) = (PORT_INSERTION_LINK, PORT_ROTATION_LINK);
    let specs = [
        JointSpec::new("insertion", slide, prismatic, z, p.insertion, (0.0, len)),
        JointSpec::new("rotation", turn, revolute, z, p.rotation, (-PI, PI)),
    ];
    // Disk 0 sits at (0, 0, −L) in both links' frames in every configuration (the rotation
    // is about that axis, and the disk is symmetric about it): each carries a share of it
    // there, so MuJoCo sees no massless moving body and the mass stays where it is.
    let mut base_share = inertia::disk(robot, 0)
        .scaled(1.0 / inertia::shares_at_disk(0, robot.sections(), true) as f64);
    base_share.com = Vector3::new(0.0, 0.0, -len);
    chain(&specs, "port", PORT_LINK, joints, values);
    links.extend(specs.iter().map(|s| mass_link(s.child, base_share)));
    joints.push(fixed_joint(
        "base_to_disk_0",
        PORT_ROTATION_LINK,
        &disk_link_name(0),
        &Vector3::new(0.0, 0.0, -len),
        &Matrix3::identity(),
    ));
}

/// The six joints and links of articulated section `i` (bend x/y, extension, tilt x/y, twist),
/// appended to `links`, `joints` and `values`.
fn articulated_section(
    robot: &Robot,
    shape: &Shape,
    opts: &UrdfOptions,
    i: usize,
    links: &mut Vec<urdf_rs::Link>,
    joints: &mut Vec<urdf_rs::Joint>,
    values: &mut Vec<JointValue>,
) {
    let n = robot.sections();
    let (prev, next) = (&shape.disks[i - 1], &shape.disks[i]);
    let t = prev.rotation.transpose() * (next.position - prev.position);
    // Share of a disk's mass on each link whose origin is its centre (see `inertia`).
    let port = shape.port.is_some();
    let share = |k: usize| 1.0 / inertia::shares_at_disk(k, n, port) as f64;
    let disk_part = |k: usize| inertia::disk(robot, k).scaled(share(k));
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
    chain(&specs, &sec, &disk_link_name(i - 1), joints, values);
    links.push(mass_link(&bend_x_link, disk_part(i - 1)));
    let mut chord = mass_link(
        &chord_link,
        inertia::backbone(
            robot,
            i,
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, t.norm()),
        ),
    );
    let c = t.norm();
    if c > MIN_CYLINDER_LENGTH {
        add_cylinder(
            &mut chord,
            &format!("{sec}_backbone"),
            &Vector3::zeros(),
            &Vector3::new(0.0, 0.0, c),
            robot.body_radius(),
            &backbone_material(),
            true,
        );
    }
    links.push(chord);
    links.push(mass_link(&chord_end, disk_part(i)));
    links.push(mass_link(&tilt_x_link, disk_part(i)));
    links.push(mass_link(&tilt_y_link, disk_part(i)));
    links.push(disk_link(robot, shape, i, opts, None, share(i)));
}

/// The URDF joint of `spec`, from `parent` to the spec's child.
/// The movable joints of `specs` in a chain from `parent` (each the next one's parent),
/// named `<prefix>_<what>`, with their values.
fn chain(
    specs: &[JointSpec],
    prefix: &str,
    parent: &str,
    joints: &mut Vec<urdf_rs::Joint>,
    values: &mut Vec<JointValue>,
) {
    let mut parent = parent.to_string();
    for spec in specs {
        let name = format!("{prefix}_{}", spec.what);
        joints.push(movable_joint(spec, &name, parent));
        values.push(JointValue {
            name,
            value: spec.value,
        });
        parent = spec.child.to_string();
    }
}

fn movable_joint(spec: &JointSpec, name: &str, parent: String) -> urdf_rs::Joint {
    let (lo, hi) = spec.limits;
    urdf_rs::Joint {
        name: name.to_string(),
        joint_type: spec.joint_type.clone(),
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
    }
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
        if let Some(why) = crate::numeric::so3::rotation_defect(&d.rotation) {
            return Err(ExportError::BadDiskFrame {
                disk: k,
                reason: format!("rotation {why}"),
            });
        }
    }
    Ok(())
}
