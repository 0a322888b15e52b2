//! What a shape read from a file must be before it is believed ([`super::ShapeJson::into_shape`]):
//! every number finite, every coordinate within ±[`MAX_EXTENT`], every disk rotation a
//! rotation (a rotation of `5·I` or a mirror was drawn), every cable no longer than the disks it
//! can pass and slack only in sections the shape has, every contact's numbers finite and its
//! points within the extent. Errors name the field (`waypoints[3].shape.disks[2].rotation`).

use super::Contact;
use crate::error::ModelError;
use crate::model::bounds;
use nalgebra::Matrix3;

/// Largest coordinate of a point of a shape read from a file \[m\]: a model's
/// coordinates lie within ±1 km ([`bounds::COORDINATE`]), its obstacles are at most 1 km
/// ([`bounds::OBSTACLE_SIZE`]) and its robot at most 100 m long ([`bounds::ROBOT_LENGTH`]).
pub const MAX_EXTENT: f64 =
    bounds::COORDINATE.hi + bounds::OBSTACLE_SIZE.hi + bounds::ROBOT_LENGTH.hi;

/// `p` (named `field`) is finite and each coordinate within ±[`MAX_EXTENT`].
pub(super) fn point(p: &[f64; 3], field: impl Fn() -> String) -> Result<(), ModelError> {
    if p.iter().any(|x| !x.is_finite()) {
        return Err(ModelError::invalid(field(), "numbers must be finite"));
    }
    let d = p.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if d > MAX_EXTENT {
        return Err(ModelError::invalid(
            field(),
            format!(
                "has a coordinate of {d:e} m; a shape lies within ±{MAX_EXTENT} m of the origin \
                 (coordinates within ±1 km, obstacles and robots smaller)"
            ),
        ));
    }
    Ok(())
}

/// `r` (named `field`) is a rotation.
pub(super) fn rotation(r: &Matrix3<f64>, field: impl Fn() -> String) -> Result<(), ModelError> {
    match crate::numeric::so3::rotation_defect(r) {
        Some(why) => Err(ModelError::invalid(field(), why)),
        None => Ok(()),
    }
}

/// A cable of `points` holes and slack in `slack_sections` fits a shape of `disks` disks.
pub(super) fn cable(
    points: usize,
    slack_sections: &[usize],
    disks: usize,
    field: &str,
) -> Result<(), ModelError> {
    if points == 0 || points > disks {
        return Err(ModelError::invalid(
            format!("{field}.points"),
            format!("has {points} holes; a cable passes 1 to {disks} disks (the shape's)"),
        ));
    }
    if let Some(s) = slack_sections.iter().find(|&&s| s == 0 || s >= disks) {
        return Err(ModelError::invalid(
            format!("{field}.slack_sections"),
            format!(
                "names section {s}; the shape has sections 1 to {}",
                disks - 1
            ),
        ));
    }
    Ok(())
}

/// Contact `c` (named `field`): finite numbers, points within the extent, a normal no longer
/// than a unit.
pub(super) fn contact(c: &Contact, field: &str) -> Result<(), ModelError> {
    point(&c.point_robot, || format!("{field}.point_robot"))?;
    point(&c.point_obstacle, || format!("{field}.point_obstacle"))?;
    let n = &c.normal;
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if !len.is_finite() || len > 1.0 + 1e-6 {
        return Err(ModelError::invalid(
            format!("{field}.normal"),
            format!("has length {len}; a normal is a unit vector"),
        ));
    }
    if !(c.distance.is_finite() && c.distance.abs() <= MAX_EXTENT) {
        return Err(ModelError::invalid(
            format!("{field}.distance"),
            format!(
                "{} is not a finite distance within {MAX_EXTENT} m",
                c.distance
            ),
        ));
    }
    if !c.multiplier.is_finite() {
        return Err(ModelError::invalid(
            format!("{field}.multiplier"),
            format!("{} is not finite", c.multiplier),
        ));
    }
    Ok(())
}
