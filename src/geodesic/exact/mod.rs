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
//!         distance to the source curve (straight in every face it crosses) up to rounding.
//! Cost:   O(W log W) time for W windows, memory O(V + F) plus the pending windows (about
//!         the wavefront). W = O(n²) in the worst case for CH/ICH; measured (native release
//!         build, `examples/geodesic_exact.rs`): developable meshes 4–6 windows per edge
//!         (cylinder ring or generator source, 200k triangles: 0.5–0.8 s; 2M triangles: 11 s,
//!         250 MB); the steep height field of the tests 22, 40, 76 windows per edge at 1,
//!         0.5, 0.25 mm edges (0.1, 0.6–1.5, 7–9 s), i.e. W ≈ n^1.5 as reported for MMP/ICH
//!         on curved meshes. About ten times the unfolding method's time on a cylinder.
//! Deviations:
//!   - The source is a curve, not points: each piece of the source polyline lying in a face
//!     seeds *line windows* (a plane wave `u·x + c`, rays parallel to the unit `u`) where the
//!     foot point of an edge point falls inside the piece, and point windows from its ends
//!     only where that end is the nearest point of the piece and of its neighbour (the
//!     convex side of a bend); the vertices of the face get their in-plane distance to the
//!     piece (`pieces.rs` cuts the curve into pieces; no paper).
//!   - The filter (ICH's idea, in a form proven here): a window on edge `AB` is dropped when
//!     `d(A) + |A b1| < d_w(b1)` or `d(B) + |B b0| < d_w(b0)`. Distance along an edge is
//!     1-Lipschitz for any window, so either inequality at the far end of the interval
//!     holds at every point of it: the window never carries a shortest path. It is applied
//!     when a child is made (with the child's own edge, whose ends include the parent's
//!     opposite vertex) and again when the window is taken from the queue.
//!   - Chen & Han's "one angle, one split", generalised to any window crossing the face
//!     through which a shorter path reached the opposite vertex (see `propagate`), and
//!     MMP's restriction of a pseudo-source to the shadow of the path that reached it (see
//!     `pseudo.rs`); ICH spawns pseudo-sources over the whole fan.
//!   - Degenerate faces (height below `DEGENERATE_HEIGHT_RATIO` of the longest edge) pass no
//!     windows; their vertices act as pseudo-sources and reach each other along edges. A
//!     source sample on a vertex makes it a pseudo-source.
//!   - An edge of three or more faces (a fin or a sliver glued on along it) passes a window
//!     on into every other active face on it (no paper: CH/ICH assume a manifold). Before,
//!     a path could enter such a face only through the edge's ends: on a generated aircraft
//!     a sliver's corner 0.115 m too far. The windows are the same in every face beyond, so
//!     when the first face's are dominated the others are not looked at (a book of `n`
//!     pages: `n²` refused windows otherwise, from its corners' pseudo-sources).
//!   - Rounding: a vertex within `RAY_TOLERANCE` of a window's border ray is reached by it
//!     (neighbouring windows meet exactly on such rays; without slack a vertex there can fall
//!     between them).
//!   - A cap on windows processed (`64·√max(1, E/10⁴)` per edge for `E` edges, plus 2²⁰,
//!     unless given) and on the queue's memory returns [`GeodesicError::LimitExceeded`].

use super::params::{GeodesicError, Progress, PROGRESS_EVERY};
use super::source::ResolvedSource;
use super::surface::Surface;
use crate::math::{angle_between, Real, Vector3, DEGENERATE_HEIGHT_RATIO};

mod front;
mod pieces;
mod pseudo;
mod seed;

use front::{cross, dot, norm2, Event, Frame, Front, Item, Queue, Window};
use pieces::curve_pieces;

/// Windows processed per mesh edge (on meshes up to `CAP_EDGES` edges) before the default cap
/// stops the computation.
const WINDOWS_PER_EDGE: Real = 64.0;
/// Beyond this many edges the per-edge allowance grows as √(edges / CAP_EDGES): window
/// counts per edge of CH/ICH grow about as √n on curved meshes (measured here: 22, 40, 76
/// per edge on the 1, 0.5, 0.25 mm height field).
const CAP_EDGES: Real = 1e4;
/// Windows always allowed on top of the per-edge allowance.
const WINDOW_CAP_BASE: u64 = 1 << 20;
/// A run that may give up early (the accurate method's exact try, `field.rs`) stops once its
/// windows exceed this many times the cap times the share of vertices reached: on course
/// for that much more than the cap if the windows per vertex reached held. They grow as the
/// front moves out, so runs that finish within the cap stay below it (on whole aircraft
/// models from a vertex, at most 1.0 times the cap at any point), and a wing-body model from
/// its vertex 0 (161 windows per face in all) with a cap of 64 per face stops at 26.
const PROJECTED_OVERRUN: Real = 1.1;
/// ...once the windows are at least this share of the cap (the first rings around a source
/// take many windows per vertex reached).
const PROJECTED_START: Real = 0.125;
/// Width of a band of the window queue, in mean edge lengths (speed only: the order is the
/// same for any width).
const QUEUE_BAND: Real = 1.0 / 32.0;
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

/// Statistics of one run.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Stats {
    /// Windows taken from the queue (those the filter then drops included).
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
    heap: Queue,
    /// The events the heap entries point to, and the free places among them.
    events: Vec<Event>,
    free: Vec<u32>,
    seq: u64,
    scale: Real,
    /// Vertices with a finite distance (for progress).
    reached: usize,
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
            heap: Queue::new((QUEUE_BAND * surface.mean_edge).max(Real::MIN_POSITIVE)),
            events: Vec::new(),
            free: Vec::new(),
            seq: 0,
            scale: surface.mean_edge.max(Real::MIN_POSITIVE),
            reached: 0,
        }
    }

    fn push(&mut self, key: Real, event: Event) {
        self.seq += 1;
        let slot = match self.free.pop() {
            Some(i) => {
                self.events[i as usize] = event;
                i
            }
            None => {
                self.events.push(event);
                (self.events.len() - 1) as u32
            }
        };
        self.heap.push(Item {
            key,
            seq: self.seq,
            slot,
        });
    }

    /// The next event and its key, in key order.
    fn pop(&mut self) -> Option<(Real, Event)> {
        let item = self.heap.pop()?;
        self.free.push(item.slot);
        Some((item.key, self.events[item.slot as usize]))
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
            if self.dist[v] == Real::INFINITY {
                self.reached += 1;
            }
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

    /// The faces across slot `k` of `f`, each with the slot of the same edge there: the
    /// face beyond a manifold edge, or every other active face on an edge of three or more
    /// faces (a path may go on into any of them: a fin glued on along that edge, a sliver).
    fn twins(&self, f: usize, k: usize) -> Twins<'a> {
        let surface: &'a Surface<'a> = self.surface;
        if let Some(h) = surface.across(f, k) {
            let t = self.surface.mesh.triangles()[f];
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let th = self.surface.mesh.triangles()[h];
            return Twins::One((0..3).find_map(|j| {
                let (c, d) = (th[j], th[(j + 1) % 3]);
                ((c == a && d == b) || (c == b && d == a)).then_some((h, j))
            }));
        }
        // Last first (the order they were once taken from a list), and not gathered: an edge
        // of `n` faces whose first twin settles the matter costs one, not `n`.
        Twins::Many(Box::new(surface.books().others(f, k).rev()))
    }

    /// True when an end of the window's edge beats the window over its whole interval.
    fn dominated(&self, w: &Window, l: Real, a: usize, b: usize) -> bool {
        self.dominated_by(w, l, a, b, 1.0)
    }

    /// [`Solver::dominated`] by more than `margin` times the filter's tolerance.
    fn dominated_by(&self, w: &Window, l: Real, a: usize, b: usize, margin: Real) -> bool {
        let (f0, f1) = (w.front.at(w.b0, 0.0), w.front.at(w.b1, 0.0));
        let tol = margin * FILTER_TOLERANCE * f0.max(f1).max(self.scale);
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
            // A flat face is a segment (no paper): its far corner is reached along it, and
            // the rays pass straight on into the faces beyond its other two edges, which lie
            // on the same line, over the part of the window each edge covers.
            for x in [w.b0, w.b1, c[0].clamp(w.b0, w.b1)] {
                let d = w.front.at(x, 0.0) + norm2(c[0] - x, c[1]);
                self.reach(vc, d, false, None);
            }
            for (j, ends) in [((k + 2) % 3, [0.0, c[0]]), ((k + 1) % 3, [c[0], l])] {
                let lo = ends[0].min(ends[1]).max(w.b0);
                let hi = ends[0].max(ends[1]).min(w.b1);
                if hi > lo {
                    self.child(&fr, &w, j, [[lo, 0.0], [hi, 0.0]]);
                }
            }
            return;
        }
        let tol = RAY_TOLERANCE * l;
        // The direction from C back along the ray that reaches it, in 3D.
        let pc = self.surface.mesh.positions()[vc];
        let back = || {
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
                    let (d, back) = (w.front.at(c[0], c[1]), back());
                    self.reach(vc, d, false, back);
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
        if xc >= w.b0 - tol && xc <= w.b1 + tol && fc < self.dist[vc] {
            self.reach_via(vc, fc, false, back(), Some((f, xc)));
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
        for (h, jh) in self.twins(w.face as usize, j) {
            self.child_in(fr, w, (h, jh), q);
        }
    }

    /// [`Solver::child`] into the face `h`, whose slot `jh` is the edge.
    fn child_in(&mut self, fr: &Frame, w: &Window, (h, jh): (usize, usize), q: [[Real; 2]; 2]) {
        let Some(nf) = self.frame(h, jh) else {
            return;
        };
        let idx = |v: usize| fr.v.iter().position(|&x| x == v);
        let (Some(ia), Some(ib)) = (idx(nf.v[0]), idx(nf.v[1])) else {
            return;
        };
        let (o, pb, third) = (fr.corner(ia), fr.corner(ib), fr.corner(3 - ia - ib));
        let e = [pb[0] - o[0], pb[1] - o[1]];
        let len = norm2(e[0], e[1]);
        if len.is_nan() || len <= 0.0 {
            return;
        }
        let ex = [e[0] / len, e[1] / len];
        let mut ey = [-ex[1], ex[0]];
        // The face the window comes from lies at y < 0 in the new frame; a flat face has no
        // inside: the face beyond lies ahead of the window (y > 0 in the old frame).
        let flip = if self.degenerate[w.face as usize] {
            ey[1] < 0.0
        } else {
            dot([third[0] - o[0], third[1] - o[1]], ey) > 0.0
        };
        if flip {
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

/// The faces across an edge ([`Solver::twins`]): one (or none) across a manifold edge,
/// any number across an edge of three or more faces.
enum Twins<'a> {
    One(Option<(usize, usize)>),
    Many(Box<dyn Iterator<Item = (usize, usize)> + 'a>),
}

impl Iterator for Twins<'_> {
    type Item = (usize, usize);

    fn next(&mut self) -> Option<(usize, usize)> {
        match self {
            Twins::One(one) => one.take(),
            Twins::Many(many) => many.next(),
        }
    }
}

/// Exact geodesic distance per vertex from `source` on the active faces; `max_windows`
/// overrides the default cap on windows processed. With `projected`, the run also stops as
/// soon as it is on course for more than [`PROJECTED_OVERRUN`] times the cap (see there).
pub(crate) fn propagate(
    surface: &Surface,
    source: &ResolvedSource,
    max_windows: Option<u64>,
    projected: bool,
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
    if s.heap.len() == 0 {
        return Err(GeodesicError::SourceMissesSurface(
            "no window could be seeded from the source".into(),
        ));
    }
    let edges = 3 * surface.faces.len() as u64 / 2;
    let growth = (edges as Real / CAP_EDGES).sqrt().max(1.0);
    let cap =
        max_windows.unwrap_or((WINDOWS_PER_EDGE * growth * edges as Real) as u64 + WINDOW_CAP_BASE);
    let max_queue = MAX_QUEUE_BYTES / (std::mem::size_of::<Item>() + std::mem::size_of::<Event>());
    let active_vertices = (0..surface.mesh.vertex_count())
        .filter(|&v| !surface.faces_of(v).is_empty())
        .count()
        .max(1);
    let mut stats = Stats::default();
    let mut popped = 0u64;
    // Each pop processes one event; events are bounded by the cap below, so the loop ends.
    while let Some((key, event)) = s.pop() {
        popped += 1;
        if popped > cap {
            return Err(GeodesicError::LimitExceeded(format!(
                "more than {cap} windows (max_windows) were processed on {edges} edges: the \
                 exact method needs more here (a source through a row of vertices, a finely \
                 curved surface, degenerate faces); the accurate method answers such cases"
            )));
        }
        if s.heap.len() > max_queue {
            return Err(GeodesicError::LimitExceeded(format!(
                "more than {max_queue} windows ({MAX_QUEUE_BYTES} bytes) are pending"
            )));
        }
        if popped % PROGRESS_EVERY as u64 == 0 {
            let reached = s.reached as f64 / active_vertices as f64;
            if projected
                && popped as f64 > PROJECTED_START * cap as f64
                && popped as f64 > PROJECTED_OVERRUN * cap as f64 * reached
            {
                return Err(GeodesicError::LimitExceeded(format!(
                    "{popped} windows (max_windows {cap}) reached {:.0} % of the vertices",
                    100.0 * reached
                )));
            }
            progress("distance", reached);
        }
        match event {
            Event::Vertex(v) => {
                // A pseudo-source improved later has a newer event; a forced one (a source
                // vertex) restarts in any case.
                if s.dist[v as usize] >= key || !s.pseudo[v as usize] {
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
