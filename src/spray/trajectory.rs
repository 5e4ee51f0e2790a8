//! The gun trajectory: offset pass segments, transitions, concave loop removal, extensions and
//! links.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), steps 3–5 (claim 1): each triangle's scan
//! points move by the standoff `h` along its normal `n`, gun axis `−n`; between adjacent
//! triangles whose normals make an angle `β`, a straight transition if `β ≤ β_T` (gun axis
//! perpendicular to it, towards the part), else a convex arc of radius `h` around the edge
//! (gun axis radial); passes are linked in zig-zag order. Concave edges: invalid-loop removal
//! of a raw offset curve as in Choi & Park, "A pair-wise offset algorithm for 2D point-sequence
//! curve" (Computer-Aided Design 31, 1999), with a uniform grid in place of their sweep.
//! Input:  passes from [`scan_passes`](super::raster::scan_passes), face normals, `h`, `β_T`.
//! Output: a [`ToolPath`]. A pose's kind is the kind of the move that arrives at it (the
//!         first pose of each pass is reached by a gun-off link). No two consecutive poses
//!         share a position (within [`SAME_POSITION_RATIO`]`·h`): the gun never turns on the
//!         spot with the process on, which a controller would run as a dwell.
//! Cost:   per pass of `n` scan segments, O(n) to build the raw offset curve and
//!         O(n + c) for the loop removal, where `c` counts the kept offset edges met in the
//!         grid cells (one cell ≈ one mean offset edge) around each new edge: bounded per cell
//!         wherever the kept offset is a simple curve of bounded density, i.e. everywhere but
//!         where the surface's radius of curvature across the passes is within a cell of `h`
//!         (there the offsets of many segments pile up near the centre of curvature).
//! Deviations:
//!   - The patent treats convex edges only. In each scan plane the raw offset curve (the
//!     offset segments, the convex transitions, a concave edge joined straight from one
//!     offset to the next, and round caps of radius `h` around both pass ends) is cut where it
//!     crosses itself and the loop in between is dropped (no paper for the caps: they make the
//!     offset of an open pass a one-sided offset, so a pass ending in a concave corner, or a
//!     concave surface tighter than `h`, still turns at a crossing). So the pass turns where
//!     the offsets of the two sides cross, never behind them, with the bisector of the two
//!     axes there. Crossings are found in the projection on the pass's plane; a crossing's
//!     position is the midpoint of the two branches' points (they coincide when the normals
//!     lie in the scan plane). Only the pass's own scan polyline is kept clear: where the
//!     normals leave the scan plane, faces of neighbouring planes may come nearer than `h`.
//!     Passes without a concave edge skip the removal (their offset only turns away).
//!   - A concave edge whose offsets meet within both faces is resolved before the loop
//!     removal, in space (no paper): each offset line reaches the other face's offset plane
//!     (`h` from both faces) at `x1 = a + s·t_i` and `x2 = b + u·t_j`,
//!     `s = h(1 − cos β)/(n_j·t_i)`, `u = h(1 − cos β)/(n_i·t_j)`, two points of the line
//!     where the offset planes meet; the pass turns at their midpoint, at `h` from both
//!     faces, reached and left within the two offset planes. (Where the normals leave the
//!     scan plane, the two offsets lie at different distances from the pass in the
//!     projection and need not cross within the faces, so the plain join `a → b` stepped
//!     back by `2h·sin(β/2)`: about 120 times on the BWB's upper skin.) Only where `x1` and
//!     `x2` are no farther apart than `a` and `b`: they part by about `2h·tan(β/2)·cot ψ`
//!     for a pass crossing the edge at `ψ`, and a pass nearly along a concave edge would
//!     swerve towards it.
//!   - An uncut cap is replaced by the pass extension (gun on, `extension` along the end
//!     segment); a cap cut by a crossing stays (gun on, radial axis, poses of kind `Arc`):
//!     the pass then ends by turning around its end point at the standoff. A cap may be cut
//!     only where the end's normal lies within [`CAP_PLANE_SINE`] of the scan plane (the cap
//!     turns in the plane of that normal and the end direction) and the branches meet in
//!     space (within [`CAP_GAP_RATIO`]`·h`). Where the whole
//!     offset collapses (a concave surface of radius below `h`) the pass is the two caps up
//!     to their crossing, at distance `h` from both pass ends.
//!   - Normals within [`SMALL_TURN_RAD`] (rounding of `f32` coordinates) get no transition.
//!   - A straight transition runs from the first segment's offset end (axis `−n_i`) through
//!     its midpoint (axis `−(n_i + n_j)`, perpendicular to it as in the patent) to the next
//!     segment's offset start (axis `−n_j`): the reorientation is spread over the
//!     transition instead of done on the spot. Arcs are polylines of at most
//!     [`ARC_STEP_RAD`] per step. Coplanar, collinear segments are merged. Links are straight
//!     moves at the standoff (gun off).
//!   - Gun off over long convex turns (no paper): while the gun turns over a convex edge by
//!     `β` (a straight transition or an arc) its axis stays on the edge, so the edge gets the
//!     spray of a spot that stands still for the turn's travel `τ` (`2h·sin(β/2)`, or about
//!     `h·β` for an arc): at constant speed, summed over parallel passes, about
//!     `8h·sin β / (3πR) ≈ 0.85·τ/R` of the mean coating on the fold line (+113 % for a 29°
//!     arc at h 250 mm, α 40°), more than the speed limits can take back. A turn longer than
//!     `max_turn_on` (the planner passes [`TURN_ON_RADIUS_RATIO`]`·R`) keeps its poses and
//!     runs with the gun off (kind `Link`): the spray then leaves one face at the edge and
//!     resumes on the other at the edge, as over a flat part. Shorter turns (a finely
//!     faceted curve) stay on; the speed optimisation takes back their smaller excess.

use super::raster::ScanPass;
use crate::math::{angle_between, any_perpendicular, Point3, Real, Vector3};
use crate::toolpath::{Pose, PoseKind, ToolPath};
use rustc_hash::FxHashMap;

/// A convex turn whose gun travel exceeds this multiple of the footprint radius `R` runs with
/// the gun off (see the file header): a shorter one adds at most about 8.5 % on its edge.
pub const TURN_ON_RADIUS_RATIO: Real = 0.1;
/// Largest turn of the gun axis between two poses of an arc, radians (5°).
pub const ARC_STEP_RAD: Real = 0.087_266_462_599_716_48;
/// A crossing cuts a cap only where the two branches are closer in space than this multiple
/// of the standoff.
const CAP_GAP_RATIO: Real = 0.05;
/// A cap may be cut only when the end's normal is within this sine of the scan plane.
const CAP_PLANE_SINE: Real = 0.25;
/// Relative slack on the number of arc steps (see [`arc_steps`]).
const ARC_STEP_SLACK: Real = 1e-6;
/// A gun-on backtrack (a turn beyond 150°) with a leg shorter than this multiple of the
/// standoff loses the pose at its tip (no paper; see [`build_trajectory`]). A concave join's
/// back leg is `2h·sin(β/2)`, and the chord that replaces it comes at most `h(1 − cos β)`,
/// i.e. `leg²/(2h)`, nearer the part: within 1 % of `h` for legs up to `√0.02·h`.
pub const BACKTRACK_RATIO: Real = 0.14;
/// Cosine of the turn beyond which consecutive moves count as turning back (150°, as the
/// exporters' exact stops).
const REVERSAL_COS: Real = -0.866_025_403_784_438_6;
/// Consecutive poses closer than this multiple of the standoff are merged into one.
pub const SAME_POSITION_RATIO: Real = 1e-6;
/// Normals closer than this angle (radians) count as coplanar: no transition.
const COPLANAR_RAD: Real = 1e-6;
/// Normals closer than this angle (radians) get no transition: the offsets of both sides
/// are within `10⁻⁴·h` (rounding of `f32` coordinates leaves turns of a few µrad).
const SMALL_TURN_RAD: Real = 1e-4;
/// Segment directions whose cross product is shorter than this give no scan-plane normal
/// (the pass is straight).
const STRAIGHT_SINE: Real = 1e-6;
/// Two 2D segments whose directions' cross product is below this fraction of their lengths'
/// product are parallel: no crossing.
const PARALLEL_SINE: Real = 1e-12;

/// Counts of what the trajectory contains.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TrajectoryCounts {
    /// Straight transitions (convex, `β ≤ β_T`).
    pub straight: usize,
    /// Arcs (convex, `β > β_T`).
    pub arcs: usize,
    /// Convex turns (straight transitions and arcs, counted there too) run with the gun off:
    /// their gun travel exceeds the longest turn allowed with the gun on.
    pub turns_off: usize,
    /// Concave edges: their offsets crossed and the offset behind the crossing was removed.
    pub trimmed: usize,
    /// Pass ends where a crossing cut the round cap, so the pass ends by turning around its
    /// end point at the standoff instead of with the extension.
    pub capped: usize,
    /// Short gun-on backtracks removed (a concave crossing just behind the previous pose).
    pub backtracks: usize,
}

/// Unit vector along `t` made perpendicular to `axis`; any perpendicular when `t ∥ axis`.
fn perpendicular(t: Vector3, axis: &Vector3) -> Vector3 {
    let p = t - axis * axis.dot(&t);
    let n = p.norm();
    if n > 1e-12 {
        p / n
    } else {
        any_perpendicular(axis)
    }
}

/// `v` normalised, or `fallback` when it vanishes.
fn unit_or(v: Vector3, fallback: &Vector3) -> Vector3 {
    let n = v.norm();
    if n > 1e-9 {
        v / n
    } else {
        *fallback
    }
}

/// Normalised `a + b`, or `a` when they cancel.
fn blend(a: &Vector3, b: &Vector3) -> Vector3 {
    let s = a + b;
    let n = s.norm();
    if n > 1e-9 {
        s / n
    } else {
        *a
    }
}

/// Steps of at most [`ARC_STEP_RAD`] for a turn of `angle` radians (an angle a rounding
/// above a whole number of steps takes that number, so mirror-image arcs match).
fn arc_steps(angle: Real) -> usize {
    (angle / ARC_STEP_RAD - ARC_STEP_SLACK).ceil().max(1.0) as usize
}

/// Spherical interpolation from `d0` to `d1` (unit, angle `gamma` apart) at `phi ∈ [0, 1]`.
fn slerp(d0: &Vector3, d1: &Vector3, gamma: Real, phi: Real) -> Vector3 {
    let mixed = d0 * libm::sin((1.0 - phi) * gamma) + d1 * libm::sin(phi * gamma);
    let n = mixed.norm();
    if n > 1e-9 {
        mixed / n
    } else if phi < 0.5 {
        *d0
    } else {
        *d1
    }
}

/// A point of the offset curve: position, its projection on the pass's plane, gun axis, the
/// kind of the move arriving at it and the index of the raw edge it lies on (its own index
/// for a raw node; raw edge `k` ends at raw node `k`).
#[derive(Debug, Clone, Copy)]
struct Node {
    p: Point3,
    q: [Real; 2],
    axis: Vector3,
    kind: PoseKind,
    origin: usize,
}

/// Where the caps are in the raw curve (they end at raw node `first` and start at raw node
/// `last`), whether each may be cut, and the largest gap in space at a crossing that cuts one.
struct Caps {
    gap: Real,
    first: usize,
    last: usize,
    start: bool,
    end: bool,
}

/// The loop-free offset curve and whether a crossing cut each cap.
struct Kept {
    nodes: Vec<Node>,
    start_cut: bool,
    end_cut: bool,
}

/// The pass's plane: an origin and two unit directions spanning it.
struct Plane {
    origin: Point3,
    normal: Vector3,
    e1: Vector3,
    e2: Vector3,
}

impl Plane {
    /// The plane of a pass from its segment directions `t` and normals `n`: the scan plane
    /// contains every `t`, so two of them that are not parallel span it; a straight pass takes
    /// the plane of its direction and mean normal.
    fn of_pass(origin: Point3, t: &[Vector3], n: &[Vector3]) -> Plane {
        let e1 = t[0];
        let best = t
            .iter()
            .map(|tk| e1.cross(tk))
            .max_by(|a, b| a.norm().total_cmp(&b.norm()))
            .unwrap_or_else(Vector3::zeros);
        let normal = if best.norm() > STRAIGHT_SINE {
            best.normalize()
        } else {
            let mean: Vector3 = n.iter().sum();
            let c = e1.cross(&mean);
            if c.norm() > STRAIGHT_SINE {
                c.normalize()
            } else {
                any_perpendicular(&e1)
            }
        };
        Plane {
            origin,
            normal,
            e1,
            e2: normal.cross(&e1),
        }
    }
    fn project(&self, p: &Point3) -> [Real; 2] {
        let d = p - self.origin;
        [d.dot(&self.e1), d.dot(&self.e2)]
    }
}

fn cross2(a: [Real; 2], b: [Real; 2]) -> Real {
    a[0] * b[1] - a[1] * b[0]
}
fn sub2(a: [Real; 2], b: [Real; 2]) -> [Real; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn len2(a: [Real; 2]) -> Real {
    libm::hypot(a[0], a[1])
}

/// A uniform grid over the kept edges of the offset curve (2D), edge `i` joining kept nodes
/// `i − 1` and `i`. Edges are removed last-in first-out, like the kept curve itself, so each
/// cell's entries form a stack: a list threaded through one array, newest first.
struct EdgeGrid {
    cell: Real,
    /// Per occupied cell: its newest entry.
    head: FxHashMap<(i64, i64), u32>,
    /// Entries in the order added: edge, next entry of the same cell (or [`NO_ENTRY`]), cell.
    entries: Vec<(u32, u32, (i64, i64))>,
    /// Per registered edge (edge `i` at `i − 1`): its first entry.
    edge_start: Vec<usize>,
    /// Per edge: the last query that tested it.
    stamp: Vec<u32>,
    query: u32,
    /// The sample cells of the segment last queried or registered ([`EdgeGrid::sample_cells`])
    /// and that segment: registering the segment just queried (no crossing found) reads them
    /// here instead of sampling it again.
    walk: Vec<(i64, i64)>,
    walk_of: Option<([Real; 2], [Real; 2])>,
    /// The cells the last query looked in, and each column's least and greatest y of its
    /// walk (scratch).
    cells: Vec<(i64, i64)>,
    columns: Vec<(i64, i64)>,
}

/// End of a cell's list of entries.
const NO_ENTRY: u32 = u32::MAX;

impl EdgeGrid {
    fn new(cell: Real) -> EdgeGrid {
        EdgeGrid {
            cell,
            head: FxHashMap::default(),
            entries: Vec::new(),
            edge_start: Vec::new(),
            stamp: Vec::new(),
            query: 0,
            walk: Vec::new(),
            walk_of: None,
            cells: Vec::new(),
            columns: Vec::new(),
        }
    }
    /// Cells of sample points at most half a cell apart along `a → b` (monotone, so repeats
    /// are consecutive): any point of the segment is within a quarter cell of a sample.
    fn sample_cells(&self, a: [Real; 2], b: [Real; 2], out: &mut Vec<(i64, i64)>) {
        out.clear();
        // The sample count is finite: both ends are finite and the cell positive.
        let steps = (2.0 * len2(sub2(b, a)) / self.cell).ceil().clamp(1.0, 1e9) as usize;
        for k in 0..=steps {
            let s = k as Real / steps as Real;
            let x = a[0] + (b[0] - a[0]) * s;
            let y = a[1] + (b[1] - a[1]) * s;
            // `floor` is exact, so any implementation gives these cells; the standard one is
            // an instruction in WebAssembly, where `libm`'s is a routine.
            let c = (
                (x / self.cell).floor() as i64,
                (y / self.cell).floor() as i64,
            );
            if out.last() != Some(&c) {
                out.push(c);
            }
        }
    }
    /// Registers edge `id` (= the number of edges registered so far + 1) from `a` to `b`.
    fn push(&mut self, id: usize, a: [Real; 2], b: [Real; 2]) {
        debug_assert_eq!(id, self.edge_start.len() + 1);
        self.walk(a, b);
        self.edge_start.push(self.entries.len());
        for &c in &self.walk {
            let index = self.entries.len() as u32;
            let next = self.head.insert(c, index).unwrap_or(NO_ENTRY);
            self.entries.push((id as u32, next, c));
        }
        if self.stamp.len() <= id {
            self.stamp.resize(id + 1, 0);
        }
    }
    /// Removes every edge above `keep` (edges `keep + 1 ..`).
    fn truncate(&mut self, keep: usize) {
        let Some(&start) = self.edge_start.get(keep) else {
            return;
        };
        self.edge_start.truncate(keep);
        while self.entries.len() > start {
            let Some((_, next, c)) = self.entries.pop() else {
                break;
            };
            if next == NO_ENTRY {
                self.head.remove(&c);
            } else {
                self.head.insert(c, next);
            }
        }
    }
    /// Calls `visit` once for every registered edge near the segment `a → b` (every edge
    /// crossing it is visited).
    fn near(&mut self, a: [Real; 2], b: [Real; 2], mut visit: impl FnMut(usize)) {
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.query = 1;
        }
        self.near_cells(a, b);
        for c in &self.cells {
            let mut entry = self.head.get(c).copied().unwrap_or(NO_ENTRY);
            while entry != NO_ENTRY {
                let (e, next, _) = self.entries[entry as usize];
                let e = e as usize;
                if self.stamp[e] != self.query {
                    self.stamp[e] = self.query;
                    visit(e);
                }
                entry = next;
            }
        }
    }

    /// The sample cells of `a → b` in `self.walk`, sampled unless they are there already.
    fn walk(&mut self, a: [Real; 2], b: [Real; 2]) {
        if self.walk_of != Some((a, b)) {
            let mut walk = std::mem::take(&mut self.walk);
            self.sample_cells(a, b, &mut walk);
            self.walk = walk;
            self.walk_of = Some((a, b));
        }
    }

    /// The cells [`EdgeGrid::near`] looks in for the segment `a → b`, in increasing order,
    /// in `self.cells` (its sample cells in `self.walk`).
    fn near_cells(&mut self, a: [Real; 2], b: [Real; 2]) {
        self.walk(a, b);
        // Two crossing segments have samples within a quarter cell of the crossing each, so
        // their cells are neighbours: visit the union of the samples' 3 × 3 neighbourhoods,
        // column by column (x, then y, increasing). The samples' cells are a walk monotone
        // in x and in y whose steps move at most one cell along each (samples are at most
        // half a cell apart), so it meets every column between its ends, and its cells in
        // columns x − 1 to x + 1 cover every y between their least and greatest: the union's
        // cells in column x are those from one below the least to one above the greatest.
        let walk = &self.walk;
        let (x0, x1) = (walk[0].0, walk[walk.len() - 1].0);
        let x_lo = x0.min(x1);
        // Each column's least and greatest y, in one pass over the walk.
        let columns = &mut self.columns;
        columns.clear();
        columns.resize((x0.max(x1) - x_lo + 1) as usize, (i64::MAX, i64::MIN));
        for &(x, y) in walk {
            let (lo, hi) = &mut columns[(x - x_lo) as usize];
            (*lo, *hi) = ((*lo).min(y), (*hi).max(y));
        }
        self.cells.clear();
        for x in x_lo - 1..=x0.max(x1) + 1 {
            let near = |k: i64| usize::try_from(k - x_lo).ok().and_then(|k| columns.get(k));
            let (lo, hi) = [near(x - 1), near(x), near(x + 1)]
                .into_iter()
                .flatten()
                .fold((i64::MAX, i64::MIN), |(lo, hi), c| {
                    (lo.min(c.0), hi.max(c.1))
                });
            for y in lo - 1..=hi + 1 {
                self.cells.push((x, y));
            }
        }
    }
}

/// A raw node: position, gun axis, kind.
type RawNode = (Point3, Vector3, PoseKind);

/// The raw offset curve of one pass: start cap, offset segments with their transitions, end
/// cap. Returns the nodes, the index of the first segment's offset start (the start cap's
/// last node) and of the last segment's offset end (the end cap's first node).
fn raw_offset(
    pass: &ScanPass,
    n: &[Vector3],
    t: &[Vector3],
    standoff: Real,
    transition_angle: Real,
    max_turn_on: Real,
    counts: &mut TrajectoryCounts,
) -> (Vec<RawNode>, usize, usize) {
    let m = n.len();
    let mut raw: Vec<RawNode> = Vec::with_capacity(2 * m + 40);
    // A round cap of radius h around `centre` from direction `d0` to `d1` (gun axis radial).
    let cap = |raw: &mut Vec<RawNode>, centre: Point3, d0: Vector3, d1: Vector3, first: bool| {
        let gamma = angle_between(&d0, &d1);
        let steps = arc_steps(gamma);
        for s in usize::from(!first)..=steps {
            let d = slerp(&d0, &d1, gamma, s as Real / steps as Real);
            raw.push((centre + d * standoff, -d, PoseKind::Arc));
        }
    };
    cap(&mut raw, pass.points[0], -t[0], n[0], true);
    let first = raw.len() - 1;
    for j in 0..m.saturating_sub(1) {
        let (ni, nj) = (n[j], n[j + 1]);
        let beta = angle_between(&ni, &nj);
        if beta < COPLANAR_RAD && angle_between(&t[j], &t[j + 1]) < COPLANAR_RAD {
            continue;
        }
        let edge = pass.points[j + 1];
        let (a, b) = (edge + ni * standoff, edge + nj * standoff);
        if beta >= SMALL_TURN_RAD && nj.dot(&t[j]) < 0.0 {
            counts.trimmed += 1;
            // Concave edge. Each offset line meets the other face's offset plane (at `h`
            // from both faces) at `x1 = a + s·t_i` and `x2 = b + u·t_j`, two points of the
            // line where the offset planes meet (one point when the normals lie in the scan
            // plane). Where both lie on their segments and no farther apart than `a` and `b`
            // (the pass crosses the edge at 45° or more), the pass turns at their midpoint,
            // reached and left within the two offset planes. Otherwise `a` is joined
            // straight to `b` and the loop removal cuts it.
            let dip = standoff * (1.0 - ni.dot(&nj));
            let (ci, cj) = (nj.dot(&t[j]), ni.dot(&t[j + 1]));
            let back = raw.last().map_or(0.0, |r| (a - r.0).dot(&t[j]));
            let ahead = (pass.points[j + 2] - edge).dot(&t[j + 1]);
            let (x1, x2) = (a + t[j] * (dip / ci), b + t[j + 1] * (dip / cj));
            if cj > 0.0
                && -dip / ci <= back
                && dip / cj <= ahead
                && (x2 - x1).norm() <= (b - a).norm()
            {
                let mid = Point3::from((x1.coords + x2.coords) * 0.5);
                raw.push((mid, -blend(&ni, &nj), PoseKind::Pass));
            } else {
                raw.push((a, -ni, PoseKind::Pass));
                raw.push((b, -nj, PoseKind::Pass));
            }
            continue;
        }
        raw.push((a, -ni, PoseKind::Pass));
        if beta < SMALL_TURN_RAD {
            // A kink within a plane or a rounding-sized turn: `b` is within 10⁻⁴·h of `a`.
            continue;
        }
        // Convex edge: the offset segments leave a gap. While the gun turns across it,
        // its axis stays on the edge: a turn longer than `max_turn_on` runs gun off.
        let gun = |travel: Real, kind: PoseKind| {
            if travel > max_turn_on {
                PoseKind::Link
            } else {
                kind
            }
        };
        if beta <= transition_angle {
            counts.straight += 1;
            let kind = gun((b - a).norm(), PoseKind::StraightTransition);
            counts.turns_off += usize::from(kind == PoseKind::Link);
            let mid = Point3::from((a.coords + b.coords) * 0.5);
            raw.push((mid, -blend(&ni, &nj), kind));
            raw.push((b, -nj, kind));
        } else {
            counts.arcs += 1;
            let steps = arc_steps(beta);
            // The polyline's length: `steps` chords of the arc.
            let travel = steps as Real * 2.0 * standoff * libm::sin(0.5 * beta / steps as Real);
            let kind = gun(travel, PoseKind::Arc);
            counts.turns_off += usize::from(kind == PoseKind::Link);
            for s in 1..=steps {
                let radial = slerp(&ni, &nj, beta, s as Real / steps as Real);
                raw.push((edge + radial * standoff, -radial, kind));
            }
        }
    }
    raw.push((
        pass.points[m] + n[m - 1] * standoff,
        -n[m - 1],
        PoseKind::Pass,
    ));
    let last = raw.len() - 1;
    cap(&mut raw, pass.points[m], n[m - 1], t[m - 1], false);
    (raw, first, last)
}

/// Where a segment `p → p + r` first crosses a kept edge: its parameter on the segment, the
/// edge and the parameter on the edge.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    t: Real,
    edge: usize,
    u: Real,
}

/// Removes the loops of the raw offset curve (see the file header): a stack of kept nodes;
/// each raw edge is tested against the kept edges near it (but the last, which it continues);
/// at its first crossing the kept curve is cut back to the crossing and the rest of the edge
/// goes on from there. Every crossing removes at least one kept node and every raw node is
/// kept at most once, so it ends after at most twice as many steps as raw nodes. A crossing
/// on an edge of the start cap (raw edges up to `first`) cuts it, unless at its very end; one
/// found by an edge of the end cap (raw edges after `last`) cuts that; either counts only
/// where the branches are within `caps.gap` in space and the cap may be cut at all.
fn remove_loops(raw: &[Node], tol: Real, caps: &Caps) -> Kept {
    let (first, last) = (caps.first, caps.last);
    let mut kept: Vec<Node> = Vec::with_capacity(raw.len());
    let (mut start_cut, mut end_cut) = (false, false);
    let Some(&first_node) = raw.first() else {
        return Kept {
            nodes: kept,
            start_cut,
            end_cut,
        };
    };
    let total: Real = raw.windows(2).map(|w| len2(sub2(w[1].q, w[0].q))).sum();
    let cell = (total / raw.len() as Real).max(tol * 16.0);
    let mut grid = EdgeGrid::new(cell);
    // The length of each kept edge (edge `e` joins kept nodes `e − 1` and `e`; 0 a dummy),
    // kept beside them rather than measured again by every query that meets the edge.
    let mut lengths: Vec<Real> = Vec::with_capacity(raw.len());
    lengths.push(0.0);
    kept.push(first_node);
    for target in &raw[1..] {
        loop {
            let from = kept[kept.len() - 1];
            let r = sub2(target.q, from.q);
            let len = len2(r);
            if len <= tol {
                // The raw node is where the curve already is: keep its turn, not a new pose.
                break;
            }
            let last_edge = kept.len() - 1;
            let mut best: Option<Crossing> = None;
            let t_min = tol / len;
            grid.near(from.q, target.q, |e| {
                if e >= last_edge {
                    return;
                }
                let (a, b) = (kept[e - 1].q, kept[e].q);
                let s = sub2(b, a);
                let ls = lengths[e];
                let denom = cross2(r, s);
                if ls <= 0.0 || denom.abs() <= PARALLEL_SINE * len * ls {
                    return;
                }
                let w = sub2(a, from.q);
                let t = cross2(w, s) / denom;
                let u = cross2(w, r) / denom;
                let u_tol = tol / ls;
                if t < t_min || t > 1.0 + t_min || u < -u_tol || u > 1.0 + u_tol {
                    return;
                }
                let (in_start, in_end) = (kept[e].origin <= first, target.origin > last);
                if (in_start && !caps.start) || (in_end && !caps.end) {
                    return;
                }
                if in_start || in_end {
                    // A cap is cut only where the curves meet in space, not merely in the
                    // projection (normals across the scan plane part the branches).
                    let on_edge = kept[e - 1].p + (kept[e].p - kept[e - 1].p) * u;
                    let on_new = from.p + (target.p - from.p) * t;
                    if (on_edge - on_new).norm() > caps.gap {
                        return;
                    }
                }
                let c = Crossing {
                    t: t.min(1.0),
                    edge: e,
                    u: u.clamp(0.0, 1.0),
                };
                best = match best {
                    Some(b) if b.t < c.t - t_min || (b.t <= c.t + t_min && b.edge < c.edge) => {
                        Some(b)
                    }
                    _ => Some(c),
                };
            });
            let Some(c) = best else {
                grid.push(kept.len(), from.q, target.q);
                lengths.push(len);
                kept.push(*target);
                break;
            };
            // Cut the kept curve back to the crossing on edge `c.edge`.
            let (a, b) = (kept[c.edge - 1], kept[c.edge]);
            let on_edge_axis = unit_or(a.axis.lerp(&b.axis, c.u), &b.axis);
            let on_new_axis = unit_or(from.axis.lerp(&target.axis, c.t), &target.axis);
            let axis = blend(&on_edge_axis, &on_new_axis);
            let edge_len = len2(sub2(b.q, a.q));
            let at = if c.u * edge_len <= tol {
                c.edge - 1
            } else {
                c.edge
            };
            let interior = at == c.edge && (1.0 - c.u) * edge_len > tol;
            if b.origin < first || (b.origin == first && (interior || at != c.edge)) {
                start_cut = true;
            }
            if target.origin > last {
                end_cut = true;
            }
            kept.truncate(at + 1);
            lengths.truncate(at + 1);
            grid.truncate(at);
            let node = &mut kept[at];
            node.axis = axis;
            if interior {
                let on_edge = a.p + (b.p - a.p) * c.u;
                let on_new = from.p + (target.p - from.p) * c.t;
                node.p = Point3::from((on_edge.coords + on_new.coords) * 0.5);
                node.q = [from.q[0] + r[0] * c.t, from.q[1] + r[1] * c.t];
                node.origin = b.origin;
                // The edge now ends at the crossing.
                lengths[at] = len2(sub2(kept[at].q, kept[at - 1].q));
            }
        }
    }
    Kept {
        nodes: kept,
        start_cut,
        end_cut,
    }
}

/// Builds the trajectory of `passes` (already in execution order and direction). A convex
/// turn (straight transition or arc) whose gun travel exceeds `max_turn_on` runs with the gun
/// off (`Real::INFINITY` keeps every turn gun on, as the patent does).
pub fn build_trajectory(
    passes: &[ScanPass],
    normals: &[Vector3],
    standoff: Real,
    transition_angle: Real,
    extension: Real,
    speed: Real,
    max_turn_on: Real,
) -> (ToolPath, TrajectoryCounts) {
    let mut poses: Vec<Pose> = Vec::new();
    let mut counts = TrajectoryCounts::default();
    let tol = SAME_POSITION_RATIO * standoff;
    for pass in passes {
        let m = pass.faces.len();
        if m == 0 {
            continue;
        }
        let pass_id = poses.last().map_or(0, |p: &Pose| p.pass + 1);
        let n: Vec<Vector3> = pass.faces.iter().map(|&f| normals[f as usize]).collect();
        let t: Vec<Vector3> = (0..m)
            .map(|i| (pass.points[i + 1] - pass.points[i]).normalize())
            .collect();
        let concave_before = counts.trimmed;
        let (raw, first, last) = raw_offset(
            pass,
            &n,
            &t,
            standoff,
            transition_angle,
            max_turn_on,
            &mut counts,
        );
        let plane = Plane::of_pass(pass.points[0], &t, &n);
        let raw: Vec<Node> = raw
            .into_iter()
            .enumerate()
            .map(|(origin, (p, axis, kind))| Node {
                p,
                q: plane.project(&p),
                axis,
                kind,
                origin,
            })
            .collect();
        // A cap turns in the plane of the end's normal and direction: only where that is the
        // scan plane (within CAP_PLANE_SINE) does its crossing mean what it means in 2D.
        let fits = |normal: &Vector3| normal.dot(&plane.normal).abs() <= CAP_PLANE_SINE;
        let caps = Caps {
            gap: CAP_GAP_RATIO * standoff,
            first,
            last,
            start: fits(&n[0]),
            end: fits(&n[m - 1]),
        };
        // Without a concave edge the offset only turns away from the part: no loop.
        let result = if counts.trimmed > concave_before {
            remove_loops(&raw, tol, &caps)
        } else {
            Kept {
                nodes: raw,
                start_cut: false,
                end_cut: false,
            }
        };
        let Kept {
            nodes: mut kept,
            start_cut,
            end_cut,
        } = result;
        // An uncut cap gives way to the extension.
        let mut nodes: Vec<(Point3, Vector3, PoseKind)> = Vec::with_capacity(kept.len() + 2);
        if start_cut {
            counts.capped += 1;
            kept[0].kind = PoseKind::Link;
        } else {
            let start = kept.iter().position(|k| k.origin >= first).unwrap_or(0);
            kept.drain(..start);
            let a0 = kept[0].p;
            if extension > 0.0 {
                nodes.push((a0 - t[0] * extension, kept[0].axis, PoseKind::Link));
                kept[0].kind = PoseKind::Extension;
            } else {
                kept[0].kind = PoseKind::Link;
            }
        }
        let tail = if end_cut {
            counts.capped += 1;
            None
        } else {
            let end = kept.iter().rposition(|k| k.origin <= last).unwrap_or(0);
            kept.truncate(end + 1);
            (extension > 0.0).then(|| {
                let e = kept[end];
                (e.p + t[m - 1] * extension, e.axis, PoseKind::Extension)
            })
        };
        nodes.extend(kept.iter().map(|k| (k.p, k.axis, k.kind)));
        nodes.extend(tail);
        // Travel: the direction of the arriving move (the first pose: of the leaving one).
        let begin = poses.len();
        let forward = pass.points[m] - pass.points[0];
        for (i, &(position, axis, kind)) in nodes.iter().enumerate() {
            if poses.len() > begin && (position - poses[poses.len() - 1].position).norm() <= tol {
                continue;
            }
            let travel = if i == 0 {
                nodes.get(1).map_or(t[0], |n| n.0 - position)
            } else {
                position - poses[poses.len() - 1].position
            };
            poses.push(Pose {
                position,
                axis,
                travel: perpendicular(travel, &axis),
                kind,
                pass: pass_id,
            });
            // A concave crossing a hair behind the previous pose (common on faceted skins)
            // makes the gun step back and forth, which a controller runs as a stop (a paint
            // dwell): the pose at the tip of such a short backtrack is dropped. Where the
            // move leaving the tip is a short turn run gun off, the tip is dropped only if
            // the gun-on move into it runs back along the pass (no coating is lost that the
            // pass had not just laid), else the gun-off pose goes; a gun-off tip between
            // gun-off moves goes too. Each round removes a pose, so the loop ends.
            while poses.len() >= begin + 3 {
                let n = poses.len();
                let (p0, p1, p2) = (&poses[n - 3], &poses[n - 2], &poses[n - 1]);
                let (a, b) = (p1.position - p0.position, p2.position - p1.position);
                let limit = BACKTRACK_RATIO * standoff;
                let short = a.norm().min(b.norm()) <= limit;
                let back = a.dot(&b) < REVERSAL_COS * a.norm() * b.norm();
                if !(short && back) {
                    break;
                }
                let drop = match (p1.kind.process_on(), p2.kind.process_on()) {
                    (true, true) | (false, false) => n - 2,
                    (true, false) if b.norm() <= limit => {
                        if a.dot(&forward) < 0.0 {
                            n - 2
                        } else {
                            n - 1
                        }
                    }
                    _ => break,
                };
                if drop == n - 2 {
                    let chord = p2.position - p0.position;
                    let axis = p2.axis;
                    poses[n - 1].travel = perpendicular(chord, &axis);
                }
                poses.remove(drop);
                counts.backtracks += 1;
            }
        }
    }
    let mut notes = vec![
        "spray trajectory after the patent 'a trajectory planning method for curved-surface spraying' (Tsinghua University): scan planes, offset by the standoff, straight or arc transitions".to_string(),
    ];
    if counts.trimmed > 0 {
        notes.push(format!(
            "{} concave edges: the offsets of both sides cross and every offset behind their crossing was removed, so the pass turns at the crossing (the patent treats convex edges only)",
            counts.trimmed
        ));
    }
    if counts.turns_off > 0 {
        notes.push(format!(
            "{} turns over convex edges run with the gun off: the gun's axis stays on the edge while it turns, so with the gun on the edge would get a spot of extra coating",
            counts.turns_off
        ));
    }
    if counts.capped > 0 {
        notes.push(format!(
            "{} pass ends lie in a concave region: the pass turns around its end point at the standoff instead of running on past it",
            counts.capped
        ));
    }
    (
        ToolPath {
            poses,
            speed,
            link_speed: speed,
            speeds: Vec::new(),
            notes,
        },
        counts,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells looked in are the union of the 3 × 3 neighbourhoods of the segment's
    /// sample cells, in increasing order, as sorting that union gives them: on segments of
    /// every direction and length (a few cells or none), anywhere on the grid.
    #[test]
    fn the_cells_near_a_segment_are_the_neighbourhoods_of_its_samples() {
        let mut grid = EdgeGrid::new(0.7);
        // A fixed sequence of pseudo-random numbers in [0, 1) (64-bit LCG).
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as Real / (1u64 << 53) as Real
        };
        let mut naive = Vec::new();
        for k in 0..20_000 {
            let a = [200.0 * next() - 100.0, 200.0 * next() - 100.0];
            let reach = [0.0, 0.3, 2.0, 9.0][k % 4];
            let b = match k % 5 {
                // Along an axis, either way.
                0 => [a[0] + reach * (next() - 0.5), a[1]],
                1 => [a[0], a[1] + reach * (next() - 0.5)],
                _ => [a[0] + reach * (next() - 0.5), a[1] + reach * (next() - 0.5)],
            };
            grid.near_cells(a, b);
            grid.sample_cells(a, b, &mut naive);
            assert_eq!(grid.walk, naive, "the sample cells");
            let walk = naive.len();
            for i in 0..walk {
                let (x, y) = naive[i];
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        naive.push((x + dx, y + dy));
                    }
                }
            }
            naive.drain(..walk);
            naive.sort_unstable();
            naive.dedup();
            assert_eq!(grid.cells, naive, "{a:?} → {b:?}");
        }
    }
}
