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
//! binds, else clarabel). Steps are
//! backtracked on the exact ℓ1 merit `E(u) + ν (|r| + max(0, margin − d))`, ν = [`MERIT_NU`]
//! m (above the multipliers: with shortenings of centimetres and tip gains of order one,
//! the price of the target in effort is ~1e-2 m). Several deterministic starts
//! ([`ReachOptions::starts`]: every cable pulled a quarter of its range, the middle of the box,
//! then a Kronecker sequence through it)
//! guard against local minima; the first that reaches wins.
//!
//! The answer is finally solved again exactly as `ccrkit solve` does (cold, through the one
//! solve path: [`Space::solve_as_cli`]), and `tip_error_m`, the clearance and the tensions are
//! measured on *that* shape: a reported actuation reproduces the reported tip.

use super::answer::{CableActuation, Reach};
use super::sens::tip_tangent;
use super::{sensitivity, Space};
use crate::error::SolveError;
use crate::method::run::SolveRequest;
use crate::model::Model;
use crate::numeric::qp::qp_dense;
use crate::shape::Shape;
use nalgebra::{DMatrix, DVector, Vector3};

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
    /// Starts tried before giving up (≥ 1).
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
            starts: 8,
            margin: None,
        }
    }
}

/// Residual `[p − p*; L (t − t*)]` of a shape.
fn residual(shape: &Shape, target: &Target, len: f64) -> DVector<f64> {
    let dp = shape.tip() - target.tip;
    match target.tangent {
        None => DVector::from_column_slice(dp.as_slice()),
        Some(t) => {
            let dt = (tip_tangent(shape) - t) * len;
            DVector::from_column_slice(&[dp.x, dp.y, dp.z, dt.x, dt.y, dt.z])
        }
    }
}

struct Attempt {
    u: Vec<f64>,
    res: f64,
    effort: f64,
    iterations: usize,
}

/// An accepted line-search point: actuation, shape, merit, residual, converged.
type Trial = (Vec<f64>, Shape, f64, f64, bool);

struct Ctx<'a> {
    space: &'a Space,
    target: &'a Target,
    opts: &'a ReachOptions,
    margin: f64,
    len: f64,
    solves: usize,
    exact: bool,
    /// Search without the clearance (the fallback of [`reach_in`]).
    free: bool,
}

impl Ctx<'_> {
    fn keep_clear(&self) -> bool {
        !self.free && !self.opts.allow_contact && !self.space.scene.is_empty()
    }

    fn merit(&self, u: &[f64], shape: &Shape) -> (f64, f64) {
        let r = residual(shape, self.target, self.len).norm();
        let viol = if self.keep_clear() {
            self.space
                .clearance(shape)
                .map_or(0.0, |c| (self.margin - c.distance).max(0.0))
        } else {
            0.0
        };
        let e: f64 = u.iter().map(|x| x * x).sum();
        (e + MERIT_NU * (r + viol), r)
    }

    /// The step at `u` (A, else B), or `None` when neither QP solves.
    fn step(&mut self, u: &[f64], shape: &Shape) -> Result<Option<Vec<f64>>, SolveError> {
        let k = u.len();
        let clear = if self.keep_clear() {
            self.space.clearance(shape).map(|c| c.distance)
        } else {
            None
        };
        let near = clear.is_some_and(|d| d < self.margin + CLEAR_BAND);
        let s = sensitivity(self.space, u, shape, near)?;
        self.solves += if s.exact && !near { 0 } else { 2 * k };
        self.exact = s.exact;
        let r = residual(shape, self.target, self.len);
        let jac = if self.target.tangent.is_some() {
            let mut j = DMatrix::zeros(6, k);
            j.rows_mut(0, 3).copy_from(&s.position);
            j.rows_mut(3, 3).copy_from(&(s.tangent * self.len));
            j
        } else {
            s.position
        };
        // Inequalities: bounds, then the linearized clearance.
        let mut rows: Vec<Vec<f64>> = Vec::new();
        let mut rhs = Vec::new();
        for c in 0..k {
            let mut e = vec![0.0; k];
            e[c] = 1.0;
            rows.push(e.clone());
            rhs.push(self.space.hi[c] - u[c]);
            e[c] = -1.0;
            rows.push(e);
            rhs.push(u[c] - self.space.lo[c]);
        }
        if let (Some(g), Some(d)) = (&s.clearance, clear) {
            rows.push(g.iter().map(|x| -x).collect());
            rhs.push(d - self.margin);
        }
        let gm = DMatrix::from_fn(rows.len(), k, |i, j| rows[i][j]);
        // Step A: least effort on the linearized targets.
        let svd = jac.clone().svd(true, true);
        let (uu, vt) = match (&svd.u, &svd.v_t) {
            (Some(a), Some(b)) => (a, b),
            _ => return Ok(None),
        };
        let smax = svd.singular_values.max();
        let keep: Vec<usize> = (0..svd.singular_values.len())
            .filter(|&i| svd.singular_values[i] > 1e-9 * smax && smax > 0.0)
            .collect();
        let eq = DMatrix::from_fn(keep.len(), k, |i, j| {
            svd.singular_values[keep[i]] * vt[(keep[i], j)]
        });
        let eb: Vec<f64> = keep.iter().map(|&i| -uu.column(i).dot(&r)).collect();
        let h = DMatrix::identity(k, k) * 2.0;
        let g: Vec<f64> = u.iter().map(|x| 2.0 * x).collect();
        if let Some(d) = qp_dense(&h, &g, (&eq, &eb), (&gm, &rhs)) {
            return Ok(Some(d));
        }
        // Step B: Levenberg–Marquardt towards the closest reachable tip.
        let jtj = jac.transpose() * &jac;
        let mu = 1e-9 * jtj.trace().max(1e-12) / k as f64;
        let h = jtj + DMatrix::identity(k, k) * mu;
        let g: Vec<f64> = (jac.transpose() * &r).iter().copied().collect();
        let none = DMatrix::zeros(0, k);
        Ok(qp_dense(&h, &g, (&none, &[]), (&gm, &rhs)))
    }

    /// Backtracking line search along `du` from `(u, shape)` with merit `phi`: the first
    /// `u + α du` (α = 1, ½, … > 1e-4) that lowers the merit, with its shape, merit, residual
    /// and whether it converged (moved < 1e-13, or on target and no longer gaining).
    fn line_search(&mut self, u: &[f64], shape: &Shape, phi: f64, du: &[f64]) -> Option<Trial> {
        let mut alpha = 1.0;
        while alpha > 1e-4 {
            let un: Vec<f64> = self.space.clamp(
                &u.iter()
                    .zip(du)
                    .map(|(a, b)| a + alpha * b)
                    .collect::<Vec<_>>(),
            );
            self.solves += 1;
            if let Ok(sn) = self.space.solve(&un, Some(shape)) {
                let (pn, rn) = self.merit(&un, &sn);
                if pn < phi {
                    let moved = un
                        .iter()
                        .zip(u)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max);
                    let done =
                        moved < 1e-13 || (rn <= self.opts.tolerance * 1e-2 && phi - pn < 1e-16);
                    return Some((un, sn, pn, rn, done));
                }
            }
            alpha *= 0.5;
        }
        None
    }

    fn descend(&mut self, u0: &[f64]) -> Result<Attempt, SolveError> {
        let mut u = self.space.clamp(u0);
        let mut shape = self.space.solve(&u, None)?;
        self.solves += 1;
        let (mut phi, mut res) = self.merit(&u, &shape);
        let mut it = 0;
        while it < self.opts.max_iterations {
            it += 1;
            let Some(du) = self.step(&u, &shape)? else {
                break;
            };
            // A step this small moves nothing (converged, or stalled where every cable is
            // slack and the tip does not depend on the inputs): no line search for it.
            if du.iter().all(|d| d.abs() < 1e-13) {
                break;
            }
            let mut trial = self.line_search(&u, &shape, phi, &du);
            // A slack cable moves only to save effort (the tip does not depend on it), and a
            // full such step can cross the point where it turns taut, which no shorter step of
            // the line search avoids when the answer has it just taut: then the step without
            // the slack cables' moves.
            let slack: Vec<bool> = shape
                .cables
                .iter()
                .map(|c| c.slack || c.tension == Some(0.0))
                .collect();
            if trial.is_none() && du.iter().zip(&slack).any(|(d, s)| *s && *d != 0.0) {
                let taut: Vec<f64> = du
                    .iter()
                    .zip(&slack)
                    .map(|(d, s)| if *s { 0.0 } else { *d })
                    .collect();
                if taut.iter().any(|d| d.abs() >= 1e-13) {
                    trial = self.line_search(&u, &shape, phi, &taut);
                }
            }
            let Some((un, sn, pn, rn, done)) = trial else {
                break;
            };
            (u, shape, phi, res) = (un, sn, pn, rn);
            if done {
                break;
            }
        }
        let effort = u.iter().map(|x| x * x).sum();
        Ok(Attempt {
            u,
            res,
            effort,
            iterations: it,
        })
    }
}

/// Start `s` of the search: a quarter of the way up each cable's pulling range, then the
/// middle of the box, then a Kronecker sequence through it.
///
/// The first start pulls every cable (from `max(lo, 0)` a quarter towards `hi`): there every
/// cable is taut and the tip Jacobian has full rank. The middle of the default limits
/// (symmetric about zero) is the straight robot with every cable slack, where the tip does not
/// depend on the inputs and no step leaves it.
fn start(space: &Space, s: usize) -> Vec<f64> {
    (0..space.dim())
        .map(|c| {
            let (lo, hi) = (space.lo[c], space.hi[c]);
            let f = match s {
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
    };
    let mut best: Option<Attempt> = None;
    let (mut iterations, mut starts) = (0, 0);
    let mut consider = |a: Attempt, best: &mut Option<Attempt>| {
        iterations += a.iterations;
        let better = best.as_ref().is_none_or(|b| {
            a.res < b.res - 1e-12 || (a.res <= b.res + 1e-12 && a.effort < b.effort)
        });
        if better {
            *best = Some(a);
        }
    };
    for s in 0..opts.starts {
        starts += 1;
        if let Ok(a) = ctx.descend(&start(space, s)) {
            consider(a, &mut best);
        }
        if best.as_ref().is_some_and(|b| b.res <= opts.tolerance) {
            break;
        }
    }
    // Keeping clear, every start may be stuck against the obstacles (a start whose shape
    // crosses a tube cannot move into it without passing through the wall): then the same
    // starts without the clearance, and a clear search from the first actuation that reaches
    // the target — if that one is clear, the search keeps it (its merit has no violation).
    if ctx.keep_clear() && best.as_ref().is_none_or(|b| b.res > opts.tolerance) {
        ctx.free = true;
        let mut seed = None;
        for s in 0..opts.starts {
            starts += 1;
            if let Ok(a) = ctx.descend(&start(space, s)) {
                if a.res <= opts.tolerance {
                    seed = Some(a.u);
                    break;
                }
            }
        }
        ctx.free = false;
        if let Some(Ok(a)) = seed.map(|u| ctx.descend(&u)) {
            ctx.solves += 1;
            let clear = space
                .solve(&a.u, None)
                .ok()
                .is_some_and(|sh| space.clearance(&sh).is_none_or(|c| c.distance >= margin));
            if clear {
                consider(a, &mut best);
            }
        }
    }
    let best = best.ok_or_else(|| SolveError::InvalidInput {
        field: "target".into(),
        reason: "no start of the search could be solved".into(),
    })?;
    let shape = space.solve_as_cli(model, &best.u)?;
    ctx.solves += 1;
    finish(
        space,
        model,
        target,
        opts,
        margin,
        best,
        shape,
        (iterations, starts, ctx.solves, ctx.exact),
    )
}

fn check_input(target: &Target, opts: &ReachOptions) -> Result<(), SolveError> {
    let bad = |field: &str, reason: String| {
        Err(SolveError::InvalidInput {
            field: field.into(),
            reason,
        })
    };
    if target.tip.iter().any(|x| !x.is_finite()) {
        return bad(
            "tip",
            format!("must be finite, got {:?}", target.tip.as_slice()),
        );
    }
    if let Some(t) = target.tangent {
        if !(t.iter().all(|x| x.is_finite()) && (t.norm() - 1.0).abs() < 1e-9) {
            return bad("tangent", "must be a finite unit vector".into());
        }
    }
    if !(opts.tolerance.is_finite() && opts.tolerance > 0.0) {
        return bad("tolerance", format!("must be > 0, got {}", opts.tolerance));
    }
    if opts.starts == 0 || opts.max_iterations == 0 {
        return bad("starts", "starts and max_iterations must be ≥ 1".into());
    }
    if let Some(m) = opts.margin {
        if !(m.is_finite() && m >= 0.0) {
            return bad("margin", format!("must be finite and ≥ 0, got {m}"));
        }
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn finish(
    space: &Space,
    _model: &Model,
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
        reasons.push(format!(
            "closest residual {res:.3e} m after {starts} starts within the shortening limits{}",
            if space.scene.is_empty() || opts.allow_contact {
                String::new()
            } else {
                format!(" keeping {margin} m clear of the obstacles")
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
    let actuation = space
        .robot
        .cables
        .iter()
        .enumerate()
        .map(|(c, cable)| CableActuation {
            cable: cable.name.clone(),
            shorten: best.u[c],
            tension: shape.cables.get(c).and_then(|p| p.tension),
        })
        .collect();
    Ok(Reach {
        reached: reasons.is_empty(),
        target: *target,
        tip_error_m,
        tangent_error_rad,
        effort_m2: best.effort,
        u: best.u,
        actuation,
        min_clearance_m,
        shape,
        iterations,
        starts,
        solves,
        sensitivities: if exact { "exact" } else { "finite-differences" },
        reason: reasons.join("; "),
    })
}
