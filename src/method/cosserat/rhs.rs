//! The rod's right-hand side `y' = f(s, y)`: Rucker & Webster 2011 eq. 13–17 (full rod) and
//! its Kirchhoff limit, as in the module docs. [`Problem::rucker_webster`] is the whole model
//! in one short function; its two pieces, the tendon sums and the strain-rate solve, are
//! shared with the variational right-hand side (`variational.rs`), which differentiates them.

use super::problem::{LoadCase, Problem};
use super::{put3, rot_of, sym_inverse, v3, Buf, RodModel, State, E3, MAX_CABLES};
use crate::model::routing::RoutePoint;
use crate::numeric::so3::hat;
use nalgebra::{Matrix3, Vector3};

/// Tendon terms of the linear system at one point (R&W eq. 13–17):
/// `A = Σ A_i`, `G = −Σ A_i r̂_i`, `H = −Σ r̂_i A_i r̂_i`, `a = Σ A_i (û ṗ_i + û r_i' + r_i'')`,
/// `b = Σ r̂_i a_i` (and `B = Gᵀ`).
#[derive(Clone, Copy)]
pub(super) struct TendonSums {
    pub(super) am: Matrix3<f64>,
    pub(super) gm: Matrix3<f64>,
    pub(super) hm: Matrix3<f64>,
    pub(super) a: Vector3<f64>,
    pub(super) b: Vector3<f64>,
    /// `Σ τ_i t_i` (body frame): the tendons' pull, `−nb` of the unloaded rod (`unloaded.rs`).
    pub(super) pull: Vector3<f64>,
    /// `Σ τ_i r_i × t_i`: their moment, `−mb` of the unloaded rod.
    pub(super) twist: Vector3<f64>,
}

/// Per-cable quantities at one point that the tangents reuse: `r_i`, `r_i'`, the unit
/// tangent `t_i`, `q_i = û ṗ_i + û r_i' + r_i''`, `ṗ_i` (body frame), and whether the cable
/// runs here.
pub(super) struct CablePoints {
    pub(super) r: [Vector3<f64>; MAX_CABLES],
    pub(super) dr: [Vector3<f64>; MAX_CABLES],
    pub(super) t: [Vector3<f64>; MAX_CABLES],
    pub(super) q: [Vector3<f64>; MAX_CABLES],
    pub(super) pd: [Vector3<f64>; MAX_CABLES],
    pub(super) on: [bool; MAX_CABLES],
}

impl CablePoints {
    #[inline(always)]
    pub(super) fn new() -> Self {
        CablePoints {
            r: [Vector3::zeros(); MAX_CABLES],
            dr: [Vector3::zeros(); MAX_CABLES],
            t: [Vector3::zeros(); MAX_CABLES],
            q: [Vector3::zeros(); MAX_CABLES],
            pd: [Vector3::zeros(); MAX_CABLES],
            on: [false; MAX_CABLES],
        }
    }
}

/// The solution `(v', u')` and the factors of the linear system the tangents reuse:
/// full rod `K1⁻¹ = (Kse + A)⁻¹`, `K1⁻¹ G`, the Schur complement's inverse; Kirchhoff
/// `(Kbt + H)⁻¹`; and `nb = Rᵀ n` (body-frame internal force).
pub(super) struct Factors {
    pub(super) dv: Vector3<f64>,
    pub(super) du: Vector3<f64>,
    pub(super) nb: Vector3<f64>,
    pub(super) k1i: Matrix3<f64>,
    pub(super) k1g: Matrix3<f64>,
    pub(super) si: Matrix3<f64>,
    pub(super) mi: Matrix3<f64>,
}

/// A state unpacked: `R`, the strain slot `w` (full rod: `v`; Kirchhoff: `n`), `u`, and `v`.
#[derive(Clone, Copy)]
pub(super) struct Point {
    pub(super) r: Matrix3<f64>,
    pub(super) w: Vector3<f64>,
    pub(super) u: Vector3<f64>,
    pub(super) v: Vector3<f64>,
}

impl Problem<'_> {
    /// `y' = f(s, y)` in section `sec` (1-based), Rucker & Webster 2011: `p' = R v`,
    /// `R' = R û`, and `[v'; u']` from the linear system with the tendon sums; `lr[c]`
    /// receives `|ṗ_c|` (the path-length rate).
    #[inline]
    pub(super) fn rucker_webster(
        &self,
        s: f64,
        y: &State,
        sec: usize,
        ld: &LoadCase,
        lr: &mut Buf,
    ) -> State {
        let pt = self.point(y);
        let mut cables = CablePoints::new();
        let sums = self.tendon_sums::<false, true>(
            |c| self.eval_route(c, s, sec),
            sec,
            &pt,
            ld,
            lr,
            &mut cables,
        );
        match self.strain_rates(&pt, &sums, ld) {
            Some((dy, _)) => dy,
            None => State::from_element(f64::NAN),
        }
    }

    /// Unpack a state.
    #[inline(always)]
    pub(super) fn point(&self, y: &State) -> Point {
        let w = v3(y, 12);
        let v = match self.set.model {
            RodModel::Full => w,
            RodModel::Kirchhoff => E3,
        };
        Point {
            r: rot_of(y),
            w,
            u: v3(y, 15),
            v,
        }
    }

    /// The tendon sums at a point of section `sec` whose routes `route(c)` gives, written from vectors: with `t = ṗ/|ṗ|`,
    /// `α = τ/|ṗ|`, `A_i = α (I − t tᵀ)`, `A_i r̂ = α (r̂ − t wᵀ)`, `r̂ A_i r̂ = α (r̂² + w wᵀ)`,
    /// `w = t × r`. `lr[c]` receives `|ṗ_c|`; with `KEEP` the per-cable quantities go to
    /// `keep` for the tangents; without `RATES` the terms `a`, `b` that only the strain
    /// rates need are left zero (the balance of `unloaded.rs` and `loaded.rs` needs `A`, `G`,
    /// `H` and the pull alone).
    #[inline(always)]
    pub(super) fn tendon_sums<const KEEP: bool, const RATES: bool>(
        &self,
        route: impl Fn(usize) -> RoutePoint,
        sec: usize,
        pt: &Point,
        ld: &LoadCase,
        lr: &mut Buf,
        keep: &mut CablePoints,
    ) -> TendonSums {
        let (u, v) = (pt.u, pt.v);
        let mut sa = [0.0; 6];
        let mut sg = [0.0; 9];
        let mut sh = [0.0; 6];
        let mut a = Vector3::zeros();
        let mut b = Vector3::zeros();
        let mut pull = Vector3::zeros();
        let mut twist = Vector3::zeros();
        for (c, cable) in self.robot.cables.iter().enumerate() {
            if cable.ends_at < sec {
                continue;
            }
            let rp = route(c);
            let pd = u.cross(&rp.r) + rp.dr + v;
            let nrm = pd.norm();
            lr[c] = nrm;
            let inv = 1.0 / nrm;
            let tt = pd * inv;
            let q = match RATES {
                true => u.cross(&pd) + u.cross(&rp.dr) + rp.ddr,
                false => Vector3::zeros(),
            };
            if KEEP {
                keep.on[c] = true;
                keep.r[c] = rp.r;
                keep.dr[c] = rp.dr;
                keep.t[c] = tt;
                keep.q[c] = q;
                keep.pd[c] = pd;
            }
            let tau = ld.tau[c];
            if tau == 0.0 {
                continue;
            }
            let al = tau * inv;
            let ww = tt.cross(&rp.r);
            pull += pd * al;
            twist -= ww * tau;
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
            if RATES {
                let ai_vec = (q - tt * tt.dot(&q)) * al;
                a += ai_vec;
                b += rr.cross(&ai_vec);
            }
        }
        TendonSums {
            am: Matrix3::new(
                sa[0], sa[1], sa[2], sa[1], sa[3], sa[4], sa[2], sa[4], sa[5],
            ),
            gm: Matrix3::new(
                sg[0], sg[1], sg[2], sg[3], sg[4], sg[5], sg[6], sg[7], sg[8],
            ),
            hm: Matrix3::new(
                sh[0], sh[1], sh[2], sh[1], sh[3], sh[4], sh[2], sh[4], sh[5],
            ),
            a,
            b,
            pull,
            twist,
        }
    }

    /// Distributed external force `f = ρ A g` at load factor `lam`, and `Rᵀ f`.
    #[inline(always)]
    pub(super) fn body_force(&self, r: &Matrix3<f64>, lam: f64) -> (Vector3<f64>, Vector3<f64>) {
        let f = self.f_dist * lam;
        let fb = if lam == 0.0 || self.f_dist == Vector3::zeros() {
            Vector3::zeros()
        } else {
            r.tr_mul(&f)
        };
        (f, fb)
    }

    /// `y'` from the tendon sums: the full rod solves
    /// `[Kse + A, G; B, Kbt + H] [v'; u'] = [d; c]` by block elimination (Schur complement on
    /// the bending block: two 3×3 inverses instead of a 6×6 LU); Kirchhoff solves
    /// `(Kbt + H) u' = c` and `n' = −f − R (a + G u')`. `None` if a block is singular.
    #[inline(always)]
    pub(super) fn strain_rates(
        &self,
        pt: &Point,
        sums: &TendonSums,
        ld: &LoadCase,
    ) -> Option<(State, Factors)> {
        let Point { r, w, u, v } = *pt;
        let TendonSums {
            am, gm, hm, a, b, ..
        } = *sums;
        let bm = gm.transpose();
        let (f, fb) = self.body_force(&r, ld.lam);
        let mut dy = State::zeros();
        let mb = self.kbt.component_mul(&u);
        let rd = r * hat(&u);
        dy.as_mut_slice()[3..12].copy_from_slice(rd.as_slice());
        let kbt_h = Matrix3::from_diagonal(&self.kbt) + hm;
        let fac = if self.set.model == RodModel::Full {
            let nb = self.kse.component_mul(&(v - E3));
            let cc = -u.cross(&mb) - v.cross(&nb) - b;
            let dd = -u.cross(&nb) - fb - a;
            let k1 = Matrix3::from_diagonal(&self.kse) + am;
            let k1inv = sym_inverse(&k1)?;
            let k1g = k1inv * gm;
            let k1d = k1inv * dd;
            // Kbt + H − Gᵀ K1⁻¹ G is symmetric.
            let schur = kbt_h - bm * k1g;
            let sinv = sym_inverse(&schur)?;
            let du = sinv * (cc - bm * k1d);
            let dv = k1d - k1g * du;
            put3(&mut dy, 0, &(r * v));
            put3(&mut dy, 12, &dv);
            put3(&mut dy, 15, &du);
            Factors {
                dv,
                du,
                nb,
                k1i: k1inv,
                k1g,
                si: sinv,
                mi: Matrix3::zeros(),
            }
        } else {
            let nb = r.tr_mul(&w);
            let cc = -u.cross(&mb) - E3.cross(&nb) - b;
            let minv = kbt_h.try_inverse()?;
            let du = minv * cc;
            put3(&mut dy, 0, &r.column(2).into_owned());
            put3(&mut dy, 12, &(-f - r * (a + gm * du)));
            put3(&mut dy, 15, &du);
            Factors {
                dv: Vector3::zeros(),
                du,
                nb,
                k1i: Matrix3::zeros(),
                k1g: Matrix3::zeros(),
                si: Matrix3::zeros(),
                mi: minv,
            }
        };
        Some((dy, fac))
    }
}
