//! Triangle meshes: STL input and output, welding, face adjacency, consistent winding and
//! per-face geometry. Everything downstream starts from [`import_stl`].

mod adjacency;
mod face_geometry;
mod face_groups;
mod import;
mod orientation;
mod spatial_index;
mod stl;
mod tri_mesh;
mod union_find;
mod weld;

/// How often (in faces) long loops report progress.
const PROGRESS_EVERY: usize = 1 << 16;

pub use adjacency::{FaceAdjacency, MAX_FACES, NO_FACE};
pub(crate) use face_geometry::is_degenerate;
pub use face_geometry::FaceGeometry;
pub use face_groups::{bounding_sphere, DrawChunk, DrawWriter, FaceGroups, EMPTY_BOX};
pub use import::{import_stl, prepare_mesh, ImportedMesh, MeshReport};
pub use orientation::{orient_consistently, OrientationReport};
pub use spatial_index::{ClosestPoint, MeshIndex, RayHit};
pub use stl::{
    binary_layout, read_stl, read_stl_with_progress, write_stl, BinaryStl, StlError, StlFormat,
    StlImport, StlInfo, StlStream, STL_HEAD_BYTES, STL_PREAMBLE_BYTES, STL_RECORD_BYTES,
};
pub use tri_mesh::{MeshError, TriMesh};
pub use union_find::{find_root, flatten, union_smallest};
pub use weld::Welder;
