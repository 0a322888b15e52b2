//! One Newton step on the KKT system of a small equality-constrained problem.
//!
//! For `min f(x)` s.t. `c(x) = 0` with Lagrangian Hessian `H`, gradient `g` and constraint
//! Jacobian `A` (k × n), the step solves, by the null-space method,
//!
//! ```text
//! A Y d_y = −c                     (range step, least squares: tolerates redundant rows)
//! (Zᵀ H Z) d_z = −Zᵀ (g + H Y d_y) (reduced Newton step)
//! dx = Y d_y + Z d_z,   Aᵀ λ ≈ −(g + H dx)   (least-squares multipliers)
//! ```
//!
//! with `[Y Z]` an orthonormal basis split into the row space and null space of `A` (from the
//! eigenvectors of `AᵀA` with row-normalized `A`). Negative or tiny eigenvalues of the reduced
//! Hessian are replaced by their magnitude (at least `reg`), so every step descends on the
//! constraint manifold; the smallest eigenvalue is returned so callers can certify a minimum
//! (second-order condition) rather than a saddle.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

/// Result of [`kkt_step`].
#[derive(Debug, Clone)]
pub struct KktStep {
    /// Primal step.
    pub dx: DVector<f64>,
    /// Multipliers for the new point (sign convention: ∇f + Aᵀλ = 0).
    pub lambda: DVector<f64>,
    /// Smallest eigenvalue of the reduced Hessian Zᵀ H Z (+∞ when the null space is empty).
    pub min_reduced_eigenvalue: f64,
    /// Rank of the constraint Jacobian (a diagnostic the tests check).
    #[cfg_attr(not(test), allow(dead_code))]
    pub rank: usize,
}

/// Relative threshold below which a singular value of the (row-normalized) Jacobian is zero.
pub const RANK_TOL: f64 = 1e-10;

/// Least-squares multipliers λ minimizing |g + Aᵀλ| (the first-order estimate).
pub fn multipliers(g: &DVector<f64>, a: &DMatrix<f64>) -> DVector<f64> {
    if a.nrows() == 0 {
        return DVector::zeros(0);
    }
    // Normal equations (A Aᵀ) λ = −A g when A has full row rank; SVD otherwise.
    if let Some(ch) = (a * a.transpose()).cholesky() {
        let l = ch.solve(&(-(a * g)));
        if l.iter().all(|x| x.is_finite()) {
            return l;
        }
    }
    let at = a.transpose();
    let svd = at.svd(true, true);
    svd.solve(&(-g), 1e-12)
        .unwrap_or_else(|_| DVector::zeros(a.nrows()))
}

/// One regularized Newton–KKT step (see module docs).
pub fn kkt_step(
    h: &DMatrix<f64>,
    g: &DVector<f64>,
    a: &DMatrix<f64>,
    c: &DVector<f64>,
    reg: f64,
) -> KktStep {
    let n = g.len();
    let k = a.nrows();
    // Row-normalize A so that constraints of different units weigh alike in the rank test.
    let mut an = a.clone();
    let mut cn = c.clone();
    for i in 0..k {
        let s = an.row(i).norm();
        if s > 0.0 {
            an.row_mut(i).scale_mut(1.0 / s);
            cn[i] /= s;
        }
    }
    let (y, z, y_eigs) = if k == 0 {
        (DMatrix::zeros(n, 0), DMatrix::identity(n, n), vec![])
    } else {
        let eig = SymmetricEigen::new(an.transpose() * &an);
        let mut yc = vec![];
        let mut zc = vec![];
        let mut ye = vec![];
        for j in 0..n {
            if eig.eigenvalues[j] > RANK_TOL {
                yc.push(eig.eigenvectors.column(j).into_owned());
                ye.push(eig.eigenvalues[j]);
            } else {
                zc.push(eig.eigenvectors.column(j).into_owned());
            }
        }
        let y = if yc.is_empty() {
            DMatrix::zeros(n, 0)
        } else {
            DMatrix::from_columns(&yc)
        };
        let z = if zc.is_empty() {
            DMatrix::zeros(n, 0)
        } else {
            DMatrix::from_columns(&zc)
        };
        (y, z, ye)
    };
    let rank = y.ncols();
    // Range step: (AY)ᵀ(AY) = diag(eigenvalues), so d_y = −Yᵀ Aᵀ c / eig.
    let mut dy = DVector::zeros(rank);
    if rank > 0 {
        let atc = an.transpose() * &cn;
        for j in 0..rank {
            dy[j] = -y.column(j).dot(&atc) / y_eigs[j];
        }
    }
    let x_range = &y * &dy;
    let mut min_eig = f64::INFINITY;
    let mut dx = x_range.clone();
    if z.ncols() > 0 {
        let hr = z.transpose() * h * &z;
        let rhs = -(z.transpose() * (g + h * &x_range));
        let e = SymmetricEigen::new(hr);
        let mut dz = DVector::zeros(z.ncols());
        for j in 0..z.ncols() {
            let lam = e.eigenvalues[j];
            min_eig = min_eig.min(lam);
            let lam_reg = lam.abs().max(reg);
            let v = e.eigenvectors.column(j);
            dz += v * (v.dot(&rhs) / lam_reg);
        }
        dx += &z * dz;
    }
    let lambda = multipliers(&(g + h * &dx), a);
    KktStep {
        dx,
        lambda,
        min_reduced_eigenvalue: min_eig,
        rank,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// min x² + y² s.t. x + y = 1 → x = y = 1/2, λ = −1 (one step, exact).
    #[test]
    fn quadratic_with_linear_constraint_in_one_step() {
        let h = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 2.0]);
        let x = DVector::from_vec(vec![0.0, 0.0]);
        let g = &h * &x;
        let a = DMatrix::from_row_slice(1, 2, &[1.0, 1.0]);
        let c = DVector::from_vec(vec![-1.0]);
        let s = kkt_step(&h, &g, &a, &c, 1e-12);
        assert!((s.dx[0] - 0.5).abs() < 1e-14 && (s.dx[1] - 0.5).abs() < 1e-14);
        assert!((s.lambda[0] + 1.0).abs() < 1e-12);
        assert!((s.min_reduced_eigenvalue - 2.0).abs() < 1e-12);
    }

    /// A repeated constraint row does not break the step (redundant cable constraints).
    #[test]
    fn redundant_rows_are_tolerated() {
        let h = DMatrix::identity(2, 2);
        let g = DVector::zeros(2);
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 2.0, 0.0]);
        let c = DVector::from_vec(vec![-1.0, -2.0]);
        let s = kkt_step(&h, &g, &a, &c, 1e-12);
        assert_eq!(s.rank, 1);
        assert!((s.dx[0] - 1.0).abs() < 1e-12 && s.dx[1].abs() < 1e-12);
    }
}

/// Fixed-size form of [`kkt_step`] for 6 unknowns and at most 6 constraint rows, without
/// heap allocation (the geometric section problems). Same method and conventions; rows whose
/// Jacobian is rank-deficient are handled by the same eigenvalue split of `AᵀA`.
pub struct KktStep6 {
    /// Primal step.
    pub dx: nalgebra::Vector6<f64>,
    /// Multipliers (first `k` entries used).
    pub lambda: [f64; 6],
    /// Smallest eigenvalue of the reduced Hessian (+∞ when the null space is empty).
    pub min_reduced_eigenvalue: f64,
    /// Rank of the constraint Jacobian (a diagnostic the tests check).
    #[cfg_attr(not(test), allow(dead_code))]
    pub rank: usize,
}

/// 6-vectors and 6×6 matrices of the fixed-size step.
type V6 = nalgebra::Vector6<f64>;
type M6 = nalgebra::Matrix6<f64>;

/// How [`kkt_step6_by`] splits the constraint rows into a range and a null space.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowSplit6 {
    /// The eigenvectors of the row-normalized `AᵀA` (the split of [`kkt_step`]).
    Eigen,
    /// Modified Gram–Schmidt on the rows (that eigendecomposition was ~14 % of a
    /// literal solve). `[Y Z]` is then another orthonormal basis of the same row space and
    /// null space, so the step, the multipliers and the reduced Hessian's eigenvalues are the
    /// same in exact arithmetic (the null-space method does not depend on the basis chosen).
    /// When a row is (numerically) dependent on the previous ones — its Gram–Schmidt
    /// remainder `ρ` has `ρ² ≤ RANK_TOL`, the same threshold the eigenvalues of the
    /// row-normalized `AᵀA` are held to — the step falls back to [`RowSplit6::Eigen`], whose
    /// least-squares range step handles redundant rows.
    GramSchmidt,
}

/// The 6×6 KKT step with the rows split by `split`; `rows[i]` is the gradient of constraint
/// `i`, `c[i]` its value. `None` when there are more than 6 rows (the one size guard of
/// [`kkt_step6`] and [`kkt_step6_gs`]).
pub fn kkt_step6_by(
    split: RowSplit6,
    h: &M6,
    g: &V6,
    rows: &[V6],
    c: &[f64],
    reg: f64,
) -> Option<KktStep6> {
    if rows.len() > 6 {
        return None;
    }
    let gram_schmidt = match split {
        RowSplit6::Eigen => None,
        RowSplit6::GramSchmidt => gram_schmidt_split6(rows, c),
    };
    match gram_schmidt {
        Some(split) => kkt_step6_from(h, g, rows, reg, split, true),
        None => kkt_step6_from(h, g, rows, reg, eigen_split6(rows, c), false),
    }
}

/// [`kkt_step6_by`] with [`RowSplit6::Eigen`].
pub fn kkt_step6(h: &M6, g: &V6, rows: &[V6], c: &[f64], reg: f64) -> Option<KktStep6> {
    kkt_step6_by(RowSplit6::Eigen, h, g, rows, c, reg)
}

/// [`kkt_step6_by`] with [`RowSplit6::GramSchmidt`].
pub fn kkt_step6_gs(h: &M6, g: &V6, rows: &[V6], c: &[f64], reg: f64) -> Option<KktStep6> {
    kkt_step6_by(RowSplit6::GramSchmidt, h, g, rows, c, reg)
}

/// The range step `Y d_y` (least-squares `A x = −c`, row-normalized), an orthonormal basis of
/// the null space (first `nz` entries) and the rank.
type Split6 = (
    nalgebra::Vector6<f64>,
    [nalgebra::Vector6<f64>; 6],
    usize,
    usize,
);

/// The split from the eigenvectors of the row-normalized `AᵀA`.
fn eigen_split6(rows: &[nalgebra::Vector6<f64>], c: &[f64]) -> Split6 {
    use nalgebra::{Matrix6, Vector6};
    let mut m = Matrix6::zeros();
    let mut atc = Vector6::zeros();
    for i in 0..rows.len() {
        let s = rows[i].norm();
        if s > 0.0 {
            let r = rows[i] / s;
            m += r * r.transpose();
            atc += r * (c[i] / s);
        }
    }
    let eig = nalgebra::SymmetricEigen::new(m);
    let mut x_range = Vector6::zeros();
    let mut z = [Vector6::zeros(); 6];
    let (mut rank, mut nz) = (0, 0);
    for j in 0..6 {
        let v = eig.eigenvectors.column(j).into_owned();
        if eig.eigenvalues[j] > RANK_TOL {
            x_range -= v * (v.dot(&atc) / eig.eigenvalues[j]);
            rank += 1;
        } else {
            z[nz] = v;
            nz += 1;
        }
    }
    (x_range, z, nz, rank)
}

/// The split by modified Gram–Schmidt (twice, for orthogonality to rounding) of the
/// row-normalized rows `r_i = Σ_{j≤i} L_ij q_j`: the range step is `x = Σ y_j q_j` with
/// `L y = −c` (forward substitution), and the null space is completed from the unit vectors,
/// taking at each round the one with the largest remainder (at least `1/√6` of its length).
/// `None` when a row is dependent on the previous ones (see [`RowSplit6::GramSchmidt`]).
fn gram_schmidt_split6(rows: &[nalgebra::Vector6<f64>], c: &[f64]) -> Option<Split6> {
    use nalgebra::{Matrix6, Vector6};
    let k = rows.len();
    let mut q = [Vector6::zeros(); 6];
    let mut l = Matrix6::zeros();
    let mut y = Vector6::zeros();
    for i in 0..k {
        let s = rows[i].norm();
        if s == 0.0 || !s.is_finite() {
            return None;
        }
        let mut v = rows[i] / s;
        for _ in 0..2 {
            for j in 0..i {
                let d = q[j].dot(&v);
                l[(i, j)] += d;
                v -= q[j] * d;
            }
        }
        let n = v.norm();
        if n * n <= RANK_TOL {
            return None;
        }
        l[(i, i)] = n;
        q[i] = v / n;
        let mut rhs = -c[i] / s;
        for j in 0..i {
            rhs -= l[(i, j)] * y[j];
        }
        y[i] = rhs / n;
    }
    let mut x_range = Vector6::zeros();
    for j in 0..k {
        x_range += q[j] * y[j];
    }
    // Remainders of the unit vectors against the row space (twice, for orthogonality); each
    // round takes the largest, and the others lose their component along it.
    let mut rem: [Vector6<f64>; 6] = std::array::from_fn(|e| {
        let mut v = Vector6::ith(e, 1.0);
        for _ in 0..2 {
            for b in &q[..k] {
                v -= b * b.dot(&v);
            }
        }
        v
    });
    let mut z = [Vector6::zeros(); 6];
    let mut used = [false; 6];
    for nz in 0..6 - k {
        let e = (0..6)
            .filter(|&e| !used[e])
            .max_by(|&a, &b| rem[a].norm_squared().total_cmp(&rem[b].norm_squared()))?;
        used[e] = true;
        let mut v = rem[e];
        for b in q[..k].iter().chain(z[..nz].iter()) {
            v -= b * b.dot(&v);
        }
        z[nz] = v.normalize();
        for (o, r) in rem.iter_mut().enumerate() {
            if !used[o] {
                *r -= z[nz] * z[nz].dot(r);
            }
        }
    }
    Some((x_range, z, 6 - k, k))
}

/// The null-space Newton step and multipliers from a range/null split. `exact_size`: the
/// reduced Hessian's eigendecomposition on its own `nz × nz` size ([`reduced_step`]) rather
/// than padded to 6 × 6 (kept for [`kkt_step6`], whose results recorded tips depend on).
fn kkt_step6_from(
    h: &nalgebra::Matrix6<f64>,
    g: &nalgebra::Vector6<f64>,
    rows: &[nalgebra::Vector6<f64>],
    reg: f64,
    (x_range, z, nz, rank): Split6,
    exact_size: bool,
) -> Option<KktStep6> {
    use nalgebra::{Matrix6, Vector6};
    let mut dx = x_range;
    let mut min_eig = f64::INFINITY;
    if nz > 0 {
        // Reduced Hessian in the leading nz×nz block; the rest padded with 2‖block‖_F + 1,
        // strictly above every real eigenvalue (so the two never mix) yet of the same scale
        // (so the eigen solver keeps its relative accuracy on the real block).
        let mut hr = Matrix6::zeros();
        let mut rhs = Vector6::zeros();
        let hz: [Vector6<f64>; 6] =
            std::array::from_fn(|a| if a < nz { h * z[a] } else { Vector6::zeros() });
        let grad = g + h * x_range;
        for a in 0..6 {
            if a < nz {
                rhs[a] = -z[a].dot(&grad);
                for b in 0..nz {
                    hr[(a, b)] = z[a].dot(&hz[b]);
                }
            }
        }
        if exact_size {
            let (dz, lam_min) = reduced_step(&hr, &rhs, nz, reg);
            min_eig = lam_min;
            for a in 0..nz {
                dx += z[a] * dz[a];
            }
            return multipliers6(g, h, rows, dx, min_eig, rank);
        }
        let fro = hr.norm();
        let pad = 2.0 * fro + 1.0;
        for a in nz..6 {
            hr[(a, a)] = pad;
        }
        let e = nalgebra::SymmetricEigen::new(hr);
        let mut dz = Vector6::zeros();
        for j in 0..6 {
            let lam = e.eigenvalues[j];
            if lam > fro + 0.5 {
                continue;
            }
            min_eig = min_eig.min(lam);
            let v = e.eigenvectors.column(j);
            dz += v * (v.dot(&rhs) / lam.abs().max(reg));
        }
        for a in 0..nz {
            dx += z[a] * dz[a];
        }
    }
    multipliers6(g, h, rows, dx, min_eig, rank)
}

/// `Σ_j v_j (v_j·rhs) / max(|λ_j|, reg)` over the eigenpairs of the leading `nz × nz` block
/// of `hr`, decomposed at its own size (1 × 1 in closed form), and the smallest `λ_j`.
fn reduced_step(
    hr: &nalgebra::Matrix6<f64>,
    rhs: &nalgebra::Vector6<f64>,
    nz: usize,
    reg: f64,
) -> (nalgebra::Vector6<f64>, f64) {
    use nalgebra::{Matrix2, Matrix3, Matrix4, Matrix5, Matrix6, Vector6};
    let mut dz = Vector6::zeros();
    let mut min_eig = f64::INFINITY;
    macro_rules! sized {
        ($n:literal, $m:ty) => {{
            let e = nalgebra::SymmetricEigen::new(<$m>::from_fn(|a, b| hr[(a, b)]));
            for j in 0..$n {
                let lam = e.eigenvalues[j];
                min_eig = min_eig.min(lam);
                let v = e.eigenvectors.column(j);
                let coef = (0..$n).map(|a| v[a] * rhs[a]).sum::<f64>() / lam.abs().max(reg);
                for a in 0..$n {
                    dz[a] += v[a] * coef;
                }
            }
        }};
    }
    match nz {
        1 => {
            min_eig = hr[(0, 0)];
            dz[0] = rhs[0] / min_eig.abs().max(reg);
        }
        2 => sized!(2, Matrix2<f64>),
        3 => sized!(3, Matrix3<f64>),
        4 => sized!(4, Matrix4<f64>),
        5 => sized!(5, Matrix5<f64>),
        _ => sized!(6, Matrix6<f64>),
    }
    (dz, min_eig)
}

/// Multipliers `(A Aᵀ) λ = −A (g + H dx)` (padded to 6 × 6 with the identity) and the step.
fn multipliers6(
    g: &nalgebra::Vector6<f64>,
    h: &nalgebra::Matrix6<f64>,
    rows: &[nalgebra::Vector6<f64>],
    dx: nalgebra::Vector6<f64>,
    min_eig: f64,
    rank: usize,
) -> Option<KktStep6> {
    use nalgebra::{Matrix6, Vector6};
    let k = rows.len();
    let r = g + h * dx;
    let mut aat = Matrix6::identity();
    let mut b = Vector6::zeros();
    for i in 0..k {
        b[i] = -rows[i].dot(&r);
        for j in 0..k {
            aat[(i, j)] = rows[i].dot(&rows[j]);
        }
    }
    let lam = aat.cholesky()?.solve(&b);
    if lam.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let mut lambda = [0.0; 6];
    lambda[..k].copy_from_slice(&lam.as_slice()[..k]);
    Some(KktStep6 {
        dx,
        lambda,
        min_reduced_eigenvalue: min_eig,
        rank,
    })
}

#[cfg(test)]
mod tests6 {
    use super::*;
    use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

    /// The fixed-size step agrees with the general one on a random indefinite problem.
    #[test]
    fn fixed_size_step_matches_general_step() {
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut h = Matrix6::from_fn(|_, _| rnd());
        h = h + h.transpose();
        let g = Vector6::from_fn(|_, _| rnd());
        let rows: Vec<Vector6<f64>> = (0..3).map(|_| Vector6::from_fn(|_, _| rnd())).collect();
        let c = [0.1, -0.2, 0.05];
        let s6 = kkt_step6(&h, &g, &rows, &c, 1e-10).unwrap();
        let hd = DMatrix::from_fn(6, 6, |i, j| h[(i, j)]);
        let gd = DVector::from_fn(6, |i, _| g[i]);
        let ad = DMatrix::from_fn(3, 6, |i, j| rows[i][j]);
        let cd = DVector::from_row_slice(&c);
        let sd = kkt_step(&hd, &gd, &ad, &cd, 1e-10);
        for i in 0..6 {
            assert!(
                (s6.dx[i] - sd.dx[i]).abs() < 1e-9,
                "dx {i}: {} vs {}",
                s6.dx,
                sd.dx
            );
        }
        for i in 0..3 {
            assert!((s6.lambda[i] - sd.lambda[i]).abs() < 1e-8, "lambda {i}");
        }
        assert!((s6.min_reduced_eigenvalue - sd.min_reduced_eigenvalue).abs() < 1e-9);
    }
}

/// Seeded cross-checks against independent solvers (kept in their own file for length).
#[cfg(test)]
#[path = "kkt_split_tests.rs"]
mod split_agreement;
