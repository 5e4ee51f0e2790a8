//! Source curves of a geodesic distance: what the caller gives, turned into dense polylines
//! lying on the surface plus isolated source vertices.
//!
//! No paper: polyline points are snapped to their closest surface point and each segment is
//! subdivided (and its samples snapped) so consecutive samples are at most a fraction of an
//! edge apart; a boundary loop is chained from the edges of the active faces that have no
//! active face across; a plane section is the zero level set of the signed distance to the
//! plane (the iso-line code), keeping the piece that passes nearest to the plane's point.
//! Cost: O(F) plus a closest-point query per sample.

use super::iso_lines::contour;
use super::params::GeodesicError;
use super::surface::{FaceGrid, Surface};
use crate::math::{Point3, Real, Vector3};
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
            match leaving(at).find(|&i| !used[i]) {
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
    let n = lp.vertices.len();
    let mut curve = Curve {
        points: Vec::new(),
        faces: Vec::new(),
        closed: true,
    };
    for i in 0..n {
        let (a, b) = (
            p[lp.vertices[i] as usize],
            p[lp.vertices[(i + 1) % n] as usize],
        );
        let pieces = ((b - a).norm() / step).ceil().max(1.0) as usize;
        for j in 0..pieces {
            curve
                .points
                .push(a + (b - a) * (j as Real / pieces as Real));
            curve.faces.push(lp.faces[i]);
        }
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
                "{} is {d:.4} from the surface (max_snap_distance = {max_snap:.4})",
                what()
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
            curve.points.push(s.0);
            curve.faces.push(s.1);
        }
    }
    Ok(curve)
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
                    GeodesicError::BadSource(format!(
                        "loop {i} does not exist (the boundary has {} loops)",
                        loops.len()
                    ))
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
            let lines = contour(surface, &values, 0.0);
            let nearest = lines.iter().min_by(|a, b| {
                let d = |l: &&super::IsoLine| {
                    l.points
                        .iter()
                        .map(|p| (p - point).norm())
                        .fold(Real::MAX, Real::min)
                };
                d(a).total_cmp(&d(b))
            });
            let Some(line) = nearest else {
                return Err(GeodesicError::SourceMissesSurface(
                    "the plane does not cut the surface".into(),
                ));
            };
            out.curves.push(snap_polyline(
                surface,
                grid(),
                &line.points,
                line.closed,
                step,
                max_snap,
            )?);
        }
    }
    Ok(out)
}
