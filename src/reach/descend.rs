//! One descent of [`super::reach`]'s search from one start: the sequential QP of
//! `reach/solve.rs` with released cables, rejected steps, and the best point kept.
//!
//! # Slack cables: released, not differentiated across
//!
//! (Shortenings only: in tension space the tip is smooth in the tensions, a slack cable is one
//! at zero tension, a bound of the QPs, and nothing is released.)
//!
//! A cable pulls and never pushes, so the tip is a *kinked* function of the shortenings: a
//! cable whose path comes out longer than its length minus `u` is slack, and the tip does not
//! depend on its `u` until it turns taut. The least-effort answer lies on such kinks more often
//! than not (the cable opposite a bend is paid out exactly as far as its path lengthens, and no
//! farther: taut at zero tension). A Newton step computed with that cable taut assumes it keeps
//! pulling; when the step turns it slack, the tip does not go where the step predicted, the
//! line search accepts only slivers of the step, and the search stalls micrometres from the
//! target (measured: 6 of 30 forward-solved targets of a four-cable, two-segment helical robot,
//! 12 µm–1.1 mm away after 8 starts, the answer's pulled-in cable at 9e-9 m with a tension of
//! 3e-3 N). So each iterate carries a set of *released* cables:
//!
//! * a released cable is solved free (no input: slack, it follows the shape) and its input is
//!   reported as its least-effort slack value: `min(clamp(0, lo, hi), s)` with `s` the change of
//!   its path length the solve reports (any `u ≤ s` leaves it slack and the shape unchanged);
//! * a driven cable that comes out slack is released (same shape, less effort);
//! * a driven cable that the full step turns slack is released at the current point (the
//!   shape changes: the descent goes on from there, and the best point seen is kept, so the
//!   search never ends worse than without it; at most [`MAX_SWITCHES`] per descent);
//! * a released cable is driven again when its slack value would pay it out beyond its lower
//!   limit, and, when the driven cables cannot reach the target (step A infeasible), every
//!   released cable is driven again just taut (`u = s`, then a step of the others), once per
//!   descent.
//!
//! # Trust region
//!
//! Through a port, a step moves each unknown by at most a fraction of its range
//! ([`TRUST_START`] at a start, doubled after every full step up to the whole range): a bound
//! row of both QPs (without a port the whole range, as the search was tuned). The first
//! Gauss–Newton step from a start is linearized far from the target, and without the bound it
//! often ran the insertion to a limit in one stride (a target beside the port asks the tip to
//! come back, and retracting does that first), where the descent stalled. Measured on the
//! random port robots (`examples/reach_random_ports.rs`, seeds 1–200): 185 → 191 of 200
//! reached.
//!
//! # Rejected steps
//!
//! A trial whose solve fails (no converged shape, or one that passes through itself: the
//! output check of every solve) is a rejected step: the line search halves it. A start that
//! cannot be solved is moved towards the unactuated robot (halving the inputs, at most
//! [`START_BACKOFF`] times). A failed sensitivity ends this descent with the best point it found.

use super::sens::{sensitivity_with, tip_tangent};
use super::solve::{ReachOptions, Target, CLEAR_BAND, MERIT_NU};
use super::Space;
use crate::numeric::qp::qp_dense;
use crate::shape::Shape;
use nalgebra::{DMatrix, DVector};

/// Most release/drive switches of one descent (times the number of cables).
pub const MAX_SWITCHES: usize = 2;
/// The trust region a descent starts with: a step moves each unknown by at most this fraction
/// of its range (module docs, "Trust region").
pub const TRUST_START: f64 = 0.1;
/// Times a start whose solve fails is halved towards the unactuated robot.
pub const START_BACKOFF: usize = 4;

/// Residual `[p − p*; L (t − t*)]` of a shape.
pub(super) fn residual(shape: &Shape, target: &Target, len: f64) -> DVector<f64> {
    let dp = shape.tip() - target.tip;
    match target.tangent {
        None => DVector::from_column_slice(dp.as_slice()),
        Some(t) => {
            let dt = (tip_tangent(shape) - t) * len;
            DVector::from_column_slice(&[dp.x, dp.y, dp.z, dt.x, dt.y, dt.z])
        }
    }
}

/// The best point of a descent.
pub(super) struct Attempt {
    pub u: Vec<f64>,
    pub res: f64,
    pub effort: f64,
    pub iterations: usize,
    /// The shape at `u` solved as `ccrkit solve` does, once confirmed (`reach/solve.rs`).
    pub cold: Option<Shape>,
}

/// An iterate: inputs (every cable driven; a slack one at its least-effort slack value),
/// shape, merit, residual.
#[derive(Clone)]
struct Point {
    u: Vec<f64>,
    /// Cables solved free (first phase of a descent, module docs).
    released: Vec<bool>,
    shape: Shape,
    phi: f64,
    res: f64,
    effort: f64,
}

impl Point {
    fn better_than(&self, b: &Point) -> bool {
        self.res < b.res - 1e-12 || (self.res <= b.res + 1e-12 && self.effort < b.effort)
    }
}

/// The search's context: space, target, options, counters.
pub(super) struct Ctx<'a> {
    pub space: &'a Space,
    pub target: &'a Target,
    pub opts: &'a ReachOptions,
    pub margin: f64,
    pub len: f64,
    pub solves: usize,
    pub exact: bool,
    /// Search without the clearance (the fallback of `reach_in`).
    pub free: bool,
    /// Trust region of the current descent: a step moves each unknown by at most this
    /// fraction of its range (module docs, "Trust region").
    pub trust: f64,
}

/// True when `shape`'s cable `c` pulls nothing (slack, or at zero tension).
fn slack(shape: &Shape, c: usize) -> bool {
    shape
        .cables
        .get(c)
        .is_some_and(|p| p.tension == Some(0.0) || (p.tension.is_none() && p.slack))
}

impl Ctx<'_> {
    pub fn keep_clear(&self) -> bool {
        !self.free && !self.opts.allow_contact && !self.space.scene.is_empty()
    }

    /// Whether the grids' bounds prove `shape` at least `cap` from every obstacle (then
    /// [`Space::clearance_below`] of `cap` is `None` too, with no exact query).
    fn keeps_by_grid(&self, shape: &Shape, cap: f64) -> bool {
        self.space
            .clearance_bounds(shape)
            .is_some_and(|b| b.keeps(cap) == Some(true))
    }

    fn merit(&self, u: &[f64], shape: &Shape) -> (f64, f64) {
        let r = residual(shape, self.target, self.len).norm();
        let viol = if self.keep_clear() {
            // Only a shape within the margin pays: one the grids put beyond it costs no exact
            // query.
            if self.keeps_by_grid(shape, self.margin) {
                0.0
            } else {
                self.space
                    .clearance_below(shape, self.margin)
                    .map_or(0.0, |c| (self.margin - c.0.distance).max(0.0))
            }
        } else {
            0.0
        };
        let nu = MERIT_NU * self.space.effort_scale;
        (self.space.effort(u) + nu * (r + viol), r)
    }

    /// A released cable's least-effort input that keeps it slack, given its path change `s`
    /// (`None` when every such input lies below its lower limit).
    fn slack_value(&self, c: usize, s: f64) -> Option<f64> {
        let (lo, hi) = (self.space.lo[c], self.space.hi[c]);
        (s >= lo).then(|| 0.0f64.clamp(lo, hi).min(s))
    }

    /// Solve `u` with the cables marked in `rel` released (free), warm from `warm`; then every
    /// cable that pulls nothing (slack, or released) is set to its least-effort slack value
    /// (the same shape: it stays slack) and, with `hold`, released (else driven); a released
    /// cable whose slack value would pay it out beyond its lower limit is driven at that limit
    /// (solved again). `None` when a solve fails.
    fn eval(
        &mut self,
        mut u: Vec<f64>,
        mut rel: Vec<bool>,
        warm: Option<&Shape>,
        hold: bool,
    ) -> Option<Point> {
        let mut shape;
        loop {
            self.solves += 1;
            shape = self.space.solve_with(&u, &rel, warm).ok()?;
            let mut resolve = false;
            // In tension space a cable at zero tension is at its bound, not at a kink: the tip
            // is smooth in the tensions, and nothing is released.
            let cables = if self.space.by_tension() { 0 } else { u.len() };
            for c in 0..cables {
                let s = shape.cables.get(c).and_then(|p| p.shortening);
                if !(rel[c] || slack(&shape, c)) {
                    continue;
                }
                match s.and_then(|s| self.slack_value(c, s)) {
                    Some(v) => (u[c], rel[c]) = (v, hold),
                    None if rel[c] => {
                        (u[c], rel[c]) = (self.space.lo[c], false);
                        resolve = true;
                    }
                    None => {}
                }
            }
            if !resolve {
                break;
            }
        }
        let (phi, res) = self.merit(&u, &shape);
        Some(Point {
            effort: self.space.effort(&u),
            u,
            released: rel,
            shape,
            phi,
            res,
        })
    }

    /// The step at `p` (A, else B), or `None` when neither QP solves or the sensitivities fail.
    fn step(&mut self, p: &Point) -> Option<(Vec<f64>, bool)> {
        let (u, shape) = (&p.u, &p.shape);
        let k = u.len();
        // The clearance matters only within the band: beyond it, no exact query.
        let band = self.margin + CLEAR_BAND;
        let near = if self.keep_clear() && !self.keeps_by_grid(shape, band) {
            self.space.clearance_below(shape, band)
        } else {
            None
        };
        let clear = near.as_ref().map(|c| c.0.distance);
        let s = sensitivity_with(self.space, u, &p.released, shape, near.map(|c| c.1)).ok()?;
        self.solves += s.solves;
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
        // Inequalities: bounds (a released cable stays where it is: its input is its slack
        // value, not a free variable), then the linearized clearance.
        let mut rows: Vec<Vec<f64>> = Vec::new();
        let mut rhs = Vec::new();
        for c in 0..k {
            let reach = self.trust * (self.space.hi[c] - self.space.lo[c]);
            let (hi, lo) = if p.released[c] {
                (0.0, 0.0)
            } else {
                (
                    (self.space.hi[c] - u[c]).min(reach),
                    (u[c] - self.space.lo[c]).min(reach),
                )
            };
            let mut e = vec![0.0; k];
            e[c] = 1.0;
            rows.push(e.clone());
            rhs.push(hi);
            e[c] = -1.0;
            rows.push(e);
            rhs.push(lo);
        }
        if let (Some(g), Some(d)) = (&s.clearance, clear) {
            rows.push(g.iter().map(|x| -x).collect());
            rhs.push(d - self.margin);
        }
        let gm = DMatrix::from_fn(rows.len(), k, |i, j| rows[i][j]);
        // Step A: least effort on the linearized targets.
        let svd = jac.clone().svd(true, true);
        let (uu, vt) = (svd.u.as_ref()?, svd.v_t.as_ref()?);
        let smax = svd.singular_values.max();
        let keep: Vec<usize> = (0..svd.singular_values.len())
            .filter(|&i| svd.singular_values[i] > 1e-9 * smax && smax > 0.0)
            .collect();
        let eq = DMatrix::from_fn(keep.len(), k, |i, j| {
            svd.singular_values[keep[i]] * vt[(keep[i], j)]
        });
        let eb: Vec<f64> = keep.iter().map(|&i| -uu.column(i).dot(&r)).collect();
        // E(x) = Σ w² (x − rest)²: its Hessian and gradient.
        let w2: Vec<f64> = self.space.weights.iter().map(|w| w * w).collect();
        let h = DMatrix::from_diagonal(&DVector::from_iterator(k, w2.iter().map(|w| 2.0 * w)));
        let g: Vec<f64> = (0..k)
            .map(|i| 2.0 * w2[i] * (u[i] - self.space.rest[i]))
            .collect();
        if let Some(d) = qp_dense(&h, &g, (&eq, &eb), (&gm, &rhs)) {
            return Some((d, true));
        }
        // Step B: Levenberg–Marquardt towards the closest reachable tip.
        let jtj = jac.transpose() * &jac;
        let mu = 1e-9 * jtj.trace().max(1e-12) / k as f64;
        let h = jtj + DMatrix::identity(k, k) * mu;
        let g: Vec<f64> = (jac.transpose() * &r).iter().copied().collect();
        let none = DMatrix::zeros(0, k);
        qp_dense(&h, &g, (&none, &[]), (&gm, &rhs)).map(|d| (d, false))
    }

    /// Backtracking line search along `du` from `p`: the first `u + α du` (α = 1, ½, … > 1e-4)
    /// whose solve succeeds and lowers the merit (a failed solve is a rejected step), and the
    /// driven cables, taut at `p`, that the full step turned slack.
    fn line_search(&mut self, p: &Point, du: &[f64], hold: bool) -> (Option<Point>, Vec<usize>) {
        let mut alpha = 1.0;
        let mut kinked = Vec::new();
        while alpha > 1e-4 {
            let un: Vec<f64> = self.space.clamp(
                &p.u.iter()
                    .zip(du)
                    .map(|(a, b)| a + alpha * b)
                    .collect::<Vec<_>>(),
            );
            if let Some(q) = self.eval(un, p.released.clone(), Some(&p.shape), hold) {
                if alpha == 1.0 && !self.space.by_tension() {
                    kinked = (0..p.u.len())
                        .filter(|&c| !p.released[c] && slack(&q.shape, c) && !slack(&p.shape, c))
                        .collect();
                }
                if q.phi < p.phi {
                    return (Some(q), kinked);
                }
            }
            alpha *= 0.5;
        }
        (None, kinked)
    }

    /// The start `u0`, solved; halved towards the unactuated robot while its solve fails.
    fn first(&mut self, u0: &[f64]) -> Option<Point> {
        let mut u = self.space.clamp(u0);
        for _ in 0..=START_BACKOFF {
            if let Some(p) = self.eval(u.clone(), vec![false; u.len()], None, true) {
                return Some(self.aimed(p));
            }
            u = self
                .space
                .clamp(&u.iter().map(|x| 0.5 * x).collect::<Vec<_>>());
        }
        None
    }

    /// A start through a port turned about the port axis so that its tip lies at the target's
    /// azimuth (the rotation that does so within the limits nearest the start's; kept when
    /// it solves and lowers the merit): the tip turns rigidly with the rotation, and a descent
    /// from the wrong side of the axis ends in a local minimum more often than not.
    fn aimed(&mut self, p: Point) -> Point {
        let (Some(port), true) = (self.space.robot.port.as_ref(), self.space.has_port()) else {
            return p;
        };
        let (a, o) = (port.axis(), port.origin());
        let flat = |v: nalgebra::Vector3<f64>| v - a * a.dot(&v);
        let (tip, goal) = (flat(p.shape.tip() - o), flat(self.target.tip - o));
        if tip.norm() < 1e-9 || goal.norm() < 1e-9 {
            return p;
        }
        let turn = a.dot(&tip.cross(&goal)).atan2(tip.dot(&goal));
        let j = self.space.cables() + 1;
        let (lo, hi) = (self.space.lo[j], self.space.hi[j]);
        let tau = std::f64::consts::TAU;
        let psi = (-3..=3)
            .map(|k| p.u[j] + turn + k as f64 * tau)
            .filter(|x| (lo..=hi).contains(x))
            .min_by(|x, y| (x - p.u[j]).abs().total_cmp(&(y - p.u[j]).abs()));
        let Some(psi) = psi else {
            return p;
        };
        let mut u = p.u.clone();
        u[j] = psi;
        match self.eval(u, p.released.clone(), Some(&p.shape), true) {
            Some(q) if q.phi < p.phi => q,
            _ => p,
        }
    }

    /// One descent from `u0` (module docs); `None` when no start point could be solved.
    pub fn descend(&mut self, u0: &[f64]) -> Option<Attempt> {
        self.trust = if self.space.has_port() {
            TRUST_START
        } else {
            1.0
        };
        let p = self.first(u0)?;
        let mut best = p.clone();
        let mut it = 0;
        // First with the slack cables released, then, from where that ends, every cable
        // driven (a slack one can then turn taut again where pulling it saves effort).
        let p = self.phase(p, &mut best, &mut it, true);
        if p.released.iter().any(|&r| r) {
            let q = self.eval(p.u.clone(), p.released.clone(), Some(&p.shape), false);
            if let Some(q) = q {
                it = it.min(self.opts.max_iterations / 2);
                self.phase(q, &mut best, &mut it, false);
            }
        }
        Some(Attempt {
            effort: best.effort,
            u: best.u,
            res: best.res,
            iterations: it,
            cold: None,
        })
    }

    /// Iterate from `p` until converged, stalled or out of iterations, keeping the best point
    /// in `best`; `hold`: slack cables stay released (module docs). The last iterate.
    fn phase(&mut self, mut p: Point, best: &mut Point, it: &mut usize, hold: bool) -> Point {
        let (mut switches, mut redriven) = (0, false);
        let max_switches = MAX_SWITCHES * p.u.len();
        while *it < self.opts.max_iterations {
            *it += 1;
            let Some((du, a)) = self.step(&p) else {
                break;
            };
            if !a && hold && !redriven && p.released.iter().any(|&r| r) {
                // The driven cables cannot reach: every released cable driven again, just taut.
                redriven = true;
                let mut u = p.u.clone();
                for (c, x) in u.iter_mut().enumerate() {
                    let path = p.shape.cables.get(c).and_then(|cp| cp.shortening);
                    if let Some(s) = path.filter(|_| p.released[c]) {
                        *x = s.clamp(self.space.lo[c], self.space.hi[c]);
                    }
                }
                let rel = vec![false; u.len()];
                match self.eval(u, rel, Some(&p.shape), false) {
                    Some(q) => p = q,
                    None => break,
                }
                continue;
            }
            if du.iter().all(|d| d.abs() < 1e-13) {
                break;
            }
            let (trial, kinked) = self.line_search(&p, &du, hold);
            let full = trial.as_ref().is_some_and(|q| {
                q.u.iter()
                    .zip(&p.u)
                    .zip(&du)
                    .all(|((a, b), d)| (a - b - d).abs() <= 1e-12 * (1.0 + d.abs()))
            });
            if full {
                self.trust = (2.0 * self.trust).min(1.0);
            }
            if hold && !full && !kinked.is_empty() && switches < max_switches {
                // The full step turned these cables slack: release them here and go on.
                switches += kinked.len();
                let mut rel = p.released.clone();
                kinked.iter().for_each(|&c| rel[c] = true);
                if let Some(q) = self.eval(p.u.clone(), rel, Some(&p.shape), hold) {
                    p = q;
                    if p.better_than(best) {
                        *best = p.clone();
                    }
                    continue;
                }
            }
            let Some(q) = trial else {
                break;
            };
            let moved =
                q.u.iter()
                    .zip(&p.u)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
            let tol = self.opts.tolerance * 1e-2;
            let done =
                moved < 1e-13 || (q.res <= tol && p.phi - q.phi < 1e-16 * self.space.effort_scale);
            p = q;
            if p.better_than(best) {
                *best = p.clone();
            }
            if done {
                break;
            }
        }
        p
    }
}
