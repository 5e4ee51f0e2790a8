//! Scalar and vector types, angle helpers and the crate's numerical tolerances (one place).

/// The scalar of all geometry: STL stores `f32`, every computation runs in `f64`.
pub type Real = f64;
/// A point in model space (the STL's own length unit).
pub type Point3 = nalgebra::Point3<Real>;
/// A vector in model space.
pub type Vector3 = nalgebra::Vector3<Real>;

/// A triangle is degenerate when its height is below this fraction of its longest edge:
/// its normal is then set by rounding of the file's `f32` coordinates, not by the shape.
pub const DEGENERATE_HEIGHT_RATIO: Real = 1e-7;

/// The larger of `a` and `b`, for numbers known not to be NaN and not to be a `+0`/`−0`
/// pair: then exactly `a.max(b)`, which on WebAssembly is a call (to keep `max`'s NaN rule)
/// rather than one comparison.
#[inline]
pub fn larger(a: Real, b: Real) -> Real {
    if b > a {
        b
    } else {
        a
    }
}

/// Angle in radians between two vectors, accurate near 0 and π (atan2 of |a×b| and a·b).
///
/// Uses `libm` so that the result is bit-identical natively and in WebAssembly.
#[inline]
pub fn angle_between(a: &Vector3, b: &Vector3) -> Real {
    libm::atan2(a.cross(b).norm(), a.dot(b))
}

/// `acos` clamped to its domain, bit-identical on every platform.
#[inline]
pub fn acos_clamped(x: Real) -> Real {
    libm::acos(x.clamp(-1.0, 1.0))
}

/// `cos`, bit-identical on every platform.
#[inline]
pub fn cos(x: Real) -> Real {
    libm::cos(x)
}

/// A unit vector perpendicular to the unit vector `n`: `n × x` normalised, or `n × y` when
/// `n` is within about 25° of the x axis; `x` itself for a zero or non-finite `n`.
pub fn any_perpendicular(n: &Vector3) -> Vector3 {
    let helper = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let t = n.cross(&helper);
    let length = t.norm();
    if length > 0.0 && length.is_finite() {
        t / length
    } else {
        Vector3::x()
    }
}

/// A number as messages show it: short enough to read, exact enough to recognise.
///
/// Plain decimals from 1e-4 to 1e15 (`0.35`, `4`), otherwise the shortest round-trip
/// scientific form (`1.7e308`, `2e-8`), and JavaScript's spelling of the special values
/// (`NaN`, `Infinity`), so a 309-digit value is never echoed back to the user.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compact(pub Real);

impl std::fmt::Display for Compact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        const PLAIN: std::ops::Range<Real> = 1e-4..1e15;
        let x = self.0;
        if x.is_nan() {
            f.write_str("NaN")
        } else if x.is_infinite() {
            f.write_str(if x > 0.0 { "Infinity" } else { "-Infinity" })
        } else if x == 0.0 {
            f.write_str("0")
        } else if PLAIN.contains(&x.abs()) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_between_is_accurate_for_tiny_and_straight_angles() {
        let x = Vector3::x();
        let tiny = Vector3::new(1.0, 1e-9, 0.0);
        assert!((angle_between(&x, &tiny) - 1e-9).abs() < 1e-20);
        assert!((angle_between(&x, &-x) - std::f64::consts::PI).abs() < 1e-15);
        assert!((angle_between(&x, &Vector3::y()) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn compact_numbers_stay_short_and_round_trip() {
        let shown = |x: Real| Compact(x).to_string();
        assert_eq!(shown(0.35), "0.35");
        assert_eq!(shown(4.0), "4");
        assert_eq!(shown(-0.0), "0");
        assert_eq!(shown(1.7e308), "1.7e308");
        assert_eq!(shown(-2e-8), "-2e-8");
        assert_eq!(shown(123456789.25), "123456789.25");
        assert_eq!(shown(Real::MAX), "1.7976931348623157e308");
        assert_eq!(shown(Real::NAN), "NaN");
        assert_eq!(shown(Real::NEG_INFINITY), "-Infinity");
        for x in [1e-300, 3.0e-5, 0.1 + 0.2, 6.02214076e23, Real::MIN_POSITIVE] {
            assert_eq!(
                shown(x).parse::<Real>().unwrap(),
                x,
                "{x} does not round-trip"
            );
        }
    }
}
