//! Proofs of infeasibility: the literal method calls an actuation `Infeasible` only when no
//! pose of the section can meet its cable lengths, shown by a bound that holds for every pose.
//!
//! For a pose `(p, Q)` with `|p| = l0`, a cable's chord is `|p + Q h − h′|` (`h`, `h′`: its
//! holes on disks i and i−1). Expanding the square and weighting cables by `α_c ≥ 0`,
//!
//! ```text
//! Σ α_c |p + Q h_c − h′_c|² = Σ α_c (l0² + |h_c|² + |h′_c|²) + 2 p·(Q Σ α_c h_c − Σ α_c h′_c)
//!                              − 2 tr(Q Σ α_c h_c h′_cᵀ)
//!                            ≥ Σ α_c (l0² + |h_c|² + |h′_c|²) − 2 l0 (|Σ α_c h_c| + |Σ α_c h′_c|)
//!                              − 2 ‖Σ α_c h_c h′_cᵀ‖_*
//! ```
//!
//! (Cauchy–Schwarz, and `tr(Q M) ≤ ‖M‖_*` for a rotation `Q`, von Neumann's trace
//! inequality). A taut or slack cable has chord ≤ length, so if `Σ α_c l_c²` is below that
//! bound no pose exists. One cable (`α = 1`) gives the triangle bound
//! `l ≥ l0 − |h| − |h′|`; two opposite cables (`α = (1, 1)`) give `l_A² + l_B² ≥ 2 l0²`, the
//! antagonists of an incompressible backbone. Pairs are tried with a few weights.

use super::problem::SectionData;
use crate::error::SolveError;
use nalgebra::Matrix3;

/// Weights of the second cable of a pair tried by [`SectionData::prove_infeasible`].
const PAIR_WEIGHTS: [f64; 7] = [0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0];

impl SectionData {
    /// The lower bound above for weights `alpha` over the constraints `set` \[m²\], and
    /// `Σ α_c l_c²`.
    fn weighted_bound(&self, set: &[(usize, f64)]) -> (f64, f64) {
        let (mut sum, mut lengths) = (0.0, 0.0);
        let (mut h, mut hp) = (nalgebra::Vector3::zeros(), nalgebra::Vector3::zeros());
        let mut m = Matrix3::zeros();
        for &(j, a) in set {
            let k = &self.cons[j];
            sum += a * (self.l0 * self.l0 + k.h.norm_squared() + k.h_prev.norm_squared());
            lengths += a * k.length * k.length;
            h += a * k.h;
            hp += a * k.h_prev;
            m += a * k.h * k.h_prev.transpose();
        }
        let nuclear: f64 = m.singular_values().iter().sum();
        (
            sum - 2.0 * self.l0 * (h.norm() + hp.norm()) - 2.0 * nuclear,
            lengths,
        )
    }

    /// A named error if the bound proves that no pose meets the cable lengths of a pair of
    /// constraints (single cables are checked where the section is built).
    pub(super) fn prove_infeasible(&self) -> Option<SolveError> {
        let m = self.cons.len();
        for a in 0..m {
            for b in a + 1..m {
                for w in PAIR_WEIGHTS {
                    let (bound, lengths) = self.weighted_bound(&[(a, 1.0), (b, w)]);
                    // Margin: well above rounding, far below any length that matters.
                    if lengths < bound - 1e-12 * self.l0 * self.l0 {
                        let (na, nb) = (
                            &self.names[self.cons[a].cables[0]],
                            &self.names[self.cons[b].cables[0]],
                        );
                        return Some(SolveError::Infeasible {
                            cable: na.clone(),
                            section: self.section,
                            reason: format!(
                                "cables {na} and {nb} cannot both be this short while the backbone segment keeps its length l0 = {} m (this method's backbone is incompressible): every pose has l_{na}² + {w}·l_{nb}² ≥ {bound:.6e} m², these lengths give {lengths:.6e} m²",
                                self.l0
                            ),
                        });
                    }
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix3, Vector3};

    /// The bound is a bound: over random poses with |p| = l0, the weighted sum of squared
    /// chords of two cables never falls below it.
    #[test]
    fn bound_holds_for_random_poses() {
        let l0 = 0.02;
        let holes = [
            (
                Vector3::new(0.008, 0.0, 0.0),
                Vector3::new(0.007, 0.004, 0.0),
            ),
            (
                Vector3::new(-0.006, 0.005, 0.0),
                Vector3::new(-0.008, 0.0, 0.0),
            ),
        ];
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        for w in super::PAIR_WEIGHTS {
            let alpha = [1.0, w];
            let mut m = Matrix3::zeros();
            let (mut sum, mut h, mut hp) = (0.0, Vector3::zeros(), Vector3::zeros());
            for (k, (hh, hhp)) in holes.iter().enumerate() {
                sum += alpha[k] * (l0 * l0 + hh.norm_squared() + hhp.norm_squared());
                h += alpha[k] * hh;
                hp += alpha[k] * hhp;
                m += alpha[k] * hh * hhp.transpose();
            }
            let nuclear: f64 = m.singular_values().iter().sum();
            let bound = sum - 2.0 * l0 * (h.norm() + hp.norm()) - 2.0 * nuclear;
            for _ in 0..2000 {
                let p = Vector3::new(rnd(), rnd(), rnd()).normalize() * l0;
                let q = crate::numeric::so3::exp_so3(&(Vector3::new(rnd(), rnd(), rnd()) * 3.0));
                let s: f64 = holes
                    .iter()
                    .enumerate()
                    .map(|(k, (hh, hhp))| alpha[k] * (p + q * hh - hhp).norm_squared())
                    .sum();
                assert!(s >= bound - 1e-15, "{s} < {bound}");
            }
        }
    }
}
