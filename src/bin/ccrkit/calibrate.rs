//! `ccrkit calibrate`: fit a model's hardware parameters to measured tips. Without `--fit` it
//! first chooses the parameter set on the training data only (`calibrate::select`), as the
//! `hardware_fit` example does; `--fit` fits the named set alone.

use super::predict::DataArgs;
use anyhow::Result;
use ccrkit::calibrate::fit::{calibrate, fitted_toml, FitOptions, FitReport};
use ccrkit::calibrate::select::{candidates, select, SelectOptions, Selection};
use ccrkit::{Model, SolveError};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

/// Options of `ccrkit calibrate`.
#[derive(Args)]
pub struct CalibrateArgs {
    /// Model file (TOML) to start from.
    pub file: PathBuf,
    /// Parameters to fit, instead of choosing a set: `default` (gain.segK and offset.segK per
    /// segment, compliance, marker.z) or names: gain, offset, compliance, backlash,
    /// axial-compliance, friction (each common, .segK or .CABLE), stiffening, base.rx/ry/rz,
    /// marker.x/y/z (see `ccrkit::calibrate::params`). Without it, every candidate set of
    /// `ccrkit::calibrate::select::candidates` is fitted and the one with the lowest error on
    /// the hold-out rows of the training data (`--holdout`) is chosen and reported.
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    pub fit: Vec<String>,
    /// Without `--fit`: rows whose `pattern_label` contains this are held out of each
    /// candidate's choice fit and score it.
    #[arg(long, default_value = "_same_")]
    pub holdout: String,
    /// Without `--fit`: also try the two candidate sets with capstan friction (a friction row
    /// costs several times more).
    #[arg(long)]
    pub friction: bool,
    /// Write the fitted model here (a file `ccrkit predict` takes).
    #[arg(long)]
    pub out: PathBuf,
    /// Most Levenberg–Marquardt iterations (of each fit).
    #[arg(long, default_value_t = 30)]
    pub max_iterations: usize,
    /// The training data (with `tip_x,tip_y,tip_z`) and how to solve its rows.
    #[command(flatten)]
    pub data: DataArgs,
}

/// Run `ccrkit calibrate`.
pub fn run(a: CalibrateArgs) -> Result<()> {
    let mut run = a.data.check_files(&a.file, &a.out)?;
    let text = ccrkit::model::read::read_text(&a.file, "model file")?;
    let model = Model::from_file(&a.file)?;
    let (data, unit) = a.data.dataset()?;
    let mut opts = FitOptions::new(a.data.predict_options(&model)?);
    crate::check_read(&mut run, &model, opts.predict.request.extra_scene.as_ref())?;
    opts.max_iterations = a.max_iterations;
    let t = Instant::now();
    let (rep, chosen) = if a.fit.is_empty() {
        if data.labels.is_none() {
            return Err(SolveError::InvalidInput {
                field: "pattern_label".into(),
                reason: format!(
                    "`{}` has no such column: choosing the parameter set on train needs \
                     labelled hold-out rows; pass `--fit default` (or parameter names) to fit \
                     one set",
                    a.data.data.display()
                ),
            }
            .into());
        }
        let mut so = SelectOptions::new(opts);
        so.holdout = a.holdout.clone();
        let sel = select(&model, &data, &candidates(&model.robot, a.friction), &so)?;
        print_selection(&sel, &so.holdout, unit, &a.data.unit);
        let c = sel.chosen();
        let label = format!(
            "chosen on train only among {} candidate sets: `{}` (lowest aligned tip RMSE on \
             the {} hold-out rows `{}`, fitted without them)",
            sel.scored.len() + sel.failed.len(),
            c.candidate.label,
            sel.holdout_rows.len(),
            so.holdout
        );
        (c.full.clone(), Some(label))
    } else {
        if a.fit != ["default"] {
            opts.params = a.fit.clone();
        }
        (calibrate(&model, &data, &opts)?, None)
    };
    let wall = t.elapsed().as_secs_f64();
    print_fit(&rep, unit, &a.data.unit, wall);
    let mut header = format!(
        "Fitted by `ccrkit calibrate {}` on {} ({} rows): aligned train tip RMSE {:.3} {}.\n\
         Parameters: {}.",
        a.file.display(),
        a.data.data.display(),
        rep.rows_used,
        rep.after.rmse / unit,
        a.data.unit,
        rep.params
            .iter()
            .map(|p| p.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    if let Some(c) = &chosen {
        println!("{c}");
        header.push_str(&format!("\nParameter set {c}."));
    }
    crate::write_out(&a.out, &fitted_toml(&text, &rep.model, &header)?)?;
    println!("wrote {}", a.out.display());
    Ok(())
}

/// The choice: every candidate's train and hold-out error, the failed ones, the chosen one.
fn print_selection(sel: &Selection, holdout: &str, unit: f64, unit_name: &str) {
    println!(
        "choosing the parameter set on train only: each candidate fitted without the {} rows \
         labelled `{holdout}` and scored on them",
        sel.holdout_rows.len()
    );
    println!(
        "candidate                  scalars  train RMSE [{unit_name}]  hold-out RMSE [{unit_name}]"
    );
    for (i, s) in sel.scored.iter().enumerate() {
        let mark = if i == sel.best { "  <- chosen" } else { "" };
        println!(
            "{:<26} {:>7}  {:>15.3}  {:>18.3}{mark}",
            s.candidate.label,
            s.candidate.params.len(),
            s.full.after.rmse / unit,
            s.holdout_rmse / unit
        );
    }
    for (c, e) in &sel.failed {
        println!("{:<26} {:>7}  not fitted: {e}", c.label, c.params.len());
    }
}

/// One fit's report: the cost per iteration, the fitted values, the train error.
fn print_fit(rep: &FitReport, unit: f64, unit_name: &str, wall: f64) {
    println!(
        "rows used {}  excluded (no solve at start) {}",
        rep.rows_used, rep.rows_excluded
    );
    println!("iteration  aligned tip RMSE [{unit_name}]  damping  data passes");
    for h in &rep.history {
        println!(
            "{:>9}  {:>20.4}  {:>7.1e}  {:>11}",
            h.iteration,
            h.rmse / unit,
            h.lambda,
            h.passes
        );
    }
    println!("stopped: {}  ({wall:.1} s)", rep.stop);
    println!("parameter        initial        fitted     ± std. error  unit");
    for p in &rep.params {
        let sig = p
            .sigma
            .map(|s| format!("{s:.3e}"))
            .unwrap_or_else(|| "singular".into());
        println!(
            "{:<14} {:>12.6} {:>13.6} {:>16}  {}",
            p.name, p.initial, p.value, sig, p.unit
        );
    }
    println!(
        "train RMSE [{unit_name}]: {:.3} -> {:.3} (mean {:.3}, median {:.3}, max {:.3})",
        rep.before.rmse / unit,
        rep.after.rmse / unit,
        rep.after.mean / unit,
        rep.after.median / unit,
        rep.after.max / unit
    );
}
