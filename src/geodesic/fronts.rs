//! Front interpolation near focal points of the accurate (virtual source) geodesic method.
//!
//! Source: no paper. Where fronts converge (around the pole of a cap measured from its rim,
//!         the antipode of a point source on a sphere), the propagation keeps one source per
//!         vertex, and neighbouring vertices often keep the same one: the sources held sample
//!         the curve (or the directions from a point) ever more sparsely towards the focus,
//!         and a vertex's nearest point of the curve lies between the ones its neighbours
//!         hold. Its distance is then too long by about `ρ α² / 2` (`ρ` the distance from the
//!         focus, `α` the angle between the held sources seen from the focus, which grows like
//!         `h / ρ`): the h²/ρ error that `focal.rs` had to refine away over large patches.
//! Input:  a settled [`Solver`] and the vertices around its focal points.
//! Output: the distances of those vertices lowered to the minimum of a parabola through
//!         three of the distances offered by their neighbours' sources.
//! Steps:  I.  Each source held by a vertex of `x`'s star (its 2-ring when the star has no
//!             sample on one side) is turned into the plane of `x`'s own source, and offers
//!             `D = σ + |x − foot|`: a sample of the distance from `x` to the source at the
//!             foot's lateral position `s` (across `x`'s own ray).
//!         II. The best sample and, on each side of it, the nearest one at least 5 % of an
//!             edge and a quarter of the other side's gap away give a parabola `D(s)`; its
//!             minimum is `x`'s distance when it is convex, lies between the outer samples,
//!             and is the minimum of a converging front or a straight one (curvature
//!             `D'' ≤ 1.1 / D`: a point or a straight curve gives `D'' = 1 / D`, a converging
//!             front less), and the three samples come from one smooth piece of curve (their
//!             segments turn by at most [`TURN`] plus 1.5 times the angle between the outer
//!             feet seen from `x`).
//!         III. The minimum never lowers a distance by more than the spread of the three
//!             samples, and no sample is shorter than the distance the propagation gave
//!             (a shorter one is a path that does not pass through the star: a front met
//!             across a shock), nor below a neighbour's distance less the edge between
//!             them by more than [`NEIGHBOUR_SLACK`] of an edge (the neighbour's own excess).
//!             Once every vertex around a focus is done, neighbours are lowered along the
//!             edges where a lowered distance plus the edge is shorter ([`relax`]): the
//!             distance stays 1-Lipschitz along every edge.
//! Accuracy: not exact; the samples carry the unfolding's own second-order error (about
//!         K·D·h²/3 for Gaussian curvature K). Measured against the analytic distance (f32
//!         positions, largest error anywhere, before → with front interpolation and the
//!         smaller focal patches it allows): cap R 1000 from its rim, 500k triangles
//!         0.033 → 0.0062 mm, 2M 0.020 → 0.0031 mm; sphere R 100 from a point, 500k
//!         0.0096 → 0.0078 mm, 2M 0.0051 → 0.0043 mm.
//! Cost:   O(1) per vertex processed (its star, and its 2-ring when the star is one-sided);
//!         the caller bounds the vertices processed (a quarter of them at most).

use super::unfolding::Entry;
use super::virtual_source::{foot, Rotation, Solver, FOLD_COSINE};
use crate::math::{Real, Vector3};
use std::collections::BinaryHeap;

/// Samples kept per vertex at most (a 2-ring on a mesh of bounded valence has about 19).
const MAX_SAMPLES: usize = 48;
/// Samples whose foot lies at a larger angle (tangent) from `x`'s own ray are not used: the
/// unfolding of a path that far from the ray it was propagated along is no longer accurate.
const MAX_SLOPE: Real = 0.25;
/// The outer samples lie at least this fraction of the mean edge from the best one.
const MIN_GAP: Real = 0.05;
/// Angle (sine) the segments of three samples may turn by, on top of 1.5 times the angle
/// between their outer feet.
const TURN: Real = 0.05;
/// How far (in mean edges) an interpolated distance may lie below a neighbour's distance
/// less the edge between them, when the caller allows it (away from the focus): the
/// neighbour's own excess or the interpolation's, which add up (about 1.5e-4 of an edge on
/// the 500k cap from its rim; 8e-4 along the seam of that cap's mesh from its section
/// through a ring of vertices, where 3e-4 refused ring after ring of right distances and
/// left them 0.014 mm too long), far below a parabola through samples of two fronts.
const NEIGHBOUR_SLACK: Real = 1e-3;
/// Relative margin by which a path through a lowered neighbour must be shorter for
/// [`relax`] to take it (far above the rounding of the sum).
const RELAX_SLACK: Real = 1e-12;
/// A sample more than this fraction of the mean edge below the distance the propagation gave
/// is not used (see [`lower`]).
const BELOW: Real = 1e-4;
/// Largest `D'' · D` of an interpolated front (1 for a point or a straight curve, less for a
/// converging front), with 10 % slack.
const MAX_CURVATURE: Real = 1.1;

#[derive(Clone, Copy)]
struct Sample {
    /// Lateral position of the foot across `x`'s ray.
    lat: Real,
    /// Distance offered.
    d: Real,
    /// Direction of the source segment (zero for a point).
    dir: Vector3,
}

/// Reusable buffers of [`lower`].
pub(super) struct Scratch {
    /// Per vertex: the last vertex whose samples it gave (dedups a 2-ring).
    stamp: Vec<u32>,
    lowered: Vec<(u32, Real)>,
    /// Every vertex lowered below what a neighbour's distance allowed (where [`relax`]
    /// starts).
    pub(super) relax_from: Vec<u32>,
}

impl Scratch {
    pub(super) fn new(vertices: usize) -> Self {
        Scratch {
            stamp: vec![u32::MAX; vertices],
            lowered: Vec::new(),
            relax_from: Vec::new(),
        }
    }
}

/// Lowers the distances of `vertices` by interpolating their neighbours' sources; returns
/// the largest amount a distance was lowered by. `slack`: see
/// [`NEIGHBOUR_SLACK`]. The sources are read, never changed, and the lowered distances are
/// written once every vertex is done, so the order of `vertices` does not matter.
pub(super) fn lower(s: &mut Solver, vertices: &[u32], slack: bool, scratch: &mut Scratch) -> Real {
    let surface = s.surface;
    let mesh = surface.mesh;
    let pos = mesh.positions();
    let normals = &surface.face_normals;
    let gap = MIN_GAP * surface.mean_edge;
    let mut smp = [Sample {
        lat: 0.0,
        d: 0.0,
        dir: Vector3::zeros(),
    }; MAX_SAMPLES];
    let mut ring = [0u32; MAX_SAMPLES];
    scratch.lowered.clear();
    for &x in vertices {
        let x = x as usize;
        let dx = s.dist[x];
        if !(dx.is_finite() && dx > 0.0) {
            continue;
        }
        let own = s.src[x];
        let t0 = own.face as usize;
        let n0 = normals[t0];
        let px = pos[x];
        let w = foot(&px, &own.p, &own.q, &own.run_on, &n0, s.reach) - px;
        let wl = w.norm();
        if wl == 0.0 {
            continue;
        }
        // x's frame: e1 towards its own foot, e2 across.
        let e1 = w / wl;
        let e2 = n0.cross(&e1);
        smp[0] = Sample {
            lat: 0.0,
            d: own.sigma + wl,
            dir: own.q - own.p,
        };
        let mut n = 1;
        // The propagation gave x the shortest path its neighbours offered through its star; a
        // sample shorter than that is a path that does not pass there (from a front met
        // across a shock), not a sample of x's own front.
        let floor = dx - BELOW * surface.mean_edge;
        // The source of vertex z, turned about z into the plane of x's source (one rotation:
        // z lies within two edges of x, so the planes through z and x differ by the
        // second order of that distance).
        let sample = |z: usize, smp: &mut [Sample; MAX_SAMPLES], n: &mut usize| {
            let sz = &s.src[z];
            let pz = pos[z];
            let (p, q) = if sz.face as usize == t0 {
                (sz.p, sz.q)
            } else {
                let r = Rotation::new(&normals[sz.face as usize], &n0);
                if r.c <= FOLD_COSINE {
                    return;
                }
                let p = pz + r.apply(sz.p - pz);
                (
                    p,
                    if sz.q == sz.p {
                        p
                    } else {
                        pz + r.apply(sz.q - pz)
                    },
                )
            };
            let v = foot(&px, &p, &q, &sz.run_on, &n0, s.reach) - px;
            let (along, lat) = (v.dot(&e1), v.dot(&e2));
            let d = sz.sigma + v.norm();
            if along > 0.0 && lat.abs() <= MAX_SLOPE * along && d >= floor && *n < MAX_SAMPLES {
                smp[*n] = Sample { lat, d, dir: q - p };
                *n += 1;
            }
        };
        let stamp = &mut scratch.stamp;
        stamp[x] = x as u32;
        // Step I: the star, then the 2-ring if needed.
        let mut ring_n = 0;
        for &t in surface.faces_of(x) {
            for y in mesh.triangles()[t as usize] {
                let y = y as usize;
                if stamp[y] == x as u32 || ring_n == MAX_SAMPLES {
                    continue;
                }
                stamp[y] = x as u32;
                ring[ring_n] = y as u32;
                ring_n += 1;
                if s.dist[y].is_finite() {
                    sample(y, &mut smp, &mut n);
                }
            }
        }
        let mut found = bracket(&smp[..n], gap);
        if found.is_none() {
            for &y in &ring[..ring_n] {
                for &t in surface.faces_of(y as usize) {
                    for z in mesh.triangles()[t as usize] {
                        let z = z as usize;
                        if stamp[z] == x as u32 {
                            continue;
                        }
                        stamp[z] = x as u32;
                        if s.dist[z].is_finite() {
                            sample(z, &mut smp, &mut n);
                        }
                    }
                }
            }
            found = bracket(&smp[..n], gap);
        }
        let Some([a, m, b]) = found.map(|k| k.map(|i| smp[i])) else {
            continue;
        };
        // One smooth piece of curve (points have no direction to check).
        let turn = TURN + 1.5 * (b.lat - a.lat) / m.d;
        let bent = |u: &Vector3, v: &Vector3| {
            let (lu, lv) = (u.norm(), v.norm());
            lu > 0.0 && lv > 0.0 && (u.cross(v).norm() > turn * lu * lv || u.dot(v) < 0.0)
        };
        if bent(&a.dir, &m.dir) || bent(&m.dir, &b.dir) || bent(&a.dir, &b.dir) {
            continue;
        }
        // Step II: the parabola through the three samples, D(s) = m.d + g (s − m.lat) + c
        // (s − m.lat)².
        let (h1, h2) = (m.lat - a.lat, b.lat - m.lat);
        let (g1, g2) = ((m.d - a.d) / h1, (b.d - m.d) / h2);
        let c = (g2 - g1) / (h1 + h2);
        if c.is_nan() || c <= 0.0 {
            continue;
        }
        let g = g1 + c * h1;
        let d = m.d - g * g / (4.0 * c);
        let at = m.lat - g / (2.0 * c);
        let ok = 2.0 * c * d <= MAX_CURVATURE
            && m.d - d <= a.d.max(b.d) - m.d
            && at > a.lat
            && at < b.lat;
        // Nor below a neighbour's distance less the edge between them (by more than
        // [`NEIGHBOUR_SLACK`] with `slack`: a neighbour may be too long by that much;
        // `relax` then lowers it).
        let allowance = if slack {
            NEIGHBOUR_SLACK * surface.mean_edge
        } else {
            0.0
        };
        // The largest amount a neighbour's distance less the edge exceeds `d` by.
        let excess = || {
            ring[..ring_n]
                .iter()
                .map(|&y| {
                    let y = y as usize;
                    s.dist[y] - (pos[y] - px).norm() - d
                })
                .filter(|e| e.is_finite())
                .fold(Real::NEG_INFINITY, Real::max)
        };
        if ok && d < dx {
            let e = excess();
            if e <= allowance {
                scratch.lowered.push((x as u32, d));
                if e > 0.0 {
                    // Below what a neighbour allows: `relax` starts here.
                    scratch.relax_from.push(x as u32);
                }
            }
        }
    }
    let mut most: Real = 0.0;
    for &(x, d) in &scratch.lowered {
        // Never below the straight line from a source vertex (see `Solver::floor`).
        let d = d.max(s.floor(x as usize)).min(s.dist[x as usize]);
        most = most.max(s.dist[x as usize] - d);
        s.dist[x as usize] = d;
    }
    most
}

/// Step III: keeps the distance 1-Lipschitz along the edges after `lowered` vertices went
/// down, as Dijkstra's algorithm would: each neighbour is lowered to a lowered vertex's
/// distance plus the edge between them where that is shorter, nearest first. The edge is a
/// path, so a neighbour ends no further below its true distance than the lowered vertex
/// was; each vertex is settled once. Returns how many vertices it lowered.
pub(super) fn relax(s: &mut Solver, lowered: &[u32]) -> usize {
    let surface = s.surface;
    let mesh = surface.mesh;
    let pos = mesh.positions();
    let mut heap: BinaryHeap<Entry> = lowered
        .iter()
        .map(|&v| Entry {
            d: s.dist[v as usize],
            v,
        })
        .collect();
    let mut count = 0;
    while let Some(Entry { d, v }) = heap.pop() {
        let x = v as usize;
        if d > s.dist[x] {
            continue;
        }
        let px = pos[x];
        for &f in surface.faces_of(x) {
            for y in mesh.triangles()[f as usize] {
                let y = y as usize;
                let through = d + (pos[y] - px).norm();
                if through < s.dist[y] * (1.0 - RELAX_SLACK) {
                    s.dist[y] = through;
                    heap.push(Entry {
                        d: through,
                        v: y as u32,
                    });
                    count += 1;
                }
            }
        }
    }
    count
}

/// The best sample and, on each side of it, the nearest sample at least `gap` away and at
/// least a quarter as far as the one chosen on the other side (a pair of samples much
/// closer than the third one would turn their rounding into the parabola's slope), if both
/// sides have one.
fn bracket(smp: &[Sample], gap: Real) -> Option<[usize; 3]> {
    let m = (0..smp.len()).min_by(|&i, &j| smp[i].d.total_cmp(&smp[j].d))?;
    let at = smp[m].lat;
    let nearest = |left: Real, right: Real| {
        let (mut a, mut b) = (None::<usize>, None::<usize>);
        for (i, q) in smp.iter().enumerate() {
            if q.lat <= at - left && a.is_none_or(|k| q.lat > smp[k].lat) {
                a = Some(i);
            }
            if q.lat >= at + right && b.is_none_or(|k| q.lat < smp[k].lat) {
                b = Some(i);
            }
        }
        Some((a?, b?))
    };
    let (a, b) = nearest(gap, gap)?;
    let (h1, h2) = (at - smp[a].lat, smp[b].lat - at);
    let (a, b) = nearest(gap.max(h2 / 4.0), gap.max(h1 / 4.0))?;
    Some([a, m, b])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(lat: Real, d: Real) -> Sample {
        Sample {
            lat,
            d,
            dir: Vector3::zeros(),
        }
    }

    #[test]
    fn bracket_takes_the_best_sample_and_its_nearest_neighbours_on_each_side() {
        let smp = [
            at(0.5, 5.0),
            at(-3.0, 4.2),
            at(-1.0, 4.0),
            at(2.0, 4.5),
            at(0.0, 4.1),
        ];
        assert_eq!(bracket(&smp, 0.1), Some([1, 2, 4]));
        // A sample 0.05 to the left of the best and 2 to the right: the left one is too close
        // (less than a quarter of 2), the next one out is taken.
        let lopsided = [at(0.0, 4.0), at(-0.05, 4.01), at(2.0, 4.3), at(-1.5, 4.2)];
        assert_eq!(bracket(&lopsided, 0.01), Some([3, 0, 2]));
        // Nothing on one side (within the gap does not count).
        let one_sided = [at(0.0, 4.0), at(0.05, 4.1), at(1.0, 4.5)];
        assert_eq!(bracket(&one_sided, 0.1), None);
        assert_eq!(bracket(&[], 0.1), None);
    }
}
