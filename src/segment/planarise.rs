//! Step 2: approximate planarisation of each region into patches around a mean normal.
//!
//! Source: Wang, Zhao, Tao 2019, §2.2, steps 1)–5): grow a patch inside a region, comparing
//! each candidate face's normal with the patch's area-weighted mean normal
//! `n_avg = Σ Aᵢ nᵢ / Σ Aᵢ` (Eq. 12); join when the angle is below `θmax`; update `n_avg`
//! as faces join; repeat until every face of the region is in a patch.
//! Input:  adjacency, geometry, step-1 regions, `θmax`, a seed order.
//! Output: a patch id per face; each patch is edge-connected, lies in one region, and every
//!         face normal in it is strictly within `θmax` of the patch's final mean normal.
//! Cost:   linear in faces in practice (see the repair bound below).
//! Deviations:
//! - Candidates refused against the running mean are retried against the mean the patch
//!   ends with (the paper's "until no boundary neighbour qualifies"), at most
//!   [`RETRY_ROUNDS`] times.
//! - Repair (no paper): comparing with the running mean alone does not bound the deviation
//!   from the final mean, which drifts as a patch wraps around a fuselage. After growing,
//!   faces at or beyond `θmax` from the final mean are released (incrementally, re-checking
//!   only faces near the limit), the largest-area connected remainder is kept, and this
//!   repeats ([`REPAIR_ROUNDS`] at most). When the mean has settled and a search within a
//!   few links of the released faces shows the rest still connected, that search stands in
//!   for the one over the whole patch (the result is the same). If it has not settled
//!   by then, the patch keeps only the connected faces within `θmax / 2` of its mean around
//!   the best-aligned face: normals inside a cap of radius `θmax/2` have their mean inside
//!   the cap, so each is within `θmax` of it. Released faces seed the next patches.
//! - θmax above `π − MIN_ANGLE_RAD` is tested as `π − MIN_ANGLE_RAD` (no paper): closer to
//!   π, cosines cannot resolve the angle, and a face almost opposite a patch's mean (a
//!   nearly closed patch, whose mean is short) could pass the test yet be reported at π.
//! - Seeds follow [`SeedRule`] instead of the paper's "any boundary face"; the order is a
//!   counting sort over 4096 bins of the rule's key, ties by face index (linear, deterministic).

use super::{Regions, SeedRule, MIN_ANGLE_RAD};
use crate::math::{angle_between, cos, larger, Real, Vector3};
use crate::mesh::{FaceAdjacency, FaceGeometry};
use rustc_hash::{FxHashMap, FxHashSet};
use std::f64::consts::PI;

/// How often refused candidates are retried against the updated mean.
pub const RETRY_ROUNDS: usize = 16;
/// How far from the trimmed faces (in links between faces) the check that a trimmed patch
/// is still connected looks (no paper: enough to go round a vertex of valence 8).
const NEAR_LINKS: usize = 4;
/// How often a grown patch is trimmed to its final mean before the cap fallback.
pub const REPAIR_ROUNDS: usize = 8;
/// Width of the band below θmax that the incremental trim watches (no paper; a tenth of a
/// typical θmax keeps the list short and the mean rarely drifts that far in one round).
pub const TRIM_MARGIN_RAD: Real = 0.05;
const SEED_BINS: usize = 4096;
/// Marks a face in no patch yet: `patch_of` holds `FREE | region` for it, so one load tells
/// "free and in this region" (patch and region ids are below 2³⁰: at most one per face, and
/// at most `MAX_FACES` < 2³⁰ faces).
const FREE: u32 = 1 << 31;
/// Marks, for the duration of one `grow` or `keep_largest_part`, a face already looked at:
/// refused (a free face) or reached (a member). Set and cleared in the entry itself, so the
/// test that skips such a face is the same load as the patch test.
const MARK: u32 = 1 << 30;

/// Whether a `patch_of` entry marks a face in no patch yet.
#[inline]
fn is_free(entry: u32) -> bool {
    entry & FREE != 0
}

/// Step-2 patches: `patch_of[f]` for every face, ids `0..count` in order of creation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Patches {
    /// Patch id of every face.
    pub patch_of: Vec<u32>,
    /// Number of patches.
    pub count: usize,
}

/// The order in which faces are tried as seeds under `rule` (a permutation of all faces).
pub fn seed_order(adjacency: &FaceAdjacency, geometry: &FaceGeometry, rule: SeedRule) -> Vec<u32> {
    let n = geometry.face_count();
    let normals = geometry.normals();
    // Key in [0, 1]: 0 is tried first.
    match rule {
        SeedRule::LowestIndex => (0..n as u32).collect(),
        SeedRule::Flattest => order_by_key(geometry, |f| {
            // (1 − cos) of the sharpest bend to a neighbour, halved into [0, 1].
            adjacency
                .neighbours_of(f)
                .filter(|&g| !geometry.is_degenerate(g))
                .map(|g| 0.5 * (1.0 - normals[f].dot(&normals[g])))
                // Keys of unit normals are never NaN, and the only zero is 0.5 · (+0).
                .fold(0.0, larger)
        }),
        SeedRule::LargestArea => {
            let areas = geometry.areas();
            let largest = areas.iter().copied().fold(0.0, Real::max);
            order_by_key(geometry, |f| {
                if largest > 0.0 {
                    1.0 - areas[f] / largest
                } else {
                    0.0
                }
            })
        }
    }
}

/// The [`SeedRule::Flattest`] order from each face's sharpest bend, as
/// [`grow_regions_and_bends`](super::region_growing::grow_regions_and_bends) gives it.
pub(crate) fn flattest_order(geometry: &FaceGeometry, bend: &[Real]) -> Vec<u32> {
    order_by_key(geometry, |f| bend[f])
}

/// Faces in increasing order of `key` binned into [`SEED_BINS`] − 1 bins, degenerate faces
/// last, ties by face index (a counting sort).
fn order_by_key(geometry: &FaceGeometry, key: impl Fn(usize) -> Real) -> Vec<u32> {
    let n = geometry.face_count();
    let mut start = vec![0u32; SEED_BINS + 1];
    let bins: Vec<u16> = (0..n)
        .map(|f| {
            let b = if geometry.is_degenerate(f) {
                SEED_BINS - 1
            } else {
                ((key(f).clamp(0.0, 1.0) * (SEED_BINS - 2) as Real) as usize).min(SEED_BINS - 2)
            };
            start[b + 1] += 1;
            b as u16
        })
        .collect();
    for b in 0..SEED_BINS {
        start[b + 1] += start[b];
    }
    let mut order = vec![0u32; n];
    for (f, &b) in bins.iter().enumerate() {
        order[start[b as usize] as usize] = f as u32;
        start[b as usize] += 1;
    }
    order
}

/// Breadth-first search from `start` with `queue` as scratch: `visit(face, queue)` is called
/// for every face taken from the queue, pushes the faces to go on with (each once: ending
/// is up to it) and returns false to stop there. Whether it ran to the end.
fn breadth_first(
    start: u32,
    queue: &mut Vec<u32>,
    mut visit: impl FnMut(u32, &mut Vec<u32>) -> bool,
) -> bool {
    queue.clear();
    queue.push(start);
    let mut head = 0;
    while head < queue.len() {
        let f = queue[head];
        head += 1;
        if !visit(f, queue) {
            return false;
        }
    }
    true
}

/// Scratch space and read-only inputs shared by the patches of one planarisation.
struct Grower<'a> {
    adjacency: &'a FaceAdjacency,
    geometry: &'a FaceGeometry,
    region_of: &'a [u32],
    cos_theta: Real,
    /// cos(θmax − margin): members beyond it are near the limit.
    near_cos: Real,
    cap_cos: Real,
    /// θmax ≥ [`MIN_ANGLE_RAD`]: the numerical tests can keep the θmax promise.
    guaranteed: bool,
    /// Patch of every face, or `FREE | region` while it has none.
    patch_of: Vec<u32>,
    members: Vec<u32>,
    refused: Vec<u32>,
    released: Vec<u32>,
}

impl Grower<'_> {
    fn weighted(&self, f: usize) -> Vector3 {
        self.geometry.normals()[f] * self.geometry.areas()[f]
    }

    /// Strictly within θmax of the mean `sum / len` (degenerate faces always are).
    #[inline]
    fn fits(&self, f: usize, sum: &Vector3, len: Real) -> bool {
        let n = &self.geometry.normals()[f];
        *n == Vector3::zeros() || len == 0.0 || n.dot(sum) > self.cos_theta * len
    }

    fn sum_of_members(&self) -> Vector3 {
        self.members
            .iter()
            .fold(Vector3::zeros(), |s, &f| s + self.weighted(f as usize))
    }

    /// Grows patch `p` from `seed` against the running mean, with retries; returns the sum
    /// of the members' weighted normals, bit for bit [`Grower::sum_of_members`].
    fn grow(&mut self, seed: usize, p: u32) -> Vector3 {
        // The entry of a free face of this region.
        let free = FREE | self.region_of[seed];
        self.members.clear();
        self.refused.clear();
        self.members.push(seed as u32);
        self.patch_of[seed] = p;
        // Summed from zero in member order, as `sum_of_members` does (which only matters
        // for the sign of zero components).
        let mut sum = Vector3::zeros() + self.weighted(seed);
        // |sum|, recomputed only when sum changes.
        let mut len = sum.norm();
        let mut head = 0;
        for _ in 0..=RETRY_ROUNDS {
            // Step 3): look at the neighbours of the patch's faces.
            while head < self.members.len() {
                let t = self.members[head] as usize;
                head += 1;
                for g in self.adjacency.neighbours_of(t) {
                    // A face refused before carries MARK and is skipped.
                    if self.patch_of[g] != free {
                        continue;
                    }
                    if self.fits(g, &sum, len) {
                        self.patch_of[g] = p;
                        sum += self.weighted(g);
                        len = sum.norm();
                        self.members.push(g as u32);
                    } else {
                        self.patch_of[g] = free | MARK;
                        self.refused.push(g as u32);
                    }
                }
            }
            // Step 4): retry the refused ones against the mean as it is now.
            let before = self.members.len();
            let refused = std::mem::take(&mut self.refused);
            for &g in &refused {
                let g = g as usize;
                if self.patch_of[g] == free | MARK && self.fits(g, &sum, len) {
                    self.patch_of[g] = p;
                    sum += self.weighted(g);
                    len = sum.norm();
                    self.members.push(g as u32);
                } else if self.patch_of[g] == free | MARK {
                    self.refused.push(g as u32);
                }
            }
            if self.members.len() == before {
                break;
            }
        }
        // The faces still refused are all the marked ones.
        for &g in &self.refused {
            self.patch_of[g as usize] = free;
        }
        sum
    }

    fn release(&mut self, f: u32) {
        self.patch_of[f as usize] = FREE | self.region_of[f as usize];
        self.released.push(f);
    }

    /// Keeps the largest-area edge-connected part of the members still in patch `p` and
    /// releases the rest; returns whether any face was released here.
    fn keep_largest_part(&mut self, p: u32) -> bool {
        let mut members = std::mem::take(&mut self.members);
        members.retain(|&f| self.patch_of[f as usize] == p);
        let mut best: (Real, usize, usize) = (-1.0, 0, 0);
        let mut order: Vec<u32> = Vec::with_capacity(members.len());
        // A member reached by the search below carries MARK until the end.
        for &f in &members {
            if self.patch_of[f as usize] != p {
                continue;
            }
            let start = order.len();
            self.patch_of[f as usize] = p | MARK;
            order.push(f);
            let mut head = start;
            let mut area = 0.0;
            while head < order.len() {
                let t = order[head] as usize;
                head += 1;
                area += self.geometry.areas()[t];
                for g in self.adjacency.neighbours_of(t) {
                    if self.patch_of[g] == p {
                        self.patch_of[g] = p | MARK;
                        order.push(g as u32);
                    }
                }
            }
            if area > best.0 {
                best = (area, start, order.len());
            }
        }
        let dropped = order.len() - (best.2 - best.1);
        for i in (0..best.1).chain(best.2..order.len()) {
            self.release(order[i]);
        }
        order.truncate(best.2);
        order.drain(..best.1);
        for &f in &order {
            self.patch_of[f as usize] = p;
        }
        self.members = order;
        dropped > 0
    }

    /// Whether the members of patch `p` are still edge-connected after the faces
    /// `released[from..]` (`T`) were released from it, as far as a search near them can
    /// tell; the patch must have been connected before. `true` is certain, `false` may not be.
    ///
    /// Why it suffices: a path between two members that crosses a connected group `C` of
    /// `T` enters and leaves it from members touching `C`. If, for every such group, the
    /// members touching it are connected among the members within [`NEAR_LINKS`] links of
    /// `T`, every crossing can be rerouted, so the members are connected. Cost: linear in
    /// `|T|` (every face looked at is within a few links of a face of `T`), not in the patch.
    fn stays_connected(&self, p: u32, from: usize) -> bool {
        const UNSET: u32 = u32::MAX;
        let (adjacency, patch_of) = (self.adjacency, &self.patch_of);
        let released = &self.released[from..];
        let trimmed: FxHashSet<u32> = released.iter().copied().collect();
        // Members within NEAR_LINKS links of T, each with the piece of the search below it
        // falls in; those one link away touch T.
        let mut piece: FxHashMap<u32, u32> = FxHashMap::default();
        let mut touching: Vec<u32> = Vec::new();
        let mut level: Vec<u32> = released.to_vec();
        for links in 1..=NEAR_LINKS {
            let mut next = Vec::new();
            for &f in &level {
                for g in adjacency.neighbours_of(f as usize) {
                    if patch_of[g] == p && !piece.contains_key(&(g as u32)) {
                        piece.insert(g as u32, UNSET);
                        next.push(g as u32);
                    }
                }
            }
            if links == 1 {
                touching.clone_from(&next);
            }
            level = next;
        }
        // Pieces: connected parts of those members, found from the ones touching T.
        let mut queue: Vec<u32> = Vec::new();
        let mut pieces = 0;
        for &start in &touching {
            if piece[&start] != UNSET {
                continue;
            }
            piece.insert(start, pieces);
            // A face enters the queue when its piece is set, once.
            breadth_first(start, &mut queue, |g, queue| {
                for h in adjacency.neighbours_of(g as usize) {
                    if let Some(id) = piece.get_mut(&(h as u32)) {
                        if *id == UNSET {
                            *id = pieces;
                            queue.push(h as u32);
                        }
                    }
                }
                true
            });
            pieces += 1;
        }
        if pieces <= 1 {
            return true;
        }
        // Every connected group of T must touch one piece only.
        let mut done: FxHashSet<u32> = FxHashSet::default();
        for &t in released {
            if !done.insert(t) {
                continue;
            }
            let mut group_piece = UNSET;
            // A face enters the queue once (`done`).
            let one_piece = breadth_first(t, &mut queue, |c, queue| {
                for h in adjacency.neighbours_of(c as usize) {
                    let h = h as u32;
                    if trimmed.contains(&h) {
                        if done.insert(h) {
                            queue.push(h);
                        }
                    } else if patch_of[h as usize] == p {
                        let id = piece[&h];
                        if group_piece == UNSET {
                            group_piece = id;
                        } else if group_piece != id {
                            return false;
                        }
                    }
                }
                true
            });
            if !one_piece {
                return false;
            }
        }
        true
    }

    /// Makes every member strictly within θmax of the patch's final mean normal.
    ///
    /// Each round sums the members once and lists those within [`TRIM_MARGIN_RAD`] of the
    /// limit; while the mean moves less than the margin only they can fall outside, so
    /// trimming re-checks just that list. Then the largest connected part is kept.
    /// `grown_sum` is the members' sum as `grow` left them.
    fn repair(&mut self, p: u32, grown_sum: Vector3) {
        debug_assert_eq!(
            grown_sum.map(Real::to_bits),
            self.sum_of_members().map(Real::to_bits)
        );
        let mut known_sum = Some(grown_sum);
        for _ in 0..REPAIR_ROUNDS {
            let mut sum = known_sum.take().unwrap_or_else(|| self.sum_of_members());
            let anchor = sum;
            let anchor_len = anchor.norm();
            let mut near: Vec<u32> = self
                .members
                .iter()
                .copied()
                .filter(|&f| {
                    let n = &self.geometry.normals()[f as usize];
                    *n != Vector3::zeros() && n.dot(&anchor) <= self.near_cos * anchor_len
                })
                .collect();
            let mut trimmed = false;
            let mut drifted = false;
            let released_before = self.released.len();
            loop {
                // Every face of the list is judged against the same mean, then the mean moves.
                let len = sum.norm();
                let before = near.len();
                let mut removed = Vector3::zeros();
                let mut kept = Vec::with_capacity(near.len());
                for &f in &near {
                    if self.fits(f as usize, &sum, len) {
                        kept.push(f);
                    } else {
                        removed += self.weighted(f as usize);
                        self.release(f);
                    }
                }
                if kept.len() == before {
                    break;
                }
                sum -= removed;
                near = kept;
                trimmed = true;
                // The members off the list are safe only while the mean stays within the margin.
                if angle_between(&anchor, &sum) >= TRIM_MARGIN_RAD {
                    drifted = true;
                    break;
                }
            }
            if !trimmed {
                return;
            }
            // With the mean settled, the members' order no longer matters (it only orders
            // the next round's sum): when a search near the trimmed faces shows the rest
            // still connected, the search over the whole patch is not needed.
            if !drifted && self.stays_connected(p, released_before) {
                let patch_of = &self.patch_of;
                self.members.retain(|&f| patch_of[f as usize] == p);
                return;
            }
            let split = self.keep_largest_part(p);
            if !split && !drifted {
                return;
            }
        }
        let sum = self.sum_of_members();
        let len = sum.norm();
        if self
            .members
            .iter()
            .all(|&f| self.fits(f as usize, &sum, len))
        {
            return;
        }
        // Cap fallback: keep faces within θmax/2 of the axis, around the best-aligned face.
        let axis = sum.try_normalize(0.0).unwrap_or_else(Vector3::z);
        let normals = self.geometry.normals();
        let best = self
            .members
            .iter()
            .copied()
            .max_by(|&a, &b| {
                let (da, db) = (
                    normals[a as usize].dot(&axis),
                    normals[b as usize].dot(&axis),
                );
                da.total_cmp(&db).then(b.cmp(&a))
            })
            .expect("a patch always has a member");
        let best_fits = normals[best as usize].dot(&axis) > self.cap_cos;
        for f in std::mem::take(&mut self.members) {
            let n = &normals[f as usize];
            let inside = if best_fits {
                *n == Vector3::zeros() || n.dot(&axis) > self.cap_cos
            } else {
                f == best
            };
            if inside {
                self.members.push(f);
            } else {
                self.release(f);
            }
        }
        self.keep_largest_part(p);
        debug_assert!(
            !self.guaranteed || {
                let sum = self.sum_of_members();
                let len = sum.norm();
                self.members
                    .iter()
                    .all(|&f| self.fits(f as usize, &sum, len))
            }
        );
    }
}

/// Planarises every region (step 2), trying seeds in `seed_order`.
///
/// The θmax promise needs `theta_max_rad` in `[MIN_ANGLE_RAD, π]` ([`SegmentParams::validate`]
/// checks it); any other value, NaN included, still ends, in at most one patch per face.
///
/// [`SegmentParams::validate`]: super::SegmentParams::validate
pub fn planarise(
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    regions: &Regions,
    theta_max_rad: Real,
    seed_order: &[u32],
    progress: &mut dyn FnMut(&str, f64),
) -> Patches {
    let n = geometry.face_count();
    let mut grower = Grower {
        adjacency,
        geometry,
        region_of: &regions.region_of,
        // Within MIN_ANGLE_RAD of π the cosine test cannot tell a face from its antipode
        // either: cap θmax there, so a face it accepts is reported below θmax too.
        cos_theta: cos(theta_max_rad.min(PI - MIN_ANGLE_RAD)),
        near_cos: cos((theta_max_rad - TRIM_MARGIN_RAD).max(0.0)),
        cap_cos: cos(0.5 * theta_max_rad),
        guaranteed: theta_max_rad >= MIN_ANGLE_RAD,
        patch_of: regions.region_of.iter().map(|&r| FREE | r).collect(),
        members: Vec::new(),
        refused: Vec::new(),
        released: Vec::new(),
    };
    // Termination: every pass of the loop below ends with at least one face in the new
    // patch, and faces of finished patches are never released again (grow takes only
    // unassigned faces, repair releases only members of the patch being built), so there
    // are at most n passes. Inside a pass, the seed search pops `released` (each entry
    // pushed by one release of a member, at most n per pass) or advances `next`; `grow`
    // and `repair` have bounded rounds whose inner loops each consume a finite list.
    let mut count = 0u32;
    let mut next = 0usize;
    let mut assigned = 0usize;
    let report_every = (n / 64).max(1);
    let mut next_report = 0;
    loop {
        // Faces released by the last repair seed first: they lie next to the patch just made.
        let seed = loop {
            if let Some(f) = grower.released.pop() {
                if is_free(grower.patch_of[f as usize]) {
                    break Some(f as usize);
                }
            } else if next < seed_order.len() {
                let f = seed_order[next] as usize;
                next += 1;
                if is_free(grower.patch_of[f]) {
                    break Some(f);
                }
            } else {
                break None;
            }
        };
        let Some(seed) = seed else { break };
        let sum = grower.grow(seed, count);
        grower.repair(count, sum);
        if grower.members.is_empty() {
            // Repair released every face (possible when the mean of what grew fits none of
            // them): the seed alone is a patch, within θmax of its own normal for any
            // θmax ≥ MIN_ANGLE_RAD. Without this the seed would come back forever.
            grower.patch_of[seed] = count;
            grower.members.push(seed as u32);
        }
        assigned += grower.members.len();
        count += 1;
        if assigned >= next_report {
            progress("planarise", assigned as f64 / n as f64);
            next_report = assigned + report_every;
        }
    }
    debug_assert!(grower.patch_of.iter().all(|&p| !is_free(p)));
    debug_assert!(count as usize <= n);
    Patches {
        patch_of: grower.patch_of,
        count: count as usize,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point3;
    use crate::mesh::TriMesh;

    /// A flat n × n grid of squares, two triangles each (faces 2(i·n + j) and +1 in square
    /// (i, j)).
    fn grid(n: usize) -> TriMesh {
        let v = |i: usize, j: usize| (i * (n + 1) + j) as u32;
        let positions = (0..=n)
            .flat_map(|i| (0..=n).map(move |j| Point3::new(j as Real, i as Real, 0.0)))
            .collect();
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

    /// Whether the faces still in patch 0 are edge-connected (a search over all of them).
    fn connected(adjacency: &FaceAdjacency, patch_of: &[u32]) -> bool {
        let members: Vec<usize> = (0..patch_of.len()).filter(|&f| patch_of[f] == 0).collect();
        let Some(&start) = members.first() else {
            return true;
        };
        let mut seen = vec![false; patch_of.len()];
        seen[start] = true;
        let mut queue = vec![start];
        while let Some(f) = queue.pop() {
            for g in adjacency.neighbours_of(f) {
                if patch_of[g] == 0 && !seen[g] {
                    seen[g] = true;
                    queue.push(g);
                }
            }
        }
        members.iter().all(|&f| seen[f])
    }

    #[test]
    fn the_local_connectivity_check_is_never_wrong_when_it_says_connected() {
        let n = 12;
        let mesh = grid(n);
        let adjacency = FaceAdjacency::new(&mesh);
        let geometry = FaceGeometry::new(&mesh);
        let region_of = vec![0; mesh.triangle_count()];
        let square = |i: usize, j: usize| [2 * (i * n + j) as u32, 2 * (i * n + j) as u32 + 1];
        let cases: Vec<(&str, Vec<u32>, bool)> = vec![
            // (what, released faces, whether the check must find them harmless)
            (
                "a border column",
                (0..n).flat_map(|i| square(i, 0)).collect(),
                true,
            ),
            (
                "scattered faces",
                vec![square(3, 3)[0], square(7, 5)[1], square(9, 9)[0]],
                true,
            ),
            (
                "a column across",
                (0..n).flat_map(|i| square(i, 5)).collect(),
                false,
            ),
            (
                "a ring round an island",
                (3..9)
                    .flat_map(|i| (3..9).map(move |j| (i, j)))
                    .filter(|&(i, j)| i == 3 || i == 8 || j == 3 || j == 8)
                    .flat_map(|(i, j)| square(i, j))
                    .collect(),
                false,
            ),
            (
                "two borders at once",
                (0..n)
                    .flat_map(|i| [square(i, 0), square(i, n - 1)])
                    .flatten()
                    .collect(),
                true,
            ),
        ];
        for (what, released, harmless) in cases {
            let mut grower = Grower {
                adjacency: &adjacency,
                geometry: &geometry,
                region_of: &region_of,
                cos_theta: 0.0,
                near_cos: 0.0,
                cap_cos: 0.0,
                guaranteed: true,
                patch_of: vec![0; mesh.triangle_count()],
                members: (0..mesh.triangle_count() as u32).collect(),
                refused: Vec::new(),
                released: Vec::new(),
            };
            for &f in &released {
                grower.release(f);
            }
            let answer = grower.stays_connected(0, 0);
            let truth = connected(&adjacency, &grower.patch_of);
            assert_eq!(truth, harmless, "{what}: the test case itself");
            assert_eq!(answer, harmless, "{what}");
        }
    }
}
