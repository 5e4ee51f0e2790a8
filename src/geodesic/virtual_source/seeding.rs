//! Seeding from a source curve: the curve cut into straight pieces (collinear samples joined,
//! each end allowed to run on only as far as the curve beyond allows, see [`RunOn`]), handed
//! to the corners of the faces the curve crosses, and to every face round a sample that lies
//! on a vertex.
//!
//! Source: none (the virtual sources of Trettner, Bommes & Kobbelt 2021 are points; see
//!         `virtual_source.rs` for segments as sources).
//! Input:  a resolved source curve (dense on-surface samples and the face under each).
//! Output: the first distances and sources of the [`Solver`], which piece of the curve each
//!         source is, and the pieces listed and linked along the curve (for
//!         `Solver::follow_curve`).
//! Cost:   O(samples · ([`STRAIGHT_PIECES`] + [`RUN_ON_SAMPLES`] + [`SEED_WINDOW`])).

use super::{
    segment_distance, CurvePiece, Rotation, RunOn, Solver, Surface, Virtual, FOLD_COSINE, NO_PIECE,
    ON_VERTEX, SEED_WINDOW, STRAIGHT,
};
use crate::geodesic::source::Curve;
use crate::math::{Point3, Real, Vector3};

/// Samples of the curve checked beyond the end of a piece, at most (the bound on the run-on
/// then rests on them; past them, or past the end of an open curve, a piece does not run on).
const RUN_ON_SAMPLES: usize = 32;
/// How far (in reaches) the curve beyond a piece's end may stray from its line away from a
/// vertex while the piece runs on for it: the most a run-on distance may fall short.
const RUN_ON_TOLERANCE: Real = 3e-4;

/// Pieces of a curve at most joined into one straight piece (see [`source_pieces`]).
const STRAIGHT_PIECES: usize = 64;

/// A straight piece of a source curve as the seeding hands it to vertices.
#[derive(Clone, Copy)]
struct SourcePiece {
    p: Point3,
    q: Point3,
    run_on: [[RunOn; 2]; 2],
}

/// For each piece `j` of `curve` (from point `j` to the next): the straight run of pieces it
/// belongs to (collinear neighbours within [`STRAIGHT`], up to [`STRAIGHT_PIECES`] each way:
/// the sub-pieces of one boundary edge, or of one segment of a polyline, make one piece), and
/// how far that may run on beyond each end, `[side][end]`: side 0 the vertices to the left of
/// the piece (about the normal of the face under its first point), side 1 those to the
/// right. The samples beyond an end up to `reach` along the piece's line give the bound (see
/// [`RunOn`]). Joining the straight runs matters where an edge of the boundary is longer than
/// the reach: a vertex beyond its end (past a corner of the boundary) is offered the corner
/// by a neighbour that holds any part of the edge. Cost: O(pieces · ([`STRAIGHT_PIECES`] +
/// [`RUN_ON_SAMPLES`])).
fn source_pieces(curve: &Curve, normals: &[Vector3], reach: Real) -> Vec<SourcePiece> {
    let n = curve.points.len();
    let closed = curve.closed && n > 2;
    let segs = if closed { n } else { n.saturating_sub(1) };
    let pts = &curve.points;
    // Point `i` of the curve (wrapped round a closed one), `None` past an open one's ends.
    let at = |i: isize| -> Option<usize> {
        if closed {
            Some(i.rem_euclid(n as isize) as usize)
        } else {
            (0..n as isize).contains(&i).then_some(i as usize)
        }
    };
    // Whether the curve goes straight on at point `k`.
    let straight = |k: isize| -> bool {
        let (Some(i0), Some(i1), Some(i2)) = (at(k - 1), at(k), at(k + 1)) else {
            return false;
        };
        let (u0, u1) = (pts[i1] - pts[i0], pts[i2] - pts[i1]);
        u0.dot(&u1) > 0.0 && u0.cross(&u1).norm() <= STRAIGHT * u0.norm() * u1.norm()
    };
    (0..segs)
        .map(|j| {
            // The run: points first..=last (indices unwrapped), never the whole of a closed
            // curve.
            let (mut first, mut last) = (j as isize, j as isize + 1);
            while j as isize - first < STRAIGHT_PIECES as isize
                && ((last - first) as usize) + 1 < n
                && straight(first)
            {
                first -= 1;
            }
            while last - (j as isize + 1) < STRAIGHT_PIECES as isize
                && ((last - first) as usize) + 1 < n
                && straight(last)
            {
                last += 1;
            }
            let (a, b) = (pts[at(first).unwrap_or(j)], pts[at(last).unwrap_or(j)]);
            let mut out = SourcePiece {
                p: a,
                q: b,
                run_on: [[RunOn::NONE; 2]; 2],
            };
            let along = b - a;
            let len = along.norm();
            let normal = &normals[curve.faces[j] as usize];
            let lateral = normal.cross(&along);
            let lateral_len = lateral.norm();
            if !(len > 0.0 && lateral_len > 0.0) {
                return out;
            }
            let (dir, lateral) = (along / len, lateral / lateral_len);
            for end in 0..2 {
                let (origin, dir) = if end == 0 { (a, -dir) } else { (b, dir) };
                // The samples beyond this end, nearest first (not round a closed curve into
                // the run).
                let pieces = (last - first) as usize;
                let beyond = (1..=RUN_ON_SAMPLES).map_while(|k| {
                    let i = if end == 0 {
                        first - k as isize
                    } else {
                        last + k as isize
                    };
                    (pieces + k < n).then(|| at(i)).flatten().map(|i| pts[i])
                });
                // Per side: the smallest cotangent seen, how far along the curve stays
                // within the tolerance of the line on the far side.
                let band = RUN_ON_TOLERANCE * reach;
                let mut cot = [Real::INFINITY; 2];
                let mut length = [Real::INFINITY; 2];
                let (mut prev, mut covered) = ((0.0, 0.0), 0.0);
                let mut nearest = true;
                for c in beyond {
                    let w = c - origin;
                    let (ahead, off) = (w.dot(&dir), w.dot(&lateral));
                    for (side, sign) in [1.0, -1.0].into_iter().enumerate() {
                        let (off, prev_off) = (sign * off, sign * prev.1);
                        if length[side] < Real::INFINITY {
                            continue;
                        }
                        // Where the curve turns away at once, its pieces' ends serve the
                        // vertices there (running on would offer them less, and so settle
                        // them before the pieces that are nearest reach them: 0.043 mm
                        // too far at 2M triangles on the section of the cap, not 0.005).
                        let tolerance = if nearest { STRAIGHT * w.norm() } else { band };
                        if off < -tolerance {
                            // The curve leaves the band between the previous sample and
                            // this one; up to there it passed every position along the
                            // line up to the furthest it reached.
                            let crossing = prev.0
                                + (ahead - prev.0) * (prev_off + tolerance) / (prev_off - off);
                            length[side] = if crossing > covered {
                                crossing
                            } else {
                                covered
                            };
                        } else if off > STRAIGHT * w.norm() {
                            let c = ahead / off;
                            if c < cot[side] {
                                cot[side] = c;
                            }
                        }
                    }
                    if ahead > covered {
                        covered = ahead;
                    }
                    prev = (ahead, off);
                    nearest = false;
                    if covered >= reach
                        || (length[0] < Real::INFINITY && length[1] < Real::INFINITY)
                    {
                        break;
                    }
                }
                for side in 0..2 {
                    let length = if length[side] < covered {
                        length[side]
                    } else {
                        covered
                    };
                    out.run_on[side][end] = if length >= reach && cot[side] == Real::INFINITY {
                        RunOn::FREE
                    } else {
                        RunOn::new(length / reach, cot[side])
                    };
                }
            }
            out
        })
        .collect()
}

/// Whether vertex `v` lies on the boundary of the active faces (an edge at it has no active
/// face across).
fn on_boundary(surface: &Surface, v: usize) -> bool {
    let tris = surface.mesh.triangles();
    surface.faces_of(v).iter().any(|&g| {
        let g = g as usize;
        (0..3).any(|k| {
            let (a, b) = (tris[g][k] as usize, tris[g][(k + 1) % 3] as usize);
            (a == v || b == v) && surface.across(g, k).is_none()
        })
    })
}

/// Seeds `s` from `curve`: each vertex of a face the curve crosses (and each corner of a
/// sliver glued on along its edges, a point of the face) gets the nearest of the pieces
/// within [`SEED_WINDOW`] samples.
pub(super) fn seed_curve(s: &mut Solver, curve: &Curve) {
    let surface = s.surface;
    let mesh = surface.mesh;
    let pos = mesh.positions();
    let n = curve.points.len();
    let segs = if curve.closed && n > 2 { n } else { n - 1 };
    let pieces = source_pieces(curve, &surface.face_normals, s.reach);
    let piece = |j: isize| -> Option<(usize, SourcePiece)> {
        let j = if n == 1 {
            0
        } else if curve.closed && n > 2 {
            j.rem_euclid(segs as isize) as usize
        } else if j < 0 || j as usize >= segs {
            return None;
        } else {
            j as usize
        };
        Some((
            j,
            pieces.get(j).copied().unwrap_or(SourcePiece {
                p: curve.points[j],
                q: curve.points[(j + 1) % n],
                run_on: [[RunOn::NONE; 2]; 2],
            }),
        ))
    };
    // The curve's pieces in the solver's list, linked along the curve.
    let base = s.pieces.len();
    let count = segs.max(1);
    for j in 0..count {
        let Some((_, sp)) = piece(j as isize) else {
            continue;
        };
        let link = |k: isize| piece(k).map_or(NO_PIECE, |(k, _)| (base + k) as u32);
        s.pieces.push(CurvePiece {
            p: sp.p,
            q: sp.q,
            normal: surface.face_normals[curve.faces[j.min(curve.faces.len() - 1)] as usize],
            run_on: sp.run_on,
            before: link(j as isize - 1),
            after: link(j as isize + 1),
        });
    }
    let seeded = |s: &mut Solver, w: usize, j: usize| {
        if !s.piece.is_empty() {
            s.piece[w] = (base + j) as u32;
        }
    };
    let on_vertex = ON_VERTEX * surface.mean_edge;
    for (i, &f) in curve.faces.iter().enumerate() {
        let window = i as isize - SEED_WINDOW as isize..=(i + SEED_WINDOW) as isize;
        // Its corners, and the corners of slivers glued on along its edges.
        let t = mesh.triangles()[f as usize].map(|v| v as usize);
        for v in t.into_iter().chain(surface.glued_corners(f as usize)) {
            let x = pos[v];
            for (j, piece) in window.clone().filter_map(piece) {
                let (d, _) = segment_distance(&x, &piece.p, &piece.q);
                let seg = Virtual {
                    p: piece.p,
                    q: piece.q,
                    sigma: 0.0,
                    face: f,
                    run_on: piece.run_on,
                };
                if s.improve(v, d, seg) {
                    seeded(s, v, j);
                }
            }
            // A sample on a vertex (a plane through a ring of vertices) lies in every
            // face around it, not only in `f`: the corners of those faces are seeded
            // too, with the pieces turned about the vertex into each face's plane (as
            // the propagation would offer them), so no corner on the far side of the
            // curve waits for a neighbour's piece that ends short of it (0.40 mm too far
            // 3.5 mm from the section of the 500k cap through its ring at θ = 0.6).
            // (On the boundary of the faces, as a boundary loop's samples are, every face
            // around the vertex lies on the one side and the propagation serves them.)
            if (curve.points[i] - x).norm() > on_vertex || on_boundary(surface, v) {
                continue;
            }
            let nf = surface.face_normals[f as usize];
            for &g in surface.faces_of(v) {
                let g = g as usize;
                let r = Rotation::new(&nf, &surface.face_normals[g]);
                // A sliver's plane is not defined (its corners are seeded as points of the
                // faces it is glued to, see `Surface::glued_corners`).
                if g == f as usize || r.c <= FOLD_COSINE || surface.is_sliver(g) {
                    continue;
                }
                for (j, piece) in window.clone().filter_map(piece) {
                    let (p, q) = (x + r.apply(piece.p - x), x + r.apply(piece.q - x));
                    for w in mesh.triangles()[g] {
                        let w = w as usize;
                        if w != v {
                            let (d, _) = segment_distance(&pos[w], &p, &q);
                            let seg = Virtual {
                                p,
                                q,
                                sigma: 0.0,
                                face: g as u32,
                                run_on: piece.run_on,
                            };
                            if s.improve(w, d, seg) {
                                seeded(s, w, j);
                            }
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A curve in the plane z = 0 (faces with normal +z) as the seeding sees it.
    fn curve(points: &[[Real; 2]], closed: bool) -> (Curve, Vec<Vector3>) {
        let points: Vec<Point3> = points
            .iter()
            .map(|p| Point3::new(p[0], p[1], 0.0))
            .collect();
        let faces = vec![0; points.len()];
        (
            Curve {
                points,
                faces,
                closed,
            },
            vec![Vector3::z()],
        )
    }

    #[test]
    fn collinear_samples_make_one_piece_that_runs_on_only_as_the_curve_allows() {
        // Half-unit samples along y = 0 to x = 3, then a corner up to (3, 2).
        let (c, normals) = curve(
            &[
                [0.0, 0.0],
                [0.5, 0.0],
                [1.0, 0.0],
                [1.5, 0.0],
                [2.0, 0.0],
                [2.5, 0.0],
                [3.0, 0.0],
                [3.0, 1.0],
                [3.0, 2.0],
            ],
            false,
        );
        let pieces = source_pieces(&c, &normals, 1.0);
        assert_eq!(pieces.len(), 8);
        // Every sub-piece of the first line holds the whole line.
        for piece in &pieces[..6] {
            assert_eq!((piece.p, piece.q), (c.points[0], c.points[6]));
        }
        let first = pieces[2].run_on;
        // Beyond (0, 0) the open curve ends: no run-on either side.
        assert_eq!([first[0][0], first[1][0]], [RunOn::NONE; 2]);
        // Beyond (3, 0) the curve turns left by 90°: for the right side (away) it leaves the
        // band at once; for the left it turns up at a right angle (cot 0 < 1/64): none.
        assert_eq!([first[0][1], first[1][1]], [RunOn::NONE; 2]);
        // A gentle left turn (1 in 4) beyond the end: the left side runs on bounded by cot 4,
        // the right side not at all (the curve leaves the band on its far side).
        let (c, normals) = curve(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.25], [3.0, 0.5]], false);
        let pieces = source_pieces(&c, &normals, 1.0);
        let run_on = pieces[0].run_on;
        assert_eq!(run_on[0][1].run(0.1, 1.0), 0.4);
        assert_eq!(run_on[1][1], RunOn::NONE);
        // Towards the left by 1e-5 at the first sample, back by 1e-5 at the next (within the
        // band, 3e-4 of the reach): the left runs on, bounded by the steepest chord (cot
        // 5e4, rounded down to the largest bound, 256); the right, which the curve leaves at
        // once, not at all.
        let (c, normals) = curve(&[[0.0, 0.0], [1.0, 0.0], [1.5, 1e-5], [2.5, -1e-5]], false);
        let piece = source_pieces(&c, &normals, 1.0)[0];
        assert_eq!((piece.p, piece.q), (c.points[0], c.points[1]));
        assert_eq!(piece.run_on[0][1].run(1e-3, 1.0), 0.256);
        assert_eq!(piece.run_on[0][1].run(1.0, 1.0), 1.0);
        assert_eq!(piece.run_on[1][1], RunOn::NONE);
        // Towards the left for half the reach, then off the band on its far side: the left
        // runs on to where the curve leaves the band (0.5004, rounded down to 7/15).
        let (c, normals) = curve(&[[0.0, 0.0], [1.0, 0.0], [1.5, 1e-4], [2.5, -1.0]], false);
        let piece = source_pieces(&c, &normals, 1.0)[0];
        assert_eq!(piece.run_on[0][1].run(100.0, 1.0), 7.0 / 15.0);
        assert_eq!(piece.run_on[1][1], RunOn::NONE);
        // A hairpin: back along the line (a turn over 90° either way): none.
        let (c, normals) = curve(&[[0.0, 0.0], [1.0, 0.0], [0.0, 0.01], [-1.0, 0.02]], false);
        let piece = source_pieces(&c, &normals, 1.0)[0];
        assert_eq!([piece.run_on[0][1], piece.run_on[1][1]], [RunOn::NONE; 2]);
    }
}
