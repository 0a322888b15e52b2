//! Stability maps on the paper's case I: the inputs of cables A and B swept on a 40×40 grid
//! (shortening 0–18 % for the displacement methods, tension 0–10× the file's for the rods),
//! every method cold and with continuation along the rows. Writes `stability.csv` and
//! `stability_METHOD.{svg,png}` to `target/` (or the folder given as first argument); an
//! optional second argument sets the grid size.
//!
//! `cargo run --release --example stability_map [OUT_DIR] [GRID]`

use anyhow::Result;
use ccrkit::study::{self, figures};
use ccrkit::Model;
use std::path::PathBuf;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "target".into()));
    let grid: usize = match args.next() {
        Some(g) => g.parse()?,
        None => 40,
    };
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model = Model::from_file(root.join("models/paper/case1.toml"))?;
    let opts = study::StabilityOptions {
        grid,
        progress: ccrkit::progress::ProgressHandle::new(|e: ccrkit::progress::Event<'_>| {
            if let ccrkit::progress::Event::Start { task, total } = e {
                eprintln!("{task}: {} steps", total.unwrap_or(0));
            }
        }),
        ..Default::default()
    };
    let st = study::stability(&model, &opts)?;
    study::write_text(&out.join("stability.csv"), &study::stability_csv(&st))?;
    for s in study::stability_summary(&st) {
        println!("{}", s.line(&st.cables));
    }
    for m in &opts.methods {
        for ext in ["svg", "png"] {
            figures::stability_figure(&st, m, &out.join(format!("stability_{m}.{ext}")))?;
        }
    }
    eprintln!("wrote {}/stability.csv and the maps", out.display());
    Ok(())
}
