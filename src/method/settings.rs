//! Method settings by name: what the command line (`--set NAME=VALUE`, and the named flags
//! `--control`, `--routing`, `--length`, `--rk4-steps`, `--adaptive`) and Python
//! (`model.solve(method, **settings)`) hand to a method. Each method lists the settings it
//! takes ([`SettingInfo`], in the registry) and applies them ([`Configure::set`]); a setting
//! a method does not take is refused, naming the methods that do take it — never ignored.
//! Every value is parsed and bounded here, so no setting can make a solve run unbounded.

use crate::error::SolveError;
use crate::model::actuation::Input;
use std::fmt;

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
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettingInfo {
    /// Name (kebab-case, as on the command line).
    pub name: &'static str,
    /// Accepted values: the one place they are written; printed by `ccrkit methods` and
    /// checked by the method's [`Configure::set`] (which reads it from the registry).
    pub values: Range,
    /// Default value.
    pub default: &'static str,
    /// What it does.
    pub help: &'static str,
}

/// The values a setting takes, typed: it prints (its `Display`, what `ccrkit methods` and
/// Python's `methods()` show) and it parses ([`Range::count`], [`Range::number`],
/// [`Range::pick`]), so the printed range and the enforced one cannot disagree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// A whole number from `min` to `max`, printed `min..=max`, then `(note)` if `note` is not
    /// empty (a further limit the method checks against the rest of its settings).
    Count {
        /// Smallest accepted.
        min: usize,
        /// Largest accepted.
        max: usize,
        /// A further limit, printed after the range.
        note: &'static str,
    },
    /// A finite number in `(lo, hi]` (`lo` excluded), printed `(lo, hi]`, then ` | word` for
    /// each word of `off` (a word that turns the feature off).
    Number {
        /// Excluded lower bound.
        lo: f64,
        /// Included upper bound.
        hi: f64,
        /// Words that mean "off" instead of a number (matched after trimming).
        off: &'static [&'static str],
    },
    /// One of a list of words, each with the index of the value it picks (several words may
    /// pick the same value: aliases). Printed `a | b`: the first word of each value.
    Choice(&'static [(&'static str, usize)]),
}

impl Range {
    /// A whole number from `min` to `max`, no note.
    pub const fn whole(min: usize, max: usize) -> Range {
        Range::Count { min, max, note: "" }
    }

    /// A finite number in `(lo, hi]`, no word for off.
    pub const fn interval(lo: f64, hi: f64) -> Range {
        Range::Number { lo, hi, off: &[] }
    }

    /// A whole-number setting.
    pub fn count(&self, name: &str, value: &str) -> Result<usize, SolveError> {
        match *self {
            Range::Count { min, max, .. } => parse_count(name, value.trim(), min, max),
            _ => Err(self.misread(name, "a whole number")),
        }
    }

    /// A number setting; `None` for one of its `off` words.
    pub fn number(&self, name: &str, value: &str) -> Result<Option<f64>, SolveError> {
        match *self {
            Range::Number { lo, hi, off } => {
                let value = value.trim();
                if off.contains(&value) {
                    return Ok(None);
                }
                parse_in(name, value, lo, hi).map(Some)
            }
            _ => Err(self.misread(name, "a number")),
        }
    }

    /// A number setting without `off` words.
    pub fn real(&self, name: &str, value: &str) -> Result<f64, SolveError> {
        self.number(name, value)?
            .ok_or_else(|| self.misread(name, "a number without an off word"))
    }

    /// A choice: the value of `values` (in the order of the choice's value indices) that the
    /// word `value` picks (case and surrounding space ignored).
    pub fn pick<T: Copy, const N: usize>(
        &self,
        name: &str,
        value: &str,
        values: [T; N],
    ) -> Result<T, SolveError> {
        match *self {
            Range::Choice(words) if words.iter().all(|&(_, i)| i < N) => {
                let typed: Vec<(&str, T)> = words.iter().map(|&(w, i)| (w, values[i])).collect();
                parse_choice(name, value, &typed)
            }
            _ => Err(self.misread(name, &format!("a choice among {N} values"))),
        }
    }

    /// A whole-number setting given as a value (typed settings, [`Configure::check`]): `v`
    /// when the range admits it, else the error `--set` would give.
    pub fn check_count(&self, name: &str, v: usize) -> Result<usize, SolveError> {
        match *self {
            Range::Count { min, max, .. } if (min..=max).contains(&v) => Ok(v),
            Range::Count { min, max, .. } => Err(invalid(
                name,
                format!("must be a whole number from {min} to {max}, got {v}"),
            )),
            _ => Err(self.misread(name, "a whole number")),
        }
    }

    /// A number setting given as a value (`None`: off, where the range has an off word): `v`
    /// when the range admits it, else the error `--set` would give.
    pub fn check_number(&self, name: &str, v: Option<f64>) -> Result<Option<f64>, SolveError> {
        match (*self, v) {
            (Range::Number { off, .. }, None) if !off.is_empty() => Ok(None),
            (Range::Number { lo, hi, .. }, Some(x)) if in_interval(x, lo, hi) => Ok(v),
            (Range::Number { lo, hi, off }, _) => {
                let got = v.map_or_else(|| "off".to_string(), |x| x.to_string());
                let or_off = off
                    .first()
                    .map(|w| format!(" or `{w}`"))
                    .unwrap_or_default();
                Err(invalid(
                    name,
                    format!("must be a number in ({lo:e}, {hi:e}]{or_off}, got {got}"),
                ))
            }
            _ => Err(self.misread(name, "a number")),
        }
    }

    /// [`Range::check_number`] of a value that is never off.
    pub fn check_real(&self, name: &str, v: f64) -> Result<f64, SolveError> {
        self.check_number(name, Some(v)).map(|_| v)
    }

    /// A setting read as another kind than the registry lists: a bug in ccrkit, reported
    /// as an error naming the setting rather than a panic.
    fn misread(&self, name: &str, kind: &str) -> SolveError {
        invalid(
            name,
            format!("the registry lists `{self}` but the method reads {kind} (a bug in ccrkit)"),
        )
    }
}

/// A bound as the range prints it: the shorter of the plain and the exponent form
/// (`0`, `1`, `1e-3`, `1e-14`, `1e6`).
fn short(x: f64) -> String {
    let (plain, exp) = (format!("{x}"), format!("{x:e}"));
    if exp.len() < plain.len() {
        exp
    } else {
        plain
    }
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Range::Count { min, max, note } => {
                write!(f, "{min}..={max}")?;
                if !note.is_empty() {
                    write!(f, " ({note})")?;
                }
                Ok(())
            }
            Range::Number { lo, hi, off } => {
                write!(f, "({}, {}]", short(lo), short(hi))?;
                off.iter().try_for_each(|w| write!(f, " | {w}"))
            }
            Range::Choice(words) => {
                let shown: Vec<&str> = words
                    .iter()
                    .enumerate()
                    .filter(|&(k, &(_, i))| !words[..k].iter().any(|&(_, j)| j == i))
                    .map(|(_, &(w, _))| w)
                    .collect();
                f.write_str(&shown.join(" | "))
            }
        }
    }
}

/// Method settings that can be set by name, and checked whatever way they were set.
pub trait Configure {
    /// Apply one setting (its canonical name); errors name the setting and the reason.
    fn set(&mut self, name: &str, value: &str) -> Result<(), SolveError>;

    /// Every setting in the range the registry gives it (the range [`Configure::set`] parses
    /// with: [`Range::check_count`], [`Range::check_number`]) and consistent with the others
    /// (e.g. the energy model's sub-arcs ≤ 4 with the chord length). The one check of a
    /// method's settings: [`MethodKind::build`](super::MethodKind::build) runs it after the
    /// named settings, and every solve runs it ([`Method::solve`](super::Method::solve),
    /// [`Method::prepare`](super::Method::prepare)), so typed settings written in code (a
    /// struct literal, a builder) are held to the same ranges as `--set`.
    fn check(&self) -> Result<(), SolveError>;
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
fn parse_count(name: &str, value: &str, min: usize, max: usize) -> Result<usize, SolveError> {
    match value.parse::<u64>() {
        Ok(v) if (min as u64..=max as u64).contains(&v) => Ok(v as usize),
        _ => Err(invalid(
            name,
            format!("must be a whole number from {min} to {max}, got `{value}`"),
        )),
    }
}

/// `v` finite and in `(lo, hi]` (`lo` excluded, `hi` included): a number setting's range.
fn in_interval(v: f64, lo: f64, hi: f64) -> bool {
    v.is_finite() && v > lo && v <= hi
}

/// A finite number in `(lo, hi]` (`lo` excluded, `hi` included).
fn parse_in(name: &str, value: &str, lo: f64, hi: f64) -> Result<f64, SolveError> {
    match value.parse::<f64>() {
        Ok(v) if in_interval(v, lo, hi) => Ok(v),
        _ => Err(invalid(
            name,
            format!("must be a number in ({lo:e}, {hi:e}], got `{value}`"),
        )),
    }
}

/// One of a list of names.
fn parse_choice<T: Copy>(name: &str, value: &str, choices: &[(&str, T)]) -> Result<T, SolveError> {
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
    common::CONTROL.pick("control", value, common::CONTROL_INPUTS)
}

/// The `control` value of an input (`displacement` or `force`), as the command line spells it.
pub fn control_name(i: Input) -> &'static str {
    match i {
        Input::Shortening => "displacement",
        Input::Tension => "force",
    }
}

/// Shared settings descriptions, and the typed values of the shared choices (in the order
/// of their words' value indices).
pub mod common {
    use super::{Range, SettingInfo, MAX_ITERATIONS};
    use crate::model::actuation::{Input, LengthMeasure};
    use crate::model::routing::RoutingFit;

    /// `control`'s words: `force`/`tension` pick a cable's tension, `displacement`/
    /// `shortening` its shortening ([`CONTROL_INPUTS`]).
    pub const CONTROL: Range = Range::Choice(&[
        ("force", 0),
        ("tension", 0),
        ("displacement", 1),
        ("shortening", 1),
    ]);
    /// What [`CONTROL`]'s words pick.
    pub const CONTROL_INPUTS: [Input; 2] = [Input::Tension, Input::Shortening];
    /// `length`'s values, as [`LENGTH_MEASURES`].
    pub const LENGTH_WORDS: Range = Range::Choice(&[("path", 0), ("chord", 1)]);
    /// What [`LENGTH_WORDS`] pick.
    pub const LENGTH_MEASURES: [LengthMeasure; 2] = [LengthMeasure::Path, LengthMeasure::Chord];
    /// `routing`'s values, as [`ROUTING_FITS`].
    pub const ROUTING_WORDS: Range = Range::Choice(&[("spline", 0), ("fourier8", 1)]);
    /// What [`ROUTING_WORDS`] pick.
    pub const ROUTING_FITS: [RoutingFit; 2] = [RoutingFit::Spline, RoutingFit::Fourier8];
    /// A switch: `on | off`, as [`ON_OFF`].
    pub const SWITCH: Range = Range::Choice(&[("on", 0), ("off", 1)]);
    /// What [`SWITCH`] and a two-word choice whose first word turns something on pick.
    pub const ON_OFF: [bool; 2] = [true, false];

    /// `control` with the given default.
    pub const fn control(default: &'static str) -> SettingInfo {
        SettingInfo {
            name: "control",
            values: CONTROL,
            default,
            help: "input used for a cable that gives both a tension and a shortening",
        }
    }
    /// `routing`.
    pub const ROUTING: SettingInfo = SettingInfo {
        name: "routing",
        values: ROUTING_WORDS,
        default: "spline",
        help: "cable routing fit through the holes",
    };
    /// `length`.
    pub const LENGTH: SettingInfo = SettingInfo {
        name: "length",
        values: LENGTH_WORDS,
        default: "path",
        help: "cable length measure under displacement control (alias cable-length)",
    };
    /// `max-iterations`.
    pub const fn max_iterations(default: &'static str) -> SettingInfo {
        SettingInfo {
            name: "max-iterations",
            values: Range::whole(1, MAX_ITERATIONS),
            default,
            help: "Newton iterations (per candidate / load step) before NotConverged",
        }
    }
    /// `tolerance`.
    pub const fn tolerance(default: &'static str, help: &'static str) -> SettingInfo {
        SettingInfo {
            name: "tolerance",
            values: Range::interval(0.0, 1.0),
            default,
            help,
        }
    }
}

/// Most iterations any setting may ask for (every run stays bounded).
pub const MAX_ITERATIONS: usize = 100_000;
