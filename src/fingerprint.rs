//! Fingerprints of what a file ccrkit writes was made for, so that reading it back with other
//! inputs is refused by name instead of believed: a stable 64-bit FNV-1a hash of the inputs'
//! canonical form, written as 16 hex digits.
//!
//! The canonical form is written here field by field, never taken from a `Debug` form or a
//! struct's layout: each field as `key=value;` in the fixed order of the functions below,
//! numbers as the bits of their IEEE-754 double (`-0` as `0`), texts as their length and
//! bytes, a list as its length and items, an absent option as `-`. So reordering a struct's
//! fields, renaming a Rust type or changing how `Debug` prints a number changes no fingerprint;
//! a field added to [`Robot`] is a compile error in [`robot`] until it is listed there, and is
//! to be written only where it differs from its default, so that files made before it stay
//! valid. What each fingerprint covers is listed in the guide (`docs/guide/files.md`).
//!
//! The hash detects a file used with inputs other than its own (a roadmap built for a robot
//! whose holes sit at 4.0 mm used with one at 4.5 mm); it is not a signature against a forger,
//! which is why the safety numbers such files hold (clearances, certificates) are recomputed
//! where they are read, never taken from the file.

use crate::error::ModelError;
use crate::method::run::SolveRequest;
use crate::model::robot::{Backbone, Body, Cable, Loads};
use crate::model::scene::Scene;
use crate::robot::Robot;
use nalgebra::{Isometry3, Vector3};
use serde::{Deserialize, Serialize};
use std::fmt::Write;

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

/// The canonical form of the module docs, hashed as it is written.
struct Canon(Fnv);

impl Canon {
    fn new() -> Canon {
        Canon(Fnv(0xcbf2_9ce4_8422_2325))
    }

    /// `key=` (writing into `Fnv` cannot fail).
    fn key(&mut self, key: &str) -> &mut Self {
        let _ = write!(self.0, "{key}=");
        self
    }

    fn raw(&mut self, v: f64) {
        let v = if v == 0.0 { 0.0 } else { v };
        let _ = write!(self.0, "{:016x},", v.to_bits());
    }

    fn num(&mut self, key: &str, v: f64) -> &mut Self {
        self.key(key).raw(v);
        self.end()
    }

    fn nums(&mut self, key: &str, v: &[f64]) -> &mut Self {
        let _ = write!(self.key(key).0, "{}:", v.len());
        v.iter().for_each(|x| self.raw(*x));
        self.end()
    }

    fn vec3(&mut self, key: &str, v: &Vector3<f64>) -> &mut Self {
        self.nums(key, v.as_slice())
    }

    fn opt(&mut self, key: &str, v: Option<f64>) -> &mut Self {
        match v {
            Some(x) => self.num(key, x),
            None => self.text(key, "-"),
        }
    }

    fn count(&mut self, key: &str, n: usize) -> &mut Self {
        let _ = write!(self.key(key).0, "{n}");
        self.end()
    }

    fn text(&mut self, key: &str, t: &str) -> &mut Self {
        let _ = write!(self.key(key).0, "{}:{t}", t.len());
        self.end()
    }

    /// A pose: the translation, then the rotation's unit quaternion `w, x, y, z` with `w ≥ 0`
    /// (`q` and `−q` are one rotation).
    fn pose(&mut self, key: &str, p: &Isometry3<f64>) -> &mut Self {
        let q = p.rotation.coords;
        let s = if q.w < 0.0 { -1.0 } else { 1.0 };
        let t = p.translation.vector;
        self.nums(key, &[t.x, t.y, t.z, s * q.w, s * q.x, s * q.y, s * q.z])
    }

    fn end(&mut self) -> &mut Self {
        let _ = self.0.write_str(";");
        self
    }

    fn finish(&self) -> String {
        format!("{:016x}", self.0 .0)
    }
}

/// A robot's fingerprint: its name, the disks (arc positions, radius, thickness), the backbone
/// (E, ν, diameters, density, stiffening), every cable (name, tied disk, hole radii and angles,
/// helix, stiffness, pretension), the body (where the tendons run, spacer disks, collision
/// radius), the loads and the port's pose.
pub fn robot(robot: &Robot) -> String {
    // Every field named: a new one does not compile until it is decided here.
    let Robot {
        name,
        disk_s,
        disk_radius,
        disk_thickness,
        backbone,
        cables,
        body,
        loads,
        port,
    } = robot;
    let mut c = Canon::new();
    c.text("name", name)
        .nums("disk_s", disk_s)
        .num("disk_radius", *disk_radius)
        .num("disk_thickness", *disk_thickness);
    let Backbone {
        youngs_modulus,
        poisson_ratio,
        diameter,
        inner_diameter,
        density,
        stiffening,
    } = backbone;
    c.num("backbone.youngs_modulus", *youngs_modulus)
        .num("backbone.poisson_ratio", *poisson_ratio)
        .num("backbone.diameter", *diameter)
        .num("backbone.inner_diameter", *inner_diameter)
        .num("backbone.density", *density)
        .num("backbone.stiffening", *stiffening);
    c.count("cables", cables.len());
    for cable in cables {
        let Cable {
            name,
            ends_at,
            radius,
            angle,
            helix,
            stiffness,
            pretension,
        } = cable;
        c.text("cable.name", name)
            .count("cable.ends_at", *ends_at)
            .nums("cable.radius", radius)
            .nums("cable.angle", angle)
            .opt("cable.helix.start", helix.map(|h| h.start))
            .opt("cable.helix.per_metre", helix.map(|h| h.per_metre))
            .opt("cable.stiffness", *stiffness)
            .num("cable.pretension", *pretension);
    }
    let Body {
        tendons,
        no_spacer_disks,
        collision_radius,
    } = body;
    let Loads {
        gravity,
        disk_mass,
        tip_force,
        tip_moment,
    } = loads;
    let spacer_disks = if *no_spacer_disks { "no" } else { "yes" };
    c.text("body.tendons", tendons.name())
        .text("body.spacer_disks", spacer_disks)
        .opt("body.collision_radius", *collision_radius)
        .vec3("loads.gravity", gravity)
        .num("loads.disk_mass", *disk_mass)
        .vec3("loads.tip_force", tip_force)
        .vec3("loads.tip_moment", tip_moment);
    match port {
        Some(p) => c.pose("port", &p.pose),
        None => c.text("port", "-"),
    };
    c.finish()
}

/// An actuation space's fingerprint: what its unknowns are (shortenings or tensions), the
/// cables' names, the limits of every unknown and the effort's scales.
pub fn space(space: &crate::reach::Space) -> String {
    let mut c = Canon::new();
    c.text("input", space.input.name());
    let names = space.cable_names();
    c.count("cables", names.len());
    for n in &names {
        c.text("cable", n);
    }
    c.nums("lo", space.lo.as_slice())
        .nums("hi", space.hi.as_slice())
        .nums("weights", space.weights.as_slice());
    c.finish()
}

/// The obstacles' fingerprint: the clearance, then each obstacle's name, pose and bounds.
pub fn scene(scene: &Scene) -> String {
    let mut c = Canon::new();
    c.num("clearance", scene.clearance)
        .count("obstacles", scene.obstacles.len());
    for o in &scene.obstacles {
        c.text("obstacle.name", &o.name)
            .pose("obstacle.pose", &o.pose)
            .vec3("obstacle.aabb.min", &o.aabb.0)
            .vec3("obstacle.aabb.max", &o.aabb.1);
    }
    c.finish()
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

    fn two_segment() -> String {
        let p =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/plan/two_segment.toml");
        std::fs::read_to_string(p).expect("model")
    }

    /// The canonical form is fixed: the two-segment planning robot's fingerprint is the value
    /// recorded when the form was written (a change here invalidates every roadmap, plan and
    /// reach answer written before: only on purpose), and it does not depend on the order of
    /// the file's fields.
    #[test]
    fn the_robot_fingerprint_matches_its_recorded_value_in_any_field_order() {
        let text = two_segment();
        let a = crate::Model::from_toml_str(&text).expect("parses");
        assert_eq!(robot(&a.robot), RECORDED_TWO_SEGMENT);
        let reordered = text
            .replace(
                "backbone = { youngs_modulus = 5e+10, poisson_ratio = 0.3, diameter = 0.001 }",
                "backbone = { diameter = 0.001, poisson_ratio = 0.3, youngs_modulus = 5e+10 }",
            )
            .replace(
                "disk_radius = 0.0055\ndisk_thickness = 0.001\n",
                "disk_thickness = 0.001\ndisk_radius = 0.0055\n",
            );
        assert_ne!(reordered, text, "the file's fields were reordered");
        let b = crate::Model::from_toml_str(&reordered).expect("parses");
        assert_eq!(robot(&b.robot), RECORDED_TWO_SEGMENT);
    }

    const RECORDED_TWO_SEGMENT: &str = "9d6ff0abbb67bb6a";

    /// Each field the canonical form lists moves the fingerprint, and a changed hole radius is
    /// refused by name where a file is read back.
    #[test]
    fn a_changed_field_changes_the_fingerprint_and_a_changed_hole_radius_is_refused() {
        let a = crate::Model::from_toml_str(&two_segment())
            .expect("parses")
            .robot;
        let changed: [&dyn Fn(&mut Robot); 6] = [
            &|r| r.cables[0].radius[1] *= 1.125,
            &|r| r.cables[1].angle[2] += 1e-9,
            &|r| r.backbone.youngs_modulus *= 2.0,
            &|r| r.disk_s[3] += 1e-6,
            &|r| r.body.collision_radius = Some(0.004),
            &|r| r.loads.tip_force.x = 0.1,
        ];
        for (k, change) in changed.iter().enumerate() {
            let mut b = a.clone();
            change(&mut b);
            assert_ne!(robot(&a), robot(&b), "change {k}");
        }
        let made = MadeFor {
            robot: a.name.clone(),
            robot_fingerprint: robot(&a),
            scene_fingerprint: scene(&Scene::default()),
            margin_m: 0.0,
            method: "geometric".into(),
            settings: vec![],
            space_fingerprint: None,
        };
        assert!(made.check_robot("made_for", &a).is_ok());
        let mut b = a.clone();
        b.cables[0].radius[1] = 0.004;
        let e = made.check_robot("made_for", &b).expect_err("refused");
        assert!(e.to_string().contains("made_for.robot_fingerprint"), "{e}");
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
