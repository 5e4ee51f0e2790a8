//! Rays that come through a gap in the surface: near a reflex part of its boundary (the rim
//! of a hole, a notch in a border), an offer's ray is walked back face by face from the edge
//! it crosses towards its source, and refused where it leaves the surface on the way; a
//! point source's offer across an edge whose other end holds a path that bent at the rim of
//! a hole the offer's did not (the edge of the shadow the hole casts, however far from it)
//! is walked back all the way; and a path bending at such a rim holds only over the rim
//! vertex's own faces (see `wedge.rs`, `rim_wedge`).
//!
//! Source: none. The paper (Trettner, Bommes & Kobbelt 2021) propagates over closed
//!         surfaces. Here an offer is checked where its ray crosses the last edge before the
//!         vertex (see [`Solver::offer`]), which holds it to the surface on smooth ground but
//!         not behind a hole: a ray that crossed the hole a few faces back enters the
//!         vertex's face through an inner edge, and the virtual sources carried on from there
//!         went straight across the hole's shadow, short of the path round it. The walk
//!         borrows the idea of the windows of exact propagation (Mitchell, Mount &
//!         Papadimitriou 1987): a source holds only for rays that cross faces all the way.
//! Input:  an offer's foot on its source and the point where its ray crosses the edge before
//!         the vertex, in the plane of the vertex's face.
//! Output: whether the ray leaves the surface (crosses an edge with no face beyond) within
//!         [`SHADOW_STEPS`] faces back ([`LONG_WALK`] at a shadow's edge); the offer is then
//!         refused, and the vertex takes another offer or the path bending at the settled
//!         vertex (on the rim, a point source there that holds over its faces).
//! Why:    the cap R 1000 with a hole 120 mm across (from the section by a plane on its far
//!         side; from a vertex there), most short of the exact distance, before → after:
//!         9.6k faces 16.7 → 0.22 mm and 6.1 → 0.10 mm; 60k faces 15.4 → 0.22 and 7.8 →
//!         2.3 mm; 239k faces 14.6 → 0.11 and 7.1 → 0.08 mm. Orion's heat shield (5,694
//!         faces, six holes about 1.3 ft across) from the plane x = 0: 1.20 → 0.50 ft.
//!         The bench's caps and sphere, and the five real models' patches from their
//!         boundaries, are unchanged to the bit. The walk at a shadow's edge: the point source
//!         on the far side of the 60k cap fell 2.3 mm short across the pole, a metre beyond
//!         the hole (0.000 now; 0.08 → 0.000 mm at 239k faces). A vertex just inside the
//!         shadow, more rings from the rim than are walked, was offered the source straight
//!         through the hole by a lit neighbour before the path round the rim reached it (the
//!         straight ray is the shorter, so its front runs ahead), took it, and handed it on
//!         inwards.
//! Deviations: the foot is moved from face to face by the rotation taking one face's normal
//!         to the next about their shared edge (an unfolding along the ray, not the rotation
//!         about the settled vertex that carried the source). A ray through a vertex is
//!         walked as if it passed beside it, through the edge it crossed a millionth of the
//!         edge from the vertex: it finds no edge to cross beyond the vertex, and was let
//!         through (a plate with a hole 20 edges across, from its section by a plane parallel
//!         to the rows of its grid, whose rays run along the columns of edges: 3.6 edges short
//!         of the exact distance behind the hole; a point source beside it, 0.073; now 0.000
//!         both). A ray that left the surface no farther from its foot than a source curve runs
//!         on beyond its ends (see [`RunOn`](super::RunOn)) is kept where the foot is so run
//!         on: a piece of a border run on along its line lies off the surface where the border
//!         turns away. A foot on the piece itself lies on the surface, and its ray is kept only
//!         within a tenth of a mean edge where it leaves through a hole's rim (it had the same
//!         allowance: 200 random plates of 50 × 70 unit squares, each with a hole, from a
//!         random point or plane section (`examples/geodesic_holes.rs`), 51 → 41 cases short of
//!         the exact distance by over 0.01 edge, mean error 0.0028 → 0.0007 edge; the heat
//!         shield split to 91k faces, mean error 0.00047 → 0.00042 ft; a section crossing a
//!         hole near its rim was carried over the rim's corner, 0.27 edges short beyond). A
//!         point source keeps the allowance, but within it, within [`DETOUR_WALK`] faces back,
//!         a ray that left by an edge away from its source vertex is refused where the path
//!         round the nearer end of that edge is longer by over [`ExitSlack::detour`]: a rim
//!         vertex's source offered across a corner of the hole (the same plates, 41 → 4 cases,
//!         mean error 0.0007 → 0.00045 edge; 0.18 edges short behind such a corner on gently
//!         curved plates; see `Solver::exit_slack`). Only faces within [`SHADOW_STEPS`] rings
//!         of a reflex boundary vertex are walked (a ray leaves the surface and comes back only
//!         past one), and a walk stops where the boundary is more rings away than faces are
//!         left. The walk all the way back starts only at the shadows of holes (loops that turn
//!         as a hole's rim does, not the notches of an outer border), and beyond
//!         [`SHADOW_STEPS`] faces it refuses only a ray that leaves through a hole's rim: a ray
//!         that runs beside a jagged outer border (a patch's, cut along the faces) leaves it at
//!         a notch, where the path round the notches is not found. Source curves have it as
//!         point sources do. (They had not: a piece that ends on a hole's rim sends its rays
//!         along it, and on the heat shield split to 22,776 faces from x = 0 distances came out
//!         up to 0.11 ft too long with it, 0.078 without. Since the check against the other end
//!         of the crossed edge leaves out hole rims and rim vertices offer the paths leaving
//!         the rim further back, the figures there are the same with it and without, 0.075.)
//!         From a curve, with it: the cap R 1000 of 239k faces with a hole 240 mm across, from
//!         its section by a plane on the far side, 7.46 → 0.11 mm short of the exact distance
//!         (holes 400 and 600 mm across: 6.6 → 0.14 and 3.2 → 0.17); the heat shield split to
//!         91k and 364k faces, mean error 0.00175 → 0.00070 and 0.00358 → 0.00153 ft, most
//!         short 0.061 → 0.061 and 0.091 → 0.072 ft; but more vertices too long by over 0.01
//!         ft, 38 → 374 and 20 → 50 (the most 0.021 → 0.037 and 0.017 → 0.017 ft), where a ray
//!         refused at a rim leaves a vertex a longer path; 62 and 10 (the most 0.024 and 0.017)
//!         since the check against the other end of the crossed edge leaves out ends whose path
//!         bent at a hole's rim (`Solver::holds`). 15 % more time at 364k faces.
//!         Limits: away from a shadow's edge, from a curve, a ray that left the surface more
//!         than [`SHADOW_STEPS`] faces back is not seen (the heat shield split to 364k faces:
//!         0.072 ft short).
//! Cost:   nothing on a surface with no reflex boundary vertex (the bench's caps and sphere,
//!         to the bit and within the noise in time). Otherwise the rings from those
//!         vertices (a breadth-first search, a byte a vertex) and, for offers into faces
//!         near them that would improve a vertex, a walk of [`SHADOW_STEPS`] faces at most,
//!         each a rotation and two crossing tests: Orion's heat shield subdivided to 91k and
//!         364k faces, from the plane x = 0, 54 → 72 and 174 → 232 ms natively (most short of
//!         the exact distance 0.96 → 0.061 and 0.96 → 0.091 ft; the exact method 10 and
//!         102 s). The walks all the way back cross at most [`LONG_WALK`] faces each and
//!         [`LONG_WALK_FACES`] per face of the surface in all (then the walk near a boundary
//!         only): from a vertex, 0.7–0.9 faces per face on that heat shield and 1.8 on the
//!         holed caps; 3–6 % more time at 364k faces. The rays of the paths a rim vertex
//!         offers from further back along the rim (`Solver::up_the_rim`) are walked all the
//!         way back from the vertex offered (see `round_a_hole.rs`), within a budget of their
//!         own of as many faces ([`LONG_WALK`] at least).

use super::{Rotation, Solver, Virtual, CROSSING_TOLERANCE, FOLD_COSINE};
use crate::geodesic::source::boundary_loops;
use crate::geodesic::surface::Surface;
use crate::geodesic::unfolding::{boundary_turn, is_hole_rim};
use crate::math::{Point3, Real};

/// Faces an offer's ray is walked back at most, and the rings of vertices round a reflex
/// boundary vertex where offers are walked (no paper: a ray that crossed a hole may run on
/// for its width before it reaches a vertex; with 12, the cap of 239k faces with a hole of
/// 24 faces across was still 0.58 mm short behind it, with 32, 0.11).
pub(super) const SHADOW_STEPS: usize = 32;
/// Where along the edge it crosses (a fraction of the edge) a walked ray through one of the
/// edge's ends is moved to (see [`Solver::walk_back`]).
const VERTEX_NUDGE: Real = 1e-6;
/// How far (a fraction of the mean edge) a point source's foot may lie from an end of the edge
/// its walked ray leaves the surface by and still be taken for that end, the ray leaving by
/// an edge at its own source vertex (no paper: after walks of 100 to 290 faces over the cap
/// R 1000 the unfolded foot lay up to half a mean edge off its vertex; on the holed plates
/// the feet of the rays across a corner lay 0.88 mean edge or more from both ends).
const OWN_EDGE: Real = 0.25;
/// Faces back within which a point source's ray is held to [`ExitSlack::detour`] (no paper:
/// on the holed plates the rays across a hole's corner left the surface within 15 faces; on
/// the cap R 1000 with a hole 120 mm across, rays that kept to the rim within their slack left
/// after 100 to 290 faces, their unfolded feet up to half a mean edge off their vertices).
const DETOUR_WALK: usize = 2 * SHADOW_STEPS;
/// How far (a fraction of the mean edge) from a foot on a piece of a source curve, not run on,
/// a walked ray may leave the surface (no paper: rounding only, as the piece lies on the
/// surface; with the reach, a plane section crossing a hole near its rim was carried over
/// the rim's corner, up to 0.27 edges short of the exact distance beyond; 0.01 and 0.1 gave
/// the same figures on 200 random holed plates).
const ON_PIECE_EXIT: Real = 0.1;
/// How much longer (a fraction of the mean edge) than a point source's ray that leaves the
/// surface within the reach the path round the nearer end of the edge it leaves by may be
/// (no paper: the rays of a rim vertex's source across a corner of a hole cost 0.09 to 0.34
/// there, 0.18 short of the exact distance beyond; 0.01 to 0.1 gave the same figures on 200
/// random holed plates, 0.2 let most of those rays through).
const POINT_EXIT_DETOUR: Real = 0.05;
/// More rings from a boundary than a walk can cross.
pub(super) const FAR: u8 = u8::MAX;
/// A source that bent at no reflex boundary vertex (see `Solver::rim`).
pub(super) const NO_RIM: u32 = u32::MAX;
/// Faces a walk all the way back crosses at most (no paper: far more than a ray crosses on
/// the meshes measured; a longer ray is let through)...
pub(super) const LONG_WALK: usize = 1 << 14;
/// ...and all of them together, per face of the surface (so the walks stay linear in its
/// size; beyond, offers get the walk of [`SHADOW_STEPS`] faces near a boundary only).
pub(super) const LONG_WALK_FACES: usize = 4;
/// How far (radians) the faces' angles at a boundary vertex must sum beyond π for the
/// border to turn away there (no paper: far above rounding on a straight border, below the
/// turn at each vertex of the rim of a hole a thousand edges round).
const REFLEX_TURN: Real = 1e-3;

/// How far from its foot a walked ray may leave the surface and still be kept (see
/// `Solver::exit_slack`).
#[derive(Clone, Copy, Debug)]
pub(super) struct ExitSlack {
    /// Through an edge of a hole's rim...
    pub(super) hole: Real,
    /// ...through any other border edge...
    pub(super) border: Real,
    /// ...and, within those, how much longer the path round the nearer end of that edge may
    /// be (`∞`: no bound), where the foot is not at one of its ends (see [`OWN_EDGE`]).
    pub(super) detour: Real,
}

impl ExitSlack {
    /// None anywhere.
    pub(super) const NONE: ExitSlack = ExitSlack {
        hole: 0.0,
        border: 0.0,
        detour: Real::INFINITY,
    };
}

/// The slot of the edge `a – b` in triangle `tri` (slot `k` runs from corner `k` to `k + 1`).
#[inline(always)]
pub(super) fn slot(tri: [u32; 3], a: usize, b: usize) -> usize {
    let off = |v: u32| v as usize != a && v as usize != b;
    if off(tri[0]) {
        1
    } else if off(tri[1]) {
        2
    } else {
        0
    }
}

/// Per vertex, the fewest rings of vertices between it and a reflex vertex of the boundary
/// of `surface` (one whose faces' angles sum to more than π by [`REFLEX_TURN`], where the
/// border turns away from the surface: the rim of a hole, a notch), 0 on one, [`FAR`] from
/// [`SHADOW_STEPS`] rings on; empty when there is none. A ray can leave the surface and come
/// back to it only past such a vertex.
pub(super) fn rings_to_a_gap(surface: &Surface) -> Vec<u8> {
    let mesh = surface.mesh;
    let tris = mesh.triangles();
    let adjacency = surface.adjacency;
    if surface.faces.len() == tris.len()
        && adjacency.boundary_edges() == 0
        && adjacency.non_manifold_edges() == 0
    {
        // A closed surface: every edge has a face across.
        return Vec::new();
    }
    let mut ring = Vec::new();
    let mut frontier: Vec<u32> = Vec::new();
    for &f in &surface.faces {
        let f = f as usize;
        for k in 0..3 {
            if surface.across(f, k).is_some() {
                continue;
            }
            for v in [tris[f][k], tris[f][(k + 1) % 3]] {
                if ring.get(v as usize).is_some_and(|&r| r != FAR) {
                    continue;
                }
                if boundary_turn(surface, v as usize) > REFLEX_TURN {
                    if ring.is_empty() {
                        ring = vec![FAR; mesh.vertex_count()];
                    }
                    ring[v as usize] = 0;
                    frontier.push(v);
                }
            }
        }
    }
    if ring.is_empty() {
        return Vec::new();
    }
    // Rings 1..SHADOW_STEPS: each vertex is pushed once, when first reached.
    let mut next: Vec<u32> = Vec::new();
    for r in 1..SHADOW_STEPS as u8 {
        for &v in &frontier {
            for &f in surface.faces_of(v as usize) {
                for w in tris[f as usize] {
                    if ring[w as usize] == FAR {
                        ring[w as usize] = r;
                        next.push(w);
                    }
                }
            }
        }
        std::mem::swap(&mut frontier, &mut next);
        next.clear();
    }
    ring
}

/// Per vertex, whether it lies on the rim of a hole (a boundary loop that turns as one does,
/// see [`is_hole_rim`]); empty when no loop does.
pub(super) fn on_hole_rims(surface: &Surface) -> Vec<bool> {
    let mut on = Vec::new();
    for l in boundary_loops(surface) {
        if is_hole_rim(surface, &l) {
            if on.is_empty() {
                on = vec![false; surface.mesh.vertex_count()];
            }
            for v in l {
                on[v as usize] = true;
            }
        }
    }
    on
}

impl Solver<'_> {
    /// How far from its foot `f` on source `s` a walked ray may leave the surface and still be
    /// kept (see `shadow.rs`): a foot where a piece of a source curve runs on past its end may
    /// lie off the surface, up to the reach. A foot on the piece itself lies on the surface,
    /// and its ray may leave through a hole's rim only within [`ON_PIECE_EXIT`] of the mean
    /// edge; through an outer border, by the reach (the path round the notches of a jagged
    /// border, a patch's cut along the faces, is not found: a patch of the BWB model from its
    /// boundary, 0.15 → 0.50 too long with the smaller slack there too). A point source's ray
    /// may leave within the reach where the path round the nearer end of the edge it leaves by
    /// is no more than [`POINT_EXIT_DETOUR`] of the mean edge longer. (With a smaller slack
    /// instead, half a mean edge, the holed plates came out as right, but on Orion's heat
    /// shield split to 22,776 faces the paths round the rim that took over from rays grazing
    /// it came out up to 0.013 ft too long: 36 → 62 vertices by over 0.01.)
    #[inline(always)]
    pub(super) fn exit_slack(&self, s: &Virtual, f: &Point3) -> ExitSlack {
        let mut slack = ExitSlack {
            hole: self.reach,
            border: self.reach,
            detour: Real::INFINITY,
        };
        if s.p == s.q {
            slack.detour = POINT_EXIT_DETOUR * self.surface.mean_edge;
        } else {
            let e = s.q - s.p;
            let along = (f - s.p).dot(&e);
            if (0.0..=e.norm_squared()).contains(&along) {
                slack.hole = ON_PIECE_EXIT * self.surface.mean_edge;
            }
        }
        slack
    }

    /// The fewest rings between face `f`'s corners and a reflex boundary vertex (see
    /// [`rings_to_a_gap`]; `gap_rings` must not be empty). From one face to the next across
    /// an edge it falls by one at most.
    #[inline(always)]
    pub(super) fn face_gap_rings(&self, f: usize) -> u8 {
        let [a, b, c] = self.surface.mesh.triangles()[f];
        let r = &self.gap_rings;
        r[a as usize].min(r[b as usize]).min(r[c as usize])
    }

    /// Whether the ray from `foot` to `crossing`, a point of edge `a – b` of face `t` (both
    /// in the plane of `t`, the foot beyond the edge), leaves the surface within `steps`
    /// faces back from the edge: [`SHADOW_STEPS`], or [`LONG_WALK`] as far as the budget of
    /// long walks allows (once it is spent, [`SHADOW_STEPS`] near a boundary and none
    /// elsewhere); a ray that leaves no farther than `slack` allows from its foot is kept.
    #[inline(never)]
    pub(super) fn through_a_gap(
        &self,
        foot: &Point3,
        crossing: &Point3,
        (t, a, b): (usize, usize, usize),
        steps: usize,
        slack: ExitSlack,
    ) -> bool {
        if steps > SHADOW_STEPS {
            // As far as the budget left allows (a walk cut short lets the ray through, as the
            // walk near a boundary does beyond its faces).
            let left = self.long_walks.get();
            let steps = steps.min(left);
            if steps > SHADOW_STEPS {
                let mut walked = 0;
                let through =
                    self.walk_back(foot, crossing, (t, a, b), steps, &mut walked, true, slack);
                self.long_walks.set(left - walked);
                return through;
            }
            if usize::from(self.face_gap_rings(t)) >= SHADOW_STEPS {
                return false;
            }
        }
        self.walk_back(
            foot,
            crossing,
            (t, a, b),
            SHADOW_STEPS,
            &mut 0,
            false,
            slack,
        )
    }

    /// The face a ray walked back from face `g` (its normal's sign `sign` in the walk's
    /// winding), its foot `f` unfolded into `g`'s plane, came from across slot `k` of `g`,
    /// an edge of three or more faces, with its normal's sign: of the other faces on the
    /// edge but slivers, unfolded across it (wound as `g`), those where the foot lies on
    /// their side of the edge, the flattest; `None` when there is none (the ray came from
    /// off the surface).
    #[inline(never)]
    fn behind_a_book(&self, g: usize, k: usize, sign: Real, f: &Point3) -> Option<(usize, Real)> {
        let surface = self.surface;
        let (pos, tris) = (surface.mesh.positions(), surface.mesh.triangles());
        let normals = &surface.face_normals;
        let tg = tris[g];
        let pa = pos[tg[k] as usize];
        let e = pos[tg[(k + 1) % 3] as usize] - pa;
        let mut best: Option<(Real, usize, Real)> = None;
        for (h, j) in surface.books().others(g, k) {
            if surface.is_sliver(h) {
                continue;
            }
            let th = tris[h];
            // Wound alike, g and h run along the edge in opposite directions.
            let sign_h = if th[j] == tg[k] { -sign } else { sign };
            let n_h = normals[h] * sign_h;
            let r = Rotation::new(&(normals[g] * sign), &n_h);
            if r.c <= FOLD_COSINE {
                continue;
            }
            let side = |p: &Point3| e.cross(&(p - pa)).dot(&n_h);
            let foot_side = side(&(pa + r.apply(f - pa)));
            if foot_side * side(&pos[th[(j + 2) % 3] as usize]) <= 0.0 {
                continue;
            }
            if best.is_none_or(|(c, _, _)| r.c > c) {
                best = Some((r.c, h, sign_h));
            }
        }
        best.map(|(_, h, sign_h)| (h, sign_h))
    }

    /// [`Self::through_a_gap`] within `steps` faces, counting the faces crossed in `walked`;
    /// with `holes_only`, a ray that leaves farther back than [`SHADOW_STEPS`] faces through
    /// an edge not on the rim of a hole (past a notch of an outer border it runs beside) is
    /// let through; so is one that leaves no farther than `slack` allows from its foot (see
    /// `Solver::exit_slack`; none for a point source on a rim).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn walk_back(
        &self,
        foot: &Point3,
        crossing: &Point3,
        (t, a, b): (usize, usize, usize),
        steps: usize,
        walked: &mut usize,
        holes_only: bool,
        slack: ExitSlack,
    ) -> bool {
        let surface = self.surface;
        let (pos, tris) = (surface.mesh.positions(), surface.mesh.triangles());
        let normals = &surface.face_normals;
        let (mut g, mut a, mut b) = (t, a, b);
        let (mut c, mut f) = (*crossing, *foot);
        // The sign of the current face's normal in the walk's winding (turned where the
        // walk went on across an edge of three or more faces into a face wound the other
        // way; within a sheet the faces are wound alike).
        let mut sign: Real = 1.0;
        // A ray through a vertex (a source curve along a row of edges of a structured mesh)
        // would find no edge to cross beyond it: it is walked as if it passed beside the
        // vertex, through the edge it crossed (here for the first edge, below for the
        // others, where it is crossed).
        let e = pos[b] - pos[a];
        let along = (c - pos[a]).dot(&e) / e.norm_squared();
        if along < VERTEX_NUDGE {
            c = pos[a] + e * VERTEX_NUDGE;
        } else if along > 1.0 - VERTEX_NUDGE {
            c = pos[a] + e * (1.0 - VERTEX_NUDGE);
        }
        // Each round moves one face back, so the walk ends after `steps` faces. The rings
        // from a face to the boundary fall by one a face at most, so a walk that cannot
        // reach it in the faces left stops.
        for left in (0..steps).rev() {
            *walked += 1;
            if usize::from(self.face_gap_rings(g)) > left {
                return false;
            }
            let k = slot(tris[g], a, b);
            let across = match surface.across(g, k) {
                Some(h) => Some((h, sign)),
                // An edge of three or more faces. The first the ray crossed: one it was
                // offered across from the source's sheet (see `books.rs`) is let through;
                // any other offer across it is refused there, as at a border (the source
                // turned into the plane of a face of another sheet, which may be wound the
                // other way or be a sliver of no plane). Further back the walk goes on into
                // the face the ray came from.
                None if !self.book_vertex.is_empty()
                    && surface.books().others(g, k).next().is_some() =>
                {
                    if left + 1 == steps {
                        if self.across_books {
                            return false;
                        }
                        None
                    } else {
                        self.behind_a_book(g, k, sign, &f)
                    }
                }
                None => None,
            };
            let Some((h, sign_h)) = across else {
                if holes_only && *walked > SHADOW_STEPS && !(self.hole_rim[a] && self.hole_rim[b]) {
                    return false;
                }
                // Nothing beyond the edge the ray crossed: it came from off the surface,
                // unless from no farther than a source curve runs on beyond its ends (a
                // piece of a border, run on along its line, lies off the surface where the
                // border turns away).
                let allowed = if self.hole_rim.get(a) == Some(&true) && self.hole_rim[b] {
                    slack.hole
                } else {
                    slack.border
                };
                let off = (f - c).norm();
                if off > allowed {
                    return true;
                }
                // Within the slack, a point source's ray is refused where it cut across a
                // corner of the gap: where it left by an edge away from its source (its foot
                // not at an end of the edge) and going round the nearer end is longer by
                // more than the detour allowed. Only a few rings back: the unfolded foot
                // drifts off its vertex along a long walk.
                if slack.detour < Real::INFINITY && *walked <= DETOUR_WALK {
                    let (pa, pb) = (pos[a], pos[b]);
                    let (fa, fb) = ((f - pa).norm(), (f - pb).norm());
                    let round = (fa + (pa - c).norm()).min(fb + (pb - c).norm());
                    return fa.min(fb) > OWN_EDGE * surface.mean_edge && round - off > slack.detour;
                }
                return false;
            };
            let r = Rotation::new(&(normals[g] * sign), &(normals[h] * sign_h));
            if r.c <= FOLD_COSINE {
                return false;
            }
            sign = sign_h;
            let pa = pos[a];
            f = pa + r.apply(f - pa);
            let n = &normals[h];
            let back = f - c;
            let z = tris[h]
                .iter()
                .map(|&v| v as usize)
                .find(|&v| v != a && v != b)
                .unwrap_or(a);
            // The edge of h the ray crosses on its way back from c to f, if any before f,
            // and where (c + s·back = p + λ·e).
            let crossed = [(a, z), (b, z)].into_iter().find_map(|(p, q)| {
                let e = pos[q] - pos[p];
                let den = e.cross(&back).dot(n);
                let scale = e.norm_squared() * back.norm_squared();
                if den * den <= CROSSING_TOLERANCE * CROSSING_TOLERANCE * scale {
                    return None;
                }
                let cp = c - pos[p];
                let lambda = cp.cross(&back).dot(n) / den;
                let s = cp.cross(&e).dot(n) / den;
                ((-CROSSING_TOLERANCE..=1.0 + CROSSING_TOLERANCE).contains(&lambda)
                    && s > CROSSING_TOLERANCE
                    && s < 1.0 - CROSSING_TOLERANCE)
                    .then(|| {
                        (
                            p,
                            q,
                            pos[p] + e * lambda.clamp(VERTEX_NUDGE, 1.0 - VERTEX_NUDGE),
                        )
                    })
            });
            let Some((p, q, at)) = crossed else {
                // The foot lies in h (or the ray ends on its edge): it crossed the surface.
                return false;
            };
            c = at;
            (g, a, b) = (h, p, q);
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point3;
    use crate::mesh::{FaceAdjacency, TriMesh};

    /// A plate of 6 × 6 unit squares (each cut along a diagonal) without its middle 2 × 2.
    fn holed_plate() -> TriMesh {
        let at = |i: u32, j: u32| j * 7 + i;
        let positions = (0..7)
            .flat_map(|j| (0..7).map(move |i| Point3::new(i as Real, j as Real, 0.0)))
            .collect();
        let mut triangles = Vec::new();
        for j in 0..6 {
            for i in 0..6 {
                if (2..4).contains(&i) && (2..4).contains(&j) {
                    continue;
                }
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        TriMesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn the_rings_count_from_the_corners_of_a_hole_not_from_a_straight_or_convex_border() {
        let mesh = holed_plate();
        let adjacency = FaceAdjacency::new(&mesh);
        let surface = Surface::new(&mesh, &adjacency, None).unwrap();
        let rings = rings_to_a_gap(&surface);
        let at = |i: usize, j: usize| rings[j * 7 + i];
        // The hole's corners turn away from the plate (3π/2 of faces); the middles of its
        // sides (π) and the plate's own border (π/2 at a corner, π along a side) do not.
        for (i, j) in [(2, 2), (4, 2), (2, 4), (4, 4)] {
            assert_eq!(at(i, j), 0, "({i}, {j})");
        }
        assert_eq!(at(3, 2), 1);
        assert_eq!(at(1, 1), 1);
        assert_eq!(at(0, 0), 2);
        assert_eq!(at(0, 3), 2);
        assert_eq!(rings.iter().filter(|&&r| r == 0).count(), 4);
        // A plate without the hole has no gap at all.
        let whole = TriMesh::new(
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(1.0, 1.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap();
        let adjacency = FaceAdjacency::new(&whole);
        let surface = Surface::new(&whole, &adjacency, None).unwrap();
        assert!(rings_to_a_gap(&surface).is_empty());
    }
}
