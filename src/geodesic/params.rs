//! Parameters, errors and the progress callback shared by the geodesic module.

use crate::math::{Compact, Real};

/// A geodesic input is invalid; every message names the parameter and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeodesicError {
    /// A numeric parameter is NaN, infinite or out of range.
    #[error("geodesic parameter {name} = {} is invalid: {why}", Compact(*.value))]
    BadParam {
        /// Parameter name as the caller writes it.
        name: &'static str,
        /// The value given.
        value: Real,
        /// What is allowed.
        why: &'static str,
    },
    /// The source does not touch the surface (or the selected faces).
    #[error("the geodesic source misses the surface: {0}")]
    SourceMissesSurface(String),
    /// The source is empty or malformed (too few points, a vertex id out of range, …).
    #[error("the geodesic source is invalid: {0}")]
    BadSource(String),
    /// The face subset is empty or names a face that does not exist.
    #[error("the face set is invalid: {0}")]
    BadFaces(String),
    /// The voxel size would need more memory than allowed.
    #[error(
        "voxel size {} is too small: about {estimated_voxels} voxels ({estimated_bytes} bytes) \
         would exceed the memory limit of {limit_bytes} bytes; use a voxel size of at least {}",
        Compact(*.voxel_size),
        Compact(*.min_size)
    )]
    VoxelTooSmall {
        /// The voxel edge requested.
        voxel_size: Real,
        /// Estimated voxel count.
        estimated_voxels: u64,
        /// Estimated bytes.
        estimated_bytes: u64,
        /// The limit.
        limit_bytes: u64,
        /// The smallest voxel edge that fits.
        min_size: Real,
    },
    /// The passes asked for would be too large to compute or to export.
    #[error(
        "the passes would need more than {} {what}, the most one computation may have: widen \
         the pass spacing or the point spacing, or ask for fewer passes",
        millions(*.limit)
    )]
    PassesTooLarge {
        /// How many (at least).
        count: u64,
        /// Of what: points, or crossings of faces.
        what: &'static str,
        /// The most allowed.
        limit: u64,
    },
    /// A bounded loop reached its cap (a guard against pathological input, never a hang).
    #[error("geodesic computation stopped: {0}")]
    LimitExceeded(String),
}

/// Which distance computation to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Dijkstra-ordered propagation of explicit virtual sources (see `virtual_source.rs`):
    /// near the exact polyhedral distance (second order in the edge length away from where
    /// fronts meet) at the cost of fast marching. The default. On a small surface with a corner or
    /// a hole, where the exact method finishes within a budget of windows (a whole coarse aircraft
    /// model, a panel with cut-outs: corners are where virtual sources err most, they are held to
    /// the shadow of a hole only partly, and few faces make the exact method cheap), the exact
    /// distance instead, and the field reports [`Method::Exact`] (see
    /// [`DistanceParams::exact_first_windows`]).
    Accurate,
    /// Per-vertex distance by unfolded wavefront propagation: fast, exact on developable
    /// surfaces, first order where fronts meet on doubly curved ones (see `unfolding.rs`);
    /// approximate (millimetres off on large doubly curved panels). Formerly `mesh`.
    Fast,
    /// The paper's voxel front propagation (Li & Zhang 2021, steps 1–3).
    Voxel,
    /// Exact polyhedral distance by window propagation (Xin & Wang 2009, ICH).
    Exact,
}

impl Method {
    /// The method's name as the JavaScript API spells it.
    pub fn name(self) -> &'static str {
        match self {
            Method::Accurate => "accurate",
            Method::Fast => "fast",
            Method::Voxel => "voxel",
            Method::Exact => "exact",
        }
    }
}

/// Parameters of [`geodesic_distance`](super::geodesic_distance).
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceParams {
    /// Accurate (default), exact, fast or voxel method.
    pub method: Method,
    /// Voxel edge `L` (mesh unit) for the voxel method; `None`: mean edge length / 4.
    pub voxel_size: Option<Real>,
    /// Memory limit for the voxel method, bytes (refused before allocating if exceeded).
    pub max_voxel_bytes: u64,
    /// Restrict the computation to these faces (a patch); `None`: the whole mesh.
    pub faces: Option<Vec<u32>>,
    /// Source points farther than this from the surface are refused; `None`: 5 mean edge
    /// lengths.
    pub max_snap_distance: Option<Real>,
    /// Exact method: windows processed at most before [`GeodesicError::LimitExceeded`];
    /// `None`: `64·√max(1, E/10⁴)` per edge for `E` edges, plus 2²⁰.
    pub max_windows: Option<u64>,
    /// Accurate method: windows the exact method may process before the virtual-source
    /// propagation runs instead (it gives up sooner when on course for 1.1 times as many).
    /// `None`: automatic, `64` per face (at least 2²²) on a surface of at most 100k faces
    /// with a corner (an interior vertex whose angle defect exceeds 0.05 rad) or a hole (a
    /// boundary loop turning as a hole's rim does), none elsewhere; `Some(0)`: never. See
    /// [`Method::Accurate`].
    pub exact_first_windows: Option<u64>,
}

/// A count in millions, one decimal (`5.0 million`).
fn millions(n: u64) -> String {
    format!("{:.1} million", n as f64 / 1e6)
}

impl Default for DistanceParams {
    fn default() -> Self {
        DistanceParams {
            method: Method::Accurate,
            voxel_size: None,
            max_voxel_bytes: 1 << 30,
            faces: None,
            max_snap_distance: None,
            max_windows: None,
            exact_first_windows: None,
        }
    }
}

/// How consecutive passes are joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkOrder {
    /// Every pass starts at the end nearest to where the previous one stopped (alternating).
    ZigZag,
    /// Every pass runs in the same direction as the first one.
    OneDirection,
}

/// Parameters of iso-distance paths and their tool path.
#[derive(Clone, Debug, PartialEq)]
pub struct PathParams {
    /// Geodesic distance between neighbouring passes (mesh unit), > 0.
    pub spacing: Real,
    /// Distance between consecutive points of a pass; `None`: spacing / 4.
    pub point_spacing: Option<Real>,
    /// Highest level `K` (levels `1..=K`); `None`: every level up to the largest distance.
    pub max_level: Option<u32>,
    /// Zig-zag or one direction.
    pub order: LinkOrder,
    /// Process speed (mesh unit per second).
    pub speed: Real,
    /// Link speed (mesh unit per second).
    pub link_speed: Real,
}

impl Default for PathParams {
    fn default() -> Self {
        PathParams {
            spacing: 10.0,
            point_spacing: None,
            max_level: None,
            order: LinkOrder::ZigZag,
            speed: 10.0,
            link_speed: 100.0,
        }
    }
}

impl PathParams {
    /// Spacing from a bead width and an overlap factor (the paper: 6.4 mm × 0.738 ≈ 4.7 mm).
    pub fn from_bead(bead_width: Real, overlap_factor: Real) -> Result<Self, GeodesicError> {
        positive("beadWidth", bead_width)?;
        if !(overlap_factor.is_finite() && overlap_factor > 0.0 && overlap_factor <= 1.0) {
            return Err(GeodesicError::BadParam {
                name: "overlapFactor",
                value: overlap_factor,
                why: "must be in (0, 1]",
            });
        }
        Ok(PathParams {
            spacing: bead_width * overlap_factor,
            ..PathParams::default()
        })
    }

    /// Checks every field.
    pub fn validate(&self) -> Result<(), GeodesicError> {
        positive("spacing", self.spacing)?;
        if let Some(p) = self.point_spacing {
            positive("pointSpacing", p)?;
        }
        positive("speed", self.speed)?;
        positive("linkSpeed", self.link_speed)?;
        Ok(())
    }
}

/// `Ok` when `value` is finite and > 0, else a [`GeodesicError::BadParam`] naming it.
pub(crate) fn positive(name: &'static str, value: Real) -> Result<(), GeodesicError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GeodesicError::BadParam {
            name,
            value,
            why: "must be finite and > 0",
        })
    }
}

/// Progress callback: `(stage, fraction in [0, 1])`.
pub type Progress<'a> = &'a mut dyn FnMut(&str, f64);

/// How often (in processed items) long loops report progress.
pub(crate) const PROGRESS_EVERY: usize = 1 << 16;
