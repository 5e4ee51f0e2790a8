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
//!   - A cap on windows processed (`64 × edges + 2²⁰` unless given) and on the queue's memory
//!     returns [`GeodesicError::LimitExceeded`].

use super::params::{GeodesicError, Progress, PROGRESS_EVERY};
use super::source::ResolvedSource;
use super::surface::{segment_distance, Surface};
use crate::math::{angle_between, Point3, Real, Vector3, DEGENERATE_HEIGHT_RATIO};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

mod pieces;
use pieces::curve_pieces;

/// Windows processed per mesh edge before the default cap stops the computation.
pub(crate) const WINDOWS_PER_EDGE: u64 = 64;
/// Windows always allowed on top of the per-edge allowance.
const WINDOW_CAP_BASE: u64 = 1 << 20;
/// Memory of the pending-window queue allowed, bytes.
const MAX_QUEUE_BYTES: usize = 1 << 30;
/// A point source closer than this (relative to the edge length) to an edge's line lies on it.
const ON_LINE_TOLERANCE: Real = 1e-10;
/// Slack (relative to the edge length) for a vertex on the border ray of a window.
const RAY_TOLERANCE: Real = 1e-12;
/// Windows narrower than this (relative to the edge length) are dropped.
const MIN_WIDTH: Real = 1e-12;
/// Relative margin of the filter: a window is dropped only when beaten by more than this.
const FILTER_TOLERANCE: Real = 1e-12;
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
        o.key.total_cmp(&self.key).then_with(|| o.seq.cmp(&self.seq))
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

    /// Lowers the distance of `v` to `d`; a pseudo-source vertex (or any vertex if `force`)
    /// then restarts the propagation. NaN never passes the comparison.
    fn reach(&mut self, v: usize, d: Real, force: bool) {
        if d < self.dist[v] {
            self.dist[v] = d;
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
    fn seed_edge(&mut self, g: usize, k: usize, make: &dyn Fn(&Frame) -> Vec<(Real, Real, Front)>) {
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
    /// both ends).
    fn seed_piece(&mut self, g: usize, p: Point3, q: Point3) {
        let mesh = self.surface.mesh;
        let t = mesh.triangles()[g];
        for v in t {
            let v = v as usize;
            let x = mesh.positions()[v];
            let at_end = (x - p).norm().min((x - q).norm()) <= ON_LINE_TOLERANCE * self.scale;
            self.reach(v, segment_distance(&x, &p, &q).0, at_end);
        }
        if self.degenerate[g] {
            return;
        }
        for k in 0..3 {
            self.seed_edge(g, k, &|fr: &Frame| {
                let (p2, q2) = (fr.unfold(&p), fr.unfold(&q));
                let mut out = vec![(0.0, fr.l, point(p2, 0.0))];
                let s = [q2[0] - p2[0], q2[1] - p2[1]];
                let len = s[0].hypot(s[1]);
                if len <= ON_LINE_TOLERANCE * fr.l {
                    return out;
                }
                out.push((0.0, fr.l, point(q2, 0.0)));
                let s = [s[0] / len, s[1] / len];
                // Edge points whose foot on the line pq is inside the piece.
                let (mut lo, mut hi) = if s[0].abs() <= ON_LINE_TOLERANCE {
                    let tau = (-p2[1] * s[1]) / len;
                    if (0.0..=1.0).contains(&tau) {
                        (0.0, fr.l)
                    } else {
                        return out;
                    }
                } else {
                    let x0 = p2[0] + p2[1] * s[1] / s[0];
                    let x1 = p2[0] + (len + p2[1] * s[1]) / s[0];
                    (x0.min(x1), x0.max(x1))
                };
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
    /// opposite `v` in each of its faces.
    fn spawn(&mut self, v: usize) {
        let d = self.dist[v];
        let surface = self.surface;
        let mesh = surface.mesh;
        let pv = mesh.positions()[v];
        for &g in surface.faces_of(v) {
            let g = g as usize;
            let t = mesh.triangles()[g];
            let Some(kv) = t.iter().position(|&x| x as usize == v) else {
                continue;
            };
            for w in [t[(kv + 1) % 3], t[(kv + 2) % 3]] {
                let w = w as usize;
                if w != v {
                    self.reach(w, d + (mesh.positions()[w] - pv).norm(), false);
                }
            }
            if self.degenerate[g] {
                continue;
            }
            self.seed_edge(g, (kv + 1) % 3, &|fr: &Frame| {
                vec![(0.0, fr.l, point(fr.unfold(&pv), d))]
            });
        }
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
                self.reach(vc, d, false);
            }
            return;
        }
        let tol = RAY_TOLERANCE * l;
        if let Front::Point { sx, sy, .. } = w.front {
            if sy >= -ON_LINE_TOLERANCE * l {
                // A source on the edge itself: rays in every direction into the face.
                if sx >= w.b0 - tol && sx <= w.b1 + tol {
                    self.reach(vc, w.front.at(c[0], c[1]), false);
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
        if xc >= w.b0 - tol && xc <= w.b1 + tol {
            self.reach(vc, w.front.at(c[0], c[1]), false);
        }
        // Where the ray through edge point x meets segment p0 → p1 (parameter in [0, 1]).
        let hit = |x: Real, p0: [Real; 2], p1: [Real; 2]| -> Option<[Real; 2]> {
            let d = w.front.ray(x);
            let e = [p1[0] - p0[0], p1[1] - p0[1]];
            let t = (cross(d, [x - p0[0], -p0[1]]) / cross(d, e)).clamp(0.0, 1.0);
            t.is_finite().then(|| [p0[0] + t * e[0], p0[1] + t * e[1]])
        };
        // Left: edge C → A (slot k + 2) gets the rays through [b0, min(b1, xc)].
        if w.b0 < xc {
            let x1 = w.b1.min(xc);
            let q0 = if w.b0 <= 0.0 {
                Some([0.0, 0.0])
            } else {
                hit(w.b0, [0.0, 0.0], c)
            };
            let q1 = if x1 >= xc { Some(c) } else { hit(x1, [0.0, 0.0], c) };
            if let (Some(q0), Some(q1)) = (q0, q1) {
                self.child(&fr, &w, (k + 2) % 3, [q0, q1]);
            }
        }
        // Right: edge B → C (slot k + 1) gets the rays through [max(b0, xc), b1].
        if w.b1 > xc {
            let x0 = w.b0.max(xc);
            let q0 = if x0 <= xc { Some(c) } else { hit(x0, c, [l, 0.0]) };
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
        if !(len > 0.0) {
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
        s.reach(v as usize, 0.0, true);
    }
    for curve in &source.curves {
        for (g, p, q) in curve_pieces(surface, curve) {
            s.seed_piece(g, p, q);
        }
    }
    if s.heap.is_empty() {
        return Err(GeodesicError::SourceMissesSurface(
            "no window could be seeded from the source".into(),
        ));
    }
    let edges = 3 * surface.faces.len() as u64 / 2;
    let cap = max_windows.unwrap_or(WINDOWS_PER_EDGE * edges + WINDOW_CAP_BASE);
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
