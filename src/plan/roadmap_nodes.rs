//! A roadmap file's nodes checked against the space it is used in, before any is believed:
//! each node's actuation has one value per unknown of the space and lies within its limits,
//! its tip and clearance are finite (hand-edited nodes of 3, 0 or 7 values for 6 cables, or
//! outside the limits, were accepted).

use super::roadmap::Roadmap;
use crate::error::SolveError;
use crate::reach::Space;

/// Every node of `rm` fits `space` (named by its index in the error).
pub(super) fn check(rm: &Roadmap, space: &Space) -> Result<(), SolveError> {
    let bad = |k: usize, reason: String| {
        Err(SolveError::InvalidInput {
            field: format!("roadmap.nodes[{k}]"),
            reason,
        })
    };
    for (k, node) in rm.nodes.iter().enumerate() {
        if node.u.len() != space.dim() {
            return bad(
                k,
                format!(
                    "has {} actuation values; this space has {} unknowns",
                    node.u.len(),
                    space.dim()
                ),
            );
        }
        if !space.contains(&node.u) {
            return bad(
                k,
                format!(
                    "actuation {:?} lies outside the limits {:?} … {:?}",
                    node.u, space.lo, space.hi
                ),
            );
        }
        let tip_finite = node.tip.iter().all(|x| x.is_finite());
        if !tip_finite || node.clearance.is_some_and(|c| !(c.is_finite() && c >= 0.0)) {
            return bad(k, "has a non-finite tip or clearance".into());
        }
    }
    Ok(())
}
