//! The gun trajectory: offset pass segments, transitions, extensions and links.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), steps 3–5 (claim 1): each triangle's scan
//! points move by the standoff `h` along its normal `n`, gun axis `−n`; between adjacent
//! triangles whose normals make an angle `β`, a straight transition if `β ≤ β_T` (gun axis
//! perpendicular to it, towards the part), else a convex arc of radius `h` around the edge
//! (gun axis radial); passes are linked in zig-zag order.
//! Input:  passes from [`scan_passes`](super::raster::scan_passes), face normals, `h`, `β_T`.
//! Output: a [`ToolPath`]. A pose's kind is the kind of the move that arrives at it (the
//!         first pose of each pass is reached by a gun-off link).
//! Cost:   linear in the number of scan segments.
//! Deviations: the patent treats convex edges only. On a concave edge the two offset
//!         segments cross; both are trimmed at their crossing (the midpoint of the closest
//!         points of the two lines, clamped to the segments and never behind the previous
//!         pose) with the bisector axis, instead of moving backwards; a note in the path says
//!         so. Arcs are polylines of at most [`ARC_STEP_RAD`] per step. Coplanar, collinear
//!         segments are merged. Passes are continued past the boundary by `extension` along
//!         the end segments (gun on); links are straight moves at the standoff (gun off).

use super::raster::ScanPass;
use crate::math::{angle_between, any_perpendicular, Point3, Real, Vector3};
use crate::toolpath::{Pose, PoseKind, ToolPath};

/// Largest turn of the gun axis between two poses of an arc, radians (5°).
pub const ARC_STEP_RAD: Real = 0.087_266_462_599_716_48;
/// Normals closer than this angle (radians) count as coplanar: no transition.
const COPLANAR_RAD: Real = 1e-6;

/// Counts of what the trajectory contains.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TrajectoryCounts {
    /// Straight transitions (convex, `β ≤ β_T`).
    pub straight: usize,
    /// Arcs (convex, `β > β_T`).
    pub arcs: usize,
    /// Concave edges where the offset segments were trimmed.
    pub trimmed: usize,
}

/// Unit vector along `t` made perpendicular to `axis`; any perpendicular when `t ∥ axis`.
fn perpendicular(t: Vector3, axis: &Vector3) -> Vector3 {
    let p = t - axis * axis.dot(&t);
    let n = p.norm();
    if n > 1e-12 {
        p / n
    } else {
        any_perpendicular(axis)
    }
}

/// Builds the trajectory of `passes` (already in execution order and direction).
pub fn build_trajectory(
    passes: &[ScanPass],
    normals: &[Vector3],
    standoff: Real,
    transition_angle: Real,
    extension: Real,
    speed: Real,
) -> (ToolPath, TrajectoryCounts) {
    let mut poses: Vec<Pose> = Vec::new();
    let mut counts = TrajectoryCounts::default();
    for (pass_index, pass) in passes.iter().enumerate() {
        let pass_id = pass_index as u32;
        let m = pass.faces.len();
        if m == 0 {
            continue;
        }
        let n: Vec<Vector3> = pass.faces.iter().map(|&f| normals[f as usize]).collect();
        let t: Vec<Vector3> = (0..m)
            .map(|i| (pass.points[i + 1] - pass.points[i]).normalize())
            .collect();
        let mut push = |position: Point3, axis: Vector3, travel: Vector3, kind: PoseKind| {
            poses.push(Pose {
                position,
                axis,
                travel: perpendicular(travel, &axis),
                kind,
                pass: pass_id,
            });
        };
        let start = pass.points[0] + n[0] * standoff;
        if extension > 0.0 {
            push(start - t[0] * extension, -n[0], t[0], PoseKind::Link);
            push(start, -n[0], t[0], PoseKind::Extension);
        } else {
            push(start, -n[0], t[0], PoseKind::Link);
        }
        let mut last = start;
        for j in 0..m.saturating_sub(1) {
            let (ni, nj) = (n[j], n[j + 1]);
            let beta = angle_between(&ni, &nj);
            if beta < COPLANAR_RAD && angle_between(&t[j], &t[j + 1]) < COPLANAR_RAD {
                continue;
            }
            let edge = pass.points[j + 1];
            let (a, b) = (edge + ni * standoff, edge + nj * standoff);
            // Opposite normals (a fold back onto itself) have no bisector: keep the first.
            let sum = ni + nj;
            let bisector = if sum.norm() > 1e-9 {
                sum.normalize()
            } else {
                ni
            };
            if nj.dot(&t[j]) >= 0.0 {
                // Convex edge (or a kink within a plane): the offset segments leave a gap.
                push(a, -ni, t[j], PoseKind::Pass);
                if beta <= transition_angle {
                    let chord = if (b - a).norm() > 0.0 {
                        (b - a).normalize()
                    } else {
                        t[j]
                    };
                    if beta >= COPLANAR_RAD {
                        counts.straight += 1;
                        push(a, -bisector, chord, PoseKind::StraightTransition);
                        push(b, -bisector, chord, PoseKind::StraightTransition);
                    }
                    push(b, -nj, t[j + 1], PoseKind::Pass);
                } else {
                    counts.arcs += 1;
                    let steps = (beta / ARC_STEP_RAD).ceil().max(1.0) as usize;
                    let mut previous = a;
                    for s in 1..=steps {
                        let phi = s as Real / steps as Real;
                        // Slerp of the normal from ni to nj.
                        let w0 = libm::sin((1.0 - phi) * beta);
                        let w1 = libm::sin(phi * beta);
                        let mixed = ni * w0 + nj * w1;
                        let radial = if mixed.norm() > 1e-9 {
                            mixed.normalize()
                        } else {
                            nj
                        };
                        let p = edge + radial * standoff;
                        push(p, -radial, p - previous, PoseKind::Arc);
                        previous = p;
                    }
                }
                last = b;
            } else {
                // Concave edge: the offset segments cross; trim both at the crossing.
                counts.trimmed += 1;
                let (ti, tj) = (t[j], t[j + 1]);
                let len_i = (pass.points[j + 1] - pass.points[j]).norm();
                let len_j = (pass.points[j + 2] - pass.points[j + 1]).norm();
                let w = a - b;
                let (bb, d, e) = (ti.dot(&tj), ti.dot(&w), tj.dot(&w));
                let denom = 1.0 - bb * bb;
                let (mut s, mut u) = if denom > 1e-12 {
                    ((bb * e - d) / denom, (e - bb * d) / denom)
                } else {
                    (0.0, 0.0)
                };
                s = s.clamp(-len_i, 0.0);
                u = u.clamp(0.0, len_j);
                let mut x = Point3::from(((a + ti * s).coords + (b + tj * u).coords) * 0.5);
                if (x - last).dot(&ti) < 0.0 {
                    x = last;
                }
                push(x, -bisector, ti + tj, PoseKind::Pass);
                last = x;
            }
        }
        let end = pass.points[m] + n[m - 1] * standoff;
        push(end, -n[m - 1], t[m - 1], PoseKind::Pass);
        if extension > 0.0 {
            push(
                end + t[m - 1] * extension,
                -n[m - 1],
                t[m - 1],
                PoseKind::Extension,
            );
        }
    }
    let mut notes = vec![
        "spray trajectory after the patent 'a trajectory planning method for curved-surface spraying' (Tsinghua University): scan planes, offset by the standoff, straight or arc transitions".to_string(),
    ];
    if counts.trimmed > 0 {
        notes.push(format!(
            "{} concave edges: the offset segments crossed and were trimmed at their crossing instead of moving backwards (the patent treats convex edges only)",
            counts.trimmed
        ));
    }
    (
        ToolPath {
            poses,
            speed,
            link_speed: speed,
            speeds: Vec::new(),
            notes,
        },
        counts,
    )
}
