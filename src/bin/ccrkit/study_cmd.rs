//! `ccrkit study …`: the studies' command-line arguments and their console summaries.

use super::create_dir;
use anyhow::{Context, Result};
use ccrkit::method::MethodKind;
use ccrkit::output::RunFiles;
use ccrkit::study::{self, figures};
use ccrkit::Model;
use clap::{Args, Subcommand};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Subcommand)]
pub(crate) enum StudyCommand {
    /// Median solve time and error against a converged Cosserat reference, for every method
    /// and resolution setting: DIR/speed_accuracy.csv, .svg, .png.
    SpeedAccuracy(SpeedAccuracyArgs),
    /// Converged/failed map over the inputs of the first two driven cables, per method, cold and
    /// with continuation: DIR/stability.csv and DIR/stability_METHOD.{svg,png}.
    Stability(StabilityArgs),
    /// Sample the driven cables' inputs (Halton), solve in parallel, write the tip cloud:
    /// DIR/workspace.csv (or workspace_shard_K_of_N.csv) and DIR/workspace.{svg,png}.
    Workspace(WorkspaceArgs),
    /// Join workspace shards into one CSV sorted by sample index.
    Merge(MergeArgs),
    /// How often `--method auto` keeps its tolerance on seeded random robots, how often its
    /// estimate bounds the true error, and its cost against the hindsight-cheapest model.
    Auto(AutoArgs),
}

#[derive(Args)]
pub(crate) struct AutoArgs {
    /// Random robots (seeds FIRST..FIRST+N).
    #[arg(long, default_value_t = 200)]
    robots: u64,
    /// The first seed.
    #[arg(long, default_value_t = 0)]
    first_seed: u64,
    /// Tolerances \[m\], comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [1e-4, 1e-3])]
    tolerance: Vec<f64>,
    /// Timed runs per solve (median).
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Write DIR/auto.csv (one row per robot and tolerance).
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(Args)]
pub(crate) struct SpeedAccuracyArgs {
    /// Model file (TOML).
    file: PathBuf,
    /// Output folder.
    #[arg(long)]
    out: PathBuf,
    /// Solves per setting (median time).
    #[arg(long, default_value_t = 5)]
    repeats: usize,
    /// Only these methods (comma-separated; default: all, and `auto` at 1, 0.1 and 0.01 mm).
    #[arg(long, value_delimiter = ',')]
    methods: Vec<String>,
}

#[derive(Args)]
pub(crate) struct StabilityArgs {
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
}

#[derive(Args)]
pub(crate) struct WorkspaceArgs {
    /// Model file (TOML).
    file: PathBuf,
    /// Output folder.
    #[arg(long)]
    out: PathBuf,
    /// Samples in the whole sweep.
    #[arg(long, default_value_t = 1000)]
    samples: usize,
    /// Method: see `ccrkit methods`.
    #[arg(long, default_value_t = MethodKind::DEFAULT.name().to_string())]
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
}

#[derive(Args)]
pub(crate) struct MergeArgs {
    /// Output CSV.
    out: PathBuf,
    /// Shard CSVs.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
}

/// The study's model loaded for a run writing `names` into the folder `out`, its files checked
/// before any work as every command's are (`ccrkit::output::RunFiles`): the folder and each file
/// it will hold are outputs, the model file and the files it names (its scene file, meshes)
/// inputs, so a study never writes its CSV or figures over one of them (by path, `..`, a link
/// to the folder or a hard link); then the folder is created.
fn load_for(file: &Path, out: &Path, names: &[String]) -> Result<Model> {
    let mut run = crate::check_files(&[("model file", Some(file))], &[])?;
    claim(&mut run, out, names)?;
    let model = Model::from_file(file)?;
    crate::check_read(&mut run, &model, None)?;
    create_dir(out)?;
    Ok(model)
}

/// Claim the study folder `out` and the files `names` in it as outputs of `run`.
fn claim(run: &mut RunFiles, out: &Path, names: &[String]) -> Result<()> {
    run.output("--out folder", out)?;
    for n in names {
        run.output(&format!("study's {n}"), &out.join(n))?;
    }
    Ok(())
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
        study::all_method_names()
    } else {
        m
    }
}

/// Runs one study subcommand.
pub(crate) fn run(cmd: StudyCommand) -> Result<()> {
    match cmd {
        StudyCommand::SpeedAccuracy(a) => speed_accuracy(a),
        StudyCommand::Stability(a) => stability(a),
        StudyCommand::Workspace(a) => workspace(a),
        StudyCommand::Merge(a) => merge(a),
        StudyCommand::Auto(a) => auto(a),
    }
}

/// `ccrkit study auto`: how often auto's answers keep their tolerance.
fn auto(a: AutoArgs) -> Result<()> {
    let opts = study::AutoStudyOptions {
        robots: a.robots,
        first_seed: a.first_seed,
        tolerances: a.tolerance,
        repeats: a.repeats,
        progress: crate::progress::handle(),
    };
    if let Some(out) = &a.out {
        // No input to clobber; the folder and its file still claimed alike.
        claim(&mut RunFiles::new(), out, &["auto.csv".to_string()])?;
    }
    let rows = study::auto_study(&opts)?;
    if let Some(out) = &a.out {
        create_dir(out)?;
        let path = out.join("auto.csv");
        study::write_text(&path, &study::auto_study_csv(&rows))?;
        eprintln!("wrote {}", path.display());
    }
    println!(
        "{:>12} {:>8} {:>16} {:>18} {:>22}",
        "tolerance", "answers", "true error ≤ T", "estimate ≥ error", "cost / hindsight (med)"
    );
    for s in study::summarize(&rows) {
        // No answer with a hindsight rung (none met the tolerance in truth): no ratio.
        let ratio = if s.median_cost_ratio.is_finite() {
            format!("{:.2}×", s.median_cost_ratio)
        } else {
            "—".to_string()
        };
        println!(
            "{:>12} {:>8} {:>14.1} % {:>16.1} % {:>22}",
            ccrkit::method::auto::mm(s.tolerance),
            s.answers,
            100.0 * s.within,
            100.0 * s.bounded,
            ratio
        );
    }
    Ok(())
}

/// `ccrkit study speed-accuracy`: the speed–accuracy study and its table.
fn speed_accuracy(a: SpeedAccuracyArgs) -> Result<()> {
    let SpeedAccuracyArgs {
        file,
        out,
        repeats,
        methods,
    } = a;
    let names: Vec<String> = ["csv", "svg", "png"]
        .iter()
        .map(|e| format!("speed_accuracy.{e}"))
        .collect();
    let model = load_for(&file, &out, &names)?;
    let opts = study::SpeedAccuracyOptions {
        repeats,
        methods: if methods.is_empty() {
            study::SpeedAccuracyOptions::default().methods
        } else {
            methods
        },
        progress: crate::progress::handle(),
    };
    let rows = study::speed_accuracy(&model, &opts)?;
    let front = study::speed_accuracy_front(&rows);
    println!(
        "{:<20} {:<20} {:<13} {:>12} {:>13} {:>13} {:>6}",
        "method", "setting", "input", "time [ms]", "tip err [m]", "rms err [m]", "pareto"
    );
    for (r, f) in rows.iter().zip(&front) {
        if r.status.is_ok() {
            println!(
                "{:<20} {:<20} {:<13} {:>12.4} {:>13.3e} {:>13.3e} {:>6}",
                r.method,
                r.setting,
                r.reference,
                r.median_time_s * 1e3,
                r.tip_error_m,
                r.rms_error_m,
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
        figures::speed_accuracy_figure(&rows, &title, &out.join(format!("speed_accuracy.{ext}")))?;
    }
    eprintln!("wrote {} (+ .svg, .png)", csv.display());
    Ok(())
}

/// `ccrkit study stability`: the stability maps and their summary.
fn stability(a: StabilityArgs) -> Result<()> {
    let StabilityArgs {
        file,
        out,
        grid,
        max_percent,
        tension_factor,
        input,
        methods,
    } = a;
    let methods = methods_or_all(methods);
    let mut names = vec!["stability.csv".to_string()];
    for m in &methods {
        names.extend(["svg", "png"].map(|e| format!("stability_{m}.{e}")));
    }
    let model = load_for(&file, &out, &names)?;
    let opts = study::StabilityOptions {
        grid,
        max_fraction: max_percent / 100.0,
        tension_factor,
        input: parse_input(&input)?,
        methods,
        progress: crate::progress::handle(),
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

/// `ccrkit study workspace`: the workspace sweep (or one shard of it) and its throughput.
fn workspace(a: WorkspaceArgs) -> Result<()> {
    let WorkspaceArgs {
        file,
        out,
        samples,
        method,
        shard,
        max_percent,
        tension_factor,
        input,
        chunk,
    } = a;
    let shard: Option<study::Shard> = shard.map(|s| s.parse()).transpose()?;
    let stem = match shard {
        Some(s) => format!("workspace_shard_{}_of_{}", s.index, s.count),
        None => "workspace".to_string(),
    };
    let names = ["csv", "svg", "png"].map(|e| format!("{stem}.{e}"));
    let model = load_for(&file, &out, &names)?;
    let opts = study::WorkspaceOptions {
        samples,
        method,
        input: parse_input(&input)?,
        max_fraction: max_percent / 100.0,
        tension_factor,
        shard,
        chunk,
        progress: crate::progress::handle(),
    };
    let ws = study::workspace(&model, &opts)?;
    let csv = out.join(format!("{stem}.csv"));
    study::write_text(&csv, &study::workspace_csv(&ws))?;
    let ok = ws.samples.iter().filter(|s| s.status.is_ok()).count();
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

/// `ccrkit study merge`: workspace shards joined into one CSV.
fn merge(a: MergeArgs) -> Result<()> {
    let MergeArgs { out, inputs } = a;
    let ins: Vec<(&str, Option<&std::path::Path>)> = inputs
        .iter()
        .map(|p| ("input CSV", Some(p.as_path())))
        .collect();
    let _ = crate::check_files(&ins, &[("--out file", Some(&out))])?;
    let texts = inputs
        .iter()
        .map(|p| {
            // Capped: a device or a huge file ends in a named error, not a hang.
            ccrkit::model::read::read_text(p, "study CSV")
                .with_context(|| format!("reading {}", p.display()))
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

fn print_stability_summary(st: &study::Stability) {
    for s in study::stability_summary(st) {
        println!("{}", s.line(&st.cables));
    }
}
