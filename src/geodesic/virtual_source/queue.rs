//! The settling order of [`super::Solver`]: vertices keyed by `(distance, id)`.
//!
//! Source: none (a d-ary heap with decrease-key, a common choice for Dijkstra's queue).
//! Cost:   O(log V) a push, lower or pop; a position per vertex.

use super::super::unfolding::Entry;
use crate::math::Real;

/// A 4-ary min-heap of vertices keyed by `(distance, id)` with decrease-key: each vertex is
/// in it once at most (a lazy heap holds about two entries a vertex and skips the stale).
/// Four children a node halve the depth of a binary heap, and a pop reads them from one or
/// two cache lines (no paper; a common choice for Dijkstra's queue). The order is total, so
/// any heap pops the same sequence as the binary one did.
pub(super) struct Queue {
    entries: Vec<Entry>,
    /// Index of each vertex in `entries` (`u32::MAX`: not queued).
    at: Vec<u32>,
}

/// Children per node of [`Queue`].
const ARITY: usize = 4;

impl Queue {
    pub(super) fn new(vertices: usize) -> Self {
        Queue {
            entries: Vec::new(),
            at: vec![u32::MAX; vertices],
        }
    }

    fn less(a: &Entry, b: &Entry) -> bool {
        a.d.total_cmp(&b.d).then(a.v.cmp(&b.v)).is_lt()
    }

    fn place(&mut self, i: usize, e: Entry) {
        self.at[e.v as usize] = i as u32;
        self.entries[i] = e;
    }

    /// Queues `v` at `d`, or lowers its key to `d` (`d` is never higher than its key).
    pub(super) fn push_or_lower(&mut self, v: u32, d: Real) {
        let e = Entry { d, v };
        let mut i = match self.at[v as usize] {
            u32::MAX => {
                self.entries.push(e);
                self.entries.len() - 1
            }
            i => i as usize,
        };
        // Sift up: each step divides i by ARITY, so at most log4(len) steps.
        while i > 0 {
            let parent = (i - 1) / ARITY;
            if !Self::less(&e, &self.entries[parent]) {
                break;
            }
            let moved = self.entries[parent];
            self.place(i, moved);
            i = parent;
        }
        self.place(i, e);
    }

    pub(super) fn pop(&mut self) -> Option<Entry> {
        let top = *self.entries.first()?;
        self.at[top.v as usize] = u32::MAX;
        let last = self.entries.pop()?;
        if !self.entries.is_empty() {
            // Sift down: each step multiplies i by ARITY, so at most log4(len) steps.
            let (n, mut i) = (self.entries.len(), 0);
            loop {
                let first = ARITY * i + 1;
                if first >= n {
                    break;
                }
                let mut m = first;
                for c in first + 1..(first + ARITY).min(n) {
                    if Self::less(&self.entries[c], &self.entries[m]) {
                        m = c;
                    }
                }
                if !Self::less(&self.entries[m], &last) {
                    break;
                }
                let child = self.entries[m];
                self.place(i, child);
                i = m;
            }
            self.place(i, last);
        }
        Some(top)
    }

    pub(super) fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queue_pops_by_distance_then_id_and_lowers_keys() {
        let mut q = Queue::new(6);
        for (v, d) in [(3, 5.0), (1, 2.0), (4, 2.0), (0, 9.0), (5, 7.0)] {
            q.push_or_lower(v, d);
        }
        q.push_or_lower(0, 1.0);
        q.push_or_lower(5, 2.0);
        let order: Vec<(u32, Real)> = std::iter::from_fn(|| q.pop().map(|e| (e.v, e.d))).collect();
        assert_eq!(order, [(0, 1.0), (1, 2.0), (4, 2.0), (5, 2.0), (3, 5.0)]);
        assert!(q.is_empty() && q.at.iter().all(|&i| i == u32::MAX));
    }
}
