//! Tool-frame orientation maths: the frame of a pose, unit quaternions and ZYX Euler angles.
//!
//! Source: the tool frame is this crate's convention (Z = tool axis towards the part, X = travel
//!         direction re-orthogonalised against Z, Y = Z × X). Quaternion from a rotation matrix
//!         by Shepperd's method (S. W. Shepperd, "Quaternion from rotation matrix", J. Guidance
//!         and Control 1(3), 1978): pivot on the largest of 4w², 4x², 4y², 4z². ZYX Euler
//!         angles `R = Rz(A)·Ry(B)·Rx(C)` as in KUKA's KRL manuals (A about Z, then B about the
//!         new Y, then C about the newest X), with the textbook inverse (e.g. Craig,
//!         "Introduction to Robotics", §2.8, X-Y-Z fixed angles).
//! Input:  unit tool axis and travel direction per pose, in execution order.
//! Output: a right-handed orthonormal frame (columns X, Y, Z) per pose; quaternions `[w,x,y,z]`
//!         with sign continuity; Euler angles with A/C unwrapped for continuity.
//! Cost:   O(1) per pose.
//! Deviations (no paper; chosen so the output is deterministic and does not flip):
//!   - travel within [`PARALLEL_SIN_TOL`] of the axis (drilling approach, a degenerate
//!     input): X is the previous pose's X re-orthogonalised against the new Z, or, for the
//!     first pose or when that is parallel too, the world axis least aligned with Z (X, then
//!     Y, then Z on ties) re-orthogonalised;
//!   - quaternions: the first has `w ≥ 0` (ties broken by the first non-zero component being
//!     positive); each next one takes the sign that makes its dot product with the previous one
//!     non-negative, so the controller never sees a spurious 360° turn of the representation;
//!   - Euler angles: B stays on the principal branch [−90°, 90°]; at gimbal lock
//!     (cos B < [`GIMBAL_COS_TOL`]) only A ∓ C is defined and A keeps the previous pose's value
//!     (0 for the first); A and C may be unwrapped by whole turns to stay within 180° of the
//!     previous pose's values while they remain within ±[`UNWRAP_LIMIT_DEG`].

use crate::math::{Real, Vector3};

/// A 3×3 rotation matrix whose columns are the frame's X, Y and Z axes in world coordinates.
pub type Matrix3 = nalgebra::Matrix3<Real>;

/// Travel directions whose component perpendicular to the axis is shorter than this (the
/// sine of the angle between them) count as parallel to the axis: the frame's X then comes
/// from the documented fallback instead.
pub const PARALLEL_SIN_TOL: Real = 1e-6;

/// Below this value of cos B the ZYX Euler angles are at gimbal lock (B = ±90°).
pub const GIMBAL_COS_TOL: Real = 1e-9;

/// Unwrapped Euler angles A and C stay strictly within ± this many degrees; beyond it they
/// are wrapped back into (−180°, 180°].
pub const UNWRAP_LIMIT_DEG: Real = 360.0;

/// The tool frame of one pose: Z = `axis`, X = `travel` re-orthogonalised against Z,
/// Y = Z × X. `previous_x` is the previous pose's X, used only when `travel` is parallel to
/// `axis` (see the module header for the fallback). `axis` must be non-zero.
pub fn tool_frame(axis: &Vector3, travel: &Vector3, previous_x: Option<&Vector3>) -> Matrix3 {
    let z = axis.normalize();
    let x = perpendicular_part(travel, &z)
        .or_else(|| previous_x.and_then(|p| perpendicular_part(p, &z)))
        .unwrap_or_else(|| least_aligned_axis_perpendicular(&z));
    let y = z.cross(&x);
    Matrix3::from_columns(&[x, y, z])
}

/// The tool frames of a sequence of poses given as `(axis, travel)`, with the fallback
/// chained through the previous frame's X.
pub fn tool_frames<'a>(
    poses: impl IntoIterator<Item = (&'a Vector3, &'a Vector3)>,
) -> Vec<Matrix3> {
    let mut frames: Vec<Matrix3> = Vec::new();
    for (axis, travel) in poses {
        let previous_x = frames.last().map(|f| f.column(0).into_owned());
        frames.push(tool_frame(axis, travel, previous_x.as_ref()));
    }
    frames
}

/// `v` minus its component along unit `z`, normalised; `None` when `v` is within
/// [`PARALLEL_SIN_TOL`] of `±z` (or zero).
fn perpendicular_part(v: &Vector3, z: &Vector3) -> Option<Vector3> {
    let n = v.norm();
    if n.is_nan() || n == 0.0 {
        return None;
    }
    let p = v / n;
    let p = p - z * p.dot(z);
    let len = p.norm();
    (len > PARALLEL_SIN_TOL).then(|| p / len)
}

/// The world axis least aligned with unit `z` (X, then Y, then Z on ties), re-orthogonalised.
fn least_aligned_axis_perpendicular(z: &Vector3) -> Vector3 {
    let mut best = 0;
    for i in 1..3 {
        if z[i].abs() < z[best].abs() {
            best = i;
        }
    }
    let mut e = Vector3::zeros();
    e[best] = 1.0;
    // |z[best]| ≤ 1/√3, so the perpendicular part has length ≥ √(2/3): never degenerate.
    let p = e - z * z[best];
    p / p.norm()
}

/// Unit quaternion `[w, x, y, z]` of a rotation matrix (Shepperd's method), with `w ≥ 0`
/// (ties: first non-zero component positive).
pub fn quaternion_from_matrix(r: &Matrix3) -> [Real; 4] {
    let (m00, m11, m22) = (r[(0, 0)], r[(1, 1)], r[(2, 2)]);
    let trace = m00 + m11 + m22;
    // Pivot on the largest of 4w² = 1 + tr, 4x² = 1 + 2m00 − tr, …, for accuracy near 180°.
    let candidates = [trace, m00, m11, m22];
    let mut pivot = 0;
    for i in 1..4 {
        let value = |k: usize| {
            if k == 0 {
                candidates[0]
            } else {
                2.0 * candidates[k] - trace
            }
        };
        if value(i) > value(pivot) {
            pivot = i;
        }
    }
    let q = match pivot {
        0 => {
            let s = 2.0 * (1.0 + trace).sqrt();
            [
                s / 4.0,
                (r[(2, 1)] - r[(1, 2)]) / s,
                (r[(0, 2)] - r[(2, 0)]) / s,
                (r[(1, 0)] - r[(0, 1)]) / s,
            ]
        }
        1 => {
            let s = 2.0 * (1.0 + m00 - m11 - m22).sqrt();
            [
                (r[(2, 1)] - r[(1, 2)]) / s,
                s / 4.0,
                (r[(0, 1)] + r[(1, 0)]) / s,
                (r[(0, 2)] + r[(2, 0)]) / s,
            ]
        }
        2 => {
            let s = 2.0 * (1.0 - m00 + m11 - m22).sqrt();
            [
                (r[(0, 2)] - r[(2, 0)]) / s,
                (r[(0, 1)] + r[(1, 0)]) / s,
                s / 4.0,
                (r[(1, 2)] + r[(2, 1)]) / s,
            ]
        }
        _ => {
            let s = 2.0 * (1.0 - m00 - m11 + m22).sqrt();
            [
                (r[(1, 0)] - r[(0, 1)]) / s,
                (r[(0, 2)] + r[(2, 0)]) / s,
                (r[(1, 2)] + r[(2, 1)]) / s,
                s / 4.0,
            ]
        }
    };
    canonical_sign(normalized(q))
}

fn normalized(q: [Real; 4]) -> [Real; 4] {
    let n = q.iter().map(|c| c * c).sum::<Real>().sqrt();
    q.map(|c| c / n)
}

/// `q` or `−q`, whichever has its first non-zero component positive.
fn canonical_sign(q: [Real; 4]) -> [Real; 4] {
    match q.iter().find(|c| **c != 0.0) {
        Some(c) if *c < 0.0 => q.map(|c| -c),
        _ => q,
    }
}

/// Rotation matrix of a unit quaternion `[w, x, y, z]` (normalised first).
pub fn matrix_from_quaternion(q: &[Real; 4]) -> Matrix3 {
    let [w, x, y, z] = normalized(*q);
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// Quaternions `[w, x, y, z]` of a sequence of frames with sign continuity: the first as
/// [`quaternion_from_matrix`], each next one with a non-negative dot product with the previous.
pub fn continuous_quaternions(frames: &[Matrix3]) -> Vec<[Real; 4]> {
    let mut out: Vec<[Real; 4]> = Vec::with_capacity(frames.len());
    for frame in frames {
        let mut q = quaternion_from_matrix(frame);
        if let Some(p) = out.last() {
            let dot: Real = p.iter().zip(&q).map(|(a, b)| a * b).sum();
            if dot < 0.0 {
                q = q.map(|c| -c);
            }
        }
        out.push(q);
    }
    out
}

/// `R = Rz(a)·Ry(b)·Rx(c)`, angles in radians.
pub fn matrix_from_euler_zyx(a: Real, b: Real, c: Real) -> Matrix3 {
    let (sa, ca) = (libm::sin(a), libm::cos(a));
    let (sb, cb) = (libm::sin(b), libm::cos(b));
    let (sc, cc) = (libm::sin(c), libm::cos(c));
    Matrix3::new(
        ca * cb,
        ca * sb * sc - sa * cc,
        ca * sb * cc + sa * sc,
        sa * cb,
        sa * sb * sc + ca * cc,
        sa * sb * cc - ca * sc,
        -sb,
        cb * sc,
        cb * cc,
    )
}

/// ZYX Euler angles `[a, b, c]` in radians with `R = Rz(a)·Ry(b)·Rx(c)`, `b ∈ [−π/2, π/2]`,
/// `a, c ∈ (−π, π]`. At gimbal lock (cos b < [`GIMBAL_COS_TOL`]) `a = a_hint` and `c` follows.
pub fn euler_zyx_from_matrix(r: &Matrix3, a_hint: Real) -> [Real; 3] {
    let cb = r[(0, 0)].hypot(r[(1, 0)]);
    let b = libm::atan2(-r[(2, 0)], cb);
    if cb >= GIMBAL_COS_TOL {
        // wrap_pi turns atan2's −π (from a −0 sine) into π.
        let a = wrap_pi(libm::atan2(r[(1, 0)], r[(0, 0)]));
        let c = wrap_pi(libm::atan2(r[(2, 1)], r[(2, 2)]));
        return [a, b, c];
    }
    let a = a_hint;
    let c = if r[(2, 0)] < 0.0 {
        // b = +90°: r01 = sin(c − a), r11 = cos(c − a).
        a + libm::atan2(r[(0, 1)], r[(1, 1)])
    } else {
        // b = −90°: r01 = −sin(a + c), r11 = cos(a + c).
        libm::atan2(-r[(0, 1)], r[(1, 1)]) - a
    };
    [a, b, wrap_pi(c)]
}

/// `x` wrapped into (−π, π].
fn wrap_pi(x: Real) -> Real {
    let tau = 2.0 * std::f64::consts::PI;
    let mut y = x - tau * libm::round(x / tau);
    if y <= -std::f64::consts::PI {
        y += tau;
    }
    y
}

/// ZYX Euler angles in degrees `[A, B, C]` of a sequence of frames, continuous where possible:
/// gimbal-lock poses keep the previous A, and with `unwrap` A and C move by whole turns to stay
/// within 180° of the previous values while inside ±[`UNWRAP_LIMIT_DEG`].
pub fn continuous_euler_zyx_deg(frames: &[Matrix3], unwrap: bool) -> Vec<[Real; 3]> {
    let mut out: Vec<[Real; 3]> = Vec::with_capacity(frames.len());
    for frame in frames {
        let previous = out.last().copied();
        let hint = previous.map_or(0.0, |p| wrap_pi(p[0].to_radians()));
        let [a, b, c] = euler_zyx_from_matrix(frame, hint).map(Real::to_degrees);
        let (a, c) = match previous {
            Some(p) if unwrap => (unwrap_near(a, p[0]), unwrap_near(c, p[2])),
            _ => (a, c),
        };
        out.push([a, b, c]);
    }
    out
}

/// `angle` (degrees, in (−180, 180]) plus the whole number of turns that brings it nearest to
/// `previous`, unless that leaves ±[`UNWRAP_LIMIT_DEG`].
fn unwrap_near(angle: Real, previous: Real) -> Real {
    let turns = libm::round((previous - angle) / 360.0);
    let candidate = angle + 360.0 * turns;
    if candidate.abs() < UNWRAP_LIMIT_DEG {
        candidate
    } else {
        angle
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    fn max_diff(a: &Matrix3, b: &Matrix3) -> Real {
        (a - b).abs().max()
    }

    /// A deterministic spread of rotations, including 180° turns about the axes.
    fn samples() -> Vec<Matrix3> {
        let mut out = vec![
            Matrix3::identity(),
            matrix_from_euler_zyx(PI, 0.0, 0.0),
            matrix_from_euler_zyx(0.0, 0.0, PI),
            matrix_from_euler_zyx(0.0, PI, 0.0),
            matrix_from_euler_zyx(PI - 1e-9, 0.0, 0.0),
            matrix_from_euler_zyx(0.3, 0.0, PI),
        ];
        for i in 0..200 {
            let t = i as Real;
            out.push(matrix_from_euler_zyx(
                libm::sin(1.7 * t) * PI,
                libm::sin(0.9 * t + 0.3) * FRAC_PI_2,
                libm::cos(2.3 * t) * PI,
            ));
        }
        out
    }

    #[test]
    fn quaternion_and_matrix_round_trip_including_half_turns() {
        for r in samples() {
            let q = quaternion_from_matrix(&r);
            let norm: Real = q.iter().map(|c| c * c).sum();
            assert!((norm - 1.0).abs() < 1e-14);
            assert!(q[0] >= 0.0);
            assert!(max_diff(&matrix_from_quaternion(&q), &r) < 1e-14, "{r}");
        }
        // A half turn about X is [0, 1, 0, 0] exactly (up to rounding of the trig).
        let q = quaternion_from_matrix(&matrix_from_euler_zyx(0.0, 0.0, PI));
        assert!((q[1] - 1.0).abs() < 1e-15 && q[0].abs() < 1e-15);
    }

    #[test]
    fn quaternion_of_a_rotation_about_z_is_the_half_angle_formula() {
        let t = 1.2;
        let q = quaternion_from_matrix(&matrix_from_euler_zyx(t, 0.0, 0.0));
        let expected = [libm::cos(t / 2.0), 0.0, 0.0, libm::sin(t / 2.0)];
        for (a, b) in q.iter().zip(expected) {
            assert!((a - b).abs() < 1e-15);
        }
    }

    #[test]
    fn euler_round_trip_away_from_gimbal_lock() {
        for r in samples() {
            let e = euler_zyx_from_matrix(&r, 0.0);
            assert!(e[1].abs() <= FRAC_PI_2);
            assert!(max_diff(&matrix_from_euler_zyx(e[0], e[1], e[2]), &r) < 1e-13);
        }
        let e = euler_zyx_from_matrix(&matrix_from_euler_zyx(0.4, -0.5, 2.9), 0.0);
        assert!((e[0] - 0.4).abs() < 1e-14 && (e[1] + 0.5).abs() < 1e-14);
        assert!((e[2] - 2.9).abs() < 1e-14);
    }

    #[test]
    fn gimbal_lock_keeps_the_hint_for_a_and_reproduces_the_matrix() {
        for b in [FRAC_PI_2, -FRAC_PI_2] {
            for (a, c) in [(0.3, 1.1), (-2.0, 2.5), (3.0, -3.0)] {
                let r = matrix_from_euler_zyx(a, b, c);
                for hint in [0.0, 0.7, -2.9] {
                    let e = euler_zyx_from_matrix(&r, hint);
                    assert_eq!(e[0], hint);
                    assert!((e[1] - b).abs() < 1e-7);
                    assert!(max_diff(&matrix_from_euler_zyx(e[0], e[1], e[2]), &r) < 1e-13);
                }
            }
        }
    }

    #[test]
    fn frame_is_orthonormal_right_handed_with_z_axis_and_x_travel() {
        let axis = Vector3::new(0.0, 0.6, -0.8);
        let travel = Vector3::new(1.0, 0.08, 0.06); // not quite perpendicular
        let f = tool_frame(&axis, &travel, None);
        assert!((f.transpose() * f - Matrix3::identity()).abs().max() < 1e-15);
        assert!((f.determinant() - 1.0).abs() < 1e-15);
        assert!((f.column(2) - axis).norm() < 1e-15);
        let x = travel - axis * travel.dot(&axis);
        assert!((f.column(0) - x.normalize()).norm() < 1e-15);
    }

    #[test]
    fn travel_parallel_to_axis_falls_back_to_previous_x_then_world_axis() {
        let down = -Vector3::z();
        let f = tool_frame(&down, &down, None);
        assert!((f.column(0) - Vector3::x()).norm() < 1e-15);
        // Y = Z × X = (−Z) × X = −Y.
        assert!((f.column(1) + Vector3::y()).norm() < 1e-15);
        let previous = Vector3::new(0.0, 1.0, 0.0);
        let f = tool_frame(&down, &(-down), Some(&previous));
        assert!((f.column(0) - previous).norm() < 1e-15);
        // Axis along X: the least aligned world axis is Y.
        let f = tool_frame(&Vector3::x(), &Vector3::x(), None);
        assert!((f.column(0) - Vector3::y()).norm() < 1e-15);
        // Previous X parallel to the new axis: world axis again.
        let f = tool_frame(&Vector3::x(), &Vector3::x(), Some(&Vector3::x()));
        assert!((f.column(0) - Vector3::y()).norm() < 1e-15);
    }

    #[test]
    fn quaternion_signs_stay_continuous() {
        // A slow turn about Z through 360°: Shepperd alone would flip the sign at 180°.
        let frames: Vec<Matrix3> = (0..=72)
            .map(|i| matrix_from_euler_zyx(i as Real * 5.0_f64.to_radians(), 0.0, 0.0))
            .collect();
        let qs = continuous_quaternions(&frames);
        for pair in qs.windows(2) {
            let dot: Real = pair[0].iter().zip(&pair[1]).map(|(a, b)| a * b).sum();
            assert!(dot > 0.99);
        }
        assert!((qs[72][0] + 1.0).abs() < 1e-12, "after a full turn q = −1");
    }

    #[test]
    fn euler_angles_unwrap_across_180_and_wrap_back_at_the_limit() {
        let frames: Vec<Matrix3> = (0..=100)
            .map(|i| matrix_from_euler_zyx((150.0 + 5.0 * i as Real).to_radians(), 0.2, 0.0))
            .collect();
        let e = continuous_euler_zyx_deg(&frames, true);
        for (i, pair) in e.windows(2).enumerate() {
            let step = pair[1][0] - pair[0][0];
            // Continuous (+5°) until A would reach 360°, then one jump back by 360°.
            if pair[0][0] + 5.0 < UNWRAP_LIMIT_DEG - 1e-9 {
                assert!((step - 5.0).abs() < 1e-9, "step {i}: {step}");
            } else {
                assert!((step + 355.0).abs() < 1e-9, "step {i}: {step}");
            }
            assert!(pair[1][0].abs() < UNWRAP_LIMIT_DEG);
        }
        let wrapped = continuous_euler_zyx_deg(&frames, false);
        assert!(wrapped.iter().all(|a| a[0] > -180.0 && a[0] <= 180.0));
    }
}
