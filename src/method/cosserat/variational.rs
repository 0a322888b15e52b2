//! The rod's derivatives: the variational equations of [`Problem::rucker_webster`] (one
//! tangent per shooting unknown, integrated with the state in the same RK4 pass) and their
//! continuation through the disks (module docs, "Jacobian: variational equations"). The
//! pass that assembles the exact Jacobian of the discrete shooting residual from them, and
//! the focal-point stability test along it, live in `jacobian.rs`.

use super::problem::{LoadCase, Problem};
use super::rhs::{CablePoints, Factors, Point, TendonSums};
use super::{put3, rot_of, v3, Buf, RodModel, State, E3, MAX_CABLES};
use crate::model::actuation::LengthMeasure;
use crate::numeric::ode::rk4;
use crate::numeric::so3::hat;
use nalgebra::{Matrix3, Vector3, Vector6};

/// Most tangent directions of the variational equations: 6 base-wrench unknowns plus one
/// tension per cable.
const MAXD: usize = 6 + MAX_CABLES;

/// Tangent directions of one right-hand-side evaluation (inputs `dy_in`, outputs `dy_out`,
/// `dlr` = `δ|ṗ_c|`); direction `d` also moves the tension of cable `tcab[d]`
/// (`usize::MAX`: none).
pub(super) struct Tangents {
    nd: usize,
    pub(super) tcab: [usize; MAXD],
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
    pub(super) tg: Tangents,
    /// `δ` of each cable's hole at the last disk passed.
    hole: [[Vector3<f64>; MAX_CABLES]; MAXD],
    pub(super) tcab: [usize; MAXD],
    pub(super) y: [State; MAXD],
    path: [Buf; MAXD],
    chord: [Buf; MAXD],
    pub(super) resid: [Vector6<f64>; MAXD],
    pub(super) len: [Buf; MAXD],
    /// RK4 stage scratch (tangents of the stage slopes and of `|ṗ_c|`).
    kt: [[State; 4]; MAXD],
    lt: [[Buf; 4]; MAXD],
    /// Track focal points at the disks (module docs, "Stability"; needs the 6 wrench columns).
    pub(super) focal: bool,
    /// No focal point found so far.
    pub(super) focal_ok: bool,
}

impl Var {
    /// Tangents for `nd` directions, all zero; the first 6 start from the base wrench.
    pub(super) fn new(prob: &Problem, nd: usize) -> Box<Var> {
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
        let sums = self.tendon_sums::<true, true>(
            |c| self.eval_route(c, s, sec),
            sec,
            &pt,
            ld,
            lr,
            &mut cp,
        );
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
}
