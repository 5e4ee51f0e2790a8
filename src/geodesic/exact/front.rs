//! Windows: their distance functions (a point source or a plane wave), their queue order,
//! and the 2D frame of a half-edge they live in (Surazhsky et al. 2005, §3).

use super::ON_LINE_TOLERANCE;
use crate::math::{Point3, Real, Vector3};
use std::cmp::Ordering;

/// The distance function of a window in its edge frame (edge on `y = 0`, face ahead at `y > 0`).
#[derive(Clone, Copy, Debug)]
pub(super) enum Front {
    /// `σ + |(x, y) − (sx, sy)|`, source unfolded at `sy ≤ 0`.
    Point { sx: Real, sy: Real, sigma: Real },
    /// `ux·x + uy·y + c`, unit `(ux, uy)` with `uy > 0`.
    Line { ux: Real, uy: Real, c: Real },
}

impl Front {
    pub(super) fn at(&self, x: Real, y: Real) -> Real {
        match *self {
            Front::Point { sx, sy, sigma } => sigma + norm2(x - sx, y - sy),
            Front::Line { ux, uy, c } => ux * x + uy * y + c,
        }
    }

    /// Smallest distance over `[b0, b1]` on the edge (the queue key).
    pub(super) fn min_on(&self, b0: Real, b1: Real) -> Real {
        match *self {
            Front::Point { sx, sy, sigma } => sigma + norm2(sx.clamp(b0, b1) - sx, sy),
            Front::Line { ux, c, .. } => c + (ux * b0).min(ux * b1),
        }
    }

    /// Direction of the ray through edge point `(x, 0)`.
    pub(super) fn ray(&self, x: Real) -> [Real; 2] {
        match *self {
            Front::Point { sx, sy, .. } => [x - sx, -sy],
            Front::Line { ux, uy, .. } => [ux, uy],
        }
    }

    /// The same front in a frame with origin `o` and axes `ex`, `ey` (given in this frame).
    pub(super) fn in_frame(&self, o: [Real; 2], ex: [Real; 2], ey: [Real; 2]) -> Front {
        match *self {
            Front::Point { sx, sy, sigma } => {
                let d = [sx - o[0], sy - o[1]];
                Front::Point {
                    sx: dot(d, ex),
                    sy: dot(d, ey),
                    sigma,
                }
            }
            Front::Line { ux, uy, c } => Front::Line {
                ux: ux * ex[0] + uy * ex[1],
                uy: ux * ey[0] + uy * ey[1],
                c: c + ux * o[0] + uy * o[1],
            },
        }
    }
}

/// Length of `(x, y)` (`sqrt` is exactly rounded, hence identical on every platform; lengths
/// here are far from overflow).
pub(super) fn norm2(x: Real, y: Real) -> Real {
    (x * x + y * y).sqrt()
}

pub(super) fn dot(a: [Real; 2], b: [Real; 2]) -> Real {
    a[0] * b[0] + a[1] * b[1]
}
pub(super) fn cross(a: [Real; 2], b: [Real; 2]) -> Real {
    a[0] * b[1] - a[1] * b[0]
}

/// A window to seed on an edge: `(b0, b1, front)` in the edge's frame.
pub(super) type Seed = (Real, Real, Front);

/// A window on the edge in slot `slot` of `face`, about to cross into `face`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Window {
    pub(super) face: u32,
    pub(super) slot: u8,
    pub(super) b0: Real,
    pub(super) b1: Real,
    pub(super) front: Front,
}

#[derive(Clone, Copy, Debug)]
pub(super) enum Event {
    Window(Window),
    /// A vertex restarts the propagation (pseudo-source) at its distance `key`.
    Vertex(u32),
}

/// A queue entry: the key, the push order, and where the event waits (a small entry keeps
/// the heap's moves cheap).
#[derive(Clone, Copy, Debug)]
pub(super) struct Item {
    pub(super) key: Real,
    pub(super) seq: u64,
    pub(super) slot: u32,
}
impl PartialEq for Item {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Item {}
impl Ord for Item {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on the key, then first pushed first: a deterministic order.
        o.key
            .total_cmp(&self.key)
            .then_with(|| o.seq.cmp(&self.seq))
    }
}
impl PartialOrd for Item {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// The 2D frame of half-edge (face, slot): `A` at the origin, `B` at `(l, 0)`, `C` at `c`.
pub(super) struct Frame {
    pub(super) v: [usize; 3],
    pub(super) a: Point3,
    pub(super) ex: Vector3,
    pub(super) l: Real,
    pub(super) c: [Real; 2],
}

impl Frame {
    /// A point of the face across the edge, unfolded to `y ≤ 0`.
    pub(super) fn unfold(&self, p: &Point3) -> [Real; 2] {
        let w = p - self.a;
        let x = w.dot(&self.ex);
        [x, -(w - self.ex * x).norm()]
    }

    pub(super) fn corner(&self, i: usize) -> [Real; 2] {
        [[0.0, 0.0], [self.l, 0.0], self.c][i]
    }
}

/// The edge points `(x, 0)` with `sign · (x − a)·d ≥ 0` as an x-range (`None` if empty).
pub(super) fn half_line(a: [Real; 2], d: [Real; 2], sign: Real) -> Option<(Real, Real)> {
    let (inf, c) = (Real::INFINITY, -a[1] * d[1] - a[0] * d[0]);
    // sign · (x·dx + c) ≥ 0.
    let dx = sign * d[0];
    let c = sign * c;
    if dx.abs() <= ON_LINE_TOLERANCE {
        return (c >= 0.0).then_some((-inf, inf));
    }
    let x = -c / dx;
    Some(if dx > 0.0 { (x, inf) } else { (-inf, x) })
}

pub(super) fn meet(a: (Real, Real), b: (Real, Real)) -> (Real, Real) {
    (a.0.max(b.0), a.1.min(b.1))
}

pub(super) fn point(s: [Real; 2], sigma: Real) -> Front {
    Front::Point {
        sx: s[0],
        sy: s[1].min(0.0),
        sigma,
    }
}

/// Buckets kept at most; keys beyond the last bucket wait in it.
const MAX_BUCKETS: usize = 1 << 22;

/// A priority queue in the same order as one binary heap (key, then push order), built as
/// bands of keys `width` wide: only the band being processed is a heap, later bands are
/// plain lists heapified when reached. Keys never go below the band being processed
/// (children are never nearer than their parent), so the order is exactly the heap's, with
/// a small heap that stays in cache (no paper: a two-level bucket queue).
pub(super) struct Queue {
    width: Real,
    current: usize,
    near: std::collections::BinaryHeap<Item>,
    bands: Vec<Vec<Item>>,
    len: usize,
}

impl Queue {
    /// An empty queue with bands `width` wide (> 0).
    pub(super) fn new(width: Real) -> Self {
        Queue {
            width,
            current: 0,
            near: std::collections::BinaryHeap::new(),
            bands: Vec::new(),
            len: 0,
        }
    }

    pub(super) fn len(&self) -> usize {
        self.len
    }

    pub(super) fn push(&mut self, item: Item) {
        self.len += 1;
        // Negative or NaN keys land in band 0; huge ones in the last band.
        let band = ((item.key / self.width) as usize).min(MAX_BUCKETS - 1);
        if band <= self.current {
            self.near.push(item);
        } else {
            if self.bands.len() <= band {
                self.bands.resize_with(band + 1, Vec::new);
            }
            self.bands[band].push(item);
        }
    }

    pub(super) fn pop(&mut self) -> Option<Item> {
        // Each round moves `current` forward: at most `bands.len()` rounds.
        loop {
            if let Some(item) = self.near.pop() {
                self.len -= 1;
                return Some(item);
            }
            let next = (self.current + 1..self.bands.len()).find(|&b| !self.bands[b].is_empty())?;
            self.current = next;
            self.near = std::mem::take(&mut self.bands[next]).into();
        }
    }
}
