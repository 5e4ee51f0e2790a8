//! Exact polyhedral geodesic distance per vertex from a source curve, by window propagation.
//!
//! Source: Xin & Wang, "Improving Chen and Han's algorithm on the discrete geodesic problem"
//!         (ACM TOG 28(4), 2009): windows in a priority queue ordered by their smallest
//!         distance, each propagated across the face on its far side into at most two child
//!         windows on the opposite edges, children discarded by a filter against the current
//!         vertex distances instead of trimming; Chen & Han, "Shortest paths on a polyhedron"
//!         (SoCG 1990) for pseudo-sources (a path bends only at a saddle or boundary vertex;
//!         such a vertex restarts the propagation with `σ = d(v)`); Surazhsky, Surazhsky,
//!         Kirsanov, Gortler & Hoppe, "Fast exact and approximate geodesics on meshes"
//!         (SIGGRAPH 2005, §3) for the window geometry (interval `[b0, b1]` on an edge, source
//!         unfolded into the edge's plane, distance `σ + |x − s|`).
//! Input:  active faces, their adjacency, a resolved source (dense on-surface polylines with
//!         the face of each sample, and vertices).
//! Output: distance per vertex (`+∞` where unreached), 0 on the source, the exact polyhedral
//!         distance to the piecewise-linear source curve up to rounding.
//! Cost:   O(W log W) for W windows processed; W = O(n²) in the worst case for CH/ICH, a few
//!         to a few tens per edge in practice (the height-field and cylinder tests report it).
//!         Memory: the queue of pending windows (about the wavefront).
//! Deviations:
//!   - The source is a curve, not points: each piece of the source polyline lying in a face
//!     seeds *line windows* (a plane wave `u·x + c`, rays parallel to the unit `u`) where the
//!     foot point of an edge point falls inside the piece, and point windows from its two
//!     ends; the vertices of the face get their in-plane distance to the piece. A chord
//!     between samples in two faces sharing an edge is split where it crosses the edge in
//!     the unfolding of the two faces (no paper).
//!   - The filter (no paper beyond ICH's idea): a window on edge `AB` is dropped when
//!     `d(A) + |A b1| < d_w(b1)` or `d(B) + |B b0| < d_w(b0)`. Distance along an edge is
//!     1-Lipschitz for any window, so either inequality at the far end of the interval
//!     holds at every point of it: the window never carries a shortest path. It is applied
//!     when a child is made (with the child's own edge, whose ends include the parent's
//!     opposite vertex) and again when the window is taken from the queue. ICH's one-angle-
//!     one-split rule is not used.
//!   - Degenerate faces (height below `DEGENERATE_HEIGHT_RATIO` of the longest edge) pass no
//!     windows; their vertices act as pseudo-sources and reach each other along edges. A
//!     source sample on a vertex makes it a pseudo-source. A sample chord between faces
//!     that share only a vertex runs through that vertex; between faces that share nothing
//!     (never at the sampling of `source.rs` on a manifold) its two ends count as points.
//!   - A cap on windows processed (`64·√max(1, E/10⁴)` per edge for `E` edges, plus 2²⁰,
//!     unless given) and on the queue's memory returns [`GeodesicError::LimitExceeded`].

use super::params::{GeodesicError, Progress, PROGRESS_EVERY};
use super::source::ResolvedSource;
use super::surface::{segment_distance, Surface};
use crate::math::{angle_between, Point3, Real, Vector3, DEGENERATE_HEIGHT_RATIO};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

mod pieces;
use pieces::{curve_pieces, Piece};

/// Windows processed per mesh edge (on meshes up to `CAP_EDGES` edges) before the default cap
/// stops the computation.
const WINDOWS_PER_EDGE: Real = 64.0;
/// Beyond this many edges the per-edge allowance grows as √(edges / CAP_EDGES): window
/// counts per edge of CH/ICH grow about as √n on curved meshes (measured here: 22, 41, 80
/// per edge on the 1, 0.5, 0.25 mm height field).
const CAP_EDGES: Real = 1e4;
/// Windows always allowed on top of the per-edge allowance.
const WINDOW_CAP_BASE: u64 = 1 << 20;
/// Memory of the pending-window queue allowed, bytes.
const MAX_QUEUE_BYTES: usize = 1 << 30;
/// A point source closer than this (relative to the edge length) to an edge's line lies on it.
const ON_LINE_TOLERANCE: Real = 1e-10;
/// Slack (relative to the edge length) for a vertex on the border ray of a window.
const RAY_TOLERANCE: Real = 1e-9;
/// Windows narrower than this (relative to the edge length) are dropped.
const MIN_WIDTH: Real = 1e-12;
/// Relative margin of the filter: a window is dropped only when beaten by more than this.
const FILTER_TOLERANCE: Real = 1e-12;
/// Angle (radians) by which the shadow of a saddle is widened on each side.
const SHADOW_ANGLE_TOLERANCE: Real = 1e-9;
/// Relative excess of the angle sum over 2π above which a vertex is a saddle.
const FLAT_VERTEX_TOLERANCE: Real = 1e-9;

/// The distance function of a window in its edge frame (edge on `y = 0`, face ahead at `y > 0`).
#[derive(Clone, Copy, Debug)]
enum Front {
    /// `σ + |(x, y) − (sx, sy)|`, source unfolded at `sy ≤ 0`.
    Point { sx: Real, sy: Real, sigma: Real },
    /// `ux·x + uy·y + c`, unit `(ux, uy)` with `uy > 0`.
    Line { ux: Real, uy: Real, c: Real },
}

impl Front {
    fn at(&self, x: Real, y: Real) -> Real {
        match *self {
            Front::Point { sx, sy, sigma } => sigma + (x - sx).hypot(y - sy),
            Front::Line { ux, uy, c } => ux * x + uy * y + c,
        }
    }

    /// Smallest distance over `[b0, b1]` on the edge (the queue key).
    fn min_on(&self, b0: Real, b1: Real) -> Real {
        match *self {
            Front::Point { sx, sy, sigma } => sigma + (sx.clamp(b0, b1) - sx).hypot(sy),
            Front::Line { ux, c, .. } => c + (ux * b0).min(ux * b1),
        }
    }

    /// Direction of the ray through edge point `(x, 0)`.
    fn ray(&self, x: Real) -> [Real; 2] {
        match *self {
            Front::Point { sx, sy, .. } => [x - sx, -sy],
            Front::Line { ux, uy, .. } => [ux, uy],
        }
    }

    /// The same front in a frame with origin `o` and axes `ex`, `ey` (given in this frame).
    fn in_frame(&self, o: [Real; 2], ex: [Real; 2], ey: [Real; 2]) -> Front {
        match *self {
            Front::Point { sx, sy, sigma } => {
                let d = [sx - o[0], sy - o[1]];
                Front::Point {
                    sx: dot(d, ex),
                    sy: dot(d, ey),
                    sigma,
                }
            }
            Front::Line { ux, uy, c } => Front::Line {
                ux: ux * ex[0] + uy * ex[1],
                uy: ux * ey[0] + uy * ey[1],
                c: c + ux * o[0] + uy * o[1],
            },
        }
    }
}

fn dot(a: [Real; 2], b: [Real; 2]) -> Real {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: [Real; 2], b: [Real; 2]) -> Real {
    a[0] * b[1] - a[1] * b[0]
}

/// A window to seed on an edge: `(b0, b1, front)` in the edge's frame.
type Seed = (Real, Real, Front);

/// A window on the edge in slot `slot` of `face`, about to cross into `face`.
#[derive(Clone, Copy, Debug)]
struct Window {
    face: u32,
    slot: u8,
    b0: Real,
    b1: Real,
    front: Front,
}

#[derive(Clone, Copy, Debug)]
enum Event {
    Window(Window),
    /// A vertex restarts the propagation (pseudo-source) at its distance `key`.
    Vertex(u32),
}

#[derive(Clone, Copy, Debug)]
struct Item {
    key: Real,
    seq: u64,
    event: Event,
}
impl PartialEq for Item {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Item {}
impl Ord for Item {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on the key, then first pushed first: a deterministic order.
        o.key
            .total_cmp(&self.key)
            .then_with(|| o.seq.cmp(&self.seq))
    }
}
impl PartialOrd for Item {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// The 2D frame of half-edge (face, slot): `A` at the origin, `B` at `(l, 0)`, `C` at `c`.
struct Frame {
    v: [usize; 3],
    a: Point3,
    ex: Vector3,
    l: Real,
    c: [Real; 2],
}

impl Frame {
    /// A point of the face across the edge, unfolded to `y ≤ 0`.
    fn unfold(&self, p: &Point3) -> [Real; 2] {
        let w = p - self.a;
        let x = w.dot(&self.ex);
        [x, -(w - self.ex * x).norm()]
    }

    fn corner(&self, i: usize) -> [Real; 2] {
        [[0.0, 0.0], [self.l, 0.0], self.c][i]
    }
}

/// Statistics of one run.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Stats {
    /// Windows taken from the queue and propagated (not filtered).
    pub windows: u64,
}

struct Solver<'a> {
    surface: &'a Surface<'a>,
    dist: Vec<Real>,
    /// Saddle, boundary or degenerate-face vertex: restarts the propagation when improved.
    pseudo: Vec<bool>,
    degenerate: Vec<bool>,
    /// Per vertex, the face and direction the path that set its distance arrives from.
    back: Vec<Option<(u32, Vector3)>>,
    /// Per vertex reached by a window ray: the face it crossed and where it crossed the edge.
    via: Vec<Option<(u32, Real)>>,
    heap: BinaryHeap<Item>,
    seq: u64,
    scale: Real,
}

impl<'a> Solver<'a> {
    fn new(surface: &'a Surface<'a>) -> Self {
        let mesh = surface.mesh;
        let nv = mesh.vertex_count();
        let mut angle = vec![0.0; nv];
        let mut pseudo = vec![false; nv];
        let mut degenerate = vec![false; mesh.triangle_count()];
        for &f in &surface.faces {
            let f = f as usize;
            let t = mesh.triangles()[f];
            let p = mesh.corners(f);
            let longest = (0..3)
                .map(|k| (p[(k + 1) % 3] - p[k]).norm_squared())
                .fold(0.0, Real::max);
            let flat = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
            if flat || mesh.scaled_normal(f).norm() <= DEGENERATE_HEIGHT_RATIO * longest {
                degenerate[f] = true;
                for v in t {
                    pseudo[v as usize] = true;
                }
            }
            for k in 0..3 {
                let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                angle[t[k] as usize] += angle_between(&a, &b);
                if surface.across(f, k).is_none() {
                    pseudo[t[k] as usize] = true;
                    pseudo[t[(k + 1) % 3] as usize] = true;
                }
            }
        }
        for v in 0..nv {
            pseudo[v] |= angle[v] > 2.0 * std::f64::consts::PI * (1.0 + FLAT_VERTEX_TOLERANCE);
        }
        Solver {
            surface,
            dist: vec![Real::INFINITY; nv],
            back: vec![None; nv],
            via: vec![None; nv],
            pseudo,
            degenerate,
            heap: BinaryHeap::new(),
            seq: 0,
            scale: surface.mean_edge.max(Real::MIN_POSITIVE),
        }
    }

    fn push(&mut self, key: Real, event: Event) {
        self.seq += 1;
        self.heap.push(Item {
            key,
            seq: self.seq,
            event,
        });
    }

    /// Lowers the distance of `v` to `d`, reached from direction `back` (in face `back.0`,
    /// pointing back along the path; `None`: unknown or any); a pseudo-source vertex (or any
    /// vertex if `force`) then restarts the propagation. NaN never passes the comparison.
    fn reach(&mut self, v: usize, d: Real, force: bool, back: Option<(usize, Vector3)>) {
        self.reach_via(v, d, force, back, None);
    }

    /// [`Solver::reach`] by a ray crossing the face `via.0` from the edge opposite `v`, at
    /// `x = via.1` on that edge (the record that trims later windows there).
    fn reach_via(
        &mut self,
        v: usize,
        d: Real,
        force: bool,
        back: Option<(usize, Vector3)>,
        via: Option<(usize, Real)>,
    ) {
        if d < self.dist[v] {
            self.dist[v] = d;
            self.back[v] = back.map(|(f, dir)| (f as u32, dir));
            self.via[v] = via.map(|(f, x)| (f as u32, x));
            if self.pseudo[v] || force {
                self.push(d, Event::Vertex(v as u32));
            }
        }
    }

    /// The frame of half-edge (f, k), or `None` for a zero-length edge or repeated corner.
    fn frame(&self, f: usize, k: usize) -> Option<Frame> {
        let mesh = self.surface.mesh;
        let t = mesh.triangles()[f];
        let v = [
            t[k] as usize,
            t[(k + 1) % 3] as usize,
            t[(k + 2) % 3] as usize,
        ];
        if v[0] == v[1] || v[1] == v[2] || v[0] == v[2] {
            return None;
        }
        let p = mesh.positions();
        let e = p[v[1]] - p[v[0]];
        let l = e.norm();
        if !(l > 0.0 && l.is_finite()) {
            return None;
        }
        let ex = e / l;
        let w = p[v[2]] - p[v[0]];
        let cx = w.dot(&ex);
        let cy = (w - ex * cx).norm();
        Some(Frame {
            v,
            a: p[v[0]],
            ex,
            l,
            c: [cx, cy],
        })
    }

    /// The face across slot `k` of `f` and the slot of the same edge there.
    fn twin(&self, f: usize, k: usize) -> Option<(usize, usize)> {
        let h = self.surface.across(f, k)?;
        let t = self.surface.mesh.triangles()[f];
        let (a, b) = (t[k], t[(k + 1) % 3]);
        let th = self.surface.mesh.triangles()[h];
        (0..3)
            .find(|&j| {
                let (c, d) = (th[j], th[(j + 1) % 3]);
                (c == a && d == b) || (c == b && d == a)
            })
            .map(|j| (h, j))
    }

    /// True when an end of the window's edge beats the window over its whole interval.
    fn dominated(&self, w: &Window, l: Real, a: usize, b: usize) -> bool {
        let (f0, f1) = (w.front.at(w.b0, 0.0), w.front.at(w.b1, 0.0));
        let tol = FILTER_TOLERANCE * f0.max(f1).max(self.scale);
        !(f0.is_finite() && f1.is_finite())
            || self.dist[a] + w.b1 < f1 - tol
            || self.dist[b] + (l - w.b0) < f0 - tol
    }

    /// Queues `w` (in the frame `fr` of its half-edge) unless it is empty or dominated.
    fn offer(&mut self, w: Window, fr: &Frame) {
        let width_ok = w.b1 - w.b0 > MIN_WIDTH * fr.l;
        let line_ok = match w.front {
            Front::Point { sy, .. } => sy <= 0.0,
            Front::Line { uy, .. } => uy > 0.0,
        };
        if !(width_ok && line_ok) || self.dominated(&w, fr.l, fr.v[0], fr.v[1]) {
            return;
        }
        let key = w.front.min_on(w.b0, w.b1);
        if key.is_finite() {
            self.push(key, Event::Window(w));
        }
    }

    /// Seeds a window over `[b0, b1]` of the edge in slot `k` of `g`, crossing into the face
    /// beyond; `make` builds the front in that half-edge's frame.
    fn seed_edge(&mut self, g: usize, k: usize, make: &dyn Fn(&Frame) -> Vec<Seed>) {
        let Some((h, j)) = self.twin(g, k) else {
            return;
        };
        let Some(fr) = self.frame(h, j) else {
            return;
        };
        for (b0, b1, front) in make(&fr) {
            let w = Window {
                face: h as u32,
                slot: j as u8,
                b0: b0.max(0.0),
                b1: b1.min(fr.l),
                front,
            };
            self.offer(w, &fr);
        }
    }

    /// Source piece `p → q` lying in face `g`: distances of its corners, and windows on its
    /// edges (line windows where the foot point is inside the piece, point windows from
    /// its ends where the end is the nearest point of the piece and of its neighbour).
    fn seed_piece(&mut self, piece: &Piece) {
        let (g, p, q) = (piece.face, piece.p, piece.q);
        let mesh = self.surface.mesh;
        let t = mesh.triangles()[g];
        for v in t {
            let v = v as usize;
            let x = mesh.positions()[v];
            let at_end = (x - p).norm().min((x - q).norm()) <= ON_LINE_TOLERANCE * self.scale;
            let (d, _) = segment_distance(&x, &p, &q);
            let foot = {
                let e = q - p;
                let t = if e.norm_squared() > 0.0 {
                    ((x - p).dot(&e) / e.norm_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                p + e * t
            };
            let back = (d > ON_LINE_TOLERANCE * self.scale).then(|| (g, foot - x));
            self.reach(v, d, at_end, back);
        }
        if self.degenerate[g] {
            return;
        }
        for k in 0..3 {
            let pd = mesh.positions()[t[(k + 2) % 3] as usize];
            self.seed_edge(g, k, &|fr: &Frame| {
                let (p2, q2) = (fr.unfold(&p), fr.unfold(&q));
                // A direction of g's plane in this frame (g lies at y < 0).
                let w = pd - fr.a;
                let ng = (w - fr.ex * w.dot(&fr.ex)).try_normalize(0.0);
                let flat = |d: Vector3| ng.map(|n| [d.dot(&fr.ex), -d.dot(&n)]);
                let s = [q2[0] - p2[0], q2[1] - p2[1]];
                let len = s[0].hypot(s[1]);
                if len <= ON_LINE_TOLERANCE * fr.l {
                    return vec![(0.0, fr.l, point(p2, 0.0))];
                }
                let s = [s[0] / len, s[1] / len];
                // The foot on the line pq of edge point x is at τ(x) = ((x − p)·s) / |pq|:
                // p is the nearest point of the piece where τ ≤ 0, q where τ ≥ 1, the line
                // between (one window each: the distance to a segment).
                let none = (Real::INFINITY, Real::NEG_INFINITY);
                let line = match half_line(p2, s, 1.0) {
                    Some(a) => meet(a, half_line(q2, s, -1.0).unwrap_or(none)),
                    None => none,
                };
                let mut near_p = half_line(p2, s, -1.0).unwrap_or(none);
                let mut near_q = half_line(q2, s, 1.0).unwrap_or(none);
                // An end is the nearest point of the neighbouring piece too only where the
                // neighbour's foot falls beyond it.
                if let Some(d) = piece.before.and_then(flat) {
                    near_p = meet(near_p, half_line(p2, d, 1.0).unwrap_or(none));
                }
                if let Some(d) = piece.after.and_then(flat) {
                    near_q = meet(near_q, half_line(q2, d, -1.0).unwrap_or(none));
                }
                if !piece.seed_p {
                    near_p = none;
                }
                let mut out = Vec::new();
                for (range, end) in [(near_p, p2), (near_q, q2)] {
                    let (lo, hi) = (range.0.max(0.0), range.1.min(fr.l));
                    if hi - lo > MIN_WIDTH * fr.l {
                        out.push((lo, hi, point(end, 0.0)));
                    }
                }
                let (mut lo, mut hi) = line;
                lo = lo.max(0.0);
                hi = hi.min(fr.l);
                // The line pq crosses the edge's line: split, the normal flips there.
                let mut cuts = vec![lo];
                if s[1].abs() > ON_LINE_TOLERANCE {
                    let xs = p2[0] - p2[1] * s[0] / s[1];
                    if xs > lo && xs < hi {
                        cuts.push(xs);
                    }
                }
                cuts.push(hi);
                for w in cuts.windows(2) {
                    if w[1] - w[0] <= MIN_WIDTH * fr.l {
                        continue;
                    }
                    let m = [0.5 * (w[0] + w[1]) - p2[0], -p2[1]];
                    let mut n = [-s[1], s[0]];
                    let side = dot(n, m);
                    if side < -ON_LINE_TOLERANCE * fr.l
                        || (side.abs() <= ON_LINE_TOLERANCE * fr.l && n[1] < 0.0)
                    {
                        n = [-n[0], -n[1]];
                    }
                    if n[1] > ON_LINE_TOLERANCE {
                        let c = -dot(n, p2);
                        out.push((
                            w[0],
                            w[1],
                            Front::Line {
                                ux: n[0],
                                uy: n[1],
                                c,
                            },
                        ));
                    }
                }
                out
            });
        }
    }

    /// A pseudo-source at `v`: its neighbours along edges, and a point window on the edge
    /// opposite `v` in each of its faces, limited to the shadow of the arriving path when
    /// it is known (see [`Solver::shadow`]).
    fn spawn(&mut self, v: usize) {
        let d = self.dist[v];
        let surface = self.surface;
        let mesh = surface.mesh;
        let pv = mesh.positions()[v];
        for &g in surface.faces_of(v) {
            let t = mesh.triangles()[g as usize];
            for w in t {
                let w = w as usize;
                if w != v {
                    let pw = mesh.positions()[w];
                    self.reach(w, d + (pw - pv).norm(), false, Some((g as usize, pv - pw)));
                }
            }
        }
        let wedges = match self.shadow(v) {
            Some(w) => w,
            None => surface
                .faces_of(v)
                .iter()
                .filter_map(|&g| {
                    let t = mesh.triangles()[g as usize];
                    let kv = t.iter().position(|&x| x as usize == v)?;
                    Some((g as usize, (kv + 1) % 3, None))
                })
                .collect(),
        };
        for (g, k, points) in wedges {
            if self.degenerate[g] {
                continue;
            }
            self.seed_edge(g, k, &|fr: &Frame| {
                let s = point(fr.unfold(&pv), d);
                match points {
                    None => vec![(0.0, fr.l, s)],
                    Some((x0, x1)) => {
                        let (a, b) = ((x0 - fr.a).dot(&fr.ex), (x1 - fr.a).dot(&fr.ex));
                        vec![(a.min(b), a.max(b), s)]
                    }
                }
            });
        }
    }

    /// The shadow of saddle `v`: geodesics bend at a vertex only when both angles between
    /// the arriving and the leaving direction are at least π (Mitchell, Mount & Papadimitriou
    /// 1987, Lemma 3.4), so the windows of a pseudo-source need only cover the directions
    /// whose angle from the arriving path, measured around the fan either way, is ≥ π (ICH
    /// spawns over the whole fan; this is MMP's restriction). Returns, per face of the fan
    /// that the shadow enters, the slot of the edge opposite `v` and the two points of that
    /// edge bounding the shadow; `None` (no restriction) for a vertex on the boundary, with
    /// a degenerate or non-manifold fan, or with no known arriving direction.
    #[allow(clippy::type_complexity)]
    fn shadow(&self, v: usize) -> Option<Vec<(usize, usize, Option<(Point3, Point3)>)>> {
        let (f0, back) = self.back[v]?;
        let mesh = self.surface.mesh;
        let pos = mesh.positions();
        let pv = pos[v];
        let degree = self.surface.faces_of(v).len();
        // Walk the fan from f0: (face, w_in, w_out, angle at the start of the face, angle).
        let mut fan = Vec::with_capacity(degree);
        let t0 = mesh.triangles()[f0 as usize];
        let k0 = t0.iter().position(|&x| x as usize == v)?;
        let (mut face, mut w_in, mut w_out) = (
            f0 as usize,
            t0[(k0 + 1) % 3] as usize,
            t0[(k0 + 2) % 3] as usize,
        );
        let mut total = 0.0;
        loop {
            if self.degenerate[face] || fan.len() >= degree {
                return None;
            }
            let alpha = angle_between(&(pos[w_in] - pv), &(pos[w_out] - pv));
            fan.push((face, w_in, w_out, total, alpha));
            total += alpha;
            let t = mesh.triangles()[face];
            let k = (0..3).find(|&k| {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                (a == v && b == w_out) || (a == w_out && b == v)
            })?;
            let next = self.surface.across(face, k)?;
            if next == f0 as usize {
                break;
            }
            let tn = mesh.triangles()[next];
            let new_out = tn
                .iter()
                .map(|&x| x as usize)
                .find(|&x| x != v && x != w_out)?;
            (face, w_in, w_out) = (next, w_out, new_out);
        }
        if fan.len() != degree || total <= 2.0 * std::f64::consts::PI {
            return None;
        }
        let (_, a_in, _, _, alpha0) = fan[0];
        let phi0 = angle_between(&(pos[a_in] - pv), &back).clamp(0.0, alpha0);
        let pi = std::f64::consts::PI;
        let (lo, hi) = (
            phi0 + pi - SHADOW_ANGLE_TOLERANCE,
            phi0 + total - pi + SHADOW_ANGLE_TOLERANCE,
        );
        let mut out = Vec::new();
        for &(g, w_in, w_out, start, alpha) in &fan {
            for shift in [0.0, total] {
                let (a, b) = (
                    (lo - shift - start).max(0.0),
                    (hi - shift - start).min(alpha),
                );
                if a > b {
                    continue;
                }
                // Rays from v at angles a, b from v→w_in meet the edge w_in → w_out.
                let (e_in, e_out) = (pos[w_in] - pv, pos[w_out] - pv);
                let l_in = e_in.norm();
                let (ox, oy) = (e_out.dot(&e_in) / l_in, e_out.cross(&e_in).norm() / l_in);
                let on_edge = |psi: Real| -> Option<Point3> {
                    let d = [libm::cos(psi), libm::sin(psi)];
                    let e = [ox - l_in, oy];
                    let den = cross(d, e);
                    let lambda = (-cross(d, [l_in, 0.0]) / den).clamp(0.0, 1.0);
                    lambda
                        .is_finite()
                        .then(|| pos[w_in] + (pos[w_out] - pos[w_in]) * lambda)
                };
                let t = mesh.triangles()[g];
                let kv = t.iter().position(|&x| x as usize == v)?;
                if let (Some(x0), Some(x1)) = (on_edge(a), on_edge(b)) {
                    out.push((g, (kv + 1) % 3, Some((x0, x1))));
                }
            }
        }
        Some(out)
    }

    /// Propagates window `w` across its face into children on the two far edges.
    fn propagate(&mut self, w: Window) {
        let (f, k) = (w.face as usize, w.slot as usize);
        let Some(fr) = self.frame(f, k) else {
            return;
        };
        let w = Window {
            b1: w.b1.min(fr.l),
            ..w
        };
        if self.dominated(&w, fr.l, fr.v[0], fr.v[1]) {
            return;
        }
        let (l, c) = (fr.l, fr.c);
        let vc = fr.v[2];
        if self.degenerate[f] {
            // No window crosses a flat face: reach its far corner along straight lines.
            for x in [w.b0, w.b1] {
                let d = w.front.at(x, 0.0) + (c[0] - x).hypot(c[1]);
                self.reach(vc, d, false, None);
            }
            return;
        }
        let tol = RAY_TOLERANCE * l;
        // The direction from C back along the ray that reaches it, in 3D.
        let back = {
            let pc = self.surface.mesh.positions()[vc];
            let ey = (pc - fr.a - fr.ex * c[0]) / c[1];
            let b = match w.front {
                Front::Point { sx, sy, .. } => [sx - c[0], sy - c[1]],
                Front::Line { ux, uy, .. } => [-ux, -uy],
            };
            Some((f, fr.ex * b[0] + ey * b[1]))
        };
        if let Front::Point { sx, sy, .. } = w.front {
            if sy >= -ON_LINE_TOLERANCE * l {
                // A source on the edge itself: rays in every direction into the face.
                if sx >= w.b0 - tol && sx <= w.b1 + tol {
                    self.reach(vc, w.front.at(c[0], c[1]), false, back);
                    self.child(&fr, &w, (k + 2) % 3, [c, [0.0, 0.0]]);
                    self.child(&fr, &w, (k + 1) % 3, [[l, 0.0], c]);
                }
                return;
            }
        }
        // Where the ray through C crosses the edge.
        let xc = match w.front {
            Front::Point { sx, sy, .. } => sx + (c[0] - sx) * (-sy) / (c[1] - sy),
            Front::Line { ux, uy, .. } => c[0] - ux * c[1] / uy,
        };
        if !xc.is_finite() {
            return;
        }
        let fc = w.front.at(c[0], c[1]);
        if xc >= w.b0 - tol && xc <= w.b1 + tol {
            self.reach_via(vc, fc, false, back, Some((f, xc)));
        }
        // One angle, one split (Chen & Han 1990, generalised): when a shorter path reached C
        // through this face, crossing the edge at q, a ray of this window crossing the edge
        // beyond q (towards B) and ending on CA meets that path's segment q → C at some Z
        // (chords of the triangle with interleaved ends), and d(Z) via the other path is
        // shorter (both distances are 1-Lipschitz, the other is shorter at C): the other
        // path then beats this window at its end. Symmetrically on CB before q.
        let (mut left_end, mut right_start) = (w.b1.min(xc), w.b0.max(xc));
        if let Some((vf, q)) = self.via[vc] {
            let slack = FILTER_TOLERANCE * fc.max(self.scale);
            if vf as usize == f && self.dist[vc] < fc - slack {
                left_end = left_end.min(q);
                right_start = right_start.max(q);
            }
        }
        // Where the ray through edge point x meets segment p0 → p1 (parameter in [0, 1]).
        let hit = |x: Real, p0: [Real; 2], p1: [Real; 2]| -> Option<[Real; 2]> {
            let d = w.front.ray(x);
            let e = [p1[0] - p0[0], p1[1] - p0[1]];
            let t = (cross(d, [x - p0[0], -p0[1]]) / cross(d, e)).clamp(0.0, 1.0);
            t.is_finite().then(|| [p0[0] + t * e[0], p0[1] + t * e[1]])
        };
        // Left: edge C → A (slot k + 2) gets the rays through [b0, min(b1, xc)].
        if w.b0 < left_end {
            let x1 = left_end;
            let q0 = if w.b0 <= 0.0 {
                Some([0.0, 0.0])
            } else {
                hit(w.b0, [0.0, 0.0], c)
            };
            let q1 = if x1 >= xc {
                Some(c)
            } else {
                hit(x1, [0.0, 0.0], c)
            };
            if let (Some(q0), Some(q1)) = (q0, q1) {
                self.child(&fr, &w, (k + 2) % 3, [q0, q1]);
            }
        }
        // Right: edge B → C (slot k + 1) gets the rays through [max(b0, xc), b1].
        if w.b1 > right_start {
            let x0 = right_start;
            let q0 = if x0 <= xc {
                Some(c)
            } else {
                hit(x0, c, [l, 0.0])
            };
            let q1 = if w.b1 >= l {
                Some([l, 0.0])
            } else {
                hit(w.b1, c, [l, 0.0])
            };
            if let (Some(q0), Some(q1)) = (q0, q1) {
                self.child(&fr, &w, (k + 1) % 3, [q0, q1]);
            }
        }
    }

    /// The child of `w` on the edge in slot `j` of its face, covering the segment `q` (two
    /// points of that edge in the frame `fr`), moved to the frame of the face beyond.
    fn child(&mut self, fr: &Frame, w: &Window, j: usize, q: [[Real; 2]; 2]) {
        let Some((h, jh)) = self.twin(w.face as usize, j) else {
            return;
        };
        let Some(nf) = self.frame(h, jh) else {
            return;
        };
        let idx = |v: usize| fr.v.iter().position(|&x| x == v);
        let (Some(ia), Some(ib)) = (idx(nf.v[0]), idx(nf.v[1])) else {
            return;
        };
        let (o, pb, third) = (fr.corner(ia), fr.corner(ib), fr.corner(3 - ia - ib));
        let e = [pb[0] - o[0], pb[1] - o[1]];
        let len = e[0].hypot(e[1]);
        if len.is_nan() || len <= 0.0 {
            return;
        }
        let ex = [e[0] / len, e[1] / len];
        let mut ey = [-ex[1], ex[0]];
        // The face the window comes from lies at y < 0 in the new frame.
        if dot([third[0] - o[0], third[1] - o[1]], ey) > 0.0 {
            ey = [-ey[0], -ey[1]];
        }
        let x = |p: [Real; 2]| dot([p[0] - o[0], p[1] - o[1]], ex);
        let (x0, x1) = (x(q[0]), x(q[1]));
        let front = w.front.in_frame(o, ex, ey);
        if let Front::Point { sy, .. } = front {
            if sy >= -ON_LINE_TOLERANCE * nf.l {
                return; // rays along the edge: nothing crosses it
            }
        }
        let child = Window {
            face: h as u32,
            slot: jh as u8,
            b0: x0.min(x1).max(0.0),
            b1: x0.max(x1).min(nf.l),
            front,
        };
        self.offer(child, &nf);
    }
}

/// The edge points `(x, 0)` with `sign · (x − a)·d ≥ 0` as an x-range (`None` if empty).
fn half_line(a: [Real; 2], d: [Real; 2], sign: Real) -> Option<(Real, Real)> {
    let (inf, c) = (Real::INFINITY, -a[1] * d[1] - a[0] * d[0]);
    // sign · (x·dx + c) ≥ 0.
    let dx = sign * d[0];
    let c = sign * c;
    if dx.abs() <= ON_LINE_TOLERANCE {
        return (c >= 0.0).then_some((-inf, inf));
    }
    let x = -c / dx;
    Some(if dx > 0.0 { (x, inf) } else { (-inf, x) })
}

fn meet(a: (Real, Real), b: (Real, Real)) -> (Real, Real) {
    (a.0.max(b.0), a.1.min(b.1))
}

fn point(s: [Real; 2], sigma: Real) -> Front {
    Front::Point {
        sx: s[0],
        sy: s[1].min(0.0),
        sigma,
    }
}

/// Exact geodesic distance per vertex from `source` on the active faces; `max_windows`
/// overrides the default cap on windows processed.
pub(crate) fn propagate(
    surface: &Surface,
    source: &ResolvedSource,
    max_windows: Option<u64>,
    progress: Progress,
) -> Result<(Vec<Real>, Stats), GeodesicError> {
    let mut s = Solver::new(surface);
    for &v in &source.vertices {
        s.reach(v as usize, 0.0, true, None);
    }
    for curve in &source.curves {
        for piece in curve_pieces(surface, curve) {
            s.seed_piece(&piece);
        }
    }
    if s.heap.is_empty() {
        return Err(GeodesicError::SourceMissesSurface(
            "no window could be seeded from the source".into(),
        ));
    }
    let edges = 3 * surface.faces.len() as u64 / 2;
    let growth = (edges as Real / CAP_EDGES).sqrt().max(1.0);
    let cap =
        max_windows.unwrap_or((WINDOWS_PER_EDGE * growth * edges as Real) as u64 + WINDOW_CAP_BASE);
    let max_queue = MAX_QUEUE_BYTES / std::mem::size_of::<Item>();
    let active_vertices = (0..surface.mesh.vertex_count())
        .filter(|&v| !surface.faces_of(v).is_empty())
        .count()
        .max(1);
    let mut stats = Stats::default();
    let mut popped = 0u64;
    // Each pop processes one event; events are bounded by the cap below, so the loop ends.
    while let Some(item) = s.heap.pop() {
        popped += 1;
        if popped > cap {
            return Err(GeodesicError::LimitExceeded(format!(
                "more than {cap} windows (max_windows) were processed on {edges} edges; \
                 the mesh may have degenerate faces"
            )));
        }
        if s.heap.len() > max_queue {
            return Err(GeodesicError::LimitExceeded(format!(
                "more than {max_queue} windows ({MAX_QUEUE_BYTES} bytes) are pending"
            )));
        }
        if popped % PROGRESS_EVERY as u64 == 0 {
            let reached = s.dist.iter().filter(|d| d.is_finite()).count();
            progress("distance", reached as f64 / active_vertices as f64);
        }
        match item.event {
            Event::Vertex(v) => {
                // A pseudo-source improved later has a newer event; a forced one (a source
                // vertex) restarts in any case.
                if s.dist[v as usize] >= item.key || !s.pseudo[v as usize] {
                    s.spawn(v as usize);
                }
            }
            Event::Window(w) => {
                stats.windows += 1;
                s.propagate(w);
            }
        }
    }
    progress("distance", 1.0);
    Ok((s.dist, stats))
}
