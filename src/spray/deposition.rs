//! Coating thickness left by a trajectory: parabolic deposition with the curved-surface
//! correction, summed over time samples.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), claims 5–7 as restated in SEEDS.md:
//! planar rate `f(r) = A(1 − r²/R²)` for `r ≤ R`, `R = h·tan(α/2)`, `A = 2ηQ/(πR²)`
//! (mass balance `∫f dA = ηQ`); on the surface `F(M') = F(M)·(h/l)²·cos λ / cos θ` with `l`
//! the axial distance of `M'` from the gun, `θ` the ray's angle to the gun axis, `λ` the
//! angle between the ray and the surface normal at `M'`; `cos λ ≤ 0` gets nothing. The patent
//! cuts the trajectory into time samples; here each straight piece is integrated over the
//! chord of every point in its cone by Gauss–Legendre (see [`deposit`]).
//! Input:  tool path (gun-on moves), evaluation samples bucketed in a [`PointGrid`].
//! Output: thickness per sample, mesh unit.
//! Cost:   O(pieces × points near a piece × 3 rate evaluations): a piece is at most
//!         [`CHUNK_RADIUS_RATIO`]·R long and visits the grid cells of its swept cone,
//!         truncated at an axial distance of [`MAX_AXIAL_RATIO`]·h; each point gets about
//!         `2R / piece + 1` pieces × 3 evaluations instead of `2R / (v·Δt)` time steps.
//!         Where the speed changes within a piece, the quadratic through the chord's three
//!         Gauss nodes (the rate itself on a plane under a constant axis) is integrated over
//!         each stretch of one speed, so per-move speeds cost no extra rate evaluations.
//! Deviations: occlusion by other parts of the mesh is ignored (every point in the cone
//!         with `cos λ > 0` is coated); points farther than `MAX_AXIAL_RATIO·h` along the axis
//!         are ignored; the gun moves at constant speed along every gun-on move (arcs
//!         included; `v`, or the move's own speed when the path has per-move speeds),
//!         position interpolated linearly and axis normalised-linearly between poses; the
//!         chord is that of the piece's straight line under its mean axis (the rate itself
//!         uses the exact interpolated pose), so where the axis turns within a piece (at most
//!         [`CHUNK_TURN_RAD`]) or the path leaves the line (its travel turning by at most
//!         [`CHUNK_TURN_RAD`], or by more while every pose stays within
//!         [`CHORD_TOLERANCE_RATIO`]·R of the line) the ends of the chord are approximate;
//!         pieces moving along their axis are time-stepped at the midpoints of steps `v·Δt`.
//!         (The tolerance serves faceted skins: there a pass steps between the offsets of
//!         neighbouring faces, its travel turning by 30–55° at every face for a few
//!         millimetres; on the wing-body model's fuselage skin this made pieces of two moves,
//!         4,556 of them for 114 m of passes. Within 0.005·R of the line the pieces are
//!         longer and the deposition 1.6 times faster, its largest difference from a time
//!         step of R/400 going from 0.74 % to 0.78 % of the mean thickness.)

use super::grid::PointGrid;
use super::params::{SprayError, MAX_TIME_SAMPLES};
use super::samples::EvaluationSamples;
use crate::math::{Point3, Real, Vector3};
use crate::toolpath::{Pose, ToolPath};

/// Points farther than this multiple of the standoff along the gun axis get nothing.
pub const MAX_AXIAL_RATIO: Real = 1.5;

/// The spray model: footprint radius `R`, peak rate `A`, standoff `h`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SprayModel {
    /// Footprint radius `R` on the plane at the standoff.
    pub radius: Real,
    /// Peak rate `A`, mesh unit of thickness per second.
    pub peak_rate: Real,
    /// Standoff `h`.
    pub standoff: Real,
}

impl SprayModel {
    /// Rate `F(M')` at offset `w` from the gun (axis `a`, unit) on a surface of normal `n`.
    #[inline]
    pub fn rate(&self, w: &Vector3, a: &Vector3, n: &Vector3) -> Real {
        let l = w.dot(a);
        if l <= 0.0 || l > MAX_AXIAL_RATIO * self.standoff {
            return 0.0;
        }
        // cos λ > 0 ⇔ −w·n > 0 (the distance |w| is positive).
        let wn = -w.dot(n);
        if wn <= 0.0 {
            return 0.0;
        }
        let rho2 = at_least(w.norm_squared() - l * l, 0.0);
        // r on the plane at distance h along the same ray: r² = ρ²·h²/l².
        let inv_l = 1.0 / l;
        let h_over_l2 = self.standoff * self.standoff * inv_l * inv_l;
        // h²/R² does not depend on the point: the compiler takes the division out of loops.
        let r2_over_big_r2 =
            rho2 * inv_l * inv_l * (self.standoff * self.standoff / (self.radius * self.radius));
        if r2_over_big_r2 >= 1.0 {
            return 0.0;
        }
        // cos λ / cos θ = (−w·n/|w|) / (l/|w|) = −w·n / l: no square root.
        self.peak_rate * (1.0 - r2_over_big_r2) * h_over_l2 * wn * inv_l
    }
}

/// `max(x, lo)` for finite values by one comparison: `f64::max` also handles NaN, which
/// WebAssembly's own `max` does not, so it becomes a call there, in the innermost loop.
#[inline]
fn at_least(x: Real, lo: Real) -> Real {
    if x < lo {
        lo
    } else {
        x
    }
}

/// `min(x, hi)` for finite values by one comparison (see [`at_least`]).
#[inline]
fn at_most(x: Real, hi: Real) -> Real {
    if x > hi {
        hi
    } else {
        x
    }
}

/// Number of time samples the trajectory takes at step `v·Δt` (a real number: a tiny step
/// makes more than any integer type holds), and the length of its gun-on moves.
pub fn time_sample_count(path: &ToolPath, step_length: Real) -> (Real, Real) {
    let (mut count, mut total) = (0.0, 0.0);
    for pair in path.poses.windows(2) {
        if pair[1].kind.process_on() {
            let length = (pair[1].position - pair[0].position).norm();
            count += (length / step_length).ceil();
            total += length;
        }
    }
    (count, total)
}

/// Gauss–Legendre nodes on `[-1, 1]` (3 points: exact for polynomials of degree 5).
const GAUSS_NODES: [Real; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
/// Gauss–Legendre weights matching [`GAUSS_NODES`].
const GAUSS_WEIGHTS: [Real; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
/// Longest run of gun-on moves integrated as one piece, as a multiple of `R`.
pub const CHUNK_RADIUS_RATIO: Real = 4.0;
/// Largest turn (radians) of the gun axis or of the travel direction within one piece.
pub const CHUNK_TURN_RAD: Real = 0.1;
/// A piece may turn its travel by more than [`CHUNK_TURN_RAD`] while its poses stay within
/// this fraction of `R` of its chord (a pass stepping between the offsets of a faceted
/// surface's faces).
pub const CHORD_TOLERANCE_RATIO: Real = 0.005;
/// Most moves of a piece that turns by more than [`CHUNK_TURN_RAD`] (bounds the work of
/// checking its poses against its chord).
const MAX_PIECE_MOVES: usize = 64;
/// A piece whose travel has `1 − k·(u·a)² ` below this (`k = 1 + R²/h²`, `u` the travel,
/// `a` the axis) moves too much along its axis for the chord formula; it is time-stepped.
const MIN_LATERAL: Real = 0.5;
/// A piece whose poses' axes differ by at most this (unit vectors), whose poses lie within
/// this fraction of its length from its chord and whose length is within it of the chord's
/// is integrated as a straight line under its first axis.
const STRAIGHT_TOLERANCE: Real = 1e-9;

/// Thickness per sample after spraying `path`: at speed `speed` along every gun-on move, or
/// at the path's per-move speeds ([`ToolPath::speeds`]) when it has them.
///
/// Consecutive gun-on moves are grouped into pieces of at most
/// [`CHUNK_RADIUS_RATIO`]·R whose axis and direction turn by at most [`CHUNK_TURN_RAD`]. For
/// each sample near a piece, the chord of the piece's straight line (start to end, mean axis)
/// inside the cone is found in closed form (a quadratic in the line parameter), and the rate
/// is integrated over that chord by Gauss–Legendre at the exact interpolated poses (over
/// each stretch of one speed, the quadratic through the three nodes). On a plane under a
/// constant axis the rate along the chord is a parabola, so both are exact there. On a
/// straight piece under one axis (a pass along a flat or ruled strip) the gun's position is
/// linear in arc length and is not looked up move by move. Pieces moving nearly along their
/// axis fall back to midpoint time steps of `time_step`, which also bounds the work
/// ([`MAX_TIME_SAMPLES`]).
pub fn deposit(
    path: &ToolPath,
    samples: &EvaluationSamples,
    grid: &PointGrid,
    model: &SprayModel,
    speed: Real,
    time_step: Real,
) -> Result<Vec<Real>, SprayError> {
    deposit_except(path, samples, grid, model, speed, time_step, None)
}

/// [`deposit`], leaving 0 on the samples marked in `known` (their thickness is known
/// already, from the speed optimiser): they are not visited at all.
pub(super) fn deposit_except(
    path: &ToolPath,
    samples: &EvaluationSamples,
    grid: &PointGrid,
    model: &SprayModel,
    speed: Real,
    time_step: Real,
    known: Option<&[bool]>,
) -> Result<Vec<Real>, SprayError> {
    let step_length = check_time_samples(path, speed, time_step)?;
    let mut thickness = vec![0.0; samples.positions.len()];
    let varying = path.has_varying_speed();
    let move_speed = |i: usize| if varying { path.move_speed(i) } else { speed };
    let mut inverse_speeds: Vec<Real> = Vec::new();
    for_each_segmented_piece(
        path,
        model,
        move_speed,
        |range, cumulative, starts, speeds| {
            // Multiplications per chord and stretch below, not divisions.
            inverse_speeds.clear();
            inverse_speeds.extend(speeds.iter().map(|v| 1.0 / v));
            deposit_piece(
                &path.poses[range],
                cumulative,
                starts,
                samples,
                grid,
                model,
                step_length,
                known,
                |i, segment, v| thickness[i] += v * inverse_speeds[segment],
            );
        },
    );
    Ok(thickness)
}

/// Refuses a time step that would cut the trajectory into more than [`MAX_TIME_SAMPLES`];
/// returns the step length `speed·time_step`.
pub(super) fn check_time_samples(
    path: &ToolPath,
    speed: Real,
    time_step: Real,
) -> Result<Real, SprayError> {
    let step_length = speed * time_step;
    let (count, length) = time_sample_count(path, step_length);
    if count.is_nan() || count > MAX_TIME_SAMPLES as Real {
        return Err(SprayError::TooManyTimeSamples {
            time_step,
            length,
            samples: count,
            // Each move's steps round up: a tenth more than the lengths alone ask.
            suggestion: 1.1 * length / (MAX_TIME_SAMPLES as Real * speed),
        });
    }
    Ok(step_length)
}

/// Whether every pose lies within `tolerance` of the line from the first to the last, their
/// projections on it advancing.
fn near_chord(poses: &[Pose], tolerance: Real) -> bool {
    let (a, b) = (poses[0].position, poses[poses.len() - 1].position);
    let chord = b - a;
    let line = chord.norm();
    if line <= 0.0 || !line.is_finite() {
        return false;
    }
    let u = chord / line;
    let mut last = 0.0;
    for p in &poses[1..] {
        let w = p.position - a;
        let along = w.dot(&u);
        if along < last || (w - u * along).norm_squared() > tolerance * tolerance {
            return false;
        }
        last = along;
    }
    true
}

/// Cuts the gun-on moves of `path` into pieces of at most [`CHUNK_RADIUS_RATIO`]·R whose axis
/// turns by at most [`CHUNK_TURN_RAD`], and whose travel does too unless every pose lies
/// within [`CHORD_TOLERANCE_RATIO`]·R of the chord (at most [`MAX_PIECE_MOVES`] moves then);
/// calls `visit(poses, arc lengths)` for each piece, the poses given as a range of
/// `path.poses`.
pub(super) fn for_each_piece(
    path: &ToolPath,
    model: &SprayModel,
    mut visit: impl FnMut(std::ops::Range<usize>, &[Real]),
) {
    let poses = &path.poses;
    let max_length = CHUNK_RADIUS_RATIO * model.radius;
    let cos_turn = libm::cos(CHUNK_TURN_RAD);
    let tolerance = CHORD_TOLERANCE_RATIO * model.radius;
    let mut cumulative: Vec<Real> = Vec::new();
    let mut j = 0;
    // Each round consumes at least one pose, so the loop ends.
    while j + 1 < poses.len() {
        if !poses[j + 1].kind.process_on() {
            j += 1;
            continue;
        }
        // Grow a piece from pose j.
        let start = j;
        cumulative.clear();
        cumulative.push(0.0);
        let mut first_dir: Option<Vector3> = None;
        let mut end = j;
        while end + 1 < poses.len() && poses[end + 1].kind.process_on() {
            let step = poses[end + 1].position - poses[end].position;
            let length = step.norm();
            let total = cumulative[cumulative.len() - 1] + length;
            if end > start
                && (total > max_length
                    || poses[end + 1].axis.dot(&poses[start].axis) < cos_turn
                    || (first_dir
                        .is_some_and(|d| length > 0.0 && step.dot(&d) < cos_turn * length)
                        && (end - start >= MAX_PIECE_MOVES
                            || !near_chord(&poses[start..end + 2], tolerance))))
            {
                break;
            }
            if first_dir.is_none() && length > 0.0 {
                first_dir = Some(step / length);
            }
            cumulative.push(total);
            end += 1;
        }
        visit(start..end + 1, &cumulative);
        j = end;
    }
}

/// [`for_each_piece`], each piece cut into segments where `key(k)` changes (`k` the move
/// arriving at pose `k`): calls `visit(poses, arc lengths, segment starts, segment keys)`,
/// the starts as arc lengths from the piece's start.
pub(super) fn for_each_segmented_piece<K: PartialEq + Copy>(
    path: &ToolPath,
    model: &SprayModel,
    key: impl Fn(usize) -> K,
    mut visit: impl FnMut(std::ops::Range<usize>, &[Real], &[Real], &[K]),
) {
    let (mut starts, mut keys): (Vec<Real>, Vec<K>) = (Vec::new(), Vec::new());
    for_each_piece(path, model, |range, cumulative| {
        starts.clear();
        keys.clear();
        for (m, k) in (range.start + 1..range.end).enumerate() {
            let this = key(k);
            if keys.last() != Some(&this) {
                starts.push(cumulative[m]);
                keys.push(this);
            }
        }
        visit(range, cumulative, &starts, &keys);
    });
}

/// Bounding box of the cone at `gun` along `axis`, truncated at the axial reach.
fn cone_box(model: &SprayModel, gun: &Point3, axis: &Vector3) -> (Vector3, Vector3) {
    let reach = MAX_AXIAL_RATIO * model.standoff;
    let spread = model.radius * MAX_AXIAL_RATIO;
    let tip = gun.coords + axis * reach;
    let half = axis.map(|c| spread * (1.0 - c * c).max(0.0).sqrt());
    (gun.coords.inf(&(tip - half)), gun.coords.sup(&(tip + half)))
}

/// The cone of a gun at `origin + s·(across + ua·axis)`, `s` in `[0, line]`, along `axis`
/// (unit), of half-angle `atan(tan)`, truncated at `reach` along the axis: the points `p`
/// with `0 < l ≤ reach` and `|w − l·axis| < tan·l` for some `s`, where `w = p − gun(s)` and
/// `l = w·axis` (the chord's cone in [`deposit_piece`]).
struct SweptCone {
    origin: Point3,
    axis: Vector3,
    /// The travel's part across the axis (the travel is unit).
    across: Vector3,
    line: Real,
    /// The travel's part along the axis.
    ua: Real,
    tan: Real,
    reach: Real,
}

impl SweptCone {
    /// Whether the ball of `radius` about `c` may hold points of the cone (false only when
    /// it holds none): along the axis every point of the ball is within `radius` of `c`'s
    /// range over the sweep, and across it no nearer to the swept axis than `c` less
    /// `radius`.
    fn may_meet(&self, c: &Point3, radius: Real) -> bool {
        let w = c - self.origin;
        let l = w.dot(&self.axis);
        let l_end = l - self.line * self.ua;
        let (l_lo, l_hi) = if l < l_end { (l, l_end) } else { (l_end, l) };
        if l_hi + radius <= 0.0 || l_lo - radius > self.reach {
            return false;
        }
        // Distance across the axis from the swept axis (a segment in the plane across).
        let w_across = w - self.axis * l;
        let across2 = self.across.norm_squared();
        let t = if across2 > 0.0 {
            at_most(
                at_least(w_across.dot(&self.across) / across2, 0.0),
                self.line,
            )
        } else {
            0.0
        };
        let d = (w_across - self.across * t).norm() - radius;
        let cone = self.tan * at_most(l_hi + radius, self.reach);
        d <= 0.0 || d * d <= cone * cone * (1.0 + 1e-9)
    }
}

/// Gun position and unit axis at arc length `sigma` along a piece (`inverse`: one over each
/// move's length, 0 for a move of none); `hint` is the move the previous call ended in (the
/// search walks on from there when `sigma` lies further on, as it does along one chord) and
/// is updated.
fn pose_at(
    poses: &[Pose],
    cumulative: &[Real],
    inverse: &[Real],
    sigma: Real,
    hint: &mut usize,
) -> (Point3, Vector3) {
    let last = cumulative.len() - 2;
    // The first move whose end lies at or beyond sigma.
    let mut k = (*hint).min(last);
    if k > 0 && cumulative[k] >= sigma {
        k = cumulative[1..].partition_point(|&c| c < sigma).min(last);
    } else {
        // Each step moves one move on, so the walk ends at `last`.
        while k < last && cumulative[k + 1] < sigma {
            k += 1;
        }
    }
    *hint = k;
    let (p0, p1) = (&poses[k], &poses[k + 1]);
    let tau = if inverse[k] > 0.0 {
        ((sigma - cumulative[k]) * inverse[k]).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let gun = p0.position + (p1.position - p0.position) * tau;
    if p0.axis == p1.axis {
        // A move under one axis (a pass along a flat or ruled strip): nothing to blend.
        return (gun, p0.axis);
    }
    // One division, not three (nalgebra's normalize divides each component).
    let axis = p0.axis * (1.0 - tau) + p1.axis * tau;
    (gun, axis * (1.0 / axis.norm()))
}

/// Hands `add(sample, segment, ∫ rate ds)` the coating of one piece (`poses`, arc lengths
/// `cumulative` from its start) per unit of gun speed, split into the segments of the piece
/// that start at the arc lengths `segments` (increasing, the first 0): divided by the
/// segment's speed, it is the thickness added. A sample may be handed more than once;
/// samples marked in `skip` are not.
#[allow(clippy::too_many_arguments)]
pub(super) fn deposit_piece(
    poses: &[Pose],
    cumulative: &[Real],
    segments: &[Real],
    samples: &EvaluationSamples,
    grid: &PointGrid,
    model: &SprayModel,
    step_length: Real,
    skip: Option<&[bool]>,
    mut add: impl FnMut(usize, usize, Real),
) {
    let arc = cumulative[cumulative.len() - 1];
    if arc <= 0.0 || segments.is_empty() {
        return;
    }
    let (first, last) = (&poses[0], &poses[poses.len() - 1]);
    let chord = last.position - first.position;
    let line = chord.norm();
    let mean_axis = (first.axis + last.axis).normalize();
    let k = 1.0 + (model.radius * model.radius) / (model.standoff * model.standoff);
    let u = if line > 0.0 {
        chord / line
    } else {
        Vector3::zeros()
    };
    let ua = u.dot(&mean_axis);
    let c2 = 1.0 - k * ua * ua;
    if line <= 0.0 || c2 < MIN_LATERAL || !mean_axis.iter().all(|c| c.is_finite()) {
        deposit_stepped(
            poses,
            cumulative,
            segments,
            samples,
            grid,
            model,
            step_length,
            skip,
            &mut add,
        );
        return;
    }
    let reach = MAX_AXIAL_RATIO * model.standoff;
    let (lo0, hi0) = cone_box(model, &first.position, &first.axis);
    let (lo1, hi1) = cone_box(model, &last.position, &last.axis);
    // The axis turns by at most CHUNK_TURN_RAD inside the piece: widen by that much.
    let margin = Vector3::repeat(reach * CHUNK_TURN_RAD);
    let (lo, hi) = (lo0.inf(&lo1) - margin, hi0.sup(&hi1) + margin);
    let to_arc = arc / line;
    // Multiplications in the loop below, not divisions (ua is only used when non-zero).
    let inverse: Vec<Real> = cumulative
        .windows(2)
        .map(|c| {
            // 0 also for a length so small its inverse overflows: the move's middle then.
            let inverse = 1.0 / (c[1] - c[0]);
            if inverse.is_finite() && inverse > 0.0 {
                inverse
            } else {
                0.0
            }
        })
        .collect();
    let inv_c2 = 1.0 / c2;
    let inv_ua = if ua != 0.0 { 1.0 / ua } else { 0.0 };
    // A straight piece under one axis (a pass along a flat or ruled strip): the gun moves
    // along the chord at a constant rate of arc length, so a pose needs no search.
    let straight = arc <= line * (1.0 + STRAIGHT_TOLERANCE)
        && poses.iter().all(|p| {
            (p.axis - first.axis).norm_squared() <= STRAIGHT_TOLERANCE * STRAIGHT_TOLERANCE && {
                let w = p.position - first.position;
                let along = w.dot(&u);
                (w - u * along).norm_squared() <= (STRAIGHT_TOLERANCE * line).powi(2)
            }
        });
    let step = chord / arc;
    // A cell is visited only if its bounding sphere can meet the swept cone, the set the
    // chord below is cut from.
    let swept = SweptCone {
        origin: first.position,
        axis: mean_axis,
        across: u - mean_axis * ua,
        line,
        ua,
        tan: (k - 1.0).sqrt(),
        reach,
    };
    let near = |c: &Point3, radius: Real| swept.may_meet(c, radius);
    grid.for_each_in_box_near(&lo, &hi, near, |i| {
        if skip.is_some_and(|s| s[i]) {
            return;
        }
        let q = samples.positions[i];
        let w0 = q - first.position;
        let l0 = w0.dot(&mean_axis);
        // Inside the cone: |w(s)|² − k·l(s)² < 0 with w(s) = w0 − s·u, l(s) = l0 − s·ua.
        let b1 = w0.dot(&u) - k * l0 * ua;
        let c0 = w0.norm_squared() - k * l0 * l0;
        let disc = b1 * b1 - c2 * c0;
        if disc <= 0.0 {
            return;
        }
        let root = disc.sqrt();
        let mut s0 = at_least((b1 - root) * inv_c2, 0.0);
        let mut s1 = at_most((b1 + root) * inv_c2, line);
        // In front of the gun (l > 0) and within the reach (l ≤ reach); l is linear in s.
        if ua > 0.0 {
            s1 = at_most(s1, l0 * inv_ua);
            s0 = at_least(s0, (l0 - reach) * inv_ua);
        } else if ua < 0.0 {
            s0 = at_least(s0, l0 * inv_ua);
            s1 = at_most(s1, (l0 - reach) * inv_ua);
        } else if l0 <= 0.0 || l0 > reach {
            return;
        }
        if s1 <= s0 {
            return;
        }
        // The chord in arc length; the rate at its three Gauss nodes.
        let (a0, a1) = (s0 * to_arc, s1 * to_arc);
        let (mid, half) = (0.5 * (a0 + a1), 0.5 * (a1 - a0));
        let n = &samples.normals[i];
        let f = if straight {
            GAUSS_NODES.map(|x| {
                let gun = first.position + step * (mid + half * x);
                model.rate(&(q - gun), &first.axis, n)
            })
        } else {
            // The move the chord starts in; the nodes along it walk on from there.
            let mut hint = cumulative[1..].partition_point(|&c| c < a0);
            GAUSS_NODES.map(|x| {
                let (gun, axis) = pose_at(poses, cumulative, &inverse, mid + half * x, &mut hint);
                model.rate(&(q - gun), &axis, n)
            })
        };
        let first = segments.partition_point(|&x| x <= a0).saturating_sub(1);
        if segments.get(first + 1).is_none_or(|&x| x >= a1) {
            // One segment: Gauss–Legendre over the chord.
            let sum: Real = f.iter().zip(&GAUSS_WEIGHTS).map(|(f, w)| f * w).sum();
            if sum > 0.0 {
                add(i, first, sum * half);
            }
            return;
        }
        // Several: the quadratic through the three nodes (the rate itself on a plane under
        // a constant axis), integrated over each stretch; the stretches sum to the
        // Gauss–Legendre value.
        // Its antiderivative αt³ + βt² + γt in t ∈ [−1, 1] (nodes at 0 and ±c).
        let c = GAUSS_NODES[2];
        let alpha = (f[0] + f[2] - 2.0 * f[1]) * (1.0 / (6.0 * c * c));
        let beta = (f[2] - f[0]) * (1.0 / (4.0 * c));
        let gamma = f[1];
        let integral = |t: Real| ((alpha * t + beta) * t + gamma) * t;
        let inv_half = 1.0 / half;
        let mut lower = integral(-1.0);
        let mut segment = first;
        // Each round moves to the next segment, so the loop ends.
        while segment < segments.len() {
            let to = segments.get(segment + 1).map_or(a1, |&x| at_most(x, a1));
            let upper = integral(at_least(at_most((to - mid) * inv_half, 1.0), -1.0));
            let v = half * (upper - lower);
            if v > 0.0 {
                add(i, segment, v);
            }
            if to >= a1 {
                break;
            }
            lower = upper;
            segment += 1;
        }
    });
}

/// Midpoint time steps of length `step_length` over every move of a piece (per unit speed),
/// each handed to the segment its midpoint lies in.
#[allow(clippy::too_many_arguments)]
fn deposit_stepped(
    poses: &[Pose],
    cumulative: &[Real],
    segments: &[Real],
    samples: &EvaluationSamples,
    grid: &PointGrid,
    model: &SprayModel,
    step_length: Real,
    skip: Option<&[bool]>,
    add: &mut impl FnMut(usize, usize, Real),
) {
    for (m, pair) in poses.windows(2).enumerate() {
        let (p0, p1) = (&pair[0], &pair[1]);
        let length = (p1.position - p0.position).norm();
        if length <= 0.0 {
            continue;
        }
        let middle = 0.5 * (cumulative[m] + cumulative[m + 1]);
        let segment = segments.partition_point(|&x| x <= middle).saturating_sub(1);
        let n = (length / step_length).ceil().max(1.0) as usize;
        let ds = length / n as Real;
        for s in 0..n {
            let tau = (s as Real + 0.5) / n as Real;
            let gun = p0.position + (p1.position - p0.position) * tau;
            let axis = (p0.axis * (1.0 - tau) + p1.axis * tau).normalize();
            let (lo, hi) = cone_box(model, &gun, &axis);
            grid.for_each_in_box(&lo, &hi, |i| {
                if skip.is_some_and(|s| s[i]) {
                    return;
                }
                let w = samples.positions[i] - gun;
                let f = model.rate(&w, &axis, &samples.normals[i]);
                if f > 0.0 {
                    add(i, segment, f * ds);
                }
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether `p` lies in the swept cone, by the definition, over `steps` gun positions.
    fn inside(cone: &SweptCone, p: &Point3, steps: usize) -> bool {
        (0..=steps).any(|j| {
            let s = cone.line * j as Real / steps as Real;
            let gun = cone.origin + (cone.across + cone.axis * cone.ua) * s;
            let w = p - gun;
            let l = w.dot(&cone.axis);
            l > 0.0 && l <= cone.reach && (w - cone.axis * l).norm() < cone.tan * l
        })
    }

    use crate::toolpath::PoseKind;

    /// A gun looking down −z from height 1 along x, stepping sideways by `amplitude` (the
    /// offsets of neighbouring faces) every `step` with a transition `jog` long: its travel
    /// turns by `atan(amplitude / jog)` at every step.
    pub(super) fn staircase(amplitude: Real, step: Real, jog: Real, steps: usize) -> ToolPath {
        let pose = |x: Real, y: Real, kind: PoseKind| Pose {
            position: Point3::new(x, y, 1.0),
            axis: -Vector3::z(),
            travel: Vector3::x(),
            kind,
            pass: 0,
        };
        let mut poses = vec![
            pose(-0.1, 0.0, PoseKind::Link),
            pose(0.0, 0.0, PoseKind::Link),
        ];
        let mut x = 0.0;
        for k in 0..steps {
            let y = if k % 2 == 0 { 0.0 } else { amplitude };
            x += step;
            poses.push(pose(x, y, PoseKind::Pass));
            x += jog;
            let next = if k % 2 == 0 { amplitude } else { 0.0 };
            poses.push(pose(x, next, PoseKind::StraightTransition));
        }
        ToolPath {
            poses,
            speed: 1.0,
            link_speed: 1.0,
            speeds: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// Samples on the plane z = 0 under the staircase, `spacing` apart.
    pub(super) fn plane_samples(
        length: Real,
        half_width: Real,
        spacing: Real,
    ) -> EvaluationSamples {
        let (nx, ny) = (
            (length / spacing).round() as usize,
            (2.0 * half_width / spacing).round() as usize,
        );
        let mut samples = EvaluationSamples::default();
        for i in 0..=nx {
            for j in 0..=ny {
                let p = Point3::new(i as Real * spacing, j as Real * spacing - half_width, 0.0);
                samples.positions.push(p);
                samples.normals.push(Vector3::z());
                samples.weights.push(spacing * spacing);
            }
        }
        samples
    }

    /// A pass stepping sideways by less than the chord tolerance at every face is cut into
    /// few pieces, and deposits as a fine time step does; one stepping by more is cut at
    /// every step, as before.
    #[test]
    fn a_pass_stepping_within_the_chord_tolerance_is_one_piece_and_deposits_as_time_steps() {
        let model = SprayModel {
            radius: 0.4,
            peak_rate: 1.0,
            standoff: 1.0,
        };
        let tolerance = CHORD_TOLERANCE_RATIO * model.radius;
        let (step, jog, steps) = (0.05, 0.005, 40);
        let pieces = |path: &ToolPath| {
            let mut count = 0;
            for_each_piece(path, &model, |_, _| count += 1);
            count
        };
        // Travel turns by about 11° at every step, sideways by half the tolerance (or by five
        // times it).
        let fine = staircase(0.5 * tolerance, step, jog, steps);
        let coarse = staircase(5.0 * tolerance, step, jog, steps);
        let length = steps as Real * (step + jog);
        let by_length = (length / (CHUNK_RADIUS_RATIO * model.radius)).ceil() as usize;
        assert!(pieces(&fine) <= by_length + 1, "{} pieces", pieces(&fine));
        assert!(pieces(&coarse) >= steps, "{} pieces", pieces(&coarse));
        let samples = plane_samples(length, 0.5, 0.02);
        let grid = PointGrid::new(&samples.positions, 0.5 * model.radius);
        // Merged, the Gauss nodes see the steps at three places per chord: within a few
        // tenths of a percent of the peak for steps of half the tolerance; cut at every
        // step, the chords are exact but for rounding.
        for (path, bound) in [(&fine, 3e-3), (&coarse, 1e-5)] {
            let chords = deposit(path, &samples, &grid, &model, 1.0, 1.0).unwrap();
            let mut stepped = vec![0.0; samples.positions.len()];
            let cumulative: Vec<Real> = std::iter::once(0.0)
                .chain(path.poses[1..].windows(2).scan(0.0, |c, w| {
                    *c += (w[1].position - w[0].position).norm();
                    Some(*c)
                }))
                .collect();
            deposit_stepped(
                &path.poses[1..],
                &cumulative,
                &[0.0],
                &samples,
                &grid,
                &model,
                model.radius / 1000.0,
                None,
                &mut |i, _, v| stepped[i] += v,
            );
            let peak = stepped.iter().fold(0.0_f64, |m, &t| m.max(t));
            let worst = chords
                .iter()
                .zip(&stepped)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(worst <= bound * peak, "{worst} against a peak of {peak}");
        }
    }

    /// Every ball holding a point of the swept cone is kept; most balls far from it are not.
    #[test]
    fn the_swept_cone_test_keeps_every_ball_that_meets_the_cone() {
        // A gun looking down −z at 100, moving along a direction tilted into the axis.
        let axis = -Vector3::z();
        let travel = Vector3::new(0.8, 0.2, -0.3).normalize();
        let ua = travel.dot(&axis);
        let cone = SweptCone {
            origin: Point3::new(0.0, 0.0, 100.0),
            axis,
            across: travel - axis * ua,
            line: 120.0,
            ua,
            tan: 0.5,
            reach: 150.0,
        };
        let radius = 9.0;
        let (mut met, mut refused) = (0, 0);
        // Ball centres on a lattice; each ball probed at 15 points.
        for i in -6..=12 {
            for j in -6..=6 {
                for k in -4..=7 {
                    let c = Point3::new(20.0 * i as Real, 20.0 * j as Real, 20.0 * k as Real);
                    let keep = cone.may_meet(&c, radius);
                    // The centre, 6 points on the axes and 8 on the diagonals of the ball.
                    let probes = (0..27).filter_map(|n| {
                        let d = Vector3::new(
                            (n % 3) as Real - 1.0,
                            (n / 3 % 3) as Real - 1.0,
                            (n / 9) as Real - 1.0,
                        );
                        let len = d.norm_squared();
                        match len as u32 {
                            0 => Some(c),
                            1 | 3 => Some(c + d * (radius / len.sqrt())),
                            _ => None,
                        }
                    });
                    if probes.into_iter().any(|p| inside(&cone, &p, 24)) {
                        assert!(keep, "a ball at {c:?} meets the cone but was dropped");
                        met += 1;
                    } else if !keep {
                        refused += 1;
                    }
                }
            }
        }
        assert!(met > 100, "only {met} balls meet the cone");
        assert!(refused > 1000, "only {refused} balls refused");
    }
}
