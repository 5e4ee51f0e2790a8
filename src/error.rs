//! The crate's error type: one variant per module, each wrapping that module's own enum.

use crate::drill::DrillError;
use crate::geodesic::GeodesicError;
use crate::mesh::{MeshError, StlError};
use crate::segment::ParamError;
use crate::spray::SprayError;
use crate::toolpath::ToolPathError;

/// Any error the crate returns. Messages are written for the person who supplied the input.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The bytes are not a readable STL file.
    #[error(transparent)]
    Stl(#[from] StlError),
    /// The mesh data violates an invariant (index out of range, non-finite coordinate, …).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Segmentation parameters are out of range or contradictory.
    #[error(transparent)]
    Params(#[from] ParamError),
    /// Spray planning parameters or the face selection are invalid.
    #[error(transparent)]
    Spray(#[from] SprayError),
    /// A tool path or one of its export options is invalid.
    #[error(transparent)]
    ToolPath(#[from] ToolPathError),
    /// A geodesic source or parameter is invalid.
    #[error(transparent)]
    Geodesic(#[from] GeodesicError),
    /// Drilling input (laser readings, reference holes, holes) is invalid.
    #[error(transparent)]
    Drill(#[from] DrillError),
}

/// `Result` with the crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
