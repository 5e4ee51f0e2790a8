//! The evaluation samples of a spray plan: the full set the figures are computed on, the
//! coarser set the spacing search screens on, and the set the speed optimiser solves on.
//!
//! Source: no paper (the patent evaluates the coating on the surface without saying where).
//! Input:  mesh, adjacency, face geometry, the patch frame, the resolved parameters.
//! Output: [`SampleSets`]: [`Sampling`]s of samples stored cell by cell, their grid and
//!         interior mask.
//! Cost:   the full samples and their grid once; with quality limits, a second set at
//!         [`COARSE_RESOLUTION_RATIO`] times the resolution serves the search's screening
//!         when it has at most half the samples (on a mesh finer than the resolution, the
//!         full samples thinned to one per cube of that size; on one a little coarser, whose
//!         faces get samples closer than the cell along their shorter edges, those thinned
//!         samples too when they are half as many and the cube is small beside the
//!         footprint). On a mesh finer than the resolution the speed optimiser also solves on
//!         the full samples thinned to one per cube of the resolution, and the speeds found
//!         are then deposited on all of them: the figures are always those of every sample.
//!         A [`SampleCache`] keeps the sets of the last plan (the screening set added by the
//!         first search): the next plan on the same faces of the same mesh at the same
//!         resolution, footprint and edge band takes them as they are.
//! Deviations: none (no paper).

use super::grid::PointGrid;
use super::params::{Resolved, SprayError};
use super::quality::interior_mask;
use super::raster::PatchFrame;
use super::samples::{sample_faces, subdivides, EvaluationSamples};
use crate::math::Real;
use crate::mesh::{FaceAdjacency, FaceGeometry, TriMesh};
use std::cell::RefCell;
use std::sync::{Arc, OnceLock};

/// Cell size of the evaluation-sample grid as a fraction of `R`: small enough that a cone's
/// box visits few points outside the cone, large enough that it visits few empty cells.
pub(super) const GRID_CELL_RATIO: Real = 0.5;
/// The grid's cells are at least this many times the samples' resolution: samples lie up
/// to a resolution apart, so on samples sparser than `R/4` (a sample budget on a large
/// patch, or the screening set of one) cells of `R/2` would be mostly empty, and a cone's
/// box would visit ten empty cells for each with a sample. (No paper. On the largest
/// patches of the 747, Orion and BWB models at the resolutions a budget of 100,000 samples
/// gives, 68–99 mm, the same plans in 0.6–0.7 of the time; 1.5 and 3 were no better.)
const GRID_CELL_SAMPLES: Real = 2.0;

/// Grid cell for samples at `resolution` (see [`GRID_CELL_RATIO`], [`GRID_CELL_SAMPLES`]).
fn grid_cell(radius: Real, resolution: Real) -> Real {
    (GRID_CELL_RATIO * radius).max(GRID_CELL_SAMPLES * resolution)
}

/// The spacing search's coarse scan samples at this multiple of the evaluation resolution.
pub const COARSE_RESOLUTION_RATIO: Real = 2.0;
/// The coarse scan is used only when its samples are at most this fraction of the full ones
/// (on a mesh coarser than the resolution both are the mesh's own vertices).
const COARSE_SAMPLE_FRACTION: Real = 0.5;
/// Coarse samples more than this many per cell² of area are thinned from the full ones
/// instead when that halves them, if the cell is at most [`COARSE_THINNED_CELL_RATIO`]·R
/// (one sample a cube stands for its cube's coating only where the cube is small beside
/// the spray's footprint).
const COARSE_DENSITY: Real = 2.0;
/// Largest coarse cell, as a fraction of `R`, whose cubes thinned samples may stand for
/// (the default resolution's coarse cell is R/4).
const COARSE_THINNED_CELL_RATIO: Real = 0.25 * (1.0 + 1e-9);
/// The speed optimiser solves on the samples thinned to the resolution only when that
/// leaves at most this fraction of them.
const SOLVE_SAMPLE_FRACTION: Real = 0.25;

/// Evaluation samples at one resolution, their grid and interior mask.
pub(super) struct Sampling {
    pub(super) resolution: Real,
    pub(super) samples: EvaluationSamples,
    pub(super) grid: PointGrid,
    pub(super) interior: Vec<bool>,
    /// For samples thinned from others: the index of each among those.
    pub(super) origin: Vec<usize>,
    /// The same samples thinned to one per cube of the resolution, when that leaves at most
    /// [`SOLVE_SAMPLE_FRACTION`] of them (a mesh finer than the resolution): the speed
    /// optimiser solves on these, and the plan's speeds are then deposited on all samples.
    pub(super) solve: Option<Box<Sampling>>,
    /// Per sample: whether it is one of `solve`'s (its thickness comes from the optimiser).
    pub(super) solved: Vec<bool>,
}

impl Sampling {
    /// The samples thinned to one per cube of side `cell`, when markedly fewer.
    fn thinned(&self, cell: Real, radius: Real) -> Option<Sampling> {
        let (samples, origin) = self.samples.thinned(cell, &self.interior);
        let fewer = samples.positions.len() as Real
            <= COARSE_SAMPLE_FRACTION * self.samples.positions.len() as Real;
        fewer.then(|| Sampling {
            resolution: cell,
            grid: PointGrid::new(&samples.positions, grid_cell(radius, cell)),
            interior: origin.iter().map(|&i| self.interior[i]).collect(),
            origin,
            samples,
            solve: None,
            solved: Vec::new(),
        })
    }

    /// Gives the speed optimiser the samples thinned to one per cube of the resolution where
    /// that leaves at most [`SOLVE_SAMPLE_FRACTION`] of them: samples several times denser
    /// than the resolution in each direction, so every cube keeps one and the thinned set
    /// has no holes (a lattice at about the resolution, thinned at its own spacing, would).
    fn with_solve_samples(mut self, radius: Real) -> Sampling {
        // Each cube the surface meets keeps a sample, and a surface flat at the cubes' scale
        // meets at least its area over √2·cell² of them (a cube's largest plane section):
        // where that alone is over the fraction (a mesh coarser than the resolution, whose
        // samples lie about one a cube), thinning is not tried.
        let area: Real = self.samples.weights.iter().sum();
        let cell = self.resolution;
        if area / (std::f64::consts::SQRT_2 * cell * cell)
            > SOLVE_SAMPLE_FRACTION * self.samples.positions.len() as Real
        {
            return self;
        }
        self.solve = self
            .thinned(self.resolution, radius)
            .filter(|t| {
                t.samples.positions.len() as Real
                    <= SOLVE_SAMPLE_FRACTION * self.samples.positions.len() as Real
            })
            .map(Box::new);
        if let Some(solve) = &self.solve {
            self.solved = vec![false; self.samples.positions.len()];
            for &i in &solve.origin {
                self.solved[i] = true;
            }
        }
        self
    }

    /// The samples `sample_faces` placed at `resolution`, stored cell by cell, with their
    /// grid and interior mask.
    fn new(
        mesh: &TriMesh,
        adjacency: &FaceAdjacency,
        frame: &PatchFrame,
        samples: EvaluationSamples,
        resolution: Real,
        radius: Real,
        edge_exclusion: Real,
    ) -> Sampling {
        // Samples stored cell by cell, so a cone's box reads them from few cache lines.
        let grid = PointGrid::new(&samples.positions, grid_cell(radius, resolution));
        let samples = samples.permuted(grid.order());
        let grid = grid.reordered();
        let interior = interior_mask(
            mesh,
            adjacency,
            &frame.faces,
            &frame.selected,
            &samples.positions,
            edge_exclusion,
        );
        Sampling {
            resolution,
            samples,
            grid,
            interior,
            origin: Vec::new(),
            solve: None,
            solved: Vec::new(),
        }
    }
}

/// What the sample sets depend on: the mesh (its size: a cache belongs to one mesh), the
/// faces, the resolution, the footprint radius (the grid's cells), the edge exclusion (the
/// interior mask) and whether the speed optimiser's set is made. Numbers compare bit for bit.
#[derive(Debug, Clone, PartialEq)]
struct SampleKey {
    vertices: usize,
    triangles: usize,
    faces: Vec<u32>,
    numbers: [u64; 3],
    optimise_speed: bool,
}

impl SampleKey {
    fn new(mesh: &TriMesh, frame: &PatchFrame, resolved: &Resolved, optimise_speed: bool) -> Self {
        Self {
            vertices: mesh.vertex_count(),
            triangles: mesh.triangle_count(),
            faces: frame.faces.clone(),
            numbers: [
                resolved.resolution,
                resolved.radius,
                resolved.edge_exclusion,
            ]
            .map(Real::to_bits),
            optimise_speed,
        }
    }
}

/// The sample sets of a plan: the full samples (with the speed optimiser's, when asked) and
/// the spacing search's screening set, made by the first plan that searches.
pub(super) struct SampleSets {
    key: SampleKey,
    pub(super) full: Sampling,
    coarse: OnceLock<Option<Sampling>>,
}

impl SampleSets {
    /// The screening set, once made (`None` also when it would not be markedly fewer).
    pub(super) fn coarse(&self) -> Option<&Sampling> {
        self.coarse.get().and_then(Option::as_ref)
    }
}

/// The sample sets of the last plan, kept for the next plan on the same faces at the same
/// resolution: a user changing the spacing, the speeds, the quality limits or the pass
/// direction plans again on the same samples. One set at a time; [`plan_spray_cached`]
/// replaces it when the faces, the resolution, the footprint or the edge exclusion change.
///
/// [`plan_spray_cached`]: super::plan_spray_cached
#[derive(Default)]
pub struct SampleCache {
    last: RefCell<Option<Arc<SampleSets>>>,
}

impl std::fmt::Debug for SampleCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kept = self.last.borrow();
        f.debug_struct("SampleCache")
            .field(
                "samples",
                &kept.as_ref().map(|s| s.full.samples.positions.len()),
            )
            .finish()
    }
}

impl SampleCache {
    /// An empty cache.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets what it holds.
    pub fn clear(&self) {
        self.last.borrow_mut().take();
    }

    /// Number of full samples kept, if any.
    pub fn kept_samples(&self) -> Option<usize> {
        self.last
            .borrow()
            .as_ref()
            .map(|s| s.full.samples.positions.len())
    }
}

/// The full samples at the resolution, with the speed optimiser's when `optimise_speed`.
fn full_set(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    frame: &PatchFrame,
    resolved: &Resolved,
    optimise_speed: bool,
) -> Result<Sampling, SprayError> {
    let radius = resolved.radius;
    let samples = sample_faces(mesh, adjacency, geometry, &frame.faces, resolved.resolution)?;
    let full = Sampling::new(
        mesh,
        adjacency,
        frame,
        samples,
        resolved.resolution,
        radius,
        resolved.edge_exclusion,
    );
    Ok(if optimise_speed {
        full.with_solve_samples(radius)
    } else {
        full
    })
}

/// The samples the spacing search screens on, if markedly fewer than `full`'s.
fn coarse_set(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    frame: &PatchFrame,
    resolved: &Resolved,
    full: &Sampling,
) -> Result<Option<Sampling>, SprayError> {
    let radius = resolved.radius;
    let cell = COARSE_RESOLUTION_RATIO * resolved.resolution;
    // A face split at the cell is split at the finer resolution too: with one sub-triangle a
    // face already (every face unsplit), no face is measured again.
    let unsplit = full.samples.triangles.len() == frame.faces.len();
    if unsplit || !subdivides(mesh, &frame.faces, cell) {
        // The coarse samples would be the mesh's vertices: thin the full ones instead.
        return Ok(full.thinned(cell, radius));
    }
    let c = sample_faces(mesh, adjacency, geometry, &frame.faces, cell)?;
    let count = c.positions.len() as Real;
    if count > COARSE_SAMPLE_FRACTION * full.samples.positions.len() as Real {
        return Ok(full.thinned(cell, radius));
    }
    // On a mesh a little coarser than the cell, a face's reach sets its subdivisions and its
    // shorter edges get samples closer than the cell: the full samples thinned to the cell
    // may then be markedly fewer.
    let area: Real = full.samples.weights.iter().sum();
    let dense =
        cell <= COARSE_THINNED_CELL_RATIO * radius && count > COARSE_DENSITY * area / (cell * cell);
    let fewer = |t: &Sampling| t.samples.positions.len() as Real <= COARSE_SAMPLE_FRACTION * count;
    Ok(match dense.then(|| full.thinned(cell, radius)).flatten() {
        Some(t) if fewer(&t) => Some(t),
        _ => Some(Sampling::new(
            mesh,
            adjacency,
            frame,
            c,
            cell,
            radius,
            resolved.edge_exclusion,
        )),
    })
}

/// The full samples at the resolution (with the speed optimiser's, when `optimise_speed`) and,
/// when `screening`, the samples the spacing search screens on, if markedly fewer: those
/// `cache` keeps when they were made for the same faces at the same resolution (made now
/// and left there otherwise). The same samples to the bit either way.
#[allow(clippy::too_many_arguments)]
pub(super) fn sample_sets(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    frame: &PatchFrame,
    resolved: &Resolved,
    screening: bool,
    optimise_speed: bool,
    cache: Option<&SampleCache>,
) -> Result<Arc<SampleSets>, SprayError> {
    let key = SampleKey::new(mesh, frame, resolved, optimise_speed);
    let kept = cache.and_then(|c| c.last.borrow().clone().filter(|s| s.key == key));
    let sets = match kept {
        Some(sets) => sets,
        None => {
            // Let the old sets go first, so the two are not held at once.
            if let Some(c) = cache {
                c.clear();
            }
            let full = full_set(mesh, adjacency, geometry, frame, resolved, optimise_speed)?;
            let sets = Arc::new(SampleSets {
                key,
                full,
                coarse: OnceLock::new(),
            });
            if let Some(c) = cache {
                *c.last.borrow_mut() = Some(sets.clone());
            }
            sets
        }
    };
    if screening && sets.coarse.get().is_none() {
        let coarse = coarse_set(mesh, adjacency, geometry, frame, resolved, &sets.full)?;
        // Set once: nothing else holds this set while it is made.
        let _ = sets.coarse.set(coarse);
    }
    Ok(sets)
}
