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
//! [`SWEEP_TOLERANCE`]. The descent runs on the normal equations `H = CᵀWC + μL`, built once
//! per set of weights: a step then costs the pieces whose coatings overlap the moved one
//! (a few dozen), not the samples it coats.
//! Input:  a spray [`ToolPath`], evaluation samples and their grid, the interior mask, the
//!         spray model, the reference speed, the speed limits, the target.
//! Output: [`SpeedPlan`]: the path with its per-move speeds, the thickness they give.
//! Cost:   building the coating matrix is one deposition, its chords cut where the piece
//!         changes (about `2R/L + 1` pieces reach each sample per pass, `L` the piece
//!         length); `H` costs the sum over samples of (pieces reaching it)², once per
//!         weighting; each sweep is linear in the non-zeros of `H`.

use super::deposition::{check_time_samples, deposit_piece, for_each_segmented_piece, SprayModel};
use super::grid::PointGrid;
use super::params::SprayError;
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
/// Coordinate descent stops once no dwell factor moved by more than this in a sweep.
pub const SWEEP_TOLERANCE: Real = 1e-3;

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

/// The coating of every piece at the reference speed, column by column.
struct Coating {
    /// Column `j` holds entries `start[j]..start[j + 1]`.
    start: Vec<usize>,
    rows: Vec<u32>,
    values: Vec<Real>,
    /// For each piece, whether the next piece continues the same run of gun-on moves.
    linked_to_next: Vec<bool>,
}

impl Coating {
    fn pieces(&self) -> usize {
        self.start.len() - 1
    }

    fn column(&self, j: usize) -> (&[u32], &[Real]) {
        let r = self.start[j]..self.start[j + 1];
        (&self.rows[r.clone()], &self.values[r])
    }

    /// `T = Σ x_j c_j`.
    fn thickness(&self, x: &[Real], samples: usize) -> Vec<Real> {
        let mut t = vec![0.0; samples];
        for (j, &xj) in x.iter().enumerate() {
            let (rows, values) = self.column(j);
            for (&i, &v) in rows.iter().zip(values) {
                t[i as usize] += xj * v;
            }
        }
        t
    }
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
) -> Coating {
    // Entries as they come (piece, sample, value), a sample possibly more than once per
    // piece; the deposition's own pieces are longer than the speed pieces and are cut where
    // the speed piece changes.
    let mut entries: Vec<(u32, u32, Real)> = Vec::new();
    let per_speed = 1.0 / v_ref;
    for_each_segmented_piece(
        path,
        model,
        |k| piece_of[k],
        |range, cumulative, starts, owner| {
            deposit_piece(
                &path.poses[range],
                cumulative,
                starts,
                samples,
                grid,
                model,
                step_length,
                None,
                |i, segment, v| entries.push((owner[segment], i as u32, v * per_speed)),
            );
        },
    );
    // Counting sort by piece, then the repeats of a sample within a column summed.
    let mut start = vec![0usize; pieces + 1];
    for &(j, _, _) in &entries {
        start[j as usize + 1] += 1;
    }
    for j in 0..pieces {
        start[j + 1] += start[j];
    }
    let mut fill = start.clone();
    let mut sorted: Vec<(u32, Real)> = vec![(0, 0.0); entries.len()];
    for &(j, i, v) in &entries {
        sorted[fill[j as usize]] = (i, v);
        fill[j as usize] += 1;
    }
    drop(entries);
    let mut slot = vec![u32::MAX; samples.positions.len()];
    let mut rows: Vec<u32> = Vec::with_capacity(sorted.len());
    let mut values: Vec<Real> = Vec::with_capacity(sorted.len());
    let mut merged = Vec::with_capacity(pieces + 1);
    merged.push(0);
    for j in 0..pieces {
        let from = rows.len();
        for &(i, v) in &sorted[start[j]..start[j + 1]] {
            match slot[i as usize] {
                u32::MAX => {
                    slot[i as usize] = rows.len() as u32;
                    rows.push(i);
                    values.push(v);
                }
                s => values[s as usize] += v,
            }
        }
        for &i in &rows[from..] {
            slot[i as usize] = u32::MAX;
        }
        merged.push(rows.len());
    }
    // Piece j is linked to j + 1 when a gun-on move of j is followed by one of j + 1.
    let mut linked_to_next = vec![false; pieces];
    for k in 1..piece_of.len() {
        let (a, b) = (piece_of[k - 1], piece_of[k]);
        if a != NO_PIECE && b == a.wrapping_add(1) {
            linked_to_next[a as usize] = true;
        }
    }
    Coating {
        start: merged,
        rows,
        values,
        linked_to_next,
    }
}

/// The coating matrix row by row (sample by sample), for the normal equations.
struct Rows {
    start: Vec<usize>,
    pieces: Vec<u32>,
    values: Vec<Real>,
}

impl Rows {
    fn of(c: &Coating, samples: usize) -> Rows {
        let mut start = vec![0usize; samples + 1];
        for &i in &c.rows {
            start[i as usize + 1] += 1;
        }
        for i in 0..samples {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut pieces = vec![0u32; c.rows.len()];
        let mut values = vec![0.0; c.rows.len()];
        for j in 0..c.pieces() {
            let (rows, vals) = c.column(j);
            for (&i, &v) in rows.iter().zip(vals) {
                let at = &mut fill[i as usize];
                pieces[*at] = j as u32;
                values[*at] = v;
                *at += 1;
            }
        }
        Rows {
            start,
            pieces,
            values,
        }
    }

    fn row(&self, i: usize) -> (&[u32], &[Real]) {
        let r = self.start[i]..self.start[i + 1];
        (&self.pieces[r.clone()], &self.values[r])
    }
}

/// The box-constrained least-squares problem over the dwell factors, in normal-equation
/// form: `H = CᵀWC + μL` (`L` the smoothing's graph Laplacian), sparse by column (pieces
/// whose coatings overlap), so a coordinate step costs the pieces it overlaps rather than
/// the samples it coats.
struct Problem<'a> {
    coating: &'a Coating,
    rows: &'a Rows,
    lo: Real,
    hi: Real,
    mu: Real,
}

/// `H` by column, with its diagonal.
struct Gram {
    start: Vec<usize>,
    pieces: Vec<u32>,
    values: Vec<Real>,
    diagonal: Vec<Real>,
}

impl Problem<'_> {
    /// Adds column `j` of `H` for the sample weights `w` into the dense `acc`, calling
    /// `touch(k)` before each entry `k` it adds to.
    fn accumulate(&self, j: usize, w: &[Real], acc: &mut [Real], mut touch: impl FnMut(usize)) {
        let c = self.coating;
        let (rows, vals) = c.column(j);
        for (&i, &a) in rows.iter().zip(vals) {
            let wa = w[i as usize] * a;
            if wa == 0.0 {
                continue;
            }
            let (ks, bs) = self.rows.row(i as usize);
            for (&k, &b) in ks.iter().zip(bs) {
                touch(k as usize);
                acc[k as usize] += wa * b;
            }
        }
        for (linked, k) in [
            (j > 0 && c.linked_to_next[j - 1], j.wrapping_sub(1)),
            (c.linked_to_next[j], j + 1),
        ] {
            if linked {
                touch(j);
                acc[j] += self.mu;
                touch(k);
                acc[k] -= self.mu;
            }
        }
    }

    /// `H` for the sample weights `w`.
    fn gram(&self, w: &[Real]) -> Gram {
        let m = self.coating.pieces();
        let mut pattern = Gram {
            start: Vec::with_capacity(m + 1),
            pieces: Vec::new(),
            values: Vec::new(),
            diagonal: Vec::new(),
        };
        pattern.start.push(0);
        let mut acc = vec![0.0; m];
        let mut seen = vec![false; m];
        pattern.diagonal = vec![0.0; m];
        for j in 0..m {
            let from = pattern.pieces.len();
            self.accumulate(j, w, &mut acc, |k| {
                if !seen[k] {
                    seen[k] = true;
                    pattern.pieces.push(k as u32);
                }
            });
            // The same sums as [`Problem::regram`] forms on this pattern.
            for &k in &pattern.pieces[from..] {
                let k = k as usize;
                pattern.values.push(acc[k]);
                if k == j {
                    pattern.diagonal[j] = acc[k];
                }
                seen[k] = false;
                acc[k] = 0.0;
            }
            pattern.start.push(pattern.pieces.len());
        }
        pattern
    }

    /// `H` for the sample weights `w` on the sparsity of `pattern`, an `H` built for weights
    /// that are zero on the same samples (or on fewer): no bookkeeping of which entries a
    /// column touches.
    fn regram(&self, w: &[Real], pattern: &Gram) -> Gram {
        let m = self.coating.pieces();
        let mut values = vec![0.0; pattern.pieces.len()];
        let mut diagonal = vec![0.0; m];
        let mut acc = vec![0.0; m];
        for (j, d) in diagonal.iter_mut().enumerate() {
            self.accumulate(j, w, &mut acc, |_| {});
            let r = pattern.start[j]..pattern.start[j + 1];
            for (v, &k) in values[r.clone()].iter_mut().zip(&pattern.pieces[r]) {
                let k = k as usize;
                *v = acc[k];
                if k == j {
                    *d = acc[k];
                }
                acc[k] = 0.0;
            }
        }
        Gram {
            start: pattern.start.clone(),
            pieces: pattern.pieces.clone(),
            values,
            diagonal,
        }
    }

    /// Cyclic coordinate descent from `x` with residuals `r = T − T*` and sample weights
    /// `w`; at most `sweeps` sweeps. `r` is brought up to date at the end. `H` is built on
    /// the sparsity of `pattern` when given (see [`Problem::regram`]); returns it.
    fn descend(
        &self,
        x: &mut [Real],
        r: &mut [Real],
        w: &[Real],
        sweeps: usize,
        pattern: Option<&Gram>,
    ) -> Gram {
        let c = self.coating;
        let m = c.pieces();
        let h = match pattern {
            Some(p) => self.regram(w, p),
            None => self.gram(w),
        };
        // Gradient (halved): CᵀW r + μ L x.
        let mut g: Vec<Real> = (0..m)
            .map(|j| {
                let (rows, values) = c.column(j);
                let mut g: Real = rows
                    .iter()
                    .zip(values)
                    .map(|(&i, &v)| w[i as usize] * v * r[i as usize])
                    .sum();
                if j > 0 && c.linked_to_next[j - 1] {
                    g += self.mu * (x[j] - x[j - 1]);
                }
                if c.linked_to_next[j] {
                    g += self.mu * (x[j] - x[j + 1]);
                }
                g
            })
            .collect();
        let start_x = x.to_vec();
        for _ in 0..sweeps {
            let mut largest: Real = 0.0;
            for j in 0..m {
                if h.diagonal[j] <= 0.0 {
                    continue;
                }
                let new = (x[j] - g[j] / h.diagonal[j]).clamp(self.lo, self.hi);
                let d = new - x[j];
                if d != 0.0 {
                    x[j] = new;
                    let r = h.start[j]..h.start[j + 1];
                    for (&k, &v) in h.pieces[r.clone()].iter().zip(&h.values[r]) {
                        g[k as usize] += v * d;
                    }
                    largest = largest.max(d.abs());
                }
            }
            if largest <= SWEEP_TOLERANCE {
                break;
            }
        }
        // r += C (x − x_start).
        for j in 0..m {
            let d = x[j] - start_x[j];
            if d != 0.0 {
                let (rows, values) = c.column(j);
                for (&i, &v) in rows.iter().zip(values) {
                    r[i as usize] += v * d;
                }
            }
        }
        h
    }
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
    );
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
        let pattern = problem.descend(&mut x, &mut r, &base, MAX_SWEEPS, None);
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
            problem.descend(&mut x, &mut r, &w, ROUND_SWEEPS, Some(&pattern));
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
