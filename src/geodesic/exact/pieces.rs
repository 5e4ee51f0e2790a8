//! The source polyline cut into straight pieces that each lie in one face.
//!
//! No paper: consecutive samples of a resolved curve lie in the same face, in two faces that
//! share an edge, or in two faces of one vertex's fan. The faces between them (none, or the
//! fan on either side of the vertex) are unfolded into the first face's plane and the chord
//! between the samples is cut where it crosses each shared edge; the result is the straight
//! (geodesic) segment of the unfolding, so the source is a polyline on the surface. When no
//! unfolding holds the chord (the samples straddle a saddle), the piece runs through the
//! vertex. Samples in faces that share nothing are kept as two points.
//! Cost: O(1) a sample (a fan is bounded by the vertex's degree).

use super::super::source::Curve;
use super::super::surface::Surface;
use super::front::norm2;
use crate::math::{Point3, Real, Vector3};

/// Pieces shorter than this (in mean edge lengths) do not restrict their neighbours' point
/// windows.
const JUNCTION_MIN_LENGTH: Real = 1e-6;
/// Slack of a chord crossing a shared edge, relative to the edge (its ends included).
const CROSSING_SLACK: Real = 1e-9;

/// A straight piece of the source lying in one face, with the directions of its neighbours
/// at its ends unfolded into its face's plane (`None`: no neighbour, or not unfoldable).
#[derive(Clone, Copy, Debug)]
pub(super) struct Piece {
    pub face: usize,
    pub p: Point3,
    pub q: Point3,
    /// Unit direction of the previous piece, arriving at `p`.
    pub before: Option<Vector3>,
    /// Unit direction of the next piece, leaving `q`.
    pub after: Option<Vector3>,
    /// Whether `p` seeds point windows (not when the previous piece, in the same face,
    /// already seeds them from the same point).
    pub seed_p: bool,
}

/// Straight pieces of a source curve with their neighbours' directions.
pub(super) fn curve_pieces(surface: &Surface, curve: &Curve) -> Vec<Piece> {
    let raw = raw_pieces(surface, curve);
    let mut out: Vec<Piece> = raw
        .iter()
        .map(|&(face, p, q)| Piece {
            face,
            p,
            q,
            before: None,
            after: None,
            seed_p: true,
        })
        .collect();
    let n = out.len();
    let pairs = if curve.closed && n > 1 {
        n
    } else {
        n.saturating_sub(1)
    };
    for i in 0..pairs {
        let j = (i + 1) % n;
        let (a, b) = (out[i], out[j]);
        if (a.q - b.p).norm() > 0.0 {
            continue;
        }
        let (da, db) = (a.q - a.p, b.q - b.p);
        // The direction of a very short piece is rounding noise: no restriction there.
        let shortest = JUNCTION_MIN_LENGTH * surface.mean_edge;
        if !(da.norm() > shortest && db.norm() > shortest) {
            continue;
        }
        let (da, db) = (da.normalize(), db.normalize());
        out[i].after = carry(surface, db, b.face, a.face, &a.q);
        out[j].before = carry(surface, da, a.face, b.face, &a.q);
        if a.face == b.face && out[i].after.is_some() {
            out[j].seed_p = false;
        }
    }
    out
}

/// Direction `d` in the plane of face `from` expressed in the plane of face `to`, unfolded
/// about their shared edge (which holds `at`); `None` unless the faces are equal or share an
/// edge.
fn carry(surface: &Surface, d: Vector3, from: usize, to: usize, at: &Point3) -> Option<Vector3> {
    if from == to {
        return Some(d);
    }
    let mesh = surface.mesh;
    let (tf, tt) = (mesh.triangles()[from], mesh.triangles()[to]);
    let shared: Vec<u32> = tf.iter().copied().filter(|v| tt.contains(v)).collect();
    if shared.len() != 2 {
        return None;
    }
    let pos = mesh.positions();
    let (a, b) = (pos[shared[0] as usize], pos[shared[1] as usize]);
    let e = (b - a).try_normalize(0.0)?;
    // The shared point lies on the edge (else the two pieces do not meet there).
    let off = (at - a) - e * (at - a).dot(&e);
    if off.norm() > 1e-9 * (b - a).norm() {
        return None;
    }
    let inward = |face: &[u32; 3]| -> Option<Vector3> {
        let c = face.iter().find(|v| !shared.contains(v))?;
        let w = pos[*c as usize] - a;
        (w - e * w.dot(&e)).try_normalize(0.0)
    };
    let (n_from, n_to) = (inward(&tf)?, inward(&tt)?);
    Some(e * d.dot(&e) - n_to * d.dot(&n_from))
}

/// A piece as `(face, from, to)`.
type RawPiece = (usize, Point3, Point3);

/// Straight pieces of a source curve, each lying in one face: `(face, from, to)`.
fn raw_pieces(surface: &Surface, curve: &Curve) -> Vec<RawPiece> {
    let mesh = surface.mesh;
    let n = curve.points.len();
    let mut out = Vec::with_capacity(2 * n);
    if n == 1 {
        out.push((curve.faces[0] as usize, curve.points[0], curve.points[0]));
        return out;
    }
    let segments = if curve.closed && n > 2 { n } else { n - 1 };
    for i in 0..segments {
        let j = (i + 1) % n;
        let (p, q) = (curve.points[i], curve.points[j]);
        let (f, g) = (curve.faces[i] as usize, curve.faces[j] as usize);
        if f == g {
            out.push((f, p, q));
            continue;
        }
        let (tf, tg) = (mesh.triangles()[f], mesh.triangles()[g]);
        let shared: Vec<u32> = tf.iter().copied().filter(|v| tg.contains(v)).collect();
        let chains = match shared.len() {
            2 => vec![vec![f, g]],
            1 => fan_chains(surface, shared[0], f, g),
            _ => Vec::new(),
        };
        let best = chains
            .iter()
            .filter_map(|c| unfold_chain(surface, c, p, q))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match (best, shared.len()) {
            (Some((_, pieces)), _) => out.extend(pieces),
            (None, 1 | 2) => {
                // The shared vertex nearer the chord's middle.
                let mid = p + (q - p) * 0.5;
                let v = shared
                    .iter()
                    .map(|&v| mesh.positions()[v as usize])
                    .min_by(|a, b| (a - mid).norm().total_cmp(&(b - mid).norm()))
                    .unwrap_or(p);
                out.push((f, p, v));
                out.push((g, v, q));
            }
            _ => {
                out.push((f, p, p));
                out.push((g, q, q));
            }
        }
    }
    out
}

/// The faces from `f` to `g` around vertex `v`, turning either way (at most two chains).
fn fan_chains(surface: &Surface, v: u32, f: usize, g: usize) -> Vec<Vec<usize>> {
    let mesh = surface.mesh;
    let degree = surface.faces_of(v as usize).len();
    let mut out = Vec::new();
    for first_way in 0..2 {
        let mut chain = vec![f];
        let mut came_from = usize::MAX;
        let mut at = f;
        let mut way = first_way;
        // A fan has `degree` faces: a longer walk went round or left it.
        for _ in 0..degree {
            let t = mesh.triangles()[at];
            let slots: Vec<usize> = (0..3)
                .filter(|&k| t[k] == v || t[(k + 1) % 3] == v)
                .collect();
            let next = slots
                .iter()
                .filter_map(|&k| surface.across(at, k))
                .filter(|&h| h != came_from)
                .nth(if came_from == usize::MAX { way } else { 0 });
            way = 0;
            let Some(h) = next else { break };
            chain.push(h);
            if h == g {
                out.push(chain);
                break;
            }
            came_from = at;
            at = h;
        }
    }
    out
}

/// Barycentric coordinates of `p` in triangle `t` (Ericson 2005, §3.4).
fn barycentric(p: &Point3, t: &[Point3; 3]) -> [Real; 3] {
    let (v0, v1, v2) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (d00, d01, d11) = (v0.dot(&v0), v0.dot(&v1), v1.dot(&v1));
    let (d20, d21) = (v2.dot(&v0), v2.dot(&v1));
    let den = d00 * d11 - d01 * d01;
    if den.is_nan() || den == 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let b = (d11 * d20 - d01 * d21) / den;
    let c = (d00 * d21 - d01 * d20) / den;
    [1.0 - b - c, b, c]
}

/// Unfolds the face chain into the first face's plane; if the chord `p → q` crosses every
/// shared edge in order, its length and the pieces cut at the crossings.
fn unfold_chain(
    surface: &Surface,
    chain: &[usize],
    p: Point3,
    q: Point3,
) -> Option<(Real, Vec<RawPiece>)> {
    let mesh = surface.mesh;
    let pos = mesh.positions();
    let t0 = mesh.triangles()[chain[0]];
    let (a, b, c) = (
        pos[t0[0] as usize],
        pos[t0[1] as usize],
        pos[t0[2] as usize],
    );
    let lab = (b - a).norm();
    if lab.is_nan() || lab <= 0.0 {
        return None;
    }
    let cx = (c - a).dot(&(b - a)) / lab;
    let cy = ((c - a).norm_squared() - cx * cx).max(0.0).sqrt();
    let mut flat: Vec<(u32, [Real; 2])> =
        vec![(t0[0], [0.0, 0.0]), (t0[1], [lab, 0.0]), (t0[2], [cx, cy])];
    let at =
        |flat: &Vec<(u32, [Real; 2])>, v: u32| flat.iter().rev().find(|e| e.0 == v).map(|e| e.1);
    let to_2d = |flat: &Vec<(u32, [Real; 2])>, face: usize, x: &Point3| -> Option<[Real; 2]> {
        let t = mesh.triangles()[face];
        let w = barycentric(x, &mesh.corners(face));
        let mut out = [0.0, 0.0];
        for k in 0..3 {
            let c = at(flat, t[k])?;
            out[0] += w[k] * c[0];
            out[1] += w[k] * c[1];
        }
        Some(out)
    };
    let p2 = to_2d(&flat, chain[0], &p)?;
    let mut edges = Vec::new();
    for w in chain.windows(2) {
        let (tp, tn) = (mesh.triangles()[w[0]], mesh.triangles()[w[1]]);
        let shared: Vec<u32> = tn.iter().copied().filter(|v| tp.contains(v)).collect();
        let (Some(&old), Some(&new)) = (
            tp.iter().find(|v| !shared.contains(v)),
            tn.iter().find(|v| !shared.contains(v)),
        ) else {
            return None;
        };
        if shared.len() != 2 {
            return None;
        }
        let (e0, e1, o) = (
            at(&flat, shared[0])?,
            at(&flat, shared[1])?,
            at(&flat, old)?,
        );
        let d = [e1[0] - e0[0], e1[1] - e0[1]];
        let l = norm2(d[0], d[1]);
        if l.is_nan() || l <= 0.0 {
            return None;
        }
        let ex = [d[0] / l, d[1] / l];
        let mut ey = [-ex[1], ex[0]];
        if (o[0] - e0[0]) * ey[0] + (o[1] - e0[1]) * ey[1] > 0.0 {
            ey = [-ey[0], -ey[1]];
        }
        let (p0, p1, pn) = (
            pos[shared[0] as usize],
            pos[shared[1] as usize],
            pos[new as usize],
        );
        let x = (pn - p0).dot(&(p1 - p0)) / l;
        let y = ((pn - p0).norm_squared() - x * x).max(0.0).sqrt();
        flat.push((
            new,
            [e0[0] + x * ex[0] + y * ey[0], e0[1] + x * ex[1] + y * ey[1]],
        ));
        edges.push((shared[0], shared[1], e0, e1));
    }
    let q2 = to_2d(&flat, chain[chain.len() - 1], &q)?;
    let r = [q2[0] - p2[0], q2[1] - p2[1]];
    let cross = |a: [Real; 2], b: [Real; 2]| a[0] * b[1] - a[1] * b[0];
    let mut pieces = Vec::with_capacity(chain.len());
    let (mut from, mut last_s) = (p, 0.0);
    for (i, &(v0, v1, e0, e1)) in edges.iter().enumerate() {
        // p2 + s·r = e0 + t·(e1 − e0).
        let e = [e1[0] - e0[0], e1[1] - e0[1]];
        let den = cross(r, e);
        if den.is_nan() || den == 0.0 {
            return None;
        }
        let w = [e0[0] - p2[0], e0[1] - p2[1]];
        let s = cross(w, e) / den;
        let t = cross(w, r) / den;
        let ok = (-CROSSING_SLACK..=1.0 + CROSSING_SLACK).contains(&t)
            && s >= last_s - CROSSING_SLACK
            && s <= 1.0 + CROSSING_SLACK;
        if !ok {
            return None;
        }
        last_s = s;
        let x = pos[v0 as usize] + (pos[v1 as usize] - pos[v0 as usize]) * t.clamp(0.0, 1.0);
        pieces.push((chain[i], from, x));
        from = x;
    }
    pieces.push((chain[chain.len() - 1], from, q));
    Some((norm2(r[0], r[1]), pieces))
}
