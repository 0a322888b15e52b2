//! What lies between a real robot's commands and measurements and the model: per-cable
//! actuation gain and offset (slack), the pose of the robot base in the measurement frame, and
//! the tip marker's offset. The `[hardware]` table of a model file:
//!
//! ```toml
//! [hardware]
//! gain = 1.0                    # one number, or one per cable in file order [-]
//! offset = 0.0                  # [m], one number or one per cable
//! base_position = [0, 0, 0]     # robot base origin in the measurement frame [m]
//! base_rotation = [0, 0, 0]     # rotation vector (axis × angle) base → measurement [rad]
//! marker = [0, 0, 0]            # marker position in the tip disk's frame [m]
//! backlash = 0.0                # [m], one number or one per cable (sequences only)
//! friction = 0.0                # capstan coefficient μ [-], one or one per cable (sequences only)
//! ```
//!
//! **Actuation.** A cable's `shorten` in the file (and each row's displacement in
//! `ccrkit predict`) is the *commanded* displacement `u` (the servo reading). The model is
//! driven by the shortening `δ = g·u − o`: the gain `g` is a spool-radius (or transmission)
//! error, the offset `o` is slack taken up before the cable pulls (`o < 0`: the cable is
//! already tight by `−o` at zero command). The gain and offset are folded into the validated
//! [`Actuation`] when the file is read, so every displacement-driven method honours them; a cable
//! that also gives a tension, or gives no displacement, is refused by name (the gain and
//! offset act on displacements only, and must not be silently dropped by a force-driven method).
//!
//! **Backlash.** In a sequence of commands (`ccrkit predict`, `ccrkit calibrate`: rows in file
//! order) friction in the transmission makes the cable lag the servo: the model is driven by
//! `δ = g·u − o − ½ b s`, with `s = +1` while the command last moved up (pulling), `−1` after
//! it last moved down, 0 before it moved ([`directions`]). That is a direction-dependent offset
//! of half the backlash width `b` per cable (a dead band of width `b` whose centre follows the
//! direction of motion). A command changes the direction only when it moves by more than
//! [`DIRECTION_DEADBAND`] from where the direction last changed, so the one-tick jitter of a
//! servo holding still does not flip it. A single solve (`ccrkit solve`) has no sequence:
//! `s = 0`.
//!
//! **Friction.** A cable sliding through the holes of bent disks rubs on them: by the capstan
//! (Euler–Eytelwein) law its tension falls from the actuator along the cable as `T(θ) = T_a
//! e^{−μ s θ}`, `θ` the angle the cable has wrapped since the base, `μ` its friction
//! coefficient and `s` its direction of motion as for the backlash (pulled in: the tension
//! falls toward the tie; paid out: it rises). Each row drives the model with the signed
//! coefficient `a = μ s` ([`crate::model::actuation::CableDrive::capstan`]); the energy model
//! honours it (derivation in `src/method/energy/friction.rs`), every other method refuses a
//! row with `a ≠ 0` by name. A single solve has no sequence: `s = 0`, no friction. It is also
//! a hysteresis: at one command the tip sits at different places after a pull and after a
//! release.
//!
//! **Frames.** Methods work in the robot base frame (disk 0 at the origin, z along the
//! undeformed backbone). A measured tip is `p_meas = R_b (p_tip + R_tip m) + t_b` with the tip
//! disk's frame `(p_tip, R_tip)`, the marker `m`, and the base pose `(R_b = exp(ω̂_b), t_b)`
//! ([`Hardware::measured_tip`]). `ccrkit predict` and `ccrkit calibrate` report tips in this
//! frame; `ccrkit solve` and the exports stay in the base frame. A marker fixed in the
//! measurement frame (the OpenCR repository's 8 mm world-z shift) is a base translation.

use super::actuation::{Actuation, Shortening};
use super::bounds;
use super::robot::Robot;
use crate::error::ModelError;
use crate::numeric::so3::{exp_so3, log_so3};
use crate::shape::Shape;
use nalgebra::{Matrix3, Vector3};
use serde::Deserialize;

/// One value for every cable, or one per cable.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub(super) enum PerCable {
    One(f64),
    Each(Vec<f64>),
}

/// The `[hardware]` table as written.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct FileHardware {
    #[serde(default)]
    gain: Option<PerCable>,
    #[serde(default)]
    offset: Option<PerCable>,
    #[serde(default)]
    base_position: Option<[f64; 3]>,
    #[serde(default)]
    base_rotation: Option<[f64; 3]>,
    #[serde(default)]
    marker: Option<[f64; 3]>,
    #[serde(default)]
    backlash: Option<PerCable>,
    #[serde(default)]
    friction: Option<PerCable>,
}

/// Validated hardware description (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Hardware {
    /// Displacement gain per cable, robot order (> 0).
    pub gain: Vec<f64>,
    /// Offset (slack) per cable \[m\], robot order.
    pub offset: Vec<f64>,
    /// Base origin in the measurement frame \[m\].
    pub base_position: Vector3<f64>,
    /// Base orientation in the measurement frame as a rotation vector \[rad\].
    pub base_rotation: Vector3<f64>,
    /// Marker in the tip disk's frame \[m\].
    pub marker: Vector3<f64>,
    /// Backlash width per cable \[m\] (≥ 0; module docs).
    pub backlash: Vec<f64>,
    /// Capstan friction coefficient `μ` per cable (in `[0, MAX_FRICTION]`; module docs).
    pub friction: Vec<f64>,
}

/// Largest friction coefficient a model file may give: `μ = 2` already leaves `e^{−2π} ≈ 0.2 %`
/// of the tension after one turn of wrap; dry friction of a tendon in a hole lies near 0.1–0.3.
pub const MAX_FRICTION: f64 = 2.0;

/// Smallest move of a command \[m\] that changes its direction of motion (module docs): 40 µm,
/// 2.6 encoder ticks of the FTDCR servos (15.3 µm per tick on a 10 mm spool), above the
/// one-tick jitter of a servo holding still.
pub const DIRECTION_DEADBAND: f64 = 4e-5;

/// The direction of motion `s ∈ {−1, 0, +1}` of every cable in every row of a sequence of
/// commands (rows in order, one value per cable; module docs).
pub fn directions(commands: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = commands.first().map_or(0, Vec::len);
    let mut dir = vec![0.0; n];
    let mut anchor: Vec<f64> = commands.first().cloned().unwrap_or_default();
    commands
        .iter()
        .map(|u| {
            for c in 0..n.min(u.len()) {
                let d = u[c] - anchor[c];
                let moved = if d > DIRECTION_DEADBAND {
                    1.0
                } else if d < -DIRECTION_DEADBAND {
                    -1.0
                } else {
                    0.0
                };
                // Follow the command while it keeps its direction; turn when it moves back
                // by more than the dead band from its extreme.
                if moved != 0.0 && moved != dir[c] {
                    dir[c] = moved;
                }
                if moved != 0.0 || (u[c] - anchor[c]) * dir[c] > 0.0 {
                    anchor[c] = u[c];
                }
            }
            dir.clone()
        })
        .collect()
}

fn per_cable(
    field: &str,
    v: &Option<PerCable>,
    n: usize,
    dflt: f64,
) -> Result<Vec<f64>, ModelError> {
    let out = match v {
        None => vec![dflt; n],
        Some(PerCable::One(x)) => vec![*x; n],
        Some(PerCable::Each(xs)) if xs.len() == n => xs.clone(),
        Some(PerCable::Each(xs)) => {
            return Err(ModelError::invalid(
                field,
                format!("needs one value per cable ({n}), got {}", xs.len()),
            ))
        }
    };
    for (k, x) in out.iter().enumerate() {
        if !x.is_finite() {
            return Err(ModelError::invalid(
                format!("{field}[{k}]"),
                format!("must be a finite number, got {x}"),
            ));
        }
    }
    Ok(out)
}

/// A 3-vector of the table (zero when absent), each component finite and in `range`: a base
/// or marker 1e308 m away, or a rotation vector of 1e308 rad (whose norm overflows), made
/// every prediction NaN or inf with exit 0.
fn vec3(
    field: &str,
    v: Option<[f64; 3]>,
    range: &bounds::Range,
) -> Result<Vector3<f64>, ModelError> {
    let v = range.check3(field, v.unwrap_or([0.0; 3]))?;
    Ok(Vector3::new(v[0], v[1], v[2]))
}

impl Hardware {
    /// No gain, offset, base pose or marker: the model's own base frame and tip.
    pub fn identity(cables: usize) -> Self {
        Hardware {
            gain: vec![1.0; cables],
            offset: vec![0.0; cables],
            base_position: Vector3::zeros(),
            base_rotation: Vector3::zeros(),
            marker: Vector3::zeros(),
            backlash: vec![0.0; cables],
            friction: vec![0.0; cables],
        }
    }

    /// Whether cable `c`'s command reaches the model unchanged.
    pub fn is_identity_for(&self, c: usize) -> bool {
        self.gain[c] == 1.0 && self.offset[c] == 0.0
    }

    /// Validate the table for `robot` (gains > 0, offsets smaller than the cable).
    pub(super) fn from_file(f: Option<&FileHardware>, robot: &Robot) -> Result<Self, ModelError> {
        let n = robot.cables.len();
        let Some(f) = f else {
            return Ok(Hardware::identity(n));
        };
        let gain = per_cable("hardware.gain", &f.gain, n, 1.0)?;
        for (c, g) in gain.iter().enumerate() {
            if *g <= 0.0 {
                return Err(ModelError::invalid(
                    format!("hardware.gain[{c}]"),
                    format!(
                        "must be > 0 (a gain ≤ 0 reverses cable `{}`), got {g}",
                        robot.cables[c].name
                    ),
                ));
            }
        }
        let offset = per_cable("hardware.offset", &f.offset, n, 0.0)?;
        for (c, o) in offset.iter().enumerate() {
            let len = robot.undeformed_chord_length(c);
            if o.abs() >= len {
                return Err(ModelError::invalid(
                    format!("hardware.offset[{c}]"),
                    format!(
                        "|{o}| m is not smaller than cable `{}` ({len:.6} m)",
                        robot.cables[c].name
                    ),
                ));
            }
        }
        let backlash = per_cable("hardware.backlash", &f.backlash, n, 0.0)?;
        for (c, b) in backlash.iter().enumerate() {
            let len = robot.undeformed_chord_length(c);
            if *b < 0.0 || *b >= len {
                return Err(ModelError::invalid(
                    format!("hardware.backlash[{c}]"),
                    format!(
                        "must lie in [0, {len:.6}) m (cable `{}`'s length), got {b}",
                        robot.cables[c].name
                    ),
                ));
            }
        }
        let friction = per_cable("hardware.friction", &f.friction, n, 0.0)?;
        for (c, mu) in friction.iter().enumerate() {
            if !(0.0..=MAX_FRICTION).contains(mu) {
                return Err(ModelError::invalid(
                    format!("hardware.friction[{c}]"),
                    format!(
                        "must lie in [0, {MAX_FRICTION}] (a capstan coefficient of cable `{}`), got {mu}",
                        robot.cables[c].name
                    ),
                ));
            }
        }
        Ok(Hardware {
            friction,
            backlash,
            gain,
            offset,
            base_position: vec3(
                "hardware.base_position",
                f.base_position,
                &bounds::COORDINATE,
            )?,
            base_rotation: vec3("hardware.base_rotation", f.base_rotation, &bounds::ANGLE)?,
            marker: vec3("hardware.marker", f.marker, &bounds::COORDINATE)?,
        })
    }

    /// Shortening \[m\] that drives the model for a commanded displacement `u` \[m\] of cable `c`.
    pub fn shortening(&self, c: usize, u: f64) -> f64 {
        self.gain[c] * u - self.offset[c]
    }

    /// Fold gain and offset into the file's actuation: each displacement becomes
    /// [`Hardware::shortening`] of it. A cable with a non-identity gain or offset that gives a
    /// tension, or no displacement, is refused by name.
    pub(super) fn fold(&self, robot: &Robot, act: &mut Actuation) -> Result<(), ModelError> {
        for (c, d) in act.cables.iter_mut().enumerate() {
            if self.is_identity_for(c) {
                continue;
            }
            let name = &robot.cables[c].name;
            let field = format!("hardware.gain[{c}] / hardware.offset[{c}]");
            if d.tension.is_some() {
                return Err(ModelError::invalid(
                    field,
                    format!("cable `{name}` also gives a tension; a gain and offset act on displacements only, give it only `shorten`"),
                ));
            }
            let u = match d.shorten {
                Some(Shortening::Length(x)) => x,
                Some(Shortening::Fraction(f)) => f * robot.undeformed_chord_length(c),
                None => {
                    return Err(ModelError::invalid(
                        field,
                        format!("cable `{name}` has no displacement to apply them to (give `shorten = 0.0`)"),
                    ))
                }
            };
            d.shorten = Some(Shortening::Length(self.shortening(c, u)));
        }
        Ok(())
    }

    /// The model's actuation for commanded displacements `u` \[m\] (one per cable, robot order):
    /// every cable displacement-driven by [`Hardware::shortening`], no tensions.
    pub fn actuation(&self, u: &[f64]) -> Actuation {
        self.actuation_moving(u, &[])
    }

    /// [`Hardware::actuation`] in a sequence, with each cable's direction of motion `dir`
    /// ([`directions`]; missing entries count as 0): `δ = g·u − o − ½ b s` and the signed
    /// capstan coefficient `μ s` (module docs).
    pub fn actuation_moving(&self, u: &[f64], dir: &[f64]) -> Actuation {
        Actuation {
            cables: u
                .iter()
                .enumerate()
                .map(|(c, &x)| {
                    let s = dir.get(c).copied().unwrap_or(0.0);
                    super::actuation::CableDrive {
                        shorten: Some(Shortening::Length(
                            self.shortening(c, x) - 0.5 * self.backlash[c] * s,
                        )),
                        tension: None,
                        capstan: self.friction[c] * s,
                    }
                })
                .collect(),
            insertion: None,
            rotation: None,
        }
    }

    /// Base rotation matrix `R_b`.
    pub fn base_matrix(&self) -> Matrix3<f64> {
        exp_so3(&self.base_rotation)
    }

    /// The same base rotation as a rotation vector of angle ≤ π (log ∘ exp, Barfoot 2017
    /// §7.1.3): a rotation vector is defined modulo 2π along its axis, and calibration starts
    /// from this form (its fit and standard errors are meaningless from |θ| > π).
    ///
    /// ```
    /// use ccrkit::model::hardware::Hardware;
    /// use nalgebra::Vector3;
    ///
    /// let mut h = Hardware::identity(1);
    /// h.base_rotation = Vector3::new(0.0, 2.0 * std::f64::consts::PI + 0.25, 0.0);
    /// let c = h.canonical_base_rotation();
    /// assert!((c - Vector3::new(0.0, 0.25, 0.0)).norm() < 1e-12);
    /// assert!((h.base_matrix() - { h.base_rotation = c; h.base_matrix() }).norm() < 1e-12);
    /// ```
    pub fn canonical_base_rotation(&self) -> Vector3<f64> {
        log_so3(&exp_so3(&self.base_rotation))
    }

    /// The marker of a solved shape in the measurement frame \[m\] (module docs).
    pub fn measured_tip(&self, shape: &Shape) -> Vector3<f64> {
        let tip = &shape.disks[shape.disks.len() - 1];
        self.base_matrix() * (tip.position + tip.rotation * self.marker) + self.base_position
    }

    /// The `[hardware]` table as TOML, for writing a fitted model file.
    pub fn to_toml(&self) -> toml::Table {
        let arr =
            |v: &[f64]| toml::Value::Array(v.iter().map(|x| toml::Value::Float(*x)).collect());
        let mut t = toml::Table::new();
        t.insert("gain".into(), arr(&self.gain));
        t.insert("offset".into(), arr(&self.offset));
        t.insert("base_position".into(), arr(self.base_position.as_slice()));
        t.insert("base_rotation".into(), arr(self.base_rotation.as_slice()));
        t.insert("marker".into(), arr(self.marker.as_slice()));
        if self.backlash.iter().any(|b| *b != 0.0) {
            t.insert("backlash".into(), arr(&self.backlash));
        }
        if self.friction.iter().any(|m| *m != 0.0) {
            t.insert("friction".into(), arr(&self.friction));
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Directions by hand: a pull, a one-tick jitter while holding (no flip), a release, a
    /// small return inside the dead band (no flip), a pull past it.
    #[test]
    fn directions_follow_moves_beyond_the_dead_band() {
        let tick = 1.534e-5;
        let u = [
            0.0,
            1e-3,
            2e-3,
            2e-3 - tick,
            2e-3,
            1e-3,
            1e-3 + 3e-5,
            1e-3 + 1e-4,
        ];
        let rows: Vec<Vec<f64>> = u.iter().map(|&x| vec![x, 0.0]).collect();
        let d: Vec<f64> = directions(&rows).iter().map(|r| r[0]).collect();
        assert_eq!(d, [0.0, 1.0, 1.0, 1.0, 1.0, -1.0, -1.0, 1.0]);
        assert!(directions(&rows).iter().all(|r| r[1] == 0.0));
        // The backlash shifts the shortening by half its width against the motion.
        let mut hw = Hardware::identity(2);
        hw.backlash = vec![4e-4, 0.0];
        let a = hw.actuation_moving(&[1e-3, 1e-3], &[1.0, 1.0]);
        assert_eq!(a.cables[0].shorten, Some(Shortening::Length(1e-3 - 2e-4)));
        assert_eq!(a.cables[1].shorten, Some(Shortening::Length(1e-3)));
    }
}
