//! `ccrkit roadmap build`: precompute a roadmap for `ccrkit plan --roadmap`
//! ([`ccrkit::plan::roadmap::build`]), whole or one shard of it; `ccrkit roadmap merge`: the
//! shards into the roadmap ([`ccrkit::plan::roadmap_shard::merge`]).

use super::reach::InverseArgs;
use anyhow::Result;
use ccrkit::plan::roadmap::{build, BuildOptions, Roadmap};
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
        /// Build only this shard of the edges, `k/N` (every shard samples the same nodes;
        /// `ccrkit roadmap merge` joins the N files into the whole roadmap).
        #[arg(long)]
        shard: Option<String>,
    },
    /// Join the shards of one build (`roadmap build --shard k/N`) into the roadmap a single
    /// build gives.
    Merge {
        /// The shard files, all N of them, any order.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// Output roadmap file (JSON).
        #[arg(long)]
        out: PathBuf,
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
            shard,
        } => {
            let mut run = super::check_files(
                &[
                    ("model file", Some(&file)),
                    ("--scene file", inverse.scene.as_deref()),
                ],
                &[("--out file", Some(&out))],
            )?;
            let model = Model::from_file(&file)?;
            let request = inverse.request(&model)?;
            super::check_read(&mut run, &model, request.extra_scene.as_ref())?;
            let opts = BuildOptions {
                samples,
                neighbours,
                seed,
                margin: inverse.margin,
                expand,
                spread,
                shard: shard.map(|s| s.parse()).transpose()?,
                progress: crate::progress::handle(),
            };
            let r = build(&model, &request, &opts)?;
            r.save(&out)?;
            let part = r.shard.map_or(String::new(), |s| {
                format!(" (shard {}/{})", s.index, s.count)
            });
            println!(
                "roadmap{part}: {} nodes of {} samples, {} edges, {} solves, {:.2} s; wrote {}",
                r.nodes.len(),
                samples + expand,
                r.edges.len(),
                r.build_solves,
                r.build_time_s,
                out.display()
            );
            Ok(())
        }
        RoadmapCommand::Merge { parts, out } => {
            let inputs: Vec<(&str, Option<&std::path::Path>)> = parts
                .iter()
                .map(|p| ("shard file", Some(p.as_path())))
                .collect();
            let _ = super::check_files(&inputs, &[("--out file", Some(&out))])?;
            let loaded = parts
                .iter()
                .map(|p| Roadmap::load(p))
                .collect::<Result<Vec<_>, _>>()?;
            let r = ccrkit::plan::roadmap_shard::merge(loaded)?;
            r.save(&out)?;
            println!(
                "roadmap: {} shards merged, {} nodes, {} edges; wrote {}",
                parts.len(),
                r.nodes.len(),
                r.edges.len(),
                out.display()
            );
            Ok(())
        }
    }
}
