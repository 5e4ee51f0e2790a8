//! `plan_spray`: scan planes, trajectory, deposition, quality and the spacing search in one
//! call.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), steps 1–7 (claims 1–7).
//! Input:  mesh, adjacency, face geometry, selected face ids, [`SprayParams`].
//! Output: [`SprayPlan`]: the tool path, evaluation samples with their thickness, quality,
//!         every spacing tried.
//! Cost:   samples and their grids once; per spacing tried O(F + S log S) for the raster and
//!         O(time samples × points per cone) for the deposition.
//!         With quality limits, a second sample set at [`COARSE_RESOLUTION_RATIO`] times the
//!         resolution serves the search's coarse scan when it has at most half the samples.
//! Deviations: optional `targetThickness` scales the speed after the spacing is fixed
//!         (thickness ∝ 1/v); the iterations keep the figures at the given speed.

use super::deposition::{deposit, SprayModel};
use super::grid::PointGrid;
use super::params::{SprayError, SprayParams};
use super::quality::{evaluate_quality, interior_mask, Quality, ThicknessStats};
use super::raster::{order_zigzag, patch_frame, scan_passes, PatchFrame};
use super::samples::{sample_faces, EvaluationSamples};
use super::search::{search_spacing, Fidelity, Iteration, Limits};
use super::trajectory::{build_trajectory, TrajectoryCounts};
use crate::math::Real;
use crate::mesh::{FaceAdjacency, FaceGeometry, TriMesh};
use crate::toolpath::ToolPath;

/// Cell size of the evaluation-sample grid as a fraction of `R`: small enough that a cone's
/// box visits few points outside the cone, large enough that it visits few empty cells.
const GRID_CELL_RATIO: Real = 0.5;
/// The spacing search's coarse scan samples at this multiple of the evaluation resolution.
pub const COARSE_RESOLUTION_RATIO: Real = 2.0;
/// The coarse scan is used only when its samples are at most this fraction of the full ones
/// (on a mesh coarser than the resolution both are the mesh's own vertices).
const COARSE_SAMPLE_FRACTION: Real = 0.5;

/// A planned spray job.
#[derive(Debug, Clone, PartialEq)]
pub struct SprayPlan {
    /// The gun trajectory (speed = the final gun speed).
    pub path: ToolPath,
    /// Pass spacing used.
    pub spacing: Real,
    /// Gun speed used (scaled when a target thickness was given).
    pub speed: Real,
    /// Number of passes.
    pub pass_count: usize,
    /// What the trajectory contains (transitions, arcs, trimmed concave edges).
    pub counts: TrajectoryCounts,
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
    /// Plain-language remarks: limits not met, empty interior, speed scaled.
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
}

/// Evaluation samples at one resolution, their grid and interior mask.
struct Sampling {
    resolution: Real,
    samples: EvaluationSamples,
    grid: PointGrid,
    interior: Vec<bool>,
}

impl Sampling {
    fn new(
        mesh: &TriMesh,
        adjacency: &FaceAdjacency,
        geometry: &FaceGeometry,
        frame: &PatchFrame,
        resolution: Real,
        radius: Real,
        edge_exclusion: Real,
    ) -> Result<Sampling, SprayError> {
        let samples = sample_faces(mesh, geometry, &frame.faces, resolution)?;
        let grid = PointGrid::new(&samples.positions, GRID_CELL_RATIO * radius);
        let interior = interior_mask(
            mesh,
            adjacency,
            &frame.faces,
            &frame.selected,
            &samples.positions,
            edge_exclusion,
        );
        Ok(Sampling {
            resolution,
            samples,
            grid,
            interior,
        })
    }
}

/// Everything that does not depend on the spacing.
struct Setup<'a> {
    mesh: &'a TriMesh,
    adjacency: &'a FaceAdjacency,
    geometry: &'a FaceGeometry,
    params: &'a SprayParams,
    frame: PatchFrame,
    full: Sampling,
    model: SprayModel,
    extension: Real,
    time_step: Real,
}

impl Setup<'_> {
    fn trajectory(&self, spacing: Real) -> Result<(ToolPath, TrajectoryCounts, usize), SprayError> {
        let offsets = self.frame.plane_offsets(spacing)?;
        let passes = scan_passes(self.mesh, self.adjacency, &self.frame, &offsets);
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
        );
        Ok((path, counts, passes.len()))
    }

    fn evaluate(&self, spacing: Real, sampling: &Sampling) -> Result<Evaluation, SprayError> {
        let (path, counts, passes) = self.trajectory(spacing)?;
        let thickness = deposit(
            &path,
            &sampling.samples,
            &sampling.grid,
            &self.model,
            self.params.speed,
            self.time_step,
        )?;
        let (quality, empty_interior) =
            evaluate_quality(&thickness, &sampling.samples.weights, &sampling.interior);
        Ok(Evaluation {
            path,
            counts,
            passes,
            thickness,
            quality,
            empty_interior,
        })
    }
}

/// Plans the spray trajectory over `faces` and predicts the coating; with quality limits,
/// searches the largest spacing meeting them. Reports `(stage, fraction)` for the stages
/// `spray samples`, `spray search` and `spray plan`.
pub fn plan_spray(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    faces: &[u32],
    params: &SprayParams,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<SprayPlan, SprayError> {
    let resolved = params.validate()?;
    let frame = patch_frame(
        mesh,
        geometry,
        faces,
        resolved.direction,
        params.raster_angle,
    )?;
    // Refuse a spacing wider than the patch before the costly set-up.
    frame.plane_offsets(params.spacing)?;
    progress("spray samples", 0.0);
    let full = Sampling::new(
        mesh,
        adjacency,
        geometry,
        &frame,
        resolved.resolution,
        resolved.radius,
        resolved.edge_exclusion,
    )?;
    // The coarse scan's samples, when they are markedly fewer.
    let coarse = if params.has_limits() {
        let c = Sampling::new(
            mesh,
            adjacency,
            geometry,
            &frame,
            COARSE_RESOLUTION_RATIO * resolved.resolution,
            resolved.radius,
            resolved.edge_exclusion,
        )?;
        let fewer = (c.samples.positions.len() as Real)
            <= COARSE_SAMPLE_FRACTION * full.samples.positions.len() as Real;
        fewer.then_some(c)
    } else {
        None
    };
    progress("spray samples", 1.0);
    let setup = Setup {
        mesh,
        adjacency,
        geometry,
        params,
        frame,
        full,
        model: SprayModel {
            radius: resolved.radius,
            peak_rate: resolved.peak_rate,
            standoff: params.standoff,
        },
        extension: resolved.extension,
        time_step: resolved.time_step,
    };
    let mut messages = Vec::new();
    let mut kept: Option<(Real, Evaluation)> = None;
    let (spacing, limits_met, iterations) = match (params.has_limits(), params.quality) {
        (true, Some(q)) => {
            let width = setup.frame.width();
            let hi = q.max_spacing.unwrap_or(2.0 * resolved.radius).min(width);
            let lo = q.min_spacing.unwrap_or(0.25 * resolved.radius).min(hi);
            let limits = Limits {
                max_std_dev: q.max_std_dev,
                max_error: q.max_error,
            };
            // Keeps the evaluation of the largest feasible spacing so far: the search
            // chooses it, so the final plan need not run it again.
            let choice = search_spacing(
                lo,
                hi,
                &limits,
                coarse.is_some(),
                &mut |b, fidelity| {
                    let sampling = match (fidelity, &coarse) {
                        (Fidelity::Coarse, Some(c)) => c,
                        _ => &setup.full,
                    };
                    let r = setup.evaluate(b, sampling)?;
                    let stats = r.quality.interior;
                    let full = std::ptr::eq(sampling, &setup.full);
                    if full && limits.met(&stats) && kept.as_ref().is_none_or(|(k, _)| b > *k) {
                        kept = Some((b, r));
                    }
                    Ok((stats, sampling.resolution))
                },
                &mut |f| progress("spray search", f),
            )?;
            if !choice.met {
                let it = choice
                    .iterations
                    .iter()
                    .rfind(|it| it.spacing == choice.spacing);
                messages.push(format!(
                    "quality limits not met: no spacing in [{lo:.6}, {hi:.6}] gives stdDev ≤ {} and error ≤ {}; the closest, spacing {:.6}, gives stdDev {:.6} and error {:.4}",
                    fmt_limit(q.max_std_dev),
                    fmt_limit(q.max_error),
                    choice.spacing,
                    it.map_or(Real::NAN, |it| it.std_dev),
                    it.map_or(Real::NAN, |it| it.error),
                ));
            }
            (choice.spacing, choice.met, choice.iterations)
        }
        _ => (params.spacing, true, Vec::new()),
    };
    progress("spray plan", 0.0);
    let Evaluation {
        mut path,
        counts,
        passes: pass_count,
        mut thickness,
        mut quality,
        empty_interior,
    } = match kept {
        Some((b, evaluation)) if b == spacing => evaluation,
        _ => setup.evaluate(spacing, &setup.full)?,
    };
    let iterations = if iterations.is_empty() {
        vec![Iteration {
            spacing,
            resolution: setup.full.resolution,
            mean: quality.interior.mean,
            std_dev: quality.interior.std_dev,
            error: quality.interior.error,
            met: true,
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
    let mut speed = params.speed;
    if let Some(target) = params.target_thickness {
        let mean = quality.interior.mean;
        if mean > 0.0 {
            // Thickness ∝ 1/v.
            let factor = mean / target;
            speed = params.speed * factor;
            thickness.iter_mut().for_each(|t| *t /= factor);
            for s in [&mut quality.interior, &mut quality.whole] {
                scale(s, 1.0 / factor);
            }
            path.speed = speed;
            path.link_speed = speed;
            messages.push(format!(
                "speed scaled from {} to {speed:.6} for an interior mean thickness of {target}",
                params.speed
            ));
        } else {
            messages.push(
                "targetThickness ignored: the trajectory deposits nothing on the interior".into(),
            );
        }
    }
    path.notes.push(format!(
        "spacing {spacing:.6}, standoff {}, speed {speed:.6}, flow rate {}, cone angle {:.6} rad, transition angle {:.6} rad, efficiency {}",
        params.standoff, params.flow_rate, params.cone_angle, params.transition_angle, params.efficiency
    ));
    path.notes.extend(messages.iter().cloned());
    progress("spray plan", 1.0);
    Ok(SprayPlan {
        path,
        spacing,
        speed,
        pass_count,
        counts,
        samples: setup.full.samples,
        thickness,
        interior: setup.full.interior,
        quality,
        iterations,
        limits_met,
        messages,
    })
}

fn fmt_limit(limit: Option<Real>) -> String {
    limit.map_or("(none)".into(), |l| format!("{l}"))
}

fn scale(s: &mut ThicknessStats, k: Real) {
    s.mean *= k;
    s.std_dev *= k;
    s.min *= k;
    s.max *= k;
}
