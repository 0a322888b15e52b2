//! `ccrkit roadmap build`: precompute a roadmap for `ccrkit plan --roadmap`
//! ([`ccrkit::plan::roadmap::build`]).

use super::reach::InverseArgs;
use anyhow::Result;
use ccrkit::plan::roadmap::{build, BuildOptions};
use ccrkit::Model;
use clap::Subcommand;
use std::path::PathBuf;

#[derive(Subcommand)]
pub(crate) enum RoadmapCommand {
    /// Sample admissible actuations, solve them and connect neighbours by validated edges.
    Build {
        /// Model file (TOML); its `[limits]` bound the samples.
        file: PathBuf,
        #[command(flatten)]
        inverse: InverseArgs,
        /// Output roadmap file (JSON).
        #[arg(long)]
        out: PathBuf,
        /// Uniform samples drawn.
        #[arg(long, default_value_t = BuildOptions::default().samples)]
        samples: usize,
        /// Samples drawn around admissible nodes (Gaussian steps; biases the roadmap to the
        /// free space).
        #[arg(long, default_value_t = BuildOptions::default().expand)]
        expand: usize,
        /// Standard deviation of an expansion step, as a fraction of each cable's range.
        #[arg(long, default_value_t = BuildOptions::default().spread)]
        spread: f64,
        /// Neighbours each node tries to connect to.
        #[arg(long, default_value_t = BuildOptions::default().neighbours)]
        neighbours: usize,
        /// Seed.
        #[arg(long, default_value_t = BuildOptions::default().seed)]
        seed: u64,
    },
}

pub(crate) fn run(cmd: RoadmapCommand) -> Result<()> {
    match cmd {
        RoadmapCommand::Build {
            file,
            inverse,
            out,
            samples,
            expand,
            spread,
            neighbours,
            seed,
        } => {
            super::check_files(
                &[
                    ("model file", Some(&file)),
                    ("--scene file", inverse.scene.as_deref()),
                ],
                &[("--out file", Some(&out))],
            )?;
            let model = Model::from_file(&file)?;
            let request = inverse.request(&model)?;
            let opts = BuildOptions {
                samples,
                neighbours,
                seed,
                margin: inverse.margin,
                expand,
                spread,
            };
            let r = build(&model, &request, &opts)?;
            r.save(&out)?;
            println!(
                "roadmap: {} nodes of {} samples, {} edges, {} solves, {:.2} s; wrote {}",
                r.nodes.len(),
                samples + expand,
                r.edges.len(),
                r.build_solves,
                r.build_time_s,
                out.display()
            );
            Ok(())
        }
    }
}
