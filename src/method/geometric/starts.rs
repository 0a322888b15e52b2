//! Starting poses of a section's Newton runs: the smooth squared-angle solution, the previous
//! section's pose and the straight pose, the last two nudged off the kinks.

use super::problem::{Pose, SectionData};
use super::{Geometric, Objective};
use crate::numeric::so3::{exp_so3, orthonormalize};
use nalgebra::Vector3;

impl Geometric {
    /// Starting poses: the smooth squared-angle solution (angles off their kinks), the previous
    /// section's relative pose, and the straight pose, both nudged off the kinks.
    pub(super) fn starts(
        &self,
        data: &SectionData,
        prev: Option<&Pose>,
        it: &mut usize,
    ) -> Vec<Pose> {
        let straight = Pose::straight(data.l0);
        let mut starts = vec![];
        if self.objective == Objective::Squared {
            starts.push(straight);
            if let Some(p) = prev {
                starts.push(*p);
            }
            return starts;
        }
        let all: Vec<usize> = (0..data.cons.len())
            .filter(|&j| data.chord(&straight, j) > data.cons[j].length)
            .take(5 - usize::from(data.gauge.is_some()))
            .collect();
        if let Some(c) = self.smooth_start(data, &all, it) {
            starts.push(c);
        }
        if let Some(p) = prev {
            starts.push(nudge(p, data));
        }
        starts.push(nudge(&straight, data));
        starts
    }

    /// Solve the smooth squared-angle problem from the straight pose, as a start for the
    /// literal faces (its angles are generically non-zero).
    pub(super) fn smooth_start(
        &self,
        data: &SectionData,
        active: &[usize],
        it: &mut usize,
    ) -> Option<Pose> {
        let r = self.newton(data, &Pose::straight(data.l0), 0, active, true);
        match r {
            Ok((c, k)) => {
                *it += k;
                Some(c.pose)
            }
            Err(e) => {
                *it += e.iterations;
                None
            }
        }
    }
}

/// A start moved slightly off every kink (deterministic): ~1.5e-4 of the section length and
/// ~1.6e-4 rad. The size is measured (Newton iterations, same certified answers on
/// `tests/methods/geometric_tips.rs`): the former 10× larger nudge (~1.5e-3) cost case I / II / III
/// 515 / 1542 / 1703 iterations and case I cut into 72 sections 2559; this one 475 / 1497 /
/// 1628 and 1059 (a nudge large against a short section's bend starts far from its
/// minimum); 3× larger lost a random robot (certified before, not converged after). The
/// former search ([`SectionData::former_search`]) keeps the former size.
pub(super) fn nudge(p: &Pose, data: &SectionData) -> Pose {
    let (dp, dw) = if data.former_search.get() {
        FORMER_NUDGE
    } else {
        NUDGE
    };
    Pose {
        p: p.p + data.l0 * Vector3::from(dp),
        q: orthonormalize(&(p.q * exp_so3(&Vector3::from(dw)))),
    }
}

/// The nudge: position (× section length) and rotation vector \[rad\].
const NUDGE: ([f64; 3], [f64; 3]) = ([1.3e-4, -0.7e-4, 0.0], [0.9e-4, 1.1e-4, -0.8e-4]);

/// The nudge of the former search (10× the current size, see [`nudge`]).
const FORMER_NUDGE: ([f64; 3], [f64; 3]) = ([1.3e-3, -0.7e-3, 0.0], [0.9e-3, 1.1e-3, -0.8e-3]);
