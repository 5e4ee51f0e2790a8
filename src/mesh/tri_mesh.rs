//! The indexed triangle mesh every algorithm reads.

use crate::math::{Point3, Real, Vector3};

/// Why a set of positions and triangles is not a valid [`TriMesh`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// No triangles at all.
    #[error("the mesh has no triangles")]
    NoTriangles,
    /// A triangle names a vertex that does not exist.
    #[error(
        "triangle {triangle} uses vertex {vertex}, but the mesh has only {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the offending triangle.
        triangle: usize,
        /// The vertex index it names.
        vertex: u32,
        /// How many vertices there are.
        vertex_count: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFinite {
        /// Index of the offending vertex.
        vertex: usize,
    },
    /// More vertices or triangles than 32-bit indices can address.
    #[error("the mesh has {count} elements; at most {max} triangles and vertices are supported", max = super::MAX_FACES)]
    TooLarge {
        /// The element count that overflowed.
        count: usize,
    },
}

/// An indexed triangle mesh: finite positions and triangles of three vertex indices each.
///
/// Indexing is written down once here: vertex `v` is `positions[v]`, face `f` is
/// `triangles[f]`, and its corners wind counter-clockwise seen from the side its normal
/// points to. Per-face data elsewhere in the crate is a `Vec` indexed by `f`.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    positions: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Builds a mesh after checking it: at least one triangle, indices in range, finite
    /// coordinates, and counts that fit 32-bit indices.
    pub fn new(positions: Vec<Point3>, triangles: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        let mesh = TriMesh {
            positions,
            triangles,
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// [`TriMesh::new`] for arrays built by the welder, whose coordinates are finite (read
    /// from finite `f32`s) and whose indices name vertices it created: only the counts are
    /// checked, sparing two passes over the mesh.
    pub(crate) fn from_welded(
        positions: Vec<Point3>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self, MeshError> {
        let mesh = TriMesh {
            positions,
            triangles,
        };
        mesh.check_counts()?;
        debug_assert!(mesh.validate().is_ok());
        Ok(mesh)
    }

    /// At least one triangle, and counts that fit 32-bit indices.
    fn check_counts(&self) -> Result<(), MeshError> {
        if self.triangles.is_empty() {
            return Err(MeshError::NoTriangles);
        }
        if self.positions.len() >= u32::MAX as usize || self.triangles.len() > super::MAX_FACES {
            return Err(MeshError::TooLarge {
                count: self.positions.len().max(self.triangles.len()),
            });
        }
        Ok(())
    }

    /// Checks the invariants [`TriMesh::new`] establishes (tests and debug builds call it).
    pub fn validate(&self) -> Result<(), MeshError> {
        self.check_counts()?;
        if let Some(vertex) = self
            .positions
            .iter()
            .position(|p| !p.coords.iter().all(|c| c.is_finite()))
        {
            return Err(MeshError::NonFinite { vertex });
        }
        let vertex_count = self.positions.len();
        for (triangle, t) in self.triangles.iter().enumerate() {
            if let Some(&vertex) = t.iter().find(|&&v| v as usize >= vertex_count) {
                return Err(MeshError::IndexOutOfRange {
                    triangle,
                    vertex,
                    vertex_count,
                });
            }
        }
        Ok(())
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[Point3] {
        &self.positions
    }

    /// Positions as flat `[x0, y0, z0, x1, …]` in `f32` (exact for meshes read from STL),
    /// the layout GPU buffers take.
    pub fn positions_f32(&self) -> Vec<f32> {
        self.positions
            .iter()
            .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect()
    }

    /// Triangles as vertex indices.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The three corner positions of face `f`.
    #[inline]
    pub fn corners(&self, f: usize) -> [Point3; 3] {
        let [a, b, c] = self.triangles[f];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// `(b − a) × (c − a)` of face `f`: along its normal, with length twice its area.
    #[inline]
    pub fn scaled_normal(&self, f: usize) -> Vector3 {
        let [a, b, c] = self.corners(f);
        (b - a).cross(&(c - a))
    }

    /// Total surface area.
    pub fn area(&self) -> Real {
        (0..self.triangles.len())
            .map(|f| 0.5 * self.scaled_normal(f).norm())
            .sum()
    }

    /// Axis-aligned bounding box of the vertices: `(min, max)`.
    pub fn bounding_box(&self) -> (Point3, Point3) {
        let mut min = Point3::from(Vector3::repeat(Real::INFINITY));
        let mut max = Point3::from(Vector3::repeat(Real::NEG_INFINITY));
        for p in &self.positions {
            min = min.inf(p);
            max = max.sup(p);
        }
        (min, max)
    }

    /// Reverses the winding of face `f` (swaps its last two corners).
    pub(crate) fn flip(&mut self, f: usize) {
        self.triangles[f].swap(1, 2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_names_the_offending_element() {
        let p = vec![Point3::origin(), Point3::new(1.0, 0.0, 0.0)];
        assert_eq!(
            TriMesh::new(p.clone(), vec![[0, 1, 2]]),
            Err(MeshError::IndexOutOfRange {
                triangle: 0,
                vertex: 2,
                vertex_count: 2
            })
        );
        assert_eq!(TriMesh::new(p, vec![]), Err(MeshError::NoTriangles));
        let nan = vec![
            Point3::origin(),
            Point3::new(f64::NAN, 0.0, 0.0),
            Point3::origin(),
        ];
        assert_eq!(
            TriMesh::new(nan, vec![[0, 1, 2]]),
            Err(MeshError::NonFinite { vertex: 1 })
        );
    }
}
