//! Broad phase: which obstacles can matter, from their axis-aligned bounds, before any
//! narrow-phase query; and the base-disk check every method makes first.

use super::features;
use super::CONTACT_TOL;
use crate::error::SolveError;
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use nalgebra::Vector3;

/// The most feature–obstacle pairs within reach one solve may have: distinct obstacles
/// within reach of the robot times its features ([`robot_features`]). Every contact
/// evaluation of the methods queries at most these pairs, and their iterations are bounded,
/// so the limit bounds a solve's contact work by a count, not a clock.
///
/// Chosen from measurements (user's guide, obstacles): the worst scene per pair is one
/// of nearly coincident boxes (distinct by 1e-9 m) across the robot, where every pair is near
/// every evaluation; paper case I (36 features) with the literal method spends ~6 ms per pair
/// there (64 boxes, 2304 pairs: 13 s on a loaded 2-core machine), the energy model ~0.2 ms.
/// 4096 pairs keep the literal method's worst case near half a minute on such a machine and
/// admit 113 obstacles around case I, 12 around a 30-section robot with 9 cables.
pub(crate) const MAX_PAIRS: usize = 4096;

/// Robot level: the distinct obstacles whose bounds come within reach of the base (the robot's
/// length plus a disk's radius and thickness plus the clearance: nothing farther can touch it;
/// exact duplicates merged, [`Scene::distinct`]), after checking that they stay within the
/// contact budget ([`MAX_PAIRS`]) and that the base disk is clear of every one of them. Every
/// method that handles obstacles, and reach and plan through them, starts here.
pub(crate) fn robot_obstacles(robot: &Robot, scene: &Scene) -> Result<Vec<usize>, SolveError> {
    let (near, _) = within_reach(robot, scene);
    check_budget(robot, near.len())?;
    check_base(robot, scene, &near)?;
    Ok(near)
}

/// The distinct obstacles within reach of the robot (as [`robot_obstacles`], unchecked) and
/// how many exact duplicates among those within reach were merged.
pub(crate) fn within_reach(robot: &Robot, scene: &Scene) -> (Vec<usize>, usize) {
    let reach = robot.length() + robot.disk_radius + scene.clearance + robot.disk_thickness;
    // Through a port, nothing comes out farther than the robot's length from the port.
    let from = robot.port.as_ref().map_or(Vector3::zeros(), |p| p.origin());
    let all = scene.near(&from, reach);
    let n = all.len();
    let near = scene.distinct(all);
    let merged = n - near.len();
    (near, merged)
}

/// The robot's contact features at section resolution: per section its backbone piece and its
/// end disk, and the chord of every cable that runs through it.
pub(crate) fn robot_features(robot: &Robot) -> usize {
    let chords: usize = robot.cables.iter().map(|c| c.ends_at).sum();
    2 * robot.sections() + chords
}

/// [`SolveError::ContactBudget`] when `obstacles` distinct obstacles within reach give more
/// feature–obstacle pairs than [`MAX_PAIRS`].
pub(crate) fn check_budget(robot: &Robot, obstacles: usize) -> Result<(), SolveError> {
    let features = robot_features(robot);
    let pairs = obstacles.saturating_mul(features);
    if pairs > MAX_PAIRS {
        return Err(SolveError::ContactBudget {
            obstacles,
            features,
            pairs,
            limit: MAX_PAIRS,
        });
    }
    Ok(())
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

/// The base disk (for a rod without spacer disks, the ball of the body's radius about the
/// base) must not lie inside (or within the clearance of) an obstacle.
pub(crate) fn check_base(
    robot: &Robot,
    scene: &Scene,
    relevant: &[usize],
) -> Result<(), SolveError> {
    let base: Box<dyn parry3d::shape::Shape> = if robot.has_disks() {
        Box::new(features::disk(robot))
    } else {
        Box::new(parry3d::shape::Ball::new(robot.body_radius()))
    };
    let pose = super::ppose(&super::y_to_z(), &Vector3::zeros());
    for &k in relevant {
        let o = &scene.obstacles[k];
        // The base of a robot in a solid mesh must be on its free side, however far from the
        // wall (the signed distances rely on it: `contact/solid.rs`).
        if let Some(mesh) = super::solid::solid(&*o.shape) {
            if super::solid::in_obstacle(mesh, &o.parry_pose, super::pvec(&Vector3::zeros())) {
                return Err(SolveError::Obstructed {
                    obstacle: o.name.clone(),
                    section: 0,
                    reason: "the base lies on the obstacle side of this solid mesh (outside a lumen, or inside an organ)".into(),
                });
            }
        }
        // A solid's distance signed (`contact/solid.rs`); any other shape's as parry gives it.
        let ct = match super::solid::solid(&*o.shape) {
            Some(_) => super::query(
                &pose,
                &*base,
                &o.parry_pose,
                &*o.shape,
                scene.clearance,
                o.field(),
            ),
            None => {
                parry3d::query::contact(&pose, &*base, &o.parry_pose, &*o.shape, scene.clearance)
                    .ok()
                    .flatten()
            }
        };
        if let Some(ct) = ct {
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
