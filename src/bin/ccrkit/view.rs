//! `ccrkit view`: one self-contained HTML page with the robot in 3-D (library:
//! `ccrkit::export::view`).

use anyhow::{Context, Result};
use ccrkit::export::view::{read_plan, read_sweep, View};
use ccrkit::method::run::SolveRequest;
use ccrkit::{study, Model, Scene};
use std::path::PathBuf;

/// Arguments of `ccrkit view`.
#[derive(clap::Args)]
pub struct ViewArgs {
    /// Model file (TOML): the robot, its actuation and obstacles.
    file: PathBuf,
    /// A scene file with obstacles (added to the model file's own).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Methods to solve and overlay, comma-separated; each `NAME` or `NAME:SETTING=VALUE:...`
    /// (default: geometric, or none with --plan / --sweep).
    #[arg(long, value_delimiter = ',')]
    method: Vec<String>,
    /// Start every method from the shape this one finds (e.g. `geometric` for `energy` inside
    /// a tube, as with `solve --warm-from`).
    #[arg(long, value_name = "METHOD")]
    warm_from: Option<String>,
    /// A plan (JSON of `ccrkit plan`: `waypoints[*].shape`), shown with a slider.
    #[arg(long)]
    plan: Option<PathBuf>,
    /// A workspace sweep (CSV of `ccrkit study workspace`), drawn as the cloud of tips.
    #[arg(long)]
    sweep: Option<PathBuf>,
    /// The sweep column that colours the tips (default: the first sampled input).
    #[arg(long)]
    color_by: Option<String>,
    /// Output page (default: the model file's name with `.html`, in the current folder).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Solve, assemble and write the page.
pub fn run(a: ViewArgs) -> Result<()> {
    let out = a.out.clone().unwrap_or_else(|| {
        let stem = a
            .file
            .file_stem()
            .map_or("view".into(), |s| s.to_string_lossy());
        PathBuf::from(format!("{stem}.html"))
    });
    let mut run = crate::check_files(
        &[
            ("model file", Some(&a.file)),
            ("--scene file", a.scene.as_deref()),
            ("--plan file", a.plan.as_deref()),
            ("--sweep file", a.sweep.as_deref()),
        ],
        &[("--out file", Some(&out))],
    )?;
    let extra = a.scene.as_ref().map(Scene::from_file).transpose()?;
    let entries: Vec<String> = if a.method.is_empty() && a.plan.is_none() && a.sweep.is_none() {
        vec![ccrkit::method::MethodKind::DEFAULT.name().into()]
    } else {
        a.method.clone()
    };
    let warm_from = a
        .warm_from
        .as_deref()
        .map(str::parse::<ccrkit::method::MethodKind>)
        .transpose()?;
    let requests = entries
        .iter()
        .map(|e| {
            let (kind, settings) = study::compare::parse_entry(e)?;
            let mut r = SolveRequest::new(kind)
                .with_settings(settings)
                .with_scene(extra.clone());
            r.warm_from = warm_from;
            r.solver()?;
            Ok((e.clone(), r))
        })
        .collect::<Result<Vec<_>>>()?;
    let sweep = match &a.sweep {
        Some(p) => Some(read_sweep(&read(p)?).with_context(|| format!("reading {}", p.display()))?),
        None => None,
    };
    let model = Model::from_file(&a.file)?;
    crate::check_read(&mut run, &model, extra.as_ref())?;
    let mut scene = model.scene.clone();
    if let Some(x) = &extra {
        scene.merge(x.clone());
    }
    let plan = match &a.plan {
        Some(p) => Some(
            read_plan(&read(p)?, &model.robot, &scene)
                .with_context(|| format!("reading {}", p.display()))?,
        ),
        None => None,
    };
    let stem = a
        .file
        .file_stem()
        .map_or("view".into(), |s| s.to_string_lossy());
    let mut view = View::new(
        format!("{} ({stem})", model.robot.name),
        &model.robot,
        &scene,
    );
    let bar = crate::progress::bar(requests.len() as u64, "solving");
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    for (label, r) in &requests {
        bar.set_message(format!("solving {label}"));
        let solved = r.run(&model).with_context(|| format!("solving {label}"))?;
        let input = r.method.input_with(&r.settings).name();
        view.add_shape(&format!("{label} (driven by {input})"), &solved.shape)?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    if let Some(p) = &plan {
        view.add_path(&format!("plan ({} waypoints)", p.len()), p)?;
    }
    if let Some(s) = &sweep {
        view.set_sweep(s, a.color_by.as_deref())?;
    } else if a.color_by.is_some() {
        anyhow::bail!("--color-by needs --sweep");
    }
    view.write(&out)?;
    let c = view.expected();
    eprintln!(
        "wrote {} ({} layers, {} obstacles, {} frames, {} tips)",
        out.display(),
        c.layers.len(),
        c.obstacles,
        c.frames,
        c.points
    );
    Ok(())
}

fn read(p: &std::path::Path) -> Result<String> {
    Ok(ccrkit::model::read::read_text(p, "plan or sweep file")?)
}
