//! Inverse problems on the cable inputs: which actuation puts the tip on a target
//! ([`reach()`]), and the shared machinery of [`crate::plan`]: the actuation space with its
//! limits ([`Space`]), the clearance of a shape from the obstacles ([`clearance`]), a bound on
//! how far any robot feature moves between two shapes ([`motion_bound`]) and the tip
//! sensitivities ([`sensitivity`]).
//!
//! # Actuation space
//!
//! The unknowns are the inputs `u` of *every* cable of the robot, in robot order — their
//! shortenings \[m\], or, when the request's method is driven by tension (`energy` with
//! `control = force`, `cosserat`), their tensions \[N\] ([`Space::input`]: *tension space*) —
//! each within its range from the model's limits ([`crate::model::limits`]), and, for a robot
//! deployed through a port ([`crate::model::port`]), its insertion `d` \[m\] and rotation `ψ`
//! \[rad\] after them, within the port's limits: `x = [u₁ … u_k, d, ψ]`.
//!
//! # Effort
//!
//! The least-effort measure is `E(x) = Σ_c u_c² + (ρ_d (d − d₀))² + (ρ_ψ (ψ − ψ₀))²` \[m²\]:
//! the cables' squared shortenings and the base motion away from the model's own port command
//! `(d₀, ψ₀)` (where the robot is), each turned into metres of cable by a scale
//! ([`Space::weights`]): `ρ_d` = [`INSERTION_SCALE`] (a metre of insertion costs as much as a
//! tenth of a metre of cable: the default shortening range is a tenth of the cable's length,
//! so sliding the whole length in or out costs as much as pulling one cable through its range)
//! and `ρ_ψ` = the mean hole radius of the cables \[m/rad\] (turning the robot by `ψ` moves
//! each hole along an arc of `r ψ`, about what a cable pulled to bend it that far moves).
//! Without a port `E = Σ u²`, as before.
//!
//! In tension space the cable terms are squared tensions \[N²\] and the base motion is
//! priced in newtons by the same rule: a metre of cable is worth `T̄ / (0.1 L)` \[N/m\] (the
//! default shortening range, a tenth of the cable, against the mean upper tension limit `T̄`),
//! so `ρ_d = T̄ / L` \[N/m\] and `ρ_ψ = r̄ T̄ / (0.1 L)` \[N/rad\]. A tension space needs a
//! finite upper tension limit on every cable (`[limits.NAME] tension = [lo, hi]`); the
//! shortening limits do not bind there (the answer reports each cable's shortening). A point is
//! solved forward by the requested method (default: `energy`, the displacement-driven
//! whole-robot model) through the same call `ccrkit solve` makes, so a reported actuation is
//! a file's `shorten = …` away from the reported shape.
//!
//! # Clearance
//!
//! By default the robot must stay clear: every feature (disks as cylinders, backbone pieces
//! as capsules of the backbone radius between the shape's backbone samples, cable chords as
//! segments — the features of the obstacle-aware methods) at least the margin (the scene's
//! `clearance`) away from every obstacle, measured with parry3d on the *free* shape (solved
//! without obstacles: a clear robot does not touch, so the obstacle-aware solve gives the same
//! shape). With contact allowed, shapes are solved with the obstacles (the robot may press on
//! them) and no clearance is required.

mod answer;
mod clear;
mod clear_bounds;
mod descend;
mod sens;
mod solve;

pub use clear::{
    clearance, clearance_below, clearance_below_hinted, clearance_hinted, Clearance, ClosestPair,
};
pub use clear_bounds::{clearance_bounds, ClearanceBounds};

pub use answer::{CableActuation, EffortJson, Reach, ReachJson};
pub use sens::{sensitivity, TipSens, FD_STEP};
pub use solve::{reach, reach_in, ReachOptions, Target};

use crate::error::SolveError;
use crate::method::run::SolveRequest;
use crate::method::{MethodKind, Solver};
use crate::model::actuation::{Actuation, CableDrive, Input, Shortening};
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::model::Model;
use crate::numeric::so3::angle_between;
use crate::shape::Shape;
use std::f64::consts::PI;

/// Scale of the insertion in the effort \[m of cable per m of insertion\] (module docs,
/// "Effort").
pub const INSERTION_SCALE: f64 = 0.1;

/// The actuation space of a robot: its cables' shortenings within their limits, a method that
/// solves a point of it, and the obstacles to keep clear of.
pub struct Space {
    /// The robot.
    pub robot: Robot,
    /// What a cable's unknown is: its shortening \[m\] or its tension \[N\] (the request's
    /// method input, module docs "Actuation space").
    pub input: Input,
    /// The method (and settings) every point is solved with.
    pub request: SolveRequest,
    solver: Solver,
    /// The obstacles: the model's and the request's.
    pub scene: Scene,
    /// Scene handed to each solve: empty when keeping clear, the obstacles when contact is
    /// allowed.
    solve_scene: Scene,
    /// Lower bound per unknown: shortening \[m\] or tension \[N\] per cable, then insertion
    /// \[m\] and rotation \[rad\] with a port.
    pub lo: Vec<f64>,
    /// Upper bound per unknown (as `lo`).
    pub hi: Vec<f64>,
    /// Tension range per cable \[N\].
    pub tension: Vec<[f64; 2]>,
    /// Scale of each unknown in the effort (module docs, "Effort"): 1 per cable, then `ρ_d`
    /// \[m/m\] and `ρ_ψ` \[m/rad\] with a port.
    pub weights: Vec<f64>,
    /// Where the effort of each unknown is zero: 0 per cable, then the model's `(d₀, ψ₀)`.
    pub rest: Vec<f64>,
    /// The effort's unit in m² of cable: 1 for shortenings, `(T̄ / (0.1 L))²` \[N²/m²\] in
    /// tension space (module docs, "Effort"); the search's merit prices the target in it.
    pub effort_scale: f64,
    /// Smallest distance every feature keeps from every obstacle \[m\] (default: the scene's
    /// `clearance`).
    pub margin: f64,
    /// Contact allowed (shapes solved with the obstacles, no clearance required).
    pub allow_contact: bool,
}

impl Space {
    /// The actuation space of `model` solved by `request`: shortenings when its method (with
    /// these settings) is driven by shortening, tensions when it is driven by tension.
    pub fn new(
        model: &Model,
        request: &SolveRequest,
        allow_contact: bool,
    ) -> Result<Space, SolveError> {
        let kind: MethodKind = request.method;
        let input = kind.input_with(&request.settings);
        let solver = request.solver()?;
        let scene = request.scene_for(model);
        let solve_scene = if allow_contact {
            scene.clone()
        } else {
            Scene::empty()
        };
        let lim = &model.limits.cables;
        if lim.len() != model.robot.cables.len() || lim.is_empty() {
            return Err(SolveError::InvalidInput {
                field: "limits".into(),
                reason: format!(
                    "{} cable limits for {} cables (a robot without cables has nothing to drive)",
                    lim.len(),
                    model.robot.cables.len()
                ),
            });
        }
        let k = lim.len();
        let (mut lo, mut hi): (Vec<f64>, Vec<f64>) = match input {
            Input::Shortening => lim.iter().map(|l| (l.shorten[0], l.shorten[1])).unzip(),
            Input::Tension => lim.iter().map(|l| (l.tension[0], l.tension[1])).unzip(),
        };
        if let Some(c) = hi.iter().position(|h| !h.is_finite()) {
            return Err(SolveError::InvalidInput {
                field: format!("limits.{}.tension", model.robot.cables[c].name),
                reason: format!(
                    "`{}` drives cables by tension: reach and plan search tensions within \
                     their limits, and need a finite upper tension limit on every cable",
                    kind.name()
                ),
            });
        }
        let mut weights = vec![1.0; k];
        let mut rest = vec![0.0; k];
        let len = model.robot.length();
        // Newtons per metre of cable in tension space (module docs, "Effort").
        let per_metre = match input {
            Input::Shortening => 1.0,
            Input::Tension => hi.iter().sum::<f64>() / k as f64 / (0.1 * len),
        };
        if let Some((d0, psi0)) = model.actuation.port_command(&model.robot)? {
            let ins = model.limits.insertion.unwrap_or([0.0, len]);
            let rot = model.limits.rotation.unwrap_or([-PI, PI]);
            let radius = model
                .robot
                .cables
                .iter()
                .map(|c| c.radius.iter().sum::<f64>() / c.radius.len().max(1) as f64)
                .sum::<f64>()
                / k as f64;
            lo.extend([ins[0], rot[0]]);
            hi.extend([ins[1], rot[1]]);
            weights.extend([INSERTION_SCALE * per_metre, radius * per_metre]);
            rest.extend([d0.clamp(ins[0], ins[1]), psi0.clamp(rot[0], rot[1])]);
        }
        Ok(Space {
            robot: model.robot.clone(),
            input,
            request: request.clone(),
            solver,
            margin: scene.clearance,
            scene,
            solve_scene,
            lo,
            hi,
            tension: lim.iter().map(|l| l.tension).collect(),
            weights,
            rest,
            effort_scale: per_metre * per_metre,
            allow_contact,
        })
    }

    /// True in tension space: the cables' unknowns are tensions \[N\].
    pub fn by_tension(&self) -> bool {
        self.input == Input::Tension
    }

    /// Newtons of tension worth one metre of cable (module docs, "Effort"): `T̄ / (0.1 L)`
    /// \[N/m\] in tension space, 1 for shortenings. The planners' distance divides by it, so
    /// it is in metres of cable in either space ([`crate::plan::metric`]).
    pub fn per_metre(&self) -> f64 {
        self.effort_scale.sqrt()
    }

    /// The name and unit of unknown `i`: `cable `A`` with `m` (`N` in tension space), `the
    /// insertion` (`m`), `the rotation` (`rad`).
    pub fn unknown(&self, i: usize) -> (String, &'static str) {
        match self.robot.cables.get(i) {
            Some(c) if self.by_tension() => (format!("cable `{}` tension", c.name), "N"),
            Some(c) => (format!("cable `{}` shortening", c.name), "m"),
            None if i == self.cables() => ("the insertion".into(), "m"),
            None => ("the rotation".into(), "rad"),
        }
    }

    /// Why `u` is not a point of this space, naming the first unknown outside its limits
    /// (`None` when [`Space::contains`] it).
    pub fn outside(&self, u: &[f64]) -> Option<String> {
        if u.len() != self.dim() {
            return Some(format!(
                "{} values for the {} unknowns of this {} space",
                u.len(),
                self.dim(),
                self.input.name()
            ));
        }
        u.iter().enumerate().find_map(|(i, x)| {
            let (lo, hi) = (self.lo[i], self.hi[i]);
            (!(x.is_finite() && *x >= lo && *x <= hi)).then(|| {
                let (name, unit) = self.unknown(i);
                format!("{name} {x} {unit} lies outside its limits [{lo}, {hi}] {unit}")
            })
        })
    }

    /// Each cable's input at `u` with what the other input was on `shape` (solved at `u`):
    /// shortenings with the tensions they made, or, in tension space, tensions with the
    /// shortenings (path-length changes) they made — what reach's and plan's JSON carry.
    pub fn cable_actuation(&self, u: &[f64], shape: &Shape) -> Vec<CableActuation> {
        CableActuation::of(&self.cable_names(), self.input, u, shape)
    }

    /// Number of unknowns (cables, then insertion and rotation with a port).
    pub fn dim(&self) -> usize {
        self.lo.len()
    }

    /// Number of cables.
    pub fn cables(&self) -> usize {
        self.robot.cables.len()
    }

    /// True when the robot has a port: `x` ends with the insertion and the rotation.
    pub fn has_port(&self) -> bool {
        self.dim() > self.cables()
    }

    /// The effort `E(x)` \[m²\] (module docs, "Effort").
    pub fn effort(&self, x: &[f64]) -> f64 {
        x.iter()
            .zip(&self.weights)
            .zip(&self.rest)
            .map(|((x, w), r)| (w * (x - r)).powi(2))
            .sum()
    }

    /// The insertion and rotation of `x` (`None` without a port).
    pub fn port_of(&self, x: &[f64]) -> Option<(f64, f64)> {
        let k = self.cables();
        (self.has_port() && x.len() >= k + 2).then(|| (x[k], x[k + 1]))
    }

    /// Cable names, in robot order.
    pub fn cable_names(&self) -> Vec<String> {
        self.robot.cables.iter().map(|c| c.name.clone()).collect()
    }

    /// The actuation shortening cable `c` by `u[c]` metres, or pulling it with `u[c]` newtons
    /// in tension space (and, with a port, inserted and turned by the last two entries).
    pub fn actuation(&self, u: &[f64]) -> Actuation {
        self.actuation_with(u, &[])
    }

    /// The actuation shortening cable `c` by `u[c]` metres, except the cables marked in
    /// `released` (shorter slices: none), which are left free: slack, they follow the shape
    /// (the search's released cables, `reach/descend.rs`; none in tension space).
    pub fn actuation_with(&self, u: &[f64], released: &[bool]) -> Actuation {
        let port = self.port_of(u);
        let tension = self.by_tension();
        Actuation {
            cables: u[..u.len().min(self.cables())]
                .iter()
                .enumerate()
                .map(|(c, &x)| CableDrive {
                    shorten: (!tension && !released.get(c).copied().unwrap_or(false))
                        .then_some(Shortening::Length(x)),
                    tension: tension.then_some(x),
                    capstan: 0.0,
                })
                .collect(),
            insertion: port.map(|p| p.0),
            rotation: port.map(|p| p.1),
        }
    }

    /// `u` moved into the limits.
    pub fn clamp(&self, u: &[f64]) -> Vec<f64> {
        u.iter()
            .enumerate()
            .map(|(c, x)| x.clamp(self.lo[c], self.hi[c]))
            .collect()
    }

    /// True when `u` lies within the limits.
    pub fn contains(&self, u: &[f64]) -> bool {
        u.len() == self.dim()
            && u.iter()
                .enumerate()
                .all(|(c, x)| x.is_finite() && *x >= self.lo[c] && *x <= self.hi[c])
    }

    /// Solve the shape at `u` (warm-started from `warm`, a shape of this space), through the
    /// request's [`Solver`] (so through the output check).
    pub fn solve(&self, u: &[f64], warm: Option<&Shape>) -> Result<Shape, SolveError> {
        self.solve_with(u, &[], warm)
    }

    /// [`Space::solve`] with the cables marked in `released` left free
    /// ([`Space::actuation_with`]).
    pub fn solve_with(
        &self,
        u: &[f64],
        released: &[bool],
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        self.solver.solve(
            &self.robot,
            &self.actuation_with(u, released),
            &self.solve_scene,
            warm,
        )
    }

    /// The shape at `u` solved exactly as `ccrkit solve` does (cold, through
    /// [`SolveRequest::run`]): what a reported actuation must reproduce. With contact allowed
    /// it is solved with every obstacle (`ccrkit solve FILE --scene S`); keeping clear, without
    /// them (`ccrkit solve FILE` on the model without its obstacles) — a clear robot touches
    /// nothing, so the obstacle-aware solve finds the same shape where it can start at all (a
    /// cold obstacle-aware solve starts from the straight robot, which may cross a bent tube).
    pub fn solve_as_cli(&self, model: &Model, u: &[f64]) -> Result<Shape, SolveError> {
        let mut m = model.clone();
        m.actuation = self.actuation(u);
        if self.allow_contact {
            Ok(self.request.run(&m)?.shape)
        } else {
            m.scene = Scene::empty();
            Ok(self.request.clone().with_scene(None).run(&m)?.shape)
        }
    }

    /// Clearance of `shape` from the obstacles (`None` without obstacles).
    pub fn clearance(&self, shape: &Shape) -> Option<Clearance> {
        clearance(&self.robot, shape, &self.scene)
    }

    /// [`Space::clearance`] when it is below `cap` \[m\], `None` when the shape is at least
    /// `cap` from every obstacle ([`clearance_below`]: cheaper for a shape well clear).
    pub fn clearance_below(&self, shape: &Shape, cap: f64) -> Option<(Clearance, ClosestPair)> {
        clearance_below(&self.robot, shape, &self.scene, cap)
    }

    /// [`Space::clearance_below`] starting from a hinted closest pair
    /// ([`clearance_below_hinted`]: the same answer).
    pub fn clearance_below_hinted(
        &self,
        shape: &Shape,
        cap: f64,
        hint: Option<ClosestPair>,
    ) -> Option<(Clearance, ClosestPair)> {
        clearance_below_hinted(&self.robot, shape, &self.scene, cap, hint)
    }

    /// [`Space::clearance`] starting from a hinted closest pair, with the closest pair found
    /// ([`clearance_hinted`]: the same answer).
    pub fn clearance_hinted(
        &self,
        shape: &Shape,
        hint: Option<ClosestPair>,
    ) -> Option<(Clearance, ClosestPair)> {
        clearance_hinted(&self.robot, shape, &self.scene, hint)
    }

    /// Why `shape`'s cable tensions break the tension limits (`None` when they keep them;
    /// always in tension space, where the tensions are the unknowns, within their limits).
    pub fn tension_violation(&self, shape: &Shape) -> Option<String> {
        if self.by_tension() {
            return None;
        }
        shape.cables.iter().enumerate().find_map(|(c, cp)| {
            let t = cp.tension?;
            let [lo, hi] = self.tension[c];
            (t < lo - 1e-9 || t > hi + 1e-9).then(|| {
                format!(
                    "cable `{}` needs tension {t:.4} N, outside its limits [{lo}, {hi}] N",
                    cp.name
                )
            })
        })
    }

    /// Certified bounds on the clearance of `shape` from the grids of the scene's solids
    /// ([`clearance_bounds`]: no triangle queried for them; `None` without obstacles, or with an
    /// obstacle that has no grid).
    pub fn clearance_bounds(&self, shape: &Shape) -> Option<ClearanceBounds> {
        clearance_bounds(&self.robot, shape, &self.scene)
    }

    /// Whether the clearance of `shape` is at least `margin` \[m\] (true without obstacles):
    /// the grids' bounds decide where they can ([`ClearanceBounds::keeps`]), the exact
    /// clearance below `margin` where they straddle it — the same answer as the exact
    /// clearance's.
    pub fn keeps_margin(&self, shape: &Shape, margin: f64) -> bool {
        match self.clearance_bounds(shape).and_then(|b| b.keeps(margin)) {
            Some(keeps) => keeps,
            None => self
                .clearance_below(shape, margin)
                .is_none_or(|c| c.0.distance >= margin),
        }
    }

    /// True when `shape` is acceptable: clear by the margin (unless contact is allowed) and
    /// within the tension limits.
    pub fn admissible(&self, shape: &Shape) -> bool {
        let clear = self.allow_contact || self.keeps_margin(shape, self.margin);
        clear && self.tension_violation(shape).is_none()
    }
}

/// An upper bound on how far any point of any robot feature of shape `a` lies from the
/// corresponding point of shape `b` (the Hausdorff distance between the two feature sets is
/// at most this), so every obstacle distance differs between them by at most this \[m\].
///
/// A point of disk `k` at offset `q` (|q| ≤ ρ = √(r² + (t/2)²)) moves by
/// `|Δp_k + (R_b − R_a) q| ≤ |Δp_k| + ρ θ_k` with `θ_k` the angle of `R_aᵀ R_b`
/// (`|R_b − R_a| q| = 2 sin(θ/2) |q_⊥| ≤ θ ρ`). Cable chords join hole points of disks; a
/// point of a segment or capsule moves by at most the larger motion of its two ends (convex
/// combination). Both shapes must have the same disks and backbone samples.
pub fn motion_bound(robot: &Robot, a: &Shape, b: &Shape) -> f64 {
    let rho = robot.disk_radius.hypot(robot.disk_thickness / 2.0);
    let disks = a.disks.iter().zip(&b.disks).map(|(x, y)| {
        (y.position - x.position).norm() + rho * angle_between(&x.rotation, &y.rotation)
    });
    let bb = a
        .backbone
        .iter()
        .zip(&b.backbone)
        .map(|(x, y)| (y - x).norm());
    disks.chain(bb).fold(0.0, f64::max)
}
