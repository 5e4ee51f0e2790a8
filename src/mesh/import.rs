//! The whole import: STL bytes → welded, consistently wound mesh with its adjacency,
//! per-face geometry and a report of what was found.

use super::orientation::orient_and_measure;
use super::stl::read_stl_with_progress;
use super::{FaceAdjacency, FaceGeometry, StlError, StlFormat, StlImport, TriMesh};
use crate::math::Real;

/// What a user should know about an imported mesh (serialised for JavaScript in camelCase).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MeshReport {
    /// Binary or ASCII.
    pub format: StlFormat,
    /// Triangles kept.
    pub triangles: usize,
    /// Welded vertices.
    pub vertices: usize,
    /// Surface area, squared model units.
    pub area: Real,
    /// Bounding-box corner with the smallest coordinates.
    pub bbox_min: [Real; 3],
    /// Bounding-box corner with the largest coordinates.
    pub bbox_max: [Real; 3],
    /// Edges with one face (holes, open borders).
    pub boundary_edges: usize,
    /// Edges with three or more faces.
    pub non_manifold_edges: usize,
    /// Faces with no usable normal (zero or near-zero height).
    pub degenerate_triangles: usize,
    /// Triangles skipped for NaN or infinite coordinates.
    pub skipped_triangles: usize,
    /// Edge-connected components.
    pub components: usize,
    /// Bytes after a binary file's last triangle.
    pub trailing_bytes: usize,
    /// Faces whose winding was reversed to agree with their neighbours.
    pub flipped_triangles: usize,
    /// Manifold edges whose faces could not be made to agree (non-orientable surface).
    pub inconsistent_edges: usize,
}

/// A mesh ready for the algorithms: consistently wound, with adjacency and face geometry.
#[derive(Debug, Clone)]
pub struct ImportedMesh {
    /// The welded, re-wound mesh.
    pub mesh: TriMesh,
    /// Its face adjacency (slots match the re-wound triangles).
    pub adjacency: FaceAdjacency,
    /// Normals, areas and centroids in the re-wound winding.
    pub geometry: FaceGeometry,
    /// What was found.
    pub report: MeshReport,
}

/// Reads STL bytes and prepares the mesh, reporting `(stage, fraction)` as it goes
/// (stages `parse`, `adjacency`, `orient`, `geometry`). Refuses a file whose triangles are
/// all degenerate ([`StlError::AllDegenerate`]).
pub fn import_stl(
    bytes: &[u8],
    progress: &mut dyn FnMut(&str, f64),
) -> Result<ImportedMesh, StlError> {
    prepare_mesh(read_stl_with_progress(bytes, progress)?, progress)
}

/// The second half of [`import_stl`], for a mesh already read (so that the caller can free
/// the file's bytes first): adjacency, winding, geometry and report, with the stages
/// `adjacency`, `orient`, `geometry`.
pub fn prepare_mesh(
    import: StlImport,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<ImportedMesh, StlError> {
    let mut mesh = import.mesh;
    let (mut adjacency, parts) = FaceAdjacency::with_parts(&mesh, progress);
    progress("orient", 0.0);
    // The geometry is computed with the winding (in the same pass where it can be).
    let (orientation, geometry) = orient_and_measure(&mut mesh, &mut adjacency, &parts);
    drop(parts);
    progress("geometry", 0.0);
    // Degenerate as the report counts it (FaceGeometry, DEGENERATE_HEIGHT_RATIO): with no
    // usable normal anywhere, every later stage would run on noise.
    if geometry.degenerate_count() == mesh.triangle_count() {
        return Err(StlError::AllDegenerate {
            count: mesh.triangle_count(),
        });
    }
    let (min, max) = mesh.bounding_box();
    let report = MeshReport {
        format: import.info.format,
        triangles: mesh.triangle_count(),
        vertices: mesh.vertex_count(),
        area: geometry.total_area(),
        bbox_min: min.coords.into(),
        bbox_max: max.coords.into(),
        boundary_edges: adjacency.boundary_edges(),
        non_manifold_edges: adjacency.non_manifold_edges(),
        degenerate_triangles: geometry.degenerate_count(),
        skipped_triangles: import.info.skipped_triangles,
        components: adjacency.components(),
        trailing_bytes: import.info.trailing_bytes,
        flipped_triangles: orientation.flipped_faces,
        inconsistent_edges: orientation.inconsistent_edges,
    };
    debug_assert!(mesh.validate().is_ok());
    progress("geometry", 1.0);
    Ok(ImportedMesh {
        mesh,
        adjacency,
        geometry,
        report,
    })
}
