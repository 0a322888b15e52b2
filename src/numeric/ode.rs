//! Explicit Runge–Kutta methods the integrators use: the classical RK4 step over any
//! right-hand side, and the Dormand–Prince 5(4) tableau.

/// The classical fourth-order Runge–Kutta method (Kutta 1901; Hairer, Nørsett & Wanner,
/// *Solving Ordinary Differential Equations I*, §II.1, Table 1.2): stage times `C = [0, ½, ½,
/// 1]`, each stage evaluated at `y + h C_i k_{i−1}` (the tableau is zero off its
/// sub-diagonal, which equals `C`), and weights `[1, 2, 2, 1]/6`.
///
/// Generic over the state (anything with `+` and `× f64`: a static vector, a scalar), so the
/// rod steps its state, its path-length quadrature and its tangents with the same formulas.
pub mod rk4 {
    use std::ops::{Add, Mul};

    /// Stage times as fractions of the step.
    pub const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];

    /// Stage `i`'s input: `y` at stage 0, else `y + h C_i k_{i−1}` (`k` holds the slopes of
    /// the stages before `i`).
    #[inline(always)]
    pub fn stage<Y: Copy + Add<Output = Y> + Mul<f64, Output = Y>>(
        y: Y,
        k: &[Y; 4],
        i: usize,
        h: f64,
    ) -> Y {
        if i == 0 {
            y
        } else {
            y + k[i - 1] * (C[i] * h)
        }
    }

    /// The step's increment from the four stage slopes: `h (k₁ + 2k₂ + 2k₃ + k₄)/6`.
    #[inline(always)]
    pub fn increment<Y: Copy + Add<Output = Y> + Mul<f64, Output = Y>>(k: &[Y; 4], h: f64) -> Y {
        (k[0] + (k[1] + k[2]) * 2.0 + k[3]) * (h / 6.0)
    }

    /// One step of size `h` from `(s, y)`: `slope(i, s_i, y_i)` is the right-hand side at
    /// stage `i` (it may also record per-stage quadrature rates, to be weighed with
    /// [`increment`]). Returns the increment of `y`.
    #[inline(always)]
    pub fn step<Y: Copy + Add<Output = Y> + Mul<f64, Output = Y>>(
        s: f64,
        h: f64,
        y: Y,
        mut slope: impl FnMut(usize, f64, &Y) -> Y,
    ) -> Y {
        let mut k = [y; 4];
        for i in 0..4 {
            let yi = stage(y, &k, i, h);
            k[i] = slope(i, s + C[i] * h, &yi);
        }
        increment(&k, h)
    }
}

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
    use super::rk4;

    /// RK4 integrates polynomials in `s` up to degree 3 exactly (its quadrature is Simpson's
    /// rule), and on `y' = y` its error over `[0, 1]` falls as `h⁴` (×16 per halving).
    #[test]
    fn rk4_has_order_four() {
        let f = |s: f64| 1.0 + s - 3.0 * s * s + 4.0 * s * s * s;
        let exact = |s: f64| s + s * s / 2.0 - s * s * s + s.powi(4);
        let mut y = 0.0;
        for j in 0..3 {
            let s = 0.3 * j as f64;
            y += rk4::step(s, 0.3, y, |_, t, _| f(t));
        }
        assert!((y - exact(0.9)).abs() < 1e-14, "{y}");
        let err = |n: usize| {
            let h = 1.0 / n as f64;
            let mut y = 1.0;
            for j in 0..n {
                y += rk4::step(j as f64 * h, h, y, |_, _, y| *y);
            }
            (y - 1f64.exp()).abs()
        };
        let ratio = err(8) / err(16);
        assert!((ratio - 16.0).abs() < 1.0, "error ratio {ratio}");
    }

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
