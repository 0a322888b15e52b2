//! Typed warm starts: what a method keeps in a shape's report so that its next solve of a
//! nearby actuation starts where this one ended. Any shape also warm-starts any method through
//! its disk frames; this is the extra a method can only read from its own shapes.

use crate::model::actuation::LengthMeasure;
use nalgebra::DMatrix;

/// Solver state carried by a shape for warm starts (never serialized).
#[derive(Debug, Clone, PartialEq)]
pub enum WarmState {
    /// The energy model's solution.
    Energy(EnergyWarm),
    /// The rod's last shooting Jacobian (`k × k`, unknowns: base wrench `n(0)`, `m(0)/L`, then
    /// the tensions of the length-controlled taut cables).
    Rod {
        /// The Jacobian.
        jacobian: DMatrix<f64>,
        /// The length-controlled taut cables whose tensions are the unknowns after the
        /// base wrench, in column order.
        unknown: Vec<usize>,
        /// Their length targets \[m\] (undeformed length minus shortening), in the same order:
        /// with the Jacobian they predict the start for new shortenings.
        targets: Vec<f64>,
    },
}

/// The energy model's solution, for warm starts and for the inverse problems built on it.
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyWarm {
    /// Sub-arcs of each section (base first) of the discretization the strains belong to.
    pub sub_arcs: Vec<usize>,
    /// Cable length measure of the solve.
    pub length: LengthMeasure,
    /// Strains `(κx, κy, τ, ε)` per sub-arc, base to tip.
    pub strains: Vec<f64>,
    /// Cable multipliers (tensions \[N\]) in robot order.
    pub multipliers: Vec<f64>,
    /// The Lagrangian Hessian blocks at these strains, when the solve built them.
    pub hessian: Option<EnergyHessian>,
    /// Shear strains `(γx, γy)` per sub-arc (empty: solved without shear).
    pub shear: Vec<[f64; 2]>,
}

/// The energy model's Lagrangian Hessian blocks `K + Σ_c w_c ∇²L_c` (path lengths; row-major
/// diagonal blocks) at a solution, with the cable weights `w_c` (multipliers of the
/// length-driven cables, input tensions) and the stiffness diagonal `K` they were built with.
/// A warm start from that solution whose first Hessian has the same strains, weights and `K`
/// uses these blocks instead of rebuilding them (so a warm solve then costs no more
/// than a cold one, whose first Hessian has no cable curvature).
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyHessian {
    /// The diagonal blocks.
    pub blocks: Vec<f64>,
    /// The cable weights they were built with.
    pub weights: Vec<f64>,
    /// The energy's stiffness diagonal they were built with.
    pub stiffness: Vec<f64>,
    /// The geometry the cable curvature in them comes from: the sub-arc lengths \[m\], then
    /// per cable the disk it ends at, its hole radii \[m\] and angles \[rad\]. Two robots
    /// that differ only in a cable's routing have the same strains, weights and stiffness but
    /// not the same blocks: a warm start from the other robot's solve rebuilds them.
    pub routing: Vec<f64>,
}

impl WarmState {
    /// The energy model's strains, if this is its state.
    pub fn strains(&self) -> Option<&[f64]> {
        match self {
            WarmState::Energy(e) => Some(&e.strains),
            WarmState::Rod { .. } => None,
        }
    }
}
