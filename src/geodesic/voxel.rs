//! The paper's voxel method: voxelise the surface, then propagate the distance from the source
//! voxels over neighbouring voxels with the tangent-plane step length.
//!
//! Source: Li & Zhang, "Research on space equidistant path planning algorithm of complex
//!         curved surface for arc additive manufacturing", Trans. China Welding Institution
//!         42(7):14-20, 2021 (DOI 10.12073/j.hjxb.20201126001), §1.1 voxelisation (Fig. 2–3),
//!         §1.2 distance between neighbouring voxels (Fig. 5, Eq. 3), §1.3 front propagation
//!         (Fig. 7–8, Eq. 1–2). The exact box–triangle test is Akenine-Möller, "Fast 3D
//!         triangle-box overlap testing" (JGT 6(1), 2001), separating axis theorem, 13 axes.
//! Input:  active faces, voxel edge `L`, a resolved source, a memory limit.
//! Output: sparse voxels (integer cell, centre, unit surface normal, distance).
//! Cost:   O(A / L²) voxels, each visited once per front with its 26 neighbours
//!         (log of the front size for the heap); memory ≈ 100 bytes a voxel, checked
//!         against the limit from the surface area before anything is allocated.
//! Deviations: (1) the paper accepts a voxel whose centre projects inside the triangle; this
//!         holds only when the centre is within L/2 of the plane, farther ones go to the exact
//!         test. (2) The cells scanned for a triangle are those of its bounding box within
//!         √3·L of its plane along the dominant normal axis (the first rejection, applied per
//!         column instead of per cell). (3) The levelling rule ("if the new front's distances
//!         differ by more than L, expand the smaller ones once more") is applied as: settle
//!         every front voxel within L of the front's smallest distance, keep the others
//!         tentative; a binary heap holds the front. (4) The voxel normal is the normalised
//!         sum of the unit normals of the faces that touch it.

use super::params::{GeodesicError, Progress, PROGRESS_EVERY};
use super::source::ResolvedSource;
use super::surface::Surface;
use crate::math::{Point3, Real, Vector3};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Estimated bytes per voxel (key, centre, normal, distance, hash slot, heap share).
const BYTES_PER_VOXEL: u64 = 96;
/// Estimated bytes per (voxel, face) pair collected during voxelisation.
const BYTES_PER_PAIR: u64 = 16;
/// Grid cells per axis at most (keys pack three 21-bit indices).
const MAX_CELLS_PER_AXIS: i64 = 1 << 21;

/// A sparse voxelisation with the distance of every voxel.
#[derive(Clone, Debug)]
pub struct VoxelField {
    /// Voxel edge `L`.
    pub size: Real,
    /// Corner of cell (0, 0, 0).
    pub origin: Point3,
    /// Integer cell of each voxel, sorted by packed key.
    pub cells: Vec<[i32; 3]>,
    /// Unit surface normal per voxel.
    pub normals: Vec<Vector3>,
    /// Distance per voxel (`+∞` if unreached).
    pub distance: Vec<Real>,
    /// Bytes held by the field and its lookup table.
    pub memory_bytes: usize,
    table: KeyTable,
}

fn pack(c: [i32; 3]) -> u64 {
    ((c[0] as u64) << 42) | ((c[1] as u64) << 21) | (c[2] as u64)
}

/// Open-addressing hash table from packed cell key to voxel index (no paper; linear
/// probing, load ≤ 1/2, multiplicative hashing).
#[derive(Clone, Debug)]
struct KeyTable {
    keys: Vec<u64>,
    values: Vec<u32>,
    mask: usize,
    shift: u32,
}

impl KeyTable {
    const EMPTY: u64 = u64::MAX;
    fn new(keys: &[u64]) -> Self {
        let cap = (keys.len() * 2).next_power_of_two().max(16);
        let mut t = KeyTable {
            keys: vec![Self::EMPTY; cap],
            values: vec![0; cap],
            mask: cap - 1,
            shift: 64 - cap.trailing_zeros(),
        };
        for (i, &k) in keys.iter().enumerate() {
            let mut s = t.slot(k);
            while t.keys[s] != Self::EMPTY {
                s = (s + 1) & t.mask;
            }
            t.keys[s] = k;
            t.values[s] = i as u32;
        }
        t
    }
    fn slot(&self, k: u64) -> usize {
        // The top bits of the product depend on every bit of the key (Knuth, TAOCP 6.4).
        (k.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> self.shift) as usize
    }
    fn get(&self, k: u64) -> Option<usize> {
        let mut s = self.slot(k);
        // Load ≤ 1/2: an empty slot is met within the table size.
        for _ in 0..=self.mask {
            match self.keys[s] {
                Self::EMPTY => return None,
                x if x == k => return Some(self.values[s] as usize),
                _ => s = (s + 1) & self.mask,
            }
        }
        None
    }
    fn bytes(&self) -> usize {
        self.keys.len() * 12
    }
}

impl VoxelField {
    /// Index of the voxel at integer cell `c`.
    pub fn find(&self, c: [i32; 3]) -> Option<usize> {
        if c.iter().any(|&x| x < 0 || x as i64 >= MAX_CELLS_PER_AXIS) {
            return None;
        }
        self.table.get(pack(c))
    }
    /// Integer cell containing point `p`.
    pub fn cell_of(&self, p: &Point3) -> [i32; 3] {
        [0, 1, 2].map(|k| ((p[k] - self.origin[k]) / self.size).floor() as i32)
    }
    /// Centre of voxel `i`.
    pub fn centre(&self, i: usize) -> Point3 {
        let c = self.cells[i];
        Point3::new(
            self.origin.x + (c[0] as Real + 0.5) * self.size,
            self.origin.y + (c[1] as Real + 0.5) * self.size,
            self.origin.z + (c[2] as Real + 0.5) * self.size,
        )
    }
    /// The voxel containing `p`, or the nearest of its 26 neighbours that exists.
    pub fn voxel_near(&self, p: &Point3) -> Option<usize> {
        let c = self.cell_of(p);
        if let Some(i) = self.find(c) {
            return Some(i);
        }
        neighbour_offsets()
            .filter_map(|o| self.find([c[0] + o[0], c[1] + o[1], c[2] + o[2]]))
            .min_by(|&a, &b| {
                (self.centre(a) - p)
                    .norm_squared()
                    .total_cmp(&(self.centre(b) - p).norm_squared())
            })
    }
}

/// The 26 neighbour offsets of a cell.
fn neighbour_offsets() -> impl Iterator<Item = [i32; 3]> {
    (0..27)
        .map(|i| [i % 3 - 1, (i / 3) % 3 - 1, i / 9 - 1])
        .filter(|o| *o != [0, 0, 0])
}

/// Estimated `(voxels, bytes)` for edge `l` (before anything is allocated).
fn estimate(surface: &Surface, l: Real) -> (u64, u64) {
    // A surface crosses at most √3·A/L² cells of a lattice; the factor 2 covers the cells
    // near edges that the exact test keeps, and the perimeter of a square sheet of area A.
    let voxels = 2.0 * surface.area / (l * l) + 8.0 * surface.area.sqrt() / l;
    // Every face adds its own cells along its edges (1.5 edges a face).
    let edges = 1.5 * surface.faces.len() as Real * surface.mean_edge;
    let pairs = voxels + 2.0 * edges / l + 8.0 * surface.faces.len() as Real;
    let v = voxels.min(1e18) as u64;
    let p = pairs.min(1e18) as u64;
    (
        v,
        v.saturating_mul(BYTES_PER_VOXEL)
            .saturating_add(p.saturating_mul(BYTES_PER_PAIR)),
    )
}

/// Akenine-Möller (2001): does the axis-aligned box `centre ± h` overlap triangle `t`?
fn box_overlaps_triangle(centre: &Point3, h: Real, t: &[Point3; 3]) -> bool {
    let v = [t[0] - centre, t[1] - centre, t[2] - centre];
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
    // 9 axes: box axis × triangle edge.
    for ax in &axes {
        for ed in &e {
            let a = ax.cross(ed);
            let p = [a.dot(&v[0]), a.dot(&v[1]), a.dot(&v[2])];
            let r = h * (a.x.abs() + a.y.abs() + a.z.abs());
            let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
            if lo > r || hi < -r {
                return false;
            }
        }
    }
    // 3 box face normals: the triangle's bounding box against the box.
    let (lo, hi) = (v[0].inf(&v[1]).inf(&v[2]), v[0].sup(&v[1]).sup(&v[2]));
    if lo.iter().any(|&x| x > h) || hi.iter().any(|&x| x < -h) {
        return false;
    }
    // The triangle's plane.
    let n = e[0].cross(&e[1]);
    let r = h * (n.x.abs() + n.y.abs() + n.z.abs());
    n.dot(&v[0]).abs() <= r
}

/// Distance from `q` (in the triangle's plane) to the triangle's edges and whether it lies
/// inside.
fn inside_and_edge_distance(q: &Point3, t: &[Point3; 3], n: &Vector3) -> (bool, Real) {
    let mut inside = true;
    let mut dmin = Real::INFINITY;
    for k in 0..3 {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        if (b - a).cross(&(q - a)).dot(n) < 0.0 {
            inside = false;
        }
        dmin = dmin.min(super::surface::segment_distance(q, &a, &b).0);
    }
    (inside, dmin)
}

/// Step 1: voxelise the active faces triangle by triangle.
pub(crate) fn voxelise(
    surface: &Surface,
    l: Real,
    max_bytes: u64,
    progress: Progress,
) -> Result<VoxelField, GeodesicError> {
    super::params::positive("voxelSize", l)?;
    let mesh = surface.mesh;
    let (est_voxels, est_bytes) = estimate(surface, l);
    let (mut lo, mut hi) = (Point3::from([Real::MAX; 3]), Point3::from([Real::MIN; 3]));
    for &f in &surface.faces {
        for p in mesh.corners(f as usize) {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
    }
    let cells_per_axis = ((hi - lo).max() / l).ceil() as i64 + 4;
    if est_bytes > max_bytes || cells_per_axis >= MAX_CELLS_PER_AXIS {
        // The smallest edge that fits: the estimate falls with L, bisect (60 halvings).
        let (mut a, mut b) = (l, (hi - lo).max().max(l) * 2.0);
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            let fits = estimate(surface, m).1 <= max_bytes
                && (((hi - lo).max() / m).ceil() as i64 + 4) < MAX_CELLS_PER_AXIS;
            if fits {
                b = m;
            } else {
                a = m;
            }
        }
        return Err(GeodesicError::VoxelTooSmall {
            voxel_size: l,
            estimated_voxels: est_voxels,
            estimated_bytes: est_bytes,
            limit_bytes: max_bytes,
            min_size: b,
        });
    }
    let origin = lo - Vector3::repeat(l);
    let sqrt3 = 3.0_f64.sqrt();
    let sqrt2 = 2.0_f64.sqrt();
    let mut pairs: Vec<(u64, u32)> = Vec::new();
    for (done, &f) in surface.faces.iter().enumerate() {
        if done % PROGRESS_EVERY == 0 {
            progress("voxelise", done as f64 / surface.faces.len() as f64);
        }
        let t = mesh.corners(f as usize);
        let sn = mesh.scaled_normal(f as usize);
        if sn.norm() <= 0.0 {
            continue;
        }
        let n = sn.normalize();
        // Dominant axis w of the normal; scan columns over the other two axes.
        let w = (0..3)
            .max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
            .unwrap_or(2);
        let (u, v) = ((w + 1) % 3, (w + 2) % 3);
        let tmin = t[0].inf(&t[1]).inf(&t[2]);
        let tmax = t[0].sup(&t[1]).sup(&t[2]);
        let idx = |x: Real, k: usize| ((x - origin[k]) / l).floor() as i64;
        let half_band = sqrt3 * l / n[w].abs();
        for iu in idx(tmin[u] - l, u)..=idx(tmax[u] + l, u) {
            for iv in idx(tmin[v] - l, v)..=idx(tmax[v] + l, v) {
                let cu = origin[u] + (iu as Real + 0.5) * l;
                let cv = origin[v] + (iv as Real + 0.5) * l;
                // Plane n·(x − t0) = 0 solved for the w coordinate of this column.
                let cw0 = t[0][w] - (n[u] * (cu - t[0][u]) + n[v] * (cv - t[0][v])) / n[w];
                let (wa, wb) = (
                    idx(cw0 - half_band, w).max(idx(tmin[w] - l, w)),
                    idx(cw0 + half_band, w).min(idx(tmax[w] + l, w)),
                );
                for iw in wa..=wb {
                    let mut c = Point3::origin();
                    c[u] = cu;
                    c[v] = cv;
                    c[w] = origin[w] + (iw as Real + 0.5) * l;
                    // Step 1, first rejection: farther than √3·L from the plane.
                    let h = n.dot(&(c - t[0]));
                    if h.abs() > sqrt3 * l {
                        continue;
                    }
                    // Second filter on the projection q of the centre onto the plane.
                    let q = c - n * h;
                    let (inside, edge_d) = inside_and_edge_distance(&q, &t, &n);
                    let hit = if inside && h.abs() <= 0.5 * l {
                        true
                    } else if !inside && edge_d > sqrt2 * l {
                        false
                    } else {
                        box_overlaps_triangle(&c, 0.5 * l, &t)
                    };
                    if hit {
                        let mut cell = [0i32; 3];
                        cell[u] = iu as i32;
                        cell[v] = iv as i32;
                        cell[w] = iw as i32;
                        pairs.push((pack(cell), f));
                    }
                }
            }
        }
    }
    pairs.sort_unstable();
    let mut cells = Vec::new();
    let mut keys = Vec::new();
    let mut normals: Vec<Vector3> = Vec::new();
    for (i, &(k, f)) in pairs.iter().enumerate() {
        let fnrm = surface.face_normal(f as usize);
        if i == 0 || pairs[i - 1].0 != k {
            keys.push(k);
            cells.push([
                (k >> 42) as i32,
                ((k >> 21) & 0x1F_FFFF) as i32,
                (k & 0x1F_FFFF) as i32,
            ]);
            normals.push(fnrm);
        } else if let Some(last) = normals.last_mut() {
            *last += fnrm;
        }
    }
    for (i, n) in normals.iter_mut().enumerate() {
        let len = n.norm();
        // Opposite faces through one voxel (a thin wall) cancel: keep the first face's normal.
        *n = if len > 1e-6 {
            *n / len
        } else {
            let first = pairs.partition_point(|p| p.0 < keys[i]);
            surface.face_normal(pairs[first].1 as usize)
        };
    }
    drop(pairs);
    let table = KeyTable::new(&keys);
    let n = cells.len();
    let memory_bytes = n * (12 + 24 + 8) + table.bytes();
    progress("voxelise", 1.0);
    Ok(VoxelField {
        size: l,
        origin,
        cells,
        normals,
        distance: vec![Real::INFINITY; n],
        memory_bytes,
        table,
    })
}

#[derive(Clone, Copy, PartialEq)]
struct Entry {
    d: Real,
    i: u32,
}
impl Eq for Entry {}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .d
            .total_cmp(&self.d)
            .then_with(|| other.i.cmp(&self.i))
    }
}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Steps 2–3: distance from the source voxels by front propagation.
pub(crate) fn propagate(
    field: &mut VoxelField,
    source: &ResolvedSource,
    surface: &Surface,
    progress: Progress,
) -> Result<(), GeodesicError> {
    let l = field.size;
    let n = field.cells.len();
    let mut heap = BinaryHeap::new();
    // Source voxels: those the source curve passes through (samples ≤ L/2 apart) or that
    // contain a source vertex.
    let mut seed = |p: &Point3, field: &mut VoxelField| {
        if let Some(i) = field.voxel_near(p) {
            if field.distance[i] > 0.0 {
                field.distance[i] = 0.0;
                heap.push(Entry {
                    d: 0.0,
                    i: i as u32,
                });
            }
        }
    };
    for c in &source.curves {
        let m = c.points.len();
        let segs = if c.closed { m } else { m.saturating_sub(1) };
        if m == 1 {
            seed(&c.points[0], field);
        }
        for j in 0..segs {
            let (a, b) = (c.points[j], c.points[(j + 1) % m]);
            let pieces = ((b - a).norm() / (0.5 * l)).ceil().max(1.0) as usize;
            for s in 0..=pieces {
                seed(&(a + (b - a) * (s as Real / pieces as Real)), field);
            }
        }
    }
    for &v in &source.vertices {
        seed(&surface.mesh.positions()[v as usize], field);
    }
    if heap.is_empty() {
        return Err(GeodesicError::SourceMissesSurface(
            "no voxel contains the source".into(),
        ));
    }
    let mut settled = vec![false; n];
    let mut front = Vec::new();
    let mut done = 0usize;
    // Every round settles at least the heap's smallest live entry; each settled voxel pushes
    // at most 26 entries, so the loop ends.
    while let Some(first) = heap.pop() {
        if settled[first.i as usize] || first.d > field.distance[first.i as usize] {
            continue;
        }
        // Step 3, levelling: the front voxels within L of the smallest distance are settled
        // together; larger ones wait for these to expand once more.
        front.clear();
        front.push(first.i as usize);
        settled[first.i as usize] = true;
        while let Some(top) = heap.peek() {
            if top.d > first.d + l {
                break;
            }
            let e = *top;
            heap.pop();
            let i = e.i as usize;
            if !settled[i] && e.d <= field.distance[i] {
                settled[i] = true;
                front.push(i);
            }
        }
        for &i in &front {
            done += 1;
            if done % PROGRESS_EVERY == 0 {
                progress("distance", done as f64 / n as f64);
            }
            let ci = field.cells[i];
            let pi = field.centre(i);
            for o in neighbour_offsets() {
                let Some(j) = field.find([ci[0] + o[0], ci[1] + o[1], ci[2] + o[2]]) else {
                    continue;
                };
                if settled[j] {
                    continue;
                }
                // Step 2 (Eq. 3): |P Pn| projected on the tangent plane at P (normal N_P).
                let ab = pi - field.centre(j);
                let len = ab.norm();
                let cos = ab.dot(&field.normals[j]) / len;
                let t = len * (1.0 - cos * cos).max(0.0).sqrt();
                // Eq. 1–2: J_P = min_n (L_n + T_n).
                let cand = field.distance[i] + t;
                if cand < field.distance[j] {
                    field.distance[j] = cand;
                    heap.push(Entry {
                        d: cand,
                        i: j as u32,
                    });
                }
            }
        }
    }
    progress("distance", 1.0);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_triangle_test_separates_and_overlaps() {
        let t = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        assert!(box_overlaps_triangle(&Point3::new(0.2, 0.2, 0.05), 0.1, &t));
        assert!(!box_overlaps_triangle(&Point3::new(0.2, 0.2, 0.2), 0.1, &t));
        // Beyond the hypotenuse but inside the bounding box: only the edge axes separate it.
        assert!(!box_overlaps_triangle(&Point3::new(0.7, 0.7, 0.0), 0.1, &t));
        assert!(box_overlaps_triangle(
            &Point3::new(0.55, 0.55, 0.0),
            0.1,
            &t
        ));
    }
}
