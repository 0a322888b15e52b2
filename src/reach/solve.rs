//! `reach`: the least-effort actuation within the limits that puts the tip on a target.
//!
//! # Problem
//!
//! ```text
//! min_u  E(u) = Σ_c u_c²                 (least effort: total squared cable displacement [m²])
//! s.t.   p_tip(u) = p*,  [t_tip(u) = t*]  lo ≤ u ≤ hi,  d(u) ≥ margin (unless contact allowed)
//! ```
//!
//! with `d` the clearance ([`super::clearance`]). The tangent residual is weighted by the
//! robot length `L` so that both residual blocks are in metres: `r = [p − p*; L (t − t*)]`.
//!
//! # Method: sequential QP on the sensitivities
//!
//! At an iterate `u` with residual `r` and Jacobian `J = ∂r/∂u` ([`super::sensitivity`]):
//!
//! * **step A** (reach and minimize effort): `min ½|u + δ|²` subject to the linearized
//!   targets on the row space of `J` (`J = U Σ Vᵀ`, singular values above `1e-9 σ_max`:
//!   `σ_i V_iᵀ δ = −U_iᵀ r`, so a redundant robot keeps its freedom and a robot with fewer
//!   cables than target components takes the Gauss–Newton step), the bounds, and, within
//!   [`CLEAR_BAND`] of the margin, the linearized clearance `d + ∇dᵀ δ ≥ margin`;
//! * **step B**, when A is infeasible (the target is out of reach under the limits or the
//!   obstacles): Levenberg–Marquardt `min ½|J δ + r|² + ½ μ |δ|²` under the same bounds
//!   and clearance rows: it ends at the closest reachable tip.
//!
//! Both QPs are solved by [`crate::numeric::qp::qp_dense`] (closed form when no inequality
//! binds, else clarabel). Slack cables are released rather than differentiated across, a
//! failed solve is a rejected step and an unsolvable start is moved towards the unactuated
//! robot (`reach/descend.rs`, one descent). Steps are
//! backtracked on the exact ℓ1 merit `E(u) + ν (|r| + max(0, margin − d))`, ν = [`MERIT_NU`]
//! m (above the multipliers: with shortenings of centimetres and tip gains of order one,
//! the price of the target in effort is ~1e-2 m), times [`Space::effort_scale`] in tension
//! space (the effort is then in N²). Several deterministic starts
//! ([`ReachOptions::starts`]: through a port, first the constant-curvature arc from the port
//! to the target; then every cable pulled a quarter of its range — through a port, at the
//! model's insertion, then all the way out —, the middle of the box, then a Kronecker sequence
//! through it) guard against local minima. Every descent keeps the best point it saw; an
//! unreachable target ends with the best of all (smallest residual, then least effort), its
//! distance, and the reason (which cables the closest answer has at a limit); when no answer
//! found can be solved as `ccrkit solve` does, the closest answer is the model's own port
//! command with every cable at rest.
//!
//! A descent that reaches is confirmed at once by solving its answer exactly as `ccrkit solve`
//! does (cold, through the one solve path: [`Space::solve_as_cli`]): the search ends only on an
//! answer that this solve reproduces (a warm-started descent can end where a cold solve from
//! the straight robot does not converge, or converges to another equilibrium; measured on the
//! random port robots). `tip_error_m`, the clearance and the tensions are measured on *that*
//! shape: a reported actuation reproduces the reported tip.

use super::answer::Reach;
use super::descend::{residual, Attempt, Ctx};
use super::sens::tip_tangent;
use super::Space;
use crate::error::SolveError;
use crate::method::run::SolveRequest;
use crate::model::Model;
use crate::shape::Shape;
use nalgebra::Vector3;

/// Clearance rows enter the step when the clearance is within this of the margin \[m\].
pub const CLEAR_BAND: f64 = 5e-3;
/// Weight of the residuals in the merit function \[m\].
pub const MERIT_NU: f64 = 1.0;

/// Where the tip should go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// Tip position, base frame \[m\].
    pub tip: Vector3<f64>,
    /// Tip tangent (the tip disk's normal), unit, if asked for.
    pub tangent: Option<Vector3<f64>>,
}

/// How to search.
#[derive(Debug, Clone, PartialEq)]
pub struct ReachOptions {
    /// Allow contact with the obstacles (solve with them) instead of keeping clear.
    pub allow_contact: bool,
    /// Reached when the residual `|r|` (tip error, plus `L ×` tangent error) is at most this
    /// \[m\].
    pub tolerance: f64,
    /// SQP iterations per start.
    pub max_iterations: usize,
    /// Starts tried before giving up (≥ 1; default 16: through a port, insertion and
    /// rotation add local minima — on seeded random port robots 8 starts missed 4 of 200
    /// forward-solved targets, 16 miss 2; a target reached stops the search, so only misses
    /// pay for them).
    pub starts: usize,
    /// Distance kept from the obstacles \[m\] (default: the scene's `clearance`).
    pub margin: Option<f64>,
}

impl Default for ReachOptions {
    fn default() -> Self {
        ReachOptions {
            allow_contact: false,
            tolerance: 1e-7,
            max_iterations: 60,
            starts: 16,
            margin: None,
        }
    }
}

/// Start `s` of the search: through a port in shortening space first the arc to the target
/// ([`arc_start`]), then the starts in the limits box ([`box_start`]).
fn start(space: &Space, target: &Target, s: usize) -> Vec<f64> {
    // Through a port (shortening space), the first start is the arc to the target.
    match (space.has_port() && !space.by_tension(), s) {
        (true, 0) => arc_start(space, target).unwrap_or_else(|| box_start(space, 0)),
        (true, s) => box_start(space, s - 1),
        (false, s) => box_start(space, s),
    }
}

/// The arc start through a port: the robot bent at one constant curvature, in one plane,
/// along the circular arc that leaves the port along its axis and ends at the target, inserted
/// by the arc's length. A cable's shortening is then `κ ℓ_c r_c cos(α_c − φ)`, `ℓ_c` the
/// length of its path beyond the port (a cable tied in the port: none), `φ` the target's
/// azimuth about the port axis at the model's rotation (the inextensible planar relation;
/// clamped to the limits). In a lumen such an arc follows the branch the target lies in far
/// more closely than a straight robot: measured on the generated airway's targets
/// (`examples/airway_benchmark.rs`), the descent from it ends on the target where the starts
/// in the box crossed the carina's wall. `None` for a target behind the port.
fn arc_start(space: &Space, target: &Target) -> Option<Vec<f64>> {
    let port = space.robot.port.as_ref()?;
    let k = space.cables();
    let psi = space.rest[k + 1].clamp(space.lo[k + 1], space.hi[k + 1]);
    let q = port
        .base_frame(psi)
        .inverse_transform_point(&nalgebra::Point3::from(target.tip));
    let (rho, z) = (q.x.hypot(q.y), q.z);
    if z.is_nan() || z <= 0.0 {
        return None;
    }
    // The arc tangent to the axis at the port turns by twice the chord's angle to the axis.
    let (chord, turn, phi) = (rho.hypot(z), 2.0 * rho.atan2(z), q.y.atan2(q.x));
    let (kappa, arc) = if turn < 1e-9 {
        (0.0, chord)
    } else {
        let radius = chord / (2.0 * (0.5 * turn).sin());
        (1.0 / radius, radius * turn)
    };
    let d = arc.clamp(space.lo[k], space.hi[k]);
    let robot = &space.robot;
    let len = robot.length();
    let mut u: Vec<f64> = (0..k)
        .map(|c| {
            let cable = &robot.cables[c];
            let h = cable.hole(0);
            let out = (robot.disk_s[cable.ends_at] - (len - d)).max(0.0);
            let u = kappa * out * (h.x * phi.cos() + h.y * phi.sin());
            u.clamp(space.lo[c], space.hi[c])
        })
        .collect();
    u.extend([d, psi]);
    Some(u)
}

/// Start `s` in the limits box: a quarter of the way up each cable's pulling range, then the
/// middle of the box, then a Kronecker sequence through it.
///
/// The first start pulls every cable (from `max(lo, 0)` a quarter towards `hi`): there every
/// cable is taut and the tip Jacobian has full rank. The middle of the default limits
/// (symmetric about zero) is the straight robot with every cable slack, where the tip does not
/// depend on the inputs and no step leaves it.
fn box_start(space: &Space, s: usize) -> Vec<f64> {
    // Through a port, the second start is the first with the robot all the way out.
    let s = match (space.has_port(), s) {
        (false, _) | (true, 0) => s,
        (true, 1) => {
            let mut u = box_start(space, 0);
            let k = space.cables();
            u[k] = space.hi[k];
            return u;
        }
        (true, s) => s - 1,
    };
    (0..space.dim())
        .map(|c| {
            let (lo, hi) = (space.lo[c], space.hi[c]);
            let f = match s {
                // The insertion and rotation start where the robot is.
                0 if c >= space.cables() => return space.rest[c],
                0 => {
                    let pull = lo.max(0.0).min(hi);
                    return pull + 0.25 * (hi - pull);
                }
                1 => 0.5,
                // Fractional parts of multiples of √(prime): equidistributed, deterministic.
                _ => {
                    let primes = [2.0f64, 3.0, 5.0, 7.0, 11.0, 13.0, 17.0, 19.0, 23.0, 29.0];
                    ((s - 1) as f64 * primes[c % primes.len()].sqrt() + 0.5 * c as f64).fract()
                }
            };
            lo + f * (hi - lo)
        })
        .collect()
}

/// Find the least-effort actuation of `model` (its limits, obstacles and those of
/// `request`, solved by `request`'s method) that puts the tip on `target`. Returns the answer
/// or the closest one found with `reached: false` ([`Reach::require_reached`] turns that into
/// [`SolveError::Unreachable`]); errors are bad input or a failed final solve.
pub fn reach(
    model: &Model,
    request: &SolveRequest,
    target: &Target,
    opts: &ReachOptions,
) -> Result<Reach, SolveError> {
    let space = Space::new(model, request, opts.allow_contact)?;
    reach_in(&space, model, target, opts)
}

/// [`reach`] in a prepared [`Space`].
pub fn reach_in(
    space: &Space,
    model: &Model,
    target: &Target,
    opts: &ReachOptions,
) -> Result<Reach, SolveError> {
    check_input(target, opts)?;
    let margin = opts.margin.unwrap_or(space.margin);
    let mut ctx = Ctx {
        space,
        target,
        opts,
        margin,
        len: model.robot.length(),
        solves: 0,
        exact: false,
        free: false,
        trust: 1.0,
    };
    let mut found: Vec<Attempt> = Vec::new();
    let (mut iterations, mut starts) = (0, 0);
    for s in 0..opts.starts {
        starts += 1;
        if let Some(a) = ctx.descend(&start(space, target, s)) {
            iterations += a.iterations;
            found.push(confirm(&mut ctx, model, a));
        }
        if found.iter().any(|a| a.res <= opts.tolerance) {
            break;
        }
    }
    // Keeping clear, every start may be stuck against the obstacles (a start whose shape
    // crosses a tube cannot move into it without passing through the wall): then the same
    // starts without the clearance, and a clear search from the first actuation that reaches
    // the target — if that one is clear, the search keeps it (its merit has no violation).
    if ctx.keep_clear() && !found.iter().any(|a| a.res <= opts.tolerance) {
        ctx.free = true;
        let mut seed = None;
        for s in 0..opts.starts {
            starts += 1;
            if let Some(a) = ctx.descend(&start(space, target, s)) {
                iterations += a.iterations;
                if a.res <= opts.tolerance {
                    seed = Some(a.u);
                    break;
                }
            }
        }
        ctx.free = false;
        if let Some(a) = seed.and_then(|u| ctx.descend(&u)) {
            iterations += a.iterations;
            let a = confirm(&mut ctx, model, a);
            let clear = a
                .cold
                .as_ref()
                .is_some_and(|sh| space.keeps_margin(sh, margin));
            if clear {
                found.push(a);
            }
        }
    }
    // Best first: the smallest residual, then the least effort. The first whose cold solve
    // (as `ccrkit solve` does) succeeds is the answer; a failed one is passed over, and when
    // every one fails, the model's own port command with every cable at rest (the closest
    // answer is then the robot as it stands).
    found.sort_by(|a, b| {
        let key = |x: &Attempt| (x.res.max(opts.tolerance * 1e-3), x.effort);
        key(a)
            .partial_cmp(&key(b))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let rest = space.clamp(&space.rest);
    found.push(Attempt {
        effort: space.effort(&rest),
        u: rest,
        res: f64::INFINITY,
        iterations: 0,
        cold: None,
    });
    let mut last = None;
    for mut best in found {
        let shape = match best.cold.take() {
            Some(shape) => Ok(shape),
            None => {
                ctx.solves += 1;
                space.solve_as_cli(model, &best.u)
            }
        };
        match shape {
            Ok(shape) => {
                return finish(
                    space,
                    target,
                    opts,
                    margin,
                    best,
                    shape,
                    (iterations, starts, ctx.solves, ctx.exact),
                )
            }
            Err(e) => last = Some(e),
        }
    }
    Err(last.unwrap_or_else(|| SolveError::InvalidInput {
        field: "target".into(),
        reason: format!(
            "no start of the search could be solved ({starts} starts, each also halved towards \
             the unactuated robot)"
        ),
    }))
}

/// An attempt that reached the target, confirmed by solving its answer as `ccrkit solve` does
/// (cold): its residual becomes that solve's (infinite when it fails), so an answer that only
/// a warm-started solve reproduces does not end the search. Others are returned as they are.
fn confirm(ctx: &mut Ctx<'_>, model: &Model, mut a: Attempt) -> Attempt {
    if a.res > ctx.opts.tolerance {
        return a;
    }
    ctx.solves += 1;
    match ctx.space.solve_as_cli(model, &a.u) {
        Ok(shape) => {
            a.res = residual(&shape, ctx.target, ctx.len).norm();
            a.cold = Some(shape);
        }
        Err(_) => a.res = f64::INFINITY,
    }
    a
}

fn check_input(target: &Target, opts: &ReachOptions) -> Result<(), SolveError> {
    let bad = |field: &str, reason: String| {
        Err(SolveError::InvalidInput {
            field: field.into(),
            reason,
        })
    };
    let t = target.tip;
    crate::model::bounds::COORDINATE.check3("tip", [t.x, t.y, t.z])?;
    if let Some(t) = target.tangent {
        if !(t.iter().all(|x| x.is_finite()) && (t.norm() - 1.0).abs() < 1e-9) {
            return bad("tangent", "must be a finite unit vector".into());
        }
    }
    crate::model::bounds::TIP_DISTANCE.check("tolerance", opts.tolerance)?;
    crate::counts::REACH_STARTS.check(opts.starts)?;
    crate::counts::REACH_ITERATIONS.check(opts.max_iterations)?;
    if let Some(m) = opts.margin {
        crate::model::bounds::CLEARANCE.check("margin", m)?;
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn finish(
    space: &Space,
    target: &Target,
    opts: &ReachOptions,
    margin: f64,
    best: Attempt,
    shape: Shape,
    (iterations, starts, solves, exact): (usize, usize, usize, bool),
) -> Result<Reach, SolveError> {
    let tip_error_m = (shape.tip() - target.tip).norm();
    let tangent_error_rad = target
        .tangent
        .map(|t| tip_tangent(&shape).dot(&t).clamp(-1.0, 1.0).acos());
    let res = residual(&shape, target, space.robot.length()).norm();
    let min_clearance_m = space.clearance(&shape).map(|c| c.distance);
    let mut reasons = Vec::new();
    if res > opts.tolerance {
        let at: Vec<String> = (0..space.dim())
            .filter_map(|c| {
                let (u, lo, hi) = (best.u[c], space.lo[c], space.hi[c]);
                let tol = 1e-9 * (hi - lo).max(1e-12);
                let cable_unit = if space.by_tension() { "N" } else { "m" };
                let (name, unit) = match space.robot.cables.get(c) {
                    Some(cable) => (format!("cable `{}`", cable.name), cable_unit),
                    None if c == space.cables() => ("the insertion".to_string(), "m"),
                    None => ("the rotation".to_string(), "rad"),
                };
                if u >= hi - tol {
                    Some(format!("{name} at its upper limit {hi} {unit}"))
                } else if u <= lo + tol {
                    Some(format!("{name} at its lower limit {lo} {unit}"))
                } else {
                    None
                }
            })
            .collect();
        reasons.push(format!(
            "closest residual {res:.3e} m after {starts} starts within the limits{}{}",
            if space.scene.is_empty() || opts.allow_contact {
                String::new()
            } else {
                format!(" keeping {margin} m clear of the obstacles")
            },
            if at.is_empty() {
                String::new()
            } else {
                format!(" (closest answer: {})", at.join(", "))
            }
        ));
    }
    if !opts.allow_contact {
        if let Some(c) = space.clearance(&shape) {
            if c.distance < margin - 1e-12 {
                reasons.push(format!(
                    "{} is {:.3e} m from `{}` (margin {margin} m)",
                    c.feature, c.distance, c.obstacle
                ));
            }
        }
    }
    if let Some(v) = space.tension_violation(&shape) {
        reasons.push(v);
    }
    let actuation = space.cable_actuation(&best.u, &shape);
    Ok(Reach {
        reached: reasons.is_empty(),
        target: *target,
        tip_error_m,
        tangent_error_rad,
        effort_m2: best.effort,
        insertion: space.port_of(&best.u).map(|p| p.0),
        rotation: space.port_of(&best.u).map(|p| p.1),
        u: best.u,
        actuation,
        min_clearance_m,
        shape,
        iterations,
        starts,
        solves,
        sensitivities: match (exact, space.has_port()) {
            (true, false) => "exact",
            (true, true) => "exact (insertion: central differences)",
            (false, _) => "finite-differences",
        },
        reason: reasons.join("; "),
        by_tension: space.by_tension(),
        made_for: crate::fingerprint::MadeFor {
            margin_m: margin,
            ..crate::fingerprint::MadeFor::of_space(space)
        },
    })
}
