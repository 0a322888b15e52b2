//! Displacement control of the inextensible rod (`kirchhoff`): balanced cable groups, the
//! proof of infeasibility they give, and the slack start they need.
//!
//! # Why the inextensible rod stalled on three tendons per segment
//!
//! Take length-controlled cables tied at the same disk whose holes do not move in the body
//! frame over their whole run (`r_i' = 0`: straight cables at one radius), and weights
//! `w_i ≥ 0`, `Σ w_i = 1`, with `Σ w_i r_i = 0` (a *balanced group*: two opposite cables, or
//! three whose holes surround the axis — every segment of the FTDCR robots). With `v ≡ e3`
//! the cable tangent is `ṗ_i = e3 + u × r_i`, and `e3·(u × r_i) = u·(r_i × e3)`, so
//!
//! ```text
//! Σ w_i |ṗ_i|  ≥  Σ w_i e3·ṗ_i  =  1 + u·((Σ w_i r_i) × e3)  =  1      at every s,
//! ```
//!
//! with equality only where the transverse parts `u_z (e3 × r_i)` vanish (no twist). The path
//! lengths (R&W eq. 6, integrated by a quadrature with positive weights, as RK4 is) therefore
//! obey `Σ w_i ℓ_i ≥ Σ w_i ℓ_i⁰` for *every* inextensible shape. A cable pulls only, so its
//! path is at most its length `ℓ_i⁰ − d_i` (`d_i`: the shortening). Hence:
//!
//! 1. **`Σ w_i d_i > 0` is infeasible**: no inextensible shape has those lengths. The
//!    extensible rod (`cosserat`) meets them only by compressing the backbone by that much,
//!    with a compression `≈ EA Σ w_i d_i / ℓ` that grows without bound as `EA → ∞` — the
//!    Kirchhoff limit of the extensible solution does not exist. The solve returns
//!    [`SolveError::Infeasible`] with the group, its weights and the excess.
//! 2. **All taut is degenerate**: at the straight rod the balanced pull
//!    `δτ = w`, `δn(0) = −(Σ w_i) e3` changes neither the tip wrench nor any length (an axial
//!    force does not deform an inextensible rod), so it is a null vector of the shooting
//!    Jacobian (checked in `tests/methods/cosserat_refs.rs`): the first continuation step hit a singular
//!    Jacobian. Away from the straight rod all taut needs `Σ w_i ℓ_i = Σ w_i ℓ_i⁰ − Σ w_i d_i`,
//!    i.e. exactly the twist that makes up `−Σ w_i d_i`, which the cables' own loads do not
//!    produce; at `Σ w_i d_i = 0` the tension along `w` is free and the least one has a cable
//!    at zero tension. So the solve keeps one cable of each balanced group slack (which one:
//!    [`slack_start`]); the active set then moves it if its tension or length says so.

use super::problem::Problem;
use super::RodModel;
use crate::error::SolveError;
use crate::model::actuation::{Drive, LengthMeasure};
use nalgebra::{Matrix2, Vector2, Vector3};

/// Cables tied at one disk, straight in the body frame, with weights balancing their holes.
pub(super) struct Group {
    /// Cable indices (2 or 3).
    pub(super) cables: Vec<usize>,
    /// Weights `w_i > 0`, `Σ w_i = 1`, `Σ w_i r_i = 0`.
    pub(super) w: Vec<f64>,
    /// The disk the cables are tied at.
    pub(super) disk: usize,
}

impl Problem<'_> {
    /// True when cable `c`'s hole is the same point of the body frame along its whole run
    /// (`r' = r'' = 0`), checked on the fitted route at every disk and mid-section.
    fn straight_in_body(&self, c: usize) -> bool {
        let robot = self.robot;
        let r0 = robot.cables[c].hole(0);
        let tol = 1e-12 * (1.0 + r0.norm());
        (1..=robot.cables[c].ends_at).all(|k| {
            let (s0, s1) = (robot.disk_s[k - 1], robot.disk_s[k]);
            [s0, 0.5 * (s0 + s1), s1].iter().all(|&s| {
                let p = self.eval_route(c, s, k);
                (p.r - r0).norm() <= tol && p.dr.norm() <= tol / robot.length()
            })
        })
    }

    /// The balanced groups of length-controlled cables (module docs): pairs of opposite
    /// holes and triples whose holes surround the axis, among straight cables tied at the
    /// same disk. Empty unless the rod is inextensible and lengths are paths. By
    /// Carathéodory, every balanced weighting of a disk's cables is a combination of these,
    /// so the infeasibility test over them is exact.
    pub(super) fn balanced_groups(&self) -> Vec<Group> {
        if self.set.model != RodModel::Kirchhoff || self.set.length != LengthMeasure::Path {
            return vec![];
        }
        let robot = self.robot;
        let cand: Vec<usize> = (0..robot.cables.len())
            .filter(|&c| matches!(self.modes[c], Drive::Shorten { .. }))
            // A compliant cable's stretch `τ/k` takes up any shortening: no bound, and its
            // length row depends on the pull (`−k_ℓ/k`), so the pull is no null vector.
            .filter(|&c| self.compliance[c] == 0.0)
            .filter(|&c| self.straight_in_body(c))
            .collect();
        let hole = |c: usize| -> Vector2<f64> {
            let h: Vector3<f64> = robot.cables[c].hole(0);
            Vector2::new(h.x, h.y)
        };
        let cross = |a: Vector2<f64>, b: Vector2<f64>| a.x * b.y - a.y * b.x;
        let mut out = vec![];
        for (ia, &a) in cand.iter().enumerate() {
            for (ib, &b) in cand.iter().enumerate().skip(ia + 1) {
                let disk = robot.cables[a].ends_at;
                if robot.cables[b].ends_at != disk {
                    continue;
                }
                let (ra, rb) = (hole(a), hole(b));
                let scale = ra.norm() * rb.norm();
                if scale == 0.0 {
                    continue;
                }
                if cross(ra, rb).abs() <= 1e-12 * scale && ra.dot(&rb) < 0.0 {
                    let (na, nb) = (ra.norm(), rb.norm());
                    let w = vec![nb / (na + nb), na / (na + nb)];
                    out.push(Group {
                        cables: vec![a, b],
                        w,
                        disk,
                    });
                }
                for &c in cand.iter().skip(ib + 1) {
                    if robot.cables[c].ends_at != disk {
                        continue;
                    }
                    let rc = hole(c);
                    // Barycentric coordinates of the origin in the triangle (a, b, c).
                    let wa = cross(rb, rc);
                    let wb = cross(rc, ra);
                    let wc = cross(ra, rb);
                    let sum = wa + wb + wc;
                    let tol = 1e-12 * (wa.abs() + wb.abs() + wc.abs());
                    if sum.abs() <= tol {
                        continue;
                    }
                    let w = [wa / sum, wb / sum, wc / sum];
                    if w.iter().all(|&x| x > 1e-12) {
                        out.push(Group {
                            cables: vec![a, b, c],
                            w: w.to_vec(),
                            disk,
                        });
                    }
                }
            }
        }
        out
    }

    /// `Σ w_i d_i` of a group at full load \[m\] (`d_i = ℓ_i⁰ − target_i`).
    pub(super) fn excess(&self, g: &Group) -> f64 {
        g.cables
            .iter()
            .zip(&g.w)
            .map(|(&c, &w)| w * (self.len0[c] - self.target(c, 1.0)))
            .sum()
    }

    /// [`SolveError::Infeasible`] for the first group whose shortenings no inextensible shape
    /// meets (`Σ w_i d_i` above the length tolerance), with the proof in the reason.
    pub(super) fn check_inextensible(&self, groups: &[Group]) -> Result<(), SolveError> {
        for g in groups {
            let ex = self.excess(g);
            let tol = g
                .cables
                .iter()
                .map(|&c| self.set.tolerance / self.kl[c])
                .fold(0.0, f64::max);
            if ex > tol {
                let names: Vec<String> = g
                    .cables
                    .iter()
                    .zip(&g.w)
                    .map(|(&c, w)| format!("{w:.4}·`{}`", self.robot.cables[c].name))
                    .collect();
                return Err(SolveError::Infeasible {
                    cable: self.robot.cables[g.cables[0]].name.clone(),
                    section: g.disk,
                    reason: format!(
                        "the inextensible rod cannot shorten these cables together: they are \
                         straight, tied at disk {} and balanced (Σ w r = 0 for w = {}), so every \
                         inextensible shape has Σ w ℓ ≥ Σ w ℓ₀, but the shortenings ask \
                         Σ w d = {:.4} mm > 0; the extensible rod (`cosserat`) meets them by \
                         compressing the backbone",
                        g.disk,
                        names.join(" + "),
                        ex * 1e3
                    ),
                });
            }
        }
        Ok(())
    }
}

/// The cable of a balanced group to start slack, if all of it is taut (module docs, 2.):
/// in the linearized straight segment a taut pair `(i, j)` bends it by `K = −(α a_i + β a_j)`,
/// `a = r × e3`, with `α, β ∝ τ_i, τ_j` from `K·a_i = −d_i`, `K·a_j = −d_j`; the pair with
/// `α, β ≥ 0` (the tension cones partition the plane) stays taut, the third goes slack.
/// Pairs (opposite holes): the cable with the smaller `d_i / |r_i|` goes slack.
pub(super) fn slack_start(prob: &Problem, g: &Group) -> usize {
    let robot = prob.robot;
    let d = |c: usize| prob.len0[c] - prob.target(c, 1.0);
    let a = |c: usize| -> Vector2<f64> {
        let h = robot.cables[c].hole(0);
        Vector2::new(h.y, -h.x)
    };
    if g.cables.len() == 2 {
        let (p, q) = (g.cables[0], g.cables[1]);
        return if d(p) / a(p).norm() < d(q) / a(q).norm() {
            p
        } else {
            q
        };
    }
    let mut best = (f64::NEG_INFINITY, g.cables[0]);
    for k in 0..3 {
        let (i, j) = (g.cables[(k + 1) % 3], g.cables[(k + 2) % 3]);
        let (ai, aj) = (a(i), a(j));
        let gram = Matrix2::new(ai.dot(&ai), ai.dot(&aj), ai.dot(&aj), aj.dot(&aj));
        let Some(sol) = gram.lu().solve(&Vector2::new(d(i), d(j))) else {
            continue;
        };
        let score = sol.x.min(sol.y) / (ai.norm() * aj.norm());
        if score > best.0 {
            best = (score, g.cables[k]);
        }
    }
    best.1
}
