//! Iso-lines of a per-vertex scalar on a triangle mesh, chained into polylines.
//!
//! Source: marching triangles (the 2-D case of Lorensen & Cline, "Marching Cubes", 1987):
//!         linear interpolation of the value on each edge whose ends lie on either side.
//! Input:  the active faces, one value per vertex (`+∞` where unreached), a level.
//! Output: open and closed polylines with the unit surface normal (vertex normals
//!         interpolated along the edge) at each point.
//! Cost:   O(F) for one level; for the levels of a distance field, O(F + C) in all (`C`
//!         the faces the levels cross: each face is listed under the levels it spans, see
//!         [`LevelLists`]), not O(F) per level.
//! Deviations: none. A vertex at the level counts as above it, so every edge is cut at most
//!         once and both faces of an edge agree; "at" allows a relative `LEVEL_TOLERANCE`, so
//!         a row of vertices lying on the level up to rounding (a rim at a multiple of the
//!         spacing) gives one line through them, not fragments weaving across it; segments are
//!         chained through the face adjacency, so a polyline is closed exactly when it comes
//!         back to its first face; a walk that meets only faces of no area gives no line. The
//!         walk stops at an edge of three faces, so the passes of a distance field are joined
//!         end to end where their ends meet ([`joined_at_ends`]; the plane source joins its
//!         pieces the same way).

use super::surface::Surface;
use crate::math::{any_perpendicular, Point3, Real, Vector3};
use crate::mesh::is_degenerate;
use rustc_hash::FxHashMap;

/// Relative distance from the level (of `max(|level|, 1)`) within which a vertex is on it.
const LEVEL_TOLERANCE: Real = 1e-9;

/// One polyline of a level set (or a pass of the voxel method), with a normal per point.
#[derive(Clone, Debug, Default, PartialEq)]
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
        let (pieces, count) = self.pieces(total, spacing);
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

impl IsoLine {
    /// The number of points [`IsoLine::resampled`] gives at `spacing`.
    pub fn resampled_count(&self, spacing: Real) -> usize {
        if self.points.len() < 2 {
            self.points.len()
        } else {
            self.pieces(self.length(), spacing).1
        }
    }

    /// The pieces and points of the line, `total` long, resampled at `spacing` (at least 3
    /// pieces for a closed line, 1 for an open one).
    fn pieces(&self, total: Real, spacing: Real) -> (usize, usize) {
        let pieces = ((total / spacing).round() as usize).max(if self.closed { 3 } else { 1 });
        (pieces, if self.closed { pieces } else { pieces + 1 })
    }
}

/// Ends of lines closer than this (in mean edge lengths) meet ([`joined_at_ends`] and the
/// plane source's pieces).
pub(crate) const JOIN_TOLERANCE: Real = 1e-4;

/// Points (the ends of lines), hashed in cubes of the tolerance, so that those near a point
/// are found in O(1): each point under an id of the caller's.
pub(crate) struct Ends {
    cells: FxHashMap<[i64; 3], Vec<(u32, Point3)>>,
    tolerance: Real,
}

impl Ends {
    pub(crate) fn new(ends: impl Iterator<Item = (u32, Point3)>, tolerance: Real) -> Ends {
        let mut index = Ends {
            cells: FxHashMap::default(),
            tolerance,
        };
        for (id, p) in ends {
            index.cells.entry(index.cell(&p)).or_default().push((id, p));
        }
        index
    }

    /// Cube of a point; a float out of range saturates (a cube far away, still one).
    fn cell(&self, p: &Point3) -> [i64; 3] {
        p.coords
            .map(|c| libm::floor(c / self.tolerance) as i64)
            .into()
    }

    /// The ids of the points within the tolerance of `p`, in a fixed order (cube by cube,
    /// each in the order given).
    pub(crate) fn near(&self, p: &Point3) -> impl Iterator<Item = u32> + '_ {
        let c = self.cell(p);
        let p = *p;
        (0..27)
            .filter_map(move |k| {
                let d = [k / 9 - 1, k / 3 % 3 - 1, k % 3 - 1];
                self.cells.get(&[
                    c[0].saturating_add(d[0]),
                    c[1].saturating_add(d[1]),
                    c[2].saturating_add(d[2]),
                ])
            })
            .flatten()
            .filter(move |(_, q)| (q - p).norm() <= self.tolerance)
            .map(|&(id, _)| id)
    }
}

/// The lines of one level with the open ones joined end to end: a line closes when its ends
/// meet. The walk along a level stops at an edge with no single face across (an edge of
/// three faces: a sliver or a fin glued along it), so one pass round a fuselage can come in
/// pieces whose ends meet (ends within `tolerance` meet); joined, it is one pass, not
/// pieces with the process switched off and on between them. A line closes rather than
/// goes on when its ends meet; where more ends meet, it goes on along the line that turns
/// least; lines of no length (a sliver's) are dropped once they have served as joints.
/// Points within `tolerance` of the one before are dropped where lines join. O(lines +
/// points).
pub(crate) fn joined_at_ends(mut lines: Vec<IsoLine>, tolerance: Real) -> Vec<IsoLine> {
    let open = |l: &IsoLine| !l.closed && !l.points.is_empty();
    if !lines.iter().any(open) {
        return lines;
    }
    // End 2i is the first point of line i, end 2i + 1 its last.
    let ends = Ends::new(
        lines
            .iter()
            .enumerate()
            .filter(|(_, l)| open(l))
            .flat_map(|(i, l)| {
                let (first, last) = (l.points[0], l.points[l.points.len() - 1]);
                [(2 * i as u32, first), (2 * i as u32 + 1, last)]
            }),
        tolerance,
    );
    // The unit direction of a line leaving end `id` (zero for a line of no length).
    let leaving = |lines: &[IsoLine], id: u32| -> Vector3 {
        let points = &lines[id as usize / 2].points;
        let n = points.len();
        let at = |k: usize| {
            if id % 2 == 0 {
                points[k]
            } else {
                points[n - 1 - k]
            }
        };
        (1..n)
            .map(at)
            .find(|p| (p - at(0)).norm() > tolerance)
            .map_or(Vector3::zeros(), |p| (p - at(0)).normalize())
    };
    let closes = |l: &IsoLine| {
        let n = l.points.len();
        n >= 3 && (l.points[0] - l.points[n - 1]).norm() <= tolerance
    };
    let mut used: Vec<bool> = lines.iter().map(|l| !open(l)).collect();
    let mut out = Vec::with_capacity(lines.len());
    for i in 0..lines.len() {
        if used[i] {
            if !lines[i].points.is_empty() && !open(&lines[i]) {
                out.push(std::mem::take(&mut lines[i]));
            }
            continue;
        }
        used[i] = true;
        let mut line = std::mem::take(&mut lines[i]);
        // Forwards from the last point, then (reversed) from the first; each step uses a line
        // not used before, so the loops end.
        let mut reversed = false;
        for _ in 0..2 {
            while !closes(&line) {
                let n = line.points.len();
                let tail = line.points[n - 1];
                let arriving = if n >= 2 {
                    (tail - line.points[n - 2])
                        .try_normalize(0.0)
                        .unwrap_or_default()
                } else {
                    Vector3::zeros()
                };
                let mut best: Option<(Real, u32)> = None;
                for id in ends.near(&tail).filter(|&id| !used[id as usize / 2]) {
                    let straight = arriving.dot(&leaving(&lines, id));
                    if best.is_none_or(|(b, _)| straight > b) {
                        best = Some((straight, id));
                    }
                }
                let Some((_, id)) = best else { break };
                let j = id as usize / 2;
                used[j] = true;
                let mut next = std::mem::take(&mut lines[j]);
                if id % 2 == 1 {
                    next.points.reverse();
                    next.normals.reverse();
                }
                for (p, n) in next.points.into_iter().zip(next.normals) {
                    if (p - line.points[line.points.len() - 1]).norm() > tolerance {
                        line.points.push(p);
                        line.normals.push(n);
                    }
                }
            }
            if closes(&line) {
                break;
            }
            line.points.reverse();
            line.normals.reverse();
            reversed = !reversed;
        }
        if reversed {
            line.points.reverse();
            line.normals.reverse();
        }
        if closes(&line) {
            line.points.pop();
            line.normals.pop();
            line.closed = true;
        } else if line.length() <= tolerance {
            continue;
        }
        out.push(line);
    }
    out
}

/// Items listed under the levels `k = 1..=levels` each may belong to (a face under the
/// levels its values span, a voxel under those within half its edge), built in one pass, so
/// that the levels of a distance field are found in time linear in the items and the
/// entries, not the items times the levels.
pub(crate) struct LevelLists {
    /// Level `k`'s items are `items[start[k - 1]..start[k]]`.
    start: Vec<usize>,
    items: Vec<u32>,
}

impl LevelLists {
    /// Lists each of `ids` under the levels `range(id)` (first and last, clamped to
    /// `1..=levels`; empty when the first is past the last), or `Err(entries)` when that
    /// would make more than `max_entries` entries (counted before anything is stored).
    pub(crate) fn new(
        ids: impl Iterator<Item = u32> + Clone,
        levels: u32,
        max_entries: u64,
        range: impl Fn(u32) -> (Real, Real),
    ) -> Result<Self, u64> {
        let clamped = |id: u32| -> (u32, u32) {
            let (first, last) = range(id);
            let (first, last) = (first.max(1.0), last.min(levels as Real));
            // NaN fails the comparison: listed under none.
            if first <= last {
                (first as u32, last as u32)
            } else {
                (1, 0)
            }
        };
        // A difference array of the levels each item spans: +1 at its first, −1 after its
        // last; its prefix sums are the items per level.
        let mut count = vec![0i64; levels as usize + 1];
        let mut entries: u64 = 0;
        for id in ids.clone() {
            let (a, b) = clamped(id);
            if a <= b {
                entries += u64::from(b - a + 1);
                count[a as usize - 1] += 1;
                count[b as usize] -= 1;
            }
        }
        if entries > max_entries {
            return Err(entries);
        }
        let mut start = Vec::with_capacity(levels as usize + 1);
        start.push(0);
        let mut spanning = 0i64;
        for k in 0..levels as usize {
            spanning += count[k];
            start.push(start[k] + spanning as usize);
        }
        let mut next = start.clone();
        let mut items = vec![0u32; start[levels as usize]];
        for id in ids {
            let (a, b) = clamped(id);
            for k in a..=b {
                let at = &mut next[k as usize - 1];
                items[*at] = id;
                *at += 1;
            }
        }
        Ok(LevelLists { start, items })
    }

    /// The active faces each level `k · spacing` may cross: a face is listed under every
    /// level between its smallest and largest value (and one more at each end: a margin for
    /// rounding and for [`LEVEL_TOLERANCE`]); faces with an unreached corner under none.
    pub(crate) fn of_faces(
        surface: &Surface,
        values: &[Real],
        spacing: Real,
        levels: u32,
        max_entries: u64,
    ) -> Result<Self, u64> {
        let tris = surface.mesh.triangles();
        LevelLists::new(surface.faces.iter().copied(), levels, max_entries, |f| {
            let v = tris[f as usize].map(|i| values[i as usize]);
            if !v.iter().all(|x| x.is_finite()) {
                return (1.0, 0.0);
            }
            let lo = v[0].min(v[1]).min(v[2]) / spacing;
            let hi = v[0].max(v[1]).max(v[2]) / spacing;
            (lo.floor(), hi.floor() + 1.0)
        })
    }

    /// The items of level `k` (`1 ≤ k ≤ levels`), in the order of the ids given.
    pub(crate) fn of(&self, k: u32) -> &[u32] {
        &self.items[self.start[k as usize - 1]..self.start[k as usize]]
    }
}

/// The level set `values = level` as polylines (level index 0), looked for from the faces
/// `starts` only (every face it crosses must be among them); `visited` holds a `false` per
/// mesh face, and is left so.
pub(crate) fn contour_from(
    surface: &Surface,
    values: &[Real],
    level: Real,
    starts: &[u32],
    visited: &mut [bool],
) -> Vec<IsoLine> {
    contour_with_faces_from(surface, values, level, starts, visited)
        .into_iter()
        .map(|(line, _)| line)
        .collect()
}

/// The level set `values = level` on the active faces as polylines (level index 0), with the
/// face each segment of a line lies in: segment `j` joins point `j` to point `j + 1` (of a
/// closed line, the last joins the last point to the first).
pub(crate) fn contour_with_faces(
    surface: &Surface,
    values: &[Real],
    level: Real,
) -> Vec<(IsoLine, Vec<u32>)> {
    let mut visited = vec![false; surface.mesh.triangle_count()];
    contour_with_faces_from(surface, values, level, &surface.faces, &mut visited)
}

/// [`contour_with_faces`] from the faces `starts` (see [`contour_from`]).
fn contour_with_faces_from(
    surface: &Surface,
    values: &[Real],
    level: Real,
    starts: &[u32],
    visited: &mut [bool],
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
    // The faces marked, to clear `visited` for the next level.
    let mut marked: Vec<u32> = Vec::new();
    let mut lines = Vec::new();
    for &f0 in starts {
        let f0 = f0 as usize;
        if visited[f0] {
            continue;
        }
        let Some(slots0) = crossing(f0) else { continue };
        visited[f0] = true;
        marked.push(f0 as u32);
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
                marked.push(g as u32);
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
        // A walk that met only faces of no area (a sliver's, its lone corner's value got
        // through them alone) runs along an edge, not across the surface: no line.
        let on_surface = chain.iter().any(|c| {
            let t = mesh.triangles()[c.2 as usize];
            !is_degenerate(t.map(|v| mesh.positions()[v as usize]))
        });
        if chain.len() >= 2 && on_surface {
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
    for f in marked {
        visited[f as usize] = false;
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{FaceAdjacency, TriMesh};

    /// A wavy square of 30 × 30 quads cut into triangles, with a value per vertex that
    /// swings over it (saddles, rings and levels through vertices), and one vertex unreached.
    fn wavy() -> (TriMesh, Vec<Real>) {
        let n = 30usize;
        let mut positions = Vec::new();
        let mut values = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as Real, j as Real);
                positions.push(Point3::new(x, y, 0.3 * libm::sin(0.4 * x + 0.2 * y)));
                values.push(4.0 + 3.0 * libm::sin(0.3 * x) * libm::cos(0.25 * y) + 0.1 * x);
            }
        }
        // Some values exactly at a level (a multiple of the spacing below).
        for v in (0..values.len()).step_by(7) {
            values[v] = (values[v] * 4.0).round() / 4.0;
        }
        // And some a hair below one, within the tolerance that counts them on it.
        for v in (3..values.len()).step_by(11) {
            values[v] = (values[v] * 4.0).round() / 4.0 * (1.0 - 1e-12);
        }
        values[5 * (n + 1) + 5] = Real::INFINITY;
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                triangles.extend([[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
            }
        }
        (TriMesh::new(positions, triangles).unwrap(), values)
    }

    #[test]
    fn the_levels_found_from_their_listed_faces_are_those_of_a_scan_of_every_face() {
        let (mesh, values) = wavy();
        let adjacency = FaceAdjacency::new(&mesh);
        let surface = Surface::new(&mesh, &adjacency, None).unwrap();
        let spacing = 0.25;
        let levels = 40;
        let by_level = LevelLists::of_faces(&surface, &values, spacing, levels, u64::MAX).unwrap();
        let mut visited = vec![false; mesh.triangle_count()];
        let mut lines = 0;
        for k in 1..=levels {
            let d = k as Real * spacing;
            let all = contour_with_faces(&surface, &values, d);
            let listed = contour_from(&surface, &values, d, by_level.of(k), &mut visited);
            assert!(visited.iter().all(|&v| !v), "level {k} left faces marked");
            assert_eq!(listed.len(), all.len(), "level {k}");
            for (a, (b, _)) in listed.iter().zip(&all) {
                assert_eq!(a.points, b.points, "level {k}");
                assert_eq!(a.closed, b.closed, "level {k}");
            }
            lines += all.len();
        }
        assert!(lines > 40, "{lines} lines");
        // Over its budget, the listing is refused with the number of entries it would hold.
        let entries = by_level.items.len() as u64;
        assert!(matches!(
            LevelLists::of_faces(&surface, &values, spacing, levels, entries - 1),
            Err(e) if e == entries
        ));
    }

    /// An open line through `points` (level 1, normals +z).
    fn open_line(points: &[[Real; 3]]) -> IsoLine {
        IsoLine {
            level: 1,
            distance: 1.0,
            closed: false,
            points: points
                .iter()
                .map(|&[x, y, z]| Point3::new(x, y, z))
                .collect(),
            normals: vec![Vector3::z(); points.len()],
        }
    }

    #[test]
    fn pieces_whose_ends_meet_are_joined_and_closed_turning_least() {
        // A square in four pieces, two of them the wrong way round, one end a hair off; a
        // fin leaves the square's corner (1, 0) turning back by 135°, and a piece of no length
        // (a sliver's) lies at the corner (1, 1).
        let hair = 1e-9;
        let lines = vec![
            open_line(&[[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0]]),
            open_line(&[[1.0, 0.0, 0.0], [0.5, 0.0, 0.5]]), // the fin, turning back
            open_line(&[[1.0, 1.0, 0.0], [1.0, hair, 0.0]]),
            open_line(&[[1.0, 1.0, 0.0], [1.0, 1.0, 0.0]]),
            open_line(&[[0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]),
            open_line(&[[0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]),
        ];
        let out = joined_at_ends(lines, 1e-6);
        assert_eq!(out.len(), 2, "{out:?}");
        let square = &out[0];
        assert!(square.closed);
        let corners: Vec<[Real; 2]> = square.points.iter().map(|p| [p.x, p.y]).collect();
        assert_eq!(
            corners,
            [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            "the first piece's way round, each corner once"
        );
        assert_eq!(square.normals.len(), square.points.len());
        assert!(!out[1].closed && out[1].points[1] == Point3::new(0.5, 0.0, 0.5));
        // Lines whose ends do not meet are left as they are.
        let apart = vec![
            open_line(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]),
            open_line(&[[1.1, 0.0, 0.0], [2.0, 0.0, 0.0]]),
        ];
        assert_eq!(joined_at_ends(apart.clone(), 1e-6), apart);
    }
}
