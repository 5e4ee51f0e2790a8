//! Point sources unfolded around sharp vertices: where the faces around a settled vertex bend
//! sharply (a crease, a coarse corner, the saddle of a wing root), its point source is
//! unfolded face by face around it rather than turned about it in one rotation, and offered
//! only where its straight way crosses the faces between. Each neighbour it reaches that way
//! keeps the wedge of rays that cross the same edges (see `wedge.rs`), and the vertices after
//! it hold the source only within that wedge.
//!
//! Source: none (a deviation from Trettner, Bommes & Kobbelt 2021, who turn every source
//!         about the vertex; see `virtual_source.rs`).
//! Input:  a settled vertex of a [`Solver`] whose source is a point.
//! Output: offers to its neighbours, as [`Solver::settle`] makes them on smooth surfaces.
//! Why:    turning misplaces a source by up to the angle defect of the faces between times
//!         its distance, and offers fall short (0.34 m at 1.8 m on a thin box of an airliner
//!         model, a drift of millimetres a step along a wing root). A segment (a piece of a
//!         source curve) is turned as before: its rays to the fan leave it from different
//!         points, most not passing the vertex (walking them took the BWB's patch from 0.36
//!         to 1.2 m off exact). Far from its curve, a sharp vertex first takes its piece as
//!         a point source at the piece's foot, and walks that (see `virtual_source.rs`).
//! Cost:   a rotation and a 3 × 3 product per face walked, a crossing test and a wedge
//!         bound per edge walked before it (fans are small); only at sharp vertices, none on
//!         the bench's meshes.

use super::{
    corners_after, Offered, Rotation, Solver, Virtual, Wedge, CROSSING_TOLERANCE, FOLD_COSINE,
};
use crate::math::{Real, Vector3};

/// Cosine of the angle between the plane of a vertex's point source and a face around it
/// below which the source is unfolded across the faces between rather than turned about the
/// vertex (see [`Solver::walk_fan`]): 3.6°, the creases, corners and wing roots of real
/// models. Finely meshed smooth surfaces stay well within it (the bench's spheres and caps,
/// to the bit as before); on coarser ones the walk's refusal of rays that enter a face from
/// beyond the fan costs about what its exactness gains (a sphere of radius 100 in 3072
/// triangles, all walked: 0.386 mm off the analytic distance at most, the exact method
/// 0.380; with every vertex walked down to 1.1°, 0.2 mm off exact at 12k triangles where
/// turning is 0.05).
const SHARP_COSINE: Real = 0.998;

/// Whether the segment `a → c` crosses the segment `0 → e` (all in one plane, normal `n`;
/// touching at an end counts, within [`CROSSING_TOLERANCE`]).
fn crosses(a: &Vector3, c: &Vector3, e: &Vector3, n: &Vector3) -> bool {
    let side = |p: &Vector3, q: &Vector3, x: &Vector3| (q - p).cross(&(x - p)).dot(n);
    let o = Vector3::zeros();
    let scale = a.norm().max(c.norm()).max(e.norm());
    let z = CROSSING_TOLERANCE * scale * scale;
    let apart = |x: Real, y: Real| !((x > z && y > z) || (x < -z && y < -z));
    apart(side(&o, e, a), side(&o, e, c)) && apart(side(a, c, &o), side(a, c, e))
}

impl Solver<'_> {
    /// Settles `u` by [`Self::settle_walked`] if the faces around it are sharp (see
    /// [`Self::is_sharp`]) and its point source gives a direction there; `false` when it is
    /// left to [`Self::settle`]. Out of line, to keep the common case's code tight.
    #[inline(never)]
    pub(super) fn settled_walking(&mut self, u: usize) -> bool {
        let walk = self.is_sharp(u, self.src[u].face as usize) && self.walk_fan(u);
        if walk {
            self.settle_walked(u);
        }
        walk
    }

    /// [`Self::settle`] at a sharp vertex, its point source unfolded by [`Self::walk_fan`]:
    /// each neighbour is offered the source as unfolded into the face between (or as it is,
    /// in the source's own face), else the other corner's source, else the bend at `u`.
    #[inline(always)]
    fn settle_walked(&mut self, u: usize) {
        let surface = self.surface;
        let (pos, tris) = (surface.mesh.positions(), surface.mesh.triangles());
        let su = self.src[u];
        let (pu, du) = (pos[u], self.dist[u]);
        let mut open = false;
        let at_a_book = self.book_vertex.get(u) == Some(&true);
        for &t in surface.faces_of(u) {
            let t = t as usize;
            let (p, q) = corners_after(tris[t], u);
            if self.settled[p] && self.settled[q] {
                continue;
            }
            open = true;
            // As in `Solver::settle`: a sliver glued on at u has no plane.
            if at_a_book && surface.is_sliver(t) {
                self.bend_into(u, t, p, q);
                continue;
            }
            for (x, y) in [(p, q), (q, p)] {
                if self.settled[x] {
                    continue;
                }
                // A walked source holds within its wedge; a bend beyond a wedge in none.
                let take = |o: Offered, s: Virtual, w: Wedge| match o {
                    Offered::Ray(d) => (d, s, w),
                    Offered::Bend(d, bend) => (d, bend, Wedge::OPEN),
                };
                let mut best: Option<(Real, Virtual, Wedge)> = None;
                if su.face as usize == t {
                    best = self
                        .offer(&su, t, x, u, y, y)
                        .map(|o| take(o, su, Wedge::OPEN));
                } else {
                    for i in 0..self.walked.len() {
                        let (g, c, s, w) = self.walked[i];
                        if g as usize == t && c as usize == x {
                            if let Some(o) = self.offer(&s, t, x, u, y, y) {
                                let offered = take(o, s, w);
                                if best.is_none_or(|(b, _, _)| offered.0 < b) {
                                    best = Some(offered);
                                }
                            }
                        }
                    }
                }
                let mut giver = u;
                if best.is_none() && self.settled[y] {
                    best = self
                        .handed_on(y, t)
                        .and_then(|s| Some(take(self.offer(&s, t, x, u, y, u)?, s, Wedge::OPEN)));
                    giver = y;
                }
                // The bend at u where nothing shorter reaches x (here the source offered may
                // be the other corner's, not bounded by it).
                let direct = du + (pos[x] - pu).norm();
                match best {
                    Some((d, s, w)) if d <= direct => {
                        self.improve_walked(x, d, s, giver, &w);
                    }
                    _ => self.improve_from(x, direct, Virtual::point(pu, du, t as u32), u),
                }
            }
        }
        if !open && !surface.faces_of(u).is_empty() {
            self.maxima.push(u as u32);
        }
    }

    /// The source of settled `y` moved into face `t`, to be offered again to a neighbour of
    /// both (see [`Solver::settle`]); `None` when it is a point source, `t` bends sharply
    /// from its face, and turning it about `y` would misplace it by more than the wedges allow
    /// (see `wedge.rs`): `y` offered it unfolded across the faces between when it was
    /// settled. (On a closed twisted 7-sided can, radius 1, the source turned about a rim
    /// vertex offered 0.05 less than the exact distance a step up the side, 0.15 at the top
    /// rim. On a coarse sphere turning stays near right, and every vertex there is sharp.)
    #[inline(always)]
    pub(super) fn handed_on(&self, y: usize, t: usize) -> Option<Virtual> {
        let s = &self.src[y];
        if s.p == s.q && s.face as usize != t {
            let normals = &self.surface.face_normals;
            if normals[s.face as usize].dot(&normals[t]) < SHARP_COSINE && self.turn_misplaces(y) {
                return None;
            }
        }
        self.moved(y, t)
    }

    /// Whether turning the point source of `y` about `y` misplaces it (see
    /// [`Self::handed_on`]); out of line and uncached (`&self` keeps the settling loop's
    /// values in registers across the call), asked at sharp vertices only.
    #[inline(never)]
    fn turn_misplaces(&self, y: usize) -> bool {
        let reach = (self.src[y].p - self.surface.mesh.positions()[y]).norm();
        self.misplaces_uncached(y, reach)
    }

    /// Whether the faces around `u` bend away from `face` (the plane of its source) by more
    /// than [`SHARP_COSINE`] allows, so that turning the source about `u` is not close enough
    /// to unfolding it across the faces between.
    #[inline(always)]
    pub(super) fn is_sharp(&self, u: usize, face: usize) -> bool {
        let normals = &self.surface.face_normals;
        let n0 = normals[face];
        self.surface
            .faces_of(u)
            .iter()
            .any(|&t| n0.dot(&normals[t as usize]) < SHARP_COSINE)
    }

    /// Unfolds the point source of settled `u` face by face around `u`, both ways from the
    /// face it lies in, and lists in [`Self::walked`] each face whose new corner `c` the
    /// straight way from the source reaches across every edge walked (laid out in the first
    /// face's plane), with the source unfolded into that face's plane. `false` when the
    /// source gives no direction at `u` (it lies on `u`, or outside the corner of its face
    /// at `u`): then it is turned as on smooth surfaces.
    #[inline(always)]
    fn walk_fan(&mut self, u: usize) -> bool {
        self.walked.clear();
        let surface = self.surface;
        let (pos, tris) = (surface.mesh.positions(), surface.mesh.triangles());
        let normals = &surface.face_normals;
        let su = self.src[u];
        let (pu, f0) = (pos[u], su.face as usize);
        let n0 = normals[f0];
        // A point source (the caller checks): its rays all leave `su.p`.
        let dir = su.p - pu;
        let tol = 1e-9 * surface.mean_edge;
        let t0 = tris[f0];
        let Some(k) = t0.iter().position(|&w| w as usize == u) else {
            return false;
        };
        let (a, b) = (t0[(k + 1) % 3] as usize, t0[(k + 2) % 3] as usize);
        // The ray reaches u from inside the corner of its face (u was offered it across the
        // opposite edge; along an edge, within rounding, when it came from the vertex at its
        // other end); a seeded source need not.
        let (ua, ub) = (pos[a] - pu, pos[b] - pu);
        let slack = CROSSING_TOLERANCE * dir.norm();
        if dir.norm_squared() <= tol * tol
            || dir.cross(&ub).dot(&n0) < -slack * ub.norm()
            || ua.cross(&dir).dot(&n0) < -slack * ua.norm()
        {
            return false;
        }
        let fan = surface.faces_of(u).len();
        // Counter-clockwise across edge (b, u), then clockwise across edge (u, a).
        for first in [b, a] {
            let (mut f, mut edge, mut n, mut s) = (f0, first, n0, su);
            // The faces walked laid out in the plane of the first about u: the rotation back
            // from the current face's plane, the edges crossed (from u).
            let mut back = nalgebra::Matrix3::<Real>::identity();
            self.crossed.clear();
            self.crossed.push(pos[first] - pu);
            self.crossed_to.clear();
            self.crossed_to.push(first as u32);
            // One face a step, never back to the first: at most once round the fan.
            for _ in 0..fan {
                let t = tris[f];
                let Some(slot) = (0..3).find(|&j| {
                    let (v, w) = (t[j] as usize, t[(j + 1) % 3] as usize);
                    (v == u && w == edge) || (v == edge && w == u)
                }) else {
                    break;
                };
                let Some(g) = surface.across(f, slot) else {
                    break;
                };
                if g == f0 {
                    break;
                }
                let tg = tris[g];
                let Some(c) = tg
                    .iter()
                    .map(|&w| w as usize)
                    .find(|&w| w != u && w != edge)
                else {
                    break;
                };
                let ng = normals[g];
                let r = Rotation::new(&n, &ng);
                if r.c <= FOLD_COSINE {
                    break;
                }
                s = self.turned(&s, u, g, &r);
                back *= nalgebra::Matrix3::from_columns(&[
                    r.unapply(Vector3::x()),
                    r.unapply(Vector3::y()),
                    r.unapply(Vector3::z()),
                ]);
                let cc = back * (pos[c] - pu);
                // The straight way from the source to c crosses every edge walked within it
                // (else it leaves the fan and unfolds nothing real).
                if self.crossed.iter().all(|e| crosses(&dir, &cc, e, &n0)) {
                    let w = self.walked_wedge(u, &dir, &n0);
                    self.walked.push((g as u32, c as u32, s, w));
                }
                self.crossed.push(cc);
                self.crossed_to.push(c as u32);
                (f, edge, n) = (g, c, ng);
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::crosses;
    use crate::math::Vector3;

    #[test]
    fn crossing_counts_touching_ends_and_refuses_the_line_beyond() {
        let (z, e) = (Vector3::z(), Vector3::new(0.0, 1.0, 0.0));
        let (a, c) = (Vector3::new(-1.0, 0.5, 0.0), Vector3::new(1.0, 0.5, 0.0));
        assert!(crosses(&a, &c, &e, &z));
        // Through the far end of the edge, and past it.
        assert!(crosses(
            &Vector3::new(-1.0, 1.0, 0.0),
            &Vector3::new(1.0, 1.0, 0.0),
            &e,
            &z
        ));
        assert!(!crosses(
            &Vector3::new(-1.0, 1.5, 0.0),
            &Vector3::new(1.0, 1.5, 0.0),
            &e,
            &z
        ));
        // Both on one side.
        assert!(!crosses(&a, &Vector3::new(-0.1, 0.2, 0.0), &e, &z));
    }
}
