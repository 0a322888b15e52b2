//! Sub-arc kinematics of the energy model: the SE(3) exponential of a constant-strain sub-arc
//! in closed form (Rodrigues; power series near θ = 0, exact to any AD order), its action on
//! a point, and the chord between a cable's holes across one section with first-order
//! ([`D1`]) or second-order ([`D2`]) derivatives in that section's strains (derivation in
//! the docs of [`super`]).

use crate::numeric::ad::{Real, D1, D2};
pub(super) use crate::numeric::so3::abc_series;
use crate::numeric::so3::{abc, hat};
use nalgebra::{Matrix3, Vector3};

/// Gauss–Legendre points per sub-arc for path lengths.
pub const GL_NODES: usize = 5;
pub(super) const GL_X: [f64; GL_NODES] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
pub(super) const GL_W: [f64; GL_NODES] = [
    0.236_926_885_056_189_08,
    0.478_628_670_499_366_47,
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_47,
    0.236_926_885_056_189_08,
];

/// The sub-arc transform `exp(ℓ ξ̂)` in f64: rotation and translation (no shear).
pub(super) fn sub_arc_exp(xi: &[f64], ell: f64) -> (Matrix3<f64>, Vector3<f64>) {
    sheared_exp(xi, [0.0; 2], ell)
}

/// The sub-arc transform with the shear strains `shear = (v_x, v_y)`: `v = (v_x, v_y, 1 + ε)`
/// (`energy/shear.rs`).
pub(super) fn sheared_exp(xi: &[f64], shear: [f64; 2], ell: f64) -> (Matrix3<f64>, Vector3<f64>) {
    let w = Vector3::new(xi[0], xi[1], xi[2]) * ell;
    let (a, b, c) = abc(w.norm_squared());
    let wh = hat(&w);
    let wh2 = wh * wh;
    let rot = Matrix3::identity() + wh * a + wh2 * b;
    let v = Vector3::new(shear[0], shear[1], 1.0 + xi[3]) * ell;
    let p = v + wh * v * b + wh2 * v * c;
    (rot, p)
}

#[inline]
fn cross<T: Real>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The action of one sub-arc on `P` points at once (the exponential's coefficients shared):
/// `exp_act(xi, ell, q)` for each `q` in `qs`, with the constant shear strains `shear`
/// (`v = (v_x, v_y, 1 + ε)`, `energy/shear.rs`).
pub(super) fn exp_act_all<T: Real, const P: usize>(
    xi: &[T],
    shear: [f64; 2],
    ell: f64,
    qs: &[[T; 3]; P],
) -> [[T; 3]; P] {
    let w = [xi[0] * ell, xi[1] * ell, xi[2] * ell];
    let x = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    let (a, b, c) = abc_series(x);
    let v = [
        T::cst(shear[0] * ell),
        T::cst(shear[1] * ell),
        (xi[3] + 1.0) * ell,
    ];
    let wv = cross(&w, &v);
    let wwv = cross(&w, &wv);
    std::array::from_fn(|p| {
        let q = &qs[p];
        let wq = cross(&w, q);
        let wwq = cross(&w, &wq);
        let mut out = [T::cst(0.0); 3];
        for k in 0..3 {
            out[k] = q[k] + a * wq[k] + b * wwq[k] + v[k] + b * wv[k] + c * wwv[k];
        }
        out
    })
}

/// The action `exp(ℓ ξ̂) q` of one sub-arc on a point `q` (any [`Real`]).
pub(super) fn exp_act<T: Real>(xi: &[T], ell: f64, q: &[T; 3]) -> [T; 3] {
    let w = [xi[0] * ell, xi[1] * ell, xi[2] * ell];
    let x = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    let (a, b, c) = abc_series(x);
    let wq = cross(&w, q);
    let wwq = cross(&w, &wq);
    let vz = (xi[3] + 1.0) * ell;
    // ω × (0, 0, vz) and ω × (ω × (0, 0, vz)).
    let wv = [w[1] * vz, -(w[0] * vz), T::cst(0.0)];
    let wwv = cross(&w, &wv);
    let mut out = [T::cst(0.0); 3];
    for k in 0..3 {
        let vk = if k == 2 { vz } else { T::cst(0.0) };
        out[k] = q[k] + a * wq[k] + b * wwq[k] + vk + b * wv[k] + c * wwv[k];
    }
    out
}

/// Chord vector `g_{i,1} ⋯ g_{i,m} h_i − h_{i−1}` of one cable across one section, with its
/// Jacobian with respect to that section's strains (`N = 4 · sub_arcs`).
pub(super) fn chord_dual<const N: usize>(
    xi: &[f64],
    ell: f64,
    h_prev: &Vector3<f64>,
    h: &Vector3<f64>,
) -> [D1<N>; 3] {
    let m = N / 4;
    let mut vars = [D1::<N>::cst(0.0); N];
    for (i, v) in vars.iter_mut().enumerate() {
        *v = D1::var(xi[i], i);
    }
    let mut q = [D1::cst(h.x), D1::cst(h.y), D1::cst(h.z)];
    for k in (0..m).rev() {
        q = exp_act(&vars[4 * k..4 * k + 4], ell, &q);
    }
    [q[0] + (-h_prev.x), q[1] + (-h_prev.y), q[2] + (-h_prev.z)]
}

/// Chord length of one cable across one section with its exact gradient and Hessian
/// (second-order AD; `N = 4 · sub_arcs`).
pub(super) fn chord_d2<const N: usize>(
    xi: &[f64],
    ell: f64,
    h_prev: &Vector3<f64>,
    h: &Vector3<f64>,
) -> D2<N> {
    let m = N / 4;
    let mut vars = [D2::<N>::cst(0.0); N];
    for (i, v) in vars.iter_mut().enumerate() {
        *v = D2::var(xi[i], i);
    }
    let mut q = [D2::cst(h.x), D2::cst(h.y), D2::cst(h.z)];
    for k in (0..m).rev() {
        q = exp_act(&vars[4 * k..4 * k + 4], ell, &q);
    }
    let d = [q[0] + (-h_prev.x), q[1] + (-h_prev.y), q[2] + (-h_prev.z)];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// Chord length in f64 (value only).
pub(super) fn chord_value(
    xi: &[f64],
    ell: f64,
    m: usize,
    h_prev: &Vector3<f64>,
    h: &Vector3<f64>,
) -> f64 {
    let mut q = [h.x, h.y, h.z];
    for k in (0..m).rev() {
        q = exp_act(&xi[4 * k..4 * k + 4], ell, &q);
    }
    (Vector3::new(q[0], q[1], q[2]) - h_prev).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponential_series_matches_closed_form() {
        // The closed forms cancel badly near 0: compare them only away from 0 …
        for &t2 in &[0.3, 2.0, 9.0, 30.0] {
            let (a, b, c) = abc_series(t2);
            let th: f64 = f64::sqrt(t2);
            let (s, co) = th.sin_cos();
            assert!((a - s / th).abs() < 1e-14);
            assert!((b - (1.0 - co) / t2).abs() < 1e-14);
            assert!((c - (th - s) / (t2 * th)).abs() < 1e-13);
        }
        // … and with the Taylor polynomials near it.
        let x = 1e-6;
        let (a, b, c) = abc_series(x);
        assert!((a - (1.0 - x / 6.0 + x * x / 120.0)).abs() < 1e-18);
        assert!((b - (0.5 - x / 24.0 + x * x / 720.0)).abs() < 1e-18);
        assert!((c - (1.0 / 6.0 - x / 120.0 + x * x / 5040.0)).abs() < 1e-18);
    }

    #[test]
    fn chord_jacobian_matches_finite_differences() {
        let xi = [3.0, -2.0, 1.5, 1e-3, -4.0, 6.0, 0.5, -2e-3];
        let (hp, h) = (Vector3::new(0.008, 0.0, 0.0), Vector3::new(0.0, 0.008, 0.0));
        let ell = 0.01;
        let d = chord_dual::<8>(&xi, ell, &hp, &h);
        let len = Vector3::new(d[0].v, d[1].v, d[2].v).norm();
        assert!((len - chord_value(&xi, ell, 2, &hp, &h)).abs() < 1e-15);
        let e = 1e-6;
        for i in 0..8 {
            let mut xp = xi;
            let mut xm = xi;
            xp[i] += e;
            xm[i] -= e;
            let (dp, dm) = (
                chord_dual::<8>(&xp, ell, &hp, &h),
                chord_dual::<8>(&xm, ell, &hp, &h),
            );
            for r in 0..3 {
                let fd = (dp[r].v - dm[r].v) / (2.0 * e);
                assert!(
                    (fd - d[r].g[i]).abs() < 1e-10,
                    "J[{r}][{i}]: {fd} vs {}",
                    d[r].g[i]
                );
            }
        }
    }

    #[test]
    fn chord_hessian_matches_finite_differences() {
        let xi = [3.0, -2.0, 1.5, 1e-3, -4.0, 6.0, 0.5, -2e-3];
        let (hp, h) = (Vector3::new(0.008, 0.0, 0.0), Vector3::new(0.0, 0.008, 0.0));
        let ell = 0.01;
        let d = chord_d2::<8>(&xi, ell, &hp, &h);
        let grad = |x: &[f64; 8]| -> [f64; 8] {
            let v = chord_dual::<8>(x, ell, &hp, &h);
            let n = Vector3::new(v[0].v, v[1].v, v[2].v);
            let e = n / n.norm();
            let mut g = [0.0; 8];
            for a in 0..8 {
                g[a] = e.x * v[0].g[a] + e.y * v[1].g[a] + e.z * v[2].g[a];
            }
            g
        };
        let g0 = grad(&xi);
        let e = 1e-6;
        for i in 0..8 {
            assert!((g0[i] - d.g[i]).abs() < 1e-12, "grad {i}");
            let (mut xp, mut xm) = (xi, xi);
            xp[i] += e;
            xm[i] -= e;
            let (gp, gm) = (grad(&xp), grad(&xm));
            for k in 0..8 {
                let fd = (gp[k] - gm[k]) / (2.0 * e);
                assert!(
                    (fd - d.h[i][k]).abs() < 1e-7,
                    "hess {i},{k}: {fd} vs {}",
                    d.h[i][k]
                );
            }
        }
    }
}
