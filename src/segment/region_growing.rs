//! Step 1: region growing over edge-adjacent faces with a pairwise threshold.
//!
//! Source: Wang, Zhao, Tao 2019 (see `params.rs`), §2.1 and Fig. 2: a neighbour joins when,
//! against the adjacent face already in the region, `γ < α_th` (spraying) or
//! `γ / l < κ` (grinding, `l` the centroid distance, Eq. 5–6).
//! Input:  face adjacency and geometry; a validated [`GrowthThreshold`].
//! Output: a region id per face; every region is edge-connected.
//! Cost:   linear in faces (each face is queued once and looks at three neighbours); with
//!         no degenerate face, one sequential union–find pass instead of the growing.
//! Deviations: the paper starts from a random face. The pairwise test is symmetric, so the
//! regions are the connected components of the "may join" graph and do not depend on the
//! seed; we take seeds in index order. A degenerate face (no usable normal) joins any region
//! that reaches it and stands in with the normal of the face it was reached from (no paper;
//! chosen so that zero-area slivers at T-junctions neither split nor bridge regions).

use super::GrowthThreshold;
use crate::math::{angle_between, cos, larger, Real};
use crate::mesh::{FaceAdjacency, FaceGeometry};

/// Step-1 regions: `region_of[f]` for every face, ids `0..count` in order of their seeds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Regions {
    /// Region id of every face.
    pub region_of: Vec<u32>,
    /// Number of regions.
    pub count: usize,
}

const UNASSIGNED: u32 = u32::MAX;

/// Grows regions (step 1) with the pairwise criterion `threshold`.
pub fn grow_regions(
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    threshold: GrowthThreshold,
) -> Regions {
    grow_regions_and_bends(adjacency, geometry, threshold, false).0
}

/// [`grow_regions`], and with `bends`, where the angle criterion compares the same dot
/// products and no face is degenerate, each face's sharpest bend to a neighbour,
/// `max(0, max_g ½(1 − n_f·n_g))` (the [`SeedRule::Flattest`] key of
/// [`seed_order`](super::seed_order), bit for bit: the dot product is symmetric and the
/// maximum does not depend on the order), from the union–find's pass.
///
/// [`SeedRule::Flattest`]: super::SeedRule::Flattest
pub(crate) fn grow_regions_and_bends(
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    threshold: GrowthThreshold,
    bends: bool,
) -> (Regions, Option<Vec<Real>>) {
    let n = adjacency.face_count();
    let normals = geometry.normals();
    let centroids = geometry.centroids();
    let cos_alpha = match threshold {
        GrowthThreshold::Angle(alpha) => cos(alpha),
        GrowthThreshold::Curvature(_) => 0.0,
    };
    // The pairwise test between two faces with usable normals (symmetric in t and g: the dot
    // product, |a × b| and the centroid distance are the same both ways round).
    let pair_joins = |t: usize, g: usize| -> bool {
        let nt = &normals[t];
        match threshold {
            // γ < α ⇔ cos γ > cos α on [0, π]; unit normals make the dot product cos γ.
            GrowthThreshold::Angle(_) => nt.dot(&normals[g]) > cos_alpha,
            GrowthThreshold::Curvature(kappa) => {
                let l: Real = (centroids[g] - centroids[t]).norm();
                angle_between(nt, &normals[g]) < kappa * l
            }
        }
    };
    if geometry.degenerate_count() == 0 {
        // One closure per criterion, so that each is inlined in the pass.
        return match threshold {
            GrowthThreshold::Angle(_) if bends => {
                let mut bend = vec![0.0; n];
                let regions = components(adjacency, |t, g| {
                    let dot = normals[t].dot(&normals[g]);
                    let b = 0.5 * (1.0 - dot);
                    bend[t] = larger(bend[t], b);
                    bend[g] = larger(bend[g], b);
                    dot > cos_alpha
                });
                (regions, Some(bend))
            }
            GrowthThreshold::Angle(_) => (
                components(adjacency, |t, g| normals[t].dot(&normals[g]) > cos_alpha),
                None,
            ),
            GrowthThreshold::Curvature(_) => (components(adjacency, pair_joins), None),
        };
    }
    let mut region_of = vec![UNASSIGNED; n];
    // The face whose normal a face stands in with: itself, or for a degenerate face the one
    // it was reached from.
    let mut proxy: Vec<u32> = (0..n as u32).collect();
    let mut queue: Vec<u32> = Vec::with_capacity(64);
    let joins = |t: usize, g: usize, proxy: &[u32]| -> bool {
        if geometry.is_degenerate(g) {
            return true;
        }
        if geometry.is_degenerate(proxy[t] as usize) {
            // Only a region seeded on a degenerate face, all of whose faces are degenerate.
            return false;
        }
        pair_joins(proxy[t] as usize, g)
    };

    let mut count = 0u32;
    // Seeds with a usable normal first, so degenerate faces only seed all-degenerate regions
    // (a second round, needed only if there are degenerate faces).
    let rounds = if geometry.degenerate_count() == 0 {
        1
    } else {
        2
    };
    let seeds = (0..rounds).flat_map(|round| (0..n).map(move |f| (round, f)));
    for (round, seed) in seeds {
        if region_of[seed] != UNASSIGNED || geometry.is_degenerate(seed) != (round == 1) {
            continue;
        }
        region_of[seed] = count;
        queue.clear();
        queue.push(seed as u32);
        while let Some(t) = queue.pop() {
            let t = t as usize;
            for g in adjacency.neighbours_of(t) {
                if region_of[g] == UNASSIGNED && joins(t, g, &proxy) {
                    region_of[g] = count;
                    if geometry.is_degenerate(g) {
                        proxy[g] = proxy[t];
                    }
                    queue.push(g as u32);
                }
            }
        }
        count += 1;
    }
    let regions = Regions {
        region_of,
        count: count as usize,
    };
    (regions, None)
}

/// Regions when no face is degenerate: the test is then symmetric and each face stands for
/// itself, so the regions are the connected components of the "may join" graph whatever
/// the order of growing. They are found with a union–find in one sequential pass over the
/// faces (the smaller face id stays the root), and numbered in order of their smallest
/// face, as growing from seeds in index order numbers them.
/// `joins` is called once for every linked pair of faces, smaller face first.
fn components(adjacency: &FaceAdjacency, mut joins: impl FnMut(usize, usize) -> bool) -> Regions {
    let n = adjacency.face_count();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    let find = |parent: &mut [u32], mut x: u32| -> u32 {
        // Ends: a parent is never larger than its child, so x decreases.
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    };
    for f in 0..n {
        for g in adjacency.neighbours_of(f) {
            if g > f && joins(f, g) {
                let (rf, rg) = (find(&mut parent, f as u32), find(&mut parent, g as u32));
                let (lo, hi) = if rf < rg { (rf, rg) } else { (rg, rf) };
                parent[hi as usize] = lo;
            }
        }
    }
    for f in 0..n {
        parent[f] = find(&mut parent, f as u32);
    }
    // Now every face points at its root, its region's smallest face, which is numbered
    // (overwritten with its region id) before the region's other faces are met.
    let mut count = 0u32;
    for f in 0..n {
        let root = parent[f] as usize;
        parent[f] = if root == f {
            count += 1;
            count - 1
        } else {
            parent[root]
        };
    }
    Regions {
        region_of: parent,
        count: count as usize,
    }
}
