//! Exports of a solved [`Shape`](crate::shape::Shape): URDF (+ SRDF and joint values) for
//! robotics tools, and the 3-D HTML view (`view`, with the `view` feature).
//!
//! JSON of the shape itself lives on [`Shape::to_json_string`](crate::shape::Shape::to_json_string).

pub mod urdf;
#[cfg(feature = "view")]
pub mod view;

pub use urdf::{
    export_urdf, rotation_from_rpy, rpy_from_rotation, JointValue, SectionJoints, UrdfExport,
    UrdfMode, UrdfOptions, DEFAULT_BACKBONE_DENSITY, DEFAULT_DISK_DENSITY,
};

use thiserror::Error;

/// Why an export could not be written.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum ExportError {
    /// The shape does not belong to the robot (e.g. a different number of disks).
    #[error("shape does not match robot `{robot}`: {reason}")]
    ShapeMismatch {
        /// Robot name.
        robot: String,
        /// What differs.
        reason: String,
    },
    /// A disk frame cannot be exported (non-finite numbers, a rotation that is not one).
    #[error("disk {disk}: {reason}")]
    BadDiskFrame {
        /// Disk index (0 = base).
        disk: usize,
        /// What is wrong.
        reason: String,
    },
    /// An option has a value the exporter cannot use.
    #[error("invalid option `{option}`: {reason}")]
    InvalidOption {
        /// Option name (e.g. `mode`).
        option: String,
        /// Why.
        reason: String,
    },
    /// urdf-rs could not serialize the robot.
    #[error("cannot write URDF: {reason}")]
    Urdf {
        /// urdf-rs's message.
        reason: String,
    },
    /// An input to an export (a plan, a sweep) cannot be used.
    #[error("invalid `{field}`: {reason}")]
    Input {
        /// What is wrong where (e.g. `waypoints[3].shape.disks`, `sweep line 7`).
        field: String,
        /// Why.
        reason: String,
    },
    /// A file could not be written.
    #[error("cannot write `{path}`: {reason}")]
    Io {
        /// Path of the file.
        path: String,
        /// What the operating system said.
        reason: String,
    },
}
