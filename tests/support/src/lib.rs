//! Test helpers that depend on nothing but std, shared by ccrkit's unit tests (`src/`), its
//! integration tests (`tests/common/` re-exports them) and its benches: a dev-dependency, so
//! no file of `src/` reaches into `tests/`.

pub mod port_robots;
pub mod rng;
pub mod scenes;
pub mod soft;
