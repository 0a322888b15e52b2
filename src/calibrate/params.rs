//! Parameters `ccrkit calibrate` can fit, by name:
//!
//! | name | what | unit |
//! |---|---|---|
//! | `gain`, `gain.segK`, `gain.CABLE` | [`Hardware::gain`] of every cable / of segment K / of one cable | – |
//! | `offset`, `offset.segK`, `offset.CABLE` | [`Hardware::offset`] (slack) of the same groups | m |
//! | `marker.x`, `marker.y`, `marker.z` | [`Hardware::marker`] in the tip frame | m |
//! | `backlash`, `backlash.segK`, `backlash.CABLE` | [`Hardware::backlash`] of the same groups | m |
//! | `compliance`, `compliance.segK`, `compliance.CABLE` | `1/k` of the cables' [`Cable::stiffness`] (0: inextensible) | m/N |
//! | `axial-compliance`, `axial-compliance.segK`, `axial-compliance.CABLE` | `1/EA` of the cables: each gets `k = EA/ℓ` (below) | 1/N |
//! | `base.rx`, `base.ry`, `base.rz` | component x, y, z of the base's rotation vector in the measurement frame ([`Hardware::base_rotation`]); with the other two 0, the rotation about that axis | rad |
//! | `friction`, `friction.segK`, `friction.CABLE` | capstan coefficient `μ` ([`Hardware::friction`], sequences only) | – |
//! | `stiffening` | the backbone's curvature stiffening `β` ([`Backbone::stiffening`]: bending energy `½ EI κ² (1 + β κ²)`; energy model only) | m² |
//!
//! The compliance `1/k` rather than the stiffness `k` is fitted: the stretch `T/k` is linear in
//! it, and 0 (the inextensible cable, the nominal models) is inside its range. A trial value
//! < 0 (or a gain ≤ 0) is outside the model and rejected as a step that does not descend. A
//! cable's `pretension` is not a separate parameter: it acts as a shortening `T₀/k`, which
//! `offset` already fits.
//!
//! **EA and free length.** A cable of axial rigidity `EA` and free length `ℓ` stretches by
//! `T ℓ/EA`: a stiffness `k = EA/ℓ`, so of two cables of one material the longer is the softer
//! (a distal segment's tendon runs through every proximal segment). `axial-compliance` fits
//! `1/EA` and sets every cable's `k = EA/ℓ_c` with `ℓ_c` the cable's undeformed length from the
//! base disk to the disk it is tied at ([`Robot::undeformed_chord_length`]); a lead from the
//! servo to the base disk (not in the model) would add a common `ℓ_lead/EA`, which is what the
//! uniform `compliance` stands for. The fitted file holds the resulting `stiffness` per cable.
//!
//! **Base rotation about z.** The measurement frame's azimuth is tied to the tendon angles
//! (identified from the tendon pulls in the data's frame); `base.rz` turns the whole robot
//! about the measurement z axis, a common offset of every tendon angle. `base.rx` and
//! `base.ry` tilt the robot's axis against the measurement frame's z axis (a robot mounted
//! askew to the motion-capture frame): the error they take up is the tilt's `ω × s`, linear in
//! the tip's lateral motion.
//!
//! Segment K is the K-th group of cables tied at the same disk, in order of that disk from the
//! base (the FTDCR models: seg0 = the three cables tied at the end of the proximal segment).
//! The base position is not a parameter: the metric aligns the mean offset, and the fitted
//! model's `base_position` is set to remove it (see `fit.rs`).
//!
//! [`Hardware::gain`]: crate::model::hardware::Hardware::gain
//! [`Hardware::offset`]: crate::model::hardware::Hardware::offset
//! [`Hardware::marker`]: crate::model::hardware::Hardware::marker
//! [`Cable::stiffness`]: crate::model::robot::Cable::stiffness
//! [`Hardware::backlash`]: crate::model::hardware::Hardware::backlash
//! [`Hardware::friction`]: crate::model::hardware::Hardware::friction
//! [`Hardware::base_rotation`]: crate::model::hardware::Hardware::base_rotation
//! [`Backbone::stiffening`]: crate::model::robot::Backbone::stiffening
//! [`Robot::undeformed_chord_length`]: crate::model::robot::Robot::undeformed_chord_length

use crate::error::SolveError;
use crate::model::hardware::MAX_FRICTION;
use crate::model::robot::{Robot, MAX_STIFFENING};
use crate::model::Model;

/// Which cables a per-cable parameter acts on.
#[derive(Debug, Clone, PartialEq)]
pub enum Group {
    /// Every cable.
    All,
    /// The cables of one segment (indices).
    Cables(Vec<usize>),
}

/// What a parameter sets.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// Displacement gain.
    Gain(Group),
    /// Offset (slack) \[m\].
    Offset(Group),
    /// Marker coordinate (0, 1, 2 = x, y, z) in the tip frame \[m\].
    Marker(usize),
    /// Cable compliance `1/k` \[m/N\] (0: inextensible).
    Compliance(Group),
    /// Backlash width \[m\].
    Backlash(Group),
    /// `1/EA` of the cables \[1/N\]: stiffness `EA/ℓ` (module docs).
    AxialCompliance(Group),
    /// Base rotation about the measurement z axis \[rad\] (the z of the rotation vector).
    BaseRotation(usize),
    /// Capstan friction coefficient `μ` \[-\].
    Friction(Group),
    /// The backbone's curvature stiffening `β` \[m²\].
    Stiffening,
}

/// A named, fittable parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// Its name as given (`gain.seg0`).
    pub name: String,
    /// What it sets.
    pub target: Target,
}

/// Smallest gain a fit step may set (a gain ≤ 0 reverses the cable; [`Param::project`]).
pub const MIN_GAIN: f64 = 1e-3;

/// Default parameters: per-segment gain and offset, one common cable compliance and the
/// marker along the tip axis (8 scalars for a 3-segment robot; at most 9, the benchmark
/// protocol's limit).
pub fn default_names(robot: &Robot) -> Vec<String> {
    let n = segments(robot).len();
    let mut v: Vec<String> = (0..n).map(|k| format!("gain.seg{k}")).collect();
    v.extend((0..n).map(|k| format!("offset.seg{k}")));
    v.push("compliance".into());
    v.push("marker.z".into());
    v
}

/// Cables grouped by the disk they are tied at, groups ordered from the base.
pub fn segments(robot: &Robot) -> Vec<Vec<usize>> {
    let mut ends: Vec<usize> = robot.cables.iter().map(|c| c.ends_at).collect();
    ends.sort_unstable();
    ends.dedup();
    ends.iter()
        .map(|e| {
            (0..robot.cables.len())
                .filter(|&c| robot.cables[c].ends_at == *e)
                .collect()
        })
        .collect()
}

impl Param {
    /// Parse a parameter name for `robot` (module docs), refusing unknown names by name.
    pub fn parse(name: &str, robot: &Robot) -> Result<Param, SolveError> {
        let bad = |why: String| SolveError::InvalidInput {
            field: format!("fit `{name}`"),
            reason: why,
        };
        let (head, tail) = match name.split_once('.') {
            Some((h, t)) => (h, Some(t)),
            None => (name, None),
        };
        let group = |t: Option<&str>| -> Result<Group, SolveError> {
            let Some(t) = t else { return Ok(Group::All) };
            if let Some(k) = t.strip_prefix("seg").and_then(|k| k.parse::<usize>().ok()) {
                let segs = segments(robot);
                return segs
                    .get(k)
                    .map(|c| Group::Cables(c.clone()))
                    .ok_or_else(|| {
                        bad(format!(
                            "the robot has {} segments (seg0..seg{})",
                            segs.len(),
                            segs.len().saturating_sub(1)
                        ))
                    });
            }
            robot
                .cable_index(t)
                .map(|c| Group::Cables(vec![c]))
                .ok_or_else(|| bad(format!("`{t}` is neither segK nor a cable name")))
        };
        let target = match head {
            "gain" => Target::Gain(group(tail)?),
            "offset" => Target::Offset(group(tail)?),
            "compliance" => Target::Compliance(group(tail)?),
            "backlash" => Target::Backlash(group(tail)?),
            "friction" => Target::Friction(group(tail)?),
            "axial-compliance" => Target::AxialCompliance(group(tail)?),
            "stiffening" => match tail {
                None => Target::Stiffening,
                Some(_) => return Err(bad("`stiffening` is one value of the backbone".into())),
            },
            "base" => match tail {
                Some("rx") => Target::BaseRotation(0),
                Some("ry") => Target::BaseRotation(1),
                Some("rz") => Target::BaseRotation(2),
                _ => return Err(bad("give base.rx, base.ry or base.rz".into())),
            },
            "marker" => match tail {
                Some("x") => Target::Marker(0),
                Some("y") => Target::Marker(1),
                Some("z") => Target::Marker(2),
                _ => return Err(bad("give marker.x, marker.y or marker.z".into())),
            },
            _ => {
                return Err(bad(
                    "unknown parameter: gain[.segK|.CABLE], offset[.segK|.CABLE], \
                     compliance[.segK|.CABLE], axial-compliance[.segK|.CABLE], \
                     backlash[.segK|.CABLE], friction[.segK|.CABLE], marker.x|y|z, base.rx|ry|rz, \
                     stiffening"
                        .into(),
                ))
            }
        };
        Ok(Param {
            name: name.to_string(),
            target,
        })
    }

    /// Scale of the parameter: its typical magnitude in SI units (the fit works in value/scale).
    pub fn scale(&self) -> f64 {
        match self.target {
            Target::Gain(_) | Target::Friction(_) => 1.0,
            Target::Offset(_) | Target::Marker(_) | Target::Backlash(_) => 1e-3,
            Target::Compliance(_) => 1e-4,
            Target::AxialCompliance(_) | Target::Stiffening => 1e-3,
            Target::BaseRotation(_) => 1e-2,
        }
    }

    /// Whether `v` lies inside the model (gain > 0, compliance ≥ 0).
    pub fn admissible(&self, v: f64) -> bool {
        match self.target {
            Target::Gain(_) => v > 0.0,
            Target::Compliance(_) | Target::Backlash(_) | Target::AxialCompliance(_) => v >= 0.0,
            Target::Friction(_) => (0.0..=MAX_FRICTION).contains(&v),
            Target::Stiffening => (0.0..=MAX_STIFFENING).contains(&v),
            Target::Offset(_) | Target::Marker(_) | Target::BaseRotation(_) => true,
        }
    }

    /// The admissible value nearest to `v` ([`Param::admissible`]): a compliance or backlash
    /// below 0 becomes 0, a gain below [`MIN_GAIN`] becomes [`MIN_GAIN`]; others unchanged.
    /// The fit projects each trial step with it (`fit.rs`).
    pub fn project(&self, v: f64) -> f64 {
        match self.target {
            Target::Gain(_) => v.max(MIN_GAIN),
            Target::Compliance(_) | Target::Backlash(_) | Target::AxialCompliance(_) => v.max(0.0),
            Target::Friction(_) => v.clamp(0.0, MAX_FRICTION),
            Target::Stiffening => v.clamp(0.0, MAX_STIFFENING),
            Target::Offset(_) | Target::Marker(_) | Target::BaseRotation(_) => v,
        }
    }

    /// Unit for reports.
    pub fn unit(&self) -> &'static str {
        match self.target {
            Target::Gain(_) | Target::Friction(_) => "-",
            Target::Offset(_) | Target::Marker(_) | Target::Backlash(_) => "m",
            Target::Compliance(_) => "m/N",
            Target::AxialCompliance(_) => "1/N",
            Target::BaseRotation(_) => "rad",
            Target::Stiffening => "m²",
        }
    }

    pub(crate) fn cables(g: &Group, n: usize) -> Vec<usize> {
        match g {
            Group::All => (0..n).collect(),
            Group::Cables(c) => c.clone(),
        }
    }

    /// The parameter's value in `model` (the mean over its cables).
    pub fn get(&self, model: &Model) -> f64 {
        let hw = &model.hardware;
        let n = model.robot.cables.len();
        let mean = |v: &[f64], g: &Group| {
            let c = Self::cables(g, n);
            c.iter().map(|&i| v[i]).sum::<f64>() / c.len().max(1) as f64
        };
        match &self.target {
            Target::Gain(g) => mean(&hw.gain, g),
            Target::Offset(g) => mean(&hw.offset, g),
            Target::Marker(k) => hw.marker[*k],
            Target::Backlash(g) => mean(&hw.backlash, g),
            Target::Friction(g) => mean(&hw.friction, g),
            Target::Compliance(g) => {
                let c: Vec<f64> = model.robot.cables.iter().map(|c| c.compliance()).collect();
                mean(&c, g)
            }
            Target::AxialCompliance(g) => {
                let c: Vec<f64> = (0..n)
                    .map(|c| {
                        model.robot.cables[c].compliance() / model.robot.undeformed_chord_length(c)
                    })
                    .collect();
                mean(&c, g)
            }
            Target::BaseRotation(k) => hw.base_rotation[*k],
            Target::Stiffening => model.robot.backbone.stiffening,
        }
    }

    /// Set the parameter to `v` in `model` (a compliance ≤ 0 makes the cables inextensible).
    pub fn set(&self, model: &mut Model, v: f64) {
        let n = model.robot.cables.len();
        if let Target::Compliance(g) = &self.target {
            for c in Self::cables(g, n) {
                model.robot.cables[c].stiffness = (v > 0.0).then(|| 1.0 / v);
            }
            return;
        }
        if let Target::Stiffening = self.target {
            model.robot.backbone.stiffening = v;
            return;
        }
        if let Target::AxialCompliance(g) = &self.target {
            for c in Self::cables(g, n) {
                let len = model.robot.undeformed_chord_length(c);
                model.robot.cables[c].stiffness = (v > 0.0).then(|| 1.0 / (v * len));
            }
            return;
        }
        let hw = &mut model.hardware;
        match &self.target {
            Target::Gain(g) => Self::cables(g, n).into_iter().for_each(|c| hw.gain[c] = v),
            Target::Offset(g) => Self::cables(g, n)
                .into_iter()
                .for_each(|c| hw.offset[c] = v),
            Target::Marker(k) => hw.marker[*k] = v,
            Target::Backlash(g) => Self::cables(g, n)
                .into_iter()
                .for_each(|c| hw.backlash[c] = v),
            Target::BaseRotation(k) => hw.base_rotation[*k] = v,
            Target::Friction(g) => Self::cables(g, n)
                .into_iter()
                .for_each(|c| hw.friction[c] = v),
            Target::Compliance(_) | Target::AxialCompliance(_) | Target::Stiffening => {}
        }
    }
}

/// Parse names, refusing duplicates and sets touching one value twice.
pub fn parse_all(names: &[String], robot: &Robot) -> Result<Vec<Param>, SolveError> {
    let ps: Vec<Param> = names
        .iter()
        .map(|n| Param::parse(n, robot))
        .collect::<Result<_, _>>()?;
    let n = robot.cables.len();
    for (i, a) in ps.iter().enumerate() {
        for b in &ps[..i] {
            let overlap = match (&a.target, &b.target) {
                (Target::Gain(x), Target::Gain(y))
                | (Target::Offset(x), Target::Offset(y))
                | (Target::Compliance(x), Target::Compliance(y))
                | (Target::Compliance(x), Target::AxialCompliance(y))
                | (Target::AxialCompliance(x), Target::Compliance(y))
                | (Target::AxialCompliance(x), Target::AxialCompliance(y))
                | (Target::Backlash(x), Target::Backlash(y))
                | (Target::Friction(x), Target::Friction(y)) => {
                    let (cx, cy) = (Param::cables(x, n), Param::cables(y, n));
                    cx.iter().any(|c| cy.contains(c))
                }
                (Target::Marker(x), Target::Marker(y)) => x == y,
                (Target::BaseRotation(x), Target::BaseRotation(y)) => x == y,
                (Target::Stiffening, Target::Stiffening) => true,
                _ => false,
            };
            if overlap {
                return Err(SolveError::InvalidInput {
                    field: format!("fit `{}`", a.name),
                    reason: format!("sets a value `{}` already sets", b.name),
                });
            }
        }
    }
    if ps.is_empty() {
        return Err(SolveError::InvalidInput {
            field: "fit".into(),
            reason: "no parameter to fit".into(),
        });
    }
    Ok(ps)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v4() -> Model {
        Model::from_file(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/hardware/ftdcr_v4.toml"
        ))
        .expect("v4")
    }

    /// `axial-compliance.seg2 = 1/EA` gives each distal cable `k = EA/ℓ` with ℓ its length from
    /// the base to disk 30 (186.5 mm of straight tendon), leaves the other cables alone, and
    /// reads back as 1/EA; `base.rz` (`rx`, `ry`) is the z (x, y) of the base rotation vector.
    #[test]
    fn axial_compliance_is_ea_over_length_and_base_rz_turns_the_base() {
        let mut m = v4();
        let ps = parse_all(
            &["axial-compliance.seg2".into(), "base.rz".into()],
            &m.robot,
        )
        .expect("names");
        let ea = 400.0; // N
        ps[0].set(&mut m, 1.0 / ea);
        ps[1].set(&mut m, 0.05);
        for (c, cable) in m.robot.cables.iter().enumerate() {
            if c >= 6 {
                let k = cable.stiffness.expect("compliant");
                assert!((k - ea / 0.1865).abs() < 1e-9 * k, "cable {c}: {k}");
            } else {
                assert_eq!(cable.stiffness, None, "cable {c}");
            }
        }
        assert!((ps[0].get(&m) - 1.0 / ea).abs() < 1e-15);
        assert_eq!(
            m.hardware.base_rotation,
            nalgebra::Vector3::new(0.0, 0.0, 0.05)
        );
        assert_eq!(ps[1].get(&m), 0.05);
        // Both forms of the compliance set a cable's stiffness: refused together, by name.
        let e = parse_all(
            &["compliance".into(), "axial-compliance.seg1".into()],
            &m.robot,
        )
        .expect_err("overlap");
        assert!(e.to_string().contains("axial-compliance.seg1"), "{e}");
        // base.rx / base.ry are the rotation vector's other components; each once.
        let tilt = parse_all(&["base.rx".into(), "base.ry".into()], &m.robot).expect("tilt");
        tilt[0].set(&mut m, -0.04);
        tilt[1].set(&mut m, 0.01);
        assert_eq!(
            m.hardware.base_rotation,
            nalgebra::Vector3::new(-0.04, 0.01, 0.05)
        );
        assert_eq!((tilt[0].get(&m), tilt[1].get(&m)), (-0.04, 0.01));
        let e = parse_all(&["base.ry".into(), "base.ry".into()], &m.robot).expect_err("twice");
        assert!(e.to_string().contains("base.ry"), "{e}");
        let e = parse_all(&["base.rw".into()], &m.robot).expect_err("no such axis");
        assert!(e.to_string().contains("base.rx, base.ry or base.rz"), "{e}");
        // A projected step stays in the model.
        assert_eq!(ps[0].project(-1e-3), 0.0);
        assert_eq!(ps[1].project(-0.3), -0.3);
    }
}
