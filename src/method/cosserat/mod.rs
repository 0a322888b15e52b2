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
//! differences in `tests/methods/cosserat.rs`). The tendon terms are differentiated in vector form,
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
//! method, `report.warm` ([`WarmState::Rod`](crate::method::WarmState::Rod): the last Jacobian): Newton then
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
//! [`SolveError::NotConverged`](crate::SolveError::NotConverged) with the iterations spent and the last residual. Every solve
//! is also bounded by [`WORK_BUDGET`] right-hand-side evaluations, whatever the section count.
//!
//! **Stability** (`report.stable`): a focal-point test, the Jacobi condition of the second
//! variation for a rod clamped at `s = 0` with a free (loaded) tip (Manning, Rogers &
//! Maddocks, Proc. R. Soc. A 454, 1998; Till & Rucker, "Elastic stability of Cosserat rods
//! and parallel continuum robots", IEEE T-RO 33(3), 2017; Dhanakoti, "Stability of
//! cantilever-like structures", arXiv:2407.07601, 2024). Tendons of fixed tension are
//! conservative (their potential is `−τ ℓ_i`, `ℓ_i = ∫ |ṗ_i|`, a local function of the strains),
//! gravity and the tip wrench are dead loads, so the rod + cables are a Lagrangian problem in
//! `s` and the variational equations of the shooting pass are its Jacobi equations. The six
//! Jacobi fields of the base wrench (`δp = δθ = 0` at the clamp) give at each disk `s`
//! `U = ∂(p, θ)(s)/∂(n₀, m₀)` and `W = ∂(n̄, m̄)(s)/∂(n₀, m₀)`, where `(n̄, m̄)` is the momentum
//! conjugate to `(p, θ)`: the wrench of the rod *and of the cables cut at `s`*
//! (`n + Σ τ R t`, `m + Σ τ (R r) × (R t)`; at the tip, the wrench after the ties). The fields
//! span a Lagrangian plane, so `C(s) = U W⁻¹` — the compliance of the base part `[0, s]` to a
//! wrench at `s` — is symmetric (to 1e-7 relative in the tests). It starts positive
//! definite (`C ≈ s·diag(1/GA, 1/GA, 1/EA, 1/EI, 1/EI, 1/GJ)` near the clamp, positive
//! semidefinite for the inextensible rod) and an eigenvalue leaves through `+∞` and comes
//! back from `−∞` at each focal point (`W` singular: a neutral mode of the base part with a
//! free end). The answer is stable iff there is none on `(0, L]`: `stable = Some(true)` when
//! `C` is positive semidefinite (eigenvalues ≥ −1e-9 of the largest) at every disk. The
//! disks sample `s`; a focal point between disks shows at the next one, where the eigenvalue
//! is still far below zero. Euler's column: `C = tan(ks)/k` for `k² = P/EI`, first focal
//! point at `ks = π/2`, i.e. `P_cr = π² EI/(4L²)` (test `tests/methods/cosserat_stability.rs`).
//! With a length-controlled cable the test holds its tension fixed, which admits more
//! perturbations than fixed lengths do: no focal point proves the displacement-controlled
//! answer stable too, a focal point does not prove it unstable (`None`). Also `None` where the
//! variational pass is not run (adaptive steps, point loads at inner disks, e.g. the FTDCR's
//! ties at disks 10 and 20, when loaded and shooting on Rucker–Webster's equations). The test
//! costs one variational pass per solve where the rod shoots on those, nothing on the
//! unloaded path and three tangents more per pass but the cold start's on the loaded one
//! (below); the setting
//! `stability = skip` leaves it out, and `stable` is then `None` meaning *not checked* (the
//! report's notes say `stability not checked`).

//! # Unloaded rod: no shooting
//!
//! With no external load (no gravity, disk weights, tip force or moment) and every tension
//! given, the rod takes another path (`unloaded.rs`, setting `solver = auto`, the default;
//! `solver = shooting` always shoots): a cut through backbone and tendons at any `s` shows
//! that the internal wrench is the tendons' pull there, `nb = −Σ τ t_i`, `mb = −Σ τ r_i × t_i`,
//! so the strains at each point solve a strictly convex six-unknown balance (Newton, two
//! evaluations per point), and one fourth-order Magnus integration on SE(3) gives the shape.
//! Shortened cables (length along the path, displacement control) keep this path: Newton on
//! their tensions, the lengths' tension Jacobian in closed form beside each pass
//! (`unloaded_solve.rs`); shooting is the fallback if it does not settle.
//! Same answer as converged shooting (to 1 µm on random tension-driven robots,
//! `tests/methods/cosserat_unloaded.rs`), exact for a straight tendon's arc, fourth order in
//! the step; the 24-section soft lung rod meets the converged rod to 0.5 µm with one step per
//! section and to 0.006 µm at the default three. The report has zero iterations, the largest
//! balance residual at a point, and a note. Stability needs no pass here: the energy is
//! strictly convex in the strains, so every answer is stable (`unloaded_solve.rs`,
//! "Stability without a pass"; the report says so in a note).

//! # Loaded rod: shooting on the external moment
//!
//! With external loads (gravity, disk weights, a tip wrench), every tension given and no
//! obstacle, the rod still shoots, but not on Rucker–Webster's strain rates (`loaded.rs`,
//! setting `solver = auto`; `shooting` shoots on them): the cut of the unloaded path gives
//! the strains at each point from a convex balance with the external wrench beyond the
//! point, `N(s)` (known: dead loads) and `M(s)` (`M′ = −p′ × N`). The unknowns are the three
//! components of `M(0)`, the residual `M(L) − M_tip`; the strains are never integrated, so
//! their error does not pile up where a route bends, and cables tied at inner disks and disk
//! weights need no kink solve. Newton with the exact Jacobian from tangents in the same pass
//! (`K⁻¹` of the balance reused), from the loads' moment on the unloaded rod; the passes after
//! a cold start's first carry the six Jacobi fields when the stability test is asked for, and
//! the focal-point test reads them at each disk (the conjugate momentum is `(N, M)` itself), so
//! the test costs no pass of its own (a start that is already the answer takes one). Each
//! pass after the first starts the strain Newton at every point from the last tangent pass's
//! strains there, moved by their tangents along the step (`loaded.rs` `Track`): near the
//! answer one balance evaluation per point instead of two. At the default steps the paper cases under lateral gravity and a 0.05 N tip force
//! meet the converged rod to 0.012 / 0.003 / 0.009 µm at the tip (shooting on the strain
//! rates: 0.17 / 0.09 / 7.5 µm), random loaded robots to 0.2 µm
//! (`tests/methods/cosserat_loaded.rs`). Displacement control with loads shoots on
//! Rucker–Webster's equations.

//! # Cable length and slack (displacement control)
//!
//! A cable's length is either the routed path `∫ |ṗ_i| ds` (integrated with the states,
//! default) or the straight chords between its holes at the disks (the geometric model's
//! measure). The target is the undeformed length in the same measure minus the shortening.
//! **Compliant cables** (a cable's `stiffness` k and `pretension` T₀, [`crate::robot::Cable`]):
//! the cable is a spring in series, so its path is its free length plus its stretch,
//! `ℓ = t + τ/k` with `t = ℓ⁰ − d − T₀/k` (the energy model's `L − t − λ/k`); the length
//! equation becomes `k_ℓ (ℓ − t − τ/k)` and its Jacobian gains `−k_ℓ/k` on the cable's own
//! tension column. A compliant solve at shortening `d` is therefore the inextensible solve
//! at `d + T₀/k − τ/k` (`tests/methods/cosserat_compliance.rs`). Under force control k changes nothing.
//! The stability test above still proves stability: a spring's potential `½ k (ℓ − t)²` adds
//! `k δℓ² ≥ 0` to the fixed-tension second variation the test checks.
//! Cables pull only: an active set makes a cable whose tension comes out negative slack
//! (tension 0, length equation dropped), and re-tensions a slack cable whose path comes out
//! longer than its length. The answer has `τ ≥ 0` and slack cables no longer than their length.
//! A frictionless cable carries one tension along its whole length, so in this model a cable is
//! slack everywhere or nowhere: `slack_sections` of a slack cable lists all its sections
//! `1..=ends_at` (section-wise slackness exists only in the section-by-section geometric
//! model). The inextensible rod cannot take every set of shortenings: cables tied at one disk
//! whose holes balance about the axis bound each other's lengths from below (see
//! `inextensible.rs`): such shortenings are reported [`SolveError::Infeasible`](crate::SolveError::Infeasible) with the proof,
//! and one cable of each such group starts slack (all taut is singular at the straight rod).
//!
//! # Contact
//!
//! Next to obstacles the rod touches the world with its disks: frictionless point forces,
//! complementary to the disks' gaps, their magnitudes extra unknowns of the shooting problem
//! and the gaps extra residuals; an outer active set; a cold start by load steps that no disk
//! can cross an obstacle in (`contact.rs`, `approach.rs`, with the formulation and its
//! references).
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
//!
//! # Files
//!
//! `settings` (the solver's options) · `rhs` (the plain Rucker–Webster right-hand side, the
//! math in one short function) · `variational` (its derivatives: the tangent equations through
//! sections and disks) · `jacobian` (the exact shooting Jacobian assembled from one
//! variational pass, the focal-point stability test, test diagnostics) · `integrate` (RK4
//! over sections, jumps at the disks, one shooting pass) · `adaptive` (Dormand–Prince over
//! stretches between jumps) · `problem` (what is fixed during a solve, global balance) ·
//! `shooting` (Newton with Broyden updates, load continuation) · `warm` (the start from a
//! previous shape) · `inextensible` (balanced cable groups of the Kirchhoff rod under
//! displacement control: proven infeasible shortenings, the slack start) · `loaded` (the
//! loaded rod shot on its external moment, its Jacobi fields and focal-point test) · `unloaded` (the
//! path without shooting: strains from the tendons' balance, Magnus steps) · `unloaded_solve`
//! (its solve: the given tensions, or Newton on the shortened cables') · `contact`
//! (point contacts at the disks: witnesses, active set, the crossing check) · `approach`
//! (the cold start next to obstacles) · `solve` (the `Method` entry: active sets of slack
//! cables and contacts, shape assembly).

mod adaptive;
mod approach;
mod contact;
mod inextensible;
mod integrate;
mod jacobian;
mod loaded;
mod problem;
mod rhs;
mod settings;
mod shooting;
mod solve;
mod unloaded;
mod unloaded_solve;
mod variational;
mod warm;

pub use problem::WORK_BUDGET;
pub use settings::{Cosserat, RodModel};

use nalgebra::{DMatrix, DVector, Matrix3, SVector, Vector3};

/// Largest number of cables the rod integrator handles (fixed-size buffers, no allocation).
pub const MAX_CABLES: usize = 16;

/// Rod state `[p, R (column-major), v (Kirchhoff: n), u]`.
type State = SVector<f64, 18>;
/// One number per cable.
type Buf = [f64; MAX_CABLES];

/// Shooting residual, its variational Jacobian and its central-difference Jacobian (see
/// [`Cosserat::shooting_jacobians`]).
pub type JacobianCheck = (DVector<f64>, DMatrix<f64>, DMatrix<f64>);

/// The undeformed body axis (`v* = e3`).
const E3: Vector3<f64> = Vector3::new(0.0, 0.0, 1.0);

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

/// The orientation `R` of a state.
#[inline]
fn rot_of(y: &State) -> Matrix3<f64> {
    Matrix3::from_column_slice(&y.as_slice()[3..12])
}

/// The 3-vector at `y[i..i + 3]`.
#[inline]
fn v3(y: &State, i: usize) -> Vector3<f64> {
    Vector3::new(y[i], y[i + 1], y[i + 2])
}

/// Write `v` to `y[i..i + 3]`.
#[inline]
fn put3(y: &mut State, i: usize, v: &Vector3<f64>) {
    y[i] = v.x;
    y[i + 1] = v.y;
    y[i + 2] = v.z;
}
