//! Contact between the robot and obstacles, written once for every method that handles
//! obstacles (the geometric section solver and the whole-robot energy model; reach and plan
//! draw the same features).
//!
//! * [`features`]: the robot features as parry shapes — backbone pieces are capsules of the
//!   backbone radius, disks thin cylinders (parry's cylinder axis is its local y, the disk
//!   normal local z, hence [`y_to_z`]), cable chords segments — the witness of one
//!   feature–obstacle pair, the exact support point on a disk rim, the fraction along a
//!   segment, and the reported [`crate::shape::Contact`] record;
//! * [`parry`]: the parry3d bridge (GJK query that stays on GJK near touching, EPA recovery,
//!   witness polish);
//! * [`curvature`]: the Hessian of an obstacle's distance function (its surface curvature),
//!   for the second derivative of a feature–obstacle distance;
//! * [`primitives`]: closed-form distances of the features to a box where one of its faces
//!   decides them, and to a ball whose centre lies off the feature's core (parry otherwise);
//! * [`sat`]: the exact distance, normal and witnesses of a feature and a box or cylinder where
//!   an edge, corner, rim or side decides them — the separating-axis maximum over their support
//!   functions, started from parry's answer (the geometric method's contact normals);
//! * [`solid`]: signed distances to a closed mesh with a declared free side (a lumen, an
//!   organ), so a feature beyond a thin wall is seen;
//! * [`broad`]: the broad phase (obstacles within reach of the robot, exact duplicates
//!   merged, bounds against a box), the contact budget ([`broad::MAX_PAIRS`]) and the
//!   base-disk check.
//!
//! What stays in a method is how its variables move a feature (the gradient of a distance):
//! `method/geometric/obstacles.rs` in one section's pose, `method/energy/contacts.rs` in the
//! strains of every sub-arc.

pub(crate) mod broad;
pub(crate) mod curvature;
pub(crate) mod features;
pub mod field;
pub(crate) mod field_build;
pub mod field_cache;
mod field_interval;
pub(crate) mod parry;
pub(crate) mod primitives;
pub(crate) mod sat;
pub(crate) mod solid;

pub(crate) use parry::{
    nvec, polish, ppose, pvec, query, query_near, y_to_z, Witness, CONTACT_TOL,
};
