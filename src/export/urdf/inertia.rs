//! Mass and inertia of every URDF link, so that simulators (MuJoCo refuses moving bodies
//! without mass) see the robot's real mass distribution.
//!
//! - **Disk** `k`: a solid cylinder of the disk radius r and thickness h (holes ignored), of
//!   mass `loads.disk_mass` when the model gives one, else [`DEFAULT_DISK_DENSITY`]·π r² h;
//!   principal moments m(3r² + h²)/12 about its diameters and m r²/2 about its normal.
//! - **Backbone** of section `i`: a solid rod of the backbone diameter and the section's
//!   undeformed length l0 (the rod is inextensible to first order: its mass does not change
//!   when it bends), of density `backbone.density` when the model gives one, else
//!   [`DEFAULT_BACKBONE_DENSITY`]; laid along the solved chord (centre at its middle), moments
//!   m(3ρ² + c²)/12 across and m ρ²/2 along it (c: chord length, ρ: rod radius).
//! - Cables are massless.
//! - A rod **without spacer disks**: its stations take the disks' place, each a thin slice of
//!   the rod carrying a quarter of each section beside it; each section's backbone body carries
//!   the other half of its rod. Total mass and each section's centre of mass stay exact (the
//!   two quarters sit at the chord's ends, whose middle is the rod body's centre).
//! - **Port links** (articulated, through a port): `port_insertion_link` and
//!   `port_rotation_link` move, so each carries a share of disk 0, which sits at `(0, 0, −L)`
//!   in both frames in every configuration (the rotation is about that axis and the disk is
//!   symmetric about it): mass, centre of mass and inertia exact, and no massless moving body
//!   for MuJoCo.
//!
//! In **articulated** mode the links between a section's joints (`bend_x_link`, `chord_end`,
//! `tilt_x_link`, `tilt_y_link`) have no body of their own, but their origins stay at a disk's
//! centre in every configuration (the joints between them are rotations about that point): so
//! disk k's mass is shared equally among the links whose origin is its centre (`disk_k`,
//! `section_k_chord_end`, `section_k_tilt_x_link`, `section_k_tilt_y_link`,
//! `section_{k+1}_bend_x_link`), each share carrying the same fraction of the disk's inertia
//! tensor in its own frame. Total mass and every centre of mass are exact in every
//! configuration; the inertia tensor is exact where the bend and tilt joints are zero and off by
//! terms of the order of those angles elsewhere. In fixed mode each disk link carries its whole
//! disk and its section's backbone (combined with the parallel-axis theorem).

use crate::model::robot::Robot;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// Density of a disk when the model gives no `loads.disk_mass` \[kg/m³\]: PLA, the usual
/// 3-D-printed spacer disk.
pub const DEFAULT_DISK_DENSITY: f64 = 1240.0;
/// Density of the backbone when the model gives no `backbone.density` \[kg/m³\]: nitinol, the
/// usual superelastic backbone.
pub const DEFAULT_BACKBONE_DENSITY: f64 = 6450.0;

/// A rigid body in a link frame: mass \[kg\], centre of mass \[m\], inertia tensor about the
/// centre of mass in the link frame \[kg m²\].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Body {
    pub mass: f64,
    pub com: Vector3<f64>,
    pub inertia: Matrix3<f64>,
}

impl Body {
    /// Two bodies as one (parallel-axis theorem: I = Σ Iᵢ + mᵢ(|dᵢ|² 1 − dᵢ dᵢᵀ)).
    pub fn combine(&self, other: &Body) -> Body {
        let mass = self.mass + other.mass;
        let com = (self.com * self.mass + other.com * other.mass) / mass;
        let shift = |b: &Body| {
            let d = b.com - com;
            b.inertia + b.mass * (Matrix3::identity() * d.norm_squared() - d * d.transpose())
        };
        Body {
            mass,
            com,
            inertia: shift(self) + shift(other),
        }
    }

    /// The same body with its mass and inertia scaled by `f`.
    pub fn scaled(&self, f: f64) -> Body {
        Body {
            mass: self.mass * f,
            com: self.com,
            inertia: self.inertia * f,
        }
    }

    /// As a URDF `<inertial>` (origin at the centre of mass, axes of the link frame).
    pub fn to_urdf(self) -> urdf_rs::Inertial {
        let i = self.inertia;
        urdf_rs::Inertial {
            origin: urdf_rs::Pose {
                xyz: urdf_rs::Vec3([self.com.x, self.com.y, self.com.z]),
                rpy: urdf_rs::Vec3([0.0; 3]),
            },
            mass: urdf_rs::Mass { value: self.mass },
            inertia: urdf_rs::Inertia {
                ixx: i[(0, 0)],
                ixy: i[(0, 1)],
                ixz: i[(0, 2)],
                iyy: i[(1, 1)],
                iyz: i[(1, 2)],
                izz: i[(2, 2)],
            },
        }
    }
}

/// Solid cylinder of mass `m`, radius `r`, length `len`, along the unit axis `axis`, centred
/// at `com`.
pub(super) fn cylinder(m: f64, r: f64, len: f64, axis: &Vector3<f64>, com: Vector3<f64>) -> Body {
    let across = m * (3.0 * r * r + len * len) / 12.0;
    let along = m * r * r / 2.0;
    let a = axis.normalize();
    Body {
        mass: m,
        com,
        inertia: Matrix3::identity() * across + (along - across) * a * a.transpose(),
    }
}

/// Mass of one disk \[kg\].
pub(super) fn disk_mass(robot: &Robot) -> f64 {
    if robot.loads.disk_mass > 0.0 {
        robot.loads.disk_mass
    } else {
        let r = robot.disk_radius;
        DEFAULT_DISK_DENSITY * PI * r * r * robot.disk_thickness
    }
}

/// Disk `k` in its own frame. A rod without spacer disks has a station there instead: a
/// thin slice of the rod (radius ρ) carrying a quarter of the rod of each section beside it
/// (the other halves stay on the sections' backbone bodies, [`backbone`]) and
/// `loads.disk_mass`, if any.
pub(super) fn disk(robot: &Robot, k: usize) -> Body {
    if robot.has_disks() {
        return cylinder(
            disk_mass(robot),
            robot.disk_radius,
            robot.disk_thickness,
            &Vector3::z(),
            Vector3::zeros(),
        );
    }
    let n = robot.sections();
    let beside: f64 = [k, k + 1]
        .into_iter()
        .filter(|i| (1..=n).contains(i))
        .map(|i| rod_mass(robot, i) / 4.0)
        .sum();
    cylinder(
        beside + robot.loads.disk_mass,
        robot.backbone.radius(),
        0.0,
        &Vector3::z(),
        Vector3::zeros(),
    )
}

/// Mass of the backbone of section `i` \[kg\].
fn rod_mass(robot: &Robot, i: usize) -> f64 {
    let rho = if robot.backbone.density > 0.0 {
        robot.backbone.density
    } else {
        DEFAULT_BACKBONE_DENSITY
    };
    rho * robot.backbone.area() * robot.section_length(i)
}

/// The backbone of section `i` laid from `a` to `b` in a link frame (half of it for a rod
/// without spacer disks: its stations carry the other half, [`disk`]).
pub(super) fn backbone(robot: &Robot, i: usize, a: &Vector3<f64>, b: &Vector3<f64>) -> Body {
    let m = rod_mass(robot, i) * if robot.has_disks() { 1.0 } else { 0.5 };
    let d = b - a;
    let axis = if d.norm() > 0.0 { d } else { Vector3::z() };
    cylinder(m, robot.backbone.radius(), d.norm(), &axis, (a + b) / 2.0)
}

/// How many links of an articulated chain of `n` sections have their origin at disk `k`'s
/// centre (the disk link and the joint links around it; see the module docs).
pub(super) fn shares_at_disk(k: usize, n: usize, port: bool) -> usize {
    let before = if k >= 1 { 3 } else { 0 }; // chord_end, tilt_x_link, tilt_y_link
    let after = usize::from(k < n); // next section's bend_x_link
    let base = if k == 0 && port { 2 } else { 0 }; // port_insertion_link, port_rotation_link
    1 + before + after + base
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The parallel-axis combination of two point-like halves of a rod equals the rod's own
    /// inertia in the limit, and a cylinder's tensor is invariant to splitting it in two.
    #[test]
    fn a_cylinder_split_in_two_and_combined_is_the_cylinder() {
        let axis = Vector3::new(1.0, 2.0, -0.5).normalize();
        let whole = cylinder(2.0, 0.01, 0.3, &axis, Vector3::new(0.1, 0.0, 0.2));
        let c = Vector3::new(0.1, 0.0, 0.2);
        let h1 = cylinder(1.0, 0.01, 0.15, &axis, c - axis * 0.075);
        let h2 = cylinder(1.0, 0.01, 0.15, &axis, c + axis * 0.075);
        let both = h1.combine(&h2);
        assert!((both.mass - 2.0).abs() < 1e-15);
        assert!((both.com - whole.com).norm() < 1e-15);
        assert!((both.inertia - whole.inertia).amax() < 1e-15 * whole.inertia.amax() * 10.0);
    }

    #[test]
    fn shares_cover_every_link_at_a_disk() {
        // n = 3: disk 0 hosts bend_x of section 1; disks 1, 2 host five links; disk 3 four.
        assert_eq!(
            (0..=3)
                .map(|k| shares_at_disk(k, 3, false))
                .collect::<Vec<_>>(),
            vec![2, 5, 5, 4]
        );
    }
}
