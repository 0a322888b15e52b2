//! The paper's three cases (Mahapatra & Ghosal, §3), side by side:
//!
//! * the literal geometric method against the Cosserat rod under force control with the
//!   paper's cable forces (the paper's own comparison), next to the paper's RMS figures;
//! * the whole-robot energy model and the literal method against the rod driven by the same
//!   cable lengths (displacement control, lengths along the routed path), with tensions.
//!
//! It draws the paper's Fig. 3 layout (one row per case, three orthogonal views; literal,
//! energy and the rod driven by the same shortenings overlaid, and the rod driven by the
//! paper's tensions — each legend entry says which input drove the curve) to `target/paper_cases.svg` and `.png` (or the folder given as the
//! first argument).
//!
//! `cargo run --release --example paper_cases [OUT_DIR]`

use anyhow::Result;
use ccrkit::plot::{plot_rows, Row};
use ccrkit::prelude::*;
use std::path::PathBuf;

/// RMS between the paper's two models, its section 3 (mm).
const PAPER_RMS_MM: [f64; 3] = [1.57, 1.52, 1.19];

struct Case {
    model: Model,
    literal: Shape,
    energy: Shape,
    /// Rod, force control (the paper's forces).
    rod_force: Shape,
    /// Rod, displacement control with the same path lengths as the energy model.
    rod_disp: Shape,
}

fn main() -> Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "target".into()));
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::empty();
    let literal = SolveRequest::new(MethodKind::Geometric).solver()?;
    let energy = SolveRequest::new(MethodKind::Energy).solver()?;
    let rod = |control: &str| {
        SolveRequest::new(MethodKind::Cosserat)
            .with_settings(Settings::new().with("control", control))
            .solver()
    };
    let (rod_force, rod_disp) = (rod("force")?, rod("displacement")?);
    let mut cases = vec![];
    for case in 1..=3 {
        let model = Model::from_file(root.join(format!("models/paper/case{case}.toml")))?;
        let (r, a) = (&model.robot, &model.actuation);
        cases.push(Case {
            literal: literal.solve(r, a, &scene, None)?,
            energy: energy.solve(r, a, &scene, None)?,
            rod_force: rod_force.solve(r, a, &scene, None)?,
            rod_disp: rod_disp.solve(r, a, &scene, None)?,
            model,
        });
    }
    let mm = |v: f64| v * 1000.0;

    println!("Tip positions (mm)\n");
    println!(
        "| case | literal geometric | energy | Cosserat (force) | Cosserat (displacement, path) |"
    );
    println!("|---|---|---|---|---|");
    let tip = |s: &Shape| {
        let t = s.tip() * 1000.0;
        format!("({:.3}, {:.3}, {:.3})", t.x, t.y, t.z)
    };
    for (k, c) in cases.iter().enumerate() {
        println!(
            "| {} | {} | {} | {} | {} |",
            k + 1,
            tip(&c.literal),
            tip(&c.energy),
            tip(&c.rod_force),
            tip(&c.rod_disp)
        );
    }

    println!("\nThe paper's comparison: literal geometric vs Cosserat rod with the paper's forces (mm)\n");
    println!("| case | RMS over disks | tip distance | the paper's RMS |");
    println!("|---|---|---|---|");
    for (k, c) in cases.iter().enumerate() {
        println!(
            "| {} | {:.2} | {:.2} | {:.2} |",
            k + 1,
            mm(c.literal.rms_distance(&c.rod_force).unwrap_or(f64::NAN)),
            mm(c.literal.tip_distance(&c.rod_force)),
            PAPER_RMS_MM[k]
        );
    }

    println!("\nSame displacement inputs: each model vs the rod driven by the same cable lengths (path)\n");
    println!("| case | literal RMS [mm] | energy RMS [mm] | energy / rod tensions [N] |");
    println!("|---|---|---|---|");
    for (k, c) in cases.iter().enumerate() {
        let tens: Vec<String> = c
            .energy
            .cables
            .iter()
            .zip(&c.rod_disp.cables)
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
            "| {} | {:.3} | {:.3} | {} |",
            k + 1,
            mm(c.literal.rms_distance(&c.rod_disp).unwrap_or(f64::NAN)),
            mm(c.energy.rms_distance(&c.rod_disp).unwrap_or(f64::NAN)),
            tens.join(", ")
        );
    }

    println!("\nZero terms of the literal method, sections 1..n:");
    for (k, c) in cases.iter().enumerate() {
        let zeros: Vec<String> = c
            .literal
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

    let rows: Vec<Row> = cases
        .iter()
        .enumerate()
        .map(|(k, c)| Row {
            title: format!("Case {}", ["I", "II", "III"][k]),
            robot: &c.model.robot,
            // The rod driven by the same shortenings first and widest: energy lies on it
            // (within 0.09 mm), drawn narrower on top.
            shapes: vec![
                (
                    &c.rod_disp,
                    "cosserat — shortening (same path lengths)".into(),
                ),
                (&c.energy, "energy — shortening".into()),
                (&c.literal, "literal geometric — shortening".into()),
                (&c.rod_force, "cosserat — the paper's tensions".into()),
            ],
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
