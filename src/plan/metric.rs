//! The distance the planners measure in the actuation space `x = [u₁ … u_k, d, ψ]`
//! (the cables' shortenings \[m\] or, in tension space, their tensions \[N\]; with a port the
//! insertion \[m\] and rotation \[rad\]).
//!
//! # The metric
//!
//! `dist(x, y) = √(Σ_i (w_i (x_i − y_i))²)` \[m of cable\], with `w` the effort's scales
//! ([`crate::reach::Space::weights`]: 1 per cable, `ρ_d` = [`crate::reach::INSERTION_SCALE`]
//! for the insertion, `ρ_ψ` = the mean hole radius \[m/rad\] for the rotation). Its square is
//! reach's effort of moving from `x` to `y`, so the planners and `reach` price a metre of
//! insertion and a radian of turn alike, in metres of cable (one scale, defined once in
//! `reach`): a turn by `ψ` counts as the arc `r̄ ψ` a cable hole travels, and a metre of
//! insertion as a tenth of a metre of cable.
//!
//! # In tension space
//!
//! The cables' unknowns are tensions \[N\] and reach's effort is in N² (its scales in N per
//! unit: 1 per cable, `ρ_d` \[N/m\], `ρ_ψ` \[N/rad\]). The planners divide every scale by the
//! same rate, the newtons worth a metre of cable ([`crate::reach::Space::per_metre`]:
//! `T̄ / (0.1 L)` \[N/m\], the mean upper tension limit `T̄` over the default shortening
//! range, a tenth of the cable length `L`), so the distance stays in metres of cable:
//! `dist = √(E(y − x)) / (T̄ / (0.1 L))`. A cable's tension moved across its whole range
//! `[0, T̄]` then counts `0.1 L`, as a shortening moved across its default range does, and
//! every option measured in the metric (a tree's step, the output step, the shortest
//! sub-interval [`super::edge::MIN_STEP`]) and every reported length mean the same in both
//! spaces. On the soft lung rod (`models/soft/lung_rod.toml`: `T̄` = 3.5 N, `L` = 0.12 m)
//! one metre of cable is 291.7 N, so the default output step of 1 mm is 0.29 N.
//!
//! Why this and not the plain Euclidean norm over mixed units: without scales a radian would
//! count as a metre of cable (about 100 times a cable's range), so nearest neighbours, tree
//! steps and path lengths would be decided by the rotation alone; with them, moving the tip by
//! about the same distance costs about the same whichever input moves it.
//!
//! It is a metric: `W = diag(w)` with every `w_i > 0` (a scale below [`MIN_WEIGHT`] — a robot
//! whose holes all lie on the axis — is raised to it) makes `dist(x, y) = |W (x − y)|₂` a norm
//! of the difference: zero only for `x = y`, symmetric, and the triangle inequality holds
//! (`tests/inverse/plan_port.rs` checks the three on random points). Without a port in
//! shortening space every weight is 1 and it is the Euclidean distance the planners measured
//! before.

use crate::reach::Space;

/// Smallest scale of one unknown \[m per unit\], so the distance stays a metric.
pub const MIN_WEIGHT: f64 = 1e-9;

/// The planners' distance over one actuation space (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Metric {
    weights: Vec<f64>,
}

impl Metric {
    /// The metric of `space`: its effort's scales over [`Space::per_metre`] (module docs), in
    /// metres of cable per unit of each unknown.
    pub fn of(space: &Space) -> Metric {
        let per_metre = space.per_metre();
        Metric::new(space.weights.iter().map(|w| w / per_metre).collect())
    }

    /// The metric with scales `weights` (each raised to at least [`MIN_WEIGHT`]; a
    /// non-finite scale is taken as 1).
    pub fn new(weights: Vec<f64>) -> Metric {
        Metric {
            weights: weights
                .into_iter()
                .map(|w| {
                    if w.is_finite() {
                        w.max(MIN_WEIGHT)
                    } else {
                        1.0
                    }
                })
                .collect(),
        }
    }

    /// The scales, one per unknown.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The distance between `a` and `b` \[m of cable\] (unknowns beyond the scales count
    /// with scale 1).
    pub fn dist(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .enumerate()
            .map(|(i, (x, y))| {
                let w = self.weights.get(i).copied().unwrap_or(1.0);
                (w * (x - y)).powi(2)
            })
            .sum::<f64>()
            .sqrt()
    }

    /// The largest extent of the box `lo … hi` along one unknown, measured in the metric
    /// \[m of cable\]: the planners' steps are fractions of it.
    pub fn largest_range(&self, lo: &[f64], hi: &[f64]) -> f64 {
        lo.iter()
            .zip(hi)
            .enumerate()
            .map(|(i, (l, h))| self.weights.get(i).copied().unwrap_or(1.0) * (h - l))
            .fold(0.0, f64::max)
    }
}
