//! The entry point: a distance field from a source by either method, its iso-distance lines
//! and the tool path that links them.
//!
//! No paper for the linking: levels are taken in increasing distance; within a level the
//! next line is the one starting nearest to where the tool is; open lines start at their end
//! nearest the tool (zig-zag) or run the same way as the first open line (one direction);
//! closed lines start at their point nearest the tool and turn like the first loop (one
//! direction) or alternately (zig-zag), and end back at their first point. Between passes a
//! `Link` pose (process off) moves to the next pass's first point, where the pass starts;
//! consecutive points of a line that coincide (within a millionth of the spacing) are one
//! pose, and a line that shrinks to one point is left out, so no process-on move has zero
//! length.
//! Cost: O(F + C) for all the levels of the mesh method, C the crossings of faces by levels
//! (each face is listed under the levels it spans, in one pass; O(V + B) for the voxel
//! method's V voxels and B band voxels), plus O(P²) over the P lines of one level for the
//! nearest-line choice (P is small: the pieces of one level). At most 5 million points and
//! 20 million crossings a call ([`MAX_PATH_POINTS`]), counted before they are made.

use super::iso_lines::{contour_from, joined_at_ends, IsoLine, LevelLists, JOIN_TOLERANCE};
use super::params::{DistanceParams, GeodesicError, LinkOrder, Method, PathParams, Progress};
use super::source::{boundary_loops, resolve, GeodesicSource};
use super::surface::{Derived, Surface, SurfaceCache};
use super::unfolding::is_hole_rim;
use super::voxel::{propagate as voxel_propagate, voxelise, VoxelField};
use super::voxel_paths::{order_level, voxels_by_level};
use crate::math::{Real, Vector3};
use crate::mesh::{FaceAdjacency, TriMesh};
use crate::toolpath::{Pose, PoseKind, ToolPath};
use std::sync::Arc;

/// Levels at most in one request (a guard against a spacing far below the part size).
pub const MAX_LEVELS: u32 = 100_000;
/// Most points the passes of one call may have (a robot program of that many moves is
/// already far beyond what a controller holds; the page gets them as 12 bytes a point).
pub const MAX_PATH_POINTS: u64 = 5_000_000;
/// Most crossings of a face (or a voxel's band) by a level the passes of one call may look
/// at (4 bytes each).
const MAX_LEVEL_CROSSINGS: u64 = 20_000_000;
/// Source samples per mean edge length (the source polyline is subdivided this finely).
const SAMPLES_PER_EDGE: Real = 2.0;
/// Default voxel edge, in mean edge lengths.
const DEFAULT_VOXEL_PER_EDGE: Real = 0.25;
/// Consecutive points of a pass closer than this multiple of the spacing are merged.
const SAME_POSITION_RATIO: Real = 1e-6;
/// Default snapping distance, in mean edge lengths.
const DEFAULT_SNAP_EDGES: Real = 5.0;
/// The accurate method tries the exact one first only on surfaces of at most this many faces
/// (where its budget below costs at most about five seconds natively)...
const EXACT_FIRST_FACES: usize = 100_000;
/// ...with a vertex whose |angle defect| exceeds this (radians, about 3°): a corner, where
/// virtual sources err most. Smooth meshes fine enough for virtual sources to be accurate
/// have defects far below it (a 500k-triangle sphere: 5·10⁻⁵), and corners stay corners
/// however fine the mesh.
const CORNER_DEFECT: Real = 0.05;
/// ...or with a hole (a boundary loop that turns as a hole's rim does, see
/// [`HOLE_TURNING`](super::unfolding::HOLE_TURNING)). Virtual sources are held to the shadow a hole
/// casts only near its rim, and a point source along the shadow's edge (see
/// `virtual_source/shadow.rs`): on Orion's heat shield (5,694 faces, six holes about 1.3 ft
/// across), from its section by the plane x = 0, they are up to 0.50 ft short of the exact distance
/// behind a hole (1.2 before that walk; no corner there, so the exact method would not be tried);
/// on the cap R 1000 mm of 60k faces with a hole 120 mm across, from a plane section, 0.22 mm (15
/// before; from a vertex, held to the shadow's edge all the way back, 0.000). Larger surfaces, and
/// a try over its budget, keep that error (see "Limits" in `virtual_source.rs`).
/// Windows per face the exact method may process there. Measured on whole aircraft models
/// from a vertex: 19–32 per face on a BWB, 45–46 on a wing-body (161 from its nose), 35–59
/// on Orion; from their sections by planes at a tenth to nine tenths of their length: 34–44
/// on the BWB, 52–63 on the airplane, 78–115 on Orion, 109–183 on the wing-body (2.1–3.9 s
/// natively). With 64 (until the virtual sources' pieces were taken as points at sharp
/// vertices far from the curve, see `virtual_source.rs`), Orion and the wing-body got virtual
/// sources from most such planes, up to 3.6 ft and 0.22 m short of exact (0.73–9.6 ft and
/// 0.12–0.90 m before that change). A try on course to overrun the budget gives up early
/// (see `exact::PROJECTED_OVERRUN`).
const EXACT_FIRST_WINDOWS_PER_FACE: u64 = 192;
/// ...and at least this many on a surface of fewer than 65,536 faces (about a second
/// natively), where a budget per face would give up on work nearly done: windows per face
/// grow about as √n (see `exact`), so Orion's heat shield from its section by the plane
/// x = 0 takes 71 per face (405k) and, each face split in four (22,776 faces), 102 per face
/// (2.32M; a budget of 2²¹ stopped it at nine tenths of the way, 0.56 s natively, and the
/// virtual sources answered 0.078 ft long and 0.032 short by a notch in a hole's rim).
const EXACT_FIRST_MIN_WINDOWS: u64 = 1 << 22;

/// Geodesic distance from a source, by the mesh or the voxel method. It keeps what it was
/// computed on (the active faces, their normals, the faces around each vertex: about 45 bytes
/// a face, shared with the mesh's [`SurfaceCache`] when it came through one), which its iso
/// lines and tool path reuse.
#[derive(Clone, Debug)]
pub struct DistanceField {
    /// Which method produced it.
    pub method: Method,
    /// Distance per mesh vertex (`+∞` where unreached or outside the faces). For the voxel
    /// method: the distance of the voxel containing the vertex (or its nearest neighbour).
    pub vertex_distance: Vec<Real>,
    /// The voxels (voxel method only).
    pub voxels: Option<VoxelField>,
    /// Largest finite distance.
    pub max_distance: Real,
    /// Samples of the resolved source (curve points + vertices).
    pub source_samples: usize,
    /// Windows propagated (exact method; 0 for the others).
    pub windows: u64,
    /// What the distance was computed on: its active faces, their normals and the faces
    /// around each vertex, shared with the iso lines.
    surface: Arc<Derived>,
}

/// Computes the geodesic distance from `source` on `mesh` (or on `params.faces`), reporting
/// `(stage, fraction)` to `progress`.
pub fn geodesic_distance(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    source: &GeodesicSource,
    params: &DistanceParams,
    progress: Progress,
) -> Result<DistanceField, GeodesicError> {
    geodesic_distance_cached(mesh, adjacency, None, source, params, progress)
}

/// [`geodesic_distance`], reusing what `cache` (the mesh's own) holds for the same faces and
/// leaving there what it derives from the mesh (the faces around each vertex, the face
/// normals): the same distances, without deriving them again on each call.
pub fn geodesic_distance_cached(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    cache: Option<&SurfaceCache>,
    source: &GeodesicSource,
    params: &DistanceParams,
    progress: Progress,
) -> Result<DistanceField, GeodesicError> {
    let surface = Surface::cached(mesh, adjacency, params.faces.as_deref(), cache)?;
    // Built only for sources that need snapping (points, plane sections).
    let grid = std::cell::OnceCell::new();
    let max_snap = match params.max_snap_distance {
        Some(m) => {
            super::params::positive("maxSnapDistance", m)?;
            m
        }
        None => DEFAULT_SNAP_EDGES * surface.mean_edge,
    };
    let voxel_size = match params.voxel_size {
        Some(l) => {
            super::params::positive("voxelSize", l)?;
            l
        }
        None => DEFAULT_VOXEL_PER_EDGE * surface.mean_edge,
    };
    // The voxel method seeds its own voxels L/2 apart along these samples.
    let step = surface.mean_edge / SAMPLES_PER_EDGE;
    let resolved = resolve(&surface, &grid, source, step, max_snap)?;
    let mut windows = 0;
    let mut ran = params.method;
    let (vertex_distance, voxels) = match params.method {
        Method::Fast => (
            super::unfolding::propagate(&surface, &resolved, progress)?,
            None,
        ),
        Method::Accurate => {
            let exact_first = match exact_first_budget(&surface, params.exact_first_windows) {
                Some(cap) => {
                    let run = super::exact::propagate(
                        &surface,
                        &resolved,
                        Some(cap),
                        true,
                        &mut *progress,
                    );
                    match run {
                        Ok((d, stats)) => {
                            ran = Method::Exact;
                            windows = stats.windows;
                            Some(d)
                        }
                        // Over budget: the virtual sources below answer instead.
                        Err(GeodesicError::LimitExceeded(_)) => None,
                        Err(e) => return Err(e),
                    }
                }
                None => None,
            };
            let d = match exact_first {
                Some(d) => d,
                None => super::virtual_source::propagate(&surface, &resolved, progress)?,
            };
            (d, None)
        }
        Method::Exact => {
            if params.max_windows == Some(0) {
                return Err(GeodesicError::BadParam {
                    name: "max_windows",
                    value: 0.0,
                    why: "must be > 0",
                });
            }
            let (d, stats) =
                super::exact::propagate(&surface, &resolved, params.max_windows, false, progress)?;
            windows = stats.windows;
            (d, None)
        }
        Method::Voxel => {
            let mut field = voxelise(&surface, voxel_size, params.max_voxel_bytes, progress)?;
            voxel_propagate(&mut field, &resolved, &surface, progress)?;
            let mut vd = vec![Real::INFINITY; mesh.vertex_count()];
            for (v, d) in vd.iter_mut().enumerate() {
                if !surface.faces_of(v).is_empty() {
                    if let Some(i) = field.voxel_near(&mesh.positions()[v]) {
                        *d = field.distance[i];
                    }
                }
            }
            (vd, Some(field))
        }
    };
    // A comparison, not `Real::max`: WebAssembly builds call `fmax` for it (its NaN rules
    // differ from the instruction's), and the values compared here are finite.
    let finite_max = |d: &[Real]| {
        d.iter()
            .fold(0.0, |m, &x| if x.is_finite() && x > m { x } else { m })
    };
    let max_distance = match &voxels {
        Some(f) => finite_max(&f.distance),
        None => finite_max(&vertex_distance),
    };
    Ok(DistanceField {
        method: ran,
        vertex_distance,
        voxels,
        max_distance,
        source_samples: resolved.sample_count(),
        windows,
        surface: surface.derived().clone(),
    })
}

/// Windows the accurate method lets the exact one process first (`None`: it does not try):
/// `given` when set (`Some(0)`: never), else [`EXACT_FIRST_WINDOWS_PER_FACE`] per face (at
/// least [`EXACT_FIRST_MIN_WINDOWS`]) on a surface of at most [`EXACT_FIRST_FACES`] faces
/// with a corner (see [`CORNER_DEFECT`]) or a hole (see
/// [`HOLE_TURNING`](super::unfolding::HOLE_TURNING)). O(F log F).
fn exact_first_budget(surface: &Surface, given: Option<u64>) -> Option<u64> {
    if let Some(w) = given {
        return (w > 0).then_some(w);
    }
    let faces = surface.faces.len();
    if faces > EXACT_FIRST_FACES {
        return None;
    }
    let cornered = (0..surface.mesh.vertex_count()).any(|v| {
        !surface.faces_of(v).is_empty()
            && super::unfolding::angle_defect(surface, v).is_some_and(|d| d.abs() > CORNER_DEFECT)
    });
    (cornered || has_hole(surface))
        .then_some((EXACT_FIRST_WINDOWS_PER_FACE * faces as u64).max(EXACT_FIRST_MIN_WINDOWS))
}

/// Whether a boundary loop of `surface` turns as the rim of a hole does (see
/// [`HOLE_TURNING`](super::unfolding::HOLE_TURNING)).
fn has_hole(surface: &Surface) -> bool {
    boundary_loops(surface)
        .iter()
        .any(|l| is_hole_rim(surface, l))
}

impl DistanceField {
    /// Iso-distance lines at `k · spacing`, `k = 1..=K`, in increasing level, each resampled
    /// at the point spacing. Mesh method: exact level sets of the piecewise-linear distance;
    /// voxel method: the paper's step 4.
    pub fn iso_lines(
        &self,
        mesh: &TriMesh,
        adjacency: &FaceAdjacency,
        params: &PathParams,
    ) -> Result<Vec<IsoLine>, GeodesicError> {
        params.validate()?;
        let surface = Surface::sharing(mesh, adjacency, self.surface.clone())?;
        let top = (self.max_distance / params.spacing).floor();
        if top > MAX_LEVELS as Real {
            return Err(GeodesicError::BadParam {
                name: "spacing",
                value: params.spacing,
                why: "gives more than 100000 levels over the largest distance",
            });
        }
        let mut k_max = top as u32;
        if let Some(m) = params.max_level {
            k_max = k_max.min(m);
        }
        let point_spacing = params.point_spacing.unwrap_or(params.spacing / 4.0);
        // The faces each level crosses (the voxels near it), found in one pass: a scan of
        // every face or voxel per level would make a fine spacing on a large mesh quadratic.
        let lists = match &self.voxels {
            Some(field) => voxels_by_level(field, params.spacing, k_max, MAX_LEVEL_CROSSINGS),
            None => LevelLists::of_faces(
                &surface,
                &self.vertex_distance,
                params.spacing,
                k_max,
                MAX_LEVEL_CROSSINGS,
            ),
        }
        .map_err(|count| GeodesicError::PassesTooLarge {
            count,
            what: "crossings of faces or voxels by the levels",
            limit: MAX_LEVEL_CROSSINGS,
        })?;
        // Faces met on the walks of a level (the mesh method only).
        let walked = if self.voxels.is_none() {
            mesh.triangle_count()
        } else {
            0
        };
        let mut visited = vec![false; walked];
        let mut out = Vec::new();
        let mut points: u64 = 0;
        for k in 1..=k_max {
            let d = k as Real * params.spacing;
            let lines = match &self.voxels {
                Some(field) => order_level(field, d, k, lists.of(k)),
                None => joined_at_ends(
                    contour_from(
                        &surface,
                        &self.vertex_distance,
                        d,
                        lists.of(k),
                        &mut visited,
                    ),
                    JOIN_TOLERANCE * surface.mean_edge,
                ),
            };
            for mut line in lines {
                // Counted before resampling, so a spacing far too fine is refused before the
                // points are made.
                points += line.resampled_count(point_spacing) as u64;
                if points > MAX_PATH_POINTS {
                    return Err(GeodesicError::PassesTooLarge {
                        count: points,
                        what: "points",
                        limit: MAX_PATH_POINTS,
                    });
                }
                line.level = k;
                out.push(line.resampled(point_spacing));
            }
        }
        Ok(out)
    }

    /// The iso-lines ordered and linked into a tool path (tool axis = −surface normal).
    pub fn tool_path(
        &self,
        mesh: &TriMesh,
        adjacency: &FaceAdjacency,
        params: &PathParams,
    ) -> Result<ToolPath, GeodesicError> {
        let lines = self.iso_lines(mesh, adjacency, params)?;
        let ordered = link(lines, params.order);
        // Consecutive points closer than this are one: the tool must not turn on the spot with
        // the process on (a controller runs that as a dwell).
        let tol = SAME_POSITION_RATIO * params.spacing;
        let mut poses = Vec::new();
        let mut pass = 0;
        for line in &ordered {
            let tangents = line.tangents();
            let mut idx: Vec<usize> = (0..line.points.len()).collect();
            if line.closed {
                idx.push(0);
            }
            let mut trace: Vec<usize> = Vec::with_capacity(idx.len());
            for i in idx {
                let moves = trace
                    .last()
                    .is_none_or(|&k| (line.points[i] - line.points[k]).norm() > tol);
                if moves {
                    trace.push(i);
                }
            }
            if trace.len() < 2 {
                // A line shorter than the tolerance: nothing to trace, only a dwell.
                continue;
            }
            for (j, &i) in trace.iter().enumerate() {
                // The link arrives at the pass's first point with the process off; the pass
                // starts from there.
                let kind = if j == 0 && pass > 0 {
                    PoseKind::Link
                } else {
                    PoseKind::Pass
                };
                poses.push(pose(line, &tangents, i, kind, pass));
            }
            pass += 1;
        }
        let path = ToolPath {
            poses,
            speed: params.speed,
            link_speed: params.link_speed,
            speeds: Vec::new(),
            notes: vec![format!(
                "geodesic passes: {} method, spacing {}, {} passes",
                self.method.name(),
                params.spacing,
                pass
            )],
        };
        path.validate().map_err(|e| {
            GeodesicError::BadSource(format!("the generated tool path is invalid: {e}"))
        })?;
        Ok(path)
    }
}

fn pose(line: &IsoLine, tangents: &[Vector3], i: usize, kind: PoseKind, pass: usize) -> Pose {
    Pose {
        position: line.points[i],
        axis: -line.normals[i],
        travel: tangents[i],
        kind,
        pass: pass as u32,
    }
}

/// Vector area of a closed line (its turning sense about its mean axis).
fn vector_area(line: &IsoLine) -> Vector3 {
    let n = line.points.len();
    (0..n)
        .map(|i| {
            line.points[i]
                .coords
                .cross(&line.points[(i + 1) % n].coords)
        })
        .sum()
}

/// Orders lines level by level, nearest first, and orients them (see the file header).
pub(crate) fn link(mut lines: Vec<IsoLine>, order: LinkOrder) -> Vec<IsoLine> {
    let mut out: Vec<IsoLine> = Vec::with_capacity(lines.len());
    let mut first_open: Option<Vector3> = None;
    let mut first_loop: Option<Vector3> = None;
    let mut loops_done = 0usize;
    lines.sort_by_key(|l| l.level);
    let mut rest = lines.into_iter().peekable();
    while let Some(first) = rest.next() {
        // Each line with its bounding box: a line whose box lies farther from the tool than
        // the nearest line so far cannot be nearer (nor as near), so its points are not
        // looked at. Without this, a level of L lines cost L times all its points (a book
        // of 2,000 pages, 1,000 lines a level: 4 s).
        let with_box = |l: IsoLine| {
            let (lo, hi) = l.points.iter().fold(
                (Vector3::repeat(Real::MAX), Vector3::repeat(Real::MIN)),
                |(lo, hi), p| (lo.inf(&p.coords), hi.sup(&p.coords)),
            );
            (l, lo, hi)
        };
        let level_of = first.level;
        let mut level = vec![with_box(first)];
        while rest.peek().is_some_and(|l| l.level == level_of) {
            level.extend(rest.next().map(with_box));
        }
        while !level.is_empty() {
            let here = out.last().and_then(|l| l.points.last().copied());
            // The first of the nearest lines in the level's order, as `min_by` finds it: the
            // box's distance is never above a point's (subtraction, squares, sums and the
            // root round monotonically), so only lines that cannot tie are skipped.
            let pick = match here {
                None => 0,
                Some(h) => {
                    let mut best = (Real::INFINITY, 0);
                    for (i, (l, lo, hi)) in level.iter().enumerate() {
                        let gap = (lo - h.coords).sup(&(h.coords - hi)).sup(&Vector3::zeros());
                        if gap.norm() > best.0 {
                            continue;
                        }
                        let d = l
                            .points
                            .iter()
                            .map(|p| (p - h).norm())
                            .fold(Real::MAX, Real::min);
                        if d < best.0 {
                            best = (d, i);
                        }
                    }
                    best.1
                }
            };
            let (mut line, _, _) = level.swap_remove(pick);
            if line.closed {
                let area = vector_area(&line);
                let want = match (first_loop, order) {
                    (None, _) => area,
                    (Some(f), LinkOrder::OneDirection) => f,
                    (Some(f), LinkOrder::ZigZag) => {
                        if loops_done % 2 == 0 {
                            f
                        } else {
                            -f
                        }
                    }
                };
                if area.dot(&want) < 0.0 {
                    line.points.reverse();
                    line.normals.reverse();
                }
                first_loop.get_or_insert(vector_area(&line));
                loops_done += 1;
                if let Some(h) = here {
                    let s = (0..line.points.len())
                        .min_by(|&a, &b| {
                            (line.points[a] - h)
                                .norm()
                                .total_cmp(&(line.points[b] - h).norm())
                        })
                        .unwrap_or(0);
                    line.points.rotate_left(s);
                    line.normals.rotate_left(s);
                }
            } else {
                let (a, b) = (line.points[0], line.points[line.points.len() - 1]);
                let flip = match (order, first_open, here) {
                    (LinkOrder::OneDirection, Some(f), _) => (b - a).dot(&f) < 0.0,
                    (_, _, Some(h)) => (b - h).norm() < (a - h).norm(),
                    _ => false,
                };
                if flip {
                    line.points.reverse();
                    line.normals.reverse();
                }
                let n = line.points.len();
                first_open.get_or_insert(line.points[n - 1] - line.points[0]);
            }
            out.push(line);
        }
    }
    out
}
