//! Method settings by name: what the command line (`--set NAME=VALUE`, and the named flags
//! `--control`, `--routing`, `--length`, `--rk4-steps`, `--adaptive`) and Python
//! (`model.solve(method, **settings)`) hand to a method. Each method lists the settings it
//! takes ([`SettingInfo`], in the registry) and applies them ([`Configure::set`]); a setting
//! a method does not take is refused, naming the methods that do take it — never ignored.
//! Every value is parsed and bounded here, so no setting can make a solve run unbounded.

use crate::error::SolveError;
use crate::model::actuation::{Input, LengthMeasure};
use crate::model::routing::RoutingFit;

/// Settings as `name = value` pairs, applied in order (a later value of the same name wins).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Settings {
    items: Vec<(String, String)>,
}

impl Settings {
    /// No settings: every method's defaults.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builder: add `name = value`.
    pub fn with(mut self, name: impl Into<String>, value: impl ToString) -> Self {
        self.push(name, value);
        self
    }

    /// Add `name = value`.
    pub fn push(&mut self, name: impl Into<String>, value: impl ToString) {
        self.items.push((name.into(), value.to_string()));
    }

    /// Parse `NAME=VALUE`.
    pub fn parse_pair(text: &str) -> Result<(String, String), SolveError> {
        match text.split_once('=') {
            Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().into(), v.trim().into())),
            _ => Err(SolveError::InvalidInput {
                field: "set".into(),
                reason: format!("`{text}` is not NAME=VALUE"),
            }),
        }
    }

    /// The pairs, in order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &str)> {
        self.items.iter().map(|(k, v)| (k.as_str(), v.as_str()))
    }

    /// True when no setting is given.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The last value given for `name` (after alias resolution by the caller).
    pub fn get(&self, name: &str) -> Option<&str> {
        self.items
            .iter()
            .rev()
            .find(|(k, _)| canonical(k) == name)
            .map(|(_, v)| v.as_str())
    }

    /// Human form, `a=1, b=2` (empty: `defaults`).
    pub fn describe(&self) -> String {
        if self.items.is_empty() {
            return "defaults".into();
        }
        let v: Vec<String> = self.items.iter().map(|(k, v)| format!("{k}={v}")).collect();
        v.join(", ")
    }
}

/// One setting a method takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SettingInfo {
    /// Name (kebab-case, as on the command line).
    pub name: &'static str,
    /// Accepted values (a list or a range).
    pub values: &'static str,
    /// Default value.
    pub default: &'static str,
    /// What it does.
    pub help: &'static str,
}

/// Method settings that can be set by name.
pub trait Configure {
    /// Apply one setting (its canonical name); errors name the setting and the reason.
    fn set(&mut self, name: &str, value: &str) -> Result<(), SolveError>;
}

/// The canonical name of a setting (`cable-length` and `rk4_steps` style aliases folded).
pub fn canonical(name: &str) -> String {
    let n = name.trim().replace('_', "-").to_ascii_lowercase();
    match n.as_str() {
        "cable-length" => "length".into(),
        "steps-per-section" => "rk4-steps".into(),
        _ => n,
    }
}

fn invalid(name: &str, reason: String) -> SolveError {
    SolveError::InvalidInput {
        field: name.into(),
        reason,
    }
}

/// An integer in `[min, max]`.
pub fn parse_count(name: &str, value: &str, min: usize, max: usize) -> Result<usize, SolveError> {
    match value.parse::<u64>() {
        Ok(v) if (min as u64..=max as u64).contains(&v) => Ok(v as usize),
        _ => Err(invalid(
            name,
            format!("must be a whole number from {min} to {max}, got `{value}`"),
        )),
    }
}

/// A finite number in `(lo, hi]` (`lo` excluded, `hi` included).
pub fn parse_in(name: &str, value: &str, lo: f64, hi: f64) -> Result<f64, SolveError> {
    match value.parse::<f64>() {
        Ok(v) if v.is_finite() && v > lo && v <= hi => Ok(v),
        _ => Err(invalid(
            name,
            format!("must be a number in ({lo:e}, {hi:e}], got `{value}`"),
        )),
    }
}

/// One of a list of names.
pub fn parse_choice<T: Copy>(
    name: &str,
    value: &str,
    choices: &[(&str, T)],
) -> Result<T, SolveError> {
    let v = value.trim().to_ascii_lowercase();
    choices
        .iter()
        .find(|(k, _)| *k == v)
        .map(|(_, t)| *t)
        .ok_or_else(|| {
            let names: Vec<&str> = choices.iter().map(|(k, _)| *k).collect();
            invalid(
                name,
                format!("unknown value `{value}` (one of: {})", names.join(", ")),
            )
        })
}

/// `control`: which input drives a cable that gives both (`force`/`tension` or
/// `displacement`/`shortening`).
pub fn parse_control(value: &str) -> Result<Input, SolveError> {
    parse_choice(
        "control",
        value,
        &[
            ("force", Input::Tension),
            ("tension", Input::Tension),
            ("displacement", Input::Shortening),
            ("shortening", Input::Shortening),
        ],
    )
}

/// `length`: how a cable's length is measured (`path` or `chord`).
pub fn parse_length(value: &str) -> Result<LengthMeasure, SolveError> {
    parse_choice(
        "length",
        value,
        &[
            ("path", LengthMeasure::Path),
            ("chord", LengthMeasure::Chord),
        ],
    )
}

/// `routing`: the cable routing fit (`spline` or `fourier8`).
pub fn parse_routing(value: &str) -> Result<RoutingFit, SolveError> {
    parse_choice(
        "routing",
        value,
        &[
            ("spline", RoutingFit::Spline),
            ("fourier8", RoutingFit::Fourier8),
        ],
    )
}

/// The `control` value of an input (`displacement` or `force`), as the command line spells it.
pub fn control_name(i: Input) -> &'static str {
    match i {
        Input::Shortening => "displacement",
        Input::Tension => "force",
    }
}

/// Shared settings descriptions.
pub mod common {
    use super::SettingInfo;

    /// `control` with the given default.
    pub const fn control(default: &'static str) -> SettingInfo {
        SettingInfo {
            name: "control",
            values: "force | displacement",
            default,
            help: "input used for a cable that gives both a tension and a shortening",
        }
    }
    /// `routing`.
    pub const ROUTING: SettingInfo = SettingInfo {
        name: "routing",
        values: "spline | fourier8",
        default: "spline",
        help: "cable routing fit through the holes",
    };
    /// `length`.
    pub const LENGTH: SettingInfo = SettingInfo {
        name: "length",
        values: "path | chord",
        default: "path",
        help: "cable length measure under displacement control (alias cable-length)",
    };
    /// `max-iterations`.
    pub const fn max_iterations(default: &'static str) -> SettingInfo {
        SettingInfo {
            name: "max-iterations",
            values: "1..=100000",
            default,
            help: "Newton iterations (per candidate / load step) before NotConverged",
        }
    }
    /// `tolerance`.
    pub const fn tolerance(default: &'static str, help: &'static str) -> SettingInfo {
        SettingInfo {
            name: "tolerance",
            values: "(0, 1]",
            default,
            help,
        }
    }
}

/// Most iterations any setting may ask for (every run stays bounded).
pub const MAX_ITERATIONS: usize = 100_000;
