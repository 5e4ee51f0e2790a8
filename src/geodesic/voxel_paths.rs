//! Step 4 of the voxel method: the voxels at distance `k·s` ordered into passes.
//!
//! Source: Li & Zhang 2021 (see `voxel.rs`), §1.4 and Fig. 10: from a start point, fit a
//!         least-squares line to the path voxels within radius `r`, step along it, repeat;
//!         stop at a closed loop (back near the start, heading against the first direction)
//!         or at an open end (no voxel within `r`), then walk from the start the other way.
//! Input:  a voxel field with distances, a level distance, the radius `r`.
//! Output: ordered polylines (open or closed) with the mean voxel normal at each point.
//! Cost:   O(B) per level for B band voxels, found among the voxels listed under the level
//!         ([`voxels_by_level`], one pass for all levels), not by a scan of every voxel; a
//!         hash grid of cell `r` instead of a k-d tree (the points lie on a lattice of known
//!         spacing, so a uniform grid answers a radius query in O(1) cells and needs no
//!         dependency).
//! Deviations: (1) "distance equals k·s" is read as |d − k·s| ≤ L/2. (2) Each new point is
//!         the centroid of the band voxels within `r` of the stepped point (the literal step
//!         along the fitted line drifts off curved bands); the line direction is the principal
//!         axis of the same voxels (32 power iterations). (3) Band voxels within `r` of a walked
//!         point are removed and walking restarts from the first remaining voxel, so every
//!         piece of a level becomes a path; walks of fewer than 3 points are dropped as noise.

use super::iso_lines::{IsoLine, LevelLists};
use super::voxel::VoxelField;
use crate::math::{Point3, Real, Vector3};
use std::collections::HashMap;

/// Search radius in voxel edges.
pub(crate) const SEARCH_RADIUS_VOXELS: Real = 3.0;
/// Step along the fitted line, in voxel edges.
const STEP_VOXELS: Real = 1.5;
/// Power iterations for the principal axis.
const POWER_ITERATIONS: usize = 32;

struct PointGrid {
    cell: Real,
    map: HashMap<[i64; 3], Vec<usize>>,
}

impl PointGrid {
    fn key(&self, p: &Point3) -> [i64; 3] {
        [0, 1, 2].map(|k| (p[k] / self.cell).floor() as i64)
    }
    fn within(&self, p: &Point3, r: Real, pts: &[Point3], alive: &[bool], out: &mut Vec<usize>) {
        out.clear();
        let k = self.key(p);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(list) = self.map.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                        out.extend(
                            list.iter()
                                .copied()
                                .filter(|&i| alive[i] && (pts[i] - p).norm() <= r),
                        );
                    }
                }
            }
        }
    }
}

/// Principal direction of `pts[idx]` around their centroid, started from `guess`.
fn principal(pts: &[Point3], idx: &[usize], centroid: &Point3, guess: &Vector3) -> Vector3 {
    let mut cov = nalgebra::Matrix3::<Real>::zeros();
    for &i in idx {
        let d = pts[i] - centroid;
        cov += d * d.transpose();
    }
    let mut v = *guess;
    for _ in 0..POWER_ITERATIONS {
        let w = cov * v;
        let len = w.norm();
        if len <= 0.0 {
            return *guess;
        }
        v = w / len;
    }
    if v.dot(guess) < 0.0 {
        -v
    } else {
        v
    }
}

/// The voxels listed under each level `k · spacing` (`k = 1..=levels`) within half an edge
/// of them (one more level each way, a margin for rounding), or `Err(entries)` beyond
/// `max_entries` (see [`LevelLists`]).
pub(crate) fn voxels_by_level(
    field: &VoxelField,
    spacing: Real,
    levels: u32,
    max_entries: u64,
) -> Result<LevelLists, u64> {
    let half = 0.5 * field.size;
    LevelLists::new(0..field.cells.len() as u32, levels, max_entries, |i| {
        let d = field.distance[i as usize];
        (
            ((d - half) / spacing).ceil() - 1.0,
            ((d + half) / spacing).floor() + 1.0,
        )
    })
}

/// Ordered passes of the voxels at `distance`, found among `cells` (which must hold every
/// voxel within half an edge of it, see `LevelLists`).
pub(crate) fn order_level(
    field: &VoxelField,
    distance: Real,
    level: u32,
    cells: &[u32],
) -> Vec<IsoLine> {
    let l = field.size;
    let band: Vec<usize> = cells
        .iter()
        .map(|&i| i as usize)
        .filter(|&i| (field.distance[i] - distance).abs() <= 0.5 * l)
        .collect();
    if band.is_empty() {
        return Vec::new();
    }
    let pts: Vec<Point3> = band.iter().map(|&i| field.centre(i)).collect();
    let r = SEARCH_RADIUS_VOXELS * l;
    let mut grid = PointGrid {
        cell: r,
        map: HashMap::new(),
    };
    for (j, p) in pts.iter().enumerate() {
        let k = grid.key(p);
        grid.map.entry(k).or_default().push(j);
    }
    let mut alive = vec![true; pts.len()];
    let mut near = Vec::new();
    let mut lines = Vec::new();
    let step = STEP_VOXELS * l;
    let max_steps = pts.len() + 8;
    let mean_normal = |idx: &[usize]| -> Vector3 {
        let s: Vector3 = idx.iter().map(|&j| field.normals[band[j]]).sum();
        if s.norm() > 0.0 {
            s.normalize()
        } else {
            Vector3::z()
        }
    };
    for start in 0..pts.len() {
        if !alive[start] {
            continue;
        }
        grid.within(&pts[start], r, &pts, &alive, &mut near);
        let c0: Point3 =
            Point3::from(near.iter().map(|&j| pts[j].coords).sum::<Vector3>() / near.len() as Real);
        let v0 = principal(&pts, &near, &c0, &Vector3::new(0.8, 0.5, 0.3).normalize());
        let n0 = mean_normal(&near);
        let mut halves: [Vec<(Point3, Vector3)>; 2] = [Vec::new(), Vec::new()];
        let mut closed = false;
        for (side, half) in halves.iter_mut().enumerate() {
            let mut x = c0;
            let mut v = if side == 0 { v0 } else { -v0 };
            let mut travelled = 0.0;
            // Bounded: at most one step per band voxel (plus slack).
            for _ in 0..max_steps {
                grid.within(&(x + v * step), r, &pts, &alive, &mut near);
                if near.is_empty() {
                    break; // open end
                }
                let c = Point3::from(
                    near.iter().map(|&j| pts[j].coords).sum::<Vector3>() / near.len() as Real,
                );
                let moved = (c - x).norm();
                if moved < 0.25 * step {
                    break; // no progress: an open end
                }
                // Back within one step of the point before last: the walk oscillates at
                // an end of the band.
                let n_half = half.len();
                if n_half >= 2 && (c - half[n_half - 2].0).norm() < step {
                    break;
                }
                let dir = principal(&pts, &near, &c, &((c - x) / moved));
                travelled += moved;
                // Closed loop: back within one step of the start after going round. The paper
                // also asks that the start lie ahead (PB against V); after a full turn that
                // holds up to the noise of the centroids, so it is not required here (a walk
                // that missed it would circle until `max_steps`).
                if side == 0 && travelled > 2.0 * r && (c - c0).norm() < step {
                    closed = true;
                    break;
                }
                half.push((c, mean_normal(&near)));
                x = c;
                v = dir;
            }
            if closed {
                break;
            }
        }
        let mut chain: Vec<(Point3, Vector3)> = halves[1].iter().rev().copied().collect();
        chain.push((c0, n0));
        chain.extend_from_slice(&halves[0]);
        // Remove the band voxels this walk passed near.
        for (p, _) in &chain {
            grid.within(p, r, &pts, &alive, &mut near);
            for &j in &near {
                alive[j] = false;
            }
        }
        alive[start] = false;
        if chain.len() >= 3 {
            lines.push(IsoLine {
                level,
                distance,
                closed,
                points: chain.iter().map(|c| c.0).collect(),
                normals: chain.iter().map(|c| c.1).collect(),
            });
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, Method};
    use crate::mesh::FaceAdjacency;

    #[test]
    fn a_level_from_the_voxels_listed_under_it_is_that_from_every_voxel() {
        // A wavy tube, its voxel distance from the bottom ring.
        let mesh = crate::geodesic::source::tests::tube(false);
        let adjacency = FaceAdjacency::new(&mesh);
        let params = DistanceParams {
            method: Method::Voxel,
            ..DistanceParams::default()
        };
        let source = GeodesicSource::Vertices((0..24).collect());
        let field = geodesic_distance(&mesh, &adjacency, &source, &params, &mut |_, _| {})
            .unwrap()
            .voxels
            .unwrap();
        let (spacing, levels) = (0.7, 25);
        let lists = voxels_by_level(&field, spacing, levels, u64::MAX).unwrap();
        let every: Vec<u32> = (0..field.cells.len() as u32).collect();
        let mut lines = 0;
        for k in 1..=levels {
            let d = k as Real * spacing;
            let listed = order_level(&field, d, k, lists.of(k));
            let all = order_level(&field, d, k, &every);
            assert_eq!(listed.len(), all.len(), "level {k}");
            for (a, b) in listed.iter().zip(&all) {
                assert_eq!(a.points, b.points, "level {k}");
            }
            lines += all.len();
            assert!(lists.of(k).len() < every.len() / 4, "level {k}");
        }
        assert!(lines >= levels as usize, "{lines} lines");
    }
}
