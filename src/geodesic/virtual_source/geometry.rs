//! The geometry of virtual sources: a source (a point, or a piece of a source curve run on
//! beyond its ends), the rotation that turns it from the plane of one face into another's
//! about a vertex, and where a ray from it crosses an edge.

use super::foot;
use super::run_on::RunOn;
use crate::math::{Point3, Real, Vector3};

/// Relative slack (of the edge length) for a ray crossing an edge at or near its ends.
pub(in crate::geodesic) const CROSSING_TOLERANCE: Real = 1e-9;

/// A virtual source: distance `sigma + dist(x, [p, q])`, lying in the plane of `face`; the
/// segment runs on beyond `p` (`run_on[side][0]`) or `q` (`run_on[side][1]`) as far as the
/// source curve beyond that end allows for the vertices on that side (see [`RunOn`]; side 0
/// is the left of `p → q` about the face's normal).
#[derive(Clone, Copy, Debug)]
pub(in crate::geodesic) struct Virtual {
    pub(in crate::geodesic) p: Point3,
    pub(in crate::geodesic) q: Point3,
    pub(in crate::geodesic) sigma: Real,
    pub(in crate::geodesic) face: u32,
    pub(in crate::geodesic) run_on: [[RunOn; 2]; 2],
}

impl Virtual {
    /// A point source at `p` with offset `sigma`, in the plane of `face`.
    pub(in crate::geodesic) fn point(p: Point3, sigma: Real, face: u32) -> Self {
        Virtual {
            p,
            q: p,
            sigma,
            face,
            run_on: [[RunOn::NONE; 2]; 2],
        }
    }
}

impl Virtual {
    /// The distance it offers `x` (in its plane, whose normal is `normal`): `σ` plus the way
    /// to its nearest point, its segment run on as its ends allow (at most `reach`).
    #[inline]
    pub(in crate::geodesic) fn distance(&self, x: &Point3, normal: &Vector3, reach: Real) -> Real {
        self.sigma + (x - foot(x, &self.p, &self.q, &self.run_on, normal, reach)).norm()
    }
}

/// The smallest rotation taking unit `n1` to unit `n2` (Rodrigues, with `k = n1 × n2`:
/// `R w = c·w + k × w + k (k·w) / (1 + c)`, `c = n1·n2`), kept to turn several vectors
/// between the same two faces.
#[derive(Clone, Copy)]
pub(in crate::geodesic) struct Rotation {
    pub(in crate::geodesic) c: Real,
    k: Vector3,
}

impl Rotation {
    #[inline(always)]
    pub(in crate::geodesic) fn new(n1: &Vector3, n2: &Vector3) -> Self {
        Rotation {
            c: n1.dot(n2),
            k: n1.cross(n2),
        }
    }

    #[inline(always)]
    pub(in crate::geodesic) fn apply(&self, w: Vector3) -> Vector3 {
        let k = &self.k;
        w * self.c + k.cross(&w) + k * (k.dot(&w) / (1.0 + self.c))
    }

    /// The inverse rotation applied to `w`: the rotation from `n2` to `n1` (its axis is
    /// `−k`; negating is exact, so this equals `Rotation::new(n2, n1).apply(w)` to the bit).
    #[inline(always)]
    pub(in crate::geodesic) fn unapply(&self, w: Vector3) -> Vector3 {
        let k = &self.k;
        w * self.c - k.cross(&w) + k * (k.dot(&w) / (1.0 + self.c))
    }
}

/// Where the ray `f + τ·w` (τ in `[0, 1]`, in the plane of normal `n`) crosses the edge
/// `pa – pb`: `τ`, or `None` when it misses the edge or runs along its line (then it reaches
/// the ray's end through `pa` or `pb` only), within [`CROSSING_TOLERANCE`].
#[inline(always)]
pub(in crate::geodesic) fn crossing(
    f: &Point3,
    w: &Vector3,
    pa: &Point3,
    pb: &Point3,
    n: &Vector3,
) -> Option<Real> {
    let e = pb - pa;
    let den = e.cross(w).dot(n);
    let tol2 = CROSSING_TOLERANCE * CROSSING_TOLERANCE * e.norm_squared();
    if den * den <= tol2 * w.norm_squared() {
        return None;
    }
    // f + τ w = a + λ e.
    let fa = f - pa;
    let lambda = fa.cross(w).dot(n) / den;
    let tau = fa.cross(&e).dot(n) / den;
    let within = -CROSSING_TOLERANCE..=1.0 + CROSSING_TOLERANCE;
    (within.contains(&lambda) && within.contains(&tau)).then_some(tau)
}

/// The corners of triangle `tri` after its corner `u`, in order.
#[inline(always)]
pub(in crate::geodesic) fn corners_after(tri: [u32; 3], u: usize) -> (usize, usize) {
    let (p, q) = if tri[0] as usize == u {
        (tri[1], tri[2])
    } else if tri[1] as usize == u {
        (tri[2], tri[0])
    } else {
        (tri[0], tri[1])
    };
    (p as usize, q as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotate(w: Vector3, n1: &Vector3, n2: &Vector3) -> Vector3 {
        Rotation::new(n1, n2).apply(w)
    }

    #[test]
    fn the_inverse_rotation_is_the_rotation_back_to_the_bit() {
        let n1 = Vector3::new(0.1, -0.3, 0.7).normalize();
        let n2 = Vector3::new(0.4, 0.2, 0.9).normalize();
        for w in [
            Vector3::new(0.3, -1.2, 0.05),
            Vector3::new(-7.0, 0.001, 3.3),
        ] {
            let back = rotate(w, &n2, &n1);
            assert_eq!(Rotation::new(&n1, &n2).unapply(w), back);
        }
    }

    #[test]
    fn rotation_takes_one_normal_to_the_other_and_keeps_lengths() {
        let n1 = Vector3::new(0.0, 0.0, 1.0);
        let n2 = Vector3::new(0.6, 0.0, 0.8);
        let r = rotate(n1, &n1, &n2);
        assert!((r - n2).norm() < 1e-15);
        let w = Vector3::new(0.3, -1.2, 0.0);
        let rw = rotate(w, &n1, &n2);
        assert!((rw.norm() - w.norm()).abs() < 1e-14);
        assert!(rw.dot(&n2).abs() < 1e-14, "stays in the new plane");
        // The axis n1 × n2 = y is fixed.
        let y = Vector3::new(0.0, 1.0, 0.0);
        assert!((rotate(y, &n1, &n2) - y).norm() < 1e-15);
    }
}
