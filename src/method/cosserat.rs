//! Static Cosserat rod with general tendon routing (Rucker & Webster, IEEE T-RO 27(6) 2011):
//! the reference model of ccrkit (`--method cosserat`, and `--method kirchhoff` for the
//! inextensible, unshearable limit).
//!
//! # Equations (Rucker & Webster 2011, §II–III; symbols as in the paper)
//!
//! The equation numbers below ("R&W eq. k") follow our reading of the paper and have not been
//! checked against its text, which is not available here; every equation is written out in
//! full, so each can be checked on its own, and the closed-form tests (arc, cantilever,
//! global balance) check the implementation independently of the numbering.
//!
//! States along the undeformed arc length `s`: position `p`, orientation `R` (columns = body
//! axes; `R(0) = I`, so the body x axis points at hole angle 0), and the strains `v`, `u`
//! (body frame). Kinematics (R&W eq. 1): `p' = R v`, `R' = R û`.
//! Linear constitutive law (R&W eq. 4–5, `v* = e3`, `u* = 0`):
//! `n = R Kse (v − e3)`, `m = R Kbt u`, `Kse = diag(GA, GA, EA)`, `Kbt = diag(EI, EI, GJ)`.
//! Rod equilibrium (R&W eq. 2–3): `n' + f + f_t = 0`, `m' + p' × n + l + l_t = 0`, with
//! `f = ρ A g` (gravity) and `l = 0`.
//!
//! Tendon `i` runs at `p_i = p + R r_i(s)` (R&W eq. 6), with `r_i` from [`crate::model::routing`].
//! In the body frame `ṗ_i = û r_i + r_i' + v` and, frictionless with constant tension `τ_i`,
//! it loads the rod per unit length with `f_t = Σ A_i p̈_i`, `l_t = Σ r̂_i A_i p̈_i`
//! (R&W eq. 9–12), `A_i = −τ_i ṗ̂_i² / |ṗ_i|³`. Writing `p̈_i = û ṗ_i + û r_i' + r_i'' + v' − r̂_i u'`
//! makes the loads linear in `v'`, `u'`; substituting into the equilibrium gives the paper's
//! final system (R&W eq. 13–17):
//!
//! ```text
//! [Kse + A   G      ] [v']   [d]      A = Σ A_i,  B = Σ r̂_i A_i,  G = −Σ A_i r̂_i,  H = −Σ r̂_i A_i r̂_i
//! [B         Kbt + H] [u'] = [c]      a = Σ A_i (û ṗ_i + û r_i' + r_i''),  b = Σ r̂_i a_i
//! c = −û Kbt u − v̂ Kse (v − e3) − Rᵀ l − b,      d = −û Kse (v − e3) − Rᵀ f − a
//! ```
//!
//! (The equation numbers follow the paper's §III as we read it offline; the symbols are the
//! paper's.) **Kirchhoff** (`v ≡ e3`): `n` cannot come from `v`, so it is a state instead,
//! `(Kbt + H) u' = −û Kbt u − e3 × Rᵀn − Rᵀ l − b`, `n' = −f − R (a + G u')`.
//!
//! **Tendon terminations and disk loads.** A tendon tied at disk `k` (possibly an inner disk)
//! pulls the rod there with the point force `F = −τ t` at `p + R r`, `t = R ṗ_i/|ṗ_i|` taken
//! just before `s_k` (R&W eq. 18–19). Static balance of the infinitesimal slice gives the
//! jumps `n(s_k⁺) = n(s_k⁻) − F`, `m(s_k⁺) = m(s_k⁻) − (R r) × F`; disk weights (disks 1..=n) and
//! the tip wrench (`loads.tip_force`, `tip_moment`, at disk n) enter the same way. The
//! boundary condition is `n(L⁺) = 0`, `m(L⁺) = 0`. Since every disk is an integration step
//! boundary (sections are integrated one after another, each step starting at its own start
//! arc length), the jumps are exact.
//!
//! # Shooting
//!
//! Unknowns: the base wrench `n(0)`, `m(0)/L` and, for displacement-controlled taut cables, the
//! tension. Residual: `[n(L⁺), m(L⁺)/L]` \[N\] and, per length-controlled cable,
//! `k_ℓ (ℓ − ℓ_target)` with `k_ℓ = EI/(r̄² L)` (≈ the tension change that moves the length by
//! that much), so one tolerance in newtons serves all. Newton with a backtracking line
//! search.
//!
//! **Jacobian: variational equations.** The sensitivities `Y = ∂y/∂x` (one column per unknown,
//! tensions included) are integrated with the state in the same RK4 pass: each stage's
//! tangent is pushed through the analytic `∂y'/∂y` (and `∂y'/∂τ` for tension columns), so the
//! result is the exact derivative of the *discrete* shooting residual (checked against central
//! differences in `tests/cosserat.rs`). The tendon terms are differentiated in vector form,
//! `δA_i x = δα (x − t(t·x)) − α (δt (t·x) + t (δt·x))` with `A_i = α (I − t tᵀ)`,
//! `α = τ/|ṗ|`, and `δ[v'; u'] = M⁻¹(δ[d; c] − δM [v'; u'])` reuses the factors of `M`. The
//! pass with all 6 base-wrench columns costs about 6.3 plain integrations (case III) — a
//! column is not much cheaper than an integration — but it is taken once per solve, and with
//! the exact Jacobian Newton needs 1–2 iterations instead of transport+Broyden's 4. The
//! tip tie forces, path and chord lengths and the wrench/strain round trip at each disk
//! (identity only for an orthonormal `R`, which RK4 misses by O(h⁴)) are differentiated too.
//! One such pass starts Newton; Broyden rank-one updates keep the Jacobian current (one
//! plain integration per iteration); a fresh variational Jacobian is taken only when a line
//! search fails. Not covered (forward differences instead): adaptive RK45, and point loads at
//! inner disks (a tendon tied there, disk weights), whose kink forces come from a fixed point.
//!
//! **Warm starts** read `report.base_wrench`, the cable tensions and, from a shape of this
//! method, `report.warm` ([`WarmState::Rod`]: the last Jacobian): Newton then
//! needs no Jacobian pass. With no shape-dependent external load the base wrench of the
//! continuous rod follows from global balance (below); the discrete rod misses it by its
//! integration error, which the warm solution has measured. That offset, and the tendon part
//! `J − J₀` of the Jacobian (`J₀`: the unloaded straight rod's, a rigid transport along
//! `L e3`), vanish at zero load and to first order grow with it, so both are scaled by the
//! load ratio `ρ = τ·τ_warm / τ_warm·τ_warm`: the start is
//! `balance(τ) + ρ (x_warm − balance(τ_warm))` with `J₀ + ρ (J_warm − J₀)`. On case III, 2 %
//! more tension, this cuts the start residual from 1.2e-6 to 1.8e-7 N and the Jacobian error
//! from 1.5 % to 0.2 %, so one Newton iteration (two integrations) converges to 1e-9 N; without
//! the scaling it took two. Anything the prediction misses, Broyden and a fresh Jacobian fix.
//!
//! **Continuation.** When the direct start fails (or with `direct_start: false`), the loads
//! (tensions, shortenings, gravity, tip wrench) are stepped from zero with an adaptive step;
//! the report notes `continuation: N load steps`. If even that stalls, the solve returns
//! [`SolveError::NotConverged`] with the iterations spent and the last residual.

//! # Cable length and slack (displacement control)
//!
//! A cable's length is either the routed path `∫ |ṗ_i| ds` (integrated with the states,
//! default) or the straight chords between its holes at the disks (the geometric model's
//! measure). The target is the undeformed length in the same measure minus the shortening.
//! Cables pull only: an active set makes a cable whose tension comes out negative slack
//! (tension 0, length equation dropped), and re-tensions a slack cable whose path comes out
//! longer than its length. The answer has `τ ≥ 0` and slack cables no longer than their length.
//! A frictionless cable carries one tension along its whole length, so in this model a cable is
//! slack everywhere or nowhere: `slack_sections` of a slack cable lists all its sections
//! `1..=ends_at` (section-wise slackness exists only in the section-by-section geometric
//! model).
//!
//! # Numbers (paper cases, force control, full model, spline routing)
//!
//! `ccrkit compare models/paper/caseN.toml` (default resolution), RMS of the disk
//! positions against `--method geometric`, paper's values in brackets:
//! case I 3.94 mm (1.57), case II 2.89 mm (1.52), case III 4.81 mm (1.19); tip distances
//! 9.2, 8.2, 13.1 mm. With Fourier8 routing case III gives 4.93 mm, and its Cosserat tip moves
//! by 0.65 mm. Displacement control with the geometric method's chord lengths differs more
//! (4.8, 8.9, 13.4 mm RMS): the file's tensions are not the ones those lengths need.
//!
//! **Default resolution.** 3 RK4 steps per section, and `⌈3 (β_k/0.5)^½⌉` in a section whose
//! route bend `β_k = h² |r''| / r̄` exceeds 0.5 (`bend_refine`): case I and II (β ≤ 0.35) get 27
//! steps, case III (cable B jumps between holes, β up to 6.5) gets 3–11 per section, 76 in
//! all. Tip distance to the converged rod (64 uniform steps per section, tolerance 1e-12 N):
//! case I 0.00002 mm, case II 0.00007 mm, case III 0.0076 mm (test
//! `default_resolution_keeps_the_tip_within_a_hundredth_of_a_millimetre`). Uniform steps would
//! need 11 per section (99 steps) for case III.

use crate::error::SolveError;
use crate::method::settings::{
    parse_control, parse_count, parse_in, parse_length, parse_routing, Configure, MAX_ITERATIONS,
};
use crate::method::warm::WarmState;
use crate::method::{Method, MethodKind};
use crate::model::actuation::{Actuation, Drive, Input, LengthMeasure};
use crate::model::robot::Robot;
use crate::model::routing::{Route, RoutePoint, RoutingFit};
use crate::model::scene::Scene;
use crate::numeric::so3::{gram_schmidt, hat};
use crate::shape::{CablePath, DiskFrame, Shape, SolveReport};
use nalgebra::{DMatrix, DVector, Matrix3, SVector, Vector3, Vector6};
use std::time::Instant;

/// Largest number of cables the rod integrator handles (fixed-size buffers, no allocation).
pub const MAX_CABLES: usize = 16;

type State = SVector<f64, 18>;
type Buf = [f64; MAX_CABLES];

/// Most tangent directions of the variational equations: 6 base-wrench unknowns plus one
/// tension per cable.
const MAXD: usize = 6 + MAX_CABLES;

/// Tangent directions of one right-hand-side evaluation (inputs `dy_in`, outputs `dy_out`,
/// `dlr` = `δ|ṗ_c|`); direction `d` also moves the tension of cable `tcab[d]`
/// (`usize::MAX`: none).
struct Tangents {
    nd: usize,
    tcab: [usize; MAXD],
    dy_in: [State; MAXD],
    dy_out: [State; MAXD],
    dlr: [Buf; MAXD],
}

impl Tangents {
    fn new() -> Self {
        Tangents {
            nd: 0,
            tcab: [usize::MAX; MAXD],
            dy_in: [State::zeros(); MAXD],
            dy_out: [State::zeros(); MAXD],
            dlr: [[0.0; MAX_CABLES]; MAXD],
        }
    }
}

/// Variational state carried along one shooting pass: `∂y/∂x` column by column, the
/// tangents of the path lengths, and at the end the tangents of the residual.
struct Var {
    nd: usize,
    tg: Tangents,
    /// `δ` of each cable's hole at the last disk passed.
    hole: [[Vector3<f64>; MAX_CABLES]; MAXD],
    tcab: [usize; MAXD],
    y: [State; MAXD],
    path: [Buf; MAXD],
    chord: [Buf; MAXD],
    resid: [Vector6<f64>; MAXD],
    len: [Buf; MAXD],
    /// RK4 stage scratch (tangents of the stage slopes and of `|ṗ_c|`).
    kt: [[State; MAXD]; 4],
    lt: [[Buf; MAXD]; 4],
}

/// Shooting residual, its variational Jacobian and its central-difference Jacobian (see
/// [`Cosserat::shooting_jacobians`]).
pub type JacobianCheck = (DVector<f64>, DMatrix<f64>, DMatrix<f64>);

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

/// Inverse of a symmetric 3×3 matrix (upper triangle read) by cofactors; `None` if singular.
#[inline]
fn sym_inverse(m: &Matrix3<f64>) -> Option<Matrix3<f64>> {
    let (a, b, c) = (m[(0, 0)], m[(0, 1)], m[(0, 2)]);
    let (d, e, f) = (m[(1, 1)], m[(1, 2)], m[(2, 2)]);
    let c00 = d * f - e * e;
    let c01 = c * e - b * f;
    let c02 = b * e - c * d;
    let det = a * c00 + b * c01 + c * c02;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let c11 = a * f - c * c;
    let c12 = b * c - a * e;
    let c22 = a * d - b * b;
    Some(Matrix3::new(
        c00 * inv,
        c01 * inv,
        c02 * inv,
        c01 * inv,
        c11 * inv,
        c12 * inv,
        c02 * inv,
        c12 * inv,
        c22 * inv,
    ))
}

/// Load ratio of tensions `tn` to `tw` along `tw`'s ray: `tn·tw / tw·tw` (1 without load).
fn load_ratio(tn: &Buf, tw: &Buf) -> f64 {
    let a: f64 = tn.iter().zip(tw).map(|(a, b)| a * b).sum();
    let b: f64 = tw.iter().map(|b| b * b).sum();
    if b > 0.0 && (a / b).is_finite() {
        a / b
    } else {
        1.0
    }
}

#[inline]
fn rot_of(y: &State) -> Matrix3<f64> {
    Matrix3::from_column_slice(&y.as_slice()[3..12])
}

#[inline]
fn v3(y: &State, i: usize) -> Vector3<f64> {
    Vector3::new(y[i], y[i + 1], y[i + 2])
}

#[inline]
fn put3(y: &mut State, i: usize, v: &Vector3<f64>) {
    y[i] = v.x;
    y[i + 1] = v.y;
    y[i + 2] = v.z;
}

/// Loads of one shooting pass.
struct LoadCase {
    tau: Buf,
    lam: f64,
}

/// Result of one shooting pass.
struct Shot {
    /// `[n(L⁺), m(L⁺)/L]`.
    resid: Vector6<f64>,
    /// Cable lengths in the chosen measure.
    len: Buf,
    /// Tip position.
    tip: Vector3<f64>,
}

/// Recorded geometry of a pass, with the inputs it was shot from.
#[derive(Default)]
struct Trace {
    disks: Vec<(Vector3<f64>, Matrix3<f64>)>,
    backbone: Vec<Vector3<f64>>,
    key: Vec<f64>,
}

impl Trace {
    /// Reset for a pass from `n0`, `m0` under `ld` (keeps the buffers' capacity).
    fn start(&mut self, n0: &Vector3<f64>, m0: &Vector3<f64>, ld: &LoadCase) {
        self.disks.clear();
        self.backbone.clear();
        self.key.clear();
        self.key.extend(n0.iter().chain(m0.iter()).chain(&ld.tau));
        self.key.push(ld.lam);
    }
}

/// Everything fixed during one solve.
struct Problem<'a> {
    robot: &'a Robot,
    set: &'a Cosserat,
    kse: Vector3<f64>,
    kbt: Vector3<f64>,
    routes: Vec<Route>,
    f_dist: Vector3<f64>,
    disk_weight: Vector3<f64>,
    tip_f: Vector3<f64>,
    tip_m: Vector3<f64>,
    len_l: f64,
    fscale: f64,
    modes: Vec<Drive>,
    /// Undeformed lengths in the chosen measure.
    len0: Buf,
    /// Residual scale of each cable's length equation.
    kl: Buf,
    /// RK4 steps of each section (index = section, 1-based; entry 0 unused).
    nsteps: Vec<usize>,
    /// Spline routes as cubics in `σ = s − s_{k−1}` per section: `[c0, c1, c2, c3]` at
    /// index `(k − 1)·ncables + c` (empty for the Fourier fit).
    cubic: Vec<[Vector3<f64>; 4]>,
    /// Geometry of the latest pass (so the converged one need not be integrated again).
    last: std::cell::RefCell<Trace>,
}

const E3: Vector3<f64> = Vector3::new(0.0, 0.0, 1.0);

impl Problem<'_> {
    /// `y'` at `s` in section `sec` (1-based); `lr[c]` receives `|ṗ_c|`.
    #[inline]
    fn deriv(&self, s: f64, y: &State, sec: usize, ld: &LoadCase, lr: &mut Buf) -> State {
        self.deriv_t::<false>(s, y, sec, ld, lr, None)
    }

    /// `y'` and, for every tangent direction `δy_d` in `tan` (with its tension direction
    /// `δτ`), the directional derivative `(∂y'/∂y) δy_d + (∂y'/∂τ) δτ_d` (the variational
    /// equations, written out analytically; `tan.dlr` receives `δ|ṗ_c|`).
    ///
    /// The tendon matrices are formed from vectors: with `t = ṗ/|ṗ|`, `α = τ/|ṗ|`,
    /// `A_i = α (I − t tᵀ)`, `A_i r̂ = α (r̂ − t wᵀ)`, `r̂ A_i r̂ = α (r̂² + w wᵀ)`, `w = t × r`,
    /// and `B = Gᵀ` (the system is symmetric). For the tangents,
    /// `δA_i x = δα (x − t (t·x)) − α (δt (t·x) + t (δt·x))`, `δα = (δτ − α δ|ṗ|)/|ṗ|`,
    /// `δt = (δṗ − t δ|ṗ|)/|ṗ|`, `δṗ = δu × r + δv`, and
    /// `δ[v'; u'] = M⁻¹ (δ[d; c] − δM [v'; u'])` with the factors of `M` reused.
    #[inline]
    fn deriv_t<const TAN: bool>(
        &self,
        s: f64,
        y: &State,
        sec: usize,
        ld: &LoadCase,
        lr: &mut Buf,
        tan: Option<&mut Tangents>,
    ) -> State {
        let r = rot_of(y);
        let w = v3(y, 12);
        let u = v3(y, 15);
        let full = self.set.model == RodModel::Full;
        let v = if full { w } else { E3 };
        let mut sa = [0.0; 6];
        let mut sg = [0.0; 9];
        let mut sh = [0.0; 6];
        let mut a = Vector3::zeros();
        let mut b = Vector3::zeros();
        // Per-cable quantities the tangents need.
        let nc = self.robot.cables.len();
        let mut cr = [Vector3::zeros(); MAX_CABLES];
        let mut cdr = [Vector3::zeros(); MAX_CABLES];
        let mut ct = [Vector3::zeros(); MAX_CABLES];
        let mut cq = [Vector3::zeros(); MAX_CABLES];
        let mut cpd = [Vector3::zeros(); MAX_CABLES];
        let mut on = [false; MAX_CABLES];
        for (c, cable) in self.robot.cables.iter().enumerate() {
            if cable.ends_at < sec {
                continue;
            }
            on[c] = true;
            let rp = self.eval_route(c, s, sec);
            let pd = u.cross(&rp.r) + rp.dr + v;
            let nrm = pd.norm();
            lr[c] = nrm;
            let inv = 1.0 / nrm;
            let tt = pd * inv;
            let q = u.cross(&pd) + u.cross(&rp.dr) + rp.ddr;
            if TAN {
                cr[c] = rp.r;
                cdr[c] = rp.dr;
                ct[c] = tt;
                cq[c] = q;
                cpd[c] = pd;
            }
            let tau = ld.tau[c];
            if tau == 0.0 {
                continue;
            }
            let al = tau * inv;
            let ww = tt.cross(&rp.r);
            let rr = rp.r;
            let (tx, ty, tz) = (tt.x, tt.y, tt.z);
            let (rx, ry, rz) = (rr.x, rr.y, rr.z);
            let (wx, wy, wz) = (ww.x, ww.y, ww.z);
            // A += A_i = α (I − t tᵀ)   (symmetric: upper triangle, row by row)
            sa[0] += al * (1.0 - tx * tx);
            sa[1] -= al * tx * ty;
            sa[2] -= al * tx * tz;
            sa[3] += al * (1.0 - ty * ty);
            sa[4] -= al * ty * tz;
            sa[5] += al * (1.0 - tz * tz);
            // G −= A_i r̂ = α (r̂ − t wᵀ)
            sg[0] += al * tx * wx;
            sg[1] += al * (rz + tx * wy);
            sg[2] += al * (tx * wz - ry);
            sg[3] += al * (ty * wx - rz);
            sg[4] += al * ty * wy;
            sg[5] += al * (rx + ty * wz);
            sg[6] += al * (ry + tz * wx);
            sg[7] += al * (tz * wy - rx);
            sg[8] += al * tz * wz;
            // H −= r̂ A_i r̂ = α (r rᵀ − |r|² I + w wᵀ)   (symmetric)
            let rr2 = rx * rx + ry * ry + rz * rz;
            sh[0] -= al * (rx * rx - rr2 + wx * wx);
            sh[1] -= al * (rx * ry + wx * wy);
            sh[2] -= al * (rx * rz + wx * wz);
            sh[3] -= al * (ry * ry - rr2 + wy * wy);
            sh[4] -= al * (ry * rz + wy * wz);
            sh[5] -= al * (rz * rz - rr2 + wz * wz);
            let ai_vec = (q - tt * tt.dot(&q)) * al;
            a += ai_vec;
            b += rr.cross(&ai_vec);
        }
        let am = Matrix3::new(
            sa[0], sa[1], sa[2], sa[1], sa[3], sa[4], sa[2], sa[4], sa[5],
        );
        let gm = Matrix3::new(
            sg[0], sg[1], sg[2], sg[3], sg[4], sg[5], sg[6], sg[7], sg[8],
        );
        let hm = Matrix3::new(
            sh[0], sh[1], sh[2], sh[1], sh[3], sh[4], sh[2], sh[4], sh[5],
        );
        let bm = gm.transpose();
        let f = self.f_dist * ld.lam;
        let fb = if ld.lam == 0.0 || self.f_dist == Vector3::zeros() {
            Vector3::zeros()
        } else {
            r.tr_mul(&f)
        };
        let mut dy = State::zeros();
        let mb = self.kbt.component_mul(&u);
        let rd = r * hat(&u);
        dy.as_mut_slice()[3..12].copy_from_slice(rd.as_slice());
        // Solution (v', u') and the factors needed again by the tangents.
        let (dv, du, nb);
        let (k1i, k1g, si, mi);
        let kbt_h = Matrix3::from_diagonal(&self.kbt) + hm;
        if full {
            nb = self.kse.component_mul(&(v - E3));
            let cc = -u.cross(&mb) - v.cross(&nb) - b;
            let dd = -u.cross(&nb) - fb - a;
            // Block elimination (Schur complement on the bending block): two 3×3
            // inverses instead of a 6×6 LU.
            let k1 = Matrix3::from_diagonal(&self.kse) + am;
            let Some(k1inv) = sym_inverse(&k1) else {
                return State::from_element(f64::NAN);
            };
            k1g = k1inv * gm;
            let k1d = k1inv * dd;
            // Kbt + H − Gᵀ K1⁻¹ G is symmetric.
            let schur = kbt_h - bm * k1g;
            let Some(sinv) = sym_inverse(&schur) else {
                return State::from_element(f64::NAN);
            };
            du = sinv * (cc - bm * k1d);
            dv = k1d - k1g * du;
            k1i = k1inv;
            si = sinv;
            mi = Matrix3::zeros();
            put3(&mut dy, 0, &(r * v));
            put3(&mut dy, 12, &dv);
            put3(&mut dy, 15, &du);
        } else {
            nb = r.tr_mul(&w);
            let cc = -u.cross(&mb) - E3.cross(&nb) - b;
            let Some(minv) = kbt_h.try_inverse() else {
                return State::from_element(f64::NAN);
            };
            du = minv * cc;
            dv = Vector3::zeros();
            mi = minv;
            k1i = Matrix3::zeros();
            k1g = Matrix3::zeros();
            si = Matrix3::zeros();
            put3(&mut dy, 0, &r.column(2).into_owned());
            put3(&mut dy, 12, &(-f - r * (a + gm * du)));
            put3(&mut dy, 15, &du);
        }
        let Some(tan) = tan.filter(|_| TAN) else {
            return dy;
        };
        // z_i = v' − r_i × u' (so that δA v' + δG u' = Σ δA_i z_i, δB v' + δH u' = Σ r_i × δA_i z_i).
        let mut cz = [Vector3::zeros(); MAX_CABLES];
        for c in 0..nc {
            if on[c] {
                cz[c] = dv - cr[c].cross(&du);
            }
        }
        let g_du = gm * du;
        for d in 0..tan.nd {
            let ty = &tan.dy_in[d];
            let dr_m = Matrix3::from_column_slice(&ty.as_slice()[3..12]);
            let dw = v3(ty, 12);
            let duu = v3(ty, 15);
            let dvv = if full { dw } else { Vector3::zeros() };
            let tc = tan.tcab[d];
            tan.dlr[d] = [0.0; MAX_CABLES];
            let mut da = Vector3::zeros();
            let mut db = Vector3::zeros();
            let mut e1 = Vector3::zeros();
            let mut e2 = Vector3::zeros();
            for c in 0..nc {
                if !on[c] {
                    continue;
                }
                let dtau = if tc == c { 1.0 } else { 0.0 };
                let tt = ct[c];
                let nrm = lr[c];
                let dpd = duu.cross(&cr[c]) + dvv;
                let dn = tt.dot(&dpd);
                tan.dlr[d][c] = dn;
                let tau = ld.tau[c];
                if tau == 0.0 && dtau == 0.0 {
                    continue;
                }
                let al = tau / nrm;
                let dal = (dtau - al * dn) / nrm;
                let dt = (dpd - tt * dn) / nrm;
                // δA_i x
                let da_x = |x: &Vector3<f64>| -> Vector3<f64> {
                    let tx = tt.dot(x);
                    (x - tt * tx) * dal - (dt * tx + tt * dt.dot(x)) * al
                };
                let dq = duu.cross(&cpd[c]) + u.cross(&dpd) + duu.cross(&cdr[c]);
                let dai = da_x(&cq[c]) + (dq - tt * tt.dot(&dq)) * al;
                da += dai;
                db += cr[c].cross(&dai);
                let az = da_x(&cz[c]);
                e1 += az;
                e2 += cr[c].cross(&az);
            }
            let dmb = self.kbt.component_mul(&duu);
            let out = &mut tan.dy_out[d];
            let drd = dr_m * hat(&u) + r * hat(&duu);
            out.as_mut_slice()[3..12].copy_from_slice(drd.as_slice());
            if full {
                let dnb = self.kse.component_mul(&dvv);
                let dcc = -duu.cross(&mb) - u.cross(&dmb) - dvv.cross(&nb) - v.cross(&dnb) - db;
                let ddd = -duu.cross(&nb) - u.cross(&dnb) - dr_m.tr_mul(&f) - da;
                let r1 = ddd - e1;
                let r2 = dcc - e2;
                let k1r = k1i * r1;
                let ddu = si * (r2 - bm * k1r);
                let ddv = k1r - k1g * ddu;
                put3(out, 0, &(dr_m * v + r * dvv));
                put3(out, 12, &ddv);
                put3(out, 15, &ddu);
            } else {
                let dnb = dr_m.tr_mul(&w) + r.tr_mul(&dw);
                let dcc = -duu.cross(&mb) - u.cross(&dmb) - E3.cross(&dnb) - db;
                let ddu = mi * (dcc - e2);
                let ddn = -dr_m * (a + g_du) - r * (da + e1 + gm * ddu);
                put3(out, 0, &dr_m.column(2).into_owned());
                put3(out, 12, &ddn);
                put3(out, 15, &ddu);
            }
        }
        dy
    }
    /// One RK4 step of the state and of its tangents (the exact derivative of the discrete
    /// RK4 map: each stage's tangent is the stage state's tangent pushed through `∂y'/∂y`).
    #[allow(clippy::too_many_arguments)]
    fn rk4_t(
        &self,
        s: f64,
        h: f64,
        y: &mut State,
        sec: usize,
        ld: &LoadCase,
        len: &mut Buf,
        var: &mut Var,
    ) {
        let nd = var.nd;
        let Var {
            tg,
            kt,
            lt,
            y: vy,
            path: vpath,
            ..
        } = var;
        let nc = self.robot.cables.len();
        let mut ks = [State::zeros(); 4];
        let mut ls = [[0.0; MAX_CABLES]; 4];
        const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
        for st in 0..4 {
            let (ys, ss) = if st == 0 {
                (*y, s)
            } else {
                (*y + ks[st - 1] * (C[st] * h), s + C[st] * h)
            };
            for d in 0..nd {
                tg.dy_in[d] = if st == 0 {
                    vy[d]
                } else {
                    vy[d] + kt[st - 1][d] * (C[st] * h)
                };
            }
            ks[st] = self.deriv_t::<true>(ss, &ys, sec, ld, &mut ls[st], Some(tg));
            for d in 0..nd {
                kt[st][d] = tg.dy_out[d];
                lt[st][d] = tg.dlr[d];
            }
        }
        *y += (ks[0] + (ks[1] + ks[2]) * 2.0 + ks[3]) * (h / 6.0);
        for c in 0..nc {
            len[c] += (ls[0][c] + 2.0 * (ls[1][c] + ls[2][c]) + ls[3][c]) * (h / 6.0);
        }
        for d in 0..nd {
            vy[d] += (kt[0][d] + (kt[1][d] + kt[2][d]) * 2.0 + kt[3][d]) * (h / 6.0);
            for c in 0..nc {
                vpath[d][c] +=
                    (lt[0][d][c] + 2.0 * (lt[1][d][c] + lt[2][d][c]) + lt[3][d][c]) * (h / 6.0);
            }
        }
    }

    /// One classical RK4 step from `s` of size `h`; path lengths accumulate in `len`.
    #[inline]
    fn rk4(&self, s: f64, h: f64, y: &mut State, sec: usize, ld: &LoadCase, len: &mut Buf) {
        let (mut l1, mut l2, mut l3, mut l4) = (
            [0.0; MAX_CABLES],
            [0.0; MAX_CABLES],
            [0.0; MAX_CABLES],
            [0.0; MAX_CABLES],
        );
        let k1 = self.deriv(s, y, sec, ld, &mut l1);
        let k2 = self.deriv(s + 0.5 * h, &(*y + k1 * (0.5 * h)), sec, ld, &mut l2);
        let k3 = self.deriv(s + 0.5 * h, &(*y + k2 * (0.5 * h)), sec, ld, &mut l3);
        let k4 = self.deriv(s + h, &(*y + k3 * h), sec, ld, &mut l4);
        *y += (k1 + (k2 + k3) * 2.0 + k4) * (h / 6.0);
        for c in 0..self.robot.cables.len() {
            len[c] += (l1[c] + 2.0 * (l2[c] + l3[c]) + l4[c]) * (h / 6.0);
        }
    }

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
    fn eval_route(&self, c: usize, s: f64, sec: usize) -> RoutePoint {
        if self.cubic.is_empty() {
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

    /// Scaled max-norm of a state error (for the adaptive integrator).
    fn err_norm(&self, e: &State) -> f64 {
        let l = self.len_l;
        let wn = match self.set.model {
            RodModel::Full => 1.0,
            RodModel::Kirchhoff => 1.0 / self.fscale,
        };
        let mut m = 0.0f64;
        for i in 0..18 {
            let w = match i {
                0..=2 => 1.0 / l,
                3..=11 => 1.0,
                12..=14 => wn,
                _ => l,
            };
            m = m.max((e[i] * w).abs());
        }
        m
    }

    /// Integrate section `sec` from `s0` to `s1` (either fixed RK4 or adaptive RK45).
    #[allow(clippy::too_many_arguments)]
    fn section(
        &self,
        sec: usize,
        y: &mut State,
        ld: &LoadCase,
        len: &mut Buf,
        h_adapt: &mut f64,
        trace: &mut Option<&mut Trace>,
        var: &mut Option<&mut Var>,
    ) -> bool {
        let (s0, s1) = (self.robot.disk_s[sec - 1], self.robot.disk_s[sec]);
        match self.set.adaptive {
            None => {
                let nsteps = self.nsteps[sec];
                let h = (s1 - s0) / nsteps as f64;
                for j in 0..nsteps {
                    // Each step starts at its own arc length (never drop s0).
                    let s = s0 + j as f64 * h;
                    match var.as_deref_mut() {
                        Some(vr) => self.rk4_t(s, h, y, sec, ld, len, vr),
                        None => self.rk4(s, h, y, sec, ld, len),
                    }
                    if let Some(t) = trace.as_deref_mut() {
                        t.backbone.push(v3(y, 0));
                    }
                }
                true
            }
            Some(tol) => {
                let mut s = s0;
                let mut guard = 0usize;
                while s < s1 - 1e-15 * s1.abs().max(1.0) {
                    guard += 1;
                    if guard > 100_000 || !h_adapt.is_finite() {
                        return false;
                    }
                    let h = h_adapt.min(s1 - s);
                    let (yn, ln, err) = self.dp45(s, h, y, sec, ld, len);
                    let e = err / tol;
                    if e <= 1.0 || h < 1e-12 * self.len_l {
                        *y = yn;
                        *len = ln;
                        s = if h == s1 - s { s1 } else { s + h };
                        if let Some(t) = trace.as_deref_mut() {
                            t.backbone.push(v3(y, 0));
                        }
                    }
                    let fac = if e == 0.0 {
                        5.0
                    } else {
                        (0.9 * e.powf(-0.2)).clamp(0.2, 5.0)
                    };
                    *h_adapt = h * fac;
                    if !e.is_finite() {
                        return false;
                    }
                }
                true
            }
        }
    }

    /// One Dormand–Prince 5(4) step: new state, new lengths, scaled error.
    fn dp45(
        &self,
        s: f64,
        h: f64,
        y: &State,
        sec: usize,
        ld: &LoadCase,
        len: &Buf,
    ) -> (State, Buf, f64) {
        const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
        const A: [[f64; 6]; 7] = [
            [0.0; 6],
            [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
            [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
            [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
            [
                19372.0 / 6561.0,
                -25360.0 / 2187.0,
                64448.0 / 6561.0,
                -212.0 / 729.0,
                0.0,
                0.0,
            ],
            [
                9017.0 / 3168.0,
                -355.0 / 33.0,
                46732.0 / 5247.0,
                49.0 / 176.0,
                -5103.0 / 18656.0,
                0.0,
            ],
            [
                35.0 / 384.0,
                0.0,
                500.0 / 1113.0,
                125.0 / 192.0,
                -2187.0 / 6784.0,
                11.0 / 84.0,
            ],
        ];
        const B5: [f64; 7] = [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
            0.0,
        ];
        const B4: [f64; 7] = [
            5179.0 / 57600.0,
            0.0,
            7571.0 / 16695.0,
            393.0 / 640.0,
            -92097.0 / 339200.0,
            187.0 / 2100.0,
            1.0 / 40.0,
        ];
        let mut k = [State::zeros(); 7];
        let mut lr = [[0.0; MAX_CABLES]; 7];
        for i in 0..7 {
            let mut yi = *y;
            for j in 0..i {
                if A[i][j] != 0.0 {
                    yi += k[j] * (h * A[i][j]);
                }
            }
            k[i] = self.deriv(s + C[i] * h, &yi, sec, ld, &mut lr[i]);
        }
        let mut yn = *y;
        let mut e = State::zeros();
        let mut ln = *len;
        for i in 0..7 {
            yn += k[i] * (h * B5[i]);
            e += k[i] * (h * (B5[i] - B4[i]));
            for c in 0..self.robot.cables.len() {
                ln[c] += h * B5[i] * lr[i][c];
            }
        }
        (yn, ln, self.err_norm(&e))
    }

    /// Tangents at disk `k` (after integrating section `k`, before its jumps): chord lengths
    /// (`δ|h_k − h_{k−1}| = e·(δh_k − δh_{k−1})`, `δh = δp + δR r_k`) and, at the tip, the
    /// residual `[n(L⁺), m(L⁺)/L]` with the tie forces of the cables ending there,
    /// `F = −τ R t`, `δF = −δτ R t − τ (δR t + R δt)`.
    fn disk_tangents(
        &self,
        k: usize,
        y: &State,
        ld: &LoadCase,
        prev: &[Vector3<f64>; MAX_CABLES],
        vr: &mut Var,
    ) {
        let robot = self.robot;
        let r = rot_of(y);
        let p = v3(y, 0);
        let full = self.set.model == RodModel::Full;
        let w = v3(y, 12);
        let u = v3(y, 15);
        let v = if full { w } else { E3 };
        let tip = k == robot.sections();
        for d in 0..vr.nd {
            let ty = vr.y[d];
            let dp = v3(&ty, 0);
            let dr_m = Matrix3::from_column_slice(&ty.as_slice()[3..12]);
            let dw = v3(&ty, 12);
            let du = v3(&ty, 15);
            let dv = if full { dw } else { Vector3::zeros() };
            for (c, cable) in robot.cables.iter().enumerate() {
                if cable.ends_at < k {
                    continue;
                }
                let hk = cable.hole(k);
                let seg = p + r * hk - prev[c];
                let dh = dp + dr_m * hk;
                let len = seg.norm();
                if len > 0.0 {
                    vr.chord[d][c] += seg.dot(&(dh - vr.hole[d][c])) / len;
                }
                vr.hole[d][c] = dh;
            }
            if !tip {
                // No jump here (`var_ok`), but the state passes through `wrench` and
                // `set_wrench`, which is the identity only for an orthonormal `R`; RK4 drifts
                // from it by O(h⁴), so differentiate the round trip too:
                // `v⁺ = e3 + Kse⁻¹ Rᵀ R Kse (v − e3)`, `u⁺ = Kbt⁻¹ Rᵀ R Kbt u` (Kirchhoff: `n`
                // is the state itself).
                let mb = self.kbt.component_mul(&u);
                let mw = r * mb;
                let dmw = dr_m * mb + r * self.kbt.component_mul(&du);
                let du_new = (dr_m.tr_mul(&mw) + r.tr_mul(&dmw)).component_div(&self.kbt);
                put3(&mut vr.y[d], 15, &du_new);
                if full {
                    let nb = self.kse.component_mul(&(w - E3));
                    let nw = r * nb;
                    let dnw = dr_m * nb + r * self.kse.component_mul(&dw);
                    let dw_new = (dr_m.tr_mul(&nw) + r.tr_mul(&dnw)).component_div(&self.kse);
                    put3(&mut vr.y[d], 12, &dw_new);
                }
                continue;
            }
            let mut dn = if full {
                dr_m * self.kse.component_mul(&(v - E3)) + r * self.kse.component_mul(&dw)
            } else {
                dw
            };
            let mut dm = dr_m * self.kbt.component_mul(&u) + r * self.kbt.component_mul(&du);
            for (c, cable) in robot.cables.iter().enumerate() {
                let tau = ld.tau[c];
                let dtau = if vr.tcab[d] == c { 1.0 } else { 0.0 };
                if cable.ends_at != k || (tau == 0.0 && dtau == 0.0) {
                    continue;
                }
                let rp = self.eval_route(c, robot.disk_s[k], k);
                let pd = u.cross(&rp.r) + rp.dr + v;
                let nrm = pd.norm();
                let t = pd / nrm;
                let dpd = du.cross(&rp.r) + dv;
                let dt = (dpd - t * t.dot(&dpd)) / nrm;
                let f = r * t * (-tau);
                let df = -(r * t) * dtau - (dr_m * t + r * dt) * tau;
                dn -= df;
                dm -= (dr_m * rp.r).cross(&f) + (r * rp.r).cross(&df);
            }
            let dm = dm / self.len_l;
            vr.resid[d] = Vector6::new(dn.x, dn.y, dn.z, dm.x, dm.y, dm.z);
            vr.len[d] = match self.set.length {
                LengthMeasure::Path => vr.path[d],
                LengthMeasure::Chord => vr.chord[d],
            };
        }
    }

    /// Rod force and moment (base frame) from the state.
    #[inline]
    fn wrench(&self, y: &State) -> (Vector3<f64>, Vector3<f64>) {
        let r = rot_of(y);
        let u = v3(y, 15);
        let n = match self.set.model {
            RodModel::Full => r * self.kse.component_mul(&(v3(y, 12) - E3)),
            RodModel::Kirchhoff => v3(y, 12),
        };
        (n, r * self.kbt.component_mul(&u))
    }

    /// Set the strains (and `n` for Kirchhoff) from a rod wrench.
    #[inline]
    fn set_wrench(&self, y: &mut State, n: &Vector3<f64>, m: &Vector3<f64>) {
        let r = rot_of(y);
        match self.set.model {
            RodModel::Full => put3(y, 12, &(E3 + r.tr_mul(n).component_div(&self.kse))),
            RodModel::Kirchhoff => put3(y, 12, n),
        }
        put3(y, 15, &r.tr_mul(m).component_div(&self.kbt));
    }

    /// Integrate base to tip from the base wrench `n0`, `m0`.
    fn shoot(
        &self,
        n0: &Vector3<f64>,
        m0: &Vector3<f64>,
        ld: &LoadCase,
        trace: Option<&mut Trace>,
        mut var: Option<&mut Var>,
    ) -> Shot {
        let robot = self.robot;
        let mut last = self.last.borrow_mut();
        let rec: &mut Trace = match trace {
            Some(t) => t,
            None => &mut last,
        };
        rec.start(n0, m0, ld);
        let mut trace = Some(rec);
        let mut y = State::zeros();
        y.as_mut_slice()[3..12].copy_from_slice(Matrix3::<f64>::identity().as_slice());
        self.set_wrench(&mut y, n0, m0);
        let mut path = [0.0; MAX_CABLES];
        let mut chord = [0.0; MAX_CABLES];
        let mut prev = [Vector3::zeros(); MAX_CABLES];
        for (c, cable) in robot.cables.iter().enumerate() {
            prev[c] = cable.hole(0);
        }
        if let Some(t) = trace.as_deref_mut() {
            t.disks.push((Vector3::zeros(), Matrix3::identity()));
            t.backbone.push(Vector3::zeros());
        }
        let mut h_adapt = self.len_l / (robot.sections() as f64 * 4.0);
        let nsec = robot.sections();
        let bad = Shot {
            resid: Vector6::from_element(f64::NAN),
            len: [f64::NAN; MAX_CABLES],
            tip: Vector3::from_element(f64::NAN),
        };
        for k in 1..=nsec {
            if !self.section(k, &mut y, ld, &mut path, &mut h_adapt, &mut trace, &mut var) {
                return bad;
            }
            let r = rot_of(&y);
            let p = v3(&y, 0);
            if let Some(vr) = var.as_deref_mut() {
                self.disk_tangents(k, &y, ld, &prev, vr);
            }
            if let Some(t) = trace.as_deref_mut() {
                t.disks.push((p, r));
            }
            let (mut n, mut m) = self.wrench(&y);
            let v = match self.set.model {
                RodModel::Full => v3(&y, 12),
                RodModel::Kirchhoff => E3,
            };
            let u = v3(&y, 15);
            for (c, cable) in robot.cables.iter().enumerate() {
                if cable.ends_at < k {
                    continue;
                }
                let hole = p + r * cable.hole(k);
                chord[c] += (hole - prev[c]).norm();
                prev[c] = hole;
                let t = ld.tau[c];
                if cable.ends_at == k && t != 0.0 {
                    let rp = self.eval_route(c, robot.disk_s[k], k);
                    let pd = u.cross(&rp.r) + rp.dr + v;
                    let f = r * pd * (-t / pd.norm());
                    n -= f;
                    m -= (r * rp.r).cross(&f);
                }
            }
            n -= self.disk_weight * ld.lam;
            if k == nsec {
                n -= self.tip_f * ld.lam;
                m -= self.tip_m * ld.lam;
            }
            // Kink force of cables passing disk k. Where the strains jump at the disk (a cable
            // is tied here, or a point load acts), a cable passing it changes direction at its
            // hole, t⁻ = (v⁻ + u⁻ × r + r′)/|·| → t⁺, and, frictionless, pushes the disk with
            // F = τ (t⁺ − t⁻): a point force the distributed Rucker–Webster loads cannot carry.
            // n⁺ = n⁻ − F, m⁺ = m⁻ − (R r) × F, with t⁺ from the post-jump strains, which
            // depend on F: a fixed point (the coupling is weak; it converges in a few sweeps).
            let tied_here = robot
                .cables
                .iter()
                .enumerate()
                .any(|(c, cable)| cable.ends_at == k && ld.tau[c] != 0.0);
            let point_load = self.disk_weight.norm() * ld.lam > 0.0;
            if k < nsec && (tied_here || point_load) {
                // The variational pass is only run where no such jump occurs (`var_ok`).
                debug_assert!(var.is_none());
                let (n_base, m_base) = (n, m);
                let mut settled = false;
                for _ in 0..50 {
                    let mut yy = y;
                    self.set_wrench(&mut yy, &n, &m);
                    let vp = match self.set.model {
                        RodModel::Full => v3(&yy, 12),
                        RodModel::Kirchhoff => E3,
                    };
                    let up = v3(&yy, 15);
                    let (mut n2, mut m2) = (n_base, m_base);
                    for (c, cable) in robot.cables.iter().enumerate() {
                        let t = ld.tau[c];
                        if cable.ends_at <= k || t == 0.0 {
                            continue;
                        }
                        let rm = self.routes[c].eval(robot.disk_s[k], k - 1);
                        let rpl = self.routes[c].eval(robot.disk_s[k], k);
                        let tm = u.cross(&rm.r) + rm.dr + v;
                        let tp = up.cross(&rpl.r) + rpl.dr + vp;
                        let f = r * (tp / tp.norm() - tm / tm.norm()) * t;
                        n2 -= f;
                        m2 -= (r * rm.r).cross(&f);
                    }
                    let change = (n2 - n).norm() + (m2 - m).norm() / self.len_l;
                    n = n2;
                    m = m2;
                    if change <= 1e-14 * (1.0 + n.norm() + m.norm() / self.len_l) {
                        settled = true;
                        break;
                    }
                }
                if !settled {
                    return bad;
                }
            }
            self.set_wrench(&mut y, &n, &m);
            if k == nsec {
                let mm = m / self.len_l;
                let resid = Vector6::new(n.x, n.y, n.z, mm.x, mm.y, mm.z);
                let len = match self.set.length {
                    LengthMeasure::Path => path,
                    LengthMeasure::Chord => chord,
                };
                return Shot { resid, len, tip: p };
            }
        }
        bad
    }
}

/// One configuration of unknowns: which cables carry unknown tensions.
struct Setup {
    /// Cables whose tension is an unknown (length-controlled, taut).
    unknown: Vec<usize>,
    /// Length-controlled cables currently slack (tension 0).
    slack: Vec<bool>,
}

/// A converged Newton run: solution, iterations, residual, last Jacobian (for warm starts).
struct Newton {
    x: DVector<f64>,
    iterations: usize,
    residual: f64,
    jac: Option<DMatrix<f64>>,
}

/// Failure of a Newton run (for continuation / error reporting).
struct Fail {
    iterations: usize,
    residual: f64,
    detail: String,
}

impl Problem<'_> {
    fn tensions(&self, x: &DVector<f64>, setup: &Setup, lam: f64) -> Buf {
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
    fn shape_free_loads(&self) -> bool {
        self.tip_f == Vector3::zeros()
            && self.f_dist == Vector3::zeros()
            && self.disk_weight == Vector3::zeros()
    }

    /// Base wrench from the static balance of rod + tendons as one body (no integration):
    /// `n(0) + Σ τ_i t_i(0) = F_ext`, `m(0) + Σ r_i(0) × τ_i t_i(0) = M_ext` (tendon loads are
    /// internal to that body; the actuators pull at the base along `t_i(0)`). `t_i(0)` depends
    /// on `v(0)`, `u(0)`, hence a short fixed-point iteration. Moments of the tip force and of
    /// the weights use the straight rod (exact when there are none). Writes `x[0..6]`.
    fn balance_guess(&self, x: &mut DVector<f64>, setup: &Setup, lam: f64) {
        let tau = self.tensions(x, setup, lam);
        let (n0, m0) = self.balance(&tau, lam);
        for i in 0..3 {
            x[i] = n0[i];
            x[3 + i] = m0[i] / self.len_l;
        }
    }

    /// The base wrench `(n(0), m(0))` of [`Self::balance_guess`] for tensions `tau`.
    fn balance(&self, tau: &Buf, lam: f64) -> (Vector3<f64>, Vector3<f64>) {
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

    fn residual(&self, x: &DVector<f64>, setup: &Setup, lam: f64) -> DVector<f64> {
        self.residual_tip(x, setup, lam).0
    }

    /// Approximate Jacobian of the tip wrench residual w.r.t. the base wrench (force
    /// control): a base wrench change is carried rigidly to the tip, `δn(L) = δn0`,
    /// `δm(L) = δm0 − p_L × δn0` (tendon and shape corrections are left to Broyden).
    fn transport_jacobian(&self, tip: &Vector3<f64>) -> DMatrix<f64> {
        let mut j = DMatrix::identity(6, 6);
        let t = hat(tip) * (-1.0 / self.len_l);
        for r in 0..3 {
            for c in 0..3 {
                j[(3 + r, c)] = t[(r, c)];
            }
        }
        j
    }

    fn residual_tip(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> (DVector<f64>, Vector3<f64>) {
        let n0 = Vector3::new(x[0], x[1], x[2]);
        let m0 = Vector3::new(x[3], x[4], x[5]) * self.len_l;
        let ld = LoadCase {
            tau: self.tensions(x, setup, lam),
            lam,
        };
        let shot = self.shoot(&n0, &m0, &ld, None, None);
        let mut f = DVector::zeros(x.len());
        for i in 0..6 {
            f[i] = shot.resid[i];
        }
        for (j, &c) in setup.unknown.iter().enumerate() {
            f[6 + j] = self.kl[c] * (shot.len[c] - self.target(c, lam));
        }
        if f.iter().any(|v| !v.is_finite()) {
            f.fill(f64::NAN);
        }
        (f, shot.tip)
    }

    fn target(&self, c: usize, lam: f64) -> f64 {
        match self.modes[c] {
            Drive::Shorten { length: d, .. } => self.len0[c] - lam * d,
            _ => self.len0[c],
        }
    }

    /// True when the variational equations give the exact Jacobian of this shooting pass:
    /// fixed RK4 steps and no point load at an inner disk (a cable tied there, or disk
    /// weights: their kink forces come from a fixed point that is not differentiated).
    fn var_ok(&self, setup: &Setup, tau: &Buf, lam: f64) -> bool {
        if self.set.adaptive.is_some() || self.disk_weight.norm() * lam > 0.0 {
            return false;
        }
        let nsec = self.robot.sections();
        self.robot.cables.iter().enumerate().all(|(c, cable)| {
            cable.ends_at >= nsec || (tau[c] == 0.0 && !setup.unknown.contains(&c))
        })
    }

    /// Residual, exact Jacobian (variational equations integrated with the state in the same
    /// RK4 pass) and tip; `None` where [`Self::var_ok`] says no.
    ///
    /// Columns: `x = [n(0), m(0)/L, τ_unknown]`. The start tangents follow from
    /// `v(0) = e3 + Kse⁻¹ n(0)`, `u(0) = Kbt⁻¹ m(0)` (`R(0) = I`; Kirchhoff: the state is `n`).
    fn residual_jac(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> Option<(DVector<f64>, DMatrix<f64>, Vector3<f64>)> {
        let tau = self.tensions(x, setup, lam);
        if !self.var_ok(setup, &tau, lam) {
            return None;
        }
        let k = x.len();
        let mut var = Box::new(Var {
            nd: k,
            tg: Tangents::new(),
            hole: [[Vector3::zeros(); MAX_CABLES]; MAXD],
            tcab: [usize::MAX; MAXD],
            y: [State::zeros(); MAXD],
            path: [[0.0; MAX_CABLES]; MAXD],
            chord: [[0.0; MAX_CABLES]; MAXD],
            resid: [Vector6::zeros(); MAXD],
            len: [[0.0; MAX_CABLES]; MAXD],
            kt: [[State::zeros(); MAXD]; 4],
            lt: [[[0.0; MAX_CABLES]; MAXD]; 4],
        });
        var.tg.nd = k;
        for (j, &c) in setup.unknown.iter().enumerate() {
            var.tcab[6 + j] = c;
            var.tg.tcab[6 + j] = c;
        }
        for i in 0..3 {
            var.y[i][12 + i] = match self.set.model {
                RodModel::Full => 1.0 / self.kse[i],
                RodModel::Kirchhoff => 1.0,
            };
            var.y[3 + i][15 + i] = self.len_l / self.kbt[i];
        }
        let n0 = Vector3::new(x[0], x[1], x[2]);
        let m0 = Vector3::new(x[3], x[4], x[5]) * self.len_l;
        let ld = LoadCase { tau, lam };
        let shot = self.shoot(&n0, &m0, &ld, None, Some(&mut var));
        let mut f = DVector::zeros(k);
        let mut jac = DMatrix::zeros(k, k);
        for i in 0..6 {
            f[i] = shot.resid[i];
            for d in 0..k {
                jac[(i, d)] = var.resid[d][i];
            }
        }
        for (j, &c) in setup.unknown.iter().enumerate() {
            f[6 + j] = self.kl[c] * (shot.len[c] - self.target(c, lam));
            for d in 0..k {
                jac[(6 + j, d)] = self.kl[c] * var.len[d][c];
            }
        }
        if f.iter().chain(jac.iter()).any(|v| !v.is_finite()) {
            f.fill(f64::NAN);
        }
        Some((f, jac, shot.tip))
    }

    /// A fresh Jacobian at `x`: variational where possible, else forward differences.
    fn jacobian(
        &self,
        x: &DVector<f64>,
        f: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> DMatrix<f64> {
        match self.residual_jac(x, setup, lam) {
            Some((_, j, _)) => j,
            None => self.fd_jacobian(x, f, setup, lam),
        }
    }

    fn fd_jacobian(
        &self,
        x: &DVector<f64>,
        f: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> DMatrix<f64> {
        let k = x.len();
        let mut j = DMatrix::zeros(k, k);
        let mut xp = x.clone();
        for col in 0..k {
            let h = 1e-7 * x[col].abs().max(self.fscale);
            xp[col] = x[col] + h;
            let fp = self.residual(&xp, setup, lam);
            xp[col] = x[col];
            j.set_column(col, &((fp - f) / h));
        }
        j
    }

    /// Newton with line search and Broyden updates at load factor `lam`.
    ///
    /// `jac0`: a Jacobian to start from (a warm start's, kept current by Broyden); without it
    /// the residual and the exact variational Jacobian come from one pass.
    fn newton(
        &self,
        x0: &DVector<f64>,
        setup: &Setup,
        lam: f64,
        jac0: Option<&DMatrix<f64>>,
    ) -> Result<Newton, Fail> {
        let tol = self.set.tolerance;
        let mut x = x0.clone();
        let jac0 = jac0.filter(|j| j.nrows() == x.len() && j.iter().all(|v| v.is_finite()));
        let (mut f, tip, var_jac) = match jac0 {
            Some(j) => {
                let (f, tip) = self.residual_tip(&x, setup, lam);
                (f, tip, Some((j.clone(), false)))
            }
            None => match self.residual_jac(&x, setup, lam) {
                Some((f, j, tip)) => (f, tip, Some((j, true))),
                None => {
                    let (f, tip) = self.residual_tip(&x, setup, lam);
                    (f, tip, None)
                }
            },
        };
        let norm_inf = |v: &DVector<f64>| v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        if !f[0].is_finite() {
            return Err(Fail {
                iterations: 0,
                residual: f64::NAN,
                detail: "integration failed at the start point".into(),
            });
        }
        if norm_inf(&f) <= tol {
            let residual = norm_inf(&f);
            let jac = var_jac.map(|(j, _)| j);
            return Ok(Newton {
                x,
                iterations: 0,
                residual,
                jac,
            });
        }
        // Start Broyden from the variational Jacobian; without it, in force control from the
        // rigid transport Jacobian (no extra integrations), else from a difference Jacobian.
        let (mut jac, mut fresh) = if let Some(j) = var_jac {
            j
        } else if setup.unknown.is_empty() && tip.iter().all(|v| v.is_finite()) {
            (self.transport_jacobian(&tip), false)
        } else {
            (self.fd_jacobian(&x, &f, setup, lam), true)
        };
        for it in 1..=self.set.max_iterations {
            let Some(dx) = jac.clone().lu().solve(&(-&f)) else {
                if fresh {
                    return Err(Fail {
                        iterations: it,
                        residual: norm_inf(&f),
                        detail: "singular Jacobian".into(),
                    });
                }
                jac = self.jacobian(&x, &f, setup, lam);
                fresh = true;
                continue;
            };
            let f2 = f.norm_squared();
            let mut alpha = 1.0;
            let mut accepted = None;
            for _ in 0..12 {
                let xn = &x + &dx * alpha;
                let fnew = self.residual(&xn, setup, lam);
                if fnew[0].is_finite() && fnew.norm_squared() <= (1.0 - 1e-4 * alpha) * f2 {
                    accepted = Some((xn, fnew));
                    break;
                }
                alpha *= 0.5;
            }
            match accepted {
                Some((xn, fnew)) => {
                    let s = &xn - &x;
                    let y = &fnew - &f;
                    let ss = s.norm_squared();
                    if ss > 0.0 {
                        let corr = (y - &jac * &s) * (s.transpose() / ss);
                        jac += corr;
                    }
                    x = xn;
                    f = fnew;
                    fresh = false;
                    let r = norm_inf(&f);
                    if r <= tol {
                        return Ok(Newton {
                            x,
                            iterations: it,
                            residual: r,
                            jac: Some(jac),
                        });
                    }
                }
                None => {
                    if fresh {
                        return Err(Fail {
                            iterations: it,
                            residual: norm_inf(&f),
                            detail: "line search failed".into(),
                        });
                    }
                    jac = self.jacobian(&x, &f, setup, lam);
                    fresh = true;
                }
            }
        }
        Err(Fail {
            iterations: self.set.max_iterations,
            residual: norm_inf(&f),
            detail: "iteration limit".into(),
        })
    }

    /// Newton from `x0` (unless `direct_start` is off); if that fails, load stepping from
    /// zero load. Returns the solution and the number of load steps taken (0: direct).
    fn solve_with_continuation(
        &self,
        x0: &DVector<f64>,
        setup: &Setup,
        jac0: Option<&DMatrix<f64>>,
    ) -> Result<(Newton, usize), Fail> {
        let mut total = 0;
        if self.set.direct_start {
            match self.newton(x0, setup, 1.0, jac0) {
                Ok(n) => return Ok((n, 0)),
                Err(e) => total += e.iterations,
            }
        }
        let mut x = DVector::zeros(x0.len());
        let (mut lam, mut dl) = (0.0f64, 0.25f64);
        let mut steps = 0;
        let mut last = Fail {
            iterations: total,
            residual: f64::NAN,
            detail: "continuation".into(),
        };
        while lam < 1.0 {
            let l1 = (lam + dl).min(1.0);
            let mut xs = x.clone();
            if self.shape_free_loads() {
                self.balance_guess(&mut xs, setup, l1);
            }
            match self.newton(&xs, setup, l1, None) {
                Ok(mut n) => {
                    total += n.iterations;
                    steps += 1;
                    x = n.x.clone();
                    lam = l1;
                    dl = (dl * 1.5).min(0.5);
                    if lam >= 1.0 {
                        n.iterations = total;
                        return Ok((n, steps));
                    }
                }
                Err(e) => {
                    total += e.iterations;
                    dl *= 0.5;
                    last = Fail {
                        iterations: total,
                        residual: e.residual,
                        detail: format!(
                            "continuation stalled at load factor {lam:.4} ({})",
                            e.detail
                        ),
                    };
                    if dl < 1.0 / 512.0 {
                        return Err(last);
                    }
                }
            }
        }
        Err(last)
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
            _ => return self.kind().check_setting(name),
        }
        Ok(())
    }
}

impl Method for Cosserat {
    fn kind(&self) -> MethodKind {
        match self.model {
            RodModel::Full => MethodKind::Cosserat,
            RodModel::Kirchhoff => MethodKind::Kirchhoff,
        }
    }

    fn solve(
        &self,
        robot: &Robot,
        act: &Actuation,
        scene: &Scene,
        warm: Option<&Shape>,
    ) -> Result<Shape, SolveError> {
        let start = Instant::now();
        let name = self.name().to_string();
        self.kind().check_support(robot, scene)?;
        let (prob, mut notes) = self.problem(robot, act)?;
        let nc = robot.cables.len();
        let len_l = prob.len_l;
        let length_cables: Vec<usize> = (0..nc)
            .filter(|&c| matches!(prob.modes[c], Drive::Shorten { .. }))
            .collect();
        // Warm start.
        let mut slack = vec![false; nc];
        let mut warm_x: Option<(Vector3<f64>, Vector3<f64>, Vec<f64>)> = None;
        // A warm start from this method also carries its last Jacobian (`report.warm`) and
        // the offset of its base wrench from the global balance.
        let same = warm.is_some_and(|w| w.method == self.name());
        let mut warm_jac = warm.filter(|_| same).and_then(|w| match &w.report.warm {
            Some(WarmState::Rod { jacobian }) if jacobian.nrows() >= 6 && jacobian.is_square() => {
                Some(jacobian.clone())
            }
            _ => None,
        });
        if let Some(w) = warm {
            if let Some(bw) = w.report.base_wrench {
                if bw.iter().all(|v| v.is_finite()) && w.cables.len() == nc {
                    let tens: Vec<f64> = w
                        .cables
                        .iter()
                        .map(|c| c.tension.filter(|t| t.is_finite()).unwrap_or(0.0))
                        .collect();
                    for &c in &length_cables {
                        slack[c] = w.cables[c].slack && tens[c] == 0.0;
                    }
                    warm_x = Some((
                        Vector3::new(bw[0], bw[1], bw[2]),
                        Vector3::new(bw[3], bw[4], bw[5]) / len_l,
                        tens,
                    ));
                }
            }
        }
        // Active set over slack cables.
        let mut total_it = 0usize;
        let max_rounds = 2 * nc + 3;
        let mut x_prev: Option<DVector<f64>> = None;
        let mut prev_setup: Option<Setup> = None;
        for _round in 0..max_rounds {
            let unknown: Vec<usize> = length_cables
                .iter()
                .copied()
                .filter(|&c| !slack[c])
                .collect();
            let setup = Setup {
                unknown,
                slack: slack.clone(),
            };
            let mut x0 = DVector::zeros(6 + setup.unknown.len());
            if let Some(xp) = &x_prev {
                // Carry the base wrench and the tensions of cables still unknown.
                for i in 0..6 {
                    x0[i] = xp[i];
                }
                if let Some(ps) = &prev_setup {
                    for (j, &c) in setup.unknown.iter().enumerate() {
                        if let Some(pj) = ps.unknown.iter().position(|&q| q == c) {
                            x0[6 + j] = xp[6 + pj].max(0.0);
                        }
                    }
                }
            } else if let Some((n0, m0s, tens)) = &warm_x {
                for i in 0..3 {
                    x0[i] = n0[i];
                    x0[3 + i] = m0s[i];
                }
                for (j, &c) in setup.unknown.iter().enumerate() {
                    x0[6 + j] = tens[c];
                }
                if prob.shape_free_loads() {
                    // The balance is exact for the rod but not for its discretization, which
                    // misses it by the integration error; a warm start from this method has
                    // measured that offset. The offset vanishes with the load and, to first
                    // order, grows with it: keep it, scaled by the load ratio `ρ`.
                    let mut tw = [0.0; MAX_CABLES];
                    tw[..nc].copy_from_slice(tens);
                    let tn = prob.tensions(&x0, &setup, 1.0);
                    let (nb, mb) = prob.balance(&tn, 1.0);
                    let (nw, mw) = if same {
                        prob.balance(&tw, 1.0)
                    } else {
                        (*n0, m0s * len_l)
                    };
                    let rho = if same { load_ratio(&tn, &tw) } else { 1.0 };
                    for i in 0..3 {
                        x0[i] = nb[i] + (n0[i] - nw[i]) * rho;
                        x0[3 + i] = (mb[i] + (m0s[i] * len_l - mw[i]) * rho) / len_l;
                    }
                    // Likewise the tendon part of the Jacobian, `J − J₀` (`J₀`: the unloaded
                    // straight rod's, a rigid transport along `L e3`), for the wrench block.
                    if let Some(j) = warm_jac.as_mut().filter(|j| j.nrows() == x0.len()) {
                        let j0 = prob.transport_jacobian(&Vector3::new(0.0, 0.0, len_l));
                        for r in 0..6 {
                            for c in 0..6 {
                                j[(r, c)] = j0[(r, c)] + rho * (j[(r, c)] - j0[(r, c)]);
                            }
                        }
                    }
                }
            } else {
                prob.balance_guess(&mut x0, &setup, 1.0);
            }
            let jac0 = if x_prev.is_none() {
                warm_jac.as_ref()
            } else {
                None
            };
            let (sol, load_steps) =
                prob.solve_with_continuation(&x0, &setup, jac0)
                    .map_err(|e| SolveError::NotConverged {
                        method: name.clone(),
                        section: None,
                        iterations: total_it + e.iterations,
                        residual: e.residual,
                        detail: e.detail,
                    })?;
            if load_steps > 0 {
                notes.push(format!("continuation: {load_steps} load steps"));
            }
            let Newton {
                x,
                iterations: it,
                residual: res,
                jac,
            } = sol;
            total_it += it;
            // Complementarity: negative tension → slack; slack but stretched → taut.
            let tau = prob.tensions(&x, &setup, 1.0);
            let mut changed = false;
            let neg = setup
                .unknown
                .iter()
                .copied()
                .filter(|&c| tau[c] < 0.0)
                .min_by(|&a, &b| tau[a].total_cmp(&tau[b]));
            if let Some(c) = neg {
                slack[c] = true;
                changed = true;
            } else if setup.slack.iter().any(|&b| b) {
                let n0 = Vector3::new(x[0], x[1], x[2]);
                let m0 = Vector3::new(x[3], x[4], x[5]) * len_l;
                let shot = prob.shoot(&n0, &m0, &LoadCase { tau, lam: 1.0 }, None, None);
                for &c in &length_cables {
                    let tol_len = 10.0 * self.tolerance / prob.kl[c];
                    if setup.slack[c] && shot.len[c] > prob.target(c, 1.0) + tol_len {
                        slack[c] = false;
                        changed = true;
                    }
                }
            }
            if !changed {
                let mut shape = self.build_shape(&prob, &x, &setup, total_it, res, start, notes);
                shape.report.warm = jac.map(|jacobian| WarmState::Rod { jacobian });
                return Ok(shape);
            }
            x_prev = Some(x);
            prev_setup = Some(setup);
        }
        Err(SolveError::NotConverged {
            method: name,
            section: None,
            iterations: total_it,
            residual: f64::NAN,
            detail: "slack active set did not settle".into(),
        })
    }
}

impl Cosserat {
    /// Everything fixed during a solve: validated settings and inputs, routes, step counts,
    /// undeformed cable lengths. Also returns the report notes.
    fn problem<'a>(
        &'a self,
        robot: &'a Robot,
        act: &Actuation,
    ) -> Result<(Problem<'a>, Vec<String>), SolveError> {
        let name = self.name().to_string();
        let nc = robot.cables.len();
        if nc > MAX_CABLES {
            return Err(SolveError::Unsupported {
                method: name.clone(),
                reason: format!("at most {MAX_CABLES} cables (got {nc})"),
            });
        }
        if self.steps_per_section == 0 && self.adaptive.is_none() {
            return Err(SolveError::InvalidInput {
                field: "steps_per_section".into(),
                reason: "must be ≥ 1".into(),
            });
        }
        if let Some(t) = self.adaptive {
            if !(t.is_finite() && t > 0.0) {
                return Err(SolveError::InvalidInput {
                    field: "adaptive".into(),
                    reason: format!("tolerance must be > 0, got {t}"),
                });
            }
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(SolveError::InvalidInput {
                field: "tolerance".into(),
                reason: format!("must be > 0, got {}", self.tolerance),
            });
        }
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
        let drives = act.drives(
            robot,
            &name,
            &[Input::Shortening, Input::Tension],
            self.control,
        )?;
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
            nsteps: vec![],
            cubic: vec![],
            last: Default::default(),
        };
        prob.nsteps = prob.steps_per_section();
        prob.cubic = prob.route_cubics();
        if self.adaptive.is_none() {
            let total: usize = prob.nsteps[1..].iter().sum();
            notes[0].push_str(&format!(
                " ({total} in all, bend refinement {})",
                self.bend_refine
            ));
        }
        // Undeformed lengths in the chosen measure: the unloaded, straight rod (exact at
        // zero load), integrated with the same quadrature as the loaded one.
        let zero = LoadCase {
            tau: [0.0; MAX_CABLES],
            lam: 0.0,
        };
        if (0..nc).any(|c| matches!(prob.modes[c], Drive::Shorten { .. })) {
            prob.len0 = prob
                .shoot(&Vector3::zeros(), &Vector3::zeros(), &zero, None, None)
                .len;
        }

        Ok((prob, notes))
    }

    /// Diagnostic for tests: at the cold start point of a solve (global-balance guess, every
    /// length-controlled cable taut, its tension `tension_guess`), the shooting residual
    /// `F(x)`, its Jacobian from the variational equations, and central differences of `F`
    /// (step `1e-4·max(|x_j|, EI/L²)`: the full rod's `n = R Kse (v − e3)` cancels ~4 digits,
    /// so smaller steps measure rounding). `Ok(None)` where the variational Jacobian is not
    /// available (adaptive steps, point loads at inner disks).
    #[doc(hidden)]
    pub fn shooting_jacobians(
        &self,
        robot: &Robot,
        act: &Actuation,
        tension_guess: f64,
        rel_step: f64,
    ) -> Result<Option<JacobianCheck>, SolveError> {
        let (prob, _) = self.problem(robot, act)?;
        let unknown: Vec<usize> = (0..robot.cables.len())
            .filter(|&c| matches!(prob.modes[c], Drive::Shorten { .. }))
            .collect();
        let setup = Setup {
            slack: vec![false; robot.cables.len()],
            unknown,
        };
        let mut x = DVector::zeros(6 + setup.unknown.len());
        for j in 0..setup.unknown.len() {
            x[6 + j] = tension_guess;
        }
        prob.balance_guess(&mut x, &setup, 1.0);
        let Some((f, jv, _)) = prob.residual_jac(&x, &setup, 1.0) else {
            return Ok(None);
        };
        let mut jc = DMatrix::zeros(x.len(), x.len());
        for col in 0..x.len() {
            let h = rel_step * x[col].abs().max(prob.fscale);
            let mut xp = x.clone();
            xp[col] += h;
            let fp = prob.residual(&xp, &setup, 1.0);
            xp[col] -= 2.0 * h;
            let fm = prob.residual(&xp, &setup, 1.0);
            jc.set_column(col, &((fp - fm) / (2.0 * h)));
        }
        Ok(Some((f, jv, jc)))
    }

    #[allow(clippy::too_many_arguments)]
    fn build_shape(
        &self,
        prob: &Problem,
        x: &DVector<f64>,
        setup: &Setup,
        iterations: usize,
        residual: f64,
        start: Instant,
        notes: Vec<String>,
    ) -> Shape {
        let robot = prob.robot;
        let n0 = Vector3::new(x[0], x[1], x[2]);
        let m0 = Vector3::new(x[3], x[4], x[5]) * prob.len_l;
        let tau = prob.tensions(x, setup, 1.0);
        let ld = LoadCase { tau, lam: 1.0 };
        // The converged point was the last one integrated (Newton returns right after it):
        // reuse its geometry; integrate again only if it was another point.
        let mut trace = prob.last.take();
        let mut probe = Trace::default();
        probe.start(&n0, &m0, &ld);
        if trace.key != probe.key || trace.disks.len() != robot.sections() + 1 {
            prob.shoot(&n0, &m0, &ld, Some(&mut probe), None);
            trace = probe;
        }
        let disks: Vec<DiskFrame> = trace
            .disks
            .iter()
            .enumerate()
            .map(|(k, (p, r))| DiskFrame {
                s: robot.disk_s[k],
                position: *p,
                rotation: gram_schmidt(r),
            })
            .collect();
        let cables = robot
            .cables
            .iter()
            .enumerate()
            .map(|(c, cable)| {
                let points = (0..=cable.ends_at)
                    .map(|k| disks[k].position + disks[k].rotation * cable.hole(k))
                    .collect();
                let slack =
                    setup.slack[c] || matches!(prob.modes[c], Drive::Tension(t) if t == 0.0);
                CablePath {
                    name: cable.name.clone(),
                    points,
                    slack,
                    // One tension along a frictionless cable: slack everywhere or nowhere.
                    slack_sections: if slack {
                        (1..=cable.ends_at).collect()
                    } else {
                        vec![]
                    },
                    tension: Some(tau[c]),
                }
            })
            .collect();
        Shape {
            method: self.name().into(),
            disks,
            backbone: trace.backbone,
            cables,
            contacts: vec![],
            report: SolveReport {
                converged: true,
                iterations,
                residual,
                solve_time_s: start.elapsed().as_secs_f64(),
                sections: vec![],
                base_wrench: Some([n0.x, n0.y, n0.z, m0.x, m0.y, m0.z]),
                notes,
                stable: None,
                jacobian: None,
                warm: None,
            },
        }
    }
}
