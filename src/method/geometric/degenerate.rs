//! Degenerate faces: an unshortened cable that is both at its length and free of tension.
//!
//! # Why the rows become dependent
//!
//! Let cable `j` be *unshortened* in section i: its segment length equals its undeformed
//! straight chord, `l_j = |l0 ẑ + h_j − h′_j|` (to `problem::UNSHORTENED_TOL`). On a face where the
//! tangent term and `j`'s coupler term are zero, `|p| = l0` and `p ∥ ẑ` give `p = l0 ẑ`, and
//! `Q ĥ_j ∥ ĥ_j` with `|Q h_j| = |h_j|` gives `Q h_j = h_j`, so
//!
//! ```text
//! |p + Q h_j − h′_j| = |l0 ẑ + h_j − h′_j| = l_j     on the whole face.
//! ```
//!
//! The cable constraint `c_j = |p + Q h_j − h′_j| − l_j` is then identically zero on the face's
//! manifold, so its gradient lies in the span of the face's other equations: the rows are
//! linearly dependent (LICQ fails), and a face that counts `c_j` among its equations has one
//! equation too many for a generic count (7 for 6 unknowns) although it is a perfectly good
//! vertex. Such faces are kept ([`SectionData::faces`]) when the taut set holds an unshortened
//! cable whose coupler the face zeroes.
//!
//! # Which multipliers certify it
//!
//! With dependent rows the KKT multipliers are not unique: every `λ(s) = λ₀ + s n`, with `λ₀`
//! the least-norm solution of `Aᵀλ = −∇F` and `n` spanning the null space of `Aᵀ`, is equally
//! stationary. The pose is certified if **some** member satisfies the sign and subgradient
//! conditions of [`Geometric::certify`](super::Geometric) and the pull-only check: every taut
//! cable `λ_k(s) ≥ 0`, every zero term `|μ_t(s)| ≤ w_t`, and, when all couplers are zero, the
//! rotation multiplier splits into coupler subgradients (`disc_sum_scale ≤ 1`). This is the
//! degenerate complementarity of a cable at its length: physically its tension is not
//! determined by the geometry, and "taut at tension λ_j(s) ≥ 0" and "slack at its length"
//! (λ_j = 0) are the same pose. Each condition is convex in `s` (linear, the norm of an affine
//! map, the gauge of a convex set at an affine map), so the largest normalized violation
//!
//! ```text
//! v(s) = max( −λ_k(s)/(1 + |λ₀|∞),  |μ_t(s)|/w_t − 1,  disc_sum_scale(s) − 1 )
//! ```
//!
//! is convex, and a golden-section search finds its minimum; the pose is certifiable iff
//! `min v ≤ 0`. The scale-aware tolerance is the certificate's own: the relative `1e-9` on
//! the subgradient balls, `−1e-9` on the cable multipliers, `1e-7` on the disc split — the
//! chosen `λ(s*)` is handed to the unchanged certificate, which applies them.
//!
//! Only at a vertex (the 7 rows have rank 6, nothing free) is the choice of `s` free of
//! consequences: there the second-order condition is empty. A degenerate face with a free
//! direction would need the reduced Hessian re-evaluated for each `s`; it is not searched
//! (the face keeps the step's own least-squares multipliers).

use super::problem::SectionData;
use crate::numeric::kkt::RANK_TOL;
use crate::numeric::qp::disc_sum_scale;
use nalgebra::{DMatrix, SymmetricEigen, Vector3, Vector6};

/// Golden-section iterations of the multiplier search (bracket shrinks by 0.618 each).
const GOLDEN_ITERATIONS: usize = 120;

impl SectionData {
    /// How many taut constraints in `taut` are implied by the face `face` (see the module
    /// docs): unshortened cables whose coupler is zero together with the tangent.
    pub(super) fn redundant_rows(&self, face: u32, taut: &[usize]) -> usize {
        if face & 1 == 0 {
            return 0;
        }
        let all_couplers = self.rotation_fixed(face);
        taut.iter()
            .filter(|&&j| {
                let k = &self.cons[j];
                k.unshortened && (all_couplers || face & (1 << k.coupler) != 0)
            })
            .count()
    }

    /// Multipliers for a stationary vertex whose rows `rows` (gradients of the constraints
    /// in [`SectionData::eval`]'s order) are dependent with a one-dimensional null space: the
    /// member of the family `λ₀ + s n` that best meets the certificate (module docs), if
    /// it meets it; `None` when the rows are not of that kind or no member qualifies.
    pub(super) fn vertex_multipliers(
        &self,
        face: u32,
        active: &[usize],
        g: &Vector6<f64>,
        rows: &[Vector6<f64>],
    ) -> Option<Vec<f64>> {
        let k = rows.len();
        if k != 7 || self.gauge.is_some() {
            return None;
        }
        // Row-normalized B = D⁻¹A; BBᵀ's eigenvectors split range and null space of Bᵀ.
        let scale: Vec<f64> = rows.iter().map(|r| r.norm()).collect();
        if scale.iter().any(|s| *s == 0.0 || !s.is_finite()) {
            return None;
        }
        let b = DMatrix::from_fn(k, 6, |r, c| rows[r][c] / scale[r]);
        let eig = SymmetricEigen::new(&b * b.transpose());
        let null: Vec<usize> = (0..k).filter(|&j| eig.eigenvalues[j] <= RANK_TOL).collect();
        if null.len() != 1 {
            return None;
        }
        // λ = D ν with Bᵀν = −g: ν₀ = −(BBᵀ)⁺ B g, and the null direction n = D v_null.
        let bg = &b * nalgebra::DVector::from_row_slice(g.as_slice());
        let mut nu = nalgebra::DVector::zeros(k);
        for j in (0..k).filter(|j| *j != null[0]) {
            let v = eig.eigenvectors.column(j);
            nu -= v * (v.dot(&bg) / eig.eigenvalues[j]);
        }
        let lambda0: Vec<f64> = (0..k).map(|r| nu[r] / scale[r]).collect();
        let mut n: Vec<f64> = (0..k)
            .map(|r| eig.eigenvectors[(r, null[0])] / scale[r])
            .collect();
        let n_max = n.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        n.iter_mut().for_each(|x| *x /= n_max);
        let lam_max = lambda0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let at = |s: f64| -> Vec<f64> { (0..k).map(|r| lambda0[r] + s * n[r]).collect() };
        let violation = |s: f64| self.violation(face, active, &at(s), 1.0 + lam_max);
        // Golden section on the convex v(s) over a bracket far wider than any multiplier.
        let (mut lo, mut hi) = (-1e6 * (1.0 + lam_max), 1e6 * (1.0 + lam_max));
        let phi = 0.5 * (5f64.sqrt() - 1.0);
        let (mut x1, mut x2) = (hi - phi * (hi - lo), lo + phi * (hi - lo));
        let (mut f1, mut f2) = (violation(x1), violation(x2));
        for _ in 0..GOLDEN_ITERATIONS {
            if f1 <= f2 {
                hi = x2;
                (x2, f2) = (x1, f1);
                x1 = hi - phi * (hi - lo);
                f1 = violation(x1);
            } else {
                lo = x1;
                (x1, f1) = (x2, f2);
                x2 = lo + phi * (hi - lo);
                f2 = violation(x2);
            }
        }
        let s = if f1 <= f2 { x1 } else { x2 };
        (f1.min(f2) <= 0.0).then(|| at(s))
    }

    /// The largest normalized violation `v(s)` of the module docs for multipliers `lambda`.
    fn violation(&self, face: u32, active: &[usize], lambda: &[f64], lam_scale: f64) -> f64 {
        let mut worst = active
            .iter()
            .enumerate()
            .map(|(k, _)| -lambda[1 + k] / lam_scale)
            .fold(f64::NEG_INFINITY, f64::max);
        let mut row = 1 + active.len();
        let fixed_rotation = self.rotation_fixed(face);
        for (t, term) in self.terms.iter().enumerate() {
            if fixed_rotation && !term.tangent {
                if t == 1 {
                    let target = Vector3::new(lambda[row], lambda[row + 1], lambda[row + 2]);
                    let discs: Vec<_> = self.terms[1..]
                        .iter()
                        .map(|k| (k.e1, k.e2, k.weight))
                        .collect();
                    let d = disc_sum_scale(&target, &discs).unwrap_or(f64::INFINITY);
                    worst = worst.max(d - 1.0);
                    row += 3;
                }
            } else if face & (1 << t) != 0 {
                let mu = (lambda[row].powi(2) + lambda[row + 1].powi(2)).sqrt();
                worst = worst.max(mu / term.weight - 1.0);
                row += 2;
            }
        }
        worst
    }
}
