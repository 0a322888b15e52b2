//! Rotations: the exponential map and its inverse (rotation vectors).

use nalgebra::{Matrix3, Rotation3, Vector3};

/// `exp([ω]×)`: the rotation by |ω| about ω/|ω| (Rodrigues' formula).
pub fn exp_so3(w: &Vector3<f64>) -> Matrix3<f64> {
    Rotation3::new(*w).into_inner()
}

/// Rotation vector of a rotation matrix (inverse of [`exp_so3`], angle in [0, π]).
pub fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    Rotation3::from_matrix_unchecked(*r).scaled_axis()
}

/// Re-orthonormalize a nearly orthonormal matrix (polar projection via SVD).
pub fn orthonormalize(r: &Matrix3<f64>) -> Matrix3<f64> {
    Rotation3::from_matrix(r).into_inner()
}

/// Angle of the relative rotation between two rotation matrices [rad].
pub fn rotation_distance(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    log_so3(&(a.transpose() * b)).norm()
}
