//! Scan planes across a patch and their chaining into passes.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), steps 1–2: parallel planes spaced `b` cut the
//! triangles; a triangle crossed by a plane gives one scan segment between its two edge
//! crossings.
//! Input:  mesh, face adjacency and geometry; the selected faces; pass direction; spacing.
//! Output: per plane, the passes (polylines of edge crossings with the face of each segment),
//!         oriented along the pass direction and ordered along it.
//! Cost:   O(F + S log S) per set of planes for F selected faces and S scan segments: a face
//!         is bucketed to the planes its extent spans (a table of 2¹⁶ bins over the patch,
//!         built with the frame, clears the faces no plane crosses; the others are binary
//!         searched), and segments of one plane are chained through the face adjacency (no
//!         search).
//! Deviations (no paper for these): the default pass direction is the principal axis of
//!         the patch in its mean plane (area-weighted vertex covariance); `b` is measured
//!         along the surface across the passes, not in space: a table of the surface
//!         distance against the plane offset (per bin of [`ARC_BINS`], the mean stretch
//!         `1/√(1 − (n·across)²)` of the faces spanning it, at most [`MAX_STRETCH`]) places
//!         the planes, so where the patch is inclined by φ to its mean plane across the
//!         passes they are `b·cos φ` apart in space and about `b` apart on the surface (the
//!         patent spaces them `b` in space, which leaves passes `b/cos φ` apart on steep
//!         parts); the stretch is averaged along each offset, so a patch steep in one place
//!         and flat in another at the same offset gets the mean; the planes are centred on
//!         the patch so the outermost ones lie at most `b/2` (along the surface) inside its
//!         extremes;
//!         a vertex exactly on a plane counts as above it, so neighbours agree on every
//!         crossing; zero-length segments (a plane through a vertex) are dropped; a plane
//!         meeting holes or a concave outline gives several passes, but one that starts
//!         within a gap too small to spray ([`JOIN_GAP_RATIO`]`·h`) of the end of the one
//!         before goes on with it (the chain stops at an edge of three faces, at a face of
//!         no area, and where a plane grazes a corner of the outline: on the Orion model's
//!         largest patch, at a spacing of 0.09, 40 of 280 passes ended 5·10⁻⁵ to 6·10⁻⁴
//!         from the next one's start, and their extensions doubled the coating there).

use super::params::{SprayError, MAX_PLANES};
use crate::math::{any_perpendicular, Point3, Real, Vector3};
use crate::mesh::{FaceAdjacency, FaceGeometry, TriMesh, NO_FACE};

/// Mean normals shorter than this fraction of the total area (a closed surface) fall back to
/// the normal of the largest face.
const MEAN_NORMAL_MIN_RATIO: Real = 1e-6;
/// A given direction within this sine of the mean normal gives no pass direction.
const DIRECTION_PARALLEL_SINE: Real = 1e-6;
/// Segments shorter than this fraction of the patch size are dropped (a plane through a vertex).
const SEGMENT_MIN_RATIO: Real = 1e-12;

/// Relative slack on `width / spacing` before rounding up the plane count, so rounding noise
/// in the frame does not add a plane (the outermost margin may then exceed `b/2` by this much).
const PLANE_COUNT_TOLERANCE: Real = 1e-6;
/// Pieces of one scan plane whose ends are closer than this fraction of the standoff are one
/// pass (the spray cannot tell such a gap from none; ended there, each piece would be
/// extended over the other).
pub const JOIN_GAP_RATIO: Real = 0.01;
/// Bins of the arc-length table across the passes.
pub const ARC_BINS: usize = 1024;
/// Largest stretch (surface distance over distance across the planes) a face counts with:
/// a face almost parallel to the scan planes would otherwise count as infinitely long.
pub const MAX_STRETCH: Real = 4.0;

const NONE: u32 = u32::MAX;

/// The selected faces with their mean plane and the raster frame.
#[derive(Debug, Clone)]
pub struct PatchFrame {
    /// Selected, non-degenerate faces in increasing order.
    pub faces: Vec<u32>,
    /// Per mesh face: whether it is selected and non-degenerate.
    pub selected: Vec<bool>,
    /// Unit mean normal (area-weighted).
    pub normal: Vector3,
    /// Unit pass direction, ⟂ `normal`.
    pub travel: Vector3,
    /// Unit direction across the passes: `normal × travel`.
    pub across: Vector3,
    /// Smallest and largest `across·x` over the patch's vertices.
    pub extent: (Real, Real),
    /// Per face of `faces`: smallest and largest `across·x` over its corners.
    pub spans: Vec<(Real, Real)>,
    /// The bins of each span's ends among 2¹⁶ over `extent` (a non-decreasing function of
    /// the offset), for a quick test of which faces a set of planes may cross.
    pub span_bins: Vec<(u32, u32)>,
    /// Size of the patch (bounding-box diagonal), for relative tolerances.
    pub size: Real,
    /// Total area.
    pub area: Real,
    /// Surface distance across the passes from `extent.0` at [`ARC_BINS`]` + 1` evenly
    /// spaced offsets from `extent.0` to `extent.1`.
    pub arc: Vec<Real>,
}

/// One pass: crossing points in travel order and the face of each segment between them.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanPass {
    /// Index of the scan plane.
    pub plane: usize,
    /// `faces.len() + 1` points on triangle edges.
    pub points: Vec<Point3>,
    /// The face of segment `i` (from `points[i]` to `points[i + 1]`).
    pub faces: Vec<u32>,
}

/// Checks the face list and computes the patch frame. `direction` (if any) is projected on
/// the mean plane; the result is turned by `raster_angle` about the mean normal.
pub fn patch_frame(
    mesh: &TriMesh,
    geometry: &FaceGeometry,
    faces: &[u32],
    direction: Option<Vector3>,
    raster_angle: Real,
) -> Result<PatchFrame, SprayError> {
    if faces.is_empty() {
        return Err(SprayError::NoFaces);
    }
    let count = mesh.triangle_count();
    let mut selected = vec![false; count];
    for &f in faces {
        if f as usize >= count {
            return Err(SprayError::UnknownFace { face: f, count });
        }
        selected[f as usize] = !geometry.is_degenerate(f as usize);
    }
    let list: Vec<u32> = (0..count as u32)
        .filter(|&f| selected[f as usize])
        .collect();
    if list.is_empty() {
        return Err(SprayError::NoArea);
    }
    let (normals, areas) = (geometry.normals(), geometry.areas());
    let mut sum = Vector3::zeros();
    let mut area = 0.0;
    let mut centroid = Vector3::zeros();
    let mut largest = list[0] as usize;
    for &f in &list {
        let f = f as usize;
        sum += normals[f] * areas[f];
        area += areas[f];
        centroid += geometry.centroids()[f].coords * areas[f];
        if areas[f] > areas[largest] {
            largest = f;
        }
    }
    if area <= 0.0 {
        return Err(SprayError::NoArea);
    }
    centroid /= area;
    let normal = if sum.norm() > MEAN_NORMAL_MIN_RATIO * area {
        sum.normalize()
    } else {
        normals[largest]
    };
    // An orthonormal basis (e1, e2) of the mean plane.
    let e1 = any_perpendicular(&normal);
    let e2 = normal.cross(&e1);
    let mut travel = match direction {
        Some(d) => {
            let along = d - normal * normal.dot(&d);
            if along.norm() <= DIRECTION_PARALLEL_SINE * d.norm() {
                return Err(SprayError::DirectionAlongNormal {
                    normal: normal.into(),
                });
            }
            along.normalize()
        }
        None => {
            // Principal axis: second moment of area in the mean plane, exact per triangle:
            // ∫ r rᵀ dA = A/12 · (a aᵀ + b bᵀ + c cᵀ + s sᵀ), s = a + b + c.
            let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
            for &f in &list {
                let w = areas[f as usize] / 12.0;
                let xy = mesh.corners(f as usize).map(|c| {
                    let r = c.coords - centroid;
                    (r.dot(&e1), r.dot(&e2))
                });
                let s = (xy[0].0 + xy[1].0 + xy[2].0, xy[0].1 + xy[1].1 + xy[2].1);
                for (x, y) in xy.into_iter().chain([s]) {
                    sxx += w * x * x;
                    sxy += w * x * y;
                    syy += w * y * y;
                }
            }
            let phi = 0.5 * libm::atan2(2.0 * sxy, sxx - syy);
            e1 * libm::cos(phi) + e2 * libm::sin(phi)
        }
    };
    travel = travel * libm::cos(raster_angle) + normal.cross(&travel) * libm::sin(raster_angle);
    travel = (travel - normal * normal.dot(&travel)).normalize();
    let across = normal.cross(&travel);
    // By comparisons: `f64::min`/`max` (and nalgebra's `inf`/`sup`) also handle NaN, which
    // makes them calls in WebAssembly; every value here is finite on a validated mesh.
    let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
    let (mut bmin, mut bmax) = (
        Vector3::repeat(Real::INFINITY),
        Vector3::repeat(-Real::INFINITY),
    );
    let mut spans = Vec::with_capacity(list.len());
    for &f in &list {
        let (mut face_lo, mut face_hi) = (Real::INFINITY, Real::NEG_INFINITY);
        for c in mesh.corners(f as usize) {
            let s = across.dot(&c.coords);
            if s < face_lo {
                face_lo = s;
            }
            if s > face_hi {
                face_hi = s;
            }
            for a in 0..3 {
                if c[a] < bmin[a] {
                    bmin[a] = c[a];
                }
                if c[a] > bmax[a] {
                    bmax[a] = c[a];
                }
            }
        }
        lo = if face_lo < lo { face_lo } else { lo };
        hi = if face_hi > hi { face_hi } else { hi };
        spans.push((face_lo, face_hi));
    }
    let arc = arc_table(geometry, &list, &spans, &across, (lo, hi));
    let scale = span_bin_scale((lo, hi));
    let span_bins = spans
        .iter()
        .map(|&(a, b)| (span_bin(a, lo, scale), span_bin(b, lo, scale)))
        .collect();
    Ok(PatchFrame {
        span_bins,
        arc,
        faces: list,
        selected,
        normal,
        travel,
        across,
        extent: (lo, hi),
        spans,
        size: (bmax - bmin).norm(),
        area,
    })
}

/// Surface distance across the passes as a function of the offset `across·x`: per bin,
/// the mean stretch `1/√(1 − (n·across)²)` (the distance along the surface, perpendicular
/// to the pass, per unit offset) over the faces spanning it, each face spread evenly over
/// its offset range with weight `area / stretch` (its extent in offset × travel); bins no
/// face covers count 1. O(F + bins).
fn arc_table(
    geometry: &FaceGeometry,
    faces: &[u32],
    spans: &[(Real, Real)],
    across: &Vector3,
    (lo, hi): (Real, Real),
) -> Vec<Real> {
    let width = hi - lo;
    let mut weight = vec![0.0; ARC_BINS + 1];
    let mut stretched = vec![0.0; ARC_BINS + 1];
    if width > 0.0 {
        // (A float cast saturates: below `lo` is bin 0. Comparisons, not `f64::max`/`min`,
        // which are calls in WebAssembly; the values are finite.)
        let bin_of =
            |c: Real| (((c - lo) / width * ARC_BINS as Real).floor() as usize).min(ARC_BINS - 1);
        for (&f, &(face_lo, face_hi)) in faces.iter().zip(spans) {
            let f = f as usize;
            let m = geometry.normals()[f];
            let cosine = m.dot(across);
            // (NaN when rounding takes |cosine| past 1: the comparison then fails too, and
            // the face gets the largest stretch, as a sine of 0 does.)
            let sine = (1.0 - cosine * cosine).sqrt();
            let stretch = if sine * MAX_STRETCH > 1.0 {
                1.0 / sine
            } else {
                MAX_STRETCH
            };
            let (b0, b1) = (bin_of(face_lo), bin_of(face_hi));
            // Difference arrays: the face adds evenly to bins b0..=b1.
            let w = geometry.areas()[f] / stretch / (b1 - b0 + 1) as Real;
            weight[b0] += w;
            weight[b1 + 1] -= w;
            stretched[b0] += w * stretch;
            stretched[b1 + 1] -= w * stretch;
        }
    }
    let step = width / ARC_BINS as Real;
    let mut arc = Vec::with_capacity(ARC_BINS + 1);
    arc.push(0.0);
    let (mut w, mut ws) = (0.0, 0.0);
    for k in 0..ARC_BINS {
        w += weight[k];
        ws += stretched[k];
        let stretch = if w > 0.0 {
            (ws / w).clamp(1.0, MAX_STRETCH)
        } else {
            1.0
        };
        arc.push(arc[k] + step * stretch);
    }
    arc
}

/// Bins of `across·x` over the patch for [`scan_passes`]' quick test.
const SPAN_BINS: usize = 1 << 16;

fn span_bin_scale((lo, hi): (Real, Real)) -> Real {
    if hi > lo {
        SPAN_BINS as Real / (hi - lo)
    } else {
        0.0
    }
}

/// Bin of offset `x`: non-decreasing in `x` (a float cast saturates: below `lo` is bin 0).
fn span_bin(x: Real, lo: Real, scale: Real) -> u32 {
    (((x - lo) * scale) as usize).min(SPAN_BINS - 1) as u32
}

impl PatchFrame {
    /// The bin of offset `x` among [`SPAN_BINS`] over the extent (the bins of the faces'
    /// spans are [`PatchFrame::span_bins`]).
    fn bin_of(&self, x: Real) -> u32 {
        span_bin(x, self.extent.0, span_bin_scale(self.extent))
    }

    /// Offset `across·x` at surface distance `s` from `extent.0` (inverse of [`Self::arc`]).
    fn offset_at(&self, s: Real) -> Real {
        let bins = self.arc.len() - 1;
        let step = self.width() / bins as Real;
        let k = self.arc[1..].partition_point(|&a| a < s).min(bins - 1);
        let span = self.arc[k + 1] - self.arc[k];
        let t = if span > 0.0 {
            ((s - self.arc[k]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.extent.0 + (k as Real + t) * step
    }

    /// Width of the patch across the passes.
    pub fn width(&self) -> Real {
        self.extent.1 - self.extent.0
    }

    /// Offsets `across·x = s_k` of the scan planes for `spacing`, measured along the
    /// surface across the passes (the arc-length table): `ceil(arc / b)` planes centred
    /// on the patch, so the outermost lie at most `b/2` (along the surface) inside the
    /// extremes. On a flat patch this is `ceil(width / b)` planes `b` apart.
    pub fn plane_offsets(&self, spacing: Real) -> Result<Vec<Real>, SprayError> {
        let width = self.arc[self.arc.len() - 1];
        if spacing > width * (1.0 + PLANE_COUNT_TOLERANCE) {
            return Err(SprayError::SpacingTooLarge { spacing, width });
        }
        let planes = (width / spacing * (1.0 - PLANE_COUNT_TOLERANCE))
            .ceil()
            .max(1.0);
        if planes > MAX_PLANES as Real {
            return Err(SprayError::TooManyPlanes {
                spacing,
                planes: planes as usize,
                width,
            });
        }
        let n = planes as usize;
        let margin = 0.5 * (width - (n - 1) as Real * spacing);
        Ok((0..n)
            .map(|k| self.offset_at(margin + k as Real * spacing))
            .collect())
    }
}

/// One scan segment of a plane: its face, the two crossed edge slots and crossing points.
struct Segment {
    face: u32,
    edges: [usize; 2],
    points: [Point3; 2],
}

/// Cuts the patch with the planes `across·x = s_k` and chains each plane's segments into
/// passes oriented along `frame.travel`, ordered along it within a plane; a pass that ends
/// within `join_gap` of the next one's start goes on into it.
pub fn scan_passes(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    frame: &PatchFrame,
    offsets: &[Real],
    join_gap: Real,
) -> Vec<ScanPass> {
    let n = offsets.len();
    if n == 0 {
        return Vec::new();
    }
    // Planes are sorted (not necessarily evenly spaced). A plane `s` crosses a face when a
    // corner lies below it and one not (`across·x < s` for some corner, not for all), i.e.
    // `lo < s ≤ hi` over the corners: the planes `k0..k1` by binary search, exactly the
    // faces the sign test below finds crossed (the test compares the same products).
    // A face crosses no plane when no plane falls in the bins its span covers (the bins are
    // a monotone function of the offset, see [`PatchFrame::bin_of`]); then both ends of its
    // range are the planes in bins before its first. Only the others are searched.
    let mut before = vec![0u32; SPAN_BINS + 1];
    for &o in offsets {
        before[frame.bin_of(o) as usize + 1] += 1;
    }
    for b in 0..SPAN_BINS {
        before[b + 1] += before[b];
    }
    let ranges: Vec<(usize, usize)> = frame
        .spans
        .iter()
        .zip(&frame.span_bins)
        .map(|(&(lo, hi), &(b0, b1))| {
            let below = before[b0 as usize];
            if before[b1 as usize + 1] == below {
                (below as usize, below as usize)
            } else {
                (
                    offsets.partition_point(|&o| o <= lo),
                    offsets.partition_point(|&o| o <= hi),
                )
            }
        })
        .collect();
    debug_assert!(frame.spans.iter().zip(&ranges).all(|(&(lo, hi), &r)| r
        == (
            offsets.partition_point(|&o| o <= lo),
            offsets.partition_point(|&o| o <= hi)
        )));
    // Bucket faces by plane (counting sort).
    let mut start = vec![0usize; n + 1];
    for &(k0, k1) in &ranges {
        for k in k0..k1 {
            start[k + 1] += 1;
        }
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut bucket = vec![0u32; start[n]];
    for (&f, &(k0, k1)) in frame.faces.iter().zip(&ranges) {
        for k in k0..k1 {
            bucket[fill[k]] = f;
            fill[k] += 1;
        }
    }
    let min_length = SEGMENT_MIN_RATIO * frame.size;
    let positions = mesh.positions();
    let mut slot = vec![NONE; mesh.triangle_count()];
    let mut passes = Vec::new();
    let mut segments: Vec<Segment> = Vec::new();
    for (k, &s) in offsets.iter().enumerate() {
        segments.clear();
        for &f in &bucket[start[k]..start[k + 1]] {
            let tri = mesh.triangles()[f as usize];
            let d = tri.map(|v| frame.across.dot(&positions[v as usize].coords) - s);
            let below = d.map(|x| x < 0.0);
            let mut edges = [0usize; 2];
            let mut points = [Point3::origin(); 2];
            let mut found = 0;
            for e in 0..3 {
                let e1 = (e + 1) % 3;
                if below[e] != below[e1] && found < 2 {
                    // Computed from the lower vertex id so both faces get the same point.
                    let (a, b) = if tri[e] < tri[e1] { (e, e1) } else { (e1, e) };
                    let t = d[a] / (d[a] - d[b]);
                    let (pa, pb) = (positions[tri[a] as usize], positions[tri[b] as usize]);
                    points[found] = pa + (pb - pa) * t;
                    edges[found] = e;
                    found += 1;
                }
            }
            // Zero-length segments (a plane through a vertex) are kept for the chaining,
            // which passes through them, and dropped from the passes below.
            if found == 2 {
                slot[f as usize] = segments.len() as u32;
                segments.push(Segment {
                    face: f,
                    edges,
                    points,
                });
            }
        }
        // The segment across end `j` of segment `i`, with the end it meets.
        let next = |i: usize, j: usize| -> Option<(usize, usize)> {
            let seg = &segments[i];
            let g = adjacency.neighbours(seg.face as usize)[seg.edges[j]];
            if g == NO_FACE || slot[g as usize] == NONE {
                return None;
            }
            let other = slot[g as usize] as usize;
            let back = adjacency.neighbours(g as usize);
            (0..2)
                .find(|&jj| back[segments[other].edges[jj]] == seg.face)
                .map(|jj| (other, jj))
        };
        let mut visited = vec![false; segments.len()];
        let mut pieces: Vec<ScanPass> = Vec::new();
        // Open chains first (start at an end with no neighbour), then closed loops.
        for round in 0..2 {
            for first in 0..segments.len() {
                if visited[first] {
                    continue;
                }
                let entry = if round == 0 {
                    match (0..2).find(|&j| next(first, j).is_none()) {
                        Some(j) => j,
                        None => continue,
                    }
                } else {
                    0
                };
                let (mut i, mut j) = (first, entry);
                let mut points = vec![segments[i].points[j]];
                let mut faces = Vec::new();
                // Each step visits a new segment, so the walk ends within segments.len() steps.
                loop {
                    visited[i] = true;
                    let out = 1 - j;
                    let p = segments[i].points[out];
                    if points.last().is_some_and(|q| (p - q).norm() > min_length) {
                        points.push(p);
                        faces.push(segments[i].face);
                    }
                    match next(i, out) {
                        Some((g, jj)) if !visited[g] => (i, j) = (g, jj),
                        _ => break,
                    }
                }
                if let (Some(a), Some(b)) = (points.first(), points.last()) {
                    if (b - a).dot(&frame.travel) < 0.0 {
                        points.reverse();
                        faces.reverse();
                    }
                }
                if faces.is_empty() {
                    continue;
                }
                pieces.push(ScanPass {
                    plane: k,
                    points,
                    faces,
                });
            }
        }
        for seg in &segments {
            slot[seg.face as usize] = NONE;
        }
        pieces.sort_by(|a, b| {
            let key = |p: &ScanPass| frame.travel.dot(&p.points[0].coords);
            key(a).total_cmp(&key(b))
        });
        // A piece that starts where the one before it ends (within `join_gap`) goes on with
        // it: the chain stops at an edge of three faces, at a face of no area (left out of
        // the patch) and where the plane grazes a corner of the outline; ended there, the
        // pass would get its extensions (gun on) over the next piece's, a thick spot.
        // A point within `min_length` of the joined pass's end is left out with its segment
        // (as the chaining leaves them out): faces glued on twice, or pieces that meet end to
        // end, would otherwise give a segment of no length, which has no direction.
        for piece in pieces {
            if let Some(last) = passes.last_mut().filter(|p: &&mut ScanPass| p.plane == k) {
                if (piece.points[0] - last.points[last.points.len() - 1]).norm() <= join_gap {
                    for (p, &f) in piece.points[1..].iter().zip(&piece.faces) {
                        if (p - last.points[last.points.len() - 1]).norm() > min_length {
                            last.points.push(*p);
                            last.faces.push(f);
                        }
                    }
                    continue;
                }
            }
            passes.push(piece);
        }
    }
    passes
}

/// Zig-zag order: passes of every other non-empty plane run backwards, in reverse order.
pub fn order_zigzag(passes: Vec<ScanPass>) -> Vec<ScanPass> {
    let mut out = Vec::with_capacity(passes.len());
    let mut i = 0;
    let mut row = 0usize;
    while i < passes.len() {
        let plane = passes[i].plane;
        let mut j = i;
        while j < passes.len() && passes[j].plane == plane {
            j += 1;
        }
        let group = &passes[i..j];
        if row % 2 == 0 {
            out.extend(group.iter().cloned());
        } else {
            out.extend(group.iter().rev().map(|p| {
                let mut p = p.clone();
                p.points.reverse();
                p.faces.reverse();
                p
            }));
        }
        row += 1;
        i = j;
    }
    out
}
