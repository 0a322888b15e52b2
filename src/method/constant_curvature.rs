//! Constant curvature (`--method constant-curvature`): the closed form for straight, parallel
//! cables (Webster & Jones, IJRR 29(13) 2010, §3 "robot-specific mapping" for tendon robots).
//!
//! # Where it applies
//!
//! One bending section: every cable with an input runs straight (the same hole angle `φ_c` and
//! radius `r_c` at every disk) and is tied at the last disk; no obstacles. Anything else is an
//! [`SolveError::Unsupported`] that names the cable (helical or jumping routing, a radius that
//! changes, a cable tied at an inner disk). Disks may be unevenly spaced: the arc does not care.
//! Cables without an input are free and only reported.
//!
//! # The mapping
//!
//! Write the bending as the vector `u = κ (cos φ, sin φ)`: curvature `κ` in the bending plane at
//! angle `φ` (the backbone bends towards `φ`). On the arc a cable at `(r_c, φ_c)` is shorter
//! than the backbone by (Webster & Jones eq. 8, continuous cable along the arc)
//!
//! ```text
//! Δl_c(u) = r_c κ L cos(φ − φ_c) = a_c · u,      a_c = L r_c (cos φ_c, sin φ_c).
//! ```
//!
//! **Displacement input** `d_c` (shortening at the base, metres of the cable's undeformed
//! length). Cables pull and do not stretch: a cable's path may be shorter than the cable
//! (slack, `a_c·u > d_c`) but never longer (`a_c·u ≥ d_c`). With two or more cables these
//! conditions over-determine `u`; the reading taken here is the one of least bending energy
//! `EI L |u|²/2` among the shapes the cables allow:
//!
//! ```text
//! min |u − u_f|²   subject to   a_c · u ≥ d_c  (every displacement-driven cable)
//! ```
//!
//! (`u_f = 0` without tension inputs.) Its KKT conditions `EI (u − u_f) = Σ μ_c r_c ĉ_c`,
//! `μ_c ≥ 0`, say the multipliers are the cables' tensions — moment balance of the rod — so the
//! taut set is the active set and the tensions are reported. Two taut cables with independent
//! directions fix `u` exactly (the usual "two cables give κ and φ"); one taut cable fixes `u`
//! along its direction. The problem is two-dimensional, so the solver examines every active
//! set of at most two cables in closed form. No `u` at all (two opposite cables both pulled)
//! is [`SolveError::Infeasible`] naming a cable.
//!
//! **Force input** `τ_c`: moment balance `EI u = Σ τ_c r_c (cos φ_c, sin φ_c)` (Rucker &
//! Webster's Kirchhoff rod with straight tendons reduces to exactly this arc); that is `u_f`.
//! Mixed inputs combine as above. Which input a cable with both uses follows
//! [`Input`] (`control`) as for the rod (default: displacement, the kinematic mapping).
//!
//! # The shape
//!
//! Disks at their arc lengths on the arc, frames `R(s) = exp(s [κ b]×)` with the bending axis
//! `b = (−sin φ, cos φ, 0)`: no twist, disk normals tangent to the arc.

use crate::error::SolveError;
use crate::method::output::cable_paths;
use crate::method::settings::{common, Configure};
use crate::method::{Method, MethodKind, SolveInput};
use crate::model::actuation::{Drive, Input};
use crate::model::robot::Robot;
use crate::model::routing::{Route, RoutingFit};
use crate::numeric::so3::exp_so3;
use crate::shape::{DiskFrame, Shape, SolveReport};
use nalgebra::{Matrix2, Vector2, Vector3};

/// Largest hole-angle change \[rad\] (and relative radius change) still read as a straight cable.
pub const STRAIGHT_TOL: f64 = 1e-9;

/// Settings of the constant-curvature method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConstantCurvature {
    /// Which input drives a cable that has both.
    pub control: Input,
}

impl Default for ConstantCurvature {
    fn default() -> Self {
        ConstantCurvature {
            control: Input::Shortening,
        }
    }
}

impl ConstantCurvature {
    /// Displacement input first (the kinematic mapping; `constant-curvature`).
    pub fn displacement() -> Self {
        Self::default()
    }
    /// Tension input first (moment balance).
    pub fn force() -> Self {
        ConstantCurvature {
            control: Input::Tension,
        }
    }
}

/// Position and rotation on the arc of bending vector `u` (body frame) at arc length `s`.
fn arc_frame(u: &Vector2<f64>, s: f64) -> (Vector3<f64>, nalgebra::Matrix3<f64>) {
    let kappa = u.norm();
    let (c, sn) = if kappa > 0.0 {
        (u.x / kappa, u.y / kappa)
    } else {
        (1.0, 0.0)
    };
    let t = kappa * s;
    let sinc = |x: f64| {
        if x.abs() < 1e-8 {
            1.0 - x * x / 6.0
        } else {
            x.sin() / x
        }
    };
    let inplane = s * (t / 2.0) * sinc(t / 2.0).powi(2); // (1 − cos κs)/κ
    let z = s * sinc(t);
    let p = Vector3::new(inplane * c, inplane * sn, z);
    let axis = Vector3::new(-sn, c, 0.0) * t;
    (p, exp_so3(&axis))
}

impl Configure for ConstantCurvature {
    fn set(&mut self, name: &str, value: &str) -> Result<(), SolveError> {
        let range = self.kind().setting(name)?.values;
        match name {
            "control" => self.control = range.pick(name, value, common::CONTROL_INPUTS)?,
            _ => return Err(self.kind().unapplied(name)),
        }
        Ok(())
    }

    /// Its one setting, `control`, is an [`Input`]: every value is valid.
    fn check(&self) -> Result<(), SolveError> {
        Ok(())
    }
}

impl Method for ConstantCurvature {
    fn kind(&self) -> MethodKind {
        MethodKind::ConstantCurvature
    }

    fn solve_supported(&self, input: SolveInput<'_>) -> Result<Shape, SolveError> {
        let (robot, act) = (input.robot, input.act);
        let name = self.name().to_string();
        let drives = self.kind().drives(robot, act, self.control)?;
        let n = robot.sections();
        let len = robot.length();
        let ei = robot.backbone.ei();
        let mut notes = vec![
            "cable shortening read along the arc (Webster & Jones): Δl = r κ L cos(φ − φ_c)"
                .to_string(),
        ];
        // Rows of the displacement constraints: (cable, a_c, d_c).
        let mut rows: Vec<(usize, Vector2<f64>, f64)> = vec![];
        let mut u_f = Vector2::zeros();
        let mut tensions: Vec<Option<f64>> = vec![None; robot.cables.len()];
        for (c, &drive) in drives.iter().enumerate() {
            if drive == Drive::Free {
                continue;
            }
            let (r0, a0) = straight_cable(&name, robot, c)?;
            let dir = Vector2::new(a0.cos(), a0.sin());
            if let Drive::Tension(tau) = drive {
                u_f += dir * (tau * r0 / ei);
                tensions[c] = Some(tau);
            } else if let Drive::Shorten { length: d, .. } = drive {
                if d >= len {
                    return Err(SolveError::InvalidInput {
                        field: format!("cables[{c}].shorten"),
                        reason: format!("shortening {d} m is not below the cable length"),
                    });
                }
                rows.push((c, dir * (len * r0), d));
            }
        }
        let (u, active) = least_bending(&u_f, &rows).map_err(|c| SolveError::Infeasible {
            cable: robot.cables[c].name.clone(),
            section: n,
            reason: "no arc shortens this cable as much as asked while the other pulled cables stay no longer than their lengths".into(),
        })?;
        // Tensions of the taut displacement cables: EI (u − u_f) = Σ μ_c r_c ĉ_c.
        let mus = multipliers(&(ei * (u - u_f)), &active, &rows, len);
        let mut residual = 0.0f64;
        let mut slack_sections: Vec<Vec<usize>> = vec![vec![]; robot.cables.len()];
        for (j, (c, a, d)) in rows.iter().enumerate() {
            let g = a.dot(&u);
            if let Some(k) = active.iter().position(|&x| x == j) {
                residual = residual.max((g - d).abs());
                tensions[*c] = Some(mus[k].max(0.0));
            } else {
                slack_sections[*c] = (1..=robot.cables[*c].ends_at).collect();
                tensions[*c] = Some(0.0);
            }
        }
        let (disks, backbone) = arc_shape(robot, &u);
        let mut cables = cable_paths(robot, &disks, &slack_sections);
        for (c, (path, t)) in cables.iter_mut().zip(&tensions).enumerate() {
            path.tension = *t;
            path.shortening = Some(arc_shortening(robot, c, &u)?);
        }
        notes.push(format!(
            "curvature {:.6} 1/m, bending plane {:.6} rad",
            u.norm(),
            u.y.atan2(u.x)
        ));
        Ok(Shape {
            method: name,
            disks,
            backbone,
            cables,
            contacts: vec![],
            port: None,
            report: SolveReport {
                converged: true,
                iterations: 1,
                residual,
                solve_time_s: 0.0, // filled in by `Method::solve`
                notes,
                ..SolveReport::default()
            },
        })
    }
}

/// Gauss–Legendre nodes on [0, 1] and weights, 5 points (exact to degree 9).
const GAUSS5: [(f64, f64); 5] = [
    (0.046_910_077_030_668, 0.118_463_442_528_094_5),
    (0.230_765_344_947_158_5, 0.239_314_335_249_683_2),
    (0.5, 0.284_444_444_444_444_4),
    (0.769_234_655_052_841_5, 0.239_314_335_249_683_2),
    (0.953_089_922_969_332, 0.118_463_442_528_094_5),
];

/// Path shortening of cable `c` on the arc of bending `u = κ (cos φ, sin φ)`: its route `r(s)`
/// (body frame, [`Route`]) runs at `|ẑ + ω × r + r'|` per unit arc with `ω = κ (−sin φ, cos φ,
/// 0)`, against `|ẑ + r'|` straight. For a straight cable the rates are constant and this is
/// exactly `a_c · u` (module docs); a free helical one is integrated by 5-point Gauss–Legendre
/// per section (its rate is smooth inside a section).
fn arc_shortening(robot: &Robot, c: usize, u: &Vector2<f64>) -> Result<f64, SolveError> {
    let route = Route::new(robot, c, RoutingFit::Spline)?;
    let omega = Vector3::new(-u.y, u.x, 0.0);
    let mut change = 0.0;
    for i in 1..=robot.cables[c].ends_at {
        let (s0, l) = (robot.disk_s[i - 1], robot.section_length(i));
        for (x, w) in GAUSS5 {
            let p = route.eval(s0 + x * l, i - 1);
            let straight = (Vector3::z() + p.dr).norm();
            let bent = (Vector3::z() + omega.cross(&p.r) + p.dr).norm();
            change += w * l * (straight - bent);
        }
    }
    Ok(change)
}

/// Hole radius and angle of a driven cable that one constant-curvature section can carry:
/// tied at the last disk, same angle and radius at every disk; otherwise `Unsupported`.
fn straight_cable(method: &str, robot: &Robot, c: usize) -> Result<(f64, f64), SolveError> {
    let cable = &robot.cables[c];
    let n = robot.sections();
    let unsupported = |reason: String| SolveError::Unsupported {
        method: method.into(),
        reason,
    };
    if cable.ends_at != n {
        return Err(unsupported(format!(
            "cable `{}` is tied at inner disk {} (one constant-curvature section needs every driven cable tied at disk {n})",
            cable.name, cable.ends_at
        )));
    }
    let (r0, a0) = (cable.radius[0], cable.angle[0]);
    for k in 1..=cable.ends_at {
        let da = cable.angle[k] - a0;
        let wrapped = da.sin().atan2(da.cos());
        if wrapped.abs() > STRAIGHT_TOL {
            return Err(unsupported(format!(
                "cable `{}` is not straight: its hole angle changes by {:.4} rad between disks 0 and {k}",
                cable.name, wrapped
            )));
        }
        if (cable.radius[k] - r0).abs() > STRAIGHT_TOL * r0.abs().max(1e-3) {
            return Err(unsupported(format!(
                "cable `{}` changes its hole radius ({} m at disk 0, {} m at disk {k})",
                cable.name, r0, cable.radius[k]
            )));
        }
    }
    Ok((r0, a0))
}

/// Disk frames at their arc lengths and 8 backbone samples per section on the arc of bending
/// vector `u`.
fn arc_shape(robot: &Robot, u: &Vector2<f64>) -> (Vec<DiskFrame>, Vec<Vector3<f64>>) {
    let n = robot.sections();
    let disks = robot
        .disk_s
        .iter()
        .map(|&s| {
            let (position, rotation) = arc_frame(u, s);
            DiskFrame {
                s,
                position,
                rotation,
            }
        })
        .collect();
    let mut backbone = Vec::with_capacity(8 * n + 1);
    for i in 1..=n {
        let (s0, s1) = (robot.disk_s[i - 1], robot.disk_s[i]);
        for j in 0..8 {
            backbone.push(arc_frame(u, s0 + (s1 - s0) * j as f64 / 8.0).0);
        }
    }
    backbone.push(arc_frame(u, robot.length()).0);
    (disks, backbone)
}

/// `min |u − u0|²` subject to `a_j · u ≥ d_j`, by enumerating the active sets of at most two
/// rows (the optimum of a 2-D strictly convex QP has one). Returns `u` and the active rows, or
/// the cable of a row no candidate satisfies.
fn least_bending(
    u0: &Vector2<f64>,
    rows: &[(usize, Vector2<f64>, f64)],
) -> Result<(Vector2<f64>, Vec<usize>), usize> {
    let scale = rows
        .iter()
        .map(|(_, a, d)| a.norm() * u0.norm() + d.abs())
        .fold(1e-12, f64::max);
    let tol = 1e-12 * scale;
    let feasible = |u: &Vector2<f64>| rows.iter().all(|(_, a, d)| a.dot(u) >= d - tol);
    let mut best: Option<(f64, Vector2<f64>, Vec<usize>)> = None;
    let mut consider = |u: Vector2<f64>, set: Vec<usize>| {
        if u.iter().all(|x| x.is_finite()) && feasible(&u) {
            let cost = (u - u0).norm_squared();
            if best.as_ref().is_none_or(|(b, _, _)| cost < *b - 1e-30) {
                best = Some((cost, u, set));
            }
        }
    };
    consider(*u0, vec![]);
    for (j, (_, a, d)) in rows.iter().enumerate() {
        let aa = a.norm_squared();
        if aa > 0.0 {
            consider(u0 + a * ((d - a.dot(u0)) / aa), vec![j]);
        }
    }
    for j in 0..rows.len() {
        for k in j + 1..rows.len() {
            let m = Matrix2::new(rows[j].1.x, rows[j].1.y, rows[k].1.x, rows[k].1.y);
            let det = m.determinant();
            let norm = rows[j].1.norm() * rows[k].1.norm();
            if det.abs() > 1e-9 * norm {
                if let Some(inv) = m.try_inverse() {
                    consider(inv * Vector2::new(rows[j].2, rows[k].2), vec![j, k]);
                }
            }
        }
    }
    match best {
        Some((_, u, mut set)) => {
            // Keep only rows that are tight (a row can be tight without being in the set).
            for (j, (_, a, d)) in rows.iter().enumerate() {
                if !set.contains(&j) && (a.dot(&u) - d).abs() <= tol {
                    set.push(j);
                }
            }
            Ok((u, set))
        }
        None => {
            // Name the cable asked to shorten the most relative to its lever.
            let worst = rows
                .iter()
                .max_by(|x, y| (x.2 / x.1.norm()).total_cmp(&(y.2 / y.1.norm())))
                .map(|r| r.0)
                .unwrap_or(0);
            Err(worst)
        }
    }
}

/// Least-squares tensions of the active rows: `m = Σ μ_k r_k ĉ_k` with `r_k ĉ_k = a_k / L`.
fn multipliers(
    m: &Vector2<f64>,
    active: &[usize],
    rows: &[(usize, Vector2<f64>, f64)],
    len: f64,
) -> Vec<f64> {
    match active.len() {
        0 => vec![],
        1 => {
            let b = rows[active[0]].1 / len;
            vec![m.dot(&b) / b.norm_squared().max(1e-300)]
        }
        _ => {
            // Two independent directions fix the tensions; extra tight rows get the
            // minimum-norm split (pseudo-inverse).
            let b = nalgebra::DMatrix::from_fn(2, active.len(), |i, k| rows[active[k]].1[i] / len);
            let rhs = nalgebra::DVector::from_column_slice(m.as_slice());
            match b.clone().svd(true, true).solve(&rhs, 1e-14) {
                Ok(x) => x.iter().copied().collect(),
                Err(_) => vec![0.0; active.len()],
            }
        }
    }
}
