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
//! The same walk joins the faces linked across manifold edges into orientable parts (a
//! union–find that keeps whether each face is turned relative to its part's first face), so
//! that making the windings agree needs no search of its own; components are the parts,
//! merged across non-manifold edges.
//! Cost: O(n log n) whatever the valence (O(n) at bounded valence); about 30 bytes a face
//! of scratch, read in contiguous runs per vertex.

use super::union_find::{flatten, union_smallest};
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

/// Union–find over faces with path halving that keeps, for each face, whether it is turned
/// relative to its parent (parity), so that a root knows how every face of its part must be
/// wound to agree with it.
struct ParityUnionFind {
    parent: Vec<u32>,
    odd: Vec<u8>,
}

impl ParityUnionFind {
    /// Root of `x` and the parity of `x` to it, halving the path on the way.
    #[inline]
    fn find(&mut self, mut x: u32) -> (u32, u8) {
        let mut parity = 0;
        // Ends: a parent is never larger than its child (see `link`), so x decreases.
        loop {
            let up = self.parent[x as usize];
            if up == x {
                return (x, parity);
            }
            let top = self.parent[up as usize];
            self.odd[x as usize] ^= self.odd[up as usize];
            self.parent[x as usize] = top;
            parity ^= self.odd[x as usize];
            x = top;
        }
    }

    /// Joins the parts of `f` and `g`, with `g` turned relative to `f` when `turn` is 1;
    /// false when they are already one part in which `g` has the other parity (the link
    /// cannot be made consistent).
    #[inline]
    fn link(&mut self, f: u32, g: u32, turn: u8) -> bool {
        let ((rf, pf), (rg, pg)) = (self.find(f), self.find(g));
        if rf == rg {
            return pf ^ pg == turn;
        }
        // The smaller root stays: deterministic, and each part's root is its first face.
        let (lo, hi) = if rf < rg { (rf, rg) } else { (rg, rf) };
        self.parent[hi as usize] = lo;
        self.odd[hi as usize] = pf ^ pg ^ turn;
        true
    }
}

/// How the windings of the faces relate, found with the adjacency (crate-internal, for
/// [`orient_consistently`](super::orient_consistently)): faces linked by manifold edges form
/// parts, numbered in order of their first face.
#[derive(Debug)]
pub(crate) struct WindingParts {
    /// Per face, `part << 1 | turned`: `turned` when the face must be turned relative to its
    /// part's first face for their windings to agree.
    pub(crate) of_face: Vec<u32>,
    /// Number of parts.
    pub(crate) count: usize,
    /// Links whose faces cannot be made to agree (non-orientable parts; which links depends
    /// on the order they are met in).
    pub(crate) inconsistent_edges: usize,
    /// Whether any face is turned relative to its part's first face.
    pub(crate) any_turned: bool,
    /// Whether every face has a face across each of its edges (so every part is closed).
    pub(crate) all_linked: bool,
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

/// Every face's part, numbered in order of the parts' first faces, and parity to its
/// first face, packed as `part << 1 | parity`; and the number of parts.
fn number_parts(mut parts: ParityUnionFind) -> (Vec<u32>, usize) {
    let n = parts.parent.len();
    // Every face points at its root with the parity to it (a face already done is a
    // one-step path for the faces below it).
    for f in 0..n {
        let (root, parity) = parts.find(f as u32);
        (parts.parent[f], parts.odd[f]) = (root, parity);
    }
    let ParityUnionFind {
        parent: mut of_face,
        odd,
    } = parts;
    // A root is its part's smallest face, so it is numbered (and its entry overwritten with
    // `part << 1`, parity 0) before the part's other faces are met.
    let mut count = 0u32;
    for f in 0..n {
        let root = of_face[f] as usize;
        of_face[f] = if root == f {
            count += 1;
            (count - 1) << 1
        } else {
            of_face[root] | u32::from(odd[f])
        };
    }
    (of_face, count as usize)
}

/// Component of every face, numbered in order of first face, and their number: the parts
/// (numbered in order of first face), merged where faces share a non-manifold edge (`books`).
fn number_components(of_face: &[u32], parts: usize, books: &[[u32; 2]]) -> (Vec<u32>, usize) {
    if books.is_empty() {
        return (of_face.iter().map(|&p| p >> 1).collect(), parts);
    }
    // Union–find over parts, the smaller part the root: a component's smallest part holds
    // its first face.
    let mut root: Vec<u32> = (0..parts as u32).collect();
    for &[f, g] in books {
        union_smallest(
            &mut root,
            of_face[f as usize] >> 1,
            of_face[g as usize] >> 1,
        );
    }
    flatten(&mut root);
    let mut count = 0u32;
    for p in 0..parts {
        let r = root[p] as usize;
        root[p] = if r == p {
            count += 1;
            count - 1
        } else {
            root[r]
        };
    }
    let component_of = of_face.iter().map(|&p| root[(p >> 1) as usize]).collect();
    (component_of, count as usize)
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
        Self::with_parts(mesh, progress).0
    }

    /// [`FaceAdjacency::with_progress`], and the orientable parts the links form.
    pub(crate) fn with_parts(
        mesh: &TriMesh,
        progress: &mut dyn FnMut(&str, f64),
    ) -> (Self, WindingParts) {
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
        // the faces on an edge are found in one place. Run r is counted in offsets[r + 2],
        // so that after the prefix sum offsets[r + 1] is its start and, advanced as it is
        // filled, ends as its end (the start of run r + 1): run r is offsets[r]..offsets[r + 1].
        let vertex_count = mesh.vertex_count();
        let runs = 2 * vertex_count;
        let run_of = |a: u32, b: u32| -> usize {
            if a < b {
                2 * a as usize
            } else {
                2 * b as usize + 1
            }
        };
        let mut offsets = vec![0u32; runs + 2];
        let mut collapsed_faces = 0;
        for t in triangles {
            if collapsed(t) {
                collapsed_faces += 1;
                continue;
            }
            for k in 0..3 {
                offsets[run_of(t[k], t[(k + 1) % 3]) + 2] += 1;
            }
        }
        for r in 2..runs + 2 {
            offsets[r] += offsets[r - 1];
        }
        let mut out = vec![OutEdge::default(); offsets[runs + 1] as usize];
        for (f, t) in triangles.iter().enumerate() {
            if collapsed(t) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let at = &mut offsets[run_of(a, b) + 1];
                out[*at as usize] = OutEdge {
                    face_corner: (f as u32) << 2 | k as u32,
                    to: a.max(b),
                };
                *at += 1;
            }
        }
        let mut neighbours = vec![[NO_FACE; 3]; n];
        let mut parts = ParityUnionFind {
            parent: (0..n as u32).collect(),
            odd: vec![0; n],
        };
        let (mut boundary_edges, mut non_manifold_edges) = (0, 0);
        let (mut winding_conflicts, mut inconsistent_edges) = (0, 0);
        // Faces on non-manifold edges, each with the edge's first face: they share a
        // component but no part.
        let mut books: Vec<[u32; 2]> = Vec::new();
        // Vertex by vertex, the faces on each edge `u – w` are the entries with other vertex
        // `w` in the two runs of `u`: sorted by `(w, face·4 + corner)` (a unique key, so the
        // order is deterministic), equal `w` are neighbours. Every edge is resolved once, so
        // the links do not depend on the order of the edges, nor do the parts (the union–find's
        // roots are the smallest faces whatever the order of the unions); only which links of
        // a non-orientable part are found inconsistent does.
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
                        // Both on one side: they traverse the edge the same way, so one of
                        // the two must turn.
                        let turn = backward.len() != 1;
                        winding_conflicts += usize::from(turn);
                        if !parts.link(f >> 2, g >> 2, u8::from(turn)) {
                            inconsistent_edges += 1;
                        }
                    }
                    _ => {
                        // Three or more faces: they link nobody (their slots stay NO_FACE)
                        // but share a component.
                        let mut faces = forward.iter().chain(backward).map(|e| e.face_corner >> 2);
                        if let Some(hub) = faces.next() {
                            books.extend(faces.map(|g| [hub, g]));
                        }
                        non_manifold_edges += 1;
                    }
                }
            }
        }
        drop((out, offsets));
        let (of_face, part_count) = number_parts(parts);
        let (component_of, components) = number_components(&of_face, part_count, &books);
        let any_turned = of_face.iter().any(|&p| p & 1 == 1);
        let adjacency = FaceAdjacency {
            neighbours,
            component_of,
            boundary_edges,
            non_manifold_edges,
            components,
            winding_conflicts,
        };
        let parts = WindingParts {
            of_face,
            count: part_count,
            inconsistent_edges,
            any_turned,
            all_linked: boundary_edges == 0 && non_manifold_edges == 0 && collapsed_faces == 0,
        };
        (adjacency, parts)
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

    /// Sets the number of winding conflicts after faces were flipped.
    pub(crate) fn set_winding_conflicts(&mut self, count: usize) {
        self.winding_conflicts = count;
    }

    /// Reorders the slots of `f` after its winding was reversed by swapping corners 1 and 2:
    /// the edges (0,1), (1,2), (2,0) become (0,2), (2,1), (1,0). The count of winding
    /// conflicts is left as it was: a caller that flips faces sets it after
    /// ([`FaceAdjacency::set_winding_conflicts`]).
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
