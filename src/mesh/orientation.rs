//! Consistent winding: flips faces so that neighbours traverse their shared edge in opposite
//! directions, as real files with flipped faces need before normals can be compared.
//!
//! No paper; the textbook propagation over manifold edges (as in MeshLab's "re-orient all
//! faces coherently"), done as a union–find with the parity of turns (one pass over the
//! links instead of a breadth-first walk). Which of the two windings a patch of linked faces keeps:
//! a closed one is turned so its signed volume is positive (normals point outwards); an open
//! one keeps the winding of the larger share of its area in the file.
//! A non-orientable patch (a Möbius strip) keeps at least one edge inconsistent; those are
//! counted (which edges are left inconsistent there depends on the order of the links).
//! Fast path: when the adjacency found no wrongly wound and no non-manifold edge, the parts
//! are the components and only closed ones with negative volume are turned (one pass).
//! The propagation reads which links are wound alike from the adjacency (no triangle is
//! read while it runs); volumes and areas are summed per part in face order, and faces are
//! turned in one sequential pass at the end. For the import,
//! both paths measure the faces (normals, areas, centroids) in the pass that turns them
//! (see `orient_and_measure`).
//! Cost: linear in faces (near-linear: union–find with path halving); 5 bytes a face of
//! scratch, plus 29 bytes a part.

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

/// Whether face `g` uses the directed edge `a → b` (so it winds the same way as a face that
/// uses `a → b` too, which is inconsistent).
#[inline]
fn uses_directed_edge(t: &[u32; 3], a: u32, b: u32) -> bool {
    (t[0] == a && t[1] == b) || (t[1] == a && t[2] == b) || (t[2] == a && t[0] == b)
}

/// Reverses faces of `mesh` (and updates `adjacency` to match) until every manifold edge is
/// traversed in opposite directions by its two faces, where the surface allows it.
pub fn orient_consistently(mesh: &mut TriMesh, adjacency: &mut FaceAdjacency) -> OrientationReport {
    if adjacency.winding_conflicts() == 0 && adjacency.non_manifold_edges() == 0 {
        return turn_closed_components_outwards(mesh, adjacency, None);
    }
    propagate_winding(mesh, adjacency, None)
}

/// [`orient_consistently`] followed by [`FaceGeometry::new`] in the new winding, with the
/// same results; on the fast path each face is measured in the pass that turns it.
pub(crate) fn orient_and_measure(
    mesh: &mut TriMesh,
    adjacency: &mut FaceAdjacency,
) -> (OrientationReport, FaceGeometry) {
    if adjacency.winding_conflicts() == 0 && adjacency.non_manifold_edges() == 0 {
        let mut geometry = FaceGeometry::with_capacity(mesh.triangle_count());
        let report = turn_closed_components_outwards(mesh, adjacency, Some(&mut geometry));
        return (report, geometry);
    }
    let mut geometry = FaceGeometry::with_capacity(mesh.triangle_count());
    let report = propagate_winding(mesh, adjacency, Some(&mut geometry));
    (report, geometry)
}

/// The general case: which faces must turn relative to which, over manifold links, by a
/// union–find that keeps for each face the parity of turns to its parent (one sequential
/// pass over the links, the smaller root kept, so each part's root is its smallest face).
/// A link whose two faces are already in one part with the wrong parity is inconsistent.
/// With `geometry`, faces are measured in the pass that sums the parts' volumes, and those
/// turned in the last pass have their normals measured again.
fn propagate_winding(
    mesh: &mut TriMesh,
    adjacency: &mut FaceAdjacency,
    mut geometry: Option<&mut FaceGeometry>,
) -> OrientationReport {
    let n = mesh.triangle_count();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    // Whether a face is turned relative to its parent.
    let mut odd = vec![0u8; n];
    // Root and parity of `x` to it, halving the path on the way. Ends: a parent is never
    // larger than its child, so x decreases.
    let find = |parent: &mut [u32], odd: &mut [u8], mut x: u32| -> (u32, u8) {
        let mut parity = 0;
        loop {
            let up = parent[x as usize];
            if up == x {
                return (x, parity);
            }
            let top = parent[up as usize];
            odd[x as usize] ^= odd[up as usize];
            parent[x as usize] = top;
            parity ^= odd[x as usize];
            x = top;
        }
    };
    let mut report = OrientationReport::default();
    for f in 0..n {
        for (k, g) in adjacency.neighbours(f).into_iter().enumerate() {
            if g == super::NO_FACE || (g as usize) < f {
                continue;
            }
            // g turns relative to f exactly when the file winds them alike.
            let turn = u8::from(adjacency.same_direction(f, k));
            let (rf, pf) = find(&mut parent, &mut odd, f as u32);
            let (rg, pg) = find(&mut parent, &mut odd, g);
            if rf == rg {
                if pf ^ pg != turn {
                    report.inconsistent_edges += 1;
                }
            } else {
                let (lo, hi) = if rf < rg { (rf, rg) } else { (rg, rf) };
                parent[hi as usize] = lo;
                odd[hi as usize] = pf ^ pg ^ turn;
            }
        }
    }
    // Each face's part (numbered in order of its smallest face) and parity to the part's root.
    for f in 0..n {
        let (root, parity) = find(&mut parent, &mut odd, f as u32);
        (parent[f], odd[f]) = (root, parity);
    }
    // Now every face points at its root, its part's smallest face, which is numbered
    // (overwritten with its part id) before the part's other faces are met.
    let mut part_count = 0u32;
    for f in 0..n {
        let root = parent[f];
        parent[f] = if root as usize == f {
            part_count += 1;
            part_count - 1
        } else {
            parent[root as usize]
        };
    }
    report.orientable_parts = part_count as usize;
    let parts = part_count as usize;
    // Per part: closed (no open or non-manifold slot), the signed volume relative to a corner
    // of its first face (divergence theorem; for accuracy far from the origin), and the areas
    // kept and turned, all in the root's winding.
    let mut closed = vec![true; parts];
    // Parts are numbered in order of their first face, so the first face of part p is
    // known when p is first met.
    let mut first_face: Vec<u32> = Vec::with_capacity(parts);
    let mut volume = vec![0.0f64; parts];
    let mut turned_area = vec![0.0f64; parts];
    let mut kept_area = vec![0.0f64; parts];
    for f in 0..n {
        let p = parent[f] as usize;
        if p == first_face.len() {
            first_face.push(f as u32);
        }
        let o = mesh.corners(first_face[p] as usize)[0].coords;
        closed[p] &= !adjacency.neighbours(f).contains(&super::NO_FACE);
        let v = signed_volume6(mesh, f, &o);
        // Faces are measured in the file's winding here; a face turned later has only its
        // normal measured again (see `FaceGeometry::turn`): its area is the same either way.
        let area = match geometry.as_deref_mut() {
            Some(geometry) => {
                geometry.push(mesh.corners(f));
                geometry.areas()[f]
            }
            None => super::face_geometry::measure(mesh.corners(f)).1,
        };
        if odd[f] == 1 {
            volume[p] -= v;
            turned_area[p] += area;
        } else {
            volume[p] += v;
            kept_area[p] += area;
        }
    }
    drop(first_face);
    // A closed part turns so its volume is positive; an open one keeps the winding of the
    // larger share of its area in the file.
    let turn_part: Vec<bool> = (0..parts)
        .map(|p| {
            if closed[p] {
                volume[p] < 0.0
            } else {
                turned_area[p] > kept_area[p]
            }
        })
        .collect();
    drop((closed, volume, turned_area, kept_area));
    for f in 0..n {
        if (odd[f] == 1) != turn_part[parent[f] as usize] {
            mesh.flip(f);
            adjacency.flip(f);
            if let Some(geometry) = geometry.as_deref_mut() {
                geometry.turn(f, mesh.corners(f));
            }
            report.flipped_faces += 1;
        }
    }
    drop((parent, odd, turn_part));
    let triangles = mesh.triangles();
    adjacency.set_winding_conflicts(report.inconsistent_edges, |f, k, g| {
        let t = &triangles[f];
        uses_directed_edge(&triangles[g], t[k], t[(k + 1) % 3])
    });
    report
}

/// Signed volume of tetrahedra from `origin` over a face (positive for an outward face of a
/// closed surface around `origin`), times 6.
#[inline(always)]
fn signed_volume6(mesh: &TriMesh, f: usize, origin: &nalgebra::Vector3<f64>) -> f64 {
    let [a, b, c] = mesh.corners(f).map(|p| p.coords - origin);
    a.dot(&b.cross(&c))
}

/// The fast path: windings already agree, so each component is one orientable part. With
/// `geometry` (empty), also measures every face in its final winding, in the pass that
/// turns the faces of inside-out components.
fn turn_closed_components_outwards(
    mesh: &mut TriMesh,
    adjacency: &mut FaceAdjacency,
    mut geometry: Option<&mut FaceGeometry>,
) -> OrientationReport {
    let count = adjacency.components();
    let mut volume = vec![0.0; count];
    let mut closed = vec![true; count];
    // Relative to a vertex of each component, for accuracy far from the origin.
    let mut origin = vec![None; count];
    for f in 0..mesh.triangle_count() {
        let c = adjacency.component_of()[f] as usize;
        let o = *origin[c].get_or_insert(mesh.corners(f)[0].coords);
        volume[c] += signed_volume6(mesh, f, &o);
        closed[c] &= !adjacency.neighbours(f).contains(&super::NO_FACE);
    }
    let mut report = OrientationReport {
        orientable_parts: count,
        ..OrientationReport::default()
    };
    for f in 0..mesh.triangle_count() {
        let c = adjacency.component_of()[f] as usize;
        if closed[c] && volume[c] < 0.0 {
            mesh.flip(f);
            adjacency.flip(f);
            report.flipped_faces += 1;
        }
        if let Some(geometry) = geometry.as_deref_mut() {
            geometry.push(mesh.corners(f));
        }
    }
    report
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
