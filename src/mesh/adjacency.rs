//! Edge adjacency between faces, with boundary, non-manifold and wrongly wound edges counted.
//!
//! No paper: every face edge is filed under its smaller vertex `u`, in one of two runs by
//! direction (`u → w` or `w → u`), with the other vertex `w` and its `(face, corner)`
//! (a counting sort); face edge `a → b` finds in the runs of `min(a, b)` the faces with
//! `b → a` (consistently wound neighbours) and those with `a → b` (neighbours wound the
//! other way), both in one place in memory. An edge with one other face links the
//! two; with none it is a boundary edge; with two or more it is non-manifold and links
//! nobody, because a surface cannot be processed across such an edge as one sheet. Faces
//! that repeat a vertex (collapsed to a line or point) link nobody.
//! Runs longer than [`SCAN_LIMIT`] (a vertex of high valence, as at the centre of a disc
//! tessellated as a fan, or an edge shared by thousands of faces) are sorted by other
//! vertex and searched by bisection; shorter runs, almost all of them, are scanned. A
//! non-manifold edge is resolved once, for all its faces.
//! Cost: O(n log n) whatever the valence (O(n) at bounded valence); about 30 bytes a face
//! of scratch, read in contiguous runs per vertex.

use super::TriMesh;

/// Marks a face edge with no neighbour across it (boundary, non-manifold or collapsed).
pub const NO_FACE: u32 = u32::MAX;

/// For each face, the face across each of its three edges. Slot `k` of face `f` is the edge
/// from corner `k` to corner `(k + 1) % 3` of `mesh.triangles()[f]`.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceAdjacency {
    neighbours: Vec<[u32; 3]>,
    component_of: Vec<u32>,
    boundary_edges: usize,
    non_manifold_edges: usize,
    components: usize,
    winding_conflicts: usize,
}

/// Union–find over faces with path halving; used to find edge-connected components.
struct UnionFind(Vec<u32>);

impl UnionFind {
    fn find(&mut self, mut x: u32) -> u32 {
        // Ends: a parent is never larger than its child (see `union`), so x decreases.
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

/// A face edge filed under its smaller vertex: the face and corner it starts at (packed as
/// `face·4 + corner`) and its larger vertex.
#[derive(Clone, Copy, Default)]
struct OutEdge {
    face_corner: u32,
    to: u32,
}

/// Out-edge runs longer than this are sorted and bisected rather than scanned (no paper:
/// below it a scan of a cache line or two beats a search; typical valence is 6).
const SCAN_LIMIT: usize = 16;

/// The edges in `run` (edges of one vertex and direction) whose other vertex is `to`: a scan
/// of short runs, a bisection of long ones (sorted by other vertex).
#[inline]
fn edges_to(run: &[OutEdge], to: u32) -> impl Iterator<Item = &OutEdge> {
    let run = if run.len() <= SCAN_LIMIT {
        run
    } else {
        let start = run.partition_point(|e| e.to < to);
        let len = run[start..].partition_point(|e| e.to == to);
        &run[start..start + len]
    };
    run.iter().filter(move |e| e.to == to)
}

/// Most faces a mesh may have here: face ids are packed with a 2-bit corner into a `u32`.
pub const MAX_FACES: usize = (u32::MAX >> 2) as usize;

impl FaceAdjacency {
    /// Builds the adjacency of `mesh` (at most [`MAX_FACES`] faces).
    pub fn new(mesh: &TriMesh) -> Self {
        Self::with_progress(mesh, &mut |_, _| {})
    }

    /// [`FaceAdjacency::new`] reporting `("adjacency", fraction)` now and then.
    pub fn with_progress(mesh: &TriMesh, progress: &mut dyn FnMut(&str, f64)) -> Self {
        let triangles = mesh.triangles();
        let n = triangles.len();
        assert!(
            n <= MAX_FACES,
            "{n} faces exceed the adjacency limit of {MAX_FACES}"
        );
        let collapsed = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[2] == t[0];

        // Each face edge is filed under its smaller vertex `u`, in run `2u` when it leaves
        // `u` and `2u + 1` when it arrives there, with its other vertex (counting sort), so
        // the faces on an edge are found in one place.
        let vertex_count = mesh.vertex_count();
        let run_of = |a: u32, b: u32| -> usize {
            if a < b {
                2 * a as usize
            } else {
                2 * b as usize + 1
            }
        };
        let mut offsets = vec![0u32; 2 * vertex_count + 1];
        for t in triangles.iter().filter(|t| !collapsed(t)) {
            for k in 0..3 {
                offsets[run_of(t[k], t[(k + 1) % 3]) + 1] += 1;
            }
        }
        for r in 0..2 * vertex_count {
            offsets[r + 1] += offsets[r];
        }
        let mut out = vec![OutEdge::default(); offsets[2 * vertex_count] as usize];
        let mut fill = offsets.clone();
        for (f, t) in triangles.iter().enumerate() {
            if collapsed(t) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let r = run_of(a, b);
                out[fill[r] as usize] = OutEdge {
                    face_corner: (f as u32) << 2 | k as u32,
                    to: a.max(b),
                };
                fill[r] += 1;
            }
        }
        drop(fill);
        for r in 0..2 * vertex_count {
            let run = &mut out[offsets[r] as usize..offsets[r + 1] as usize];
            if run.len() > SCAN_LIMIT {
                // (other vertex, face·4 + corner) is unique: the order is deterministic.
                run.sort_unstable_by_key(|e| (e.to, e.face_corner));
            }
        }
        let run = |r: usize| &out[offsets[r] as usize..offsets[r + 1] as usize];

        const UNSEEN: u32 = u32::MAX - 1;
        let mut neighbours = vec![[UNSEEN; 3]; n];
        let mut union_find = UnionFind((0..n as u32).collect());
        let (mut boundary_edges, mut non_manifold_edges, mut winding_conflicts) = (0, 0, 0);
        // (face·4 + corner, wound the same way as f) of every other face on the edge.
        let mut sharers: Vec<(u32, bool)> = Vec::with_capacity(8);
        for f in 0..n {
            if f % super::PROGRESS_EVERY == 0 {
                progress("adjacency", f as f64 / n as f64);
            }
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
                let (u, w) = (a.min(b), a.max(b));
                // The edges u → w and w → u; this face's own edge is among those of its
                // direction.
                let (same, opposite) = if a < b {
                    (2 * u as usize, 2 * u as usize + 1)
                } else {
                    (2 * u as usize + 1, 2 * u as usize)
                };
                let others = || {
                    let opposite = edges_to(run(opposite), w).map(|e| (e.face_corner, false));
                    let same = edges_to(run(same), w)
                        .filter(|e| (e.face_corner >> 2) as usize != f)
                        .map(|e| (e.face_corner, true));
                    opposite.chain(same)
                };
                // Almost every edge has one other face: count without collecting.
                let mut found = others();
                let shared = match (found.next(), found.next()) {
                    (None, _) => None,
                    (Some(only), None) => Some(only),
                    _ => {
                        sharers.clear();
                        sharers.extend(others());
                        None
                    }
                };
                match (shared, sharers.is_empty()) {
                    (None, true) => {
                        neighbours[f][k] = NO_FACE;
                        boundary_edges += 1;
                    }
                    (Some((g, same_direction)), _) => {
                        let (g, slot) = (g >> 2, (g & 3) as usize);
                        neighbours[f][k] = g;
                        neighbours[g as usize][slot] = f as u32;
                        union_find.union(f as u32, g);
                        winding_conflicts += usize::from(same_direction);
                    }
                    (None, false) => {
                        // Every sharer will meet this edge; mark them all now, count it once.
                        neighbours[f][k] = NO_FACE;
                        for &(g, _) in &sharers {
                            neighbours[(g >> 2) as usize][(g & 3) as usize] = NO_FACE;
                            union_find.union(f as u32, g >> 2);
                        }
                        sharers.clear();
                        non_manifold_edges += 1;
                    }
                }
            }
        }
        drop(out);
        // Number components 0, 1, … in order of their first face.
        let mut component_of = vec![u32::MAX; n];
        let mut components = 0u32;
        for f in 0..n {
            let root = union_find.find(f as u32) as usize;
            if component_of[root] == u32::MAX {
                component_of[root] = components;
                components += 1;
            }
            component_of[f] = component_of[root];
        }
        FaceAdjacency {
            neighbours,
            component_of,
            boundary_edges,
            non_manifold_edges,
            components: components as usize,
            winding_conflicts,
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

    /// Component id (`0..components()`, in order of first face) of every face.
    pub fn component_of(&self) -> &[u32] {
        &self.component_of
    }

    /// Linked edges whose two faces traverse them in the same direction (one of the two is
    /// wound the wrong way); [`orient_consistently`](super::orient_consistently) brings this
    /// to zero wherever the surface is orientable.
    pub fn winding_conflicts(&self) -> usize {
        self.winding_conflicts
    }

    pub(crate) fn set_winding_conflicts(&mut self, count: usize) {
        self.winding_conflicts = count;
    }

    /// Reorders the slots of `f` after its winding was reversed by swapping corners 1 and 2:
    /// the edges (0,1), (1,2), (2,0) become (0,2), (2,1), (1,0).
    pub(crate) fn flip(&mut self, f: usize) {
        self.neighbours[f].swap(0, 2);
    }
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
        assert_eq!(adj.neighbours(1), [0, NO_FACE, NO_FACE]);
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
