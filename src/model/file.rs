//! The TOML form of a model file and its validation into a [`Model`]: every rule is checked
//! here, once, with an error naming the field.

use super::actuation::Actuation;
use super::bounds;
use super::file_cable::FileCable;
use super::hardware::{FileHardware, Hardware};
use super::robot::{Backbone, Body, Loads, Robot, Tendons};
use super::scene::Scene;
use super::scene_file::FileObstacle;
use super::{Model, MAX_SECTIONS};
use crate::error::ModelError;
use nalgebra::Vector3;
use serde::Deserialize;
use std::path::Path;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileModel {
    name: String,
    #[serde(default)]
    description: Option<String>,
    robot: FileRobot,
    #[serde(default)]
    cables: Vec<FileCable>,
    #[serde(default)]
    loads: Option<FileLoads>,
    /// Distance every robot feature keeps from every obstacle \[m\].
    #[serde(default)]
    clearance: Option<f64>,
    /// A scene file, relative to this file.
    #[serde(default)]
    scene: Option<String>,
    #[serde(default)]
    obstacles: Vec<FileObstacle>,
    /// Gains, offsets, frames of a real robot (`model/hardware.rs`).
    #[serde(default)]
    hardware: Option<FileHardware>,
    /// Actuation limits per cable (`src/model/limits.rs`).
    #[serde(default)]
    limits: std::collections::BTreeMap<String, super::limits::FileLimit>,
    /// The port the robot is deployed through (`src/model/port.rs`).
    #[serde(default)]
    port: Option<super::port::FilePort>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileRobot {
    sections: i64,
    section_length: Option<f64>,
    section_lengths: Option<Vec<f64>>,
    /// Spacer disks' radius and thickness; only without `spacer_disks = false`.
    #[serde(default)]
    disk_radius: Option<f64>,
    #[serde(default)]
    disk_thickness: Option<f64>,
    backbone: FileBackbone,
    /// Where the cables run: `disks` (default) or `inside` the rod.
    #[serde(default)]
    tendons: Option<String>,
    /// `false`: a rod without spacer disks (cables inside it).
    #[serde(default)]
    spacer_disks: Option<bool>,
    /// The body's radius for contact \[m\] (default: the backbone's).
    #[serde(default)]
    collision_radius: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileBackbone {
    youngs_modulus: f64,
    poisson_ratio: f64,
    diameter: f64,
    #[serde(default)]
    inner_diameter: Option<f64>,
    #[serde(default)]
    density: Option<f64>,
    #[serde(default)]
    stiffening: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileLoads {
    #[serde(default)]
    gravity: Option<[f64; 3]>,
    #[serde(default)]
    disk_mass: Option<f64>,
    #[serde(default)]
    tip_force: Option<[f64; 3]>,
    #[serde(default)]
    tip_moment: Option<[f64; 3]>,
}

pub(super) fn finite(field: &str, v: f64) -> Result<f64, ModelError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ModelError::invalid(
            field,
            format!("must be a finite number, got {v}"),
        ))
    }
}

pub(super) fn positive(field: &str, v: f64) -> Result<f64, ModelError> {
    finite(field, v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(ModelError::invalid(field, format!("must be > 0, got {v}")))
    }
}

impl FileModel {
    pub(super) fn validate(self, dir: &Path) -> Result<Model, ModelError> {
        super::name::check_name("name", &self.name)?;
        let _ = &self.description;
        let r = &self.robot;
        if r.sections < 1 || r.sections as usize > MAX_SECTIONS {
            return Err(ModelError::invalid(
                "robot.sections",
                format!("must be between 1 and {MAX_SECTIONS}, got {}", r.sections),
            ));
        }
        let n = r.sections as usize;
        bounds::check_cable_count(self.cables.len())?;
        let (lengths, disk_s) = r.stations(n)?;
        let body = r.body()?;
        let backbone = r.backbone.validate()?;
        let (disk_radius, disk_thickness) = r.disks(&body, &backbone, &lengths)?;
        let loads = match &self.loads {
            None => Loads::default(),
            Some(l) => l.validate()?,
        };
        let mut robot = Robot {
            name: self.name.clone(),
            disk_s,
            disk_radius,
            disk_thickness,
            backbone,
            cables: Vec::with_capacity(self.cables.len()),
            loads,
            port: None,
            body,
        };
        robot.backbone.check(if robot.has_disks() {
            disk_radius
        } else {
            f64::INFINITY
        })?;

        let mut drives = Vec::with_capacity(self.cables.len());
        for (ci, fc) in self.cables.iter().enumerate() {
            if robot.cables.iter().any(|c| c.name == fc.name) && !fc.name.trim().is_empty() {
                return Err(ModelError::invalid(
                    format!("cables[{ci}].name"),
                    format!("two cables are named `{}`", fc.name),
                ));
            }
            let cable = fc.cable(ci, &robot)?;
            drives.push(fc.drive(ci, &cable, &robot.disk_s)?);
            robot.cables.push(cable);
        }

        let scene = self.scene(dir)?;
        let port = self
            .port
            .as_ref()
            .map(|p| p.validate(robot.disk_s[n]))
            .transpose()?;
        robot.port = port.as_ref().map(|p| p.port.clone());
        // The rules every robot keeps, however built (the file's own spellings were checked
        // above, each naming the file's field).
        robot.check()?;
        let hardware = Hardware::from_file(self.hardware.as_ref(), &robot)?;
        let mut limits = super::limits::validate(&self.limits, &robot)?;
        let mut actuation = Actuation {
            cables: drives,
            insertion: None,
            rotation: None,
        };
        if let Some(p) = &port {
            limits.insertion = Some(p.insertion_limits);
            limits.rotation = Some(p.rotation_limits);
            actuation.insertion = Some(p.insertion);
            actuation.rotation = Some(p.rotation);
        }
        hardware.fold(&robot, &mut actuation)?;
        Ok(Model {
            scene,
            robot,
            actuation,
            hardware,
            limits,
            source: None,
        })
    }

    /// The inline obstacles merged with the named scene file; obstacle names unique.
    fn scene(&self, dir: &Path) -> Result<Scene, ModelError> {
        let mut scene = Scene::from_parts(self.clearance, &self.obstacles, dir, "")?;
        if let Some(rel) = &self.scene {
            let other = Scene::from_file_as(&dir.join(rel), "scene file named in the model")
                .map_err(|e| match e {
                    ModelError::Io { path, reason } => {
                        ModelError::invalid("scene", format!("cannot read `{path}`: {reason}"))
                    }
                    other => other,
                })?;
            scene.merge(other);
            let mut names: Vec<&str> = scene.obstacles.iter().map(|o| o.name.as_str()).collect();
            names.sort_unstable();
            if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
                return Err(ModelError::invalid(
                    "scene",
                    format!("two obstacles are named `{}`", w[0]),
                ));
            }
        }
        Ok(scene)
    }
}

impl FileRobot {
    /// Where the cables run, spacer disks, collision radius ([`Body::check`]).
    fn body(&self) -> Result<Body, ModelError> {
        let tendons = match self.tendons.as_deref() {
            None | Some("disks") => Tendons::Disks,
            Some("inside") => Tendons::Inside,
            Some(other) => {
                return Err(ModelError::invalid(
                    "robot.tendons",
                    format!(
                        "must be `disks` (through spacer disks, outside the rod) or `inside` \
                         (in channels inside the rod), got `{other}`"
                    ),
                ))
            }
        };
        let body = Body {
            tendons,
            no_spacer_disks: self.spacer_disks == Some(false),
            collision_radius: self.collision_radius,
        };
        body.check()?;
        Ok(body)
    }

    /// The spacer disks' radius and thickness, checked; a rod without spacer disks takes
    /// neither (its stations are drawn at the body's radius, with no thickness).
    fn disks(
        &self,
        body: &Body,
        backbone: &Backbone,
        lengths: &[f64],
    ) -> Result<(f64, f64), ModelError> {
        if body.no_spacer_disks {
            for (field, v) in [
                ("robot.disk_radius", self.disk_radius),
                ("robot.disk_thickness", self.disk_thickness),
            ] {
                if v.is_some() {
                    return Err(ModelError::invalid(
                        field,
                        "a rod without spacer disks (`spacer_disks = false`) has no disks to size",
                    ));
                }
            }
            return Ok((body.collision_radius.unwrap_or(backbone.radius()), 0.0));
        }
        let need = |field: &str, v: Option<f64>| {
            v.ok_or_else(|| {
                ModelError::invalid(
                    field,
                    "missing: give the spacer disks' size (or `spacer_disks = false` for a rod \
                     without disks, its cables inside it)",
                )
            })
        };
        let disk_radius = bounds::DISK_RADIUS.check(
            "robot.disk_radius",
            need("robot.disk_radius", self.disk_radius)?,
        )?;
        let disk_thickness = bounds::DISK_THICKNESS.check(
            "robot.disk_thickness",
            need("robot.disk_thickness", self.disk_thickness)?,
        )?;
        let min_l = lengths.iter().cloned().fold(f64::INFINITY, f64::min);
        if disk_thickness >= min_l {
            return Err(ModelError::invalid(
                "robot.disk_thickness",
                format!("{disk_thickness} m is not smaller than the shortest section ({min_l} m)"),
            ));
        }
        Ok((disk_radius, disk_thickness))
    }

    /// The checked section lengths and the arc length of every disk (`disk_s[0] = 0`).
    fn stations(&self, n: usize) -> Result<(Vec<f64>, Vec<f64>), ModelError> {
        let lengths: Vec<f64> = match (&self.section_length, &self.section_lengths) {
            (Some(_), Some(_)) => {
                return Err(ModelError::invalid(
                    "robot.section_lengths",
                    "give either section_length or section_lengths, not both",
                ))
            }
            (None, None) => {
                return Err(ModelError::invalid(
                    "robot.section_length",
                    "missing: give section_length or section_lengths",
                ))
            }
            (Some(l), None) => vec![bounds::SECTION_LENGTH.check("robot.section_length", *l)?; n],
            (None, Some(ls)) => {
                if ls.len() != n {
                    return Err(ModelError::invalid(
                        "robot.section_lengths",
                        format!("needs one length per section ({n}), got {}", ls.len()),
                    ));
                }
                for (k, l) in ls.iter().enumerate() {
                    bounds::SECTION_LENGTH.check(&format!("robot.section_lengths[{k}]"), *l)?;
                }
                ls.clone()
            }
        };
        let mut disk_s = Vec::with_capacity(n + 1);
        disk_s.push(0.0);
        for l in &lengths {
            let last = disk_s[disk_s.len() - 1];
            disk_s.push(last + l);
        }
        let total = disk_s[n];
        if total > bounds::ROBOT_LENGTH.hi {
            return Err(ModelError::invalid(
                if self.section_length.is_some() {
                    "robot.section_length"
                } else {
                    "robot.section_lengths"
                },
                format!(
                    "the backbone would be {total:e} m long; at most {:e} m",
                    bounds::ROBOT_LENGTH.hi
                ),
            ));
        }
        Ok((lengths, disk_s))
    }
}

impl FileBackbone {
    /// The backbone, checked by its own rules ([`Backbone::check`]) short of the disks (the
    /// caller checks it against them).
    fn validate(&self) -> Result<Backbone, ModelError> {
        let b = Backbone {
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            diameter: self.diameter,
            inner_diameter: self.inner_diameter.unwrap_or(0.0),
            density: self.density.unwrap_or(0.0),
            stiffening: self.stiffening.unwrap_or(0.0),
        };
        b.check(f64::INFINITY)?;
        Ok(b)
    }
}

impl FileLoads {
    /// The loads (absent ones zero), checked by their own rules ([`Loads::check`]).
    fn validate(&self) -> Result<Loads, ModelError> {
        let v = |x: Option<[f64; 3]>| Vector3::from(x.unwrap_or([0.0; 3]));
        let l = Loads {
            gravity: v(self.gravity),
            disk_mass: self.disk_mass.unwrap_or(0.0),
            tip_force: v(self.tip_force),
            tip_moment: v(self.tip_moment),
        };
        l.check()?;
        Ok(l)
    }
}
