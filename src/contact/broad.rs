//! Broad phase: which obstacles can matter, from their axis-aligned bounds, before any
//! narrow-phase query; and the base-disk check every method makes first.

use super::features;
use super::CONTACT_TOL;
use crate::error::SolveError;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use nalgebra::Vector3;

/// Robot level: the obstacles whose bounds come within reach of the base (the robot's length
/// plus a disk's radius and thickness plus the clearance: nothing farther can touch it), after
/// checking that the base disk is clear of every one of them.
pub(crate) fn robot_obstacles(robot: &Robot, scene: &Scene) -> Result<Vec<usize>, SolveError> {
    let reach = robot.length() + robot.disk_radius + scene.clearance + robot.disk_thickness;
    let near = scene.near(&Vector3::zeros(), reach);
    check_base(robot, scene, &near)?;
    Ok(near)
}

/// The obstacles of `among` whose bounds come within `margin` of the box `lo..hi`, and the
/// smallest gap of the others (infinite when none is left out): a lower bound on their
/// distance from anything inside the box.
pub(crate) fn within_box(
    scene: &Scene,
    among: &[usize],
    lo: &Vector3<f64>,
    hi: &Vector3<f64>,
    margin: f64,
) -> (Vec<usize>, f64) {
    let mut clear = f64::INFINITY;
    let mut kept = Vec::with_capacity(among.len());
    for &k in among {
        let gap = scene.bounds_gap(k, lo, hi);
        if gap > margin {
            clear = clear.min(gap);
        } else {
            kept.push(k);
        }
    }
    (kept, clear)
}

/// The base disk must not lie inside (or within the clearance of) an obstacle.
pub(crate) fn check_base(
    robot: &Robot,
    scene: &Scene,
    relevant: &[usize],
) -> Result<(), SolveError> {
    let disk = features::disk(robot);
    let pose = super::ppose(&super::y_to_z(), &Vector3::zeros());
    for &k in relevant {
        let o = &scene.obstacles[k];
        if let Ok(Some(ct)) =
            parry3d::query::contact(&pose, &disk, &o.parry_pose, &*o.shape, scene.clearance)
        {
            if ct.dist < scene.clearance - CONTACT_TOL {
                return Err(SolveError::Obstructed {
                    obstacle: o.name.clone(),
                    section: 0,
                    reason: format!(
                        "the base disk lies inside or within the clearance of this obstacle (distance {:.3e} m)",
                        ct.dist
                    ),
                });
            }
        }
    }
    Ok(())
}
