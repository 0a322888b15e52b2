//! Tip sensitivities `∂p_tip/∂u` and `∂t_tip/∂u` (t: the tip disk's normal) at a solved
//! shape, one column per cable of the [`Space`].
//!
//! With a port, the rotation's column is exact (a rigid turn about the port axis, when the
//! robot carries no loads) and the insertion's is a central difference (one-sided at its
//! limits): sliding the robot out changes the robot that bends, not an input of its solve.
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

/// Central-difference step of an unknown: shortening \[m\], insertion \[m\], rotation \[rad\]
/// (a tension's is `FD_STEP_TENSION`).
pub const FD_STEP: f64 = 1e-6;
/// Central-difference step of a tension \[N\].
pub const FD_STEP_TENSION: f64 = 1e-4;

/// Tip sensitivities at one point of the actuation space.
#[derive(Debug, Clone)]
pub struct TipSens {
    /// `∂p_tip/∂u` (3 × cables) \[m/m\].
    pub position: DMatrix<f64>,
    /// `∂t_tip/∂u` (3 × cables) \[1/m\].
    pub tangent: DMatrix<f64>,
    /// True when the cable columns were read from the method's `report.jacobian`, false for
    /// central differences (the insertion's column is always one, module docs).
    pub exact: bool,
    /// `∂(clearance)/∂u` (per cable) \[m/m\], when asked for and there are obstacles.
    pub clearance: Option<Vec<f64>>,
    /// Forward solves the central differences took.
    pub solves: usize,
}

fn tangent(shape: &Shape) -> Vector3<f64> {
    shape.disks[shape.disks.len() - 1]
        .rotation
        .column(2)
        .into_owned()
}

/// The method's own Jacobian, when it has a column of the space's input (shortening or
/// tension) for every cable of `space` not released (a released cable is free: the tip does not depend on its input, a zero column).
fn exact(space: &Space, shape: &Shape, released: &[bool]) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let j = shape.report.jacobian.as_ref()?;
    let k = space.cables();
    let (mut p, mut t) = (DMatrix::zeros(3, k), DMatrix::zeros(3, k));
    for (c, cable) in space.robot.cables.iter().enumerate() {
        if released.get(c).copied().unwrap_or(false) {
            continue;
        }
        let col = j
            .inputs
            .iter()
            .position(|(name, input)| name == &cable.name && input == space.input.name())?;
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
    let (n, k) = (space.dim(), space.cables());
    let ex = exact(space, shape, released);
    let (mut p, mut t) = (DMatrix::zeros(3, n), DMatrix::zeros(3, n));
    let mut g = vec![0.0; n];
    let mut exact_rotation = false;
    let mut solves = 0;
    if let Some((pe, te)) = &ex {
        p.columns_mut(0, k).copy_from(pe);
        t.columns_mut(0, k).copy_from(te);
    }
    if let (true, Some(port)) = (space.has_port(), space.robot.port.as_ref()) {
        // Rotation ψ turns the whole solved robot about the port axis `a` through the port
        // origin `o` when nothing else turns with it (no loads): ∂p/∂ψ = a × (p − o),
        // ∂t/∂ψ = a × t, exactly.
        let l = &space.robot.loads;
        let unloaded = (l.gravity.norm() == 0.0 || l.disk_mass == 0.0)
            && l.tip_force.norm() == 0.0
            && l.tip_moment.norm() == 0.0;
        if unloaded {
            let (a, o) = (port.axis(), port.origin());
            let (dp, dt) = (a.cross(&(shape.tip() - o)), a.cross(&tangent(shape)));
            p.column_mut(k + 1).copy_from(&dp);
            t.column_mut(k + 1).copy_from(&dt);
            exact_rotation = true;
        }
    }
    for j in 0..n {
        let known = if j < k {
            ex.is_some() || released.get(j).copied().unwrap_or(false)
        } else {
            j == k + 1 && exact_rotation
        };
        if known && !want_clearance {
            continue;
        }
        // Central differences, one-sided at a limit (an insertion cannot pass [0, L]).
        let h = if j < k && space.by_tension() {
            FD_STEP_TENSION
        } else {
            FD_STEP
        };
        let (up, um) = (
            (u[j] + h).min(space.hi[j].max(u[j])),
            (u[j] - h).max(space.lo[j].min(u[j])),
        );
        if up - um <= 0.0 {
            continue;
        }
        let at = |x: f64| {
            let mut v = u.to_vec();
            v[j] = x;
            v
        };
        solves += 2;
        let sp = space.solve_with(&at(up), released, Some(shape))?;
        let sm = space.solve_with(&at(um), released, Some(shape))?;
        if !known {
            let dp = (sp.tip() - sm.tip()) / (up - um);
            let dt = (tangent(&sp) - tangent(&sm)) / (up - um);
            p.column_mut(j).copy_from(&dp);
            t.column_mut(j).copy_from(&dt);
        }
        if want_clearance {
            let cp = space.clearance(&sp).map_or(0.0, |c| c.distance);
            let cm = space.clearance(&sm).map_or(0.0, |c| c.distance);
            g[j] = (cp - cm) / (up - um);
        }
    }
    Ok(TipSens {
        position: p,
        tangent: t,
        exact: ex.is_some(),
        clearance: want_clearance.then_some(g),
        solves,
    })
}

/// The tip tangent (the tip disk's normal) of a shape.
pub(super) fn tip_tangent(shape: &Shape) -> Vector3<f64> {
    tangent(shape)
}
