//! Edge adjacency between faces, with boundary and non-manifold edges counted.
//!
//! No paper: faces are grouped by vertex (a compressed vertex→faces table), and each face
//! edge `(a, b)` looks for the other faces around `a` that also use `b`. An edge with one
//! other face links the two; with none it is a boundary edge; with two or more it is
//! non-manifold and links nobody, because a surface cannot be processed across such an
//! edge as one sheet. Faces that repeat a vertex (collapsed to a line or point) link nobody.
//! Cost: O(Σ valence²) ≈ linear for meshes of bounded valence; 14 bytes a face of scratch.

use super::TriMesh;

/// Marks a face edge with no neighbour across it (boundary, non-manifold or collapsed).
pub const NO_FACE: u32 = u32::MAX;

/// For each face, the face across each of its three edges. Slot `k` of face `f` is the edge
/// from corner `k` to corner `(k + 1) % 3` of `mesh.triangles()[f]`.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceAdjacency {
    neighbours: Vec<[u32; 3]>,
    boundary_edges: usize,
    non_manifold_edges: usize,
    components: usize,
}

/// Union–find over faces with path halving; used to count edge-connected components.
struct Components(Vec<u32>);

impl Components {
    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let parent = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = parent;
            x = parent;
        }
        x
    }

    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // Attach the larger id under the smaller: deterministic and shallow enough here.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.0[hi as usize] = lo;
        }
    }
}

impl FaceAdjacency {
    /// Builds the adjacency of `mesh`.
    pub fn new(mesh: &TriMesh) -> Self {
        let triangles = mesh.triangles();
        let n = triangles.len();
        let collapsed = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[2] == t[0];

        // Vertex → faces, as offsets into one array (counting sort by vertex).
        let mut offsets = vec![0u32; mesh.vertex_count() + 1];
        for t in triangles.iter().filter(|t| !collapsed(t)) {
            for &v in t {
                offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..mesh.vertex_count() {
            offsets[v + 1] += offsets[v];
        }
        let mut faces_of_vertex = vec![0u32; offsets[mesh.vertex_count()] as usize];
        let mut fill = offsets.clone();
        for (f, t) in triangles.iter().enumerate() {
            if collapsed(t) {
                continue;
            }
            for &v in t {
                faces_of_vertex[fill[v as usize] as usize] = f as u32;
                fill[v as usize] += 1;
            }
        }
        drop(fill);

        const UNSEEN: u32 = u32::MAX - 1;
        let mut neighbours = vec![[UNSEEN; 3]; n];
        let mut components = Components((0..n as u32).collect());
        let (mut boundary_edges, mut non_manifold_edges) = (0, 0);
        let mut sharers: Vec<u32> = Vec::with_capacity(8);
        for f in 0..n {
            let t = triangles[f];
            if collapsed(&t) {
                neighbours[f] = [NO_FACE; 3];
                continue;
            }
            for k in 0..3 {
                if neighbours[f][k] != UNSEEN {
                    continue;
                }
                let (a, b) = (t[k], t[(k + 1) % 3]);
                sharers.clear();
                let around_a = &faces_of_vertex
                    [offsets[a as usize] as usize..offsets[a as usize + 1] as usize];
                sharers.extend(
                    around_a
                        .iter()
                        .copied()
                        .filter(|&g| g as usize != f && triangles[g as usize].contains(&b)),
                );
                match sharers.as_slice() {
                    [] => {
                        neighbours[f][k] = NO_FACE;
                        boundary_edges += 1;
                    }
                    &[g] => {
                        neighbours[f][k] = g;
                        let slot = edge_slot(&triangles[g as usize], a, b);
                        neighbours[g as usize][slot] = f as u32;
                        components.union(f as u32, g);
                    }
                    _ => {
                        // Every sharer will meet this edge; mark them all now, count it once.
                        neighbours[f][k] = NO_FACE;
                        for &g in &sharers {
                            let slot = edge_slot(&triangles[g as usize], a, b);
                            neighbours[g as usize][slot] = NO_FACE;
                            components.union(f as u32, g);
                        }
                        non_manifold_edges += 1;
                    }
                }
            }
        }
        let components = (0..n as u32).filter(|&f| components.find(f) == f).count();
        FaceAdjacency {
            neighbours,
            boundary_edges,
            non_manifold_edges,
            components,
        }
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.neighbours.len()
    }

    /// The faces across the three edges of `f` ([`NO_FACE`] where there is none).
    #[inline]
    pub fn neighbours(&self, f: usize) -> [u32; 3] {
        self.neighbours[f]
    }

    /// The faces across the edges of `f` that have exactly one.
    #[inline]
    pub fn neighbours_of(&self, f: usize) -> impl Iterator<Item = usize> + '_ {
        self.neighbours[f]
            .into_iter()
            .filter(|&g| g != NO_FACE)
            .map(|g| g as usize)
    }

    /// Edges used by exactly one face.
    pub fn boundary_edges(&self) -> usize {
        self.boundary_edges
    }

    /// Edges used by three or more faces.
    pub fn non_manifold_edges(&self) -> usize {
        self.non_manifold_edges
    }

    /// Connected components, counting faces that share any edge (non-manifold ones too) as
    /// connected; a collapsed face is a component of its own.
    pub fn components(&self) -> usize {
        self.components
    }

    /// Reorders the slots of `f` after its winding was reversed by swapping corners 1 and 2:
    /// the edges (0,1), (1,2), (2,0) become (0,2), (2,1), (1,0).
    pub(crate) fn flip(&mut self, f: usize) {
        self.neighbours[f].swap(0, 2);
    }
}

/// The slot of triangle `t` whose edge joins `a` and `b` in either direction.
fn edge_slot(t: &[u32; 3], a: u32, b: u32) -> usize {
    (0..3)
        .find(|&k| {
            let (p, q) = (t[k], t[(k + 1) % 3]);
            (p == a && q == b) || (p == b && q == a)
        })
        .expect("the face was found through both endpoints of the edge")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point3;

    fn mesh(triangles: Vec<[u32; 3]>) -> TriMesh {
        let vertices = triangles.iter().flatten().max().map_or(0, |&m| m + 1);
        let positions = (0..vertices)
            .map(|v| Point3::new(v as f64, (v * v) as f64, (v % 3) as f64))
            .collect();
        TriMesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn two_triangles_share_one_edge() {
        let adj = FaceAdjacency::new(&mesh(vec![[0, 1, 2], [2, 1, 3]]));
        assert_eq!(adj.neighbours(0), [NO_FACE, 1, NO_FACE]);
        assert_eq!(adj.neighbours(1), [NO_FACE, NO_FACE, 0]);
        assert_eq!((adj.boundary_edges(), adj.non_manifold_edges()), (4, 0));
        assert_eq!(adj.components(), 1);
    }

    #[test]
    fn three_faces_on_an_edge_link_nobody_but_stay_one_component() {
        let adj = FaceAdjacency::new(&mesh(vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]));
        assert_eq!(adj.non_manifold_edges(), 1);
        assert_eq!(adj.neighbours_of(0).count(), 0);
        assert_eq!(adj.components(), 1);
        assert_eq!(adj.boundary_edges(), 6);
    }

    #[test]
    fn collapsed_faces_are_isolated() {
        let adj = FaceAdjacency::new(&mesh(vec![[0, 1, 2], [1, 1, 2]]));
        assert_eq!(adj.neighbours(1), [NO_FACE; 3]);
        assert_eq!(adj.components(), 2);
    }
}
