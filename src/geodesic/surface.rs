//! The part of a mesh the geodesic module works on: the active faces (all, or a patch), the
//! faces around each vertex, face and vertex normals, and a uniform grid for closest-point queries.
//!
//! What a surface derives from its mesh is shared (an `Arc`) by the surfaces made from it: a
//! mesh's [`SurfaceCache`] keeps it for the next distance on the same faces, and a distance
//! field for its iso lines.
//!
//! No paper for the grid: faces are binned by bounding box into cubic cells of about two mean
//! edge lengths (grown so there are at most 4 cells a face), and a query scans rings of cells
//! around the point until the ring's distance exceeds the best hit (Ericson, "Real-Time
//! Collision Detection", 2005, §5.1.5 for the closest point on a triangle).
//! Cost: O(F) to build; a query visits O(1) cells on a surface of bounded face size.

use super::params::GeodesicError;
use crate::math::{Point3, Real, Vector3};
use crate::mesh::{FaceAdjacency, TriMesh, NO_FACE};
use rustc_hash::FxHashMap;
use std::sync::{Arc, OnceLock};

/// Cells per active face at most in the closest-point grid.
const GRID_CELLS_PER_FACE: usize = 4;

/// Active faces with the derived data every method needs (see [`Derived`], which a surface
/// shares with the others made from it).
pub(crate) struct Surface<'a> {
    pub mesh: &'a TriMesh,
    pub adjacency: &'a FaceAdjacency,
    derived: Arc<Derived>,
}

/// What a [`Surface`] derives from its mesh for one set of active faces: built once, and
/// shared by the surfaces made from it (a [`SurfaceCache`], a distance field's iso lines).
#[derive(Debug)]
pub struct Derived {
    /// The face subset it was built for (`None`: every face), and the mesh's counts.
    subset: Option<Vec<u32>>,
    counts: (usize, usize),
    /// `active[f]`: face `f` takes part.
    pub(crate) active: Vec<bool>,
    /// Active face ids, ascending.
    pub(crate) faces: Vec<u32>,
    /// CSR offsets into `vertex_faces` per vertex.
    vertex_face_start: Vec<u32>,
    vertex_faces: Vec<u32>,
    /// Unit face normals of the active faces ([`Surface::face_normal`]; +z for the others).
    pub(crate) face_normals: Vec<Vector3>,
    /// Mean active edge length.
    pub(crate) mean_edge: Real,
    /// Total active area.
    pub(crate) area: Real,
    /// Per vertex, the rings to a gap in the surface and whether it lies on a hole's rim
    /// (see `virtual_source/shadow.rs`), found by the first distance that needs them.
    gaps: OnceLock<(Vec<u8>, Vec<bool>)>,
    /// Unit vertex normals ([`Surface::vertex_normals`]), made by the first iso line.
    vertex_normals: OnceLock<Vec<Vector3>>,
    /// The active faces on the edges of three or more faces, found by the first distance
    /// that needs them.
    books: OnceLock<EdgeBooks>,
}

/// The edges of three or more faces with two or more of them active ("books", the faces
/// their pages), found among the half-edges the adjacency links to nobody (boundary,
/// non-manifold), sorted by their vertices: O(E log E) in those half-edges, nothing on a
/// mesh without edges of three or more faces. A path may go on across such an edge into any
/// of its faces (a fin or a sliver glued on along it).
#[derive(Debug)]
pub(crate) struct EdgeBooks {
    /// The half-edges `face·4 + slot` of each book, book after book.
    half_edges: Vec<u32>,
    /// The start of each book in `half_edges`, and the end of the last.
    starts: Vec<u32>,
    /// The book of each of those half-edges.
    book_of: FxHashMap<u32, u32>,
}

impl EdgeBooks {
    fn new(surface: &Surface) -> Self {
        let mesh = surface.mesh;
        let mut open: Vec<([u32; 2], u32)> = Vec::new();
        // Without an edge of three or more faces, nothing to look for.
        let faces: &[u32] = if surface.adjacency.non_manifold_edges() == 0 {
            &[]
        } else {
            &surface.faces
        };
        for &f in faces {
            let t = mesh.triangles()[f as usize];
            for (k, &g) in surface.adjacency.neighbours(f as usize).iter().enumerate() {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if g == NO_FACE && a != b {
                    open.push(([a.min(b), a.max(b)], f << 2 | k as u32));
                }
            }
        }
        open.sort_unstable();
        let mut books = EdgeBooks {
            half_edges: Vec::new(),
            starts: vec![0],
            book_of: FxHashMap::default(),
        };
        for run in open.chunk_by(|x, y| x.0 == y.0) {
            // One face alone: a boundary edge (its other faces, if any, are not active).
            // Two: the active ones of an edge of three or more faces, a manifold edge here.
            if run.len() < 2 {
                continue;
            }
            for &(_, half_edge) in run {
                let book = (books.starts.len() - 1) as u32;
                books.book_of.insert(half_edge, book);
                books.half_edges.push(half_edge);
            }
            books.starts.push(books.half_edges.len() as u32);
        }
        books
    }

    /// Per vertex of `mesh`, whether it ends an edge of three or more faces with two or
    /// more of them active; empty when none does.
    pub(crate) fn vertices(&self, mesh: &TriMesh) -> Vec<bool> {
        if self.half_edges.is_empty() {
            return Vec::new();
        }
        let mut on = vec![false; mesh.vertex_count()];
        for &e in &self.half_edges {
            let (t, k) = (mesh.triangles()[(e >> 2) as usize], (e & 3) as usize);
            on[t[k] as usize] = true;
            on[t[(k + 1) % 3] as usize] = true;
        }
        on
    }

    /// The other active faces on the edge in slot `k` of face `f`, each with the slot of
    /// the edge there (none unless the edge has three or more faces).
    pub(crate) fn others(
        &self,
        f: usize,
        k: usize,
    ) -> impl DoubleEndedIterator<Item = (usize, usize)> + '_ {
        let range = match self.book_of.get(&((f as u32) << 2 | k as u32)) {
            Some(&b) => self.starts[b as usize] as usize..self.starts[b as usize + 1] as usize,
            None => 0..0,
        };
        self.half_edges[range]
            .iter()
            .filter(move |&&e| e >> 2 != f as u32)
            .map(|&e| ((e >> 2) as usize, (e & 3) as usize))
    }
}

impl std::ops::Deref for Surface<'_> {
    type Target = Derived;

    fn deref(&self) -> &Derived {
        &self.derived
    }
}

/// What the last geodesic call on a mesh derived from it (the faces around each vertex, the
/// face normals, the rings to a hole's rim), for the next call on the same faces (the Paths
/// tool recomputes on one patch as its user changes the source or the spacing): one set at a
/// time, replaced when the faces change. A cache belongs to one mesh: give it that mesh's
/// calls only (it checks the mesh's size, not its coordinates).
#[derive(Debug, Default)]
pub struct SurfaceCache {
    last: std::cell::RefCell<Option<Arc<Derived>>>,
}

impl SurfaceCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds (or keeps) the data of `faces` (`None`: every face) of `mesh`, so that the next
    /// distance on them starts at once; refuses as [`geodesic_distance`] would.
    ///
    /// [`geodesic_distance`]: super::geodesic_distance
    pub fn prepare(
        &self,
        mesh: &TriMesh,
        adjacency: &FaceAdjacency,
        faces: Option<&[u32]>,
    ) -> Result<(), GeodesicError> {
        Surface::cached(mesh, adjacency, faces, Some(self)).map(drop)
    }

    /// Forgets what it holds (its memory is freed once no distance field shares it).
    pub fn clear(&self) {
        self.last.borrow_mut().take();
    }
}

impl<'a> Surface<'a> {
    /// Active faces from an optional subset; refuses an empty set or an id out of range.
    pub fn new(
        mesh: &'a TriMesh,
        adjacency: &'a FaceAdjacency,
        subset: Option<&[u32]>,
    ) -> Result<Self, GeodesicError> {
        Self::cached(mesh, adjacency, subset, None)
    }

    /// [`Surface::new`], reusing the data `cache` holds when it was built for the same faces
    /// of a mesh of the same size (the cache belongs to one mesh), and leaving there what it
    /// builds.
    pub fn cached(
        mesh: &'a TriMesh,
        adjacency: &'a FaceAdjacency,
        subset: Option<&[u32]>,
        cache: Option<&SurfaceCache>,
    ) -> Result<Self, GeodesicError> {
        if let Some(cache) = cache {
            if let Some(d) = cache.last.borrow().as_ref() {
                if d.fits(mesh, subset) {
                    return Self::sharing(mesh, adjacency, d.clone());
                }
            }
            // Let the old set go first (freed now unless a distance field holds it), so the
            // two are not held at once.
            cache.clear();
        }
        let derived = Arc::new(Derived::new(mesh, adjacency, subset)?);
        if let Some(cache) = cache {
            *cache.last.borrow_mut() = Some(derived.clone());
        }
        Self::sharing(mesh, adjacency, derived)
    }

    /// The surface of `derived` on `mesh`, which it must have been built on: refused for an
    /// adjacency that is not the mesh's or a mesh of another size than it was built on.
    pub fn sharing(
        mesh: &'a TriMesh,
        adjacency: &'a FaceAdjacency,
        derived: Arc<Derived>,
    ) -> Result<Self, GeodesicError> {
        check_adjacency(mesh, adjacency)?;
        let (faces, vertices) = derived.counts;
        if (faces, vertices) != (mesh.triangle_count(), mesh.vertex_count()) {
            return Err(GeodesicError::BadFaces(format!(
                "this distance was computed on a mesh of {faces} triangles and {vertices} \
                 vertices, not on this one ({} and {})",
                mesh.triangle_count(),
                mesh.vertex_count()
            )));
        }
        Ok(Surface {
            mesh,
            adjacency,
            derived,
        })
    }

    /// The data it shares.
    pub fn derived(&self) -> &Arc<Derived> {
        &self.derived
    }

    /// Active faces around vertex `v`.
    pub fn faces_of(&self, v: usize) -> &[u32] {
        let (a, b) = (self.vertex_face_start[v], self.vertex_face_start[v + 1]);
        &self.vertex_faces[a as usize..b as usize]
    }

    /// The active faces on the edges of three or more faces ([`EdgeBooks`]).
    pub(crate) fn books(&self) -> &EdgeBooks {
        self.derived.books.get_or_init(|| EdgeBooks::new(self))
    }

    /// The corners of faces glued on along the edges of face `f` (edges of three or more
    /// faces) that lie on the edge (within [`SLIVER_HEIGHT`] of its length): a sliver's lone
    /// corner, which is a point of `f` (the methods that start the vertices of the faces a
    /// source crosses start these too).
    pub(crate) fn glued_corners(&self, f: usize) -> impl Iterator<Item = usize> + '_ {
        let (mesh, books) = (self.mesh, self.books());
        let (pos, t) = (mesh.positions(), mesh.triangles()[f]);
        (0..3).flat_map(move |k| {
            let (a, b) = (pos[t[k] as usize], pos[t[(k + 1) % 3] as usize]);
            books.others(f, k).filter_map(move |(g, j)| {
                let c = mesh.triangles()[g][(j + 2) % 3] as usize;
                on_segment(&pos[c], &a, &b).then_some(c)
            })
        })
    }

    /// Whether face `f` is a sliver: its height lower than [`SLIVER_HEIGHT`] of its longest
    /// edge, so that its normal is rounding and its plane not defined.
    pub(crate) fn is_sliver(&self, f: usize) -> bool {
        let [a, b, c] = self.mesh.corners(f);
        let (ab, bc, ca) = (b - a, c - b, a - c);
        let longest = ab
            .norm_squared()
            .max(bc.norm_squared())
            .max(ca.norm_squared());
        ab.cross(&ca).norm() <= SLIVER_HEIGHT * longest
    }

    /// The active face across slot `k` of face `f`, if any.
    pub fn across(&self, f: usize, k: usize) -> Option<usize> {
        let g = self.adjacency.neighbours(f)[k];
        (g != NO_FACE && self.active[g as usize]).then_some(g as usize)
    }

    /// A unit normal at a point of face `f`: the face normal (vertex normals are for output).
    pub fn face_normal(&self, f: usize) -> Vector3 {
        let n = self.mesh.scaled_normal(f);
        let len = n.norm();
        if len > 0.0 {
            n / len
        } else {
            Vector3::z()
        }
    }

    /// Unit area-weighted normal at vertex `v` (zero for a vertex of no active face). Found
    /// on demand, in O(faces around `v`): the propagation never needs it, and a focal
    /// candidate goes round its faces anyway. Bit for bit the entry of
    /// [`Surface::vertex_normals`].
    pub fn vertex_normal(&self, v: usize) -> Vector3 {
        // Summed in ascending face order, as the table is built face by face.
        unit_or_zero(self.faces_of(v).iter().fold(Vector3::zeros(), |n, &f| {
            n + self.mesh.scaled_normal(f as usize)
        }))
    }

    /// [`Surface::vertex_normal`] of every vertex, made by the first call (O(F), then kept
    /// with the faces' other derived data). Iso lines ask for the vertex normals of every
    /// edge they cross: asked one by one, the centre of a disc tessellated as a fan would
    /// cost its valence at each of its edges, so every iso line round it the square of it.
    pub fn vertex_normals(&self) -> &[Vector3] {
        self.derived.vertex_normals.get_or_init(|| {
            let mut sums = vec![Vector3::zeros(); self.mesh.vertex_count()];
            // Ascending face order, each face's corners in turn: the order of `faces_of`.
            for &f in &self.faces {
                let n = self.mesh.scaled_normal(f as usize);
                for v in self.mesh.triangles()[f as usize] {
                    sums[v as usize] += n;
                }
            }
            sums.into_iter().map(unit_or_zero).collect()
        })
    }

    /// Unit normal interpolated from the vertex normals of edge `(a, b)` at parameter `t`.
    pub fn edge_normal(&self, a: usize, b: usize, t: Real) -> Vector3 {
        let normals = self.vertex_normals();
        let n = normals[a] * (1.0 - t) + normals[b] * t;
        let len = n.norm();
        if len > 0.0 {
            n / len
        } else {
            Vector3::z()
        }
    }
}

/// `n` scaled to unit length, or `n` itself when it has none (zero).
fn unit_or_zero(n: Vector3) -> Vector3 {
    let len = n.norm();
    if len > 0.0 {
        n / len
    } else {
        n
    }
}

impl Derived {
    /// The data of the active faces `subset` (all when `None`) of `mesh`; refuses an empty set
    /// or an id out of range.
    fn new(
        mesh: &TriMesh,
        adjacency: &FaceAdjacency,
        subset: Option<&[u32]>,
    ) -> Result<Self, GeodesicError> {
        check_adjacency(mesh, adjacency)?;
        let nf = mesh.triangle_count();
        let mut active = vec![subset.is_none(); nf];
        if let Some(set) = subset {
            if set.is_empty() {
                return Err(GeodesicError::BadFaces("faces is empty".into()));
            }
            for &f in set {
                if f as usize >= nf {
                    return Err(GeodesicError::BadFaces(format!(
                        "face {f} does not exist (the mesh has {nf} faces)"
                    )));
                }
                active[f as usize] = true;
            }
        }
        let faces: Vec<u32> = if subset.is_none() {
            (0..nf as u32).collect()
        } else {
            (0..nf as u32).filter(|&f| active[f as usize]).collect()
        };
        let (pos, triangles) = (mesh.positions(), mesh.triangles());
        let nv = mesh.vertex_count();
        // Faces around vertex v are counted in vertex_face_start[v + 2], so that after the
        // prefix sum vertex_face_start[v + 1] is their start and, advanced as they are filled
        // in, ends as their end (the start of v + 1): no second array of cursors.
        let mut vertex_face_start = vec![0u32; nv + 2];
        // The normals are written once, in face order (inactive faces get +z).
        let mut face_normals = Vec::with_capacity(nf);
        let (mut edge_sum, mut area) = (0.0, 0.0);
        for (f, t) in triangles.iter().enumerate() {
            if !active[f] {
                face_normals.push(Vector3::z());
                continue;
            }
            let [a, b, c] = t.map(|v| pos[v as usize]);
            // TriMesh::scaled_normal, from the corners at hand.
            let n = (b - a).cross(&(c - a));
            let len = n.norm();
            area += 0.5 * len;
            face_normals.push(if len > 0.0 { n / len } else { Vector3::z() });
            edge_sum += (b - a).norm() + (c - b).norm() + (a - c).norm();
            for &v in t {
                vertex_face_start[v as usize + 2] += 1;
            }
        }
        for v in 0..nv {
            vertex_face_start[v + 2] += vertex_face_start[v + 1];
        }
        let mut vertex_faces = vec![0u32; faces.len() * 3];
        for &f in &faces {
            for v in triangles[f as usize] {
                let at = &mut vertex_face_start[v as usize + 1];
                vertex_faces[*at as usize] = f;
                *at += 1;
            }
        }
        vertex_face_start.pop();
        Ok(Derived {
            subset: subset.map(<[u32]>::to_vec),
            counts: (nf, nv),
            gaps: OnceLock::new(),
            vertex_normals: OnceLock::new(),
            books: OnceLock::new(),
            active,
            mean_edge: edge_sum / (3 * faces.len()).max(1) as Real,
            faces,
            vertex_face_start,
            vertex_faces,
            face_normals,
            area,
        })
    }

    /// The rings to a gap and the hole-rim flags per vertex (see [`Derived::gaps`]), made by
    /// `make` the first time.
    pub(crate) fn gaps(&self, make: impl FnOnce() -> (Vec<u8>, Vec<bool>)) -> (&[u8], &[bool]) {
        let (rings, rim) = self.gaps.get_or_init(make);
        (rings, rim)
    }

    /// Whether it was built for the faces `subset` of a mesh the size of `mesh`.
    fn fits(&self, mesh: &TriMesh, subset: Option<&[u32]>) -> bool {
        self.counts == (mesh.triangle_count(), mesh.vertex_count())
            && self.subset.as_deref() == subset
    }
}

/// A face lower than this fraction of its longest edge is a sliver: its plane is not
/// defined (its normal is rounding). A corner of a face glued on along an edge of three or
/// more faces within this fraction of the edge's length of it is a point of the faces on
/// the edge. The path through such a corner and the path to its foot on the edge differ by
/// at most this fraction of the edge. (No paper; a thousand times the import's degeneracy
/// ratio [`DEGENERATE_HEIGHT_RATIO`](crate::math::DEGENERATE_HEIGHT_RATIO), which
/// coordinates rounded to `f32` already exceed on slivers of edges a few hundredths of
/// their distance from the origin long.)
const SLIVER_HEIGHT: Real = 1e-4;

/// Whether `c` lies on the segment `a`–`b`: within [`SLIVER_HEIGHT`] of its length from it,
/// between its ends.
fn on_segment(c: &Point3, a: &Point3, b: &Point3) -> bool {
    let (d, inside) = segment_distance(c, a, b);
    inside && d <= SLIVER_HEIGHT * (b - a).norm()
}

/// Refuses an adjacency that is not the mesh's (another face count).
fn check_adjacency(mesh: &TriMesh, adjacency: &FaceAdjacency) -> Result<(), GeodesicError> {
    if adjacency.face_count() != mesh.triangle_count() {
        return Err(GeodesicError::BadFaces(format!(
            "the adjacency has {} faces but the mesh {}",
            adjacency.face_count(),
            mesh.triangle_count()
        )));
    }
    Ok(())
}

/// Uniform grid of active faces for closest-point queries.
pub(crate) struct FaceGrid {
    origin: Point3,
    cell: Real,
    dims: [usize; 3],
    start: Vec<u32>,
    faces: Vec<u32>,
}

impl FaceGrid {
    /// Bins the active faces of `surface`.
    pub fn new(surface: &Surface) -> Self {
        let mesh = surface.mesh;
        let (mut lo, mut hi) = (Point3::from([Real::MAX; 3]), Point3::from([Real::MIN; 3]));
        for &f in &surface.faces {
            for p in mesh.corners(f as usize) {
                lo = lo.inf(&p);
                hi = hi.sup(&p);
            }
        }
        let extent = hi - lo;
        let max_cells = (surface.faces.len() * GRID_CELLS_PER_FACE).max(1) as Real;
        let mut cell = (2.0 * surface.mean_edge)
            .max(extent.max() * 1e-6)
            .max(Real::MIN_POSITIVE);
        // Grow the cell until the grid has at most GRID_CELLS_PER_FACE cells a face (≤ 64 rounds:
        // each doubles the cell).
        let dims_for = |c: Real| extent.map(|e| ((e / c).floor() as usize + 1).max(1));
        for _ in 0..64 {
            let d = dims_for(cell);
            if (d.x as Real) * (d.y as Real) * (d.z as Real) <= max_cells {
                break;
            }
            cell *= 2.0;
        }
        let d = dims_for(cell);
        let dims = [d.x, d.y, d.z];
        let mut grid = FaceGrid {
            origin: lo,
            cell,
            dims,
            start: vec![0; dims[0] * dims[1] * dims[2] + 1],
            faces: Vec::new(),
        };
        for pass in 0..2 {
            let mut fill = grid.start.clone();
            for &f in &surface.faces {
                let c = mesh.corners(f as usize);
                let (a, b) = (
                    grid.cell_of(&c[0].inf(&c[1]).inf(&c[2])),
                    grid.cell_of(&c[0].sup(&c[1]).sup(&c[2])),
                );
                for x in a[0]..=b[0] {
                    for y in a[1]..=b[1] {
                        for z in a[2]..=b[2] {
                            let i = grid.index([x, y, z]);
                            if pass == 0 {
                                grid.start[i + 1] += 1;
                            } else {
                                grid.faces[fill[i] as usize] = f;
                                fill[i] += 1;
                            }
                        }
                    }
                }
            }
            if pass == 0 {
                for i in 0..grid.start.len() - 1 {
                    grid.start[i + 1] += grid.start[i];
                }
                grid.faces = vec![0; *grid.start.last().unwrap_or(&0) as usize];
            }
        }
        grid
    }

    fn cell_of(&self, p: &Point3) -> [usize; 3] {
        let mut c = [0; 3];
        for k in 0..3 {
            let x = ((p[k] - self.origin[k]) / self.cell).floor();
            c[k] = if x.is_nan() || x < 0.0 {
                0
            } else {
                (x as usize).min(self.dims[k] - 1)
            };
        }
        c
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// The closest point of the active surface to `p`: `(point, face, distance)`.
    pub fn closest(&self, mesh: &TriMesh, p: &Point3) -> Option<(Point3, usize, Real)> {
        let c = self.cell_of(p);
        let mut best: Option<(Point3, usize, Real)> = None;
        let max_ring = self.dims.iter().copied().max().unwrap_or(1);
        for r in 0..=max_ring {
            if let Some((_, _, d)) = best {
                // Cells beyond ring r - 1 are at least (r - 1)·cell away.
                if d <= (r as Real - 1.0) * self.cell {
                    break;
                }
            }
            let lo = c.map(|x| x.saturating_sub(r));
            let hi = [0, 1, 2].map(|k| (c[k] + r).min(self.dims[k] - 1));
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        let ring = x.abs_diff(c[0]).max(y.abs_diff(c[1])).max(z.abs_diff(c[2]));
                        if ring != r {
                            continue;
                        }
                        let i = self.index([x, y, z]);
                        for &f in &self.faces[self.start[i] as usize..self.start[i + 1] as usize] {
                            let q = closest_on_triangle(p, &mesh.corners(f as usize));
                            let d = (q - p).norm();
                            if best
                                .is_none_or(|(_, bf, bd)| d < bd || (d == bd && (f as usize) < bf))
                            {
                                best = Some((q, f as usize, d));
                            }
                        }
                    }
                }
            }
        }
        best
    }
}

/// Closest point of triangle `t` to `p` (Ericson 2005, §5.1.5, by Voronoi regions).
pub(crate) fn closest_on_triangle(p: &Point3, t: &[Point3; 3]) -> Point3 {
    let (a, b, c) = (t[0], t[1], t[2]);
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom.abs() < Real::MIN_POSITIVE {
        // Collapsed triangle: the closest of its vertices is good enough.
        return *[a, b, c]
            .iter()
            .min_by(|x, y| (*x - p).norm_squared().total_cmp(&(*y - p).norm_squared()))
            .unwrap_or(&a);
    }
    a + ab * (vb / denom) + ac * (vc / denom)
}

/// Distance from `p` to segment `ab` and whether the foot is inside the segment (not an end).
pub(crate) fn segment_distance(p: &Point3, a: &Point3, b: &Point3) -> (Real, bool) {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 <= 0.0 {
        return ((p - a).norm(), false);
    }
    let t = (p - a).dot(&ab) / len2;
    if t <= 0.0 {
        ((p - a).norm(), false)
    } else if t >= 1.0 {
        ((p - b).norm(), false)
    } else {
        ((p - (a + ab * t)).norm(), true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vertex_normal_table_is_the_normals_asked_one_by_one() {
        // A fan of 40 triangles round vertex 0 on a cone (a vertex of high valence), a face
        // repeating a vertex and a vertex in no face; all faces, then half of them.
        let mut positions = vec![Point3::new(0.0, 0.0, 1.0)];
        for k in 0..40 {
            let t = k as Real * 0.157;
            positions.push(Point3::new(t.cos(), t.sin(), 0.1 * (3.0 * t).sin()));
        }
        positions.push(Point3::new(5.0, 5.0, 5.0));
        let mut triangles: Vec<[u32; 3]> = (0..40).map(|k| [0, k + 1, (k + 1) % 40 + 1]).collect();
        triangles.push([1, 1, 2]);
        let mesh = TriMesh::new(positions, triangles).unwrap();
        let adjacency = FaceAdjacency::new(&mesh);
        let half: Vec<u32> = (0..41).step_by(2).collect();
        for subset in [None, Some(&half[..])] {
            let surface = Surface::new(&mesh, &adjacency, subset).unwrap();
            let table = surface.vertex_normals();
            assert_eq!(table.len(), mesh.vertex_count());
            for (v, n) in table.iter().enumerate() {
                let one = surface.vertex_normal(v);
                assert_eq!(n.map(Real::to_bits), one.map(Real::to_bits), "vertex {v}");
            }
            assert_eq!(table[41], Vector3::zeros());
            assert!((table[0].norm() - 1.0).abs() < 1e-12);
        }
    }
}
