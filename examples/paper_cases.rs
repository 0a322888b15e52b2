//! The paper's three cases (Mahapatra & Ghosal, §3): solve each with the literal geometric
//! method, print the tip positions, put the whole-robot energy model and the Cosserat rod
//! (displacement control, path lengths) next to it (RMS table), and draw the paper's Fig. 3 layout (one row per case, three
//! orthogonal views) to `target/paper_cases.svg` and `.png` (or the folder given as argument).
//!
//! `cargo run --release --example paper_cases [OUT_DIR]`

use anyhow::Result;
use ccrkit::method::cosserat::{Control, Cosserat};
use ccrkit::plot::{plot_rows, Row};
use ccrkit::{method_by_name, Method, Model, Scene};
use std::path::PathBuf;

fn main() -> Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "target".into()));
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let method = method_by_name("geometric")?;
    let mut solved = vec![];
    for case in 1..=3 {
        let model = Model::from_file(root.join(format!("models/paper/case{case}.toml")))?;
        let shape = method.solve(&model.robot, &model.actuation, &Scene::empty(), None)?;
        solved.push((case, model, shape));
    }
    println!(
        "| case | method | tip x [mm] | tip y [mm] | tip z [mm] | zero terms (sections 1..n) |"
    );
    println!("|---|---|---|---|---|---|");
    for (case, _, s) in &solved {
        let t = s.tip() * 1000.0;
        let zeros: Vec<String> = s
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
        println!(
            "| {case} | {} | {:.3} | {:.3} | {:.3} | {} |",
            s.method,
            t.x,
            t.y,
            t.z,
            zeros.join(" ")
        );
    }
    // The whole-robot energy model and the rod driven by the same (path) cable lengths.
    let energy = method_by_name("energy")?;
    let rod = Cosserat::full().with_control(Control::Displacement);
    let mut others = vec![];
    println!();
    println!("| case | literal vs rod [mm] | energy vs rod [mm] | energy tensions / rod [N] |");
    println!("|---|---|---|---|");
    for (case, model, geo) in &solved {
        let en = energy.solve(&model.robot, &model.actuation, &Scene::empty(), None)?;
        let cos = rod.solve(&model.robot, &model.actuation, &Scene::empty(), None)?;
        let tens: Vec<String> = en
            .cables
            .iter()
            .zip(&cos.cables)
            .map(|(a, b)| {
                format!(
                    "{} {:.3}/{:.3}",
                    a.name,
                    a.tension.unwrap_or(0.0),
                    b.tension.unwrap_or(0.0)
                )
            })
            .collect();
        println!(
            "| {case} | {:.3} | {:.3} | {} |",
            geo.rms_distance(&cos).unwrap_or(f64::NAN) * 1e3,
            en.rms_distance(&cos).unwrap_or(f64::NAN) * 1e3,
            tens.join(", ")
        );
        others.push((en, cos));
    }
    let rows: Vec<Row> = solved
        .iter()
        .zip(&others)
        .map(|((case, model, shape), (en, cos))| Row {
            title: format!("Case {}", ["I", "II", "III"][case - 1]),
            robot: &model.robot,
            shapes: vec![
                (shape, shape.method.clone()),
                (en, "energy".into()),
                (cos, "cosserat (displacement)".into()),
            ],
        })
        .collect();
    for ext in ["svg", "png"] {
        let p = out.join(format!("paper_cases.{ext}"));
        plot_rows(&rows, &p)?;
        println!("wrote {}", p.display());
    }
    Ok(())
}
