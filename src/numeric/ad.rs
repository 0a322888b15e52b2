//! Second-order forward-mode automatic differentiation on fixed-size numbers.
//!
//! One number type, [`Jet<N, M>`]: [`D2<N>`] (`M = N`) carries a value, its gradient and its
//! Hessian with respect to `N` variables, [`D1<N>`] (`M = 0`) only value and gradient, so a
//! function written once over [`Real`] yields exact first (and second) derivatives (the
//! section problems of the geometric method use `D2<6>`, the energy model's chord Jacobians
//! `D1<4 m>`). Unary functions use the chain rule
//! `∇f(u) = f′ ∇u`, `∇²f(u) = f′ ∇²u + f″ ∇u ∇uᵀ`; products use the Leibniz rule.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// Scalar arithmetic shared by `f64` and [`Jet`].
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Mul<f64, Output = Self>
{
    /// A constant.
    fn cst(v: f64) -> Self;
    /// The plain value.
    fn val(&self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Four-quadrant arctangent of `self / x`.
    fn atan2(self, x: Self) -> Self;
}

impl Real for f64 {
    fn cst(v: f64) -> Self {
        v
    }
    fn val(&self) -> f64 {
        *self
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
}

/// A number with its gradient with respect to `N` variables and, when `M = N`, its Hessian
/// (`M = 0`: first order only, no Hessian stored or computed). Use the aliases [`D1`] and
/// [`D2`]; other `M` are refused at compile time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet<const N: usize, const M: usize> {
    /// Value.
    pub v: f64,
    /// Gradient.
    pub g: [f64; N],
    /// Hessian (symmetric, stored in full; empty when `M = 0`).
    pub h: [[f64; M]; M],
}

/// First-order forward AD: value and gradient with respect to `N` variables.
pub type D1<const N: usize> = Jet<N, 0>;

/// Second-order forward AD: value, gradient and Hessian with respect to `N` variables.
pub type D2<const N: usize> = Jet<N, N>;

impl<const N: usize, const M: usize> Jet<N, M> {
    /// Only `M = 0` (first order) and `M = N` (second order) make sense.
    const ORDER_OK: () = assert!(M == 0 || M == N, "Jet<N, M> needs M = 0 or M = N");

    /// The variable number `i` with value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::ORDER_OK;
        let mut g = [0.0; N];
        g[i] = 1.0;
        Jet {
            v,
            g,
            h: [[0.0; M]; M],
        }
    }

    /// Apply a unary function with value `f`, derivative `df`, second derivative `d2f`.
    fn chain(self, f: f64, df: f64, d2f: f64) -> Self {
        let mut out = Jet {
            v: f,
            g: [0.0; N],
            h: [[0.0; M]; M],
        };
        for i in 0..N {
            out.g[i] = df * self.g[i];
        }
        for i in 0..M {
            for j in i..M {
                let v = df * self.h[i][j] + d2f * self.g[i] * self.g[j];
                out.h[i][j] = v;
                out.h[j][i] = v;
            }
        }
        out
    }
}

impl<const N: usize, const M: usize> Add for Jet<N, M> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for i in 0..N {
            self.g[i] += o.g[i];
        }
        for i in 0..M {
            for j in 0..M {
                self.h[i][j] += o.h[i][j];
            }
        }
        self
    }
}

impl<const N: usize, const M: usize> Sub for Jet<N, M> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self + (-o)
    }
}

impl<const N: usize, const M: usize> Neg for Jet<N, M> {
    type Output = Self;
    fn neg(mut self) -> Self {
        self.v = -self.v;
        for i in 0..N {
            self.g[i] = -self.g[i];
        }
        for i in 0..M {
            for j in 0..M {
                self.h[i][j] = -self.h[i][j];
            }
        }
        self
    }
}

impl<const N: usize, const M: usize> Mul for Jet<N, M> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut out = Jet {
            v: self.v * o.v,
            g: [0.0; N],
            h: [[0.0; M]; M],
        };
        for i in 0..N {
            out.g[i] = self.v * o.g[i] + o.v * self.g[i];
        }
        for i in 0..M {
            for j in i..M {
                let v = self.v * o.h[i][j]
                    + o.v * self.h[i][j]
                    + self.g[i] * o.g[j]
                    + o.g[i] * self.g[j];
                out.h[i][j] = v;
                out.h[j][i] = v;
            }
        }
        out
    }
}

impl<const N: usize, const M: usize> Div for Jet<N, M> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.v;
        self * o.chain(inv, -inv * inv, 2.0 * inv * inv * inv)
    }
}

impl<const N: usize, const M: usize> Add<f64> for Jet<N, M> {
    type Output = Self;
    fn add(mut self, o: f64) -> Self {
        self.v += o;
        self
    }
}

impl<const N: usize, const M: usize> Mul<f64> for Jet<N, M> {
    type Output = Self;
    fn mul(mut self, o: f64) -> Self {
        self.v *= o;
        for i in 0..N {
            self.g[i] *= o;
        }
        for i in 0..M {
            for j in 0..M {
                self.h[i][j] *= o;
            }
        }
        self
    }
}

impl<const N: usize, const M: usize> Real for Jet<N, M> {
    fn cst(v: f64) -> Self {
        Jet {
            v,
            g: [0.0; N],
            h: [[0.0; M]; M],
        }
    }
    fn val(&self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }
    /// atan2(y, x) with ∂/∂y = x/ρ², ∂/∂x = −y/ρ², ∂²/∂y² = −2xy/ρ⁴, ∂²/∂x² = 2xy/ρ⁴,
    /// ∂²/∂x∂y = (y² − x²)/ρ⁴, ρ² = x² + y².
    fn atan2(self, x: Self) -> Self {
        let y = self;
        let r2 = x.v * x.v + y.v * y.v;
        let r4 = r2 * r2;
        let (fy, fx) = (x.v / r2, -y.v / r2);
        let (fyy, fxx, fxy) = (
            -2.0 * x.v * y.v / r4,
            2.0 * x.v * y.v / r4,
            (y.v * y.v - x.v * x.v) / r4,
        );
        let mut out = Jet {
            v: y.v.atan2(x.v),
            g: [0.0; N],
            h: [[0.0; M]; M],
        };
        for i in 0..N {
            out.g[i] = fy * y.g[i] + fx * x.g[i];
        }
        for i in 0..M {
            for j in i..M {
                let v = fy * y.h[i][j]
                    + fx * x.h[i][j]
                    + fyy * y.g[i] * y.g[j]
                    + fxx * x.g[i] * x.g[j]
                    + fxy * (y.g[i] * x.g[j] + x.g[i] * y.g[j]);
                out.h[i][j] = v;
                out.h[j][i] = v;
            }
        }
        out
    }
}

/// A 3-vector over any [`Real`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct V3<T>(pub [T; 3]);

impl<T: Real> V3<T> {
    /// From plain numbers.
    pub fn cst(v: &nalgebra::Vector3<f64>) -> Self {
        V3([T::cst(v.x), T::cst(v.y), T::cst(v.z)])
    }
    /// Dot product.
    pub fn dot(&self, o: &Self) -> T {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }
    /// Cross product.
    pub fn cross(&self, o: &Self) -> Self {
        let (a, b) = (&self.0, &o.0);
        V3([
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ])
    }
    /// Dot product with a constant vector.
    pub fn dot_c(&self, b: &nalgebra::Vector3<f64>) -> T {
        self.0[0] * b.x + self.0[1] * b.y + self.0[2] * b.z
    }
    /// Euclidean norm.
    pub fn norm(&self) -> T {
        self.dot(self).sqrt()
    }
    /// Sum.
    pub fn add(&self, o: &Self) -> Self {
        V3([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
    /// Angle between two vectors, `atan2(|a × b|, a · b)` (well-conditioned near 0 and π,
    /// unlike `acos`).
    pub fn angle(&self, o: &Self) -> T {
        self.cross(o).norm().atan2(self.dot(o))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks D2 derivatives of a composite function against central finite differences.
    #[test]
    fn hessian_matches_finite_differences() {
        fn f<T: Real>(x: [T; 2]) -> T {
            let a = V3([x[0], x[1], T::cst(0.3)]);
            let b = V3([T::cst(0.2), x[0] * x[1], T::cst(1.0)]);
            a.angle(&b) + (x[0] * x[0] + T::cst(1.0)).sqrt() / (x[1] + 2.0)
        }
        let x0 = [0.4, -0.7];
        let d = f([D2::<2>::var(x0[0], 0), D2::<2>::var(x0[1], 1)]);
        let h = 1e-5;
        for i in 0..2 {
            let mut xp = x0;
            let mut xm = x0;
            xp[i] += h;
            xm[i] -= h;
            let fd = (f(xp) - f(xm)) / (2.0 * h);
            assert!((fd - d.g[i]).abs() < 1e-8, "gradient {i}");
            let dp = f([D2::<2>::var(xp[0], 0), D2::<2>::var(xp[1], 1)]);
            let dm = f([D2::<2>::var(xm[0], 0), D2::<2>::var(xm[1], 1)]);
            for j in 0..2 {
                let fd2 = (dp.g[j] - dm.g[j]) / (2.0 * h);
                assert!((fd2 - d.h[i][j]).abs() < 1e-6, "hessian {i}{j}");
            }
        }
    }

    /// The first-order jet carries the same value and gradient as the second-order one.
    #[test]
    fn first_order_matches_second_order() {
        fn f<T: Real>(x: [T; 3]) -> T {
            let a = V3([x[0], x[1] * x[2], T::cst(0.3)]);
            (a.dot(&a) + 1.0).sqrt() / (x[2] * 2.0 + 3.0) - a.angle(&V3([x[2], x[0], x[1]]))
        }
        let x0 = [0.4, -0.7, 1.3];
        let d1 = f([D1::<3>::var(x0[0], 0), D1::var(x0[1], 1), D1::var(x0[2], 2)]);
        let d2 = f([D2::<3>::var(x0[0], 0), D2::var(x0[1], 1), D2::var(x0[2], 2)]);
        assert_eq!(d1.v, d2.v);
        for i in 0..3 {
            assert!(
                (d1.g[i] - d2.g[i]).abs() <= 1e-15 * d2.g[i].abs().max(1.0),
                "{i}"
            );
        }
    }
}
