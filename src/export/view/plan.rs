//! Plans for the view: the JSON `ccrkit plan` writes: an object whose `waypoints`
//! each carry a `shape` in the format of [`Shape::to_json`](crate::shape::Shape::to_json);
//! other fields (actuation, statistics, clearance) are not needed to draw and are skipped.

use super::ExportError;
use crate::shape::{Shape, ShapeJson};
use serde::Deserialize;

#[derive(Deserialize)]
struct PlanFile {
    waypoints: Vec<Waypoint>,
}

#[derive(Deserialize)]
struct Waypoint {
    shape: ShapeJson,
}

/// The waypoint shapes of a plan, in order.
pub fn read_plan(text: &str) -> Result<Vec<Shape>, ExportError> {
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
    plan.waypoints
        .into_iter()
        .enumerate()
        .map(|(k, w)| {
            w.shape
                .into_shape(&format!("waypoints[{k}].shape"))
                .map_err(|e| ExportError::Input {
                    field: e.field().unwrap_or("plan").to_string(),
                    reason: e.to_string(),
                })
        })
        .collect()
}
