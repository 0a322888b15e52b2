//! The Gram–Schmidt split of the 6×6 KKT step (`kkt_step6_gs`) gives the same step,
//! multipliers and smallest reduced-Hessian eigenvalue as the eigendecomposition split
//! (`kkt_step6`) and as the general dynamic-size `kkt_step`, on seeded random problems with
//! 0–6 rows, indefinite Hessians included, and falls back on dependent rows.

use super::{kkt_step, kkt_step6, kkt_step6_gs};
use crate::numeric::test_rng::Rng;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-9 * scale
}

#[test]
fn gram_schmidt_split_equals_eigen_split_and_general_step() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for trial in 0..600 {
        let k = trial % 7;
        let b = Matrix6::from_fn(|_, _| rng.range(-1.0, 1.0));
        let mut h = b + b.transpose();
        if trial % 2 == 0 {
            h += Matrix6::identity() * 8.0; // positive definite half the time
        }
        let g = Vector6::from_fn(|_, _| rng.range(-1.0, 1.0));
        // Rows of mixed scale, like the section problem's (1/l0 ≈ 50 next to 8 mm).
        let rows: Vec<Vector6<f64>> = (0..k)
            .map(|i| Vector6::from_fn(|_, _| rng.range(-1.0, 1.0)) * [1.0, 50.0, 0.008][i % 3])
            .collect();
        let c: Vec<f64> = (0..k).map(|_| 1e-3 * rng.range(-1.0, 1.0)).collect();
        let e = kkt_step6(&h, &g, &rows, &c, 1e-10).expect("eigen split");
        let q = kkt_step6_gs(&h, &g, &rows, &c, 1e-10).expect("Gram–Schmidt split");
        let d = kkt_step(
            &DMatrix::from_fn(6, 6, |r, s| h[(r, s)]),
            &DVector::from_row_slice(g.as_slice()),
            &DMatrix::from_fn(k, 6, |r, s| rows[r][s]),
            &DVector::from_row_slice(&c),
            1e-10,
        );
        let sx = 1.0 + e.dx.amax();
        for i in 0..6 {
            assert!(close(q.dx[i], e.dx[i], sx), "trial {trial} dx {i}");
            assert!(close(d.dx[i], e.dx[i], sx), "trial {trial} general dx {i}");
        }
        let sl = 1.0 + e.lambda.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..k {
            assert!(close(q.lambda[i], e.lambda[i], sl), "trial {trial} λ {i}");
        }
        assert_eq!(q.rank, e.rank);
        if e.min_reduced_eigenvalue.is_finite() {
            let s = 1.0 + h.amax();
            assert!(
                close(q.min_reduced_eigenvalue, e.min_reduced_eigenvalue, s),
                "trial {trial} min eig {} {}",
                q.min_reduced_eigenvalue,
                e.min_reduced_eigenvalue
            );
        } else {
            assert!(q.min_reduced_eigenvalue.is_infinite());
        }
    }
}

/// A repeated row (redundant constraints): the Gram–Schmidt split declines and the eigen
/// split's least-squares step is used, so both give the same answer.
#[test]
fn dependent_rows_fall_back_to_the_eigen_split() {
    let h = Matrix6::identity();
    let g = Vector6::zeros();
    let r = Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let rows = [r, r * 2.0];
    let c = [-1.0, -2.0];
    let q = kkt_step6_gs(&h, &g, &rows, &c, 1e-12);
    let e = kkt_step6(&h, &g, &rows, &c, 1e-12);
    assert_eq!(q.is_some(), e.is_some());
    if let (Some(q), Some(e)) = (q, e) {
        assert_eq!(q.rank, 1);
        assert!((q.dx - e.dx).amax() < 1e-14);
    }
}
