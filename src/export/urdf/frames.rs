//! Disk frames ↔ joint values: the six joints of an articulated section and URDF roll-pitch-yaw
//! (derivations in the module docs of [`super`]).

use crate::shape::DiskFrame;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// The six joint values of one articulated section (see the module docs for the chain).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionJoints {
    /// Chord bending about x \[rad\].
    pub bend_x: f64,
    /// Chord bending about y \[rad\].
    pub bend_y: f64,
    /// Chord length minus the nominal section length \[m\].
    pub extension: f64,
    /// Disk tilt about the chord frame's x \[rad\].
    pub tilt_x: f64,
    /// Disk tilt about y \[rad\].
    pub tilt_y: f64,
    /// Disk twist about z \[rad\].
    pub twist: f64,
}

impl SectionJoints {
    /// Joint values taking disk frame `prev` to disk frame `next` for a section of nominal
    /// length `l0` (derivation in the module docs).
    pub fn from_frames(prev: &DiskFrame, next: &DiskFrame, l0: f64) -> SectionJoints {
        let t = prev.rotation.transpose() * (next.position - prev.position);
        let c = t.norm();
        let (bend_x, bend_y) = if c > 0.0 {
            let u = t / c;
            let a = (-u.y).atan2(u.z);
            let v = rot_x(-a) * u;
            (a, v.x.atan2(v.z))
        } else {
            (0.0, 0.0)
        };
        let chord = rot_x(bend_x) * rot_y(bend_y);
        let d = chord.transpose() * prev.rotation.transpose() * next.rotation;
        let alpha = (-d[(1, 2)]).atan2(d[(2, 2)]);
        let m = rot_x(-alpha) * d;
        let gamma = m[(1, 0)].atan2(m[(1, 1)]);
        let beta = m[(0, 2)].atan2(m[(2, 2)]);
        SectionJoints {
            bend_x,
            bend_y,
            extension: c - l0,
            tilt_x: alpha,
            tilt_y: beta,
            twist: gamma,
        }
    }
}

/// URDF roll-pitch-yaw of a rotation: `R = Rz(yaw) Ry(pitch) Rx(roll)` (fixed axes x, y, z).
///
/// `yaw = atan2(R₁₀, R₀₀)`, then `M = Rz(−yaw) R = Ry(pitch) Rx(roll)` gives
/// `roll = atan2(−M₁₂, M₁₁)` and `pitch = atan2(−M₂₀, M₀₀)`: accurate to rounding also at
/// `pitch = ±π/2`, where yaw is arbitrary and roll absorbs it. Returns `[roll, pitch, yaw]`.
pub fn rpy_from_rotation(r: &Matrix3<f64>) -> [f64; 3] {
    let yaw = r[(1, 0)].atan2(r[(0, 0)]);
    let m = rot_z(-yaw) * r;
    let roll = (-m[(1, 2)]).atan2(m[(1, 1)]);
    let pitch = (-m[(2, 0)]).atan2(m[(0, 0)]);
    [roll, pitch, yaw]
}

/// Rotation of URDF `rpy = [roll, pitch, yaw]`: `Rz(yaw) Ry(pitch) Rx(roll)`.
pub fn rotation_from_rpy(rpy: [f64; 3]) -> Matrix3<f64> {
    rot_z(rpy[2]) * rot_y(rpy[1]) * rot_x(rpy[0])
}

pub(super) fn rot_x(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::x_axis(), a).into_inner()
}

pub(super) fn rot_y(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::y_axis(), a).into_inner()
}

pub(super) fn rot_z(a: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), a).into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    const TOL: f64 = 1e-12;

    fn angle_between(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
        // ‖A − B‖_F = 2√2 sin(θ/2): accurate for small angles.
        let s = (a - b).norm() / (2.0 * 2f64.sqrt());
        2.0 * s.min(1.0).asin()
    }

    #[test]
    fn rpy_round_trips_including_gimbal_lock() {
        let cases = [
            [0.1, 0.2, 0.3],
            [-2.0, 1.2, 3.0],
            [0.4, FRAC_PI_2, -0.7],
            [0.4, -FRAC_PI_2, 1.1],
            [0.3, FRAC_PI_2 - 1e-9, 0.2],
            [3.0, -1e-8, -3.1],
        ];
        for rpy in cases {
            let r = rotation_from_rpy(rpy);
            let back = rotation_from_rpy(rpy_from_rotation(&r));
            assert!(angle_between(&r, &back) < TOL, "{rpy:?}");
        }
    }

    #[test]
    fn section_joints_reproduce_relative_pose() {
        let prev = DiskFrame {
            s: 0.0,
            position: Vector3::new(0.01, -0.02, 0.03),
            rotation: Rotation3::new(Vector3::new(0.3, -0.2, 0.9)).into_inner(),
        };
        for (w, t) in [
            (
                Vector3::new(0.2, 0.1, 1.4),
                Vector3::new(0.004, -0.003, 0.019),
            ),
            (Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.0, 0.0, 0.02)),
            (Vector3::new(-0.5, 0.7, -2.0), Vector3::new(0.02, 0.0, 0.0)),
            (
                Vector3::new(0.0, FRAC_PI_2, 0.0),
                Vector3::new(0.0, -0.01, -0.01),
            ),
        ] {
            let next = DiskFrame {
                s: 0.02,
                position: prev.position + prev.rotation * t,
                rotation: prev.rotation * Rotation3::new(w).into_inner(),
            };
            let q = SectionJoints::from_frames(&prev, &next, 0.02);
            let chord = rot_x(q.bend_x) * rot_y(q.bend_y);
            let rel_p = chord * Vector3::new(0.0, 0.0, 0.02 + q.extension);
            let rel_r = chord * rot_x(q.tilt_x) * rot_y(q.tilt_y) * rot_z(q.twist);
            let p = prev.position + prev.rotation * rel_p;
            let r = prev.rotation * rel_r;
            assert!((p - next.position).norm() < TOL, "{t:?}");
            assert!(angle_between(&r, &next.rotation) < TOL, "{w:?}");
        }
    }
}
