//! Geodesic distance per vertex by Dijkstra-ordered propagation of explicit virtual sources.
//!
//! Source: Trettner, Bommes & Kobbelt, "Geodesic distance computation via virtual source
//!         propagation" (SGP 2021, Computer Graphics Forum 40(5)): every vertex stores the
//!         virtual source it was reached from (a point unfolded into the plane of the face
//!         that reached it, plus a distance offset `σ`), vertices are settled in order of
//!         distance, and a settled vertex offers its neighbours `σ + |x − S|` with `S` moved
//!         into the plane of the face between them. The source is carried as geometry, never
//!         rebuilt from two distances (as in Novotni & Klein 2002, which `unfolding.rs` does),
//!         so errors do not grow with the distance from the source.
//! Input:  active faces, their vertex → face table, a resolved source (dense on-surface
//!         polylines and vertices).
//! Output: distance per vertex (`+∞` for vertices not reached), 0 on the source. Exact on
//!         cylinders and folded plates (every move of a source is an unfolding there);
//!         on doubly curved ones the error is second order in the edge length away from focal
//!         points. Near them (where fronts from a continuum of directions meet: the pole of a
//!         cap measured from its rim, the antipode of a point source on a sphere) a vertex is
//!         offered only its neighbours' sources, whose rays miss it: first order there.
//!         Around them `fronts.rs` interpolates between the sources the neighbours hold, and
//!         `focal.rs` reruns the propagation on nested subdivided patches at the focus
//!         itself. The tests check the orders and the focal error. Measured (`npm run
//!         bench -- geodesic`: WebAssembly in Node beside native fast marching, potpourri3d
//!         1.4.0; max / mean error in mm against the analytic distance): cap R 1000 from its
//!         rim, 500k triangles 0.0062 / 0.0009, 2M 0.0031 / 0.0002 (fast marching 1.8 / 0.10
//!         and 1.0 / 0.05); sphere R 100 from a point, 500k 0.0078 / 0.0006, 2M 0.0043 /
//!         0.00013 (fast marching 3.0 / 1.3 and 2.9 / 1.2); the cap from its section by
//!         the plane at θ = 0.6 (the accuracy example, native), 0.043 / 0.0028 and 0.0051 /
//!         0.0008. Time on a shared machine (one run), ratio to fast marching's solve: cap
//!         500k 0.85×, 2M 0.66×; sphere 500k 0.95×, 2M 0.82× (about 1.1 of the time
//!         without front interpolation at 500k, alternating the builds; fast marching itself
//!         moves by 10–15 % between runs). The bench times a first call in a fresh process:
//!         at 500k its fixed costs (the engine's baseline code in loops run once, memory
//!         growth) weigh most.
//! Cost:   O(V log V) time; memory O(V + F) (a source segment, its face and `σ` per vertex,
//!         a normal per face, the heap, the focal patches: at most a quarter of the faces
//!         again; front interpolation reuses the heap's memory), its worst case refused up
//!         front above 1 GiB (about 7M triangles): each vertex is settled once and offers
//!         each face around it twice.
//! Deviations (no paper):
//!   - A virtual source is a *segment* `[p, q]` (distance `σ + dist(x, [p, q])`): a point
//!     when `p = q`, the straight piece of a source curve nearest to the vertex otherwise, so
//!     curve sources (a boundary, a plane section) are propagated as well as points; a piece
//!     runs on by one mean edge beyond an end where the curve turns towards the vertex's
//!     side or goes straight on (see [`EXTENSION`] and [`STRAIGHT`]).
//!   - A source is moved from the plane of one face around vertex `u` to another by the
//!     smallest rotation about `u` taking one normal to the other (Rodrigues), not by
//!     unfolding the faces between (the two differ by the angle defect of the part of the fan
//!     between them, which changes distances only in the third order of the edge length;
//!     unfolding the fan exactly was tried: within 20 % on the tests' meshes, 1.5–2× slower).
//!   - An offer is used only when the straight segment from the source's nearest point to
//!     `x` crosses the edge of the face opposite `x` (the paper accepts every offer); when
//!     none does, `x` gets the path bending at the settled vertex, which then becomes a
//!     point source with `σ = d(u)` (exact at saddle and boundary vertices, where shortest
//!     paths bend; an upper bound elsewhere).

use super::focal;
use super::params::{GeodesicError, Progress, PROGRESS_EVERY};
use super::source::ResolvedSource;
use super::surface::{segment_distance, Surface};
use super::unfolding::is_saddle_or_boundary;
use super::unfolding::Entry;
use crate::math::{Point3, Real, Vector3};

/// Relative slack (of the edge length) for a ray crossing an edge at or near its ends.
const CROSSING_TOLERANCE: Real = 1e-9;
/// Source segments searched on each side of a sample when seeding a crossed face.
const SEED_WINDOW: usize = 4;
/// Faces whose normals are closer to opposite than this (cosine) do not pass sources.
pub(super) const FOLD_COSINE: Real = -0.999;
/// How far (in mean edge lengths) a piece of a source curve runs on beyond an end where the
/// curve turns towards the side it serves (no paper: on that side the nearest point of the
/// curve to a vertex beyond the end lies on the next piece, which the vertex may not be
/// offered; its neighbours' pieces lie up to an edge away, so running on by less leaves
/// the vertex the end of a piece (0.11 mm too far on the 500k cap with half an edge), and
/// running on far makes a wavy curve seem nearer than it is).
const EXTENSION: Real = 1.0;
/// Sine of the turn between two pieces of a source curve below which the curve runs
/// straight on (either way, as rounding has it for the two halves of one edge).
const STRAIGHT: Real = 1e-9;
/// Memory the propagation may hold at most (its worst case is checked before allocating).
const MAX_BYTES: u64 = 1 << 30;
/// Relative slack of the lower bound on an offer (far above the rounding of the offer).
const BOUND_SLACK: Real = 1e-9;
/// Vertices settled by a call of [`Solver::settle_next`] (the first call is enough to make it
/// hot in V8, whose optimised code then serves the later calls; see [`Solver::run`]).
const CHUNK: usize = 1 << 12;

/// A virtual source: distance `sigma + dist(x, [p, q])`, lying in the plane of `face`; the
/// segment runs on by the solver's `reach` beyond `p` (`extend[0]`) or `q`
/// (`extend[1]`) where the source curve turns towards the side it serves.
#[derive(Clone, Copy, Debug)]
pub(super) struct Virtual {
    pub(super) p: Point3,
    pub(super) q: Point3,
    pub(super) sigma: Real,
    pub(super) face: u32,
    pub(super) extend: [bool; 2],
}

impl Virtual {
    /// A point source at `p` with offset `sigma`, in the plane of `face`.
    pub(super) fn point(p: Point3, sigma: Real, face: u32) -> Self {
        Virtual {
            p,
            q: p,
            sigma,
            face,
            extend: [false; 2],
        }
    }
}

impl Virtual {
    /// The distance it offers `x` (in its plane): `σ` plus the way to its nearest point,
    /// its segment run on by `reach` at the ends marked.
    #[inline]
    pub(super) fn distance(&self, x: &Point3, reach: Real) -> Real {
        self.sigma + (x - foot(x, &self.p, &self.q, self.extend, reach)).norm()
    }
}

/// The nearest point to `x` of segment `[p, q]`, run on by `reach` (a length) beyond the
/// ends marked.
#[inline]
pub(super) fn foot(x: &Point3, p: &Point3, q: &Point3, extend: [bool; 2], reach: Real) -> Point3 {
    let e = q - p;
    let l2 = e.norm_squared();
    if l2 > 0.0 {
        let t = (x - p).dot(&e) / l2;
        let (lo, hi) = if extend == [false; 2] {
            (0.0, 1.0)
        } else {
            let run = reach / l2.sqrt();
            (
                if extend[0] { -run } else { 0.0 },
                if extend[1] { 1.0 + run } else { 1.0 },
            )
        };
        p + e * t.clamp(lo, hi)
    } else {
        *p
    }
}

/// The smallest rotation taking unit `n1` to unit `n2` (Rodrigues, with `k = n1 × n2`:
/// `R w = c·w + k × w + k (k·w) / (1 + c)`, `c = n1·n2`), kept to turn several vectors
/// between the same two faces.
#[derive(Clone, Copy)]
pub(super) struct Rotation {
    pub(super) c: Real,
    k: Vector3,
}

impl Rotation {
    #[inline(always)]
    pub(super) fn new(n1: &Vector3, n2: &Vector3) -> Self {
        Rotation {
            c: n1.dot(n2),
            k: n1.cross(n2),
        }
    }

    #[inline(always)]
    pub(super) fn apply(&self, w: Vector3) -> Vector3 {
        let k = &self.k;
        w * self.c + k.cross(&w) + k * (k.dot(&w) / (1.0 + self.c))
    }

    /// The inverse rotation applied to `w`: the rotation from `n2` to `n1` (its axis is
    /// `−k`; negating is exact, so this equals `Rotation::new(n2, n1).apply(w)` to the bit).
    #[inline(always)]
    fn unapply(&self, w: Vector3) -> Vector3 {
        let k = &self.k;
        w * self.c - k.cross(&w) + k * (k.dot(&w) / (1.0 + self.c))
    }
}

/// A 4-ary min-heap of vertices keyed by `(distance, id)` with decrease-key: each vertex is
/// in it once at most (a lazy heap holds about two entries a vertex and skips the stale).
/// Four children a node halve the depth of a binary heap, and a pop reads them from one or
/// two cache lines (no paper; a common choice for Dijkstra's queue). The order is total, so
/// any heap pops the same sequence as the binary one did.
struct Queue {
    entries: Vec<Entry>,
    /// Index of each vertex in `entries` (`u32::MAX`: not queued).
    at: Vec<u32>,
}

/// Children per node of [`Queue`].
const ARITY: usize = 4;

impl Queue {
    fn new(vertices: usize) -> Self {
        Queue {
            entries: Vec::new(),
            at: vec![u32::MAX; vertices],
        }
    }

    fn less(a: &Entry, b: &Entry) -> bool {
        a.d.total_cmp(&b.d).then(a.v.cmp(&b.v)).is_lt()
    }

    fn place(&mut self, i: usize, e: Entry) {
        self.at[e.v as usize] = i as u32;
        self.entries[i] = e;
    }

    /// Queues `v` at `d`, or lowers its key to `d` (`d` is never higher than its key).
    fn push_or_lower(&mut self, v: u32, d: Real) {
        let e = Entry { d, v };
        let mut i = match self.at[v as usize] {
            u32::MAX => {
                self.entries.push(e);
                self.entries.len() - 1
            }
            i => i as usize,
        };
        // Sift up: each step divides i by ARITY, so at most log4(len) steps.
        while i > 0 {
            let parent = (i - 1) / ARITY;
            if !Self::less(&e, &self.entries[parent]) {
                break;
            }
            let moved = self.entries[parent];
            self.place(i, moved);
            i = parent;
        }
        self.place(i, e);
    }

    fn pop(&mut self) -> Option<Entry> {
        let top = *self.entries.first()?;
        self.at[top.v as usize] = u32::MAX;
        let last = self.entries.pop()?;
        if !self.entries.is_empty() {
            // Sift down: each step multiplies i by ARITY, so at most log4(len) steps.
            let (n, mut i) = (self.entries.len(), 0);
            loop {
                let first = ARITY * i + 1;
                if first >= n {
                    break;
                }
                let mut m = first;
                for c in first + 1..(first + ARITY).min(n) {
                    if Self::less(&self.entries[c], &self.entries[m]) {
                        m = c;
                    }
                }
                if !Self::less(&self.entries[m], &last) {
                    break;
                }
                let child = self.entries[m];
                self.place(i, child);
                i = m;
            }
            self.place(i, last);
        }
        Some(top)
    }

    fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

pub(super) struct Solver<'a> {
    pub(super) surface: &'a Surface<'a>,
    pub(super) dist: Vec<Real>,
    pub(super) src: Vec<Virtual>,
    /// How far a source segment runs on beyond an end marked in `extend` (a length).
    pub(super) reach: Real,
    settled: Vec<bool>,
    /// Whether paths may bend at a vertex: 0 not yet known, 1 no, 2 yes (asked rarely, so
    /// found on demand).
    bend: Vec<u8>,
    heap: Queue,
    /// Vertices settled after all their neighbours (local maxima of the distance).
    pub(super) maxima: Vec<u32>,
}

impl<'a> Solver<'a> {
    /// Nothing reached yet on `surface`.
    pub(super) fn new(surface: &'a Surface<'a>) -> Self {
        let mesh = surface.mesh;
        let nv = mesh.vertex_count();
        Solver {
            surface,
            dist: vec![Real::INFINITY; nv],
            src: vec![Virtual::point(Point3::origin(), 0.0, 0); nv],
            reach: EXTENSION * surface.mean_edge,
            settled: vec![false; nv],
            bend: vec![0; nv],
            heap: Queue::new(nv),
            maxima: Vec::new(),
        }
    }

    /// Settles every vertex reachable from the seeds, nearest first.
    pub(super) fn run(&mut self, progress: Option<Progress>) {
        let nv = self.dist.len();
        let mut progress = progress;
        // The settling runs in chunks of a function kept out of line: a WebAssembly engine
        // (V8) first runs a function's quickly compiled baseline code and switches to its
        // optimised code only at a later call, so a loop settling every vertex in one call
        // ran baseline code to its end (the first distance on the 500k cap executed 2.4 G
        // instructions in Node, 2.0 G in chunks; 1.8 G once compiled). The first chunk
        // makes the function hot; the second call site keeps wasm-opt from inlining it here
        // again (it inlines a function called once). Each chunk settles `CHUNK` vertices or
        // empties the queue, so the loop ends.
        if !self.settle_next(CHUNK) {
            return;
        }
        let mut done = CHUNK;
        while self.settle_next(CHUNK) {
            done += CHUNK;
            if done % PROGRESS_EVERY == 0 {
                if let Some(p) = progress.as_mut() {
                    p("distance", done as f64 / nv as f64);
                }
            }
        }
    }

    /// Frees the queue and the per-vertex flags once [`Self::run`] has settled every vertex
    /// (nothing is offered after that), so the focal refinement allocates into their memory
    /// rather than growing the heap (first touches of new memory are slow in WebAssembly).
    pub(super) fn free_queue(&mut self) {
        self.heap = Queue::new(0);
        self.settled = Vec::new();
        self.bend = Vec::new();
    }

    /// Settles up to `count` vertices, nearest first; `false` when the queue ran empty.
    #[inline(never)]
    fn settle_next(&mut self, count: usize) -> bool {
        // Each pop settles a vertex (a vertex is queued only while unsettled, once at most):
        // at most one pop per vertex.
        for _ in 0..count {
            let Some(Entry { v, .. }) = self.heap.pop() else {
                return false;
            };
            let v = v as usize;
            self.settled[v] = true;
            self.settle(v);
        }
        true
    }

    /// The source of settled vertex `u` moved into the plane of face `t` (about `u`), or
    /// `None` when the two faces are folded onto each other. Inlined, as are [`Self::offer`]
    /// and [`Self::improve`]: V8 does not inline WebAssembly calls and spills every live
    /// value around one (a repeated distance on the 500k sphere: 1.7 G → 1.5 G instructions).
    #[inline(always)]
    pub(super) fn moved(&self, u: usize, t: usize) -> Option<Virtual> {
        let s = self.src[u];
        if s.face as usize == t {
            return Some(s);
        }
        let normals = &self.surface.face_normals;
        let r = Rotation::new(&normals[s.face as usize], &normals[t]);
        (r.c > FOLD_COSINE).then(|| self.turned(&s, u, t, &r))
    }

    /// Source `s` of `u` turned about `u` by `r` into the plane of face `t`.
    #[inline(always)]
    fn turned(&self, s: &Virtual, u: usize, t: usize, r: &Rotation) -> Virtual {
        let pu = self.surface.mesh.positions()[u];
        let p = pu + r.apply(s.p - pu);
        // A point source (p = q) is turned once.
        let q = if s.q == s.p {
            p
        } else {
            pu + r.apply(s.q - pu)
        };
        Virtual {
            p,
            q,
            sigma: s.sigma,
            face: t as u32,
            extend: s.extend,
        }
    }

    /// Distance offered to `x` by source `s` (in the plane of face `t`) when the straight
    /// segment from its nearest point to `x` crosses edge `[a, b]` of `t` (opposite `x`). An
    /// offer no better than `x` has is returned unchecked (it changes nothing).
    #[inline(always)]
    fn offer(&self, s: &Virtual, t: usize, x: usize, a: usize, b: usize) -> Option<Real> {
        let pos = self.surface.mesh.positions();
        let (px, pa, pb) = (pos[x], pos[a], pos[b]);
        let f = foot(&px, &s.p, &s.q, s.extend, self.reach);
        let w = px - f;
        let d = s.sigma + w.norm();
        if d >= self.dist[x] {
            return Some(d);
        }
        let n = &self.surface.face_normals[t];
        let e = pb - pa;
        let den = e.cross(&w).dot(n);
        let tol2 = CROSSING_TOLERANCE * CROSSING_TOLERANCE * e.norm_squared();
        if den * den <= tol2 * w.norm_squared() {
            // The ray runs along the edge's line: it reaches x through a or b only.
            return None;
        }
        // f + τ w = a + λ e.
        let fa = f - pa;
        let lambda = fa.cross(&w).dot(n) / den;
        let tau = fa.cross(&e).dot(n) / den;
        let within = -CROSSING_TOLERANCE..=1.0 + CROSSING_TOLERANCE;
        (within.contains(&lambda) && within.contains(&tau)).then_some(d)
    }

    fn bends_at(&mut self, u: usize) -> bool {
        if self.bend[u] == 0 {
            self.bend[u] = 1 + is_saddle_or_boundary(self.surface, u) as u8;
        }
        self.bend[u] == 2
    }

    #[inline(always)]
    pub(super) fn improve(&mut self, x: usize, d: Real, s: Virtual) {
        if d < self.dist[x] {
            self.dist[x] = d;
            self.src[x] = s;
            if !self.settled[x] {
                self.heap.push_or_lower(x as u32, d);
            }
        }
    }

    /// Settled `u` offers its neighbours in every face around it.
    fn settle(&mut self, u: usize) {
        let surface = self.surface;
        let mesh = surface.mesh;
        let pos = mesh.positions();
        let mut open = false;
        let su = self.src[u];
        let (pu, du) = (pos[u], self.dist[u]);
        for &t in surface.faces_of(u) {
            let t = t as usize;
            let tri = mesh.triangles()[t];
            // The corners after u, in order (u is a corner of t).
            let (p, q) = if tri[0] as usize == u {
                (tri[1], tri[2])
            } else if tri[1] as usize == u {
                (tri[2], tri[0])
            } else {
                (tri[0], tri[1])
            };
            let (p, q) = (p as usize, q as usize);
            if self.settled[p] && self.settled[q] {
                continue;
            }
            open = true;
            // Offers are checked first with x turned back about u into the plane of u's
            // source (the inverse of moving the source, one rotation instead of two for a
            // segment); most cannot improve x and need no more.
            // The rotation from the plane of u's source into t's, shared by both neighbours.
            let normals = &surface.face_normals;
            let same = su.face as usize == t;
            let r = Rotation::new(&normals[su.face as usize], &normals[t]);
            let c = if same { 1.0 } else { r.c };
            let mut from_u = None;
            for (x, y) in [(p, q), (q, p)] {
                if self.settled[x] {
                    continue;
                }
                let ux = pos[x] - pu;
                let ux_len = ux.norm();
                let direct = du + ux_len;
                if c > FOLD_COSINE {
                    let xb = if same { pos[x] } else { pu + r.unapply(ux) };
                    let w_len = (xb - foot(&xb, &su.p, &su.q, su.extend, self.reach)).norm();
                    let lower = su.sigma + w_len;
                    let slack = BOUND_SLACK * (su.sigma.abs() + w_len + ux_len);
                    if lower - slack >= self.dist[x] {
                        // The full offer would be no better than x's distance: only the
                        // bend at u can change x.
                        if direct < self.dist[x] && self.bends_at(u) {
                            self.improve(x, direct, Virtual::point(pu, du, t as u32));
                        }
                        continue;
                    }
                }
                // self.moved(u, t), with the rotation at hand.
                let from_u = *from_u.get_or_insert_with(|| {
                    if same {
                        Some(su)
                    } else {
                        (c > FOLD_COSINE).then(|| self.turned(&su, u, t, &r))
                    }
                });
                let mut best = from_u.and_then(|s| Some((self.offer(&s, t, x, u, y)?, s)));
                // A settled y offered its own source to x across the same edge when it was
                // settled; it matters again only as the alternative to a bend at u.
                if best.is_none() && self.settled[y] {
                    best = self
                        .moved(y, t)
                        .and_then(|s| Some((self.offer(&s, t, x, u, y)?, s)));
                }
                // The path bending at u: a new point source there (exact at saddle and
                // boundary vertices; elsewhere only when no unfolded ray reaches x).
                let at_u = Virtual::point(pu, du, t as u32);
                match best {
                    Some((d, s)) if !(direct < d && self.bends_at(u)) => self.improve(x, d, s),
                    _ => self.improve(x, direct, at_u),
                }
            }
        }
        if !open && !surface.faces_of(u).is_empty() {
            // Every neighbour was nearer: a local maximum, where fronts end.
            self.maxima.push(u as u32);
        }
    }
}

/// Geodesic distance per vertex from `source` on the active faces.
pub(crate) fn propagate(
    surface: &Surface,
    source: &ResolvedSource,
    progress: Progress,
) -> Result<Vec<Real>, GeodesicError> {
    let mesh = surface.mesh;
    let pos = mesh.positions();
    let nv = mesh.vertex_count();
    // Worst case: a source, distance, two flags, a queue entry and its index per vertex,
    // the face normals (held by the surface) and the focal patches.
    let per_vertex = std::mem::size_of::<Virtual>() + std::mem::size_of::<Entry>() + 14;
    let bytes = nv as u64 * per_vertex as u64
        + mesh.triangle_count() as u64 * std::mem::size_of::<Vector3>() as u64
        + focal::budget(surface.faces.len()) as u64 * focal::BYTES_PER_FACE;
    if bytes > MAX_BYTES {
        return Err(GeodesicError::LimitExceeded(format!(
            "the accurate method would need up to {bytes} bytes on this mesh, over its limit of \
             {MAX_BYTES} bytes; use the fast method or a patch"
        )));
    }
    let mut s = Solver::new(surface);
    for &v in &source.vertices {
        let v = v as usize;
        let face = surface.faces_of(v).first().copied().unwrap_or(0);
        s.improve(v, 0.0, Virtual::point(pos[v], 0.0, face));
    }
    for curve in &source.curves {
        let n = curve.points.len();
        let segs = if curve.closed && n > 2 { n } else { n - 1 };
        for (i, &f) in curve.faces.iter().enumerate() {
            for v in mesh.triangles()[f as usize] {
                let v = v as usize;
                let x = pos[v];
                let lo = i as isize - SEED_WINDOW as isize;
                for j in lo..=(i + SEED_WINDOW) as isize {
                    let j = if n == 1 {
                        0
                    } else if curve.closed && n > 2 {
                        j.rem_euclid(segs as isize) as usize
                    } else if j < 0 || j as usize >= segs {
                        continue;
                    } else {
                        j as usize
                    };
                    let (a, b) = (curve.points[j], curve.points[(j + 1) % n]);
                    let (d, _) = segment_distance(&x, &a, &b);
                    // Run on beyond an end where the curve turns towards x's side.
                    let normal = &surface.face_normals[f as usize];
                    let side = normal.cross(&(b - a)).dot(&(x - a));
                    let turns = |from: Option<usize>, to: Option<usize>, at: Point3| {
                        let (Some(i0), Some(i1)) = (from, to) else {
                            return false;
                        };
                        let (u0, u1) = (at - curve.points[i0], curve.points[i1] - at);
                        let turn = normal.cross(&u0).dot(&u1);
                        // Straight on (two halves of one edge, rounded either way) runs on.
                        turn.abs() <= STRAIGHT * u0.norm() * u1.norm() || turn * side >= 0.0
                    };
                    let prev = (j > 0 || (curve.closed && n > 2)).then(|| (j + n - 1) % n);
                    let next2 = (j + 2 < n || (curve.closed && n > 2)).then(|| (j + 2) % n);
                    let extend = if n == 1 {
                        [false; 2]
                    } else {
                        [turns(prev, Some((j + 1) % n), a), turns(Some(j), next2, b)]
                    };
                    let seg = Virtual {
                        p: a,
                        q: b,
                        sigma: 0.0,
                        face: f,
                        extend,
                    };
                    s.improve(v, d, seg);
                }
            }
        }
    }
    if s.heap.is_empty() {
        return Err(GeodesicError::SourceMissesSurface(
            "no vertex could be seeded from the source".into(),
        ));
    }
    s.run(Some(&mut *progress));
    s.free_queue();
    focal::refine_focal(
        &mut s,
        focal::budget(surface.faces.len()),
        focal::MAX_DEPTH,
        focal::RINGS,
        None,
    )?;
    progress("distance", 1.0);
    Ok(s.dist)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotate(w: Vector3, n1: &Vector3, n2: &Vector3) -> Vector3 {
        Rotation::new(n1, n2).apply(w)
    }

    #[test]
    fn the_inverse_rotation_is_the_rotation_back_to_the_bit() {
        let n1 = Vector3::new(0.1, -0.3, 0.7).normalize();
        let n2 = Vector3::new(0.4, 0.2, 0.9).normalize();
        for w in [
            Vector3::new(0.3, -1.2, 0.05),
            Vector3::new(-7.0, 0.001, 3.3),
        ] {
            let back = rotate(w, &n2, &n1);
            assert_eq!(Rotation::new(&n1, &n2).unapply(w), back);
        }
    }

    #[test]
    fn rotation_takes_one_normal_to_the_other_and_keeps_lengths() {
        let n1 = Vector3::new(0.0, 0.0, 1.0);
        let n2 = Vector3::new(0.6, 0.0, 0.8);
        let r = rotate(n1, &n1, &n2);
        assert!((r - n2).norm() < 1e-15);
        let w = Vector3::new(0.3, -1.2, 0.0);
        let rw = rotate(w, &n1, &n2);
        assert!((rw.norm() - w.norm()).abs() < 1e-14);
        assert!(rw.dot(&n2).abs() < 1e-14, "stays in the new plane");
        // The axis n1 × n2 = y is fixed.
        let y = Vector3::new(0.0, 1.0, 0.0);
        assert!((rotate(y, &n1, &n2) - y).norm() < 1e-15);
    }

    #[test]
    fn queue_pops_by_distance_then_id_and_lowers_keys() {
        let mut q = Queue::new(6);
        for (v, d) in [(3, 5.0), (1, 2.0), (4, 2.0), (0, 9.0), (5, 7.0)] {
            q.push_or_lower(v, d);
        }
        q.push_or_lower(0, 1.0);
        q.push_or_lower(5, 2.0);
        let order: Vec<(u32, Real)> = std::iter::from_fn(|| q.pop().map(|e| (e.v, e.d))).collect();
        assert_eq!(order, [(0, 1.0), (1, 2.0), (4, 2.0), (5, 2.0), (3, 5.0)]);
        assert!(q.is_empty() && q.at.iter().all(|&i| i == u32::MAX));
    }

    #[test]
    fn foot_is_the_nearest_point_of_the_segment() {
        let (p, q) = (Point3::new(0.0, 0.0, 0.0), Point3::new(2.0, 0.0, 0.0));
        let (no, reach) = ([false; 2], 1.5);
        assert_eq!(
            foot(&Point3::new(1.0, 3.0, 0.0), &p, &q, no, reach),
            Point3::new(1.0, 0.0, 0.0)
        );
        assert_eq!(foot(&Point3::new(-1.0, 3.0, 0.0), &p, &q, no, reach), p);
        assert_eq!(foot(&Point3::new(5.0, 1.0, 0.0), &p, &p, no, reach), p);
        let on = foot(&Point3::new(-1.0, 3.0, 0.0), &p, &q, [true, false], reach);
        assert_eq!(on, Point3::new(-1.0, 0.0, 0.0));
        let far = foot(&Point3::new(-9.0, 3.0, 0.0), &p, &q, [true, false], reach);
        assert_eq!(far, Point3::new(-reach, 0.0, 0.0));
    }
}
