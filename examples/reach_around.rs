//! The paper's case-1 robot reaching next to the wall of `models/scenes/wall.toml`: the tip of
//! the most bent free shape 3 mm clear of the wall is reached keeping a 1 mm margin (least Σ shortening²),
//! and a target behind the wall's face — reachable only pressed on the wall — is refused
//! with the closest clear tip, then reached with contact allowed. Writes the figures to
//! OUT_DIR (default `target/reach_around`).
//!
//! `cargo run --release --example reach_around [OUT_DIR]`

use ccrkit::method::run::SolveRequest;
use ccrkit::method::MethodKind;
use ccrkit::plot::{plot_rows, Row};
use ccrkit::reach::{reach, ReachOptions, Space, Target};
use ccrkit::{Model, Scene};
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/reach_around".into()),
    );
    std::fs::create_dir_all(&out)?;
    let root = env!("CARGO_MANIFEST_DIR");
    let model = Model::from_file(format!("{root}/models/paper/case1.toml"))?;
    let wall = Scene::from_file(format!("{root}/models/scenes/wall.toml"))?;
    let req = SolveRequest::new(MethodKind::Energy).with_scene(Some(wall.clone()));
    let clear = ReachOptions {
        margin: Some(0.001),
        ..ReachOptions::default()
    };
    // The most bent free shape (cable A alone) still 3 mm clear of the wall: its tip is the
    // target.
    let free = Space::new(&model, &req, false)?;
    let mut near = None;
    for k in 1..=400 {
        let s = free.solve(&[k as f64 * 5e-5, 0.0], None)?;
        match free.clearance(&s) {
            Some(c) if c.distance >= 0.003 => near = Some(s.tip()),
            _ => break,
        }
    }
    let near = near.ok_or_else(|| anyhow::anyhow!("no free shape keeps 3 mm from the wall"))?;
    let a = reach(
        &model,
        &req,
        &Target {
            tip: near,
            tangent: None,
        },
        &clear,
    )?;
    println!(
        "near the wall: reached {}, tip error {:.2e} m, clearance {:.3} mm, A {:.3} mm, B {:.3} mm",
        a.reached,
        a.tip_error_m,
        a.min_clearance_m.unwrap_or(f64::NAN) * 1e3,
        a.u[0] * 1e3,
        a.u[1] * 1e3
    );
    // Behind the face: the tip of the robot pressed on the wall.
    let pressed = Space::new(&model, &req, true)?.solve_as_cli(&model, &[0.010, 0.0])?;
    let behind = Target {
        tip: pressed.tip(),
        tangent: None,
    };
    let b = reach(&model, &req, &behind, &clear)?;
    println!(
        "pressed tip, keeping clear: reached {}, closest tip {:.2} mm away ({})",
        b.reached,
        b.tip_error_m * 1e3,
        b.reason
    );
    let contact = ReachOptions {
        allow_contact: true,
        ..ReachOptions::default()
    };
    let c = reach(&model, &req, &behind, &contact)?;
    println!(
        "pressed tip, contact allowed: reached {}, tip error {:.2e} m, {} contact(s)",
        c.reached,
        c.tip_error_m,
        c.shape.contacts.len()
    );
    let rows = [
        Row {
            title: "target of a shape 3 mm from the wall, 1 mm margin".into(),
            robot: &model.robot,
            shapes: vec![(&a.shape, "reach (clear)".into())],
            scene: Some(&wall),
        },
        Row {
            title: "target only reachable pressed on the wall".into(),
            robot: &model.robot,
            shapes: vec![
                (&b.shape, "closest clear".into()),
                (&c.shape, "contact allowed".into()),
            ],
            scene: Some(&wall),
        },
    ];
    plot_rows(&rows, &out.join("reach_around.svg"))?;
    plot_rows(&rows, &out.join("reach_around.png"))?;
    ccrkit::output::write_file(
        out.join("reach_contact.json"),
        serde_json::to_string_pretty(&c.to_json())?,
    )?;
    println!(
        "wrote {}/{{reach_around.svg, reach_around.png, reach_contact.json}}",
        out.display()
    );
    Ok(())
}
