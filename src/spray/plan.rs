//! `plan_spray`: scan planes, trajectory, deposition, gun-speed optimisation, quality and the
//! spacing search in one call.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), steps 1–7 (claims 1–7).
//! Input:  mesh, adjacency, face geometry, selected face ids, [`SprayParams`].
//! Output: [`SprayPlan`]: the tool path with its speeds, evaluation samples with their
//!         thickness, quality, every spacing tried, the worst regions and what would help.
//! Cost:   samples and their grids once ([`sample_sets`]: the full samples, the search's
//!         screening samples, the speed optimiser's), or not at all when a [`SampleCache`]
//!         holds them from the plan before ([`plan_spray_cached`]); per spacing tried
//!         O(F + S log S) for the raster, O(time samples × points per cone) for the
//!         deposition and, with speed optimisation, the coating matrix and its sweeps
//!         ([`optimise_speeds`]).
//! Deviations: the patent keeps the speed constant; here, by default, the speed of each short
//!         piece of path is optimised within `[minSpeed, maxSpeed]` ([`optimise_speeds`]),
//!         towards `targetThickness` when given. Without speed optimisation, `targetThickness`
//!         scales the constant speed (thickness ∝ 1/v), held within the limits. Every
//!         spacing tried is judged on the figures of the plan as it would run (speeds and
//!         target included). With `bestDirection`, the pass direction turned by 90° and ±45°
//!         is tried at the chosen spacing too (no paper).

use super::deposition::{deposit_except, SprayModel};
use super::params::{SprayError, SprayParams};
use super::quality::{evaluate_quality, interior_mask, Quality, ThicknessStats};
use super::raster::{order_zigzag, patch_frame, scan_passes, PatchFrame, JOIN_GAP_RATIO};
use super::samples::{fit_resolution, EvaluationSamples};
use super::sampling::{sample_sets, SampleCache, Sampling};
use super::search::{ripple, search_spacing, Fidelity, Iteration, Limits, FALLBACK_MARGIN};
use super::speed::{optimise_speeds, SpeedLimits};
use super::trajectory::{build_trajectory, TrajectoryCounts, TURN_ON_RADIUS_RATIO};
use crate::math::{angle_between, Compact, Point3, Real, Vector3};
use crate::mesh::{FaceAdjacency, FaceGeometry, TriMesh};
use crate::toolpath::ToolPath;

/// A target thickness counts as reached when the interior mean is within this fraction.
pub const TARGET_TOLERANCE: Real = 0.02;
/// Two directions whose scores differ by less than this fraction count as equally good
/// (the shorter cycle time then decides).
const DIRECTION_TIE: Real = 0.01;
/// Most worst regions reported.
pub const MAX_HOTSPOTS: usize = 5;
/// A worst region whose normals spread by more than this within `R` lies on a curved part
/// (radians, 8°); see [`HotspotCause`].
const CURVED_SPREAD_RAD: Real = 0.139_626_340_159_546_36;

/// Why a region of the coating is off (a heuristic, no paper): what lies under it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub enum HotspotCause {
    /// Within twice the edge exclusion of the patch boundary.
    Edge,
    /// Normals within `R/2` spread by more than the transition angle: a fold or sharp edge.
    Fold,
    /// Normals within `R` spread by more than 8°: a tightly curved part.
    Curvature,
    /// None of those: the ripple between neighbouring passes.
    Spacing,
}

/// One of the worst regions of the interior coating.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hotspot {
    /// The worst sample's position.
    pub position: Point3,
    /// Its deviation from the interior mean, as a fraction of the mean (signed).
    pub deviation: Real,
    /// What lies under it.
    pub cause: HotspotCause,
}

/// One pass direction tried with `bestDirection`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DirectionTrial {
    /// Turn about the mean normal, radians (as `rasterAngle`).
    pub raster_angle: Real,
    /// Interior `δ` at the chosen spacing (infinite when the spacing does not fit).
    pub error: Real,
    /// Interior `E`.
    pub std_dev: Real,
    /// Cycle time, seconds.
    pub cycle_time: Real,
    /// Whether this direction was chosen.
    pub chosen: bool,
}

/// A planned spray job.
#[derive(Debug, Clone, PartialEq)]
pub struct SprayPlan {
    /// The gun trajectory; with optimised speeds, a speed per move.
    pub path: ToolPath,
    /// Pass spacing used.
    pub spacing: Real,
    /// Gun speed: the nominal one, or the constant speed scaled for a target thickness.
    pub speed: Real,
    /// Whether the speeds were optimised piece by piece.
    pub speed_optimised: bool,
    /// Slowest and fastest gun-on speed commanded.
    pub speed_range: (Real, Real),
    /// Time to run the whole path (gun on and links), seconds.
    pub cycle_time: Real,
    /// Length of the gun-on path.
    pub spray_length: Real,
    /// Length of the whole path.
    pub path_length: Real,
    /// Turn of the pass direction used, radians.
    pub raster_angle: Real,
    /// The directions tried with `bestDirection` (empty without).
    pub directions: Vec<DirectionTrial>,
    /// Number of passes.
    pub pass_count: usize,
    /// What the trajectory contains (transitions, arcs, trimmed concave edges).
    pub counts: TrajectoryCounts,
    /// Distance between evaluation samples used (the one asked for, or coarser to fit
    /// `sample_budget`).
    pub resolution: Real,
    /// Evaluation samples and their display mesh.
    pub samples: EvaluationSamples,
    /// Thickness per sample, mesh unit.
    pub thickness: Vec<Real>,
    /// Whether each sample counts as interior (away from the boundary).
    pub interior: Vec<bool>,
    /// Figures over the interior and the whole patch.
    pub quality: Quality,
    /// Every spacing tried with its interior figures (one entry without quality limits).
    pub iterations: Vec<Iteration>,
    /// Whether the quality limits hold (true without limits).
    pub limits_met: bool,
    /// The worst regions of the interior coating, worst first.
    pub hotspots: Vec<Hotspot>,
    /// Plain-language remarks: limits not met and what would help, empty interior, target
    /// thickness not reached.
    pub messages: Vec<String>,
}

/// The outcome of one spacing.
struct Evaluation {
    path: ToolPath,
    counts: TrajectoryCounts,
    passes: usize,
    thickness: Vec<Real>,
    quality: Quality,
    empty_interior: bool,
    /// The constant speed (nominal, or scaled for the target without optimisation).
    speed: Real,
}

/// Everything that does not depend on the spacing.
struct Setup<'a> {
    mesh: &'a TriMesh,
    adjacency: &'a FaceAdjacency,
    geometry: &'a FaceGeometry,
    params: &'a SprayParams,
    full: &'a Sampling,
    /// Samples at twice the resolution, when markedly fewer: the search screens on them.
    coarse: Option<&'a Sampling>,
    model: SprayModel,
    extension: Real,
    time_step: Real,
    speed_limits: SpeedLimits,
    limits: Option<Limits>,
}

impl Setup<'_> {
    fn trajectory(
        &self,
        frame: &PatchFrame,
        spacing: Real,
    ) -> Result<(ToolPath, TrajectoryCounts, usize), SprayError> {
        let offsets = frame.plane_offsets(spacing)?;
        let join_gap = JOIN_GAP_RATIO * self.params.standoff;
        let passes = scan_passes(self.mesh, self.adjacency, frame, &offsets, join_gap);
        if passes.is_empty() {
            return Err(SprayError::PlanesMissPatch);
        }
        let passes = order_zigzag(passes);
        let (path, counts) = build_trajectory(
            &passes,
            self.geometry.normals(),
            self.params.standoff,
            self.params.transition_angle,
            self.extension,
            self.params.speed,
            TURN_ON_RADIUS_RATIO * self.model.radius,
        );
        // A non-finite pose would reach the deposition as a time-step count of NaN (and a
        // search would take it for a spacing too narrow to plan): refused here, by name.
        path.validate()?;
        Ok((path, counts, passes.len()))
    }

    /// How figures are ranked: the excess over the limits, or `δ` without limits.
    fn score(&self, s: &ThicknessStats) -> Real {
        match &self.limits {
            Some(l) => l.excess(s),
            None => s.error,
        }
    }

    fn evaluate(
        &self,
        frame: &PatchFrame,
        spacing: Real,
        sampling: &Sampling,
    ) -> Result<Evaluation, SprayError> {
        let v0 = self.params.speed;
        let mut speed = v0;
        let (mut path, counts, passes) = self.trajectory(frame, spacing)?;
        // Thickness straight from the optimiser on the samples it solved on.
        let mut solved = None;
        if self.params.optimise_speed {
            let solve = sampling.solve.as_deref().unwrap_or(sampling);
            let plan = optimise_speeds(
                &path,
                &solve.samples,
                &solve.grid,
                &solve.interior,
                &self.model,
                v0,
                self.speed_limits,
                self.params.target_thickness,
                self.time_step,
                solve.resolution,
                &|s| self.score(s),
                // A screening asks only whether the limits are met (excess below 1): it
                // stops reweighting at the first round that meets them. The plans the
                // search may deliver (full samples) get every round.
                match (&self.limits, std::ptr::eq(sampling, self.full)) {
                    (Some(_), false) => 1.0,
                    _ => Real::NEG_INFINITY,
                },
            )?;
            path = plan.path;
            solved = Some(plan.thickness);
        }
        // Otherwise the path (at its speeds) deposited on every sample, but for those the
        // optimiser solved on (thinned from these): the same sums, in another order.
        let mut thickness = match (solved, sampling.solve.as_deref()) {
            (Some(t), None) => t,
            (solved, solve) => {
                let given = solved.zip(solve);
                let mut all = deposit_except(
                    &path,
                    &sampling.samples,
                    &sampling.grid,
                    &self.model,
                    v0,
                    self.time_step,
                    given.is_some().then_some(&sampling.solved[..]),
                )?;
                if let Some((t, solve)) = given {
                    for (&i, &ti) in solve.origin.iter().zip(&t) {
                        all[i] = ti;
                    }
                }
                all
            }
        };
        let (mut quality, empty_interior) =
            evaluate_quality(&thickness, &sampling.samples.weights, &sampling.interior);
        if let (false, Some(target)) = (self.params.optimise_speed, self.params.target_thickness) {
            let mean = quality.interior.mean;
            if mean > 0.0 {
                // Thickness ∝ 1/v, the speed held within its limits.
                speed = (v0 * mean / target).clamp(self.speed_limits.min, self.speed_limits.max);
                let k = v0 / speed;
                thickness.iter_mut().for_each(|t| *t *= k);
                for s in [&mut quality.interior, &mut quality.whole] {
                    scale(s, k);
                }
                path.speed = speed;
                path.link_speed = speed;
            }
        }
        Ok(Evaluation {
            path,
            counts,
            passes,
            thickness,
            quality,
            empty_interior,
            speed,
        })
    }
}

/// Predicted excess over the limits at spacing `b` from the ripple of parallel passes on a
/// plane ([`ripple`]); the mean is the target, or the mass balance `ηQ/(v·b)`.
fn predicted_excess(params: &SprayParams, radius: Real, limits: &Limits, b: Real) -> Real {
    let (error, relative_std) = ripple(b / radius);
    let mean = params
        .target_thickness
        .unwrap_or(params.efficiency * params.flow_rate / (params.speed * b));
    limits.excess(&ThicknessStats {
        mean,
        std_dev: relative_std * mean,
        error,
        ..Default::default()
    })
}

/// Plans the spray trajectory over `faces` and predicts the coating; with quality limits,
/// searches the widest spacing meeting them. Reports `(stage, fraction)` for the stages
/// `spray samples`, `spray search` and `spray plan`.
pub fn plan_spray(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    faces: &[u32],
    params: &SprayParams,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<SprayPlan, SprayError> {
    plan_spray_cached(mesh, adjacency, geometry, faces, params, None, progress)
}

/// [`plan_spray`], on the evaluation samples `cache` keeps when they were made for the same
/// faces of the mesh at the same resolution, footprint and edge exclusion, leaving there
/// those it makes (the cache belongs to one mesh). The same plan to the bit.
pub fn plan_spray_cached(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    faces: &[u32],
    params: &SprayParams,
    cache: Option<&SampleCache>,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<SprayPlan, SprayError> {
    let mut resolved = params.validate()?;
    let frame = patch_frame(
        mesh,
        geometry,
        faces,
        resolved.direction,
        params.raster_angle,
    )?;
    // Refuse a spacing wider than the patch before the costly set-up.
    if !params.has_limits() {
        frame.plane_offsets(params.spacing)?;
    }
    progress("spray samples", 0.0);
    if let Some(budget) = params.sample_budget {
        resolved.resolution = fit_resolution(mesh, &frame.faces, resolved.resolution, budget);
    }
    let sets = sample_sets(
        mesh,
        adjacency,
        geometry,
        &frame,
        &resolved,
        params.has_limits(),
        params.optimise_speed,
        cache,
    )?;
    progress("spray samples", 1.0);
    let limits = params
        .quality
        .filter(|_| params.has_limits())
        .map(|q| Limits {
            max_std_dev: q.max_std_dev,
            max_error: q.max_error,
        });
    let setup = Setup {
        mesh,
        adjacency,
        geometry,
        params,
        full: &sets.full,
        coarse: sets.coarse(),
        model: SprayModel {
            radius: resolved.radius,
            peak_rate: resolved.peak_rate,
            standoff: params.standoff,
        },
        extension: resolved.extension,
        time_step: resolved.time_step,
        speed_limits: SpeedLimits {
            min: resolved.speed_limits.0,
            max: resolved.speed_limits.1,
        },
        limits,
    };
    let coarse = setup.coarse.filter(|_| params.has_limits());
    let mut messages = Vec::new();
    let mut kept: Option<(Real, Evaluation)> = None;
    let (spacing, iterations) = match (limits, params.quality) {
        (Some(limits), Some(q)) => {
            let width = frame.arc[frame.arc.len() - 1];
            let hi = q.max_spacing.unwrap_or(2.0 * resolved.radius).min(width);
            let lo = q.min_spacing.unwrap_or(0.25 * resolved.radius).min(hi);
            // Keeps the evaluation of the widest feasible spacing so far: the search
            // chooses it, so the final plan need not run it again.
            let choice = search_spacing(
                lo,
                hi,
                &limits,
                coarse.is_some(),
                &|b| predicted_excess(params, resolved.radius, &limits, b),
                &mut |b, fidelity| {
                    let sampling = match (fidelity, coarse) {
                        (Fidelity::Coarse, Some(c)) => c,
                        _ => setup.full,
                    };
                    let r = setup.evaluate(&frame, b, sampling)?;
                    let stats = r.quality.interior;
                    let full = std::ptr::eq(sampling, setup.full);
                    let better = kept.as_ref().is_none_or(|(k, e)| {
                        limits.met(&stats) && (!limits.met(&e.quality.interior) || b > *k)
                    });
                    if full && better {
                        kept = Some((b, r));
                    }
                    Ok((stats, sampling.resolution))
                },
                &mut |f| progress("spray search", f),
            )?;
            if let Some((b, why)) = &choice.too_narrow {
                messages.push(format!(
                    "spacings of {} and narrower were left out of the search: {why}",
                    Compact(*b)
                ));
            }
            (choice.spacing, choice.iterations)
        }
        _ => (params.spacing, Vec::new()),
    };
    progress("spray plan", 0.0);
    let chosen = match kept {
        Some((b, evaluation)) if b == spacing => evaluation,
        _ => setup.evaluate(&frame, spacing, setup.full)?,
    };
    // Other pass directions at the chosen spacing.
    let mut raster_angle = params.raster_angle;
    let mut directions = Vec::new();
    let chosen = if params.best_direction {
        let quarter = std::f64::consts::FRAC_PI_4;
        let mut best = (raster_angle, chosen);
        let mut trials = vec![trial(raster_angle, &best.1)];
        for turn in [2.0 * quarter, quarter, -quarter] {
            let angle = params.raster_angle + turn;
            let other = patch_frame(mesh, geometry, faces, resolved.direction, angle)
                .and_then(|f| setup.evaluate(&f, spacing, setup.full));
            let Ok(other) = other else {
                trials.push(DirectionTrial {
                    raster_angle: angle,
                    error: Real::INFINITY,
                    std_dev: Real::INFINITY,
                    cycle_time: Real::INFINITY,
                    chosen: false,
                });
                continue;
            };
            trials.push(trial(angle, &other));
            let (a, b) = (
                setup.score(&other.quality.interior),
                setup.score(&best.1.quality.interior),
            );
            let tie = (a - b).abs() <= DIRECTION_TIE * a.max(b);
            if (!tie && a < b) || (tie && cycle_time(&other.path) < cycle_time(&best.1.path)) {
                best = (angle, other);
            }
        }
        for t in &mut trials {
            t.chosen = t.raster_angle == best.0;
        }
        directions = trials;
        raster_angle = best.0;
        best.1
    } else {
        chosen
    };
    let Evaluation {
        mut path,
        counts,
        passes: pass_count,
        thickness,
        quality,
        empty_interior,
        speed,
    } = chosen;
    // The figures of the plan delivered decide: with `bestDirection`, another direction may
    // meet the limits at a spacing where the searched one did not.
    let limits_met = limits.is_none_or(|l| l.met(&quality.interior));
    let iterations = if iterations.is_empty() {
        vec![Iteration {
            spacing,
            resolution: setup.full.resolution,
            mean: quality.interior.mean,
            std_dev: quality.interior.std_dev,
            error: quality.interior.error,
            met: true,
            full: true,
        }]
    } else {
        iterations
    };
    if empty_interior {
        messages.push(format!(
            "no sample lies edgeExclusion = {:.6} from the boundary: the interior figures are the whole patch's",
            resolved.edge_exclusion
        ));
    }
    let hotspots = hotspots(&setup, &frame, &thickness, &quality);
    if let (Some(l), false) = (limits, limits_met) {
        messages.extend(limit_messages(
            &l,
            &quality.interior,
            spacing,
            &iterations,
            &hotspots,
            params,
        ));
    }
    if let Some(target) = params.target_thickness {
        let mean = quality.interior.mean;
        if mean <= 0.0 {
            messages.push(
                "targetThickness not reached: the trajectory deposits nothing on the interior"
                    .into(),
            );
        } else if (mean - target).abs() > TARGET_TOLERANCE * target {
            let (lo, hi) = resolved.speed_limits;
            messages.push(format!(
                "targetThickness {} not reached within the speed limits {} to {}: the interior mean is {}; a flow rate of {} (now {}) would reach it",
                Compact(target),
                Compact(lo),
                Compact(hi),
                Compact(mean),
                Compact(params.flow_rate * target / mean),
                Compact(params.flow_rate),
            ));
        }
    }
    let (spray_length, path_length) = lengths(&path);
    let speed_range = path
        .poses
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(_, p)| p.kind.process_on())
        .map(|(k, _)| path.move_speed(k))
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let speed_range = if speed_range.0.is_finite() {
        speed_range
    } else {
        (speed, speed)
    };
    let cycle = cycle_time(&path);
    path.notes.push(format!(
        "spacing {spacing:.6}, standoff {}, speed {speed:.6}, flow rate {}, cone angle {:.6} rad, transition angle {:.6} rad, efficiency {}",
        params.standoff, params.flow_rate, params.cone_angle, params.transition_angle, params.efficiency
    ));
    if params.optimise_speed {
        path.notes.push(format!(
            "gun speed optimised along the passes within {} to {}: {} to {} commanded; cycle time {:.1} s",
            Compact(resolved.speed_limits.0),
            Compact(resolved.speed_limits.1),
            Compact(speed_range.0),
            Compact(speed_range.1),
            cycle
        ));
    }
    path.notes.extend(messages.iter().cloned());
    progress("spray plan", 1.0);
    Ok(SprayPlan {
        path,
        spacing,
        speed,
        speed_optimised: params.optimise_speed,
        speed_range,
        cycle_time: cycle,
        spray_length,
        path_length,
        raster_angle,
        directions,
        pass_count,
        counts,
        resolution: setup.full.resolution,
        samples: setup.full.samples.clone(),
        thickness,
        interior: setup.full.interior.clone(),
        quality,
        iterations,
        limits_met,
        hotspots,
        messages,
    })
}

fn trial(raster_angle: Real, e: &Evaluation) -> DirectionTrial {
    DirectionTrial {
        raster_angle,
        error: e.quality.interior.error,
        std_dev: e.quality.interior.std_dev,
        cycle_time: cycle_time(&e.path),
        chosen: false,
    }
}

/// Time to run `path` at its move speeds, seconds.
pub fn cycle_time(path: &ToolPath) -> Real {
    path.poses
        .windows(2)
        .enumerate()
        .map(|(k, w)| (w[1].position - w[0].position).norm() / path.move_speed(k + 1))
        .sum()
}

/// Lengths of the gun-on path and of the whole path.
fn lengths(path: &ToolPath) -> (Real, Real) {
    path.poses.windows(2).fold((0.0, 0.0), |(on, all), w| {
        let l = (w[1].position - w[0].position).norm();
        (on + if w[1].kind.process_on() { l } else { 0.0 }, all + l)
    })
}

/// The worst interior regions: samples deviating most from the interior mean, at least `R`
/// apart, each with what lies under it.
fn hotspots(
    setup: &Setup,
    frame: &PatchFrame,
    thickness: &[Real],
    quality: &Quality,
) -> Vec<Hotspot> {
    let mean = quality.interior.mean;
    if mean <= 0.0 {
        return Vec::new();
    }
    let sampling = setup.full;
    let radius = setup.model.radius;
    let any_interior = sampling.interior.iter().any(|&i| i);
    let deviation = |i: usize| (thickness[i] - mean) / mean;
    let candidate = |i: &usize| sampling.interior[*i] || !any_interior;
    let positions = &sampling.samples.positions;
    // Beyond a tenth of the worst, a region is no longer among the worst.
    let worst = (0..thickness.len())
        .filter(candidate)
        .fold(0.0, |m: Real, i| m.max(deviation(i).abs()));
    // Worst first, each at least R from those picked before (ties to the lower sample):
    // each round scans the candidates once, so this is linear, not a sort.
    let mut picked: Vec<usize> = Vec::new();
    while picked.len() < MAX_HOTSPOTS {
        let mut next: Option<(Real, usize)> = None;
        for i in (0..thickness.len()).filter(candidate) {
            let d = deviation(i).abs();
            if d < 0.1 * worst || next.is_some_and(|(best, _)| d <= best) {
                continue;
            }
            if picked
                .iter()
                .all(|&k| (positions[k] - positions[i]).norm() >= radius)
            {
                next = Some((d, i));
            }
        }
        match next {
            Some((_, i)) => picked.push(i),
            None => break,
        }
    }
    let points: Vec<Point3> = picked.iter().map(|&i| positions[i]).collect();
    let away_from_edge = interior_mask(
        setup.mesh,
        setup.adjacency,
        &frame.faces,
        &frame.selected,
        &points,
        2.0 * setup.params.edge_exclusion.unwrap_or(radius),
    );
    picked
        .iter()
        .zip(&away_from_edge)
        .map(|(&i, &away)| {
            let spread = |reach: Real| {
                let n = sampling.samples.normals[i];
                let r = Vector3::repeat(reach);
                let mut widest: Real = 0.0;
                sampling.grid.for_each_in_box(
                    &(positions[i].coords - r),
                    &(positions[i].coords + r),
                    |k| {
                        if (positions[k] - positions[i]).norm() <= reach {
                            widest = widest.max(angle_between(&n, &sampling.samples.normals[k]));
                        }
                    },
                );
                widest
            };
            let cause = if !away {
                HotspotCause::Edge
            } else if spread(0.5 * radius) > setup.params.transition_angle {
                HotspotCause::Fold
            } else if spread(radius) > CURVED_SPREAD_RAD {
                HotspotCause::Curvature
            } else {
                HotspotCause::Spacing
            };
            Hotspot {
                position: positions[i],
                deviation: deviation(i),
                cause,
            }
        })
        .collect()
}

/// Which limit fails and by how much, where, and what would help.
fn limit_messages(
    limits: &Limits,
    interior: &ThicknessStats,
    spacing: Real,
    iterations: &[Iteration],
    hotspots: &[Hotspot],
    params: &SprayParams,
) -> Vec<String> {
    let mut failing = Vec::new();
    if let Some(d) = limits.max_error.filter(|&d| interior.error > d) {
        failing.push(format!(
            "error δ {:.1} % exceeds maxError {:.1} %",
            100.0 * interior.error,
            100.0 * d
        ));
    }
    if let Some(e) = limits.max_std_dev.filter(|&e| interior.std_dev > e) {
        failing.push(format!(
            "stdDev E {} exceeds maxStdDev {}",
            Compact(interior.std_dev),
            Compact(e)
        ));
    }
    let mut out = vec![format!(
        "quality limits not met: no spacing tried meets them; spacing {} is the widest within {:.0} % of the best figures seen ({} spacings tried): {}",
        Compact(spacing),
        100.0 * FALLBACK_MARGIN,
        iterations.len(),
        failing.join("; ")
    )];
    if !hotspots.is_empty() {
        let mut count = [0usize; 4];
        for h in hotspots {
            count[h.cause as usize] += 1;
        }
        let names = [
            "at the patch edge",
            "at a fold",
            "on a tightly curved part",
            "between passes",
        ];
        let wheres: Vec<String> = names
            .iter()
            .zip(count)
            .filter(|(_, c)| *c > 0)
            .map(|(n, c)| format!("{c} {n}"))
            .collect();
        out.push(format!(
            "the worst regions (marked on the map): {}; the worst deviates {:+.1} % from the mean",
            wheres.join(", "),
            100.0 * hotspots[0].deviation
        ));
        let mut help = Vec::new();
        if count[HotspotCause::Fold as usize] + count[HotspotCause::Curvature as usize] > 0 {
            help.push("smaller, flatter patches (a smaller θmax in Segment)");
        }
        if count[HotspotCause::Edge as usize] > 0 {
            help.push("a wider edgeExclusion or a longer extension past the edge");
        }
        if !params.best_direction {
            help.push("another pass direction (\"best of\")");
        }
        help.push("looser limits");
        out.push(format!("what would help: {}", help.join(", ")));
    }
    out
}

fn scale(s: &mut ThicknessStats, k: Real) {
    s.mean *= k;
    s.std_dev *= k;
    s.min *= k;
    s.max *= k;
}
