//! Welding: merging bit-identical corner positions of a triangle soup into shared vertices.
//!
//! No paper. Vertices are numbered in order of first appearance, in two steps:
//! 1. While triangles arrive, a direct-mapped cache of recently seen corners (1 MiB, the L2
//!    cache of current desktop cores) catches the neighbours STL files list close together;
//!    a corner it misses gets a provisional vertex at once (appended, nothing looked up). A corner first seen is
//!    always a miss, so provisional ids are in order of first appearance; a corner evicted
//!    from the cache and seen again gets a duplicate.
//! 2. `finish` finds the duplicates cache-locally: the provisional vertices are partitioned
//!    by hash into buckets of a few thousand (one counting-sort pass), and each bucket is
//!    welded with a small linear-probing table that stays in L1/L2. A duplicate maps to its
//!    earliest copy; the survivors keep their relative order, so the numbering is the same
//!    as a single global table would give. With no duplicate (the common case for files
//!    written surface by surface) nothing is renumbered.
//!
//! This replaces one random access into a table of 32 bytes a vertex per new vertex (the
//! cost of welding large files) with sequential passes.
//! `-0.0` and `+0.0` count as the same coordinate.
//! Cost: expected O(1) per corner; scratch of 12 bytes a provisional vertex, 20 more during
//! `finish`, dropped by it.

use crate::math::Point3;

/// Builds a [`TriMesh`](super::TriMesh)'s arrays from triangles given by corner coordinates.
#[derive(Debug)]
pub struct Welder {
    /// Canonical bit patterns of the provisional vertices, in order of creation.
    bits: Vec<[u32; 3]>,
    /// Triangles as provisional vertex ids.
    triangles: Vec<[u32; 3]>,
    /// Direct-mapped cache of recently seen corners (1 MiB).
    recent: Vec<Slot>,
}

/// A cached corner: its canonical bit pattern and provisional id ([`EMPTY_ID`] when unused).
#[derive(Debug, Clone, Copy)]
struct Slot {
    bits: [u32; 3],
    id: u32,
}

const EMPTY_ID: u32 = u32::MAX;
const EMPTY: Slot = Slot {
    bits: [0; 3],
    id: EMPTY_ID,
};
/// Slots of the cache: 1 MiB of them. Against 256 KiB, duplicates (corners evicted before
/// they came again) fall from 22 % to 6 % of the vertices on the bench's 4M-triangle
/// fuselage, whose rings are long, and `finish` takes about a third less; at 1M (12 % to
/// 3 %) the time is about even.
const RECENT_SLOTS: usize = 1 << 16;
/// The bit pattern of `-0.0_f32`.
const NEGATIVE_ZERO: u32 = 0x8000_0000;
/// Provisional vertices per bucket in `finish`, on average (a bucket and its table stay in
/// L2; no paper).
const BUCKET_TARGET: usize = 4096;

/// The bit pattern of a finite corner, with `-0.0` folded into `+0.0`.
#[inline]
fn canonical_bits(p: &[f32; 3]) -> [u32; 3] {
    p.map(|c| (c + 0.0).to_bits())
}

/// A hash of the packed bit patterns whose high bits are well mixed (the low bits are not:
/// the callers take the top ones). Three independent multiplications by odd constants, so
/// the three corners of a triangle hash in parallel; coordinates with zero low mantissa
/// bits (integer grids) still spread, as the products' high bits depend on every bit.
#[inline]
fn hash_bits(bits: &[u32; 3]) -> u64 {
    let [x, y, z] = bits.map(u64::from);
    x.wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ y.wrapping_mul(0xc2b2_ae3d_27d4_eb4f)
        ^ z.wrapping_mul(0x1656_67b1_9e37_79f9)
}

/// The cache slot of a corner: the hash's top bits.
#[inline]
fn recent_slot(bits: &[u32; 3]) -> usize {
    (hash_bits(bits) >> (64 - RECENT_SLOTS.trailing_zeros())) as usize
}

impl Welder {
    /// A welder sized for about `triangles` triangles (only a hint: it grows as needed).
    pub fn with_capacity(triangles: usize) -> Self {
        // Closed meshes have about half as many vertices as triangles.
        Welder {
            bits: Vec::with_capacity(triangles / 2 + 16),
            triangles: Vec::with_capacity(triangles),
            recent: vec![EMPTY; RECENT_SLOTS],
        }
    }

    /// Adds a triangle whose corners must be finite; returns its face id.
    pub fn add_triangle(&mut self, corners: &[[f32; 3]; 3]) -> usize {
        debug_assert!(corners.iter().flatten().all(|c| c.is_finite()));
        let ids = corners.map(|c| self.vertex_id(canonical_bits(&c)));
        self.triangles.push(ids);
        self.triangles.len() - 1
    }

    /// [`Welder::add_triangle`] for corners given as the bit patterns of finite `f32`s.
    #[inline]
    pub(crate) fn add_triangle_bits(&mut self, corners: &[[u32; 3]; 3]) {
        debug_assert!(corners
            .iter()
            .flatten()
            .all(|&b| f32::from_bits(b).is_finite()));
        // `(c + 0.0)` only changes −0.0 (into +0.0): the same canonical patterns.
        let ids =
            corners.map(|c| self.vertex_id(c.map(|b| if b == NEGATIVE_ZERO { 0 } else { b })));
        self.triangles.push(ids);
    }

    #[inline]
    fn vertex_id(&mut self, bits: [u32; 3]) -> u32 {
        let slot = &mut self.recent[recent_slot(&bits)];
        if slot.id != EMPTY_ID && slot.bits == bits {
            return slot.id;
        }
        // At most three ids a triangle: below 2^32 for up to MAX_FACES triangles. Beyond that
        // an id could wrap (still a valid index of `bits`), but such a mesh is refused as
        // too large (TriMesh::from_welded) after `finish`.
        let id = self.bits.len() as u32;
        self.bits.push(bits);
        *slot = Slot { bits, id };
        id
    }

    /// Number of triangles added so far.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The welded positions and triangles; drops the tables.
    pub fn finish(self) -> (Vec<Point3>, Vec<[u32; 3]>) {
        let Welder {
            bits,
            mut triangles,
            recent,
        } = self;
        drop(recent);
        let (canonical, duplicates) = earliest_copies(&bits);
        let to_point = |b: &[u32; 3]| {
            let [x, y, z] = b.map(|b| f32::from_bits(b) as f64);
            Point3::new(x, y, z)
        };
        if duplicates == 0 {
            return (bits.iter().map(to_point).collect(), triangles);
        }
        // Survivors keep their order; a duplicate takes the id of its earliest copy, which
        // comes before it and so is already numbered.
        let mut final_id = canonical;
        let mut positions = Vec::with_capacity(bits.len() - duplicates);
        for v in 0..final_id.len() {
            let c = final_id[v] as usize;
            if c == v {
                final_id[v] = positions.len() as u32;
                positions.push(to_point(&bits[v]));
            } else {
                final_id[v] = final_id[c];
            }
        }
        drop(bits);
        for t in &mut triangles {
            *t = t.map(|v| final_id[v as usize]);
        }
        (positions, triangles)
    }
}

/// For every entry of `bits`, the index of its first equal entry (itself if it is the
/// first), and how many entries are not first; found bucket by bucket after partitioning
/// by hash, so every pass but the rare duplicate's write is sequential.
fn earliest_copies(bits: &[[u32; 3]]) -> (Vec<u32>, usize) {
    let n = bits.len();
    let buckets = (n / BUCKET_TARGET).next_power_of_two().max(1);
    let shift = 64 - buckets.trailing_zeros();
    // Bucket by the hash's top bits (the local tables use bits below them).
    let bucket_of = |b: &[u32; 3]| {
        if buckets == 1 {
            0
        } else {
            (hash_bits(b) >> shift) as usize
        }
    };
    let mut start = vec![0u32; buckets + 1];
    for b in bits {
        start[bucket_of(b) + 1] += 1;
    }
    for i in 0..buckets {
        start[i + 1] += start[i];
    }
    // Counting sort: each bucket holds its entries (pattern and index) in index order.
    let mut sorted = vec![EMPTY; n];
    let mut fill = start.clone();
    for (v, b) in bits.iter().enumerate() {
        let k = bucket_of(b);
        sorted[fill[k] as usize] = Slot {
            bits: *b,
            id: v as u32,
        };
        fill[k] += 1;
    }
    drop(fill);
    let mut canonical: Vec<u32> = (0..n as u32).collect();
    let mut duplicates = 0;
    // Slots of the bucket's entries (positions in `members`), EMPTY_ID when free.
    let mut table: Vec<u32> = Vec::new();
    for k in 0..buckets {
        let members = &sorted[start[k] as usize..start[k + 1] as usize];
        // At most half full, so probing meets an empty slot.
        let size = (2 * members.len()).next_power_of_two().max(2);
        table.clear();
        table.resize(size, EMPTY_ID);
        let mask = size - 1;
        for (m, slot) in members.iter().enumerate() {
            // Bits below the bucket's, which are mixed (not the lowest: see `hash_bits`).
            let mut i = (hash_bits(&slot.bits) >> 24) as usize & mask;
            // Ends: the table has more empty slots than members.
            loop {
                match table[i] {
                    EMPTY_ID => {
                        table[i] = m as u32;
                        break;
                    }
                    e if members[e as usize].bits == slot.bits => {
                        canonical[slot.id as usize] = members[e as usize].id;
                        duplicates += 1;
                        break;
                    }
                    _ => i = (i + 1) & mask,
                }
            }
        }
    }
    (canonical, duplicates)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welds_identical_corners_and_signed_zeros() {
        let mut w = Welder::with_capacity(2);
        w.add_triangle(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        w.add_triangle(&[[-0.0, 1.0, 0.0], [1.0, 0.0, -0.0], [1.0, 1.0, 0.0]]);
        let (p, t) = w.finish();
        assert_eq!(p.len(), 4);
        assert_eq!(t, vec![[0, 1, 2], [2, 1, 3]]);
    }

    #[test]
    fn nearly_identical_corners_stay_apart() {
        let mut w = Welder::with_capacity(1);
        let e = f32::EPSILON;
        w.add_triangle(&[[1.0, 0.0, 0.0], [1.0 + e, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert_eq!(w.finish().0.len(), 3);
    }

    #[test]
    fn the_table_grows_past_its_first_size() {
        // A soup of unconnected triangles: three times more vertices than the hint allows.
        let mut w = Welder::with_capacity(1);
        for i in 0..1000 {
            let x = i as f32;
            w.add_triangle(&[[x, 0.0, 0.0], [x, 1.0, 0.0], [x, 0.0, 1.0]]);
        }
        w.add_triangle(&[[5.0, 0.0, 0.0], [7.0, 1.0, 0.0], [999.0, 0.0, 1.0]]);
        let (p, t) = w.finish();
        assert_eq!(p.len(), 3000);
        assert_eq!(t[1000], [15, 22, 2999]);
    }
}
