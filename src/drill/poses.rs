//! Drilling poses: approach, drill point and retract for every corrected hole.
//!
//! Source: no paper; the usual drilling cycle (approach along the axis with the spindle off,
//!         drill to the hole's surface point, retract along the axis).
//! Input:  a [`Correction`] (positions, outward normals, travel directions) and [`PoseParams`].
//! Output: a [`ToolPath`] with, per hole `i`, the poses [`PoseKind::Approach`] at
//!         `approach` outside the surface, [`PoseKind::Pass`] at the hole, and
//!         [`PoseKind::Retract`] at `retract` outside, all with `pass = i` and the tool axis
//!         `−normal` (into the part).
//! Cost:   O(holes).

use super::{Correction, DrillError};
use crate::math::Real;
use crate::toolpath::{Pose, PoseKind, ToolPath};

/// Distances and speeds of the drilling cycle, in the mesh's unit (and per second).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseParams {
    /// Distance of the approach pose from the surface along the normal, ≥ 0.
    pub approach: Real,
    /// Distance of the retract pose from the surface along the normal, ≥ 0.
    pub retract: Real,
    /// Feed speed while drilling, > 0.
    pub feed_speed: Real,
    /// Speed of the moves with the spindle feed off, > 0.
    pub link_speed: Real,
}

impl Default for PoseParams {
    /// 20 units approach and retract, feed 5 and links 100 units per second (millimetre
    /// meshes: a cautious drilling feed and a modest rapid).
    fn default() -> Self {
        PoseParams {
            approach: 20.0,
            retract: 20.0,
            feed_speed: 5.0,
            link_speed: 100.0,
        }
    }
}

/// The drilling cycle of every corrected hole, in input order.
pub fn drilling_path(
    correction: &Correction,
    params: &PoseParams,
    notes: Vec<String>,
) -> Result<ToolPath, DrillError> {
    for (name, value, strict) in [
        ("approach", params.approach, false),
        ("retract", params.retract, false),
        ("feedSpeed", params.feed_speed, true),
        ("linkSpeed", params.link_speed, true),
    ] {
        if !(value.is_finite() && (value > 0.0 || (!strict && value == 0.0))) {
            return Err(DrillError::BadParam {
                name,
                value,
                allowed: "distances must be finite and ≥ 0, speeds finite and > 0",
            });
        }
    }
    let mut poses = Vec::with_capacity(3 * correction.corrected.len());
    for (i, ((p, n), t)) in correction
        .corrected
        .iter()
        .zip(&correction.normals)
        .zip(&correction.travel)
        .enumerate()
    {
        let pose = |distance: Real, kind| Pose {
            position: p + n * distance,
            axis: -n,
            travel: *t,
            kind,
            pass: i as u32,
        };
        poses.push(pose(params.approach, PoseKind::Approach));
        poses.push(pose(0.0, PoseKind::Pass));
        poses.push(pose(params.retract, PoseKind::Retract));
    }
    let mut all_notes = vec![format!(
        "drilling poses: {} holes, approach {} and retract {} along the surface normal",
        correction.corrected.len(),
        params.approach,
        params.retract
    )];
    let extrapolated = correction.outside.iter().filter(|&&o| o).count();
    if extrapolated > 0 {
        all_notes.push(format!(
            "{extrapolated} holes lie outside the reference quadrilateral (extrapolated)"
        ));
    }
    all_notes.extend(notes);
    Ok(ToolPath {
        poses,
        speed: params.feed_speed,
        link_speed: params.link_speed,
        speeds: Vec::new(),
        notes: all_notes,
    })
}
