//! Iso-lines of a per-vertex scalar on a triangle mesh, chained into polylines.
//!
//! Source: marching triangles (the 2-D case of Lorensen & Cline, "Marching Cubes", 1987):
//!         linear interpolation of the value on each edge whose ends lie on either side.
//! Input:  the active faces, one value per vertex (`+∞` where unreached), a level.
//! Output: open and closed polylines with the unit surface normal (vertex normals
//!         interpolated along the edge) at each point.
//! Cost:   O(F) per level.
//! Deviations: none. A vertex at the level counts as above it, so every edge is cut at most
//!         once and both faces of an edge agree; "at" allows a relative `LEVEL_TOLERANCE`, so
//!         a row of vertices lying on the level up to rounding (a rim at a multiple of the
//!         spacing) gives one line through them, not fragments weaving across it; segments are chained through the face
//!         adjacency, so a polyline is closed exactly when it comes back to its first face.

use super::surface::Surface;
use crate::math::{any_perpendicular, Point3, Real, Vector3};

/// Relative distance from the level (of `max(|level|, 1)`) within which a vertex is on it.
const LEVEL_TOLERANCE: Real = 1e-9;

/// One polyline of a level set (or a pass of the voxel method), with a normal per point.
#[derive(Clone, Debug, PartialEq)]
pub struct IsoLine {
    /// Level index `k` (the line is at distance `k · spacing`; 0 for other uses).
    pub level: u32,
    /// The distance value of the line.
    pub distance: Real,
    /// Whether the last point connects back to the first (the first point is not repeated).
    pub closed: bool,
    /// Points on the surface, in travel order.
    pub points: Vec<Point3>,
    /// Unit outward surface normal per point.
    pub normals: Vec<Vector3>,
}

impl IsoLine {
    /// Length of the polyline, including the closing segment of a closed line.
    pub fn length(&self) -> Real {
        let n = self.points.len();
        let open: Real = self.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        if self.closed && n > 1 {
            open + (self.points[0] - self.points[n - 1]).norm()
        } else {
            open
        }
    }

    /// Unit travel direction at each point (central differences, perpendicular to the normal).
    pub fn tangents(&self) -> Vec<Vector3> {
        let n = self.points.len();
        (0..n)
            .map(|i| {
                let (prev, next) = if self.closed {
                    ((i + n - 1) % n, (i + 1) % n)
                } else {
                    (i.saturating_sub(1), (i + 1).min(n - 1))
                };
                let d = self.points[next] - self.points[prev];
                let nrm = self.normals[i];
                let t = d - nrm * d.dot(&nrm);
                let len = t.norm();
                if len > 0.0 {
                    t / len
                } else {
                    any_perpendicular(&nrm)
                }
            })
            .collect()
    }

    /// The same line with points every `spacing` along it (ends kept; normals interpolated).
    pub fn resampled(&self, spacing: Real) -> IsoLine {
        let n = self.points.len();
        if n < 2 {
            return self.clone();
        }
        let mut pts = self.points.clone();
        let mut nrm = self.normals.clone();
        if self.closed {
            pts.push(pts[0]);
            nrm.push(nrm[0]);
        }
        let mut cum = vec![0.0; pts.len()];
        for i in 1..pts.len() {
            cum[i] = cum[i - 1] + (pts[i] - pts[i - 1]).norm();
        }
        let total = cum[pts.len() - 1];
        let pieces = ((total / spacing).round() as usize).max(if self.closed { 3 } else { 1 });
        let count = if self.closed { pieces } else { pieces + 1 };
        let (mut points, mut normals) = (Vec::with_capacity(count), Vec::with_capacity(count));
        let mut seg = 0;
        for j in 0..count {
            let s = total * j as Real / pieces as Real;
            while seg + 2 < pts.len() && cum[seg + 1] < s {
                seg += 1;
            }
            let len = cum[seg + 1] - cum[seg];
            let t = if len > 0.0 {
                ((s - cum[seg]) / len).clamp(0.0, 1.0)
            } else {
                0.0
            };
            points.push(pts[seg] + (pts[seg + 1] - pts[seg]) * t);
            let m = nrm[seg] * (1.0 - t) + nrm[seg + 1] * t;
            normals.push(if m.norm() > 0.0 {
                m.normalize()
            } else {
                nrm[seg]
            });
        }
        IsoLine {
            points,
            normals,
            ..self.clone()
        }
    }
}

/// The level set `values = level` on the active faces as polylines (level index 0).
pub(crate) fn contour(surface: &Surface, values: &[Real], level: Real) -> Vec<IsoLine> {
    contour_with_faces(surface, values, level)
        .into_iter()
        .map(|(line, _)| line)
        .collect()
}

/// [`contour`] with the face each segment of a line lies in: segment `j` joins point `j` to
/// point `j + 1` (of a closed line, the last joins the last point to the first).
pub(crate) fn contour_with_faces(
    surface: &Surface,
    values: &[Real],
    level: Real,
) -> Vec<(IsoLine, Vec<u32>)> {
    let mesh = surface.mesh;
    let on = level - LEVEL_TOLERANCE * level.abs().max(1.0);
    let above = |v: u32| values[v as usize] >= on;
    // Crossing slots of each face: slot k is edge corner k → corner k+1.
    let crossing = |f: usize| -> Option<[usize; 2]> {
        let t = mesh.triangles()[f];
        if t.iter().any(|&v| !values[v as usize].is_finite()) {
            return None;
        }
        let mut slots = [0usize; 2];
        let mut n = 0;
        for k in 0..3 {
            if above(t[k]) != above(t[(k + 1) % 3]) {
                if n < 2 {
                    slots[n] = k;
                }
                n += 1;
            }
        }
        (n == 2).then_some(slots)
    };
    let point = |f: usize, k: usize| -> (Point3, Vector3) {
        let t = mesh.triangles()[f];
        // Always interpolate from the smaller vertex id so both faces get the same point.
        let (a, b) = (
            t[k].min(t[(k + 1) % 3]) as usize,
            t[k].max(t[(k + 1) % 3]) as usize,
        );
        let (da, db) = (values[a], values[b]);
        let s = ((level - da) / (db - da)).clamp(0.0, 1.0);
        let p = mesh.positions()[a] + (mesh.positions()[b] - mesh.positions()[a]) * s;
        (p, surface.edge_normal(a, b, s))
    };
    // The slot of face g that leads back to face f through the same crossing edge.
    let entry = |g: usize, f: usize, slots: [usize; 2]| -> Option<usize> {
        slots.into_iter().find(|&k| surface.across(g, k) == Some(f))
    };
    let mut visited = vec![false; mesh.triangle_count()];
    let mut lines = Vec::new();
    for &f0 in &surface.faces {
        let f0 = f0 as usize;
        if visited[f0] {
            continue;
        }
        let Some(slots0) = crossing(f0) else { continue };
        visited[f0] = true;
        // Walk one way from f0 through slots0[1], then the other way through slots0[0]; each
        // point with the face it leaves.
        let mut halves: [Vec<(Point3, Vector3, u32)>; 2] = [Vec::new(), Vec::new()];
        let mut closed = false;
        for (side, half) in halves.iter_mut().enumerate() {
            let (mut f, mut exit) = (f0, slots0[1 - side]);
            // Each step visits a new face, so at most F steps.
            loop {
                let (p, n) = point(f, exit);
                half.push((p, n, f as u32));
                let Some(g) = surface.across(f, exit) else {
                    break;
                };
                if g == f0 {
                    closed = true;
                    break;
                }
                if visited[g] {
                    break;
                }
                let Some(slots) = crossing(g) else { break };
                let Some(k) = entry(g, f, slots) else { break };
                visited[g] = true;
                exit = if slots[0] == k { slots[1] } else { slots[0] };
                f = g;
            }
            if closed {
                break;
            }
        }
        let back = halves[1].len();
        let mut chain: Vec<(Point3, Vector3, u32)> = halves[1].iter().rev().copied().collect();
        chain.extend_from_slice(&halves[0]);
        // A closed walk ends on the crossing of slots0[0], the edge it started from: the
        // polyline closes back to its first point without repeating it.
        if chain.len() >= 2 {
            // Walking back, a point's face holds the segment to the next point (towards f0);
            // walking on, the next point's face holds it. The closing segment lies in f0,
            // the face of the first point of a closed walk (which only the first half makes).
            let segments = if closed { chain.len() } else { chain.len() - 1 };
            let faces = (0..segments)
                .map(|j| {
                    if j + 1 == chain.len() {
                        chain[0].2
                    } else if j < back {
                        chain[j].2
                    } else {
                        chain[j + 1].2
                    }
                })
                .collect();
            lines.push((
                IsoLine {
                    level: 0,
                    distance: level,
                    closed,
                    points: chain.iter().map(|c| c.0).collect(),
                    normals: chain.iter().map(|c| c.1).collect(),
                },
                faces,
            ));
        }
    }
    lines
}
