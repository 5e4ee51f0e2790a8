//! Why a drilling computation refused its input.

use crate::math::{Compact, Real};

/// Bad input to the drilling module; each message names the offending value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DrillError {
    /// A number that must be finite is NaN or infinite.
    #[error("{name} must be finite, got {}", Compact(*.value))]
    NonFinite {
        /// What the value is (e.g. "reading of beam 2", "hole 5 x").
        name: String,
        /// The value.
        value: Real,
    },
    /// A parameter is out of its allowed range.
    #[error("{name} = {} is invalid: {allowed}", Compact(*.value))]
    BadParam {
        /// The parameter's name as the caller wrote it.
        name: &'static str,
        /// The refused value.
        value: Real,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A laser beam direction is zero or not a unit vector.
    #[error("direction of beam {beam} must be a unit vector, its length is {}", Compact(*.length))]
    BadBeamDirection {
        /// Beam number, 1-based.
        beam: usize,
        /// Its length.
        length: Real,
    },
    /// A laser reading is negative.
    #[error("reading of beam {beam} must be ≥ 0, got {}", Compact(*.value))]
    NegativeReading {
        /// Beam number, 1-based.
        beam: usize,
        /// The reading.
        value: Real,
    },
    /// The four laser points do not span a plane.
    #[error("the four laser points are degenerate: {0}")]
    DegenerateLaserPoints(String),
    /// The reference holes do not span a usable quadrilateral, or their normals are unusable.
    #[error("the reference holes are degenerate: {0}")]
    DegenerateReferences(String),
    /// A hole lies outside the reference quadrilateral and extrapolation was not requested.
    #[error(
        "hole {hole} lies outside the reference quadrilateral (u = {u:.4}, w = {w:.4}; inside is \
         0 ≤ u, w ≤ 1): move the reference holes or request extrapolation"
    )]
    Outside {
        /// Index of the hole (0-based, in input order).
        hole: usize,
        /// Its patch parameter across the flight direction (A→B).
        u: Real,
        /// Its patch parameter along the flight direction (A→D).
        w: Real,
    },
    /// The panel mesh has no point to project onto.
    #[error("the panel mesh gave no closest point for {0}")]
    NoClosestPoint(String),
}
