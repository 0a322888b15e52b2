//! The rod carried by its tendons alone: the strains from the balance at each point and one
//! integration, no shooting (module docs, "Unloaded rod").
//!
//! # Why the strains are known along the rod
//!
//! With no external load — no gravity, no disk weights, no tip force or moment (the rod has
//! no obstacles) — cut the robot at arc length `s` through the backbone *and* the tendons.
//! The part beyond the cut, the rod on `[s, L]` with every tendon from `s` to where it is
//! tied, is in static balance, and every force on it acts at the cut: the backbone's
//! internal wrench `(−n, −m)` from the base part and each running tendon's tension pulling
//! back along its tangent, `−τ_i t_i` at `p_i = p + R r_i`. The tendons' distributed loads on
//! the rod, their ties and their kink forces at disks are internal to that part. Hence, in
//! the body frame (`nb = Rᵀ n`, `mb = Rᵀ m`; the global balance of
//! [`Problem::balance`] at every `s`, not only at the base):
//!
//! ```text
//! nb(s) = −Σ τ_i t_i,   mb(s) = −Σ τ_i r_i × t_i,   t_i = ṗ_i/|ṗ_i|,   ṗ_i = v + u × r_i + r_i′
//! ```
//!
//! summed over the tendons running at `s`. With the constitutive law `nb = Kse (v − e3)`,
//! `mb = Kbt u` these are six equations in the six local strains (Kirchhoff: three in `u`,
//! `v ≡ e3`), free of `p` and `R`:
//!
//! ```text
//! F(v, u) = [Kse (v − e3) + Σ τ_i t_i ;  Kbt u + Σ τ_i r_i × t_i] = 0.
//! ```
//!
//! `F` is the gradient of `Φ(v, u) = ½ (v − e3)ᵀ Kse (v − e3) + ½ uᵀ Kbt u + Σ τ_i |ṗ_i|`, and
//! with `∂ṗ_i/∂(v, u) = [I, −r̂_i]` its Hessian is `[Kse + A, G; Gᵀ, Kbt + H]`, the matrix of
//! Rucker & Webster's eq. 13–17 (`A_i = τ_i (I − t_i t_iᵀ)/|ṗ_i| ⪰ 0`): symmetric positive
//! definite for `τ ≥ 0`. So `Φ` is strictly convex, the strains at `s` are unique, and
//! Newton from the neighbouring point finds them in two or three iterations (steps capped
//! so that no tendon's `ṗ_i` moves by more than a quarter). Differentiating `F(v(s), u(s)) =
//! 0` along `s` gives R&W's system for `(v′, u′)` again: the balance is a first integral of
//! the ODE that shooting integrates, and shooting's root is the rod whose base strains solve
//! `F = 0` at `s = 0` (the published fast forward kinematics of tendon robots uses the same
//! fact: a fixed point for the base strains, then one integration). Where a tendon is tied
//! the sum loses its term and the strains jump; the ties' point loads need no extra care.
//!
//! # One integration
//!
//! The shape follows from `g′ = g ξ̂`, `g = (R, p) ∈ SE(3)`, with the body twist `ξ = (v, u)`
//! known along `s`: a linear ODE on a Lie group, stepped by the fourth-order Magnus method at
//! the two Gauss points `s + h (½ ∓ √3/6)` (Iserles, Munthe-Kaas, Nørsett & Zanna, "Lie-group
//! methods", Acta Numerica 9, 2000, §4; the sign of the bracket is the one for `g′ = g ξ̂`):
//! `g ← g exp(Ω)`, `Ω = h/2 (ξ₁ + ξ₂) + √3 h²/12 [ξ₁, ξ₂]`, with the bracket
//! `[(v₁, u₁), (v₂, u₂)] = (u₁ × v₂ − u₂ × v₁, u₁ × u₂)` and the closed-form SE(3)
//! exponential. It is exact for constant strains (the arc of a straight tendon), keeps `R`
//! orthonormal to rounding, and is fourth order otherwise; the path lengths `∫ |ṗ_i| ds` use
//! the same two Gauss points (fourth order too). Disks are step boundaries, and each section
//! takes the steps shooting would (`rk4-steps`, more where a route bends).

use super::problem::{LoadCase, Problem, Shot, Trace};
use super::rhs::{CablePoints, Point};
use super::{sym_inverse, Buf, RodModel, E3, MAX_CABLES};
use crate::model::routing::RoutePoint;
use crate::numeric::so3::{abc, hat};
use nalgebra::{Matrix3, Vector3, Vector6};

/// Newton iterations allowed for the strains at one point (two or three are typical).
const STRAIN_ITERATIONS: usize = 60;
/// Newton also stops after a step that moves no tendon's `ṗ_i` by more than this (relative,
/// `|ṗ| ≈ 1`): rounding, where a tight `tolerance` cannot be met.
const STRAIN_STEP_TOL: f64 = 1e-14;
/// Largest move of a tendon's `ṗ_i` per Newton step (a cap, not a line search: `Φ` is convex).
const STRAIN_STEP_CAP: f64 = 0.25;

/// The unloaded pass: the shot (zero tip residual: the balance holds at every point), the
/// base wrench, and the largest balance residual left at a point \[N\] (moments / L).
pub(super) struct Unloaded {
    pub(super) shot: Shot,
    pub(super) n0: Vector3<f64>,
    /// `m(0)/L`, as the solution vector holds it.
    pub(super) ms: Vector3<f64>,
    pub(super) residual: f64,
}

/// What one point gives besides its strains: each running cable's `|ṗ_c|` (`lr`), its value
/// `|e3 + r_c′|` on the straight, unloaded rod (`rest`), and, for the cables `sens` marks,
/// the tension sensitivities `dl[i][j] = ∂|ṗ_i|/∂τ_j` (`unloaded_solve.rs`).
pub(super) struct At {
    pub(super) lr: Buf,
    pub(super) rest: Buf,
    sens: [bool; MAX_CABLES],
    dl: Sens,
    /// The balance's Hessian at the last evaluation, factored (the loaded pass's tangents).
    pub(super) stiffness: Stiffness,
    /// `Σ τ_i t_i` at the last evaluation (the Kirchhoff rod's force is `N − Rᵀ` of it).
    pub(super) pull: Vector3<f64>,
    /// Take a point after a Newton step whose second-order remainder bounds the balance
    /// below the tolerance, without evaluating it again ([`Problem::strains_at`]; the loaded
    /// pass's, whose starts are predicted close).
    pub(super) quadratic: bool,
}

/// One number per pair of cables.
pub(super) type Sens = [[f64; MAX_CABLES]; MAX_CABLES];

impl At {
    pub(super) fn new(sens: [bool; MAX_CABLES]) -> Self {
        At {
            lr: [0.0; MAX_CABLES],
            rest: [0.0; MAX_CABLES],
            sens,
            dl: [[0.0; MAX_CABLES]; MAX_CABLES],
            stiffness: Stiffness {
                k1inv: Matrix3::zeros(),
                sinv: Matrix3::zeros(),
                p: Matrix3::zeros(),
                full: false,
            },
            pull: Vector3::zeros(),
            quadratic: false,
        }
    }
}

/// The balance's Hessian `K = [Kse + A, G; Gᵀ, Kbt + H]` at a point, factored by blocks:
/// `(Kse + A)⁻¹`, the Schur complement's inverse and `P = (Kse + A)⁻¹ G` (Kirchhoff:
/// `(Kbt + H)⁻¹` alone).
#[derive(Clone, Copy)]
pub(super) struct Stiffness {
    k1inv: Matrix3<f64>,
    sinv: Matrix3<f64>,
    p: Matrix3<f64>,
    full: bool,
}

impl Stiffness {
    /// `K⁻¹ [bv; bu]` (Kirchhoff: `(Kbt + H)⁻¹ bu`, no `v` part): `xu = S⁻¹ (bu − Pᵀ bv)`,
    /// `xv = (Kse + A)⁻¹ bv − P xu`, four products with a 3×3 matrix.
    pub(super) fn solve(
        &self,
        bv: &Vector3<f64>,
        bu: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        if !self.full {
            return (Vector3::zeros(), self.sinv * bu);
        }
        let xu = self.sinv * (bu - self.p.tr_mul(bv));
        (self.k1inv * bv - self.p * xu, xu)
    }
}

/// The strains `(v, u)` at one point.
#[derive(Clone, Copy)]
pub(super) struct Strains {
    pub(super) v: Vector3<f64>,
    pub(super) u: Vector3<f64>,
}

impl Problem<'_> {
    /// True when this solve takes the unloaded path: the `solver` setting allows it, fixed
    /// steps (not `--adaptive`), no external load at all, and every cable pulled with a given
    /// tension, free, or shortened with its length measured along its path (its tension then
    /// an unknown, `unloaded_solve.rs`; chords go on shooting).
    pub(super) fn unloaded_applies(&self) -> bool {
        use crate::model::actuation::{Drive, LengthMeasure};
        self.set.unloaded
            && self.set.adaptive.is_none()
            && self.shape_free_loads()
            && self.tip_m == Vector3::zeros()
            && self.modes.iter().all(|m| match m {
                Drive::Tension(_) | Drive::Free => true,
                Drive::Shorten { .. } => self.set.length == LengthMeasure::Path,
            })
    }

    /// One pass at the loads `ld`: the unloaded path's when it applies ([`Problem::fast`]),
    /// else shooting from the base wrench `n0`, `m0`.
    pub(super) fn pass(
        &self,
        n0: &Vector3<f64>,
        m0: &Vector3<f64>,
        ld: &LoadCase,
        trace: Option<&mut Trace>,
    ) -> Shot {
        if self.fast {
            if let Some(un) = self.unloaded_pass(ld, trace, None) {
                return un.shot;
            }
            return Shot::failed();
        }
        if self.loaded {
            return self.loaded_shot(n0, m0, ld, trace);
        }
        self.shoot(n0, m0, ld, trace, None)
    }

    /// The strains at `s` in section `sec` from the start `z` (the neighbouring point's):
    /// Newton on `F = b` (module docs; `ext = b = (bv, bu)`, the external loads' wrench on the
    /// part beyond `s` in the body frame, `loaded.rs`; zero here). `at` receives each running cable's `|ṗ_c|` there, its
    /// value on the straight, unloaded rod, and, if asked, their tension sensitivities
    /// ([`At`]). Returns the strains and the balance residual \[N\] of the last evaluation, or
    /// `None` if Newton does not settle (never seen for `τ ≥ 0`: `Φ` is strictly convex).
    pub(super) fn strains_at(
        &self,
        s: f64,
        sec: usize,
        ld: &LoadCase,
        mut z: Strains,
        ext: (&Vector3<f64>, &Vector3<f64>),
        at: &mut At,
    ) -> Option<(Strains, f64)> {
        let (bv, bu) = ext;
        let full = self.set.model == RodModel::Full;
        // The routes once for all iterations, and the largest tendon offset here
        // (`|δṗ_i| ≤ |δv| + |δu| r_max`).
        let zero = Vector3::zeros();
        let mut routes = [RoutePoint {
            r: zero,
            dr: zero,
            ddr: zero,
        }; MAX_CABLES];
        let mut rmax = 0.0f64;
        for (c, cable) in self.robot.cables.iter().enumerate() {
            if cable.ends_at >= sec {
                routes[c] = self.eval_route(c, s, sec);
                rmax = rmax.max(routes[c].r.norm());
                at.rest[c] = (routes[c].dr + E3).norm();
            }
        }
        if rmax == 0.0 {
            rmax = self.robot.disk_radius.max(1e-6);
        }
        // No tendon pulls here (the rest lengths' pass, or beyond the pulled ties): the
        // balance is linear, `Kse (v − e3) = 0`, `Kbt u = 0`, and the rod is straight.
        let mut cables = self.robot.cables.iter().enumerate();
        if !cables.any(|(c, cable)| cable.ends_at >= sec && ld.tau[c] != 0.0) {
            // (With external loads the balance is still linear: `v = e3 + Kse⁻¹ bv`,
            // `u = Kbt⁻¹ bu`; the running cables' rates are the ones of these strains.)
            let straight = Strains {
                v: match full {
                    true => E3 + bv.component_div(&self.kse),
                    false => E3,
                },
                u: bu.component_div(&self.kbt),
            };
            at.lr = at.rest;
            if *bv != Vector3::zeros() || *bu != Vector3::zeros() {
                for (c, cable) in self.robot.cables.iter().enumerate() {
                    if cable.ends_at >= sec {
                        let rp = &routes[c];
                        at.lr[c] = (straight.u.cross(&rp.r) + rp.dr + straight.v).norm();
                    }
                }
            }
            let k = Stiffness {
                k1inv: Matrix3::from_diagonal(&self.kse.map(|x| 1.0 / x)),
                sinv: Matrix3::from_diagonal(&self.kbt.map(|x| 1.0 / x)),
                p: Matrix3::zeros(),
                full,
            };
            at.stiffness = k;
            at.pull = Vector3::zeros();
            if at.sens.contains(&true) {
                self.sensitivities(&straight, &routes, sec, &k, at);
            }
            return Some((straight, 0.0));
        }
        let mut keep = CablePoints::new();
        for _ in 0..STRAIN_ITERATIONS {
            let v = if full { z.v } else { E3 };
            let pt = Point {
                r: Matrix3::identity(),
                w: v,
                u: z.u,
                v,
            };
            let sums = self.tendon_sums::<false, false>(
                |c| routes[c],
                sec,
                &pt,
                ld,
                &mut at.lr,
                &mut keep,
            );
            self.work.set(self.work.get() + 1);
            let fv = self.kse.component_mul(&(v - E3)) + sums.pull - bv;
            let fu = self.kbt.component_mul(&z.u) + sums.twist - bu;
            at.pull = sums.pull;
            // (Kirchhoff: `v ≡ e3` and `n` is no strain, so the force rows are not equations.)
            let residual = match full {
                true => fv.norm().max(fu.norm() / self.len_l),
                false => fu.norm() / self.len_l,
            };
            let k = if full {
                let k1 = Matrix3::from_diagonal(&self.kse) + sums.am;
                let k1inv = sym_inverse(&k1)?;
                let p = k1inv * sums.gm;
                let schur = Matrix3::from_diagonal(&self.kbt) + sums.hm - sums.gm.tr_mul(&p);
                Stiffness {
                    k1inv,
                    sinv: sym_inverse(&schur)?,
                    p,
                    full,
                }
            } else {
                let m = Matrix3::from_diagonal(&self.kbt) + sums.hm;
                Stiffness {
                    k1inv: Matrix3::zeros(),
                    sinv: sym_inverse(&m)?,
                    p: Matrix3::zeros(),
                    full,
                }
            };
            let (dv, du) = k.solve(&-fv, &-fu);
            let size = dv.norm() + du.norm() * rmax;
            if !size.is_finite() {
                return None;
            }
            let scale = if size > STRAIN_STEP_CAP {
                STRAIN_STEP_CAP / size
            } else {
                1.0
            };
            let before = z;
            z.v += dv * scale;
            z.u += du * scale;
            // Converged when the balance holds to the solver's tolerance (the step just taken
            // only shrinks it further), or when the step is at rounding level.
            if residual <= self.set.tolerance || size <= STRAIN_STEP_TOL {
                at.stiffness = k;
                if at.sens.contains(&true) {
                    self.sensitivities(&z, &routes, sec, &k, at);
                }
                return Some((z, residual));
            }
            if at.quadratic && scale == 1.0 {
                let bound = self.remainder_bound(sec, ld, size, rmax, at);
                if bound <= self.set.tolerance {
                    at.stiffness = k;
                    self.moved_to_first_order(&before, (&dv, &du), &routes, sec, &sums, at);
                    return Some((z, bound));
                }
            }
        }
        None
    }

    /// A bound on the balance left after a full Newton step that moves no tendon's `ṗ_i` by
    /// more than `size`: the step zeroes the linear model, and `F` is linear but for the
    /// tendons' `τ_i t_i(ṗ_i)`, whose second derivative is at most `3/|ṗ_i|²` in norm, so each
    /// leaves at most `3/2 τ_i size² / (|ṗ_i| − size)²` in the force rows (the moment rows:
    /// `r_i ×` it, over `L`). Infinite where the step is not small against `|ṗ_i|`.
    fn remainder_bound(&self, sec: usize, ld: &LoadCase, size: f64, rmax: f64, at: &At) -> f64 {
        let mut sum = 0.0;
        for (c, cable) in self.robot.cables.iter().enumerate() {
            if cable.ends_at < sec || ld.tau[c] == 0.0 {
                continue;
            }
            let gap = at.lr[c] - size;
            if gap <= 0.5 * at.lr[c] {
                return f64::INFINITY;
            }
            sum += 1.5 * ld.tau[c] * (size / gap).powi(2);
        }
        sum * (rmax / self.len_l).max(1.0)
    }

    /// After a point taken on the remainder bound ([`At::quadratic`]): each running cable's
    /// `|ṗ_c|` and the pull moved by the step `(dv, du)` from the strains `before` to first
    /// order (`δ|ṗ_c| = t_cᵀ (δv + δu × r_c)`, `δ pull = A δv + G δu`), leaving `O(size²)`.
    fn moved_to_first_order(
        &self,
        before: &Strains,
        (dv, du): (&Vector3<f64>, &Vector3<f64>),
        routes: &[RoutePoint; MAX_CABLES],
        sec: usize,
        sums: &super::rhs::TendonSums,
        at: &mut At,
    ) {
        let full = self.set.model == RodModel::Full;
        let v = if full { before.v } else { E3 };
        for (c, cable) in self.robot.cables.iter().enumerate() {
            if cable.ends_at < sec {
                continue;
            }
            let rp = &routes[c];
            let pd = before.u.cross(&rp.r) + rp.dr + v;
            at.lr[c] += pd.dot(&(dv + du.cross(&rp.r))) / at.lr[c];
        }
        at.pull += sums.am * dv + sums.gm * du;
    }

    /// The tension sensitivities of the running cables' `|ṗ_i|` among those asked for (`at.sens`) at strains `z` (into
    /// `at.dl`): `∂|ṗ_i|/∂τ_j = −b_iᵀ K⁻¹ b_j` with `b_i = [t_i; r_i × t_i]` (Kirchhoff:
    /// `r_i × t_i`), which is both `∂F/∂τ_i` and `∂|ṗ_i|/∂(v, u)`; `K` the balance's Hessian
    /// (module docs) at the last evaluation.
    fn sensitivities(
        &self,
        z: &Strains,
        routes: &[RoutePoint; MAX_CABLES],
        sec: usize,
        k: &Stiffness,
        at: &mut At,
    ) {
        let v = if k.full { z.v } else { E3 };
        let mut b = [(Vector3::zeros(), Vector3::zeros()); MAX_CABLES];
        let mut w = b;
        let running = |c: &usize| self.robot.cables[*c].ends_at >= sec && at.sens[*c];
        let nc = self.robot.cables.len();
        for c in (0..nc).filter(running) {
            let rp = &routes[c];
            let t = (z.u.cross(&rp.r) + rp.dr + v).normalize();
            let bu = rp.r.cross(&t);
            let bv = if k.full { t } else { Vector3::zeros() };
            b[c] = (bv, bu);
            w[c] = k.solve(&bv, &bu);
        }
        for i in (0..nc).filter(running) {
            for j in (0..nc).filter(running) {
                at.dl[i][j] = -(b[i].0.dot(&w[j].0) + b[i].1.dot(&w[j].1));
            }
        }
    }

    /// The unloaded pass (module docs): the strains at `s = 0` give the base wrench, then each
    /// section is stepped by fourth-order Magnus at the Gauss points, disks are step
    /// boundaries. The geometry goes to `trace` (default: the problem's `last`, marked as this
    /// path's). With `sens` (the Jacobian and the cables asked for), the path lengths'
    /// tension sensitivities `∂ℓ_i/∂τ_j` among those cables by the same quadrature go there.
    /// `None` if the strains cannot be found at some point.
    pub(super) fn unloaded_pass(
        &self,
        ld: &LoadCase,
        trace: Option<&mut Trace>,
        sens: Option<(&mut Sens, [bool; MAX_CABLES])>,
    ) -> Option<Unloaded> {
        self.unloaded_pass_steps(ld, trace, sens, &self.nsteps)
    }

    /// [`Self::unloaded_pass`] with `steps[k]` Magnus steps in section `k` (a loaded solve's
    /// cold start takes one per section: `loaded.rs`).
    pub(super) fn unloaded_pass_steps(
        &self,
        ld: &LoadCase,
        trace: Option<&mut Trace>,
        sens: Option<(&mut Sens, [bool; MAX_CABLES])>,
        nsteps: &[usize],
    ) -> Option<Unloaded> {
        let robot = self.robot;
        let nc = robot.cables.len();
        let asked = sens.as_ref().map_or([false; MAX_CABLES], |s| s.1);
        let mut sens = sens.map(|s| s.0);
        let (mut a, mut b) = (At::new(asked), At::new(asked));
        let straight = Strains {
            v: E3,
            u: Vector3::zeros(),
        };
        let zero = Vector3::zeros();
        let none = (&zero, &zero);
        let (z0, mut residual) = self.strains_at(0.0, 1, ld, straight, none, &mut a)?;
        // Kirchhoff: `n` is not a strain, but the same balance gives it (`−Σ τ t`).
        let n0 = match self.set.model {
            RodModel::Full => self.kse.component_mul(&(z0.v - E3)),
            RodModel::Kirchhoff => self.kirchhoff_force(0.0, 1, ld, &z0),
        };
        // The solution vector holds `m0 / L`, and the shape reads `m0` back from it: the
        // trace's key is taken the same way, so the two match bit for bit.
        let ms = self.kbt.component_mul(&z0.u) / self.len_l;
        let m0 = ms * self.len_l;
        let mut last = self.last.borrow_mut();
        let rec: &mut Trace = match trace {
            Some(t) => t,
            None => &mut last,
        };
        rec.start(&n0, &m0, ld);
        rec.fast = true;
        rec.disks.push((Vector3::zeros(), Matrix3::identity()));
        rec.backbone.push(Vector3::zeros());
        let (mut p, mut r) = (Vector3::<f64>::zeros(), Matrix3::<f64>::identity());
        // The lengths, and the rest lengths of the straight rod by the same quadrature.
        let (mut path, mut path0) = ([0.0; MAX_CABLES], [0.0; MAX_CABLES]);
        let (mut chord, mut chord0) = ([0.0; MAX_CABLES], [0.0; MAX_CABLES]);
        let mut prev = [Vector3::zeros(); MAX_CABLES];
        for (c, cable) in robot.cables.iter().enumerate() {
            prev[c] = cable.hole(0);
        }
        let mut prev0 = prev;
        if let Some(d) = sens.as_deref_mut() {
            *d = [[0.0; MAX_CABLES]; MAX_CABLES];
        }
        let gauss = 3f64.sqrt() / 6.0;
        let mut guess = Guess::new(0.0, z0);
        for (k, &steps) in nsteps.iter().enumerate().take(robot.sections() + 1).skip(1) {
            let (s0, s1) = (robot.disk_s[k - 1], robot.disk_s[k]);
            // The strains jump where a pulled tendon is tied: no extrapolation across.
            let tied = robot.cables.iter().enumerate();
            if tied
                .clone()
                .any(|(c, cable)| cable.ends_at + 1 == k && ld.tau[c] != 0.0)
            {
                guess.forget();
            }
            let h = (s1 - s0) / steps as f64;
            for j in 0..steps {
                let s = s0 + j as f64 * h;
                let (sa, sb) = (s + h * (0.5 - gauss), s + h * (0.5 + gauss));
                let (z1, r1) = self.strains_at(sa, k, ld, guess.at(sa), none, &mut a)?;
                guess.push(sa, z1);
                let (z2, r2) = self.strains_at(sb, k, ld, guess.at(sb), none, &mut b)?;
                guess.push(sb, z2);
                residual = residual.max(r1).max(r2);
                let (dp, dr) = magnus_step(h, &z1, &z2);
                p += r * dp;
                r *= dr;
                let running = |c: &usize| robot.cables[*c].ends_at >= k;
                for c in (0..nc).filter(running) {
                    path[c] += 0.5 * h * (a.lr[c] + b.lr[c]);
                    path0[c] += 0.5 * h * (a.rest[c] + b.rest[c]);
                }
                if let Some(d) = sens.as_deref_mut() {
                    let asked = |c: &usize| running(c) && asked[*c];
                    for i in (0..nc).filter(asked) {
                        for j in (0..nc).filter(asked) {
                            d[i][j] += 0.5 * h * (a.dl[i][j] + b.dl[i][j]);
                        }
                    }
                }
                rec.backbone.push(p);
            }
            rec.disks.push((p, r));
            self.advance_chords(k, &p, &r, &mut chord, &mut prev);
            let straight = Vector3::new(0.0, 0.0, s1);
            self.advance_chords(k, &straight, &Matrix3::identity(), &mut chord0, &mut prev0);
        }
        let (len, len0) = match self.set.length {
            crate::model::actuation::LengthMeasure::Path => (path, path0),
            crate::model::actuation::LengthMeasure::Chord => (chord, chord0),
        };
        rec.len.extend_from_slice(&len[..nc]);
        rec.rest.extend_from_slice(&len0[..nc]);
        Some(Unloaded {
            shot: Shot {
                resid: Vector6::zeros(),
                len,
                tip: p,
                touch: Vec::new(),
            },
            n0,
            ms,
            residual,
        })
    }

    /// The straight rod's path lengths by the unloaded pass's quadrature (`|e3 + r_c′|` at its
    /// Gauss points; the same bits as the `rest` it records beside a pass), without a pass.
    pub(super) fn rest_paths(&self) -> Buf {
        let robot = self.robot;
        let gauss = 3f64.sqrt() / 6.0;
        let mut path0 = [0.0; MAX_CABLES];
        for k in 1..=robot.sections() {
            let (s0, s1) = (robot.disk_s[k - 1], robot.disk_s[k]);
            let h = (s1 - s0) / self.nsteps[k] as f64;
            for j in 0..self.nsteps[k] {
                let s = s0 + j as f64 * h;
                let (sa, sb) = (s + h * (0.5 - gauss), s + h * (0.5 + gauss));
                for (c, cable) in robot.cables.iter().enumerate() {
                    if cable.ends_at >= k {
                        let a = (self.eval_route(c, sa, k).dr + E3).norm();
                        let b = (self.eval_route(c, sb, k).dr + E3).norm();
                        path0[c] += 0.5 * h * (a + b);
                    }
                }
            }
        }
        path0
    }

    /// The Kirchhoff rod's internal force at `s` (base frame at the base): `−Σ τ t`.
    fn kirchhoff_force(&self, s: f64, sec: usize, ld: &LoadCase, z: &Strains) -> Vector3<f64> {
        let pt = Point {
            r: Matrix3::identity(),
            w: E3,
            u: z.u,
            v: E3,
        };
        let mut lr = [0.0; MAX_CABLES];
        let mut keep = CablePoints::new();
        -self
            .tendon_sums::<false, false>(
                |c| self.eval_route(c, s, sec),
                sec,
                &pt,
                ld,
                &mut lr,
                &mut keep,
            )
            .pull
    }
}

/// Newton's start at the next point: the strains extrapolated from the last three points by
/// their interpolating parabola (fewer after [`Guess::forget`]).
struct Guess {
    pts: [(f64, Strains); 3],
    n: usize,
}

impl Guess {
    fn new(s: f64, z: Strains) -> Self {
        Guess {
            pts: [(s, z); 3],
            n: 1,
        }
    }
    fn forget(&mut self) {
        self.pts[0] = self.pts[self.n - 1];
        self.n = 1;
    }
    fn push(&mut self, s: f64, z: Strains) {
        if self.n == 3 {
            self.pts.rotate_left(1);
            self.pts[2] = (s, z);
        } else {
            self.pts[self.n] = (s, z);
            self.n += 1;
        }
    }
    fn at(&self, s: f64) -> Strains {
        // Lagrange weights of the points kept at `s`.
        let pts = &self.pts[..self.n];
        let mut out = Strains {
            v: Vector3::zeros(),
            u: Vector3::zeros(),
        };
        for (i, (si, zi)) in pts.iter().enumerate() {
            let mut w = 1.0;
            for (j, (sj, _)) in pts.iter().enumerate() {
                if j != i {
                    w *= (s - sj) / (si - sj);
                }
            }
            out.v += zi.v * w;
            out.u += zi.u * w;
        }
        out
    }
}

/// One fourth-order Magnus step of `g′ = g ξ̂` over `h` from the twists at the two Gauss
/// points (module docs): the step's displacement and rotation in the frame at its start.
fn magnus_step(h: f64, a: &Strains, b: &Strains) -> (Vector3<f64>, Matrix3<f64>) {
    let c = 3f64.sqrt() / 12.0 * h * h;
    let rho = (a.v + b.v) * (0.5 * h) + (a.u.cross(&b.v) - b.u.cross(&a.v)) * c;
    let phi = (a.u + b.u) * (0.5 * h) + a.u.cross(&b.u) * c;
    se3_exp(&rho, &phi)
}

/// The SE(3) exponential of the twist `(ρ, φ)`: `R = I + A φ̂ + B φ̂²`, `p = (I + B φ̂ + C φ̂²) ρ`
/// (Barfoot 2017 §7.1.5; `A, B, C` from [`abc`], series near zero).
fn se3_exp(rho: &Vector3<f64>, phi: &Vector3<f64>) -> (Vector3<f64>, Matrix3<f64>) {
    let (a, b, c) = abc(phi.norm_squared());
    let w = hat(phi);
    let w2 = w * w;
    let r = Matrix3::identity() + w * a + w2 * b;
    let p = rho + (w * rho) * b + (w2 * rho) * c;
    (p, r)
}

#[cfg(test)]
#[path = "unloaded_tests.rs"]
mod tests;
