//! Paths that leave the rim of a hole further back: round a hole meshed as fans of long
//! triangles (as CAD exports the faces round a hole), the path to a vertex behind the hole
//! leaves the rim at a rim vertex far from the vertex's own neighbours there, and no vertex
//! in between holds it, so no offer brings it. A vertex of the rim whose path bent at the
//! rim therefore also offers its neighbours the paths that leave the rim at the rim vertices
//! where the paths before it bent ([`Solver::up_the_rim`]), each ray walked all the way back
//! from the vertex offered ([`Solver::rim_ray_holds`]).
//!
//! Source: none (the paper propagates over closed surfaces). The candidates are those a
//!         taut string round a convex obstacle leaves at (the pseudo-sources of exact window
//!         propagation at a hole's rim, Mitchell, Mount & Papadimitriou 1987), found here
//!         along the chain of bends the solver records per vertex (`Solver::rim`).
//! Why:    a flat annulus of 226 faces (a hole of 200 sides, an outer polygon of 26) from an
//!         outer vertex: 4.0 too long at 82 before, 0.000 after; Orion's heat shield split to
//!         91k and 364k faces from x = 0, vertices more than 0.01 ft beyond exact 440 → 38
//!         and 428 → 20.
//! Cost:   only at vertices of a hole's rim whose path bent there, once per neighbour: at
//!         most [`RIM_STEPS`] candidates laid out and a bisection of walks, which cross at
//!         most [`LONG_WALK_FACES`](super::shadow::LONG_WALK_FACES) faces per face of the
//!         surface in all (5–8 % more time on that heat shield at 364k faces).

use super::shadow::{ExitSlack, LONG_WALK, NO_RIM, SHADOW_STEPS};
use super::{
    corners_after, crossing, Rotation, Solver, Virtual, Wedge, CONSISTENCY, CROSSING_TOLERANCE,
    FOLD_COSINE,
};
use crate::math::Real;

/// Rim vertices [`Solver::up_the_rim`] looks back along at most (no paper: a path round a
/// hole of 200 sides leaves it up to a quarter of the way round from a vertex beside it).
const RIM_STEPS: usize = 64;
/// A rim vertex's path is taken to come straight from the rim vertex it bent at when it is
/// longer by at most this fraction more than their chord (far above the chord's shortfall
/// from the arc between close vertices of a curved rim; the path round a notch is longer).
const STRAIGHT_CHORD: Real = 1e-3;

impl Solver<'_> {
    /// Offers `x` the path that leaves the rim of a hole furthest back from `u`, a vertex of
    /// that rim whose path bent at the rim: the vertices of the rim where the paths before
    /// it bent (`rim[u]`, the one its path bent at, and so on, while each path came straight
    /// from the one before), each laid out in the plane of face `t` from the one after it
    /// (by its own source where that is the point at the next, else by their chord, turned
    /// from the plane of the face its source lies in), as long as they come nearer to `x`
    /// (at most [`RIM_STEPS`]). On a convex rim the ray from them reaches `x` up to where
    /// the path leaves the rim and crosses the hole beyond, so the last that holds is found
    /// by bisection, each ray walked all the way back ([`Self::rim_ray_holds`]). It
    /// replaces the source of `x` only when shorter by more than [`CONSISTENCY`] mean edges:
    /// beside a notch two paths of about the same length reach a vertex, and the one it
    /// holds may be the one the vertices beyond need.
    pub(super) fn up_the_rim(&mut self, u: usize, t: usize, x: usize, y: usize) {
        let pos = self.surface.mesh.positions();
        let normals = &self.surface.face_normals;
        let px = pos[x];
        let (mut at, mut from) = (pos[u], u);
        let mut last = self.dist[u] + (px - pos[u]).norm();
        let mut chain = std::mem::take(&mut self.rim_chain);
        chain.clear();
        for _ in 0..RIM_STEPS {
            let next = self.rim[from];
            if next == NO_RIM {
                break;
            }
            let next = next as usize;
            // The path from `next` to `from` must be the straight chord (not round a notch).
            let chord = (pos[from] - pos[next]).norm();
            if self.dist[from] - self.dist[next] > chord * (1.0 + STRAIGHT_CHORD) {
                break;
            }
            let n = &normals[self.src[from].face as usize];
            let rot = Rotation::new(n, &normals[t]);
            if rot.c <= FOLD_COSINE {
                break;
            }
            // Where `from`'s source is the point at `next` itself, as it lies in that face's
            // plane; else the chord in that plane, at its length.
            let sf = self.src[from];
            let step = if sf.p == sf.q && sf.sigma == self.dist[next] {
                sf.p - pos[from]
            } else {
                let chord3 = pos[next] - pos[from];
                let flat = chord3 - n * n.dot(&chord3);
                let flat_len = flat.norm();
                if flat_len <= 0.0 {
                    break;
                }
                flat * (chord / flat_len)
            };
            let p = at + rot.apply(step);
            let d = self.dist[next] + (px - p).norm();
            // Nearer, or the chain ends (a NaN too).
            if d.partial_cmp(&last) != Some(std::cmp::Ordering::Less) {
                break;
            }
            chain.push((d, Virtual::point(p, self.dist[next], t as u32), next as u32));
            (at, from, last) = (p, next, d);
        }
        if chain.is_empty() {
            self.rim_chain = chain;
            return;
        }
        // The last candidate whose ray holds: `lo` holds (or is none), `hi` does not (or is
        // past the end); each round halves the gap, so the loop ends.
        let (mut lo, mut hi) = (0, chain.len() + 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            let (d, candidate, _) = chain[mid - 1];
            if self.rim_ray_holds(&candidate, t, x) && self.holds(d, &candidate, &px, u, y) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        if lo > 0 {
            let (d, candidate, bent_at) = chain[lo - 1];
            if d < self.dist[x] - CONSISTENCY * self.surface.mean_edge
                && self.improve_walked(x, d, candidate, u, &Wedge::OPEN)
            {
                self.rim[x] = bent_at;
            }
        }
        self.rim_chain = chain;
    }

    /// Whether the ray from point source `s` (in the plane of face `t`, a face of vertex `x`)
    /// reaches `x` over the surface: it enters one of the faces round `x` across the edge
    /// opposite `x` (the source moved into that face's plane about `x`) and, walked back all
    /// the way to the source from there, never leaves the surface (within the budget of such
    /// walks: with too little left, or cut short by it, no).
    pub(super) fn rim_ray_holds(&self, s: &Virtual, t: usize, x: usize) -> bool {
        let surface = self.surface;
        let (pos, tris) = (surface.mesh.positions(), surface.mesh.triangles());
        let px = pos[x];
        for &g in surface.faces_of(x) {
            let g = g as usize;
            let n = &surface.face_normals[g];
            let foot = if g == t {
                s.p
            } else {
                let r = Rotation::new(&surface.face_normals[t], n);
                if r.c <= FOLD_COSINE {
                    continue;
                }
                px + r.apply(s.p - px)
            };
            let (a, b) = corners_after(tris[g], x);
            let w = px - foot;
            let Some(tau) = crossing(&foot, &w, &pos[a], &pos[b], n) else {
                continue;
            };
            if tau <= CROSSING_TOLERANCE {
                return true;
            }
            let left = self.rim_walks.get();
            if left <= SHADOW_STEPS {
                return false;
            }
            let (mut walked, steps) = (0, LONG_WALK.min(left));
            let through = self.walk_back(
                &foot,
                &(foot + w * tau),
                (g, a, b),
                steps,
                &mut walked,
                false,
                ExitSlack::NONE,
            );
            self.rim_walks.set(left - walked);
            return !through && walked < steps;
        }
        false
    }
}
