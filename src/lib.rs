//! # ccrkit
//!
//! Shapes of cable-driven continuum robots (CCR) with many, generally routed cables.
//!
//! The flow: a model file ([`model::Model`]) gives a [`robot::Robot`] and an
//! [`actuation::Actuation`]; a [`method::Method`] turns them into a [`shape::Shape`], which is
//! written as JSON or drawn ([`plot`]). The user's guide (`docs/guide/`) describes the methods and
//! their accuracy.

#![warn(missing_docs)]

pub mod batch;
pub mod calibrate;
pub mod check;
pub(crate) mod contact;
pub mod error;
pub mod export;
pub mod method;
pub mod model;
pub use model::{actuation, mesh, robot, routing, scene};
pub mod numeric;
pub mod plan;
pub mod plot;
pub mod progress;
pub mod reach;
pub mod shape;
pub mod study;

pub use actuation::{Actuation, CableDrive, Shortening};
pub use error::{ModelError, SolveError};
pub use method::{method_by_name, Method};
pub use model::Model;
pub use robot::{Backbone, Cable, Robot};
pub use scene::Scene;
pub use shape::Shape;
