//! Compare methods on one model: each solved through the one solve path (same scene, same
//! settings rules), with the input that drove it, and pairwise distances. Two methods driven
//! by the same kind of input whose shapes lie farther apart than a stated tolerance are
//! flagged: they found different equilibria, or one of them is the wrong model here.

use super::{outcome, Input, Status, StudyError};
use crate::method::run::SolveRequest;
use crate::method::{MethodKind, Settings};
use crate::model::Model;
use crate::shape::Shape;

/// Default tip-distance tolerance above which two same-input methods are said to disagree \[m\].
pub const DISAGREE_TOL: f64 = 1e-3;

/// One compared method.
#[derive(Debug, Clone)]
pub struct ComparisonRow {
    /// Label: the method name and its settings (`cosserat control=displacement`).
    pub label: String,
    /// The method.
    pub method: MethodKind,
    /// The input that drove it.
    pub input: Input,
    /// How the solve ended.
    pub status: Status,
    /// The failure message, when it failed.
    pub error: Option<String>,
    /// The shape, when it solved.
    pub shape: Option<Shape>,
    /// Median solve time \[s\].
    pub time_s: f64,
}

/// Distance between two solved rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairDistance {
    /// Row indices.
    pub rows: (usize, usize),
    /// RMS distance of the disk positions \[m\].
    pub rms_m: f64,
    /// Tip distance \[m\].
    pub tip_m: f64,
    /// Both rows driven by the same kind of input.
    pub same_input: bool,
    /// Same input and farther apart than the tolerance.
    pub disagree: bool,
}

/// The result of [`compare`].
#[derive(Debug, Clone)]
pub struct Comparison {
    /// Model name.
    pub model: String,
    /// One row per request, in order.
    pub rows: Vec<ComparisonRow>,
    /// Every pair of solved rows.
    pub pairs: Vec<PairDistance>,
    /// Tip-distance tolerance used for [`PairDistance::disagree`] \[m\].
    pub tolerance_m: f64,
}

impl Comparison {
    /// True when any same-input pair disagrees.
    pub fn any_disagreement(&self) -> bool {
        self.pairs.iter().any(|p| p.disagree)
    }
}

/// Label of a request: method name plus its settings.
pub fn request_label(r: &SolveRequest) -> String {
    if r.settings.is_empty() {
        r.method.name().to_string()
    } else {
        let s: Vec<String> = r.settings.iter().map(|(k, v)| format!("{k}={v}")).collect();
        format!("{} {}", r.method.name(), s.join(" "))
    }
}

/// Parse a method entry of `--methods`: `NAME` or `NAME:SETTING=VALUE:SETTING=VALUE`.
pub fn parse_entry(text: &str) -> Result<(MethodKind, Settings), StudyError> {
    let mut parts = text.split(':');
    let kind: MethodKind = parts.next().unwrap_or_default().parse()?;
    let mut s = Settings::new();
    for p in parts {
        let (k, v) = Settings::parse_pair(p)?;
        kind.check_setting(&k)?;
        s.push(k, v);
    }
    Ok((kind, s))
}

/// Solve every request on `model` (a failure becomes a row with its kind) and measure every
/// pair. `tolerance_m` is the tip distance beyond which same-input rows disagree.
pub fn compare(
    model: &Model,
    requests: &[SolveRequest],
    tolerance_m: f64,
) -> Result<Comparison, StudyError> {
    crate::model::bounds::TIP_DISTANCE
        .check("tolerance", tolerance_m)
        .map_err(crate::error::SolveError::from)?;
    let mut rows = Vec::with_capacity(requests.len());
    for r in requests {
        r.solver()?;
        let res = r.run(model);
        let time_s = res.as_ref().map(|s| s.median_time_s).unwrap_or(f64::NAN);
        let error = res.as_ref().err().map(|e| e.to_string());
        let o = outcome(res.map(|s| s.shape));
        rows.push(ComparisonRow {
            label: request_label(r),
            method: r.method,
            input: r.method.input_with(&r.settings),
            status: o.status,
            error,
            shape: o.shape,
            time_s,
        });
    }
    let mut pairs = vec![];
    for i in 0..rows.len() {
        for j in i + 1..rows.len() {
            let (Some(a), Some(b)) = (&rows[i].shape, &rows[j].shape) else {
                continue;
            };
            let Some(rms_m) = a.rms_distance(b) else {
                continue;
            };
            let tip_m = a.tip_distance(b);
            let same_input = rows[i].input == rows[j].input;
            pairs.push(PairDistance {
                rows: (i, j),
                rms_m,
                tip_m,
                same_input,
                disagree: same_input && tip_m > tolerance_m,
            });
        }
    }
    Ok(Comparison {
        model: model.robot.name.clone(),
        rows,
        pairs,
        tolerance_m,
    })
}

impl std::fmt::Display for Comparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "model {}", self.model)?;
        writeln!(
            f,
            "{:<4} {:<40} {:<11} {:<14} {:>32} {:>10}",
            "row", "method", "input", "status", "tip [mm]", "time [µs]"
        )?;
        for (k, r) in self.rows.iter().enumerate() {
            let tip = r
                .shape
                .as_ref()
                .map(|s| {
                    let t = s.tip() * 1e3;
                    format!("[{:.3}, {:.3}, {:.3}]", t.x, t.y, t.z)
                })
                .unwrap_or_default();
            // A row that did not solve has no time (`NaN` inside): left blank, as its tip.
            let time = match r.time_s.is_finite() {
                true => format!("{:.0}", r.time_s * 1e6),
                false => String::new(),
            };
            writeln!(
                f,
                "{:<4} {:<40} {:<11} {:<14} {:>32} {:>10}",
                k + 1,
                r.label,
                r.input.name(),
                r.status.name(),
                tip,
                time
            )?;
            if let Some(e) = &r.error {
                writeln!(f, "     {e}")?;
            }
        }
        writeln!(f)?;
        writeln!(
            f,
            "pairs (RMS over disks, tip distance; same-input pairs beyond {} at the tip disagree):",
            crate::method::auto::mm(self.tolerance_m)
        )?;
        for p in &self.pairs {
            writeln!(
                f,
                "  {} vs {}: RMS {:.3} mm, tip {:.3} mm{}",
                self.rows[p.rows.0].label,
                self.rows[p.rows.1].label,
                p.rms_m * 1e3,
                p.tip_m * 1e3,
                if p.disagree {
                    "  DISAGREE (same input)"
                } else if p.same_input {
                    "  (same input)"
                } else {
                    "  (different inputs: not comparable as models)"
                }
            )?;
        }
        Ok(())
    }
}

/// One row of [`ComparisonJson`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct RowJson {
    /// The method and its settings.
    pub label: String,
    /// The input that drove it (`shortening` or `tension`).
    pub input: String,
    /// How the solve ended ([`Status`] name).
    pub status: String,
    /// The failure message, when it failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The tip, base frame \[m\], when it solved.
    pub tip_m: Option<[f64; 3]>,
    /// Whether the method found its answer stable, when it says.
    pub stable: Option<bool>,
    /// Median solve time \[s\] (`null` when it failed).
    pub time_s: Option<f64>,
}

/// One pair of [`ComparisonJson`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct PairJson {
    /// The two rows' labels.
    pub rows: (String, String),
    /// RMS distance over the disks \[m\].
    pub rms_m: f64,
    /// Tip distance \[m\].
    pub tip_m: f64,
    /// Both driven by the same kind of input.
    pub same_input: bool,
    /// Same input and farther apart than the tolerance (`DISAGREE (same input)` in the text).
    pub disagree: bool,
}

/// A comparison as JSON (`ccrkit compare --json`): the rows, every pair with its
/// disagreement flag, and whether any pair disagrees.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ComparisonJson {
    /// Model name.
    pub model: String,
    /// Tip-distance tolerance of the flag \[m\].
    pub tolerance_m: f64,
    /// Some same-input pair disagrees ([`Comparison::any_disagreement`]).
    pub any_disagreement: bool,
    /// One per method, in order.
    pub rows: Vec<RowJson>,
    /// Every pair of solved rows.
    pub pairs: Vec<PairJson>,
}

impl Comparison {
    /// This comparison as JSON ([`ComparisonJson`]).
    pub fn to_json(&self) -> ComparisonJson {
        let rows = self
            .rows
            .iter()
            .map(|r| RowJson {
                label: r.label.clone(),
                input: r.input.name().to_string(),
                status: r.status.name().to_string(),
                error: r.error.clone(),
                tip_m: r.shape.as_ref().map(|s| {
                    let t = s.tip();
                    [t.x, t.y, t.z]
                }),
                stable: r.shape.as_ref().and_then(|s| s.report.stable),
                time_s: Some(r.time_s).filter(|t| t.is_finite()),
            })
            .collect();
        let pairs = self
            .pairs
            .iter()
            .map(|p| PairJson {
                rows: (
                    self.rows[p.rows.0].label.clone(),
                    self.rows[p.rows.1].label.clone(),
                ),
                rms_m: p.rms_m,
                tip_m: p.tip_m,
                same_input: p.same_input,
                disagree: p.disagree,
            })
            .collect();
        ComparisonJson {
            model: self.model.clone(),
            tolerance_m: self.tolerance_m,
            any_disagreement: self.any_disagreement(),
            rows,
            pairs,
        }
    }
}
