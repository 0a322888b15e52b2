//! Per-cable inputs: displacement (shortening), tension, or nothing (free).
//!
//! A model file may give a cable both a shortening and a tension (the paper's files do).
//! [`Actuation`] keeps what the file says; [`Actuation::drives`] resolves it once, for one
//! method, into what actually drives each cable ([`Drive`]): the input the method prefers
//! ([`Input`]) when the cable has it, else the other one if the method can use it, else the
//! cable is refused by name. A cable with neither is free: it follows the shape, constrains
//! nothing, and its path is still reported. Every value is checked here (finite, tension ≥ 0,
//! shortening below the cable's length), so methods receive valid drives.

use crate::error::SolveError;
use crate::model::robot::Robot;

/// The kind of input that drives a cable: a displacement (shortening at the base) or a
/// tension (force).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Input {
    /// Shortening at the base (displacement control).
    Shortening,
    /// Tension \[N\] (force control).
    Tension,
}

impl Input {
    /// Name used in CSV files and on the command line (`shortening_fraction` or `tension_n`).
    pub fn csv_name(self) -> &'static str {
        match self {
            Input::Shortening => "shortening_fraction",
            Input::Tension => "tension_n",
        }
    }
    /// Axis label for a cable.
    pub fn label(self, cable: &str) -> String {
        match self {
            Input::Shortening => format!("{cable} shortening [%]"),
            Input::Tension => format!("{cable} tension [N]"),
        }
    }
    /// Human name: `shortening` or `tension`.
    pub fn name(self) -> &'static str {
        match self {
            Input::Shortening => "shortening",
            Input::Tension => "tension",
        }
    }
}

/// How a cable's length is measured (displacement control): along its routed path or as
/// straight chords between the holes of consecutive disks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum LengthMeasure {
    /// Along the routed C² curve `p + R r(s)` (the Cosserat rod's measure; default).
    #[default]
    Path,
    /// Straight chords between the holes at consecutive disks (the geometric model's).
    Chord,
}

/// What drives one cable in a solve, resolved by [`Actuation::drives`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Drive {
    /// Shortened at the base.
    Shorten {
        /// Shortening \[m\].
        length: f64,
        /// The same as a fraction of the cable's undeformed straight-chord length.
        fraction: f64,
    },
    /// Pulled with this tension \[N\] (≥ 0).
    Tension(f64),
    /// Neither: the cable follows the shape.
    #[default]
    Free,
}

impl Drive {
    /// The input kind of a driven cable (`None` when free).
    pub fn input(&self) -> Option<Input> {
        match self {
            Drive::Shorten { .. } => Some(Input::Shortening),
            Drive::Tension(_) => Some(Input::Tension),
            Drive::Free => None,
        }
    }
}

/// How much a cable is pulled in at the base.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shortening {
    /// Absolute shortening \[m\].
    Length(f64),
    /// Shortening as a fraction of the cable's undeformed length (0.04 = 4 %).
    Fraction(f64),
}

/// What drives one cable.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CableDrive {
    /// Displacement input, if any.
    pub shorten: Option<Shortening>,
    /// Tension input \[N\], if any (≥ 0: cables pull).
    pub tension: Option<f64>,
    /// Signed capstan coefficient `a = μ s` \[1/rad\] of a displacement-driven cable sliding
    /// through its holes (`μ` the friction coefficient, `s = ±1` the direction it slides, `+1`
    /// while it is pulled in): its tension falls from the actuator along the cable as
    /// `e^{−a θ}` with `θ` the angle it has wrapped ([`crate::model::hardware`], "Friction").
    /// 0 (the default): frictionless. Only the energy model honours it; [`Actuation::drives`]
    /// refuses it by name for every other method.
    pub capstan: f64,
}

impl CableDrive {
    /// A cable with neither a displacement nor a tension.
    pub fn is_free(&self) -> bool {
        self.shorten.is_none() && self.tension.is_none()
    }
}

/// Inputs for every cable of a robot, index-aligned with [`Robot::cables`], and the two base
/// degrees of freedom of a robot deployed through a port ([`crate::model::port`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Actuation {
    /// One drive per cable.
    pub cables: Vec<CableDrive>,
    /// Insertion `d` \[m\]: the robot's length out of its port, in `[0, L]` (`None`: all of it,
    /// `d = L`). Only for a robot with a port; refused by name otherwise.
    pub insertion: Option<f64>,
    /// Rotation `ψ` \[rad\] of the robot about its port's axis (`None`: 0). Only for a robot
    /// with a port; refused by name otherwise.
    pub rotation: Option<f64>,
}

impl Actuation {
    /// Every cable free (and, with a port, the robot all the way out, unturned).
    pub fn free(robot: &Robot) -> Self {
        Actuation {
            cables: vec![CableDrive::default(); robot.cables.len()],
            insertion: None,
            rotation: None,
        }
    }

    /// The port command `(d, ψ)` this actuation gives `robot`, checked: `None` for a robot
    /// without a port (which refuses an insertion or a rotation by name); absent values are
    /// `d = L` and `ψ = 0`; `d` must lie in `[0, L]`, `ψ` be finite.
    pub fn port_command(&self, robot: &Robot) -> Result<Option<(f64, f64)>, SolveError> {
        if robot.port.is_none() {
            let given = [("insertion", self.insertion), ("rotation", self.rotation)];
            if let Some((field, Some(v))) = given.into_iter().find(|(_, v)| v.is_some()) {
                return Err(SolveError::InvalidInput {
                    field: field.into(),
                    reason: format!(
                        "{field} {v} is an input of a robot deployed through a port; robot `{}` \
                         has none (give its model file a [port] table)",
                        robot.name
                    ),
                });
            }
            return Ok(None);
        }
        let d = match self.insertion {
            Some(d) => crate::model::port::check_insertion("insertion", d, robot.length())
                .map_err(SolveError::from)?,
            None => robot.length(),
        };
        let psi = match self.rotation {
            Some(r) => {
                crate::model::port::check_rotation("rotation", r).map_err(SolveError::from)?
            }
            None => 0.0,
        };
        Ok(Some((d, psi)))
    }

    /// Set the insertion \[m\] (builder style, for sweeps).
    pub fn with_insertion(mut self, d: f64) -> Self {
        self.insertion = Some(d);
        self
    }

    /// Set the rotation \[rad\] (builder style, for sweeps).
    pub fn with_rotation(mut self, psi: f64) -> Self {
        self.rotation = Some(psi);
        self
    }

    /// Shortening of cable `c` as a fraction Δ of its undeformed chord length
    /// (see [`Robot::undeformed_chord_length`]), or `None` if it has no displacement input.
    pub fn shortening_fraction(&self, robot: &Robot, c: usize) -> Option<f64> {
        match self.cables.get(c)?.shorten? {
            Shortening::Fraction(f) => Some(f),
            Shortening::Length(d) => Some(d / robot.undeformed_chord_length(c)),
        }
    }

    /// Shortening of cable `c` in metres of its undeformed chord length, if given.
    pub fn shortening_length(&self, robot: &Robot, c: usize) -> Option<f64> {
        match self.cables.get(c)?.shorten? {
            Shortening::Fraction(f) => Some(f * robot.undeformed_chord_length(c)),
            Shortening::Length(d) => Some(d),
        }
    }

    /// Tension of cable `c` \[N\], if given.
    pub fn tension(&self, c: usize) -> Option<f64> {
        self.cables.get(c)?.tension
    }

    /// Resolve every cable's input for a method named `method` that accepts the inputs
    /// `accepts` and prefers `prefer` where a cable gives both. A cable that gives only an
    /// input the method cannot use is refused by name (never silently treated as free).
    /// Values are checked: finite, tension ≥ 0, shortening below the cable's undeformed
    /// length (a fraction in (−1, 1)). A cable's capstan friction ([`CableDrive::capstan`])
    /// is checked (finite, on a displacement-driven cable) and left for the method to read;
    /// whether the method models it at all is the registry's to say, and a method that does
    /// not refuses it by name before resolving (`MethodKind::drives`, the one caller).
    pub fn drives(
        &self,
        robot: &Robot,
        method: &str,
        accepts: &[Input],
        prefer: Input,
    ) -> Result<Vec<Drive>, SolveError> {
        if self.cables.len() != robot.cables.len() {
            return Err(SolveError::InvalidInput {
                field: "actuation".into(),
                reason: format!(
                    "gives {} cable inputs for a robot with {} cables",
                    self.cables.len(),
                    robot.cables.len()
                ),
            });
        }
        let mut out = Vec::with_capacity(self.cables.len());
        for (c, d) in self.cables.iter().enumerate() {
            // Checked in full where it drives the cable (below); a shortening the method
            // does not use (a cable that gives both, driven by tension) must still be finite.
            let short = match d.shorten {
                Some(_) => Some(self.finite_shortening(robot, c)?),
                None => None,
            };
            if let Some(t) = d.tension {
                if !(t.is_finite() && t >= 0.0) {
                    return Err(SolveError::InvalidInput {
                        field: format!("cables[{c}].tension"),
                        reason: format!("must be finite and ≥ 0 (cables pull), got {t}"),
                    });
                }
            }
            let other = match prefer {
                Input::Shortening => Input::Tension,
                Input::Tension => Input::Shortening,
            };
            let pick = |i: Input| match i {
                Input::Shortening => {
                    short.map(|(length, fraction)| Drive::Shorten { length, fraction })
                }
                Input::Tension => d.tension.map(Drive::Tension),
            };
            let usable = |i: Input| accepts.contains(&i);
            let drive = [prefer, other]
                .into_iter()
                .filter(|&i| usable(i))
                .find_map(pick);
            let drive = match drive {
                Some(Drive::Shorten { .. }) => {
                    let (length, fraction) = self.checked_shortening(robot, c)?;
                    Drive::Shorten { length, fraction }
                }
                Some(x) => x,
                None if d.is_free() => Drive::Free,
                None => {
                    let given = if short.is_some() {
                        Input::Shortening
                    } else {
                        Input::Tension
                    };
                    let by: Vec<&str> = accepts.iter().map(|i| i.name()).collect();
                    return Err(SolveError::InvalidInput {
                        field: format!("cables[{c}]"),
                        reason: format!(
                            "{method} is driven by {}; cable `{}` gives only {}",
                            by.join(" or "),
                            robot.cables[c].name,
                            given.name()
                        ),
                    });
                }
            };
            if d.capstan != 0.0
                && !(d.capstan.is_finite() && matches!(drive, Drive::Shorten { .. }))
            {
                return Err(SolveError::InvalidInput {
                    field: format!("cables[{c}].capstan"),
                    reason: format!(
                        "capstan friction {} acts on a finite, displacement-driven cable; cable `{}` is not",
                        d.capstan, robot.cables[c].name
                    ),
                });
            }
            out.push(drive);
        }
        Ok(out)
    }

    /// Shortening of cable `c` as (metres, fraction), checked: finite and in (−L, L) for the
    /// cable's undeformed straight-chord length `L` (a shortening of `L` or more is
    /// [`SolveError::Infeasible`]: no shape can reach it).
    fn checked_shortening(&self, robot: &Robot, c: usize) -> Result<(f64, f64), SolveError> {
        let (len, frac) = self.finite_shortening(robot, c)?;
        if frac >= 1.0 {
            return Err(SolveError::Infeasible {
                cable: robot.cables[c].name.clone(),
                section: robot.cables[c].ends_at,
                reason: format!(
                    "shortening {len} m is not less than the cable's undeformed straight-chord \
                     length {:.6} m",
                    robot.undeformed_chord_length(c)
                ),
            });
        }
        Ok((len, frac))
    }

    /// Shortening of cable `c` as (metres, fraction), finite and a payout smaller than the
    /// cable (fraction > −1).
    fn finite_shortening(&self, robot: &Robot, c: usize) -> Result<(f64, f64), SolveError> {
        let frac = self.shortening_fraction(robot, c).unwrap_or(0.0);
        let len = self.shortening_length(robot, c).unwrap_or(0.0);
        if !(frac.is_finite() && len.is_finite() && frac > -1.0) {
            return Err(SolveError::InvalidInput {
                field: format!("cables[{c}].shorten"),
                reason: format!(
                    "shortening {len} m ({:.4} % of the cable's undeformed length) must be \
                     finite, and a payout smaller than the cable",
                    100.0 * frac
                ),
            });
        }
        Ok((len, frac))
    }

    /// Every displacement and tension scaled by `f` (a point on the path from no actuation to
    /// this one, for continuation); the insertion and rotation are kept (they move the robot,
    /// they do not load it).
    pub fn scaled(&self, f: f64) -> Actuation {
        let mut a = self.clone();
        for d in &mut a.cables {
            d.shorten = d.shorten.map(|s| match s {
                Shortening::Length(x) => Shortening::Length(f * x),
                Shortening::Fraction(x) => Shortening::Fraction(f * x),
            });
            d.tension = d.tension.map(|t| f * t);
        }
        a
    }

    /// Set the shortening of the named cable as a fraction (builder style, for sweeps).
    pub fn with_fraction(mut self, c: usize, fraction: f64) -> Self {
        if let Some(d) = self.cables.get_mut(c) {
            d.shorten = Some(Shortening::Fraction(fraction));
        }
        self
    }

    /// Set the tension of cable `c` (builder style, for sweeps).
    pub fn with_tension(mut self, c: usize, tension: f64) -> Self {
        if let Some(d) = self.cables.get_mut(c) {
            d.tension = Some(tension);
        }
        self
    }
}
