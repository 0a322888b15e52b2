//! Small dense linear algebra on row-major slices: Cholesky of symmetric positive definite
//! blocks (the energy model's block-diagonal Hessians) and Gaussian elimination with partial
//! pivoting for small symmetric systems (the dual of a step's QP). Allocation-free; `nalgebra`
//! is used where sizes are static (`kkt.rs`), these serve runtime sizes in hot loops.

// Index loops mirror the row-major layout.
#![allow(clippy::needless_range_loop)]

/// In-place Cholesky `A = L Lᵀ` of a dense `n × n` row-major block (lower triangle kept).
/// Returns false if the block is not positive definite.
#[inline]
pub fn chol_factor(a: &mut [f64], n: usize) -> bool {
    if n == 4 {
        chol_factor_n::<4>(a)
    } else {
        chol_factor_dyn(a, n)
    }
}

#[inline(always)]
fn chol_factor_n<const N: usize>(a: &mut [f64]) -> bool {
    chol_factor_dyn(a, N)
}

#[inline(always)]
fn chol_factor_dyn(a: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    true
}

/// Solve `L Lᵀ x = b` in place (`x` holds `b`) with the factor of [`chol_factor`].
#[inline]
pub fn chol_solve(l: &[f64], n: usize, x: &mut [f64]) {
    if n == 4 {
        chol_solve_dyn(l, 4, x)
    } else {
        chol_solve_dyn(l, n, x)
    }
}

#[inline(always)]
fn chol_solve_dyn(l: &[f64], n: usize, x: &mut [f64]) {
    for i in 0..n {
        let mut s = x[i];
        for k in 0..i {
            s -= l[i * n + k] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = x[i];
        for k in i + 1..n {
            s -= l[k * n + i] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
}

/// Solve the small symmetric system `S λ = r` (dimension ≤ number of cables) by Gaussian
/// elimination with partial pivoting; `None` if singular.
pub fn small_solve(s: &mut [f64], r: &mut [f64], n: usize) -> Option<()> {
    for col in 0..n {
        let piv =
            (col..n).max_by(|&a, &b| s[a * n + col].abs().total_cmp(&s[b * n + col].abs()))?;
        let scale = (0..n).map(|i| s[i * n + i].abs()).fold(0.0, f64::max);
        if s[piv * n + col].abs() <= 1e-13 * scale {
            return None;
        }
        if piv != col {
            for k in 0..n {
                s.swap(piv * n + k, col * n + k);
            }
            r.swap(piv, col);
        }
        for i in col + 1..n {
            let f = s[i * n + col] / s[col * n + col];
            for k in col..n {
                s[i * n + k] -= f * s[col * n + k];
            }
            r[i] -= f * r[col];
        }
    }
    for i in (0..n).rev() {
        let mut v = r[i];
        for k in i + 1..n {
            v -= s[i * n + k] * r[k];
        }
        r[i] = v / s[i * n + i];
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_and_refuses_indefinite() {
        for n in [3, 4, 6] {
            // A = B Bᵀ + n I, b = A x*.
            let b: Vec<f64> = (0..n * n)
                .map(|i| ((i * 7 % 11) as f64 - 5.0) / 3.0)
                .collect();
            let mut a = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    a[i * n + j] = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum::<f64>()
                        + if i == j { n as f64 } else { 0.0 };
                }
            }
            let xs: Vec<f64> = (0..n).map(|i| i as f64 - 1.5).collect();
            let mut x: Vec<f64> = (0..n)
                .map(|i| (0..n).map(|j| a[i * n + j] * xs[j]).sum())
                .collect();
            let mut s = a.clone();
            let mut r = x.clone();
            assert!(chol_factor(&mut a, n));
            chol_solve(&a, n, &mut x);
            small_solve(&mut s, &mut r, n).expect("regular");
            for i in 0..n {
                assert!((x[i] - xs[i]).abs() < 1e-12, "cholesky {n} {i}");
                assert!((r[i] - xs[i]).abs() < 1e-12, "elimination {n} {i}");
            }
        }
        let mut ind = vec![1.0, 2.0, 2.0, 1.0];
        assert!(!chol_factor(&mut ind, 2));
        let mut sing = vec![1.0, 2.0, 2.0, 4.0];
        assert!(small_solve(&mut sing, &mut [1.0, 2.0], 2).is_none());
    }
}
