//! A solved robot: disk frames, cable paths, contacts and the solver's report.
//!
//! Every method returns a [`Shape`]; every export reads one. Positions in metres, base frame.

use crate::error::ModelError;
use crate::method::warm::WarmState;

#[path = "shape_check.rs"]
mod check;
pub use check::MAX_EXTENT;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Pose of one disk.
#[derive(Debug, Clone, PartialEq)]
pub struct DiskFrame {
    /// Arc length of the disk along the undeformed backbone \[m\].
    pub s: f64,
    /// Backbone point at the disk \[m\].
    pub position: Vector3<f64>,
    /// Disk orientation: columns are the disk's x, y, z axes in the base frame; z is the disk
    /// normal, x points at angle 0 of the hole pattern.
    pub rotation: Matrix3<f64>,
}

/// Path of one cable through the disks it passes.
#[derive(Debug, Clone, PartialEq)]
pub struct CablePath {
    /// Cable name.
    pub name: String,
    /// Hole positions at disks `0..=ends_at` \[m\].
    pub points: Vec<Vector3<f64>>,
    /// True when the cable is slack somewhere (its path is shorter than its length).
    pub slack: bool,
    /// Sections (1-based) where the cable is slack.
    pub slack_sections: Vec<usize>,
    /// Tension \[N\], where the method computes one.
    pub tension: Option<f64>,
    /// Shortening \[m\]: the change of the cable's path length (undeformed minus solved, in
    /// the method's length measure) plus, for a compliant cable, its stretch `T/k − T₀/k` —
    /// the displacement under which the same method, displacement-driven, returns this shape.
    /// Every method reports it for every cable, whatever drove it (`None` only in a shape read
    /// from a file that lacks it).
    pub shortening: Option<f64>,
}

/// A contact between the robot and an obstacle (filled by obstacle-aware methods).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    /// Obstacle name.
    pub obstacle: String,
    /// Robot feature: `backbone`, `disk` or `cable` (`cable:NAME` names the cable).
    pub feature: String,
    /// Disk index, for disk features.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub disk: Option<usize>,
    /// Section index (1-based), for backbone and cable-chord features.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<usize>,
    /// Closest point on the robot \[m\].
    pub point_robot: [f64; 3],
    /// Closest point on the obstacle \[m\].
    pub point_obstacle: [f64; 3],
    /// Contact normal, unit, from the obstacle towards the robot.
    pub normal: [f64; 3],
    /// Signed distance between the two (≈ the clearance for an active contact) \[m\].
    pub distance: f64,
    /// Multiplier of the active distance constraint (≥ 0): a reaction in the units of the
    /// method's objective per metre (rad/m for the geometric methods, N for energy methods).
    pub multiplier: f64,
}

/// What happened in one section of a section-by-section method.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SectionReport {
    /// Section index (1-based).
    pub section: usize,
    /// Iterations spent (summed over every candidate examined).
    pub iterations: usize,
    /// Largest constraint residual of the accepted solution \[m\].
    pub residual: f64,
    /// Objective value of the accepted solution.
    pub objective: f64,
    /// Objective terms that are exactly zero at the accepted solution (`tangent`, or a cable name).
    pub zero_terms: Vec<String>,
    /// Cables slack in this section.
    pub slack: Vec<String>,
    /// How many candidates (faces × starts) were certified.
    pub candidates: usize,
}

/// How a solve went.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct SolveReport {
    /// True when every tolerance was met.
    pub converged: bool,
    /// Total iterations.
    pub iterations: usize,
    /// Largest residual (constraint residual \[m\] for geometric methods, shooting residual for rods).
    pub residual: f64,
    /// Wall time of the solve \[s\] (median over `--repeat` where the CLI sets it).
    pub solve_time_s: f64,
    /// Per-section details (section methods).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<SectionReport>,
    /// Internal force and moment at the base, base frame [N, N m] (rod methods).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_wrench: Option<[f64; 6]>,
    /// Notes: choices made, inputs ignored.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// Whether the answer is a stable equilibrium: `Some(true)` when the method verified it
    /// (energy: the reduced Hessian on the active constraints is positive definite),
    /// `Some(false)` when it found the answer unstable (a saddle: the robot would not stay
    /// there), `None` when the method cannot tell or was asked not to check (the rods'
    /// `stability = skip`, noted in `notes`). See each method's docs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stable: Option<bool>,
    /// Sensitivities of the tip to the inputs, where the method computes them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub jacobian: Option<TipJacobian>,
    /// The estimated distance of the tip from the converged reference rod for the same
    /// inputs, when asked for ([`SolveRequest::estimate`](crate::method::run::SolveRequest),
    /// `--estimate`; [`crate::method::estimate`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_estimate: Option<crate::method::estimate::ErrorEstimate>,
    /// What `auto` chose for this answer and what that cost ([`crate::method::auto`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub auto: Option<crate::method::auto::AutoReport>,
    /// Whether the answer is the only equilibrium found along other paths, when asked for
    /// ([`SolveRequest::check_unique`](crate::method::run::SolveRequest), `--check unique`;
    /// [`crate::method::unique`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unique: Option<crate::method::unique::UniqueReport>,
    /// Method-specific solver state for warm starts (not serialized).
    #[serde(skip)]
    pub warm: Option<WarmState>,
}

/// Sensitivities of the tip to the driven cables' inputs at a solved shape: one column per
/// driven cable (in robot order), `position[j] = ∂p_tip/∂u_j` [m per input unit] and
/// `tangent[j] = ∂t_tip/∂u_j` (t: the tip disk's normal), where `u_j` is the cable's shortening
/// \[m\] or tension \[N\] as `inputs[j]` says.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TipJacobian {
    /// The column's cable and input: `(cable name, "shortening" | "tension")`.
    pub inputs: Vec<(String, String)>,
    /// `∂p_tip/∂u_j`, one 3-vector per column, base frame.
    pub position: Vec<[f64; 3]>,
    /// `∂t_tip/∂u_j`, one 3-vector per column, base frame.
    pub tangent: Vec<[f64; 3]>,
}

/// A solved shape.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// Method that produced it.
    pub method: String,
    /// Disk frames `0..=n`.
    pub disks: Vec<DiskFrame>,
    /// Dense backbone samples (at least the disk positions) \[m\].
    pub backbone: Vec<Vector3<f64>>,
    /// Cable paths, in robot order.
    pub cables: Vec<CablePath>,
    /// Contacts with obstacles.
    pub contacts: Vec<Contact>,
    /// Solver report.
    pub report: SolveReport,
    /// Where the robot stood in its port (`None` for a robot without a port). With a port
    /// every position of the shape is in the scene frame, disks behind the port included.
    pub port: Option<PortState>,
}

/// A robot's place in its port at one solve ([`crate::model::port`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PortState {
    /// The port frame in the scene frame (origin at the port, +z out of it).
    pub pose: nalgebra::Isometry3<f64>,
    /// Insertion `d` \[m\]: the robot's length out of the port.
    pub insertion: f64,
    /// Rotation `ψ` \[rad\] about the port axis.
    pub rotation: f64,
    /// The first disk beyond the port (`disks.len()` when every disk is at or behind it);
    /// the disks before it lie straight along the port axis, behind the port.
    pub first_disk: usize,
}

impl PortState {
    /// JSON form.
    pub fn to_json(&self) -> PortJson {
        let r = self.pose.rotation.to_rotation_matrix().into_inner();
        let t = self.pose.translation.vector;
        PortJson {
            position: [t.x, t.y, t.z],
            orientation: rows(&r),
            insertion: self.insertion,
            rotation: self.rotation,
            first_disk: self.first_disk,
        }
    }
}

/// JSON form of a [`PortState`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PortJson {
    /// Port origin, scene frame \[m\].
    pub position: [f64; 3],
    /// Port frame's rotation in the scene frame, row-major (its third column is the axis).
    pub orientation: [[f64; 3]; 3],
    /// Insertion `d` \[m\].
    pub insertion: f64,
    /// Rotation `ψ` \[rad\].
    pub rotation: f64,
    /// First disk beyond the port.
    pub first_disk: usize,
}

impl PortJson {
    /// The port state this JSON describes; `field` prefixes the field names in errors.
    pub fn into_state(self, field: &str) -> Result<PortState, ModelError> {
        let o = &self.orientation;
        let nums = [
            self.position[0],
            self.position[1],
            self.position[2],
            self.insertion,
            self.rotation,
        ];
        if nums
            .iter()
            .chain(o.iter().flatten())
            .any(|x| !x.is_finite())
        {
            return Err(ModelError::invalid(
                format!("{field}.port"),
                "numbers must be finite",
            ));
        }
        let m = Matrix3::new(
            o[0][0], o[0][1], o[0][2], o[1][0], o[1][1], o[1][2], o[2][0], o[2][1], o[2][2],
        );
        check::rotation(&m, || format!("{field}.port.orientation"))?;
        check::point(&self.position, || format!("{field}.port.position"))?;
        let q = nalgebra::UnitQuaternion::from_matrix(&m);
        let t = nalgebra::Translation3::from(Vector3::from(self.position));
        Ok(PortState {
            pose: nalgebra::Isometry3::from_parts(t, q),
            insertion: self.insertion,
            rotation: self.rotation,
            first_disk: self.first_disk,
        })
    }
}

fn rows(r: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [
        [r[(0, 0)], r[(0, 1)], r[(0, 2)]],
        [r[(1, 0)], r[(1, 1)], r[(1, 2)]],
        [r[(2, 0)], r[(2, 1)], r[(2, 2)]],
    ]
}

impl Shape {
    /// Tip (last disk) position.
    pub fn tip(&self) -> Vector3<f64> {
        self.disks[self.disks.len() - 1].position
    }

    /// Root-mean-square distance between corresponding disk positions of two shapes \[m\].
    /// Both must have the same number of disks (else `None`).
    pub fn rms_distance(&self, other: &Shape) -> Option<f64> {
        if self.disks.len() != other.disks.len() || self.disks.is_empty() {
            return None;
        }
        let sum: f64 = self
            .disks
            .iter()
            .zip(&other.disks)
            .map(|(a, b)| (a.position - b.position).norm_squared())
            .sum();
        Some((sum / self.disks.len() as f64).sqrt())
    }

    /// Distance between the tips of two shapes \[m\].
    pub fn tip_distance(&self, other: &Shape) -> f64 {
        (self.tip() - other.tip()).norm()
    }

    /// Serializable form (see [`ShapeJson`]).
    pub fn to_json(&self) -> ShapeJson {
        ShapeJson {
            model: None,
            method: self.method.clone(),
            input: None,
            disks: self
                .disks
                .iter()
                .map(|d| DiskJson {
                    s: d.s,
                    position: arr(&d.position),
                    rotation: rows(&d.rotation),
                })
                .collect(),
            backbone: self.backbone.iter().map(arr).collect(),
            cables: self
                .cables
                .iter()
                .map(|c| CableJson {
                    name: c.name.clone(),
                    points: c.points.iter().map(arr).collect(),
                    slack: c.slack,
                    slack_sections: c.slack_sections.clone(),
                    tension: c.tension,
                    shortening: c.shortening,
                })
                .collect(),
            contacts: self.contacts.clone(),
            report: self.report.clone(),
            port: self.port.as_ref().map(PortState::to_json),
        }
    }

    /// JSON text (pretty-printed).
    pub fn to_json_string(&self) -> String {
        // Serializing plain structs of numbers and strings cannot fail.
        serde_json::to_string_pretty(&self.to_json())
            .unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}

impl ShapeJson {
    /// The shape this JSON describes (the reader of [`Shape::to_json`]'s output; warm-start
    /// state is not carried). Refused when there is no disk, a number is not finite, a point
    /// lies beyond [`MAX_EXTENT`], a rotation is not one, or a cable's holes or slack sections
    /// do not fit the disks (`src/shape_check.rs`); `field` prefixes the field names in errors
    /// (e.g. `waypoints[3].shape`).
    pub fn into_shape(self, field: &str) -> Result<Shape, ModelError> {
        if self.disks.is_empty() {
            return Err(ModelError::invalid(
                format!("{field}.disks"),
                "a shape has at least the base disk",
            ));
        }
        let finite = |v: &[f64], f: String| {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(ModelError::invalid(f, "numbers must be finite"))
            }
        };
        let mut disks = Vec::with_capacity(self.disks.len());
        for (k, d) in self.disks.iter().enumerate() {
            let r = &d.rotation;
            let flat = [
                d.s,
                d.position[0],
                d.position[1],
                d.position[2],
                r[0][0],
                r[0][1],
                r[0][2],
                r[1][0],
                r[1][1],
                r[1][2],
                r[2][0],
                r[2][1],
                r[2][2],
            ];
            finite(&flat, format!("{field}.disks[{k}]"))?;
            check::point(&d.position, || format!("{field}.disks[{k}].position"))?;
            let rotation = Matrix3::new(
                r[0][0], r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1], r[2][2],
            );
            check::rotation(&rotation, || format!("{field}.disks[{k}].rotation"))?;
            disks.push(DiskFrame {
                s: d.s,
                position: Vector3::from(d.position),
                rotation,
            });
        }
        let mut backbone = Vec::with_capacity(self.backbone.len());
        for (i, p) in self.backbone.iter().enumerate() {
            check::point(p, || format!("{field}.backbone[{i}]"))?;
            backbone.push(Vector3::from(*p));
        }
        for (i, c) in self.contacts.iter().enumerate() {
            check::contact(c, &format!("{field}.contacts[{i}]"))?;
        }
        let mut cables = Vec::with_capacity(self.cables.len());
        for (c, cj) in self.cables.into_iter().enumerate() {
            let at = format!("{field}.cables[{c}]");
            check::cable(cj.points.len(), &cj.slack_sections, disks.len(), &at)?;
            for (i, p) in cj.points.iter().enumerate() {
                check::point(p, || format!("{at}.points[{i}]"))?;
            }
            cables.push(CablePath {
                name: cj.name,
                points: cj.points.into_iter().map(Vector3::from).collect(),
                slack: cj.slack,
                slack_sections: cj.slack_sections,
                tension: cj.tension,
                shortening: cj.shortening,
            });
        }
        let port = self.port.map(|p| p.into_state(field)).transpose()?;
        Ok(Shape {
            method: self.method,
            disks,
            backbone,
            cables,
            contacts: self.contacts,
            report: self.report,
            port,
        })
    }
}

impl Shape {
    /// Read a shape back from the JSON text [`Shape::to_json_string`] writes.
    pub fn from_json_str(text: &str) -> Result<Shape, ModelError> {
        let j: ShapeJson = serde_json::from_str(text).map_err(|e| ModelError::Parse {
            path: "<shape JSON>".into(),
            reason: e.to_string(),
        })?;
        j.into_shape("shape")
    }
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// JSON form of a disk frame: rotation is row-major 3×3.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DiskJson {
    /// Arc length \[m\].
    pub s: f64,
    /// Position \[m\].
    pub position: [f64; 3],
    /// Rotation, row-major.
    pub rotation: [[f64; 3]; 3],
}

/// JSON form of a cable path.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CableJson {
    /// Cable name.
    pub name: String,
    /// Hole positions per disk it passes \[m\].
    pub points: Vec<[f64; 3]>,
    /// Slack anywhere.
    pub slack: bool,
    /// Sections where slack.
    pub slack_sections: Vec<usize>,
    /// Tension \[N\] where computed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tension: Option<f64>,
    /// Shortening \[m\] (see [`CablePath::shortening`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shortening: Option<f64>,
}

/// JSON form of a [`Shape`].
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShapeJson {
    /// Name of the model (robot) solved, where the writer knew it (the CLI's `solve --json`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// Method name.
    pub method: String,
    /// The input that drove the solve, where the writer knew it (the CLI's `solve --json`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub input: Option<DrivenBy>,
    /// Disk frames.
    pub disks: Vec<DiskJson>,
    /// Dense backbone samples.
    pub backbone: Vec<[f64; 3]>,
    /// Cable paths.
    pub cables: Vec<CableJson>,
    /// Contacts.
    pub contacts: Vec<Contact>,
    /// Solver report.
    pub report: SolveReport,
    /// The robot's place in its port (absent without a port).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub port: Option<PortJson>,
}

/// What drove a solve: the method's input where a cable gives both, and each cable's drive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DrivenBy {
    /// `shortening` or `tension`: the input the method used where a cable gave both.
    pub control: String,
    /// Method settings given (`name`, `value`), in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub settings: Vec<(String, String)>,
    /// Per cable, in robot order.
    pub cables: Vec<CableDriveJson>,
    /// Insertion `d` through the port \[m\] (absent without a port).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub insertion: Option<f64>,
    /// Rotation `ψ` about the port axis \[rad\] (absent without a port).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<f64>,
}

/// One cable's drive in a solve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CableDriveJson {
    /// Cable name.
    pub name: String,
    /// `shorten`, `tension` or `free`.
    pub drive: String,
    /// Shortening at the base \[m\] (for `shorten`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shorten_m: Option<f64>,
    /// Tension \[N\] (for `tension`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tension_n: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Shape {
        let rot = nalgebra::Rotation3::from_euler_angles(0.1, -0.2, 0.3).into_inner();
        Shape {
            method: "energy".into(),
            disks: vec![
                DiskFrame {
                    s: 0.0,
                    position: Vector3::zeros(),
                    rotation: Matrix3::identity(),
                },
                DiskFrame {
                    s: 0.02,
                    position: Vector3::new(0.001, -0.002, 0.0199),
                    rotation: rot,
                },
            ],
            backbone: vec![Vector3::zeros(), Vector3::new(0.001, -0.002, 0.0199)],
            cables: vec![CablePath {
                name: "A".into(),
                points: vec![
                    Vector3::new(0.008, 0.0, 0.0),
                    Vector3::new(0.009, 0.0, 0.02),
                ],
                slack: false,
                slack_sections: vec![],
                tension: Some(1.5),
                shortening: Some(0.001),
            }],
            contacts: vec![],
            port: None,
            report: SolveReport {
                converged: true,
                iterations: 7,
                residual: 1e-12,
                ..Default::default()
            },
        }
    }

    #[test]
    fn json_round_trip_gives_the_same_shape() {
        let s = sample();
        let back = Shape::from_json_str(&s.to_json_string()).expect("reads back");
        assert_eq!(back, s);
    }

    #[test]
    fn json_without_disks_is_refused_by_field() {
        let mut j = sample().to_json();
        j.disks.clear();
        let e = j.into_shape("waypoints[2].shape").unwrap_err();
        assert_eq!(e.field(), Some("waypoints[2].shape.disks"));
        let e = Shape::from_json_str("{\"method\": 3}").unwrap_err();
        assert!(matches!(e, ModelError::Parse { .. }), "{e}");
    }
}
