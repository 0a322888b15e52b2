//! `ccrkit`: the command line, a thin shell over the library.

use anyhow::{Context, Result};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::{plot, study, Model, Scene};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

mod anatomy;
mod calibrate;
mod plan;
mod predict;
mod progress;
mod reach;
mod roadmap;
mod study_cmd;
mod summary;
mod view;
use study_cmd::StudyCommand;

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
        #[command(flatten)]
        solve: SolveArgs,
        /// Write the shape as JSON to this path (`-` for standard output).
        #[arg(long)]
        json: Option<String>,
        /// Write a three-view figure (.svg or .png).
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Solve N times and report the median time.
        #[arg(long, default_value_t = 1)]
        repeat: usize,
        /// `unique`: solve the input again along other paths (a ramp from zero, an overshoot,
        /// each cable leading, the other model's answer) and say whether this answer is the
        /// only equilibrium found (a few extra solves; their count and time are printed).
        #[arg(long, value_enum)]
        check: Option<Check>,
    },
    /// Compare methods on one model: a table of tips and times, pairwise distances, and a
    /// flag where two methods driven by the same input disagree.
    Compare {
        /// Model file (TOML).
        file: PathBuf,
        /// Methods, comma-separated; each `NAME` or `NAME:SETTING=VALUE:...`
        /// (default: geometric, energy, cosserat:control=displacement, cosserat).
        #[arg(long, value_delimiter = ',')]
        methods: Vec<String>,
        /// A scene file with obstacles (added to the model file's own).
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Tip distance \[m\] beyond which two same-input methods are flagged as disagreeing.
        #[arg(long, default_value_t = study::compare::DISAGREE_TOL)]
        tolerance: f64,
        /// Write the solved shapes overlaid in three views (.svg or .png).
        #[arg(long)]
        plot: Option<PathBuf>,
        /// Write the comparison as JSON (rows, pairs, each pair's `disagree` flag and
        /// `any_disagreement`) to this path (`-` for standard output, the table then not printed).
        #[arg(long)]
        json: Option<String>,
    },
    /// List the available methods, their inputs, obstacle and load support, and settings.
    Methods,
    /// Solve one model file and export the shape for other tools.
    #[command(subcommand)]
    Export(ExportCommand),
    /// Studies: speed against accuracy, stability maps, workspace sweeps.
    #[command(subcommand)]
    Study(StudyCommand),
    /// Write one self-contained HTML page showing the robot in 3-D (methods overlaid, a plan's
    /// waypoints, a sweep's tips), to turn in any browser, offline.
    View(view::ViewArgs),
    /// The least-effort actuation within the limits that puts the tip on a target.
    Reach(reach::ReachArgs),
    /// A path of actuations to a tip or an actuation, clear of the obstacles.
    Plan(plan::PlanArgs),
    /// Generated anatomy: a seeded airway tree as one closed mesh.
    #[command(subcommand)]
    Anatomy(anatomy::AnatomyCommand),
    /// Roadmaps for repeated `plan` queries.
    #[command(subcommand)]
    Roadmap(roadmap::RoadmapCommand),
    /// Predict the measured tip for every row of a data CSV (in-process, warm-started, parallel).
    Predict(predict::PredictArgs),
    /// Fit a model's hardware parameters to measured tips (Levenberg–Marquardt).
    Calibrate(calibrate::CalibrateArgs),
}

/// A check of the answer after a solve.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
enum Check {
    /// Is it the only equilibrium found along other paths?
    Unique,
}

#[derive(Subcommand)]
enum ExportCommand {
    /// URDF (+ SRDF and joint values as JSON in articulated mode), in metres and radians.
    Urdf {
        /// Model file (TOML).
        file: PathBuf,
        #[command(flatten)]
        solve: SolveArgs,
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

/// What to solve and how: the method, its settings, obstacles, warm start, continuation. The
/// same for every subcommand that solves, through the library's one solve path.
#[derive(clap::Args, Clone)]
struct SolveArgs {
    /// Method: see `ccrkit methods` (`geometric` is the paper's literal section solver), or
    /// `auto`: the cheapest model and resolution whose estimated error is within `--tolerance`.
    #[arg(long, default_value_t = MethodArg::Named(MethodKind::DEFAULT), value_parser = parse_method_arg)]
    method: MethodArg,
    /// The tolerance of `--method auto`: the estimated tip distance from the converged rod the
    /// answer may have \[m\] (default 1e-4).
    #[arg(long)]
    tolerance: Option<f64>,
    /// A scene file with obstacles (added to the model file's own).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Reach the actuation in K equal steps, each warm-started from the last.
    #[arg(long, default_value_t = 1)]
    steps: usize,
    /// Start from the shape another method finds (e.g. `geometric`, whose sections never
    /// cross an obstacle, for `energy` inside a tube); its time is not counted.
    #[arg(long, value_name = "METHOD", value_parser = parse_method)]
    warm_from: Option<MethodKind>,
    /// Method setting NAME=VALUE (repeatable; `ccrkit methods` lists each method's).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    /// Input used where a cable gives both: `force` or `displacement` (setting `control`).
    #[arg(long)]
    control: Option<String>,
    /// Cable routing fit: `spline` or `fourier8` (setting `routing`).
    #[arg(long)]
    routing: Option<String>,
    /// Cable length measure: `path` or `chord` (setting `length`; alias `--cable-length`).
    #[arg(long, visible_alias = "cable-length")]
    length: Option<String>,
    /// RK4 steps per section before bend refinement (setting `rk4-steps`).
    #[arg(long = "rk4-steps")]
    rk4_steps: Option<String>,
    /// Adaptive RK45 tolerance instead of fixed RK4 steps (setting `adaptive`).
    #[arg(long)]
    adaptive: Option<String>,
    /// Estimate the answer's distance from the converged reference rod (one extra solve).
    #[arg(long)]
    estimate: bool,
}

fn parse_method(s: &str) -> Result<MethodKind, String> {
    s.parse::<MethodKind>().map_err(|e| e.to_string())
}

/// The tolerance of `--method auto` when none is given \[m\].
pub(crate) const AUTO_TOLERANCE: f64 = 1e-4;

/// A method by name, or `auto`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum MethodArg {
    /// A registered method.
    Named(MethodKind),
    /// The cheapest model and resolution within a tolerance.
    Auto,
}

impl std::fmt::Display for MethodArg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MethodArg::Named(k) => write!(f, "{k}"),
            MethodArg::Auto => f.write_str("auto"),
        }
    }
}

fn parse_method_arg(s: &str) -> Result<MethodArg, String> {
    if s.trim() == "auto" {
        Ok(MethodArg::Auto)
    } else {
        parse_method(s).map(MethodArg::Named)
    }
}

impl MethodArg {
    /// The request of this method (`auto` at `tolerance`, default [`AUTO_TOLERANCE`]); a
    /// tolerance without `auto` is refused by name.
    pub(crate) fn request(self, tolerance: Option<f64>) -> Result<SolveRequest> {
        match (self, tolerance) {
            (MethodArg::Auto, t) => Ok(SolveRequest::auto(t.unwrap_or(AUTO_TOLERANCE))),
            (MethodArg::Named(k), None) => Ok(SolveRequest::new(k)),
            (MethodArg::Named(k), Some(_)) => {
                anyhow::bail!("--tolerance is the tolerance of `--method auto`, not of {k}")
            }
        }
    }
}

impl SolveArgs {
    /// The settings given, named flags first, then `--set` in order.
    fn settings(&self) -> Result<Settings> {
        let mut s = Settings::new();
        for (name, v) in [
            ("control", &self.control),
            ("routing", &self.routing),
            ("length", &self.length),
            ("rk4-steps", &self.rk4_steps),
            ("adaptive", &self.adaptive),
        ] {
            if let Some(v) = v {
                s.push(name, v);
            }
        }
        for kv in &self.set {
            let (k, v) = Settings::parse_pair(kv)?;
            s.push(k, v);
        }
        Ok(s)
    }

    /// The request, checked before anything is solved.
    fn request(&self, repeat: usize) -> Result<SolveRequest> {
        let scene = self.scene.as_ref().map(Scene::from_file).transpose()?;
        let r = SolveRequest {
            settings: self.settings()?,
            extra_scene: scene,
            warm_from: self.warm_from,
            steps: self.steps,
            repeat,
            estimate: self.estimate,
            ..self.method.request(self.tolerance)?
        };
        if r.auto.is_none() {
            r.solver()?;
        }
        Ok(r)
    }
}

fn main() {
    restore_sigpipe();
    let result = run();
    // The grid cache's warnings (a refused cache file, one that could not be written).
    for note in ccrkit::model::field_cache::take_notes() {
        eprintln!("warning: {note}");
    }
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

/// `ccrkit methods | head -1` must end quietly when the reader closes the pipe, as Unix tools
/// do. Rust starts programs with SIGPIPE ignored, so every `println!` after the reader has gone
/// panics with "Broken pipe" (exit 101); the default action ends the process silently instead.
#[cfg(unix)]
fn restore_sigpipe() {
    // SAFETY: called first in `main`, before any thread exists; installing the default
    // disposition of one signal has no other effect on the process.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Other platforms have no SIGPIPE.
#[cfg(not(unix))]
fn restore_sigpipe() {}

fn run() -> Result<()> {
    match Cli::parse().command {
        Command::Study(cmd) => study_cmd::run(cmd),
        Command::View(args) => view::run(args),
        Command::Reach(a) => reach::run(a),
        Command::Plan(a) => plan::run(a),
        Command::Roadmap(c) => roadmap::run(c),
        Command::Anatomy(c) => anatomy::run(c),
        Command::Predict(a) => predict::run(a),
        Command::Calibrate(a) => calibrate::run(a),
        Command::Compare {
            file,
            methods,
            scene,
            tolerance,
            plot: plot_path,
            json,
        } => compare(
            &file,
            &methods,
            scene.as_ref(),
            tolerance,
            plot_path.as_ref(),
            json.as_deref(),
        ),
        Command::Methods => {
            print_methods();
            Ok(())
        }
        Command::Export(ExportCommand::Urdf {
            file,
            solve,
            mode,
            cables,
            out,
        }) => {
            let mode = mode.parse()?;
            let outs = ccrkit::export::UrdfExport::paths(mode, &out);
            let outs: Vec<(&str, Option<&Path>)> =
                outs.iter().map(|(r, p)| (*r, Some(p.as_path()))).collect();
            let mut run = check_files(
                &[
                    ("model file", Some(&file)),
                    ("--scene file", solve.scene.as_deref()),
                ],
                &outs,
            )?;
            let request = solve.request(1)?;
            let model = Model::from_file(&file)?;
            check_read(&mut run, &model, request.extra_scene.as_ref())?;
            let shape = request.run(&model)?.shape;
            let opts = ccrkit::export::UrdfOptions {
                mode,
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
            solve,
            json,
            plot: plot_path,
            repeat,
            check,
        } => {
            if let Some(p) = &plot_path {
                plot::check_path(p)?;
            }
            let mut run = check_files(
                &[
                    ("model file", Some(&file)),
                    ("--scene file", solve.scene.as_deref()),
                ],
                &[
                    ("--json file", json.as_deref().map(Path::new)),
                    ("--plot file", plot_path.as_deref()),
                ],
            )?;
            let request = solve
                .request(repeat)?
                .with_unique_check(matches!(check, Some(Check::Unique)));
            let model = Model::from_file(&file)?;
            check_read(&mut run, &model, request.extra_scene.as_ref())?;
            let bar = progress::spinner(&format!("solving with {}", solve.method));
            let solved = request.run(&model);
            bar.finish_and_clear();
            let solved = solved?;
            let (shape, median) = (&solved.shape, solved.median_time_s);
            let quiet = json.as_deref() == Some("-");
            if !quiet {
                summary::print_summary(&model, shape, median, repeat);
                if solved.merged_duplicates > 0 {
                    println!(
                        "scene   {} obstacles, {} within reach merged as exact duplicates (contacts name the first of each)",
                        solved.scene.obstacles.len(),
                        solved.merged_duplicates
                    );
                }
            }
            if let Some(j) = json {
                // Model name and driving input included (the library's `SolveRequest::json`).
                let text = serde_json::to_string_pretty(&request.json(&model, shape))?;
                if j == "-" {
                    println!("{text}");
                } else {
                    write_out(Path::new(&j), &text)?;
                    eprintln!("wrote {j}");
                }
            }
            if let Some(p) = plot_path {
                plot::plot_scene(shape, &model.robot, &solved.scene, &p)?;
                if !quiet {
                    eprintln!("wrote {}", p.display());
                }
            }
            Ok(())
        }
    }
}

fn print_methods() {
    for k in MethodKind::ALL {
        let i = k.info();
        let inputs: Vec<&str> = i.inputs.iter().map(|x| x.name()).collect();
        println!("{}", i.name);
        println!("    {}", i.summary);
        println!(
            "    inputs: {} (default {}); obstacles: {}; loads: gravity {}, tip force {}, tip moment {}",
            inputs.join(", "),
            i.default_input.name(),
            yes(i.obstacles),
            yes(i.loads.gravity),
            yes(i.loads.tip_force),
            yes(i.loads.tip_moment)
        );
        println!(
            "    cables inside the rod: {}; compliant cables: {}; capstan friction: {}; bending stiffening: {}",
            yes(i.tendons_inside),
            yes(i.cable_compliance),
            yes(i.capstan_friction),
            yes(i.bending_stiffening)
        );
        for s in i.settings {
            println!(
                "    --set {}=<{}>   default {}: {}",
                s.name, s.values, s.default, s.help
            );
        }
    }
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

fn compare(
    file: &PathBuf,
    methods: &[String],
    scene: Option<&PathBuf>,
    tolerance: f64,
    plot_path: Option<&PathBuf>,
    json: Option<&str>,
) -> Result<()> {
    if let Some(p) = plot_path {
        plot::check_path(p)?;
    }
    let mut run = check_files(
        &[
            ("model file", Some(file)),
            ("--scene file", scene.map(|p| p.as_path())),
        ],
        &[
            ("--plot file", plot_path.map(|p| p.as_path())),
            ("--json file", json.filter(|j| *j != "-").map(Path::new)),
        ],
    )?;
    let default = [
        "geometric",
        "energy",
        "cosserat:control=displacement",
        "cosserat",
    ];
    let entries: Vec<String> = if methods.is_empty() {
        default.iter().map(|s| s.to_string()).collect()
    } else {
        methods.to_vec()
    };
    let extra = scene.map(Scene::from_file).transpose()?;
    let requests = entries
        .iter()
        .map(|e| {
            let (kind, settings) = study::compare::parse_entry(e)?;
            Ok(SolveRequest::new(kind)
                .with_settings(settings)
                .with_scene(extra.clone()))
        })
        .collect::<Result<Vec<_>>>()?;
    let model = Model::from_file(file)?;
    check_read(&mut run, &model, extra.as_ref())?;
    let cmp = study::compare(&model, &requests, tolerance)?;
    match json {
        Some("-") => println!("{}", serde_json::to_string_pretty(&cmp.to_json())?),
        Some(path) => {
            print!("{cmp}");
            let text = serde_json::to_string_pretty(&cmp.to_json())?;
            write_out(Path::new(path), &text)?;
            eprintln!("wrote {path}");
        }
        None => print!("{cmp}"),
    }
    if let Some(p) = plot_path {
        let mut all = model.scene.clone();
        if let Some(x) = extra {
            all.merge(x);
        }
        let row = plot::Row {
            title: format!("{}: methods compared", model.robot.name),
            robot: &model.robot,
            shapes: cmp
                .rows
                .iter()
                .filter_map(|r| r.shape.as_ref().map(|s| (s, r.label.clone())))
                .collect(),
            scene: Some(&all),
        };
        plot::plot_rows(&[row], p)?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

/// The files of one run checked before any work: no output is one of the inputs, no two outputs
/// are one file (`ccrkit::output::RunFiles`). `None` entries are options not given. The files a
/// model or scene names (a scene file, meshes) are known once it is loaded: [`check_read`].
pub(crate) fn check_files(
    inputs: &[(&str, Option<&Path>)],
    outputs: &[(&str, Option<&Path>)],
) -> Result<ccrkit::output::RunFiles> {
    let mut run = ccrkit::output::RunFiles::new();
    for (role, p) in inputs {
        if let Some(p) = p {
            run.input(role, p);
        }
    }
    for (role, p) in outputs {
        if let Some(p) = p {
            run.output(role, p)?;
        }
    }
    Ok(run)
}

/// The files the loaded `model` and the `--scene` scene were read from (the scene file a model
/// names, every mesh file an obstacle names) checked against the outputs `run` claimed: an
/// output onto one of them is refused by name before anything is written.
pub(crate) fn check_read(
    run: &mut ccrkit::output::RunFiles,
    model: &Model,
    extra: Option<&Scene>,
) -> Result<()> {
    run.read(&model.files())?;
    if let Some(s) = extra {
        run.read(s.files())?;
    }
    Ok(())
}

/// Write an output file atomically, its folder created (`ccrkit::output::write_file`).
pub(crate) fn write_out(path: &Path, text: &str) -> Result<()> {
    Ok(ccrkit::output::write_file(path, text.as_bytes())?)
}

fn create_dir(out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))
}
