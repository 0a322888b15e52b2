//! SO(3): the skew map, the exponential map and its inverse (rotation vectors), and
//! re-orthonormalization (polar and Gram–Schmidt).

use crate::numeric::ad::Real;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// `exp([ω]×)`: the rotation by |ω| about ω/|ω| (Rodrigues' formula).
pub fn exp_so3(w: &Vector3<f64>) -> Matrix3<f64> {
    Rotation3::new(*w).into_inner()
}

/// Rotation vector of a rotation matrix (inverse of [`exp_so3`], angle in [0, π]).
pub fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    Rotation3::from_matrix_unchecked(*r).scaled_axis()
}

/// Inverse factorials 1/k!, k = 0..=84.
const INV_FACT: [f64; 85] = {
    let mut t = [1.0; 85];
    let mut k = 1;
    while k < 85 {
        t[k] = t[k - 1] / k as f64;
        k += 1;
    }
    t
};

#[inline]
fn inv_fact(k: usize) -> f64 {
    INV_FACT[k]
}

/// `A, B, C` of the SE(3) exponential as power series in `x = θ²` (any [`Real`]):
/// `A = Σ (−x)ᵏ/(2k+1)!`, `B = Σ (−x)ᵏ/(2k+2)!`, `C = Σ (−x)ᵏ/(2k+3)!`, truncated when the
/// next term is below 1e-18 (valid for any θ; used where derivatives are needed).
pub fn abc_series<T: Real>(x: T) -> (T, T, T) {
    let x0 = x.val();
    let xv = x0.abs();
    let mut n = 4;
    let mut xn = xv.powi(4);
    while n < 40 && xn * inv_fact(2 * n + 1) > 1e-18 {
        n += 1;
        xn *= xv;
    }
    // f, f′, f″ at x0 by Horner in f64 (coefficient of xᵏ: (−1)ᵏ/(2k+o)!), then the
    // second-order expansion in dx = x − x0 (zero in value), which carries exact first and
    // second derivatives for AD types: one AD product instead of 3n.
    let series = |o: usize| -> (f64, f64, f64) {
        let coef = |k: usize| if k.is_multiple_of(2) { 1.0 } else { -1.0 } * inv_fact(2 * k + o);
        let (mut f, mut d1, mut d2) = (0.0, 0.0, 0.0);
        for k in (0..=n).rev() {
            f = f * x0 + coef(k);
            if k >= 1 {
                d1 = d1 * x0 + k as f64 * coef(k);
            }
            if k >= 2 {
                d2 = d2 * x0 + (k * (k - 1)) as f64 * coef(k);
            }
        }
        (f, d1, d2)
    };
    let dx = x + (-x0);
    let dx2 = dx * dx;
    let mk = |(f, d1, d2): (f64, f64, f64)| T::cst(f) + dx * d1 + dx2 * (0.5 * d2);
    (mk(series(1)), mk(series(2)), mk(series(3)))
}

/// `A, B, C` in f64: closed form, series near θ = 0. With `θ² = |ω|²`, `exp([ω]×) = I + A[ω]× +
/// B[ω]×²` and the left Jacobian of SO(3) (the `V` of the SE(3) exponential) is `I + B[ω]× +
/// C[ω]×²` (Barfoot 2017 §7.1.5).
pub fn abc(theta2: f64) -> (f64, f64, f64) {
    if theta2 < 1e-4 {
        // [`abc_series`]'s five terms (there the next is below 3e-22) by its Horner order,
        // so the same bits, without its derivatives.
        let series = |o: usize| {
            (0..=4usize).rev().fold(0.0, |f, k| {
                let sign = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
                f * theta2 + sign * inv_fact(2 * k + o)
            })
        };
        (series(1), series(2), series(3))
    } else {
        let th = theta2.sqrt();
        let (s, c) = th.sin_cos();
        (s / th, (1.0 - c) / theta2, (th - s) / (theta2 * th))
    }
}

/// Largest deviation from orthonormality (`|RᵀR − I|`, largest entry) a rotation read from a
/// file or handed to an export may have: files hold rotations to ~1e-15.
pub const ROTATION_TOL: f64 = 1e-6;

/// Why `r` is not a proper rotation, or `None` when it is one: not finite, `|RᵀR − I|`
/// (largest entry) above [`ROTATION_TOL`], or a determinant ≤ 0 (a reflection). `5·I` and a
/// mirror (det −1) are both refused.
pub fn rotation_defect(r: &Matrix3<f64>) -> Option<String> {
    if r.iter().any(|x| !x.is_finite()) {
        return Some("has a number that is not finite".into());
    }
    let err = (r.transpose() * r - Matrix3::identity()).amax();
    let det = r.determinant();
    (err > ROTATION_TOL || det <= 0.0).then(|| {
        format!("is not a rotation (|RᵀR − I| = {err:.1e}, det = {det:.3}; a rotation has 0 and 1)")
    })
}

/// Re-orthonormalize a nearly orthonormal matrix (polar projection via SVD).
pub fn orthonormalize(r: &Matrix3<f64>) -> Matrix3<f64> {
    Rotation3::from_matrix(r).into_inner()
}

/// `v` with `[v]× = M − Mᵀ`: twice the axial vector of `M`'s skew part (the inverse of
/// [`hat`] on skew matrices, up to the factor 2; for a rotation by `θ` about `n`, `2 sin θ n`).
#[inline]
pub fn vee_skew(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

/// The angle of `Raᵀ Rb` \[rad\] (atan2 keeps small angles exact, where the acos of a cosine
/// near 1 loses half the digits).
pub fn angle_between(ra: &Matrix3<f64>, rb: &Matrix3<f64>) -> f64 {
    let rel = ra.transpose() * rb;
    let c = (rel.trace() - 1.0) / 2.0;
    (0.5 * vee_skew(&rel).norm()).atan2(c)
}

/// `[v]×`, the skew matrix with `[v]× x = v × x`.
#[inline]
pub fn hat(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// `m · hat(v)` without the products with `hat`'s zeros: column `j` of it is `m (v × e_j)`,
/// two columns of `m` weighed (the full product's sums less its products with zero).
#[inline(always)]
pub fn mul_hat(m: &Matrix3<f64>, v: &Vector3<f64>) -> Matrix3<f64> {
    let (c0, c1, c2) = (m.column(0), m.column(1), m.column(2));
    Matrix3::from_columns(&[
        c1 * v.z - c2 * v.y,
        c2 * v.x - c0 * v.z,
        c0 * v.y - c1 * v.x,
    ])
}

/// The nearest rotation to a matrix that has drifted slightly from orthonormal, by
/// Gram–Schmidt on its columns: for a drift ε it differs from the polar factor
/// ([`orthonormalize`]) by O(ε) and costs a tenth of it. Used for RK4-integrated frames (drift
/// O(h⁴)) and products of rotations (drift ~1e-16).
#[inline]
pub fn gram_schmidt(r: &Matrix3<f64>) -> Matrix3<f64> {
    let x = r.column(0).normalize();
    let y = (r.column(1) - x * x.dot(&r.column(1))).normalize();
    let z = x.cross(&y);
    Matrix3::from_columns(&[x, y, z])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mul_hat_is_the_product_with_hat() {
        let m = exp_so3(&Vector3::new(0.3, -1.2, 2.0)) * 1.7 + Matrix3::from_element(0.1);
        let v = Vector3::new(-0.4, 2.5, 0.9);
        let gap = (mul_hat(&m, &v) - m * hat(&v)).amax();
        assert!(gap <= 1e-15, "{gap:e}");
    }

    #[test]
    fn rotations_pass_and_scalings_mirrors_and_nans_do_not() {
        let r = exp_so3(&Vector3::new(0.3, -1.2, 2.0));
        assert_eq!(rotation_defect(&r), None);
        assert!(rotation_defect(&(r * 5.0)).is_some());
        let mirror = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0)) * r;
        let why = rotation_defect(&mirror).expect("refused");
        assert!(why.contains("det = -1"), "{why}");
        let mut nan = r;
        nan[(1, 2)] = f64::NAN;
        assert!(rotation_defect(&nan).is_some());
    }

    /// `vee_skew` undoes `hat` (times 2) on skew matrices and ignores the symmetric part;
    /// `angle_between` gives the rotation vector's length, against Rodrigues' `exp_so3`, at
    /// angles from 1e-9 rad to near π, and does not depend on the frame both are seen in.
    #[test]
    fn vee_undoes_hat_and_the_angle_is_the_rotation_vectors_length() {
        let mut rng = crate::numeric::test_rng::Rng(0x0050_3ee5_0a46_1e00);
        for k in 0..200 {
            let v = Vector3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let sym =
                Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 5.0, 3.0, 5.0, 6.0) * rng.range(-1.0, 1.0);
            assert!(
                (vee_skew(&(hat(&v) + sym)) - 2.0 * v).amax() < 1e-15,
                "{v:?}"
            );
            let theta = 10f64.powi(-(k % 10)) * rng.range(0.1, 3.1);
            let w = v.normalize() * theta;
            let ra = exp_so3(&Vector3::new(
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
                0.5,
            ));
            let got = angle_between(&ra, &(ra * exp_so3(&w)));
            assert!(
                (got - theta).abs() < 1e-14 * (1.0 + theta) + 1e-15,
                "{theta} {got}"
            );
        }
    }
}
