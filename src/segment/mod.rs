//! Surface segmentation into machinable patches (seed 000: Wang, Zhao, Tao 2019).
//!
//! [`segment`] runs the three steps: region growing with a process-derived threshold
//! ([`grow_regions`]), approximate planarisation of each region ([`planarise()`]), and removal
//! of patches below a share of the total area (in [`segment`] itself).

mod params;
mod planarise;
mod region_growing;
mod segmentation;

pub use params::{
    grind_curvature_threshold, spray_angle_threshold, Checked, Criterion, GrindParams,
    GrowthThreshold, ParamError, ParamsSpec, SeedRule, SegmentParams, SprayParams, MIN_ANGLE_RAD,
};
pub use planarise::{planarise, seed_order, Patches};
pub use region_growing::{grow_regions, Regions};
pub use segmentation::{segment, segment_with_progress, BorderEdge, Patch, Segmentation, DROPPED};
