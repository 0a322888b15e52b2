//! The rod's derivatives: the variational equations of [`Problem::rucker_webster`] (one
//! tangent per shooting unknown, integrated with the state in the same RK4 pass), their
//! continuation through the disks, and the exact Jacobian of the discrete shooting residual
//! they give (module docs, "Jacobian: variational equations").

use super::problem::{LoadCase, Problem};
use super::rhs::{CablePoints, Factors, Point, TendonSums};
use super::shooting::Setup;
use super::{put3, rot_of, v3, Buf, Cosserat, JacobianCheck, RodModel, State, E3, MAX_CABLES};
use crate::error::SolveError;
use crate::model::actuation::{Actuation, Drive, LengthMeasure};
use crate::model::robot::Robot;
use crate::numeric::ode::rk4;
use crate::numeric::so3::hat;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, Vector3, Vector6};

/// Residual, exact Jacobian, tip, and "no focal point found" of one variational pass.
type JacPass = (DVector<f64>, DMatrix<f64>, Vector3<f64>, bool);

/// Most tangent directions of the variational equations: 6 base-wrench unknowns plus one
/// tension per cable.
const MAXD: usize = 6 + MAX_CABLES;

/// Tangent directions of one right-hand-side evaluation (inputs `dy_in`, outputs `dy_out`,
/// `dlr` = `δ|ṗ_c|`); direction `d` also moves the tension of cable `tcab[d]`
/// (`usize::MAX`: none).
pub(super) struct Tangents {
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
pub(super) struct Var {
    pub(super) nd: usize,
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
    kt: [[State; 4]; MAXD],
    lt: [[Buf; 4]; MAXD],
    /// Track focal points at the disks (module docs, "Stability"; needs the 6 wrench columns).
    focal: bool,
    /// No focal point found so far.
    focal_ok: bool,
}

impl Var {
    /// Tangents for `nd` directions, all zero; the first 6 start from the base wrench.
    fn new(prob: &Problem, nd: usize) -> Box<Var> {
        let mut var = Box::new(Var {
            nd,
            tg: Tangents::new(),
            hole: [[Vector3::zeros(); MAX_CABLES]; MAXD],
            tcab: [usize::MAX; MAXD],
            y: [State::zeros(); MAXD],
            path: [[0.0; MAX_CABLES]; MAXD],
            chord: [[0.0; MAX_CABLES]; MAXD],
            resid: [Vector6::zeros(); MAXD],
            len: [[0.0; MAX_CABLES]; MAXD],
            kt: [[State::zeros(); 4]; MAXD],
            lt: [[[0.0; MAX_CABLES]; 4]; MAXD],
            focal: false,
            focal_ok: true,
        });
        var.tg.nd = nd;
        for i in 0..3 {
            var.y[i][12 + i] = match prob.set.model {
                RodModel::Full => 1.0 / prob.kse[i],
                RodModel::Kirchhoff => 1.0,
            };
            var.y[3 + i][15 + i] = prob.len_l / prob.kbt[i];
        }
        var
    }
}

/// The right-hand side at one point, as the tangents need it.
struct At<'a> {
    pt: Point,
    sums: TendonSums,
    fac: Factors,
    cp: &'a CablePoints,
    cz: &'a [Vector3<f64>; MAX_CABLES],
    lr: &'a Buf,
    /// Distributed external force `f` (base frame).
    f: Vector3<f64>,
}

impl Problem<'_> {
    /// `y'` and, for every tangent direction `δy_d` in `tan` (with its tension direction
    /// `δτ`), the directional derivative `(∂y'/∂y) δy_d + (∂y'/∂τ) δτ_d` of
    /// [`Problem::rucker_webster`] (the variational equations, written out analytically;
    /// `tan.dlr` receives `δ|ṗ_c|`).
    ///
    /// With `t = ṗ/|ṗ|`, `α = τ/|ṗ|`, `A_i = α (I − t tᵀ)`:
    /// `δA_i x = δα (x − t (t·x)) − α (δt (t·x) + t (δt·x))`, `δα = (δτ − α δ|ṗ|)/|ṗ|`,
    /// `δt = (δṗ − t δ|ṗ|)/|ṗ|`, `δṗ = δu × r + δv`, and
    /// `δ[v'; u'] = M⁻¹ (δ[d; c] − δM [v'; u'])` with the factors of `M` reused.
    #[inline]
    fn rucker_webster_tangents(
        &self,
        s: f64,
        y: &State,
        sec: usize,
        ld: &LoadCase,
        lr: &mut Buf,
        tan: &mut Tangents,
    ) -> State {
        let pt = self.point(y);
        let mut cp = CablePoints::new();
        let sums = self.tendon_sums::<true>(s, sec, &pt, ld, lr, &mut cp);
        let Some((dy, fac)) = self.strain_rates(&pt, &sums, ld) else {
            return State::from_element(f64::NAN);
        };
        // z_i = v' − r_i × u' (so that δA v' + δG u' = Σ δA_i z_i, δB v' + δH u' = Σ r_i × δA_i z_i).
        let mut cz = [Vector3::zeros(); MAX_CABLES];
        // Parallel per-cable arrays, indexed together.
        #[allow(clippy::needless_range_loop)]
        for c in 0..self.robot.cables.len() {
            if cp.on[c] {
                cz[c] = fac.dv - cp.r[c].cross(&fac.du);
            }
        }
        let at = At {
            pt,
            sums,
            fac,
            cp: &cp,
            cz: &cz,
            lr,
            f: self.f_dist * ld.lam,
        };
        let Tangents {
            nd,
            tcab,
            dy_in,
            dy_out,
            dlr,
        } = tan;
        for d in 0..*nd {
            self.tangent(&at, ld, &dy_in[d], tcab[d], &mut dy_out[d], &mut dlr[d]);
        }
        dy
    }

    /// One tangent direction `δy` (moving the tension of cable `tc`, if any) pushed through
    /// the right-hand side at `at`: `δy'` to `out`, `δ|ṗ|` to `dlr`.
    #[inline(always)]
    fn tangent(
        &self,
        at: &At,
        ld: &LoadCase,
        ty: &State,
        tc: usize,
        out: &mut State,
        dlr: &mut Buf,
    ) {
        let Point { r, w, u, v } = at.pt;
        let (cp, fac) = (at.cp, &at.fac);
        let full = self.set.model == RodModel::Full;
        let dr_m = Matrix3::from_column_slice(&ty.as_slice()[3..12]);
        let dw = v3(ty, 12);
        let duu = v3(ty, 15);
        let dvv = if full { dw } else { Vector3::zeros() };
        *dlr = [0.0; MAX_CABLES];
        let mut da = Vector3::zeros();
        let mut db = Vector3::zeros();
        let mut e1 = Vector3::zeros();
        let mut e2 = Vector3::zeros();
        #[allow(clippy::needless_range_loop)]
        for c in 0..self.robot.cables.len() {
            if !cp.on[c] {
                continue;
            }
            let dtau = if tc == c { 1.0 } else { 0.0 };
            let tt = cp.t[c];
            let nrm = at.lr[c];
            let dpd = duu.cross(&cp.r[c]) + dvv;
            let dn = tt.dot(&dpd);
            dlr[c] = dn;
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
            let dq = duu.cross(&cp.pd[c]) + u.cross(&dpd) + duu.cross(&cp.dr[c]);
            let dai = da_x(&cp.q[c]) + (dq - tt * tt.dot(&dq)) * al;
            da += dai;
            db += cp.r[c].cross(&dai);
            let az = da_x(&at.cz[c]);
            e1 += az;
            e2 += cp.r[c].cross(&az);
        }
        let mb = self.kbt.component_mul(&u);
        let dmb = self.kbt.component_mul(&duu);
        let gm = at.sums.gm;
        let drd = dr_m * hat(&u) + r * hat(&duu);
        out.as_mut_slice()[3..12].copy_from_slice(drd.as_slice());
        let nb = fac.nb;
        if full {
            let bm = gm.transpose();
            let dnb = self.kse.component_mul(&dvv);
            let dcc = -duu.cross(&mb) - u.cross(&dmb) - dvv.cross(&nb) - v.cross(&dnb) - db;
            let ddd = -duu.cross(&nb) - u.cross(&dnb) - dr_m.tr_mul(&at.f) - da;
            let r1 = ddd - e1;
            let r2 = dcc - e2;
            let k1r = fac.k1i * r1;
            let ddu = fac.si * (r2 - bm * k1r);
            let ddv = k1r - fac.k1g * ddu;
            put3(out, 0, &(dr_m * v + r * dvv));
            put3(out, 12, &ddv);
            put3(out, 15, &ddu);
        } else {
            let g_du = gm * fac.du;
            let dnb = dr_m.tr_mul(&w) + r.tr_mul(&dw);
            let dcc = -duu.cross(&mb) - u.cross(&dmb) - E3.cross(&dnb) - db;
            let ddu = fac.mi * (dcc - e2);
            let ddn = -dr_m * (at.sums.a + g_du) - r * (da + e1 + gm * ddu);
            put3(out, 0, &dr_m.column(2).into_owned());
            put3(out, 12, &ddn);
            put3(out, 15, &ddu);
        }
    }

    /// One RK4 step of the state and of its tangents (the exact derivative of the discrete
    /// RK4 map: each stage's tangent is the stage state's tangent pushed through `∂y'/∂y`).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn rk4_t(
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
        let mut ls = [[0.0; MAX_CABLES]; 4];
        *y += rk4::step(s, h, *y, |st, ss, ys| {
            for d in 0..nd {
                tg.dy_in[d] = rk4::stage(vy[d], &kt[d], st, h);
            }
            let k = self.rucker_webster_tangents(ss, ys, sec, ld, &mut ls[st], tg);
            for d in 0..nd {
                kt[d][st] = tg.dy_out[d];
                lt[d][st] = tg.dlr[d];
            }
            k
        });
        self.add_rk4_lengths(len, &ls, h);
        for d in 0..nd {
            vy[d] += rk4::increment(&kt[d], h);
            self.add_rk4_lengths(&mut vpath[d], &lt[d], h);
        }
    }

    /// Tangents at disk `k` (after integrating section `k`, before its jumps): chord lengths
    /// (`δ|h_k − h_{k−1}| = e·(δh_k − δh_{k−1})`, `δh = δp + δR r_k`) and, at the tip, the
    /// residual `[n(L⁺), m(L⁺)/L]` with the tie forces of the cables ending there,
    /// `F = −τ R t`, `δF = −δτ R t − τ (δR t + R δt)`.
    pub(super) fn disk_tangents(
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
        if vr.focal && vr.focal_ok {
            vr.focal_ok = self.no_focal_point(k, y, ld, vr);
        }
    }

    /// The focal-point test at one disk `s` (module docs, "Stability"): with the 6 Jacobi
    /// fields of the base wrench, `U = ∂(p, θ)(s)/∂(n₀, m₀)` (`θ`: spatial rotation,
    /// `δR Rᵀ = θ̂`) and `W = ∂(n, m)(s)/∂(n₀, m₀)` (after the tip's point loads at the tip),
    /// true when `W` is regular and the compliance `C = U W⁻¹` of the base part `[0, s]` to a
    /// wrench at `s` is positive definite (its symmetric part: `C` is symmetric up to the
    /// integration error, the fields spanning a Lagrangian plane).
    fn no_focal_point(&self, k: usize, y: &State, ld: &LoadCase, vr: &Var) -> bool {
        let tip = k == self.robot.sections();
        let r = rot_of(y);
        let w = v3(y, 12);
        let u = v3(y, 15);
        let v = match self.set.model {
            RodModel::Full => w,
            RodModel::Kirchhoff => E3,
        };
        let mut um = Matrix6::zeros();
        let mut wm = Matrix6::zeros();
        for d in 0..6 {
            let ty = vr.y[d];
            let dr_m = Matrix3::from_column_slice(&ty.as_slice()[3..12]);
            let om = dr_m * r.transpose();
            let dth = Vector3::new(
                om[(2, 1)] - om[(1, 2)],
                om[(0, 2)] - om[(2, 0)],
                om[(1, 0)] - om[(0, 1)],
            ) * 0.5;
            let (dn, dm) = if tip {
                let e = vr.resid[d];
                (
                    Vector3::new(e[0], e[1], e[2]),
                    Vector3::new(e[3], e[4], e[5]) * self.len_l,
                )
            } else {
                let dw = v3(&ty, 12);
                let dn = match self.set.model {
                    RodModel::Full => {
                        dr_m * self.kse.component_mul(&(w - E3)) + r * self.kse.component_mul(&dw)
                    }
                    RodModel::Kirchhoff => dw,
                };
                let du = v3(&ty, 15);
                let mut dm = dr_m * self.kbt.component_mul(&u) + r * self.kbt.component_mul(&du);
                // The cables passing `s` are cut with the rod: the momentum conjugate to
                // `(p, θ)` is the wrench of rod and cables, `n + Σ τ R t`,
                // `m + Σ τ (R r) × (R t)` (what the tip's tie forces add at `L`).
                let dv = match self.set.model {
                    RodModel::Full => dw,
                    RodModel::Kirchhoff => Vector3::zeros(),
                };
                let mut dn = dn;
                for (c, cable) in self.robot.cables.iter().enumerate() {
                    let tau = ld.tau[c];
                    if cable.ends_at <= k || tau == 0.0 {
                        continue;
                    }
                    let rp = self.eval_route(c, self.robot.disk_s[k], k);
                    let pd = u.cross(&rp.r) + rp.dr + v;
                    let nrm = pd.norm();
                    let t = pd / nrm;
                    let dpd = du.cross(&rp.r) + dv;
                    let dt = (dpd - t * t.dot(&dpd)) / nrm;
                    let f = r * t * tau;
                    let df = (dr_m * t + r * dt) * tau;
                    dn += df;
                    dm += (dr_m * rp.r).cross(&f) + (r * rp.r).cross(&df);
                }
                (dn, dm)
            };
            let col_u = [ty[0], ty[1], ty[2], dth.x, dth.y, dth.z];
            let col_w = [dn.x, dn.y, dn.z, dm.x, dm.y, dm.z];
            for i in 0..6 {
                um[(i, d)] = col_u[i];
                wm[(i, d)] = col_w[i];
            }
        }
        let Some(wi) = wm.try_inverse() else {
            return false;
        };
        // In units of length per force: `∂(p, L θ)/∂(n, m/L)`, then relative to its largest
        // entry; the inextensible rod's straight state has a zero eigenvalue (an axial force
        // moves nothing), so the test is "no eigenvalue below −1e-9".
        let mut c = um * wi;
        let l = self.len_l;
        for i in 0..3 {
            for j in 0..3 {
                c[(3 + i, j)] *= l;
                c[(i, 3 + j)] *= l;
                c[(3 + i, 3 + j)] *= l * l;
            }
        }
        let sym = (c + c.transpose()) * 0.5;
        let top = sym.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if !(top.is_finite() && top > 0.0) {
            return false;
        }
        let eig = nalgebra::SymmetricEigen::new(sym / top).eigenvalues;
        eig.iter().all(|&e| e >= -1e-9)
    }

    /// `Some(true)` when the converged `x` has no focal point along the rod with its tensions
    /// held (module docs, "Stability"), `Some(false)` when it has one and every tension is
    /// given (force control), `None` where the test cannot decide: no variational pass
    /// (adaptive steps, point loads at inner disks), or a focal point under displacement
    /// control (fixed cable lengths can still hold a shape that fixed tensions cannot). The
    /// same pass gives the exact shooting Jacobian at `x` (second item), which warm starts
    /// carry.
    pub(super) fn focal_stable(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
    ) -> (Option<bool>, Option<DMatrix<f64>>) {
        let Some((f, jac, _, ok)) = self.jac_pass(x, setup, 1.0, true) else {
            return (None, None);
        };
        if !f[0].is_finite() {
            return (None, None);
        }
        let stable = match (ok, setup.unknown.is_empty()) {
            (true, _) => Some(true),
            (false, true) => Some(false),
            (false, false) => None,
        };
        (stable, Some(jac))
    }

    /// Residual, exact Jacobian (variational equations integrated with the state in the same
    /// RK4 pass) and tip; `None` where [`Self::var_ok`] says no.
    ///
    /// Columns: `x = [n(0), m(0)/L, τ_unknown]`. The start tangents follow from
    /// `v(0) = e3 + Kse⁻¹ n(0)`, `u(0) = Kbt⁻¹ m(0)` (`R(0) = I`; Kirchhoff: the state is `n`).
    pub(super) fn residual_jac(
        &self,
        x: &DVector<f64>,
        setup: &Setup,
        lam: f64,
    ) -> Option<(DVector<f64>, DMatrix<f64>, Vector3<f64>)> {
        self.jac_pass(x, setup, lam, false)
            .map(|(f, j, tip, _)| (f, j, tip))
    }

    /// [`Self::residual_jac`], and with `focal` the focal-point test along the same pass
    /// (last item: no focal point found).
    fn jac_pass(&self, x: &DVector<f64>, setup: &Setup, lam: f64, focal: bool) -> Option<JacPass> {
        let tau = self.tensions(x, setup, lam);
        if !self.var_ok(setup, &tau, lam) {
            return None;
        }
        let k = x.len();
        let mut var = Var::new(self, k);
        var.focal = focal;
        for (j, &c) in setup.unknown.iter().enumerate() {
            var.tcab[6 + j] = c;
            var.tg.tcab[6 + j] = c;
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
            f[6 + j] = self.length_row(c, shot.len[c], x[6 + j], lam);
            for d in 0..k {
                jac[(6 + j, d)] = self.kl[c] * var.len[d][c];
            }
            jac[(6 + j, 6 + j)] -= self.kl[c] * self.compliance[c];
        }
        if f.iter().chain(jac.iter()).any(|v| !v.is_finite()) {
            f.fill(f64::NAN);
        }
        Some((f, jac, shot.tip, var.focal_ok))
    }
}

impl Cosserat {
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
        let (setup, x) = cold_start(&prob, robot, tension_guess);
        let Some((f, jv, _)) = prob.residual_jac(&x, &setup, 1.0) else {
            return Ok(None);
        };
        let jc = central_jacobian(&prob, &setup, &x, rel_step);
        Ok(Some((f, jv, jc)))
    }

    /// Diagnostic for tests: the start point `x` of [`Self::shooting_jacobians`] (every
    /// length-controlled cable taut at `tension_guess`, global-balance base wrench) and the
    /// central-difference Jacobian of the shooting residual there, for any robot (also where
    /// the variational one is not available, e.g. cables tied at inner disks).
    #[doc(hidden)]
    pub fn shooting_jacobian_fd(
        &self,
        robot: &Robot,
        act: &Actuation,
        tension_guess: f64,
        rel_step: f64,
    ) -> Result<(DVector<f64>, DMatrix<f64>), SolveError> {
        let (prob, _) = self.problem(robot, act)?;
        let (setup, x) = cold_start(&prob, robot, tension_guess);
        let jc = central_jacobian(&prob, &setup, &x, rel_step);
        Ok((x, jc))
    }
}

/// The cold start point of the test diagnostics: every length-controlled cable taut at
/// `tension_guess`, the base wrench from global balance.
fn cold_start(prob: &Problem<'_>, robot: &Robot, tension_guess: f64) -> (Setup, DVector<f64>) {
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
    (setup, x)
}

/// Central differences of the shooting residual at `x`, step `rel_step·max(|x_j|, fscale)`.
fn central_jacobian(
    prob: &Problem<'_>,
    setup: &Setup,
    x: &DVector<f64>,
    rel_step: f64,
) -> DMatrix<f64> {
    let mut jc = DMatrix::zeros(x.len(), x.len());
    for col in 0..x.len() {
        let h = rel_step * x[col].abs().max(prob.fscale);
        let mut xp = x.clone();
        xp[col] += h;
        let fp = prob.residual(&xp, setup, 1.0);
        xp[col] -= 2.0 * h;
        let fm = prob.residual(&xp, setup, 1.0);
        jc.set_column(col, &((fp - fm) / (2.0 * h)));
    }
    jc
}
