//! The answer of [`super::reach`]: reached or the closest found, with its JSON form and the
//! named [`SolveError::Unreachable`] it turns into when the target was not reached.

use super::solve::Target;
use crate::error::SolveError;
use crate::fingerprint::MadeFor;
use crate::model::actuation::Input;
use crate::shape::{Shape, ShapeJson};
use nalgebra::Vector3;
use serde::Serialize;

/// One cable's input in a reach answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CableActuation {
    /// Cable name (as in the model).
    pub cable: String,
    /// Shortening \[m\].
    pub shorten: f64,
    /// Tension of the solved shape \[N\], where the method computes one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tension: Option<f64>,
}

impl CableActuation {
    /// Each cable's entry at the point `u` of a space driven by `input` (`cables` its names,
    /// `shape` solved at `u`): shortenings with the tensions they made, or tensions with the
    /// shortenings — each cable's path-length change — they made.
    pub fn of(cables: &[String], input: Input, u: &[f64], shape: &Shape) -> Vec<CableActuation> {
        cables
            .iter()
            .zip(u)
            .enumerate()
            .map(|(c, (name, &x))| {
                let path = shape.cables.get(c);
                match input {
                    Input::Tension => CableActuation {
                        cable: name.clone(),
                        shorten: path.and_then(|p| p.shortening).unwrap_or(f64::NAN),
                        tension: Some(x),
                    },
                    Input::Shortening => CableActuation {
                        cable: name.clone(),
                        shorten: x,
                        tension: path.and_then(|p| p.tension),
                    },
                }
            })
            .collect()
    }
}

/// The answer of [`super::reach`]: reached or the closest found.
#[derive(Debug, Clone)]
pub struct Reach {
    /// True when the tip (and tangent) are on target within the tolerance, clear of the
    /// obstacles (unless contact is allowed) and within the tension limits.
    pub reached: bool,
    /// The target.
    pub target: Target,
    /// Distance from the tip to the target \[m\].
    pub tip_error_m: f64,
    /// Angle between the tip tangent and the target tangent \[rad\], if one was given.
    pub tangent_error_rad: Option<f64>,
    /// The unknowns: shortenings \[m\] (tensions \[N\] in tension space), one per cable in
    /// robot order, then, with a port, the insertion \[m\] and the rotation \[rad\]
    /// ([`super::Space`]).
    pub u: Vec<f64>,
    /// Insertion `d` \[m\] of a robot with a port.
    pub insertion: Option<f64>,
    /// Rotation `ψ` \[rad\] of a robot with a port.
    pub rotation: Option<f64>,
    /// The same, named, with tensions.
    pub actuation: Vec<CableActuation>,
    /// The effort \[m²; N² in tension space\]: `Σ u²`, plus the scaled base motion with a
    /// port ([`super::Space`], "Effort").
    pub effort_m2: f64,
    /// Clearance of the answer \[m\] (`None` without obstacles).
    pub min_clearance_m: Option<f64>,
    /// The shape, solved as `ccrkit solve` does.
    pub shape: Shape,
    /// SQP iterations over every start.
    pub iterations: usize,
    /// Starts tried.
    pub starts: usize,
    /// Forward solves spent.
    pub solves: usize,
    /// Whether the sensitivities came from the method (`exact`) or central differences.
    pub sensitivities: &'static str,
    /// Why the target was not reached (empty when reached).
    pub reason: String,
    /// True in tension space: `u` and the effort are in newtons ([`super::Space::input`]).
    pub by_tension: bool,
    /// What it was found for: robot, actuation space, obstacles, margin, method — written into
    /// the JSON, checked where the actuation is read back
    /// ([`crate::plan::read_actuation_file`]).
    pub made_for: MadeFor,
}

/// JSON form of a [`Reach`].
#[derive(Debug, Clone, Serialize)]
pub struct ReachJson {
    /// See [`Reach::reached`].
    pub reached: bool,
    /// Target tip \[m\].
    pub target: [f64; 3],
    /// Target tangent, if given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target_tangent: Option<[f64; 3]>,
    /// Tip of the shape \[m\].
    pub tip: [f64; 3],
    /// See [`Reach::tip_error_m`].
    pub tip_error_m: f64,
    /// See [`Reach::tangent_error_rad`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangent_error_rad: Option<f64>,
    /// Per-cable inputs.
    pub actuation: Vec<CableActuation>,
    /// Insertion \[m\] (robots with a port).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub insertion: Option<f64>,
    /// Rotation \[rad\] (robots with a port).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotation: Option<f64>,
    /// Effort measure and value.
    pub effort: EffortJson,
    /// See [`Reach::min_clearance_m`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_clearance_m: Option<f64>,
    /// Search statistics.
    pub iterations: usize,
    /// Starts tried.
    pub starts: usize,
    /// Forward solves spent.
    pub solves: usize,
    /// `exact`, `exact (insertion: central differences)` or `finite-differences`.
    pub sensitivities: &'static str,
    /// Why not reached (absent when reached).
    #[serde(skip_serializing_if = "String::is_empty")]
    pub reason: String,
    /// The space searched: `shortening` (cables' `shorten` \[m\] are the inputs) or `tension`
    /// (their `tension` \[N\]).
    pub space: &'static str,
    /// What it was found for (robot, space, obstacles, margin, method): an actuation file read
    /// back with another robot or space is refused by name.
    pub made_for: MadeFor,
    /// The shape.
    pub shape: ShapeJson,
}

/// The effort measure, named.
#[derive(Debug, Clone, Serialize)]
pub struct EffortJson {
    /// `sum_shorten_squared` (`sum_tension_squared` in tension space), with a port followed by
    /// `_plus_scaled_port_motion` ([`super::Space`], "Effort").
    pub measure: String,
    /// Value \[m²\] (shortenings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value_m2: Option<f64>,
    /// Value \[N²\] (tension space).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value_n2: Option<f64>,
}

impl Reach {
    /// JSON form.
    pub fn to_json(&self) -> ReachJson {
        let a = |v: Vector3<f64>| [v.x, v.y, v.z];
        ReachJson {
            reached: self.reached,
            target: a(self.target.tip),
            target_tangent: self.target.tangent.map(a),
            tip: a(self.shape.tip()),
            tip_error_m: self.tip_error_m,
            tangent_error_rad: self.tangent_error_rad,
            actuation: self.actuation.clone(),
            insertion: self.insertion,
            rotation: self.rotation,
            effort: EffortJson {
                measure: format!(
                    "sum_{}_squared{}",
                    if self.by_tension {
                        "tension"
                    } else {
                        "shorten"
                    },
                    if self.insertion.is_some() {
                        "_plus_scaled_port_motion"
                    } else {
                        ""
                    }
                ),
                value_m2: (!self.by_tension).then_some(self.effort_m2),
                value_n2: self.by_tension.then_some(self.effort_m2),
            },
            min_clearance_m: self.min_clearance_m,
            iterations: self.iterations,
            starts: self.starts,
            solves: self.solves,
            sensitivities: self.sensitivities,
            reason: self.reason.clone(),
            space: if self.by_tension {
                Input::Tension.name()
            } else {
                Input::Shortening.name()
            },
            made_for: self.made_for.clone(),
            shape: self.shape.to_json(),
        }
    }

    /// This answer when reached, else the named [`SolveError::Unreachable`] with the closest
    /// tip.
    pub fn require_reached(self) -> Result<Reach, SolveError> {
        if self.reached {
            return Ok(self);
        }
        let (t, c) = (self.target.tip, self.shape.tip());
        Err(SolveError::Unreachable {
            target: [t.x, t.y, t.z],
            closest: [c.x, c.y, c.z],
            distance: self.tip_error_m,
            reason: self.reason,
        })
    }
}
