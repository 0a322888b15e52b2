//! Small numerical kernels shared by the methods; nothing robot-specific.

pub mod active_qp;
pub mod ad;
pub mod dense;
pub mod disc_split;
pub mod kkt;
pub mod ode;
pub mod qp;
pub mod semisep;
pub mod so3;
/// The tests' deterministic generator (xorshift64), the one `tests/common/rng.rs` gives the
/// integration tests, for the unit tests here.
#[cfg(test)]
#[path = "../../tests/common/rng.rs"]
pub(crate) mod test_rng;
