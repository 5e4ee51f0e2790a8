//! Focal-point refinement of the accurate (virtual source) geodesic method.
//!
//! Source: no paper; chosen because the error of virtual-source propagation (Trettner, Bommes
//!         & Kobbelt 2021) is first order in the edge length only where fronts from a
//!         continuum of directions converge (the pole of a cap measured from its rim, the
//!         antipode of a point on a sphere): a vertex there is offered its neighbours'
//!         sources, whose rays miss it by an angle that does not shrink with the edges; the
//!         error is first order at the focus and falls off slowly around it (measured on the
//!         cap: about h²/ρ at distance ρ from the focus, h the edge). Away from the focus
//!         `fronts.rs` interpolates between the neighbours' sources, which removes most of
//!         that error from a few rings out; at the focus itself the sources' rays miss by
//!         too wide an angle for that. Linear subdivision keeps the polyhedron, so the
//!         propagation rerun on a subdivided patch around the focus converges to the same
//!         distance with shorter edges.
//! Input:  a settled [`Solver`] (distance and virtual source per vertex).
//! Output: the same distances, lowered around the foci by front interpolation and inside
//!         each refined patch to the patch's answer.
//! Steps:  I. a local maximum of the distance is focal when the ray directions of its neighbours (foot of the
//!            virtual source → vertex, in its tangent plane) wind once around it and point
//!            inwards: a sink of the direction field lies in its star (a shock between two
//!            fronts has two directions only and does not wind); the distances around them
//!            are lowered by front interpolation (`fronts.rs`, see [`interpolate_fronts`]);
//!         II. a patch is the faces within [`RINGS`] vertex rings of the focal vertices
//!            (fewer if the budget asks), at each nested level;
//!         III. its faces are cut into four,
//!             the vertices on its outer edges are seeded with the sources of the settled
//!             vertices there (moved into the patch's faces), and the propagation is rerun
//!             inside; a vertex keeps the smaller of its two distances (both are lengths of
//!             unfolded paths, so the smaller is the better one).
//!         IV. the same again inside the patch, [`MAX_DEPTH`] levels at most.
//! Cost:   step I tests the stars of the local maxima of the distance only (the propagation
//!         lists them: vertices settled after all their neighbours) and interpolates fronts
//!         at a quarter of the vertices at most; steps II–IV at most `budget` subdivided
//!         faces in all.

use super::fronts;
use super::params::GeodesicError;
use super::surface::Surface;
use super::unfolding::angle_defect;
use super::virtual_source::{foot, Solver, Virtual};
use crate::math::{Point3, Real, Vector3};
use crate::mesh::{FaceAdjacency, TriMesh};
use rustc_hash::FxHashMap as HashMap;
use std::collections::VecDeque;

/// Vertex rings around a focal vertex that are subdivided, at each level (no paper: front
/// interpolation brings the error to the order of the unfolding's own from about 6 rings
/// out and stops [`PATCH_MARGIN`] rings short of a patch's edge, so each level has to
/// reach over 2 × (6 + 8) of its own rings, twice its parent's: 16 parent rings reach 32).
pub(super) const RINGS: u8 = 16;
/// Rings short of a patch's edge where front interpolation stops.
const PATCH_MARGIN: u32 = 8;
/// Front interpolation on the whole surface stops at the first ring of vertices around the
/// foci where no distance was lowered by this fraction of the mean edge or more (not where
/// few of a ring's distances were lowered: on the 500k cap from its section through a ring
/// of vertices, 30 % of the distances of the ring 92 out were lowered, by up to 0.006 mm,
/// and stopping there, as a rule of three quarters lowered did, left the 20 rings beyond
/// up to 0.011 mm too long; 0.008 now)...
const GAIN_STOP: Real = 1e-3;
/// ...or when it has processed this share of the vertices...
const FRONT_SHARE: f64 = 0.25;
/// ...or at the first ring where no distance was lowered by more than this share of the
/// unfolding's own error there (about K·D·h²/3, see `fronts.rs`): the samples carry that
/// error, so what is lowered by less is as likely their error as the fronts' excess. On a
/// sphere from a point (K D large) the excess falls below it about 100 rings out, and going
/// on lowered distances that were right (500k triangles: mean signed error −0.0012 mm on
/// the rings past that, −0.0004 mm left as they were); on the cap from its rim (K D small)
/// the excess stays above it (twice it at a quarter of the vertices).
const BIAS_SHARE: Real = 0.5;
/// Vertices of a ring whose angle defects estimate its Gaussian curvature, at most.
const BIAS_SAMPLES: usize = 32;
/// Nested refinements at most (edges up to 2^depth times shorter at the focus).
pub(super) const MAX_DEPTH: u32 = 3;

/// Subdivided faces allowed in all on a surface of `faces` active faces (no paper: a quarter of
/// the surface, so the refinement costs at most about a quarter of the propagation, and at
/// least enough for one patch on small meshes).
pub(super) fn budget(faces: usize) -> usize {
    (faces / 4).max(1 << 14)
}

/// Bytes per subdivided face at most (mesh, adjacency, surface tables, solver state).
pub(super) const BYTES_PER_FACE: u64 = 256;

/// Lowers the distances of `s` inside patches around its focal points, refining at most
/// `budget` faces in all.
pub(super) fn refine_focal(
    s: &mut Solver,
    budget: usize,
    depth: u32,
    rings: u8,
    extent: Option<u32>,
) -> Result<usize, GeodesicError> {
    let surface = s.surface;
    let mesh = surface.mesh;
    let pos = mesh.positions();
    // Step I, at the local maxima of the distance only (where fronts end: a focus is in the
    // star of the last vertex of its face to settle).
    let mut focal: Vec<u32> = s
        .maxima
        .iter()
        .copied()
        .filter(|&v| is_sink(s, v as usize))
        .collect();
    focal.sort_unstable();
    if focal.is_empty() || depth == 0 {
        return Ok(0);
    }
    // Front interpolation around the foci, before the patches are cut (a patch is seeded
    // from the sources, which it leaves as they were).
    interpolate_fronts(s, &focal, extent, rings as u32);
    // Step II: vertex rings by breadth-first search (each vertex enters the queue once).
    let mut ring = vec![u8::MAX; mesh.vertex_count()];
    let mut queue = VecDeque::new();
    for &v in &focal {
        ring[v as usize] = 0;
        queue.push_back(v as usize);
    }
    let mut reached = Vec::new();
    // Faces a patch may have: each becomes four.
    let cap = budget / 4;
    let mut faces_seen = 0usize;
    let mut last_ring = rings;
    while let Some(v) = queue.pop_front() {
        if ring[v] > last_ring {
            ring[v] = u8::MAX;
            continue;
        }
        reached.push(v);
        faces_seen += surface.faces_of(v).len();
        if faces_seen > 2 * cap && last_ring > ring[v] {
            // A vertex has about six faces and a face three vertices: stop after this ring.
            last_ring = ring[v];
        }
        if ring[v] >= last_ring {
            continue;
        }
        for &f in surface.faces_of(v) {
            for w in mesh.triangles()[f as usize] {
                if ring[w as usize] == u8::MAX {
                    ring[w as usize] = ring[v] + 1;
                    queue.push_back(w as usize);
                }
            }
        }
    }
    // Every vertex left with a ring was reached (the others were reset), so a face is in the
    // patch when all its corners have a ring: a test in O(1).
    let in_patch = |f: usize| {
        mesh.triangles()[f]
            .iter()
            .all(|&w| ring[w as usize] != u8::MAX)
    };
    // Ascending without a sort: marked in a bit set over the faces, then read in order.
    let mut marked = vec![0u64; mesh.triangle_count().div_ceil(64)];
    for &v in &reached {
        for &f in surface.faces_of(v) {
            if in_patch(f as usize) {
                marked[f as usize / 64] |= 1 << (f % 64);
            }
        }
    }
    let mut patch: Vec<u32> = Vec::with_capacity(faces_seen / 3 + 1);
    for (w, &bits) in marked.iter().enumerate() {
        let mut bits = bits;
        while bits != 0 {
            patch.push((64 * w) as u32 + bits.trailing_zeros());
            bits &= bits - 1;
        }
    }
    if patch.is_empty() || 4 * patch.len() > budget {
        return Ok(0);
    }
    let levels = 1;
    // Step III.
    let mut refined = subdivide(surface, &patch, levels);
    let (positions, triangles) = (
        std::mem::take(&mut refined.positions),
        std::mem::take(&mut refined.triangles),
    );
    let mesh2 = TriMesh::new(positions, triangles).map_err(|e| {
        GeodesicError::LimitExceeded(format!("the focal patch could not be built: {e}"))
    })?;
    let adjacency2 = FaceAdjacency::new(&mesh2);
    let surface2 = Surface::new(&mesh2, &adjacency2, None)?;
    let mut s2 = Solver::new(&surface2);
    s2.reach = s.reach;
    let pos2 = mesh2.positions();
    // Seeds: the coarse vertices and edge points on the patch's outer edges.
    for (i, &f) in patch.iter().enumerate() {
        let f = f as usize;
        let child = refined.first_child[i];
        let tri = mesh.triangles()[f];
        for k in 0..3 {
            let v = tri[k] as usize;
            let outer_vertex = surface.faces_of(v).iter().any(|&g| !in_patch(g as usize));
            if outer_vertex && s.dist[v].is_finite() {
                let r = refined.corner[i][k] as usize;
                let src = s
                    .moved(v, f)
                    .unwrap_or_else(|| Virtual::point(pos[v], s.dist[v], f as u32));
                // The distance its source gives (front interpolation may have lowered
                // the vertex's below it, which the patch's propagation would not match).
                let own =
                    src.distance(&pos[v], &s.surface.face_normals[src.face as usize], s.reach);
                s2.improve(r, own.max(s.dist[v]), Virtual { face: child, ..src });
            }
            let outer_edge = matches!(surface.across(f, k), Some(g) if !in_patch(g));
            if !outer_edge {
                continue;
            }
            let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
            // Only reached ends carry a source (an unreached one holds a placeholder).
            let sources = [a, b].map(|u| s.dist[u].is_finite().then(|| s.moved(u, f)).flatten());
            for &r in refined.edge_points(i, k) {
                let x = pos2[r as usize];
                let best = sources
                    .iter()
                    .flatten()
                    .map(|src| {
                        (
                            src.distance(&x, &s.surface.face_normals[src.face as usize], s.reach),
                            src,
                        )
                    })
                    .min_by(|p, q| p.0.total_cmp(&q.0));
                if let Some((d, src)) = best {
                    s2.improve(
                        r as usize,
                        d,
                        Virtual {
                            face: child,
                            ..*src
                        },
                    );
                }
            }
        }
    }
    s2.run(None);
    s2.free_queue();
    let used = 4 * patch.len();
    let used = used
        + refine_focal(
            &mut s2,
            budget - used,
            depth - 1,
            rings,
            // The patch reaches `rings` coarse rings from its focal vertices: twice as many
            // of its own.
            Some(2 * rings as u32),
        )?;
    for (i, &f) in patch.iter().enumerate() {
        for (k, &v) in mesh.triangles()[f as usize].iter().enumerate() {
            let d = s2.dist[refined.corner[i][k] as usize];
            let v = v as usize;
            // (never below the straight line from a source vertex: a patch is propagated
            // without that bound).
            if d < s.dist[v] && d >= s.floor(v) {
                s.dist[v] = d;
            }
        }
    }
    Ok(used)
}

/// Lowers the distances around `focal` by [`fronts::lower`], ring by ring of vertices
/// outwards: on a patch reaching `extent` rings, up to [`PATCH_MARGIN`] rings short of its
/// edge (where its vertices see one side only); on the whole surface while a ring beyond
/// the first patch's `rings` still lowers distances (see [`GAIN_STOP`]), [`FRONT_SHARE`] of
/// the vertices at most. Each vertex is processed once, so this ends.
fn interpolate_fronts(s: &mut Solver, focal: &[u32], extent: Option<u32>, rings: u32) {
    let surface = s.surface;
    let mesh = surface.mesh;
    let nv = mesh.vertex_count();
    let (last, most) = match extent {
        Some(e) => (e.saturating_sub(PATCH_MARGIN), nv),
        None => (u32::MAX, (nv as f64 * FRONT_SHARE) as usize),
    };
    let mut scratch = fronts::Scratch::new(nv);
    let mut seen = vec![false; nv];
    let mut ring: Vec<u32> = focal.to_vec();
    for &v in focal {
        seen[v as usize] = true;
    }
    let (mut k, mut done) = (0u32, 0usize);
    while !ring.is_empty() && k < last && done < most {
        // Away from the focus (beyond the first patch) an interpolated distance may lie a
        // little below what a neighbour allows; `relax` lowers the neighbour after.
        let slack = extent.is_none() && k >= rings;
        let gain = fronts::lower(s, &ring, slack, &mut scratch);
        done += ring.len();
        if extent.is_none()
            && k >= rings
            && (gain < GAIN_STOP * surface.mean_edge
                || gain < BIAS_SHARE * unfolding_error(s, &ring))
        {
            break;
        }
        let mut next = Vec::with_capacity(ring.len() + 8);
        for &v in &ring {
            for &f in surface.faces_of(v as usize) {
                for w in mesh.triangles()[f as usize] {
                    if !seen[w as usize] {
                        seen[w as usize] = true;
                        next.push(w);
                    }
                }
            }
        }
        ring = next;
        k += 1;
    }
    fronts::relax(s, &scratch.relax_from);
}

/// The unfolding's own error at the vertices of `ring`, about K·D·h²/3 (`fronts.rs`): K the
/// Gaussian curvature (the angle defects of up to [`BIAS_SAMPLES`] of its interior vertices
/// over a third of their faces' area), D their mean distance, h the mean edge.
fn unfolding_error(s: &Solver, ring: &[u32]) -> Real {
    let surface = s.surface;
    let (mut defect, mut area, mut distance, mut n) = (0.0, 0.0, 0.0, 0);
    for &v in ring
        .iter()
        .step_by(ring.len().div_ceil(BIAS_SAMPLES).max(1))
    {
        let v = v as usize;
        let (Some(d), true) = (angle_defect(surface, v), s.dist[v].is_finite()) else {
            continue;
        };
        defect += d;
        for &f in surface.faces_of(v) {
            area += surface.mesh.scaled_normal(f as usize).norm() / 6.0;
        }
        distance += s.dist[v];
        n += 1;
    }
    if n == 0 || area <= 0.0 {
        return 0.0;
    }
    (defect / area).abs() * (distance / n as Real) * surface.mean_edge * surface.mean_edge / 3.0
}

/// Whether the ray directions of the neighbours of interior vertex `v` wind once around it
/// and point inwards: a focus lies in the star of `v` (on `v`, on an edge or in a face).
fn is_sink(s: &Solver, v: usize) -> bool {
    let surface = s.surface;
    let mesh = surface.mesh;
    let pos = mesh.positions();
    // The unit direction of the ray arriving at a reached vertex (zero at the source).
    let direction = |v: usize| {
        let src = &s.src[v];
        if !s.dist[v].is_finite() {
            return Vector3::zeros();
        }
        let w = pos[v]
            - foot(
                &pos[v],
                &src.p,
                &src.q,
                &src.run_on,
                &surface.face_normals[src.face as usize],
                s.reach,
            );
        let l = w.norm();
        if l > 0.0 {
            w / l
        } else {
            Vector3::zeros()
        }
    };
    let n = &surface.vertex_normal(v);
    let flat = |g: &Vector3| g - n * n.dot(g);
    let (mut turn, mut inwards) = (0.0, 0.0);
    for &f in surface.faces_of(v) {
        let f = f as usize;
        let t = mesh.triangles()[f];
        let k = t.iter().position(|&x| x as usize == v).unwrap_or(0);
        if surface.across(f, k).is_none() || surface.across(f, (k + 2) % 3).is_none() {
            return false;
        }
        let (a, b) = (t[(k + 1) % 3] as usize, t[(k + 2) % 3] as usize);
        let (ga, gb) = (flat(&direction(a)), flat(&direction(b)));
        if ga.norm_squared() == 0.0 || gb.norm_squared() == 0.0 {
            return false;
        }
        turn += libm::atan2(ga.cross(&gb).dot(n), ga.dot(&gb));
        inwards += direction(a).dot(&(pos[v] - pos[a]));
    }
    turn.abs() > std::f64::consts::PI && inwards > 0.0
}

/// A patch cut into 4^L faces each: vertices welded along shared edges.
struct Subdivision {
    positions: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
    /// Per patch face: the id of its first child (in its plane).
    first_child: Vec<u32>,
    /// Per patch face: the new ids of its corners.
    corner: Vec<[u32; 3]>,
    /// Per patch face and edge slot k (corner k → k + 1): the new ids of the `m − 1` points
    /// inside the edge, in one table ([`Subdivision::edge_points`] reads it).
    edge_points: Vec<u32>,
    /// Parts an edge is cut into.
    m: usize,
}

impl Subdivision {
    /// The new ids of the points inside edge slot `k` of patch face `i`.
    fn edge_points(&self, i: usize, k: usize) -> &[u32] {
        let n = self.m - 1;
        let at = (3 * i + k) * n;
        &self.edge_points[at..at + n]
    }
}

/// Linear subdivision of `patch` (ascending face ids) into `m = 2^levels` parts an edge; the
/// points on an edge are computed from its smaller vertex id so neighbours share them exactly.
fn subdivide(surface: &Surface, patch: &[u32], levels: u32) -> Subdivision {
    let mesh = surface.mesh;
    let pos = mesh.positions();
    let m = 1usize << levels;
    let n = patch.len();
    // Sized up front, so nothing is copied as it grows: at most 3 corners, 3 (m − 1) edge
    // points and (m − 1)(m − 2) / 2 inner points a face (the part not used is never written).
    // A patch of a surface has about half a vertex and one and a half edges a face, a few
    // more along its rim.
    let most = n * (m + 1) * (m + 2) / 2;
    let mut out = Subdivision {
        positions: Vec::with_capacity(most),
        triangles: Vec::with_capacity(n * m * m),
        first_child: Vec::with_capacity(n),
        corner: Vec::with_capacity(n),
        edge_points: Vec::with_capacity(3 * n * (m - 1)),
        m,
    };
    let mut corners: HashMap<u32, u32> = HashMap::default();
    corners.reserve(n / 2 + n / 4 + 8);
    let mut edges: HashMap<(u32, u32, usize), u32> = HashMap::default();
    edges.reserve((2 * n + 8) * (m - 1));
    let mut id = vec![0u32; (m + 1) * (m + 1)];
    for &f in patch {
        let t = mesh.triangles()[f as usize];
        let [a, b, c] = t.map(|v| pos[v as usize]);
        // Lattice point (i, j) = a + i/m (b − a) + j/m (c − a).
        let mut on_edge = |p: u32, q: u32, k: usize, out: &mut Subdivision| -> u32 {
            let (lo, hi, k) = if p < q { (p, q, k) } else { (q, p, m - k) };
            *edges.entry((lo, hi, k)).or_insert_with(|| {
                let (pl, ph) = (pos[lo as usize], pos[hi as usize]);
                out.positions.push(pl + (ph - pl) * (k as Real / m as Real));
                (out.positions.len() - 1) as u32
            })
        };
        // This face's edge points: slot k's are at `base + k (m − 1)`, `fill[k]` of them so far.
        let base = out.edge_points.len();
        out.edge_points.resize(base + 3 * (m - 1), 0);
        let mut fill = [0usize; 3];
        let mut on_slot = |k: usize, v: u32, out: &mut Subdivision| {
            out.edge_points[base + k * (m - 1) + fill[k]] = v;
            fill[k] += 1;
        };
        for i in 0..=m {
            for j in 0..=m - i {
                let v = if (i, j) == (0, 0) || (i, j) == (m, 0) || (i, j) == (0, m) {
                    let k = if i == m {
                        1
                    } else if j == m {
                        2
                    } else {
                        0
                    };
                    *corners.entry(t[k]).or_insert_with(|| {
                        out.positions.push(pos[t[k] as usize]);
                        (out.positions.len() - 1) as u32
                    })
                } else if j == 0 {
                    let v = on_edge(t[0], t[1], i, &mut out);
                    on_slot(0, v, &mut out);
                    v
                } else if i + j == m {
                    let v = on_edge(t[1], t[2], j, &mut out);
                    on_slot(1, v, &mut out);
                    v
                } else if i == 0 {
                    let v = on_edge(t[0], t[2], j, &mut out);
                    on_slot(2, v, &mut out);
                    v
                } else {
                    let (u, w) = (i as Real / m as Real, j as Real / m as Real);
                    out.positions.push(a + (b - a) * u + (c - a) * w);
                    (out.positions.len() - 1) as u32
                };
                id[i * (m + 1) + j] = v;
            }
        }
        let at = |i: usize, j: usize| id[i * (m + 1) + j];
        out.first_child.push(out.triangles.len() as u32);
        out.corner.push([at(0, 0), at(m, 0), at(0, m)]);
        for i in 0..m {
            for j in 0..m - i {
                out.triangles.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
                if i + j + 1 < m {
                    out.triangles
                        .push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_unfolding_error_of_a_ring_on_a_sphere_follows_its_curvature_and_distance() {
        // A latitude-longitude sphere of radius 10; the ring is the row of vertices at
        // colatitude 2π/5 from the north pole, their distance from it 10 · 2π/5.
        let (r, around, rows) = (10.0, 96usize, 48usize);
        let mut positions = vec![Point3::new(0.0, 0.0, r)];
        for i in 1..rows {
            let th = std::f64::consts::PI as Real * i as Real / rows as Real;
            for j in 0..around {
                let ph = 2.0 * std::f64::consts::PI as Real * j as Real / around as Real;
                positions.push(Point3::new(
                    r * libm::sin(th) * libm::cos(ph),
                    r * libm::sin(th) * libm::sin(ph),
                    r * libm::cos(th),
                ));
            }
        }
        positions.push(Point3::new(0.0, 0.0, -r));
        let south = positions.len() as u32 - 1;
        let at = |i: usize, j: usize| (1 + (i - 1) * around + j % around) as u32;
        let mut triangles = Vec::new();
        for j in 0..around {
            triangles.push([0, at(1, j), at(1, j + 1)]);
            triangles.push([south, at(rows - 1, j + 1), at(rows - 1, j)]);
            for i in 1..rows - 1 {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let mesh = TriMesh::new(positions, triangles).unwrap();
        let adjacency = FaceAdjacency::new(&mesh);
        let surface = Surface::new(&mesh, &adjacency, None).unwrap();
        let mut s = Solver::new(&surface);
        let row = 2 * rows / 5;
        let ring: Vec<u32> = (0..around).map(|j| at(row, j)).collect();
        let d = r * std::f64::consts::PI as Real * row as Real / rows as Real;
        for &v in &ring {
            s.dist[v as usize] = d;
        }
        let h = surface.mean_edge;
        let expected = d * h * h / (3.0 * r * r);
        let got = unfolding_error(&s, &ring);
        assert!(
            (got / expected - 1.0).abs() < 0.05,
            "{got} against {expected}"
        );
        // Unreached vertices tell nothing.
        assert_eq!(unfolding_error(&Solver::new(&surface), &ring), 0.0);
    }

    #[test]
    fn subdivision_welds_shared_edges_and_keeps_the_planes() {
        // Two faces sharing edge 1–2, cut into 16 each: 4 corners, 5 edges × 3 inner points,
        // 2 × 3 interior points.
        let mesh = TriMesh::new(
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(4.0, 0.0, 0.0),
                Point3::new(0.0, 4.0, 0.0),
                Point3::new(4.0, 4.0, 1.0),
            ],
            vec![[0, 1, 2], [1, 3, 2]],
        )
        .unwrap();
        let adjacency = FaceAdjacency::new(&mesh);
        let surface = Surface::new(&mesh, &adjacency, None).unwrap();
        let out = subdivide(&surface, &[0, 1], 2);
        assert_eq!(out.positions.len(), 4 + 5 * 3 + 2 * 3);
        assert_eq!(out.triangles.len(), 32);
        let fine = TriMesh::new(out.positions.clone(), out.triangles.clone()).unwrap();
        let fine_adjacency = FaceAdjacency::new(&fine);
        let boundary: usize = (0..32)
            .map(|f| {
                fine_adjacency
                    .neighbours(f)
                    .iter()
                    .filter(|&&g| g == crate::mesh::NO_FACE)
                    .count()
            })
            .sum();
        assert_eq!(boundary, 4 * 4, "only the outer edges are open");
        // Every child lies in its parent's plane and keeps its orientation.
        for (f, t) in out.triangles.iter().enumerate() {
            let parent = if f < 16 { 0 } else { 1 };
            let n = fine.scaled_normal(f).normalize();
            assert!((n - surface.face_normals[parent]).norm() < 1e-12);
            assert!(t.iter().all(|&v| (v as usize) < out.positions.len()));
        }
        // Edge 1–2 is slot 1 of face 0 and slot 2 of face 1: the same three vertices.
        let sorted = |mut v: Vec<u32>| {
            v.sort_unstable();
            v
        };
        assert_eq!(out.edge_points(0, 1).len(), 3);
        assert_eq!(
            sorted(out.edge_points(0, 1).to_vec()),
            sorted(out.edge_points(1, 2).to_vec())
        );
    }
}
