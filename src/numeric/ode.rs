//! Butcher tableaux of the explicit Runge–Kutta methods the integrators use.

/// The Dormand–Prince 5(4) pair (Dormand & Prince 1980; Hairer, Nørsett & Wanner, *Solving
/// Ordinary Differential Equations I*, §II.5, Table 5.2): seven stages, a fifth-order solution
/// and an embedded fourth-order one for the error estimate.
pub mod dormand_prince {
    /// Stage times as fractions of the step.
    pub const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
    /// Stage coefficients: stage `i` is evaluated at `y + h Σ_{j<i} A[i][j] k_j`.
    pub const A: [[f64; 6]; 7] = [
        [0.0; 6],
        [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ];
    /// Fifth-order weights: the last stage's row (first same as last: the seventh stage is
    /// the slope at the new point, reusable as the next step's first).
    pub const B5: [f64; 7] = {
        let r = A[6];
        [r[0], r[1], r[2], r[3], r[4], r[5], 0.0]
    };
    /// Embedded fourth-order weights; `B5 − B4` weighs the error estimate.
    pub const B4: [f64; 7] = [
        5179.0 / 57600.0,
        0.0,
        7571.0 / 16695.0,
        393.0 / 640.0,
        -92097.0 / 339200.0,
        187.0 / 2100.0,
        1.0 / 40.0,
    ];
}

#[cfg(test)]
mod tests {
    use super::dormand_prince::{A, B4, B5, C};

    /// The classical order conditions (Hairer–Nørsett–Wanner §II.2): row sums give the stage
    /// times; the weights integrate polynomials exactly up to order 5 (B5) and 4 (B4).
    #[test]
    fn dormand_prince_meets_its_order_conditions() {
        for i in 0..7 {
            let row: f64 = A[i].iter().sum();
            assert!((row - C[i]).abs() < 1e-14, "row {i}");
        }
        for (b, order) in [(B5, 5), (B4, 4)] {
            // Σ b_i c_i^(q−1) = 1/q for q = 1..=order (the quadrature conditions).
            for q in 1..=order {
                let s: f64 = (0..7).map(|i| b[i] * C[i].powi(q - 1)).sum();
                assert!(
                    (s - 1.0 / q as f64).abs() < 1e-14,
                    "order {order}, q = {q}: {s}"
                );
            }
            // Σ b_i a_ij c_j = 1/6 (a third-order tree).
            let s: f64 = (0..7)
                .map(|i| b[i] * (0..6).map(|j| A[i][j] * C[j]).sum::<f64>())
                .sum();
            assert!((s - 1.0 / 6.0).abs() < 1e-14, "order {order}: {s}");
        }
        // The fourth-order solution is not the fifth: the pair estimates an error.
        assert!((0..7).any(|i| (B5[i] - B4[i]).abs() > 1e-3));
    }
}
