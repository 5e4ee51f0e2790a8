//! Consistent winding: flips faces so that neighbours traverse their shared edge in opposite
//! directions, as real files with flipped faces need before normals can be compared.
//!
//! No paper; the textbook propagation over manifold edges (as in MeshLab's "re-orient all
//! faces coherently"), done as a union–find with the parity of turns while the adjacency is
//! built (see `adjacency.rs`: one pass over the links instead of a breadth-first walk).
//! Which of the two windings a part of linked faces keeps: a closed one is turned so its
//! signed volume is positive (normals point outwards); an open one keeps the winding of the
//! larger share of its area in the file.
//! A non-orientable part (a Möbius strip) keeps at least one edge inconsistent; those are
//! counted (which edges are left inconsistent there depends on the order of the links).
//! Here: volumes of closed parts (and areas of open parts where some face must turn) are
//! summed per part in face order, then faces are turned in one sequential pass, in which
//! the import measures them (normals, areas, centroids) in their final winding (see
//! `orient_and_measure`).
//! Cost: two passes over the faces (and up to two over the parts' ids where some part is
//! open or some face turns); 21 bytes a part of scratch (38 when some face turns).

use super::adjacency::WindingParts;
use super::face_geometry::face_area;
use super::{FaceAdjacency, FaceGeometry, TriMesh};

/// What [`orient_consistently`] changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OrientationReport {
    /// Faces whose winding was reversed.
    pub flipped_faces: usize,
    /// Manifold edges whose two faces still disagree (only on non-orientable surfaces).
    pub inconsistent_edges: usize,
    /// Sets of faces linked by manifold edges, each oriented on its own.
    pub orientable_parts: usize,
}

/// Reverses faces of `mesh` (and updates `adjacency`, which must be the mesh's, to match)
/// until every manifold edge is traversed in opposite directions by its two faces, where
/// the surface allows it.
pub fn orient_consistently(mesh: &mut TriMesh, adjacency: &mut FaceAdjacency) -> OrientationReport {
    // The parts come with the adjacency; it is built again to have them.
    let (fresh, parts) = FaceAdjacency::with_parts(mesh, &mut |_, _| {});
    debug_assert!(fresh == *adjacency, "the adjacency must be the mesh's");
    *adjacency = fresh;
    orient(mesh, adjacency, &parts, None)
}

/// [`orient_consistently`] followed by [`FaceGeometry::new`] in the new winding, with the
/// same results, for an adjacency built with its `parts`: each face is measured once, in
/// the pass that turns it.
pub(crate) fn orient_and_measure(
    mesh: &mut TriMesh,
    adjacency: &mut FaceAdjacency,
    parts: &WindingParts,
) -> (OrientationReport, FaceGeometry) {
    let mut geometry = FaceGeometry::with_capacity(mesh.triangle_count());
    let report = orient(mesh, adjacency, parts, Some(&mut geometry));
    (report, geometry)
}

/// Turns the faces whose parity to their part's first face disagrees with the winding the
/// part keeps: a closed part the one that makes its signed volume positive (divergence
/// theorem, relative to a corner of its first face for accuracy far from the origin), an
/// open one the winding of the larger share of its area in the file. Volumes and areas are
/// summed per part in face order, in the first face's winding. With `geometry` (empty),
/// measures every face in its final winding, in the pass that turns it.
fn orient(
    mesh: &mut TriMesh,
    adjacency: &mut FaceAdjacency,
    parts: &WindingParts,
    mut geometry: Option<&mut FaceGeometry>,
) -> OrientationReport {
    let n = mesh.triangle_count();
    let count = parts.count;
    let part = |f: usize| ((parts.of_face[f] >> 1) as usize, parts.of_face[f] & 1 == 1);
    // What decides each part: its volume if it is closed (no open or non-manifold slot),
    // else the areas kept and turned, which matter only if some face turns.
    let mut closed = vec![true; count];
    if !parts.all_linked {
        for f in 0..n {
            closed[part(f).0] &= !adjacency.neighbours(f).contains(&super::NO_FACE);
        }
    }
    let mut weigh = vec![false; if parts.any_turned { count } else { 0 }];
    if parts.any_turned {
        for f in 0..n {
            let (p, turned) = part(f);
            weigh[p] |= turned && !closed[p];
        }
    }
    // Parts are numbered in order of their first face, so the first face of part p is
    // known when p is first met.
    let mut first_face: Vec<u32> = Vec::with_capacity(count);
    let mut volume = vec![0.0f64; count];
    let mut turned_area = vec![0.0f64; weigh.len()];
    let mut kept_area = vec![0.0f64; weigh.len()];
    for f in 0..n {
        let (p, turned) = part(f);
        if p == first_face.len() {
            first_face.push(f as u32);
        }
        if closed[p] {
            let first = mesh.triangles()[first_face[p] as usize][0];
            let o = mesh.positions()[first as usize].coords;
            let v = signed_volume6(mesh.corners(f), &o);
            if turned {
                volume[p] -= v;
            } else {
                volume[p] += v;
            }
        } else if parts.any_turned && weigh[p] {
            let area = face_area(mesh.corners(f));
            if turned {
                turned_area[p] += area;
            } else {
                kept_area[p] += area;
            }
        }
    }
    drop(first_face);
    let turn_part: Vec<bool> = (0..count)
        .map(|p| {
            if closed[p] {
                volume[p] < 0.0
            } else {
                parts.any_turned && weigh[p] && turned_area[p] > kept_area[p]
            }
        })
        .collect();
    drop((closed, weigh, volume, turned_area, kept_area));
    let mut report = OrientationReport {
        orientable_parts: count,
        inconsistent_edges: parts.inconsistent_edges,
        ..OrientationReport::default()
    };
    for f in 0..n {
        let (p, turned) = part(f);
        if turned != turn_part[p] {
            mesh.flip(f);
            adjacency.flip(f);
            report.flipped_faces += 1;
        }
        if let Some(geometry) = geometry.as_deref_mut() {
            geometry.push(mesh.corners(f));
        }
    }
    drop(turn_part);
    // A link is still wound alike exactly when its parity could not be satisfied.
    adjacency.set_winding_conflicts(report.inconsistent_edges);
    report
}

/// Signed volume of the tetrahedron from `origin` over a face with `corners` (positive for
/// an outward face of a closed surface around `origin`), times 6.
#[inline(always)]
fn signed_volume6(corners: [crate::math::Point3; 3], origin: &nalgebra::Vector3<f64>) -> f64 {
    let [a, b, c] = corners.map(|p| p.coords - origin);
    a.dot(&b.cross(&c))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point3;

    /// A tetrahedron with outward winding, optionally with some faces reversed.
    fn tetra(flip: &[usize]) -> TriMesh {
        let p = vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        let mut t = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        for &f in flip {
            t[f].swap(1, 2);
        }
        TriMesh::new(p, t).unwrap()
    }

    #[test]
    fn restores_outward_winding_of_a_closed_surface() {
        let reference = tetra(&[]);
        for flips in [vec![1], vec![0, 2], vec![0, 1, 2, 3]] {
            let mut mesh = tetra(&flips);
            let mut adj = FaceAdjacency::new(&mesh);
            let report = orient_consistently(&mut mesh, &mut adj);
            assert_eq!(report.flipped_faces, flips.len());
            assert_eq!(report.inconsistent_edges, 0);
            for f in 0..4 {
                let n = mesh.scaled_normal(f);
                assert!(n.dot(&reference.scaled_normal(f)) > 0.0);
            }
            assert_eq!(adj, FaceAdjacency::new(&mesh));
        }
    }
}
