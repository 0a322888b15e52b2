//! Plans for the view: the JSON `ccrkit plan` writes: an object whose `waypoints`
//! each carry a `shape` in the format of [`Shape::to_json`](crate::shape::Shape::to_json);
//! other fields (actuation, statistics, clearance) are not needed to draw and are skipped,
//! except a waypoint's `insertion` \[m\] and `rotation` \[rad\] (robots with a port), which
//! must be finite and be the shape's own (a hand-edited plan whose base values and shapes
//! disagree is refused by waypoint); the view then checks each shape against the robot
//! (disks, cables, port pose, insertion within `[0, L]`).
//!
//! A plan names what it was made for (`made_for`, [`MadeFor`]): a plan read with another
//! robot (a hole radius of 4.0 mm instead of 4.5) or other obstacles is refused by name
//! (`plan.made_for.robot_fingerprint`, `….scene_fingerprint`), and so is a plan that names
//! nothing. No clearance is read from the file: the view draws shapes and obstacles only.

use super::ExportError;
use crate::fingerprint::MadeFor;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::{Shape, ShapeJson};
use serde::Deserialize;

#[derive(Deserialize)]
struct PlanFile {
    waypoints: Vec<Waypoint>,
    #[serde(default)]
    made_for: Option<MadeFor>,
}

#[derive(Deserialize)]
struct Waypoint {
    shape: ShapeJson,
    #[serde(default)]
    insertion: Option<f64>,
    #[serde(default)]
    rotation: Option<f64>,
}

/// Why waypoint `k`'s `insertion` / `rotation` disagree with its shape's port (`None`: they
/// agree, or neither is given).
fn base_mismatch(k: usize, given: [Option<f64>; 2], shape: &Shape) -> Option<ExportError> {
    let port = shape.port.as_ref().map(|p| (p.insertion, p.rotation));
    [("insertion", given[0]), ("rotation", given[1])]
        .into_iter()
        .enumerate()
        .find_map(|(i, (key, given))| {
            let given = given?;
            let field = format!("waypoints[{k}].{key}");
            let reason = match port {
                _ if !given.is_finite() => format!("{given} is not finite"),
                None => "given, but the waypoint's shape was solved without a port".into(),
                Some(p) => {
                    let own = if i == 0 { p.0 } else { p.1 };
                    if (own - given).abs() <= 1e-12 * own.abs().max(1.0) {
                        return None;
                    }
                    format!("{given} differs from the shape's own {own}")
                }
            };
            Some(ExportError::Input { field, reason })
        })
}

/// The waypoint shapes of a plan, in order, once its `made_for` names `robot` and `scene`
/// (the model's obstacles and any added ones, merged as `plan` merges them).
pub fn read_plan(text: &str, robot: &Robot, scene: &Scene) -> Result<Vec<Shape>, ExportError> {
    let plan: PlanFile = serde_json::from_str(text).map_err(|e| ExportError::Input {
        field: "plan".into(),
        reason: e.to_string(),
    })?;
    if plan.waypoints.is_empty() {
        return Err(ExportError::Input {
            field: "plan.waypoints".into(),
            reason: "no waypoint".into(),
        });
    }
    let shapes = plan
        .waypoints
        .into_iter()
        .enumerate()
        .map(|(k, w)| {
            let given = [w.insertion, w.rotation];
            let shape = w
                .shape
                .into_shape(&format!("waypoints[{k}].shape"))
                .map_err(|e| ExportError::Input {
                    field: e.field().unwrap_or("plan").to_string(),
                    reason: e.to_string(),
                })?;
            match base_mismatch(k, given, &shape) {
                Some(e) => Err(e),
                None => Ok(shape),
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let made_for = plan.made_for.ok_or_else(|| ExportError::Input {
        field: "plan.made_for".into(),
        reason: "the plan does not name the robot and obstacles it was made for (a plan \
                 written before fingerprints, or edited): plan again"
            .into(),
    })?;
    made_for
        .check("plan.made_for", robot, scene)
        .map_err(|e| ExportError::Input {
            field: e.field().unwrap_or("plan.made_for").to_string(),
            reason: match e {
                crate::error::ModelError::Invalid { reason, .. } => reason,
                other => other.to_string(),
            },
        })?;
    Ok(shapes)
}
