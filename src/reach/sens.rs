//! Tip sensitivities `∂p_tip/∂u` and `∂t_tip/∂u` (t: the tip disk's normal) at a solved
//! shape, one column per cable of the [`Space`].
//!
//! When the method fills `report.jacobian` ([`crate::shape::TipJacobian`], the implicit
//! function theorem on the converged KKT system) with a shortening column for every cable,
//! that is used as is. Otherwise the columns are central differences of full solves at
//! `u ± h e_j` ([`FD_STEP`]), each warm-started from the shape: the error is `O(h²)` from
//! the third derivative plus `O(ε/h)` from the solver tolerance ε (1e-10 m for `energy`),
//! about 1e-4 relative — ample for the Gauss–Newton steps of [`super::reach`], whose final
//! answer is checked by a forward solve, not by the Jacobian.
//!
//! The same differences give the gradient of the clearance ([`super::clearance`]) when it is
//! asked for (a min over feature–obstacle pairs: a one-sided derivative where the closest
//! pair changes, which the line search of the caller tolerates).

use super::Space;
use crate::error::SolveError;
use crate::shape::Shape;
use nalgebra::{DMatrix, Vector3};

/// Central-difference step in the shortenings \[m\].
pub const FD_STEP: f64 = 1e-6;

/// Tip sensitivities at one point of the actuation space.
#[derive(Debug, Clone)]
pub struct TipSens {
    /// `∂p_tip/∂u` (3 × cables) \[m/m\].
    pub position: DMatrix<f64>,
    /// `∂t_tip/∂u` (3 × cables) \[1/m\].
    pub tangent: DMatrix<f64>,
    /// True when read from the method's `report.jacobian`, false for central differences.
    pub exact: bool,
    /// `∂(clearance)/∂u` (per cable) \[m/m\], when asked for and there are obstacles.
    pub clearance: Option<Vec<f64>>,
}

fn tangent(shape: &Shape) -> Vector3<f64> {
    shape.disks[shape.disks.len() - 1]
        .rotation
        .column(2)
        .into_owned()
}

/// The method's own Jacobian, when it has a shortening column for every cable of `space` not
/// released (a released cable is free: the tip does not depend on its input, a zero column).
fn exact(space: &Space, shape: &Shape, released: &[bool]) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let j = shape.report.jacobian.as_ref()?;
    let k = space.dim();
    let (mut p, mut t) = (DMatrix::zeros(3, k), DMatrix::zeros(3, k));
    for (c, cable) in space.robot.cables.iter().enumerate() {
        if released.get(c).copied().unwrap_or(false) {
            continue;
        }
        let col = j
            .inputs
            .iter()
            .position(|(name, input)| name == &cable.name && input == "shortening")?;
        for a in 0..3 {
            p[(a, c)] = *j.position.get(col)?.get(a)?;
            t[(a, c)] = *j.tangent.get(col)?.get(a)?;
        }
    }
    Some((p, t))
}

/// Tip sensitivities of `space` at `u`, where `shape` is the solved shape at `u`; with
/// `want_clearance`, also the clearance gradient (central differences).
pub fn sensitivity(
    space: &Space,
    u: &[f64],
    shape: &Shape,
    want_clearance: bool,
) -> Result<TipSens, SolveError> {
    sensitivity_with(space, u, &[], shape, want_clearance)
}

/// [`sensitivity`] with the cables marked in `released` left free ([`Space::solve_with`]):
/// their columns are zero.
pub(super) fn sensitivity_with(
    space: &Space,
    u: &[f64],
    released: &[bool],
    shape: &Shape,
    want_clearance: bool,
) -> Result<TipSens, SolveError> {
    let want_clearance = want_clearance && !space.scene.is_empty();
    let k = space.dim();
    let ex = exact(space, shape, released);
    if let (Some((p, t)), false) = (&ex, want_clearance) {
        return Ok(TipSens {
            position: p.clone(),
            tangent: t.clone(),
            exact: true,
            clearance: None,
        });
    }
    let (mut p, mut t) = (DMatrix::zeros(3, k), DMatrix::zeros(3, k));
    let mut g = vec![0.0; k];
    for j in 0..k {
        if released.get(j).copied().unwrap_or(false) {
            continue;
        }
        let mut up = u.to_vec();
        up[j] += FD_STEP;
        let mut um = u.to_vec();
        um[j] -= FD_STEP;
        let sp = space.solve_with(&up, released, Some(shape))?;
        let sm = space.solve_with(&um, released, Some(shape))?;
        let dp = (sp.tip() - sm.tip()) / (2.0 * FD_STEP);
        let dt = (tangent(&sp) - tangent(&sm)) / (2.0 * FD_STEP);
        for a in 0..3 {
            p[(a, j)] = dp[a];
            t[(a, j)] = dt[a];
        }
        if want_clearance {
            let cp = space.clearance(&sp).map_or(0.0, |c| c.distance);
            let cm = space.clearance(&sm).map_or(0.0, |c| c.distance);
            g[j] = (cp - cm) / (2.0 * FD_STEP);
        }
    }
    let exact_used = ex.is_some();
    if let Some((pe, te)) = ex {
        p = pe;
        t = te;
    }
    Ok(TipSens {
        position: p,
        tangent: t,
        exact: exact_used,
        clearance: want_clearance.then_some(g),
    })
}

/// The tip tangent (the tip disk's normal) of a shape.
pub(super) fn tip_tangent(shape: &Shape) -> Vector3<f64> {
    tangent(shape)
}
