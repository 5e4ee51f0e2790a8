//! Invalid-loop removal of a pass's raw offset curve: where the curve crosses itself, the
//! loop in between is dropped (see [`super`] for where the raw curve comes from and how its
//! caps and concave corners are treated).
//!
//! Source: Choi & Park, "A pair-wise offset algorithm for 2D point-sequence curve"
//! (Computer-Aided Design 31, 1999): the raw offset is walked edge by edge and cut at its
//! first crossing with the curve kept so far.
//! Input:  the raw offset curve's nodes (positions, their projections on the pass's plane,
//!         axes), a length tolerance, where its caps are and whether each may be cut.
//! Output: [`Kept`]: the loop-free curve, and whether a crossing cut each cap.
//! Cost:   O(n + c) for `n` raw nodes, where `c` counts the kept edges met in the grid cells
//!         (one cell ≈ one mean offset edge) around each new edge (see [`super`]'s header for
//!         when that is bounded).
//! Deviations: a uniform grid over the kept edges ([`EdgeGrid`]) in place of the paper's
//!         sweep; crossings are found in the projection on the pass's plane, and a crossing's
//!         position is the midpoint of the two branches' points.

use super::{blend, unit_or};
use crate::math::{Point3, Real, Vector3};
use crate::toolpath::PoseKind;
use rustc_hash::FxHashMap;

/// Two 2D segments whose directions' cross product is below this fraction of their lengths'
/// product are parallel: no crossing.
const PARALLEL_SINE: Real = 1e-12;

/// A point of the offset curve: position, its projection on the pass's plane, gun axis, the
/// kind of the move arriving at it and the index of the raw edge it lies on (its own index
/// for a raw node; raw edge `k` ends at raw node `k`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Node {
    pub(super) p: Point3,
    pub(super) q: [Real; 2],
    pub(super) axis: Vector3,
    pub(super) kind: PoseKind,
    pub(super) origin: usize,
}

/// Where the caps are in the raw curve (they end at raw node `first` and start at raw node
/// `last`), whether each may be cut, and the largest gap in space at a crossing that cuts one.
pub(super) struct Caps {
    pub(super) gap: Real,
    pub(super) first: usize,
    pub(super) last: usize,
    pub(super) start: bool,
    pub(super) end: bool,
}

/// The loop-free offset curve and whether a crossing cut each cap.
pub(super) struct Kept {
    pub(super) nodes: Vec<Node>,
    pub(super) start_cut: bool,
    pub(super) end_cut: bool,
}

fn cross2(a: [Real; 2], b: [Real; 2]) -> Real {
    a[0] * b[1] - a[1] * b[0]
}
fn sub2(a: [Real; 2], b: [Real; 2]) -> [Real; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn len2(a: [Real; 2]) -> Real {
    libm::hypot(a[0], a[1])
}

/// A uniform grid over the kept edges of the offset curve (2D), edge `i` joining kept nodes
/// `i − 1` and `i`. Edges are removed last-in first-out, like the kept curve itself, so each
/// cell's entries form a stack: a list threaded through one array, newest first.
struct EdgeGrid {
    cell: Real,
    /// Per occupied cell: its newest entry.
    head: FxHashMap<(i64, i64), u32>,
    /// Entries in the order added: edge, next entry of the same cell (or [`NO_ENTRY`]), cell.
    entries: Vec<(u32, u32, (i64, i64))>,
    /// Per registered edge (edge `i` at `i − 1`): its first entry.
    edge_start: Vec<usize>,
    /// Per edge: the last query that tested it.
    stamp: Vec<u32>,
    query: u32,
    /// The sample cells of the segment last queried or registered ([`EdgeGrid::sample_cells`])
    /// and that segment: registering the segment just queried (no crossing found) reads them
    /// here instead of sampling it again.
    walk: Vec<(i64, i64)>,
    walk_of: Option<([Real; 2], [Real; 2])>,
    /// The cells the last query looked in, and each column's least and greatest y of its
    /// walk (scratch).
    cells: Vec<(i64, i64)>,
    columns: Vec<(i64, i64)>,
}

/// End of a cell's list of entries.
const NO_ENTRY: u32 = u32::MAX;

impl EdgeGrid {
    fn new(cell: Real) -> EdgeGrid {
        EdgeGrid {
            cell,
            head: FxHashMap::default(),
            entries: Vec::new(),
            edge_start: Vec::new(),
            stamp: Vec::new(),
            query: 0,
            walk: Vec::new(),
            walk_of: None,
            cells: Vec::new(),
            columns: Vec::new(),
        }
    }
    /// Cells of sample points at most half a cell apart along `a → b` (monotone, so repeats
    /// are consecutive): any point of the segment is within a quarter cell of a sample.
    fn sample_cells(&self, a: [Real; 2], b: [Real; 2], out: &mut Vec<(i64, i64)>) {
        out.clear();
        // The sample count is finite: both ends are finite and the cell positive.
        let steps = (2.0 * len2(sub2(b, a)) / self.cell).ceil().clamp(1.0, 1e9) as usize;
        for k in 0..=steps {
            let s = k as Real / steps as Real;
            let x = a[0] + (b[0] - a[0]) * s;
            let y = a[1] + (b[1] - a[1]) * s;
            // `floor` is exact, so any implementation gives these cells; the standard one is
            // an instruction in WebAssembly, where `libm`'s is a routine.
            let c = (
                (x / self.cell).floor() as i64,
                (y / self.cell).floor() as i64,
            );
            if out.last() != Some(&c) {
                out.push(c);
            }
        }
    }
    /// Registers edge `id` (= the number of edges registered so far + 1) from `a` to `b`.
    fn push(&mut self, id: usize, a: [Real; 2], b: [Real; 2]) {
        debug_assert_eq!(id, self.edge_start.len() + 1);
        self.walk(a, b);
        self.edge_start.push(self.entries.len());
        for &c in &self.walk {
            let index = self.entries.len() as u32;
            let next = self.head.insert(c, index).unwrap_or(NO_ENTRY);
            self.entries.push((id as u32, next, c));
        }
        if self.stamp.len() <= id {
            self.stamp.resize(id + 1, 0);
        }
    }
    /// Removes every edge above `keep` (edges `keep + 1 ..`).
    fn truncate(&mut self, keep: usize) {
        let Some(&start) = self.edge_start.get(keep) else {
            return;
        };
        self.edge_start.truncate(keep);
        while self.entries.len() > start {
            let Some((_, next, c)) = self.entries.pop() else {
                break;
            };
            if next == NO_ENTRY {
                self.head.remove(&c);
            } else {
                self.head.insert(c, next);
            }
        }
    }
    /// Calls `visit` once for every registered edge near the segment `a → b` (every edge
    /// crossing it is visited).
    fn near(&mut self, a: [Real; 2], b: [Real; 2], mut visit: impl FnMut(usize)) {
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.query = 1;
        }
        self.near_cells(a, b);
        for c in &self.cells {
            let mut entry = self.head.get(c).copied().unwrap_or(NO_ENTRY);
            while entry != NO_ENTRY {
                let (e, next, _) = self.entries[entry as usize];
                let e = e as usize;
                if self.stamp[e] != self.query {
                    self.stamp[e] = self.query;
                    visit(e);
                }
                entry = next;
            }
        }
    }

    /// The sample cells of `a → b` in `self.walk`, sampled unless they are there already.
    fn walk(&mut self, a: [Real; 2], b: [Real; 2]) {
        if self.walk_of != Some((a, b)) {
            let mut walk = std::mem::take(&mut self.walk);
            self.sample_cells(a, b, &mut walk);
            self.walk = walk;
            self.walk_of = Some((a, b));
        }
    }

    /// The cells [`EdgeGrid::near`] looks in for the segment `a → b`, in increasing order,
    /// in `self.cells` (its sample cells in `self.walk`).
    fn near_cells(&mut self, a: [Real; 2], b: [Real; 2]) {
        self.walk(a, b);
        // Two crossing segments have samples within a quarter cell of the crossing each, so
        // their cells are neighbours: visit the union of the samples' 3 × 3 neighbourhoods,
        // column by column (x, then y, increasing). The samples' cells are a walk monotone
        // in x and in y whose steps move at most one cell along each (samples are at most
        // half a cell apart), so it meets every column between its ends, and its cells in
        // columns x − 1 to x + 1 cover every y between their least and greatest: the union's
        // cells in column x are those from one below the least to one above the greatest.
        let walk = &self.walk;
        let (x0, x1) = (walk[0].0, walk[walk.len() - 1].0);
        let x_lo = x0.min(x1);
        // Each column's least and greatest y, in one pass over the walk.
        let columns = &mut self.columns;
        columns.clear();
        columns.resize((x0.max(x1) - x_lo + 1) as usize, (i64::MAX, i64::MIN));
        for &(x, y) in walk {
            let (lo, hi) = &mut columns[(x - x_lo) as usize];
            (*lo, *hi) = ((*lo).min(y), (*hi).max(y));
        }
        self.cells.clear();
        for x in x_lo - 1..=x0.max(x1) + 1 {
            let near = |k: i64| usize::try_from(k - x_lo).ok().and_then(|k| columns.get(k));
            let (lo, hi) = [near(x - 1), near(x), near(x + 1)]
                .into_iter()
                .flatten()
                .fold((i64::MAX, i64::MIN), |(lo, hi), c| {
                    (lo.min(c.0), hi.max(c.1))
                });
            for y in lo - 1..=hi + 1 {
                self.cells.push((x, y));
            }
        }
    }
}

/// Where a segment `p → p + r` first crosses a kept edge: its parameter on the segment, the
/// edge and the parameter on the edge.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    t: Real,
    edge: usize,
    u: Real,
}

/// Removes the loops of the raw offset curve (see the file header): a stack of kept nodes;
/// each raw edge is tested against the kept edges near it (but the last, which it continues);
/// at its first crossing the kept curve is cut back to the crossing and the rest of the edge
/// goes on from there. Every crossing removes at least one kept node and every raw node is
/// kept at most once, so it ends after at most twice as many steps as raw nodes. A crossing
/// on an edge of the start cap (raw edges up to `first`) cuts it, unless at its very end; one
/// found by an edge of the end cap (raw edges after `last`) cuts that; either counts only
/// where the branches are within `caps.gap` in space and the cap may be cut at all.
pub(super) fn remove_loops(raw: &[Node], tol: Real, caps: &Caps) -> Kept {
    let (first, last) = (caps.first, caps.last);
    let mut kept: Vec<Node> = Vec::with_capacity(raw.len());
    let (mut start_cut, mut end_cut) = (false, false);
    let Some(&first_node) = raw.first() else {
        return Kept {
            nodes: kept,
            start_cut,
            end_cut,
        };
    };
    let total: Real = raw.windows(2).map(|w| len2(sub2(w[1].q, w[0].q))).sum();
    let cell = (total / raw.len() as Real).max(tol * 16.0);
    let mut grid = EdgeGrid::new(cell);
    // The length of each kept edge (edge `e` joins kept nodes `e − 1` and `e`; 0 a dummy),
    // kept beside them rather than measured again by every query that meets the edge.
    let mut lengths: Vec<Real> = Vec::with_capacity(raw.len());
    lengths.push(0.0);
    kept.push(first_node);
    for target in &raw[1..] {
        loop {
            let from = kept[kept.len() - 1];
            let r = sub2(target.q, from.q);
            let len = len2(r);
            if len <= tol {
                // The raw node is where the curve already is: keep its turn, not a new pose.
                break;
            }
            let last_edge = kept.len() - 1;
            let mut best: Option<Crossing> = None;
            let t_min = tol / len;
            grid.near(from.q, target.q, |e| {
                if e >= last_edge {
                    return;
                }
                let (a, b) = (kept[e - 1].q, kept[e].q);
                let s = sub2(b, a);
                let ls = lengths[e];
                let denom = cross2(r, s);
                if ls <= 0.0 || denom.abs() <= PARALLEL_SINE * len * ls {
                    return;
                }
                let w = sub2(a, from.q);
                let t = cross2(w, s) / denom;
                let u = cross2(w, r) / denom;
                let u_tol = tol / ls;
                if t < t_min || t > 1.0 + t_min || u < -u_tol || u > 1.0 + u_tol {
                    return;
                }
                let (in_start, in_end) = (kept[e].origin <= first, target.origin > last);
                if (in_start && !caps.start) || (in_end && !caps.end) {
                    return;
                }
                if in_start || in_end {
                    // A cap is cut only where the curves meet in space, not merely in the
                    // projection (normals across the scan plane part the branches).
                    let on_edge = kept[e - 1].p + (kept[e].p - kept[e - 1].p) * u;
                    let on_new = from.p + (target.p - from.p) * t;
                    if (on_edge - on_new).norm() > caps.gap {
                        return;
                    }
                }
                let c = Crossing {
                    t: t.min(1.0),
                    edge: e,
                    u: u.clamp(0.0, 1.0),
                };
                best = match best {
                    Some(b) if b.t < c.t - t_min || (b.t <= c.t + t_min && b.edge < c.edge) => {
                        Some(b)
                    }
                    _ => Some(c),
                };
            });
            let Some(c) = best else {
                grid.push(kept.len(), from.q, target.q);
                lengths.push(len);
                kept.push(*target);
                break;
            };
            // Cut the kept curve back to the crossing on edge `c.edge`.
            let (a, b) = (kept[c.edge - 1], kept[c.edge]);
            let on_edge_axis = unit_or(a.axis.lerp(&b.axis, c.u), &b.axis);
            let on_new_axis = unit_or(from.axis.lerp(&target.axis, c.t), &target.axis);
            let axis = blend(&on_edge_axis, &on_new_axis);
            let edge_len = len2(sub2(b.q, a.q));
            let at = if c.u * edge_len <= tol {
                c.edge - 1
            } else {
                c.edge
            };
            let interior = at == c.edge && (1.0 - c.u) * edge_len > tol;
            if b.origin < first || (b.origin == first && (interior || at != c.edge)) {
                start_cut = true;
            }
            if target.origin > last {
                end_cut = true;
            }
            kept.truncate(at + 1);
            lengths.truncate(at + 1);
            grid.truncate(at);
            let node = &mut kept[at];
            node.axis = axis;
            if interior {
                let on_edge = a.p + (b.p - a.p) * c.u;
                let on_new = from.p + (target.p - from.p) * c.t;
                node.p = Point3::from((on_edge.coords + on_new.coords) * 0.5);
                node.q = [from.q[0] + r[0] * c.t, from.q[1] + r[1] * c.t];
                node.origin = b.origin;
                // The edge now ends at the crossing.
                lengths[at] = len2(sub2(kept[at].q, kept[at - 1].q));
            }
        }
    }
    Kept {
        nodes: kept,
        start_cut,
        end_cut,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spray::normal_equations::tests::sequence;

    /// The cells looked in are the union of the 3 × 3 neighbourhoods of the segment's
    /// sample cells, in increasing order, as sorting that union gives them: on segments of
    /// every direction and length (a few cells or none), anywhere on the grid.
    #[test]
    fn the_cells_near_a_segment_are_the_neighbourhoods_of_its_samples() {
        let mut grid = EdgeGrid::new(0.7);
        // A fixed sequence of pseudo-random numbers in [0, 1).
        let mut next = sequence(0x2545_f491_4f6c_dd1d);
        let mut naive = Vec::new();
        for k in 0..20_000 {
            let a = [200.0 * next() - 100.0, 200.0 * next() - 100.0];
            let reach = [0.0, 0.3, 2.0, 9.0][k % 4];
            let b = match k % 5 {
                // Along an axis, either way.
                0 => [a[0] + reach * (next() - 0.5), a[1]],
                1 => [a[0], a[1] + reach * (next() - 0.5)],
                _ => [a[0] + reach * (next() - 0.5), a[1] + reach * (next() - 0.5)],
            };
            grid.near_cells(a, b);
            grid.sample_cells(a, b, &mut naive);
            assert_eq!(grid.walk, naive, "the sample cells");
            let walk = naive.len();
            for i in 0..walk {
                let (x, y) = naive[i];
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        naive.push((x + dx, y + dy));
                    }
                }
            }
            naive.drain(..walk);
            naive.sort_unstable();
            naive.dedup();
            assert_eq!(grid.cells, naive, "{a:?} → {b:?}");
        }
    }
}
