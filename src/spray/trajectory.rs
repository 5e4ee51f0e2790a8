//! The gun trajectory: offset pass segments, transitions, concave loop removal, extensions and
//! links.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), steps 3–5 (claim 1): each triangle's scan
//! points move by the standoff `h` along its normal `n`, gun axis `−n`; between adjacent
//! triangles whose normals make an angle `β`, a straight transition if `β ≤ β_T` (gun axis
//! perpendicular to it, towards the part), else a convex arc of radius `h` around the edge
//! (gun axis radial); passes are linked in zig-zag order. Concave edges: invalid-loop removal
//! of a raw offset curve as in Choi & Park, "A pair-wise offset algorithm for 2D point-sequence
//! curve" (Computer-Aided Design 31, 1999), with a uniform grid in place of their sweep
//! (in [`loop_removal`]).
//! Input:  passes from [`scan_passes`](super::raster::scan_passes), face normals, `h`, `β_T`.
//! Output: a [`ToolPath`]. A pose's kind is the kind of the move that arrives at it (the
//!         first pose of each pass is reached by a gun-off link). No two consecutive poses
//!         share a position (within [`SAME_POSITION_RATIO`]`·h`): the gun never turns on the
//!         spot with the process on, which a controller would run as a dwell.
//! Cost:   per pass of `n` scan segments, O(n) to build the raw offset curve and
//!         O(n + c) for the loop removal, where `c` counts the kept offset edges met in the
//!         grid cells (one cell ≈ one mean offset edge) around each new edge: bounded per cell
//!         wherever the kept offset is a simple curve of bounded density, i.e. everywhere but
//!         where the surface's radius of curvature across the passes is within a cell of `h`
//!         (there the offsets of many segments pile up near the centre of curvature).
//! Deviations:
//!   - The patent treats convex edges only. In each scan plane the raw offset curve (the
//!     offset segments, the convex transitions, a concave edge joined straight from one
//!     offset to the next, and round caps of radius `h` around both pass ends) is cut where it
//!     crosses itself and the loop in between is dropped (no paper for the caps: they make the
//!     offset of an open pass a one-sided offset, so a pass ending in a concave corner, or a
//!     concave surface tighter than `h`, still turns at a crossing). So the pass turns where
//!     the offsets of the two sides cross, never behind them, with the bisector of the two
//!     axes there. Crossings are found in the projection on the pass's plane; a crossing's
//!     position is the midpoint of the two branches' points (they coincide when the normals
//!     lie in the scan plane). Only the pass's own scan polyline is kept clear: where the
//!     normals leave the scan plane, faces of neighbouring planes may come nearer than `h`.
//!     Passes without a concave edge skip the removal (their offset only turns away).
//!   - A concave edge whose offsets meet within both faces is resolved before the loop
//!     removal, in space (no paper): each offset line reaches the other face's offset plane
//!     (`h` from both faces) at `x1 = a + s·t_i` and `x2 = b + u·t_j`,
//!     `s = h(1 − cos β)/(n_j·t_i)`, `u = h(1 − cos β)/(n_i·t_j)`, two points of the line
//!     where the offset planes meet; the pass turns at their midpoint, at `h` from both
//!     faces, reached and left within the two offset planes. (Where the normals leave the
//!     scan plane, the two offsets lie at different distances from the pass in the
//!     projection and need not cross within the faces, so the plain join `a → b` stepped
//!     back by `2h·sin(β/2)`: about 120 times on the BWB's upper skin.) Only where `x1` and
//!     `x2` are no farther apart than `a` and `b`: they part by about `2h·tan(β/2)·cot ψ`
//!     for a pass crossing the edge at `ψ`, and a pass nearly along a concave edge would
//!     swerve towards it.
//!   - An uncut cap is replaced by the pass extension (gun on, `extension` along the end
//!     segment); a cap cut by a crossing stays (gun on, radial axis, poses of kind `Arc`):
//!     the pass then ends by turning around its end point at the standoff. A cap may be cut
//!     only where the end's normal lies within [`CAP_PLANE_SINE`] of the scan plane (the cap
//!     turns in the plane of that normal and the end direction) and the branches meet in
//!     space (within [`CAP_GAP_RATIO`]`·h`). Where the whole
//!     offset collapses (a concave surface of radius below `h`) the pass is the two caps up
//!     to their crossing, at distance `h` from both pass ends.
//!   - Normals within [`SMALL_TURN_RAD`] (rounding of `f32` coordinates) get no transition.
//!   - A straight transition runs from the first segment's offset end (axis `−n_i`) through
//!     its midpoint (axis `−(n_i + n_j)`, perpendicular to it as in the patent) to the next
//!     segment's offset start (axis `−n_j`): the reorientation is spread over the
//!     transition instead of done on the spot. Arcs are polylines of at most
//!     [`ARC_STEP_RAD`] per step. Coplanar, collinear segments are merged. Links are straight
//!     moves at the standoff (gun off).
//!   - Gun off over long convex turns (no paper): while the gun turns over a convex edge by
//!     `β` (a straight transition or an arc) its axis stays on the edge, so the edge gets the
//!     spray of a spot that stands still for the turn's travel `τ` (`2h·sin(β/2)`, or about
//!     `h·β` for an arc): at constant speed, summed over parallel passes, about
//!     `8h·sin β / (3πR) ≈ 0.85·τ/R` of the mean coating on the fold line (+113 % for a 29°
//!     arc at h 250 mm, α 40°), more than the speed limits can take back. A turn longer than
//!     `max_turn_on` (the planner passes [`TURN_ON_RADIUS_RATIO`]`·R`) keeps its poses and
//!     runs with the gun off (kind `Link`): the spray then leaves one face at the edge and
//!     resumes on the other at the edge, as over a flat part. Shorter turns (a finely
//!     faceted curve) stay on; the speed optimisation takes back their smaller excess.

mod loop_removal;

use super::raster::ScanPass;
use crate::math::{angle_between, any_perpendicular, Point3, Real, Vector3};
use crate::toolpath::{Pose, PoseKind, ToolPath};
use loop_removal::{remove_loops, Caps, Kept, Node};

/// A convex turn whose gun travel exceeds this multiple of the footprint radius `R` runs with
/// the gun off (see the file header): a shorter one adds at most about 8.5 % on its edge.
pub const TURN_ON_RADIUS_RATIO: Real = 0.1;
/// Largest turn of the gun axis between two poses of an arc, radians (5°).
pub const ARC_STEP_RAD: Real = 0.087_266_462_599_716_48;
/// A crossing cuts a cap only where the two branches are closer in space than this multiple
/// of the standoff.
const CAP_GAP_RATIO: Real = 0.05;
/// A cap may be cut only when the end's normal is within this sine of the scan plane.
const CAP_PLANE_SINE: Real = 0.25;
/// Relative slack on the number of arc steps (see [`arc_steps`]).
const ARC_STEP_SLACK: Real = 1e-6;
/// A gun-on backtrack (a turn beyond 150°) with a leg shorter than this multiple of the
/// standoff loses the pose at its tip (no paper; see [`build_trajectory`]). A concave join's
/// back leg is `2h·sin(β/2)`, and the chord that replaces it comes at most `h(1 − cos β)`,
/// i.e. `leg²/(2h)`, nearer the part: within 1 % of `h` for legs up to `√0.02·h`.
pub const BACKTRACK_RATIO: Real = 0.14;
/// Cosine of the turn beyond which consecutive moves count as turning back (150°, as the
/// exporters' exact stops).
const REVERSAL_COS: Real = -0.866_025_403_784_438_6;
/// Consecutive poses closer than this multiple of the standoff are merged into one.
pub const SAME_POSITION_RATIO: Real = 1e-6;
/// Normals closer than this angle (radians) count as coplanar: no transition.
const COPLANAR_RAD: Real = 1e-6;
/// Normals closer than this angle (radians) get no transition: the offsets of both sides
/// are within `10⁻⁴·h` (rounding of `f32` coordinates leaves turns of a few µrad).
const SMALL_TURN_RAD: Real = 1e-4;
/// Segment directions whose cross product is shorter than this give no scan-plane normal
/// (the pass is straight).
const STRAIGHT_SINE: Real = 1e-6;

/// Counts of what the trajectory contains.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TrajectoryCounts {
    /// Straight transitions (convex, `β ≤ β_T`).
    pub straight: usize,
    /// Arcs (convex, `β > β_T`).
    pub arcs: usize,
    /// Convex turns (straight transitions and arcs, counted there too) run with the gun off:
    /// their gun travel exceeds the longest turn allowed with the gun on.
    pub turns_off: usize,
    /// Concave edges: their offsets crossed and the offset behind the crossing was removed.
    pub trimmed: usize,
    /// Pass ends where a crossing cut the round cap, so the pass ends by turning around its
    /// end point at the standoff instead of with the extension.
    pub capped: usize,
    /// Short gun-on backtracks removed (a concave crossing just behind the previous pose).
    pub backtracks: usize,
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

/// `v` normalised, or `fallback` when it vanishes.
fn unit_or(v: Vector3, fallback: &Vector3) -> Vector3 {
    let n = v.norm();
    if n > 1e-9 {
        v / n
    } else {
        *fallback
    }
}

/// Normalised `a + b`, or `a` when they cancel.
fn blend(a: &Vector3, b: &Vector3) -> Vector3 {
    let s = a + b;
    let n = s.norm();
    if n > 1e-9 {
        s / n
    } else {
        *a
    }
}

/// Steps of at most [`ARC_STEP_RAD`] for a turn of `angle` radians (an angle a rounding
/// above a whole number of steps takes that number, so mirror-image arcs match).
fn arc_steps(angle: Real) -> usize {
    (angle / ARC_STEP_RAD - ARC_STEP_SLACK).ceil().max(1.0) as usize
}

/// Spherical interpolation from `d0` to `d1` (unit, angle `gamma` apart) at `phi ∈ [0, 1]`.
fn slerp(d0: &Vector3, d1: &Vector3, gamma: Real, phi: Real) -> Vector3 {
    let mixed = d0 * libm::sin((1.0 - phi) * gamma) + d1 * libm::sin(phi * gamma);
    let n = mixed.norm();
    if n > 1e-9 {
        mixed / n
    } else if phi < 0.5 {
        *d0
    } else {
        *d1
    }
}

/// The pass's plane: an origin and two unit directions spanning it.
struct Plane {
    origin: Point3,
    normal: Vector3,
    e1: Vector3,
    e2: Vector3,
}

impl Plane {
    /// The plane of a pass from its segment directions `t` and normals `n`: the scan plane
    /// contains every `t`, so two of them that are not parallel span it; a straight pass takes
    /// the plane of its direction and mean normal.
    fn of_pass(origin: Point3, t: &[Vector3], n: &[Vector3]) -> Plane {
        let e1 = t[0];
        let best = t
            .iter()
            .map(|tk| e1.cross(tk))
            .max_by(|a, b| a.norm().total_cmp(&b.norm()))
            .unwrap_or_else(Vector3::zeros);
        let normal = if best.norm() > STRAIGHT_SINE {
            best.normalize()
        } else {
            let mean: Vector3 = n.iter().sum();
            let c = e1.cross(&mean);
            if c.norm() > STRAIGHT_SINE {
                c.normalize()
            } else {
                any_perpendicular(&e1)
            }
        };
        Plane {
            origin,
            normal,
            e1,
            e2: normal.cross(&e1),
        }
    }
    fn project(&self, p: &Point3) -> [Real; 2] {
        let d = p - self.origin;
        [d.dot(&self.e1), d.dot(&self.e2)]
    }
}

/// A raw node: position, gun axis, kind.
type RawNode = (Point3, Vector3, PoseKind);

/// The raw offset curve of one pass: start cap, offset segments with their transitions, end
/// cap. Returns the nodes, the index of the first segment's offset start (the start cap's
/// last node) and of the last segment's offset end (the end cap's first node).
fn raw_offset(
    pass: &ScanPass,
    n: &[Vector3],
    t: &[Vector3],
    standoff: Real,
    transition_angle: Real,
    max_turn_on: Real,
    counts: &mut TrajectoryCounts,
) -> (Vec<RawNode>, usize, usize) {
    let m = n.len();
    let mut raw: Vec<RawNode> = Vec::with_capacity(2 * m + 40);
    // A round cap of radius h around `centre` from direction `d0` to `d1` (gun axis radial).
    let cap = |raw: &mut Vec<RawNode>, centre: Point3, d0: Vector3, d1: Vector3, first: bool| {
        let gamma = angle_between(&d0, &d1);
        let steps = arc_steps(gamma);
        for s in usize::from(!first)..=steps {
            let d = slerp(&d0, &d1, gamma, s as Real / steps as Real);
            raw.push((centre + d * standoff, -d, PoseKind::Arc));
        }
    };
    cap(&mut raw, pass.points[0], -t[0], n[0], true);
    let first = raw.len() - 1;
    for j in 0..m.saturating_sub(1) {
        let (ni, nj) = (n[j], n[j + 1]);
        let beta = angle_between(&ni, &nj);
        if beta < COPLANAR_RAD && angle_between(&t[j], &t[j + 1]) < COPLANAR_RAD {
            continue;
        }
        let edge = pass.points[j + 1];
        let (a, b) = (edge + ni * standoff, edge + nj * standoff);
        if beta >= SMALL_TURN_RAD && nj.dot(&t[j]) < 0.0 {
            counts.trimmed += 1;
            // Concave edge. Each offset line meets the other face's offset plane (at `h`
            // from both faces) at `x1 = a + s·t_i` and `x2 = b + u·t_j`, two points of the
            // line where the offset planes meet (one point when the normals lie in the scan
            // plane). Where both lie on their segments and no farther apart than `a` and `b`
            // (the pass crosses the edge at 45° or more), the pass turns at their midpoint,
            // reached and left within the two offset planes. Otherwise `a` is joined
            // straight to `b` and the loop removal cuts it.
            let dip = standoff * (1.0 - ni.dot(&nj));
            let (ci, cj) = (nj.dot(&t[j]), ni.dot(&t[j + 1]));
            let back = raw.last().map_or(0.0, |r| (a - r.0).dot(&t[j]));
            let ahead = (pass.points[j + 2] - edge).dot(&t[j + 1]);
            let (x1, x2) = (a + t[j] * (dip / ci), b + t[j + 1] * (dip / cj));
            if cj > 0.0
                && -dip / ci <= back
                && dip / cj <= ahead
                && (x2 - x1).norm() <= (b - a).norm()
            {
                let mid = Point3::from((x1.coords + x2.coords) * 0.5);
                raw.push((mid, -blend(&ni, &nj), PoseKind::Pass));
            } else {
                raw.push((a, -ni, PoseKind::Pass));
                raw.push((b, -nj, PoseKind::Pass));
            }
            continue;
        }
        raw.push((a, -ni, PoseKind::Pass));
        if beta < SMALL_TURN_RAD {
            // A kink within a plane or a rounding-sized turn: `b` is within 10⁻⁴·h of `a`.
            continue;
        }
        // Convex edge: the offset segments leave a gap. While the gun turns across it,
        // its axis stays on the edge: a turn longer than `max_turn_on` runs gun off.
        let gun = |travel: Real, kind: PoseKind| {
            if travel > max_turn_on {
                PoseKind::Link
            } else {
                kind
            }
        };
        if beta <= transition_angle {
            counts.straight += 1;
            let kind = gun((b - a).norm(), PoseKind::StraightTransition);
            counts.turns_off += usize::from(kind == PoseKind::Link);
            let mid = Point3::from((a.coords + b.coords) * 0.5);
            raw.push((mid, -blend(&ni, &nj), kind));
            raw.push((b, -nj, kind));
        } else {
            counts.arcs += 1;
            let steps = arc_steps(beta);
            // The polyline's length: `steps` chords of the arc.
            let travel = steps as Real * 2.0 * standoff * libm::sin(0.5 * beta / steps as Real);
            let kind = gun(travel, PoseKind::Arc);
            counts.turns_off += usize::from(kind == PoseKind::Link);
            for s in 1..=steps {
                let radial = slerp(&ni, &nj, beta, s as Real / steps as Real);
                raw.push((edge + radial * standoff, -radial, kind));
            }
        }
    }
    raw.push((
        pass.points[m] + n[m - 1] * standoff,
        -n[m - 1],
        PoseKind::Pass,
    ));
    let last = raw.len() - 1;
    cap(&mut raw, pass.points[m], n[m - 1], t[m - 1], false);
    (raw, first, last)
}

/// Builds the trajectory of `passes` (already in execution order and direction). A convex
/// turn (straight transition or arc) whose gun travel exceeds `max_turn_on` runs with the gun
/// off (`Real::INFINITY` keeps every turn gun on, as the patent does).
pub fn build_trajectory(
    passes: &[ScanPass],
    normals: &[Vector3],
    standoff: Real,
    transition_angle: Real,
    extension: Real,
    speed: Real,
    max_turn_on: Real,
) -> (ToolPath, TrajectoryCounts) {
    let mut poses: Vec<Pose> = Vec::new();
    let mut counts = TrajectoryCounts::default();
    let tol = SAME_POSITION_RATIO * standoff;
    for pass in passes {
        let m = pass.faces.len();
        if m == 0 {
            continue;
        }
        let pass_id = poses.last().map_or(0, |p: &Pose| p.pass + 1);
        let n: Vec<Vector3> = pass.faces.iter().map(|&f| normals[f as usize]).collect();
        let t: Vec<Vector3> = (0..m)
            .map(|i| (pass.points[i + 1] - pass.points[i]).normalize())
            .collect();
        let concave_before = counts.trimmed;
        let (raw, first, last) = raw_offset(
            pass,
            &n,
            &t,
            standoff,
            transition_angle,
            max_turn_on,
            &mut counts,
        );
        let plane = Plane::of_pass(pass.points[0], &t, &n);
        let raw: Vec<Node> = raw
            .into_iter()
            .enumerate()
            .map(|(origin, (p, axis, kind))| Node {
                p,
                q: plane.project(&p),
                axis,
                kind,
                origin,
            })
            .collect();
        // A cap turns in the plane of the end's normal and direction: only where that is the
        // scan plane (within CAP_PLANE_SINE) does its crossing mean what it means in 2D.
        let fits = |normal: &Vector3| normal.dot(&plane.normal).abs() <= CAP_PLANE_SINE;
        let caps = Caps {
            gap: CAP_GAP_RATIO * standoff,
            first,
            last,
            start: fits(&n[0]),
            end: fits(&n[m - 1]),
        };
        // Without a concave edge the offset only turns away from the part: no loop.
        let result = if counts.trimmed > concave_before {
            remove_loops(&raw, tol, &caps)
        } else {
            Kept {
                nodes: raw,
                start_cut: false,
                end_cut: false,
            }
        };
        let Kept {
            nodes: mut kept,
            start_cut,
            end_cut,
        } = result;
        // An uncut cap gives way to the extension.
        let mut nodes: Vec<(Point3, Vector3, PoseKind)> = Vec::with_capacity(kept.len() + 2);
        if start_cut {
            counts.capped += 1;
            kept[0].kind = PoseKind::Link;
        } else {
            let start = kept.iter().position(|k| k.origin >= first).unwrap_or(0);
            kept.drain(..start);
            let a0 = kept[0].p;
            if extension > 0.0 {
                nodes.push((a0 - t[0] * extension, kept[0].axis, PoseKind::Link));
                kept[0].kind = PoseKind::Extension;
            } else {
                kept[0].kind = PoseKind::Link;
            }
        }
        let tail = if end_cut {
            counts.capped += 1;
            None
        } else {
            let end = kept.iter().rposition(|k| k.origin <= last).unwrap_or(0);
            kept.truncate(end + 1);
            (extension > 0.0).then(|| {
                let e = kept[end];
                (e.p + t[m - 1] * extension, e.axis, PoseKind::Extension)
            })
        };
        nodes.extend(kept.iter().map(|k| (k.p, k.axis, k.kind)));
        nodes.extend(tail);
        // Travel: the direction of the arriving move (the first pose: of the leaving one).
        let begin = poses.len();
        let forward = pass.points[m] - pass.points[0];
        for (i, &(position, axis, kind)) in nodes.iter().enumerate() {
            if poses.len() > begin && (position - poses[poses.len() - 1].position).norm() <= tol {
                continue;
            }
            let travel = if i == 0 {
                nodes.get(1).map_or(t[0], |n| n.0 - position)
            } else {
                position - poses[poses.len() - 1].position
            };
            poses.push(Pose {
                position,
                axis,
                travel: perpendicular(travel, &axis),
                kind,
                pass: pass_id,
            });
            // A concave crossing a hair behind the previous pose (common on faceted skins)
            // makes the gun step back and forth, which a controller runs as a stop (a paint
            // dwell): the pose at the tip of such a short backtrack is dropped. Where the
            // move leaving the tip is a short turn run gun off, the tip is dropped only if
            // the gun-on move into it runs back along the pass (no coating is lost that the
            // pass had not just laid), else the gun-off pose goes; a gun-off tip between
            // gun-off moves goes too. Each round removes a pose, so the loop ends.
            while poses.len() >= begin + 3 {
                let n = poses.len();
                let (p0, p1, p2) = (&poses[n - 3], &poses[n - 2], &poses[n - 1]);
                let (a, b) = (p1.position - p0.position, p2.position - p1.position);
                let limit = BACKTRACK_RATIO * standoff;
                let short = a.norm().min(b.norm()) <= limit;
                let back = a.dot(&b) < REVERSAL_COS * a.norm() * b.norm();
                if !(short && back) {
                    break;
                }
                let drop = match (p1.kind.process_on(), p2.kind.process_on()) {
                    (true, true) | (false, false) => n - 2,
                    (true, false) if b.norm() <= limit => {
                        if a.dot(&forward) < 0.0 {
                            n - 2
                        } else {
                            n - 1
                        }
                    }
                    _ => break,
                };
                if drop == n - 2 {
                    let chord = p2.position - p0.position;
                    let axis = p2.axis;
                    poses[n - 1].travel = perpendicular(chord, &axis);
                }
                poses.remove(drop);
                counts.backtracks += 1;
            }
        }
    }
    let mut notes = vec![
        "spray trajectory after the patent 'a trajectory planning method for curved-surface spraying' (Tsinghua University): scan planes, offset by the standoff, straight or arc transitions".to_string(),
    ];
    if counts.trimmed > 0 {
        notes.push(format!(
            "{} concave edges: the offsets of both sides cross and every offset behind their crossing was removed, so the pass turns at the crossing (the patent treats convex edges only)",
            counts.trimmed
        ));
    }
    if counts.turns_off > 0 {
        notes.push(format!(
            "{} turns over convex edges run with the gun off: the gun's axis stays on the edge while it turns, so with the gun on the edge would get a spot of extra coating",
            counts.turns_off
        ));
    }
    if counts.capped > 0 {
        notes.push(format!(
            "{} pass ends lie in a concave region: the pass turns around its end point at the standoff instead of running on past it",
            counts.capped
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
