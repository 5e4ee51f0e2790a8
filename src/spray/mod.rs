//! Spray trajectories with a coating-thickness model (seed 002: the Tsinghua patent "a
//! trajectory planning method for curved-surface spraying").
//!
//! [`plan_spray`] cuts the selected faces with parallel scan planes ([`scan_passes`]),
//! offsets the scan segments by the standoff and joins them with straight or arc
//! transitions ([`build_trajectory`]), predicts the coating on evaluation samples
//! ([`sample_faces`], [`deposit`]), measures its quality ([`evaluate_quality`]) and, given
//! quality limits, searches the widest pass spacing meeting them ([`search_spacing`]); by
//! default the gun speed is optimised piece by piece along the passes ([`optimise_speeds`]).

mod deposition;
mod grid;
mod normal_equations;
mod params;
mod plan;
mod quality;
mod raster;
mod samples;
mod sampling;
mod search;
mod speed;
mod trajectory;

pub use deposition::{
    deposit, time_sample_count, SprayModel, CHORD_TOLERANCE_RATIO, CHUNK_RADIUS_RATIO,
    CHUNK_TURN_RAD, MAX_AXIAL_RATIO,
};
pub use grid::PointGrid;
pub use params::{
    QualityLimits, Resolved, SprayError, SprayParams, MAX_COATING_ENTRIES, MAX_PLANES, MAX_SAMPLES,
    MAX_TIME_SAMPLES,
};
pub use plan::{
    cycle_time, plan_spray, plan_spray_cached, DirectionTrial, Hotspot, HotspotCause, SprayPlan,
    MAX_HOTSPOTS, TARGET_TOLERANCE,
};
pub use quality::{evaluate_quality, interior_mask, thickness_stats, Quality, ThicknessStats};
pub use raster::{
    order_zigzag, patch_frame, scan_passes, PatchFrame, ScanPass, ARC_BINS, JOIN_GAP_RATIO,
    MAX_STRETCH,
};
pub use samples::{fit_resolution, sample_faces, EvaluationSamples};
pub use sampling::{SampleCache, COARSE_RESOLUTION_RATIO};
pub use search::{
    ripple, search_spacing, Fidelity, Iteration, Limits, SpacingChoice, COARSE_STEPS,
    FALLBACK_MARGIN, PREDICTED_WINDOWS, PREDICTION_STEPS, REFINE_STEPS, REFINE_TOLERANCE,
};
pub use speed::{
    optimise_speeds, split_long_moves, SpeedLimits, SpeedPlan, MAX_SWEEPS, MINIMAX_ROUNDS,
    PIECE_RADIUS_RATIO, SMOOTHING,
};
pub use trajectory::{build_trajectory, TrajectoryCounts, ARC_STEP_RAD, TURN_ON_RADIUS_RATIO};
