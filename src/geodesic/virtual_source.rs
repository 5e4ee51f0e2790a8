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
//!         itself. The tests check the orders and the focal error. On the coarse, creased
//!         patches of real aircraft meshes (edges up to 2 m) distances from the patch
//!         boundary keep to the exact method within a mean 0.009 of an edge and never fall
//!         more than 0.011 of an edge below the straight line (a test checks it). A point
//!         source carried across a whole coarse model is unfolded exactly at its creases,
//!         held there to the wedge of rays the unfolding is right for (beyond it the path
//!         bends at the wedge's side), refused where it runs past a cone vertex on the wrong
//!         side (see `fan_walk.rs`, `wedge.rs`, [`CONSISTENCY`]), and never offers less than
//!         the straight line from its source vertex (see [`Solver::floor`]): from vertex 0,
//!         largest / mean error against the exact method on a wing-body model (5 cm edges)
//!         0.027 / 0.003 m at up to 10 m (the fast method 0.013 / 0.005), on an airliner
//!         0.009 / 0.001 m, on a BWB model with metre-long edges 1.05 / 0.19 m (a test checks
//!         the line and the mean on three models). Measured (`npm run
//!         bench -- geodesic`: WebAssembly in Node beside native fast marching, potpourri3d
//!         1.4.0; max / mean error in mm against the analytic distance): cap R 1000 from its
//!         rim, 500k triangles 0.0062 / 0.0009, 2M 0.0031 / 0.0002 (fast marching 1.8 / 0.10
//!         and 1.0 / 0.05); sphere R 100 from a point, 500k 0.0078 / 0.0006, 2M 0.0043 /
//!         0.00013 (fast marching 3.0 / 1.3 and 2.9 / 1.2); the cap from its section by
//!         the plane at θ = 0.6 (the accuracy example, native), 0.0073 / 0.0030 and 0.0038 /
//!         0.0006 (f32 positions as in an STL: 0.0073 and 0.0036; the exact method 0.0052 /
//!         0.0031 at 500k); by the plane through its ring of vertices nearest to θ = 0.6,
//!         0.0066 / 0.0013 at 500k. The plane at θ = 0.6 at other resolutions (max error,
//!         mm): 20k triangles 0.14, 70k 0.044, 150k 0.018, 200k 0.014, 400k 0.0082, 1M
//!         0.0043 (before [`Solver::follow_curve`]: 1.15, 0.60, 0.41, 0.34, 0.25, 0.16; 500k
//!         0.043). Time on a shared machine (one run), ratio to fast marching's solve: cap
//!         500k 0.85×, 2M 0.66×; sphere 500k 0.95×, 2M 0.82× (about
//!         1.1 of the time without front interpolation at 500k, alternating the builds; fast
//!         marching itself moves by 10–15 % between runs). The bench times a first call in a
//!         fresh process: at 500k its fixed costs (the engine's baseline code in loops run
//!         once, memory growth) weigh most; the page warms the code up first (see
//!         `www/worker/warm-up.js`).
//! Cost:   O(V log V) time; memory O(V + F) (a source segment, its face and `σ` per vertex,
//!         a normal per face, the heap, the focal patches: at most a quarter of the faces
//!         again; front interpolation reuses the heap's memory), its worst case refused up
//!         front above 1 GiB (about 7M triangles): each vertex is settled once and offers
//!         each face around it twice.
//! Limits: a source is offered on wherever the ray from it crosses the last edge before
//!         the vertex and, near a reflex part of the boundary (the rim of a hole), where the
//!         ray crosses faces for [`shadow::SHADOW_STEPS`] faces back (see `shadow.rs`); at
//!         the edge of a hole's shadow, all the way back. Elsewhere farther back nothing
//!         holds a source curve to the part of the surface it can see past the rim of a
//!         hole: the cap R 1000 with a hole 120 mm across, from a plane section on the
//!         far side, 0.22 mm short at 60k faces and 0.11 mm at 239k (before the walk 15.4
//!         and 14.6 mm; from a vertex there 0.000 at both, 7.8 and 7.1 mm before); Orion's
//!         heat shield subdivided to 364k faces from the plane x = 0, 0.072 ft (0.091 before
//!         the walk all the way back at a shadow's edge held source curves too). Beside a
//!         narrow notch in a hole's rim (two boundary edges meeting at a sharp tip),
//!         distances from a curve come out too long: the heat shield with each face split in
//!         four (22,776 faces) from x = 0, up to 0.075 ft beyond a notch of another hole
//!         (0.078 before the check against unfoldings past a cone vertex left out the rims
//!         of holes, see [`Solver::holds`], and rim vertices offered the paths leaving the
//!         rim further back, see [`Solver::up_the_rim`]; 0.056 with the first alone: a vertex
//!         beside the notch now holds the path from further back, shorter, which the
//!         vertices past the notch's tip cannot use). Round a wide hole a path that leaves
//!         the rim some way from the rim vertex it should leave at comes out too long, by
//!         0.58 mm at 870 mm from a point beyond a hole 400 mm across on the cap of 239k
//!         faces (2.0 before the check against the other end of the crossed edge left out
//!         ends whose path bent at a hole's rim). Where fronts meet on a very coarse
//!         mesh their interpolation may fall short: the flat annulus of 226 faces (a hole of
//!         200 sides, an outer polygon of 26) from an outer vertex, 0.16 at 82. On surfaces
//!         of up to 100k faces with a hole the exact method answers first, within its budget
//!         (see `field.rs`; that heat shield: 2.3M windows, within it).
//!         Sources carried round a thin trailing edge may still fall short: the wing-body
//!         model from its sections by the planes x = 7 and 8.5 m, aft of the wing, up to
//!         0.22 and 0.17 m short of exact at the wing tip, 3.4 and 4.9 m on (fast marching
//!         within 0.002 m there). On a surface that small the accurate method answers
//!         with the exact distance (its exact try's budget covers these planes, see
//!         `field.rs`); on larger cornered ones the virtual sources keep that error.
//! Deviations (no paper):
//!   - A virtual source is a *segment* `[p, q]` (distance `σ + dist(x, [p, q])`): a point
//!     when `p = q`, otherwise the straight run of a source curve nearest to the vertex (the
//!     collinear samples of one boundary edge or polyline segment make one run), so curve
//!     sources (a boundary, a plane section) are propagated as well as points. A run runs on
//!     beyond its ends, up to one mean edge, as far as the curve beyond stays in a wedge on
//!     the vertex's side (see [`RunOn`], [`EXTENSION`] and [`STRAIGHT`]).
//!   - A source is moved from the plane of one face around vertex `u` to another by the
//!     smallest rotation about `u` taking one normal to the other (Rodrigues), not by
//!     unfolding the faces between (the two differ by the angle defect of the part of the fan
//!     between them, which changes distances only in the third order of the edge length;
//!     unfolding the fan exactly was tried: within 20 % on the tests' meshes, 1.5–2× slower).
//!   - For a source of vertices, each vertex also keeps the source vertex its source came
//!     from (4 bytes), and no offer, focal patch or interpolated front gives it less than
//!     the straight line from there: an unfolding carried round a sharp edge (the trailing
//!     edge of a coarse wing) and on past where it held is refused, not taken.
//!   - A vertex where the faces around it bend sharply (see `fan_walk.rs`), more than
//!     [`settle::POINT_AFTER`] mean edges from the source curve, takes the piece of the curve it
//!     holds as a point source at the piece's foot (its nearest point, the same distance),
//!     which is then unfolded around the vertex as point sources are. Turned about the
//!     vertices of a wing root, a piece carried far along a fuselage is misplaced by the
//!     angle defect of the faces between times its distance, and the error grows on the
//!     way: from plane sections across whole models at a tenth to nine tenths of their
//!     length, the airplane's distances fell short of the exact ones by up to 5.8–19 mean
//!     edges (now 0.09–2.3), the 747's by up to 2.1 (now 0.10), the wing-body's by 0.54
//!     and 0.90 m from the planes x = 1 and 2.9 m (now 0.006). A point at the foot offers the
//!     neighbours at most `h²/2d` more than the piece would (`h` the edge, `d` the
//!     distance), and the vertices after take the least of their neighbours' points, whose
//!     circles envelop the piece's front to the same order. Not nearer the curve, where
//!     that excess is not small (a patch's own boundary, whose pieces lie near the vertices
//!     they serve).
//!   - A vertex settled past the end of its piece, where the piece stops for its side (the
//!     curve turns away), looks at the next pieces of the curve carried rigidly with the one
//!     it holds, and takes the nearest ([`Solver::follow_curve`]): a piece shorter than the
//!     spacing of the vertices can be nearest to a vertex whose neighbours each hold a nearer
//!     piece of their own. Pieces so carried are never offered below the straight line to
//!     where they lie, and only while the source's plane has turned by less than 18°.
//!   - An offer is used only when the straight segment from the source's nearest point to
//!     `x` crosses the edge of the face opposite `x` (the paper accepts every offer); when
//!     none does, `x` gets the path bending at the settled vertex, which then becomes a
//!     point source with `σ = d(u)` (exact at saddle and boundary vertices, where shortest
//!     paths bend; an upper bound elsewhere).
//!   - A vertex on the rim of a hole whose path bent at the rim also offers its neighbours
//!     the paths that leave the rim further back, at the rim vertices where the paths before
//!     it bent ([`Solver::up_the_rim`]): round a hole meshed as fans of long triangles (as
//!     CAD exports them) a vertex's path leaves the rim far from its neighbours there, and
//!     no vertex in between holds it. A flat annulus of 226 faces (a hole of 200 sides, an
//!     outer polygon of 26) from an outer vertex: 4.0 too long at 82 before, 0.000 after;
//!     Orion's heat shield split to 91k and 364k faces from x = 0, vertices more than
//!     0.01 ft beyond exact 440 → 38 and 428 → 20, the most 0.050 → 0.021 and 0.021 →
//!     0.017 ft, 5–8 % more time at 364k (the walks are bounded as those of `shadow.rs`).
//!
//! Layout: here the solver's state, its queue loop and the entry point [`propagate`];
//! `geometry.rs` the sources, the rotation between faces and ray crossings; `seeding.rs`
//! the sources laid on the surface; `settle.rs` a settled vertex offering its neighbours;
//! `offers.rs` an offer and its checks; `run_on.rs`, `follow.rs` the pieces of source
//! curves; `fan_walk.rs`, `wedge.rs` point sources at sharp vertices; `books.rs` sources
//! carried across edges of three or more faces (a fin glued on along an edge); `shadow.rs`,
//! `round_a_hole.rs` holes; `queue.rs` the priority queue.

mod books;
mod fan_walk;
mod follow;
mod geometry;
mod offers;
mod queue;
mod round_a_hole;
mod run_on;
mod seeding;
mod settle;
mod shadow;
mod wedge;

use super::focal;
use super::params::{GeodesicError, Progress, PROGRESS_EVERY};
use super::source::ResolvedSource;
use super::surface::{segment_distance, Surface};
use super::unfolding::is_saddle_or_boundary;
use super::unfolding::Entry;
use crate::math::{Point3, Real, Vector3};
use follow::{CurvePiece, NO_PIECE};
use geometry::{corners_after, crossing, CROSSING_TOLERANCE};
pub(super) use geometry::{Rotation, Virtual};
use offers::{Offered, CONSISTENCY};
use queue::Queue;
pub(super) use run_on::{foot, RunOn};
use wedge::Wedge;

/// Source segments searched on each side of a sample when seeding a crossed face.
const SEED_WINDOW: usize = 4;
/// A sample of a source curve this near a vertex (in mean edge lengths) lies on it.
const ON_VERTEX: Real = 1e-3;
/// Faces whose normals are closer to opposite than this (cosine) do not pass sources.
pub(super) const FOLD_COSINE: Real = -0.999;
/// How far (in mean edge lengths) a piece of a source curve runs on beyond an end at most,
/// where the curve beyond allows it (no paper: where the curve turns towards a vertex beyond
/// the end, its nearest point lies on the next piece, which the vertex may not be offered;
/// its neighbours' pieces lie up to an edge away, so running on by less leaves the vertex the
/// end of a piece (0.11 mm too far on the 500k cap with half an edge), and running on far
/// makes a wavy curve seem nearer than it is).
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

pub(super) struct Solver<'a> {
    pub(super) surface: &'a Surface<'a>,
    pub(super) dist: Vec<Real>,
    pub(super) src: Vec<Virtual>,
    /// How far a source segment runs on beyond an end at most (a length; see [`RunOn`]).
    pub(super) reach: Real,
    settled: Vec<bool>,
    /// Whether paths may bend at a vertex: 0 not yet known, 1 no, 2 yes (asked rarely, so
    /// found on demand).
    bend: Vec<u8>,
    heap: Queue,
    /// Vertices settled after all their neighbours (local maxima of the distance).
    pub(super) maxima: Vec<u32>,
    /// The source of the vertex being settled unfolded around it (see `fan_walk.rs`):
    /// face, the corner it reaches there, the source in that face's plane, the wedge of rays
    /// it holds for (measured from the ray to the vertex).
    walked: Vec<(u32, u32, Virtual, Wedge)>,
    /// Scratch of the walk round a vertex: the edges it crossed, laid out in one plane.
    crossed: Vec<Vector3>,
    /// The far vertices of [`Self::crossed`].
    crossed_to: Vec<u32>,
    /// The wedge each vertex's point source holds in (see `wedge.rs`); empty until a walk
    /// bounds one.
    wedge: Vec<Wedge>,
    /// |Angle defect| per vertex, NaN until asked (see `wedge.rs`); empty until then.
    defect: Vec<f32>,
    /// For a source of vertices only: the source vertex each vertex's source comes from
    /// (an index into [`Self::origins`]); empty otherwise.
    origin: Vec<u32>,
    /// The positions of the source vertices.
    origins: Vec<Point3>,
    /// For a source of curves only: the piece of the curves each vertex's source is (an
    /// index into [`Self::pieces`], marked when carried along the curve, see `follow.rs`;
    /// [`NO_PIECE`] for a point source); empty otherwise.
    piece: Vec<u32>,
    /// The straight pieces of every source curve, in the curves' own coordinates, with the
    /// normal of the face under each and the pieces before and after it (see
    /// [`Self::follow_curve`]).
    pieces: Vec<CurvePiece>,
    /// Per vertex, the rings between it and a reflex vertex of the boundary (where the
    /// surface has a gap), near which offers are walked back (see `shadow.rs`); empty on a
    /// surface with none and in the focal patches.
    gap_rings: &'a [u8],
    /// Per vertex, the vertex of a hole's rim its path bent at last ([`shadow::NO_RIM`] for
    /// none): where a point source's offer and the crossed edge's other end differ here, the
    /// offer is walked back all the way (see `shadow.rs`); empty until a path bends at one.
    rim: Vec<u32>,
    /// Faces the walks all the way back may still cross (see `shadow.rs`).
    long_walks: std::cell::Cell<usize>,
    /// Per vertex, whether it lies on the rim of a hole; empty where [`Self::gap_rings`] is
    /// or no boundary loop turns as a hole's rim does.
    hole_rim: &'a [bool],
    /// Per vertex, whether it ends an edge of three or more faces (see `books.rs`); empty on
    /// a mesh with none.
    book_vertex: Vec<bool>,
    /// Scratch of [`Self::offer_across_books`]: the faces of a sheet round a vertex.
    sheet: Vec<u32>,
    /// Whether the offers being made are across an edge of three or more faces, from the
    /// sheet the source lies in (see `books.rs`): the shadow walk lets them through that
    /// edge, which it otherwise takes for a border.
    across_books: bool,
    /// Scratch of [`Self::up_the_rim`]: the paths leaving the rim further back, their
    /// distance and the rim vertex each bends at.
    rim_chain: Vec<(Real, Virtual, u32)>,
    /// Faces the walks of [`Self::up_the_rim`] may still cross.
    pub(super) rim_walks: std::cell::Cell<usize>,
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
            walked: Vec::new(),
            crossed: Vec::new(),
            crossed_to: Vec::new(),
            wedge: Vec::new(),
            defect: Vec::new(),
            origin: Vec::new(),
            origins: Vec::new(),
            piece: Vec::new(),
            pieces: Vec::new(),
            gap_rings: &[],
            rim: Vec::new(),
            long_walks: std::cell::Cell::new(shadow::LONG_WALK_FACES * surface.faces.len()),
            hole_rim: &[],
            book_vertex: if surface.adjacency.non_manifold_edges() == 0 {
                Vec::new()
            } else {
                surface.books().vertices(mesh)
            },
            sheet: Vec::new(),
            across_books: false,
            rim_chain: Vec::new(),
            rim_walks: std::cell::Cell::new(
                (shadow::LONG_WALK_FACES * surface.faces.len()).max(shadow::LONG_WALK),
            ),
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
            if !self.piece.is_empty() {
                if let Some(beyond_q) = self.past_an_end(v) {
                    self.follow_curve(v, beyond_q);
                }
            }
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
            run_on: s.run_on,
        }
    }

    fn bends_at(&mut self, u: usize) -> bool {
        if self.bend[u] == 0 {
            self.bend[u] = 1 + is_saddle_or_boundary(self.surface, u) as u8;
        }
        self.bend[u] == 2
    }

    #[inline(always)]
    pub(super) fn improve(&mut self, x: usize, d: Real, s: Virtual) -> bool {
        if d < self.dist[x] {
            self.dist[x] = d;
            self.src[x] = s;
            if !self.settled[x] {
                self.heap.push_or_lower(x as u32, d);
            }
            true
        } else {
            false
        }
    }

    /// The least distance `v` may have: the straight line from its source vertex when the
    /// source is vertices only (see [`Self::origin`]), else 0. The focal patches and the
    /// front interpolation lower distances without tracking sources, and keep to it.
    pub(super) fn floor(&self, v: usize) -> Real {
        match self.origin.get(v) {
            Some(&o) => {
                let r = (self.surface.mesh.positions()[v] - self.origins[o as usize]).norm();
                r * (1.0 - BOUND_SLACK)
            }
            None => 0.0,
        }
    }

    /// [`Self::improve`] with the source handed on by vertex `giver` (whose source vertex
    /// `x` then shares).
    #[inline(always)]
    fn improve_from(&mut self, x: usize, d: Real, s: Virtual, giver: usize) {
        self.improve_walked(x, d, s, giver, &Wedge::OPEN);
    }

    /// [`Self::improve_from`] with the source unfolded round `giver` by a walk, which holds
    /// only within `walked` (see `wedge.rs`; open for any other source).
    #[inline(always)]
    fn improve_walked(
        &mut self,
        x: usize,
        d: Real,
        s: Virtual,
        giver: usize,
        walked: &Wedge,
    ) -> bool {
        if self.improve(x, d, s) {
            if !self.origin.is_empty() {
                self.origin[x] = self.origin[giver];
            }
            if !self.piece.is_empty() {
                self.piece[x] = if s.p == s.q {
                    NO_PIECE
                } else {
                    self.piece[giver]
                };
            }
            let at_a_rim = self.bends_at_a_gap(&s, giver);
            if self.wedge.is_empty() && at_a_rim {
                self.wedge = vec![Wedge::OPEN; self.dist.len()];
            }
            // The rim of a hole (not a notch of an outer border) casts a shadow.
            let at_a_hole = at_a_rim && self.hole_rim.get(giver) == Some(&true);
            if self.rim.is_empty() && at_a_hole {
                self.rim = vec![shadow::NO_RIM; self.dist.len()];
            }
            if !self.rim.is_empty() {
                self.rim[x] = if at_a_hole {
                    giver as u32
                } else {
                    self.rim[giver]
                };
            }
            if !self.wedge.is_empty() {
                self.pass_wedge(x, &s, giver, walked);
            }
            return true;
        }
        false
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
    // Worst case: a source, distance, two flags, a queue entry and its index, the source
    // vertex or curve piece it comes from (one or the other), a wedge and a cached angle
    // defect (see `wedge.rs`), and the rings to a gap, the rim bent at and whether on a
    // hole's rim (see `shadow.rs`) per vertex,
    // the face normals (held by the surface) and the focal patches.
    let per_vertex = std::mem::size_of::<Virtual>()
        + std::mem::size_of::<Entry>()
        + std::mem::size_of::<Wedge>()
        + 28;
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
    // Not in the focal patches below: their borders are cuts, not gaps.
    // Found once per surface (they do not depend on the source) and kept with it.
    let (rings, hole_rim) = surface.gaps(|| {
        let rings = shadow::rings_to_a_gap(surface);
        let hole_rim = if rings.is_empty() {
            Vec::new()
        } else {
            shadow::on_hole_rims(surface)
        };
        (rings, hole_rim)
    });
    (s.gap_rings, s.hole_rim) = (rings, hole_rim);
    if source.curves.is_empty() {
        s.origin = vec![0; nv];
        s.origins = source.vertices.iter().map(|&v| pos[v as usize]).collect();
    }
    for (i, &v) in source.vertices.iter().enumerate() {
        let v = v as usize;
        let face = surface.faces_of(v).first().copied().unwrap_or(0);
        if s.improve(v, 0.0, Virtual::point(pos[v], 0.0, face)) && !s.origin.is_empty() {
            s.origin[v] = i as u32;
        }
    }
    if !source.curves.is_empty() {
        s.piece = vec![NO_PIECE; nv];
    }
    for curve in &source.curves {
        seeding::seed_curve(&mut s, curve);
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
