//! Physical ranges of every model input: a value outside its range is refused with
//! [`ModelError::Invalid`] naming the field, the range and the unit.
//!
//! The ranges are deliberately wide (from micro-robots to metre-scale manipulators, from
//! silicone to diamond) and exist so that no input can push a solver into overflow: with
//! `section_length = 1e308` the literal method used to exit 0 with `null` coordinates
//! before these bounds. A range is a promise that every product ccrkit forms (EI = E·π d⁴/64,
//! tension × radius, lengths summed over [`super::MAX_SECTIONS`] sections) stays far from the
//! limits of `f64`.

use crate::error::ModelError;

/// An inclusive range `[lo, hi]` with its unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Smallest accepted value.
    pub lo: f64,
    /// Largest accepted value.
    pub hi: f64,
    /// SI unit, for messages.
    pub unit: &'static str,
}

impl Range {
    /// `v` when it is finite and inside the range, else an error naming `field`.
    pub fn check(&self, field: &str, v: f64) -> Result<f64, ModelError> {
        if self.accepts(v) {
            Ok(v)
        } else {
            Err(ModelError::invalid(
                field,
                format!(
                    "must lie in [{:e}, {:e}] {} (the physical range ccrkit accepts), got {v:e}",
                    self.lo, self.hi, self.unit
                ),
            ))
        }
    }

    /// True when `v` is finite and inside the range.
    pub fn accepts(&self, v: f64) -> bool {
        v.is_finite() && v >= self.lo && v <= self.hi
    }

    /// Each component of `v` checked against the range (`field[k]` in the error).
    pub fn check3(&self, field: &str, v: [f64; 3]) -> Result<[f64; 3], ModelError> {
        for (k, x) in v.iter().enumerate() {
            // The field name is formatted only for the error (scenes check thousands).
            if !self.accepts(*x) {
                self.check(&format!("{field}[{k}]"), *x)?;
            }
        }
        Ok(v)
    }
}

const fn range(lo: f64, hi: f64, unit: &'static str) -> Range {
    Range { lo, hi, unit }
}

/// Length of one section (disk spacing): 1 µm to 10 m.
pub const SECTION_LENGTH: Range = range(1e-6, 10.0, "m");
/// Whole backbone length: at most 100 m.
pub const ROBOT_LENGTH: Range = range(1e-6, 100.0, "m");
/// Disk radius: 1 µm to 1 m.
pub const DISK_RADIUS: Range = range(1e-6, 1.0, "m");
/// Disk thickness: 0.1 µm to 1 m (and less than the shortest section).
pub const DISK_THICKNESS: Range = range(1e-7, 1.0, "m");
/// Backbone diameter: 0.1 µm to 2 m (and less than the disk diameter).
pub const DIAMETER: Range = range(1e-7, 2.0, "m");
/// Young's modulus: 1 kPa (soft gels) to 10 TPa (ten times diamond).
pub const YOUNGS_MODULUS: Range = range(1e3, 1e13, "Pa");
/// Backbone density: 0 (weightless) to 10⁵ kg/m³ (four times osmium).
pub const DENSITY: Range = range(0.0, 1e5, "kg/m^3");
/// Each component of gravity: |g| up to 1000 m/s² (100 g).
pub const GRAVITY: Range = range(-1e3, 1e3, "m/s^2");
/// Mass of one disk: 0 to 1000 kg.
pub const DISK_MASS: Range = range(0.0, 1e3, "kg");
/// Each component of the tip force: up to 1 MN.
pub const TIP_FORCE: Range = range(-1e6, 1e6, "N");
/// Each component of the tip moment: up to 100 kN m.
pub const TIP_MOMENT: Range = range(-1e5, 1e5, "N m");
/// Cable tension: 0 to 1 MN (cables pull, they do not push).
pub const TENSION: Range = range(0.0, 1e6, "N");
/// Axial stiffness of a cable in series with its actuator: 1 mN/m to 1 TN/m.
pub const CABLE_STIFFNESS: Range = range(1e-3, 1e12, "N/m");
/// A hole angle (unwrapped): |a| up to 10⁵ rad (covers 10 000 disks turning 2π each).
pub const ANGLE: Range = range(-1e5, 1e5, "rad");
/// A helix's turn per disk: at most one full turn either way.
pub const HELIX_PER_DISK: Range = range(
    -2.0 * std::f64::consts::PI,
    2.0 * std::f64::consts::PI,
    "rad",
);
/// A helix's turn per metre of arc: up to 10⁶ rad/m (a turn per 6 µm).
pub const HELIX_PER_METRE: Range = range(-1e6, 1e6, "rad/m");
/// Obstacle position components: within 1 km of the base.
pub const COORDINATE: Range = range(-1e3, 1e3, "m");
/// Obstacle sizes (radius, half extents, half height): 1 nm to 1 km.
pub const OBSTACLE_SIZE: Range = range(1e-9, 1e3, "m");
/// Mesh scale factors: 10⁻⁹ to 10⁶ (vertices must still land within [`COORDINATE`]).
pub const MESH_SCALE: Range = range(1e-9, 1e6, "-");
/// Clearance kept from obstacles: 0 to 1 m (a scene's `clearance`, and the `margin` of
/// `reach`, `plan` and roadmaps).
pub const CLEARANCE: Range = range(0.0, 1.0, "m");
/// A tip distance asked for: the tolerance of `auto`, of `reach`, of `study auto`, and the
/// distance at which `compare` flags two methods. From a picometre (the round-off of a tip
/// on the longest backbone, 100 m × 1e-14, lies below it) to the longest backbone
/// ([`ROBOT_LENGTH`]): beyond it every answer is within, and `1e308` m was printed as
/// `inf mm`.
pub const TIP_DISTANCE: Range = range(1e-12, 100.0, "m");
/// Most cables in one model (each method may refuse fewer, by name).
pub const MAX_CABLES: usize = 256;

/// A robot's cable count within [`MAX_CABLES`], or the error that names `cables`.
pub fn check_cable_count(n: usize) -> Result<(), ModelError> {
    if n > MAX_CABLES {
        return Err(ModelError::invalid(
            "cables",
            format!("at most {MAX_CABLES} cables, got {n}"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_name_the_field_and_refuse_non_finite_values() {
        for v in [f64::NAN, f64::INFINITY, -f64::INFINITY, 1e308, -1.0, 0.0] {
            let e = SECTION_LENGTH.check("robot.section_length", v).unwrap_err();
            assert_eq!(e.field(), Some("robot.section_length"), "{v}");
            assert!(e.to_string().contains("m (the physical range"), "{e}");
        }
        assert_eq!(SECTION_LENGTH.check("x", 0.02), Ok(0.02));
        assert_eq!(DENSITY.check("x", 0.0), Ok(0.0));
        let e = GRAVITY
            .check3("loads.gravity", [0.0, 0.0, -1e9])
            .unwrap_err();
        assert_eq!(e.field(), Some("loads.gravity[2]"));
    }
}
