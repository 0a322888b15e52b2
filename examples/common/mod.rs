//! Shared by the obstacle examples: solve the paper's case-1 robot next to a scene file with
//! the obstacle-aware geometric method (in continuation steps) and with the whole-robot energy
//! model, print the free and obstructed tips and the contacts of both, and draw shape,
//! obstacles and contact points.

// Each example includes this module and uses the part it needs.
#![allow(dead_code)]

use anyhow::Result;
use ccrkit::plot::plot_scene;
use ccrkit::prelude::*;
use std::path::PathBuf;

/// Solve case 1 next to `models/scenes/{scene}.toml` in `steps` warm-started steps and write
/// `{out}/{name}.{png,svg}` (`out`: the first command-line argument, default `target`).
pub fn run(scene: &str, name: &str, what: &str, steps: usize) -> Result<()> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "target".into()));
    std::fs::create_dir_all(&out)?;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let model = Model::from_file(root.join("models/paper/case1.toml"))?;
    let scene = Scene::from_file(root.join(format!("models/scenes/{scene}.toml")))?;
    let geometric = SolveRequest::new(MethodKind::Geometric);
    let free = geometric
        .solver()?
        .solve(&model.robot, &model.actuation, &Scene::empty(), None)?;
    let mut stepped = geometric.clone();
    stepped.steps = steps;
    let shape = stepped
        .solver()?
        .solve(&model.robot, &model.actuation, &scene, None)?;
    let (f, t) = (free.tip() * 1e3, shape.tip() * 1e3);
    println!("geometric (the paper's section solver; multipliers in rad/m)");
    println!("free tip         [{:.3}, {:.3}, {:.3}] mm", f.x, f.y, f.z);
    println!("with the {what:<7} [{:.3}, {:.3}, {:.3}] mm", t.x, t.y, t.z);
    print_contacts(&shape.contacts);
    for ext in ["png", "svg"] {
        let p = out.join(format!("{name}.{ext}"));
        plot_scene(&shape, &model.robot, &scene, &p)?;
        println!("wrote {}", p.display());
    }
    // The whole-robot energy model: one solve, contact multipliers are reactions in newtons.
    let energy = SolveRequest::new(MethodKind::Energy).solver()?;
    let free = energy.solve(&model.robot, &model.actuation, &Scene::empty(), None)?;
    let shape = energy.solve(&model.robot, &model.actuation, &scene, None)?;
    let (f, t) = (free.tip() * 1e3, shape.tip() * 1e3);
    println!(
        "\nenergy (whole robot; multipliers are reactions in N; {} iterations, {:.2} ms)",
        shape.report.iterations,
        shape.report.solve_time_s * 1e3
    );
    println!("free tip         [{:.3}, {:.3}, {:.3}] mm", f.x, f.y, f.z);
    println!("with the {what:<7} [{:.3}, {:.3}, {:.3}] mm", t.x, t.y, t.z);
    print_contacts(&shape.contacts);
    for ext in ["png", "svg"] {
        let p = out.join(format!("{name}_energy.{ext}"));
        plot_scene(&shape, &model.robot, &scene, &p)?;
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The contacts as a Markdown table.
pub fn print_contacts(contacts: &[ccrkit::shape::Contact]) {
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
