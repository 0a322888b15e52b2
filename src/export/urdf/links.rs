//! Links, joints and geometry of the URDF: disks and backbone chords as cylinders with
//! materials, inertias, fixed joints, limits, number formatting. Visual and collision
//! elements get distinct names (`NAME_visual`, `NAME_collision`): MuJoCo refuses repeated names.

use super::frames::{rot_x, rpy_from_rotation};
use super::inertia;
use super::{UrdfOptions, CABLE_DIAMETER_FRACTION, CABLE_MIN_DIAMETER, MIN_CYLINDER_LENGTH};
use crate::model::robot::Robot;
use crate::shape::Shape;
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::f64::consts::PI;

pub(super) fn disk_link_name(k: usize) -> String {
    format!("disk_{k}")
}

pub(super) fn pose(xyz: [f64; 3], rpy: [f64; 3]) -> urdf_rs::Pose {
    // `+ 0.0` turns −0 into 0 (cosmetic: the text then reads `0`, not `-0`).
    urdf_rs::Pose {
        xyz: urdf_rs::Vec3(xyz.map(|v| v + 0.0)),
        rpy: urdf_rs::Vec3(rpy.map(|v| v + 0.0)),
    }
}

/// A number as XML attribute text that parses back to the same `f64` (shortest round trip;
/// scientific notation for tiny magnitudes instead of 20 leading zeros).
pub(super) fn num(v: f64) -> String {
    let v = v + 0.0;
    if v != 0.0 && v.abs() < 1e-4 {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

pub(super) fn limit(lower: f64, upper: f64) -> urdf_rs::JointLimit {
    urdf_rs::JointLimit {
        lower,
        upper,
        // Nominal: the exported chain is kinematic; planners need finite values here.
        effort: 1.0,
        velocity: 1.0,
        acceleration: f64::INFINITY,
        deceleration: f64::INFINITY,
        jerk: f64::INFINITY,
    }
}

pub(super) fn fixed_joint(
    name: &str,
    parent: &str,
    child: &str,
    xyz: &Vector3<f64>,
    rot: &Matrix3<f64>,
) -> urdf_rs::Joint {
    urdf_rs::Joint {
        name: name.into(),
        joint_type: urdf_rs::JointType::Fixed,
        origin: pose([xyz.x, xyz.y, xyz.z], rpy_from_rotation(rot)),
        parent: urdf_rs::LinkName {
            link: parent.into(),
        },
        child: urdf_rs::LinkName { link: child.into() },
        axis: urdf_rs::Axis {
            xyz: urdf_rs::Vec3([0.0, 0.0, 1.0]),
        },
        limit: limit(0.0, 0.0),
        calibration: None,
        dynamics: None,
        mimic: None,
        safety_controller: None,
    }
}

/// A link without geometry carrying `body`'s mass.
pub(super) fn mass_link(name: &str, body: inertia::Body) -> urdf_rs::Link {
    let mut link = empty_link(name);
    link.inertial = body.to_urdf();
    link
}

pub(super) fn empty_link(name: &str) -> urdf_rs::Link {
    urdf_rs::Link {
        name: name.into(),
        inertial: zero_inertial(),
        visual: vec![],
        collision: vec![],
    }
}

pub(super) fn zero_inertial() -> urdf_rs::Inertial {
    urdf_rs::Inertial {
        origin: pose([0.0; 3], [0.0; 3]),
        mass: urdf_rs::Mass { value: 0.0 },
        inertia: urdf_rs::Inertia {
            ixx: 0.0,
            ixy: 0.0,
            ixz: 0.0,
            iyy: 0.0,
            iyz: 0.0,
            izz: 0.0,
        },
    }
}

pub(super) fn material(name: &str, rgba: [f64; 4]) -> urdf_rs::Material {
    urdf_rs::Material {
        name: name.into(),
        color: Some(urdf_rs::Color {
            rgba: urdf_rs::Vec4(rgba),
        }),
        texture: None,
    }
}

pub(super) fn disk_material() -> urdf_rs::Material {
    material("ccrkit_disk", [0.85, 0.65, 0.2, 1.0])
}

pub(super) fn backbone_material() -> urdf_rs::Material {
    material("ccrkit_backbone", [0.25, 0.25, 0.3, 1.0])
}

pub(super) fn cable_material() -> urdf_rs::Material {
    material("ccrkit_cable", [0.1, 0.35, 0.9, 1.0])
}

/// Add a cylinder (visual, and collision when `collide`) from `a` to `b` in the link frame.
pub(super) fn add_cylinder(
    link: &mut urdf_rs::Link,
    name: &str,
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    radius: f64,
    mat: &urdf_rs::Material,
    collide: bool,
) {
    let d = b - a;
    let length = d.norm();
    if length <= MIN_CYLINDER_LENGTH {
        return;
    }
    // URDF cylinders lie along their local z.
    let rot = Rotation3::rotation_between(&Vector3::z(), &d)
        .map(|r| r.into_inner())
        .unwrap_or_else(|| rot_x(PI));
    let mid = (a + b) / 2.0;
    let origin = pose([mid.x, mid.y, mid.z], rpy_from_rotation(&rot));
    let geometry = urdf_rs::Geometry::Cylinder { radius, length };
    link.visual.push(urdf_rs::Visual {
        name: Some(format!("{name}_visual")),
        origin: origin.clone(),
        geometry: geometry.clone(),
        material: Some(mat.clone()),
    });
    if collide {
        link.collision.push(urdf_rs::Collision {
            name: Some(format!("{name}_collision")),
            origin,
            geometry,
        });
    }
}

/// Link of disk `k`: the disk cylinder, the backbone of section `k` when `backbone_to_prev`
/// (the previous disk's position in this disk's frame) is given, and the cable chords; it
/// carries the fraction `disk_share` of the disk's mass and inertia (see [`inertia`]) and the
/// backbone it draws.
pub(super) fn disk_link(
    robot: &Robot,
    shape: &Shape,
    k: usize,
    opts: &UrdfOptions,
    backbone_to_prev: Option<Vector3<f64>>,
    disk_share: f64,
) -> urdf_rs::Link {
    let name = disk_link_name(k);
    let mut link = empty_link(&name);
    let (r, h) = (robot.disk_radius, robot.disk_thickness);
    let mut body = inertia::disk(robot, k).scaled(disk_share);
    if let Some(prev) = backbone_to_prev {
        body = body.combine(&inertia::backbone(robot, k, &Vector3::zeros(), &prev));
    }
    link.inertial = body.to_urdf();
    if robot.has_disks() {
        let half = Vector3::new(0.0, 0.0, h / 2.0);
        add_cylinder(&mut link, &name, &-half, &half, r, &disk_material(), true);
    }
    if let Some(prev) = backbone_to_prev {
        add_cylinder(
            &mut link,
            &format!("section_{k}_backbone"),
            &Vector3::zeros(),
            &prev,
            robot.body_radius(),
            &backbone_material(),
            true,
        );
    }
    if opts.cables && k >= 1 {
        let (prev, here) = (&shape.disks[k - 1], &shape.disks[k]);
        let radius =
            (robot.backbone.diameter * CABLE_DIAMETER_FRACTION).max(CABLE_MIN_DIAMETER) / 2.0;
        for cable in robot.cables.iter().filter(|c| c.reaches_section(k)) {
            let a = cable.hole(k);
            let hole_prev = prev.position + prev.rotation * cable.hole(k - 1);
            let b = here.rotation.transpose() * (hole_prev - here.position);
            add_cylinder(
                &mut link,
                &format!("cable_{}_section_{k}", cable.name),
                &a,
                &b,
                radius,
                &cable_material(),
                true,
            );
        }
    }
    link
}
