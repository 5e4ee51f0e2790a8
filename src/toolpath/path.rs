//! The tool-path data type: poses with a tool axis and a travel direction.

use crate::math::{Point3, Real, Vector3};

/// What the tool does at a pose. The numeric codes are part of the JavaScript API
/// (`pointKinds()`), so they never change.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "camelCase")]
#[repr(u8)]
pub enum PoseKind {
    /// On a process pass (gun on / torch on / tool engaged).
    Pass = 0,
    /// A straight transition between two pass segments (process on).
    StraightTransition = 1,
    /// An arc transition around a convex edge (process on).
    Arc = 2,
    /// A pass continued past the patch boundary (process on).
    Extension = 3,
    /// A link move between passes (process off).
    Link = 4,
    /// Approach towards a process point (process off), e.g. before drilling.
    Approach = 5,
    /// Retract from a process point (process off).
    Retract = 6,
}

impl PoseKind {
    /// Whether the process (spray gun, torch, spindle feed) is on while moving to this pose.
    pub fn process_on(self) -> bool {
        matches!(
            self,
            PoseKind::Pass | PoseKind::StraightTransition | PoseKind::Arc | PoseKind::Extension
        )
    }
    /// The numeric code of the JavaScript API.
    pub fn code(self) -> u8 {
        self as u8
    }
    /// The name used in the CSV and JSON exports (camelCase, as serde writes it).
    pub fn name(self) -> &'static str {
        match self {
            PoseKind::Pass => "pass",
            PoseKind::StraightTransition => "straightTransition",
            PoseKind::Arc => "arc",
            PoseKind::Extension => "extension",
            PoseKind::Link => "link",
            PoseKind::Approach => "approach",
            PoseKind::Retract => "retract",
        }
    }
    /// Every kind, in code order.
    pub const ALL: [PoseKind; 7] = [
        PoseKind::Pass,
        PoseKind::StraightTransition,
        PoseKind::Arc,
        PoseKind::Extension,
        PoseKind::Link,
        PoseKind::Approach,
        PoseKind::Retract,
    ];
}

/// One robot target: a position, the unit tool axis (pointing from the tool towards the part)
/// and the unit travel direction, in the mesh's unit. The exports use the part of `travel`
/// perpendicular to `axis`; a travel along the axis (drilling) is allowed and gets the
/// fallback of [`super::frames`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Tool centre point, mesh unit.
    pub position: Point3,
    /// Unit tool axis, towards the part (the tool frame's Z).
    pub axis: Vector3,
    /// Unit travel direction, normally perpendicular to `axis` (the tool frame's X).
    pub travel: Vector3,
    /// What the tool does here.
    pub kind: PoseKind,
    /// Index of the pass (or hole) this pose belongs to.
    pub pass: u32,
}

/// A tool path is invalid (a non-finite coordinate, a zero axis, a bad speed).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ToolPathError {
    /// A pose has a non-finite coordinate or a non-unit axis / travel direction.
    #[error("pose {index} is invalid: {what}")]
    BadPose {
        /// Index of the pose.
        index: usize,
        /// What is wrong.
        what: &'static str,
    },
    /// The speed is not finite and positive.
    #[error("the tool-path speed must be finite and positive, got {}", crate::math::Compact(*.0))]
    BadSpeed(Real),
    /// The tool path has no poses: there is nothing to export.
    #[error("the tool path has no poses")]
    Empty,
    /// An export option is out of range.
    #[error("export option {name} is invalid: {why}")]
    BadOption {
        /// The option's name as the caller wrote it.
        name: &'static str,
        /// Why it is refused.
        why: String,
    },
}

/// A sequence of poses with the process speed, ready for export.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolPath {
    /// The poses in execution order.
    pub poses: Vec<Pose>,
    /// Process speed along the path (mesh unit per second).
    pub speed: Real,
    /// Speed for moves with the process off (links, approach, retract), mesh unit per second.
    pub link_speed: Real,
    /// Speed of the move that arrives at each pose, mesh unit per second, when it varies
    /// along the path (a spray plan with optimised gun speeds); empty when every process-on
    /// move runs at `speed` and every other move at `link_speed`. Read it through
    /// [`ToolPath::move_speed`].
    pub speeds: Vec<Real>,
    /// Lines for the header of every exported file (what produced it, parameters, caveats).
    pub notes: Vec<String>,
}

impl ToolPath {
    /// Checks every pose: finite position, unit axis and travel within 1e-6, and the speeds.
    pub fn validate(&self) -> Result<(), ToolPathError> {
        for s in [self.speed, self.link_speed] {
            if !(s.is_finite() && s > 0.0) {
                return Err(ToolPathError::BadSpeed(s));
            }
        }
        if !self.speeds.is_empty() && self.speeds.len() != self.poses.len() {
            return Err(ToolPathError::BadOption {
                name: "speeds",
                why: format!(
                    "{} speeds for {} poses (one per pose, or none)",
                    self.speeds.len(),
                    self.poses.len()
                ),
            });
        }
        if let Some(&s) = self.speeds.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
            return Err(ToolPathError::BadSpeed(s));
        }
        for (index, p) in self.poses.iter().enumerate() {
            let bad = |what| Err(ToolPathError::BadPose { index, what });
            if !p.position.coords.iter().all(|c| c.is_finite()) {
                return bad("non-finite position");
            }
            if (p.axis.norm() - 1.0).abs() > 1e-6 {
                return bad("tool axis is not a unit vector");
            }
            if (p.travel.norm() - 1.0).abs() > 1e-6 {
                return bad("travel direction is not a unit vector");
            }
        }
        Ok(())
    }
    /// Speed of the move that arrives at pose `i` (the first pose's is that of the move to
    /// it from wherever the tool stands).
    pub fn move_speed(&self, i: usize) -> Real {
        match self.speeds.get(i) {
            Some(&s) => s,
            None if self.poses.get(i).is_some_and(|p| p.kind.process_on()) => self.speed,
            None => self.link_speed,
        }
    }
    /// Whether the speed varies from move to move (per-pose speeds are present).
    pub fn has_varying_speed(&self) -> bool {
        !self.speeds.is_empty()
    }
    /// Number of distinct passes (the largest pass index + 1; 0 when empty).
    pub fn pass_count(&self) -> usize {
        self.poses
            .iter()
            .map(|p| p.pass as usize + 1)
            .max()
            .unwrap_or(0)
    }
}
