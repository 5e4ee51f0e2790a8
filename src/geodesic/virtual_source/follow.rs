//! Following a source curve past the end of a piece: a vertex settled past an end of the
//! piece it holds looks at the next pieces of the curve, carried rigidly with the one it
//! holds, and takes the nearest.
//!
//! Source: none (a deviation from Trettner, Bommes & Kobbelt 2021, whose sources are points;
//!         see `virtual_source.rs` for pieces of curves as sources).
//! Input:  a vertex of a [`Solver`] being settled, its source a piece of a source curve, and
//!         the curve's pieces as the seeding lists them ([`CurvePiece`], `seeding.rs`).
//! Output: its distance and source lowered to the nearest of those pieces.
//! Why:    each vertex holds one piece. A piece shorter than the spacing of the vertices can
//!         be the nearest to a vertex whose neighbours each hold a nearer piece of their own,
//!         and those stop at their ends on the convex side of the curve: the vertex got such
//!         an end. The cap from a plane between its vertices was up to 1.15 mm off at 20k
//!         triangles and 0.16 mm at 1M, within a few rings of the section (now 0.14 and
//!         0.0043). Where the curve turns towards the vertex instead, the piece runs on
//!         along its line (see [`RunOn`]), which lies further from the vertex than the curve
//!         by about u²/2ρ at u past the end (ρ the curve's radius of curvature on the
//!         surface): the next pieces are nearer there too. The cap from its section at
//!         θ = 0.6, on the concave side: up to 0.011 mm above the exact method where a
//!         vertex's foot lay one to three pieces past its own at 500k triangles, mean
//!         0.0017 mm (following there too: 0.0013). A carry is taken only for a gain of
//!         [`FOLLOW_GAIN`] of an edge.
//! Guards: pieces are carried only while the source's plane has turned by less than 18°
//!         since it was seeded and across faces of the curve within 3.6° of the held piece's
//!         (unlimited, a carry across creases put a coarse BWB patch a third of an edge off
//!         exact), and never below the straight line to where they lie.
//! Cost:   an inline test per settled vertex; where it holds, two frames and up to
//!         [`FOLLOW_PIECES`] carried pieces (a tenth more time on the bench's section through
//!         a ring of vertices, most of whose convex side lies past an end; following past
//!         the ends that run on too: up to 5 % more, on the cap from its rim).

use super::{foot, RunOn, Solver, Virtual, BOUND_SLACK};
use crate::geodesic::surface::segment_distance;
use crate::math::{Point3, Real, Vector3};

/// Pieces of the curve [`Solver::follow_curve`] looks at beyond an end.
const FOLLOW_PIECES: usize = 4;
/// Pieces (sub-pieces of straight runs included) [`Solver::follow_curve`] steps over at most.
const FOLLOW_STEPS: usize = 256;
/// Faces under the pieces followed must be this close to coplanar (cosine of the angle
/// between their normals and the held piece's) for a rigid carry (as in `fan_walk.rs`).
const FOLLOW_COSINE: Real = 0.998;
/// [`Solver::follow_curve`] carries pieces only for sources whose plane has turned by less
/// than this (cosine, 18°) since they were seeded.
const FOLLOW_TURN_COSINE: Real = 0.95;

/// Least gain (in mean edge lengths) for which [`Solver::follow_curve`] takes a carried piece
/// (no paper): a carried piece is placed rigidly against the held one, a copy of its own
/// piece that came another way along the surface, and the two copies of a piece differ by
/// about as much. Taking every gain let carried pieces win by that difference ever further
/// from the curve, where a neighbour's own piece or the held piece's end is the answer: the
/// cap from its section at θ = 0.6 was up to 0.009 mm above the exact method 60–400 mm
/// out on the convex side (0.0040 with this bound; max error against R·|θ − 0.6| at 150k,
/// 500k, 2M triangles: 0.031, 0.0116, 0.0058 mm before, 0.018, 0.0095, 0.0031 with it; 0.0005
/// gave the same, 0.002 up to 0.001 mm more).
const FOLLOW_GAIN: Real = 1e-3;

/// No piece of a source curve (see `Solver::piece`).
pub(super) const NO_PIECE: u32 = u32::MAX;
/// Marks in `Solver::piece` a piece carried along the curve by [`Solver::follow_curve`].
const CARRIED: u32 = 1 << 31;

/// A piece of a source curve as seeded (see `seeding.rs`), with what
/// [`Solver::follow_curve`] needs to carry its neighbours along with it.
#[derive(Clone, Copy, Debug)]
pub(super) struct CurvePiece {
    pub(super) p: Point3,
    pub(super) q: Point3,
    pub(super) normal: Vector3,
    pub(super) run_on: [[RunOn; 2]; 2],
    /// The pieces before `p` and after `q` along the curve ([`NO_PIECE`] past an open end).
    pub(super) before: u32,
    pub(super) after: u32,
}

impl Solver<'_> {
    /// Whether settled `v` holds a piece of a source curve and lies past an end of it:
    /// `Some(true)` past `q`, `Some(false)` past `p`. Inline, since most vertices are not.
    #[inline(always)]
    pub(super) fn past_an_end(&self, v: usize) -> Option<bool> {
        if self.piece[v] == NO_PIECE {
            return None;
        }
        let sv = &self.src[v];
        let e = sv.q - sv.p;
        let w = self.surface.mesh.positions()[v] - sv.p;
        let (along, l2) = (w.dot(&e), e.norm_squared());
        // (A zero-length piece, or NaN, is never past an end.)
        if l2.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || (0.0..=l2).contains(&along)
        {
            return None;
        }
        Some(along > l2)
    }

    /// Settling `v`, past an end of its piece (beyond `q` when `beyond_q`, see
    /// [`Self::past_an_end`]): the next pieces of the curve beyond that end, carried
    /// rigidly with the piece it holds, may be nearer; `v` takes the nearest.
    #[inline(never)]
    pub(super) fn follow_curve(&mut self, v: usize, beyond_q: bool) {
        let k = self.piece[v] & !CARRIED;
        let sv = self.src[v];
        let pv = self.surface.mesh.positions()[v];
        let n = self.surface.face_normals[sv.face as usize];
        let held = self.pieces[k as usize];
        // Only where the source's plane has turned by less than 18° since it was seeded: on a
        // coarse creased patch (a BWB's, edges of 1.3 m) a carry across creases put a piece
        // off by a third of an edge.
        if n.dot(&held.normal) < FOLLOW_TURN_COSINE {
            return;
        }
        // The rigid motion taking the held piece (in the curve's frame) onto the source.
        let frame = |p: &Point3, q: &Point3, normal: &Vector3| {
            let e1 = (q - p).normalize();
            let e3 = (normal - e1 * normal.dot(&e1)).normalize();
            (e1, e3.cross(&e1), e3)
        };
        let (a1, a2, a3) = frame(&held.p, &held.q, &held.normal);
        let (b1, b2, b3) = frame(&sv.p, &sv.q, &n);
        if !(a3.iter().all(|c| c.is_finite()) && b3.iter().all(|c| c.is_finite())) {
            return;
        }
        let carry = |y: &Point3| {
            let w = y - held.p;
            sv.p + b1 * w.dot(&a1) + b2 * w.dot(&a2) + b3 * w.dot(&a3)
        };
        let mut best = (self.dist[v], k);
        let (mut j, mut last, mut runs) = (k, (held.p, held.q), 0);
        // Each step moves one piece along the curve, at most FOLLOW_STEPS of them.
        for _ in 0..FOLLOW_STEPS {
            let here = &self.pieces[j as usize];
            j = if beyond_q { here.after } else { here.before };
            if j == NO_PIECE || j == k {
                break;
            }
            let c = self.pieces[j as usize];
            // The sub-pieces of one straight run hold the run: the next run is the next piece.
            if (c.p, c.q) == last {
                continue;
            }
            // Carried rigidly only where the curve's faces are nearly coplanar.
            if c.normal.dot(&held.normal) < FOLLOW_COSINE {
                break;
            }
            last = (c.p, c.q);
            runs += 1;
            if runs > FOLLOW_PIECES {
                break;
            }
            let (p, q) = (carry(&c.p), carry(&c.q));
            let d = (pv - foot(&pv, &p, &q, &c.run_on, &n, self.reach)).norm();
            // No path to the curve is shorter than the straight line to the piece where it
            // lies: a carry below it went across creases on the way, and is not taken.
            let (straight, _) = segment_distance(&pv, &c.p, &c.q);
            if !(d < best.0 && d >= straight * (1.0 - BOUND_SLACK)) {
                // Where the curve turns away, the distance along it falls to the nearest
                // point and then grows: past it, no piece further on is nearer.
                break;
            }
            best = (d, j);
        }
        if best.1 != k && best.0 < self.dist[v] - FOLLOW_GAIN * self.surface.mean_edge {
            let c = self.pieces[best.1 as usize];
            self.dist[v] = best.0;
            self.src[v] = Virtual {
                p: carry(&c.p),
                q: carry(&c.q),
                sigma: 0.0,
                face: sv.face,
                run_on: c.run_on,
            };
            self.piece[v] = best.1 | CARRIED;
        }
    }
}
