//! `ccrkit`: the command line, a thin shell over the library.

use anyhow::{Context, Result};
use ccrkit::method::{method_by_name, METHOD_NAMES};
use ccrkit::{plot, Model, Scene, Shape};
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "ccrkit",
    version,
    about = "Shapes of cable-driven continuum robots"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve one model file and print the tip, per-section residuals and time.
    Solve {
        /// Model file (TOML).
        file: PathBuf,
        /// Method: see `ccrkit methods`.
        #[arg(long, default_value = "geometric")]
        method: String,
        /// Write the shape as JSON to this path (`-` for standard output).
        #[arg(long)]
        json: Option<String>,
        /// Write a three-view figure (.svg or .png).
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Solve N times and report the median time.
        #[arg(long, default_value_t = 1)]
        repeat: usize,
    },
    /// List the available methods.
    Methods,
    /// Solve one model file and export the shape for other tools.
    #[command(subcommand)]
    Export(ExportCommand),
}

#[derive(Subcommand)]
enum ExportCommand {
    /// URDF (+ SRDF and joint values as JSON in articulated mode), in metres and radians.
    Urdf {
        /// Model file (TOML).
        file: PathBuf,
        /// Method: see `ccrkit methods`.
        #[arg(long, default_value = "geometric")]
        method: String,
        /// `fixed`: one link per disk at the solved poses (a snapshot for collision checking);
        /// `articulated`: six joints per section, the shape as joint values (SRDF + JSON).
        #[arg(long, default_value = "articulated")]
        mode: String,
        /// Also draw the cables as thin cylinders between holes.
        #[arg(long)]
        cables: bool,
        /// Output URDF path; the SRDF and `.joints.json` are written next to it.
        #[arg(long)]
        out: PathBuf,
    },
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    match Cli::parse().command {
        Command::Methods => {
            for m in METHOD_NAMES {
                println!("{m}");
            }
            Ok(())
        }
        Command::Export(ExportCommand::Urdf {
            file,
            method,
            mode,
            cables,
            out,
        }) => {
            let model = Model::from_file(&file)?;
            let m = method_by_name(&method)?;
            let shape = m.solve(&model.robot, &model.actuation, &Scene::empty(), None)?;
            let opts = ccrkit::export::UrdfOptions {
                mode: mode.parse()?,
                cables,
                name: None,
            };
            let export = ccrkit::export::export_urdf(&shape, &model.robot, &opts)?;
            for p in export.write_files(&out)? {
                eprintln!("wrote {}", p.display());
            }
            Ok(())
        }
        Command::Solve {
            file,
            method,
            json,
            plot: plot_path,
            repeat,
        } => {
            let model = Model::from_file(&file)?;
            let m = method_by_name(&method)?;
            let scene = Scene::empty();
            let (shape, median) = solve_timed(&*m, &model, &scene, repeat.max(1))?;
            let quiet = json.as_deref() == Some("-");
            if !quiet {
                print_summary(&model, &shape, median, repeat.max(1));
            }
            if let Some(j) = json {
                let text = shape.to_json_string();
                if j == "-" {
                    println!("{text}");
                } else {
                    std::fs::write(&j, text).with_context(|| format!("writing {j}"))?;
                    eprintln!("wrote {j}");
                }
            }
            if let Some(p) = plot_path {
                plot::plot_shape(&shape, &model.robot, &p)?;
                if !quiet {
                    eprintln!("wrote {}", p.display());
                }
            }
            Ok(())
        }
    }
}

/// Solve `repeat` times; the shape's reported time is the median.
fn solve_timed(
    m: &dyn ccrkit::Method,
    model: &Model,
    scene: &Scene,
    repeat: usize,
) -> Result<(Shape, f64)> {
    let mut times = Vec::with_capacity(repeat);
    let mut shape = None;
    for _ in 0..repeat {
        let t = Instant::now();
        let s = m.solve(&model.robot, &model.actuation, scene, None)?;
        times.push(t.elapsed().as_secs_f64());
        shape = Some(s);
    }
    times.sort_by(f64::total_cmp);
    let median = times[times.len() / 2];
    let mut shape = shape.context("no solve ran")?;
    shape.report.solve_time_s = median;
    Ok((shape, median))
}

fn print_summary(model: &Model, shape: &Shape, median: f64, repeat: usize) {
    let tip = shape.tip() * 1000.0;
    println!("model   {}", model.robot.name);
    println!("method  {}", shape.method);
    println!("tip     [{:.3}, {:.3}, {:.3}] mm", tip.x, tip.y, tip.z);
    for s in &shape.report.sections {
        println!(
            "section {:>2}: residual {:.1e} m, {:>3} iterations, zero terms [{}]{}",
            s.section,
            s.residual,
            s.iterations,
            s.zero_terms.join(", "),
            if s.slack.is_empty() {
                String::new()
            } else {
                format!(", slack [{}]", s.slack.join(", "))
            }
        );
    }
    for c in &shape.cables {
        if let Some(t) = c.tension {
            println!(
                "cable {}: tension {:.4} N{}",
                c.name,
                t,
                if c.slack { " (slack)" } else { "" }
            );
        }
    }
    println!(
        "residual {:.2e}, iterations {}, time {:.1} µs (median of {repeat})",
        shape.report.residual,
        shape.report.iterations,
        median * 1e6
    );
}
