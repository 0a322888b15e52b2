//! Generated anatomy: a reproducible airway tree from a seed ([`airway`]), written as one
//! closed, manifold, consistently oriented mesh ([`tetra`]), ready to be a lumen
//! (`free = "inside"`).
//!
//! The tree follows the airway literature's laws (diameters, lengths, branching angles: see
//! [`airway`]); its surface is the union of swept spheres along the branches' curved
//! centrelines, meshed by marching tetrahedra, which joins the branches at every bifurcation
//! without a hole by construction.

pub mod airway;
pub mod tasks;
pub mod tetra;

pub use airway::{AirwayOptions, Branch};
use nalgebra::Vector3;

/// A generated airway: its branches and its surface.
#[derive(Debug, Clone)]
pub struct Airway {
    /// The branches, the trachea first, parents before children.
    pub branches: Vec<Branch>,
    /// Children of the tree dropped because they did not fit beside other branches.
    pub dropped: usize,
    /// The surface's vertices \[m\].
    pub vertices: Vec<Vector3<f64>>,
    /// The surface's triangles, wound outward (a closed solid).
    pub triangles: Vec<[u32; 3]>,
    /// The grid cell the surface was meshed with \[m\].
    pub cell: f64,
}

/// Why an airway cannot be generated: the option and the reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("airway option `{field}`: {reason}")]
pub struct AirwayError {
    /// The option's name.
    pub field: &'static str,
    /// What is wrong with it.
    pub reason: String,
}

/// Most generations generated (2¹³ − 1 branches; deeper airways are below a CT's resolution).
pub const MAX_GENERATIONS: u32 = 12;

/// Most grid points sampled while meshing (about 1 GiB of hash map).
pub const MAX_GRID_POINTS: f64 = 3e7;

fn check(opts: &AirwayOptions) -> Result<(), AirwayError> {
    let bad = |field: &'static str, reason: String| Err(AirwayError { field, reason });
    if opts.generations > MAX_GENERATIONS {
        return bad(
            "generations",
            format!("{} is more than {MAX_GENERATIONS}", opts.generations),
        );
    }
    for (field, v) in [
        ("trachea_diameter", opts.trachea_diameter),
        ("trachea_length", opts.trachea_length),
        ("length_ratio", opts.length_ratio),
    ] {
        if !(v.is_finite() && v > 0.0 && v <= 10.0) {
            return bad(field, format!("{v} is not in (0, 10]"));
        }
    }
    if !(0.0..=0.4).contains(&opts.asymmetry) {
        return bad(
            "asymmetry",
            format!("{} is not in [0, 0.4]", opts.asymmetry),
        );
    }
    if let Some(c) = opts.cell {
        check_cell(c, opts)?;
    }
    Ok(())
}

/// Finest grid cell \[m\] (below it the grid's count is beyond any bound, its estimate too).
pub const MIN_CELL: f64 = 1e-9;

/// A grid cell (given or the default) that resolves the narrowest branch: from [`MIN_CELL`]
/// to half the smallest diameter (a coarser grid drew every branch as one 24-triangle box).
fn check_cell(cell: f64, opts: &AirwayOptions) -> Result<(), AirwayError> {
    let most = smallest_diameter(opts) / 2.0;
    if cell.is_finite() && (MIN_CELL..=most).contains(&cell) {
        return Ok(());
    }
    Err(AirwayError {
        field: "cell",
        reason: format!(
            "{cell:e} m is not in [{MIN_CELL:e}, {most:.3e}] m (half the smallest branch's \
             diameter: a coarser grid cannot draw it)"
        ),
    })
}

/// The smallest diameter of a tree `opts` describes: the minor child's at the last generation.
fn smallest_diameter(opts: &AirwayOptions) -> f64 {
    opts.trachea_diameter * (0.5 - opts.asymmetry).cbrt().powi(opts.generations as i32)
}

/// Generate the airway `opts` describes: the same options give the same mesh, bit for bit.
pub fn generate(opts: &AirwayOptions) -> Result<Airway, AirwayError> {
    check(opts)?;
    let cell = opts.cell.unwrap_or(smallest_diameter(opts) / 4.0);
    check_cell(cell, opts)?;
    let branches = airway::tree(opts);
    let capsules: Vec<tetra::Capsule> = branches
        .iter()
        .flat_map(|b| {
            b.centreline.windows(2).map(|w| tetra::Capsule {
                a: w[0],
                b: w[1],
                radius: b.radius,
            })
        })
        .collect();
    // The grid points the sampling writes, bounded before allocating.
    let points: f64 = capsules
        .iter()
        .map(|c| {
            ((c.a - c.b).abs().add_scalar(2.0 * c.radius + 8.0 * cell) / cell)
                .map(|x| x + 1.0)
                .product()
        })
        .sum();
    if points > MAX_GRID_POINTS {
        return Err(AirwayError {
            field: "cell",
            reason: format!(
                "{cell:e} m samples about {points:.1e} grid points, more than {MAX_GRID_POINTS:.0e}: use a larger cell or fewer generations"
            ),
        });
    }
    let full = (1usize << (opts.generations + 1)) - 1;
    let dropped = full.saturating_sub(branches.len());
    let (vertices, triangles) = tetra::mesh(&capsules, cell);
    Ok(Airway {
        branches,
        dropped,
        vertices,
        triangles,
        cell,
    })
}
