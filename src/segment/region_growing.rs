//! Step 1: region growing over edge-adjacent faces with a pairwise threshold.
//!
//! Source: Wang, Zhao, Tao 2019 (see `params.rs`), §2.1 and Fig. 2: a neighbour joins when,
//! against the adjacent face already in the region, `γ < α_th` (spraying) or
//! `γ / l < κ` (grinding, `l` the centroid distance, Eq. 5–6).
//! Input:  face adjacency and geometry; a validated [`GrowthThreshold`].
//! Output: a region id per face; every region is edge-connected.
//! Cost:   linear in faces: one sequential union–find pass over the links between faces
//!         with usable normals; only regions that reach a degenerate face are grown face by
//!         face (each face queued once, looking at three neighbours).
//! Deviations: the paper starts from a random face. The pairwise test is symmetric, so the
//! regions are the connected components of the "may join" graph and do not depend on the
//! seed; we take seeds in index order. A degenerate face (no usable normal) joins any region
//! that reaches it and stands in with the normal of the face it was reached from (no paper;
//! chosen so that zero-area slivers at T-junctions neither split nor bridge regions).

use super::GrowthThreshold;
use crate::math::{angle_between, cos, larger, Real};
use crate::mesh::{flatten, union_smallest, FaceAdjacency, FaceGeometry};

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

/// [`grow_regions`], and with `bends` each face's sharpest bend to a neighbour with a usable
/// normal, `max(0, max_g ½(1 − n_f·n_g))` (the [`SeedRule::Flattest`] key of
/// [`seed_order`](super::seed_order), bit for bit: the dot product is symmetric and the
/// maximum does not depend on the order; 0 for a degenerate face), from the union–find's
/// pass.
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
    let any_degenerate = geometry.degenerate_count() > 0;
    // Links between two faces with usable normals: the test is symmetric there, so their
    // "may join" components are found by a union–find (one closure per criterion, so that
    // each is inlined in the pass).
    let usable = |t: usize, g: usize| {
        !any_degenerate || !(geometry.is_degenerate(t) || geometry.is_degenerate(g))
    };
    let mut bend = if bends { vec![0.0; n] } else { Vec::new() };
    let mut parent = match threshold {
        GrowthThreshold::Angle(_) if bends => components(adjacency, |t, g| {
            if !usable(t, g) {
                return false;
            }
            let dot = normals[t].dot(&normals[g]);
            let b = 0.5 * (1.0 - dot);
            bend[t] = larger(bend[t], b);
            bend[g] = larger(bend[g], b);
            dot > cos_alpha
        }),
        GrowthThreshold::Angle(_) => components(adjacency, |t, g| {
            usable(t, g) && normals[t].dot(&normals[g]) > cos_alpha
        }),
        GrowthThreshold::Curvature(_) if bends => components(adjacency, |t, g| {
            if !usable(t, g) {
                return false;
            }
            let b = 0.5 * (1.0 - normals[t].dot(&normals[g]));
            bend[t] = larger(bend[t], b);
            bend[g] = larger(bend[g], b);
            pair_joins(t, g)
        }),
        GrowthThreshold::Curvature(_) => {
            components(adjacency, |t, g| usable(t, g) && pair_joins(t, g))
        }
    };
    let bend = bends.then_some(bend);
    if !any_degenerate {
        return (number_components(parent), bend);
    }
    // Degenerate faces make the growing depend on its order (a degenerate face stands in
    // with the normal of the face it was reached from), so regions that reach one are grown
    // face by face as the paper does; the others are their component. A component is
    // "touched" when one of its faces borders a degenerate face: only a search from a
    // touched component can cross a degenerate face, and it only ever reaches faces of
    // touched components (a face reached across a degenerate face borders it), so the
    // untouched components are exactly the regions the search would grow from them.
    let mut touched = vec![false; n];
    for f in 0..n {
        if geometry.is_degenerate(f) {
            for g in adjacency.neighbours_of(f) {
                if !geometry.is_degenerate(g) {
                    touched[parent[g] as usize] = true;
                }
            }
        }
    }
    let mut region_of = vec![UNASSIGNED; n];
    let mut search = Search {
        adjacency,
        geometry,
        proxy: Vec::new(),
        queue: Vec::new(),
    };
    let mut count = 0u32;
    // Seeds with a usable normal first, in index order: an untouched component gets its id
    // at its smallest face (its root, met before its other faces); a touched one is grown.
    for f in 0..n {
        if region_of[f] != UNASSIGNED || geometry.is_degenerate(f) {
            continue;
        }
        let root = parent[f] as usize;
        if touched[root] {
            search.grow(f, count, &mut region_of, &pair_joins);
            count += 1;
        } else {
            if root == f {
                region_of[f] = count;
                count += 1;
            }
            region_of[f] = region_of[root];
        }
    }
    drop((touched, std::mem::take(&mut parent)));
    // Then degenerate seeds: regions of degenerate faces only (a second round).
    for f in 0..n {
        if region_of[f] == UNASSIGNED {
            search.grow(f, count, &mut region_of, &pair_joins);
            count += 1;
        }
    }
    let regions = Regions {
        region_of,
        count: count as usize,
    };
    (regions, bend)
}

/// The paper's growing from one seed, for regions that reach a degenerate face.
struct Search<'a> {
    adjacency: &'a FaceAdjacency,
    geometry: &'a FaceGeometry,
    /// For each degenerate face reached, the face whose normal it stands in with (the one it
    /// was reached from, or its own proxy); allocated on first use.
    proxy: Vec<u32>,
    queue: Vec<u32>,
}

impl Search<'_> {
    /// The face whose normal `t` stands in with: itself, or for a degenerate face its proxy.
    #[inline]
    fn proxy_of(&self, t: usize) -> usize {
        if self.geometry.is_degenerate(t) {
            self.proxy[t] as usize
        } else {
            t
        }
    }

    /// Grows region `id` from `seed` over the unassigned faces: depth first, a neighbour
    /// joins when it is degenerate or passes `pair_joins` against the proxy of the face it is
    /// reached from (never from an all-degenerate region's faces).
    fn grow(
        &mut self,
        seed: usize,
        id: u32,
        region_of: &mut [u32],
        pair_joins: &impl Fn(usize, usize) -> bool,
    ) {
        let geometry = self.geometry;
        if self.proxy.is_empty() {
            self.proxy = (0..region_of.len() as u32).collect();
        }
        region_of[seed] = id;
        self.queue.clear();
        self.queue.push(seed as u32);
        // Ends: a face is pushed only when it is assigned, which happens once.
        while let Some(t) = self.queue.pop() {
            let t = t as usize;
            let from = self.proxy_of(t);
            for g in self.adjacency.neighbours_of(t) {
                if region_of[g] != UNASSIGNED {
                    continue;
                }
                let joins = if geometry.is_degenerate(g) {
                    true
                } else if geometry.is_degenerate(from) {
                    // Only a region seeded on a degenerate face, all of whose faces are
                    // degenerate.
                    false
                } else {
                    pair_joins(from, g)
                };
                if joins {
                    region_of[g] = id;
                    if geometry.is_degenerate(g) {
                        self.proxy[g] = from as u32;
                    }
                    self.queue.push(g as u32);
                }
            }
        }
    }
}

/// The union–find over the links for which `joins` holds (called once for every linked pair
/// of faces, smaller face first), in one sequential pass over the faces (the smaller face id
/// stays the root): the root, its component's smallest face, of every face.
fn components(adjacency: &FaceAdjacency, mut joins: impl FnMut(usize, usize) -> bool) -> Vec<u32> {
    let n = adjacency.face_count();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    for f in 0..n {
        for g in adjacency.neighbours_of(f) {
            if g > f && joins(f, g) {
                union_smallest(&mut parent, f as u32, g as u32);
            }
        }
    }
    flatten(&mut parent);
    parent
}

/// Regions when no face is degenerate: the test is then symmetric and each face stands for
/// itself, so the regions are the connected components of the "may join" graph whatever
/// the order of growing, numbered in order of their smallest face, as growing from seeds
/// in index order numbers them. `root` is [`components`]' result.
fn number_components(mut root: Vec<u32>) -> Regions {
    // Every face points at its root, its region's smallest face, which is numbered
    // (overwritten with its region id) before the region's other faces are met.
    let mut count = 0u32;
    for f in 0..root.len() {
        let r = root[f] as usize;
        root[f] = if r == f {
            count += 1;
            count - 1
        } else {
            root[r]
        };
    }
    Regions {
        region_of: root,
        count: count as usize,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point3;
    use crate::mesh::TriMesh;
    use crate::segment::{seed_order, SeedRule};

    /// The paper's growing from every seed in index order (usable normals first): what the
    /// union–find shortcut must reproduce.
    fn grow_by_search(
        adjacency: &FaceAdjacency,
        geometry: &FaceGeometry,
        threshold: GrowthThreshold,
    ) -> Regions {
        let normals = geometry.normals();
        let centroids = geometry.centroids();
        let pair_joins = |t: usize, g: usize| match threshold {
            GrowthThreshold::Angle(alpha) => normals[t].dot(&normals[g]) > cos(alpha),
            GrowthThreshold::Curvature(kappa) => {
                angle_between(&normals[t], &normals[g])
                    < kappa * (centroids[g] - centroids[t]).norm()
            }
        };
        let n = adjacency.face_count();
        let mut region_of = vec![UNASSIGNED; n];
        let mut search = Search {
            adjacency,
            geometry,
            proxy: Vec::new(),
            queue: Vec::new(),
        };
        let mut count = 0;
        for round in [false, true] {
            for f in 0..n {
                if region_of[f] == UNASSIGNED && geometry.is_degenerate(f) == round {
                    search.grow(f, count, &mut region_of, &pair_joins);
                    count += 1;
                }
            }
        }
        Regions {
            region_of,
            count: count as usize,
        }
    }

    /// A bumpy n × n grid (seeded heights) in which some vertices are moved onto a
    /// neighbour, so that the faces holding both are degenerate but still linked.
    fn bumpy_grid_with_collapsed_faces(n: usize, seed: u64) -> TriMesh {
        let mut state = seed;
        let mut random = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let v = |i: usize, j: usize| (i * (n + 1) + j) as u32;
        let mut positions: Vec<Point3> = (0..=n)
            .flat_map(|i| (0..=n).map(move |j| (i, j)))
            .map(|(i, j)| Point3::new(j as f64, i as f64, 0.0))
            .collect();
        for p in &mut positions {
            p.z = 0.6 * random();
        }
        for i in 0..n {
            for j in 0..n {
                if random() < 0.08 {
                    positions[v(i, j) as usize] = positions[v(i, j + 1) as usize];
                }
            }
        }
        let triangles = (0..n)
            .flat_map(|i| {
                (0..n).flat_map(move |j| {
                    [
                        [v(i, j), v(i, j + 1), v(i + 1, j + 1)],
                        [v(i, j), v(i + 1, j + 1), v(i + 1, j)],
                    ]
                })
            })
            .collect();
        TriMesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn the_union_find_shortcut_grows_the_regions_of_the_search() {
        for seed in 1..=6 {
            let mesh = bumpy_grid_with_collapsed_faces(24, seed);
            let adjacency = FaceAdjacency::new(&mesh);
            let geometry = FaceGeometry::new(&mesh);
            assert!(geometry.degenerate_count() > 20, "the case itself");
            for threshold in [
                GrowthThreshold::Angle(0.2),
                GrowthThreshold::Angle(0.5),
                GrowthThreshold::Curvature(0.4),
            ] {
                let expected = grow_by_search(&adjacency, &geometry, threshold);
                assert!(expected.count > 3, "the case itself: {threshold:?}");
                let (regions, bend) =
                    grow_regions_and_bends(&adjacency, &geometry, threshold, true);
                assert_eq!(regions, expected, "seed {seed}, {threshold:?}");
                let bend = bend.expect("asked for");
                assert_eq!(
                    crate::segment::planarise::flattest_order(&geometry, &bend),
                    seed_order(&adjacency, &geometry, SeedRule::Flattest)
                );
            }
        }
    }
}
