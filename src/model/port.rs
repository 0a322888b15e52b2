//! The entry port a robot is deployed through (a bronchoscope's working channel, a trocar,
//! an introducer), and its two base degrees of freedom: insertion `d` and rotation `ψ`.
//!
//! ```toml
//! [port]
//! position = [0.0, 0.0, 0.0]          # port origin in the scene frame [m]
//! orientation = { rpy = [0, 0, 0] }   # port frame (or { quaternion = [w, x, y, z] }); the
//!                                     # robot comes out along its +z
//! insertion = 0.08                    # command d [m]: length out of the port (default: all, L)
//! rotation = 0.0                      # command ψ [rad] about the port axis (default 0)
//! limits = { insertion = [0.01, 0.12], rotation = [-3.1416, 3.1416] }   # for reach and plan
//! ```
//!
//! **Geometry.** The robot's material coordinate `s` runs from its base (`s = 0`, disk 0) to
//! its tip (`s = L`). At insertion `d` (`0 ≤ d ≤ L`) the material at `s > L − d` has come out
//! of the port and bends, clamped at the port origin with its tangent along the port's +z; the
//! material at `s ≤ L − d` lies straight along the port axis behind it (port-frame `z ≤ 0`),
//! and so do the cables in it. Rotation `ψ` turns the whole robot (and its hole pattern) about
//! the port axis, so the bending part starts from the frame `T_port · Rz(ψ)`.
//!
//! **Reduction.** What lies beyond the port is a robot in its own right ([`beyond`]): its
//! disk 0 is the material point at the port, its disks are the real disks beyond it (the first
//! section partial), its holes at the new disk 0 are each cable's route evaluated at
//! `s = L − d` (a declared helix or straight run exactly; a per-disk table by the natural cubic
//! spline the rod routes it by, [`crate::model::routing`]), and its cables are the ones tied
//! beyond the port. Every method solves that robot unchanged; the solve path places the answer
//! by `T_port · Rz(ψ)` and adds the straight part behind the port (`method/port.rs`). A cable's
//! path length includes its straight part, which does not change, so its shortening (the
//! change of its whole length) is the shortening of the robot beyond the port — the same
//! number.
//!
//! **Short first section.** When a disk is within [`SNAP`] of the port (beyond it), the
//! exposed piece before it is held straight, as if still in the port: the robot beyond is
//! solved from that disk, shifted out by the piece's length `ℓ' < SNAP`. Against bending that
//! piece with the rest, the tip moves by at most `θ·d + ℓ'`, `θ ≤ κ_max ℓ'` the angle the piece
//! would have turned (a rigid turn of the rest about the port), i.e. `O(SNAP)`; the methods'
//! section problems stay well scaled (none sees a section shorter than `SNAP`). The sweep test
//! (`tests/methods/port_sweep.rs`: 1000 insertion steps through the whole length, one landing
//! exactly on a disk) finds no tip step longer than the insertion step under a fixed tension
//! of a straight cable (energy and the rod), and no jump along helical cables.
//!
//! **Cables behind the port.** A cable tied at a disk at or behind the port is straight over
//! its whole length and held: it cannot change the shape. A tension on it is carried by the
//! robot inside the port (reported, no effect); a payout leaves it slack; a positive shortening
//! of an inextensible cable would have to stretch it and is refused by name
//! ([`crate::error::SolveError::Infeasible`]); a compliant cable takes it up as stretch and
//! reports the tension `k·(shortening) + T₀`.
//!
//! **Frames.** With a port, every position a solve takes or gives is in the scene frame: the
//! obstacles, the shape, the contacts, and the loads (gravity and the tip wrench, which the
//! methods receive turned into the frame of the bending part). Without a port the scene frame
//! is the robot's base frame, as before.

use super::bounds;
use super::robot::{Cable, Robot};
use super::routing::{Helix, Route, RoutingFit};
use super::scene_file::{quaternion, FileRotation};
use crate::error::{ModelError, SolveError};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use serde::Deserialize;

/// A first exposed section shorter than this is held straight (module docs, "Short first
/// section") \[m\].
pub const SNAP: f64 = 1e-9;

/// The port: where and how the robot enters the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Port {
    /// Port frame in the scene frame: origin at the port, +z the direction the robot comes out.
    pub pose: Isometry3<f64>,
}

impl Port {
    /// The frame the bending part starts from at rotation `psi`: `T_port · Rz(ψ)`.
    pub fn base_frame(&self, psi: f64) -> Isometry3<f64> {
        self.pose * Isometry3::rotation(Vector3::z() * psi)
    }

    /// The port axis (unit, scene frame).
    pub fn axis(&self) -> Vector3<f64> {
        self.pose.rotation * Vector3::z()
    }

    /// The port origin (scene frame) \[m\].
    pub fn origin(&self) -> Vector3<f64> {
        self.pose.translation.vector
    }
}

/// The `[port]` table of a model file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FilePort {
    #[serde(default)]
    position: Option<[f64; 3]>,
    #[serde(default)]
    orientation: Option<FileRotation>,
    #[serde(default)]
    insertion: Option<f64>,
    #[serde(default)]
    rotation: Option<f64>,
    #[serde(default)]
    limits: Option<FilePortLimits>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FilePortLimits {
    insertion: Option<[f64; 2]>,
    rotation: Option<[f64; 2]>,
}

/// Largest rotation command or limit accepted \[rad\] (a hundred turns either way).
pub const MAX_ROTATION: f64 = 200.0 * std::f64::consts::PI;

/// The validated `[port]` table: the port, the command `(d, ψ)` and the limits
/// (`insertion`, `rotation`).
pub(super) struct Validated {
    pub port: Port,
    pub insertion: f64,
    pub rotation: f64,
    pub insertion_limits: [f64; 2],
    pub rotation_limits: [f64; 2],
}

impl FilePort {
    /// Check every field against the robot's length `length`, naming the field.
    pub(super) fn validate(&self, length: f64) -> Result<Validated, ModelError> {
        let p = self.position.unwrap_or([0.0; 3]);
        bounds::COORDINATE.check3("port.position", p)?;
        let q: UnitQuaternion<f64> = quaternion(self.orientation.as_ref(), &|n| {
            format!("port.{}", n.replacen("rotation", "orientation", 1))
        })?;
        let pose = Isometry3::from_parts(Translation3::new(p[0], p[1], p[2]), q);
        let insertion = match self.insertion {
            None => length,
            Some(d) => check_insertion("port.insertion", d, length)?,
        };
        let rotation = match self.rotation {
            None => 0.0,
            Some(r) => check_rotation("port.rotation", r)?,
        };
        let lim = self.limits.as_ref();
        let insertion_limits = match lim.and_then(|l| l.insertion) {
            None => [0.0, length],
            Some(r) => {
                let f = "port.limits.insertion";
                let r = [
                    check_insertion(&format!("{f}[0]"), r[0], length)?,
                    check_insertion(&format!("{f}[1]"), r[1], length)?,
                ];
                ordered(f, r, "m")?
            }
        };
        let rotation_limits = match lim.and_then(|l| l.rotation) {
            None => [-std::f64::consts::PI, std::f64::consts::PI],
            Some(r) => {
                let f = "port.limits.rotation";
                check_rotation(&format!("{f}[0]"), r[0])?;
                check_rotation(&format!("{f}[1]"), r[1])?;
                ordered(f, r, "rad")?
            }
        };
        Ok(Validated {
            port: Port { pose },
            insertion,
            rotation,
            insertion_limits,
            rotation_limits,
        })
    }
}

fn ordered(field: &str, r: [f64; 2], unit: &str) -> Result<[f64; 2], ModelError> {
    if r[0] > r[1] {
        return Err(ModelError::invalid(
            field,
            format!("min {} {unit} exceeds max {} {unit}", r[0], r[1]),
        ));
    }
    Ok(r)
}

/// An insertion `d` \[m\]: finite and in `[0, L]` (0: all of the robot in the port; `L`: all of
/// it out). A `d` above `L` by rounding only (1e-12 relative: `L` is a sum of section lengths,
/// 12 × 0.01 = 0.11999999999999998) is `L`.
pub(crate) fn check_insertion(field: &str, d: f64, length: f64) -> Result<f64, ModelError> {
    if d.is_finite() && (0.0..=length * (1.0 + 1e-12)).contains(&d) {
        Ok(d.min(length))
    } else {
        Err(ModelError::invalid(
            field,
            format!(
                "insertion must lie in [0, {length}] m (0: the whole robot inside the port; \
                 {length} m: its whole length out), got {d}"
            ),
        ))
    }
}

/// A rotation `ψ` \[rad\]: finite, `|ψ| ≤` [`MAX_ROTATION`].
pub(crate) fn check_rotation(field: &str, r: f64) -> Result<f64, ModelError> {
    if r.is_finite() && r.abs() <= MAX_ROTATION {
        Ok(r)
    } else {
        Err(ModelError::invalid(
            field,
            format!("rotation must be finite and within ±{MAX_ROTATION:.4} rad, got {r}"),
        ))
    }
}

/// The robot beyond the port at one insertion ([`beyond`]).
#[derive(Debug, Clone)]
pub struct Beyond {
    /// The robot that has come out of the port (no port of its own; loads as the original's,
    /// still to be turned into its frame by the caller).
    pub robot: Robot,
    /// Where its disk 0 lies on the original robot: material coordinate `s` \[m\].
    pub s0: f64,
    /// Length between the port and the beyond-robot's disk 0, held straight (the snapped
    /// first section, module docs; 0 otherwise) \[m\].
    pub straight: f64,
    /// Original disk index of beyond-disk `j` is `j + offset` (for `j ≥ 1`; and for `j = 0`
    /// when `snapped`).
    pub offset: usize,
    /// True when the beyond-robot's disk 0 is a real disk (the snapped case), false when it is
    /// the material point at the port.
    pub snapped: bool,
    /// For each original cable, its index in the beyond-robot (`None`: tied at or behind the
    /// port).
    pub cables: Vec<Option<usize>>,
}

impl Beyond {
    /// The original disk index of beyond-disk `j`, `None` for the port point.
    pub fn disk(&self, j: usize) -> Option<usize> {
        (j >= 1 || self.snapped).then_some(j + self.offset)
    }
    /// The original section index of beyond-section `i` (1-based).
    pub fn section(&self, i: usize) -> usize {
        i + self.offset
    }
    /// The first original disk wholly beyond the port.
    pub fn first_disk(&self) -> usize {
        if self.snapped {
            self.offset
        } else {
            self.offset + 1
        }
    }
}

/// The robot beyond the port at insertion `d` (module docs, "Reduction"), or `None` when
/// nothing bends: `d` is 0, or shorter than [`SNAP`] past the last disk... i.e. the exposed
/// length holds no disk farther than [`SNAP`] from the port. `d` must already be checked
/// (`0 ≤ d ≤ L`).
pub fn beyond(robot: &Robot, d: f64) -> Result<Option<Beyond>, SolveError> {
    let n = robot.sections();
    let len = robot.length();
    let s0 = (len - d).max(0.0);
    // First disk strictly beyond the port.
    let Some(k0) = (0..=n).find(|&k| robot.disk_s[k] > s0) else {
        return Ok(None);
    };
    let first = robot.disk_s[k0] - s0;
    let snapped = first < SNAP;
    if snapped && k0 == n {
        return Ok(None);
    }
    // Beyond-disk 0 and the original disks after it.
    let (base_s, from, offset) = if snapped {
        (robot.disk_s[k0], k0 + 1, k0)
    } else {
        (s0, k0, k0 - 1)
    };
    let mut disk_s = Vec::with_capacity(n + 2 - from);
    disk_s.push(0.0);
    disk_s.extend(robot.disk_s[from..].iter().map(|s| s - base_s));
    let mut cables = Vec::new();
    let mut map = Vec::with_capacity(robot.cables.len());
    for (c, cable) in robot.cables.iter().enumerate() {
        if cable.ends_at < from {
            map.push(None);
            continue;
        }
        map.push(Some(cables.len()));
        cables.push(cut_cable(robot, c, cable, base_s, from, snapped)?);
    }
    let out = Robot {
        name: robot.name.clone(),
        disk_s,
        disk_radius: robot.disk_radius,
        disk_thickness: robot.disk_thickness,
        backbone: robot.backbone.clone(),
        cables,
        loads: robot.loads.clone(),
        port: None,
        body: robot.body,
    };
    Ok(Some(Beyond {
        robot: out,
        s0: base_s,
        straight: if snapped { first } else { 0.0 },
        offset,
        snapped,
        cables: map,
    }))
}

/// Cable `c` from material coordinate `base_s` on: its hole there (the disk's own when
/// `snapped`, else its route evaluated there) and its holes at disks `from..=ends_at`.
fn cut_cable(
    robot: &Robot,
    c: usize,
    cable: &Cable,
    base_s: f64,
    from: usize,
    snapped: bool,
) -> Result<Cable, SolveError> {
    let (r0, a0) = if snapped {
        (cable.radius[from - 1], cable.angle[from - 1])
    } else {
        hole_at(robot, c, base_s, from)?
    };
    let mut radius = vec![r0];
    radius.extend_from_slice(&cable.radius[from..=cable.ends_at]);
    let mut angle = vec![a0];
    angle.extend_from_slice(&cable.angle[from..=cable.ends_at]);
    Ok(Cable {
        name: cable.name.clone(),
        ends_at: cable.ends_at - from + 1,
        radius,
        angle,
        helix: cable.helix.map(|h| Helix {
            start: h.start + h.per_metre * base_s,
            per_metre: h.per_metre,
        }),
        stiffness: cable.stiffness,
        pretension: cable.pretension,
    })
}

/// Hole radius and (unwrapped) angle of cable `c` at material coordinate `s`, inside the
/// section that ends at disk `k`: the declared helix or straight run exactly; a per-disk table
/// by the natural cubic spline through its holes, the angle unwrapped next to the one at disk
/// `k − 1`.
fn hole_at(robot: &Robot, c: usize, s: f64, k: usize) -> Result<(f64, f64), SolveError> {
    let cable = &robot.cables[c];
    if let Some(w) = cable.helix_rate(&robot.disk_s) {
        return Ok((cable.radius[0], cable.angle[0] + w * (s - robot.disk_s[0])));
    }
    let p = Route::new(robot, c, RoutingFit::Spline)?.eval(s, k - 1).r;
    let prev = cable.angle[k - 1];
    let a = p.y.atan2(p.x);
    let turns = ((prev - a) / std::f64::consts::TAU).round();
    Ok((p.norm(), a + turns * std::f64::consts::TAU))
}
