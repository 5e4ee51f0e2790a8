//! Ferguson curves with arc-matching tangents and the bilinearly blended Coons patch over
//! four reference holes.
//!
//! Source: Bi et al. 2015 (seed 004) §3.3.1–3.3.4: tangent at a reference hole in the plane of
//!         its normal and the chord, perpendicular to the normal; Ferguson (cubic Hermite)
//!         curves A→B and D→C across the flight direction, straight lines A→D and B→C along
//!         it; Ferguson, "Multivariable curve interpolation", J. ACM 11(2), 1964; Coons,
//!         "Surfaces for computer-aided design of space forms", MIT MAC-TR-41, 1967 (also
//!         Farin, *Curves and Surfaces for CAGD*, 5th ed., ch. 22 "Coons patches").
//! Input:  corners `A, B, C, D` (in order around the region) with their normals.
//! Output: [`CoonsPatch`] `S(u, w)`, `u` from A towards B (across the flight direction), `w`
//!         from A towards D (along it), with its partial derivatives.
//! Cost:   O(1) per evaluation.
//!
//! Coons patch, bilinearly blended: `S = L_c + L_d − B`, where `L_c` blends the two Ferguson
//! curves linearly in `w` (`(1 − w)·C_AB(u) + w·C_DC(u)`), `L_d` blends the two straight sides
//! linearly in `u` (`(1 − u)·L_AD(w) + u·L_BC(w)`) and `B` is the bilinear interpolant of the
//! four corners. With straight `w`-sides `L_d = B`, so `S` is the ruled surface between the two
//! curves; the general formula is kept so that curved sides can replace the lines.
//!
//! Tangent length (the paper only bounds it by 3× the chord, §3.3.1, and asks for the length
//! that fits the real curve best): choose the length that makes the Ferguson curve reproduce a
//! circular arc of angle `φ` between the two end tangents as closely as a cubic can. The
//! classic cubic Bézier approximation of a circular arc of radius `r` with the curve's midpoint
//! on the arc has inner control points at `k·r` along the end tangents with
//! `k = 4/3·tan(φ/4)` (e.g. Goldapp, "Approximation of circular arcs by cubic polynomials",
//! CAGD 8, 1991; Dokken et al., CAGD 7, 1990), radial error ≈ 2.7·10⁻⁴·r at φ = 90°. A Hermite
//! end tangent is 3× the Bézier handle, so `|T| = 4·r·tan(φ/4)`; with the chord
//! `c = 2·r·sin(φ/2) = 4·r·sin(φ/4)·cos(φ/4)` this is `|T| = c / cos²(φ/4)`, independent of
//! the radius and equal to the chord for a straight segment (φ = 0). It is capped at
//! 3× the chord, a bound it never reaches (φ ≤ π gives at most 2× the chord);
//! `tangent_scale` replaces it by `tangent_scale × chord`. No paper chooses `φ`
//! for twisted normals: here it is the angle between the two unit end tangents, which for a
//! planar arc equals the angle between the normals.

use super::DrillError;
use crate::math::{angle_between, Point3, Real, Vector3};

/// The paper's bound on a tangent's length, as a multiple of the chord (§3.3.1, after Faux &
/// Pratt 1979).
pub const MAX_TANGENT_TO_CHORD: Real = 3.0;
/// A normal counts as parallel to the chord (no tangent direction) when the chord's component
/// perpendicular to it is below this fraction of the chord.
pub const MIN_CHORD_NORMAL_SINE: Real = 1e-6;

/// A Ferguson (cubic Hermite) curve: end points and end tangents, parameter `s ∈ [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FergusonCurve {
    /// Point at `s = 0`.
    pub p0: Point3,
    /// Point at `s = 1`.
    pub p1: Point3,
    /// Derivative at `s = 0`.
    pub t0: Vector3,
    /// Derivative at `s = 1`.
    pub t1: Vector3,
}

/// Hermite tangent length that reproduces a circular arc of angle `phi_rad` over `chord`
/// best (`chord / cos²(φ/4)`, see the module header).
pub fn arc_tangent_length(chord: Real, phi_rad: Real) -> Real {
    let c = libm::cos(0.25 * phi_rad);
    chord / (c * c)
}

impl FergusonCurve {
    /// The curve from `p0` to `p1` whose end tangents lie in the plane of the chord and the
    /// end's normal, perpendicular to the normal, with the arc-matching length (capped at
    /// 3× the chord) or `tangent_scale × chord`. `names` label the ends in error messages.
    pub fn from_normals(
        (p0, n0): (Point3, Vector3),
        (p1, n1): (Point3, Vector3),
        tangent_scale: Option<Real>,
        names: [&str; 2],
    ) -> Result<Self, DrillError> {
        let chord = p1 - p0;
        let length = chord.norm();
        if let Some(scale) = tangent_scale {
            if !(scale.is_finite() && scale > 0.0 && scale <= MAX_TANGENT_TO_CHORD) {
                return Err(DrillError::BadParam {
                    name: "tangentScale",
                    value: scale,
                    allowed: "a tangent length in chords must be > 0 and ≤ 3",
                });
            }
        }
        let direction = |n: &Vector3, name: &str| {
            let Some(n) = n
                .try_normalize(0.0)
                .filter(|n| n.iter().all(|c| c.is_finite()))
            else {
                return Err(DrillError::DegenerateReferences(format!(
                    "the normal at {name} is zero or not finite"
                )));
            };
            let along = chord - n * n.dot(&chord);
            if along.norm() <= MIN_CHORD_NORMAL_SINE * length {
                return Err(DrillError::DegenerateReferences(format!(
                    "the normal at {name} is parallel to the chord {}{}",
                    names[0], names[1]
                )));
            }
            Ok(along.normalize())
        };
        let d0 = direction(&n0, names[0])?;
        let d1 = direction(&n1, names[1])?;
        let magnitude = match tangent_scale {
            Some(scale) => scale * length,
            None => arc_tangent_length(length, angle_between(&d0, &d1))
                .min(MAX_TANGENT_TO_CHORD * length),
        };
        Ok(FergusonCurve {
            p0,
            p1,
            t0: d0 * magnitude,
            t1: d1 * magnitude,
        })
    }

    /// Point at `s` (Hermite basis `2s³−3s²+1, −2s³+3s², s³−2s²+s, s³−s²`).
    pub fn point(&self, s: Real) -> Point3 {
        let (s2, s3) = (s * s, s * s * s);
        let h0 = 2.0 * s3 - 3.0 * s2 + 1.0;
        let h1 = -2.0 * s3 + 3.0 * s2;
        let h2 = s3 - 2.0 * s2 + s;
        let h3 = s3 - s2;
        Point3::from(self.p0.coords * h0 + self.p1.coords * h1 + self.t0 * h2 + self.t1 * h3)
    }

    /// Derivative with respect to `s`.
    pub fn derivative(&self, s: Real) -> Vector3 {
        let s2 = s * s;
        let h0 = 6.0 * s2 - 6.0 * s;
        let h2 = 3.0 * s2 - 4.0 * s + 1.0;
        let h3 = 3.0 * s2 - 2.0 * s;
        (self.p0.coords - self.p1.coords) * h0 + self.t0 * h2 + self.t1 * h3
    }
}

/// Bilinearly blended Coons patch over corners `A, B, C, D` with Ferguson curves `A→B`,
/// `D→C` and straight lines `A→D`, `B→C` (see the module header for `S = L_c + L_d − B`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoonsPatch {
    /// Corners `A, B, C, D` in order around the region.
    pub corners: [Point3; 4],
    /// The curve `A→B` (`w = 0`), parameter `u`.
    pub ab: FergusonCurve,
    /// The curve `D→C` (`w = 1`), parameter `u`.
    pub dc: FergusonCurve,
}

impl CoonsPatch {
    /// Builds the patch from the corners and their normals (any orientation, any length > 0);
    /// `tangent_scale` as in [`FergusonCurve::from_normals`].
    pub fn new(
        corners: [Point3; 4],
        normals: [Vector3; 4],
        tangent_scale: Option<Real>,
    ) -> Result<Self, DrillError> {
        let [a, b, c, d] = corners;
        let [na, nb, nc, nd] = normals;
        Ok(CoonsPatch {
            corners,
            ab: FergusonCurve::from_normals((a, na), (b, nb), tangent_scale, ["A", "B"])?,
            dc: FergusonCurve::from_normals((d, nd), (c, nc), tangent_scale, ["D", "C"])?,
        })
    }

    /// `S(u, w) = L_c + L_d − B`.
    pub fn point(&self, u: Real, w: Real) -> Point3 {
        let [a, b, c, d] = self.corners.map(|p| p.coords);
        let lc = self.ab.point(u).coords * (1.0 - w) + self.dc.point(u).coords * w;
        let lad = a * (1.0 - w) + d * w;
        let lbc = b * (1.0 - w) + c * w;
        let ld = lad * (1.0 - u) + lbc * u;
        let bilinear = (a * (1.0 - w) + d * w) * (1.0 - u) + (b * (1.0 - w) + c * w) * u;
        Point3::from(lc + ld - bilinear)
    }

    /// Partial derivatives `(∂S/∂u, ∂S/∂w)`.
    pub fn partials(&self, u: Real, w: Real) -> (Vector3, Vector3) {
        let [a, b, c, d] = self.corners.map(|p| p.coords);
        let lc_u = self.ab.derivative(u) * (1.0 - w) + self.dc.derivative(u) * w;
        let lc_w = self.dc.point(u).coords - self.ab.point(u).coords;
        let (lad, lbc) = (a * (1.0 - w) + d * w, b * (1.0 - w) + c * w);
        let ld_u = lbc - lad;
        let ld_w = (d - a) * (1.0 - u) + (c - b) * u;
        // The bilinear term has the same derivatives as L_d (both interpolate the corners
        // linearly along the straight sides).
        let (b_u, b_w) = (ld_u, ld_w);
        (lc_u + ld_u - b_u, lc_w + ld_w - b_w)
    }

    /// Unit normal `∂S/∂u × ∂S/∂w` (zero where the patch is singular).
    pub fn normal(&self, u: Real, w: Real) -> Vector3 {
        let (su, sw) = self.partials(u, w);
        su.cross(&sw)
            .try_normalize(0.0)
            .unwrap_or_else(Vector3::zeros)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partials_match_finite_differences() {
        let corners = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(10.0, 1.0, 2.0),
            Point3::new(11.0, 0.0, 9.0),
            Point3::new(-1.0, 1.0, 8.0),
        ];
        let normals = [
            Vector3::new(-0.2, 1.0, 0.0),
            Vector3::new(0.3, 1.0, 0.1),
            Vector3::new(0.3, 1.0, -0.1),
            Vector3::new(-0.2, 1.0, 0.05),
        ];
        let patch = CoonsPatch::new(corners, normals, None).unwrap();
        let h = 1e-6;
        for (u, w) in [(0.3, 0.7), (0.0, 0.0), (1.2, -0.1)] {
            let (su, sw) = patch.partials(u, w);
            let fu = (patch.point(u + h, w) - patch.point(u - h, w)) / (2.0 * h);
            let fw = (patch.point(u, w + h) - patch.point(u, w - h)) / (2.0 * h);
            assert!(
                (su - fu).norm() < 1e-6 && (sw - fw).norm() < 1e-6,
                "{u} {w}"
            );
        }
    }
}
