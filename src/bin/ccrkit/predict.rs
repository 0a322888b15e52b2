//! `ccrkit predict`: every row of a data CSV solved in-process, tips written as CSV.

use super::SolveArgs;
use anyhow::Result;
use ccrkit::calibrate::data::{family, unit_scale, DataOptions, Dataset};
use ccrkit::calibrate::predict::{predict, write_csv, PredictOptions, DEFAULT_CHUNK};
use ccrkit::calibrate::{aligned_errors, ErrorStats};
use ccrkit::Model;
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `predict` and `calibrate` share: the data, its columns and unit, the chunking and the
/// solve options (the method defaults to `MethodKind::DEFAULT`, as everywhere).
#[derive(Args)]
pub struct DataArgs {
    /// Data CSV: one row per sample, cable displacements (and `tip_x,tip_y,tip_z` to compare
    /// or fit to).
    #[arg(long)]
    pub data: PathBuf,
    /// Cable columns in the model's cable order (default: every `servo_*` column in file order).
    #[arg(long, value_delimiter = ',')]
    pub columns: Vec<String>,
    /// Unit of the data's displacements and tips: `mm` or `m`.
    #[arg(long, default_value = "mm")]
    pub unit: String,
    /// Rows solved in sequence per parallel chunk (each warm-started from the previous).
    #[arg(long, default_value_t = DEFAULT_CHUNK)]
    pub chunk: usize,
    #[command(flatten)]
    pub solve: SolveArgs,
}

impl DataArgs {
    /// The files of a `predict` or `calibrate` run checked before any work
    /// ([`crate::check_files`]): the model, the data and the scene are inputs, `out` the output
    /// (the files the model names are checked once it is loaded: [`crate::check_read`]).
    pub fn check_files(&self, model: &Path, out: &Path) -> Result<ccrkit::output::RunFiles> {
        crate::check_files(
            &[
                ("model file", Some(model)),
                ("--data file", Some(&self.data)),
                ("--scene file", self.solve.scene.as_deref()),
            ],
            &[("--out file", Some(out))],
        )
    }

    /// The data (read and checked) and the unit's size in metres.
    pub fn dataset(&self) -> Result<(Dataset, f64)> {
        let unit = unit_scale(&self.unit)?;
        let opts = DataOptions {
            columns: self.columns.clone(),
            unit,
        };
        Ok((Dataset::from_file(&self.data, &opts)?, unit))
    }

    /// The prediction options for `model` (request checked, `auto` settled on the model's
    /// own actuation, progress bar on).
    pub fn predict_options(&self, model: &Model) -> Result<PredictOptions> {
        Ok(PredictOptions {
            request: self.solve.request(1)?.resolved(model)?,
            chunk: self.chunk,
            progress: crate::progress::handle(),
        })
    }
}

/// Options of `ccrkit predict`.
#[derive(Args)]
pub struct PredictArgs {
    /// Model file (TOML); its `[hardware]` table maps commands and frames.
    pub file: PathBuf,
    /// Output CSV: `tip_x,tip_y,tip_z,status`, one row per input row, in the data's unit;
    /// `-` writes it to standard output (the summary then goes to standard error).
    #[arg(long)]
    pub out: PathBuf,
    #[command(flatten)]
    pub data: DataArgs,
}

/// Run `ccrkit predict`.
pub fn run(a: PredictArgs) -> Result<()> {
    let mut run = a.data.check_files(&a.file, &a.out)?;
    let model = Model::from_file(&a.file)?;
    let (data, unit) = a.data.dataset()?;
    let opts = a.data.predict_options(&model)?;
    crate::check_read(&mut run, &model, opts.request.extra_scene.as_ref())?;
    let t = Instant::now();
    let rows = predict(&model, &data, &opts)?;
    let wall = t.elapsed().as_secs_f64();
    let to_stdout = a.out.as_os_str() == "-";
    // With the CSV on standard output, the summary must not mix into it.
    let say = |line: String| {
        if to_stdout {
            eprintln!("{line}");
        } else {
            println!("{line}");
        }
    };
    if to_stdout {
        print!("{}", write_csv(&rows, unit));
    } else {
        crate::write_out(&a.out, &write_csv(&rows, unit))?;
    }
    let ok = rows.iter().filter(|r| r.tip.is_ok()).count();
    say(format!(
        "rows {}  solved {ok}  failed {}  wall {wall:.3} s  ({:.0} rows/s)",
        rows.len(),
        rows.len() - ok,
        rows.len() as f64 / wall
    ));
    if let Some(tips) = &data.tips {
        let (mut sim, mut real, mut fam) = (Vec::new(), Vec::new(), Vec::new());
        for (i, r) in rows.iter().enumerate() {
            if let Ok(t) = &r.tip {
                sim.push(*t);
                real.push(tips[i]);
                fam.push(
                    data.labels
                        .as_ref()
                        .map(|l| family(&l[i]))
                        .unwrap_or_default(),
                );
            }
        }
        let e = aligned_errors(&sim, &real);
        if let Some(s) = ErrorStats::of(&e) {
            say(format!(
                "mean-offset-aligned tip error [{}]: rmse {:.3}  mean {:.3}  median {:.3}  max {:.3}  over {} rows",
                a.data.unit, s.rmse / unit, s.mean / unit, s.median / unit, s.max / unit, s.n
            ));
        }
    }
    if !to_stdout {
        println!("wrote {}", a.out.display());
    }
    // Some rows solved: exit 0, the statuses per row tell which failed. None solved: the
    // prediction as a whole failed, say why with the first row's error.
    if ok == 0 {
        let first = rows.iter().find_map(|r| r.tip.as_ref().err()).map_or_else(
            || "the data has no row".to_string(),
            |e| format!("row 1: {e}"),
        );
        anyhow::bail!(
            "no row solved: {} of {} rows failed (statuses in {}); {first}",
            rows.len(),
            rows.len(),
            if to_stdout {
                "the CSV on standard output".to_string()
            } else {
                a.out.display().to_string()
            }
        );
    }
    Ok(())
}
