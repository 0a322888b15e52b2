//! The registry: every method's identity, capabilities and settings, in one place.

use super::constant_curvature::ConstantCurvature;
use super::cosserat::Cosserat;
use super::energy::Energy;
use super::geometric::Geometric;
use super::settings::{canonical, Configure, SettingInfo, Settings};
use super::Method;
use crate::error::SolveError;
use crate::model::actuation::{Actuation, Drive, Input};
use crate::model::robot::{Robot, Tendons};
use crate::model::scene::Scene;
use std::fmt;
use std::str::FromStr;

mod info;
use info::INFO;
pub(super) use info::NAMES;

/// Every method ccrkit has. The only place a method's name is spelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MethodKind {
    /// The paper's section solver, read literally (sum of angles).
    Geometric,
    /// The same sections minimizing squared angles.
    GeometricSquared,
    /// The whole-robot energy model.
    Energy,
    /// The Cosserat rod with shear and extension.
    Cosserat,
    /// The Kirchhoff rod (inextensible, unshearable).
    Kirchhoff,
    /// The constant-curvature closed form.
    ConstantCurvature,
}

impl MethodKind {
    /// The method every front end uses when none is named (`ccrkit solve`, `view`, `study
    /// workspace`, `reach`, `plan`, `predict`, `calibrate`, Python): the whole-robot energy
    /// model, accurate against the Cosserat rod and fast. The paper's literal section solver
    /// stays available by name ([`MethodKind::Geometric`], `--method geometric`).
    pub const DEFAULT: MethodKind = MethodKind::Energy;
}

impl Default for MethodKind {
    /// [`MethodKind::DEFAULT`].
    fn default() -> Self {
        MethodKind::DEFAULT
    }
}

/// Which external loads a method models (a load it does not model is refused, not ignored).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadSupport {
    /// Gravity on the backbone and disks.
    pub gravity: bool,
    /// A force at the tip.
    pub tip_force: bool,
    /// A moment at the tip.
    pub tip_moment: bool,
}

/// What the rest of ccrkit needs to know about a method.
#[derive(Debug, Clone, Copy)]
pub struct MethodInfo {
    /// The method.
    pub kind: MethodKind,
    /// Command-line name.
    pub name: &'static str,
    /// One line: what it is.
    pub summary: &'static str,
    /// Inputs it can be driven by.
    pub inputs: &'static [Input],
    /// The input it uses where a cable gives both (its default `control`).
    pub default_input: Input,
    /// Whether it keeps the robot clear of obstacles.
    pub obstacles: bool,
    /// Which loads it models.
    pub loads: LoadSupport,
    /// Whether it models compliant cables (`stiffness`, `pretension` of a cable).
    pub cable_compliance: bool,
    /// Whether it models capstan friction along the cables (a cable's
    /// [`capstan`](crate::model::actuation::CableDrive::capstan) coefficient, set by hardware
    /// rows); a method that does not refuses a cable with friction ([`MethodKind::drives`]).
    pub capstan_friction: bool,
    /// Whether it models a bending stiffness that rises with curvature (the backbone's
    /// `stiffening` β, [`crate::model::robot::Backbone::stiffening`]).
    pub bending_stiffening: bool,
    /// Whether it models cables that run inside the backbone rod (`robot.tendons = "inside"`,
    /// [`crate::model::robot::Tendons::Inside`]): the cable follows the rod, its moment arm
    /// the hole's position in the section.
    pub tendons_inside: bool,
    /// Settings it takes (by name).
    pub settings: &'static [SettingInfo],
    /// Unit of its contact multipliers (`N` where they are reactions, `rad/m` for the
    /// geometric methods' angle objective; empty without obstacle support).
    pub contact_unit: &'static str,
    /// Its resolution ladder for the speed–accuracy study: (label, settings as `name=value`).
    pub resolutions: &'static [(&'static str, &'static [(&'static str, &'static str)])],
}

impl MethodKind {
    /// Every method, in registry order.
    pub const ALL: [MethodKind; 6] = [
        MethodKind::Geometric,
        MethodKind::GeometricSquared,
        MethodKind::Energy,
        MethodKind::Cosserat,
        MethodKind::Kirchhoff,
        MethodKind::ConstantCurvature,
    ];

    /// What the method is and takes.
    pub fn info(self) -> &'static MethodInfo {
        &INFO[self as usize]
    }

    /// Command-line name.
    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// Whether the method can be driven by `input`.
    pub fn accepts(self, input: Input) -> bool {
        self.info().inputs.contains(&input)
    }

    /// Build the method with its defaults, then `settings` applied in order. A setting the
    /// method does not take is an error naming the methods that do.
    pub fn build(self, settings: &Settings) -> Result<Box<dyn Method>, SolveError> {
        fn apply<M: Configure + Method + 'static>(
            mut m: M,
            settings: &Settings,
        ) -> Result<Box<dyn Method>, SolveError> {
            for (name, value) in settings.iter() {
                m.set(&canonical(name), value)?;
            }
            // Each value was in range; now the settings together (e.g. sub-arcs with length).
            m.check()?;
            Ok(Box::new(m))
        }
        match self {
            MethodKind::Geometric => apply(Geometric::literal(), settings),
            MethodKind::GeometricSquared => apply(Geometric::squared(), settings),
            MethodKind::Energy => apply(Energy::default(), settings),
            MethodKind::Cosserat => apply(Cosserat::full(), settings),
            MethodKind::Kirchhoff => apply(Cosserat::kirchhoff(), settings),
            MethodKind::ConstantCurvature => apply(ConstantCurvature::default(), settings),
        }
    }

    /// The settings that drive this method by `input` where a cable gives both (its
    /// `control`), when it accepts both; otherwise none (its defaults).
    pub fn driven_by(self, input: Input) -> Settings {
        if self.accepts(Input::Shortening) && self.accepts(Input::Tension) {
            Settings::new().with("control", super::settings::control_name(input))
        } else {
            Settings::new()
        }
    }

    /// Refuse a setting this method does not take, naming the methods that take it.
    pub fn check_setting(self, name: &str) -> Result<(), SolveError> {
        self.setting(name).map(|_| ())
    }

    /// The registry's entry of a setting this method takes (its range is what the method's
    /// [`Configure::set`] parses with); a setting it does not take is refused, naming the
    /// methods that take it.
    pub fn setting(self, name: &str) -> Result<&'static SettingInfo, SolveError> {
        let name = canonical(name);
        if let Some(s) = self.info().settings.iter().find(|s| s.name == name) {
            return Ok(s);
        }
        let takers = Self::names_with(|i| i.settings.iter().any(|s| s.name == name));
        let own: Vec<&str> = self.info().settings.iter().map(|s| s.name).collect();
        Err(SolveError::InvalidInput {
            field: name.clone(),
            reason: if takers.is_empty() {
                format!(
                    "no method takes a setting `{name}`; {} takes: {}",
                    self.name(),
                    own.join(", ")
                )
            } else {
                format!(
                    "applies to {}, not to {} (which takes: {})",
                    takers.join(", "),
                    self.name(),
                    own.join(", ")
                )
            },
        })
    }

    /// Refuse obstacles or external loads this method does not model, naming them: a load or
    /// an obstacle is never silently left out of a shape.
    pub fn check_support(self, robot: &Robot, scene: &Scene) -> Result<(), SolveError> {
        let info = self.info();
        let refuse = |reason: String| {
            Err(SolveError::Unsupported {
                method: info.name.into(),
                reason,
            })
        };
        if !info.obstacles && !scene.is_empty() {
            return refuse(format!(
                "obstacles are not modelled by {} (scene has {}); methods that keep the robot \
                 clear of obstacles: {}",
                info.name,
                scene.obstacles.len(),
                Self::names_with(|i| i.obstacles).join(", ")
            ));
        }
        let l = &robot.loads;
        let weight = l.gravity.norm() > 0.0 && (l.disk_mass > 0.0 || robot.backbone.density > 0.0);
        let loads = [
            ("gravity", weight, info.loads.gravity),
            (
                "loads.tip_force",
                l.tip_force.norm() > 0.0,
                info.loads.tip_force,
            ),
            (
                "loads.tip_moment",
                l.tip_moment.norm() > 0.0,
                info.loads.tip_moment,
            ),
        ];
        for (name, present, modelled) in loads {
            if present && !modelled {
                let by = Self::names_with(|i| match name {
                    "gravity" => i.loads.gravity,
                    "loads.tip_force" => i.loads.tip_force,
                    _ => i.loads.tip_moment,
                });
                return refuse(format!(
                    "the model's `{name}` is not modelled by {} (it would be ignored); use {}",
                    info.name,
                    by.join(" or ")
                ));
            }
        }
        if !info.bending_stiffening && robot.backbone.stiffening > 0.0 {
            let by = Self::names_with(|i| i.bending_stiffening);
            return refuse(format!(
                "the backbone's `stiffening` (β = {} m², a bending stiffness rising with \
                 curvature) is not modelled by {} (it would be ignored); use {}, or drop it",
                robot.backbone.stiffening,
                info.name,
                by.join(" or ")
            ));
        }
        if !info.tendons_inside && robot.body.tendons == Tendons::Inside {
            let by = Self::names_with(|i| i.tendons_inside);
            return refuse(format!(
                "the model's cables run inside the rod (`robot.tendons = \"inside\"`), which {} \
                 does not model (its cables run straight between spacer disks' holes); use {}",
                info.name,
                by.join(" or ")
            ));
        }
        if !info.cable_compliance {
            if let Some(c) = robot
                .cables
                .iter()
                .find(|c| c.stiffness.is_some() || c.pretension > 0.0)
            {
                let by = Self::names_with(|i| i.cable_compliance);
                return refuse(format!(
                    "cable `{}` has a `stiffness` (compliant cable), which {} does not model \
                     (its cables are inextensible); use {}, or drop the stiffness",
                    c.name,
                    info.name,
                    by.join(" or ")
                ));
            }
        }
        Ok(())
    }

    /// The input a configured variant of this method is driven by (its `control` setting,
    /// else its default).
    pub fn input_with(self, settings: &Settings) -> Input {
        settings
            .get("control")
            .and_then(|v| super::settings::parse_control(v).ok())
            .filter(|&i| self.accepts(i))
            .unwrap_or(self.info().default_input)
    }

    /// Each cable's drive under this method: the actuation resolved against the inputs the
    /// registry lists for it (`MethodInfo::inputs`, the one place they are written), a cable
    /// that gives both driven by `prefer`. A cable with capstan friction is refused by name
    /// unless the method models it (`MethodInfo::capstan_friction`).
    pub fn drives(
        self,
        robot: &Robot,
        act: &Actuation,
        prefer: Input,
    ) -> Result<Vec<Drive>, SolveError> {
        let info = self.info();
        if !info.capstan_friction {
            if let Some(c) = act.cables.iter().position(|d| d.capstan != 0.0) {
                let by = Self::names_with(|i| i.capstan_friction);
                return Err(SolveError::Unsupported {
                    method: info.name.into(),
                    reason: format!(
                        "cable `{}` slides with capstan friction (`hardware.friction` in a \
                         sequence of rows): only the {} model honours it; set the friction to \
                         0 or use `--method {}`",
                        robot.cables.get(c).map_or("?", |k| k.name.as_str()),
                        by.join(" or "),
                        by.join("` or `--method ")
                    ),
                });
            }
        }
        act.drives(robot, info.name, info.inputs, prefer)
    }
}

impl MethodKind {
    /// The method with this command-line name, if any.
    pub fn from_name(name: &str) -> Option<MethodKind> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The error of a setting the registry lists for this method but its
    /// [`Configure::set`] does not apply (a bug in ccrkit, never a silently ignored setting).
    pub fn unapplied(self, name: &str) -> SolveError {
        SolveError::InvalidInput {
            field: name.into(),
            reason: format!(
                "listed for {} in the registry but not applied by it (a bug in ccrkit)",
                self.name()
            ),
        }
    }

    /// The names of the methods whose registry entry satisfies `has` (a capability), in
    /// registry order: what an error names as the methods to use instead.
    fn names_with(has: impl Fn(&MethodInfo) -> bool) -> Vec<&'static str> {
        Self::ALL
            .into_iter()
            .filter(|k| has(k.info()))
            .map(|k| k.name())
            .collect()
    }
}

impl fmt::Display for MethodKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MethodKind {
    type Err = SolveError;
    fn from_str(s: &str) -> Result<Self, SolveError> {
        Self::from_name(s.trim()).ok_or_else(|| SolveError::InvalidInput {
            field: "method".into(),
            reason: format!("unknown method `{s}`; known: {}", NAMES.join(", ")),
        })
    }
}
