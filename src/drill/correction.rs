//! Hole-position correction: the error field between the nominal and the actual Coons patch
//! over four reference holes, applied to every hole to drill (or the bilinear baseline).
//!
//! Source: Bi et al. 2015 (seed 004) §3.2 (reference errors `ΔP_i = actual − nominal`) and
//!         §3.3.5 (`ΔQ(u, w) = S_actual(u, w) − S_nominal(u, w)`, hole parameters `(u*, w*)`,
//!         corrected = nominal + `ΔQ(u*, w*)`); the bilinear baseline interpolates the four
//!         `ΔP_i` (Zhu & Qu 2013, the paper's reference \[2\]).
//! Input:  four [`ReferenceHole`]s A, B, C, D (in order; A→B across the flight direction),
//!         the nominal holes, and optionally the panel as a [`MeshIndex`].
//! Output: [`Correction`]: corrected positions, unit surface normals (pointing out of the
//!         part, towards the tool; the drilling axis is their opposite), travel directions,
//!         `(u*, w*)` and whether each hole lies outside the reference quadrilateral.
//! Cost:   O(1) per hole (a fixed grid of patch evaluations and ≤ 50 Gauss–Newton steps),
//!         plus one closest-point query per hole (O(log n)) when a mesh is given.
//! Deviations:
//! - `(u*, w*)` is the closest point of the nominal patch to the nominal hole (the paper
//!   "projects the hole onto the u, w directions" without saying how). Method: the best
//!   point of a 31 × 31 grid over `[−1, 2]²`, then Gauss–Newton on the 2 × 2 normal equations
//!   `(JᵀJ)·δ = −Jᵀ(S − P)` with backtracking (step halved until the distance decreases, at
//!   most 40 halvings), at most 50 steps: the distance never increases, so it always ends,
//!   at a stationary point near the grid's best (no paper; chosen for robustness).
//! - The nominal patch is built from nominal normals (`nominal_normal`, or the panel mesh's
//!   normal at the nominal hole, or the measured normal), the actual patch from the measured
//!   ones; with one normal for both a rigid move of the panel is not reproduced.
//! - A hole with `u` or `w` outside `[0, 1]` (beyond [`PARAM_OUTSIDE_TOLERANCE`]) is an error
//!   unless extrapolation is requested; extrapolated holes are flagged.
//! - With a panel mesh the corrected point is moved to the closest point of the mesh and the
//!   normal is the mesh's smooth normal there; the mesh should then describe the actual panel
//!   (or the deviation along the normal must not matter, as with a pressure foot).

use super::{CoonsPatch, DrillError};
use crate::math::{any_perpendicular, Point3, Real, Vector3};
use crate::mesh::MeshIndex;

/// A hole is outside the reference quadrilateral when `u` or `w` is beyond `[0, 1]` by more
/// than this.
pub const PARAM_OUTSIDE_TOLERANCE: Real = 1e-6;
/// Two reference holes closer than this fraction of the largest distance between them count
/// as coincident; three count as collinear when their triangle's height is below this fraction
/// of its longest side.
pub const REFERENCE_DEGENERACY_RATIO: Real = 1e-6;
/// Grid cells per unit of `u` and `w` for the start of the parameter search over `[−1, 2]²`.
const GRID_CELLS_PER_UNIT: usize = 10;
/// Gauss–Newton steps at most.
const MAX_NEWTON_STEPS: usize = 50;
/// Step halvings at most per Gauss–Newton step.
const MAX_HALVINGS: usize = 40;
/// Gauss–Newton stops when its parameter step is below this.
const PARAM_STEP_TOLERANCE: Real = 1e-14;

/// One reference hole: where it should be, where it was measured, and the surface normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceHole {
    /// Nominal (CAD) position.
    pub nominal: Point3,
    /// Measured position, same frame.
    pub actual: Point3,
    /// Measured surface normal (e.g. [`super::normal_from_lasers`]), any length > 0.
    pub normal: Vector3,
    /// Nominal (CAD) normal; `None`: the panel mesh's normal at `nominal` if a mesh is given,
    /// else `normal`.
    pub nominal_normal: Option<Vector3>,
}

/// How the error of a hole is interpolated from the four reference errors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// Difference of the actual and nominal Coons patches (the paper's method).
    #[default]
    Coons,
    /// Bilinear interpolation of the four reference errors at the same `(u*, w*)`.
    Bilinear,
}

/// What [`correct_holes`] needs.
#[derive(Clone, Debug, PartialEq)]
pub struct CorrectionParams {
    /// Reference holes A, B, C, D in order around the region; A→B across the flight
    /// direction (Ferguson curves), A→D along it (straight lines).
    pub references: [ReferenceHole; 4],
    /// Nominal positions of the holes to drill.
    pub holes: Vec<Point3>,
    /// Interpolation method.
    pub method: Method,
    /// Tangent length in chords, in `(0, 3]`; `None`: the arc-matching length.
    pub tangent_scale: Option<Real>,
    /// Correct holes outside the reference quadrilateral too (they are flagged either way).
    pub extrapolate: bool,
}

/// Corrected holes, indexed like [`CorrectionParams::holes`].
#[derive(Clone, Debug, PartialEq)]
pub struct Correction {
    /// Corrected positions.
    pub corrected: Vec<Point3>,
    /// Unit surface normals there, pointing out of the part (the drilling axis is `−normal`).
    pub normals: Vec<Vector3>,
    /// Unit directions perpendicular to the normal, along `∂S/∂u` (across the flight
    /// direction): the tool frame's X for the poses.
    pub travel: Vec<Vector3>,
    /// Patch parameter across the flight direction (A→B).
    pub u: Vec<Real>,
    /// Patch parameter along the flight direction (A→D).
    pub w: Vec<Real>,
    /// Whether the hole lies outside the reference quadrilateral (then extrapolated).
    pub outside: Vec<bool>,
}

/// The nominal and actual patches over the references, ready to correct holes.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorSurface {
    /// Patch through the nominal reference positions with the nominal normals.
    pub nominal: CoonsPatch,
    /// Patch through the measured reference positions with the measured normals.
    pub actual: CoonsPatch,
    /// Reference errors `ΔP_i = actual − nominal`, A, B, C, D.
    pub reference_errors: [Vector3; 4],
    /// Mean of the measured unit normals (orients every normal returned).
    pub outward: Vector3,
}

const NAMES: [&str; 4] = ["A", "B", "C", "D"];

impl ErrorSurface {
    /// Checks the references and builds both patches; `panel` supplies the default nominal
    /// normals.
    pub fn new(
        references: &[ReferenceHole; 4],
        tangent_scale: Option<Real>,
        panel: Option<&MeshIndex>,
    ) -> Result<Self, DrillError> {
        for (r, name) in references.iter().zip(NAMES) {
            let values = r.nominal.coords.iter().chain(r.actual.coords.iter());
            let mut values = values
                .chain(r.normal.iter())
                .chain(r.nominal_normal.iter().flatten());
            if let Some(&value) = values.find(|v| !v.is_finite()) {
                return Err(DrillError::NonFinite {
                    name: format!("a coordinate of reference {name}"),
                    value,
                });
            }
        }
        check_quadrilateral(&references.map(|r| r.nominal), "nominal")?;
        check_quadrilateral(&references.map(|r| r.actual), "actual")?;
        let normals = unit_normals(references.map(|r| r.normal), "normal")?;
        let outward = normals.iter().sum::<Vector3>().normalize();
        let mut nominal_normals = [Vector3::zeros(); 4];
        for (i, r) in references.iter().enumerate() {
            nominal_normals[i] = match (r.nominal_normal, panel) {
                (Some(n), _) => n,
                (None, Some(index)) => {
                    let cp = index.closest_point(&r.nominal).ok_or_else(|| {
                        DrillError::NoClosestPoint(format!("reference {}", NAMES[i]))
                    })?;
                    // Mesh winding is arbitrary: take the side of the measured normal.
                    cp.normal * cp.normal.dot(&normals[i]).signum()
                }
                (None, None) => normals[i],
            };
        }
        let nominal_normals = unit_normals(nominal_normals, "nominal normal")?;
        Ok(ErrorSurface {
            nominal: CoonsPatch::new(
                references.map(|r| r.nominal),
                nominal_normals,
                tangent_scale,
            )?,
            actual: CoonsPatch::new(references.map(|r| r.actual), normals, tangent_scale)?,
            reference_errors: references.map(|r| r.actual - r.nominal),
            outward,
        })
    }

    /// Interpolated error at `(u, w)`.
    pub fn error(&self, method: Method, u: Real, w: Real) -> Vector3 {
        match method {
            Method::Coons => self.actual.point(u, w) - self.nominal.point(u, w),
            Method::Bilinear => {
                let [a, b, c, d] = self.reference_errors;
                (a * (1.0 - u) + b * u) * (1.0 - w) + (d * (1.0 - u) + c * u) * w
            }
        }
    }
}

/// Parameters `(u, w)` of the point of `patch` closest to `p` (method in the module header).
pub fn closest_parameters(patch: &CoonsPatch, p: &Point3) -> (Real, Real) {
    let f = |u: Real, w: Real| (patch.point(u, w) - p).norm_squared();
    let cells = 3 * GRID_CELLS_PER_UNIT;
    let mut best = (Real::INFINITY, 0.0, 0.0);
    for i in 0..=cells {
        for j in 0..=cells {
            let (u, w) = (
                -1.0 + 3.0 * i as Real / cells as Real,
                -1.0 + 3.0 * j as Real / cells as Real,
            );
            let d = f(u, w);
            if d < best.0 {
                best = (d, u, w);
            }
        }
    }
    let (mut value, mut u, mut w) = best;
    for _ in 0..MAX_NEWTON_STEPS {
        let r = patch.point(u, w) - p;
        let (su, sw) = patch.partials(u, w);
        let (a, b, d) = (su.dot(&su), su.dot(&sw), sw.dot(&sw));
        let (gu, gw) = (su.dot(&r), sw.dot(&r));
        let det = a * d - b * b;
        let (mut du, mut dw) = if det > 0.0 {
            ((-d * gu + b * gw) / det, (b * gu - a * gw) / det)
        } else {
            // Singular normal equations: a steepest-descent step instead.
            let scale = 1.0 / (a + d).max(Real::MIN_POSITIVE);
            (-gu * scale, -gw * scale)
        };
        let mut accepted = false;
        for _ in 0..MAX_HALVINGS {
            let candidate = f(u + du, w + dw);
            if candidate < value {
                (value, u, w) = (candidate, u + du, w + dw);
                accepted = true;
                break;
            }
            du *= 0.5;
            dw *= 0.5;
        }
        if !accepted || du.abs().max(dw.abs()) < PARAM_STEP_TOLERANCE {
            break;
        }
    }
    (u, w)
}

/// Corrects every hole of `params` (see the module header); `panel` is the panel mesh, if
/// any, for default nominal normals, projection and drilling axes.
pub fn correct_holes(
    params: &CorrectionParams,
    panel: Option<&MeshIndex>,
) -> Result<Correction, DrillError> {
    let surface = ErrorSurface::new(&params.references, params.tangent_scale, panel)?;
    let n = params.holes.len();
    let mut out = Correction {
        corrected: Vec::with_capacity(n),
        normals: Vec::with_capacity(n),
        travel: Vec::with_capacity(n),
        u: Vec::with_capacity(n),
        w: Vec::with_capacity(n),
        outside: Vec::with_capacity(n),
    };
    for (hole, p) in params.holes.iter().enumerate() {
        if let Some(&value) = p.coords.iter().find(|v| !v.is_finite()) {
            return Err(DrillError::NonFinite {
                name: format!("a coordinate of hole {hole}"),
                value,
            });
        }
        let (u, w) = closest_parameters(&surface.nominal, p);
        let inside =
            |t: Real| (-PARAM_OUTSIDE_TOLERANCE..=1.0 + PARAM_OUTSIDE_TOLERANCE).contains(&t);
        let outside = !(inside(u) && inside(w));
        if outside && !params.extrapolate {
            return Err(DrillError::Outside { hole, u, w });
        }
        let mut corrected = p + surface.error(params.method, u, w);
        let patch_normal = surface.actual.normal(u, w);
        let patch_normal = patch_normal * patch_normal.dot(&surface.outward).signum();
        let mut normal = patch_normal;
        if let Some(index) = panel {
            let cp = index
                .closest_point(&corrected)
                .ok_or_else(|| DrillError::NoClosestPoint(format!("hole {hole}")))?;
            corrected = cp.point;
            normal = cp.normal * cp.normal.dot(&patch_normal).signum();
        }
        let (su, _) = surface.actual.partials(u, w);
        let along = su - normal * normal.dot(&su);
        let travel = along
            .try_normalize(0.0)
            .unwrap_or_else(|| any_perpendicular(&normal));
        out.corrected.push(corrected);
        out.normals.push(normal);
        out.travel.push(travel);
        out.u.push(u);
        out.w.push(w);
        out.outside.push(outside);
    }
    Ok(out)
}

fn unit_normals(normals: [Vector3; 4], what: &str) -> Result<[Vector3; 4], DrillError> {
    let mut units = [Vector3::zeros(); 4];
    for i in 0..4 {
        units[i] = normals[i].try_normalize(0.0).ok_or_else(|| {
            DrillError::DegenerateReferences(format!(
                "the {what} of reference {} is zero",
                NAMES[i]
            ))
        })?;
    }
    let mean: Vector3 = units.iter().sum();
    for i in 0..4 {
        if units[i].dot(&mean) <= 0.0 {
            return Err(DrillError::DegenerateReferences(format!(
                "the {what} of reference {} points away from the others (normals must all \
                 point out of the part, or all into it)",
                NAMES[i]
            )));
        }
    }
    Ok(units)
}

fn check_quadrilateral(p: &[Point3; 4], which: &str) -> Result<(), DrillError> {
    let mut spread: Real = 0.0;
    for i in 0..4 {
        for j in i + 1..4 {
            spread = spread.max((p[j] - p[i]).norm());
        }
    }
    for i in 0..4 {
        for j in i + 1..4 {
            if (p[j] - p[i]).norm() <= REFERENCE_DEGENERACY_RATIO * spread {
                return Err(DrillError::DegenerateReferences(format!(
                    "the {which} positions of {} and {} coincide",
                    NAMES[i], NAMES[j]
                )));
            }
        }
    }
    for (i, j, k) in [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)] {
        let (a, b, c) = (p[i], p[j], p[k]);
        let longest = (b - a).norm().max((c - b).norm()).max((a - c).norm());
        let height = (b - a).cross(&(c - a)).norm() / longest;
        if height <= REFERENCE_DEGENERACY_RATIO * longest {
            return Err(DrillError::DegenerateReferences(format!(
                "the {which} positions of {}, {} and {} are collinear",
                NAMES[i], NAMES[j], NAMES[k]
            )));
        }
    }
    Ok(())
}
