//! An a-priori estimate of a converged `energy` answer's discretization error, read from that
//! answer alone (no second solve; `method/estimate.rs` holds it to a calibrated factor).
//!
//! On sub-arc `j` the model holds the strain `u_j` constant where the rod's strain `u(s)`
//! varies: a cut at `s` through backbone and cables carries, in the body frame,
//!
//! ```text
//! m(s) = Σ_c T_c r_c(s) × ŵ_c(s) − Rᵀ(s) Σ_{f beyond s} (p_f − p(s)) × F_f,
//! ŵ_c = normalize(v + u × r_c + r_c'),
//! ```
//!
//! the cables' pull at their offsets `r_c` (the routing curve) and the dead loads `F_f` beyond
//! `s` (disk weights, the backbone's weight lumped at sub-arc ends as the model does, the tip
//! force). The rod's strain follows it, `u(s) = K⁻¹ m(s)`. The model's constant strain is the
//! sub-arc's mean of it; what it leaves out, `δu(s) ≈ Δu_j (s − s_mid)/ℓ` with
//! `Δu_j = K⁻¹ (m(s_end) − m(s_start))`, moves the tip by
//!
//! * `ℓ²/12 |e₃ × Δu_j|` through the sub-arc's own bending (its first moment), and
//! * `ℓ²/12 |u_j × Δu_j| |p_tip − p_mid|` through the rotation it leaves at the sub-arc's end
//!   (the second Magnus term of `R' = R û`),
//!
//! summed over the sub-arcs without cancellation: the leading term of the error, `O(ℓ²)` as
//! the measured order. Straight cables without loads give 0: constant strain per section is
//! then the rod's exact answer. Helices (a turning `r_c`) and loads (a turning moment arm)
//! give the rest. It does not see what the model's geometry feeds back through the loads; the
//! calibration factor in `estimate.rs` covers that, measured on random robots.

use super::kinematics::sheared_exp;
use super::problem::section_of;
use crate::method::port::solved_beyond;
use crate::method::warm::{EnergyWarm, WarmState};
use crate::model::actuation::LengthMeasure;
use crate::model::robot::Robot;
use crate::model::routing::{Route, RoutingFit};
use crate::shape::{CablePath, Shape, TipJacobian};
use nalgebra::{Matrix3, Vector3};

/// A body frame along the backbone: arc length (undeformed), rotation, position.
type Frame = (f64, Matrix3<f64>, Vector3<f64>);

/// The leading discretization error of the energy answer `shape` of `robot` (module docs)
/// \[m\], unscaled, per section (base first; the tip error is bounded by their sum); where it
/// does not apply, why: not an energy answer, with contacts, chord cable lengths, a tip
/// moment, no Jacobian, or strains that do not fit the robot. Through a port, the robot
/// beyond it is what was solved (`method/port.rs`): its loads turned into its frame, its
/// cables those not tied behind the port; the tip error of a rigid placement is its own, and
/// nothing bending beyond the port is exact (0).
pub fn local_error(
    robot: &Robot,
    shape: &Shape,
    routing: RoutingFit,
) -> Result<Vec<f64>, &'static str> {
    let Some(WarmState::Energy(e)) = shape.report.warm.as_ref() else {
        return Err("the answer carries no energy strains");
    };
    if !shape.contacts.is_empty() {
        return Err("with contacts");
    }
    if e.length != LengthMeasure::Path {
        return Err("with chord cable lengths");
    }
    if shape.cables.len() != robot.cables.len() {
        return Err("with strains that do not fit the robot");
    }
    let jac = shape.report.jacobian.as_ref();
    let Some(state) = shape.port.as_ref() else {
        let paths: Vec<&CablePath> = shape.cables.iter().collect();
        return strain_error(robot, e, &paths, jac, routing);
    };
    let port = robot
        .port
        .as_ref()
        .ok_or("through a port the robot does not have")?;
    let Some((b, sub)) = solved_beyond(robot, port, state)
        .map_err(|_| "through a port that does not cut the robot")?
    else {
        return Ok(vec![0.0; robot.sections()]);
    };
    let paths: Vec<&CablePath> = shape
        .cables
        .iter()
        .zip(&b.cables)
        .filter_map(|(p, at)| at.map(|_| p))
        .collect();
    let beyond = strain_error(&sub, e, &paths, jac, routing)?;
    let mut out = vec![0.0; robot.sections()];
    for (i, x) in beyond.into_iter().enumerate() {
        if let Some(o) = out.get_mut(b.section(i + 1) - 1) {
            *o += x;
        }
    }
    Ok(out)
}

/// [`local_error`] of the strains `e` of `robot` (no port), with its cables' `paths` (tensions,
/// names) and the answer's Jacobian `jac`.
fn strain_error(
    robot: &Robot,
    e: &EnergyWarm,
    paths: &[&CablePath],
    jac: Option<&TipJacobian>,
    routing: RoutingFit,
) -> Result<Vec<f64>, &'static str> {
    let n = robot.sections();
    let mut first = vec![0];
    for m in &e.sub_arcs {
        first.push(first[first.len() - 1] + m);
    }
    let nsub = first[first.len() - 1];
    if robot.loads.tip_moment != Vector3::zeros() {
        return Err("with a tip moment");
    }
    let fits = e.sub_arcs.len() == n
        && e.sub_arcs.iter().all(|&m| m > 0)
        && e.strains.len() == 4 * nsub
        && (e.shear.is_empty() || e.shear.len() == nsub)
        && paths.len() == robot.cables.len();
    if !fits {
        return Err("with strains that do not fit the robot");
    }
    let routes = (0..robot.cables.len())
        .map(|c| Route::new(robot, c, routing).ok())
        .collect::<Option<Vec<Route>>>()
        .ok_or("without a routing curve for every cable")?;
    let tensions: Vec<f64> = paths
        .iter()
        .map(|c| c.tension.unwrap_or(0.0).max(0.0))
        .collect();
    let shear = |j: usize| e.shear.get(j).copied().unwrap_or([0.0; 2]);
    let section_of = |j: usize| section_of(&first, j);
    let ell = |j: usize| robot.section_length(section_of(j)) / e.sub_arcs[section_of(j) - 1] as f64;
    // Frames at the sub-arc ends, base to tip.
    let mut frames: Vec<Frame> = Vec::with_capacity(nsub + 1);
    let (mut s, mut rot, mut pos) = (0.0, Matrix3::identity(), Vector3::zeros());
    frames.push((s, rot, pos));
    for j in 0..nsub {
        let (r, p) = sheared_exp(&e.strains[4 * j..4 * j + 4], shear(j), ell(j));
        pos += rot * p;
        rot *= r;
        s += ell(j);
        frames.push((s, rot, pos));
    }
    // The tip's pull per metre of each length-driven cable's shortening (the answer's
    // Jacobian): a path the sub-arcs measure differently moves the tip as a shortening would.
    let driven =
        length_driven(paths, jac).ok_or("without the answer's Jacobian (sensitivity = off)")?;
    let loads = dead_loads(robot, &frames, &first);
    let b = &robot.backbone;
    let (ei, gj) = (b.ei(), b.gj());
    let tip = frames[nsub].2;
    let mut per_section = vec![0.0; n];
    for j in 0..nsub {
        let x = &e.strains[4 * j..4 * j + 4];
        let u = Vector3::new(x[0], x[1], x[2]);
        let g = shear(j);
        let v = Vector3::new(g[0], g[1], 1.0 + x[3]);
        let section = section_of(j);
        // Each cable's arm `r × ŵ` at `f` (0: beyond its end), and its derivative in the
        // strain, `[r]× (I − ŵŵᵀ) (−[r]×) / |w|` (`w = v + u × r + r'`).
        let arm = |c: usize, f: &Frame| {
            if !robot.cables[c].reaches_section(section) {
                return (Vector3::zeros(), Matrix3::zeros());
            }
            let rp = routes[c].eval(f.0, section - 1);
            let w = v + u.cross(&rp.r) + rp.dr;
            let (len, hat) = (w.norm(), w.normalize());
            let rx = rp.r.cross_matrix();
            let turn = -(rx * (Matrix3::identity() - hat * hat.transpose()) * rx) / len;
            (rp.r.cross(&hat), turn)
        };
        // The body-frame moment at `f` and the pull's derivative in the strain there.
        let moment = |f: &Frame| {
            let mut world = Vector3::zeros();
            for (sf, pf, force) in &loads {
                if *sf >= f.0 {
                    world += (pf - f.2).cross(force);
                }
            }
            let (mut pull, mut turn) = (Vector3::zeros(), Matrix3::zeros());
            for c in (0..routes.len()).filter(|&c| tensions[c] > 0.0) {
                let (a, d) = arm(c, f);
                pull += a * tensions[c];
                turn += d * tensions[c];
            }
            (pull - f.1.transpose() * world, turn)
        };
        let (m0, turn0) = moment(&frames[j]);
        let (m1, turn1) = moment(&frames[j + 1]);
        // The pull turns with the strain it bends (`r × (u × r)`): the rod answers a moment
        // change with `(K − ∂pull/∂u)⁻¹`, the derivative averaged over the sub-arc's ends.
        let stiff = Matrix3::from_diagonal(&Vector3::new(ei, ei, gj)) - 0.5 * (turn0 + turn1);
        let du = stiff
            .try_inverse()
            .ok_or("with a singular stiffness under the cables' pull")?
            * (m1 - m0);
        let l = ell(j);
        let mid = 0.5 * (frames[j].2 + frames[j + 1].2);
        let mut term = l * l / 12.0 * (du.x.hypot(du.y) + u.cross(&du).norm() * (tip - mid).norm());
        // The path's first-order change under the left-out strain `δu(s) · (r × ŵ)(s)`, times
        // the tip's pull per metre of that cable's shortening.
        for (c, pull) in driven.iter().enumerate() {
            if *pull > 0.0 {
                let turn = arm(c, &frames[j + 1]).0 - arm(c, &frames[j]).0;
                term += l / 12.0 * du.dot(&turn).abs() * pull;
            }
        }
        per_section[section - 1] += term;
    }
    if per_section.iter().all(|x| x.is_finite()) {
        Ok(per_section)
    } else {
        Err("with a non-finite term")
    }
}

/// Per cable, `|∂p_tip/∂shortening|` of the length-driven cables (0 for the others), from the
/// answer's Jacobian; `None` when a cable with a tension is neither in it as a shortening nor as
/// a tension (no Jacobian: solved with `sensitivity = off`).
fn length_driven(paths: &[&CablePath], jac: Option<&TipJacobian>) -> Option<Vec<f64>> {
    let mut out = vec![0.0; paths.len()];
    for (c, path) in paths.iter().enumerate() {
        if path.tension.unwrap_or(0.0) <= 0.0 {
            continue;
        }
        let col = jac?
            .inputs
            .iter()
            .position(|(name, _)| *name == path.name)?;
        if jac?.inputs[col].1 == "shortening" {
            out[c] = Vector3::from(*jac?.position.get(col)?).norm();
        }
    }
    Some(out)
}

/// The dead loads as the model applies them: the disks' weight at the disks, the backbone's
/// weight lumped half to each end of its sub-arc, the tip force at the tip; as (undeformed
/// arc length, position, force).
fn dead_loads(
    robot: &Robot,
    frames: &[Frame],
    first: &[usize],
) -> Vec<(f64, Vector3<f64>, Vector3<f64>)> {
    let l = &robot.loads;
    let nsub = frames.len() - 1;
    let mut out = vec![];
    if l.gravity != Vector3::zeros() {
        let line = robot.backbone.density * robot.backbone.area();
        for (j, f) in frames.iter().enumerate() {
            let before = if j > 0 { f.0 - frames[j - 1].0 } else { 0.0 };
            let after = frames.get(j + 1).map_or(0.0, |g| g.0 - f.0);
            let mut mass = 0.5 * line * (before + after);
            if j > 0 && first.binary_search(&j).is_ok() {
                mass += l.disk_mass;
            }
            if mass > 0.0 {
                out.push((f.0, f.2, l.gravity * mass));
            }
        }
    }
    if l.tip_force != Vector3::zeros() {
        out.push((frames[nsub].0, frames[nsub].2, l.tip_force));
    }
    out
}
