//! Obstacles around the robot.
//!
//! A [`Scene`] holds the obstacles a method must keep the robot clear of. Methods accept a scene
//! today; scene files, parry3d shapes and the broad phase arrive with the obstacle work, and a
//! method that cannot handle a non-empty scene says so with [`crate::SolveError::Unsupported`].

/// Obstacles near the robot (none by default).
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// Minimum distance every robot feature keeps from every obstacle [m].
    pub clearance: f64,
    obstacle_count: usize,
}

impl Scene {
    /// A scene with no obstacles.
    pub fn empty() -> Self {
        Scene::default()
    }
    /// True when there are no obstacles.
    pub fn is_empty(&self) -> bool {
        self.obstacle_count == 0
    }
}
