//! Cable lengths of the energy model in either measure, their exact gradients, and the
//! block-diagonal Lagrangian Hessian `K + Σ w_c ∇²L_c` (derivation in the docs of
//! [`super`]).

use super::kinematics::{chord_d2, chord_dual, chord_value};
use super::problem::{Problem, Target};
use crate::model::actuation::LengthMeasure;
use crate::numeric::dense::chol_solve;
use nalgebra::Vector3;

/// Routing samples of one cable at the Gauss nodes of one sub-arc: `(rx, ry, rx', ry', ds)`.
pub(super) type Node = [f64; 5];

/// Scratch for the Newton iterations (allocated once per solve).
pub(super) struct Work {
    pub(super) len: Vec<f64>,
    pub(super) grad: Vec<Vec<f64>>,
    pub(super) hess: Vec<f64>,
    pub(super) raw: Vec<f64>,
    pub(super) y: Vec<Vec<f64>>,
    pub(super) z: Vec<f64>,
    pub(super) gobj: Vec<f64>,
}

impl Work {
    /// Scratch sized for `prob`.
    pub(super) fn new(prob: &Problem) -> Self {
        let (nc, nv, nb) = (prob.robot.cables.len(), prob.nvar(), prob.nb);
        Work {
            len: vec![0.0; nc],
            grad: vec![vec![0.0; nv]; nc],
            hess: vec![0.0; prob.nblocks * nb * nb],
            raw: vec![0.0; prob.nblocks * nb * nb],
            y: vec![],
            z: vec![0.0; nv],
            gobj: vec![0.0; nv],
        }
    }
}

impl Problem<'_> {
    /// Lengths of every cable in the chosen measure (value only).
    pub(super) fn lengths(&self, xi: &[f64], out: &mut [f64]) {
        for (c, cable) in self.robot.cables.iter().enumerate() {
            let mut total = 0.0;
            match self.set.cable_length {
                LengthMeasure::Path => {
                    for j in 0..self.first[cable.ends_at] {
                        let x = &xi[4 * j..4 * j + 4];
                        for nd in &self.nodes[c][j] {
                            total += nd[4] * path_w(nd, x, self.shear_at(j)).norm();
                        }
                    }
                }
                LengthMeasure::Chord => {
                    for i in 1..=cable.ends_at {
                        let (j0, m) = (self.first[i - 1], self.count(i));
                        total += chord_value(
                            &xi[4 * j0..4 * (j0 + m)],
                            self.ell[j0],
                            m,
                            &cable.hole(i - 1),
                            &cable.hole(i),
                        );
                    }
                }
            }
            out[c] = total;
        }
    }

    /// Lengths and gradients of every cable; for chords also the Lagrangian Hessian blocks
    /// with cable weights `wgt` (they come out of the same pass).
    pub(super) fn evaluate(&self, xi: &[f64], wgt: &[f64], w: &mut Work, exact: bool) {
        let nb = self.nb;
        if self.set.cable_length == LengthMeasure::Chord {
            self.energy_hessian(xi, w);
        }
        for (c, cable) in self.robot.cables.iter().enumerate() {
            let g = &mut w.grad[c];
            g.fill(0.0);
            if self.targets[c] == Target::Free {
                w.len[c] = 0.0;
                continue;
            }
            let mut total = 0.0;
            let wc = wgt[c];
            match self.set.cable_length {
                LengthMeasure::Path => {
                    for j in 0..self.first[cable.ends_at] {
                        let x = &xi[4 * j..4 * j + 4];
                        let sh = self.shear_at(j);
                        let mut gj = [0.0; 4];
                        for nd in &self.nodes[c][j] {
                            let (rx, ry, ds) = (nd[0], nd[1], nd[4]);
                            let wv = path_w(nd, x, sh);
                            let n = wv.norm();
                            total += ds * n;
                            let f = ds / n;
                            // ∇|w| = Bᵀ w / |w|.
                            gj[0] += f * wv.z * ry;
                            gj[1] -= f * wv.z * rx;
                            gj[2] += f * (wv.y * rx - wv.x * ry);
                            gj[3] += f * wv.z;
                        }
                        g[4 * j..4 * j + 4].copy_from_slice(&gj);
                    }
                }
                LengthMeasure::Chord => {
                    for i in 1..=cable.ends_at {
                        let (j0, m) = (self.first[i - 1], self.count(i));
                        let xs = &xi[4 * j0..4 * (j0 + m)];
                        let (hp, h) = (cable.hole(i - 1), cable.hole(i));
                        let ell = self.ell[j0];
                        let hb = &mut w.hess[(i - 1) * nb * nb..i * nb * nb];
                        macro_rules! exact {
                            ($n:expr) => {{
                                let d = chord_d2::<$n>(xs, ell, &hp, &h);
                                total += d.v;
                                for a in 0..$n {
                                    g[4 * j0 + a] += d.g[a];
                                    if wc != 0.0 {
                                        for bb in 0..$n {
                                            hb[a * $n + bb] += wc * d.h[a][bb];
                                        }
                                    }
                                }
                            }};
                        }
                        macro_rules! acc {
                            ($n:expr) => {{
                                let d = chord_dual::<$n>(xs, ell, &hp, &h);
                                let len =
                                    (d[0].v * d[0].v + d[1].v * d[1].v + d[2].v * d[2].v).sqrt();
                                total += len;
                                let e = [d[0].v / len, d[1].v / len, d[2].v / len];
                                for a in 0..$n {
                                    g[4 * j0 + a] +=
                                        e[0] * d[0].g[a] + e[1] * d[1].g[a] + e[2] * d[2].g[a];
                                }
                                if wc != 0.0 {
                                    // Gauss–Newton part Jᵀ (I − êêᵀ) J / |d|.
                                    let mut pj = [[0.0; $n]; 3];
                                    for a in 0..$n {
                                        let ej =
                                            e[0] * d[0].g[a] + e[1] * d[1].g[a] + e[2] * d[2].g[a];
                                        for r in 0..3 {
                                            pj[r][a] = d[r].g[a] - e[r] * ej;
                                        }
                                    }
                                    let f = wc / len;
                                    for a in 0..$n {
                                        for bb in 0..$n {
                                            hb[a * $n + bb] += f
                                                * (pj[0][a] * pj[0][bb]
                                                    + pj[1][a] * pj[1][bb]
                                                    + pj[2][a] * pj[2][bb]);
                                        }
                                    }
                                }
                            }};
                        }
                        match (m, exact) {
                            (1, false) => acc!(4),
                            (2, false) => acc!(8),
                            (3, false) => acc!(12),
                            (_, false) => acc!(16),
                            (1, true) => exact!(4),
                            (2, true) => exact!(8),
                            (3, true) => exact!(12),
                            (_, true) => exact!(16),
                        }
                    }
                }
            }
            w.len[c] = total;
        }
    }

    /// Reset the Hessian blocks to the energy's `∇²E` at `xi`: the diagonal `K`, plus each
    /// sub-arc's curvature stiffening block when `β > 0` ([`Problem::stiffening_block`]).
    pub(super) fn energy_hessian(&self, xi: &[f64], w: &mut Work) {
        let nb = self.nb;
        w.hess.fill(0.0);
        for b in 0..self.nblocks {
            for i in 0..nb {
                w.hess[b * nb * nb + i * nb + i] = self.k[b * nb + i];
            }
        }
        if self.stiffening == 0.0 {
            return;
        }
        for j in 0..self.nsub {
            // Sub-arc j's curvatures are the global variables 4j, 4j + 1, in block 4j / nb.
            let (b, o) = ((4 * j) / nb, (4 * j) % nb);
            let h = self.stiffening_block(xi, j);
            for a in 0..2 {
                for c in 0..2 {
                    w.hess[b * nb * nb + (o + a) * nb + o + c] += h[a][c];
                }
            }
        }
    }

    /// Path measure: Hessian blocks `K + Σ wgt_c Σ_nodes Bᵀ (I − ŵŵᵀ) B / |w| ds` (exact).
    pub(super) fn path_hessian(&self, xi: &[f64], wgt: &[f64], w: &mut Work) {
        self.energy_hessian(xi, w);
        for (c, cable) in self.robot.cables.iter().enumerate() {
            let wc = wgt[c];
            if wc == 0.0 {
                continue;
            }
            for j in 0..self.first[cable.ends_at] {
                let x = &xi[4 * j..4 * j + 4];
                let sh = self.shear_at(j);
                let mut h = [0.0; 10];
                for nd in &self.nodes[c][j] {
                    let (rx, ry, ds) = (nd[0], nd[1], nd[4]);
                    let wv = path_w(nd, x, sh);
                    let n = wv.norm();
                    let e = wv / n;
                    let bt = [e.z * ry, -e.z * rx, e.y * rx - e.x * ry, e.z];
                    let f = wc * ds / n;
                    // BᵀB (columns of B: (0,0,ry), (0,0,−rx), (−ry,rx,0), (0,0,1)) − (Bᵀê)(Bᵀê)ᵀ.
                    h[0] += f * (ry * ry - bt[0] * bt[0]);
                    h[1] += f * (-rx * ry - bt[0] * bt[1]);
                    h[2] += f * (-bt[0] * bt[2]);
                    h[3] += f * (ry - bt[0] * bt[3]);
                    h[4] += f * (rx * rx - bt[1] * bt[1]);
                    h[5] += f * (-bt[1] * bt[2]);
                    h[6] += f * (-rx - bt[1] * bt[3]);
                    h[7] += f * (rx * rx + ry * ry - bt[2] * bt[2]);
                    h[8] += f * (-bt[2] * bt[3]);
                    h[9] += f * (1.0 - bt[3] * bt[3]);
                }
                let hb = &mut w.hess[j * 16..(j + 1) * 16];
                let idx = [
                    (0, 0),
                    (0, 1),
                    (0, 2),
                    (0, 3),
                    (1, 1),
                    (1, 2),
                    (1, 3),
                    (2, 2),
                    (2, 3),
                    (3, 3),
                ];
                for (v, &(a, b)) in h.iter().zip(&idx) {
                    hb[a * 4 + b] += v;
                    if a != b {
                        hb[b * 4 + a] += v;
                    }
                }
            }
        }
    }

    /// Solve `H x = rhs` in place with the factored blocks.
    pub(super) fn block_solve(&self, hess: &[f64], x: &mut [f64]) {
        let nb = self.nb;
        for b in 0..self.nblocks {
            chol_solve(
                &hess[b * nb * nb..(b + 1) * nb * nb],
                nb,
                &mut x[b * nb..(b + 1) * nb],
            );
        }
    }
}

/// Body-frame cable tangent `w = v + u × r + r'` at one Gauss node.
#[inline]
pub(super) fn path_w(nd: &Node, x: &[f64], shear: [f64; 2]) -> Vector3<f64> {
    let (rx, ry, dx, dy) = (nd[0], nd[1], nd[2], nd[3]);
    Vector3::new(
        shear[0] + dx - x[2] * ry,
        shear[1] + dy + x[2] * rx,
        1.0 + x[3] + x[0] * ry - x[1] * rx,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::energy::kinematics::{GL_NODES, GL_W, GL_X};
    use crate::method::energy::{cable_lengths, Energy};
    use crate::model::robot::Robot;
    use crate::model::routing::Route;
    use crate::model::scene::Scene;
    use crate::model::Model;

    fn case(n: usize) -> Model {
        let path = format!("{}/models/paper/case{n}.toml", env!("CARGO_MANIFEST_DIR"));
        Model::from_file(path).expect("paper model parses")
    }

    /// Path length by a refined rule: every sub-arc split into 64 pieces, 6 Gauss points each.
    fn refined_length(robot: &Robot, set: &Energy, c: usize, xi: &[f64]) -> f64 {
        let route = Route::new(robot, c, set.routing).expect("route");
        let m = set.sub_arcs;
        let mut total = 0.0;
        for j in 0..robot.cables[c].ends_at * m {
            let sec = j / m + 1;
            let ell = robot.section_length(sec) / m as f64;
            let s0 = robot.disk_s[sec - 1] + (j % m) as f64 * ell;
            let pieces = 64;
            let h = ell / pieces as f64;
            for p in 0..pieces {
                for q in 0..GL_NODES {
                    let s = s0 + p as f64 * h + 0.5 * h * (GL_X[q] + 1.0);
                    let rp = route.eval(s, sec - 1);
                    let nd = [rp.r.x, rp.r.y, rp.dr.x, rp.dr.y, 0.0];
                    total +=
                        0.5 * h * GL_W[q] * path_w(&nd, &xi[4 * j..4 * j + 4], [0.0; 2]).norm();
                }
            }
        }
        total
    }

    /// Quadrature error allowed on a strongly bent and twisted state \[m\] (the target is
    /// ≤ 1e-9 m; measured 5e-12 m worst, on case III's jumping cable B).
    const QUAD_TOL: f64 = 1e-10;

    #[test]
    fn path_quadrature_is_accurate() {
        for n in 1..=3 {
            let m = case(n);
            let set = Energy::default();
            let nv = 4 * set.sub_arcs * m.robot.sections();
            // A strongly bent, twisted state.
            let xi: Vec<f64> = (0..nv)
                .map(|i| match i % 4 {
                    0 => 8.0 * ((i as f64) * 0.37).sin(),
                    1 => -6.0 + 0.1 * i as f64,
                    2 => 3.0 * ((i as f64) * 0.11).cos(),
                    _ => -2e-3,
                })
                .collect();
            let lens = cable_lengths(&m.robot, &set, &xi).expect("lengths");
            for (c, l) in lens.iter().enumerate() {
                let r = refined_length(&m.robot, &set, c, &xi);
                assert!((l - r).abs() < QUAD_TOL, "case {n} cable {c}: {l} vs {r}");
            }
        }
    }

    #[test]
    fn path_derivatives_match_finite_differences() {
        let m = case(3);
        let set = Energy::default().with_sub_arcs(2);
        let empty = Scene::empty();
        let prob = set.setup(&m.robot, &m.actuation, &empty).expect("setup");
        let nv = prob.nvar();
        let xi: Vec<f64> = (0..nv).map(|i| 0.5 * ((i as f64) * 0.7).sin()).collect();
        let nc = m.robot.cables.len();
        let mk = || Work {
            len: vec![0.0; nc],
            grad: vec![vec![0.0; nv]; nc],
            hess: vec![0.0; prob.nblocks * 16],
            raw: vec![0.0; prob.nblocks * 16],
            y: vec![vec![0.0; nv]; nc],
            z: vec![0.0; nv],
            gobj: vec![0.0; nv],
        };
        let mut w = mk();
        let wgt = [1.0, 0.0];
        prob.evaluate(&xi, &wgt, &mut w, false);
        prob.path_hessian(&xi, &wgt, &mut w);
        let e = 1e-6;
        for i in [0, 1, 2, 3, 17, 18, 19, 20] {
            let (mut xp, mut xm) = (xi.clone(), xi.clone());
            xp[i] += e;
            xm[i] -= e;
            let (mut wp, mut wm) = (mk(), mk());
            prob.evaluate(&xp, &wgt, &mut wp, false);
            prob.evaluate(&xm, &wgt, &mut wm, false);
            let fd = (wp.len[0] - wm.len[0]) / (2.0 * e);
            assert!((fd - w.grad[0][i]).abs() < 1e-9, "grad {i}");
            let b = i / 4;
            for k in 0..4 {
                let col = 4 * b + k;
                let fd = (wp.grad[0][col] - wm.grad[0][col]) / (2.0 * e);
                let k_diag = if i == col { prob.k[i] } else { 0.0 };
                let h = w.hess[b * 16 + (i % 4) * 4 + k] - k_diag;
                assert!((fd - h).abs() < 1e-7, "hess {i},{col}: {fd} vs {h}");
            }
        }
    }
}
