//! `ccrkit calibrate`: fit a model's hardware parameters to measured tips.

use super::predict::DataArgs;
use anyhow::{Context, Result};
use ccrkit::calibrate::fit::{calibrate, fitted_toml, FitOptions};
use ccrkit::Model;
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

/// Options of `ccrkit calibrate`.
#[derive(Args)]
pub struct CalibrateArgs {
    /// Model file (TOML) to start from.
    pub file: PathBuf,
    /// Parameters to fit (default: gain.segK and offset.segK per segment, compliance, marker.z;
    /// also backlash[.segK], axial-compliance[.segK] (1/EA: k = EA/length), base.rx/ry/rz, marker.x/y; see `ccrkit::calibrate::params`).
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    pub fit: Vec<String>,
    /// Write the fitted model here (a file `ccrkit predict` takes).
    #[arg(long)]
    pub out: PathBuf,
    /// Most Levenberg–Marquardt iterations.
    #[arg(long, default_value_t = 30)]
    pub max_iterations: usize,
    /// The training data (with `tip_x,tip_y,tip_z`) and how to solve its rows.
    #[command(flatten)]
    pub data: DataArgs,
}

/// Run `ccrkit calibrate`.
pub fn run(a: CalibrateArgs) -> Result<()> {
    let text = ccrkit::model::read::read_text(&a.file, "model file")?;
    let model = Model::from_file(&a.file)?;
    let (data, unit) = a.data.dataset()?;
    let predict = a.data.predict_options(&model)?;
    let mut opts = FitOptions::new(predict);
    opts.params = a.fit.clone();
    opts.max_iterations = a.max_iterations;
    let t = Instant::now();
    let rep = calibrate(&model, &data, &opts)?;
    let wall = t.elapsed().as_secs_f64();
    println!(
        "rows used {}  excluded (no solve at start) {}",
        rep.rows_used, rep.rows_excluded
    );
    println!(
        "iteration  aligned tip RMSE [{}]  damping  data passes",
        a.data.unit
    );
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
        "train RMSE [{}]: {:.3} -> {:.3} (mean {:.3}, median {:.3}, max {:.3})",
        a.data.unit,
        rep.before.rmse / unit,
        rep.after.rmse / unit,
        rep.after.mean / unit,
        rep.after.median / unit,
        rep.after.max / unit
    );
    let header = format!(
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
    std::fs::write(&a.out, fitted_toml(&text, &rep.model, &header)?)
        .with_context(|| format!("writing {}", a.out.display()))?;
    println!("wrote {}", a.out.display());
    Ok(())
}
