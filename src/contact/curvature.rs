//! Curvature of an obstacle's distance function: `G = ∇²_x dist(x, B)` at a point `x` outside
//! a convex obstacle `B`, for the second derivative of a feature–obstacle distance.
//!
//! # Derivation
//!
//! Outside a convex set the distance is differentiable with `∇ dist = n(x) = (x − π(x)) /
//! |x − π(x)|` (`π` the closest point), and `G = ∂n/∂x` is constant along the normal ray: at
//! distance `d` from a surface point with shape operator `K` (principal curvatures `κ_i`),
//! `G(d) = K (I + d K)⁻¹` (eigenvalues `κ_i / (1 + d κ_i)`, `n` in its null space; do Carmo,
//! *Differential Geometry of Curves and Surfaces*, §3-3, offset surfaces). Two points on one
//! ray, at `δ` and at `d`, are related by `G(d) = G(δ) (I − (δ − d) G(δ))⁻¹` (the functions of
//! `K` commute). `G(δ)` is taken by central differences of parry's exact projection at the
//! point `δ` = [`OFFSET`] off the surface, where `n(x)` is well defined even when the robot
//! touches (`d ≈ 0`), and carried to `d`. A flat face gives `G = 0`; a sphere of radius `R`,
//! `(I − n nᵀ)/(R + d)`; a cylinder, the same without its axis. An edge or vertex touched at
//! `d → 0` has unbounded curvature (the distance is not twice differentiable there): `None`.

use super::parry::{nvec, pvec};
use nalgebra::{DMatrix, Matrix3, Vector3};
use parry3d::math::Pose as PPose;
use parry3d::shape::Shape as PShape;

/// Distance off the surface at which the normal field is differentiated \[m\].
pub(crate) const OFFSET: f64 = 1e-3;

/// Step of the central differences of the normal field \[m\] (the normal's round-off, ~1e-14,
/// over this step stays below 1e-8 of `1/OFFSET`; the truncation, `(h/ρ)²` of the curvature,
/// below 1e-6 for any radius `ρ ≥ OFFSET`).
const STEP: f64 = 1e-6;

/// `∇²_x dist(x, B)` at the point at distance `d` from the obstacle `shape` (at `pose`) whose
/// closest point is `on` with outward unit normal `n` (module docs); `None` where the distance
/// is not twice differentiable (an edge or vertex touched, or a normal that cannot be
/// differentiated: the point projects inside).
pub(crate) fn distance_hessian(
    shape: &dyn PShape,
    pose: &PPose,
    on: &Vector3<f64>,
    n: &Vector3<f64>,
    d: f64,
) -> Option<Matrix3<f64>> {
    let x0 = on + n * OFFSET;
    let normal_at = |x: &Vector3<f64>| -> Option<Vector3<f64>> {
        let pr = shape.project_point(pose, pvec(x), false);
        if pr.is_inside {
            return None;
        }
        let g = x - nvec(pr.point);
        let len = g.norm();
        (len > 0.5 * OFFSET).then(|| g / len)
    };
    let mut gd = Matrix3::zeros();
    for i in 0..3 {
        let e = Vector3::ith(i, STEP);
        let col = (normal_at(&(x0 + e))? - normal_at(&(x0 - e))?) / (2.0 * STEP);
        gd.set_column(i, &col);
    }
    let gd = (gd + gd.transpose()) * 0.5;
    // Carry from δ to d: G(d) = G(δ) (I − (δ − d) G(δ))⁻¹.
    let m = Matrix3::identity() - gd * (OFFSET - d);
    // An eigenvalue of G(δ) near 1/δ: the radius of curvature is ~0 (an edge or vertex).
    if m.determinant() < 1e-6 {
        return None;
    }
    let g = gd * m.try_inverse()?;
    Some((g + g.transpose()) * 0.5)
}

/// `φ_ss⁻¹` of the envelope theorem's sliding term `−φ_ξs φ_ss⁻¹ φ_sξ` of a distance's second
/// derivative (`method/energy/contact_curvature.rs`, `method/geometric/contact_curvature.rs`
/// derive it), the one place both models decide it: `φ_ss = x_sᵀ G x_s + diag(n · x_ss)` over
/// the witness's parameters `s` (tangents `x_s`, normal curvatures `n · x_ss`) with `G` the
/// obstacle's distance Hessian. `None` where there is no parameter or `d` is not twice
/// differentiable: `φ_ss` zero, or not positive definite (its Cholesky factor's smallest
/// diagonal at most `1e-6 √max|φ_ss|`: a segment parallel to a plane, a face on a face).
pub(crate) fn sliding_inverse(
    g: &Matrix3<f64>,
    tangents: &[Vector3<f64>],
    normal_curv: &[f64],
) -> Option<DMatrix<f64>> {
    let k = tangents.len();
    let mut phi_ss = DMatrix::zeros(k, k);
    for (a, ta) in tangents.iter().enumerate() {
        for (b, tb) in tangents.iter().enumerate() {
            phi_ss[(a, b)] = ta.dot(&(g * tb));
        }
        phi_ss[(a, a)] += normal_curv[a];
    }
    let scale = phi_ss.amax();
    (k > 0 && scale > 0.0)
        .then(|| phi_ss.cholesky())
        .flatten()
        .filter(|c| c.l().diagonal().min() > 1e-6 * scale.sqrt())
        .map(|c| c.inverse())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ppose;
    use parry3d::shape::{Ball, Cuboid, Cylinder};

    /// Closed forms: a ball's `(I − n nᵀ)/(R + d)`, a cylinder's without its axis, a box
    /// face's zero, an edge touched at zero distance refused.
    #[test]
    fn matches_closed_forms() {
        let pose = ppose(&Matrix3::identity(), &Vector3::new(0.1, -0.2, 0.3));
        let c = Vector3::new(0.1, -0.2, 0.3);
        let n = Vector3::new(1.0, 2.0, -0.5).normalize();
        let r = 0.015;
        for d in [0.0, 2e-3] {
            let g = distance_hessian(&Ball::new(r), &pose, &(c + n * r), &n, d).expect("ball");
            let want = (Matrix3::identity() - n * n.transpose()) / (r + d);
            assert!((g - want).amax() < 1e-6 * want.amax(), "{g} vs {want}");
        }
        // parry's cylinder axis is its local y.
        let ny = Vector3::new(0.6, 0.0, 0.8);
        let on = c + ny * r + Vector3::new(0.0, 0.01, 0.0);
        let g = distance_hessian(&Cylinder::new(0.05, r), &pose, &on, &ny, 0.0).expect("cyl");
        let ey = Vector3::y();
        let want = (Matrix3::identity() - ny * ny.transpose() - ey * ey.transpose()) / r;
        assert!((g - want).amax() < 1e-6 * want.amax(), "{g} vs {want}");
        let cube = Cuboid::new(pvec(&Vector3::new(0.02, 0.03, 0.04)));
        let face = c + Vector3::new(0.02, 0.01, -0.01);
        let g = distance_hessian(&cube, &pose, &face, &Vector3::x(), 0.0).expect("face");
        assert!(g.amax() < 1e-6, "{g}");
        let edge = c + Vector3::new(0.02, 0.03, 0.0);
        let ne = Vector3::new(1.0, 1.0, 0.0).normalize();
        assert!(distance_hessian(&cube, &pose, &edge, &ne, 0.0).is_none());
        // Off the edge by 5 mm: the distance to a line, (I − n nᵀ − e eᵀ)/d.
        let g = distance_hessian(&cube, &pose, &edge, &ne, 5e-3).expect("edge at 5 mm");
        let ez = Vector3::z();
        let want = (Matrix3::identity() - ne * ne.transpose() - ez * ez.transpose()) / 5e-3;
        assert!((g - want).amax() < 1e-5 * want.amax(), "{g} vs {want}");
    }
}
