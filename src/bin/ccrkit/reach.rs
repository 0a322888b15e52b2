//! `ccrkit reach`: the least-effort actuation that puts the tip on a target
//! ([`ccrkit::reach::reach`]), and the arguments `plan` and `roadmap` share.

use super::MethodArg;
use anyhow::{bail, Result};
use ccrkit::method::run::SolveRequest;
use ccrkit::method::{MethodKind, Settings};
use ccrkit::reach::{reach, ReachOptions, Target};
use ccrkit::{Model, Scene};
use nalgebra::Vector3;
use std::path::PathBuf;

/// What the inverse commands solve with: method, settings, obstacles, contact.
#[derive(clap::Args, Clone)]
pub(crate) struct InverseArgs {
    /// Method (see `ccrkit methods`), or `auto` (chosen once for the model's own actuation at
    /// `--model-tolerance`). A method driven by tension (`cosserat`, or `energy` with `--set
    /// control=force`) makes `reach`, `plan` and `roadmap` search the cables' tensions \[N\]
    /// within their tension limits instead of shortenings.
    #[arg(long, default_value_t = MethodArg::Named(MethodKind::DEFAULT), value_parser = super::parse_method_arg)]
    pub method: MethodArg,
    /// The tolerance of `--method auto` \[m\] (default 1e-4).
    #[arg(long)]
    pub model_tolerance: Option<f64>,
    /// A scene file with obstacles (added to the model file's own).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Method setting NAME=VALUE (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Distance every feature keeps from every obstacle \[m\] (default: the scene's
    /// `clearance`).
    #[arg(long)]
    pub margin: Option<f64>,
}

impl InverseArgs {
    /// The solve request for `model`, checked (`auto` settled on the model's own actuation).
    pub fn request(&self, model: &Model) -> Result<SolveRequest> {
        let mut s = Settings::new();
        for kv in &self.set {
            let (k, v) = Settings::parse_pair(kv)?;
            s.push(k, v);
        }
        let scene = self.scene.as_ref().map(Scene::from_file).transpose()?;
        let r = self
            .method
            .request(self.model_tolerance)?
            .with_settings(s)
            .with_scene(scene)
            .resolved(model)?;
        r.solver()?;
        Ok(r)
    }
}

/// `ccrkit reach` arguments.
#[derive(clap::Args)]
pub(crate) struct ReachArgs {
    /// Model file (TOML); its `[limits]` bound the search.
    file: PathBuf,
    /// Target tip position X,Y,Z \[m\], base frame.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    tip: Vec<f64>,
    /// Target tip tangent X,Y,Z (normalized here).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    tangent: Vec<f64>,
    #[command(flatten)]
    inverse: InverseArgs,
    /// Allow contact with the obstacles instead of keeping clear.
    #[arg(long)]
    allow_contact: bool,
    /// Reached when the tip error (plus length × tangent error) is at most this \[m\].
    #[arg(long, default_value_t = ReachOptions::default().tolerance)]
    tolerance: f64,
    /// Starts of the search before giving up.
    #[arg(long, default_value_t = ReachOptions::default().starts)]
    starts: usize,
    /// Write the answer as JSON (`-` for standard output).
    #[arg(long)]
    json: Option<String>,
}

/// Three numbers named `field`.
pub(crate) fn vec3(field: &str, v: &[f64]) -> Result<Vector3<f64>> {
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        bail!("--{field} needs three finite numbers X,Y,Z, got {v:?}");
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}

/// Write JSON text to a path or `-`.
pub(crate) fn write_json(path: &str, text: &str) -> Result<()> {
    if path == "-" {
        println!("{text}");
    } else {
        super::write_out(std::path::Path::new(path), text)?;
        eprintln!("wrote {path}");
    }
    Ok(())
}

pub(crate) fn run(a: ReachArgs) -> Result<()> {
    let tip = vec3("tip", &a.tip)?;
    let tangent = if a.tangent.is_empty() {
        None
    } else {
        let t = vec3("tangent", &a.tangent)?;
        if t.norm() == 0.0 {
            bail!("--tangent must not be zero");
        }
        Some(t.normalize())
    };
    let mut run = super::check_files(
        &[
            ("model file", Some(&a.file)),
            ("--scene file", a.inverse.scene.as_deref()),
        ],
        &[("--json file", a.json.as_deref().map(std::path::Path::new))],
    )?;
    let model = Model::from_file(&a.file)?;
    let request = a.inverse.request(&model)?;
    super::check_read(&mut run, &model, request.extra_scene.as_ref())?;
    let opts = ReachOptions {
        allow_contact: a.allow_contact,
        tolerance: a.tolerance,
        starts: a.starts,
        margin: a.inverse.margin,
        ..ReachOptions::default()
    };
    let r = reach(&model, &request, &Target { tip, tangent }, &opts)?;
    let quiet = a.json.as_deref() == Some("-");
    if let Some(j) = &a.json {
        let text = serde_json::to_string_pretty(&r.to_json())?;
        write_json(j, &text)?;
    }
    if !quiet {
        let t = r.shape.tip() * 1e3;
        println!(
            "{} tip [{:.4}, {:.4}, {:.4}] mm, error {:.3e} m{}",
            if r.reached { "reached" } else { "NOT reached" },
            t.x,
            t.y,
            t.z,
            r.tip_error_m,
            r.tangent_error_rad
                .map(|e| format!(", tangent error {e:.3e} rad"))
                .unwrap_or_default()
        );
        for c in &r.actuation {
            println!(
                "cable {}: shorten {:.6} mm{}",
                c.cable,
                c.shorten * 1e3,
                c.tension
                    .map(|t| format!(", tension {t:.4} N"))
                    .unwrap_or_default()
            );
        }
        if let (Some(d), Some(psi)) = (r.insertion, r.rotation) {
            println!(
                "port: insertion {:.6} mm, rotation {:.6} rad ({:.3}°)",
                d * 1e3,
                psi,
                psi.to_degrees()
            );
        }
        if let Some(c) = r.min_clearance_m {
            println!("clearance {:.3} mm", c * 1e3);
        }
        println!(
            "effort {:.4e} {}, {} iterations, {} starts, {} solves ({} sensitivities)",
            r.effort_m2,
            if r.by_tension { "N²" } else { "m²" },
            r.iterations,
            r.starts,
            r.solves,
            r.sensitivities
        );
    }
    r.require_reached()?;
    Ok(())
}
