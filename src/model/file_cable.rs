//! One cable of a model file ([`super::file`]): its routing (hole radii and angles, per disk or
//! by rule), its compliance (stiffness, pretension) and its drive (shortening or tension),
//! checked against the disks and the backbone, errors naming `cables[i].field`.

use super::actuation::{CableDrive, Shortening};
use super::bounds;
use super::file::finite;
use super::robot::{Cable, Robot};
use super::robot_check::{hole_radius, pretension};
use super::routing::Helix;
use crate::error::ModelError;
use nalgebra::Vector3;
use serde::Deserialize;

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum FileRadius {
    One(f64),
    PerDisk(Vec<f64>),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
enum FileAngleRule {
    Straight(f64),
    Helix(FileHelix),
}

/// `helix = { start, per_disk }` or `helix = { start, per_metre }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileHelix {
    start: f64,
    per_disk: Option<f64>,
    per_metre: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum FileAngles {
    PerDisk(Vec<f64>),
    Rule(FileAngleRule),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileCable {
    pub(super) name: String,
    radius: FileRadius,
    angles: FileAngles,
    ends_at: Option<i64>,
    shorten: Option<f64>,
    shorten_percent: Option<f64>,
    tension: Option<f64>,
    /// Axial stiffness of cable and actuator \[N/m\] (absent: inextensible).
    stiffness: Option<f64>,
    /// Pretension \[N\] (needs `stiffness`).
    pretension: Option<f64>,
}

/// Undeformed straight-chord length of `cable` through disks at arc lengths `disk_s` \[m\].
fn chord_length(cable: &Cable, disk_s: &[f64]) -> f64 {
    (1..=cable.ends_at)
        .map(|i| {
            (cable.hole(i) - cable.hole(i - 1) + Vector3::new(0.0, 0.0, disk_s[i] - disk_s[i - 1]))
                .norm()
        })
        .sum()
}

/// A cable's `stiffness` and `pretension`, checked (`f` names a field of this cable; the
/// pretension's stretch must stay below the cable's undeformed length `len`).
fn compliance(
    fc: &FileCable,
    f: &dyn Fn(&str) -> String,
    len: f64,
) -> Result<(Option<f64>, f64), ModelError> {
    let k = fc
        .stiffness
        .map(|k| bounds::CABLE_STIFFNESS.check(&f("stiffness"), k))
        .transpose()?;
    pretension(&f("pretension"), fc.pretension, k, len)?;
    let t0 = fc.pretension.unwrap_or(0.0);
    Ok((k, t0))
}

impl FileCable {
    /// The routed cable `cables[ci]` of `robot` (its stations, disks, backbone and body; its
    /// cables so far are not read): end disk, hole radii and angles, checked against the disk
    /// and the backbone.
    pub(super) fn cable(&self, ci: usize, robot: &Robot) -> Result<Cable, ModelError> {
        let disk_s = &robot.disk_s[..];
        let f = |name: &str| format!("cables[{ci}].{name}");
        super::name::check_name(f("name"), &self.name)?;
        let n = disk_s.len() - 1;
        let ends_at = match self.ends_at {
            None => n,
            Some(e) if e >= 1 && e as usize <= n => e as usize,
            Some(e) => {
                return Err(ModelError::invalid(
                    f("ends_at"),
                    format!("must be a disk between 1 and {n}, got {e}"),
                ))
            }
        };
        let (angle, helix) = self.angles(ci, ends_at, disk_s)?;
        let mut cable = Cable {
            name: self.name.clone(),
            ends_at,
            radius: self.radii(ci, ends_at, robot)?,
            angle,
            helix,
            stiffness: None,
            pretension: 0.0,
        };
        (cable.stiffness, cable.pretension) = compliance(self, &f, chord_length(&cable, disk_s))?;
        Ok(cable)
    }

    /// One hole radius per disk `0..=ends_at`, each between the backbone and the disk rim (in
    /// the rod's wall for cables inside the rod).
    fn radii(&self, ci: usize, ends_at: usize, robot: &Robot) -> Result<Vec<f64>, ModelError> {
        let count = ends_at + 1;
        let radius = match &self.radius {
            FileRadius::One(r) => vec![*r; count],
            FileRadius::PerDisk(v) => {
                if v.len() != count {
                    return Err(ModelError::invalid(
                        format!("cables[{ci}].radius"),
                        format!(
                            "needs one radius per disk the cable passes (0..={ends_at}: {count}), got {}",
                            v.len()
                        ),
                    ));
                }
                v.clone()
            }
        };
        for (k, rr) in radius.iter().enumerate() {
            let field = if matches!(self.radius, FileRadius::One(_)) {
                format!("cables[{ci}].radius")
            } else {
                format!("cables[{ci}].radius[{k}]")
            };
            hole_radius(&field, *rr, robot)?;
        }
        Ok(radius)
    }

    /// One hole angle per disk `0..=ends_at`, from a rule or a per-disk table, and the rule
    /// as a helix per metre of arc where there is one (`per_disk` on unequally spaced disks is
    /// a table: its holes do not lie on one helix).
    fn angles(
        &self,
        ci: usize,
        ends_at: usize,
        disk_s: &[f64],
    ) -> Result<(Vec<f64>, Option<Helix>), ModelError> {
        let f = |name: &str| format!("cables[{ci}].{name}");
        let count = ends_at + 1;
        Ok(match &self.angles {
            FileAngles::Rule(FileAngleRule::Straight(a)) => {
                let a = bounds::ANGLE.check(&f("angles.straight"), *a)?;
                let helix = Helix {
                    start: a,
                    per_metre: 0.0,
                };
                (vec![a; count], Some(helix))
            }
            FileAngles::Rule(FileAngleRule::Helix(h)) => {
                let start = bounds::ANGLE.check(&f("angles.helix.start"), h.start)?;
                match (h.per_disk, h.per_metre) {
                    (Some(_), Some(_)) | (None, None) => {
                        return Err(ModelError::invalid(
                            f("angles.helix"),
                            "give exactly one of per_disk [rad per disk] or per_metre [rad/m]",
                        ))
                    }
                    (Some(pd), None) => {
                        bounds::HELIX_PER_DISK.check(&f("angles.helix.per_disk"), pd)?;
                        let angle: Vec<f64> = (0..count).map(|k| start + pd * k as f64).collect();
                        let ell = disk_s[1] - disk_s[0];
                        let equal = (1..=ends_at)
                            .all(|k| ((disk_s[k] - disk_s[k - 1]) - ell).abs() <= 1e-12 * ell);
                        let helix = equal.then_some(Helix {
                            start,
                            per_metre: pd / ell,
                        });
                        (angle, helix)
                    }
                    (None, Some(w)) => {
                        let field = f("angles.helix.per_metre");
                        bounds::HELIX_PER_METRE.check(&field, w)?;
                        let end = start + w * disk_s[ends_at];
                        bounds::ANGLE.check(&field, end).map_err(|_| {
                            ModelError::invalid(
                                &field,
                                format!(
                                    "turns the cable to {end:e} rad at its end, beyond ±{:e} rad",
                                    bounds::ANGLE.hi
                                ),
                            )
                        })?;
                        let angle = (0..count).map(|k| start + w * disk_s[k]).collect();
                        let helix = Helix {
                            start,
                            per_metre: w,
                        };
                        (angle, Some(helix))
                    }
                }
            }
            FileAngles::PerDisk(v) => {
                if v.len() != count {
                    return Err(ModelError::invalid(
                        f("angles"),
                        format!(
                            "needs one angle per disk the cable passes (0..={ends_at}: {count}), got {}",
                            v.len()
                        ),
                    ));
                }
                for (k, a) in v.iter().enumerate() {
                    bounds::ANGLE.check(&format!("cables[{ci}].angles[{k}]"), *a)?;
                }
                (v.clone(), None)
            }
        })
    }

    /// The file's shortening and tension for this cable, bounded by its undeformed length.
    pub(super) fn drive(
        &self,
        ci: usize,
        cable: &Cable,
        disk_s: &[f64],
    ) -> Result<CableDrive, ModelError> {
        let f = |name: &str| format!("cables[{ci}].{name}");
        let shorten = match (self.shorten, self.shorten_percent) {
            (Some(_), Some(_)) => {
                return Err(ModelError::invalid(
                    f("shorten_percent"),
                    "give either shorten or shorten_percent, not both",
                ))
            }
            (Some(d), None) => {
                finite(&f("shorten"), d)?;
                // Undeformed chord length, to check an absolute shortening against.
                let chord_len = chord_length(cable, disk_s);
                if d >= chord_len {
                    return Err(ModelError::invalid(
                        f("shorten"),
                        format!(
                            "{d} m is not less than the cable's undeformed length {chord_len:.6} m"
                        ),
                    ));
                }
                if d <= -chord_len {
                    return Err(ModelError::invalid(
                        f("shorten"),
                        format!(
                            "a payout of {:e} m is not smaller than the cable's undeformed length {chord_len:.6} m",
                            -d
                        ),
                    ));
                }
                Some(Shortening::Length(d))
            }
            (None, Some(p)) => {
                finite(&f("shorten_percent"), p)?;
                if p >= 100.0 {
                    return Err(ModelError::invalid(
                        f("shorten_percent"),
                        format!("{p} % would shorten the cable to nothing (must be < 100)"),
                    ));
                }
                if p <= -100.0 {
                    return Err(ModelError::invalid(
                        f("shorten_percent"),
                        format!("{p} % is not a plausible payout (must be > -100)"),
                    ));
                }
                Some(Shortening::Fraction(p / 100.0))
            }
            (None, None) => None,
        };
        let tension = match self.tension {
            Some(t) if t.is_finite() && t < 0.0 => {
                return Err(ModelError::invalid(
                    f("tension"),
                    format!("cables pull, they do not push: must be >= 0, got {t}"),
                ))
            }
            Some(t) => Some(bounds::TENSION.check(&f("tension"), t)?),
            None => None,
        };
        Ok(CableDrive {
            shorten,
            tension,
            capstan: 0.0,
        })
    }
}
