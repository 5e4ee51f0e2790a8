//! Coating quality: area-weighted mean, standard deviation `E`, error `δ`, min and max, over
//! the patch's interior and over the whole patch.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), step 6 and claim 4: mean thickness
//! (area-weighted), standard deviation `E` and error `δ = max |T − T̄| / T̄`.
//! Input:  samples with area weights and thickness; the patch's boundary edges.
//! Output: [`Quality`] for the interior (samples at least `edgeExclusion` from the boundary)
//!         and for the whole patch.
//! Cost:   O(samples + boundary length / edgeExclusion) through a bucket grid.
//! Deviations: the interior uses the Euclidean distance to the patch's boundary edges (not
//!         the geodesic one): boundary edges are cut into pieces no longer than the band,
//!         whose midpoints go into a [`PointGrid`]; a sample is interior when no piece lies
//!         within the band. A band wider than half the patch leaves no interior: the
//!         interior figures then equal the whole patch's and a note says so.

use super::grid::PointGrid;
use crate::math::{Point3, Real};
use crate::mesh::{FaceAdjacency, TriMesh, NO_FACE};

/// Thickness figures over a set of samples (mesh unit; `error` a ratio).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ThicknessStats {
    /// Area-weighted mean `T̄`.
    pub mean: Real,
    /// Area-weighted standard deviation `E`.
    pub std_dev: Real,
    /// `δ = max |T − T̄| / T̄` (0 when `T̄ = 0`).
    pub error: Real,
    /// Smallest thickness.
    pub min: Real,
    /// Largest thickness.
    pub max: Real,
    /// Area covered.
    pub area: Real,
}

/// Quality over the interior and the whole patch.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Quality {
    /// Away from the boundary by at least `edgeExclusion`.
    pub interior: ThicknessStats,
    /// The whole patch.
    pub whole: ThicknessStats,
}

/// Figures over the samples where `keep` holds.
pub fn thickness_stats(
    thickness: &[Real],
    weights: &[Real],
    keep: impl Fn(usize) -> bool,
) -> ThicknessStats {
    let (mut area, mut sum) = (0.0, 0.0);
    let (mut min, mut max) = (Real::INFINITY, Real::NEG_INFINITY);
    for (i, (&t, &w)) in thickness.iter().zip(weights).enumerate() {
        if keep(i) && w > 0.0 {
            area += w;
            sum += w * t;
            // As `f64::min`/`max` (a NaN is passed over), without their calls in WebAssembly.
            if t < min {
                min = t;
            }
            if t > max {
                max = t;
            }
        }
    }
    if area <= 0.0 {
        return ThicknessStats::default();
    }
    let mean = sum / area;
    let mut var = 0.0;
    for (i, (&t, &w)) in thickness.iter().zip(weights).enumerate() {
        if keep(i) && w > 0.0 {
            var += w * (t - mean) * (t - mean);
        }
    }
    let error = if mean > 0.0 {
        (max - mean).max(mean - min) / mean
    } else {
        0.0
    };
    ThicknessStats {
        mean,
        std_dev: (var / area).sqrt(),
        error,
        min,
        max,
        area,
    }
}

/// Whether each sample is at least `band` (Euclidean) from the boundary of the selected faces.
pub fn interior_mask(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    faces: &[u32],
    selected: &[bool],
    samples: &[Point3],
    band: Real,
) -> Vec<bool> {
    if band <= 0.0 {
        return vec![true; samples.len()];
    }
    // Boundary edges cut into pieces of at most `band / 2`: a piece within `band` of a sample
    // has its midpoint within 1.25·band of it. The pieces are bucketed in cells of `band`:
    // the box that reach around a cube of samples below (3·band wide) covers at most four
    // along each axis (with cells of `band / 2`, up to seven: 343 cells a cube, most of them
    // empty, and the mask took a third to three quarters longer on the bench's 20k panel and
    // on the Orion and 747 patches at the page's budget). The first piece found within
    // `band` decides, so a sample near the boundary stops early.
    let piece = 0.5 * band;
    let mut pieces: Vec<Point3> = Vec::new();
    let mut ends: Vec<(Point3, Point3)> = Vec::new();
    for &f in faces {
        let tri = mesh.triangles()[f as usize];
        for (e, &g) in adjacency.neighbours(f as usize).iter().enumerate() {
            if g != NO_FACE && selected[g as usize] {
                continue;
            }
            let a = mesh.positions()[tri[e] as usize];
            let b = mesh.positions()[tri[(e + 1) % 3] as usize];
            let n = ((b - a).norm() / piece).ceil().max(1.0) as usize;
            for s in 0..n {
                let p = a + (b - a) * (s as Real / n as Real);
                let q = a + (b - a) * ((s + 1) as Real / n as Real);
                pieces.push(Point3::from((p.coords + q.coords) * 0.5));
                ends.push((p, q));
            }
        }
    }
    if pieces.is_empty() {
        return vec![true; samples.len()];
    }
    let grid = PointGrid::new(&pieces, band);
    let reach = 1.25 * band;
    let distance = |x: &Point3, i: u32| {
        let (p, q) = ends[i as usize];
        let d = q - p;
        let t = ((x - p).dot(&d) / d.norm_squared().max(Real::MIN_POSITIVE)).clamp(0.0, 1.0);
        (x - (p + d * t)).norm()
    };
    // Every point of a cube lies within its half-diagonal of the centre (a little more,
    // for rounding), so a piece farther than `band` plus that from the centre is beyond
    // `band` from each of its samples, and one nearer than `band` less that is within
    // `band` of all of them: those cubes are decided once, not sample by sample.
    let half_diagonal = 0.5 * piece * 3f64.sqrt() * (1.0 + 1e-9);
    // The pieces within reach of a cube of side `piece` are listed once for all the samples
    // in it (samples come stored cell by cell, so runs share a cube, but the sample grid's
    // cells need not line up with these cubes: a cube met again is looked up, not listed
    // again); far from the boundary the list is empty.
    let mut cubes: rustc_hash::FxHashMap<[i64; 3], (bool, u32, u32)> =
        rustc_hash::FxHashMap::default();
    let mut lists: Vec<u32> = Vec::new();
    let mut cube: Option<[i64; 3]> = None;
    let (mut all_near, mut near) = (false, 0..0);
    samples
        .iter()
        .map(|x| {
            // Finite: samples lie on validated faces.
            let key = [0, 1, 2].map(|a| (x[a] / piece).floor() as i64);
            if cube != Some(key) {
                cube = Some(key);
                let (all, from, to) = *cubes.entry(key).or_insert_with(|| {
                    let from = lists.len() as u32;
                    let mut all = false;
                    let lo = crate::math::Vector3::from(key.map(|k| k as Real * piece - reach));
                    let hi =
                        crate::math::Vector3::from(key.map(|k| (k + 1) as Real * piece + reach));
                    let centre = Point3::from(key.map(|k| (k as Real + 0.5) * piece));
                    grid.any_in_box(&lo, &hi, |i| {
                        let d = distance(&centre, i as u32);
                        if d + half_diagonal < band {
                            all = true;
                        } else if d - half_diagonal < band {
                            lists.push(i as u32);
                        }
                        all
                    });
                    if all {
                        lists.truncate(from as usize);
                    }
                    (all, from, lists.len() as u32)
                });
                all_near = all;
                near = from as usize..to as usize;
            }
            !all_near && !lists[near.clone()].iter().any(|&i| distance(x, i) < band)
        })
        .collect()
}

/// Interior and whole-patch figures; the interior falls back to the whole when it is empty
/// (the returned flag says so).
pub fn evaluate_quality(
    thickness: &[Real],
    weights: &[Real],
    interior: &[bool],
) -> (Quality, bool) {
    let whole = thickness_stats(thickness, weights, |_| true);
    let inner = thickness_stats(thickness, weights, |i| interior[i]);
    if inner.area > 0.0 {
        (
            Quality {
                interior: inner,
                whole,
            },
            false,
        )
    } else {
        (
            Quality {
                interior: whole,
                whole,
            },
            true,
        )
    }
}
