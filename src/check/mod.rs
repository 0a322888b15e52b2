//! Checks on a solved shape at the output boundary, independent of the method that made it:
//! every number finite, and the robot not passing through itself.
//!
//! The one solve path ([`crate::method::Solver`], behind [`crate::method::run::SolveRequest`])
//! applies [`output`] to every shape it hands out — single solves, batch rows, study points,
//! reach and plan, hardware predictions, calibration passes — so no caller gets a non-finite
//! number or a backbone or disks that interpenetrate (99.99 % shortening under `energy` once
//! curled the robot through itself with no word).
//!
//! **Self-contact** is tested with parry3d on the shape's own geometry, not on any method's
//! internal state:
//! - every pair of disks (cylinders of the robot's radius and thickness at the solved frames),
//!   adjacent ones included: rigid disks may touch, not overlap;
//! - backbone against backbone: the polyline of `Shape::backbone` as capsules of the backbone
//!   radius ρ = d/2, for pairs of segments more than π d apart along the arc. On a circle of
//!   radius r ≥ ρ (the tightest bend a tube of radius ρ can take without overlapping itself)
//!   two points s apart lie 2r sin(s/2r) apart, which is ≥ d once s ≥ π d/2 (sin(πx/2) ≥ x on
//!   [0, 1]); so two segments that far apart and closer than d overlap — the backbone crosses
//!   itself. The π d gap (twice the bound) keeps discretization of the polyline from counting;
//! - each disk against backbone segments more than π R along the arc from it (a curve leaving
//!   a disk along its normal returns to the disk's plane only after half a turn).
//!
//! An overlap deeper than tol = [`SELF_CONTACT_TOL`] × min(disk thickness, backbone diameter) is
//! reported: the parts shrunk by tol intersect (GJK's boolean test, robust also where EPA's
//! penetration depth fails, e.g. for coaxial disks); the depth given is EPA's where it has one,
//! else tol (a lower bound). The parts are taken in order along the arc and the first one that
//! overlaps a later part is reported, with its deepest such partner. A broad phase (parry's
//! bounding-volume hierarchy over the parts' axis-aligned bounds, `self_contact.rs`) and that
//! early stop keep the cost at n log n in the number of parts also for a shape coiled through
//! itself many times (every turn overlapping every other: the deepest pair of all took 41 s at
//! 1000 sections); a backbone sampled more finely than d/8 is thinned to about that spacing.
//! [`self_contact_exhaustive`] tests every pair and is the oracle the broad phase is held to.

use crate::error::SolveError;
use crate::robot::Robot;
use crate::shape::Shape;

mod self_contact;
pub use self_contact::{
    self_contact, self_contact_exhaustive, SelfContact, MAX_BACKBONE_SEGMENTS, SELF_CONTACT_TOL,
};

/// Both checks; the first failure as a [`SolveError`] (`NotConverged` for a non-finite number,
/// `Obstructed` by `self` for a self-contact).
pub fn output(robot: &Robot, shape: &Shape) -> Result<(), SolveError> {
    finite(shape)?;
    if let Some(c) = self_contact(robot, shape) {
        return Err(SolveError::Obstructed {
            obstacle: "self".into(),
            section: c.section,
            reason: format!(
                "{} overlap by {:.3e} m: the shape passes through itself (ccrkit does not model self-contact; reduce the actuation)",
                c.what, c.depth
            ),
        });
    }
    Ok(())
}

/// The first half of [`output`], which needs no robot: every number of `shape` finite, else
/// `NotConverged` naming the first field that is not.
pub fn finite(shape: &Shape) -> Result<(), SolveError> {
    match first_non_finite(shape) {
        None => Ok(()),
        Some(field) => Err(SolveError::NotConverged {
            method: shape.method.clone(),
            section: None,
            iterations: shape.report.iterations,
            residual: shape.report.residual,
            detail: format!("the result holds a non-finite number at `{field}`"),
        }),
    }
}

/// A method's result passed through [`output`], so a shape through itself or a non-finite
/// one counts as the failure it is.
pub fn checked(robot: &Robot, result: Result<Shape, SolveError>) -> Result<Shape, SolveError> {
    let shape = result?;
    output(robot, &shape)?;
    Ok(shape)
}

/// The first field of `shape` holding a NaN or an infinity (a dotted path such as
/// `disks[3].position`), if any.
pub fn first_non_finite(shape: &Shape) -> Option<String> {
    let bad = |xs: &[f64]| xs.iter().any(|x| !x.is_finite());
    for (k, d) in shape.disks.iter().enumerate() {
        if bad(&[d.s]) || bad(d.position.as_slice()) || bad(d.rotation.as_slice()) {
            return Some(format!("disks[{k}]"));
        }
    }
    if let Some(k) = shape.backbone.iter().position(|p| bad(p.as_slice())) {
        return Some(format!("backbone[{k}]"));
    }
    for c in &shape.cables {
        if c.points.iter().any(|p| bad(p.as_slice())) || c.tension.is_some_and(|t| !t.is_finite()) {
            return Some(format!("cables[{}]", c.name));
        }
    }
    for (k, c) in shape.contacts.iter().enumerate() {
        let nums = [c.distance, c.multiplier];
        if bad(&nums) || bad(&c.point_robot) || bad(&c.point_obstacle) || bad(&c.normal) {
            return Some(format!("contacts[{k}]"));
        }
    }
    let r = &shape.report;
    if bad(&[r.residual, r.solve_time_s]) {
        return Some("report.residual".into());
    }
    for s in &r.sections {
        if bad(&[s.residual, s.objective]) {
            return Some(format!("report.sections[{}]", s.section));
        }
    }
    if r.base_wrench.is_some_and(|w| bad(&w)) {
        return Some("report.base_wrench".into());
    }
    if let Some(j) = &r.jacobian {
        if j.position.iter().chain(&j.tangent).any(|v| bad(v)) {
            return Some("report.jacobian".into());
        }
    }
    None
}
