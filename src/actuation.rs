//! Per-cable inputs: displacement (shortening), tension, or nothing (free).
//!
//! Displacement-driven methods (geometric, energy) read the shortening; force-driven methods
//! (Cosserat with force control) read the tension. A cable with neither is free: it follows
//! the shape, constrains nothing, and its path is still reported.

use crate::robot::Robot;

/// How much a cable is pulled in at the base.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shortening {
    /// Absolute shortening [m].
    Length(f64),
    /// Shortening as a fraction of the cable's undeformed length (0.04 = 4 %).
    Fraction(f64),
}

/// What drives one cable.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CableDrive {
    /// Displacement input, if any.
    pub shorten: Option<Shortening>,
    /// Tension input [N], if any (≥ 0: cables pull).
    pub tension: Option<f64>,
}

impl CableDrive {
    /// A cable with neither a displacement nor a tension.
    pub fn is_free(&self) -> bool {
        self.shorten.is_none() && self.tension.is_none()
    }
}

/// Inputs for every cable of a robot, index-aligned with [`Robot::cables`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Actuation {
    /// One drive per cable.
    pub cables: Vec<CableDrive>,
}

impl Actuation {
    /// Every cable free.
    pub fn free(robot: &Robot) -> Self {
        Actuation {
            cables: vec![CableDrive::default(); robot.cables.len()],
        }
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

    /// Tension of cable `c` [N], if given.
    pub fn tension(&self, c: usize) -> Option<f64> {
        self.cables.get(c)?.tension
    }

    /// Every displacement and tension scaled by `f` (a point on the path from no actuation to
    /// this one, for continuation).
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
