//! The fixture of the energy model's unit tests of contact derivatives (`contacts.rs`:
//! `∂d/∂ξ`, `contact_curvature.rs`: `∇²d`): paper case II next to a tilted box, a ball and a
//! third tilted obstacle, and a bent, twisted, stretched state of its strains, so that the
//! backbone, the disks and the cable chords all come near an obstacle.

use super::contacts::{Kin, PairKey, World};
use crate::model::robot::Robot;
use crate::model::Model;

/// The third obstacle beside the box and the ball. The tests differ here on purpose: the
/// gradients are checked against a capsule, the Hessians against a cylinder (a disk's rim on
/// a smooth curved side, the slow case of the witness polish).
#[derive(Debug, Clone, Copy)]
pub(super) enum Third {
    /// A capsule `rod` at `y = −25 mm`.
    Capsule,
    /// A cylinder `pillar` at `y = −30 mm`.
    Cylinder,
}

/// Paper case II with a box, a ball and the `third` obstacle (same size and tilt either way).
pub(super) fn case2_beside(third: Third) -> Model {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/models/paper/case2.toml"
    ))
    .expect("case 2");
    let (name, shape, y) = match third {
        Third::Capsule => ("rod", "capsule", "-0.025"),
        Third::Cylinder => ("pillar", "cylinder", "-0.03"),
    };
    Model::from_toml_str(&format!(
        "{text}
[[obstacles]]
name = \"box\"
shape = \"box\"
position = [0.03, 0.0, 0.12]
rotation = {{ rpy = [0.2, 0.3, 0.1] }}
half_extents = [0.01, 0.03, 0.02]
[[obstacles]]
name = \"ball\"
shape = \"sphere\"
position = [-0.02, 0.02, 0.09]
radius = 0.012
[[obstacles]]
name = \"{name}\"
shape = \"{shape}\"
position = [0.0, {y}, 0.15]
rotation = {{ rpy = [1.2, 0.0, 0.4] }}
radius = 0.006
half_height = 0.03
"
    ))
    .expect("model")
}

/// Every obstacle of `model` in the world of `m` sub-arcs per section, with a margin of 5 cm
/// (every pair of the bent state is kept).
pub(super) fn world(model: &Model, m: usize) -> World<'_> {
    let near: Vec<usize> = (0..model.scene.obstacles.len()).collect();
    let first = (0..=model.robot.sections()).map(|k| k * m).collect();
    let mut world = World::new(&model.robot, &model.scene, near, first).expect("world");
    world.margin = 0.05;
    world
}

/// The length of each of the `sections × m` sub-arcs of `robot` (`m` per section).
pub(super) fn sub_arc_lengths(robot: &Robot, m: usize) -> Vec<f64> {
    (0..robot.sections() * m)
        .map(|j| robot.section_length(j / m + 1) / m as f64)
        .collect()
}

/// A bent, twisted, stretched state of `nv` strains (four per sub-arc: two curvatures,
/// twist, stretch), different on every sub-arc.
pub(super) fn bent_state(nv: usize) -> Vec<f64> {
    (0..nv)
        .map(|i| match i % 4 {
            0 => 3.0 + 0.7 * (i as f64).sin(),
            1 => -2.0 + 1.3 * (0.3 * i as f64).cos(),
            2 => 1.5 * (0.2 * i as f64).sin(),
            _ => -2e-3,
        })
        .collect()
}

/// The distance of pair `key` among the pairs `world` finds at `kin` (a perturbed state of a
/// finite-difference check); the pair must still be found there.
pub(super) fn pair_dist(world: &World, kin: &Kin, key: PairKey) -> f64 {
    world
        .pairs(kin)
        .0
        .into_iter()
        .find(|p| p.key() == key)
        .map(|p| p.dist)
        .expect("pair still present")
}
