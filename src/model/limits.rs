//! Actuation limits: the range each cable's input may take, for the inverse problems
//! ([`crate::reach`], [`crate::plan`]).
//!
//! ```toml
//! [limits.A]                    # one table per cable, by name (optional)
//! shorten = [0.0, 0.012]        # shortening range [m] (or shorten_percent = [0.0, 6.0])
//! tension = [0.0, 25.0]         # tension range [N]
//! ```
//!
//! Defaults, for a cable without a table or a table without the field:
//! * **shortening**: ± [`DEFAULT_MAX_SHORTEN_FRACTION`] (10 %) of the cable's undeformed
//!   straight-chord length ([`crate::robot::Robot::undeformed_chord_length`]): a negative
//!   shortening pays the cable out, which a cable on the outside of a bend needs (it gets
//!   longer; a pull-only cable held at its length would fight the bend);
//! * **tension**: from 0 to unbounded (cables pull; the motor is assumed strong enough).
//!
//! Checked here, once, naming the field: the cable exists; both ends finite; `min ≤ max`;
//! the shortening range lies in (−L, L) for the cable's undeformed chord length `L` (a payout
//! or a shortening of the whole cable is no actuation); the tension range lies in `[0, ∞)`.
//! Displacement-driven inverse problems search within the shortening range and check the
//! tensions of the solved shape against the tension range.

use super::robot::Robot;
use crate::error::ModelError;
use serde::Deserialize;
use std::collections::BTreeMap;

/// Default largest shortening, as a fraction of a cable's undeformed straight-chord length.
pub const DEFAULT_MAX_SHORTEN_FRACTION: f64 = 0.10;

/// Limits of one cable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CableLimits {
    /// Shortening range `[min, max]` \[m\].
    pub shorten: [f64; 2],
    /// Tension range `[min, max]` \[N\] (`max` may be `f64::INFINITY`).
    pub tension: [f64; 2],
}

/// Limits of every cable, index-aligned with [`Robot::cables`], and of the port's insertion
/// and rotation when the robot has a port (`[port] limits = { insertion, rotation }`,
/// [`crate::model::port`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Limits {
    /// One entry per cable.
    pub cables: Vec<CableLimits>,
    /// Insertion range `[min, max]` \[m\] within `[0, L]` (`None` without a port; default
    /// `[0, L]`).
    pub insertion: Option<[f64; 2]>,
    /// Rotation range `[min, max]` \[rad\] (`None` without a port; default `[−π, π]`).
    pub rotation: Option<[f64; 2]>,
}

impl Limits {
    /// The documented defaults for every cable of `robot`.
    pub fn defaults(robot: &Robot) -> Limits {
        Limits {
            cables: (0..robot.cables.len())
                .map(|c| CableLimits {
                    shorten: [
                        -DEFAULT_MAX_SHORTEN_FRACTION * robot.undeformed_chord_length(c),
                        DEFAULT_MAX_SHORTEN_FRACTION * robot.undeformed_chord_length(c),
                    ],
                    tension: [0.0, f64::INFINITY],
                })
                .collect(),
            insertion: robot.port.as_ref().map(|_| [0.0, robot.length()]),
            rotation: robot
                .port
                .as_ref()
                .map(|_| [-std::f64::consts::PI, std::f64::consts::PI]),
        }
    }
}

/// The `[limits.NAME]` table of a model file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileLimit {
    shorten: Option<[f64; 2]>,
    shorten_percent: Option<[f64; 2]>,
    tension: Option<[f64; 2]>,
}

fn range(field: &str, r: [f64; 2], lo: f64, hi: f64, unit: &str) -> Result<[f64; 2], ModelError> {
    for (k, v) in r.iter().enumerate() {
        if !v.is_finite() {
            return Err(ModelError::invalid(
                format!("{field}[{k}]"),
                format!("must be a finite number, got {v}"),
            ));
        }
    }
    if r[0] > r[1] {
        return Err(ModelError::invalid(
            field,
            format!("min {} {unit} exceeds max {} {unit}", r[0], r[1]),
        ));
    }
    if r[0] < lo || r[1] > hi {
        return Err(ModelError::invalid(
            field,
            format!(
                "[{}, {}] {unit} must lie within [{lo}, {hi}] {unit}",
                r[0], r[1]
            ),
        ));
    }
    Ok(r)
}

/// Validate the `[limits]` tables against the robot (defaults for what is not given).
pub(super) fn validate(
    file: &BTreeMap<String, FileLimit>,
    robot: &Robot,
) -> Result<Limits, ModelError> {
    let mut out = Limits::defaults(robot);
    for (name, fl) in file {
        let field = |f: &str| format!("limits.{name}.{f}");
        let c = robot
            .cables
            .iter()
            .position(|c| &c.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = robot.cables.iter().map(|c| c.name.as_str()).collect();
                ModelError::invalid(
                    format!("limits.{name}"),
                    format!("no cable is named `{name}` (cables: {})", names.join(", ")),
                )
            })?;
        let chord = robot.undeformed_chord_length(c);
        // Strictly inside (−L, L): the open interval, checked on the bound below.
        let open = |f: &str, r: [f64; 2], scale: f64, unit: &str| -> Result<[f64; 2], ModelError> {
            let r = range(&field(f), r, -scale, scale, unit)?;
            if r[0] <= -scale || r[1] >= scale {
                return Err(ModelError::invalid(
                    field(f),
                    format!(
                        "must lie strictly within the cable's undeformed length ({scale} {unit})"
                    ),
                ));
            }
            Ok(r)
        };
        match (fl.shorten, fl.shorten_percent) {
            (Some(_), Some(_)) => {
                return Err(ModelError::invalid(
                    field("shorten_percent"),
                    "give either shorten or shorten_percent, not both",
                ))
            }
            (Some(r), None) => out.cables[c].shorten = open("shorten", r, chord, "m")?,
            (None, Some(r)) => {
                let p = open("shorten_percent", r, 100.0, "%")?;
                out.cables[c].shorten = [p[0] / 100.0 * chord, p[1] / 100.0 * chord];
            }
            (None, None) => {}
        }
        if let Some(t) = fl.tension {
            out.cables[c].tension = range(&field("tension"), t, 0.0, f64::MAX, "N")?;
        }
    }
    Ok(out)
}
