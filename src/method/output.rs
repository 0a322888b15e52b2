//! Shape assembly shared by every method: cable paths through the solved disks.

use crate::model::robot::Robot;
use crate::shape::{CablePath, DiskFrame};

/// Hole positions of every cable at the solved disks (base frame). `slack_sections[c]` lists
/// the sections (1-based) where cable `c` is slack; tensions are left to the method.
pub fn cable_paths(
    robot: &Robot,
    disks: &[DiskFrame],
    slack_sections: &[Vec<usize>],
) -> Vec<CablePath> {
    robot
        .cables
        .iter()
        .enumerate()
        .map(|(c, cable)| CablePath {
            name: cable.name.clone(),
            points: (0..=cable.ends_at)
                .map(|k| disks[k].position + disks[k].rotation * cable.hole(k))
                .collect(),
            slack: !slack_sections[c].is_empty(),
            slack_sections: slack_sections[c].clone(),
            tension: None,
            shortening: None,
        })
        .collect()
}

/// The change of a cable's length between holes `points` (one per disk it passes, in order)
/// against its undeformed straight chords: undeformed minus solved \[m\] (the geometric
/// methods' measure, [`crate::model::actuation::LengthMeasure::Chord`]).
pub fn chord_shortening(robot: &Robot, c: usize, points: &[nalgebra::Vector3<f64>]) -> f64 {
    let solved: f64 = points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    robot.undeformed_chord_length(c) - solved
}
