//! What is fixed during one solve ([`Problem`]): stiffnesses, routes (as per-section cubics
//! for the spline fit), external loads, step counts, undeformed cable lengths; the load case
//! of one pass; and the global static balance that gives the base wrench without integrating.

use super::contact::{Push, RodWorld};
use super::shooting::Setup;
use super::{Buf, Cosserat, RodModel, E3, MAX_CABLES};
use crate::contact::Witness;
use crate::error::SolveError;
use crate::method::Method;
use crate::model::actuation::{Actuation, Drive, Input};
use crate::model::robot::Robot;
use crate::model::routing::{Route, RoutePoint, RoutingFit};
use nalgebra::{DVector, Matrix3, Vector3, Vector6};

/// Loads of one shooting pass.
pub(super) struct LoadCase {
    pub(super) tau: Buf,
    pub(super) lam: f64,
    /// Contact forces at disks (`contact.rs`; empty without obstacles). Not scaled by `lam`:
    /// they are unknowns of the solve, not given loads.
    pub(super) push: Vec<Push>,
}

impl LoadCase {
    /// Tensions `tau` at load factor `lam`, no contact force.
    pub(super) fn new(tau: Buf, lam: f64) -> Self {
        LoadCase {
            tau,
            lam,
            push: Vec::new(),
        }
    }
}

/// Result of one shooting pass.
pub(super) struct Shot {
    /// `[n(L⁺), m(L⁺)/L]`.
    pub(super) resid: Vector6<f64>,
    /// Cable lengths in the chosen measure.
    pub(super) len: Buf,
    /// Tip position.
    pub(super) tip: Vector3<f64>,
    /// The witness of every contact of the load case, in its order (`contact.rs`).
    pub(super) touch: Vec<Witness>,
}

impl Shot {
    /// The shot of a pass that failed: every number NaN.
    pub(super) fn failed() -> Self {
        Shot {
            resid: Vector6::from_element(f64::NAN),
            len: [f64::NAN; MAX_CABLES],
            tip: Vector3::from_element(f64::NAN),
            touch: Vec::new(),
        }
    }
}

/// Recorded geometry of a pass, with the inputs it was shot from.
#[derive(Default)]
pub(super) struct Trace {
    pub(super) disks: Vec<(Vector3<f64>, Matrix3<f64>)>,
    pub(super) backbone: Vec<Vector3<f64>>,
    /// Cable lengths in the chosen measure at the end of the pass (empty until it ends).
    pub(super) len: Vec<f64>,
    pub(super) key: Vec<f64>,
    /// Integrated by the unloaded path (`unloaded.rs`), not by shooting.
    pub(super) fast: bool,
    /// The rest lengths the unloaded and loaded paths compute beside `len`: the straight
    /// rod's, in the same measure and by the same quadrature (empty for shooting, and for the
    /// loaded path's chords, whose rest lengths take a pass at zero load).
    pub(super) rest: Vec<f64>,
}

impl Trace {
    /// Reset for a pass from `n0`, `m0` under `ld` (keeps the buffers' capacity).
    pub(super) fn start(&mut self, n0: &Vector3<f64>, m0: &Vector3<f64>, ld: &LoadCase) {
        self.disks.clear();
        self.backbone.clear();
        self.len.clear();
        self.rest.clear();
        self.key.clear();
        self.fast = false;
        self.key.extend(n0.iter().chain(m0.iter()).chain(&ld.tau));
        self.key.push(ld.lam);
        for p in &ld.push {
            self.key
                .extend([p.touch.disk as f64, p.touch.obstacle as f64, p.force]);
        }
    }
}

/// Everything fixed during one solve.
pub(super) struct Problem<'a> {
    pub(super) robot: &'a Robot,
    pub(super) set: &'a Cosserat,
    pub(super) kse: Vector3<f64>,
    pub(super) kbt: Vector3<f64>,
    pub(super) routes: Vec<Route>,
    pub(super) f_dist: Vector3<f64>,
    pub(super) disk_weight: Vector3<f64>,
    pub(super) tip_f: Vector3<f64>,
    pub(super) tip_m: Vector3<f64>,
    pub(super) len_l: f64,
    pub(super) fscale: f64,
    pub(super) modes: Vec<Drive>,
    /// Undeformed lengths in the chosen measure.
    pub(super) len0: Buf,
    /// Residual scale of each cable's length equation.
    pub(super) kl: Buf,
    /// Each cable's compliance `1/k` \[m/N\] (0: inextensible; [`crate::robot::Cable`]).
    pub(super) compliance: Buf,
    /// Each cable's pretension stretch `T₀/k` \[m\] (0: inextensible).
    pub(super) pre_stretch: Buf,
    /// RK4 steps of each section (index = section, 1-based; entry 0 unused).
    pub(super) nsteps: Vec<usize>,
    /// Spline routes as cubics in `σ = s − s_{k−1}` per section: `[c0, c1, c2, c3]` at
    /// index `(k − 1)·ncables + c` (empty for the Fourier fit; closed-form routes — declared
    /// helices and straight cables — are evaluated exactly instead).
    pub(super) cubic: Vec<[Vector3<f64>; 4]>,
    /// Geometry of the latest pass (so the converged one need not be integrated again).
    pub(super) last: std::cell::RefCell<Trace>,
    /// Step mesh of the adaptive integrator (see [`Mesh`]).
    pub(super) mesh: std::cell::RefCell<Mesh>,
    /// Right-hand-side evaluations spent so far (a tangent direction counts as one more),
    /// against [`WORK_BUDGET`].
    pub(super) work: std::cell::Cell<usize>,
    /// This solve takes the unloaded path (`unloaded.rs`): no external load, tensions given.
    pub(super) fast: bool,
    /// This solve shoots on the external moment (`loaded.rs`): external loads, tensions given.
    pub(super) loaded: bool,
    /// The loaded solve's stability verdict, when its passes carried the Jacobi fields
    /// (`loaded.rs`: no focal point found along the last one).
    pub(super) loaded_focal: std::cell::Cell<Option<bool>>,
    /// The obstacles within reach and the contact feature (`contact.rs`); `None` without.
    pub(super) world: Option<RodWorld<'a>>,
}

/// Right-hand-side evaluations one solve may spend (≈ 9 s for two cables on 3000 sections)
/// before it ends in `NotConverged` naming the budget: every run is bounded, whatever the
/// section count (a 3000-section rod that does not converge took 36 s before it gave up).
/// The paper cases spend ~10³.
pub const WORK_BUDGET: usize = 10_000_000;

impl Problem<'_> {
    /// True once the solve has spent [`WORK_BUDGET`].
    pub(super) fn over_budget(&self) -> bool {
        self.work.get() > WORK_BUDGET
    }

    /// The detail of a `NotConverged` for a spent budget.
    pub(super) fn budget_detail(&self) -> String {
        format!(
            "work budget spent: {} right-hand-side evaluations (limit {WORK_BUDGET})",
            self.work.get()
        )
    }
}

/// The adaptive integrator's steps: recorded by a pass that adapts, replayed by the passes
/// of one Newton solve (frozen), so that the shooting residual is a smooth function of the
/// unknowns there (a step sequence that changes with them makes it jump by the integration
/// error, which stalls line searches and difference Jacobians at tight tolerances).
#[derive(Default)]
pub(super) struct Mesh {
    /// Replay `ends` instead of adapting.
    pub(super) frozen: bool,
    /// Accepted step ends of the last adapting pass, in order.
    pub(super) ends: Vec<f64>,
    /// Next end to replay.
    pub(super) cursor: usize,
    /// Largest scaled error estimate (error / TOL) of the steps of the last pass.
    pub(super) worst: f64,
}

impl Problem<'_> {
    /// The natural-spline routes as one cubic per section (exact: a cubic is fixed by `r`,
    /// `r'`, `r''` at the section start and `r''` at its end), evaluated without the
    /// spline's divisions in the hot loop.
    fn route_cubics(&self) -> Vec<[Vector3<f64>; 4]> {
        if self.set.routing != RoutingFit::Spline {
            return vec![];
        }
        let robot = self.robot;
        let mut out = Vec::with_capacity(robot.sections() * robot.cables.len());
        for k in 1..=robot.sections() {
            let (s0, s1) = (robot.disk_s[k - 1], robot.disk_s[k]);
            for route in &self.routes {
                let a = route.eval(s0, k - 1);
                let b = route.eval(s1, k - 1);
                out.push([a.r, a.dr, a.ddr * 0.5, (b.ddr - a.ddr) / (6.0 * (s1 - s0))]);
            }
        }
        out
    }

    /// Route of cable `c` at `s` in section `sec` (1-based).
    #[inline(always)]
    pub(super) fn eval_route(&self, c: usize, s: f64, sec: usize) -> RoutePoint {
        if self.cubic.is_empty() || self.routes[c].is_closed_form() {
            return self.routes[c].eval(s, sec - 1);
        }
        let [c0, c1, c2, c3] = &self.cubic[(sec - 1) * self.robot.cables.len() + c];
        let x = s - self.robot.disk_s[sec - 1];
        RoutePoint {
            r: c0 + (c1 + (c2 + c3 * x) * x) * x,
            dr: c1 + (c2 * 2.0 + c3 * (3.0 * x)) * x,
            ddr: c2 * 2.0 + c3 * (6.0 * x),
        }
    }

    /// RK4 steps of every section: `steps_per_section`, more where a route bends sharply.
    fn steps_per_section(&self) -> Vec<usize> {
        let robot = self.robot;
        let base = self.set.steps_per_section.max(1);
        let mut out = vec![base; robot.sections() + 1];
        for (k, n) in out.iter_mut().enumerate().skip(1) {
            let (s0, s1) = (robot.disk_s[k - 1], robot.disk_s[k]);
            let h = s1 - s0;
            let mut bend = 0.0f64;
            for (c, cable) in robot.cables.iter().enumerate() {
                if cable.ends_at < k {
                    continue;
                }
                let rbar = 0.5 * (cable.radius[k - 1] + cable.radius[k]);
                let rbar = if rbar > 0.0 { rbar } else { robot.disk_radius };
                let a = self.routes[c].eval(s0, k - 1).ddr.norm();
                let b = self.routes[c].eval(s1, k - 1).ddr.norm();
                bend = bend.max(a.max(b) * h * h / rbar);
            }
            let ratio = bend / self.set.bend_refine;
            if ratio > 1.0 {
                *n = (base as f64 * ratio.sqrt()).ceil() as usize;
            }
        }
        out
    }

    /// Tensions at `x`: the file's (scaled by the load factor `lam`) and the unknown ones.
    pub(super) fn tensions(&self, x: &DVector<f64>, setup: &Setup, lam: f64) -> Buf {
        let mut tau = [0.0; MAX_CABLES];
        for (c, mode) in self.modes.iter().enumerate() {
            if let Drive::Tension(t) = mode {
                tau[c] = t * lam;
            }
        }
        for (j, &c) in setup.unknown.iter().enumerate() {
            tau[c] = x[6 + j];
        }
        tau
    }

    /// True when no external load depends on the shape (no tip force, no weight): then the
    /// global balance below gives the base wrench up to the integration error.
    pub(super) fn shape_free_loads(&self) -> bool {
        self.tip_f == Vector3::zeros()
            && self.f_dist == Vector3::zeros()
            && self.disk_weight == Vector3::zeros()
    }

    /// Base wrench from the static balance of rod + tendons as one body (no integration):
    /// `n(0) + Σ τ_i t_i(0) = F_ext`, `m(0) + Σ r_i(0) × τ_i t_i(0) = M_ext` (tendon loads are
    /// internal to that body; the actuators pull at the base along `t_i(0)`). `t_i(0)` depends
    /// on `v(0)`, `u(0)`, hence a short fixed-point iteration. Moments of the tip force and of
    /// the weights use the straight rod (exact when there are none). Writes `x[0..6]`.
    pub(super) fn balance_guess(&self, x: &mut DVector<f64>, setup: &Setup, lam: f64) {
        let tau = self.tensions(x, setup, lam);
        let (n0, m0) = self.balance(&tau, lam);
        for i in 0..3 {
            x[i] = n0[i];
            x[3 + i] = m0[i] / self.len_l;
        }
    }

    /// The base wrench `(n(0), m(0))` of [`Self::balance_guess`] for tensions `tau`.
    pub(super) fn balance(&self, tau: &Buf, lam: f64) -> (Vector3<f64>, Vector3<f64>) {
        let robot = self.robot;
        let l = self.len_l;
        let tipf = self.tip_f * lam;
        let mut fext = tipf;
        let mut mext = self.tip_m * lam + Vector3::new(0.0, 0.0, l).cross(&tipf);
        for k in 1..=robot.sections() {
            let w = self.disk_weight * lam;
            fext += w;
            mext += Vector3::new(0.0, 0.0, robot.disk_s[k]).cross(&w);
        }
        let g = self.f_dist * (lam * l);
        fext += g;
        mext += Vector3::new(0.0, 0.0, 0.5 * l).cross(&g);
        let (mut n0, mut m0) = (fext, mext);
        // Fixed point on t_i(0) (contraction ≈ τ r²/EI): iterate to rounding.
        for _ in 0..30 {
            let v0 = match self.set.model {
                RodModel::Full => E3 + n0.component_div(&self.kse),
                RodModel::Kirchhoff => E3,
            };
            let u0 = m0.component_div(&self.kbt);
            let (mut n, mut m) = (fext, mext);
            for (route, &t) in self.routes.iter().zip(tau) {
                if t == 0.0 {
                    continue;
                }
                let rp = route.eval(0.0, 0);
                let pd = v0 + u0.cross(&rp.r) + rp.dr;
                let f = pd * (t / pd.norm());
                n -= f;
                m -= rp.r.cross(&f);
            }
            let change = (n - n0).norm() + (m - m0).norm() / l;
            n0 = n;
            m0 = m;
            if change <= 1e-15 * (1.0 + n0.norm() + m0.norm() / l) {
                break;
            }
        }
        (n0, m0)
    }
}

impl Cosserat {
    /// A robot this rod cannot take, refused by name (its settings were checked on the way
    /// in: `Configure::check`, in `Method::solve` and `Method::prepare`).
    fn validate(&self, nc: usize) -> Result<(), SolveError> {
        let name = self.name().to_string();
        if nc > MAX_CABLES {
            return Err(SolveError::Unsupported {
                method: name,
                reason: format!("at most {MAX_CABLES} cables (got {nc})"),
            });
        }
        Ok(())
    }

    /// Everything fixed during a solve: validated settings and inputs, routes, step counts,
    /// undeformed cable lengths. Also returns the report notes.
    pub(super) fn problem<'a>(
        &'a self,
        robot: &'a Robot,
        act: &Actuation,
    ) -> Result<(Problem<'a>, Vec<String>), SolveError> {
        let nc = robot.cables.len();
        self.validate(nc)?;
        let bb = &robot.backbone;
        let len_l = robot.length();
        let fscale = bb.ei() / (len_l * len_l);
        let routes = (0..nc)
            .map(|c| Route::new(robot, c, self.routing))
            .collect::<Result<Vec<_>, _>>()?;
        let mut modes = Vec::with_capacity(nc);
        let mut notes = vec![format!(
            "rod {:?}, routing {:?}, control {}, length {:?}, {}",
            self.model,
            self.routing,
            match self.control {
                Input::Tension => "Force",
                Input::Shortening => "Displacement",
            },
            self.length,
            match self.adaptive {
                Some(t) => format!("adaptive RK45 tol {t:e}"),
                None => format!("RK4 {} steps/section", self.steps_per_section),
            }
        )];
        let drives = self.kind().drives(robot, act, self.control)?;
        for (c, cable) in robot.cables.iter().enumerate() {
            let mode = drives[c];
            if mode == Drive::Free {
                notes.push(format!(
                    "cable `{}` is free (no tension, no displacement)",
                    cable.name
                ));
            }
            modes.push(mode);
        }
        let mut kl = [0.0; MAX_CABLES];
        for (c, cable) in robot.cables.iter().enumerate() {
            let rbar = cable.radius.iter().sum::<f64>() / cable.radius.len().max(1) as f64;
            let rbar = if rbar > 0.0 { rbar } else { robot.disk_radius };
            kl[c] = bb.ei() / (rbar * rbar * len_l);
        }
        let area = bb.area();
        let mut prob = Problem {
            robot,
            set: self,
            kse: Vector3::new(bb.ga(), bb.ga(), bb.ea()),
            kbt: Vector3::new(bb.ei(), bb.ei(), bb.gj()),
            routes,
            f_dist: robot.loads.gravity * (bb.density * area),
            disk_weight: robot.loads.gravity * robot.loads.disk_mass,
            tip_f: robot.loads.tip_force,
            tip_m: robot.loads.tip_moment,
            len_l,
            fscale,
            modes,
            len0: [0.0; MAX_CABLES],
            kl,
            compliance: [0.0; MAX_CABLES],
            pre_stretch: [0.0; MAX_CABLES],
            nsteps: vec![],
            cubic: vec![],
            last: Default::default(),
            mesh: Default::default(),
            work: Default::default(),
            fast: false,
            loaded: false,
            loaded_focal: Default::default(),
            world: None,
        };
        for (c, cable) in robot.cables.iter().enumerate() {
            prob.compliance[c] = cable.compliance();
            prob.pre_stretch[c] = cable.pretension_stretch();
        }
        prob.nsteps = prob.steps_per_section();
        prob.cubic = prob.route_cubics();
        prob.fast = prob.unloaded_applies();
        prob.loaded = prob.loaded_applies();
        if self.adaptive.is_none() {
            let total: usize = prob.nsteps[1..].iter().sum();
            notes[0].push_str(&format!(
                " ({total} in all, bend refinement {})",
                self.bend_refine
            ));
        }
        // Undeformed lengths in the chosen measure: the unloaded, straight rod (exact at
        // zero load), integrated with the same quadrature as the loaded one.
        let zero = LoadCase::new([0.0; MAX_CABLES], 0.0);
        if (0..nc).any(|c| matches!(prob.modes[c], Drive::Shorten { .. })) {
            prob.len0 = match prob.fast {
                // (The unloaded path shortens only cables measured along their paths.)
                true => prob.rest_paths(),
                false => {
                    prob.pass(&Vector3::zeros(), &Vector3::zeros(), &zero, None)
                        .len
                }
            };
        }

        Ok((prob, notes))
    }
}
