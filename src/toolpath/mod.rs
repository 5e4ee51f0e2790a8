//! Tool paths shared by every system (spray passes, geodesic passes, drilling poses) and their
//! exports for a robot cell or a colleague: CSV, JSON, ABB RAPID and KUKA KRL.
//!
//! A [`ToolPath`] is a sequence of [`Pose`]s in the mesh's own length unit; exports convert to
//! millimetres with [`ExportOptions::mm_per_unit`].

mod export;
mod path;

pub use export::{to_csv, to_json, to_krl, to_rapid, ExportOptions};
pub use path::{Pose, PoseKind, ToolPath, ToolPathError};
