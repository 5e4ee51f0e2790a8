//! Seeding: windows from the pieces of the source curve (line windows where an edge point's
//! foot falls inside a piece, point windows from its ends where an end is the nearest point).

use super::super::surface::segment_distance;
use super::front::{dot, half_line, meet, norm2, point, Frame, Front, Seed, Window};
use super::pieces::Piece;
use super::{Solver, MIN_WIDTH, ON_LINE_TOLERANCE};
use crate::math::{Real, Vector3};

impl Solver<'_> {
    /// Seeds a window over `[b0, b1]` of the edge in slot `k` of `g`, crossing into the face
    /// beyond; `make` builds the front in that half-edge's frame.
    ///
    /// Across an edge of many faces the windows are the same in every face beyond (the
    /// distances along the edge do not depend on the face they are unfolded into): when
    /// the first face's are all dominated with room to spare (twice the filter's tolerance,
    /// far above the rounding of another frame), the other faces are not looked at. Without
    /// this, every corner of a book of `n` pages restarting as a pseudo-source sent `n`
    /// windows across its spine, `n²` in all, each refused.
    pub(super) fn seed_edge(&mut self, g: usize, k: usize, make: &dyn Fn(&Frame) -> Vec<Seed>) {
        let mut twins = self.twins(g, k).peekable();
        let mut first = true;
        while let Some((h, j)) = twins.next() {
            let Some(fr) = self.frame(h, j) else {
                continue;
            };
            let window = |(b0, b1, front): Seed| Window {
                face: h as u32,
                slot: j as u8,
                b0: b0.max(0.0),
                b1: b1.min(fr.l),
                front,
            };
            let seeds = make(&fr);
            if std::mem::take(&mut first)
                && twins.peek().is_some()
                && seeds
                    .iter()
                    .all(|&s| self.dominated_by(&window(s), fr.l, fr.v[0], fr.v[1], 2.0))
            {
                return;
            }
            for s in seeds {
                self.offer(window(s), &fr);
            }
        }
    }

    /// Source piece `p → q` lying in face `g`: distances of its corners, and windows on its
    /// edges (line windows where the foot point is inside the piece, point windows from
    /// its ends where the end is the nearest point of the piece and of its neighbour).
    pub(super) fn seed_piece(&mut self, piece: &Piece) {
        let (g, p, q) = (piece.face, piece.p, piece.q);
        let mesh = self.surface.mesh;
        let t = mesh.triangles()[g];
        for v in t {
            let v = v as usize;
            let x = mesh.positions()[v];
            let at_end = (x - p).norm().min((x - q).norm()) <= ON_LINE_TOLERANCE * self.scale;
            let (d, _) = segment_distance(&x, &p, &q);
            let foot = {
                let e = q - p;
                let t = if e.norm_squared() > 0.0 {
                    ((x - p).dot(&e) / e.norm_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                p + e * t
            };
            let back = (d > ON_LINE_TOLERANCE * self.scale).then(|| (g, foot - x));
            self.reach(v, d, at_end, back);
        }
        if self.degenerate[g] {
            return;
        }
        for k in 0..3 {
            let pd = mesh.positions()[t[(k + 2) % 3] as usize];
            self.seed_edge(g, k, &|fr: &Frame| {
                let (p2, q2) = (fr.unfold(&p), fr.unfold(&q));
                // A direction of g's plane in this frame (g lies at y < 0).
                let w = pd - fr.a;
                let ng = (w - fr.ex * w.dot(&fr.ex)).try_normalize(0.0);
                let flat = |d: Vector3| ng.map(|n| [d.dot(&fr.ex), -d.dot(&n)]);
                let s = [q2[0] - p2[0], q2[1] - p2[1]];
                let len = norm2(s[0], s[1]);
                if len <= ON_LINE_TOLERANCE * fr.l {
                    return vec![(0.0, fr.l, point(p2, 0.0))];
                }
                let s = [s[0] / len, s[1] / len];
                // The foot on the line pq of edge point x is at τ(x) = ((x − p)·s) / |pq|:
                // p is the nearest point of the piece where τ ≤ 0, q where τ ≥ 1, the line
                // between (one window each: the distance to a segment).
                let none = (Real::INFINITY, Real::NEG_INFINITY);
                let line = match half_line(p2, s, 1.0) {
                    Some(a) => meet(a, half_line(q2, s, -1.0).unwrap_or(none)),
                    None => none,
                };
                let mut near_p = half_line(p2, s, -1.0).unwrap_or(none);
                let mut near_q = half_line(q2, s, 1.0).unwrap_or(none);
                // An end is the nearest point of the neighbouring piece too only where the
                // neighbour's foot falls beyond it.
                if let Some(d) = piece.before.and_then(flat) {
                    near_p = meet(near_p, half_line(p2, d, 1.0).unwrap_or(none));
                }
                if let Some(d) = piece.after.and_then(flat) {
                    near_q = meet(near_q, half_line(q2, d, -1.0).unwrap_or(none));
                }
                if !piece.seed_p {
                    near_p = none;
                }
                let mut out = Vec::new();
                for (range, end) in [(near_p, p2), (near_q, q2)] {
                    let (lo, hi) = (range.0.max(0.0), range.1.min(fr.l));
                    if hi - lo > MIN_WIDTH * fr.l {
                        out.push((lo, hi, point(end, 0.0)));
                    }
                }
                let (mut lo, mut hi) = line;
                lo = lo.max(0.0);
                hi = hi.min(fr.l);
                // The line pq crosses the edge's line: split, the normal flips there.
                let mut cuts = vec![lo];
                if s[1].abs() > ON_LINE_TOLERANCE {
                    let xs = p2[0] - p2[1] * s[0] / s[1];
                    if xs > lo && xs < hi {
                        cuts.push(xs);
                    }
                }
                cuts.push(hi);
                for w in cuts.windows(2) {
                    if w[1] - w[0] <= MIN_WIDTH * fr.l {
                        continue;
                    }
                    let m = [0.5 * (w[0] + w[1]) - p2[0], -p2[1]];
                    let mut n = [-s[1], s[0]];
                    let side = dot(n, m);
                    if side < -ON_LINE_TOLERANCE * fr.l
                        || (side.abs() <= ON_LINE_TOLERANCE * fr.l && n[1] < 0.0)
                    {
                        n = [-n[0], -n[1]];
                    }
                    if n[1] > ON_LINE_TOLERANCE {
                        let c = -dot(n, p2);
                        out.push((
                            w[0],
                            w[1],
                            Front::Line {
                                ux: n[0],
                                uy: n[1],
                                c,
                            },
                        ));
                    }
                }
                out
            });
        }
    }
}
