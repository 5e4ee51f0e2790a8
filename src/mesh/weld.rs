//! Welding: merging bit-identical corner positions of a triangle soup into shared vertices.
//!
//! No paper: an open-addressing hash table (hashbrown's `HashTable`) of `u32` vertex ids whose
//! key is read back from the position array, so a slot costs 5 bytes instead of the 30 or so
//! of a map from coordinates to ids. `-0.0` and `+0.0` count as the same coordinate.
//! Cost: expected O(1) per corner.

use crate::math::Point3;
use hashbrown::HashTable;

/// Builds a [`TriMesh`](super::TriMesh)'s arrays from triangles given by corner coordinates.
#[derive(Debug, Default)]
pub struct Welder {
    positions: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
    table: HashTable<u32>,
}

/// fmix64 of MurmurHash3 over the packed `f32` bit patterns; `+ 0.0` folds `-0.0` into `+0.0`.
#[inline]
fn hash_corner(p: &[f32; 3]) -> u64 {
    let [x, y, z] = p.map(|c| (c + 0.0).to_bits() as u64);
    let mut h = (x | (y << 32)) ^ z.wrapping_mul(0x9e37_79b9_7f4a_7c15);
    h ^= h >> 33;
    h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
    h ^= h >> 33;
    h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    h ^ (h >> 33)
}

#[inline]
fn as_f32(p: &Point3) -> [f32; 3] {
    // Exact: every stored position came from an f32.
    [p.x as f32, p.y as f32, p.z as f32]
}

impl Welder {
    /// A welder sized for about `triangles` triangles (only a hint: it grows as needed).
    pub fn with_capacity(triangles: usize) -> Self {
        // Closed meshes have about half as many vertices as triangles.
        let vertices = triangles / 2 + 16;
        Welder {
            positions: Vec::with_capacity(vertices),
            triangles: Vec::with_capacity(triangles),
            table: HashTable::with_capacity(vertices),
        }
    }

    /// Adds a triangle whose corners must be finite; returns its face id.
    pub fn add_triangle(&mut self, corners: &[[f32; 3]; 3]) -> usize {
        debug_assert!(corners.iter().flatten().all(|c| c.is_finite()));
        let ids = corners.map(|c| self.vertex_id(&c));
        self.triangles.push(ids);
        self.triangles.len() - 1
    }

    fn vertex_id(&mut self, corner: &[f32; 3]) -> u32 {
        let positions = &mut self.positions;
        let hash = hash_corner(corner);
        let entry = self.table.entry(
            hash,
            |&id| as_f32(&positions[id as usize]) == *corner,
            |&id| hash_corner(&as_f32(&positions[id as usize])),
        );
        match entry {
            hashbrown::hash_table::Entry::Occupied(slot) => *slot.get(),
            hashbrown::hash_table::Entry::Vacant(slot) => {
                let id = positions.len() as u32;
                positions.push(Point3::new(
                    corner[0] as f64,
                    corner[1] as f64,
                    corner[2] as f64,
                ));
                slot.insert(id);
                id
            }
        }
    }

    /// Number of triangles added so far.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The welded positions and triangles; drops the hash table.
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
}
