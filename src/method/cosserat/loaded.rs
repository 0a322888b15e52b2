//! The loaded rod shot on its external wrench (module docs, "Loaded rod: shooting on the
//! external wrench"): the strains from the balance at each point, as on the unloaded path,
//! with the external loads beyond the point added to it.
//!
//! # The balance with external loads
//!
//! Cut the robot at `s` through the backbone and the tendons running there (`unloaded.rs`):
//! the part beyond the cut is held by the backbone's internal wrench and the cut tendons'
//! pull, and loaded by the external loads beyond `s` — the tip wrench, the weights of the
//! disks beyond `s` and the distributed weight of the rod beyond `s`. Their resultant at
//! `p(s)` (base frame), `N(s)` and `M(s)`, is the only thing the strains at `s` still need:
//!
//! ```text
//! F(v, u) = [Kse (v − e3) + Σ τ_i t_i ;  Kbt u + Σ τ_i r_i × t_i] = [Rᵀ N ; Rᵀ M]
//! N(s) = F_tip + Σ_{s_k > s} w_k + f (L − s),     M′ = −p′ × N,     M(L) = M_tip
//! ```
//!
//! — the gradient of the same strictly convex `Φ` as unloaded, minus a linear term, so the
//! strains at `s` are unique and Newton from the neighbouring point finds them. `N(s)` is
//! known in closed form (dead loads), so the unknowns of the shooting are the three
//! components of `M(0)`, the external moment about the base, against the three of `M(L⁻) =
//! M_tip`: half of shooting on the base wrench, and the strains are never integrated, so
//! their error does not pile up along the rod (where a route bends sharply, Rucker–Webster's
//! `v′, u′` carry most of the error of shooting on them). Cables tied at inner disks need
//! nothing (their tie and kink forces are internal to the cut part: the strains jump by the
//! balance), disk weights jump `N`.
//!
//! The state `(p, R, M)` is stepped by the classical RK4 at the disks' step counts; the path
//! lengths are its quadrature of `|ṗ_i|`. The Jacobian of `M(L)` in `M(0)` comes from the
//! tangents in the same pass: `δz = K⁻¹ [δRᵀ N + Rᵀ δN; δRᵀ M + Rᵀ δM]` with the balance's
//! Hessian `K` factored at the point, `δp′ = δR v + R δv`, `δR′ = δR û + R δû`,
//! `δM′ = −δp′ × N − p′ × δN`. With the three more tangents of `N(0)` they are the rod's
//! six Jacobi fields: the momentum conjugate to `(p, θ)` is `(N, M)` itself, so the
//! focal-point test (`jacobian.rs`) reads `U = ∂(p, θ)/∂(N₀, M₀)` and `W = ∂(N, M)/∂(N₀, M₀)`
//! at each disk from one pass.

use super::problem::{LoadCase, Problem, Shot, Trace};
use super::shooting::{Fail, Newton, Setup};
use super::unloaded::{At, Strains};
use super::{RodModel, E3, MAX_CABLES};
use crate::model::actuation::LengthMeasure;
use crate::numeric::ode::rk4;
use crate::numeric::so3::{mul_hat, vee_skew};
use nalgebra::{DVector, Matrix3, Matrix6, SMatrix, Vector3, Vector6};

/// The pass's state in column 0, `[p, R (column-major), M]`, and `C − 1` tangents in the
/// columns after it (none; three: directions of `M(0)/L`; six: then of `N(0)` for the
/// focal-point test).
type Cols<const C: usize> = SMatrix<f64, 15, C>;

/// Halvings of a Newton step before the loaded solve gives up (and the rod shoots).
const MAX_HALVINGS: usize = 12;

/// Magnus steps per section of the cold start's unloaded pass ([`Problem::unloaded_moment`]).
const START_STEPS: usize = 1;

/// One loaded pass: the shot (`resid = [N(L⁺), (M(L⁺))/L]` after the tip loads: zero force
/// by construction), the rod's base wrench, the Jacobian of the moment rows in `M(0)/L`, the
/// largest strain-balance residual, and whether the focal-point test found no focal point.
pub(super) struct Loaded {
    pub(super) shot: Shot,
    pub(super) n0: Vector3<f64>,
    /// `m(0)/L`, as the solution vector holds it (the trace's key is `m(0)` read back from it).
    pub(super) ms: Vector3<f64>,
    pub(super) jac: Matrix3<f64>,
    pub(super) residual: f64,
    pub(super) no_focal: bool,
    /// Whether the pass carried the six Jacobi fields (else `no_focal` says nothing).
    pub(super) checked: bool,
    /// With Newton's tangents, the strains at each of the pass's points in order and their
    /// derivatives in `M(0)/L` ([`Track`]); else empty.
    pub(super) track: Vec<Track>,
}

/// The strains a tangent pass met at one point and their derivatives in the three
/// components of `M(0)/L`: the next pass starts the strain Newton there from their
/// first-order prediction `z + Σ_d ∂z/∂x_d Δx_d` (a step `Δx` of `O(r)` leaves `O(r²)`, below
/// the tolerance near the answer: one balance evaluation at most points instead of two).
#[derive(Clone, Copy)]
pub(super) struct Track {
    z: Strains,
    dz: [Strains; 3],
}

impl Track {
    /// The strains predicted after a step `dx` in `M(0)/L`.
    fn predict(&self, dx: &Vector3<f64>) -> Strains {
        let mut z = self.z;
        for (d, dz) in self.dz.iter().enumerate() {
            z.v += dz.v * dx[d];
            z.u += dz.u * dx[d];
        }
        z
    }
}

impl Problem<'_> {
    /// True when a loaded rod takes this path: the `solver` setting allows it, fixed steps,
    /// an external load (else the unloaded path), every cable pulled with a given tension or
    /// free (displacement control shoots), no obstacles (checked by the caller).
    pub(super) fn loaded_applies(&self) -> bool {
        use crate::model::actuation::Drive;
        self.set.unloaded
            && self.set.adaptive.is_none()
            && !self.fast
            && self
                .modes
                .iter()
                .all(|m| matches!(m, Drive::Tension(_) | Drive::Free))
    }

    /// The external force beyond the point `s` of section `sec` (base frame): the tip force,
    /// the weights of disks `sec..=n` and the rod's weight beyond `s`, at load factor `lam`.
    fn outer_force(&self, s: f64, sec: usize, lam: f64) -> Vector3<f64> {
        let n = self.robot.sections();
        let disks = (n + 1 - sec) as f64;
        (self.tip_f + self.disk_weight * disks + self.f_dist * (self.len_l - s)) * lam
    }

    /// The external wrench at the base `(N(0), M(0))` of the rod's base wrench `(n0, m0)`:
    /// `N(0) = n0 + Σ τ t_i`, `M(0) = m0 + Σ τ r_i × t_i` with the strains `n0`, `m0` give.
    fn outer_of_rod(
        &self,
        n0: &Vector3<f64>,
        m0: &Vector3<f64>,
        ld: &LoadCase,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let v = match self.set.model {
            RodModel::Full => E3 + n0.component_div(&self.kse),
            RodModel::Kirchhoff => E3,
        };
        let u = m0.component_div(&self.kbt);
        let (mut pull, mut twist) = (Vector3::zeros(), Vector3::zeros());
        for (c, cable) in self.robot.cables.iter().enumerate() {
            let tau = ld.tau[c];
            if cable.ends_at < 1 || tau == 0.0 {
                continue;
            }
            let rp = self.eval_route(c, 0.0, 1);
            let t = (u.cross(&rp.r) + rp.dr + v).normalize();
            pull += t * tau;
            twist += rp.r.cross(&t) * tau;
        }
        (n0 + pull, m0 + twist)
    }

    /// One pass from the rod's base wrench (the shooting unknowns' form): its external
    /// wrench at the base, then [`Self::loaded_pass`].
    pub(super) fn loaded_shot(
        &self,
        n0: &Vector3<f64>,
        m0: &Vector3<f64>,
        ld: &LoadCase,
        trace: Option<&mut Trace>,
    ) -> Shot {
        let (_, mo) = self.outer_of_rod(n0, m0, ld);
        match self.loaded_pass::<1>(&mo, ld, trace, None) {
            Some(l) => l.shot,
            None => Shot::failed(),
        }
    }

    /// The loaded pass from the external moment `m_out` about the base (module docs) with
    /// `C − 1` tangents ([`Cols`]: 0; 3, the Jacobian in `M(0)/L`; 6, also the focal-point
    /// test). `None` if the strains cannot be found at some point. `pred`: a previous
    /// tangent pass's [`Track`] and the step in `M(0)/L` since, the strain guesses.
    pub(super) fn loaded_pass<const C: usize>(
        &self,
        m_out: &Vector3<f64>,
        ld: &LoadCase,
        trace: Option<&mut Trace>,
        pred: Option<(&[Track], Vector3<f64>)>,
    ) -> Option<Loaded> {
        let nd = C - 1;
        let robot = self.robot;
        let nc = robot.cables.len();
        let l = self.len_l;
        let lam = ld.lam;
        let mut at = At::new([false; MAX_CABLES]);
        at.quadratic = true;
        let n_base = self.outer_force(0.0, 1, lam);
        let straight = Strains {
            v: E3,
            u: Vector3::zeros(),
        };
        let zb = (&n_base, m_out);
        // The strain guess at the pass's point `i`: predicted from `pred`, or `neighbour`.
        let predicted = |i: usize, neighbour: Strains| match pred {
            Some((t, dx)) if t.len() > i => t[i].predict(&dx),
            _ => neighbour,
        };
        let (z0, mut residual) =
            self.strains_at(0.0, 1, ld, predicted(0, straight), zb, &mut at)?;
        let mut track = Vec::new();
        if nd >= 3 {
            track.reserve(1 + 4 * self.nsteps[1..].iter().sum::<usize>());
            let mut dz = [z0; 3];
            for (d, dzd) in dz.iter_mut().enumerate() {
                let (dv, du) = at.stiffness.solve(&Vector3::zeros(), &(Vector3::ith(d, l)));
                *dzd = Strains { v: dv, u: du };
            }
            track.push(Track { z: z0, dz });
        }
        // The rod's base wrench (Kirchhoff: the force is what the tendons leave of `N(0)`).
        let n0 = match self.set.model {
            RodModel::Full => self.kse.component_mul(&(z0.v - E3)),
            RodModel::Kirchhoff => n_base - at.pull,
        };
        let ms = self.kbt.component_mul(&z0.u) / l;
        let m0 = ms * l;
        let mut last = self.last.borrow_mut();
        let rec: &mut Trace = match trace {
            Some(t) => t,
            None => &mut last,
        };
        rec.start(&n0, &m0, ld);
        rec.disks.push((Vector3::zeros(), Matrix3::identity()));
        rec.backbone.push(Vector3::zeros());
        let mut y = Cols::<C>::zeros();
        for i in 0..3 {
            y[(3 + 4 * i, 0)] = 1.0;
            y[(12 + i, 0)] = m_out[i];
            if nd >= 3 {
                y[(12 + i, 1 + i)] = l;
            }
        }
        let (mut path, mut chord) = ([0.0; MAX_CABLES], [0.0; MAX_CABLES]);
        // The rest lengths beside, from each point's `|e3 + r_i′|` by the same quadrature: what
        // a pass at zero load gives bit for bit (its strains are the straight rod's there).
        let mut path0 = [0.0; MAX_CABLES];
        let mut prev = [Vector3::zeros(); MAX_CABLES];
        for (c, cable) in robot.cables.iter().enumerate() {
            prev[c] = cable.hole(0);
        }
        let mut no_focal = true;
        let mut guess = z0;
        let mut point = 0;
        for k in 1..=robot.sections() {
            let (s0, s1) = (robot.disk_s[k - 1], robot.disk_s[k]);
            let steps = self.nsteps[k];
            let h = (s1 - s0) / steps as f64;
            for j in 0..steps {
                let s = s0 + j as f64 * h;
                let mut lr = [[0.0; MAX_CABLES]; 4];
                let mut lr0 = lr;
                let mut fail = false;
                y += rk4::step(s, h, y, |i, si, yi| {
                    let n = self.outer_force(si, k, lam);
                    let start = predicted(1 + i + 4 * point, guess);
                    match self.loaded_slope(si, k, ld, yi, &n, (start, &mut guess), &mut at) {
                        Some((dy, res, dz)) => {
                            residual = residual.max(res);
                            lr[i] = at.lr;
                            lr0[i] = at.rest;
                            if nd >= 3 {
                                track.push(Track { z: guess, dz });
                            }
                            dy
                        }
                        None => {
                            fail = true;
                            Cols::<C>::from_element(f64::NAN)
                        }
                    }
                });
                if fail {
                    return None;
                }
                point += 1;
                self.add_rk4_lengths(&mut path, &lr, h);
                self.add_rk4_lengths(&mut path0, &lr0, h);
                rec.backbone
                    .push(Vector3::new(y[(0, 0)], y[(1, 0)], y[(2, 0)]));
            }
            let p = Vector3::new(y[(0, 0)], y[(1, 0)], y[(2, 0)]);
            let r = Matrix3::from_fn(|i, j| y[(3 + 3 * j + i, 0)]);
            rec.disks.push((p, r));
            self.advance_chords(k, &p, &r, &mut chord, &mut prev);
            if nd == 6 && no_focal {
                no_focal = self.loaded_no_focal(&y, &r);
            }
        }
        let len = match self.set.length {
            LengthMeasure::Path => path,
            LengthMeasure::Chord => chord,
        };
        rec.len.extend_from_slice(&len[..nc]);
        // (Chords: the rest lengths take the pass at zero load, `solve.rs`.)
        if self.set.length == LengthMeasure::Path {
            rec.rest.extend_from_slice(&path0[..nc]);
        }
        // After the tip: the force left is `N(L⁻) − w − F_tip = 0` by construction.
        let mm = (Vector3::new(y[(12, 0)], y[(13, 0)], y[(14, 0)]) - self.tip_m * lam) / l;
        let mut jac = Matrix3::zeros();
        for d in 0..nd.min(3) {
            for i in 0..3 {
                jac[(i, d)] = y[(12 + i, 1 + d)] / l;
            }
        }
        let tip = Vector3::new(y[(0, 0)], y[(1, 0)], y[(2, 0)]);
        Some(Loaded {
            shot: Shot {
                resid: Vector6::new(0.0, 0.0, 0.0, mm.x, mm.y, mm.z),
                len,
                tip,
                touch: Vec::new(),
            },
            n0,
            ms,
            jac,
            residual,
            no_focal,
            checked: nd == 6,
            track,
        })
    }

    /// The slope of the pass's state and of its tangents at `(s, y)` in section `sec`
    /// (module docs), the strains from `start` (else, should they not settle from there,
    /// from the neighbour's `guess`; `guess` receives them), `at` receiving `|ṗ_i|`; the
    /// strain balance's residual and the first three tangents' strains (zero without them).
    /// `n`: the external force beyond `s`.
    #[allow(clippy::too_many_arguments)]
    fn loaded_slope<const C: usize>(
        &self,
        s: f64,
        sec: usize,
        ld: &LoadCase,
        y: &Cols<C>,
        n: &Vector3<f64>,
        (start, guess): (Strains, &mut Strains),
        at: &mut At,
    ) -> Option<(Cols<C>, f64, [Strains; 3])> {
        let nd = C - 1;
        let r = Matrix3::from_fn(|i, j| y[(3 + 3 * j + i, 0)]);
        let m = Vector3::new(y[(12, 0)], y[(13, 0)], y[(14, 0)]);
        let (bv, bu) = (r.tr_mul(n), r.tr_mul(&m));
        let (z, res) = match self.strains_at(s, sec, ld, start, (&bv, &bu), at) {
            Some(found) => found,
            None => self.strains_at(s, sec, ld, *guess, (&bv, &bu), at)?,
        };
        *guess = z;
        let mut dzs = [Strains {
            v: Vector3::zeros(),
            u: Vector3::zeros(),
        }; 3];
        let full = self.set.model == RodModel::Full;
        let v = if full { z.v } else { E3 };
        let mut dy = Cols::<C>::zeros();
        let pd = r * v;
        let rd = mul_hat(&r, &z.u);
        let md = -pd.cross(n);
        for i in 0..3 {
            dy[(i, 0)] = pd[i];
            dy[(12 + i, 0)] = md[i];
        }
        for (i, x) in rd.iter().enumerate() {
            dy[(3 + i, 0)] = *x;
        }
        for d in 0..nd {
            let dp_r = Matrix3::from_fn(|i, j| y[(3 + 3 * j + i, 1 + d)]);
            let dm = Vector3::new(y[(12, 1 + d)], y[(13, 1 + d)], y[(14, 1 + d)]);
            // Directions 3..6 move `N(0)`, hence `N` along the rod, by a unit vector `e_k`
            // (`Rᵀ e_k` is `R`'s row `k`; the other directions skip the products with zero).
            let mut dbv = dp_r.tr_mul(n);
            let dbu = dp_r.tr_mul(&m) + r.tr_mul(&dm);
            if d >= 3 {
                dbv += r.row(d - 3).transpose();
            }
            let (dv, du) = at.stiffness.solve(&dbv, &dbu);
            let dv = if full { dv } else { Vector3::zeros() };
            if d < 3 {
                dzs[d] = Strains { v: dv, u: du };
            }
            let dpd = dp_r * v + r * dv;
            let drd = mul_hat(&dp_r, &z.u) + mul_hat(&r, &du);
            let mut dmd = -dpd.cross(n);
            if d >= 3 {
                dmd -= pd.cross(&Vector3::ith(d - 3, 1.0));
            }
            for i in 0..3 {
                dy[(i, 1 + d)] = dpd[i];
                dy[(12 + i, 1 + d)] = dmd[i];
            }
            for (i, x) in drd.iter().enumerate() {
                dy[(3 + i, 1 + d)] = *x;
            }
        }
        Some((dy, res, dzs))
    }

    /// The focal-point test at a disk from the six tangents of the loaded pass (module
    /// docs): `U = ∂(p, θ)`, `W = ∂(N, M)` in the directions `(N₀, M₀/L)`.
    fn loaded_no_focal<const C: usize>(&self, y: &Cols<C>, r: &Matrix3<f64>) -> bool {
        let mut um = Matrix6::zeros();
        let mut wm = Matrix6::zeros();
        // Columns in the order (N₀, M₀): tangents 4..=6, then 1..=3 (those are of `M₀/L`).
        for (col, t, scale) in [
            (0, 4, 1.0),
            (1, 5, 1.0),
            (2, 6, 1.0),
            (3, 1, 1.0 / self.len_l),
            (4, 2, 1.0 / self.len_l),
            (5, 3, 1.0 / self.len_l),
        ] {
            let dr_m = Matrix3::from_fn(|i, j| y[(3 + 3 * j + i, t)]);
            let om = dr_m * r.transpose();
            let dth = vee_skew(&om) * 0.5;
            let mut dn = Vector3::zeros();
            if col < 3 {
                dn[col] = 1.0;
            }
            for i in 0..3 {
                um[(i, col)] = y[(i, t)] * scale;
                um[(3 + i, col)] = dth[i] * scale;
                wm[(i, col)] = dn[i];
                wm[(3 + i, col)] = y[(12 + i, t)] * scale;
            }
        }
        self.compliance_psd(&um, &wm)
    }

    /// The loaded solve (force control): Newton on `M(0)/L`, each iteration one pass with its
    /// exact Jacobian, a halving line search; the rod's base wrench `x = [n(0), m(0)/L]` of
    /// the last pass. A cold start (`cold`) takes `M(0)` from the loads on the unloaded rod
    /// (one unloaded pass, `unloaded.rs`), else from the start `x0`'s base wrench. With
    /// `focal` every pass carries the six Jacobi fields, so the last one also decides the
    /// stability ([`Problem::loaded_focal`]). A note says which path was taken.
    pub(super) fn solve_loaded(
        &self,
        x0: &DVector<f64>,
        setup: &Setup,
        (cold, focal): (bool, bool),
        notes: &mut Vec<String>,
    ) -> Result<(Newton, usize), Fail> {
        let ld = self.load_case(x0, setup, 1.0);
        let n0 = Vector3::new(x0[0], x0[1], x0[2]);
        let m0 = Vector3::new(x0[3], x0[4], x0[5]) * self.len_l;
        let (_, mut mo) = self.outer_of_rod(&n0, &m0, &ld);
        if cold {
            if let Some(m) = self.unloaded_moment(&ld) {
                mo = m;
            }
        }
        // A cold start's first pass is never the answer's: it carries only Newton's tangents.
        let (pass, iterations) = self.newton_loaded(mo, &ld, (focal, focal && !cold))?;
        self.loaded_focal.set(focal.then_some(pass.no_focal));
        let steps: usize = self.nsteps[1..].iter().sum();
        notes.push(format!(
            "loaded: strains from the balance with the external loads, {steps} RK4 steps, \
             {iterations} Newton iterations on the base moment"
        ));
        let mut x = x0.clone();
        for i in 0..3 {
            x[i] = pass.n0[i];
            x[3 + i] = pass.ms[i];
        }
        let residual = pass.shot.resid.amax().max(pass.residual);
        Ok((
            Newton {
                x,
                iterations,
                residual,
                jac: None,
            },
            0,
        ))
    }

    /// A pass with Newton's three tangents, and with `focal` also the three more of the
    /// focal-point test ([`Cols`]); strain guesses from `pred` ([`Self::loaded_pass`]).
    fn tangent_pass(
        &self,
        mo: &Vector3<f64>,
        ld: &LoadCase,
        focal: bool,
        pred: Option<(&[Track], Vector3<f64>)>,
    ) -> Option<Loaded> {
        match focal {
            true => self.loaded_pass::<7>(mo, ld, None, pred),
            false => self.loaded_pass::<4>(mo, ld, None, pred),
        }
    }

    /// Newton on `M(0)/L` from `mo`: the last pass and the iterations. With `focal` the
    /// passes carry the focal-point test's Jacobi fields and the pass returned has its
    /// verdict, at the answer or one Newton step from it; with `first` also the first pass
    /// (else it carries Newton's tangents alone, and should it already be the answer, one
    /// more pass there decides).
    fn newton_loaded(
        &self,
        mut mo: Vector3<f64>,
        ld: &LoadCase,
        (focal, first): (bool, bool),
    ) -> Result<(Loaded, usize), Fail> {
        let fail = |iterations, residual, detail: &str| Fail {
            iterations,
            residual,
            detail: detail.into(),
        };
        let unsettled = "the strains of the loaded rod did not settle at some point";
        let mut pass = self
            .tangent_pass(&mo, ld, first, None)
            .ok_or_else(|| fail(0, f64::NAN, unsettled))?;
        let norm = |p: &Loaded| p.shot.resid.amax();
        let mut iterations = 0;
        let mut last = f64::INFINITY;
        // (A NaN residual is not converged.)
        while norm(&pass).is_nan() || norm(&pass) > self.set.tolerance {
            if iterations == self.set.max_iterations || self.over_budget() {
                let detail = "Newton on the loaded rod's base moment did not converge";
                return Err(fail(iterations, norm(&pass), detail));
            }
            iterations += 1;
            let f = Vector3::new(pass.shot.resid[3], pass.shot.resid[4], pass.shot.resid[5]);
            let Some(step) = pass.jac.lu().solve(&-f) else {
                let detail = "singular Jacobian of the loaded rod's base moment";
                return Err(fail(iterations, norm(&pass), detail));
            };
            // Where Newton's quadratic convergence, `r_next ≈ r (r / r_prev)²`, predicts that
            // the full step meets the tolerance, its pass carries no tangents: the answer
            // needs none (its stability verdict is this iterate's, one step away).
            let r = norm(&pass);
            if last.is_finite() && r * (r / last).powi(2) <= 0.1 * self.set.tolerance {
                let mt = mo + step * self.len_l;
                let pred = Some((&pass.track[..], step));
                if let Some(mut pt) = self.loaded_pass::<1>(&mt, ld, None, pred) {
                    if norm(&pt) <= self.set.tolerance && pass.checked == focal {
                        (pt.no_focal, pt.checked) = (pass.no_focal, pass.checked);
                        return Ok((pt, iterations));
                    }
                }
            }
            last = r;
            let mut alpha = 1.0;
            let mut halvings = 0;
            loop {
                let mt = mo + step * (alpha * self.len_l);
                let pred = Some((&pass.track[..], step * alpha));
                match self.tangent_pass(&mt, ld, focal, pred) {
                    Some(pt) if norm(&pt) < norm(&pass) => {
                        (mo, pass) = (mt, pt);
                        break;
                    }
                    _ if halvings == MAX_HALVINGS => {
                        let detail = "line search failed on the loaded rod's base moment";
                        return Err(fail(iterations, norm(&pass), detail));
                    }
                    _ => {
                        alpha *= 0.5;
                        halvings += 1;
                    }
                }
            }
        }
        if focal && !pass.checked {
            pass = self
                .tangent_pass(&mo, ld, true, Some((&pass.track[..], Vector3::zeros())))
                .ok_or_else(|| fail(iterations, f64::NAN, unsettled))?;
        }
        Ok((pass, iterations))
    }

    /// The external moment about the base of the loads on the unloaded rod (its shape under
    /// the tensions of `ld` alone, one unloaded pass of one Magnus step per section: a start
    /// needs no more, its error is far below the loads' own share of the first residual): the
    /// start of a cold loaded solve. `M_tip + p_L × F_tip + Σ p_k × w + ∫ p × f ds` (the
    /// trapezoid rule over the pass's steps); `None` if that pass fails.
    fn unloaded_moment(&self, ld: &LoadCase) -> Option<Vector3<f64>> {
        let mut probe = Trace::default();
        let steps = vec![START_STEPS; self.nsteps.len()];
        self.unloaded_pass_steps(ld, Some(&mut probe), None, &steps)?;
        let robot = self.robot;
        let lam = ld.lam;
        let tip = probe.disks.last()?.0;
        let mut m = (self.tip_m + tip.cross(&self.tip_f)) * lam;
        for (p, _) in probe.disks.iter().skip(1) {
            m += p.cross(&self.disk_weight) * lam;
        }
        let mut at = 0;
        for k in 1..=robot.sections() {
            let h = (robot.disk_s[k] - robot.disk_s[k - 1]) / START_STEPS as f64;
            for _ in 0..START_STEPS {
                let (a, b) = (probe.backbone.get(at)?, probe.backbone.get(at + 1)?);
                m += ((a + b) * (0.5 * h)).cross(&self.f_dist) * lam;
                at += 1;
            }
        }
        Some(m)
    }
}
