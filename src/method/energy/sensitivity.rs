//! What the converged KKT system of an energy solve says beyond the shape: whether the
//! equilibrium is stable, and how the tip moves with each input (implicit function theorem).
//!
//! # The converged system
//!
//! At a KKT point with active rows `A` (the gradients `∇L_c` of taut cables, `λ_c > 0`, and
//! `−∇d` of pressing contacts, `μ > 0`) and Lagrangian Hessian
//! `H = K + Σ w_c ∇²L_c + ∇²V` (`w_c` the multiplier of a taut cable or the tension of a
//! tension-driven one, `V` the dead-load potential), the equilibrium is a strict local minimum —
//! a **stable** equilibrium — when `H` is positive definite on the null space of `A`
//! (second-order sufficient condition, Nocedal & Wright, *Numerical Optimization*, Thm 12.6);
//! `report.stable = Some(false)` when it is not (a saddle: the robot would not stay there).
//! Without loads the path measure makes the problem convex (`∇²L_c ⪰ 0`), `H` is block
//! diagonal and positive definite, and stability follows from the block factorization alone;
//! otherwise `Zᵀ H Z` (`Z` an orthonormal null-space basis from a Householder QR of `Aᵀ`) is
//! factored densely.
//!
//! # Tip Jacobian
//!
//! Differentiating `∇ℒ(ξ, λ; u) = 0`, `c_A(ξ; u) = 0` in an input `u` (implicit function
//! theorem, same reference, §12.8 / Fiacco's sensitivity theorem, with the active set fixed):
//!
//! ```text
//! [ H  Aᵀ ] [ dξ ]   [ −∂(∇ℒ)/∂u ]        shortening δ_c of a taut cable: rhs (0, −e_c)
//! [ A  0  ] [ dλ ] = [ −∂c_A/∂u   ]        tension T_c:                    rhs (−∇L_c, 0)
//! ```
//!
//! (a slack cable's shortening moves nothing: its column is zero). A compliant cable's row reads
//! `L − t − λ/k = 0`, so its `dλ` enters its own row: the lower-right block is `−C`,
//! `C = diag(1/k)` (0 for rigid cables and contacts). With `H` block diagonal it
//! is solved by the Schur complement `S = A H⁻¹ Aᵀ + C` (one block solve per active row), else by
//! a dense LU of the whole matrix. The tip position and tangent `t = R e_z` move along `dξ`
//! as their directional derivatives, by first-order forward AD ([`D1`]) through the product
//! of sub-arc exponentials (exact, one pass per column).
//!
//! # Curvature of loads and contacts
//!
//! `∇²V` of the dead loads and `−Σ μ ∇²d` of the pressing contacts (on the wall scene leaving
//! the latter out puts the Jacobian 16 % off) are the exact, analytic terms the Newton loop
//! factors too: `energy/curvature.rs` (forces on the chain, a unit test against central
//! differences of the exact load gradient) and `energy/contact_curvature.rs` (`∇²d` of each
//! feature type, a unit test against central differences of the exact distance gradient);
//! here they are added densely to the Hessian blocks.

use super::contacts::{Kin, Pair};
use super::curvature::dense;
use super::kinematics::exp_act_all;
use super::lengths::Work;
use super::problem::{Problem, Target};
use crate::model::actuation::{Input, LengthMeasure};
use crate::numeric::ad::{Jet, Real, D1};
use crate::numeric::dense::{chol_factor, small_solve};
use crate::shape::TipJacobian;
use nalgebra::{DMatrix, DVector, Vector3};

/// Stability verdict and tip Jacobian of a converged solve.
pub(super) struct Sensitivity {
    pub stable: Option<bool>,
    pub jacobian: Option<TipJacobian>,
}

/// The Lagrangian Hessian at the solution: factored blocks when it is block diagonal and
/// positive definite, else dense.
enum Hessian {
    Blocks(Vec<f64>),
    Dense(DMatrix<f64>),
}

/// One Jacobian column: cable, input kind, right-hand side `(r, s)` of the KKT system.
struct Column {
    cable: usize,
    input: Input,
    r: Vec<f64>,
    s: Vec<f64>,
}

impl Problem<'_> {
    /// Stability and tip Jacobian at the converged point `xi` with cable weights `wgt`
    /// (multipliers of taut cables, input tensions), cable multipliers `lam`, and the
    /// pressing pairs with their multipliers; `kin` the frames with integrals if already computed; `w`
    /// the scratch of the last linearization at `xi` (lengths and gradients).
    pub(super) fn sensitivity(
        &self,
        xi: &[f64],
        wgt: &[f64],
        lam: &[f64],
        pressing: &[(&Pair, f64)],
        kin: Option<&Kin>,
        w: &mut Work,
    ) -> Sensitivity {
        let nc = self.robot.cables.len();
        // `w` holds the lengths and gradients at `xi` (the last linearization); its Hessian
        // blocks are rebuilt here, exact.
        match self.set.cable_length {
            LengthMeasure::Path => self.path_hessian(xi, wgt, w),
            LengthMeasure::Chord => self.evaluate(xi, wgt, w, true),
        }
        // Active rows: taut cables, then pressing contacts (gradient of clearance − d).
        let taut: Vec<usize> = (0..nc)
            .filter(|&c| matches!(self.targets[c], Target::Length(_)) && lam[c] > 0.0)
            .collect();
        let mut rows: Vec<Vec<f64>> = taut.iter().map(|&c| w.grad[c].clone()).collect();
        for (p, _) in pressing {
            rows.push(p.grad.iter().map(|g| -g).collect());
        }
        // Compliance of each active row (cables `1/k`, contacts 0).
        let mut soft: Vec<f64> = taut.iter().map(|&c| self.compliance[c]).collect();
        soft.resize(rows.len(), 0.0);
        let hess = self.lagrangian_hessian(xi, w, kin, pressing);
        let stable = Some(match &hess {
            Hessian::Blocks(_) => true,
            Hessian::Dense(h) => {
                // A compliant row is a spring: `H + k a aᵀ` on the null space of the rigid rows.
                let mut h = h.clone();
                let mut rigid = vec![];
                for (row, &c) in rows.iter().zip(&soft) {
                    if c > 0.0 {
                        let a = DVector::from_column_slice(row);
                        h += (&a * a.transpose()) / c;
                    } else {
                        rigid.push(row.clone());
                    }
                }
                reduced_positive_definite(&h, &rigid)
            }
        });
        let nrow = rows.len();
        let mut cols = vec![];
        for c in 0..nc {
            match self.targets[c] {
                Target::Length(_) => {
                    let mut s = vec![0.0; nrow];
                    if let Some(r) = taut.iter().position(|&t| t == c) {
                        s[r] = -1.0;
                    }
                    let r = vec![0.0; self.nvar()];
                    cols.push(Column {
                        cable: c,
                        input: Input::Shortening,
                        r,
                        s,
                    });
                }
                Target::Tension(_) => {
                    let r = w.grad[c].iter().map(|g| -g).collect();
                    let s = vec![0.0; nrow];
                    cols.push(Column {
                        cable: c,
                        input: Input::Tension,
                        r,
                        s,
                    });
                }
                Target::Free => {}
            }
        }
        let jacobian = self.tip_jacobian(xi, &hess, &rows, &soft, &cols);
        Sensitivity { stable, jacobian }
    }

    /// `H` from the blocks of `w` plus the dead-load curvature; factored blocks when that is
    /// all and they are positive definite.
    fn lagrangian_hessian(
        &self,
        xi: &[f64],
        w: &Work,
        kin: Option<&Kin>,
        pressing: &[(&Pair, f64)],
    ) -> Hessian {
        let (nb, nv) = (self.nb, self.nvar());
        if self.frame_forces.is_empty() && pressing.is_empty() {
            let mut f = w.hess.clone();
            if (0..self.nblocks).all(|b| chol_factor(&mut f[b * nb * nb..(b + 1) * nb * nb], nb)) {
                return Hessian::Blocks(f);
            }
        }
        let mut h = DMatrix::zeros(nv, nv);
        for b in 0..self.nblocks {
            for i in 0..nb {
                for j in 0..nb {
                    h[(b * nb + i, b * nb + j)] = w.hess[b * nb * nb + i * nb + j];
                }
            }
        }
        let owned;
        let kin = match kin.filter(|k| k.m_int.len() == self.nsub) {
            Some(k) => k,
            None => {
                owned = self.kin(xi, true);
                &owned
            }
        };
        if let Some((loads, low)) = self.curvature_terms(kin, pressing) {
            let zero = vec![0.0; w.hess.len()];
            h += dense(&self.curvature(xi, kin, &loads, &low, &zero));
        }
        Hessian::Dense(h)
    }

    /// Add `∇²V` of the dead loads (`energy/curvature.rs`) to `h`; `kin` with integrals.
    #[cfg(test)]
    pub(super) fn add_load_hessian(&self, xi: &[f64], kin: &Kin, h: &mut DMatrix<f64>) {
        if let Some((loads, low)) = self.curvature_terms(kin, &[]) {
            let zero = vec![0.0; self.nblocks * self.nb * self.nb];
            *h += dense(&self.curvature(xi, kin, &loads, &low, &zero));
        }
    }

    /// Solve the KKT system for every column and map `dξ` to the tip (module docs); `None`
    /// if the system is singular or the result is not finite. `soft[a]` is row `a`'s
    /// compliance (`−1/k` on the KKT matrix's diagonal, module docs).
    fn tip_jacobian(
        &self,
        xi: &[f64],
        hess: &Hessian,
        rows: &[Vec<f64>],
        soft: &[f64],
        cols: &[Column],
    ) -> Option<TipJacobian> {
        let (nv, k) = (self.nvar(), rows.len());
        let dxis: Vec<Vec<f64>> = match hess {
            Hessian::Blocks(f) => {
                // Schur complement: Y = H⁻¹ Aᵀ, S = A Y + C, dλ = S⁻¹ (A H⁻¹ r − s).
                let ys: Vec<Vec<f64>> = rows
                    .iter()
                    .map(|r| {
                        let mut y = r.clone();
                        self.block_solve(f, &mut y);
                        y
                    })
                    .collect();
                let mut s = vec![0.0; k * k];
                for a in 0..k {
                    for b in 0..k {
                        s[a * k + b] = dot(&rows[a], &ys[b]);
                    }
                    s[a * k + a] += soft[a];
                }
                let mut out = Vec::with_capacity(cols.len());
                for col in cols {
                    let mut z = col.r.clone();
                    self.block_solve(f, &mut z);
                    let mut dl: Vec<f64> = (0..k).map(|a| dot(&rows[a], &z) - col.s[a]).collect();
                    small_solve(&mut s.clone(), &mut dl, k)?;
                    for a in 0..k {
                        for i in 0..nv {
                            z[i] -= dl[a] * ys[a][i];
                        }
                    }
                    out.push(z);
                }
                out
            }
            Hessian::Dense(h) => {
                let mut m = DMatrix::zeros(nv + k, nv + k);
                m.view_mut((0, 0), (nv, nv)).copy_from(h);
                for a in 0..k {
                    for i in 0..nv {
                        m[(nv + a, i)] = rows[a][i];
                        m[(i, nv + a)] = rows[a][i];
                    }
                    m[(nv + a, nv + a)] = -soft[a];
                }
                let lu = m.lu();
                let mut out = Vec::with_capacity(cols.len());
                for col in cols {
                    let b =
                        DVector::from_iterator(nv + k, col.r.iter().chain(col.s.iter()).copied());
                    let x = lu.solve(&b)?;
                    out.push(x.rows(0, nv).iter().copied().collect());
                }
                out
            }
        };
        let which: Vec<(usize, Input)> = cols.iter().map(|c| (c.cable, c.input)).collect();
        self.tip_columns(xi, &which, &dxis)
    }

    /// The tip Jacobian from the strain changes `dxis[k]` of each column `which[k]` (cable,
    /// input); `None` if a result is not finite.
    pub(super) fn tip_columns(
        &self,
        xi: &[f64],
        which: &[(usize, Input)],
        dxis: &[Vec<f64>],
    ) -> Option<TipJacobian> {
        let mut jac = TipJacobian {
            inputs: vec![],
            position: vec![],
            tangent: vec![],
        };
        let mut tips = Vec::with_capacity(which.len());
        for chunk in dxis.chunks(4) {
            let refs: Vec<&Vec<f64>> = chunk.iter().collect();
            tips.extend(match refs.len() {
                1 => tip_directional::<1>(xi, &self.shear.borrow(), &self.ell, &refs),
                2 => tip_directional::<2>(xi, &self.shear.borrow(), &self.ell, &refs),
                3 => tip_directional::<3>(xi, &self.shear.borrow(), &self.ell, &refs),
                _ => tip_directional::<4>(xi, &self.shear.borrow(), &self.ell, &refs),
            });
        }
        for (&(cable, input), (dp, dt)) in which.iter().zip(tips) {
            if !(dp.iter().chain(dt.iter()).all(|v| v.is_finite())) {
                return None;
            }
            jac.inputs.push((
                self.robot.cables[cable].name.clone(),
                input.name().to_string(),
            ));
            jac.position.push([dp.x, dp.y, dp.z]);
            jac.tangent.push([dt.x, dt.y, dt.z]);
        }
        Some(jac)
    }
}

/// Directional derivatives of the tip position and tangent along each of `dxis`: forward-mode
/// AD ([`D1`], one direction per gradient slot) through the chain `g_0 ⋯ g_{n−1}` applied to
/// the tip (origin of the last frame) and to the point one metre along its tangent, from the
/// tip back to the base (as the chord lengths are formed).
fn tip_directional<const K: usize>(
    xi: &[f64],
    shear: &[[f64; 2]],
    ell: &[f64],
    dxis: &[&Vec<f64>],
) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    let z = D1::<K>::cst(0.0);
    let mut qs = [[z; 3], [z, z, D1::cst(1.0)]];
    for j in (0..ell.len()).rev() {
        let v: [D1<K>; 4] = std::array::from_fn(|a| Jet {
            v: xi[4 * j + a],
            g: std::array::from_fn(|c| dxis.get(c).map_or(0.0, |d| d[4 * j + a])),
            h: [],
        });
        qs = exp_act_all(&v, shear.get(j).copied().unwrap_or_default(), ell[j], &qs);
    }
    (0..dxis.len())
        .map(|c| {
            let dp = Vector3::new(qs[0][0].g[c], qs[0][1].g[c], qs[0][2].g[c]);
            let dt = Vector3::new(qs[1][0].g[c], qs[1][1].g[c], qs[1][2].g[c]) - dp;
            (dp, dt)
        })
        .collect()
}

/// Whether `Zᵀ H Z` is positive definite, `Z` an orthonormal basis of the null space of the
/// rows (Householder QR of the square matrix `[Aᵀ 0]`: the last `n − k` columns of `Q`).
fn reduced_positive_definite(h: &DMatrix<f64>, rows: &[Vec<f64>]) -> bool {
    let n = h.nrows();
    let k = rows.len().min(n);
    let z = if k == 0 {
        DMatrix::identity(n, n)
    } else {
        let mut at = DMatrix::zeros(n, n);
        for (r, row) in rows.iter().take(k).enumerate() {
            for i in 0..n {
                at[(i, r)] = row[i];
            }
        }
        at.qr().q().columns(k, n - k).into_owned()
    };
    let red = z.transpose() * h * &z;
    let red = (&red + red.transpose()) * 0.5;
    red.cholesky().is_some()
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use crate::method::energy::contacts::kinematics;
    use crate::method::energy::Energy;
    use crate::model::scene::Scene;
    use crate::model::Model;
    use nalgebra::DMatrix;

    /// The dead-load Hessian equals central differences of the exact load gradient.
    #[test]
    fn load_hessian_matches_finite_differences() {
        let path = format!("{}/models/paper/case3.toml", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(path).expect("case 3")
            + "\n[loads]\ngravity = [0.0, -9.81, -3.0]\ndisk_mass = 0.004\ntip_force = [0.3, -0.2, -0.5]\n";
        let mut m = Model::from_toml_str(&text).expect("loaded model");
        m.robot.backbone.density = 6450.0;
        let set = Energy::default().with_sub_arcs(2);
        let empty = Scene::empty();
        let prob = set.setup(&m.robot, &m.actuation, &empty).expect("setup");
        let nv = prob.nvar();
        let xi: Vec<f64> = (0..nv)
            .map(|i| 3.0 * ((i as f64) * 0.7).sin() * if i % 4 == 3 { 1e-3 } else { 1.0 })
            .collect();
        let grad = |x: &[f64]| {
            let kin = kinematics(x, &prob.ell, true);
            let mut g = vec![0.0; nv];
            prob.add_load_gradient(Some(&kin), &mut g);
            g
        };
        let mut h = DMatrix::zeros(nv, nv);
        prob.add_load_hessian(&xi, &kinematics(&xi, &prob.ell, true), &mut h);
        let e = 1e-6;
        let scale = h.amax();
        assert!(scale > 0.0);
        for i in 0..nv {
            let (mut xp, mut xm) = (xi.clone(), xi.clone());
            xp[i] += e;
            xm[i] -= e;
            let (gp, gm) = (grad(&xp), grad(&xm));
            for k in 0..nv {
                let fd = (gp[k] - gm[k]) / (2.0 * e);
                assert!(
                    (fd - h[(i, k)]).abs() < 1e-6 * scale,
                    "H[{i},{k}]: fd {fd} vs {}",
                    h[(i, k)]
                );
            }
        }
    }
}
