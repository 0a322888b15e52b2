//! Settings of the rod solver: the constitutive model, the resolution (fixed RK4 steps with
//! bend refinement, or adaptive RK45), routing, control, length measure and the Newton budget,
//! each with its default and its bounded parser (`Configure`).

use crate::error::SolveError;
use crate::method::settings::{common, Configure};
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
    /// Take the unloaded path where it applies (`solver = auto`, default): with no external
    /// load and every tension given, the strains follow from the tendons' balance at each
    /// point and one integration gives the shape (`unloaded.rs`); with external loads and
    /// every tension given, the rod shoots on its external moment with the strains from the
    /// same balance (`loaded.rs`). `false` (`solver = shooting`) always shoots on
    /// Rucker–Webster's strain rates.
    pub unloaded: bool,
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
            unloaded: true,
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
    /// Builder: always shoot (`false`), or take the unloaded path where it applies (`true`).
    pub fn with_unloaded(mut self, unloaded: bool) -> Self {
        self.unloaded = unloaded;
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
        let range = self.kind().setting(name)?.values;
        match name {
            "control" => self.control = range.pick(name, value, common::CONTROL_INPUTS)?,
            "routing" => self.routing = range.pick(name, value, common::ROUTING_FITS)?,
            "length" => self.length = range.pick(name, value, common::LENGTH_MEASURES)?,
            "rk4-steps" => self.steps_per_section = range.count(name, value)?,
            "adaptive" => self.adaptive = range.number(name, value)?,
            "bend-refine" => self.bend_refine = range.number(name, value)?.unwrap_or(f64::INFINITY),
            "max-iterations" => self.max_iterations = range.count(name, value)?,
            "tolerance" => self.tolerance = range.real(name, value)?,
            "stability" => self.check_stability = range.pick(name, value, common::ON_OFF)?,
            "solver" => self.unloaded = range.pick(name, value, common::ON_OFF)?,
            _ => return Err(self.kind().unapplied(name)),
        }
        Ok(())
    }

    fn check(&self) -> Result<(), SolveError> {
        let range = |name| self.kind().setting(name).map(|s| s.values);
        range("rk4-steps")?.check_count("rk4-steps", self.steps_per_section)?;
        range("adaptive")?.check_number("adaptive", self.adaptive)?;
        // Off (no refinement) is an infinite threshold.
        let refine = (self.bend_refine != f64::INFINITY).then_some(self.bend_refine);
        range("bend-refine")?.check_number("bend-refine", refine)?;
        range("max-iterations")?.check_count("max-iterations", self.max_iterations)?;
        range("tolerance")?.check_real("tolerance", self.tolerance)?;
        Ok(())
    }
}
