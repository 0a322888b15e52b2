//! Speed against accuracy on the paper's case II: every method at each resolution setting of
//! the registry, median solve time and error against the converged Cosserat rod (80 RK4 steps
//! per section) driven by the same kind of input — the file's tensions for the force-driven
//! rows, the file's shortenings for the displacement-driven ones. Writes
//! `speed_accuracy.csv`, `.svg`, `.png` to `target/` (or the folder given as argument) and
//! prints the table. Each time is the median of `REPEATS` solves (default 21: on a loaded
//! machine a median of 5 still catches preempted solves).
//!
//! `cargo run --release --example speed_vs_accuracy [OUT_DIR] [REPEATS]`

use anyhow::{Context, Result};
use ccrkit::study::{self, figures};
use ccrkit::Model;
use std::path::PathBuf;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "target".into()));
    let repeats: usize = match args.next() {
        Some(r) => r
            .parse()
            .ok()
            .filter(|&n| n >= 1)
            .with_context(|| format!("REPEATS must be a whole number ≥ 1, got `{r}`"))?,
        None => 21,
    };
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model = Model::from_file(root.join("models/paper/case2.toml"))?;
    let rows = study::speed_accuracy(
        &model,
        &study::SpeedAccuracyOptions {
            repeats,
            progress: ccrkit::progress::ProgressHandle::new(|e: ccrkit::progress::Event<'_>| {
                if let ccrkit::progress::Event::Start { task, total } = e {
                    eprintln!("{task}: {} steps", total.unwrap_or(0));
                }
            }),
            ..Default::default()
        },
    )?;
    let front = study::speed_accuracy_front(&rows);
    println!("Errors against the converged rod driven by the same kind of input (force: the file's tensions; displacement: the file's shortenings); times are medians of {repeats} solves.\n");
    println!("| method | setting | input / reference | median time [ms] | tip error [mm] | RMS error [mm] | Pareto |");
    println!("|---|---|---|---|---|---|---|");
    for (r, f) in rows.iter().zip(front) {
        if r.status.is_ok() {
            println!(
                "| {} | {} | {} | {:.3} | {:.2e} | {:.2e} | {} |",
                r.method,
                r.setting,
                r.reference,
                r.median_time_s * 1e3,
                r.tip_error_m * 1e3,
                r.rms_error_m * 1e3,
                if f { "yes" } else { "" }
            );
        } else {
            println!(
                "| {} | {} | {} | {} | | | |",
                r.method, r.setting, r.reference, r.status
            );
        }
    }
    study::write_text(
        &out.join("speed_accuracy.csv"),
        &study::speed_accuracy_csv(&rows),
    )?;
    let title = format!("{}: speed against accuracy", model.robot.name);
    for ext in ["svg", "png"] {
        figures::speed_accuracy_figure(&rows, &title, &out.join(format!("speed_accuracy.{ext}")))?;
    }
    eprintln!("wrote {}/speed_accuracy.{{csv,svg,png}}", out.display());
    Ok(())
}
