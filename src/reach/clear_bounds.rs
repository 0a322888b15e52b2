//! A whole-shape clearance from the solids' signed-distance grids alone: certified bounds
//! `lower ≤ clearance ≤ upper`, enough for the search's margin tests (is this shape at least
//! `margin` from every obstacle?) without a query against the triangles.
//!
//! Each feature–obstacle pair of a solid with a grid is bounded by the grid
//! (`contact/field_interval.rs`): first coarsely (trilinear bounds at samples one cell apart),
//! then, for the pairs whose coarse lower bound is not above the best upper bound so far (the
//! only ones that can hold the smallest lower bound), corner by corner at samples half a cell
//! apart. A pair whose grid gives no bounds is measured exactly (`lower = upper`). A scene with
//! an obstacle that has no grid (a convex shape, a surface mesh) gets no bounds at all: there
//! the exact clearance's bounded question (`clearance_below`, features in the order of their
//! bounds, stopping at the first above the best) is far cheaper than every feature's distance to
//! every obstacle (`plan/vessel_cold`, a surface mesh: 14 ms with it, 430 ms with the pairs).
//!
//! * `upper`: a pair's grid value `u` bounds the feature's smallest signed distance `m` by
//!   `max(u, 0)`; the exact clearance of the pair is `m` when `m > 0` and at most 0 otherwise
//!   (`contact/solid.rs`), so `max(u, 0)` is above it;
//! * `lower`: a pair whose grid lower bound `l` is positive is wholly on the free side, where
//!   its exact clearance is the distance to the triangles, at least `l`. A pair with `l ≤ 0`
//!   may touch or cross the wall, where the exact clearance is the depth to the wall's plane
//!   (`contact/solid.rs`), which the grid does not bound: `lower` is then `−∞`.
//!
//! So `lower ≥ margin` proves the shape keeps a margin `margin > 0`, and `upper < margin`
//! proves it does not: the decision the exact clearance makes, never another. Nothing here is
//! a number reported to a user: reported clearances are exact ([`super::clearance`]).

use super::clear::{features_of, pair_grown};
use crate::model::robot::Robot;
use crate::model::scene::Scene;
use crate::shape::Shape;

/// Certified bounds on a shape's clearance \[m\] (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceBounds {
    /// At most the clearance \[m\] (`−∞` when a feature may touch or cross a solid's wall).
    pub lower: f64,
    /// At least the clearance \[m\].
    pub upper: f64,
}

impl ClearanceBounds {
    /// Whether the clearance is at least `margin` \[m\]: `Some(true)` when `lower` proves it,
    /// `Some(false)` when `upper` disproves it, `None` when the bounds straddle it (the exact
    /// clearance decides).
    pub fn keeps(&self, margin: f64) -> Option<bool> {
        if self.lower >= margin {
            Some(true)
        } else if self.upper < margin {
            Some(false)
        } else {
            None
        }
    }
}

/// Certified bounds on the clearance of `shape` ([`super::clearance`]'s distance) from the
/// grids of the scene's solids (module docs); `None` for an empty scene or one with an
/// obstacle without a grid, where the exact clearance is the cheaper test.
pub fn clearance_bounds(robot: &Robot, shape: &Shape, scene: &Scene) -> Option<ClearanceBounds> {
    if scene.is_empty() || scene.obstacles.iter().any(|o| o.field().is_none()) {
        return None;
    }
    let feats = features_of(robot, shape);
    let (mut exact_lo, mut upper) = (f64::INFINITY, f64::INFINITY);
    // Grid pairs: feature, obstacle, lower, upper (coarse).
    let mut grid: Vec<(usize, usize, f64, f64)> = Vec::new();
    for (i, f) in feats.iter().enumerate() {
        for (k, o) in scene.obstacles.iter().enumerate() {
            let coarse = o
                .field()
                .and_then(|fd| fd.feature_bounds(&*f.shape, &f.pose, &o.parry_pose, false));
            match coarse {
                Some((lo, hi)) => {
                    upper = upper.min(hi.max(0.0));
                    grid.push((i, k, lo, hi));
                }
                // (A pair whose every query fails is left out of the exact clearance too;
                // it bounds nothing here but `lower`.)
                None => match pair_grown(f, scene, k, 2.0 * scene.clearance.max(5e-4)) {
                    Some(d) => {
                        exact_lo = exact_lo.min(d);
                        upper = upper.min(d);
                    }
                    None => exact_lo = f64::NEG_INFINITY,
                },
            }
        }
    }
    grid.sort_by(|a, b| a.2.total_cmp(&b.2));
    let mut grid_lo = f64::INFINITY;
    for (i, k, lo, hi) in grid {
        if lo > upper {
            // Neither this pair nor any after it holds the smallest lower bound.
            grid_lo = grid_lo.min(lo);
            break;
        }
        let (f, o) = (&feats[i], &scene.obstacles[k]);
        let fine = o
            .field()
            .and_then(|fd| fd.feature_interval(&*f.shape, &f.pose, &o.parry_pose));
        let (lo, hi) = fine.map_or((lo, hi), |(l, u)| (lo.max(l), hi.min(u)));
        upper = upper.min(hi.max(0.0));
        grid_lo = grid_lo.min(lo);
    }
    let grid_lo = if grid_lo > 0.0 {
        grid_lo
    } else {
        f64::NEG_INFINITY
    };
    Some(ClearanceBounds {
        lower: exact_lo.min(grid_lo),
        upper,
    })
}
