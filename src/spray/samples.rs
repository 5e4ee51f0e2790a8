//! Evaluation points on the patch: a regular subdivision of every triangle.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), step 6 evaluates thickness at points where
//! equally spaced section planes cut the STL. No paper for this replacement: each triangle
//! is split into `k²` sub-triangles, `k` the least whole number at which every point of a
//! sub-triangle lies within `resolution/√2` of one of its corners: the reach of the samples
//! of a square grid `resolution` apart. So coarse CAD meshes (a flat panel of two
//! triangles) get dense samples too, a mesh already that fine (a grid of squares of the
//! resolution, cut along a diagonal longer than it) is sampled at its vertices, and the
//! sub-triangles form a display mesh for a smooth heat map.
//! Input:  mesh, its face adjacency, selected faces, resolution.
//! Output: sample positions, unit normals (area-weighted over the faces that share the
//!         sample), area weights (a third of each touching sub-triangle), sub-triangles.
//! Cost:   linear in the number of samples (plus one index per mesh vertex and face);
//!         refused above [`MAX_SAMPLES`] before allocating. The samples on an edge are read
//!         from the grid of the face across it (the adjacency's neighbour), so only edges
//!         without one (boundary, non-manifold) are looked up in a hash map.
//! Deviations: samples on an edge are shared between its faces when they use the same
//!         `k` (always at vertices); otherwise the display mesh has T-junctions there.
//!         Slivers are split by their area (`k ≤ 2·√area / resolution`), so their samples
//!         are farther apart than the resolution along their long edge.

use super::params::{SprayError, MAX_SAMPLES};
use crate::math::{Point3, Real, Vector3};
use crate::mesh::{FaceAdjacency, FaceGeometry, TriMesh, NO_FACE};

/// Evaluation samples and their display mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EvaluationSamples {
    /// Sample positions on the surface.
    pub positions: Vec<Point3>,
    /// Unit surface normal at each sample.
    pub normals: Vec<Vector3>,
    /// Surface area each sample stands for; they sum to the patch area.
    pub weights: Vec<Real>,
    /// Sub-triangles over the samples, wound like their faces.
    pub triangles: Vec<[u32; 3]>,
}

/// Subdivisions of a face for `resolution`: its [`reach`] times `√2` over the resolution,
/// rounded up, but no more than `2·√area / resolution`, so a sliver (a long edge, hardly
/// any area) does not get thousands of samples; the two agree on well-shaped triangles.
fn subdivisions(corners: &[Point3; 3], resolution: Real) -> usize {
    subdivision_count(face_scale(corners), resolution) as usize
}

/// A face's spacing (`√2` times its [`reach`]: the spacing of a square grid whose samples
/// reach as far) and `2·√area`, which decide its [`subdivisions`].
fn face_scale([a, b, c]: &[Point3; 3]) -> (Real, Real) {
    let (ab, bc, ca) = (b - a, c - b, a - c);
    // Squared sides, each opposite its corner, and the squared norm of a side's cross
    // product with the next: (2·area)².
    let sides = [bc.norm_squared(), ca.norm_squared(), ab.norm_squared()];
    let doubled_area2 = ab.cross(&ca).norm_squared();
    let reach = reach(sides, doubled_area2);
    (
        std::f64::consts::SQRT_2 * reach,
        2.0 * (0.5 * doubled_area2.sqrt()).sqrt(),
    )
}

/// The farthest any point of a triangle lies from its nearest corner, from its squared sides
/// and its squared doubled area: the circumradius `abc / (4·area)` of a triangle without an
/// obtuse angle; for an obtuse one, the farther of the two points of the long side as far
/// from the obtuse corner as from the near end (`b²·c / (b² + c² − a²)`, with `c` the long
/// side and `b` the side from that end to the obtuse corner). At most the longest side, which
/// it falls back to where the formulas divide by nothing (a collapsed triangle).
fn reach(sides: [Real; 3], doubled_area2: Real) -> Real {
    let [x, y, z] = sides;
    let longest = x.max(y).max(z);
    // The other two, in any order (selects, not branches: which is longest is a coin toss
    // on a mesh of right triangles).
    let (s, t) = if longest == x {
        (y, z)
    } else if longest == y {
        (z, x)
    } else {
        (x, y)
    };
    let squared = if longest > s + t {
        // Obtuse at the corner opposite the long side: from either end of it.
        let near = (s / (s + longest - t)).max(t / (t + longest - s));
        longest * near * near
    } else {
        // R² = a²b²c² / (16·area²).
        s * t * longest / (4.0 * doubled_area2)
    };
    if squared.is_finite() {
        squared.min(longest).sqrt()
    } else {
        longest.sqrt()
    }
}

/// [`subdivisions`] from a face's [`face_scale`], as a real number (a tiny resolution splits
/// a face more times than an integer type holds).
fn subdivision_count((spacing, root): (Real, Real), resolution: Real) -> Real {
    let by_spacing = (spacing / resolution).ceil();
    let by_area = (root / resolution).ceil();
    by_spacing.min(by_area).max(1.0)
}

/// Steps of the bisection in [`fit_resolution`] at most.
const FIT_STEPS: usize = 40;

/// The finest resolution, not below `resolution`, at which sampling `faces` gives at most
/// `budget` samples, counting `(k + 1)(k + 2)/2` a face of `k` subdivisions (as
/// [`sample_faces`] splits it; an upper bound: samples on shared edges count twice). Where
/// even one subdivision a face (the vertices) counts more, the resolution at which every face
/// has one. No paper: a bisection, to within 0.1 %, on a count that falls as the resolution
/// grows; O(F) a step, 40 steps at most.
pub fn fit_resolution(mesh: &TriMesh, faces: &[u32], resolution: Real, budget: usize) -> Real {
    let scales: Vec<(Real, Real)> = faces
        .iter()
        .map(|&f| face_scale(&mesh.corners(f as usize)))
        .collect();
    let count = |r: Real| -> Real {
        scales
            .iter()
            .map(|&s| {
                let k = subdivision_count(s, r);
                (k + 1.0) * (k + 2.0) / 2.0
            })
            .sum()
    };
    let budget = budget as Real;
    if resolution.is_nan() || resolution <= 0.0 || count(resolution) <= budget {
        return resolution;
    }
    // From this resolution on every face has one subdivision: coarser changes nothing.
    let coarsest = scales
        .iter()
        .fold(resolution, |m, &(spacing, root)| m.max(spacing.min(root)));
    if count(coarsest) > budget {
        return coarsest;
    }
    let (mut lo, mut hi) = (resolution, coarsest);
    for _ in 0..FIT_STEPS {
        if hi - lo <= 1e-3 * hi {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if count(mid) > budget {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// Whether sampling `faces` at `resolution` subdivides any of them (if not, the samples are
/// the faces' vertices).
pub fn subdivides(mesh: &TriMesh, faces: &[u32], resolution: Real) -> bool {
    faces
        .iter()
        .any(|&f| subdivisions(&mesh.corners(f as usize), resolution) > 1)
}

/// Samples the faces `faces` at `resolution` (at least their vertices).
pub fn sample_faces(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    faces: &[u32],
    resolution: Real,
) -> Result<EvaluationSamples, SprayError> {
    // Count first: refuse before allocating.
    let mut total: Real = 0.0;
    let mut subdivided: Vec<u32> = Vec::with_capacity(faces.len());
    // Sub-triangles, and (for the reservations) the samples on edges and inside faces.
    let (mut sub_triangles, mut on_edges, mut inside) = (0usize, 0usize, 0usize);
    for &f in faces {
        // Counted as a real number (a tiny resolution splits a face more times than a usize
        // holds); the integer is used only once the count is known to fit.
        let kr = subdivision_count(face_scale(&mesh.corners(f as usize)), resolution);
        let k = kr as usize;
        // At most MAX_SAMPLES samples on a face: k fits a u32 once the count passes.
        subdivided.push(k.min(u32::MAX as usize) as u32);
        total += (kr + 1.0) * (kr + 2.0) / 2.0;
        if total <= MAX_SAMPLES as Real {
            sub_triangles += k * k;
            on_edges += 3 * (k - 1);
            inside += (k - 1) * k.saturating_sub(2) / 2;
        }
    }
    if total > MAX_SAMPLES as Real {
        // Every face unsplit already: a coarser resolution cannot help.
        if subdivided.iter().all(|&k| k == 1) {
            return Err(SprayError::TooManyFaces {
                faces: faces.len(),
                samples: total as usize,
            });
        }
        return Err(SprayError::TooManySamples {
            resolution,
            samples: total,
            suggestion: fit_resolution(mesh, faces, resolution, MAX_SAMPLES),
        });
    }
    // About half as many vertices as faces on a closed mesh, and edge samples shared by two
    // faces: reserve about that, so the arrays grow once.
    let expected = faces.len() / 2 + on_edges / 2 + inside;
    let mut out = EvaluationSamples {
        positions: Vec::with_capacity(expected),
        normals: Vec::with_capacity(expected),
        weights: Vec::with_capacity(expected),
        triangles: Vec::with_capacity(sub_triangles),
    };
    let mut at_vertex = vec![u32::MAX; mesh.vertex_count()];
    // Samples on an edge are shared with the face across it (the adjacency's neighbour, once
    // sampled with the same k), read from that face's grid; only edges without a manifold
    // neighbour (boundary, non-manifold) are keyed by (lower vertex, higher vertex, k, index
    // from the lower one).
    let mut sampled_as = vec![u32::MAX; mesh.triangle_count()];
    let mut grids: Vec<u32> = Vec::with_capacity(total as usize);
    let mut grid_start: Vec<usize> = Vec::with_capacity(faces.len());
    let mut on_edge: rustc_hash::FxHashMap<(u32, u32, u32, u32), u32> =
        rustc_hash::FxHashMap::default();
    // Index of grid point (i, j), i + j ≤ k, row by row.
    let index = |k: usize, i: usize, j: usize| j * (k + 1) - j * (j.saturating_sub(1)) / 2 + i;
    // Grid point `m` of `k` along slot `e` of a face (from corner e to corner e + 1).
    let along = |k: usize, e: usize, m: usize| match e {
        0 => (m, 0),
        1 => (k - m, m),
        _ => (0, k - m),
    };
    for (n, (&f, &k)) in faces.iter().zip(&subdivided).enumerate() {
        let f = f as usize;
        let tri = mesh.triangles()[f];
        let [a, b, c] = mesh.corners(f);
        let k = k as usize;
        let kk = k as u32;
        let normal = geometry.normals()[f];
        if k == 1 {
            // Unsplit (most faces of a mesh finer than the resolution): its corners, placed
            // and weighed as the grid below would (the same sums, to the bit).
            grid_start.push(grids.len());
            sampled_as[f] = n as u32;
            let third = geometry.areas()[f] / 3.0;
            let mut ids = [0u32; 3];
            for (corner, (i, j)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
                let v = tri[corner] as usize;
                if at_vertex[v] == u32::MAX {
                    at_vertex[v] = out.positions.len() as u32;
                    out.positions.push(a + (b - a) * i + (c - a) * j);
                    out.normals.push(Vector3::zeros());
                    out.weights.push(0.0);
                }
                ids[corner] = at_vertex[v];
            }
            grids.extend(ids);
            for s in ids.map(|s| s as usize) {
                out.weights[s] += third;
                out.normals[s] += normal * (3.0 * third);
            }
            out.triangles.push(ids);
            continue;
        }
        // Per slot: the grid of the face across, sampled before with the same k, its slot for
        // this edge, and whether it runs the same way.
        let across = adjacency.neighbours(f);
        let shared: [Option<(usize, usize, bool)>; 3] = std::array::from_fn(|e| {
            let g = across[e];
            if g == NO_FACE {
                return None;
            }
            let at = sampled_as[g as usize];
            if at == u32::MAX || subdivided[at as usize] != kk {
                return None;
            }
            let other = mesh.triangles()[g as usize];
            let (p, q) = (tri[e], tri[(e + 1) % 3]);
            (0..3).find_map(|s| {
                let (u, v) = (other[s], other[(s + 1) % 3]);
                ((u, v) == (p, q) || (u, v) == (q, p)).then_some((
                    grid_start[at as usize],
                    s,
                    u == p,
                ))
            })
        });
        grid_start.push(grids.len());
        sampled_as[f] = n as u32;
        for j in 0..=k {
            for i in 0..=(k - j) {
                let position =
                    a + (b - a) * (i as Real / k as Real) + (c - a) * (j as Real / k as Real);
                let edge_key = |x: u32, y: u32, m: usize| {
                    if x < y {
                        (x, y, kk, m as u32)
                    } else {
                        (y, x, kk, (k - m) as u32)
                    }
                };
                let new_sample = |out: &mut EvaluationSamples| {
                    out.positions.push(position);
                    out.normals.push(Vector3::zeros());
                    out.weights.push(0.0);
                    (out.positions.len() - 1) as u32
                };
                let vertex = match (i, j) {
                    (0, 0) => Some(tri[0]),
                    (i, 0) if i == k => Some(tri[1]),
                    (0, j) if j == k => Some(tri[2]),
                    _ => None,
                };
                let id = if let Some(v) = vertex {
                    if at_vertex[v as usize] == u32::MAX {
                        at_vertex[v as usize] = new_sample(&mut out);
                    }
                    at_vertex[v as usize]
                } else {
                    // The slot and the point's index from its first corner.
                    let edge = if j == 0 {
                        Some((0, i))
                    } else if i == 0 {
                        Some((2, k - j))
                    } else if i + j == k {
                        Some((1, j))
                    } else {
                        None
                    };
                    match edge {
                        None => new_sample(&mut out),
                        Some((e, m)) => match shared[e] {
                            Some((g, s, same)) => {
                                let (gi, gj) = along(k, s, if same { m } else { k - m });
                                grids[g + index(k, gi, gj)]
                            }
                            None if across[e] == NO_FACE => {
                                let key = edge_key(tri[e], tri[(e + 1) % 3], m);
                                *on_edge.entry(key).or_insert_with(|| new_sample(&mut out))
                            }
                            None => new_sample(&mut out),
                        },
                    }
                };
                grids.push(id);
            }
        }
        let grid = &grids[grid_start[n]..];
        debug_assert_eq!(grid.len(), (k + 1) * (k + 2) / 2);
        let index = |i: usize, j: usize| index(k, i, j);
        // Each sub-triangle gives a third of its area (and its area times the face normal)
        // to each of its corners; a grid point is a corner of 1 sub-triangle at a corner of
        // the face, 3 on an edge, 6 inside: added once per point, not per sub-triangle.
        let third = geometry.areas()[f] / (k * k) as Real / 3.0;
        for j in 0..=k {
            for i in 0..=(k - j) {
                let on_edges = usize::from(j == 0) + usize::from(i == 0) + usize::from(i + j == k);
                let share = match on_edges {
                    0 => 6.0,
                    1 => 3.0,
                    _ => 1.0,
                } * third;
                let s = grid[index(i, j)] as usize;
                out.weights[s] += share;
                out.normals[s] += normal * (3.0 * share);
            }
        }
        for j in 0..k {
            for i in 0..(k - j) {
                out.triangles.push([
                    grid[index(i, j)],
                    grid[index(i + 1, j)],
                    grid[index(i, j + 1)],
                ]);
                if i + j + 2 <= k {
                    out.triangles.push([
                        grid[index(i + 1, j)],
                        grid[index(i + 1, j + 1)],
                        grid[index(i, j + 1)],
                    ]);
                }
            }
        }
    }
    for n in &mut out.normals {
        let len = n.norm();
        if len > 0.0 {
            *n /= len;
        }
    }
    Ok(out)
}

impl EvaluationSamples {
    /// The samples in the order `order` (a permutation of their ids), display triangles
    /// renumbered: sample `k` of the result is sample `order[k]` of `self`.
    pub fn permuted(&self, order: &[u32]) -> EvaluationSamples {
        let mut new_id = vec![0u32; order.len()];
        for (k, &i) in order.iter().enumerate() {
            new_id[i as usize] = k as u32;
        }
        EvaluationSamples {
            positions: order.iter().map(|&i| self.positions[i as usize]).collect(),
            normals: order.iter().map(|&i| self.normals[i as usize]).collect(),
            weights: order.iter().map(|&i| self.weights[i as usize]).collect(),
            triangles: self
                .triangles
                .iter()
                .map(|t| t.map(|i| new_id[i as usize]))
                .collect(),
        }
    }

    /// The samples thinned to the first one in each cube of side `cell` (no paper; for a
    /// coarse screening on a mesh finer than the resolution): it keeps its position and
    /// normal and carries the weight of its whole cube; `keep_apart[i]` samples are thinned
    /// separately from the others (the interior from the band along the edge). No display
    /// triangles. Also returns the index of each kept sample among `self`'s.
    pub fn thinned(&self, cell: Real, keep_apart: &[bool]) -> (EvaluationSamples, Vec<usize>) {
        self.thinned_by(cell, keep_apart, true)
    }

    /// [`EvaluationSamples::thinned`], the cubes numbered in a dense array when `dense` and
    /// their box has at most [`DENSE_CUBES_PER_SAMPLE`] cubes a sample, else hashed.
    fn thinned_by(
        &self,
        cell: Real,
        keep_apart: &[bool],
        dense: bool,
    ) -> (EvaluationSamples, Vec<usize>) {
        // Finite: samples lie on validated faces.
        let cube = |p: &Point3| [p.x, p.y, p.z].map(|c| (c / cell).floor() as i64);
        let (mut lo, mut hi) = ([i64::MAX; 3], [i64::MIN; 3]);
        if dense {
            for p in &self.positions {
                let k = cube(p);
                for a in 0..3 {
                    lo[a] = lo[a].min(k[a]);
                    hi[a] = hi[a].max(k[a]);
                }
            }
        }
        let dims = [0, 1, 2].map(|a| hi[a].saturating_sub(lo[a]).saturating_add(1).max(0) as u64);
        let cubes = dims[0].saturating_mul(dims[1]).saturating_mul(dims[2]);
        let mut out = EvaluationSamples::default();
        let mut origin = Vec::new();
        let mut keep = |i: usize, slot: &mut u32| {
            if *slot == u32::MAX {
                *slot = out.positions.len() as u32;
                origin.push(i);
                out.positions.push(self.positions[i]);
                out.normals.push(self.normals[i]);
                out.weights.push(self.weights[i]);
            } else {
                out.weights[*slot as usize] += self.weights[i];
            }
        };
        if dense && cubes <= DENSE_CUBES_PER_SAMPLE * self.positions.len() as u64 {
            // Two slots a cube (the samples kept apart and the others).
            let mut slots = vec![u32::MAX; 2 * cubes as usize];
            for (i, p) in self.positions.iter().enumerate() {
                let k = cube(p);
                let [x, y, z] = [0, 1, 2].map(|a| (k[a] - lo[a]) as usize);
                let at = ((z * dims[1] as usize + y) * dims[0] as usize + x) * 2
                    + keep_apart[i] as usize;
                keep(i, &mut slots[at]);
            }
        } else {
            let mut index: rustc_hash::FxHashMap<([i64; 3], bool), u32> =
                rustc_hash::FxHashMap::default();
            for (i, p) in self.positions.iter().enumerate() {
                keep(i, index.entry((cube(p), keep_apart[i])).or_insert(u32::MAX));
            }
        }
        (out, origin)
    }
}

/// Most cubes per sample for which [`EvaluationSamples::thinned`] numbers the cubes of the
/// samples' box in a dense array (faster than hashing them, above all in WebAssembly).
const DENSE_CUBES_PER_SAMPLE: u64 = 8;

#[cfg(test)]
mod tests {
    use super::super::normal_equations::tests::sequence;
    use super::*;

    #[test]
    fn one_triangle_split_in_four_shares_every_sample() {
        let mesh = TriMesh::new(
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(2.0, 0.0, 0.0),
                Point3::new(0.0, 2.0, 0.0),
            ],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let geometry = FaceGeometry::new(&mesh);
        let s = sample_faces(&mesh, &FaceAdjacency::new(&mesh), &geometry, &[0], 1.5).unwrap();
        // Reach √2 (half the long side), spacing 2: k = ceil(2 / 1.5) = 2: 6 samples, 4
        // sub-triangles.
        assert_eq!((s.positions.len(), s.triangles.len()), (6, 4));
        let total: Real = s.weights.iter().sum();
        assert!((total - 2.0).abs() < 1e-12);
        assert!(s.normals.iter().all(|n| (n.z - 1.0).abs() < 1e-12));
    }

    /// The triangles of a grid of `(n + 1)²` vertices numbered row by row, each square cut
    /// along the same diagonal.
    fn grid_triangles(n: u32) -> Vec<[u32; 3]> {
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        triangles
    }

    /// A grid of `n` × `n` squares of side 1 split in two, plus one sliver 10 long.
    fn grid_and_sliver(n: u32) -> TriMesh {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.push(Point3::new(i as Real, j as Real, 0.0));
            }
        }
        let mut triangles = grid_triangles(n);
        let s = positions.len() as u32;
        positions.extend([
            Point3::new(0.0, -1.0, 0.0),
            Point3::new(10.0, -1.0, 0.0),
            Point3::new(5.0, -1.01, 0.0),
        ]);
        triangles.push([s, s + 2, s + 1]);
        TriMesh::new(positions, triangles).unwrap()
    }

    /// The farthest point of a triangle from its corners, searched on a barycentric grid of
    /// `n` steps (a lower bound, within the grid's step of the truth).
    fn reach_by_search([a, b, c]: &[Point3; 3], n: usize) -> Real {
        let mut far: Real = 0.0;
        for j in 0..=n {
            for i in 0..=(n - j) {
                let (u, v) = (i as Real / n as Real, j as Real / n as Real);
                let p = a + (b - a) * u + (c - a) * v;
                let near = [a, b, c].map(|q| (p - q).norm());
                far = far.max(near[0].min(near[1]).min(near[2]));
            }
        }
        far
    }

    #[test]
    fn the_reach_is_the_farthest_point_from_the_corners() {
        let p = |x: Real, y: Real| Point3::new(x, y, 0.0);
        let h = (3.0 as Real).sqrt() / 2.0;
        let mut triangles = vec![
            // Equilateral: the circumradius 1/√3.
            (
                [p(0.0, 0.0), p(1.0, 0.0), p(0.5, h)],
                Some(1.0 / (3.0 as Real).sqrt()),
            ),
            // Right: half the hypotenuse.
            ([p(0.0, 0.0), p(3.0, 0.0), p(0.0, 4.0)], Some(2.5)),
            // Obtuse (120° at the apex, sides 1): the points a third of the long side in.
            (
                [p(0.0, 0.0), p(2.0 * h, 0.0), p(h, 0.5)],
                Some(2.0 * h / 3.0),
            ),
            // A sliver with its apex off the middle.
            ([p(0.0, 0.0), p(10.0, 0.0), p(3.0, 0.01)], None),
        ];
        let mut uniform = sequence(7);
        for _ in 0..200 {
            let mut q = || {
                let x = uniform();
                let y = uniform();
                Point3::new(x, y, uniform())
            };
            triangles.push(([q(), q(), q()], None));
        }
        for (corners, expected) in &triangles {
            let [a, b, c] = corners;
            let sides = [
                (c - b).norm_squared(),
                (a - c).norm_squared(),
                (b - a).norm_squared(),
            ];
            let r = reach(sides, (b - a).cross(&(a - c)).norm_squared());
            if let Some(e) = expected {
                assert!((r - e).abs() < 1e-12, "{corners:?}: {r} against {e}");
            }
            let longest = sides.iter().fold(0.0, |m: Real, &s| m.max(s)).sqrt();
            let searched = reach_by_search(corners, 400);
            assert!(
                searched <= r + 1e-12,
                "{corners:?}: a point {searched} away, reach {r}"
            );
            assert!(
                r - searched <= longest / 400.0,
                "{corners:?}: reach {r}, searched {searched}"
            );
        }
        // A collapsed triangle: its longest side, not a division by nothing.
        let sides = [1.0, 1.0, 0.0];
        assert_eq!(reach(sides, 0.0), 1.0);
        assert_eq!(reach([0.0; 3], 0.0), 0.0);
    }

    #[test]
    fn every_point_lies_within_the_resolution_over_root_two_of_a_sample() {
        // Random triangles over a bumpy square, sampled at a resolution about their size.
        let mut uniform = sequence(11);
        let n = 6;
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as Real, j as Real);
                let jitter = 0.35;
                positions.push(Point3::new(
                    x + jitter * (uniform() - 0.5),
                    y + jitter * (uniform() - 0.5),
                    0.3 * uniform(),
                ));
            }
        }
        let triangles = grid_triangles(n);
        let mesh = TriMesh::new(positions, triangles).unwrap();
        let (adjacency, geometry) = (FaceAdjacency::new(&mesh), FaceGeometry::new(&mesh));
        let faces: Vec<u32> = (0..mesh.triangle_count() as u32).collect();
        for resolution in [0.3, 0.7, 1.0, 2.0] {
            let s = sample_faces(&mesh, &adjacency, &geometry, &faces, resolution).unwrap();
            let bound = resolution / std::f64::consts::SQRT_2 + 1e-12;
            let mut subdivided = false;
            for &f in &faces {
                let corners = mesh.corners(f as usize);
                let (spacing, root) = face_scale(&corners);
                // (Slivers, split by their area, are the documented exception.)
                assert!(spacing <= root, "face {f} is a sliver");
                subdivided |= subdivisions(&corners, resolution) > 1;
                let [a, b, c] = corners;
                let steps = 30;
                for j in 0..=steps {
                    for i in 0..=(steps - j) {
                        let (u, v) = (i as Real / steps as Real, j as Real / steps as Real);
                        let p = a + (b - a) * u + (c - a) * v;
                        let near = s
                            .positions
                            .iter()
                            .fold(Real::INFINITY, |m, q| m.min((p - q).norm()));
                        assert!(
                            near <= bound,
                            "resolution {resolution}: {p:?} {near} from a sample"
                        );
                    }
                }
            }
            // Split at the finer resolutions, sampled at the vertices at the coarsest.
            assert_eq!(subdivided, resolution < 2.0, "resolution {resolution}");
        }
    }

    #[test]
    fn a_grid_of_squares_of_the_resolution_is_sampled_at_its_vertices() {
        // Squares of side 1 cut along a diagonal of √2: at resolution 1 (and a rounding) the
        // samples of a square grid 1 apart reach as far as the vertices do.
        let mesh = grid_and_sliver(10);
        let (adjacency, geometry) = (FaceAdjacency::new(&mesh), FaceGeometry::new(&mesh));
        let faces: Vec<u32> = (0..mesh.triangle_count() as u32).collect();
        let at = |r: Real| {
            let s = sample_faces(&mesh, &adjacency, &geometry, &faces, r).unwrap();
            (s.positions.len(), s.triangles.len())
        };
        assert_eq!(at(1.0 + 1e-12), (mesh.vertex_count(), faces.len()));
        // A little finer: every square's triangles split in four, the sliver not.
        assert_eq!(at(0.99), (21 * 21 + 3, 4 * 200 + 1));
    }

    #[test]
    fn the_fitted_resolution_is_the_finest_within_the_budget() {
        let mesh = grid_and_sliver(20);
        let faces: Vec<u32> = (0..mesh.triangle_count() as u32).collect();
        let count = |r: Real| -> usize {
            faces
                .iter()
                .map(|&f| {
                    let k = subdivisions(&mesh.corners(f as usize), r);
                    (k + 1) * (k + 2) / 2
                })
                .sum()
        };
        // Within the budget already: unchanged.
        assert_eq!(fit_resolution(&mesh, &faces, 0.25, count(0.25)), 0.25);
        for budget in [5_000, 20_000, 100_000] {
            let r = fit_resolution(&mesh, &faces, 0.05, budget);
            assert!(count(r) <= budget, "budget {budget}: {} at {r}", count(r));
            assert!(
                count(r * 0.998) > budget,
                "budget {budget}: {r} is not the finest"
            );
            assert!(r >= 0.05);
        }
        // Fewer than one subdivision a face can give: the resolution of one a face (the
        // sliver's 2·√area, about 0.45, is its largest scale), and the count is the least.
        let least = 3 * faces.len();
        let r = fit_resolution(&mesh, &faces, 0.05, least - 1);
        assert_eq!(count(r), least);
        assert!(count(r * 0.999) > least);
        // The sliver never decides by its length: at 1 it has one subdivision, not ten.
        assert_eq!(subdivisions(&mesh.corners(faces.len() - 1), 1.0), 1);
    }

    #[test]
    fn too_many_faces_for_any_resolution_say_so_not_to_coarsen() {
        // 720,001 faces: 3 corners each is over MAX_SAMPLES at any resolution.
        let mesh = grid_and_sliver(600);
        let faces: Vec<u32> = (0..mesh.triangle_count() as u32).collect();
        let (adjacency, geometry) = (FaceAdjacency::new(&mesh), FaceGeometry::new(&mesh));
        for resolution in [0.5, 1000.0] {
            let e = sample_faces(&mesh, &adjacency, &geometry, &faces, resolution).unwrap_err();
            let message = e.to_string();
            if resolution < 1.0 {
                assert!(message.contains("use a coarser resolution"), "{message}");
            } else {
                assert!(
                    message.starts_with("720001 triangles are selected: even unsplit")
                        && message.ends_with("plan on fewer triangles, e.g. one patch"),
                    "{message}"
                );
            }
        }
    }

    /// Sample positions as bit patterns, for exact comparisons.
    fn distinct(s: &EvaluationSamples) -> usize {
        let keys: std::collections::HashSet<[u64; 3]> = s
            .positions
            .iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
            .collect();
        keys.len()
    }

    #[test]
    fn a_closed_mesh_shares_every_edge_sample_with_the_face_across() {
        // Octahedron, edges √2, k = 3 on every face: V + E·(k − 1) + F·(k − 1)(k − 2)/2.
        let mesh = TriMesh::new(
            vec![
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(-1.0, 0.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
                Point3::new(0.0, -1.0, 0.0),
                Point3::new(0.0, 0.0, 1.0),
                Point3::new(0.0, 0.0, -1.0),
            ],
            vec![
                [0, 2, 4],
                [2, 1, 4],
                [1, 3, 4],
                [3, 0, 4],
                [2, 0, 5],
                [1, 2, 5],
                [3, 1, 5],
                [0, 3, 5],
            ],
        )
        .unwrap();
        let geometry = FaceGeometry::new(&mesh);
        let adjacency = FaceAdjacency::new(&mesh);
        // Faces in an order that meets every edge from both sides and both directions.
        let faces = [5, 0, 7, 2, 1, 6, 3, 4];
        let s = sample_faces(&mesh, &adjacency, &geometry, &faces, 2f64.sqrt() / 2.5).unwrap();
        assert_eq!(s.positions.len(), 6 + 12 * 2 + 8);
        assert_eq!(distinct(&s), s.positions.len());
        assert_eq!(s.triangles.len(), 8 * 9);
        // Every sub-triangle a ninth of its face, wound like it: a shared sample read from
        // the wrong end of an edge would skew or flip some.
        let face_area = geometry.areas()[0];
        for t in &s.triangles {
            let [p, q, r] = t.map(|i| s.positions[i as usize]);
            let n = (q - p).cross(&(r - p)) * 0.5;
            let outward = Vector3::new(p.x + q.x + r.x, p.y + q.y + r.y, p.z + q.z + r.z);
            assert!((n.norm() - face_area / 9.0).abs() < 1e-12, "{t:?}");
            assert!(n.dot(&outward) > 0.0, "{t:?}");
        }
        let total: Real = s.weights.iter().sum();
        assert!((total - geometry.areas().iter().sum::<Real>()).abs() < 1e-12);
    }

    #[test]
    fn an_edge_of_three_faces_keeps_one_set_of_samples() {
        // Edge 0–1 is shared by three faces (non-manifold: no neighbour across it).
        let mesh = TriMesh::new(
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(0.5, 1.0, 0.0),
                Point3::new(0.5, -1.0, 0.0),
                Point3::new(0.5, 0.0, 1.0),
            ],
            vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        )
        .unwrap();
        let geometry = FaceGeometry::new(&mesh);
        let adjacency = FaceAdjacency::new(&mesh);
        let s = sample_faces(&mesh, &adjacency, &geometry, &[0, 1, 2], 0.6).unwrap();
        // k = 2: five vertices, one midpoint on the shared edge, two more per face.
        assert_eq!(s.positions.len(), 5 + 1 + 3 * 2);
        assert_eq!(distinct(&s), s.positions.len());
    }

    #[test]
    fn thinning_by_a_dense_array_keeps_what_hashing_keeps() {
        let mesh = TriMesh::new(
            vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(10.0, 0.0, 1.0),
                Point3::new(0.0, 7.0, -2.0),
                Point3::new(9.0, 8.0, 0.5),
            ],
            vec![[0, 1, 2], [1, 3, 2]],
        )
        .unwrap();
        let geometry = FaceGeometry::new(&mesh);
        let adjacency = FaceAdjacency::new(&mesh);
        let s = sample_faces(&mesh, &adjacency, &geometry, &[0, 1], 0.7).unwrap();
        let apart: Vec<bool> = s.positions.iter().map(|p| p.x < 2.0).collect();
        let (dense, dense_origin) = s.thinned_by(1.9, &apart, true);
        let (hashed, hashed_origin) = s.thinned_by(1.9, &apart, false);
        assert_eq!(dense_origin, hashed_origin);
        assert_eq!(dense, hashed);
        assert!(
            dense.positions.len() * 4 < s.positions.len(),
            "{}",
            dense.positions.len()
        );
        let (a, b): (Real, Real) = (dense.weights.iter().sum(), s.weights.iter().sum());
        assert!((a - b).abs() < 1e-9 * b);
    }
}
