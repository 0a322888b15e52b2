//! Settings of the rod solver: the constitutive model, the resolution (fixed RK4 steps with
//! bend refinement, or adaptive RK45), routing, control, length measure and the Newton budget,
//! each with its default and its bounded parser (`Configure`).

use crate::error::SolveError;
use crate::method::settings::{
    parse_choice, parse_control, parse_count, parse_in, parse_length, parse_routing, Configure,
    MAX_ITERATIONS,
};
use crate::method::Method;
use crate::model::actuation::{Input, LengthMeasure};
use crate::model::routing::RoutingFit;

/// Rod constitutive model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RodModel {
    /// Shear and extension (Kse = diag(GA, GA, EA)).
    #[default]
    Full,
    /// Inextensible and unshearable (v ≡ e3).
    Kirchhoff,
}

/// Settings of the Cosserat rod solver.
#[derive(Debug, Clone)]
pub struct Cosserat {
    /// Full (shear + extension) or Kirchhoff rod.
    pub model: RodModel,
    /// Fixed RK4 steps per section (used when `adaptive` is `None`) where the routing is
    /// smooth; sections where a cable's route bends sharply get more (see `bend_refine`).
    pub steps_per_section: usize,
    /// Route bend `β_k = max_c h_k² |r_c''| / r̄_c` (over the section's ends and cables)
    /// above which section `k` gets `⌈N (β_k / bend_refine)^½⌉` RK4 steps instead of `N =
    /// steps_per_section`: the tendon load is `∝ τ r''`, so a sharply bent route (case III's
    /// jumping cable B, `β ≈ 6.5`) needs finer steps than a straight or helical one (`β ≤ 0.35`).
    /// `f64::INFINITY` disables the refinement.
    pub bend_refine: f64,
    /// Adaptive Dormand–Prince RK45 with this tolerance (scaled state error) instead of RK4.
    pub adaptive: Option<f64>,
    /// Cable routing fit.
    pub routing: RoutingFit,
    /// Which input drives a cable that gives both (force control: tension).
    pub control: Input,
    /// Cable length measure for displacement control.
    pub length: LengthMeasure,
    /// Newton iterations per solve (per continuation step).
    pub max_iterations: usize,
    /// Residual tolerance \[N\] (moments divided by L, lengths times `EI/(r̄² L)`).
    pub tolerance: f64,
    /// Try Newton at full load first (default); `false` goes straight to load stepping.
    pub direct_start: bool,
    /// Run the focal-point stability test on the answer (`stability = check`, default).
    /// `false` (`stability = skip`) saves its variational pass: `report.stable` is then
    /// `None` meaning *not checked* (a note says so), and a warm start from the shape reuses
    /// Newton's last Jacobian instead of the exact one that pass also gives.
    pub check_stability: bool,
}

impl Default for Cosserat {
    fn default() -> Self {
        Cosserat {
            model: RodModel::Full,
            steps_per_section: 3,
            bend_refine: 0.5,
            adaptive: None,
            routing: RoutingFit::Spline,
            control: Input::Tension,
            length: LengthMeasure::Path,
            max_iterations: 50,
            tolerance: 1e-9,
            direct_start: true,
            check_stability: true,
        }
    }
}

impl Cosserat {
    /// The full rod (`cosserat`).
    pub fn full() -> Self {
        Self::default()
    }
    /// The Kirchhoff rod (`kirchhoff`).
    pub fn kirchhoff() -> Self {
        Cosserat {
            model: RodModel::Kirchhoff,
            ..Self::default()
        }
    }
    /// Builder: control mode.
    pub fn with_control(mut self, control: Input) -> Self {
        self.control = control;
        self
    }
    /// Builder: routing fit.
    pub fn with_routing(mut self, routing: RoutingFit) -> Self {
        self.routing = routing;
        self
    }
    /// Builder: length measure.
    pub fn with_length(mut self, length: LengthMeasure) -> Self {
        self.length = length;
        self
    }
    /// Builder: fixed RK4 steps per section.
    pub fn with_steps(mut self, steps: usize) -> Self {
        self.steps_per_section = steps;
        self
    }
    /// Builder: adaptive RK45 tolerance (`None`: fixed RK4).
    pub fn with_adaptive(mut self, tol: Option<f64>) -> Self {
        self.adaptive = tol;
        self
    }
}

impl Configure for Cosserat {
    fn set(&mut self, name: &str, value: &str) -> Result<(), SolveError> {
        match name {
            "control" => self.control = parse_control(value)?,
            "routing" => self.routing = parse_routing(value)?,
            "length" => self.length = parse_length(value)?,
            "rk4-steps" => self.steps_per_section = parse_count(name, value, 1, 1000)?,
            "adaptive" => {
                self.adaptive = match value.trim() {
                    "off" | "none" => None,
                    v => Some(parse_in(name, v, 1e-14, 1.0)?),
                }
            }
            "bend-refine" => {
                self.bend_refine = match value.trim() {
                    "inf" | "off" => f64::INFINITY,
                    v => parse_in(name, v, 0.0, 1e6)?,
                }
            }
            "max-iterations" => self.max_iterations = parse_count(name, value, 1, MAX_ITERATIONS)?,
            "tolerance" => self.tolerance = parse_in(name, value, 0.0, 1.0)?,
            "stability" => {
                self.check_stability =
                    parse_choice(name, value, &[("check", true), ("skip", false)])?
            }
            _ => return self.kind().check_setting(name),
        }
        Ok(())
    }
}
