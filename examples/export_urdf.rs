//! Solve the paper's case 1 (or another model file, with its obstacles) with the geometric
//! method and export it as URDF.
//!
//! ```text
//! cargo run --release --example export_urdf [OUT_DIR] [MODEL]
//! # defaults: target/urdf, models/paper/case1.toml
//! ```
//!
//! Writes `paper-case-1.urdf` (articulated chain), `.srdf` (group `backbone` and the solved
//! `group_state`), `.joints.json` (the same joint values) and `paper-case-1-fixed.urdf` (a
//! snapshot with fixed joints), all with disks, backbone and cables as cylinders.

use anyhow::{Context, Result};
use ccrkit::export::{export_urdf, UrdfMode, UrdfOptions};
use ccrkit::prelude::*;
use std::path::{Path, PathBuf};

fn main() -> Result<()> {
    let out_dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target/urdf"));
    let model_path = std::env::args()
        .nth(2)
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("models/paper/case1.toml"));
    let model = Model::from_file(&model_path)?;
    // The one solve path: the model's own obstacles included, the shape checked.
    let shape = SolveRequest::new(MethodKind::Geometric).run(&model)?.shape;
    let tip = shape.tip() * 1000.0;
    println!(
        "{}: solved with {}, tip [{:.3}, {:.3}, {:.3}] mm",
        model.robot.name, shape.method, tip.x, tip.y, tip.z
    );

    let name = &model.robot.name;
    let articulated = out_dir.join(format!("{name}.urdf"));
    let fixed = out_dir.join(format!("{name}-fixed.urdf"));
    for (mode, path) in [
        (UrdfMode::Articulated, &articulated),
        (UrdfMode::Fixed, &fixed),
    ] {
        let opts = UrdfOptions {
            mode,
            cables: true,
            name: None,
        };
        let export = export_urdf(&shape, &model.robot, &opts)?;
        for p in export
            .write_files(path)
            .with_context(|| format!("writing {mode} export"))?
        {
            println!("wrote {}", p.display());
        }
    }

    let (a, f) = (articulated.display(), fixed.display());
    let j = articulated.with_extension("joints.json");
    let j = j.display();
    println!();
    println!("View it:");
    println!("  the fixed snapshot (the solved shape as it is):");
    println!("    urdf-viz {f}          # cargo install urdf-viz");
    println!("    yourdfpy {f}          # pip install yourdfpy");
    println!("  the articulated chain at its solved joint values (at zero it is straight):");
    println!(
        "    python3 -c \"import json, yourdfpy; r = yourdfpy.URDF.load('{a}'); \
         r.update_cfg({{v['name']: v['value'] for v in json.load(open('{j}'))['joints']}}); r.show()\""
    );
    println!(
        "  RViz / MoveIt: URDF as robot_description, the .srdf as robot_description_semantic;"
    );
    println!("    set group `backbone` to the named state `{name}`.");
    println!("  check it: check_urdf {a}          # apt-get install liburdfdom-tools");
    Ok(())
}
