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
//! **Frames.** Methods work in the robot base frame (disk 0 at the origin, z along the
//! undeformed backbone). A measured tip is `p_meas = R_b (p_tip + R_tip m) + t_b` with the tip
//! disk's frame `(p_tip, R_tip)`, the marker `m`, and the base pose `(R_b = exp(ω̂_b), t_b)`
//! ([`Hardware::measured_tip`]). `ccrkit predict` and `ccrkit calibrate` report tips in this
//! frame; `ccrkit solve` and the exports stay in the base frame. A marker fixed in the
//! measurement frame (the OpenCR repository's 8 mm world-z shift) is a base translation.

use super::actuation::{Actuation, Shortening};
use super::robot::Robot;
use crate::error::ModelError;
use crate::numeric::so3::exp_so3;
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

fn vec3(field: &str, v: Option<[f64; 3]>) -> Result<Vector3<f64>, ModelError> {
    let v = v.unwrap_or([0.0; 3]);
    for (k, x) in v.iter().enumerate() {
        if !x.is_finite() {
            return Err(ModelError::invalid(
                format!("{field}[{k}]"),
                format!("must be a finite number, got {x}"),
            ));
        }
    }
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
        Ok(Hardware {
            gain,
            offset,
            base_position: vec3("hardware.base_position", f.base_position)?,
            base_rotation: vec3("hardware.base_rotation", f.base_rotation)?,
            marker: vec3("hardware.marker", f.marker)?,
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
        Actuation {
            cables: u
                .iter()
                .enumerate()
                .map(|(c, &x)| super::actuation::CableDrive {
                    shorten: Some(Shortening::Length(self.shortening(c, x))),
                    tension: None,
                })
                .collect(),
        }
    }

    /// Base rotation matrix `R_b`.
    pub fn base_matrix(&self) -> Matrix3<f64> {
        exp_so3(&self.base_rotation)
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
        t
    }
}
