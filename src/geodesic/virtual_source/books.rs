//! Sources carried across an edge of three or more faces: into a fin or a sliver glued on
//! along an edge of the sheet a settled vertex's source lies in.
//!
//! Source: none (Trettner, Bommes & Kobbelt 2021 assume a manifold mesh).
//! Input:  a settled vertex at an end of such an edge ("book", see `surface.rs`).
//! Output: offers to the corners of the faces glued on along the edge, as [`Solver::settle`]
//!         makes them within one sheet.
//! Why:    a source is moved from face to face round a vertex by the smallest rotation
//!         between their planes, which unfolds it across a shared edge only when the two
//!         faces are wound alike. A fin is a sheet of its own, wound either way, and its
//!         faces are not across any edge from the sheet the source lies in (the adjacency
//!         links nobody across an edge of three or more faces), so the walk round a sharp
//!         vertex (see `fan_walk.rs`) stops there too, and the shadow walk (`shadow.rs`)
//!         took such an edge for a border. A fin's corner was offered the path through an
//!         end of the edge (a fin standing on a plate, from a plane 1.7 away: 2.818 where
//!         the path straight across the edge is 1.7 + 1).
//! How:    the source's sheet round `u` is the set of faces reached from the source's face
//!         across manifold edges through `u`. A face `t` outside it with an edge `u – y`
//!         that also bounds a face `g` of the sheet is offered the source moved into `g`
//!         (as [`Solver::settle`] moves it) where it lies on `g`'s side of the edge, then
//!         unfolded across the edge into `t`'s plane: by the rotation from `g`'s normal to
//!         `t`'s, or to its opposite where `t` runs along the edge in the same direction
//!         as `g` (wound the other way). The offer checks, as every offer, that the ray
//!         crosses the edge. A sliver (whose plane is not defined, see
//!         `Surface::is_sliver`) has its corner offered as a point of `g`, at its foot on
//!         the edge, and that corner becomes a point source of its own; the generic offers
//!         give a sliver at `u` only the path bending at `u` (a source turned into a plane
//!         that rounding sets passed paths shorter than any on the surface: a closed sphere
//!         with slivers glued on went 2.06 below the exact distance, 0.043 without them;
//!         now 0.085). Where `u`'s source holds only in a
//!         walked wedge, a face wound the other way is left out (the wedge's angles are
//!         measured about the face's normal).
//! Cost:   only at vertices on such an edge (none on a manifold mesh): the sheet round the
//!         vertex, and per glued face a turning and an offer for each face of the sheet on
//!         its edge (a handful).

use super::shadow::slot;
use super::{corners_after, crossing, foot, Rotation, Solver, Virtual, FOLD_COSINE};
use crate::math::Point3;

impl Solver<'_> {
    /// Offers the source of settled `u`, at an end of an edge of three or more faces, to the
    /// faces glued on along such edges to its own sheet round `u`, unfolded across the edge
    /// (see the module's header).
    #[inline(never)]
    pub(super) fn offer_across_books(&mut self, u: usize) {
        let surface = self.surface;
        let (tris, normals) = (surface.mesh.triangles(), &surface.face_normals);
        let pos = surface.mesh.positions();
        let books = surface.books();
        let su = self.src[u];
        let (f0, pu) = (su.face as usize, pos[u]);
        let fan = surface.faces_of(u);
        if !fan.contains(&su.face) {
            return;
        }
        // The source's sheet round u: the faces reached from its face across manifold edges
        // through u (each face added once: at most the fan).
        let mut sheet = std::mem::take(&mut self.sheet);
        sheet.clear();
        sheet.push(su.face);
        let mut next = 0;
        while next < sheet.len() {
            let f = sheet[next] as usize;
            next += 1;
            let t = tris[f];
            for k in 0..3 {
                if t[k] as usize != u && t[(k + 1) % 3] as usize != u {
                    continue;
                }
                if let Some(g) = surface.across(f, k) {
                    if !sheet.contains(&(g as u32)) {
                        sheet.push(g as u32);
                    }
                }
            }
        }
        self.across_books = true;
        for &t in fan {
            if sheet.contains(&t) {
                continue;
            }
            let t = t as usize;
            let (p, q) = corners_after(tris[t], u);
            let sliver = surface.is_sliver(t);
            for (x, y) in [(p, q), (q, p)] {
                if self.settled[x] {
                    continue;
                }
                // The edge u – y of t, glued on along an edge of the sheet.
                let tt = tris[t];
                let k = slot(tt, u, y);
                // Through each face of the sheet on the edge whose side of it the source
                // lies on, unfolded across the edge.
                for (g, j) in books.others(t, k) {
                    if !sheet.contains(&(g as u32)) {
                        continue;
                    }
                    let sg = if g == f0 {
                        su
                    } else {
                        let r = Rotation::new(&normals[f0], &normals[g]);
                        if r.c <= FOLD_COSINE {
                            continue;
                        }
                        self.turned(&su, u, g, &r)
                    };
                    let tg = tris[g];
                    let (py, pc) = (pos[y], pos[tg[(j + 2) % 3] as usize]);
                    let e = py - pu;
                    let mid = pu + e * 0.5;
                    let nearest = foot(&mid, &sg.p, &sg.q, &sg.run_on, &normals[g], self.reach);
                    let side = |p: &Point3| e.cross(&(p - pu)).dot(&normals[g]);
                    if side(&nearest) * side(&pc) <= 0.0 {
                        continue;
                    }
                    if sliver {
                        self.offer_sliver_corner(&sg, g, x, u, y, t);
                        continue;
                    }
                    // Wound alike, g and t run along the edge in opposite directions; else
                    // t's normal is turned for the unfolding.
                    let sign = if tg[j] == tt[k] { -1.0 } else { 1.0 };
                    if sign < 0.0 && !self.wedge.is_empty() && !self.wedge[u].is_open() {
                        continue;
                    }
                    let r = Rotation::new(&normals[g], &(normals[t] * sign));
                    if r.c <= FOLD_COSINE {
                        continue;
                    }
                    let s = self.turned(&sg, u, t, &r);
                    if let Some(o) = self.offer(&s, t, x, u, y, y) {
                        let (d, s, giver) = o.of(s, u);
                        self.improve_from(x, d, s, giver);
                    }
                }
            }
        }
        self.across_books = false;
        self.sheet = sheet;
    }

    /// Offers corner `x` of sliver `t`, glued on along the edge `u – y` of face `g`, source
    /// `sg` (in `g`'s plane, on `g`'s side of the edge): `x` is a point of `g`, at its foot
    /// on the edge, reached by the ray from the source that enters `g` across one of its
    /// other edges (or starts in `g`); it becomes a point source of its own (`t`'s plane is
    /// not defined). Checked against the straight line from the source vertex, as offers
    /// are.
    fn offer_sliver_corner(
        &mut self,
        sg: &Virtual,
        g: usize,
        x: usize,
        u: usize,
        y: usize,
        t: usize,
    ) {
        let surface = self.surface;
        let pos = surface.mesh.positions();
        let n = &surface.face_normals[g];
        let (pu, py) = (pos[u], pos[y]);
        let c = surface.mesh.triangles()[g]
            .into_iter()
            .map(|v| v as usize)
            .find(|&v| v != u && v != y)
            .unwrap_or(u);
        let pc = pos[c];
        let e = py - pu;
        if e.norm_squared() == 0.0 {
            return;
        }
        let along = ((pos[x] - pu).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
        let on_edge = pu + e * along;
        let f = foot(&on_edge, &sg.p, &sg.q, &sg.run_on, n, self.reach);
        let w = on_edge - f;
        let d = sg.sigma + w.norm() + (pos[x] - on_edge).norm();
        if d >= self.dist[x] {
            return;
        }
        // Within g: f on its side of every edge (within rounding), or the ray crossing the
        // edge u – c or y – c on its way.
        let side = |a: &Point3, b: &Point3, o: &Point3| {
            (b - a).cross(&(f - a)).dot(n) * (b - a).cross(&(o - a)).dot(n) >= 0.0
        };
        let inside = side(&pu, &py, &pc) && side(&py, &pc, &pu) && side(&pc, &pu, &py);
        let enters = inside
            || crossing(&f, &w, &pu, &pc, n).is_some()
            || crossing(&f, &w, &py, &pc, n).is_some();
        if enters && self.holds(d, sg, &pos[x], u, y) {
            self.improve_from(x, d, Virtual::point(pos[x], d, t as u32), u);
        }
    }
}
