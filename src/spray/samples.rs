//! Evaluation points on the patch: a regular subdivision of every triangle.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), step 6 evaluates thickness at points where
//! equally spaced section planes cut the STL. No paper for this replacement: each triangle
//! is split into `k²` sub-triangles with `k = ceil(longest edge / resolution)`, so coarse
//! CAD meshes (a flat panel of two triangles) get dense samples too, and the sub-triangles
//! form a display mesh for a smooth heat map.
//! Input:  mesh, selected faces, resolution.
//! Output: sample positions, unit normals (area-weighted over the faces that share the
//!         sample), area weights (a third of each touching sub-triangle), sub-triangles.
//! Cost:   linear in the number of samples; refused above [`MAX_SAMPLES`] before allocating.
//! Deviations: samples on an edge are shared between its two faces when both use the same
//!         `k` (always at vertices); otherwise the display mesh has T-junctions there.
//!         Slivers are split by their area (`k ≤ 2·√area / resolution`), so their samples
//!         are farther apart than the resolution along their long edge.

use super::params::{SprayError, MAX_SAMPLES};
use crate::math::{Point3, Real, Vector3};
use crate::mesh::{FaceGeometry, TriMesh};

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

/// Subdivisions of a face for `resolution`: its longest edge over the resolution, rounded
/// up, but no more than `2·√area / resolution`, so a sliver (a long edge, hardly any area)
/// does not get thousands of samples; the two agree on well-shaped triangles.
fn subdivisions(corners: &[Point3; 3], resolution: Real) -> usize {
    let [a, b, c] = corners;
    let longest = (b - a).norm().max((c - b).norm()).max((a - c).norm());
    let area = 0.5 * (b - a).cross(&(c - a)).norm();
    let by_edge = (longest / resolution).ceil();
    let by_area = (2.0 * area.sqrt() / resolution).ceil();
    by_edge.min(by_area).max(1.0) as usize
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
    geometry: &FaceGeometry,
    faces: &[u32],
    resolution: Real,
) -> Result<EvaluationSamples, SprayError> {
    // Count first: refuse before allocating.
    let mut total: Real = 0.0;
    for &f in faces {
        let k = subdivisions(&mesh.corners(f as usize), resolution) as Real;
        total += (k + 1.0) * (k + 2.0) / 2.0;
    }
    if total > MAX_SAMPLES as Real {
        return Err(SprayError::TooManySamples {
            resolution,
            samples: total as usize,
            suggestion: resolution * (total / MAX_SAMPLES as Real).sqrt() * 1.1,
        });
    }
    let mut out = EvaluationSamples::default();
    let mut at_vertex = vec![u32::MAX; mesh.vertex_count()];
    let mut on_edge: rustc_hash::FxHashMap<(u32, u32, u32, u32), u32> =
        rustc_hash::FxHashMap::default();
    let mut grid: Vec<u32> = Vec::new();
    for &f in faces {
        let f = f as usize;
        let tri = mesh.triangles()[f];
        let [a, b, c] = mesh.corners(f);
        let k = subdivisions(&[a, b, c], resolution);
        let kk = k as u32;
        let normal = geometry.normals()[f];
        // Index of grid point (i, j), i + j ≤ k, row by row.
        let index = |i: usize, j: usize| j * (k + 1) - j * (j.saturating_sub(1)) / 2 + i;
        grid.clear();
        for j in 0..=k {
            for i in 0..=(k - j) {
                let position =
                    a + (b - a) * (i as Real / k as Real) + (c - a) * (j as Real / k as Real);
                // Shared samples: vertices, then edge points keyed by (lower vertex, higher
                // vertex, k, index from the lower one).
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
                    let key = if j == 0 {
                        Some(edge_key(tri[0], tri[1], i))
                    } else if i == 0 {
                        Some(edge_key(tri[0], tri[2], j))
                    } else if i + j == k {
                        Some(edge_key(tri[1], tri[2], j))
                    } else {
                        None
                    };
                    match key {
                        Some(key) => *on_edge.entry(key).or_insert_with(|| new_sample(&mut out)),
                        None => new_sample(&mut out),
                    }
                };
                grid.push(id);
            }
        }
        debug_assert_eq!(grid.len(), (k + 1) * (k + 2) / 2);
        let sub_area = geometry.areas()[f] / (k * k) as Real;
        let add = |out: &mut EvaluationSamples, t: [u32; 3]| {
            for s in t {
                out.weights[s as usize] += sub_area / 3.0;
                out.normals[s as usize] += normal * sub_area;
            }
            out.triangles.push(t);
        };
        for j in 0..k {
            for i in 0..(k - j) {
                add(
                    &mut out,
                    [
                        grid[index(i, j)],
                        grid[index(i + 1, j)],
                        grid[index(i, j + 1)],
                    ],
                );
                if i + j + 2 <= k {
                    add(
                        &mut out,
                        [
                            grid[index(i + 1, j)],
                            grid[index(i + 1, j + 1)],
                            grid[index(i, j + 1)],
                        ],
                    );
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
        let mut index: rustc_hash::FxHashMap<(i64, i64, i64, bool), usize> =
            rustc_hash::FxHashMap::default();
        let mut out = EvaluationSamples::default();
        let mut origin = Vec::new();
        for (i, p) in self.positions.iter().enumerate() {
            // Finite: samples lie on validated faces.
            let key = (
                (p.x / cell).floor() as i64,
                (p.y / cell).floor() as i64,
                (p.z / cell).floor() as i64,
                keep_apart[i],
            );
            match index.get(&key) {
                Some(&k) => out.weights[k] += self.weights[i],
                None => {
                    index.insert(key, out.positions.len());
                    origin.push(i);
                    out.positions.push(*p);
                    out.normals.push(self.normals[i]);
                    out.weights.push(self.weights[i]);
                }
            }
        }
        (out, origin)
    }
}

#[cfg(test)]
mod tests {
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
        let s = sample_faces(&mesh, &geometry, &[0], 1.5).unwrap();
        // k = ceil(2√2 / 1.5) = 2: 6 samples, 4 sub-triangles.
        assert_eq!((s.positions.len(), s.triangles.len()), (6, 4));
        let total: Real = s.weights.iter().sum();
        assert!((total - 2.0).abs() < 1e-12);
        assert!(s.normals.iter().all(|n| (n.z - 1.0).abs() < 1e-12));
    }
}
