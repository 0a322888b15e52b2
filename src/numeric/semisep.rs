//! Cholesky factorization of symmetric block *semiseparable* matrices in `O(n r² b)`: `n`
//! diagonal blocks of size `b` given explicitly, and every block below the diagonal of the
//! generator form `A_jk = V_jᵀ U_k` (`j > k`, `V_j`, `U_k` of size `r × b`; above the diagonal
//! `A_kj = A_jkᵀ`). The Hessian of a potential on a serial chain has this form (the energy
//! model's contact and dead-load curvature, `method/energy/curvature.rs`); a dense Cholesky
//! would cost `O((n b)³)`.
//!
//! # Factorization
//!
//! The Cholesky factor keeps the generator form with the same left generators,
//! `L_jk = V_jᵀ q_k` (`j > k`), `L_jj = l_j` (lower triangular). Matching `L Lᵀ = A` block by
//! block, with `S_i = Σ_{k<i} q_k q_kᵀ` (`r × r`):
//!
//! ```text
//! A_ii = V_iᵀ S_i V_i + l_i l_iᵀ          ⇒  l_i = chol(A_ii − V_iᵀ S_i V_i)
//! A_ji = V_jᵀ (S_i V_i + q_i l_iᵀ) = V_jᵀ U_i  ⇒  q_i = (U_i − S_i V_i) l_i⁻ᵀ
//! ```
//!
//! (the generator-representable semiseparable Cholesky of Vandebril, Van Barel & Mastronardi,
//! *Matrix Computations and Semiseparable Matrices*, vol. 1, Johns Hopkins 2008, ch. 13 —
//! here with matrix-valued blocks). Solves run one forward and one backward sweep carrying an
//! `r`-vector: `y_i = l_i⁻¹ (b_i − V_iᵀ Σ_{k<i} q_k y_k)`, `x_i = l_i⁻ᵀ (y_i − q_iᵀ Σ_{j>i} V_j x_j)`.

// Index loops mirror the row-major block layout.
#![allow(clippy::needless_range_loop)]

use super::dense::chol_factor;

/// A symmetric block semiseparable matrix (module docs): `n` blocks of size `b`, generators of
/// rank `r`, all row-major.
#[derive(Debug, Clone)]
pub struct SemiSep {
    /// Number of diagonal blocks.
    pub n: usize,
    /// Block size.
    pub b: usize,
    /// Generator rank.
    pub r: usize,
    /// Diagonal blocks `A_ii`, `n · b · b`.
    pub diag: Vec<f64>,
    /// Left generators `V_i` (`r × b` each), `n · r · b`.
    pub v: Vec<f64>,
    /// Right generators `U_i` (`r × b` each), `n · r · b`.
    pub u: Vec<f64>,
}

/// The Cholesky factor of a [`SemiSep`]: the diagonal factors `l_i` and generators `q_i`
/// (module docs), with the matrix's own `V_i`.
#[derive(Debug, Clone)]
pub struct SemiSepFactor {
    n: usize,
    b: usize,
    r: usize,
    l: Vec<f64>,
    q: Vec<f64>,
    v: Vec<f64>,
}

impl SemiSep {
    /// Zero matrix of `n` blocks of size `b` with generators of rank `r` (the tests build
    /// theirs from it; the energy model assembles its own).
    #[cfg(test)]
    pub fn zeros(n: usize, b: usize, r: usize) -> Self {
        SemiSep {
            n,
            b,
            r,
            diag: vec![0.0; n * b * b],
            v: vec![0.0; n * r * b],
            u: vec![0.0; n * r * b],
        }
    }

    /// Entry `(i, j)` of the whole `nb × nb` matrix.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (b, r) = (self.b, self.r);
        let (bi, bj) = (i / b, j / b);
        let (ii, jj) = (i % b, j % b);
        if bi == bj {
            return self.diag[bi * b * b + ii * b + jj];
        }
        // Below the diagonal: A_jk = V_jᵀ U_k with j the later block.
        let (hi, lo, ch, cl) = if bi > bj {
            (bi, bj, ii, jj)
        } else {
            (bj, bi, jj, ii)
        };
        (0..r)
            .map(|p| self.v[hi * r * b + p * b + ch] * self.u[lo * r * b + p * b + cl])
            .sum()
    }

    /// The factor, or `None` if the matrix is not positive definite.
    pub fn factor(&self) -> Option<SemiSepFactor> {
        // Blocks of one sub-arc's four strains: the same code with `b` a constant, so that
        // the short loops over a block are unrolled (the same operations in the same order).
        if self.b == 4 {
            self.factor_b(4)
        } else {
            self.factor_b(self.b)
        }
    }

    /// [`SemiSep::factor`] with block size `b` (`== self.b`).
    #[inline(always)]
    fn factor_b(&self, b: usize) -> Option<SemiSepFactor> {
        let (n, r) = (self.n, self.r);
        let mut s = vec![0.0; r * r];
        let mut l = vec![0.0; n * b * b];
        let mut q = vec![0.0; n * r * b];
        let mut sv = vec![0.0; r * b];
        let mut row = vec![0.0; b];
        // The sums below run in the same order as the textbook loops (index ascending), with
        // the contiguous index innermost.
        for i in 0..n {
            let vi = &self.v[i * r * b..(i + 1) * r * b];
            let ui = &self.u[i * r * b..(i + 1) * r * b];
            // SV = S V_i.
            for p in 0..r {
                let svp = &mut sv[p * b..(p + 1) * b];
                svp.fill(0.0);
                for t in 0..r {
                    let spt = s[p * r + t];
                    for (o, &v) in svp.iter_mut().zip(&vi[t * b..(t + 1) * b]) {
                        *o += spt * v;
                    }
                }
            }
            // l_i = chol(A_ii − V_iᵀ S V_i).
            let li = &mut l[i * b * b..(i + 1) * b * b];
            li.copy_from_slice(&self.diag[i * b * b..(i + 1) * b * b]);
            for a in 0..b {
                row.fill(0.0);
                for p in 0..r {
                    let vpa = vi[p * b + a];
                    for (o, &x) in row.iter_mut().zip(&sv[p * b..(p + 1) * b]) {
                        *o += vpa * x;
                    }
                }
                for (o, &x) in li[a * b..(a + 1) * b].iter_mut().zip(&row) {
                    *o -= x;
                }
            }
            if !chol_factor(li, b) {
                return None;
            }
            // q_i = (U_i − S V_i) l_i⁻ᵀ: each row ρ solves l_i z = ρ.
            let qi = &mut q[i * r * b..(i + 1) * r * b];
            for p in 0..r {
                let qp = &mut qi[p * b..(p + 1) * b];
                for a in 0..b {
                    let mut acc = ui[p * b + a] - sv[p * b + a];
                    for (&lc, &qc) in li[a * b..a * b + a].iter().zip(&qp[..a]) {
                        acc -= lc * qc;
                    }
                    qp[a] = acc / li[a * b + a];
                }
            }
            // S += q_i q_iᵀ (symmetric: each product is computed once).
            for p in 0..r {
                for t in p..r {
                    let acc: f64 = dot(&qi[p * b..(p + 1) * b], &qi[t * b..(t + 1) * b]);
                    s[p * r + t] += acc;
                    if t != p {
                        s[t * r + p] += acc;
                    }
                }
            }
        }
        Some(SemiSepFactor {
            n,
            b,
            r,
            l,
            q,
            v: self.v.clone(),
        })
    }
}

impl SemiSepFactor {
    /// Solve `A x = rhs` in place (`x` holds `rhs`): [`SemiSepFactor::forward`], then
    /// [`SemiSepFactor::backward`]. The tests' reference; the Newton step calls the two
    /// sweeps itself.
    #[cfg(test)]
    pub fn solve(&self, x: &mut [f64]) {
        self.forward(x);
        self.backward(x);
    }

    /// Solve `L y = rhs` in place (the factor's lower triangle; `A = L Lᵀ`).
    pub fn forward(&self, x: &mut [f64]) {
        // As in [`SemiSep::factor`]: four-strain blocks with `b` a constant.
        if self.b == 4 {
            self.forward_b(x, 4);
        } else {
            self.forward_b(x, self.b);
        }
    }

    /// Solve `Lᵀ x = y` in place.
    pub fn backward(&self, x: &mut [f64]) {
        if self.b == 4 {
            self.backward_b(x, 4);
        } else {
            self.backward_b(x, self.b);
        }
    }

    /// The blocks both sweeps visit, base to tip: block `i`'s generators `v_i`, `q_i` (`r`
    /// rows of `b`), its diagonal factor `L_ii` (`b × b`, row-major) and its part of `x`, for
    /// block size `b` (`== self.b`). [`SemiSepFactor::backward`] takes them in reverse.
    #[inline(always)]
    fn blocks<'a>(
        &'a self,
        x: &'a mut [f64],
        b: usize,
    ) -> impl DoubleEndedIterator<Item = (&'a [f64], &'a [f64], &'a [f64], &'a mut [f64])> {
        let rb = self.r * b;
        self.v
            .chunks_exact(rb)
            .zip(self.q.chunks_exact(rb))
            .zip(self.l.chunks_exact(b * b))
            .zip(x.chunks_exact_mut(b))
            .take(self.n)
            .map(|(((v, q), l), x)| (v, q, l, x))
    }

    /// [`SemiSepFactor::forward`] with block size `b` (`== self.b`).
    #[inline(always)]
    fn forward_b(&self, x: &mut [f64], b: usize) {
        let r = self.r;
        let mut acc = vec![0.0; r];
        for (vi, qi, li, xi) in self.blocks(x, b) {
            for p in 0..r {
                let (a, vp) = (acc[p], &vi[p * b..(p + 1) * b]);
                for t in 0..b {
                    xi[t] -= vp[t] * a;
                }
            }
            for a in 0..b {
                let mut t = xi[a];
                for c in 0..a {
                    t -= li[a * b + c] * xi[c];
                }
                xi[a] = t / li[a * b + a];
            }
            for p in 0..r {
                let qp = &qi[p * b..(p + 1) * b];
                let mut s = acc[p];
                for t in 0..b {
                    s += qp[t] * xi[t];
                }
                acc[p] = s;
            }
        }
    }

    /// [`SemiSepFactor::backward`] with block size `b` (`== self.b`).
    #[inline(always)]
    fn backward_b(&self, x: &mut [f64], b: usize) {
        let r = self.r;
        let mut acc = vec![0.0; r];
        for (vi, qi, li, xi) in self.blocks(x, b).rev() {
            for p in 0..r {
                let (a, qp) = (acc[p], &qi[p * b..(p + 1) * b]);
                for t in 0..b {
                    xi[t] -= qp[t] * a;
                }
            }
            for a in (0..b).rev() {
                let mut t = xi[a];
                for c in a + 1..b {
                    t -= li[c * b + a] * xi[c];
                }
                xi[a] = t / li[a * b + a];
            }
            for p in 0..r {
                let vp = &vi[p * b..(p + 1) * b];
                let mut s = acc[p];
                for t in 0..b {
                    s += vp[t] * xi[t];
                }
                acc[p] = s;
            }
        }
    }
}

/// `Σ a_c b_c`, `c` ascending.
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = 0.0;
    for (x, y) in a.iter().zip(b) {
        acc += x * y;
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// The factor solves the same system as a dense LU of the whole matrix, and refuses an
    /// indefinite one.
    #[test]
    fn solves_like_dense_and_refuses_indefinite() {
        let (n, b, r) = (7, 4, 5);
        let mut a = SemiSep::zeros(n, b, r);
        let f = |k: usize| ((k as f64) * 0.731).sin();
        for (k, v) in a.v.iter_mut().enumerate() {
            *v = f(3 * k + 1);
        }
        for (k, u) in a.u.iter_mut().enumerate() {
            *u = f(5 * k + 2);
        }
        for i in 0..n {
            for x in 0..b {
                for y in 0..=x {
                    let s = 0.3 * f(11 * (i * b * b + x * b + y));
                    a.diag[i * b * b + x * b + y] = s;
                    a.diag[i * b * b + y * b + x] = s;
                }
                a.diag[i * b * b + x * b + x] += 60.0;
            }
        }
        let nb = n * b;
        let dense = DMatrix::from_fn(nb, nb, |i, j| a.get(i, j));
        assert!((&dense - dense.transpose()).amax() < 1e-15);
        let rhs: Vec<f64> = (0..nb).map(|k| f(7 * k + 3)).collect();
        let want = dense
            .clone()
            .lu()
            .solve(&DVector::from_column_slice(&rhs))
            .expect("dense solve");
        let fac = a.factor().expect("positive definite");
        let mut x = rhs.clone();
        fac.solve(&mut x);
        for k in 0..nb {
            assert!(
                (x[k] - want[k]).abs() < 1e-12,
                "{k}: {} vs {}",
                x[k],
                want[k]
            );
        }
        // The forward sweep alone: |L⁻¹ b|² = bᵀ A⁻¹ b.
        let mut y = rhs.clone();
        fac.forward(&mut y);
        let quad: f64 = rhs.iter().zip(want.iter()).map(|(b, x)| b * x).sum();
        let yy: f64 = y.iter().map(|v| v * v).sum();
        assert!((yy - quad).abs() < 1e-12 * quad.abs(), "{yy} vs {quad}");
        // Indefinite: a large negative diagonal entry in the last block.
        let mut bad = a.clone();
        bad.diag[(n - 1) * b * b] = -50.0;
        assert!(bad.factor().is_none());
    }
}
