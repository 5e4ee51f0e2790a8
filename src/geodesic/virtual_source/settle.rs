//! Settling a vertex: its source (a piece of a source curve far from the curve taken as a
//! point at its foot where the faces bend sharply) offered to its unsettled neighbours in
//! every face around it, or the path bending at it.

use super::NO_PIECE;
use super::{corners_after, foot, shadow, Rotation, Solver, Virtual, BOUND_SLACK, FOLD_COSINE};
use crate::math::Real;

/// Distance from a source curve (in mean edge lengths) beyond which a vertex where the faces
/// bend sharply takes its segment source as a point source at the segment's foot (2, 5 and
/// 10 measured the same on the wing-body model's plane sections; no paper).
pub(super) const POINT_AFTER: Real = 10.0;
impl Solver<'_> {
    /// Settled `u` offers its neighbours in every face around it.
    pub(super) fn settle(&mut self, u: usize) {
        let surface = self.surface;
        let mesh = surface.mesh;
        let pos = mesh.positions();
        let mut open = false;
        let (pu, du) = (pos[u], self.dist[u]);
        if self.src[u].p != self.src[u].q
            && du >= POINT_AFTER * surface.mean_edge
            && self.is_sharp(u, self.src[u].face as usize)
        {
            self.source_to_point(u);
        }
        let su = self.src[u];
        // A vertex of a hole's rim whose path bent at the rim offers paths that leave it
        // further back too (see `up_the_rim`).
        let round_a_hole = self.hole_rim.get(u) == Some(&true)
            && self.rim.get(u).is_some_and(|&r| r != shadow::NO_RIM);
        // Where the faces around u bend sharply, a point source is unfolded around u instead
        // of turned about it (see `fan_walk.rs`).
        let at_a_book = self.book_vertex.get(u) == Some(&true);
        if su.p == su.q && self.settled_walking(u) {
            if at_a_book {
                self.offer_across_books(u);
            }
            return;
        }
        for &t in surface.faces_of(u) {
            let t = t as usize;
            let (p, q) = corners_after(mesh.triangles()[t], u);
            if self.settled[p] && self.settled[q] {
                continue;
            }
            open = true;
            // A sliver glued on at u has no plane to turn a source into: its corners get
            // the bend at u here, and across the edge from `offer_across_books`.
            if at_a_book && surface.is_sliver(t) {
                self.bend_into(u, t, p, q);
                continue;
            }
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
                    let w_len = (xb
                        - foot(
                            &xb,
                            &su.p,
                            &su.q,
                            &su.run_on,
                            &normals[su.face as usize],
                            self.reach,
                        ))
                    .norm();
                    let lower = su.sigma + w_len;
                    let slack = BOUND_SLACK * (su.sigma.abs() + w_len + ux_len);
                    if lower - slack >= self.dist[x] {
                        // The full offer would be no better than x's distance: only the
                        // bend at u can change x.
                        if direct < self.dist[x] && self.bends_at(u) {
                            self.improve_from(x, direct, Virtual::point(pu, du, t as u32), u);
                        }
                        if round_a_hole && x == p {
                            self.up_the_rim(u, t, x, y);
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
                let mut best = from_u.and_then(|s| Some(self.offer(&s, t, x, u, y, y)?.of(s, u)));
                // A settled y offered its own source to x across the same edge when it was
                // settled; it matters again only as the alternative to a bend at u.
                if best.is_none() && self.settled[y] {
                    best = self
                        .handed_on(y, t)
                        .and_then(|s| Some(self.offer(&s, t, x, u, y, u)?.of(s, y)));
                }
                // The path bending at u: a new point source there (exact at saddle and
                // boundary vertices; elsewhere only when no unfolded ray reaches x).
                let at_u = Virtual::point(pu, du, t as u32);
                match best {
                    Some((d, s, giver)) if !(direct < d && self.bends_at(u)) => {
                        self.improve_from(x, d, s, giver)
                    }
                    _ => self.improve_from(x, direct, at_u, u),
                }
                if round_a_hole && x == p {
                    self.up_the_rim(u, t, x, y);
                }
            }
        }
        if at_a_book {
            self.offer_across_books(u);
        }
        if !open && !surface.faces_of(u).is_empty() {
            // Every neighbour was nearer: a local maximum, where fronts end.
            self.maxima.push(u as u32);
        }
    }

    /// Offers the unsettled corners among `p`, `q` of face `t` the path bending at settled
    /// `u` (a point source there).
    #[inline(never)]
    pub(super) fn bend_into(&mut self, u: usize, t: usize, p: usize, q: usize) {
        let pu = self.surface.mesh.positions()[u];
        let du = self.dist[u];
        for x in [p, q] {
            if !self.settled[x] {
                let direct = du + (self.surface.mesh.positions()[x] - pu).norm();
                self.improve_from(x, direct, Virtual::point(pu, du, t as u32), u);
            }
        }
    }

    /// Replaces the segment source of settled `u` by a point source at its foot (the
    /// segment's point nearest to `u`, at the same distance), so that it is unfolded around
    /// `u` as point sources are (see `fan_walk.rs`).
    #[inline(never)]
    fn source_to_point(&mut self, u: usize) {
        let s = self.src[u];
        let pu = self.surface.mesh.positions()[u];
        let n = &self.surface.face_normals[s.face as usize];
        let f = foot(&pu, &s.p, &s.q, &s.run_on, n, self.reach);
        self.src[u] = Virtual::point(f, s.sigma, s.face);
        if !self.piece.is_empty() {
            self.piece[u] = NO_PIECE;
        }
    }
}
