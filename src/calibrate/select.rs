//! Model selection on training data only (the protocol of `models/hardware/data/README.md` §8:
//! "never use val for fitting or for model selection").
//!
//! [`select`] takes a model, **one** dataset (train) and candidate parameter sets, and by its
//! signature can see nothing else: no file, no path, no validation rows. Every candidate is
//! fitted on all of train (the model one reports) and again on train without the hold-out rows
//! ([`SelectOptions::holdout`], by default the two-segment `_same_` patterns, the train family
//! nearest to the FTDCR val files' three-segment motions); the second fit predicts the held-out
//! rows, and the candidate with the lowest mean-offset-aligned tip RMSE there is chosen. Ties
//! go to the earlier candidate, so the order of the list is the preference among equals.
//!
//! [`candidates`] is the list `ccrkit calibrate` chooses from when no `--fit` is given, and the
//! `hardware_fit` example too. Val is read by the caller only after [`select`] has returned
//! (`examples/hardware_fit.rs`);
//! `tests/hardware/hardware_select.rs` checks that the choice does not change with a val file present,
//! absent or garbage beside the train file.

use super::data::Dataset;
use super::fit::{calibrate, FitOptions, FitReport};
use super::params::{default_names, segments};
use super::predict::predict;
use super::{aligned_errors, ErrorStats};
use crate::error::SolveError;
use crate::model::robot::Robot;
use crate::model::Model;
use nalgebra::Vector3;

/// One candidate: a label and the parameter names it fits ([`super::params`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// Label for reports and file names.
    pub label: String,
    /// Parameter names.
    pub params: Vec<String>,
}

/// How to select.
#[derive(Debug, Clone)]
pub struct SelectOptions {
    /// Fit options of every fit (their `params` are replaced by each candidate's).
    pub fit: FitOptions,
    /// Rows whose `pattern_label` contains this are held out of the selection fit.
    pub holdout: String,
}

impl SelectOptions {
    /// Around `fit`, holding out the `_same_` patterns.
    pub fn new(fit: FitOptions) -> Self {
        SelectOptions {
            fit,
            holdout: "_same_".into(),
        }
    }
}

/// One scored candidate.
#[derive(Debug, Clone)]
pub struct Scored {
    /// The candidate.
    pub candidate: Candidate,
    /// Its fit on all of train.
    pub full: FitReport,
    /// Its fit on train without the hold-out rows.
    pub reduced: FitReport,
    /// Aligned tip RMSE \[m\] of `reduced` on the hold-out rows that solved.
    pub holdout_rmse: f64,
    /// Hold-out rows that did not solve (left out of `holdout_rmse`).
    pub holdout_failed: usize,
}

/// The outcome of [`select`].
#[derive(Debug, Clone)]
pub struct Selection {
    /// Every candidate that fitted, in the order given.
    pub scored: Vec<Scored>,
    /// Candidates whose fit (or hold-out prediction) failed, with the error: not chosen.
    pub failed: Vec<(Candidate, SolveError)>,
    /// Index of the chosen candidate in `scored`.
    pub best: usize,
    /// The held-out rows (indices into train).
    pub holdout_rows: Vec<usize>,
}

impl Selection {
    /// The chosen candidate.
    pub fn chosen(&self) -> &Scored {
        &self.scored[self.best]
    }
}

/// Fit every candidate on `train` and choose one on a hold-out split of `train` (module docs).
/// A candidate whose fit fails, or whose hold-out has no row that solves, is listed in
/// [`Selection::failed`] and not chosen. Errors name the field: no candidate, no labels, an
/// empty hold-out or an empty remainder, every candidate failed.
pub fn select(
    model: &Model,
    train: &Dataset,
    candidates: &[Candidate],
    opts: &SelectOptions,
) -> Result<Selection, SolveError> {
    let bad = |field: &str, reason: String| SolveError::InvalidInput {
        field: field.into(),
        reason,
    };
    if candidates.is_empty() {
        return Err(bad("candidates", "no candidate to select from".into()));
    }
    opts.fit.check()?;
    let labels = train.labels.as_ref().ok_or_else(|| {
        bad(
            "holdout",
            "the training data has no pattern_label column to split on".into(),
        )
    })?;
    let (held, rest): (Vec<usize>, Vec<usize>) =
        (0..train.len()).partition(|&i| labels[i].contains(opts.holdout.as_str()));
    if held.is_empty() || rest.len() < 2 {
        return Err(bad(
            "holdout",
            format!(
                "`{}` holds out {} of {} rows: need some held out and some left to fit",
                opts.holdout,
                held.len(),
                train.len()
            ),
        ));
    }
    let (fit_rows, test_rows) = (train.select(&rest), train.select(&held));
    let mut scored = Vec::with_capacity(candidates.len());
    let mut failed = vec![];
    for cand in candidates {
        match score(model, train, cand, opts, (&fit_rows, &test_rows)) {
            Ok(sc) => scored.push(sc),
            Err(e) => failed.push((cand.clone(), e)),
        }
    }
    if scored.is_empty() {
        let why: Vec<String> = failed
            .iter()
            .map(|(c, e)| format!("`{}`: {e}", c.label))
            .collect();
        return Err(bad(
            "candidates",
            format!("every candidate failed: {}", why.join("; ")),
        ));
    }
    let mut best = 0;
    for (i, s) in scored.iter().enumerate() {
        if s.holdout_rmse < scored[best].holdout_rmse {
            best = i;
        }
    }
    Ok(Selection {
        scored,
        failed,
        best,
        holdout_rows: held,
    })
}

/// Fit `cand` on all of train and on `split.0` (train without the hold-out), and score the
/// latter on `split.1` (the hold-out).
fn score(
    model: &Model,
    train: &Dataset,
    cand: &Candidate,
    opts: &SelectOptions,
    split: (&Dataset, &Dataset),
) -> Result<Scored, SolveError> {
    let (fit_rows, test_rows) = split;
    let mut fo = opts.fit.clone();
    fo.params = cand.params.clone();
    let full = calibrate(model, train, &fo)?;
    let reduced = calibrate(model, fit_rows, &fo)?;
    let pred = predict(&reduced.model, test_rows, &fo.predict)?;
    let meas = test_rows.tips.clone().unwrap_or_default();
    let (mut sim, mut real) = (Vec::<Vector3<f64>>::new(), Vec::new());
    for (p, m) in pred.iter().zip(&meas) {
        if let Ok(t) = &p.tip {
            sim.push(*t);
            real.push(*m);
        }
    }
    let rmse = ErrorStats::of(&aligned_errors(&sim, &real))
        .ok_or_else(|| SolveError::InvalidInput {
            field: "holdout".into(),
            reason: format!("no held-out row solves with candidate `{}`", cand.label),
        })?
        .rmse;
    Ok(Scored {
        candidate: cand.clone(),
        full,
        reduced,
        holdout_rmse: rmse,
        holdout_failed: pred.len() - sim.len(),
    })
}

/// The candidate parameter sets `ccrkit calibrate` (without `--fit`) and the `hardware_fit`
/// example choose among, each ≤ 9 scalars on a three-segment robot (the data protocol's
/// limit): the default set ([`super::params::default_names`]: per-segment gain and offset, one
/// cable compliance, the marker), the same plus one common backlash, plus the base rotation
/// about z, plus capstan friction, the EA form of the compliance (`k = EA/ℓ`: longer cables
/// softer) in place of the uniform one, plus the backbone's curvature stiffening `β` (bending
/// energy `½ EI κ² (1 + β κ²)`), and `β` with the backlash, the base rotation or the friction
/// in place of the marker (kept at its value in the model). Two with `β` that spend scalars
/// elsewhere than per segment (marker kept, no backlash): the base tilted against the
/// measurement frame's z axis (`base.rx`, `base.ry`) in place of the proximal offset, and an
/// offset per tendon of the distal segment in place of its segment's (the proximal offset
/// kept). The two with friction only when `friction`: a friction row costs several times more.
/// The default set comes first, so it wins ties.
pub fn candidates(robot: &Robot, friction: bool) -> Vec<Candidate> {
    let default = default_names(robot);
    let segs = segments(robot);
    let n = segs.len();
    let gains = || (0..n).map(|k| format!("gain.seg{k}")).collect::<Vec<_>>();
    let stiff = ["compliance".to_string(), "stiffening".to_string()];
    let mut tilt = gains();
    tilt.extend((1..n).map(|k| format!("offset.seg{k}")));
    tilt.extend(stiff.clone());
    tilt.extend(["base.rx".to_string(), "base.ry".to_string()]);
    let mut per_tendon = gains();
    per_tendon.extend((1..n.saturating_sub(1)).map(|k| format!("offset.seg{k}")));
    if let Some(distal) = segs.last() {
        per_tendon.extend(
            distal
                .iter()
                .map(|&c| format!("offset.{}", robot.cables[c].name)),
        );
    }
    per_tendon.extend(stiff);
    let with = |extra: &str| {
        let mut v = default.clone();
        v.push(extra.into());
        v
    };
    let no_marker = |extra: &[&str]| {
        let mut v: Vec<String> = default
            .iter()
            .filter(|n| *n != "marker.z")
            .cloned()
            .collect();
        v.extend(extra.iter().map(|e| e.to_string()));
        v
    };
    let ea = default
        .iter()
        .map(|n| match n.as_str() {
            "compliance" => "axial-compliance".to_string(),
            _ => n.clone(),
        })
        .collect();
    [
        ("fitted", default.clone()),
        ("fitted+backlash", with("backlash")),
        ("fitted+base.rz", with("base.rz")),
        ("fitted+friction", with("friction")),
        ("fitted_EA", ea),
        ("fitted+stiffening", with("stiffening")),
        (
            "backlash+stiffening",
            no_marker(&["backlash", "stiffening"]),
        ),
        ("base.rz+stiffening", no_marker(&["base.rz", "stiffening"])),
        (
            "friction+stiffening",
            no_marker(&["friction", "stiffening"]),
        ),
        ("tilt+stiffening", tilt),
        ("offset.tendon+stiffening", per_tendon),
    ]
    .into_iter()
    .filter(|(label, _)| friction || !label.contains("friction"))
    .map(|(label, params)| Candidate {
        label: label.into(),
        params,
    })
    .collect()
}
