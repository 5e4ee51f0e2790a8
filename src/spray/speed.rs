//! Gun speed along the passes: the speed of each short piece of gun-on path chosen, within
//! limits, so that the coating over the interior is as even as possible.
//!
//! Source: the patent keeps the gun speed `v` constant. Varying the speed along the passes
//! to even out the coating is the dwell-time idea of spray-painting trajectory optimisation
//! (e.g. Chen & Xi, 2008, who vary the speed along each pass); the formulation here is this
//! planner's own (no paper):
//! - The gun-on path is cut into pieces of at most `max(`[`PIECE_RADIUS_RATIO`]`·R,`
//!   [`PIECE_SAMPLE_RATIO`]` × the sample spacing)` (long moves are split by interpolated
//!   poses); piece `j` runs at speed `v_j`, its dwell factor
//!   `x_j = v_ref / v_j`.
//! - Thickness is linear in the dwell factors: `T = Σ_j x_j·c_j`, with `c_j` the coating of
//!   piece `j` at `v_ref` ([`deposit_piece`]).
//! - Step 1 (least squares): minimise `Σ_i w_i (T_i − T*)² + μ Σ (x_j − x_k)²` over the
//!   interior samples `i` (area weights `w_i`), the second sum over consecutive pieces of one
//!   run of gun-on moves (a light smoothing, [`SMOOTHING`], that keeps neighbouring speeds
//!   close where the coating does not decide them), subject to `v_min ≤ v_j ≤ v_max`. `T*` is
//!   the target thickness, or the interior mean at the constant speed `v_ref`.
//! - Step 2 (max deviation): a few rounds of Lawson's reweighting (weights grow with the
//!   residual), keeping the round with the smallest error `δ` (or the smallest excess over
//!   the quality limits when they are given).
//!
//! Both steps are solved by cyclic coordinate descent: each dwell factor in turn moves to the
//! minimum of the quadratic along its axis, clamped to its bounds. For a convex quadratic with
//! box constraints every sweep lowers the objective and the iteration converges to the
//! minimum; it stops after [`MAX_SWEEPS`] sweeps or once no factor moved by more than
//! [`SWEEP_TOLERANCE`](super::normal_equations::SWEEP_TOLERANCE). The descent runs on the
//! normal equations `H = CᵀWC + μL`, built once per set of weights: a step then costs the
//! pieces whose coatings overlap the moved one (a few dozen), not the samples it coats (see
//! [`super::normal_equations`]).
//! Input:  a spray [`ToolPath`], evaluation samples and their grid, the interior mask, the
//!         spray model, the reference speed, the speed limits, the target.
//! Output: [`SpeedPlan`]: the path with its per-move speeds, the thickness they give.
//! Cost:   building the coating matrix is one deposition, its chords cut where the piece
//!         changes (about `2R/L + 1` pieces reach each sample per pass, `L` the piece
//!         length), its columns filled in path order (no sort of all entries); `H` and the
//!         sweeps as in [`super::normal_equations`]. A matrix of more than
//!         [`MAX_COATING_ENTRIES`] entries (surfaces
//!         stacked within the gun's reach, all coated at once) is refused as it is built.

use super::deposition::{check_time_samples, deposit_piece, for_each_segmented_piece, SprayModel};
use super::grid::PointGrid;
use super::normal_equations::{Coating, Problem, Rows};
use super::params::{SprayError, MAX_COATING_ENTRIES};
use super::quality::{thickness_stats, ThicknessStats};
use super::samples::EvaluationSamples;
use crate::math::{Real, Vector3};
use crate::toolpath::{Pose, ToolPath};

/// Shortest piece of gun-on path with one speed, as a fraction of `R` (R/4 gave the same
/// plans as R/2 on the real skins measured, at about 1.4 times the cost).
pub const PIECE_RADIUS_RATIO: Real = 0.5;
/// Pieces are at least this many sample spacings long, so the samples see each piece's
/// coating apart from its neighbours' (shorter pieces let the speeds alternate between
/// samples unseen).
pub const PIECE_SAMPLE_RATIO: Real = 2.0;
/// Weight `μ` of the smoothing term, relative to the mean diagonal of the least-squares
/// problem.
pub const SMOOTHING: Real = 0.05;
/// Most coordinate-descent sweeps of the least-squares step.
pub const MAX_SWEEPS: usize = 20;
/// Sweeps per reweighting round of the max-deviation step.
pub const ROUND_SWEEPS: usize = 8;
/// Reweighting rounds of the max-deviation step.
pub const MINIMAX_ROUNDS: usize = 3;

/// Gun speed limits, mesh unit per second.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedLimits {
    /// Slowest gun speed.
    pub min: Real,
    /// Fastest gun speed.
    pub max: Real,
}

/// How the figures of a candidate are judged in the max-deviation step: the smaller the
/// better.
pub type Score<'a> = &'a dyn Fn(&ThicknessStats) -> Real;

/// The result of [`optimise_speeds`].
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedPlan {
    /// The path, long gun-on moves split into pieces, with a speed per move.
    pub path: ToolPath,
    /// Thickness per sample at those speeds.
    pub thickness: Vec<Real>,
    /// Number of pieces with their own speed.
    pub pieces: usize,
    /// Pieces held at the slowest speed.
    pub at_min: usize,
    /// Pieces held at the fastest speed.
    pub at_max: usize,
    /// The thickness aimed at (`T*`).
    pub aim: Real,
}

/// Splits every gun-on move longer than `max_length` by interpolated poses (position linear,
/// axis and travel normalised-linear, travel kept perpendicular to the axis); the pieces of a
/// move keep its speed.
pub fn split_long_moves(path: &ToolPath, max_length: Real) -> ToolPath {
    let mut poses: Vec<Pose> = Vec::with_capacity(path.poses.len());
    let mut speeds: Vec<Real> = Vec::new();
    for (k, p) in path.poses.iter().enumerate() {
        if k > 0 && p.kind.process_on() {
            let q = &path.poses[k - 1];
            let length = (p.position - q.position).norm();
            // Finite: the path was validated, and its length bounded by the time samples.
            let n = (length / max_length).ceil().max(1.0) as usize;
            for s in 1..n {
                let tau = s as Real / n as Real;
                let axis = nlerp(&q.axis, &p.axis, tau).unwrap_or(p.axis);
                let travel = nlerp(&q.travel, &p.travel, tau)
                    .map(|t| t - axis * axis.dot(&t))
                    .filter(|t| t.norm() > 1e-9)
                    .map_or(p.travel, |t| t.normalize());
                poses.push(Pose {
                    position: q.position + (p.position - q.position) * tau,
                    axis,
                    travel,
                    kind: p.kind,
                    pass: p.pass,
                });
                if path.has_varying_speed() {
                    speeds.push(path.move_speed(k));
                }
            }
        }
        poses.push(*p);
        if path.has_varying_speed() {
            speeds.push(path.move_speed(k));
        }
    }
    ToolPath {
        poses,
        speeds,
        notes: path.notes.clone(),
        ..*path
    }
}

fn nlerp(a: &Vector3, b: &Vector3, tau: Real) -> Option<Vector3> {
    let v = a * (1.0 - tau) + b * tau;
    (v.norm() > 1e-12).then(|| v.normalize())
}

/// No piece: the move is gun-off.
const NO_PIECE: u32 = u32::MAX;

/// Piece of each move (the move arriving at pose `k`); consecutive gun-on moves are grouped
/// until their length would exceed `max_length`. Returns the pieces' count too.
fn assign_pieces(path: &ToolPath, max_length: Real) -> (Vec<u32>, usize) {
    let poses = &path.poses;
    let mut piece_of = vec![NO_PIECE; poses.len()];
    let mut count = 0usize;
    let mut open = false;
    let mut length = 0.0;
    for k in 1..poses.len() {
        if !poses[k].kind.process_on() {
            open = false;
            continue;
        }
        let step = (poses[k].position - poses[k - 1].position).norm();
        // A small tolerance: split moves are exactly max_length long up to rounding.
        if !open || length + step > max_length * (1.0 + 1e-9) {
            count += 1;
            length = 0.0;
            open = true;
        }
        length += step;
        piece_of[k] = (count - 1) as u32;
    }
    (piece_of, count)
}

/// Builds the coating matrix of the pieces at speed `v_ref`.
#[allow(clippy::too_many_arguments)]
fn coating_matrix(
    path: &ToolPath,
    piece_of: &[u32],
    pieces: usize,
    samples: &EvaluationSamples,
    grid: &PointGrid,
    model: &SprayModel,
    v_ref: Real,
    step_length: Real,
    max_entries: usize,
) -> Result<Coating, SprayError> {
    // Columns are filled in order: the speed pieces follow the path, and so do the
    // deposition's own pieces (longer, cut where the speed piece changes), so the pieces a
    // deposition piece reaches never precede those of the one before. Each deposition
    // piece's entries (segment, sample, value) are grouped by segment and appended to their
    // columns; a column is closed, its repeats of a sample summed in the order they came,
    // once a later piece is reached.
    let n = samples.positions.len();
    let per_speed = 1.0 / v_ref;
    let mut start: Vec<usize> = Vec::with_capacity(pieces + 1);
    start.push(0);
    let mut rows: Vec<u32> = Vec::new();
    let mut values: Vec<Real> = Vec::new();
    let mut slot = vec![u32::MAX; n];
    // The column being filled is start.len() − 1, its entries from start[start.len() − 1] on.
    let mut close = |rows: &mut Vec<u32>, values: &mut Vec<Real>, start: &mut Vec<usize>| {
        let from = start[start.len() - 1];
        let mut kept = from;
        for e in from..rows.len() {
            let i = rows[e] as usize;
            match slot[i] {
                u32::MAX => {
                    slot[i] = kept as u32;
                    rows[kept] = rows[e];
                    values[kept] = values[e];
                    kept += 1;
                }
                s => values[s as usize] += values[e],
            }
        }
        for &i in &rows[from..kept] {
            slot[i as usize] = u32::MAX;
        }
        rows.truncate(kept);
        values.truncate(kept);
        start.push(kept);
    };
    let mut entries: Vec<(u32, u32, Real)> = Vec::new();
    let mut count: Vec<usize> = Vec::new();
    let mut grouped: Vec<(u32, Real)> = Vec::new();
    // Set once the entries exceed `max_entries`: the pieces after it are skipped.
    let mut too_many = false;
    for_each_segmented_piece(
        path,
        model,
        |k| piece_of[k],
        |range, cumulative, starts, owner| {
            if too_many {
                return;
            }
            entries.clear();
            deposit_piece(
                &path.poses[range],
                cumulative,
                starts,
                samples,
                grid,
                model,
                step_length,
                None,
                |i, segment, v| entries.push((segment as u32, i as u32, v * per_speed)),
            );
            // Counting sort by segment (stable: each column keeps the order entries came).
            count.clear();
            count.resize(owner.len() + 1, 0);
            for &(s, _, _) in &entries {
                count[s as usize + 1] += 1;
            }
            for s in 0..owner.len() {
                count[s + 1] += count[s];
            }
            grouped.clear();
            grouped.resize(entries.len(), (0, 0.0));
            for &(s, i, v) in &entries {
                grouped[count[s as usize]] = (i, v);
                count[s as usize] += 1;
            }
            // count[s] is now the end of segment s's entries.
            let mut from = 0;
            for (s, &j) in owner.iter().enumerate() {
                let to = count[s];
                if to > from {
                    let j = j as usize;
                    debug_assert!(j + 1 >= start.len(), "piece {j} after a later one");
                    while start.len() <= j {
                        close(&mut rows, &mut values, &mut start);
                    }
                    for &(i, v) in &grouped[from..to] {
                        rows.push(i);
                        values.push(v);
                    }
                }
                from = to;
            }
            too_many = rows.len() > max_entries;
        },
    );
    if too_many {
        return Err(SprayError::TooManyCoatingEntries { samples: n });
    }
    while start.len() <= pieces {
        close(&mut rows, &mut values, &mut start);
    }
    // Piece j is linked to j + 1 when a gun-on move of j is followed by one of j + 1.
    let mut linked_to_next = vec![false; pieces];
    for k in 1..piece_of.len() {
        let (a, b) = (piece_of[k - 1], piece_of[k]);
        if a != NO_PIECE && b == a.wrapping_add(1) {
            linked_to_next[a as usize] = true;
        }
    }
    Ok(Coating {
        start,
        rows,
        values,
        linked_to_next,
    })
}

/// Chooses the speed of every piece of the gun-on path within `limits` to even out the
/// interior coating around `target` (default: the interior mean at `v_ref`) on samples about
/// `resolution` apart; `score` ranks the rounds of the max-deviation step, which stop once
/// a round scores below `enough` (pass `Real::NEG_INFINITY` for every round: a screening
/// that only asks whether the limits are met can stop at the first that meets them). The
/// returned path has per-move speeds. The descent starts from the path's own speeds when it
/// has them.
#[allow(clippy::too_many_arguments)]
pub fn optimise_speeds(
    path: &ToolPath,
    samples: &EvaluationSamples,
    grid: &PointGrid,
    interior: &[bool],
    model: &SprayModel,
    v_ref: Real,
    limits: SpeedLimits,
    target: Option<Real>,
    time_step: Real,
    resolution: Real,
    score: Score,
    enough: Real,
) -> Result<SpeedPlan, SprayError> {
    let step_length = check_time_samples(path, v_ref, time_step)?;
    let max_length = (PIECE_RADIUS_RATIO * model.radius).max(PIECE_SAMPLE_RATIO * resolution);
    let mut path = split_long_moves(path, max_length);
    let (piece_of, pieces) = assign_pieces(&path, max_length);
    let n = samples.positions.len();
    let coating = coating_matrix(
        &path,
        &piece_of,
        pieces,
        samples,
        grid,
        model,
        v_ref,
        step_length,
        MAX_COATING_ENTRIES,
    )?;
    // Interior samples carry their area; with no interior, every sample does.
    let any_interior = interior
        .iter()
        .zip(&samples.weights)
        .any(|(&inside, &w)| inside && w > 0.0);
    let base: Vec<Real> = samples
        .weights
        .iter()
        .zip(interior)
        .map(|(&w, &inside)| if inside || !any_interior { w } else { 0.0 })
        .collect();
    let keep = |i: usize| base[i] > 0.0;
    let (lo, hi) = (v_ref / limits.max, v_ref / limits.min);
    // Start from the path's own speeds when it has them (mean dwell factor of each piece's
    // moves), else from v_ref.
    let mut x = vec![0.0; pieces];
    let mut moves = vec![0usize; pieces];
    for (k, &j) in piece_of.iter().enumerate() {
        if j != NO_PIECE {
            x[j as usize] += v_ref / path.move_speed(k);
            moves[j as usize] += 1;
        }
    }
    for (xj, &m) in x.iter_mut().zip(&moves) {
        *xj = if m > 0 && path.has_varying_speed() {
            (*xj / m as Real).clamp(lo, hi)
        } else {
            1.0_f64.clamp(lo, hi)
        };
    }
    let start_thickness = coating.thickness(&x, n);
    let aim = match target {
        Some(t) => t,
        None => thickness_stats(&start_thickness, &samples.weights, keep).mean,
    };
    let mut r: Vec<Real> = start_thickness.iter().map(|t| t - aim).collect();
    // μ relative to the mean diagonal, so the smoothing does not depend on units.
    let mean_diagonal = if pieces > 0 {
        (0..pieces)
            .map(|j| {
                let (rows, values) = coating.column(j);
                rows.iter()
                    .zip(values)
                    .map(|(&i, &v)| base[i as usize] * v * v)
                    .sum::<Real>()
            })
            .sum::<Real>()
            / pieces as Real
    } else {
        0.0
    };
    let rows = Rows::of(&coating, n);
    let problem = Problem {
        coating: &coating,
        rows: &rows,
        lo,
        hi,
        mu: SMOOTHING * mean_diagonal,
    };
    if aim > 0.0 && mean_diagonal > 0.0 {
        // Step 1: least squares.
        let (pattern, h) = problem.gram(&base);
        problem.descend(&mut x, &mut r, &base, MAX_SWEEPS, &pattern, &h);
        // Step 2: Lawson's reweighting towards the smallest max deviation.
        let stats_of = |r: &[Real]| {
            let t: Vec<Real> = r.iter().map(|d| d + aim).collect();
            thickness_stats(&t, &samples.weights, keep)
        };
        let mut best = (score(&stats_of(&r)), x.clone(), r.clone());
        let mut w = base.clone();
        for _ in 0..MINIMAX_ROUNDS {
            if best.0 < enough {
                break;
            }
            let largest = r
                .iter()
                .zip(&base)
                .filter(|(_, &b)| b > 0.0)
                .fold(0.0, |m: Real, (d, _)| m.max(d.abs()));
            if largest <= 0.0 {
                break;
            }
            for ((wi, &bi), d) in w.iter_mut().zip(&base).zip(&r) {
                *wi *= 0.5 + d.abs() / largest;
                if bi <= 0.0 {
                    *wi = 0.0;
                }
            }
            // Keep the weights' scale, so μ keeps its meaning.
            let (sw, sb): (Real, Real) = (w.iter().sum(), base.iter().sum());
            if sw > 0.0 {
                w.iter_mut().for_each(|wi| *wi *= sb / sw);
            }
            let h = problem.regram(&w, &pattern);
            problem.descend(&mut x, &mut r, &w, ROUND_SWEEPS, &pattern, &h);
            let s = score(&stats_of(&r));
            if s < best.0 {
                best = (s, x.clone(), r.clone());
            }
        }
        (_, x, r) = best;
    }
    let thickness: Vec<Real> = r.iter().map(|d| d + aim).collect();
    let speeds: Vec<Real> = x.iter().map(|xj| v_ref / xj).collect();
    path.speeds = piece_of
        .iter()
        .map(|&j| {
            if j == NO_PIECE {
                path.link_speed
            } else {
                speeds[j as usize]
            }
        })
        .collect();
    // Bounds hold up to rounding: clamp the speeds themselves to the limits.
    for s in path.speeds.iter_mut() {
        *s = s.clamp(
            limits.min.min(path.link_speed),
            limits.max.max(path.link_speed),
        );
    }
    let at = |bound: Real| x.iter().filter(|&&xj| xj == bound).count();
    Ok(SpeedPlan {
        at_min: at(hi),
        at_max: at(lo),
        pieces,
        thickness,
        path,
        aim,
    })
}

#[cfg(test)]
mod tests {
    use super::super::grid::PointGrid;
    use super::super::normal_equations::tests::sequence;
    use super::*;
    use crate::math::Point3;
    use crate::toolpath::PoseKind;

    fn pose(x: Real, kind: PoseKind) -> Pose {
        Pose {
            position: Point3::new(x, 0.0, 1.0),
            axis: -Vector3::z(),
            travel: Vector3::x(),
            kind,
            pass: 0,
        }
    }

    /// The coating matrix, its columns filled in path order, times any dwell factors is the
    /// deposition of the path at the speeds they give, on a pass that steps sideways and
    /// tilts its axis (pieces of the deposition and speed pieces cut across each other).
    #[test]
    fn the_coating_matrix_is_the_deposition_piece_by_piece() {
        let model = SprayModel {
            radius: 0.4,
            peak_rate: 1.0,
            standoff: 1.0,
        };
        let mut poses = vec![pose(-0.1, PoseKind::Link), pose(0.0, PoseKind::Link)];
        for k in 1..=60 {
            let x = 0.04 * k as Real;
            let mut p = pose(x, PoseKind::Pass);
            p.position.y = if k % 2 == 0 { 0.001 } else { 0.0 };
            p.axis = Vector3::new(0.0, 0.2 * (x / 2.4).sin(), -1.0).normalize();
            poses.push(p);
        }
        let path = ToolPath {
            poses,
            speed: 1.0,
            link_speed: 1.0,
            speeds: Vec::new(),
            notes: Vec::new(),
        };
        let max_length = PIECE_RADIUS_RATIO * model.radius;
        let path = split_long_moves(&path, max_length);
        let (piece_of, pieces) = assign_pieces(&path, max_length);
        assert!(pieces > 4, "{pieces} pieces");
        let mut samples = EvaluationSamples::default();
        for i in 0..=130 {
            for j in 0..=40 {
                samples.positions.push(Point3::new(
                    0.02 * i as Real - 0.2,
                    0.02 * j as Real - 0.4,
                    0.0,
                ));
                samples.normals.push(Vector3::z());
                samples.weights.push(4e-4);
            }
        }
        let grid = PointGrid::new(&samples.positions, 0.5 * model.radius);
        let v_ref = 2.0;
        let build = |max_entries| {
            coating_matrix(
                &path,
                &piece_of,
                pieces,
                &samples,
                &grid,
                &model,
                v_ref,
                1.0,
                max_entries,
            )
        };
        let coating = build(MAX_COATING_ENTRIES).unwrap();
        // Bounded: one entry fewer than it holds is refused, naming the samples.
        assert_eq!(
            build(coating.rows.len() - 1).err(),
            Some(SprayError::TooManyCoatingEntries {
                samples: samples.positions.len()
            })
        );
        for j in 0..pieces {
            let (rows, _) = coating.column(j);
            let mut sorted = rows.to_vec();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), rows.len(), "column {j} repeats a sample");
        }
        let mut next = sequence(11);
        let x: Vec<Real> = (0..pieces).map(|_| 0.5 + next()).collect();
        let mut slowed = path.clone();
        slowed.speeds = piece_of
            .iter()
            .map(|&j| {
                if j == NO_PIECE {
                    1.0
                } else {
                    v_ref / x[j as usize]
                }
            })
            .collect();
        let n = samples.positions.len();
        let expected =
            super::super::deposition::deposit(&slowed, &samples, &grid, &model, v_ref, 1.0)
                .unwrap();
        let got = coating.thickness(&x, n);
        let peak = expected.iter().fold(0.0_f64, |m, &t| m.max(t));
        assert!(peak > 0.0);
        for (a, b) in got.iter().zip(&expected) {
            assert!((a - b).abs() <= 1e-12 * peak, "{a} against {b}");
        }
    }

    #[test]
    fn long_moves_split_and_pieces_bounded() {
        let path = ToolPath {
            poses: vec![
                pose(0.0, PoseKind::Link),
                pose(1.0, PoseKind::Link),
                pose(1.1, PoseKind::Pass),
                pose(3.0, PoseKind::Link),
                pose(4.0, PoseKind::Pass),
            ],
            speed: 1.0,
            link_speed: 2.0,
            speeds: Vec::new(),
            notes: Vec::new(),
        };
        let split = split_long_moves(&path, 0.25);
        // Links are not split; 1→1.1 stays one move; 3→4 becomes four.
        assert_eq!(split.poses.len(), 5 + 3);
        let (piece_of, count) = assign_pieces(&split, 0.25);
        assert_eq!(piece_of[1], NO_PIECE);
        assert_eq!(piece_of[2], 0);
        assert_eq!(piece_of[3], NO_PIECE);
        assert_eq!(count, 1 + 4);
        for (k, &j) in piece_of.iter().enumerate().skip(4) {
            assert_eq!(j, (k - 3) as u32);
        }
    }
}
