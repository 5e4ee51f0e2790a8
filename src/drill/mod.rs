//! Drilling-hole correction (seed 004, Bi et al. 2015): surface normals from four laser
//! readings, the Coons-patch error surface over four reference holes (and the bilinear
//! baseline), corrected holes, drilling poses, the hole-list CSV and the paper's example as
//! data. Ray casts and closest points on the panel go through [`crate::mesh::MeshIndex`]
//! (re-exported here).

mod coons;
mod correction;
mod error;
mod example;
mod holes_csv;
mod laser;
mod poses;

pub use crate::mesh::{ClosestPoint, MeshIndex, RayHit};
pub use coons::{arc_tangent_length, CoonsPatch, FergusonCurve, MAX_TANGENT_TO_CHORD};
pub use correction::{
    closest_parameters, correct_holes, Correction, CorrectionParams, ErrorSurface, Method,
    ReferenceHole, PARAM_OUTSIDE_TOLERANCE,
};
pub use error::DrillError;
pub use example::{
    paper_corner_params, paper_deformed, paper_example, paper_hole_params, paper_nominal_surface,
    paper_panel_mesh, PaperExample, PAPER_HALF_SECTOR, PAPER_LENGTH, PAPER_RADIUS,
};
pub use holes_csv::{parse_holes_csv, CsvRowError, HoleList, HoleRow};
pub use laser::{
    laser_points, laser_readings, normal_from_lasers, normal_from_points, BeamAim, SensorHead,
};
pub use poses::{drilling_path, PoseParams};
