//! How a cable runs between the disks: a C² curve `r(s) = (x(s), y(s), 0)` in the backbone's
//! body frame, with its first and second arc-length derivatives, for the Cosserat rod.
//!
//! The model file gives a cable's hole at every disk it passes (`Cable::hole(k)` at arc length
//! `Robot::disk_s[k]`). Between disks the rod model needs a twice-differentiable curve (the
//! tendon load of Rucker & Webster 2011 uses `r''`). Two fits are offered, both applied to the
//! Cartesian components `x`, `y` of the holes (never to the unwrapped angle, so hole jumps such
//! as case III's cable B are fitted as the straight-across moves they are):
//!
//! * [`RoutingFit::Spline`] (default): a natural cubic spline through the holes, knots at the
//!   disks. It interpolates every hole exactly, is C² everywhere, is local (a hole moves the
//!   curve only nearby), cannot ring between knots, and evaluating it is a handful of flops.
//!   Its third derivative jumps only at the knots, which are integration step boundaries, so
//!   RK4 keeps its fourth order. That is why it is the default.
//! * [`RoutingFit::Fourier8`]: the paper's choice, an 8th-order Fourier series in `s`
//!   (17 coefficients per component), period `T = 2·s_end` (the cable's span is half a period,
//!   so the fit is not forced to be periodic over the robot). With 10 disks the interpolation
//!   conditions are under-determined; ccrkit takes the interpolant of minimum weighted norm
//!   `Σ_k w_k (a_k² + b_k²)`, `w_k = 1 + k⁴` — the `k⁴` weight is the Fourier-space
//!   `∫|r''|² ds` over one period, so among all exact fits it takes the least curved one (the
//!   `1` keeps `a_0` determined). With more than 17 disks the same formula with a tiny ridge
//!   term becomes a regularized least-squares fit.
//!
//! **Declared helices stay helices.** A cable whose file gives `angles = { helix = … }` or
//! `{ straight = … }` (and one hole radius) is routed by its closed
//! form under the default fit: `r(s) = ρ (cos θ, sin θ, 0)`, `θ = θ₀ + ω s` (`ω` the file's
//! `per_metre`, or `δ/ℓ` for an angle `δ` per disk on disks `ℓ` apart), `r' = ρω (−sin θ, cos θ, 0)`,
//! `r'' = −ρω² (cos θ, sin θ, 0)` — the curve public Cosserat codes use (e.g. Rucker &
//! Webster 2011's helical examples). A spline through a helix's holes misses it between disks
//! (case II: 0.036 mm with 9 sections). Per-disk tables keep the spline; `fourier8` keeps the
//! paper's fit for every cable.
//!
//! Effect of the choice on case III (force control, full model, 12 RK4 steps per section):
//! the tip moves by 0.65 mm (spline [-24.693, 36.437, 171.988] mm, Fourier8
//! [-25.127, 35.968, 172.082] mm; `ccrkit solve models/paper/case3.toml --method cosserat
//! [--routing fourier8]`) — small next to the 13 mm between the rod and the geometric method,
//! but larger than the 0.01 mm integration accuracy, so the routing is part of the model.

use crate::error::SolveError;
use crate::model::robot::Robot;
use nalgebra::{DMatrix, DVector, Vector3};

/// Which C² curve runs a cable through its holes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RoutingFit {
    /// Natural cubic spline through the holes (default).
    #[default]
    Spline,
    /// The paper's 8th-order Fourier series, minimum-curvature-norm interpolant.
    Fourier8,
}

/// Position and arc-length derivatives of a cable in the body frame at one `s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoutePoint {
    /// `r(s)` \[m\].
    pub r: Vector3<f64>,
    /// `r'(s)` [-].
    pub dr: Vector3<f64>,
    /// `r''(s)` [1/m].
    pub ddr: Vector3<f64>,
}

/// A hole pattern declared by rule in the model file: the hole at arc length `s` at angle
/// `start + per_metre · s` (a straight cable: `per_metre = 0`). A file's `per_disk` rule on
/// equally spaced disks is the same helix with `per_metre = per_disk / ℓ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Helix {
    /// Angle at `s = 0` \[rad\].
    pub start: f64,
    /// Angle added per metre of arc \[rad/m\].
    pub per_metre: f64,
}

/// Order of the Fourier fit.
pub const FOURIER_ORDER: usize = 8;
const NCOEF: usize = 2 * FOURIER_ORDER + 1;

#[derive(Debug, Clone)]
enum Curve {
    Spline {
        knots: Vec<f64>,
        x: Vec<f64>,
        y: Vec<f64>,
        /// Second derivatives at the knots.
        mx: Vec<f64>,
        my: Vec<f64>,
    },
    Fourier {
        omega: f64,
        cx: [f64; NCOEF],
        cy: [f64; NCOEF],
    },
    /// A straight cable: the constant hole position.
    Straight { r: Vector3<f64> },
    /// A helix: `θ(s) = theta0 + omega s`, radius `rho`.
    Helix { rho: f64, theta0: f64, omega: f64 },
}

/// A fitted cable route.
#[derive(Debug, Clone)]
pub struct Route {
    curve: Curve,
}

/// Second derivatives of the natural cubic spline through `(t, y)` (Thomas algorithm).
fn natural_spline_moments(t: &[f64], y: &[f64]) -> Vec<f64> {
    let m = t.len();
    let mut mom = vec![0.0; m];
    if m < 3 {
        return mom;
    }
    // Interior unknowns 1..m-1: h_{j-1} M_{j-1} + 2(h_{j-1}+h_j) M_j + h_j M_{j+1} = rhs_j.
    let k = m - 2;
    let mut diag = vec![0.0; k];
    let mut sup = vec![0.0; k];
    let mut rhs = vec![0.0; k];
    for j in 1..m - 1 {
        let h0 = t[j] - t[j - 1];
        let h1 = t[j + 1] - t[j];
        diag[j - 1] = 2.0 * (h0 + h1);
        sup[j - 1] = h1;
        rhs[j - 1] = 6.0 * ((y[j + 1] - y[j]) / h1 - (y[j] - y[j - 1]) / h0);
    }
    // Forward sweep (sub-diagonal of row j is h_{j-1} = t[j] - t[j-1]).
    for r in 1..k {
        let sub = t[r + 1] - t[r];
        let w = sub / diag[r - 1];
        diag[r] -= w * sup[r - 1];
        rhs[r] -= w * rhs[r - 1];
    }
    let mut sol = vec![0.0; k];
    sol[k - 1] = rhs[k - 1] / diag[k - 1];
    for r in (0..k - 1).rev() {
        sol[r] = (rhs[r] - sup[r] * sol[r + 1]) / diag[r];
    }
    mom[1..m - 1].copy_from_slice(&sol);
    mom
}

fn fourier_basis(omega: f64, s: f64) -> [[f64; NCOEF]; 3] {
    let mut b = [[0.0; NCOEF]; 3];
    b[0][0] = 1.0;
    for k in 1..=FOURIER_ORDER {
        let w = k as f64 * omega;
        let (sn, cs) = (w * s).sin_cos();
        b[0][2 * k - 1] = cs;
        b[0][2 * k] = sn;
        b[1][2 * k - 1] = -w * sn;
        b[1][2 * k] = w * cs;
        b[2][2 * k - 1] = -w * w * cs;
        b[2][2 * k] = -w * w * sn;
    }
    b
}

/// The closed-form route of cable `c` if its file declared a helix or a straight run and its
/// holes follow that rule ([`crate::model::robot::Cable::helix_rate`]; else `None`: a per-disk
/// table).
fn closed_form(robot: &Robot, c: usize) -> Option<Curve> {
    let cable = &robot.cables[c];
    let omega = cable.helix_rate(&robot.disk_s)?;
    Some(if omega == 0.0 {
        Curve::Straight { r: cable.hole(0) }
    } else {
        Curve::Helix {
            rho: cable.radius[0],
            theta0: cable.angle[0] - omega * robot.disk_s[0],
            omega,
        }
    })
}

impl Route {
    /// True for the closed-form routes of declared helices and straight cables.
    pub fn is_closed_form(&self) -> bool {
        matches!(self.curve, Curve::Straight { .. } | Curve::Helix { .. })
    }

    /// Fit cable `c` of `robot` with `fit`. Knots are the disks `0..=ends_at`.
    pub fn new(robot: &Robot, c: usize, fit: RoutingFit) -> Result<Route, SolveError> {
        let cable = robot
            .cables
            .get(c)
            .ok_or_else(|| SolveError::InvalidInput {
                field: format!("cables[{c}]"),
                reason: "no such cable".into(),
            })?;
        let count = cable.ends_at + 1;
        if count < 2 || robot.disk_s.len() < count {
            return Err(SolveError::InvalidInput {
                field: format!("cables[{c}].ends_at"),
                reason: "a cable must pass at least two disks of the robot".into(),
            });
        }
        let knots: Vec<f64> = robot.disk_s[..count].to_vec();
        if let (RoutingFit::Spline, Some(curve)) = (fit, closed_form(robot, c)) {
            return Ok(Route { curve });
        }
        let x: Vec<f64> = (0..count).map(|k| cable.hole(k).x).collect();
        let y: Vec<f64> = (0..count).map(|k| cable.hole(k).y).collect();
        let curve = match fit {
            RoutingFit::Spline => {
                let mx = natural_spline_moments(&knots, &x);
                let my = natural_spline_moments(&knots, &y);
                Curve::Spline {
                    knots,
                    x,
                    y,
                    mx,
                    my,
                }
            }
            RoutingFit::Fourier8 => {
                let span = knots[count - 1];
                let omega = std::f64::consts::PI / span; // period 2·span
                let phi =
                    DMatrix::from_fn(count, NCOEF, |i, j| fourier_basis(omega, knots[i])[0][j]);
                let winv = DVector::from_fn(NCOEF, |j, _| {
                    let k = j.div_ceil(2) as f64;
                    1.0 / (1.0 + k.powi(4))
                });
                // Gram = Φ W⁻¹ Φᵀ (+ tiny ridge), c = W⁻¹ Φᵀ Gram⁻¹ y.
                let phiw = DMatrix::from_fn(count, NCOEF, |i, j| phi[(i, j)] * winv[j]);
                let mut gram = &phiw * phi.transpose();
                let ridge = 1e-13 * gram.trace() / count as f64;
                for i in 0..count {
                    gram[(i, i)] += ridge;
                }
                let chol = gram.cholesky().ok_or_else(|| SolveError::InvalidInput {
                    field: format!("cables[{c}]"),
                    reason: "Fourier routing fit is singular".into(),
                })?;
                let fitc = |vals: &[f64]| -> [f64; NCOEF] {
                    let lam = chol.solve(&DVector::from_column_slice(vals));
                    let coef = phiw.transpose() * lam;
                    let mut out = [0.0; NCOEF];
                    out.copy_from_slice(coef.as_slice());
                    out
                };
                Curve::Fourier {
                    omega,
                    cx: fitc(&x),
                    cy: fitc(&y),
                }
            }
        };
        Ok(Route { curve })
    }

    /// Evaluate at arc length `s`; `interval` is the section index minus one (the knot
    /// interval `s` lies in), used by the spline to avoid a search. Out-of-range `s` is clamped
    /// to that interval's polynomial (extrapolated smoothly).
    #[inline]
    pub fn eval(&self, s: f64, interval: usize) -> RoutePoint {
        match &self.curve {
            Curve::Spline {
                knots,
                x,
                y,
                mx,
                my,
            } => {
                let j = interval.min(knots.len() - 2);
                let (t0, t1) = (knots[j], knots[j + 1]);
                let h = t1 - t0;
                let a = (t1 - s) / h;
                let b = (s - t0) / h;
                let comp = |v: &[f64], m: &[f64]| -> (f64, f64, f64) {
                    let val = a * v[j]
                        + b * v[j + 1]
                        + ((a * a * a - a) * m[j] + (b * b * b - b) * m[j + 1]) * h * h / 6.0;
                    let d = (v[j + 1] - v[j]) / h - (3.0 * a * a - 1.0) / 6.0 * h * m[j]
                        + (3.0 * b * b - 1.0) / 6.0 * h * m[j + 1];
                    let dd = a * m[j] + b * m[j + 1];
                    (val, d, dd)
                };
                let (x0, x1, x2) = comp(x, mx);
                let (y0, y1, y2) = comp(y, my);
                RoutePoint {
                    r: Vector3::new(x0, y0, 0.0),
                    dr: Vector3::new(x1, y1, 0.0),
                    ddr: Vector3::new(x2, y2, 0.0),
                }
            }
            Curve::Straight { r } => RoutePoint {
                r: *r,
                dr: Vector3::zeros(),
                ddr: Vector3::zeros(),
            },
            Curve::Helix { rho, theta0, omega } => {
                let (sn, cs) = (theta0 + omega * s).sin_cos();
                let (w, w2) = (rho * omega, rho * omega * omega);
                RoutePoint {
                    r: Vector3::new(rho * cs, rho * sn, 0.0),
                    dr: Vector3::new(-w * sn, w * cs, 0.0),
                    ddr: Vector3::new(-w2 * cs, -w2 * sn, 0.0),
                }
            }
            Curve::Fourier { omega, cx, cy } => {
                let b = fourier_basis(*omega, s);
                let dot = |row: &[f64; NCOEF], c: &[f64; NCOEF]| -> f64 {
                    row.iter().zip(c).map(|(p, q)| p * q).sum()
                };
                RoutePoint {
                    r: Vector3::new(dot(&b[0], cx), dot(&b[0], cy), 0.0),
                    dr: Vector3::new(dot(&b[1], cx), dot(&b[1], cy), 0.0),
                    ddr: Vector3::new(dot(&b[2], cx), dot(&b[2], cy), 0.0),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;

    fn case(n: usize) -> Model {
        let path = format!("{}/models/paper/case{n}.toml", env!("CARGO_MANIFEST_DIR"));
        Model::from_file(path).expect("paper model parses")
    }

    #[test]
    fn both_fits_interpolate_the_holes() {
        let m = case(3);
        for fit in [RoutingFit::Spline, RoutingFit::Fourier8] {
            for c in 0..m.robot.cables.len() {
                let route = Route::new(&m.robot, c, fit).expect("fit");
                for k in 0..=m.robot.cables[c].ends_at {
                    let interval = k.saturating_sub(1);
                    let p = route.eval(m.robot.disk_s[k], interval);
                    let err = (p.r - m.robot.cables[c].hole(k)).norm();
                    assert!(err < 1e-9, "{fit:?} cable {c} disk {k}: {err}");
                }
            }
        }
    }

    #[test]
    fn spline_is_c2_at_the_knots() {
        let m = case(2);
        let route = Route::new(&m.robot, 0, RoutingFit::Spline).expect("fit");
        for k in 1..m.robot.sections() {
            let s = m.robot.disk_s[k];
            let left = route.eval(s, k - 1);
            let right = route.eval(s, k);
            assert!((left.dr - right.dr).norm() < 1e-12);
            assert!((left.ddr - right.ddr).norm() < 1e-9);
        }
    }

    #[test]
    fn spline_derivatives_match_finite_differences() {
        let m = case(3);
        let route = Route::new(&m.robot, 1, RoutingFit::Spline).expect("fit");
        let (s, h) = (0.031, 1e-6);
        let p = route.eval(s, 1);
        let dr = (route.eval(s + h, 1).r - route.eval(s - h, 1).r) / (2.0 * h);
        let ddr = (route.eval(s + h, 1).dr - route.eval(s - h, 1).dr) / (2.0 * h);
        assert!((dr - p.dr).norm() < 1e-6);
        assert!((ddr - p.ddr).norm() < 1e-4);
    }

    #[test]
    fn declared_helix_is_closed_form_with_exact_derivatives() {
        let m = case(2);
        let route = Route::new(&m.robot, 0, RoutingFit::Spline).expect("fit");
        assert!(route.is_closed_form());
        // Between the holes: on the circle of radius 8 mm at the helix's angle.
        let ell = m.robot.disk_s[1];
        let (s, h) = (0.031, 1e-6);
        let p = route.eval(s, 1);
        let theta = std::f64::consts::FRAC_PI_6 * s / ell;
        let exact = Vector3::new(0.008 * theta.cos(), 0.008 * theta.sin(), 0.0);
        assert!((p.r - exact).norm() < 1e-15);
        let dr = (route.eval(s + h, 1).r - route.eval(s - h, 1).r) / (2.0 * h);
        let ddr = (route.eval(s + h, 1).dr - route.eval(s - h, 1).dr) / (2.0 * h);
        assert!((dr - p.dr).norm() < 1e-8);
        assert!((ddr - p.ddr).norm() < 1e-6);
        // Fourier keeps the paper's fit.
        let fourier = Route::new(&m.robot, 0, RoutingFit::Fourier8).expect("fit");
        assert!(!fourier.is_closed_form());
    }
}
