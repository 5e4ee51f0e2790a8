//! Welding: merging bit-identical corner positions of a triangle soup into shared vertices.
//!
//! No paper: a linear-probing hash table of 16-byte slots, each holding a corner's `f32` bit
//! pattern and its vertex id, kept at most half full, so a lookup reads one cache line and
//! never the position array. In front of it a small direct-mapped cache of recent corners
//! catches the neighbours STL files list close together. Hand-written because hashbrown's
//! portable probing (WebAssembly has no SSE2) measured about twice as slow here.
//! `-0.0` and `+0.0` count as the same coordinate.
//! Cost: expected O(1) per corner; the table (32 bytes a vertex) is dropped by `finish`.

use crate::math::Point3;

/// Builds a [`TriMesh`](super::TriMesh)'s arrays from triangles given by corner coordinates.
#[derive(Debug)]
pub struct Welder {
    positions: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
    table: Vec<Slot>,
    /// Direct-mapped cache of recently seen corners (256 KiB, stays in L2).
    recent: Vec<Slot>,
}

/// A welded corner: its canonical bit pattern and vertex id ([`EMPTY_ID`] when unused).
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
const RECENT_SLOTS: usize = 1 << 14;

/// The bit pattern of a finite corner, with `-0.0` folded into `+0.0`.
#[inline]
fn canonical_bits(p: &[f32; 3]) -> [u32; 3] {
    p.map(|c| (c + 0.0).to_bits())
}

/// fmix64 of MurmurHash3 over the packed bit patterns.
#[inline]
fn hash_bits(bits: &[u32; 3]) -> u64 {
    let [x, y, z] = bits.map(u64::from);
    let mut h = (x | (y << 32)) ^ z.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
    h ^= h >> 33;
    h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    h ^ (h >> 33)
}

impl Welder {
    /// A welder sized for about `triangles` triangles (only a hint: it grows as needed).
    pub fn with_capacity(triangles: usize) -> Self {
        // Closed meshes have about half as many vertices as triangles.
        let vertices = triangles / 2 + 16;
        Welder {
            positions: Vec::with_capacity(vertices),
            triangles: Vec::with_capacity(triangles),
            table: vec![EMPTY; (2 * vertices).next_power_of_two()],
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

    #[inline]
    fn vertex_id(&mut self, bits: [u32; 3]) -> u32 {
        let hash = hash_bits(&bits);
        let cached = self.recent[hash as usize & (RECENT_SLOTS - 1)];
        if cached.id != EMPTY_ID && cached.bits == bits {
            return cached.id;
        }
        let mask = self.table.len() - 1;
        let mut i = (hash >> 32) as usize & mask;
        // Ends: the table is kept at most half full, so probing meets an empty slot.
        let id = loop {
            let slot = self.table[i];
            if slot.id == EMPTY_ID {
                let id = self.positions.len() as u32;
                self.table[i] = Slot { bits, id };
                let [x, y, z] = bits.map(|b| f32::from_bits(b) as f64);
                self.positions.push(Point3::new(x, y, z));
                if 2 * self.positions.len() > self.table.len() {
                    self.grow();
                }
                break id;
            }
            if slot.bits == bits {
                break slot.id;
            }
            i = (i + 1) & mask;
        };
        self.recent[hash as usize & (RECENT_SLOTS - 1)] = Slot { bits, id };
        id
    }

    /// Doubles the table and re-inserts every slot.
    fn grow(&mut self) {
        let doubled = vec![EMPTY; 2 * self.table.len()];
        let old = std::mem::replace(&mut self.table, doubled);
        let mask = self.table.len() - 1;
        for slot in old.into_iter().filter(|s| s.id != EMPTY_ID) {
            let mut i = (hash_bits(&slot.bits) >> 32) as usize & mask;
            while self.table[i].id != EMPTY_ID {
                i = (i + 1) & mask;
            }
            self.table[i] = slot;
        }
    }

    /// Number of triangles added so far.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The welded positions and triangles; drops the tables.
    pub fn finish(self) -> (Vec<Point3>, Vec<[u32; 3]>) {
        (self.positions, self.triangles)
    }
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
