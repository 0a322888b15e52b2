//! Errors: every failure names what failed and where.
//!
//! [`ModelError`] is raised at the file boundary (parse + validation) and names the field;
//! [`SolveError`] is raised by methods and says which cable, section, iteration count and
//! residual were involved. Nothing in ccrkit panics on user input.

use thiserror::Error;

/// A robot, actuation or scene description that cannot be used.
#[derive(Debug, Clone, Error, PartialEq)]
#[non_exhaustive]
pub enum ModelError {
    /// The file could not be read.
    #[error("cannot read `{path}`: {reason}")]
    Io {
        /// Path of the file.
        path: String,
        /// What the operating system said.
        reason: String,
    },
    /// The TOML text does not parse or has unknown / missing / mistyped fields.
    #[error("cannot parse `{path}`: {reason}")]
    Parse {
        /// Path of the file (or `<string>`).
        path: String,
        /// The parser's message; it names the offending field.
        reason: String,
    },
    /// A field parses but its value is not acceptable.
    #[error("invalid field `{field}`: {reason}")]
    Invalid {
        /// Dotted path of the field, e.g. `cables[1].radius`.
        field: String,
        /// Why it is rejected.
        reason: String,
    },
}

impl ModelError {
    /// Shorthand for [`ModelError::Invalid`].
    pub fn invalid(field: impl Into<String>, reason: impl Into<String>) -> Self {
        ModelError::Invalid {
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// The field this error names (`None` for I/O errors).
    pub fn field(&self) -> Option<&str> {
        match self {
            ModelError::Invalid { field, .. } => Some(field),
            _ => None,
        }
    }
}

/// Why a method could not produce a shape.
#[derive(Debug, Clone, Error, PartialEq)]
#[non_exhaustive]
pub enum SolveError {
    /// The input is not valid for this method (field and reason).
    #[error("invalid input `{field}`: {reason}")]
    InvalidInput {
        /// The offending field or option.
        field: String,
        /// Why.
        reason: String,
    },
    /// The requested actuation cannot be reached by any shape of this robot.
    #[error("infeasible actuation: cable `{cable}` in section {section}: {reason}")]
    Infeasible {
        /// Cable name.
        cable: String,
        /// Section index (1-based: section i lies between disks i-1 and i).
        section: usize,
        /// What is out of reach.
        reason: String,
    },
    /// An iterative solver stopped without meeting its tolerance.
    #[error(
        "{method} did not converge{}: {iterations} iterations, residual {}{}",
        section.map(|s| format!(" in section {s}")).unwrap_or_default(),
        // A residual that overflowed is said in words, never printed as `NaN`/`inf`.
        if residual.is_finite() { format!("{residual:.3e}") } else { "not finite".into() },
        if detail.is_empty() { String::new() } else { format!(" ({detail})") }
    )]
    NotConverged {
        /// Method name.
        method: String,
        /// Section, where the method works section by section.
        section: Option<usize>,
        /// Iterations spent.
        iterations: usize,
        /// Final residual (method-specific norm, stated in the method docs).
        residual: f64,
        /// Extra context.
        detail: String,
    },
    /// An obstacle makes the requested shape impossible (the base inside it, or no pose of a
    /// section that meets the cable lengths without penetrating it).
    #[error("obstructed by `{obstacle}` in section {section}: {reason}")]
    Obstructed {
        /// Obstacle name.
        obstacle: String,
        /// Section (0: the base disk).
        section: usize,
        /// What cannot be done.
        reason: String,
    },
    /// No actuation within the limits puts the tip on the target (keeping clear of the
    /// obstacles, unless contact is allowed): the closest tip found and its distance.
    #[error(
        "unreachable target [{:.6}, {:.6}, {:.6}] m: closest tip [{:.6}, {:.6}, {:.6}] m at {distance:.3e} m ({reason})",
        target[0], target[1], target[2], closest[0], closest[1], closest[2]
    )]
    Unreachable {
        /// The target tip position \[m\].
        target: [f64; 3],
        /// The closest tip found \[m\].
        closest: [f64; 3],
        /// Its distance to the target \[m\].
        distance: f64,
        /// Why the search stopped (limits, obstacles, tension bound, tangent).
        reason: String,
    },
    /// No collision-free path of actuations was found (planner budget spent, or start and
    /// goal in different free regions).
    #[error("no path found after {samples} samples: {reason}")]
    NoPath {
        /// Samples drawn.
        samples: usize,
        /// What stopped the search.
        reason: String,
    },
    /// The scene asks for more contact work than one solve may spend: its distinct obstacles
    /// within reach of the robot times the robot's features (disks, backbone sections, cable
    /// chords) exceed the limit (user's guide, errors). Exact duplicates are merged
    /// before counting. Raised before any solving.
    #[error(
        "contact budget exceeded: {obstacles} distinct obstacles within reach of the robot × \
         {features} robot features (disks, backbone sections, cable chords) = {pairs} \
         feature–obstacle pairs, the limit is {limit}: merge obstacles into fewer (exact \
         duplicates already are), give them as one mesh, or crop the scene to the robot's \
         workspace"
    )]
    ContactBudget {
        /// Distinct obstacles within reach (exact duplicates merged).
        obstacles: usize,
        /// The robot's contact features.
        features: usize,
        /// Their product: feature–obstacle pairs.
        pairs: usize,
        /// The most pairs a solve may have.
        limit: usize,
    },
    /// The method cannot represent this robot or actuation.
    #[error("{method} cannot solve this: {reason}")]
    Unsupported {
        /// Method name.
        method: String,
        /// Why.
        reason: String,
    },
}

/// A robot, actuation or scene refused on the solve path (e.g. a robot built in code that
/// breaks a rule, [`crate::robot::Robot::check`]): an invalid input naming the same field.
impl From<ModelError> for SolveError {
    fn from(e: ModelError) -> Self {
        match e {
            ModelError::Invalid { field, reason } => SolveError::InvalidInput { field, reason },
            other => SolveError::InvalidInput {
                field: "model".into(),
                reason: other.to_string(),
            },
        }
    }
}

impl SolveError {
    /// The outcome this error is ([`Status`]).
    pub fn status(&self) -> Status {
        match self {
            SolveError::InvalidInput { .. } => Status::InvalidInput,
            SolveError::Infeasible { .. } => Status::Infeasible,
            SolveError::NotConverged { .. } => Status::NotConverged,
            SolveError::Obstructed { .. } => Status::Obstructed,
            SolveError::Unsupported { .. } => Status::Unsupported,
            SolveError::Unreachable { .. } => Status::Unreachable,
            SolveError::NoPath { .. } => Status::NoPath,
            SolveError::ContactBudget { .. } => Status::ContactBudget,
        }
    }

    /// A short machine-readable kind: the name of its [`Status`] (`not_converged`, ...), as
    /// written in CSV files.
    pub fn kind(&self) -> &'static str {
        self.status().name()
    }

    /// Iterations and final residual the error reports (a solver that stopped short says;
    /// otherwise 0 and NaN).
    pub fn iterations_residual(&self) -> (usize, f64) {
        match self {
            SolveError::NotConverged {
                iterations,
                residual,
                ..
            } => (*iterations, *residual),
            _ => (0, f64::NAN),
        }
    }
}

/// How one solve ended: the one outcome vocabulary of ccrkit. Batch rows, study points and
/// samples, hardware predictions, CSV files and Python's `STATUSES` all use these names.
///
/// ```
/// use ccrkit::error::{SolveError, Status};
///
/// let e = SolveError::Infeasible {
///     cable: "c1".into(),
///     section: 2,
///     reason: "longer than the cable".into(),
/// };
/// assert_eq!(e.status(), Status::Infeasible);
/// assert_eq!(Status::of(&Err::<(), _>(e)).name(), "infeasible");
/// assert_eq!(Status::from_name("ok"), Some(Status::Ok));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Status {
    /// Solved: a shape that passed the output check.
    Ok,
    /// [`SolveError::InvalidInput`].
    InvalidInput,
    /// [`SolveError::Infeasible`].
    Infeasible,
    /// [`SolveError::NotConverged`] (also a shape with a non-finite number, refused at the
    /// output check).
    NotConverged,
    /// [`SolveError::Obstructed`] (also a shape through itself, refused at the output check).
    Obstructed,
    /// [`SolveError::Unsupported`].
    Unsupported,
    /// [`SolveError::ContactBudget`].
    ContactBudget,
    /// [`SolveError::Unreachable`].
    Unreachable,
    /// [`SolveError::NoPath`].
    NoPath,
    /// The method panicked: a bug in ccrkit, caught by a batch so that the other rows go on.
    Panicked,
}

impl Status {
    /// Every status, in a fixed order (Python's `STATUSES`).
    pub const ALL: [Status; 10] = [
        Status::Ok,
        Status::InvalidInput,
        Status::Infeasible,
        Status::NotConverged,
        Status::Obstructed,
        Status::Unsupported,
        Status::ContactBudget,
        Status::Unreachable,
        Status::NoPath,
        Status::Panicked,
    ];

    /// The status of a result: [`Status::Ok`] or its error's.
    pub fn of<T>(result: &Result<T, SolveError>) -> Status {
        match result {
            Ok(_) => Status::Ok,
            Err(e) => e.status(),
        }
    }

    /// Its name, as written in CSV files and shown in Python (`ok`, `not_converged`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::InvalidInput => "invalid_input",
            Status::Infeasible => "infeasible",
            Status::NotConverged => "not_converged",
            Status::Obstructed => "obstructed",
            Status::Unsupported => "unsupported",
            Status::ContactBudget => "contact_budget",
            Status::Unreachable => "unreachable",
            Status::NoPath => "no_path",
            Status::Panicked => "panicked",
        }
    }

    /// The status of a name ([`Status::name`]'s inverse).
    pub fn from_name(name: &str) -> Option<Status> {
        Status::ALL.into_iter().find(|s| s.name() == name)
    }

    /// True for [`Status::Ok`].
    pub fn is_ok(self) -> bool {
        self == Status::Ok
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl PartialEq<&str> for Status {
    fn eq(&self, other: &&str) -> bool {
        self.name() == *other
    }
}

#[cfg(test)]
mod tests {
    use super::SolveError;

    /// A residual that overflowed reads `not finite` (it printed `residual NaN`, a non-finite
    /// token in the output of a run that exits 0, e.g. a `compare` row).
    #[test]
    fn a_non_finite_residual_is_said_in_words() {
        let e = |residual| SolveError::NotConverged {
            method: "cosserat".into(),
            section: None,
            iterations: 3,
            residual,
            detail: String::new(),
        };
        assert_eq!(
            e(f64::NAN).to_string(),
            "cosserat did not converge: 3 iterations, residual not finite"
        );
        assert!(e(f64::INFINITY)
            .to_string()
            .ends_with("residual not finite"));
        assert!(e(1.5e-3).to_string().ends_with("residual 1.500e-3"));
    }
}
