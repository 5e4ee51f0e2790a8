//! A uniform bucket grid over points, for "which points lie in this box" queries.
//!
//! No paper: a dense grid of cubic cells over the points' bounding box, points sorted by
//! cell (counting sort) with one offset per cell. Cells are enlarged when the box would need
//! more than [`MAX_CELLS`].
//! Input:  points, wanted cell size. Output: per-box iteration over candidate point ids.
//! Cost:   O(P + cells) to build; a query visits the cells its box overlaps (a trimmed query
//!         tests only those holding points).

use crate::math::{Point3, Real, Vector3};

/// Most cells a grid may have (memory: 4 bytes a cell).
pub const MAX_CELLS: usize = 1 << 23;

/// Points bucketed by cell.
#[derive(Debug, Clone)]
pub struct PointGrid {
    origin: Vector3,
    cell: Real,
    dims: [usize; 3],
    start: Vec<u32>,
    ids: Vec<u32>,
    /// Whether `ids` is `0, 1, 2, …` (a [`PointGrid::reordered`] grid): queries then read
    /// the id ranges without loading them.
    in_order: bool,
}

impl PointGrid {
    /// Buckets `points` into cells of about `cell` (larger if the box would need too many).
    pub fn new(points: &[Point3], cell: Real) -> Self {
        let (mut lo, mut hi) = (
            Vector3::repeat(Real::INFINITY),
            Vector3::repeat(-Real::INFINITY),
        );
        for p in points {
            lo = lo.inf(&p.coords);
            hi = hi.sup(&p.coords);
        }
        if points.is_empty() {
            (lo, hi) = (Vector3::zeros(), Vector3::zeros());
        }
        let size = hi - lo;
        let mut cell = if cell > 0.0 && cell.is_finite() {
            cell
        } else {
            1.0
        };
        let dims_for = |c: Real| size.map(|s| (s / c).floor() as usize + 1);
        let mut dims = dims_for(cell);
        // Each round at least doubles the cell, so this ends within ~64 rounds.
        while (dims.x as Real) * (dims.y as Real) * (dims.z as Real) > MAX_CELLS as Real {
            cell *= 2.0;
            dims = dims_for(cell);
        }
        let dims = [dims.x, dims.y, dims.z];
        let cells = dims[0] * dims[1] * dims[2];
        let mut grid = PointGrid {
            origin: lo,
            cell,
            dims,
            start: vec![0; cells + 1],
            ids: vec![0; points.len()],
            in_order: false,
        };
        let keys: Vec<usize> = points.iter().map(|p| grid.cell_of(p)).collect();
        for &k in &keys {
            grid.start[k + 1] += 1;
        }
        for k in 0..cells {
            grid.start[k + 1] += grid.start[k];
        }
        let mut fill = grid.start.clone();
        for (i, &k) in keys.iter().enumerate() {
            grid.ids[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        grid
    }

    fn coord(&self, x: Real, axis: usize) -> usize {
        let c = ((x - self.origin[axis]) / self.cell).floor();
        if c <= 0.0 {
            0
        } else {
            (c as usize).min(self.dims[axis] - 1)
        }
    }

    fn cell_of(&self, p: &Point3) -> usize {
        let [i, j, k] = [0, 1, 2].map(|a| self.coord(p[a], a));
        (k * self.dims[1] + j) * self.dims[0] + i
    }

    /// The point ids in cell order (points of one cell together).
    pub fn order(&self) -> &[u32] {
        &self.ids
    }

    /// This grid over the points reordered by [`PointGrid::order`] (point `k` of the new
    /// order is point `order()[k]`): the same cells, ids renumbered, no second bucketing.
    pub fn reordered(mut self) -> PointGrid {
        for (k, id) in self.ids.iter_mut().enumerate() {
            *id = k as u32;
        }
        self.in_order = true;
        self
    }

    /// Whether `found(id)` holds for some point in a cell overlapping the box `[lo, hi]`;
    /// stops at the first.
    pub fn any_in_box(&self, lo: &Vector3, hi: &Vector3, found: impl FnMut(usize) -> bool) -> bool {
        self.any_in_box_near(lo, hi, |_, _| true, found)
    }

    /// Calls `visit(id)` for every point in a cell overlapping the box `[lo, hi]` (a superset
    /// of the points inside the box).
    pub fn for_each_in_box(&self, lo: &Vector3, hi: &Vector3, visit: impl FnMut(usize)) {
        self.for_each_in_box_near(lo, hi, |_, _| true, visit);
    }

    /// [`PointGrid::for_each_in_box`], skipping at both ends of each row of cells the cells
    /// for which `near(centre, half_diagonal)` is false: `near` must be true for every cell
    /// holding a point the caller wants (a conservative test of the cell's bounding sphere).
    /// Empty cells are skipped untested. The cells between the first and the last near cell
    /// holding points of a row are all visited.
    pub fn for_each_in_box_near(
        &self,
        lo: &Vector3,
        hi: &Vector3,
        near: impl FnMut(&Point3, Real) -> bool,
        mut visit: impl FnMut(usize),
    ) {
        self.any_in_box_near(lo, hi, near, |id| {
            visit(id);
            false
        });
    }

    /// [`PointGrid::any_in_box`] over the rows trimmed as in
    /// [`PointGrid::for_each_in_box_near`].
    fn any_in_box_near(
        &self,
        lo: &Vector3,
        hi: &Vector3,
        mut near: impl FnMut(&Point3, Real) -> bool,
        mut found: impl FnMut(usize) -> bool,
    ) -> bool {
        for a in 0..3 {
            if hi[a] < self.origin[a] || lo[a] > self.origin[a] + self.cell * self.dims[a] as Real {
                return false;
            }
        }
        let l = [0, 1, 2].map(|a| self.coord(lo[a], a));
        let h = [0, 1, 2].map(|a| self.coord(hi[a], a));
        let radius = 0.5 * self.cell * 3f64.sqrt() * (1.0 + 1e-9);
        let centre = |a: usize, c: usize| self.origin[a] + (c as Real + 0.5) * self.cell;
        for k in l[2]..=h[2] {
            for j in l[1]..=h[1] {
                let row = (k * self.dims[1] + j) * self.dims[0];
                let (y, z) = (centre(1, j), centre(2, k));
                let at = |i: usize| Point3::new(centre(0, i), y, z);
                // An empty cell is skipped before it is tested: a surface's samples fill few
                // of the cells of a box in space.
                let empty = |i: usize| self.start[row + i] == self.start[row + i + 1];
                // Each step moves one cell in, so both loops end.
                let mut first = l[0];
                while first <= h[0] && (empty(first) || !near(&at(first), radius)) {
                    first += 1;
                }
                if first > h[0] {
                    continue;
                }
                let mut last = h[0];
                while last > first && (empty(last) || !near(&at(last), radius)) {
                    last -= 1;
                }
                let (s, e) = (
                    self.start[row + first] as usize,
                    self.start[row + last + 1] as usize,
                );
                let hit = if self.in_order {
                    (s..e).any(&mut found)
                } else {
                    self.ids[s..e].iter().any(|&id| found(id as usize))
                };
                if hit {
                    return true;
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` points scattered over the box `[0, size]` (a fixed sequence).
    fn cloud(n: usize, size: [Real; 3]) -> Vec<Point3> {
        (0..n)
            .map(|i| {
                let t = i as Real;
                Point3::new(
                    (t * 0.618).fract() * size[0],
                    (t * 0.414).fract() * size[1],
                    (t * 0.732).fract() * size[2],
                )
            })
            .collect()
    }

    /// The points of a box query, sorted.
    fn query(grid: &PointGrid, lo: [Real; 3], hi: [Real; 3]) -> Vec<usize> {
        let mut found = Vec::new();
        grid.for_each_in_box(&Vector3::from(lo), &Vector3::from(hi), |i| found.push(i));
        found.sort_unstable();
        found
    }

    /// Trimming rows by a conservative cell test keeps every point the test is for, and
    /// visits fewer than the whole box.
    #[test]
    fn rows_trimmed_by_a_cell_test_keep_every_point_it_is_for() {
        let points = cloud(4000, [10.0, 10.0, 2.0]);
        let first = PointGrid::new(&points, 0.7);
        let moved: Vec<Point3> = first.order().iter().map(|&i| points[i as usize]).collect();
        let grid = first.reordered();
        // A ball; a cell may hold its points when its bounding sphere meets it.
        let (centre, r) = (Point3::new(4.0, 5.0, 1.0), 3.0);
        let (lo, hi) = (
            centre.coords - Vector3::repeat(r),
            centre.coords + Vector3::repeat(r),
        );
        let mut near = Vec::new();
        grid.for_each_in_box_near(
            &lo,
            &hi,
            |c, radius| (c - centre).norm() <= r + radius,
            |i| near.push(i),
        );
        let mut all = Vec::new();
        grid.for_each_in_box(&lo, &hi, |i| all.push(i));
        let inside: Vec<usize> = (0..moved.len())
            .filter(|&i| (moved[i] - centre).norm() <= r)
            .collect();
        assert!(inside.len() > 300);
        assert!(inside.iter().all(|i| near.contains(i)));
        assert!(near.iter().all(|i| all.contains(i)));
        assert!(
            near.len() < all.len() * 9 / 10,
            "{} of {}",
            near.len(),
            all.len()
        );
    }

    /// A query over a box in space around a sheet of points tests only the cells holding
    /// points (a surface fills few cells of a box), and still finds every point in the box.
    #[test]
    fn a_query_tests_only_cells_that_hold_points() {
        let flat: Vec<Point3> = cloud(3000, [10.0, 10.0, 0.0])
            .into_iter()
            .chain([Point3::new(0.0, 0.0, -4.0), Point3::new(10.0, 10.0, 4.0)])
            .collect();
        let grid = PointGrid::new(&flat, 0.5);
        let (lo, hi) = (Vector3::new(2.0, 2.0, -3.0), Vector3::new(6.0, 7.0, 3.0));
        let mut tested = Vec::new();
        let mut found = Vec::new();
        grid.for_each_in_box_near(
            &lo,
            &hi,
            |c, _| {
                tested.push(*c);
                true
            },
            |i| found.push(i),
        );
        assert!(!tested.is_empty());
        for c in &tested {
            assert!(c.z.abs() < 0.5, "an empty cell at z = {} was tested", c.z);
        }
        found.sort_unstable();
        assert_eq!(found, query(&grid, lo.into(), hi.into()));
        let inside = (0..flat.len())
            .filter(|&i| (0..3).all(|a| flat[i][a] >= lo[a] && flat[i][a] <= hi[a]))
            .count();
        assert!(inside > 300 && found.len() >= inside);
    }

    #[test]
    fn a_reordered_grid_is_the_grid_of_the_reordered_points() {
        // Several points per cell.
        let points = cloud(500, [10.0, 7.0, 1.0]);
        let grid = PointGrid::new(&points, 1.3);
        let order = grid.order().to_vec();
        let moved: Vec<Point3> = order.iter().map(|&i| points[i as usize]).collect();
        let fresh = PointGrid::new(&moved, 1.3);
        let reordered = grid.reordered();
        assert_eq!(reordered.start, fresh.start);
        assert_eq!(reordered.ids, fresh.ids);
        // And its queries are those of the first grid, renumbered.
        let first = PointGrid::new(&points, 1.3);
        let (lo, hi) = ([2.0, 1.0, 0.0], [5.5, 4.0, 0.6]);
        let mut renumbered: Vec<usize> = query(&reordered, lo, hi)
            .iter()
            .map(|&k| order[k] as usize)
            .collect();
        renumbered.sort_unstable();
        assert_eq!(renumbered, query(&first, lo, hi));
        assert!(!renumbered.is_empty());
    }
}
