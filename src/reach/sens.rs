//! Tip sensitivities `∂p_tip/∂u` and `∂t_tip/∂u` (t: the tip disk's normal) at a solved
//! shape, one column per unknown of the [`Space`].
//!
//! When the method fills `report.jacobian` ([`crate::shape::TipJacobian`], the implicit
//! function theorem on the converged KKT system) with a column of the space's input for every
//! cable beyond the port, that is used as is (a cable tied at or behind the port moves nothing:
//! a zero column). Otherwise the columns are central differences of full solves at
//! `u ± h e_j` ([`FD_STEP`]), each warm-started from the shape: the error is `O(h²)` from
//! the third derivative plus `O(ε/h)` from the solver tolerance ε (1e-10 m for `energy`),
//! about 1e-4 relative — ample for the Gauss–Newton steps of [`super::reach`], whose final
//! answer is checked by a forward solve, not by the Jacobian.
//!
//! # Rotation
//!
//! Rotation `ψ` turns the whole solved robot about the port axis `a` through the port origin
//! `o` when nothing else turns with it (no loads, no contact): `∂p/∂ψ = a × (p − o)`,
//! `∂t/∂ψ = a × t`, exactly.
//!
//! # Insertion
//!
//! Inserting by `δd` brings a piece of material of length `δd` out of the port at its base
//! (`model/port.rs`: the robot beyond the port starts at material `s₀ = L − d`). The rest of
//! the bending part keeps its shape relative to its own base to first order, and the new
//! piece, between the port and that base, takes the strains the rod has at its base — the
//! body curvature and twist `u₀` and the stretch `v₀ = (γx, γy, 1 + ε)` (by continuity: the
//! same material under the same internal wrench). So the old base moves by `R_b v₀ δd` and
//! turns by `R_b u₀ δd` about the port (`R_b = R_port Rz(ψ)` the base frame), carrying the tip
//! with it. The cables, however, keep their length: a cable's path runs at `p + R r(s)` with
//! `r(s)` its hole in the body frame, so per metre of material it is `|e_z + r'|` straight in
//! the port and `|v₀ + u₀ × r + r'|` in the new piece (Rucker & Webster 2011, eq. 6–7). A
//! shortening-driven cable `c` whose length is held must take the difference from the rest:
//! the rest sees its shortening grow by `Δu_c = |v₀ + u₀ × r_c + r_c'| − |e_z + r_c'|` per
//! metre. Hence, with `J_c` the method's shortening column of cable `c`:
//!
//! ```text
//! ∂p/∂d = R_b v₀ + (R_b u₀) × (p − o) + Σ_c J_c^p Δu_c
//! ∂t/∂d =          (R_b u₀) × t       + Σ_c J_c^t Δu_c
//! ```
//!
//! A tension-driven cable keeps its tension whatever its length: no third term in tension
//! space. A released (free) cable has none either.
//!
//! This is the derivative of the continuous rod. The energy model's strains are constant on
//! sub-arcs of length `ℓ` (the partial first section's all lengthen with `d`), so `u₀`, `v₀`
//! are its first two sub-arcs' strains (body-frame components, at `ℓ/2` and `3ℓ/2`)
//! extrapolated linearly to the base, and the model's own derivative differs from the rod's
//! by its discretization error, `O(ℓ²)`: on seeded random port robots the column is within
//! 1 % of central differences of full solves at the default 4 sub-arcs (tip and `L ×`
//! tangent) and 16× closer at 16 (`tests/inverse/insertion_column.rs`; the first sub-arc's strain alone leaves an `O(ℓ)`
//! gap, 7 %, only 4× closer; a quadratic extrapolation gains nothing: what is left is the
//! model's). Reach's Gauss–Newton steps only need that; its answers are checked by forward
//! solves. The formula is used where its assumptions hold — `energy` with path lengths and
//! the default routing, a closed-form (straight or helical) route at the port, no loads, no
//! contact, and in shortening space the method's own cable columns — and central
//! differences elsewhere: a load does not turn with the robot (gravity stays down), an
//! obstacle does not move with it, a spline through per-disk holes is refitted at every cut,
//! and another method does not report its strains.
//!
//! The same differences give the gradient of the clearance ([`super::clearance`]) when it is
//! asked for: the gradient of its active piece, the distance of the closest feature–obstacle
//! pair at the shape, measured on the differenced shapes (the clearance is a min over pairs:
//! its one-sided derivative where the closest pair changes, which the line search of the
//! caller tolerates). One pair query per shape instead of a whole clearance: in the generated
//! airway a whole clearance of a shape across the wall queries ~36 pairs (each feature across
//! it), and these differences were 79 % of a reach's instructions.

use super::clear::{label_of, pair_distance};
use super::{ClosestPair, Space};
use crate::error::SolveError;
use crate::method::warm::WarmState;
use crate::method::MethodKind;
use crate::model::actuation::LengthMeasure;
use crate::model::port::{self, Beyond};
use crate::model::routing::{Route, RoutingFit};
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
    /// central differences.
    pub exact: bool,
    /// True when the insertion's column is the rod's kinematics (module docs, "Insertion"),
    /// false for central differences (or without a port).
    pub exact_insertion: bool,
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
/// tension) for every cable of `space` that is neither released (free: the tip does not
/// depend on its input) nor tied at or behind the port (`cut`: held straight, it moves
/// nothing); those have zero columns.
fn exact(
    space: &Space,
    shape: &Shape,
    released: &[bool],
    cut: Option<&Beyond>,
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let j = shape.report.jacobian.as_ref()?;
    let k = space.cables();
    let (mut p, mut t) = (DMatrix::zeros(3, k), DMatrix::zeros(3, k));
    for (c, cable) in space.robot.cables.iter().enumerate() {
        let behind = cut.is_some_and(|b| b.cables.get(c).is_some_and(|j| j.is_none()));
        if released.get(c).copied().unwrap_or(false) || behind {
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

/// True when the robot carries no load (a load does not turn with the robot).
fn unloaded(space: &Space) -> bool {
    let l = &space.robot.loads;
    (l.gravity.norm() == 0.0 || l.disk_mass == 0.0)
        && l.tip_force.norm() == 0.0
        && l.tip_moment.norm() == 0.0
}

/// The strains at the base of the bending part, `(u₀, v₀)` in the base frame (module docs,
/// "Insertion"): the first sub-arc's of an `energy` solve with path lengths (`None` for
/// another method or measure).
fn base_strains(shape: &Shape) -> Option<(Vector3<f64>, Vector3<f64>)> {
    let Some(WarmState::Energy(e)) = shape.report.warm.as_ref() else {
        return None;
    };
    if e.length != LengthMeasure::Path || e.strains.len() < 4 {
        return None;
    }
    let at = |j: usize| {
        let g = e.shear.get(j).copied().unwrap_or([0.0; 2]);
        let x = &e.strains[4 * j..4 * j + 4];
        (
            Vector3::new(x[0], x[1], x[2]),
            Vector3::new(g[0], g[1], 1.0 + x[3]),
        )
    };
    let (u1, v1) = at(0);
    if e.sub_arcs.first().is_none_or(|&m| m < 2) || e.strains.len() < 8 {
        return Some((u1, v1));
    }
    // Body-frame components at the midpoints ℓ/2 and 3ℓ/2, extrapolated to the base.
    let (u2, v2) = at(1);
    Some((1.5 * u1 - 0.5 * u2, 1.5 * v1 - 0.5 * v2))
}

/// The insertion column `(∂p/∂d, ∂t/∂d)` by the rod's kinematics (module docs, "Insertion"),
/// or `None` where its assumptions do not hold (then central differences). `cables`: the
/// method's own cable columns (needed in shortening space), `cut` the robot beyond the port.
fn insertion_column(
    space: &Space,
    shape: &Shape,
    released: &[bool],
    cut: &Beyond,
    cables: Option<&(DMatrix<f64>, DMatrix<f64>)>,
) -> Option<(Vector3<f64>, Vector3<f64>)> {
    let (port, state) = (space.robot.port.as_ref()?, shape.port.as_ref()?);
    let spline = space
        .request
        .settings
        .get("routing")
        .is_none_or(|r| r == "spline");
    let plain = space.request.method == MethodKind::Energy && spline;
    if !(plain && unloaded(space) && shape.contacts.is_empty()) {
        return None;
    }
    let (u0, v0) = base_strains(shape)?;
    let rb = port
        .base_frame(state.rotation)
        .rotation
        .to_rotation_matrix();
    let turn = rb * u0;
    let mut dp = rb * v0 + turn.cross(&(shape.tip() - port.origin()));
    let mut dt = turn.cross(&tangent(shape));
    if !space.by_tension() {
        let (jp, jt) = cables?;
        for (c, j) in cut.cables.iter().enumerate() {
            let Some(j) = *j else { continue };
            if released.get(c).copied().unwrap_or(false) {
                continue;
            }
            let route = Route::new(&cut.robot, j, RoutingFit::Spline).ok()?;
            if !route.is_closed_form() {
                return None;
            }
            let at = route.eval(0.0, 0);
            let grow = (v0 + u0.cross(&at.r) + at.dr).norm() - (Vector3::z() + at.dr).norm();
            dp += jp.column(c) * grow;
            dt += jt.column(c) * grow;
        }
    }
    Some((dp, dt))
}

/// Tip sensitivities of `space` at `u`, where `shape` is the solved shape at `u`; with
/// `want_clearance`, also the clearance gradient (central differences).
pub fn sensitivity(
    space: &Space,
    u: &[f64],
    shape: &Shape,
    want_clearance: bool,
) -> Result<TipSens, SolveError> {
    let hint = want_clearance.then(|| space.clearance_hinted(shape, None).map(|c| c.1));
    sensitivity_with(space, u, &[], shape, hint.flatten())
}

/// [`sensitivity`] with the cables marked in `released` left free ([`Space::solve_with`]):
/// their columns are zero. The clearance gradient is asked for by the closest pair at
/// `shape` (`hint`): the gradient of that pair's distance (the clearance's active piece;
/// the whole clearance where the pair cannot be measured), one pair query per differenced
/// shape instead of a whole clearance.
pub(super) fn sensitivity_with(
    space: &Space,
    u: &[f64],
    released: &[bool],
    shape: &Shape,
    hint: Option<ClosestPair>,
) -> Result<TipSens, SolveError> {
    let want_clearance = hint.is_some() && !space.scene.is_empty();
    let active = hint.and_then(|(f, k)| Some((label_of(&space.robot, shape, f)?, k)));
    let (n, k) = (space.dim(), space.cables());
    let cut = match (space.has_port(), shape.port.as_ref()) {
        (true, Some(state)) => port::beyond(&space.robot, state.insertion)?,
        _ => None,
    };
    let ex = exact(space, shape, released, cut.as_ref());
    let (mut p, mut t) = (DMatrix::zeros(3, n), DMatrix::zeros(3, n));
    let mut g = vec![0.0; n];
    let (mut exact_rotation, mut exact_insertion) = (false, false);
    let mut solves = 0;
    if let Some((pe, te)) = &ex {
        p.columns_mut(0, k).copy_from(pe);
        t.columns_mut(0, k).copy_from(te);
    }
    if let (true, Some(port)) = (space.has_port(), space.robot.port.as_ref()) {
        // Rotation: a rigid turn about the port axis (module docs, "Rotation").
        if unloaded(space) && shape.contacts.is_empty() {
            let (a, o) = (port.axis(), port.origin());
            let (dp, dt) = (a.cross(&(shape.tip() - o)), a.cross(&tangent(shape)));
            p.column_mut(k + 1).copy_from(&dp);
            t.column_mut(k + 1).copy_from(&dt);
            exact_rotation = true;
        }
        // Insertion: the rod's kinematics where they hold (module docs, "Insertion").
        if let Some((dp, dt)) = cut
            .as_ref()
            .and_then(|b| insertion_column(space, shape, released, b, ex.as_ref()))
        {
            p.column_mut(k).copy_from(&dp);
            t.column_mut(k).copy_from(&dt);
            exact_insertion = true;
        }
    }
    for j in 0..n {
        let known = if j < k {
            ex.is_some() || released.get(j).copied().unwrap_or(false)
        } else {
            (j == k && exact_insertion) || (j == k + 1 && exact_rotation)
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
            let (cp, cm) = match active {
                // The active pair's distance: one pair query per shape.
                Some((label, k)) => (
                    pair_distance(&space.robot, &sp, &space.scene, label, k),
                    pair_distance(&space.robot, &sm, &space.scene, label, k),
                ),
                None => (None, None),
            };
            let whole = |x: &Shape| space.clearance(x).map_or(0.0, |c| c.distance);
            let (cp, cm) = match (cp, cm) {
                (Some(a), Some(b)) if a.is_finite() && b.is_finite() => (a, b),
                _ => (whole(&sp), whole(&sm)),
            };
            g[j] = (cp - cm) / (up - um);
        }
    }
    Ok(TipSens {
        position: p,
        tangent: t,
        exact: ex.is_some(),
        exact_insertion,
        clearance: want_clearance.then_some(g),
        solves,
    })
}

/// The tip tangent (the tip disk's normal) of a shape.
pub(super) fn tip_tangent(shape: &Shape) -> Vector3<f64> {
    tangent(shape)
}
