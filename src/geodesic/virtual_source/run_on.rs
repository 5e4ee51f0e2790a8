//! How far a piece of a source curve runs on past its ends, and the nearest point of such a
//! piece to a vertex (the foot every offer of a piece is measured from).
//!
//! Source: none (the virtual sources of Trettner, Bommes & Kobbelt 2021 are points; see
//!         `virtual_source.rs` for pieces of curves as sources, `seeding.rs` for the bounds).
//! Cost:   O(1) a foot; one byte a bound, four a source.

use crate::math::{Point3, Real, Vector3};

/// How far a piece of a source curve runs on beyond one end, for the vertices on one side of
/// it (no paper): `min(L, h·c)` for a vertex at distance `h` from the piece's line, `L` up to
/// the solver's `reach` and `c` a cotangent, both kept in one byte and rounded down.
///
/// Why: beyond the end, up to `L` along the piece's line, the source curve keeps within the
/// wedge between the line moved `RUN_ON_TOLERANCE` (in `seeding.rs`) away from the vertex's
/// side and the ray at angle `φ` (`cot φ = c`) towards it (checked on its samples, see
/// `source_pieces` in `seeding.rs`). Where `s ≤ h·cot φ` past the end, the curve then crosses
/// the perpendicular from the vertex to the line no further from the vertex than the tolerance
/// beyond the line, so the distance to the line, which the piece offers there, is never more
/// than the tolerance below the distance to the curve. Where the curve turns away at its very
/// next sample the piece does not run on for that side (see `seeding.rs`). Run on regardless
/// (by the full reach wherever the curve turned towards the vertex at the end), a piece offered
/// distances up to 0.63 m too short on a real airliner patch, shorter than the straight line to
/// the boundary: past a corner, a hairpin or a turn away further on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(in crate::geodesic) struct RunOn(u8);

impl RunOn {
    /// Stops at the end.
    pub(in crate::geodesic) const NONE: RunOn = RunOn(0);
    /// Runs on by the full reach, whatever the distance from the line.
    pub(in crate::geodesic) const FREE: RunOn = RunOn(u8::MAX);
    /// Steps of the length (in fifteenths of the reach) and code of "no bound on the
    /// cotangent".
    const STEPS: u8 = 15;

    /// The bounds for `length` (a fraction of the reach) and cotangent `cot` (`∞`: none),
    /// rounded down: the length to fifteenths, the cotangent to a power of two from 1/64 to
    /// 256. A cotangent below 1/64 (a turn over 89°), a length under a fifteenth or NaN:
    /// [`RunOn::NONE`].
    pub(in crate::geodesic) fn new(length: Real, cot: Real) -> RunOn {
        let steps = length * Real::from(Self::STEPS);
        if !(steps >= 1.0 && cot >= 1.0 / 64.0) {
            return RunOn::NONE;
        }
        let steps = if steps >= Real::from(Self::STEPS) {
            Self::STEPS
        } else {
            steps as u8
        };
        let cot = if cot == Real::INFINITY {
            Self::STEPS
        } else {
            // ⌊log2 cot⌋ + 6 from the exponent bits (cot ≥ 1/64 is a normal float).
            let exponent = ((cot.to_bits() >> 52) & 0x7ff) as i64 - 1023;
            (exponent + 6).min(i64::from(Self::STEPS) - 1) as u8
        };
        RunOn(steps << 4 | cot)
    }

    /// The tighter bound of the two, each part.
    pub(in crate::geodesic) fn tighter(self, other: RunOn) -> RunOn {
        let (a, b) = (self.0, other.0);
        RunOn((a >> 4).min(b >> 4) << 4 | (a & 15).min(b & 15))
    }

    /// How far to run on for a vertex at distance `h` from the line.
    #[inline]
    pub(super) fn run(self, h: Real, reach: Real) -> Real {
        let steps = self.0 >> 4;
        let mut run = if steps == Self::STEPS {
            reach
        } else {
            reach * Real::from(steps) / Real::from(Self::STEPS)
        };
        let cot = self.0 & 15;
        if cot != Self::STEPS {
            let cot = Real::from_bits(((i64::from(cot) - 6 + 1023) as u64) << 52);
            // A comparison, not `Real::min` (a call to `fmin` in WebAssembly builds).
            if h * cot < run {
                run = h * cot;
            }
        }
        run
    }
}

/// The nearest point to `x` of segment `[p, q]` (in the plane of normal `normal`), run on
/// beyond its ends as `run_on[side]` allows for x's side, `reach` (a length) at most.
#[inline(always)]
pub(in crate::geodesic) fn foot(
    x: &Point3,
    p: &Point3,
    q: &Point3,
    run_on: &[[RunOn; 2]; 2],
    normal: &Vector3,
    reach: Real,
) -> Point3 {
    let e = q - p;
    let l2 = e.norm_squared();
    if l2 > 0.0 {
        let t = (x - p).dot(&e) / l2;
        let end = if t < 0.0 {
            0
        } else if t > 1.0 {
            1
        } else {
            return p + e * t;
        };
        // Left, right, or on the line (rounding): then the nearer bound of the two.
        let lateral = e.cross(&(x - p)).dot(normal);
        let code = if lateral > 0.0 {
            run_on[0][end]
        } else if lateral < 0.0 {
            run_on[1][end]
        } else {
            run_on[0][end].tighter(run_on[1][end])
        };
        if code == RunOn::NONE {
            return if end == 0 { *p } else { *q };
        }
        let run = if code == RunOn::FREE {
            reach
        } else {
            code.run((x - (p + e * t)).norm(), reach)
        };
        // Comparisons, not `Real::max` / `min` (calls in WebAssembly builds).
        let r = run / l2.sqrt();
        let t = if end == 0 {
            if t < -r {
                -r
            } else {
                t
            }
        } else if t > 1.0 + r {
            1.0 + r
        } else {
            t
        };
        p + e * t
    } else {
        *p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn foot_is_the_nearest_point_of_the_segment_run_on_as_its_side_allows() {
        let (p, q) = (Point3::new(0.0, 0.0, 0.0), Point3::new(2.0, 0.0, 0.0));
        let (none, reach, up) = ([[RunOn::NONE; 2]; 2], 1.5, Vector3::z());
        let foot = |x: [Real; 3], run_on: &[[RunOn; 2]; 2]| {
            foot(&Point3::new(x[0], x[1], x[2]), &p, &q, run_on, &up, reach)
        };
        assert_eq!(foot([1.0, 3.0, 0.0], &none), Point3::new(1.0, 0.0, 0.0));
        assert_eq!(foot([-1.0, 3.0, 0.0], &none), p);
        assert_eq!(foot([5.0, 1.0, 0.0], &none), q);
        // Runs on beyond p for the left side (y > 0) only.
        let left = [[RunOn::FREE, RunOn::NONE], [RunOn::NONE; 2]];
        assert_eq!(foot([-1.0, 3.0, 0.0], &left), Point3::new(-1.0, 0.0, 0.0));
        assert_eq!(foot([-9.0, 3.0, 0.0], &left), Point3::new(-reach, 0.0, 0.0));
        assert_eq!(foot([-1.0, -3.0, 0.0], &left), p);
        // Half the reach (7/15 after rounding down), and a cotangent of 1/2 (exact in the
        // code): min(7/15 · 1.5, h / 2).
        let bounded = [[RunOn::new(0.5, 0.5), RunOn::NONE], [RunOn::NONE; 2]];
        assert_eq!(
            foot([-5.0, 3.0, 0.0], &bounded),
            Point3::new(-0.7, 0.0, 0.0)
        );
        assert_eq!(
            foot([-5.0, 1.0, 0.0], &bounded),
            Point3::new(-0.5, 0.0, 0.0)
        );
        // On the line (rounding decides the side): the tighter of the two sides.
        let sides = [
            [RunOn::FREE, RunOn::NONE],
            [RunOn::new(1.0, 0.5), RunOn::NONE],
        ];
        assert_eq!(foot([-1.0, 0.0, 0.0], &sides), p);
    }

    #[test]
    fn run_on_bounds_round_down_and_refuse_steep_turns_and_nan() {
        let code = RunOn::new(1.0, 3.0);
        assert_eq!(code.run(1.0, 10.0), 2.0, "cot 3 rounds down to 2");
        assert_eq!(code.run(100.0, 10.0), 10.0, "the reach bounds it");
        assert_eq!(
            RunOn::new(0.99, Real::INFINITY).run(1e9, 15.0),
            14.0,
            "14/15 of the reach"
        );
        assert_eq!(RunOn::new(2.0, Real::INFINITY), RunOn::FREE);
        for (length, cot) in [
            (0.05, 1.0),
            (1.0, 0.01),
            (Real::NAN, 1.0),
            (1.0, Real::NAN),
            (1.0, -2.0),
        ] {
            assert_eq!(RunOn::new(length, cot), RunOn::NONE, "{length} {cot}");
        }
        assert_eq!(
            RunOn::new(1.0, 1e30).run(1.0, 1e9),
            256.0,
            "the largest bound is 256"
        );
        let tight = RunOn::new(0.5, 8.0).tighter(RunOn::new(1.0, 2.0));
        assert_eq!(tight.run(1.0, 15.0), 2.0);
        assert_eq!(tight.run(10.0, 15.0), 7.0);
    }
}
