//! A small deterministic generator (xorshift64), so every run of a test draws the same values:
//! the integration tests' `common::rng`, the library's unit tests' `crate::numeric::test_rng`.

/// Xorshift64 state; seed it with any non-zero value.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1), 53 bits.
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}
