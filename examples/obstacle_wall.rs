//! The paper's case-1 robot pressing against a wall (`models/scenes/wall.toml`): solve with the
//! obstacle-aware geometric method in `--steps`-style continuation, print the contacts, and
//! draw shape, wall and contact points to `target/obstacle_wall.{png,svg}` (or OUT_DIR).
//!
//! `cargo run --release --example obstacle_wall [OUT_DIR]`

use anyhow::Result;
use ccrkit::method::solve_stepped;
use ccrkit::plot::plot_scene;
use ccrkit::{method_by_name, Model, Scene};
use std::path::PathBuf;

fn main() -> Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "target".into()));
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model = Model::from_file(root.join("models/paper/case1.toml"))?;
    let scene = Scene::from_file(root.join("models/scenes/wall.toml"))?;
    let method = method_by_name("geometric")?;
    let free = method.solve(&model.robot, &model.actuation, &Scene::empty(), None)?;
    // Four steps: each warm start is close enough that no Newton step jumps through the wall.
    let shape = solve_stepped(&*method, &model.robot, &model.actuation, &scene, 4)?;
    let (f, t) = (free.tip() * 1e3, shape.tip() * 1e3);
    println!("free tip      [{:.3}, {:.3}, {:.3}] mm", f.x, f.y, f.z);
    println!("with the wall [{:.3}, {:.3}, {:.3}] mm", t.x, t.y, t.z);
    print_contacts(&shape.contacts);
    for ext in ["png", "svg"] {
        let p = out.join(format!("obstacle_wall.{ext}"));
        plot_scene(&shape, &model.robot, &scene, &p)?;
        println!("wrote {}", p.display());
    }
    Ok(())
}

fn print_contacts(contacts: &[ccrkit::shape::Contact]) {
    println!(
        "| obstacle | feature | disk/section | point on robot [mm] | distance [m] | multiplier |"
    );
    println!("|---|---|---|---|---|---|");
    for c in contacts {
        let p = c.point_robot.map(|x| x * 1e3);
        println!(
            "| {} | {} | {} | [{:.3}, {:.3}, {:.3}] | {:.2e} | {:.4} |",
            c.obstacle,
            c.feature,
            c.disk.or(c.section).unwrap_or(0),
            p[0],
            p[1],
            p[2],
            c.distance,
            c.multiplier
        );
    }
}
