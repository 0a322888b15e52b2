//! `ccrkit plan`: a clear path of actuations to a tip or an actuation
//! ([`ccrkit::plan::plan`], on a loaded [`ccrkit::plan::roadmap::Roadmap`] when one is given).

use super::reach::{vec3, write_json, InverseArgs};
use anyhow::{bail, Result};
use ccrkit::plan::roadmap::Roadmap;
use ccrkit::plan::{plan, read_actuation_file, Goal, Plan, PlanOptions};
use ccrkit::Model;
use std::path::PathBuf;

/// `ccrkit plan` arguments.
#[derive(clap::Args)]
pub(crate) struct PlanArgs {
    /// Model file (TOML); its `[limits]` bound the actuations.
    file: PathBuf,
    #[command(flatten)]
    inverse: InverseArgs,
    /// Goal: a tip position X,Y,Z \[m\] (reached with least effort first).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    to_tip: Vec<f64>,
    /// Goal: an actuation file (`"actuation": [{"cable", "shorten"}]`, as `reach --json`
    /// writes; each entry's `tension` \[N\] when the method is driven by tension).
    #[arg(long)]
    to_actuation: Option<PathBuf>,
    /// Start: an actuation file (default: the model file's shortenings, or its tensions when
    /// the method is driven by tension; 0 where none).
    #[arg(long)]
    from_actuation: Option<PathBuf>,
    /// Answer from this roadmap (`ccrkit roadmap build`) instead of a new search.
    #[arg(long)]
    roadmap: Option<PathBuf>,
    /// Seed of every random choice.
    #[arg(long, default_value_t = PlanOptions::default().seed)]
    seed: u64,
    /// Samples before giving up.
    #[arg(long, default_value_t = PlanOptions::default().max_samples)]
    max_samples: usize,
    /// Write the plan as JSON (`-` for standard output).
    #[arg(long)]
    json: Option<String>,
    /// Write the waypoints as joint values of the articulated URDF export (CSV).
    #[arg(long)]
    trajectory: Option<PathBuf>,
}

pub(crate) fn run(a: PlanArgs) -> Result<()> {
    let mut run = super::check_files(
        &[
            ("model file", Some(&a.file)),
            ("--scene file", a.inverse.scene.as_deref()),
            ("--to-actuation file", a.to_actuation.as_deref()),
            ("--from-actuation file", a.from_actuation.as_deref()),
            ("--roadmap file", a.roadmap.as_deref()),
        ],
        &[
            ("--json file", a.json.as_deref().map(std::path::Path::new)),
            ("--trajectory file", a.trajectory.as_deref()),
        ],
    )?;
    let model = Model::from_file(&a.file)?;
    let request = a.inverse.request(&model)?;
    super::check_read(&mut run, &model, request.extra_scene.as_ref())?;
    // The space the actuation files are read in: refused by name when made for another robot
    // or space; a file without `made_for` is read by cable name, with a warning.
    let space = ccrkit::reach::Space::new(&model, &request, false)?;
    let read_actuation = |p: &std::path::Path| -> Result<Vec<f64>> {
        let file = read_actuation_file(p, &model, &space)?;
        if let Some(w) = file.warning(p) {
            eprintln!("warning: {w}");
        }
        Ok(file.point)
    };
    let goal = match (a.to_tip.is_empty(), &a.to_actuation) {
        (false, None) => Goal::Tip(vec3("to-tip", &a.to_tip)?),
        (true, Some(p)) => Goal::Actuation(read_actuation(p)?),
        _ => bail!("give exactly one goal: --to-tip X,Y,Z or --to-actuation FILE"),
    };
    let start = a
        .from_actuation
        .as_ref()
        .map(|p| read_actuation(p))
        .transpose()?;
    let opts = PlanOptions {
        seed: a.seed,
        margin: a.inverse.margin,
        max_samples: a.max_samples,
        ..PlanOptions::default()
    };
    let roadmap = a.roadmap.as_deref().map(Roadmap::load).transpose()?;
    let p: Plan = plan(&model, &request, start, &goal, &opts, roadmap.as_ref())?;
    let quiet = a.json.as_deref() == Some("-");
    if let Some(j) = &a.json {
        write_json(j, &serde_json::to_string_pretty(&p.to_json())?)?;
    }
    if let Some(t) = &a.trajectory {
        let csv = p.trajectory_csv(&model)?;
        super::write_out(t, &csv)?;
        if !quiet {
            eprintln!("wrote {}", t.display());
        }
    }
    if !quiet {
        let s = &p.stats;
        // Without obstacles both clearances are unbounded (`+∞`): said in words, not `inf`.
        let clearance = if p.min_clearance_m.is_finite() {
            format!(
                "clearance ≥ {:.3} mm measured, {} (margin {} mm)",
                p.min_clearance_m * 1e3,
                if p.certified_clearance_m.is_finite() {
                    format!("≥ {:.3} mm certified", p.certified_clearance_m * 1e3)
                } else {
                    "no edge to certify".into()
                },
                p.margin_m * 1e3
            )
        } else {
            "no obstacles to keep clear of".into()
        };
        println!(
            "{}: {} waypoints, {clearance}",
            s.planner,
            p.waypoints.len(),
        );
        println!(
            "{} samples, {} tree nodes, {} solves, {} edges checked ({} refused), {} shortcut \
             waypoints, length {:.3} → {:.3} mm, {:.1} ms",
            s.samples,
            s.tree_nodes,
            s.checks.solves,
            s.checks.edges_checked,
            s.checks.edges_rejected,
            s.shortcut_removed,
            s.length_before_m * 1e3,
            s.length_after_m * 1e3,
            s.time_s * 1e3
        );
    }
    Ok(())
}
