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
/// The tests' deterministic generator (xorshift64), the one the integration tests use
/// (`ccrkit-test-support`, a dev-dependency), for the unit tests here.
#[cfg(test)]
pub(crate) use ccrkit_test_support::rng as test_rng;
