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
