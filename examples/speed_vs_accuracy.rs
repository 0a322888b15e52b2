//! Speed against accuracy on the paper's case II: every method at each resolution setting,
//! median solve time and error against a converged Cosserat rod (80 RK4 steps per section,
//! force control). Writes `speed_accuracy.csv`, `.svg`, `.png` to `target/` (or the folder
//! given as argument) and prints the table.
//!
//! `cargo run --release --example speed_vs_accuracy [OUT_DIR]`

use anyhow::Result;
use ccrkit::study::{self, figures};
use ccrkit::Model;
use std::path::PathBuf;

fn main() -> Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "target".into()));
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model = Model::from_file(root.join("models/paper/case2.toml"))?;
    let rows = study::speed_accuracy(
        &model,
        &study::SpeedAccuracyOptions {
            progress: true,
            ..Default::default()
        },
    )?;
    let front = study::speed_accuracy_front(&rows);
    println!("Errors against the converged rod driven by the same kind of input (force: the file's tensions; displacement: the file's shortenings).\n");
    println!("| method | setting | input / reference | median time [ms] | tip error [mm] | RMS error [mm] | Pareto |");
    println!("|---|---|---|---|---|---|---|");
    for (r, f) in rows.iter().zip(front) {
        if r.status == "ok" {
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
