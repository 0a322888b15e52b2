//! # ccrkit
//!
//! Shapes of cable-driven continuum robots (CCR) with many, generally routed cables.
//!
//! The flow: a model file ([`model::Model`]) gives a [`robot::Robot`] and an
//! [`actuation::Actuation`]; a [`method::Method`] turns them into a [`shape::Shape`], which is
//! written as JSON or drawn (`plot`, with the `plot` feature). The user's guide (`docs/guide/`)
//! describes the methods and their accuracy.
//!
//! ## Cargo features
//!
//! All on by default. `cli`: the `ccrkit` binary (clap, anyhow, indicatif; implies the other
//! two). `plot`: SVG/PNG figures (`plot`, `study::figures`; plotters and an embedded font).
//! `view`: the 3-D HTML view (`export::view`; an embedded viewer bundle). With
//! `default-features = false` the library builds none of them: models, every method, batches,
//! studies' numbers, reach, plan, calibration, URDF/SRDF and JSON stay.

#![warn(missing_docs)]

pub mod anatomy;
pub mod batch;
pub mod calibrate;
pub mod check;
pub(crate) mod contact;
pub mod counts;
pub mod error;
pub mod export;
pub mod fingerprint;
pub mod method;
pub mod model;
pub mod output;
pub use model::{actuation, mesh, robot, routing, scene};
pub(crate) mod numeric;
pub mod plan;
#[cfg(feature = "plot")]
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

/// What most programs need, in one import: a model, the one way to solve it
/// ([`SolveRequest`](crate::method::run::SolveRequest) → [`Solver`](crate::method::Solver)),
/// the method registry and settings, and the errors.
///
/// ```
/// use ccrkit::prelude::*;
///
/// let model = Model::from_file("models/paper/case1.toml")?;
/// // The default method (energy), the model's own actuation and obstacles; the shape checked.
/// let solved = SolveRequest::new(MethodKind::DEFAULT).run(&model)?;
/// let tip = solved.shape.tip();
/// assert!(tip.z > 0.0 && solved.shape.report.converged);
///
/// // The paper's literal section solver, by name, with a setting.
/// let literal = SolveRequest::new("geometric".parse()?)
///     .with_settings(Settings::new().with("zero-angle", "1e-9"))
///     .run(&model)?;
/// assert!((literal.shape.tip() - tip).norm() < 0.01);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub mod prelude {
    pub use crate::error::{ModelError, SolveError};
    pub use crate::method::run::{SolveRequest, Solved};
    pub use crate::method::{MethodKind, PreparedSolver, Settings, Solver};
    pub use crate::model::actuation::{Actuation, CableDrive, Shortening};
    pub use crate::model::robot::Robot;
    pub use crate::model::scene::Scene;
    pub use crate::model::Model;
    pub use crate::progress::{Event, ProgressHandle};
    pub use crate::shape::Shape;
}
