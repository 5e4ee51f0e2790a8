//! Consistent winding: flips faces so that neighbours traverse their shared edge in opposite
//! directions, as real files with flipped faces need before normals can be compared.
//!
//! No paper; the textbook breadth-first propagation over manifold edges (as in MeshLab's
//! "re-orient all faces coherently"). Which of the two windings a patch of linked faces keeps:
//! a closed one is turned so its signed volume is positive (normals point outwards); an open
//! one keeps the winding of the larger share of its area in the file.
//! A non-orientable patch (a Möbius strip) keeps one edge inconsistent; those are counted.
//! Fast path: when the adjacency found no wrongly wound and no non-manifold edge, the parts
//! are the components and only closed ones with negative volume are turned (one pass).
//! The propagation reads which links are wound alike from the adjacency (no triangle is
//! read while it runs) and turns faces in one sequential pass at the end. For the import,
//! both paths measure the faces (normals, areas, centroids) in the pass that turns them
//! (see `orient_and_measure`).
//! Cost: linear in faces; 5 bytes a face of scratch.

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

/// The general case: breadth-first propagation of the winding over manifold edges. The
/// faces are turned (and with `geometry`, measured) in one sequential pass at the end.
fn propagate_winding(
    mesh: &mut TriMesh,
    adjacency: &mut FaceAdjacency,
    mut geometry: Option<&mut FaceGeometry>,
) -> OrientationReport {
    const UNSET: u8 = 0;
    const KEEP: u8 = 1;
    const FLIP: u8 = 2;
    // Once a part is decided: whether the face is turned.
    const TURN: u8 = 3;
    let n = mesh.triangle_count();
    let mut state = vec![UNSET; n];
    let mut queue: Vec<u32> = Vec::with_capacity(n);
    let mut report = OrientationReport::default();

    for seed in 0..n {
        if state[seed] != UNSET {
            continue;
        }
        report.orientable_parts += 1;
        let start = queue.len();
        state[seed] = KEEP;
        queue.push(seed as u32);
        let mut head = start;
        let mut closed = true;
        while head < queue.len() {
            let f = queue[head] as usize;
            head += 1;
            for (k, g) in adjacency.neighbours(f).into_iter().enumerate() {
                if g == super::NO_FACE {
                    closed = false;
                    continue;
                }
                let g = g as usize;
                // g must end up flipped relative to f exactly when the file winds them alike
                // (as the adjacency found; no face of this part is flipped yet).
                let same = adjacency.same_direction(f, k);
                let want = if same == (state[f] == FLIP) {
                    KEEP
                } else {
                    FLIP
                };
                if state[g] == UNSET {
                    state[g] = want;
                    queue.push(g as u32);
                } else if state[g] != want && f < g {
                    report.inconsistent_edges += 1;
                }
            }
        }

        let part = &queue[start..];
        let flip_whole_part = if closed {
            // Signed volume (divergence theorem), relative to a vertex of the part for accuracy.
            let origin = mesh.corners(part[0] as usize)[0].coords;
            let volume: f64 = part
                .iter()
                .map(|&f| {
                    let v = signed_volume6(mesh, f as usize, &origin);
                    if state[f as usize] == FLIP {
                        -v
                    } else {
                        v
                    }
                })
                .sum();
            volume < 0.0
        } else {
            let (mut kept, mut flipped) = (0.0, 0.0);
            for &f in part {
                let area = mesh.scaled_normal(f as usize).norm();
                if state[f as usize] == FLIP {
                    flipped += area;
                } else {
                    kept += area;
                }
            }
            flipped > kept
        };
        // Parts share no link and the volume's origin is a corner 0, which turning keeps:
        // turning later gives the same results.
        for &f in part {
            let f = f as usize;
            state[f] = if (state[f] == FLIP) != flip_whole_part {
                TURN
            } else {
                KEEP
            };
        }
    }
    debug_assert_eq!(queue.len(), n);
    drop(queue);
    for (f, &s) in state.iter().enumerate() {
        if s == TURN {
            mesh.flip(f);
            adjacency.flip(f);
            report.flipped_faces += 1;
        }
        if let Some(geometry) = geometry.as_deref_mut() {
            geometry.push(mesh.corners(f));
        }
    }
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
