//! Real robots against measured data: batch prediction ([`predict`]) and calibration
//! ([`fit`]) of a model's parameters to measured tips, the choice among candidate parameter
//! sets on training data only ([`select`]), with the metric of the OpenCR FTDCR
//! benchmark ([`aligned_errors`]).
//!
//! The metric (`models/hardware/data/README.md` §5, the data's own): the predicted tips are shifted
//! by the mean offset `mean(sim − real)` over the rows compared, then the Euclidean error per row
//! is taken; the RMSE of these is the "mean-offset-aligned tip RMSE". The alignment absorbs three
//! degrees of freedom (the unknown frame origin).

pub mod data;
pub mod fit;
mod jacobian;
pub mod params;
pub mod predict;
pub mod select;

use nalgebra::Vector3;

/// Errors per row after mean-offset alignment (`sim ← sim − mean(sim − real)`), same units as
/// the inputs. Empty inputs give no errors.
pub fn aligned_errors(sim: &[Vector3<f64>], real: &[Vector3<f64>]) -> Vec<f64> {
    let n = sim.len().min(real.len());
    if n == 0 {
        return Vec::new();
    }
    let off: Vector3<f64> = (0..n).map(|i| sim[i] - real[i]).sum::<Vector3<f64>>() / n as f64;
    (0..n).map(|i| (sim[i] - off - real[i]).norm()).collect()
}

/// Errors per row after aligning the first rows (the older convention of the data README §5).
pub fn first_point_errors(sim: &[Vector3<f64>], real: &[Vector3<f64>]) -> Vec<f64> {
    let n = sim.len().min(real.len());
    if n == 0 {
        return Vec::new();
    }
    let off = sim[0] - real[0];
    (0..n).map(|i| (sim[i] - off - real[i]).norm()).collect()
}

/// Summary of per-row errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorStats {
    /// Rows.
    pub n: usize,
    /// Root mean square.
    pub rmse: f64,
    /// Mean.
    pub mean: f64,
    /// Median.
    pub median: f64,
    /// Largest.
    pub max: f64,
}

impl ErrorStats {
    /// Statistics of `e` (`None` when empty).
    pub fn of(e: &[f64]) -> Option<ErrorStats> {
        if e.is_empty() {
            return None;
        }
        let n = e.len();
        let mut s = e.to_vec();
        s.sort_by(f64::total_cmp);
        let median = if n % 2 == 1 {
            s[n / 2]
        } else {
            0.5 * (s[n / 2 - 1] + s[n / 2])
        };
        Some(ErrorStats {
            n,
            rmse: (e.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt(),
            mean: e.iter().sum::<f64>() / n as f64,
            median,
            max: s[n - 1],
        })
    }
}
