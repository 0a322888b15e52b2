//! Fingerprints of what a file ccrkit writes was made for, so that reading it back with other
//! inputs is refused by name instead of believed: a stable 64-bit FNV-1a hash of the inputs'
//! canonical text (their `Debug` form: every field, numbers in Rust's shortest round-trip
//! form, no hash-map order), written as 16 hex digits.
//!
//! The hash detects a file used with inputs other than its own (a roadmap built for a robot
//! whose holes sit at 4.0 mm used with one at 4.5 mm); it is not a signature against a forger,
//! which is why the safety numbers such files hold (clearances, certificates) are recomputed
//! where they are read, never taken from the file.

use crate::error::ModelError;
use crate::method::run::SolveRequest;
use crate::model::scene::Scene;
use crate::robot::Robot;
use serde::{Deserialize, Serialize};
use std::fmt::{Debug, Write};

/// FNV-1a (64 bit) over the text written into it.
struct Fnv(u64);

impl Write for Fnv {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for b in s.bytes() {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
        Ok(())
    }
}

/// The fingerprint of `parts`' canonical text, in order, without building the text.
pub fn of_parts(parts: &[&dyn Debug]) -> String {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    for p in parts {
        // Writing into `Fnv` cannot fail.
        let _ = write!(h, "{p:?};");
    }
    format!("{:016x}", h.0)
}

/// A robot's fingerprint: every field that shapes it (disks, backbone, cables and their
/// routing, body, loads, port) and its name.
pub fn robot(robot: &Robot) -> String {
    of_parts(&[robot])
}

/// An actuation space's fingerprint: what its unknowns are (shortenings or tensions), the
/// cables' names, the limits of every unknown and the effort's scales.
pub fn space(space: &crate::reach::Space) -> String {
    of_parts(&[
        &space.input.name(),
        &space.cable_names(),
        &space.lo,
        &space.hi,
        &space.weights,
    ])
}

/// The obstacles' fingerprint: names, poses, bounds and the clearance.
pub fn scene(scene: &Scene) -> String {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    let _ = write!(h, "{:e};", scene.clearance);
    for o in &scene.obstacles {
        let _ = write!(h, "{}|{:?}|{:?};", o.name, o.pose, o.aabb);
    }
    format!("{:016x}", h.0)
}

/// What a written file was made for (a plan's `made_for`): the robot (name and fingerprint),
/// the obstacles' fingerprint, the margin kept, the method and its settings. Where the file is
/// read back with a model, [`MadeFor::check`] refuses it by name when the robot or the
/// obstacles differ.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MadeFor {
    /// Robot name.
    pub robot: String,
    /// The robot's fingerprint ([`robot`]).
    pub robot_fingerprint: String,
    /// The obstacles' fingerprint ([`scene`]): the model's and the request's, merged.
    pub scene_fingerprint: String,
    /// Margin kept from the obstacles \[m\].
    pub margin_m: f64,
    /// Method name.
    pub method: String,
    /// Its settings, `NAME=VALUE`.
    pub settings: Vec<String>,
    /// The actuation space's fingerprint ([`space`]): what its unknowns are (shortenings or
    /// tensions), the cables, their limits and the effort's scales. Written by reach answers
    /// and plans; absent from plans written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub space_fingerprint: Option<String>,
}

impl MadeFor {
    /// What a file made by `request` for `robot` among `scene` keeping `margin` \[m\] is for.
    pub fn new(robot: &Robot, scene: &Scene, margin: f64, request: &SolveRequest) -> MadeFor {
        MadeFor {
            robot: robot.name.clone(),
            robot_fingerprint: self::robot(robot),
            scene_fingerprint: self::scene(scene),
            margin_m: margin,
            method: request.method.name().into(),
            settings: request
                .settings
                .iter()
                .map(|(k, v)| format!("{k}={v}"))
                .collect(),
            space_fingerprint: None,
        }
    }

    /// What a file made in `space` (its robot, obstacles, margin and request) is for,
    /// with the space's fingerprint.
    pub fn of_space(space: &crate::reach::Space) -> MadeFor {
        MadeFor {
            space_fingerprint: Some(self::space(space)),
            ..MadeFor::new(&space.robot, &space.scene, space.margin, &space.request)
        }
    }

    /// Refused, with `field` (e.g. `made_for`) and the fingerprints in the reason, when the
    /// robot of `space` is not the one the file was made for, or the space is another (other
    /// unknowns — shortenings or tensions —, other limits or scales). The obstacles, the margin
    /// and the method are recorded but not required: a point of the space means the same
    /// actuation among other obstacles or solved by another method of the same input, and
    /// whatever is measured at it (clearance, tip) is measured again where it is used.
    pub fn check_space(&self, field: &str, space: &crate::reach::Space) -> Result<(), ModelError> {
        self.check_robot(field, &space.robot)?;
        let s = self::space(space);
        match &self.space_fingerprint {
            Some(f) if *f == s => Ok(()),
            f => Err(ModelError::invalid(
                format!("{field}.space_fingerprint"),
                format!(
                    "made for an actuation space with fingerprint {}; this request's {} space \
                     has {s} (shortenings or tensions, a cable's limits or the effort's scales \
                     differ): make it again with this model and method",
                    f.as_deref().unwrap_or("(none)"),
                    space.input.name()
                ),
            )),
        }
    }

    /// Refused, with `field` (e.g. `plan.made_for`) and the fingerprints in the reason, when
    /// `robot` or `scene` is not what the file was made for.
    pub fn check(&self, field: &str, robot: &Robot, scene: &Scene) -> Result<(), ModelError> {
        self.check_robot(field, robot)?;
        let s = self::scene(scene);
        if self.scene_fingerprint != s {
            return Err(ModelError::invalid(
                format!("{field}.scene_fingerprint"),
                format!(
                    "made among obstacles with fingerprint {}; these obstacles have {s} (an \
                     obstacle, its pose, or the clearance differs): make it again with this \
                     scene",
                    self.scene_fingerprint
                ),
            ));
        }
        Ok(())
    }

    /// Refused, naming `field.robot_fingerprint`, when `robot` is not the file's.
    pub fn check_robot(&self, field: &str, robot: &Robot) -> Result<(), ModelError> {
        let r = self::robot(robot);
        if self.robot_fingerprint != r {
            return Err(ModelError::invalid(
                format!("{field}.robot_fingerprint"),
                format!(
                    "made for robot `{}` with fingerprint {}; this model's robot `{}` has {r} \
                     (a hole, a disk, the backbone or a cable's routing differs): make it again \
                     for this robot",
                    self.robot, self.robot_fingerprint, robot.name
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FNV-1a's published test vectors (Fowler, Noll, Vo): "" and "a".
    #[test]
    fn the_hash_is_fnv_1a() {
        let mut h = Fnv(0xcbf2_9ce4_8422_2325);
        assert_eq!(h.0, 0xcbf2_9ce4_8422_2325);
        let _ = h.write_str("a");
        assert_eq!(h.0, 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn a_changed_hole_radius_changes_the_robot_fingerprint() {
        let text = std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/plan/two_segment.toml"),
        )
        .expect("model");
        let a = crate::Model::from_toml_str(&text).expect("parses");
        let mut b = a.robot.clone();
        assert_eq!(robot(&a.robot), robot(&b), "stable");
        b.cables[0].radius[1] *= 1.125;
        assert_ne!(robot(&a.robot), robot(&b));
    }
}
