//! The paper's three cases (Mahapatra & Ghosal, §3): solve each with the literal geometric
//! method and the Cosserat rod (force control with the paper's cable forces, as the paper
//! compared them), print the tip positions and the RMS distance between the two next to the
//! paper's figures, and draw the paper's Fig. 3 layout (one row per case, three orthogonal
//! views, both models overlaid) to `target/paper_cases.svg` and `.png` (or the folder given as
//! the first argument). Every method in `EXTRA` that this build knows is drawn too.
//!
//! `cargo run --release --example paper_cases [OUT_DIR]`

use anyhow::Result;
use ccrkit::plot::{plot_rows, Row};
use ccrkit::{method_by_name, Model, Scene, Shape};
use std::path::PathBuf;

/// RMS between the paper's two models, its section 3 (mm).
const PAPER_RMS_MM: [f64; 3] = [1.57, 1.52, 1.19];

/// Further displacement-driven methods compared when available.
const EXTRA: &[&str] = &["energy"];

fn main() -> Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "target".into()));
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut methods = vec!["geometric", "cosserat"];
    methods.extend(EXTRA.iter().filter(|m| method_by_name(m).is_ok()));
    let mut solved: Vec<(Model, Vec<Shape>)> = vec![];
    for case in 1..=3 {
        let model = Model::from_file(root.join(format!("models/paper/case{case}.toml")))?;
        let mut shapes = vec![];
        for m in &methods {
            let method = method_by_name(m)?;
            shapes.push(method.solve(&model.robot, &model.actuation, &Scene::empty(), None)?);
        }
        solved.push((model, shapes));
    }

    println!("Tip positions (mm)\n");
    println!("| case | method | tip x | tip y | tip z |");
    println!("|---|---|---|---|---|");
    for (k, (_, shapes)) in solved.iter().enumerate() {
        for s in shapes {
            let t = s.tip() * 1000.0;
            println!(
                "| {} | {} | {:.3} | {:.3} | {:.3} |",
                k + 1,
                s.method,
                t.x,
                t.y,
                t.z
            );
        }
    }
    println!("\nAgainst the Cosserat rod (force control, the paper's forces), mm\n");
    println!("| case | method | RMS over disks | tip distance | paper's RMS (its geometric vs its rod) |");
    println!("|---|---|---|---|---|");
    for (k, (_, shapes)) in solved.iter().enumerate() {
        let rod = &shapes[1];
        for s in shapes.iter().filter(|s| s.method != "cosserat") {
            let rms = s.rms_distance(rod).unwrap_or(f64::NAN) * 1000.0;
            println!(
                "| {} | {} | {:.2} | {:.2} | {:.2} |",
                k + 1,
                s.method,
                rms,
                s.tip_distance(rod) * 1000.0,
                PAPER_RMS_MM[k]
            );
        }
    }
    println!("\nZero terms of the literal method, sections 1..n:");
    for (k, (_, shapes)) in solved.iter().enumerate() {
        let zeros: Vec<String> = shapes[0]
            .report
            .sections
            .iter()
            .map(|r| {
                if r.zero_terms.is_empty() {
                    "-".into()
                } else {
                    r.zero_terms.join("+")
                }
            })
            .collect();
        println!("  case {}: {}", k + 1, zeros.join(" "));
    }

    let rows: Vec<Row> = solved
        .iter()
        .enumerate()
        .map(|(k, (model, shapes))| Row {
            title: format!("Case {}", ["I", "II", "III"][k]),
            robot: &model.robot,
            shapes: shapes.iter().map(|s| (s, s.method.clone())).collect(),
            scene: None,
        })
        .collect();
    for ext in ["svg", "png"] {
        let p = out.join(format!("paper_cases.{ext}"));
        plot_rows(&rows, &p)?;
        println!("wrote {}", p.display());
    }
    Ok(())
}
