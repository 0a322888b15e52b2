//! `ccrkit anatomy airway`: generate a seeded airway and write it as one closed mesh
//! ([`ccrkit::anatomy::generate`]).

use anyhow::Result;
use ccrkit::anatomy::{generate, AirwayOptions};
use clap::Subcommand;
use std::path::PathBuf;

#[derive(Subcommand)]
pub(crate) enum AnatomyCommand {
    /// A bifurcating airway tree from a seed (Weibel diameters, Murray angles, curved
    /// branches), written as one closed mesh for `free = "inside"`.
    Airway {
        /// Seed: the same seed and options give the same mesh.
        #[arg(long, default_value_t = AirwayOptions::default().seed)]
        seed: u64,
        /// Generations below the trachea.
        #[arg(long, default_value_t = AirwayOptions::default().generations)]
        generations: u32,
        /// Flow-split asymmetry in [0, 0.4] (0: symmetric, Weibel).
        #[arg(long, default_value_t = AirwayOptions::default().asymmetry)]
        asymmetry: f64,
        /// Meshing grid cell [m] (default: a quarter of the smallest diameter).
        #[arg(long)]
        cell: Option<f64>,
        /// Output mesh (.stl binary or .obj).
        #[arg(long)]
        out: PathBuf,
    },
}

pub(crate) fn run(cmd: AnatomyCommand) -> Result<()> {
    match cmd {
        AnatomyCommand::Airway {
            seed,
            generations,
            asymmetry,
            cell,
            out,
        } => {
            let opts = AirwayOptions {
                seed,
                generations,
                asymmetry,
                cell,
                ..AirwayOptions::default()
            };
            let airway = generate(&opts)?;
            ccrkit::mesh::write(&out, &airway.vertices, &airway.triangles)?;
            println!(
                "wrote {}: {} branches ({} left out where they did not fit), {} triangles, cell {:.3e} m",
                out.display(),
                airway.branches.len(),
                airway.dropped,
                airway.triangles.len(),
                airway.cell
            );
            Ok(())
        }
    }
}
