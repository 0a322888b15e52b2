//! `ccrkit`: the command line, a thin shell over the library.

use anyhow::{bail, Context, Result};
use ccrkit::method::cosserat::{Control, Cosserat, LengthMeasure};
use ccrkit::method::{method_by_name, Method, METHOD_NAMES};
use ccrkit::routing::RoutingFit;
use ccrkit::{plot, study, Model, Scene, Shape};
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
        /// A scene file with obstacles (added to the model file's own).
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Reach the actuation in K equal steps, each warm-started from the last.
        #[arg(long, default_value_t = 1)]
        steps: usize,
        /// Start from the shape another method finds (e.g. `geometric`, whose sections never
        /// cross an obstacle, for `energy` inside a tube); its time is not counted.
        #[arg(long, value_name = "METHOD")]
        warm_from: Option<String>,
        #[command(flatten)]
        rod: RodArgs,
    },
    /// Compare the geometric method with the Cosserat rod (force control, as the paper did;
    /// also displacement control with the geometric method's chord lengths).
    Compare {
        /// Model file (TOML).
        file: PathBuf,
        #[command(flatten)]
        rod: RodArgs,
    },
    /// List the available methods.
    Methods,
    /// Solve one model file and export the shape for other tools.
    #[command(subcommand)]
    Export(ExportCommand),
    /// Studies: speed against accuracy, stability maps, workspace sweeps.
    #[command(subcommand)]
    Study(StudyCommand),
}

#[derive(Subcommand)]
enum StudyCommand {
    /// Median solve time and error against a converged Cosserat reference, for every method
    /// and resolution setting: DIR/speed_accuracy.csv, .svg, .png.
    SpeedAccuracy {
        /// Model file (TOML).
        file: PathBuf,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
        /// Solves per setting (median time).
        #[arg(long, default_value_t = 5)]
        repeats: usize,
        /// Only these methods (comma-separated; default: all).
        #[arg(long, value_delimiter = ',')]
        methods: Vec<String>,
    },
    /// Converged/failed map over the inputs of the first two driven cables, per method, cold and
    /// with continuation: DIR/stability.csv and DIR/stability_METHOD.{svg,png}.
    Stability {
        /// Model file (TOML).
        file: PathBuf,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
        /// Grid points per axis.
        #[arg(long, default_value_t = 40)]
        grid: usize,
        /// Largest shortening swept (percent of the cable length).
        #[arg(long, default_value_t = 18.0)]
        max_percent: f64,
        /// Largest tension swept, as a multiple of the file's.
        #[arg(long, default_value_t = 10.0)]
        tension_factor: f64,
        /// Input swept: `auto` (tension for the rods, shortening otherwise), `shortening`, `tension`.
        #[arg(long, default_value = "auto")]
        input: String,
        /// Only these methods (comma-separated; default: all).
        #[arg(long, value_delimiter = ',')]
        methods: Vec<String>,
    },
    /// Sample the driven cables' inputs (Halton), solve in parallel, write the tip cloud:
    /// DIR/workspace.csv (or workspace_shard_K_of_N.csv) and DIR/workspace.{svg,png}.
    Workspace {
        /// Model file (TOML).
        file: PathBuf,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
        /// Samples in the whole sweep.
        #[arg(long, default_value_t = 1000)]
        samples: usize,
        /// Method: see `ccrkit methods`.
        #[arg(long, default_value = "geometric")]
        method: String,
        /// Solve only this share, `k/N` (blocks of --chunk samples, block j to shard j % N).
        #[arg(long)]
        shard: Option<String>,
        /// Largest shortening sampled (percent).
        #[arg(long, default_value_t = 10.0)]
        max_percent: f64,
        /// Largest tension sampled, as a multiple of the file's.
        #[arg(long, default_value_t = 3.0)]
        tension_factor: f64,
        /// Input sampled: `auto`, `shortening`, `tension`.
        #[arg(long, default_value = "auto")]
        input: String,
        /// Samples per block (warm starts stay inside a block; keep it equal across shards).
        #[arg(long, default_value_t = 32)]
        chunk: usize,
    },
    /// Join workspace shards into one CSV sorted by sample index.
    Merge {
        /// Output CSV.
        out: PathBuf,
        /// Shard CSVs.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
    },
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

/// Settings of the rod methods (`cosserat`, `kirchhoff`); ignored by the others.
#[derive(clap::Args, Clone)]
struct RodArgs {
    /// Cable input used when a file gives both: `force` or `displacement`.
    #[arg(long, default_value = "force")]
    control: String,
    /// Cable routing fit: `spline` or `fourier8`.
    #[arg(long, default_value = "spline")]
    routing: String,
    /// Cable length measure under displacement control: `path` or `chord` (also read by
    /// `--method energy`; alias `--cable-length`).
    #[arg(long, visible_alias = "cable-length", default_value = "path")]
    length: String,
    /// RK4 steps per section before bend refinement (default: the library's, which keeps
    /// every paper case's tip within 0.01 mm of a converged run).
    #[arg(long = "rk4-steps")]
    rk4_steps: Option<usize>,
    /// Adaptive RK45 tolerance instead of fixed RK4 steps.
    #[arg(long)]
    adaptive: Option<f64>,
}

impl RodArgs {
    fn cosserat(&self, kirchhoff: bool) -> Result<Cosserat> {
        let base = if kirchhoff {
            Cosserat::kirchhoff()
        } else {
            Cosserat::full()
        };
        let control = match self.control.as_str() {
            "force" => Control::Force,
            "displacement" => Control::Displacement,
            o => anyhow::bail!("unknown --control `{o}` (force, displacement)"),
        };
        let routing = match self.routing.as_str() {
            "spline" => RoutingFit::Spline,
            "fourier8" => RoutingFit::Fourier8,
            o => anyhow::bail!("unknown --routing `{o}` (spline, fourier8)"),
        };
        let length = match self.length.as_str() {
            "path" => LengthMeasure::Path,
            "chord" => LengthMeasure::Chord,
            o => anyhow::bail!("unknown --length `{o}` (path, chord)"),
        };
        let rod = base
            .with_control(control)
            .with_routing(routing)
            .with_length(length)
            .with_adaptive(self.adaptive);
        Ok(match self.rk4_steps {
            Some(n) => rod.with_steps(n),
            None => rod,
        })
    }

    fn energy(&self) -> Result<ccrkit::method::energy::Energy> {
        use ccrkit::method::energy::{CableLength, Energy};
        let length = match self.length.as_str() {
            "path" => CableLength::Path,
            "chord" => CableLength::Chord,
            o => anyhow::bail!("unknown --cable-length `{o}` (path, chord)"),
        };
        let routing = match self.routing.as_str() {
            "spline" => RoutingFit::Spline,
            "fourier8" => RoutingFit::Fourier8,
            o => anyhow::bail!("unknown --routing `{o}` (spline, fourier8)"),
        };
        Ok(Energy::default()
            .with_cable_length(length)
            .with_routing(routing))
    }

    fn method(&self, name: &str) -> Result<Box<dyn ccrkit::Method>> {
        Ok(match name {
            "cosserat" => Box::new(self.cosserat(false)?),
            "kirchhoff" => Box::new(self.cosserat(true)?),
            "energy" => Box::new(self.energy()?),
            other => method_by_name(other)?,
        })
    }
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    match Cli::parse().command {
        Command::Study(cmd) => study(cmd),
        Command::Compare { file, rod } => compare(&file, &rod),
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
            scene,
            steps,
            warm_from,
            rod,
        } => {
            let model = Model::from_file(&file)?;
            let m = rod.method(&method)?;
            let mut sc = model.scene.clone();
            if let Some(p) = scene {
                sc.merge(Scene::from_file(&p)?);
            }
            let warm = match warm_from {
                Some(name) if steps > 1 => {
                    bail!("--warm-from {name} and --steps {steps} cannot be combined")
                }
                Some(name) => {
                    let w = rod.method(&name)?;
                    Some(
                        w.solve(&model.robot, &model.actuation, &sc, None)
                            .with_context(|| format!("the --warm-from method `{name}`"))?,
                    )
                }
                None => None,
            };
            let (shape, median) =
                solve_timed(&*m, &model, &sc, repeat.max(1), steps, warm.as_ref())?;
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
                plot::plot_scene(&shape, &model.robot, &sc, &p)?;
                if !quiet {
                    eprintln!("wrote {}", p.display());
                }
            }
            Ok(())
        }
    }
}

fn compare(file: &PathBuf, rod: &RodArgs) -> Result<()> {
    let model = Model::from_file(file)?;
    let scene = Scene::empty();
    let geo = method_by_name("geometric")?.solve(&model.robot, &model.actuation, &scene, None)?;
    let force = rod.cosserat(false)?.with_control(Control::Force);
    let t = Instant::now();
    let cos = force.solve(&model.robot, &model.actuation, &scene, None)?;
    let tcos = t.elapsed().as_secs_f64();
    let mm = |v: f64| v * 1000.0;
    println!("model {}", model.robot.name);
    let tip = |s: &Shape| {
        let t = s.tip() * 1000.0;
        format!("[{:.3}, {:.3}, {:.3}] mm", t.x, t.y, t.z)
    };
    println!("geometric          tip {}", tip(&geo));
    println!(
        "cosserat (force)   tip {}  ({} iterations, {:.0} µs)",
        tip(&cos),
        cos.report.iterations,
        tcos * 1e6
    );
    let rms = geo.rms_distance(&cos).context("disk counts differ")?;
    println!(
        "geometric vs cosserat (force):  RMS {:.3} mm, tip distance {:.3} mm",
        mm(rms),
        mm(geo.tip_distance(&cos))
    );
    let disp = rod
        .cosserat(false)?
        .with_control(Control::Displacement)
        .with_length(LengthMeasure::Chord);
    match disp.solve(&model.robot, &model.actuation, &scene, Some(&cos)) {
        Ok(d) => {
            let tens: Vec<String> = d
                .cables
                .iter()
                .map(|c| {
                    format!(
                        "{} {:.4} N{}",
                        c.name,
                        c.tension.unwrap_or(0.0),
                        if c.slack { " (slack)" } else { "" }
                    )
                })
                .collect();
            println!(
                "cosserat (displacement, chord lengths as geometric) tip {}, tensions [{}]",
                tip(&d),
                tens.join(", ")
            );
            if let Some(r) = geo.rms_distance(&d) {
                println!(
                    "geometric vs cosserat (displacement): RMS {:.3} mm, tip distance {:.3} mm",
                    mm(r),
                    mm(geo.tip_distance(&d))
                );
            }
        }
        Err(e) => println!("cosserat (displacement): {e}"),
    }
    compare_energy(&model, rod, &geo, &cos)
}

/// The energy model next to the literal geometric method, each against the rod driven by the
/// same cable lengths (path or chord measure): an RMS table.
fn compare_energy(model: &Model, rod: &RodArgs, geo: &Shape, cos_force: &Shape) -> Result<()> {
    use ccrkit::method::energy::{CableLength, Energy};
    let scene = Scene::empty();
    let mm = |v: f64| v * 1000.0;
    println!();
    println!("| model | length | rod (displacement) | RMS [mm] | tip [mm] | tensions model / rod [N] | time [µs] |");
    println!("|---|---|---|---|---|---|---|");
    for (lm, cl, tag) in [
        (LengthMeasure::Path, CableLength::Path, "path"),
        (LengthMeasure::Chord, CableLength::Chord, "chord"),
    ] {
        let rod_d = rod
            .cosserat(false)?
            .with_control(Control::Displacement)
            .with_length(lm);
        let cos_d = match rod_d.solve(&model.robot, &model.actuation, &scene, Some(cos_force)) {
            Ok(s) => s,
            Err(e) => {
                println!("| rod | {tag} | error: {e} | | | | |");
                continue;
            }
        };
        let energy = Energy::default()
            .with_cable_length(cl)
            .with_routing(rod_d.routing);
        let t = Instant::now();
        let en = energy.solve(&model.robot, &model.actuation, &scene, None)?;
        let te = t.elapsed().as_secs_f64();
        let mut rows = vec![("energy", &en, Some(te))];
        if cl == CableLength::Chord {
            rows.push(("geometric", geo, Some(geo.report.solve_time_s)));
        }
        for (name, s, time) in rows {
            let rms = s.rms_distance(&cos_d).context("disk counts differ")?;
            let tens: Vec<String> = s
                .cables
                .iter()
                .zip(&cos_d.cables)
                .map(|(a, b)| match a.tension {
                    Some(t) => format!("{} {:.4}/{:.4}", a.name, t, b.tension.unwrap_or(0.0)),
                    None => format!("{} –/{:.4}", a.name, b.tension.unwrap_or(0.0)),
                })
                .collect();
            println!(
                "| {name} | {tag} | cosserat, {tag} lengths | {:.3} | {:.3} | {} | {} |",
                mm(rms),
                mm(s.tip_distance(&cos_d)),
                tens.join(", "),
                time.map(|t| format!("{:.0}", t * 1e6)).unwrap_or_default()
            );
        }
    }
    Ok(())
}

/// Solve `repeat` times; the shape's reported time is the median.
fn solve_timed(
    m: &dyn ccrkit::Method,
    model: &Model,
    scene: &Scene,
    repeat: usize,
    steps: usize,
    warm: Option<&Shape>,
) -> Result<(Shape, f64)> {
    let mut times = Vec::with_capacity(repeat);
    let mut shape = None;
    for _ in 0..repeat {
        let t = Instant::now();
        let s = match warm {
            Some(w) => m.solve(&model.robot, &model.actuation, scene, Some(w))?,
            None => ccrkit::method::solve_stepped(m, &model.robot, &model.actuation, scene, steps)?,
        };
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
    for c in &shape.contacts {
        let p = [
            c.point_robot[0] * 1e3,
            c.point_robot[1] * 1e3,
            c.point_robot[2] * 1e3,
        ];
        println!(
            "contact {} {}{}: at [{:.3}, {:.3}, {:.3}] mm, distance {:.2e} m, multiplier {:.4}",
            c.obstacle,
            c.feature,
            c.disk
                .map(|d| format!(" disk {d}"))
                .or(c.section.map(|s| format!(" section {s}")))
                .unwrap_or_default(),
            p[0],
            p[1],
            p[2],
            c.distance,
            c.multiplier
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

fn parse_input(s: &str) -> Result<Option<study::Input>> {
    Ok(match s {
        "auto" => None,
        "shortening" => Some(study::Input::Shortening),
        "tension" => Some(study::Input::Tension),
        o => anyhow::bail!("unknown --input `{o}` (auto, shortening, tension)"),
    })
}

fn methods_or_all(m: Vec<String>) -> Vec<String> {
    if m.is_empty() {
        METHOD_NAMES.iter().map(|s| s.to_string()).collect()
    } else {
        m
    }
}

fn create_dir(out: &PathBuf) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))
}

fn study(cmd: StudyCommand) -> Result<()> {
    use study::figures;
    match cmd {
        StudyCommand::SpeedAccuracy {
            file,
            out,
            repeats,
            methods,
        } => {
            let model = Model::from_file(&file)?;
            create_dir(&out)?;
            let opts = study::SpeedAccuracyOptions {
                repeats,
                methods: methods_or_all(methods),
            };
            let rows = study::speed_accuracy(&model, &opts)?;
            let front = study::speed_accuracy_front(&rows);
            println!(
                "{:<20} {:<20} {:>14} {:>14} {:>14} {:>6}",
                "method", "setting", "time [ms]", "tip err [mm]", "rms err [mm]", "pareto"
            );
            for (r, f) in rows.iter().zip(&front) {
                if r.status == "ok" {
                    println!(
                        "{:<20} {:<20} {:>14.4} {:>14.6} {:>14.6} {:>6}",
                        r.method,
                        r.setting,
                        r.median_time_s * 1e3,
                        r.tip_error_m * 1e3,
                        r.rms_error_m * 1e3,
                        if *f { "*" } else { "" }
                    );
                } else {
                    println!("{:<20} {:<20} {}", r.method, r.setting, r.status);
                }
            }
            let csv = out.join("speed_accuracy.csv");
            study::write_text(&csv, &study::speed_accuracy_csv(&rows))?;
            let title = format!("{}: speed against accuracy", model.robot.name);
            for ext in ["svg", "png"] {
                figures::speed_accuracy_figure(
                    &rows,
                    &title,
                    &out.join(format!("speed_accuracy.{ext}")),
                )?;
            }
            eprintln!("wrote {} (+ .svg, .png)", csv.display());
            Ok(())
        }
        StudyCommand::Stability {
            file,
            out,
            grid,
            max_percent,
            tension_factor,
            input,
            methods,
        } => {
            let model = Model::from_file(&file)?;
            create_dir(&out)?;
            let opts = study::StabilityOptions {
                grid,
                max_fraction: max_percent / 100.0,
                tension_factor,
                input: parse_input(&input)?,
                methods: methods_or_all(methods),
                progress: true,
            };
            let t = Instant::now();
            let st = study::stability(&model, &opts)?;
            let secs = t.elapsed().as_secs_f64();
            study::write_text(&out.join("stability.csv"), &study::stability_csv(&st))?;
            print_stability_summary(&st);
            for m in &opts.methods {
                for ext in ["svg", "png"] {
                    figures::stability_figure(&st, m, &out.join(format!("stability_{m}.{ext}")))?;
                }
            }
            eprintln!(
                "wrote {} and one map per method ({} solves in {secs:.1} s)",
                out.join("stability.csv").display(),
                st.points.len()
            );
            Ok(())
        }
        StudyCommand::Workspace {
            file,
            out,
            samples,
            method,
            shard,
            max_percent,
            tension_factor,
            input,
            chunk,
        } => {
            let model = Model::from_file(&file)?;
            create_dir(&out)?;
            let shard: Option<study::Shard> = shard.map(|s| s.parse()).transpose()?;
            let opts = study::WorkspaceOptions {
                samples,
                method,
                input: parse_input(&input)?,
                max_fraction: max_percent / 100.0,
                tension_factor,
                shard,
                chunk,
                progress: true,
            };
            let ws = study::workspace(&model, &opts)?;
            let stem = match shard {
                Some(s) => format!("workspace_shard_{}_of_{}", s.index, s.count),
                None => "workspace".to_string(),
            };
            let csv = out.join(format!("{stem}.csv"));
            study::write_text(&csv, &study::workspace_csv(&ws))?;
            let ok = ws.samples.iter().filter(|s| s.status == "ok").count();
            println!(
                "{}: {} samples ({} ok) in {:.2} s: {:.1} solves/s on {} threads",
                ws.method,
                ws.samples.len(),
                ok,
                ws.elapsed_s,
                ws.throughput(),
                rayon::current_num_threads()
            );
            let title = format!("{} — {}", model.robot.name, ws.method);
            for ext in ["svg", "png"] {
                figures::workspace_figure(&ws, &title, &out.join(format!("{stem}.{ext}")))?;
            }
            eprintln!("wrote {} (+ .svg, .png)", csv.display());
            Ok(())
        }
        StudyCommand::Merge { out, inputs } => {
            let texts = inputs
                .iter()
                .map(|p| {
                    std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))
                })
                .collect::<Result<Vec<_>>>()?;
            let merged = study::merge_csv(&texts)?;
            study::write_text(&out, &merged)?;
            eprintln!(
                "wrote {} ({} rows)",
                out.display(),
                merged.lines().count().saturating_sub(1)
            );
            Ok(())
        }
    }
}

fn print_stability_summary(st: &study::Stability) {
    for s in study::stability_summary(st) {
        let fails: Vec<String> = s.failures.iter().map(|(k, n)| format!("{k} {n}")).collect();
        println!(
            "{:<20} {:<13} {:>5}/{:<5} ok{}{}",
            s.method,
            if s.continuation {
                "continuation"
            } else {
                "cold"
            },
            s.ok,
            s.total,
            if fails.is_empty() {
                String::new()
            } else {
                format!(", failed: {}", fails.join(", "))
            },
            s.first_failure
                .map(|(a, b)| format!(", first failure at ({a:.4}, {b:.4})"))
                .unwrap_or_default()
        );
    }
}
