//! Segmentation parameters and the growing thresholds derived from process parameters.
//!
//! Source: Wang, Zhao, Tao, "Investigation on Surface Segmentation Algorithm for Robotic
//! Manufacturing of Aircraft Skin", Civil Aircraft Design and Research 2019(3):9-14, §1:
//! grinding (Hertz contact) `κ ≤ 2·d·(1 − δ²) / Lc²` (Eq. 4); spraying
//! `α_th ≤ arccos((Qd − ΔQd) / Qmin)` (Eq. 9).

use crate::math::{acos_clamped, Compact, Real};
use std::f64::consts::PI;

/// Smallest angle (θmax, angle threshold) accepted, radians.
///
/// Face normals come from `f32` corners: rounding a corner moves a normal by about
/// `f32::EPSILON` ≈ 1.2e-7 rad times the triangle's size over its height, so two normals
/// closer than ~1e-7 rad cannot be told apart. Region growing and planarisation compare
/// cosines in `f64`, which stop resolving angles near 2·10⁻⁸ rad (`cos θ` rounds to 1 below
/// ~1.5e-8), where a face no longer fits its own mean. 1e-6 rad (0.2 arc seconds) sits above both with room
/// to spare and far below any process tolerance.
pub const MIN_ANGLE_RAD: Real = 1e-6;
/// The range of θmax and of angle thresholds in words; keep it in step with [`MIN_ANGLE_RAD`].
const TOO_SMALL_ANGLE: &str = "at least 1e-6 radians (allowed: 1e-6 to π; smaller angles are below the precision of face normals from f32 coordinates)";

/// Why segmentation parameters were refused. Messages name the parameter as the page shows it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// A number is NaN or infinite.
    #[error("{name} must be a finite number, got {}", Compact(*value))]
    NotFinite {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: Real,
    },
    /// A number is outside its allowed range.
    #[error("{name} must be {range}, got {}", Compact(*value))]
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: Real,
        /// The allowed range, in words.
        range: &'static str,
    },
    /// Eq. 9's arccos argument is outside [−1, 1].
    #[error("spraying parameters are contradictory: (mean thickness − allowed deviation) / minimum thickness = {argument:.4} is outside [−1, 1], so no tilt angle satisfies Eq. 9; the minimum thickness must be at least mean thickness − allowed deviation")]
    ArccosDomain {
        /// `(Qd − ΔQd) / Qmin`.
        argument: Real,
    },
    /// A derived threshold of zero lets no two triangles join.
    #[error("the derived angle threshold is 0 rad ((mean thickness − allowed deviation) / minimum thickness = 1): no two triangles could join; allow a larger deviation")]
    ZeroThreshold,
    /// A threshold derived from process parameters is not a usable number (zero, too small,
    /// or infinite after overflow or underflow).
    #[error("the {what} derived from {from} is {}, but it must be {range}", Compact(*value))]
    DerivedOutOfRange {
        /// What was derived, with its unit.
        what: &'static str,
        /// The parameters it was derived from, with their values.
        from: String,
        /// The derived value.
        value: Real,
        /// The allowed range, in words.
        range: &'static str,
    },
    /// A parameter name that is not known (usually a typo).
    #[error("unknown segmentation parameter '{name}'")]
    Unknown {
        /// The name as given.
        name: String,
    },
    /// Not exactly one growing criterion given.
    #[error(
        "give exactly one of angleThreshold, curvatureThreshold, spray or grind (got {given})"
    )]
    CriterionCount {
        /// The criteria given, comma-separated, or "none".
        given: String,
    },
}

/// Spraying parameters (Eq. 9); thicknesses in any one unit.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct SprayParams {
    /// Mean film thickness `Qd`.
    pub mean_thickness: Real,
    /// Largest allowed deviation from the mean `ΔQd`.
    pub allowed_deviation: Real,
    /// Minimum film thickness `Qmin`.
    pub min_thickness: Real,
}

/// Grinding parameters (Eq. 4); lengths in the mesh's unit.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GrindParams {
    /// Indentation depth `d` of the wheel.
    pub indentation_depth: Real,
    /// Smallest allowed pressure at the contact edge, as a share `δ` of the peak, in (0, 1).
    pub min_pressure_ratio: Real,
    /// Contact width `Lc`.
    pub contact_width: Real,
}

/// How neighbouring triangles are compared while regions grow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Criterion {
    /// Normal angle below `alpha_rad` (spraying criterion with `l = 1`).
    Angle {
        /// Threshold in radians, from [`MIN_ANGLE_RAD`] to π.
        alpha_rad: Real,
    },
    /// Approximate curvature `θ / l` below `kappa` (grinding criterion, Eq. 5–6).
    Curvature {
        /// Threshold in 1 / mesh unit, > 0.
        kappa: Real,
    },
    /// Angle threshold derived from spraying parameters (Eq. 9).
    Spray(SprayParams),
    /// Curvature threshold derived from grinding parameters (Eq. 4).
    Grind(GrindParams),
}

/// The threshold region growing compares against, after deriving it from the criterion.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "kind", content = "value", rename_all = "lowercase")]
pub enum GrowthThreshold {
    /// Angle between neighbour normals, radians.
    Angle(Real),
    /// Angle over centroid distance, 1 / mesh unit.
    Curvature(Real),
}

impl GrowthThreshold {
    /// The numeric value (radians or 1 / mesh unit).
    pub fn value(&self) -> Real {
        match *self {
            GrowthThreshold::Angle(v) | GrowthThreshold::Curvature(v) => v,
        }
    }
}

/// Where planarisation starts each patch inside a region (the paper starts anywhere).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub enum SeedRule {
    /// The unassigned face with the lowest index.
    LowestIndex,
    /// Faces whose neighbours bend least first, so patches grow out of flat areas.
    #[default]
    Flattest,
    /// Largest faces first.
    LargestArea,
}

/// Everything [`segment`](super::segment) needs; `Default` is the paper's run
/// (α = 0.35 rad, θmax = 1 rad, ε = 10 %).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentParams {
    /// Region-growing criterion.
    pub criterion: Criterion,
    /// Largest angle between a face normal and its patch's mean normal, radians, from
    /// [`MIN_ANGLE_RAD`] to π.
    pub theta_max_rad: Real,
    /// Patches below this share of the total area are dropped, in [0, 1).
    pub min_area_ratio: Real,
    /// Seed choice for planarisation.
    pub seed_rule: SeedRule,
}

impl Default for SegmentParams {
    fn default() -> Self {
        SegmentParams {
            criterion: Criterion::Angle { alpha_rad: 0.35 },
            theta_max_rad: 1.0,
            min_area_ratio: 0.1,
            seed_rule: SeedRule::default(),
        }
    }
}

fn finite(name: &'static str, value: Real) -> Result<Real, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError::NotFinite { name, value })
    }
}

fn positive(name: &'static str, value: Real) -> Result<Real, ParamError> {
    if finite(name, value)? > 0.0 {
        Ok(value)
    } else {
        Err(ParamError::OutOfRange {
            name,
            value,
            range: "greater than 0",
        })
    }
}

/// Eq. 9: `α_th = arccos((Qd − ΔQd) / Qmin)`.
pub fn spray_angle_threshold(p: &SprayParams) -> Result<Real, ParamError> {
    let qd = positive("meanThickness", p.mean_thickness)?;
    let qmin = positive("minThickness", p.min_thickness)?;
    let dq = finite("allowedDeviation", p.allowed_deviation)?;
    if !(0.0..qd).contains(&dq) {
        return Err(ParamError::OutOfRange {
            name: "allowedDeviation",
            value: dq,
            range: "at least 0 and less than the mean thickness",
        });
    }
    let argument = (qd - dq) / qmin;
    if !(-1.0..=1.0).contains(&argument) {
        return Err(ParamError::ArccosDomain { argument });
    }
    let alpha = acos_clamped(argument);
    if alpha == 0.0 {
        return Err(ParamError::ZeroThreshold);
    }
    if alpha < MIN_ANGLE_RAD {
        return Err(ParamError::DerivedOutOfRange {
            what: "angle threshold (rad)",
            from: format!(
                "spray (meanThickness {}, allowedDeviation {}, minThickness {})",
                Compact(qd),
                Compact(dq),
                Compact(qmin)
            ),
            value: alpha,
            range: TOO_SMALL_ANGLE,
        });
    }
    Ok(alpha)
}

/// Eq. 4: `κ = 2·d·(1 − δ²) / Lc²`.
pub fn grind_curvature_threshold(p: &GrindParams) -> Result<Real, ParamError> {
    let d = positive("indentationDepth", p.indentation_depth)?;
    let lc = positive("contactWidth", p.contact_width)?;
    let delta = finite("minPressureRatio", p.min_pressure_ratio)?;
    if !(delta > 0.0 && delta < 1.0) {
        return Err(ParamError::OutOfRange {
            name: "minPressureRatio",
            value: delta,
            range: "strictly between 0 and 1",
        });
    }
    let kappa = 2.0 * d * (1.0 - delta * delta) / (lc * lc);
    // Finite inputs can still over- or underflow (d = 1e300, Lc = 1e-300): 0 would let no
    // two faces join and ∞ would join all, neither of which the user asked for.
    if !(kappa.is_finite() && kappa > 0.0) {
        return Err(ParamError::DerivedOutOfRange {
            what: "curvature threshold (1 / mesh unit)",
            from: format!(
                "grind (indentationDepth {}, minPressureRatio {}, contactWidth {})",
                Compact(d),
                Compact(delta),
                Compact(lc)
            ),
            value: kappa,
            range: "a finite number greater than 0",
        });
    }
    Ok(kappa)
}

/// An angle in `[MIN_ANGLE_RAD, π]`, or why not.
fn angle(name: &'static str, value: Real) -> Result<Real, ParamError> {
    let a = finite(name, value)?;
    if !(a > 0.0 && a <= PI) {
        return Err(ParamError::OutOfRange {
            name,
            value: a,
            range: "in (0, π] radians",
        });
    }
    if a < MIN_ANGLE_RAD {
        return Err(ParamError::OutOfRange {
            name,
            value: a,
            range: TOO_SMALL_ANGLE,
        });
    }
    Ok(a)
}

impl Criterion {
    /// The growing threshold this criterion stands for, or why it is invalid.
    pub fn threshold(&self) -> Result<GrowthThreshold, ParamError> {
        match self {
            Criterion::Angle { alpha_rad } => {
                angle("angleThreshold", *alpha_rad).map(GrowthThreshold::Angle)
            }
            Criterion::Curvature { kappa } => Ok(GrowthThreshold::Curvature(positive(
                "curvatureThreshold",
                *kappa,
            )?)),
            Criterion::Spray(p) => spray_angle_threshold(p).map(GrowthThreshold::Angle),
            Criterion::Grind(p) => grind_curvature_threshold(p).map(GrowthThreshold::Curvature),
        }
    }
}

impl SegmentParams {
    /// Checks every parameter and returns the growing threshold.
    pub fn validate(&self) -> Result<GrowthThreshold, ParamError> {
        let threshold = self.criterion.threshold()?;
        // Below MIN_ANGLE_RAD no face would fit even its own mean (see there).
        angle("thetaMax", self.theta_max_rad)?;
        let ratio = finite("minAreaRatio", self.min_area_ratio)?;
        if !(0.0..1.0).contains(&ratio) {
            return Err(ParamError::OutOfRange {
                name: "minAreaRatio",
                value: ratio,
                range: "at least 0 and less than 1",
            });
        }
        Ok(threshold)
    }
}

/// The parameters as JavaScript (or JSON) spells them: exactly one of `angleThreshold`,
/// `curvatureThreshold`, `spray`, `grind`; `thetaMax`, `minAreaRatio` and `seedRule` default
/// to the paper's values and [`SeedRule::default`].
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct ParamsSpec {
    /// Direct angle threshold, radians.
    pub angle_threshold: Option<Real>,
    /// Direct curvature threshold, 1 / mesh unit.
    pub curvature_threshold: Option<Real>,
    /// Spraying parameters (Eq. 9).
    pub spray: Option<Checked<SprayParams>>,
    /// Grinding parameters (Eq. 4).
    pub grind: Option<Checked<GrindParams>>,
    /// θmax, radians.
    pub theta_max: Option<Real>,
    /// ε, share of the total area.
    pub min_area_ratio: Option<Real>,
    /// Planarisation seed rule.
    pub seed_rule: Option<SeedRule>,
    /// Fields not listed above, refused by the conversion.
    #[serde(flatten)]
    pub unknown: std::collections::BTreeMap<String, serde::de::IgnoredAny>,
}

/// A parameter group plus whatever other fields came with it. Unknown names are caught here
/// rather than with `deny_unknown_fields`, which some deserialisers (serde-wasm-bindgen)
/// do not enforce for structs.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
pub struct Checked<T> {
    /// The known fields.
    #[serde(flatten)]
    pub value: T,
    /// Every other field, refused by the conversion.
    #[serde(flatten)]
    pub unknown: std::collections::BTreeMap<String, serde::de::IgnoredAny>,
}

impl<T> From<T> for Checked<T> {
    fn from(value: T) -> Self {
        Checked {
            value,
            unknown: Default::default(),
        }
    }
}

fn refuse_unknown<V>(
    prefix: &str,
    unknown: &std::collections::BTreeMap<String, V>,
) -> Result<(), ParamError> {
    match unknown.keys().next() {
        Some(name) => Err(ParamError::Unknown {
            name: format!("{prefix}{name}"),
        }),
        None => Ok(()),
    }
}

impl TryFrom<ParamsSpec> for SegmentParams {
    type Error = ParamError;

    fn try_from(spec: ParamsSpec) -> Result<Self, ParamError> {
        refuse_unknown("", &spec.unknown)?;
        if let Some(p) = &spec.spray {
            refuse_unknown("spray.", &p.unknown)?;
        }
        if let Some(p) = &spec.grind {
            refuse_unknown("grind.", &p.unknown)?;
        }
        let mut criteria = Vec::new();
        let mut names = Vec::new();
        if let Some(alpha_rad) = spec.angle_threshold {
            criteria.push(Criterion::Angle { alpha_rad });
            names.push("angleThreshold");
        }
        if let Some(kappa) = spec.curvature_threshold {
            criteria.push(Criterion::Curvature { kappa });
            names.push("curvatureThreshold");
        }
        if let Some(p) = spec.spray {
            criteria.push(Criterion::Spray(p.value));
            names.push("spray");
        }
        if let Some(p) = spec.grind {
            criteria.push(Criterion::Grind(p.value));
            names.push("grind");
        }
        let [criterion] = criteria[..] else {
            let given = if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            };
            return Err(ParamError::CriterionCount { given });
        };
        let defaults = SegmentParams::default();
        let params = SegmentParams {
            criterion,
            theta_max_rad: spec.theta_max.unwrap_or(defaults.theta_max_rad),
            min_area_ratio: spec.min_area_ratio.unwrap_or(defaults.min_area_ratio),
            seed_rule: spec.seed_rule.unwrap_or_default(),
        };
        params.validate()?;
        Ok(params)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_small_angle_message_states_the_constant() {
        assert!(TOO_SMALL_ANGLE.starts_with(&format!("at least {MIN_ANGLE_RAD:e} radians")));
        // At the limit a unit normal still fits its own mean in the cosine test planarise uses.
        assert!(crate::math::cos(MIN_ANGLE_RAD) < 1.0 - 4.0 * Real::EPSILON);
    }

    #[test]
    fn derived_thresholds_that_overflow_or_underflow_are_refused() {
        for (d, lc, value) in [(1e-300, 1e150, "0"), (1e300, 1e-300, "Infinity")] {
            // The message spells huge and tiny inputs with an exponent.
            let spelled =
                format!("indentationDepth {d:e}, minPressureRatio 0.5, contactWidth {lc:e}");
            let p = GrindParams {
                indentation_depth: d,
                min_pressure_ratio: 0.5,
                contact_width: lc,
            };
            let message = grind_curvature_threshold(&p).unwrap_err().to_string();
            assert!(
                message.contains(&format!(
                    "is {value}, but it must be a finite number greater than 0"
                )),
                "{message}"
            );
            assert!(message.contains(&spelled), "{message}");
        }
        // (Qd − ΔQd) / Qmin one ulp below 1: arccos ≈ 1.5e-8 rad, below the resolution.
        let p = SprayParams {
            mean_thickness: 1.0,
            allowed_deviation: Real::EPSILON / 2.0,
            min_thickness: 1.0,
        };
        let message = spray_angle_threshold(&p).unwrap_err().to_string();
        assert!(
            message.contains("angle threshold (rad) derived from spray"),
            "{message}"
        );
    }
}
