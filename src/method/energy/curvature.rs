//! Curvature of forces on the chain of sub-arcs, written once for the dead loads and the
//! contacts: the Hessian of `−Σ F · x` for point forces `F` at points `x` carried by the
//! frames (with `F` fixed), plus symmetric low-rank terms `Σ_pq M_pq w_p w_qᵀ`, assembled as a
//! block semiseparable matrix ([`SemiSep`]) that factors in `O(n r²)`.
//!
//! # Point forces
//!
//! Raising strain `a` of sub-arc `j` moves everything beyond it rigidly with the spatial twist
//! `T_{j,a} = (ω, t)` (`ω = M_j e_a`, `t = −N_{j,a}` for a rotation, `ω = 0`, `t = M_j e_z`
//! for the stretch; `energy/contacts.rs`), a point `x` with `v = ω × x + t`. A downstream
//! twist is carried along by an upstream one, so for `k < j` (both upstream of `x`)
//! `∂²x/∂ξ_k∂ξ_j = ω_k × v_j(x)` and
//!
//! ```text
//! ∂²(−F·x)/∂ξ_k∂ξ_j = T_kᵀ P T_j,   P = [ (x·F) I − x Fᵀ   F̂ ]
//!                                       [       0          0 ]
//! ```
//!
//! linear in `F` and `x Fᵀ`: summed over the forces beyond `j` it needs only the suffix sums
//! `S_j = Σ F`, `D_j = Σ x Fᵀ`, `P_j = [tr(D_j) I − D_j, Ŝ_j; 0, 0]`. That is the generator form
//! `A_jk = V_jᵀ U_k` with `V_j = P_j T_j`, `U_k = T_k` (rank 6). Within one sub-arc,
//! `x = p_j + R_j (R_l y + p_l)` with `y` fixed, so the 4×4 block is
//! `−∇²[Σ_b W_{:,b}·(R_l e_b) + g·p_l]`, `W = R_jᵀ (D_jᵀ − S_j p_{j+1}ᵀ) R_{j+1}`,
//! `g = R_jᵀ S_j`, by second-order AD ([`D2`]) of the sub-arc exponential.
//!
//! A dead load is such a force at a frame origin; a contact with multiplier `μ` and normal `n`
//! is the force `μ n` at its witness, plus the low-rank terms of `energy/contact_curvature.rs`
//! (the obstacle's curvature, the witness sliding on the feature).

use super::contacts::{Kin, Pair};
use super::kinematics::abc_series;
use super::problem::Problem;
use crate::numeric::ad::D2;
use crate::numeric::semisep::SemiSep;
use nalgebra::{DMatrix, Matrix3, Vector3};

/// Point forces summed per frame: `S_f = Σ F`, `D_f = Σ x Fᵀ` (`x` the world point where `F`
/// acts, carried by frame `f`).
pub(super) struct FrameLoads {
    s: Vec<Vector3<f64>>,
    d: Vec<Matrix3<f64>>,
    any: bool,
}

impl FrameLoads {
    /// No forces on `frames` frames.
    pub(super) fn new(frames: usize) -> Self {
        FrameLoads {
            s: vec![Vector3::zeros(); frames],
            d: vec![Matrix3::zeros(); frames],
            any: false,
        }
    }

    /// The force `force` at the world point `x` carried by frame `f`.
    pub(super) fn add(&mut self, f: usize, x: &Vector3<f64>, force: &Vector3<f64>) {
        self.s[f] += force;
        self.d[f] += x * force.transpose();
        self.any = true;
    }
}

/// A symmetric low-rank term `Σ_pq M_pq w_p w_qᵀ` (`w_p` of the strains' length).
pub(super) struct LowRank {
    pub(super) w: Vec<Vec<f64>>,
    pub(super) m: DMatrix<f64>,
}

/// The spatial twists `(ω; t)` of unit changes of the four strains of sub-arc `j` (module
/// docs), as columns.
pub(super) fn twists(kin: &Kin, j: usize) -> [[f64; 6]; 4] {
    let (m, n) = (&kin.m_int[j], &kin.n_int[j]);
    let mut out = [[0.0; 6]; 4];
    for a in 0..3 {
        for i in 0..3 {
            out[a][i] = m[(i, a)];
            out[a][3 + i] = -n[a][i];
        }
    }
    for i in 0..3 {
        out[3][3 + i] = m[(i, 2)];
    }
    out
}

/// The velocity `ω × x + t` of the point `x` under twist `tw`.
#[inline]
pub(super) fn point_velocity(tw: &[f64; 6], x: &Vector3<f64>) -> Vector3<f64> {
    let w = Vector3::new(tw[0], tw[1], tw[2]);
    w.cross(x) + Vector3::new(tw[3], tw[4], tw[5])
}

impl Problem<'_> {
    /// The forces and low-rank terms of the curvature at `kin` (with integrals): the dead
    /// loads at the frame origins and `−μ ∇²d` of each pressing pair `(pair, μ)`
    /// (`energy/contact_curvature.rs`). `None` when there is neither.
    pub(super) fn curvature_terms(
        &self,
        kin: &Kin,
        pressing: &[(&Pair, f64)],
    ) -> Option<(FrameLoads, Vec<LowRank>)> {
        if self.frame_forces.is_empty() && pressing.is_empty() {
            return None;
        }
        let mut loads = FrameLoads::new(self.nsub + 1);
        for (f, force) in self.frame_forces.iter().enumerate() {
            if *force != Vector3::zeros() {
                loads.add(f, &kin.pos[f], force);
            }
        }
        let mut low = vec![];
        if let Some(wd) = &self.world {
            for (p, mu) in pressing {
                wd.pair_curvature(kin, p, *mu, &mut loads, &mut low);
            }
        }
        Some((loads, low))
    }

    /// `base + ∇²(−Σ F·x) + Σ low-rank` in block semiseparable form with this problem's
    /// blocks (`nb`; `base` its `nblocks` diagonal blocks, e.g. `K + Σ w_c ∇²L_c`).
    pub(super) fn curvature(
        &self,
        xi: &[f64],
        kin: &Kin,
        loads: &FrameLoads,
        low: &[LowRank],
        base: &[f64],
    ) -> SemiSep {
        self.curvature_parts(xi, kin, loads, low).semisep(&[], base)
    }

    /// The parts of [`Problem::curvature`] that do not depend on its base or on low-rank
    /// terms added later ([`CurvatureParts::semisep`]).
    pub(super) fn curvature_parts(
        &self,
        xi: &[f64],
        kin: &Kin,
        loads: &FrameLoads,
        low: &[LowRank],
    ) -> CurvatureParts {
        let nsub = self.nsub;
        let r = 6 + low.iter().map(|l| l.w.len()).sum::<usize>();
        // Per sub-arc: generators (r × 4, row-major) and the diagonal 4×4 block.
        let mut vs = vec![0.0; nsub * r * 4];
        let mut us = vec![0.0; nsub * r * 4];
        let mut dsub = vec![[[0.0; 4]; 4]; nsub];
        let (mut s, mut d) = (Vector3::zeros(), Matrix3::zeros());
        for j in (0..nsub).rev() {
            if loads.any {
                s += loads.s[j + 1];
                d += loads.d[j + 1];
            }
            let tw = twists(kin, j);
            let (v, u) = (&mut vs[j * r * 4..], &mut us[j * r * 4..]);
            let (tr, sh) = (d.trace(), crate::numeric::so3::hat(&s));
            for a in 0..4 {
                let om = Vector3::new(tw[a][0], tw[a][1], tw[a][2]);
                let t = Vector3::new(tw[a][3], tw[a][4], tw[a][5]);
                let pv = om * tr - d * om + sh * t;
                for i in 0..3 {
                    v[i * 4 + a] = pv[i];
                }
                for i in 0..6 {
                    u[i * 4 + a] = tw[a][i];
                }
            }
            if s != Vector3::zeros() || d != Matrix3::zeros() {
                let (rj, rj1, pj1) = (&kin.rot[j], &kin.rot[j + 1], &kin.pos[j + 1]);
                let wm = rj.transpose() * (d.transpose() - s * pj1.transpose()) * rj1;
                let g = rj.transpose() * s;
                let x4 = [xi[4 * j], xi[4 * j + 1], xi[4 * j + 2], xi[4 * j + 3]];
                dsub[j] = sub_arc_load_block(&x4, self.ell[j], &wm, &g);
            }
        }
        let mut row = 6;
        for l in low {
            add_low_rank(l, row, r, &mut vs, &mut us, &mut dsub);
            row += l.w.len();
        }
        // Within a block, the pairs of sub-arcs `k < j`: `Σ_p V_jp U_kp` (the generators'
        // product, entry by entry; rows added later continue these sums).
        let (nb, nbl) = (self.nb, self.nblocks);
        let spb = nb / 4;
        let mut off = Vec::with_capacity(nbl * spb * spb.saturating_sub(1) * 8);
        for bl in 0..nbl {
            for lj in 0..spb {
                let j = bl * spb + lj;
                for lk in 0..lj {
                    let k = bl * spb + lk;
                    for a in 0..4 {
                        for b in 0..4 {
                            off.push(
                                (0..r)
                                    .map(|p| vs[j * r * 4 + p * 4 + a] * us[k * r * 4 + p * 4 + b])
                                    .sum::<f64>(),
                            );
                        }
                    }
                }
            }
        }
        CurvatureParts {
            nb,
            nblocks: nbl,
            r,
            vs,
            us,
            dsub,
            off,
        }
    }
}

/// [`Problem::curvature`] built up to its base ([`Problem::curvature_parts`]): generators of
/// rank `r` and the diagonal 4×4 block per sub-arc, and, within each block, the sums
/// `Σ_p V_jp U_kp` for the pairs of sub-arcs `k < j`. A Newton iteration that retries its
/// factor with a growing contact penalty (`newton/curved.rs`) builds these once and only the
/// penalty's term per try ([`CurvatureParts::semisep`]), in the order a whole build would
/// add it, so the matrix is the same to the last bit.
pub(super) struct CurvatureParts {
    nb: usize,
    nblocks: usize,
    r: usize,
    vs: Vec<f64>,
    us: Vec<f64>,
    dsub: Vec<[[f64; 4]; 4]>,
    off: Vec<f64>,
}

impl CurvatureParts {
    /// `base` + these parts + the low-rank terms `extra`, as [`Problem::curvature`] with
    /// `extra` after its own low-rank terms: the extra rows' products continue each sum where
    /// the parts left it.
    pub(super) fn semisep(&self, extra: &[LowRank], base: &[f64]) -> SemiSep {
        let (nb, nbl, r0) = (self.nb, self.nblocks, self.r);
        let nsub = self.dsub.len();
        let spb = nb / 4;
        let k = extra.iter().map(|l| l.w.len()).sum::<usize>();
        let r = r0 + k;
        let (mut ev, mut eu) = (vec![0.0; nsub * k * 4], vec![0.0; nsub * k * 4]);
        let mut extra_dsub = vec![];
        if k > 0 {
            extra_dsub = self.dsub.clone();
            let mut row = 0;
            for l in extra {
                add_low_rank(l, row, k, &mut ev, &mut eu, &mut extra_dsub);
                row += l.w.len();
            }
        }
        let dsub = if k > 0 { &extra_dsub } else { &self.dsub };
        let mut out = SemiSep {
            n: nbl,
            b: nb,
            r,
            diag: base.to_vec(),
            v: vec![0.0; nbl * r * nb],
            u: vec![0.0; nbl * r * nb],
        };
        let mut off = self.off.iter();
        for bl in 0..nbl {
            let dg = &mut out.diag[bl * nb * nb..(bl + 1) * nb * nb];
            for lj in 0..spb {
                let j = bl * spb + lj;
                for a in 0..4 {
                    for b in 0..4 {
                        dg[(4 * lj + a) * nb + 4 * lj + b] += dsub[j][a][b];
                    }
                }
                for p in 0..r {
                    let o = bl * r * nb + p * nb + 4 * lj;
                    let (v, u) = if p < r0 {
                        let i = j * r0 * 4 + p * 4;
                        (&self.vs[i..i + 4], &self.us[i..i + 4])
                    } else {
                        let i = j * k * 4 + (p - r0) * 4;
                        (&ev[i..i + 4], &eu[i..i + 4])
                    };
                    out.v[o..o + 4].copy_from_slice(v);
                    out.u[o..o + 4].copy_from_slice(u);
                }
                for lk in 0..lj {
                    let kk = bl * spb + lk;
                    for a in 0..4 {
                        for b in 0..4 {
                            let mut e = *off.next().expect("one sum per entry");
                            for p in 0..k {
                                e += ev[j * k * 4 + p * 4 + a] * eu[kk * k * 4 + p * 4 + b];
                            }
                            dg[(4 * lj + a) * nb + 4 * lk + b] += e;
                            dg[(4 * lk + b) * nb + 4 * lj + a] += e;
                        }
                    }
                }
            }
        }
        out
    }
}

/// Write the term `l` into the generators `vs`, `us` (rank `r`, rows from `row`) of each
/// sub-arc, `V = M W`, `U = W`, and add its part of the sub-arc's own block to `dsub`.
fn add_low_rank(
    l: &LowRank,
    row: usize,
    r: usize,
    vs: &mut [f64],
    us: &mut [f64],
    dsub: &mut [[[f64; 4]; 4]],
) {
    let k = l.w.len();
    for (j, dj) in dsub.iter_mut().enumerate() {
        let (v, u) = (&mut vs[j * r * 4..], &mut us[j * r * 4..]);
        for p in 0..k {
            for a in 0..4 {
                u[(row + p) * 4 + a] = l.w[p][4 * j + a];
                v[(row + p) * 4 + a] = (0..k).map(|q| l.m[(p, q)] * l.w[q][4 * j + a]).sum();
            }
        }
        for a in 0..4 {
            for b in 0..4 {
                dj[a][b] += (0..k)
                    .map(|p| l.w[p][4 * j + a] * v[(row + p) * 4 + b])
                    .sum::<f64>();
            }
        }
    }
}

/// The whole matrix of a [`SemiSep`], dense.
pub(super) fn dense(a: &SemiSep) -> DMatrix<f64> {
    let n = a.n * a.b;
    DMatrix::from_fn(n, n, |i, j| a.get(i, j))
}

/// `−∇²[Σ_b W_{:,b}·(R_l e_b) + g·p_l]` in the strains of one sub-arc, by second-order AD of
/// the scalar in closed form. With `w = ℓ (ξ₀, ξ₁, ξ₂)`, `v = ℓ (1 + ξ₃) e_z`, `x = |w|²` and
/// the exponential `R = I + A ŵ + B ŵ²`, `p = v + B ŵ v + C ŵ² v`
/// ([`exp_act`](super::kinematics::exp_act); `ŵ² = w wᵀ − x I`):
///
/// ```text
/// Σ_ab W_ab R_ab = tr W + A α·w + B (wᵀ W w − x tr W),  α = (W₃₂−W₂₃, W₁₃−W₃₁, W₂₁−W₁₂)
/// g·p = v_z [g_z + B (g_x w_y − g_y w_x) + C (w_z g·w − x g_z)]
/// ```
///
/// (one `A, B, C` instead of four actions of the exponential: ~8× fewer instructions; the
/// test checks it against the actions).
fn sub_arc_load_block(
    xi: &[f64; 4],
    ell: f64,
    wm: &Matrix3<f64>,
    g: &Vector3<f64>,
) -> [[f64; 4]; 4] {
    let w: [D2<4>; 3] = std::array::from_fn(|i| D2::var(xi[i], i) * ell);
    let vz = (D2::<4>::var(xi[3], 3) + 1.0) * ell;
    let x = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    let (a, b, c) = abc_series(x);
    let tr = wm.trace();
    let alpha = [
        wm[(2, 1)] - wm[(1, 2)],
        wm[(0, 2)] - wm[(2, 0)],
        wm[(1, 0)] - wm[(0, 1)],
    ];
    let lin = |k: [f64; 3]| w[0] * k[0] + w[1] * k[1] + w[2] * k[2];
    let wmw: [D2<4>; 3] = std::array::from_fn(|r| lin([wm[(r, 0)], wm[(r, 1)], wm[(r, 2)]]));
    let quad = w[0] * wmw[0] + w[1] * wmw[1] + w[2] * wmw[2];
    let rot = a * lin(alpha) + b * (quad + x * (-tr));
    let gw = lin([g[0], g[1], g[2]]);
    let trans = vz * ((b * (w[1] * g[0] + w[0] * (-g[1]))) + c * (w[2] * gw + x * (-g[2])) + g[2]);
    let v = rot + trans;
    let mut out = [[0.0; 4]; 4];
    for a in 0..4 {
        for b in 0..4 {
            out[a][b] = -v.h[a][b];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::energy::contacts::kinematics;
    use crate::method::energy::kinematics::exp_act;
    use crate::method::energy::test_fixture::{bent_state, case2_beside, world, Third};
    use crate::method::energy::Energy;
    use crate::model::actuation::LengthMeasure;
    use crate::numeric::ad::Real;

    /// The parts built once plus a penalty term added later are the whole build with that
    /// term last, to the bit (`newton/curved.rs` relies on it so that its stiffening tries
    /// change no answer), for one-sub-arc blocks and for blocks of three sub-arcs (where the
    /// within-block sums continue), with no penalty, one and two penalty terms.
    #[test]
    fn parts_plus_penalty_are_the_whole_build() {
        let model = case2_beside(Third::Cylinder);
        for length in [LengthMeasure::Path, LengthMeasure::Chord] {
            let set = Energy::default().with_sub_arcs(3).with_cable_length(length);
            let prob = set
                .setup(&model.robot, &model.actuation, &model.scene)
                .expect("problem");
            let world = world(&model, 3);
            let xi = bent_state(prob.nvar());
            let kin = kinematics(&xi, &prob.ell, true);
            let (pairs, _) = world.pairs(&kin);
            assert!(pairs.len() >= 3, "{} pairs", pairs.len());
            let mut loads = FrameLoads::new(prob.nsub + 1);
            let mut low = vec![];
            for (k, p) in pairs.iter().enumerate() {
                world.pair_curvature(&kin, p, 0.3 + 0.1 * k as f64, &mut loads, &mut low);
            }
            assert!(!low.is_empty());
            let base: Vec<f64> = (0..prob.nblocks * prob.nb * prob.nb)
                .map(|i| 1.0 + (i % 7) as f64 * 0.37)
                .collect();
            let unit = |p: &crate::method::energy::contacts::Pair| {
                let n = p.grad.iter().map(|g| g * g).sum::<f64>().sqrt();
                p.grad.iter().map(|g| g / n).collect::<Vec<f64>>()
            };
            let pen = |rows: &[usize], rho: f64| LowRank {
                w: rows.iter().map(|&k| unit(&pairs[k])).collect(),
                m: DMatrix::identity(rows.len(), rows.len()) * rho,
            };
            let parts = prob.curvature_parts(&xi, &kin, &loads, &low);
            for extra in [
                vec![],
                vec![pen(&[0, 2], 3.7e-2)],
                vec![pen(&[1], 5.0), pen(&[0, 1, 2], 1e-3)],
            ] {
                let mut all: Vec<LowRank> = low
                    .iter()
                    .chain(&extra)
                    .map(|l| LowRank {
                        w: l.w.clone(),
                        m: l.m.clone(),
                    })
                    .collect();
                let whole = prob.curvature(&xi, &kin, &loads, &all, &base);
                let split = parts.semisep(&extra, &base);
                assert_eq!((split.n, split.b, split.r), (whole.n, whole.b, whole.r));
                // The first entry whose bits differ, if any.
                let first =
                    |a: &[f64], b: &[f64]| (0..a.len()).find(|&i| a[i].to_bits() != b[i].to_bits());
                for (name, a, b) in [
                    ("diag", &split.diag, &whole.diag),
                    ("v", &split.v, &whole.v),
                    ("u", &split.u, &whole.u),
                ] {
                    assert_eq!(a.len(), b.len());
                    if let Some(i) = first(a, b) {
                        panic!("{length:?} {name}[{i}]: {:e} vs {:e}", a[i], b[i]);
                    }
                }
                // The penalty is in the matrix: without it the diagonal differs.
                if !extra.is_empty() {
                    all.truncate(low.len());
                    let bare = prob.curvature(&xi, &kin, &loads, &all, &base);
                    assert!(first(&bare.diag, &whole.diag).is_some());
                }
            }
            if length == LengthMeasure::Chord {
                assert!(prob.nb > 4, "blocks of several sub-arcs");
            }
        }
    }

    /// The closed-form block equals the one built from four actions of the exponential
    /// (`R_l e_b = exp_act(e_b) − exp_act(0)`, `p_l = exp_act(0)`), bent and straight.
    #[test]
    fn sub_arc_block_matches_the_exponential_actions() {
        let wm = Matrix3::new(0.3, -1.2, 0.7, 2.1, -0.4, 0.9, -0.8, 1.5, 0.2);
        let g = Vector3::new(-0.6, 1.1, 2.3);
        for xi in [[3.0, -5.0, 1.5, 0.02], [1e-5, 2e-6, -3e-6, -0.01], [0.0; 4]] {
            let ell = 0.0083;
            let vars: [D2<4>; 4] = std::array::from_fn(|i| D2::var(xi[i], i));
            let zero = [D2::<4>::cst(0.0); 3];
            let p0 = exp_act(&vars, ell, &zero);
            let mut v = D2::<4>::cst(0.0);
            for k in 0..3 {
                v = v + p0[k] * g[k];
            }
            for b in 0..3 {
                let mut e = [D2::<4>::cst(0.0); 3];
                e[b] = D2::cst(1.0);
                let pb = exp_act(&vars, ell, &e);
                for a in 0..3 {
                    v = v + (pb[a] - p0[a]) * wm[(a, b)];
                }
            }
            let blk = sub_arc_load_block(&xi, ell, &wm, &g);
            let scale = v.h.iter().flatten().fold(0.0f64, |m, h| m.max(h.abs()));
            assert!(scale > 0.0);
            for a in 0..4 {
                for b in 0..4 {
                    let e = (blk[a][b] + v.h[a][b]).abs();
                    assert!(e <= 1e-13 * scale, "{xi:?} ({a},{b}): {e:e} of {scale:e}");
                }
            }
        }
    }
}
