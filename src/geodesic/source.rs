//! Source curves of a geodesic distance: what the caller gives, turned into dense polylines
//! lying on the surface plus isolated source vertices.
//!
//! No paper: polyline points are snapped to their closest surface point and each segment is
//! subdivided (and its samples snapped) so consecutive samples are at most a fraction of an
//! edge apart; a boundary loop is chained from the edges of the active faces that have no
//! active face across; a plane section is the zero level set of the signed distance to the
//! plane (the iso-line code), keeping the piece that passes nearest to the plane's point with
//! every piece joined to it end to end (the walk along a level set stops at an edge of three
//! faces, and real files have them: one cut of a fuselage came in two halves), the pieces of
//! no length (a sliver's) after the others; its segments lie in known faces, so it is
//! subdivided without snapping.
//! Cost: O(F) plus a closest-point query per sample.

use super::iso_lines::{contour_with_faces, Ends, IsoLine, JOIN_TOLERANCE};
use super::params::GeodesicError;
use super::surface::{FaceGrid, Surface};
use crate::math::{Compact, Point3, Real, Vector3};
use std::cell::OnceCell;

/// Where the distance is measured from.
#[derive(Clone, Debug, PartialEq)]
pub enum GeodesicSource {
    /// Points on or near the surface, joined by straight segments and snapped onto it.
    Polyline {
        /// The points (mesh unit).
        points: Vec<Point3>,
        /// Whether the last point joins the first.
        closed: bool,
    },
    /// A set of mesh vertices (point sources).
    Vertices(Vec<u32>),
    /// A boundary loop of the active faces (the mesh, or the face subset of the parameters),
    /// numbered by decreasing length; `None`: every loop.
    Boundary {
        /// Which loop (0 = longest).
        loop_index: Option<usize>,
    },
    /// The section of the surface by a plane, the connected piece nearest to `point`.
    Plane {
        /// A point of the plane (usually picked on the surface).
        point: Point3,
        /// The plane's normal (any length > 0).
        normal: Vector3,
    },
}

/// A source polyline lying on the surface: dense samples and the face under each.
#[derive(Clone, Debug)]
pub(crate) struct Curve {
    pub points: Vec<Point3>,
    pub faces: Vec<u32>,
    pub closed: bool,
}

/// A source ready for propagation.
#[derive(Clone, Debug, Default)]
pub(crate) struct ResolvedSource {
    pub curves: Vec<Curve>,
    pub vertices: Vec<u32>,
}

impl ResolvedSource {
    /// Total number of source samples (for reports).
    pub fn sample_count(&self) -> usize {
        self.curves.iter().map(|c| c.points.len()).sum::<usize>() + self.vertices.len()
    }
}

/// Boundary loops of the active faces as vertex ids, longest first; a loop is closed
/// (its last vertex joins its first) unless the boundary is pinched in a way that breaks it.
pub(crate) fn boundary_loops(surface: &Surface) -> Vec<Vec<u32>> {
    boundary_loops_with_faces(surface)
        .into_iter()
        .map(|l| l.vertices)
        .collect()
}

/// A boundary loop: its vertices, the face of the edge from each to the next, and whether
/// the last vertex joins the first along a boundary edge.
pub(crate) struct BoundaryLoop {
    pub vertices: Vec<u32>,
    pub faces: Vec<u32>,
    pub closed: bool,
}

/// [`boundary_loops`] with the face of each edge.
fn boundary_loops_with_faces(surface: &Surface) -> Vec<BoundaryLoop> {
    let mesh = surface.mesh;
    let mut edges: Vec<(u32, u32, u32)> = Vec::new();
    for &f in &surface.faces {
        let t = mesh.triangles()[f as usize];
        for k in 0..3 {
            if surface.across(f as usize, k).is_none() {
                edges.push((t[k], t[(k + 1) % 3], f));
            }
        }
    }
    // Sorted by start vertex: the edges leaving a vertex are a contiguous run.
    edges.sort_unstable();
    let leaving = |v: u32| {
        let lo = edges.partition_point(|e| e.0 < v);
        let hi = edges.partition_point(|e| e.0 <= v);
        lo..hi
    };
    let mut used = vec![false; edges.len()];
    // Per run (at its first edge), where its first unused edge may be: every edge before it
    // is used, so a vertex that many boundary edges leave (the ends of an edge of many
    // faces) is not scanned from its start at every visit.
    let mut unused_from: Vec<u32> = (0..edges.len() as u32).collect();
    let mut loops = Vec::new();
    for first in 0..edges.len() {
        if used[first] {
            continue;
        }
        used[first] = true;
        let start = edges[first].0;
        let mut lp = BoundaryLoop {
            vertices: vec![start],
            faces: vec![edges[first].2],
            closed: true,
        };
        let mut at = edges[first].1;
        // Each step uses a new edge: at most `edges.len()` steps.
        while at != start {
            lp.vertices.push(at);
            let run = leaving(at);
            let next = if run.is_empty() {
                None
            } else {
                let from = &mut unused_from[run.start];
                let mut i = *from as usize;
                // Ends: i advances to the run's end at the latest.
                while i < run.end && used[i] {
                    i += 1;
                }
                *from = i as u32;
                (i < run.end).then_some(i)
            };
            match next {
                Some(i) => {
                    used[i] = true;
                    lp.faces.push(edges[i].2);
                    at = edges[i].1;
                }
                None => {
                    lp.closed = false;
                    break;
                }
            }
        }
        loops.push(lp);
    }
    let length = |lp: &BoundaryLoop| -> Real {
        let p = mesh.positions();
        let v = &lp.vertices;
        (0..v.len())
            .map(|i| (p[v[(i + 1) % v.len()] as usize] - p[v[i] as usize]).norm())
            .sum()
    };
    let mut keyed: Vec<(Real, BoundaryLoop)> = loops.into_iter().map(|l| (length(&l), l)).collect();
    keyed.sort_by(|a, b| {
        b.0.total_cmp(&a.0)
            .then_with(|| a.1.vertices.cmp(&b.1.vertices))
    });
    keyed.into_iter().map(|(_, l)| l).collect()
}

/// A closed boundary loop as a source curve, each edge cut into pieces of at most `step`:
/// the samples lie on the loop's edges, so they need no snapping.
fn boundary_curve(surface: &Surface, lp: &BoundaryLoop, step: Real) -> Curve {
    let p = surface.mesh.positions();
    let points: Vec<Point3> = lp.vertices.iter().map(|&v| p[v as usize]).collect();
    subdivided_curve(&points, &lp.faces, true, step)
}

/// A polyline lying on the surface as a source curve, each segment (lying in face
/// `faces[j]`: a boundary edge's face, or the face a plane section crosses) cut into pieces of
/// at most `step`. The samples lie on the surface already, so they need no snapping (nor the
/// closest-point grid, which costs more than a whole plane section to build).
fn subdivided_curve(points: &[Point3], faces: &[u32], closed: bool, step: Real) -> Curve {
    let mut curve = Curve {
        points: Vec::with_capacity(points.len()),
        faces: Vec::with_capacity(points.len()),
        closed,
    };
    for (j, &f) in faces.iter().enumerate() {
        let (a, b) = (points[j], points[(j + 1) % points.len()]);
        // A segment of no length (a plane section through a vertex, met again in each face
        // round it that the plane only touches) would make a piece of no direction, which
        // the propagation would take for a point source.
        if a == b && !(curve.points.is_empty() && j + 1 == faces.len()) {
            continue;
        }
        let pieces = ((b - a).norm() / step).ceil().max(1.0) as usize;
        for k in 0..pieces {
            curve
                .points
                .push(a + (b - a) * (k as Real / pieces as Real));
            curve.faces.push(f);
        }
    }
    if !closed {
        // The last point ends the last segment, in its face.
        curve.points.push(points[points.len() - 1]);
        curve.faces.push(faces[faces.len() - 1]);
    }
    curve
}

/// Snaps `points` to the surface and subdivides every segment to at most `step`.
fn snap_polyline(
    surface: &Surface,
    grid: &FaceGrid,
    points: &[Point3],
    closed: bool,
    step: Real,
    max_snap: Real,
) -> Result<Curve, GeodesicError> {
    let snap = |p: &Point3, what: &dyn Fn() -> String| -> Result<(Point3, u32), GeodesicError> {
        match grid.closest(surface.mesh, p) {
            Some((q, f, d)) if d <= max_snap => Ok((q, f as u32)),
            Some((_, _, d)) => Err(GeodesicError::SourceMissesSurface(format!(
                "{} is {} from the surface (maxSnapDistance = {})",
                what(),
                Compact(d),
                Compact(max_snap)
            ))),
            None => Err(GeodesicError::SourceMissesSurface("no active face".into())),
        }
    };
    let mut snapped = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        if !p.coords.iter().all(|c| c.is_finite()) {
            return Err(GeodesicError::BadSource(format!("point {i} is not finite")));
        }
        snapped.push(snap(p, &|| {
            format!("source point {i} {:?}", p.coords.as_slice())
        })?);
    }
    let mut curve = Curve {
        points: Vec::new(),
        faces: Vec::new(),
        closed,
    };
    let n = snapped.len();
    let segments = if closed && n > 2 { n } else { n - 1 };
    curve.points.push(snapped[0].0);
    curve.faces.push(snapped[0].1);
    for i in 0..segments {
        let (a, b) = (snapped[i].0, snapped[(i + 1) % n].0);
        let pieces = ((b - a).norm() / step).ceil().max(1.0) as usize;
        for j in 1..=pieces {
            if closed && i + 1 == segments && j == pieces {
                break; // the first point closes the loop
            }
            let q = a + (b - a) * (j as Real / pieces as Real);
            let s = if j == pieces {
                snapped[(i + 1) % n]
            } else {
                snap(&q, &|| {
                    format!("the segment from source point {i} to {}", (i + 1) % n)
                })?
            };
            // A point repeated (given twice, or two points snapped to one) would make a
            // piece of no length, which the propagation would take for a point source.
            if curve.points.last() != Some(&s.0) {
                curve.points.push(s.0);
                curve.faces.push(s.1);
            }
        }
    }
    if closed && curve.points.len() > 1 && curve.points.last() == curve.points.first() {
        curve.points.pop();
        curve.faces.pop();
    }
    Ok(curve)
}

/// The pieces of a section joined end to end to piece `first`, directly or through others,
/// `first` included, in increasing order. The level-set walk stops where an edge has no
/// single face across (an edge of three faces, such as a sliver glued along it), so one cut
/// of the surface can come as several pieces whose ends meet (within `tolerance`); they are
/// one section. O(pieces).
fn joined_pieces(lines: &[(IsoLine, Vec<u32>)], first: usize, tolerance: Real) -> Vec<usize> {
    let open = |i: usize| !lines[i].0.closed && !lines[i].0.points.is_empty();
    let ends = |i: usize| {
        let points = &lines[i].0.points;
        [points[0], points[points.len() - 1]]
    };
    let index = Ends::new(
        (0..lines.len())
            .filter(|&i| open(i))
            .flat_map(|i| ends(i).map(|p| (i as u32, p))),
        tolerance,
    );
    let mut taken = vec![false; lines.len()];
    taken[first] = true;
    let mut queue = vec![first];
    // Each piece enters the queue once.
    while let Some(i) = queue.pop() {
        if !open(i) {
            continue;
        }
        for end in ends(i) {
            for j in index.near(&end) {
                if !taken[j as usize] {
                    taken[j as usize] = true;
                    queue.push(j as usize);
                }
            }
        }
    }
    (0..lines.len()).filter(|&i| taken[i]).collect()
}

/// Turns a [`GeodesicSource`] into dense on-surface curves and vertices.
pub(crate) fn resolve(
    surface: &Surface,
    grid: &OnceCell<FaceGrid>,
    source: &GeodesicSource,
    step: Real,
    max_snap: Real,
) -> Result<ResolvedSource, GeodesicError> {
    let mesh = surface.mesh;
    let grid = || grid.get_or_init(|| FaceGrid::new(surface));
    let mut out = ResolvedSource::default();
    match source {
        GeodesicSource::Polyline { points, closed } => {
            if points.is_empty() {
                return Err(GeodesicError::BadSource(
                    "the polyline has no points".into(),
                ));
            }
            out.curves.push(snap_polyline(
                surface,
                grid(),
                points,
                *closed,
                step,
                max_snap,
            )?);
        }
        GeodesicSource::Vertices(vs) => {
            if vs.is_empty() {
                return Err(GeodesicError::BadSource("the vertex set is empty".into()));
            }
            for &v in vs {
                if v as usize >= mesh.vertex_count() {
                    return Err(GeodesicError::BadSource(format!(
                        "vertex {v} does not exist (the mesh has {} vertices)",
                        mesh.vertex_count()
                    )));
                }
                if surface.faces_of(v as usize).is_empty() {
                    return Err(GeodesicError::SourceMissesSurface(format!(
                        "vertex {v} belongs to no active face"
                    )));
                }
            }
            out.vertices = vs.clone();
            out.vertices.sort_unstable();
            out.vertices.dedup();
        }
        GeodesicSource::Boundary { loop_index } => {
            let loops = boundary_loops_with_faces(surface);
            if loops.is_empty() {
                return Err(GeodesicError::BadSource(
                    "the surface is closed: it has no boundary loop".into(),
                ));
            }
            let chosen: Vec<&BoundaryLoop> = match loop_index {
                None => loops.iter().collect(),
                Some(i) => vec![loops.get(*i).ok_or_else(|| {
                    GeodesicError::BadSource(match loops.len() {
                        1 => format!("loop {i} does not exist: the boundary has 1 loop, loop 0"),
                        n => format!(
                            "loop {i} does not exist: the boundary has {n} loops, 0 to {} \
                             (longest first)",
                            n - 1
                        ),
                    })
                })?],
            };
            for lp in chosen {
                if lp.closed {
                    out.curves.push(boundary_curve(surface, lp, step));
                } else {
                    // A loop broken at a pinch: its closing chord is snapped like any polyline.
                    let p = mesh.positions();
                    let pts: Vec<Point3> = lp.vertices.iter().map(|&v| p[v as usize]).collect();
                    out.curves
                        .push(snap_polyline(surface, grid(), &pts, true, step, max_snap)?);
                }
            }
        }
        GeodesicSource::Plane { point, normal } => {
            let len = normal.norm();
            if !(len.is_finite() && len > 0.0 && point.coords.iter().all(|c| c.is_finite())) {
                return Err(GeodesicError::BadSource(
                    "the plane needs a finite point and a finite, non-zero normal".into(),
                ));
            }
            let n = normal / len;
            let values: Vec<Real> = mesh
                .positions()
                .iter()
                .map(|p| n.dot(&(p - point)))
                .collect();
            let lines = contour_with_faces(surface, &values, 0.0);
            let nearest = (0..lines.len()).min_by(|&a, &b| {
                let d = |i: usize| {
                    lines[i]
                        .0
                        .points
                        .iter()
                        .map(|p| (p - point).norm())
                        .fold(Real::MAX, Real::min)
                };
                d(a).total_cmp(&d(b))
            });
            let Some(nearest) = nearest else {
                return Err(GeodesicError::SourceMissesSurface(
                    "the plane does not cut the surface".into(),
                ));
            };
            let tolerance = JOIN_TOLERANCE * surface.mean_edge;
            // Pieces of no length (a sliver's, between two pieces glued on along its edge)
            // come last: they add the faces they lie in to the source, so that the
            // vertex-based methods start the sliver's lone corner at its distance, but a
            // vertex the other pieces start at the same distance keeps their front.
            let (mut long, mut short) = (Vec::new(), Vec::new());
            for i in joined_pieces(&lines, nearest, tolerance) {
                let (line, faces) = &lines[i];
                let curve = subdivided_curve(&line.points, faces, line.closed, step);
                if i == nearest || line.length() > tolerance {
                    long.push(curve);
                } else {
                    short.push(curve);
                }
            }
            out.curves.extend(long);
            out.curves.extend(short);
        }
    }
    Ok(out)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::{FaceAdjacency, TriMesh};

    /// A wavy strip bent into most of a tube (open along one seam when `open`): quads of
    /// alternating diagonals, so a section crosses faces both ways round (24 vertices a
    /// ring, 11 rings 2 apart).
    pub(crate) fn tube(open: bool) -> TriMesh {
        let (around, along) = (24usize, 10usize);
        let columns = if open { around + 1 } else { around };
        let mut positions = Vec::new();
        for j in 0..=along {
            for i in 0..columns {
                let a = 5.5 * i as Real / around as Real;
                let r = 10.0 + 0.7 * libm::sin(3.0 * a + 0.4 * j as Real);
                positions.push(Point3::new(
                    r * libm::cos(a),
                    r * libm::sin(a),
                    2.0 * j as Real,
                ));
            }
        }
        let id = |i: usize, j: usize| (j * columns + i % columns) as u32;
        let mut triangles = Vec::new();
        for j in 0..along {
            for i in 0..around {
                let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                if (i + j) % 2 == 0 {
                    triangles.extend([[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
                } else {
                    triangles.extend([[q[0], q[1], q[3]], [q[1], q[2], q[3]]]);
                }
            }
        }
        TriMesh::new(positions, triangles).unwrap()
    }

    /// Whether `p` lies in face `f` (in its plane and within its edges, up to rounding).
    fn in_face(mesh: &TriMesh, f: u32, p: &Point3) -> bool {
        let [a, b, c] = mesh.corners(f as usize);
        let n = (b - a).cross(&(c - a));
        let scale = n.norm();
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|(u, v)| (v - u).cross(&(p - u)).dot(&n) >= -1e-9 * scale * scale);
        inside && (p - a).dot(&n).abs() <= 1e-9 * scale
    }

    #[test]
    fn a_plane_section_is_sampled_in_the_faces_it_crosses_without_snapping() {
        for open in [false, true] {
            let mesh = tube(open);
            let adjacency = FaceAdjacency::new(&mesh);
            let surface = Surface::new(&mesh, &adjacency, None).unwrap();
            let step = surface.mean_edge / 4.0;
            // Tilted, so the section crosses rows of faces; it misses the seam's gap.
            let source = GeodesicSource::Plane {
                point: Point3::new(10.0, 0.0, 9.0),
                normal: Vector3::new(0.0, 0.25, 1.0),
            };
            let resolved = resolve(&surface, &OnceCell::new(), &source, step, 1.0).unwrap();
            let curve = &resolved.curves[0];
            assert_eq!(curve.closed, !open);
            assert_eq!(curve.points.len(), curve.faces.len());
            let n = curve.points.len();
            assert!(n > 50, "{n} samples");
            let segments = if curve.closed { n } else { n - 1 };
            for j in 0..segments {
                let (p, q) = (curve.points[j], curve.points[(j + 1) % n]);
                // On the plane, at most a step apart, and each sample and the next one in
                // the face of the sample (the piece between them lies in it).
                let off = Vector3::new(0.0, 0.25, 1.0)
                    .normalize()
                    .dot(&(p - Point3::new(10.0, 0.0, 9.0)));
                assert!(off.abs() < 1e-9, "sample {j} is {off} off the plane");
                assert!((q - p).norm() <= step * (1.0 + 1e-9));
                assert!(
                    in_face(&mesh, curve.faces[j], &p),
                    "sample {j} outside its face"
                );
                assert!(
                    in_face(&mesh, curve.faces[j], &q),
                    "sample {} outside face of {j}",
                    j + 1
                );
            }
            // The closed section goes all the way round: its length is about 2π r.
            let length: Real = (0..segments)
                .map(|j| (curve.points[(j + 1) % n] - curve.points[j]).norm())
                .sum();
            let full = 2.0 * std::f64::consts::PI as Real * 10.0;
            if open {
                assert!(
                    length > 0.8 * full && length < 0.95 * full,
                    "length {length}"
                );
            } else {
                assert!(
                    length > 0.95 * full && length < 1.15 * full,
                    "length {length}"
                );
            }
        }
    }

    #[test]
    fn a_plane_section_takes_the_pieces_joined_to_the_nearest_and_no_other() {
        // Two tubes side by side, the second cut open along a seam: the plane z = 5 cuts
        // each in one piece (a circle; an open arc). Only the nearer tube's is the source,
        // whichever the point is near; the pieces of one cut joined end to end are one
        // source (tests/geodesic.rs breaks a circle at edges of three faces).
        let (a, b) = (tube(false), tube(true));
        let shift = Vector3::new(30.0, 0.0, 0.0);
        let mut positions = a.positions().to_vec();
        positions.extend(b.positions().iter().map(|p| p + shift));
        let offset = a.vertex_count() as u32;
        let mut triangles = a.triangles().to_vec();
        triangles.extend(b.triangles().iter().map(|t| t.map(|v| v + offset)));
        let mesh = TriMesh::new(positions, triangles).unwrap();
        let adjacency = FaceAdjacency::new(&mesh);
        let surface = Surface::new(&mesh, &adjacency, None).unwrap();
        for (x, closed) in [(0.0, true), (30.0, false)] {
            let plane = GeodesicSource::Plane {
                point: Point3::new(x, 0.0, 5.0),
                normal: Vector3::z(),
            };
            let step = surface.mean_edge / 4.0;
            let resolved = resolve(&surface, &OnceCell::new(), &plane, step, 1.0).unwrap();
            assert_eq!(resolved.curves.len(), 1, "near x = {x}");
            let curve = &resolved.curves[0];
            assert_eq!(curve.closed, closed, "near x = {x}");
            assert!(
                curve.points.iter().all(|p| (p.x - x).abs() < 12.0),
                "near x = {x}"
            );
        }
    }

    #[test]
    fn no_piece_of_a_source_curve_has_no_length() {
        // A plane through a ring of vertices (z = 4) touches the faces round each of them
        // at that vertex only; a polyline repeats a point and ends where it began.
        let mesh = tube(false);
        let adjacency = FaceAdjacency::new(&mesh);
        let surface = Surface::new(&mesh, &adjacency, None).unwrap();
        let step = surface.mean_edge / 4.0;
        let plane = GeodesicSource::Plane {
            point: Point3::new(10.0, 0.0, 4.0),
            normal: Vector3::z(),
        };
        let ring: Vec<Point3> = (0..24)
            .filter(|&v| v % 3 == 0)
            .map(|v| mesh.positions()[2 * 24 + v])
            .collect();
        let mut repeated = vec![ring[0], ring[1], ring[1]];
        repeated.extend_from_slice(&ring[2..]);
        repeated.push(ring[0]);
        let polyline = GeodesicSource::Polyline {
            points: repeated,
            closed: true,
        };
        for source in [plane, polyline] {
            // The polyline's chords cut inside the tube, up to 1.2 from it.
            let resolved = resolve(&surface, &OnceCell::new(), &source, step, 2.0).unwrap();
            let curve = &resolved.curves[0];
            assert!(curve.closed);
            assert_eq!(curve.points.len(), curve.faces.len());
            let n = curve.points.len();
            assert!(n > 50, "{n} samples");
            for j in 0..n {
                let (p, q) = (curve.points[j], curve.points[(j + 1) % n]);
                assert!(p != q, "{source:?}: samples {j} and the next are one point");
            }
        }
    }
}
