//! Offers: what the source of a settled vertex offers a neighbour across the edge between,
//! and the checks an offer must pass (the ray crosses the edge, stays out of a hole's
//! shadow, keeps to a walked wedge, to the straight line from a source vertex and to the
//! distance settled at the edge's other end).

use super::{crossing, foot, CROSSING_TOLERANCE};
use super::{shadow, Solver, Virtual, BOUND_SLACK};
use crate::math::{Point3, Real};

/// How far (in mean edge lengths) a source offered across an edge may fall short of the
/// distance settled at the edge's other end before the offer is refused (see
/// [`Solver::offer`]): far above the differences between neighbours' sources on smooth
/// meshes (the bench's caps and spheres never come near it), far below the shortfall of an
/// unfolding taken past a cone vertex on the wrong side on a coarse real mesh.
pub(super) const CONSISTENCY: Real = 1e-2;
/// What [`Solver::offer`] offers: the distance along the ray from the source, or, where the
/// ray leaves the wedge the source holds in (see `wedge.rs`), the path bending at its side,
/// with a point source there.
#[derive(Clone, Copy)]
pub(super) enum Offered {
    Ray(Real),
    Bend(Real, Virtual),
}

impl Offered {
    /// The distance and the source `x` would take from `giver`, whose source is `s`.
    #[inline(always)]
    pub(super) fn of(self, s: Virtual, giver: usize) -> (Real, Virtual, usize) {
        match self {
            Offered::Ray(d) => (d, s, giver),
            Offered::Bend(d, bend) => (d, bend, giver),
        }
    }
}

impl Solver<'_> {
    /// Distance offered to `x` by source `s` (in the plane of face `t`) when the straight
    /// segment from its nearest point to `x` crosses edge `[a, b]` of `t` (opposite `x`), and
    /// the source offers the edge's end `other` (the one it does not come from), if settled,
    /// no less than it has, within [`CONSISTENCY`]. An offer no better than `x` has is
    /// returned unchecked (it changes nothing).
    #[inline(always)]
    pub(super) fn offer(
        &self,
        s: &Virtual,
        t: usize,
        x: usize,
        a: usize,
        b: usize,
        other: usize,
    ) -> Option<Offered> {
        let surface = self.surface;
        let pos = surface.mesh.positions();
        let (px, pa, pb) = (pos[x], pos[a], pos[b]);
        let n = &surface.face_normals[t];
        let f = foot(&px, &s.p, &s.q, &s.run_on, n, self.reach);
        let w = px - f;
        let d = s.sigma + w.norm();
        if d >= self.dist[x] {
            return Some(Offered::Ray(d));
        }
        let tau = crossing(&f, &w, &pa, &pb, n)?;
        // Near a boundary, a ray that left the surface on its way is refused (see
        // `shadow.rs`); one that starts on the edge it crosses (a source on a border) is not.
        // Where the crossed edge's other end holds a path that bent at another hole's rim,
        // the ray is walked all the way back: it may run along the edge of a hole's shadow,
        // however far from the hole.
        let giver = if other == b { a } else { b };
        if !self.gap_rings.is_empty() && tau > CROSSING_TOLERANCE {
            let steps = if self
                .rim
                .get(other)
                .is_some_and(|&r| r != shadow::NO_RIM && r != self.rim[giver])
            {
                shadow::LONG_WALK
            } else if usize::from(self.face_gap_rings(t)) < shadow::SHADOW_STEPS {
                shadow::SHADOW_STEPS
            } else {
                0
            };
            if steps > 0
                && self.through_a_gap(&f, &(f + w * tau), (t, a, b), steps, self.exit_slack(s, &f))
            {
                return None;
            }
        }
        // A point source walked round a sharp vertex holds only in its wedge (see `wedge.rs`);
        // beyond it, the path bends at the wedge's side, held to the same checks.
        if !self.wedge.is_empty() && s.p == s.q && !self.wedge[giver].is_open() {
            if let Some(bend) = self.beyond_wedge(s, t, &px, giver, other, n) {
                return bend;
            }
        }
        if !self.holds(d, s, &px, giver, other) {
            return None;
        }
        Some(Offered::Ray(d))
    }

    /// Whether distance `d` offered to the vertex at `px` by source `s`, handed on by `giver`
    /// across an edge whose other end is `other`, keeps to the straight line from the source
    /// vertex and to the distance settled at `other`.
    #[inline(always)]
    pub(super) fn holds(
        &self,
        d: Real,
        s: &Virtual,
        px: &Point3,
        giver: usize,
        other: usize,
    ) -> bool {
        // No path from a source vertex is shorter than the straight line from it: an offer
        // below it is an unfolding carried round a sharp edge past where it held (the
        // trailing edge of a coarse wing: 8 m short at 25 m on a BWB model).
        if !self.origin.is_empty() {
            let o = self.origins[self.origin[giver] as usize];
            let reach = d * (1.0 + BOUND_SLACK) + BOUND_SLACK * self.surface.mean_edge;
            if reach * reach < (px - o).norm_squared() {
                return false;
            }
        }
        // The source reaches the crossed edge, so it must not offer its settled other end
        // less than that end has: where it does, it is an unfolding carried past a cone
        // vertex (a coarse convex corner) on the wrong side, and it falls short of every
        // path on the surface (no paper: Dijkstra's minimum picks exactly such offers, and
        // on a coarse wing-body mesh they took a point source's distances 0.6 m below the
        // exact ones at 7 m, below the straight line). Checked for point sources: a
        // segment's foot at the other end would cost more (7 % on the bench's 500k cap in
        // WebAssembly), and the pieces of a source curve lie near the vertices they serve,
        // with no cone vertex between. Not where the other end lies on a hole's rim: the
        // straight line to it may cross the hole while the ray to the vertex goes past it
        // (Orion's heat shield split to 22,776 faces, from x = 0: a row of vertices between
        // a hole and a notch in its rim, each refused the source on the rim below it, took
        // the path bending at the last and ended 0.078 ft too long). Nor where the other
        // end's path bent at a hole's rim: it holds the path round the hole that its
        // neighbours handed on, an upper bound, and a vertex after it too long refused
        // every better source after it (the cap R 1000 of 239k faces with a hole 400 mm
        // across, from a point beyond the hole: 2.0 mm too long there, 0.58 now).
        if s.p == s.q
            && self.settled[other]
            && self.hole_rim.get(other) != Some(&true)
            && self.rim.get(other).is_none_or(|&r| r == shadow::NO_RIM)
        {
            let po = self.surface.mesh.positions()[other];
            let short = self.dist[other] - CONSISTENCY * self.surface.mean_edge;
            if s.sigma + (po - s.p).norm() < short {
                return false;
            }
        }
        true
    }
}
