//! Whole-robot energy model (`--method energy`): piecewise constant strains, elastic energy,
//! one total-length constraint per displacement-driven cable. A displacement-driven geometric
//! model that agrees with the Cosserat rod ([`crate::method::cosserat`]).
//!
//! # Kinematics
//!
//! Each section `i` (disks `i−1` → `i`, length `l_i`) is cut into [`Energy::sub_arcs`] sub-arcs
//! of equal undeformed length `ℓ = l_i / sub_arcs`. On sub-arc `j` the strains are constant:
//! body twist `u_j = (κx, κy, τ)` (bending about the body x and y axes, twist about the
//! backbone) and `v_j = (0, 0, 1 + ε)` (axial strain ε; with [`Energy::shear`] also the
//! shear, `v_j = (γx, γy, 1 + ε)`, condensed from its equilibrium: `energy/shear.rs`). The
//! body frame follows
//! `p' = R v`, `R' = R û` (Rucker & Webster 2011, eq. 1), so across the sub-arc it moves by the
//! SE(3) exponential `g_j = exp(ℓ [û_j v_j; 0 0])`, in closed form (Rodrigues, ω = ℓu, θ = |ω|):
//!
//! ```text
//! R = I + A ω̂ + B ω̂²,      p = (I + B ω̂ + C ω̂²) ℓ v,
//! A = sin θ / θ,  B = (1 − cos θ) / θ²,  C = (θ − sin θ) / θ³
//! ```
//!
//! The frame at `s = 0` is the base frame; the disks are square to the backbone, so the frame
//! of disk `k` is the backbone frame at `disk_s[k]` (x axis at hole angle 0).
//!
//! # Energy and constraints
//!
//! `E(ξ) = Σ_j ½ ℓ_j (EI (κx² + κy²) + GJ τ² + EA ε²)` (with the backbone's curvature
//! stiffening `β > 0` the bending term is `EI κ² (1 + β κ²)`, `κ² = κx² + κy²`:
//! [`crate::model::robot::Backbone::stiffening`], `problem.rs`), minimized over all strains `ξ` subject,
//! for every displacement-driven cable `c`, to `L_c(ξ) ≤ L_c⁰ − δ_c`: cables pull, never push
//! (a cable whose path comes out shorter than its length is slack, tension 0). `δ_c` is
//! [`Actuation::shortening_length`] (metres; a percentage is of the straight-chord undeformed
//! length, as for the geometric method) and `L_c⁰` is the undeformed length *in the chosen
//! measure*: the same convention as the Cosserat model's displacement control. A cable that has
//! only a tension `T_c` is force-driven: it adds the potential `T_c L_c(ξ)` to the energy. A
//! cable with neither is free: its path is reported and it constrains nothing.
//!
//! The Lagrangian is `E + Σ λ_c (L_c − L_c⁰ + δ_c)`; at the optimum `∂E/∂L_c = −λ_c`, so the
//! multiplier is the energy released per metre of cable paid out: the cable tension \[N\]
//! (reported in `cables[c].tension`).
//!
//! # Compliant cables
//!
//! A cable with a `stiffness` `k` (cable and actuator in series, [`crate::model::robot::Cable`])
//! stretches by `T/k` under tension `T`: the commanded shortening is taken up by the path change
//! plus the stretch, so its constraint becomes `L_c(ξ) − t_c − λ_c/k_c ≤ 0 ⊥ λ_c ≥ 0` with the
//! unstretched target `t_c = L_c⁰ − δ_c − T₀_c/k_c` (`T₀` the pretension: the cable was tied
//! stretched by `T₀/k`). It is the stabilized (elastic) constraint of a spring: eliminating
//! `λ = k (L − t)₊` gives the potential `½ k (L − t)₊²` (used in the merit). In the step's dual
//! QP, `1/k` adds to the diagonal (a primal stretch variable costing `½ k s²`); the tip
//! Jacobian's KKT system gets `−1/k` on the same diagonal (`energy/sensitivity.rs`). `k → ∞`
//! is the inextensible cable. Cross-checks in `tests/methods/compliance.rs`: the series-spring relation
//! (a compliant solve equals an inextensible one at the effective shortening `δ − T/k`), the
//! closed-form pretension of three symmetric cables, and the Jacobian against central
//! differences.
//!
//! Cable length, [`LengthMeasure`]:
//! * **Path** (default, the rod's measure): the cable runs at `p(s) + R(s) r(s)` with `r(s)` the
//!   C² routing curve of [`crate::model::routing`]. In the body frame its tangent is
//!   `w = v + u × r + r'` (R&W eq. 6–7), so `L_c = Σ_j ∫ |w_j(s)| ds`. `w` is *affine* in the
//!   sub-arc's own strains, `w = w₀(s) + B(s) ξ_j`, hence each `L_c` is a sum of convex,
//!   separable terms with exact derivatives `∇ = Bᵀ ŵ`, `∇² = Bᵀ (I − ŵŵᵀ) B / |w|`. The
//!   problem is convex (quadratic energy, convex constraints), so its KKT point is the global
//!   minimum. The integral uses [`GL_NODES`]-point Gauss–Legendre per sub-arc (the spline is a
//!   cubic inside a section and sub-arcs never straddle a disk); a unit test checks it against a
//!   64×-refined rule: ≤ 5e-12 m on a strongly bent, twisted state of case III.
//! * **Chord**: straight chords between the holes at consecutive disks (as physical disks guide
//!   the cable), `|g_{i,1} ⋯ g_{i,m} h_i − h_{i−1}|`, separable by section. The chord vector and
//!   its Jacobian `J` come from first-order forward AD through the exponentials (`sub_arcs ≤
//!   4`). The constraint curvature first uses only the Gauss–Newton part `Jᵀ (I − d̂d̂ᵀ) J / |d|`
//!   (dropping `Σ d̂ᵢ ∇²dᵢ`; linear convergence, ≈ 9 iterations on the paper's cases); if that
//!   contracts the residual by less than 70 % per iteration after the fourth, or the line
//!   search stalls, the exact Hessian from second-order AD (`numeric::ad::D2`,
//!   quadratic convergence, ≈ 10× dearer per iteration) takes over. Both reach the same KKT point: the residual uses
//!   the exact gradient.
//!
//! Because both measures are separable, the Hessian of the Lagrangian is block diagonal (4×4
//! per sub-arc for paths, `4m × 4m` per section for chords).
//!
//! A frictionless cable that kinks where the strains jump (at sub-arc ends here, at a disk where
//! another cable is tied in the rod) presses on its hole with `τ (t⁺ − t⁻)`; varying the whole
//! path length includes that force automatically. The rod of [`crate::method::cosserat`] adds it
//! as a point force at the disk; before it did, the two disagreed by ≈ 2.4 mm RMS when a cable
//! with `r' ≠ 0` passed a disk where another is tied (`tests/methods/energy.rs`,
//! `agrees_with_cosserat_with_a_helix_passing_a_termination_disk`).
//!
//! # Accuracy (against the rod driven by the same path lengths, 20 RK4 steps per section)
//!
//! `sub_arcs` = 4 (default) gives RMS over the disks 0.000 / 0.014 / 0.088 mm on the paper's
//! cases I / II / III and tensions within 0.0 / 0.24 / 1.24 %; 3 sub-arcs give 0.020 / 0.136 mm
//! and 1.93 % (case III's cable B, which jumps across the disk); 8 give 0.008 / 0.041 mm and
//! 0.55 % (`cargo run --release --example energy_sweep`).
//!
//! # Solver
//!
//! Sequential QP (Newton–KKT) with the exact Lagrangian Hessian of the cable terms,
//! `H = K + Σ (λ_c or T_c) ∇²L_c` (block diagonal). Every displacement-driven cable is a
//! pull-only inequality and every feature–obstacle pair within a margin (module
//! `energy/contacts.rs`) a distance inequality; the step's QP is solved in its dual: with
//! `z = H⁻¹ ∇f` and `y_r = H⁻¹ a_r` for each constraint row `a_r`, the multipliers minimize
//! `½ λᵀ S λ − qᵀ λ` over `λ ≥ 0` (`S = [a_rᵀ y_s]`, `q_r = c_r − a_rᵀ z`; a small dense
//! problem, primal active set in `numeric::qp::nonneg_qp`) and the step is
//! `−z − Σ λ_r y_r`. A cable whose multiplier is zero is slack; a contact whose multiplier is positive presses. Line
//! search on the ℓ1 merit `E + Σ T L + μ Σ max(0, c_r)`, with every pair re-queried at the
//! trial point; a step whose predicted and actual merit changes both lie below the merit's
//! round-off from the cable lengths is taken (the merit cannot judge it; `Problem::merit_roundoff`).
//! Converged when the length residual is ≤ [`Energy::tolerance`] \[m\] and the
//! stationarity residual, expressed as a length (`r̄ |∇ℒ|∞ / (EI ℓ)`, a curvature error
//! times the hole radius), is below the same tolerance (with active contacts, see
//! `energy/contacts.rs` and `CONTACT_STEP`). Cost per iteration is linear in the number of
//! sub-arcs without obstacles. Warm starts read `report.warm`
//! ([`crate::method::warm::WarmState::Energy`]: ξ, λ and the last Hessian blocks, which the
//! first iteration takes instead of rebuilding them) of a previous shape of the same robot
//! and settings, or fit strains to the disk frames of any other shape
//! (e.g. the geometric method's, to start inside a tube).
//!
//! # Loads
//!
//! Gravity (`loads.gravity` on the backbone's `ρ A` per length, lumped half to each end of
//! its sub-arc, and on `loads.disk_mass` at each disk) and `loads.tip_force` are dead loads
//! `F_f` at the sub-arc ends, with the potential `V = −Σ F_f · p_f` added to the objective and
//! its exact gradient (see `add_load_gradient`) to the stationarity, and their exact curvature
//! to the Hessian (`energy/curvature.rs`, shared with the contacts). A dead tip moment has no potential
//! for finite 3-D rotations: [`SolveError::Unsupported`].
//!
//! # Obstacles
//!
//! Distance constraints for backbone sub-arcs, disks and cable chords, with exact gradients
//! in the strains (derivation in `energy/contacts.rs`); the multiplier of a contact is its normal
//! reaction \[N\] (energy J over distance m). No feature passes through an obstacle between
//! iterates — distances to open meshes are unsigned: a step is taken when no point moves
//! farther than the robot's distance to the obstacles (or half the pair margin when closer),
//! or when every feature–obstacle pair passes the distance and separating-plane tests of
//! `energy/step_guard.rs` (which let a feature in contact slide along a convex obstacle). A
//! start that already crosses an obstacle (the straight robot through a bent tube) ends in
//! [`SolveError::Obstructed`] naming the obstacle (across a solid mesh's wall: at once, before
//! the first step); start from a clear shape instead. A base
//! disk inside an obstacle is `Obstructed` at section 0.
//!
//! Errors: a target length ≤ 0, or a solution that needs the backbone compressed below
//! [`Energy::min_stretch`], is [`SolveError::Infeasible`] naming the cable (the most loaded one
//! in the second case) and the section; no convergence within [`Energy::max_iterations`] is
//! [`SolveError::NotConverged`] with the residual. Non-finite values never reach a shape.
//!
//! Speed (paper cases, path, 4 sub-arcs, cold start; `cargo run --release --example
//! energy_timing`, machine shared with other builds): median 25 / 52 / 54 µs (1 / 3 / 3
//! Newton iterations); chord ≈ 0.5 ms (9 iterations). `cargo bench --bench energy`.

// Index loops mirror the block/variable layout of the math below.
#![allow(clippy::needless_range_loop)]

mod assemble;
mod contact_curvature;
mod contacts;
mod curvature;
pub mod friction;
mod kinematics;
mod lengths;
pub(crate) mod local_error;
mod newton;
mod problem;
mod sensitivity;
mod shear;
mod step_guard;
#[cfg(test)]
mod test_fixture;

pub use kinematics::GL_NODES;

use crate::error::SolveError;
use crate::method::settings::{common, Configure};
use crate::method::{Method, MethodKind, Prepared, SolveInput};
use crate::model::actuation::{Actuation, Input, LengthMeasure};
use crate::model::robot::Robot;
use crate::model::routing::RoutingFit;
use crate::model::scene::Scene;
use crate::shape::Shape;
use problem::{Problem, RobotPart, Target};
use std::borrow::Cow;

/// Settings of the whole-robot energy method.
#[derive(Debug, Clone)]
pub struct Energy {
    /// Which input drives a cable that gives both a shortening and a tension.
    pub control: Input,
    /// Constant-strain sub-arcs per section (≥ 1; ≤ 4 with [`LengthMeasure::Chord`]).
    pub sub_arcs: usize,
    /// Sub-arcs of each section, base first, where they differ (empty: [`Energy::sub_arcs`]
    /// in every section; setting `sub-arcs = 1,2,4`): the adaptive discretization `auto`
    /// refines where the a-priori estimate's per-section part is large. Path measure only.
    pub section_sub_arcs: Vec<usize>,
    /// Cable length measure.
    pub cable_length: LengthMeasure,
    /// Routing curve of the path measure.
    pub routing: RoutingFit,
    /// Newton iterations.
    pub max_iterations: usize,
    /// Length and stationarity tolerance \[m\] (see module docs).
    pub tolerance: f64,
    /// Smallest acceptable stretch `1 + ε`: a solution that needs more axial compression means
    /// the shortening cannot be reached by bending ([`SolveError::Infeasible`]).
    pub min_stretch: f64,
    /// Backbone samples per sub-arc in the output shape.
    pub samples_per_sub_arc: usize,
    /// Compute `report.stable` and `report.jacobian` also when contacts press: their
    /// curvature costs `2 · 4 · sub-arcs` contact queries (`sensitivity.rs`). Off: such
    /// solves report neither (a note says so); without pressing contacts both are always
    /// reported.
    pub contact_sensitivity: bool,
    /// Compute `report.stable` and `report.jacobian` at all (default on). Off: a solve
    /// reports neither (a note says so) and skips their KKT solves, e.g. `ccrkit predict`,
    /// which reads only the tip.
    pub sensitivity: bool,
    /// Model the backbone's shear (`v = (γx, γy, 1 + ε)`, `GA |γ|²` in the energy, the
    /// Cosserat rod's continuum): the shear condensed from its equilibrium between Newton
    /// solves (`energy/shear.rs`; next to obstacles the pressing contacts load it and its step
    /// is guarded: `newton/shear_step.rs`). Path measure only, without capstan friction.
    pub shear: bool,
}

impl Default for Energy {
    fn default() -> Self {
        Energy {
            control: Input::Shortening,
            sub_arcs: 4,
            section_sub_arcs: vec![],
            cable_length: LengthMeasure::Path,
            routing: RoutingFit::Spline,
            max_iterations: 60,
            tolerance: 1e-10,
            min_stretch: 0.5,
            samples_per_sub_arc: 1,
            contact_sensitivity: false,
            sensitivity: true,
            shear: false,
        }
    }
}

impl Energy {
    /// Builder: sub-arcs per section.
    pub fn with_sub_arcs(mut self, n: usize) -> Self {
        self.sub_arcs = n;
        self.section_sub_arcs.clear();
        self
    }
    /// Builder: sub-arcs of each section, base first ([`Energy::section_sub_arcs`]).
    pub fn with_section_sub_arcs(mut self, counts: Vec<usize>) -> Self {
        self.section_sub_arcs = counts;
        self
    }
    /// The sub-arcs of each of `robot`'s sections, base first: [`Energy::section_sub_arcs`]
    /// where given (one per section, else refused by name), else [`Energy::sub_arcs`] in each.
    pub fn counts(&self, robot: &Robot) -> Result<Vec<usize>, SolveError> {
        let n = robot.sections();
        if self.section_sub_arcs.is_empty() {
            return Ok(vec![self.sub_arcs; n]);
        }
        if self.section_sub_arcs.len() != n {
            return Err(SolveError::InvalidInput {
                field: "sub-arcs".into(),
                reason: format!(
                    "{} counts given for a robot of {n} sections (one per section, base first)",
                    self.section_sub_arcs.len()
                ),
            });
        }
        Ok(self.section_sub_arcs.clone())
    }
    /// Builder: cable length measure.
    pub fn with_cable_length(mut self, l: LengthMeasure) -> Self {
        self.cable_length = l;
        self
    }
    /// Builder: routing fit.
    pub fn with_routing(mut self, r: RoutingFit) -> Self {
        self.routing = r;
        self
    }
}

impl Configure for Energy {
    fn set(&mut self, name: &str, value: &str) -> Result<(), SolveError> {
        let range = self.kind().setting(name)?.values;
        match name {
            "control" => self.control = range.pick(name, value, common::CONTROL_INPUTS)?,
            "sub-arcs" if value.contains(',') => {
                self.section_sub_arcs = value
                    .split(',')
                    .map(|v| range.count(name, v.trim()))
                    .collect::<Result<_, _>>()?;
                self.sub_arcs = self.section_sub_arcs.iter().copied().max().unwrap_or(1);
            }
            "sub-arcs" => {
                self.sub_arcs = range.count(name, value)?;
                self.section_sub_arcs.clear();
            }
            "length" => self.cable_length = range.pick(name, value, common::LENGTH_MEASURES)?,
            "routing" => self.routing = range.pick(name, value, common::ROUTING_FITS)?,
            "max-iterations" => self.max_iterations = range.count(name, value)?,
            "tolerance" => self.tolerance = range.real(name, value)?,
            "min-stretch" => self.min_stretch = range.real(name, value)?,
            "samples-per-sub-arc" => self.samples_per_sub_arc = range.count(name, value)?,
            "contact-sensitivity" => {
                self.contact_sensitivity = range.pick(name, value, common::ON_OFF)?
            }
            "sensitivity" => self.sensitivity = range.pick(name, value, common::ON_OFF)?,
            "shear" => self.shear = range.pick(name, value, common::ON_OFF)?,
            _ => return Err(self.kind().unapplied(name)),
        }
        Ok(())
    }

    fn check(&self) -> Result<(), SolveError> {
        let range = |name| self.kind().setting(name).map(|s| s.values);
        range("sub-arcs")?.check_count("sub-arcs", self.sub_arcs)?;
        for &n in &self.section_sub_arcs {
            range("sub-arcs")?.check_count("sub-arcs", n)?;
        }
        if self.cable_length == LengthMeasure::Chord && !self.section_sub_arcs.is_empty() {
            return Err(SolveError::InvalidInput {
                field: "sub-arcs".into(),
                reason: "the chord measure takes one count for every section".into(),
            });
        }
        range("max-iterations")?.check_count("max-iterations", self.max_iterations)?;
        range("tolerance")?.check_real("tolerance", self.tolerance)?;
        range("min-stretch")?.check_real("min-stretch", self.min_stretch)?;
        range("samples-per-sub-arc")?
            .check_count("samples-per-sub-arc", self.samples_per_sub_arc)?;
        if self.cable_length == LengthMeasure::Chord && self.sub_arcs > 4 {
            return Err(SolveError::InvalidInput {
                field: "sub-arcs".into(),
                reason: "the chord measure supports at most 4 sub-arcs per section".into(),
            });
        }
        Ok(())
    }
}

impl Method for Energy {
    fn kind(&self) -> MethodKind {
        MethodKind::Energy
    }

    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError> {
        self.ready(input.robot)?.solve_supported(input)
    }

    fn prepare_fixed<'a>(&'a self, robot: &'a Robot) -> Result<Box<dyn Prepared + 'a>, SolveError> {
        Ok(Box::new(self.ready(robot)?))
    }
}

/// The energy model readied for one robot: the settings checked, the routing samples at the
/// Gauss nodes and the undeformed cable lengths computed once ([`Method::prepare`]).
struct ReadyEnergy<'a> {
    set: &'a Energy,
    robot: &'a Robot,
    part: RobotPart,
}

impl Prepared for ReadyEnergy<'_> {
    fn kind(&self) -> MethodKind {
        self.set.kind()
    }
    fn robot(&self) -> &Robot {
        self.robot
    }
    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError> {
        self.solve_at(input.act, input.scene, input.warm)
    }
}

impl Energy {
    /// Check the settings and compute what depends on the robot alone.
    fn ready<'a>(&'a self, robot: &'a Robot) -> Result<ReadyEnergy<'a>, SolveError> {
        // The settings were checked on the way in (`Configure::check`, in `Method::solve`
        // and `Method::prepare`).
        Ok(ReadyEnergy {
            set: self,
            robot,
            part: self.robot_part(robot)?,
        })
    }
}

impl ReadyEnergy<'_> {
    /// One solve of a robot and scene the method supports ([`Prepared::solve_supported`]).
    fn solve_at(
        &self,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        let (set, robot) = (self.set, self.robot);
        let prob = set.setup_from(
            robot,
            act,
            scene,
            Cow::Borrowed(&self.part.nodes),
            &self.part.len0,
        )?;
        let capstan = friction::coefficients(act);
        set.check_shear(capstan.is_some())?;
        let per = if set.section_sub_arcs.is_empty() {
            set.sub_arcs.to_string()
        } else {
            let c: Vec<String> = set.section_sub_arcs.iter().map(|n| n.to_string()).collect();
            c.join(",")
        };
        let mut notes = vec![format!(
            "energy: {per} sub-arcs/section, {:?} cable length, {:?} routing",
            set.cable_length, set.routing
        )];
        if !prob.frame_forces.is_empty() {
            notes.push(
                "gravity and the tip force enter as dead-load potentials (backbone weight lumped \
                 at sub-arc ends); their curvature is in the Hessian"
                    .into(),
            );
        }
        for (c, d) in prob.targets.iter().enumerate() {
            match d {
                Target::Free => notes.push(format!("cable `{}` is free", robot.cables[c].name)),
                Target::Length(_) if act.tension(c).is_some() => notes.push(format!(
                    "cable `{}`: displacement used, tension input ignored",
                    robot.cables[c].name
                )),
                Target::Tension(_) if act.cables[c].shorten.is_some() => notes.push(format!(
                    "cable `{}`: tension used (control = force), displacement input ignored",
                    robot.cables[c].name
                )),
                _ => {}
            }
        }
        if let Some(wd) = &prob.world {
            notes.push(format!(
                "obstacles: {} of {} within reach; contact multipliers are reactions [N]",
                wd.obstacle_count(),
                scene.obstacles.len()
            ));
        }
        if !set.sensitivity {
            notes.push("stable and jacobian not computed (`sensitivity = off`)".into());
        }
        if set.shear {
            notes.push(
                "shear: GA |γ|² in the energy, the shear condensed from its equilibrium \
                 (`energy/shear.rs`); the jacobian at fixed shear"
                    .into(),
            );
        }
        if let Some(a) = capstan {
            notes.push(
                "capstan friction along the cables (lagged weights, `energy/friction.rs`); the \
                 jacobian from the non-symmetric linearization, stable not computed"
                    .into(),
            );
            let from = set.start_point(&prob, warm);
            let (prob, sol) = set.solve_with_friction(prob, &self.part.nodes, &a, from)?;
            return Ok(set.build_shape(&prob, sol, notes));
        }
        let sol = set.newton(&prob, warm)?;
        Ok(set.build_shape(&prob, sol, notes))
    }
}

/// Run `f` on the unactuated, obstacle-free problem of `robot` and `set` once `xi` is known
/// to have the right length: the shared front of the check functions below.
fn with_problem<T>(
    robot: &Robot,
    set: &Energy,
    xi: &[f64],
    f: impl FnOnce(&Problem) -> T,
) -> Result<T, SolveError> {
    let empty = Scene::empty();
    let prob = set.setup(robot, &Actuation::free(robot), &empty)?;
    if xi.len() != prob.nvar() {
        return Err(SolveError::InvalidInput {
            field: "xi".into(),
            reason: format!("expected {} strains, got {}", prob.nvar(), xi.len()),
        });
    }
    Ok(f(&prob))
}

/// Length of every cable of `robot` for the strains `xi` (4 per sub-arc, `sub_arcs` per
/// section) in the measure of `set`: the function the constraints use, exposed for checks.
pub fn cable_lengths(robot: &Robot, set: &Energy, xi: &[f64]) -> Result<Vec<f64>, SolveError> {
    with_problem(robot, set, xi, |prob| {
        let mut out = vec![0.0; robot.cables.len()];
        prob.lengths(xi, &mut out);
        out
    })
}

/// Elastic energy `Σ ½ ℓ (EI κ² + GJ τ² + EA ε²)` \[J\] of the strains `xi` (layout as in
/// [`cable_lengths`]), the objective the method minimizes when every cable is
/// displacement-driven: exposed for checks (e.g. that a contact multiplier is the price of
/// the clearance, `∂E*/∂clearance`).
pub fn elastic_energy(robot: &Robot, set: &Energy, xi: &[f64]) -> Result<f64, SolveError> {
    with_problem(robot, set, xi, |prob| prob.energy(xi))
}
