//! Errors: every failure names what failed and where.
//!
//! [`ModelError`] is raised at the file boundary (parse + validation) and names the field;
//! [`SolveError`] is raised by methods and says which cable, section, iteration count and
//! residual were involved. Nothing in ccrkit panics on user input.

use thiserror::Error;

/// A robot, actuation or scene description that cannot be used.
#[derive(Debug, Clone, Error, PartialEq)]
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
        "{method} did not converge{}: {iterations} iterations, residual {residual:.3e}{}",
        section.map(|s| format!(" in section {s}")).unwrap_or_default(),
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

impl SolveError {
    /// A short machine-readable kind, used in study CSVs.
    pub fn kind(&self) -> &'static str {
        match self {
            SolveError::InvalidInput { .. } => "invalid_input",
            SolveError::Infeasible { .. } => "infeasible",
            SolveError::NotConverged { .. } => "not_converged",
            SolveError::Obstructed { .. } => "obstructed",
            SolveError::Unsupported { .. } => "unsupported",
            SolveError::Unreachable { .. } => "unreachable",
            SolveError::NoPath { .. } => "no_path",
            SolveError::ContactBudget { .. } => "contact_budget",
        }
    }
}
