//! Where an unfolding round a sharp vertex holds: the wedge of directions from a point source
//! through the faces walked round the vertex (see `fan_walk.rs`), carried on with the source,
//! and the path bending at the wedge's side for a vertex beyond it.
//!
//! Source: none. It borrows the idea of the windows of exact propagation (Mitchell, Mount &
//!         Papadimitriou 1987; Surazhsky et al. 2005): an unfolded source holds only for the
//!         rays that cross every edge it was unfolded across, and a ray past the end of such
//!         an edge bends there or takes another unfolding. Here a vertex keeps one wedge, not a
//!         list of windows. It is set only where a point source is walked round a sharp
//!         vertex, and a side is bounded only by a vertex whose angle defect `δ`, times its
//!         distance `ρ` from the source, exceeds [`DEFECT_REACH`] mean edges. Passing such a
//!         vertex on the wrong side would misplace the source by about `ρ·δ`. Passing a
//!         vertex of small defect misplaces it by less, and is allowed: on the smooth parts
//!         of a surface, neighbouring strips unfold the source alike, and bounding every side
//!         would bend the paths at every vertex. A path bending at a reflex vertex of the
//!         boundary (the rim of a hole, see `shadow.rs`) holds over that vertex's faces only:
//!         its wedge is their angles at the vertex, and a ray beyond it crosses the gap (no
//!         path bends there: such an offer is refused).
//! Input:  the edges walked round a sharp vertex (laid out in one plane), their far vertices.
//! Output: per vertex, the wedge its point source holds in, and at an offer from beyond it the
//!         path bending at the vertex on the side crossed, a new point source there.
//! Why:    a wing-body model (5 cm edges) from vertex 0: a point source walked round a crease
//!         4.2 m from it (faces 55° apart) was carried on past where the straight way from it
//!         crosses the crease, and offered distances up to 0.28 m short of the exact ones at
//!         7 m (its rays 10–14° off the exact ones). Bounded by its wedge the largest error is 0.027 m, the mean 0.003 m (0.020 m
//!         before; the fast method's 0.005). Refusing the rays beyond the wedge without the
//!         bend left vertices to bends at their neighbours, too long (in a trial, an Orion
//!         model from vertex 3000 came out 4.3 m off exact instead of 2.5 m).
//! Cost:   nothing until a walk bounds a wedge: the wedges (16 bytes a vertex) are allocated
//!         then, the cached defects (4 bytes) when first asked (here, or by
//!         [`Solver::handed_on`]), both counted in the memory refused up front; an
//!         `atan2` per improvement of a vertex whose source holds in a bounded wedge, and one
//!         per offer it makes.

use super::{corners_after, Offered, Solver, Virtual};
use crate::geodesic::unfolding::corner_angle;
use crate::math::{Point3, Real, Vector3};

/// A vertex bounds a side of a wedge when its angle defect (radians) times its distance from
/// the source exceeds this many mean edges: the most a source unfolded on the wrong side of
/// it may be misplaced by (no paper; 0.01–1 was tried on five real models from five vertices
/// each: 0.1–1 gave much the same largest errors, 0.01 more bends; at 0.3 a sphere of 3072
/// triangles, where every vertex is walked, ran 5 % further from the analytic distance than
/// the exact method does, at 0.5 no further than before).
const DEFECT_REACH: Real = 0.5;
/// Slack (radians) of the test whether a ray lies within a wedge: far above the rounding of
/// the angles kept in `f32`, far below the angles between the rays to neighbouring vertices.
const SLACK: Real = 1e-6;

/// The directions from a point source in which the unfolding that carried it holds, as the
/// angles (about the normal of the source's face, counter-clockwise positive) of its two
/// sides from the ray from the source to the vertex that holds it, and the distance from the
/// source to the vertex that bounds each side (where a path beyond it bends).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Wedge {
    side: [f32; 2],
    reach: [f32; 2],
}

impl Wedge {
    /// Every direction.
    pub(super) const OPEN: Wedge = Wedge {
        side: [f32::NEG_INFINITY, f32::INFINITY],
        reach: [0.0, 0.0],
    };

    pub(super) fn is_open(&self) -> bool {
        self.side == Wedge::OPEN.side
    }

    /// The same wedge measured from a ray at angle `phi` from the present one.
    fn measured_from(&self, phi: Real) -> Wedge {
        Wedge {
            side: self.side.map(|a| (Real::from(a) - phi) as f32),
            reach: self.reach,
        }
    }

    /// The directions within both (each side the tighter of the two).
    fn within(&self, other: &Wedge) -> Wedge {
        let mut w = *self;
        if other.side[0] > w.side[0] {
            (w.side[0], w.reach[0]) = (other.side[0], other.reach[0]);
        }
        if other.side[1] < w.side[1] {
            (w.side[1], w.reach[1]) = (other.side[1], other.reach[1]);
        }
        w
    }

    /// The side a ray at angle `phi` lies beyond (its angle and the distance to its vertex),
    /// `None` when the ray lies within.
    fn beyond(&self, phi: Real) -> Option<(Real, Real)> {
        let side = if phi < Real::from(self.side[0]) - SLACK {
            0
        } else if phi > Real::from(self.side[1]) + SLACK {
            1
        } else {
            return None;
        };
        Some((Real::from(self.side[side]), Real::from(self.reach[side])))
    }
}

/// Signed angle from `a` to `b` about `n` (both perpendicular to it), bit-identical on every
/// platform.
fn angle_about(a: &Vector3, b: &Vector3, n: &Vector3) -> Real {
    libm::atan2(a.cross(b).dot(n), a.dot(b))
}

impl Solver<'_> {
    /// |Angle defect| at `v` (`∞` on the boundary of the active faces), cached.
    fn defect(&mut self, v: usize) -> Real {
        if self.defect.is_empty() {
            self.defect = vec![f32::NAN; self.dist.len()];
        }
        if self.defect[v].is_nan() {
            self.defect[v] = self.defect_uncached(v) as f32;
        }
        Real::from(self.defect[v])
    }

    /// |Angle defect| at `v` (`∞` on the boundary of the active faces).
    fn defect_uncached(&self, v: usize) -> Real {
        super::super::unfolding::angle_defect(self.surface, v).map_or(Real::INFINITY, Real::abs)
    }

    /// Whether a point source at distance `reach` from `v`, unfolded on the wrong side of `v`
    /// (or turned about it in one rotation), is misplaced by more than [`DEFECT_REACH`]
    /// allows.
    pub(super) fn misplaces(&mut self, v: usize, reach: Real) -> bool {
        self.defect(v) * reach > DEFECT_REACH * self.surface.mean_edge
    }

    /// [`Self::misplaces`] without the cache.
    pub(super) fn misplaces_uncached(&self, v: usize, reach: Real) -> bool {
        self.defect_uncached(v) * reach > DEFECT_REACH * self.surface.mean_edge
    }

    /// The wedge of the rays from the point source at `u + dir` (in the plane of normal `n`)
    /// that cross every edge walked so far round `u` ([`Solver::crossed`], from `u`, their
    /// far vertices in [`Solver::crossed_to`]), measured from the ray to `u`: each edge lets
    /// through the rays between `u` and its far vertex; only vertices of large enough defect
    /// (see [`DEFECT_REACH`]) bound it.
    pub(super) fn walked_wedge(&mut self, u: usize, dir: &Vector3, n: &Vector3) -> Wedge {
        let to_u = -dir;
        let at_u = dir.norm();
        let u_bounds = self.misplaces(u, at_u);
        let mut w = Wedge::OPEN;
        for i in 0..self.crossed.len() {
            let to_e = self.crossed[i] - dir;
            let psi = angle_about(&to_u, &to_e, n);
            let at_e = to_e.norm();
            let e_bounds = self.misplaces(self.crossed_to[i] as usize, at_e);
            // The edge spans the rays from angle 0 (to u) to `psi` (to its far vertex).
            let (near, far) = if psi < 0.0 { (1, 0) } else { (0, 1) };
            let mut edge = Wedge::OPEN;
            if u_bounds {
                (edge.side[near], edge.reach[near]) = (0.0, at_u as f32);
            }
            if e_bounds {
                (edge.side[far], edge.reach[far]) = (psi as f32, at_e as f32);
            }
            w = w.within(&edge);
        }
        if !w.is_open() && self.wedge.is_empty() {
            self.wedge = vec![Wedge::OPEN; self.dist.len()];
        }
        w
    }

    /// `None` when the ray from point source `s` (in the plane of normal `n`) to `px` lies
    /// within the wedge of `giver`'s source; else what it offers instead: the path to `px`
    /// bending at the vertex on the side it crosses (a point source there, in face `t`), if
    /// it keeps to [`Solver::holds`] across the edge whose other end is `other`. Out of line:
    /// the settling loop keeps one copy of the checks.
    #[inline(never)]
    pub(super) fn beyond_wedge(
        &self,
        s: &Virtual,
        t: usize,
        px: &Point3,
        giver: usize,
        other: usize,
        n: &Vector3,
    ) -> Option<Option<Offered>> {
        let pg = self.surface.mesh.positions()[giver];
        let to_giver = pg - s.p;
        let phi = angle_about(&to_giver, &(px - s.p), n);
        let (side, reach) = self.wedge[giver].beyond(phi)?;
        if reach == 0.0 {
            // Beyond a border's faces (see `rim_wedge`): across the gap, no path at all.
            return Some(None);
        }
        let g = to_giver.normalize();
        let bend = s.p + (g * libm::cos(side) + n.cross(&g) * libm::sin(side)) * reach;
        let sigma = s.sigma + reach;
        let bend = Virtual::point(bend, sigma, t as u32);
        let d = sigma + (px - bend.p).norm();
        Some(
            self.holds(d, &bend, px, giver, other)
                .then_some(Offered::Bend(d, bend)),
        )
    }

    /// Whether `s` is the path bending at `giver` on the border of a surface with gaps (see
    /// `shadow.rs`): its rays hold only over the faces round `giver` (see [`Self::rim_wedge`]).
    pub(super) fn bends_at_a_gap(&self, s: &Virtual, giver: usize) -> bool {
        self.gap_rings.get(giver) == Some(&0)
            && s.p == s.q
            && s.p == self.surface.mesh.positions()[giver]
    }

    /// The wedge of the rays from boundary vertex `u` that leave it over its faces, measured
    /// from the ray to its neighbour `x`: the faces' angles at `u` summed each way round from
    /// the edge to `x` up to the border. A ray beyond it crosses the gap beside `u`, so no
    /// side is a place to bend (reach 0, see [`Self::beyond_wedge`]).
    fn rim_wedge(&self, u: usize, x: usize) -> Wedge {
        let surface = self.surface;
        let tris = surface.mesh.triangles();
        let faces = surface.faces_of(u);
        // Counter-clockwise about the faces' normals: from the edge u → a of a face (u, a, b)
        // to u → b; clockwise the other way. Each step takes a face, so the walk ends; a
        // fan that closes (no border) bounds nothing.
        let turn = |ccw: bool| -> Real {
            let (mut from, mut sum) = (x, 0.0);
            for _ in 0..faces.len() {
                let next = faces.iter().find_map(|&f| {
                    let (a, b) = corners_after(tris[f as usize], u);
                    match ccw {
                        true => (a == from).then_some((f as usize, b)),
                        false => (b == from).then_some((f as usize, a)),
                    }
                });
                let Some((f, to)) = next else {
                    return sum;
                };
                sum += corner_angle(surface, f, u).1;
                from = to;
                if from == x {
                    break;
                }
            }
            Real::INFINITY
        };
        Wedge {
            side: [-turn(false) as f32, turn(true) as f32],
            reach: [0.0, 0.0],
        }
    }

    /// The wedge `x` holds its new source `s` in, handed on by `giver`: the giver's own,
    /// measured from the ray to `x`, when `s` is the giver's source moved (not a bend);
    /// within `walked` too (a wedge from a walk round `giver`, measured from the ray to it);
    /// for a bend at a border, the faces round it (see [`Self::rim_wedge`]).
    pub(super) fn pass_wedge(&mut self, x: usize, s: &Virtual, giver: usize, walked: &Wedge) {
        if self.bends_at_a_gap(s, giver) {
            self.wedge[x] = self.rim_wedge(giver, x);
            return;
        }
        let own = self.src[giver];
        let pos = self.surface.mesh.positions();
        let w = self.wedge[giver].within(walked);
        self.wedge[x] = if s.p != s.q || s.sigma != own.sigma || s.p == pos[giver] || w.is_open() {
            Wedge::OPEN
        } else {
            let n = &self.surface.face_normals[s.face as usize];
            w.measured_from(angle_about(&(pos[giver] - s.p), &(pos[x] - s.p), n))
        };
    }
}

#[cfg(test)]
mod tests {
    use super::{Wedge, SLACK};

    #[test]
    fn a_wedge_keeps_the_tighter_sides_and_turns_with_its_ray() {
        let a = Wedge {
            side: [-0.5, 0.25],
            reach: [2.0, 3.0],
        };
        let b = Wedge {
            side: [-0.25, f32::INFINITY],
            reach: [4.0, 0.0],
        };
        let w = a.within(&b);
        assert_eq!(w.side, [-0.25, 0.25]);
        assert_eq!(w.reach, [4.0, 3.0]);
        assert_eq!(Wedge::OPEN.within(&a), a);
        assert!(w.beyond(0.0).is_none());
        assert!(w.beyond(0.25 + SLACK / 2.0).is_none());
        assert_eq!(w.beyond(0.3), Some((0.25, 3.0)));
        assert_eq!(w.beyond(-0.3), Some((-0.25, 4.0)));
        // Measured from a ray at 0.25, the old ray lies at -0.25.
        let turned = w.measured_from(0.25);
        assert_eq!(turned.side, [-0.5, 0.0]);
        assert!(Wedge::OPEN.measured_from(1.0).is_open());
        assert!(Wedge::OPEN.beyond(1e30).is_none());
    }
}
