//! Pseudo-sources: a saddle or boundary vertex restarts the propagation with `σ = d(v)`
//! (Chen & Han 1990), over the shadow of the path that reached it (Mitchell, Mount &
//! Papadimitriou 1987).

use super::front::{cross, point, Frame};
use super::{Solver, SHADOW_ANGLE_TOLERANCE};
use crate::math::{angle_between, Point3, Real};

impl Solver<'_> {
    /// A pseudo-source at `v`: its neighbours along edges, and a point window on the edge
    /// opposite `v` in each of its faces, limited to the shadow of the arriving path when
    /// it is known (see [`Solver::shadow`]).
    pub(super) fn spawn(&mut self, v: usize) {
        let d = self.dist[v];
        let surface = self.surface;
        let mesh = surface.mesh;
        let pv = mesh.positions()[v];
        for &g in surface.faces_of(v) {
            let t = mesh.triangles()[g as usize];
            for w in t {
                let w = w as usize;
                if w != v {
                    let pw = mesh.positions()[w];
                    self.reach(w, d + (pw - pv).norm(), false, Some((g as usize, pv - pw)));
                }
            }
        }
        let wedges = match self.shadow(v) {
            Some(w) => w,
            None => surface
                .faces_of(v)
                .iter()
                .filter_map(|&g| {
                    let t = mesh.triangles()[g as usize];
                    let kv = t.iter().position(|&x| x as usize == v)?;
                    Some((g as usize, (kv + 1) % 3, None))
                })
                .collect(),
        };
        for (g, k, points) in wedges {
            if self.degenerate[g] {
                continue;
            }
            self.seed_edge(g, k, &|fr: &Frame| {
                let s = point(fr.unfold(&pv), d);
                match points {
                    None => vec![(0.0, fr.l, s)],
                    Some((x0, x1)) => {
                        let (a, b) = ((x0 - fr.a).dot(&fr.ex), (x1 - fr.a).dot(&fr.ex));
                        vec![(a.min(b), a.max(b), s)]
                    }
                }
            });
        }
    }

    /// The shadow of saddle `v`: geodesics bend at a vertex only when both angles between
    /// the arriving and the leaving direction are at least π (Mitchell, Mount & Papadimitriou
    /// 1987, Lemma 3.4), so the windows of a pseudo-source need only cover the directions
    /// whose angle from the arriving path, measured around the fan either way, is ≥ π (ICH
    /// spawns over the whole fan; this is MMP's restriction). Returns, per face of the fan
    /// that the shadow enters, the slot of the edge opposite `v` and the two points of that
    /// edge bounding the shadow; `None` (no restriction) for a vertex on the boundary, with
    /// a degenerate or non-manifold fan, or with no known arriving direction.
    #[allow(clippy::type_complexity)]
    fn shadow(&self, v: usize) -> Option<Vec<(usize, usize, Option<(Point3, Point3)>)>> {
        let (f0, back) = self.back[v]?;
        let mesh = self.surface.mesh;
        let pos = mesh.positions();
        let pv = pos[v];
        let degree = self.surface.faces_of(v).len();
        // Walk the fan from f0: (face, w_in, w_out, angle at the start of the face, angle).
        let mut fan = Vec::with_capacity(degree);
        let t0 = mesh.triangles()[f0 as usize];
        let k0 = t0.iter().position(|&x| x as usize == v)?;
        let (mut face, mut w_in, mut w_out) = (
            f0 as usize,
            t0[(k0 + 1) % 3] as usize,
            t0[(k0 + 2) % 3] as usize,
        );
        let mut total = 0.0;
        loop {
            if self.degenerate[face] || fan.len() >= degree {
                return None;
            }
            let alpha = angle_between(&(pos[w_in] - pv), &(pos[w_out] - pv));
            fan.push((face, w_in, w_out, total, alpha));
            total += alpha;
            let t = mesh.triangles()[face];
            let k = (0..3).find(|&k| {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                (a == v && b == w_out) || (a == w_out && b == v)
            })?;
            let next = self.surface.across(face, k)?;
            if next == f0 as usize {
                break;
            }
            let tn = mesh.triangles()[next];
            let new_out = tn
                .iter()
                .map(|&x| x as usize)
                .find(|&x| x != v && x != w_out)?;
            (face, w_in, w_out) = (next, w_out, new_out);
        }
        if fan.len() != degree || total <= 2.0 * std::f64::consts::PI {
            return None;
        }
        let (_, a_in, _, _, alpha0) = fan[0];
        let phi0 = angle_between(&(pos[a_in] - pv), &back).clamp(0.0, alpha0);
        let pi = std::f64::consts::PI;
        let (lo, hi) = (
            phi0 + pi - SHADOW_ANGLE_TOLERANCE,
            phi0 + total - pi + SHADOW_ANGLE_TOLERANCE,
        );
        let mut out = Vec::new();
        for &(g, w_in, w_out, start, alpha) in &fan {
            for shift in [0.0, total] {
                let (a, b) = (
                    (lo - shift - start).max(0.0),
                    (hi - shift - start).min(alpha),
                );
                if a > b {
                    continue;
                }
                // Rays from v at angles a, b from v→w_in meet the edge w_in → w_out.
                let (e_in, e_out) = (pos[w_in] - pv, pos[w_out] - pv);
                let l_in = e_in.norm();
                let (ox, oy) = (e_out.dot(&e_in) / l_in, e_out.cross(&e_in).norm() / l_in);
                let on_edge = |psi: Real| -> Option<Point3> {
                    let d = [libm::cos(psi), libm::sin(psi)];
                    let e = [ox - l_in, oy];
                    let den = cross(d, e);
                    let lambda = (-cross(d, [l_in, 0.0]) / den).clamp(0.0, 1.0);
                    lambda
                        .is_finite()
                        .then(|| pos[w_in] + (pos[w_out] - pos[w_in]) * lambda)
                };
                let t = mesh.triangles()[g];
                let kv = t.iter().position(|&x| x as usize == v)?;
                if let (Some(x0), Some(x1)) = (on_edge(a), on_edge(b)) {
                    out.push((g, (kv + 1) % 3, Some((x0, x1))));
                }
            }
        }
        Some(out)
    }
}
