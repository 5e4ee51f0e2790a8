//! Geodesically equidistant passes (WAAM beads, grinding, spray): the geodesic distance from a
//! source curve on the surface, by the paper's voxel method or by a more accurate mesh
//! method, its iso-distance lines and the tool path linking them.
//!
//! Entry point: [`geodesic_distance`] → [`DistanceField`] → [`DistanceField::iso_lines`] /
//! [`DistanceField::tool_path`].

mod exact;
mod field;
mod focal;
mod fronts;
mod iso_lines;
mod params;
mod source;
mod surface;
mod unfolding;
mod virtual_source;
mod voxel;
mod voxel_paths;

pub use field::{geodesic_distance, geodesic_distance_cached, DistanceField, MAX_LEVELS};
pub use iso_lines::IsoLine;
pub use params::{DistanceParams, GeodesicError, LinkOrder, Method, PathParams, Progress};
pub use source::GeodesicSource;
pub use surface::SurfaceCache;
pub use voxel::VoxelField;

use crate::mesh::{FaceAdjacency, TriMesh};

/// Boundary loops of the mesh (or of a face subset) as vertex ids, longest first: the loops
/// a [`GeodesicSource::Boundary`] numbers.
pub fn boundary_loops(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    faces: Option<&[u32]>,
) -> Result<Vec<Vec<u32>>, GeodesicError> {
    let surface = surface::Surface::new(mesh, adjacency, faces)?;
    Ok(source::boundary_loops(&surface))
}
