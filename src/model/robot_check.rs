//! What makes a [`Robot`] valid, checked on the robot itself: the one check every robot passes
//! before a method sees it, whatever way it was built — read from a model file (which checks
//! its own spellings first, then this) or written in code (a struct literal, or a file's
//! robot with a field changed). The solve path runs it ([`crate::method::Method::solve`] and
//! [`crate::method::Method::prepare`], behind every [`crate::method::Solver`]), so a robot a
//! method cannot stand behind is refused by field, never solved into a NaN or a panic.
//!
//! Fields are named as in a model file (`robot.disk_radius`, `robot.backbone.diameter`,
//! `cables[1].radius[3]`, `loads.gravity[2]`, `port.position`); the ranges are
//! [`super::bounds`]'s.

use super::bounds;
use super::robot::{Backbone, Body, Cable, Loads, Robot, Tendons, MAX_STIFFENING};
use super::MAX_SECTIONS;
use crate::error::ModelError;
use nalgebra::Vector3;

impl Robot {
    /// Every rule a robot keeps (module docs): `1..=MAX_SECTIONS` sections with
    /// `disk_s[0] = 0` and each section length in [`bounds::SECTION_LENGTH`], the whole in
    /// [`bounds::ROBOT_LENGTH`]; disks in range and thinner than the shortest section; the
    /// backbone ([`Backbone::check`]) inside the disks; at most [`bounds::MAX_CABLES`]
    /// cables with distinct, non-empty names, each with a hole per disk it passes inside the
    /// disk and outside the backbone (in the rod's wall with cables inside the rod, [`Body`]),
    /// angles and compliance in range; a body that holds together ([`Body::check`]); loads
    /// ([`Loads::check`]); a port placed within [`bounds::COORDINATE`].
    ///
    /// ```
    /// use ccrkit::prelude::*;
    ///
    /// let mut robot = Model::from_file("models/paper/case1.toml")?.robot;
    /// assert!(robot.check().is_ok());
    /// robot.cables[0].radius[3] = 0.5; // beyond the 12 mm disk
    /// let e = robot.check().unwrap_err();
    /// assert_eq!(e.field(), Some("cables[0].radius[3]"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn check(&self) -> Result<(), ModelError> {
        let n = self.disk_s.len().saturating_sub(1);
        if !(1..=MAX_SECTIONS).contains(&n) {
            return Err(ModelError::invalid(
                "robot.sections",
                format!(
                    "must be between 1 and {MAX_SECTIONS} (disk_s holds n + 1 arc lengths), got {n}"
                ),
            ));
        }
        if self.disk_s[0] != 0.0 {
            return Err(ModelError::invalid(
                "robot.disk_s[0]",
                format!("the base disk sits at s = 0, got {}", self.disk_s[0]),
            ));
        }
        let mut shortest = f64::INFINITY;
        for i in 1..=n {
            let l = self.disk_s[i] - self.disk_s[i - 1];
            named(
                || format!("robot.section_lengths[{}]", i - 1),
                |f| bounds::SECTION_LENGTH.check(f, l),
            )?;
            shortest = shortest.min(l);
        }
        bounds::ROBOT_LENGTH.check("robot.section_lengths", self.length())?;
        if self.has_disks() {
            bounds::DISK_RADIUS.check("robot.disk_radius", self.disk_radius)?;
            bounds::DISK_THICKNESS.check("robot.disk_thickness", self.disk_thickness)?;
            if self.disk_thickness >= shortest {
                return Err(ModelError::invalid(
                    "robot.disk_thickness",
                    format!(
                        "{} m is not smaller than the shortest section ({shortest} m)",
                        self.disk_thickness
                    ),
                ));
            }
        }
        self.body.check()?;
        let room = if self.has_disks() {
            self.disk_radius
        } else {
            f64::INFINITY
        };
        self.backbone.check(room)?;
        self.loads.check()?;
        bounds::check_cable_count(self.cables.len())?;
        for (ci, c) in self.cables.iter().enumerate() {
            if self.cables[..ci].iter().any(|o| o.name == c.name) {
                return Err(ModelError::invalid(
                    format!("cables[{ci}].name"),
                    format!("two cables are named `{}`", c.name),
                ));
            }
            self.check_cable(ci)?;
        }
        if let Some(p) = &self.port {
            let t = p.pose.translation.vector;
            bounds::COORDINATE.check3("port.position", [t.x, t.y, t.z])?;
            let q = p.pose.rotation.coords;
            if !(q.iter().all(|x| x.is_finite()) && (q.norm() - 1.0).abs() <= 1e-9) {
                return Err(ModelError::invalid(
                    "port.orientation",
                    format!("must be a rotation (a finite unit quaternion), got {q:?}"),
                ));
            }
        }
        Ok(())
    }

    /// Cable `ci`'s rules (see [`Robot::check`]).
    fn check_cable(&self, ci: usize) -> Result<(), ModelError> {
        let c: &Cable = &self.cables[ci];
        let f = |name: &str| format!("cables[{ci}].{name}");
        named(
            || f("name"),
            |field| super::name::check_name(field, &c.name),
        )?;
        let n = self.sections();
        if !(1..=n).contains(&c.ends_at) {
            return Err(ModelError::invalid(
                f("ends_at"),
                format!("must be a disk between 1 and {n}, got {}", c.ends_at),
            ));
        }
        let count = c.ends_at + 1;
        for (what, len) in [("radius", c.radius.len()), ("angles", c.angle.len())] {
            if len != count {
                return Err(ModelError::invalid(
                    f(what),
                    format!(
                        "needs one value per disk the cable passes (0..={}: {count}), got {len}",
                        c.ends_at
                    ),
                ));
            }
        }
        for (k, r) in c.radius.iter().enumerate() {
            named(
                || f(&format!("radius[{k}]")),
                |field| hole_radius(field, *r, self),
            )?;
        }
        for (k, a) in c.angle.iter().enumerate() {
            named(
                || f(&format!("angles[{k}]")),
                |field| bounds::ANGLE.check(field, *a),
            )?;
        }
        if let Some(h) = &c.helix {
            named(
                || f("angles.helix.start"),
                |field| bounds::ANGLE.check(field, h.start),
            )?;
            named(
                || f("angles.helix.per_metre"),
                |field| bounds::HELIX_PER_METRE.check(field, h.per_metre),
            )?;
        }
        if let Some(k) = c.stiffness {
            named(
                || f("stiffness"),
                |field| bounds::CABLE_STIFFNESS.check(field, k),
            )?;
        }
        // A pretension of 0 is none (the struct's default).
        if c.pretension == 0.0 {
            return Ok(());
        }
        named(
            || f("pretension"),
            |field| {
                pretension(
                    field,
                    Some(c.pretension),
                    c.stiffness,
                    self.undeformed_chord_length(ci),
                )
            },
        )
    }
}

/// `check` run with an empty field name and, only if it refuses, again with the name
/// `field()` formatted: a valid robot (every solve checks one, [`Robot::check`]) formats no
/// field names. `check` must decide the same both times (a pure check of the value).
fn named<T>(
    field: impl FnOnce() -> String,
    check: impl Fn(&str) -> Result<T, ModelError>,
) -> Result<T, ModelError> {
    match check("") {
        Ok(v) => Ok(v),
        Err(_) => check(&field()),
    }
}

/// A hole radius `r` \[m\] of `robot` (only its disks, backbone and body are read): positive;
/// with cables through the disks ([`Tendons::Disks`]) inside the disk and outside the backbone,
/// with cables inside the rod ([`Tendons::Inside`]) inside the rod and outside a tube's bore
/// (`field` names it in the error). The file's cables and [`Robot::check`] both ask this.
pub(super) fn hole_radius(field: &str, r: f64, robot: &Robot) -> Result<f64, ModelError> {
    super::file::positive(field, r)?;
    let (rod, bore) = (robot.backbone.radius(), robot.backbone.inner_radius());
    if robot.has_disks() && r >= robot.disk_radius {
        return Err(ModelError::invalid(
            field,
            format!(
                "hole radius {r} m lies beyond the disk (radius {} m)",
                robot.disk_radius
            ),
        ));
    }
    match robot.body.tendons {
        Tendons::Disks if r <= rod => Err(ModelError::invalid(
            field,
            format!(
                "hole radius {r} m lies inside the backbone (radius {rod} m); a cable that runs \
                 inside the rod needs `robot.tendons = \"inside\"`"
            ),
        )),
        Tendons::Inside if r >= rod => Err(ModelError::invalid(
            field,
            format!(
                "hole radius {r} m lies outside the rod (radius {rod} m), but `robot.tendons = \
                 \"inside\"` routes every cable inside it"
            ),
        )),
        Tendons::Inside if r <= bore => Err(ModelError::invalid(
            field,
            format!(
                "hole radius {r} m lies in the tube's bore (inner radius {bore} m); a cable \
                 inside the rod runs in its wall"
            ),
        )),
        _ => Ok(r),
    }
}

/// A pretension `t` \[N\] (`None`: none given) of a cable of stiffness `k` and undeformed
/// length `len`: only with a stiffness, in [`bounds::TENSION`], stretching the cable by less
/// than its length. The file's cables and [`Robot::check`] both ask this.
pub(super) fn pretension(
    field: &str,
    t: Option<f64>,
    k: Option<f64>,
    len: f64,
) -> Result<(), ModelError> {
    match (t, k) {
        (None, _) => Ok(()),
        (Some(_), None) => Err(ModelError::invalid(
            field,
            "a pretension needs the cable's `stiffness` (it is the tension of a cable tied stretched by pretension/stiffness)",
        )),
        (Some(t), Some(k)) => {
            let t = bounds::TENSION.check(field, t)?;
            if t / k >= len {
                return Err(ModelError::invalid(
                    field,
                    format!(
                        "stretches the cable by {:e} m, not less than its length {len:.6} m",
                        t / k
                    ),
                ));
            }
            Ok(())
        }
    }
}

impl Backbone {
    /// The backbone's rules (fields named `robot.backbone.*`): Young's modulus in
    /// [`bounds::YOUNGS_MODULUS`], Poisson's ratio in (−1, 0.5], the diameter in
    /// [`bounds::DIAMETER`] and inside disks of radius `disk_radius` (infinite: no spacer
    /// disks), a tube's inner diameter in `[0, diameter)`, the density in
    /// [`bounds::DENSITY`], the curvature stiffening in `[0, MAX_STIFFENING]`.
    pub fn check(&self, disk_radius: f64) -> Result<(), ModelError> {
        bounds::YOUNGS_MODULUS.check("robot.backbone.youngs_modulus", self.youngs_modulus)?;
        let nu = super::file::finite("robot.backbone.poisson_ratio", self.poisson_ratio)?;
        if !(nu > -1.0 && nu <= 0.5) {
            return Err(ModelError::invalid(
                "robot.backbone.poisson_ratio",
                format!("must lie in (-1, 0.5], got {nu}"),
            ));
        }
        let d = bounds::DIAMETER.check("robot.backbone.diameter", self.diameter)?;
        if d >= 2.0 * disk_radius {
            return Err(ModelError::invalid(
                "robot.backbone.diameter",
                format!("{d} m does not fit inside the disk (radius {disk_radius} m)"),
            ));
        }
        let di = super::file::finite("robot.backbone.inner_diameter", self.inner_diameter)?;
        if !(0.0..d).contains(&di) {
            return Err(ModelError::invalid(
                "robot.backbone.inner_diameter",
                format!(
                    "a tube's inner diameter lies in [0, {d}) m (0: a solid rod; below the outer \
                     diameter), got {di}"
                ),
            ));
        }
        bounds::DENSITY.check("robot.backbone.density", self.density)?;
        let beta = super::file::finite("robot.backbone.stiffening", self.stiffening)?;
        if !(0.0..=MAX_STIFFENING).contains(&beta) {
            return Err(ModelError::invalid(
                "robot.backbone.stiffening",
                format!(
                    "must lie in [0, {MAX_STIFFENING}] m² (the β of ½ EI κ² (1 + β κ²)), got {beta}"
                ),
            ));
        }
        Ok(())
    }
}

impl Body {
    /// The body's rules: a rod without spacer disks carries its cables inside
    /// (`robot.spacer_disks`), a collision radius in [`bounds::DISK_RADIUS`]
    /// (`robot.collision_radius`).
    pub fn check(&self) -> Result<(), ModelError> {
        if self.no_spacer_disks && self.tendons != Tendons::Inside {
            return Err(ModelError::invalid(
                "robot.spacer_disks",
                "false needs `tendons = \"inside\"`: cables outside the rod run through the \
                 spacer disks' holes",
            ));
        }
        if let Some(r) = self.collision_radius {
            bounds::DISK_RADIUS.check("robot.collision_radius", r)?;
        }
        Ok(())
    }
}

impl Loads {
    /// The loads' rules (fields named `loads.*`): each component of gravity, the tip force and
    /// the tip moment, and the disk mass, in their [`bounds`] ranges.
    pub fn check(&self) -> Result<(), ModelError> {
        let arr = |v: &Vector3<f64>| [v.x, v.y, v.z];
        bounds::GRAVITY.check3("loads.gravity", arr(&self.gravity))?;
        bounds::DISK_MASS.check("loads.disk_mass", self.disk_mass)?;
        bounds::TIP_FORCE.check3("loads.tip_force", arr(&self.tip_force))?;
        bounds::TIP_MOMENT.check3("loads.tip_moment", arr(&self.tip_moment))?;
        Ok(())
    }
}
