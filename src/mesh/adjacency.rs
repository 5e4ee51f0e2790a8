//! Edge adjacency between faces, with boundary, non-manifold and wrongly wound edges counted.
//!
//! No paper: every face edge is filed under its smaller vertex `u`, in one of two runs by
//! direction (`u → w` or `w → u`), with the other vertex `w` and its `(face, corner)`
//! (a counting sort). Then, vertex by vertex, each run is sorted by `w`, and the entries
//! with the same `w` in the two runs are all the faces on edge `u – w`, those in opposite
//! runs wound consistently, those in the same run the other way round. An edge with two
//! faces links them; with one it is a boundary edge; with three or more it is non-manifold
//! and links nobody, because a surface cannot be processed across such an edge as one
//! sheet. Faces that repeat a vertex (collapsed to a line or point) link nobody.
//! Every edge is resolved once, in a sequential walk over the runs; a vertex of high
//! valence (the centre of a disc tessellated as a fan, an edge shared by thousands of
//! faces) costs a sort of its runs, never a scan per face.
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
    /// Per face, bit `k` set when the face across slot `k` traverses their edge in the same
    /// direction (a winding conflict); empty when no linked edge has one.
    same_direction: Vec<u8>,
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

/// Sorts a run by `(to, face_corner)`, a unique key: in place by insertion when short (the
/// common case: a vertex has a handful of edges, and a call into the library's sort per run
/// costs more than the sorting), else by the library's unstable sort (O(k log k)).
#[inline]
fn sort_run(run: &mut [OutEdge]) {
    let key = |e: &OutEdge| (e.to, e.face_corner);
    if run.len() > 8 {
        run.sort_unstable_by_key(key);
        return;
    }
    for i in 1..run.len() {
        let e = run[i];
        let mut j = i;
        // Ends: j decreases to 0 at the latest.
        while j > 0 && key(&run[j - 1]) > key(&e) {
            run[j] = run[j - 1];
            j -= 1;
        }
        run[j] = e;
    }
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
        progress("adjacency", 0.0);
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
        let mut neighbours = vec![[NO_FACE; 3]; n];
        let mut union_find = UnionFind((0..n as u32).collect());
        let (mut boundary_edges, mut non_manifold_edges, mut winding_conflicts) = (0, 0, 0);
        // The two (face, corner) ends of every link wound alike (rare: kept out of the walk).
        let mut conflicts: Vec<[u32; 2]> = Vec::new();
        // Vertex by vertex, the faces on each edge `u – w` are the entries with other vertex
        // `w` in the two runs of `u`: sorted by `(w, face·4 + corner)` (a unique key, so the
        // order is deterministic), equal `w` are neighbours. Every edge is resolved once, so
        // the result does not depend on the order of the edges (the union–find's roots are
        // the smallest faces whatever the order of the unions).
        for u in 0..vertex_count {
            if u % super::PROGRESS_EVERY == 0 {
                progress("adjacency", u as f64 / vertex_count as f64);
            }
            let (o0, o1, o2) = (
                offsets[2 * u] as usize,
                offsets[2 * u + 1] as usize,
                offsets[2 * u + 2] as usize,
            );
            sort_run(&mut out[o0..o1]);
            sort_run(&mut out[o1..o2]);
            let (leaving, arriving) = out[o0..o2].split_at(o1 - o0);
            let (mut i, mut j) = (0, 0);
            // Ends: each pass consumes at least one entry of the two runs.
            while i < leaving.len() || j < arriving.len() {
                let w = match (leaving.get(i), arriving.get(j)) {
                    (Some(a), Some(b)) => a.to.min(b.to),
                    (Some(a), None) => a.to,
                    (None, Some(b)) => b.to,
                    (None, None) => break,
                };
                let i0 = i;
                while i < leaving.len() && leaving[i].to == w {
                    i += 1;
                }
                let j0 = j;
                while j < arriving.len() && arriving[j].to == w {
                    j += 1;
                }
                let (forward, backward) = (&leaving[i0..i], &arriving[j0..j]);
                match forward.len() + backward.len() {
                    1 => boundary_edges += 1,
                    2 => {
                        let nth = |x: usize| match forward.get(x) {
                            Some(e) => e.face_corner,
                            None => backward[x - forward.len()].face_corner,
                        };
                        let (f, g) = (nth(0), nth(1));
                        neighbours[(f >> 2) as usize][(f & 3) as usize] = g >> 2;
                        neighbours[(g >> 2) as usize][(g & 3) as usize] = f >> 2;
                        union_find.union(f >> 2, g >> 2);
                        // Both on one side: they traverse the edge the same way.
                        if backward.len() != 1 {
                            conflicts.push([f, g]);
                        }
                    }
                    _ => {
                        // Three or more faces: they link nobody (their slots stay NO_FACE)
                        // but share a component.
                        let mut faces = forward.iter().chain(backward).map(|e| e.face_corner >> 2);
                        if let Some(hub) = faces.next() {
                            for g in faces {
                                union_find.union(hub, g);
                            }
                        }
                        non_manifold_edges += 1;
                    }
                }
            }
        }
        drop(out);
        winding_conflicts += conflicts.len();
        let mut same_direction: Vec<u8> = Vec::new();
        if !conflicts.is_empty() {
            same_direction = vec![0; n];
            for e in conflicts.into_iter().flatten() {
                same_direction[(e >> 2) as usize] |= 1 << (e & 3);
            }
        }
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
            same_direction,
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

    /// Whether the face across slot `k` of `f` traverses their shared edge in the same
    /// direction as `f` (false where there is no face across).
    #[inline]
    pub(crate) fn same_direction(&self, f: usize, k: usize) -> bool {
        self.same_direction
            .get(f)
            .is_some_and(|&bits| bits >> k & 1 != 0)
    }

    /// Sets the winding conflicts after faces were flipped: `count` of them, on the links
    /// for which `conflict(f, k, g)` holds (`g` the face across slot `k` of `f`; called
    /// only when `count > 0`).
    pub(crate) fn set_winding_conflicts(
        &mut self,
        count: usize,
        mut conflict: impl FnMut(usize, usize, usize) -> bool,
    ) {
        self.winding_conflicts = count;
        self.same_direction.clear();
        if count > 0 {
            let neighbours = &self.neighbours;
            self.same_direction = (0..neighbours.len())
                .map(|f| {
                    (0..3)
                        .filter(|&k| {
                            let g = neighbours[f][k];
                            g != NO_FACE && conflict(f, k, g as usize)
                        })
                        .fold(0u8, |bits, k| bits | 1 << k)
                })
                .collect();
        }
        self.same_direction.shrink_to_fit();
    }

    /// Reorders the slots of `f` after its winding was reversed by swapping corners 1 and 2:
    /// the edges (0,1), (1,2), (2,0) become (0,2), (2,1), (1,0). The directions of its links
    /// are left as they were: a caller that flips faces with conflicts calls
    /// [`FaceAdjacency::set_winding_conflicts`] after.
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
