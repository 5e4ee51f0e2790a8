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
}
