//! The paper's hole-correction example as data: a 60° cylindrical panel sector, four reference
//! holes at its corners, 16 holes between them, and a deformed "actual" panel.
//!
//! Source: Bi et al. 2015 (seed 004) §4.2 (60° cylindrical sector, 4 reference holes, 16 holes
//!         between them; max/min errors 5.586/3.302 mm uncorrected, 2.442/0.175 mm bilinear,
//!         0.628/0.005 mm Coons).
//! Input:  none (the shape is fixed below).
//! Output: [`PaperExample`]: the actual panel as a mesh, the references A, B, C, D (nominal and
//!         actual positions, nominal and actual normals), the 16 nominal holes and where they
//!         truly are on the actual panel.
//! Cost:   O(panel triangles) (about 9 500).
//! Deviations:
//! - The paper's table of coordinates is not in its text: radius 1000 mm (our choice),
//!   θ ∈ [−30°, 30°] across the flight direction, z ∈ [0, 400] mm along it; the holes sit at
//!   fifths of θ and z between the corners.
//! - The actual panel ([`paper_deformed`] with no taper): 3 mm larger radius, stretched by
//!   0.2 % across and 0.1 % along, twisted by 1 mrad over the length, then a small rigid move;
//!   so each corner moves differently and the errors are of the paper's size.
//! - Normals of the references are central differences of the analytic surfaces.

use super::ReferenceHole;
use crate::math::{Point3, Real, Vector3};
use crate::mesh::TriMesh;

/// Radius of the nominal cylinder, mm.
pub const PAPER_RADIUS: Real = 1000.0;
/// Half the sector angle (30°), rad.
pub const PAPER_HALF_SECTOR: Real = std::f64::consts::PI / 6.0;
/// Length of the region along the flight direction (the cylinder axis z), mm.
pub const PAPER_LENGTH: Real = 400.0;
/// Step of the central differences giving the surfaces' normals (in θ rad and z mm).
const NORMAL_STEP: Real = 1e-5;
/// Facets of the panel mesh across (0.2° each: sag 1.5e-3 mm, not aligned with the holes).
const PANEL_CELLS_ACROSS: usize = 397;
/// Facets of the panel mesh along the flight direction (50 mm each).
const PANEL_CELLS_ALONG: usize = 12;
/// Half angle of the panel mesh, rad (40°: the panel reaches beyond the region).
const PANEL_HALF_ANGLE: Real = 40.0 * std::f64::consts::PI / 180.0;
/// Start and length of the panel mesh along z, mm.
const PANEL_Z: (Real, Real) = (-100.0, 600.0);

/// Everything the example needs (see the module header).
#[derive(Clone, Debug)]
pub struct PaperExample {
    /// The actual panel (what a scan of the part would give), mm.
    pub panel: TriMesh,
    /// Reference holes A, B, C, D with nominal and actual positions and normals.
    pub references: [ReferenceHole; 4],
    /// Identifiers of the holes to drill, `H01` … `H16`.
    pub ids: Vec<String>,
    /// Nominal (CAD) positions of the holes to drill.
    pub holes: Vec<Point3>,
    /// Where the holes truly are on the actual panel.
    pub truth: Vec<Point3>,
}

/// The nominal cylinder: surface point of parameters (θ, z).
pub fn paper_nominal_surface(theta: Real, z: Real) -> Point3 {
    Point3::new(
        PAPER_RADIUS * libm::sin(theta),
        PAPER_RADIUS * libm::cos(theta),
        z,
    )
}

/// Rotation of `v` by `angle` about the unit `axis` (Rodrigues).
fn rotate(v: &Vector3, axis: &Vector3, angle: Real) -> Vector3 {
    let (s, c) = (libm::sin(angle), libm::cos(angle));
    v * c + axis.cross(v) * s + axis * axis.dot(v) * (1.0 - c)
}

/// The actual panel: the nominal one bent to a 3 mm larger radius, growing by `taper` mm more
/// over the length (a cone when `taper ≠ 0`), stretched by 0.2 % across and 0.1 % along,
/// twisted by 1 mrad over the length, then rotated by 0.1° and shifted by (0.5, 1, −0.8) mm.
pub fn paper_deformed(theta: Real, z: Real, taper: Real) -> Point3 {
    let r = PAPER_RADIUS + 3.0 + taper * z / PAPER_LENGTH;
    let a = theta * 1.002 + 1e-3 * z / PAPER_LENGTH;
    let p = Point3::new(r * libm::sin(a), r * libm::cos(a), 1.001 * z);
    let axis = Vector3::new(1.0, 0.0, 0.2).normalize();
    Point3::from(rotate(&p.coords, &axis, 0.1_f64.to_radians())) + Vector3::new(0.5, 1.0, -0.8)
}

/// Surface parameters (θ, z) of the reference holes A, B, C, D.
pub fn paper_corner_params() -> [(Real, Real); 4] {
    [
        (-PAPER_HALF_SECTOR, 0.0),
        (PAPER_HALF_SECTOR, 0.0),
        (PAPER_HALF_SECTOR, PAPER_LENGTH),
        (-PAPER_HALF_SECTOR, PAPER_LENGTH),
    ]
}

/// Surface parameters (θ, z) of the 16 holes: 4 × 4 at fifths between the corners, row by row.
pub fn paper_hole_params() -> Vec<(Real, Real)> {
    let mut v = Vec::with_capacity(16);
    for j in 1..=4 {
        for i in 1..=4 {
            let (s, t) = (i as Real / 5.0, j as Real / 5.0);
            v.push((
                -PAPER_HALF_SECTOR + 2.0 * PAPER_HALF_SECTOR * s,
                PAPER_LENGTH * t,
            ));
        }
    }
    v
}

/// Outward unit normal of `surface` at (θ, z) by central differences (pointing away from the
/// cylinder axis).
fn normal_of(surface: &dyn Fn(Real, Real) -> Point3, theta: Real, z: Real) -> Vector3 {
    let h = NORMAL_STEP;
    let st = (surface(theta + h, z) - surface(theta - h, z)) / (2.0 * h);
    let sz = (surface(theta, z + h) - surface(theta, z - h)) / (2.0 * h);
    let n = sz.cross(&st).normalize();
    let p = surface(theta, z).coords;
    if n.dot(&Vector3::new(p.x, p.y, 0.0)) < 0.0 {
        -n
    } else {
        n
    }
}

/// A mesh of `surface` over θ ∈ [−40°, 40°], z ∈ [−100, 500] mm, 0.2° × 50 mm cells of two
/// triangles, wound so that the normals point away from the cylinder axis.
pub fn paper_panel_mesh(surface: &dyn Fn(Real, Real) -> Point3) -> TriMesh {
    let (nu, nv) = (PANEL_CELLS_ACROSS, PANEL_CELLS_ALONG);
    let mut positions = Vec::with_capacity((nu + 1) * (nv + 1));
    for j in 0..=nv {
        for i in 0..=nu {
            let theta = -PANEL_HALF_ANGLE + 2.0 * PANEL_HALF_ANGLE * i as Real / nu as Real;
            let z = PANEL_Z.0 + PANEL_Z.1 * j as Real / nv as Real;
            positions.push(surface(theta, z));
        }
    }
    let id = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    let mut triangles = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            triangles.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
            triangles.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
        }
    }
    // Cannot fail: every index is below the vertex count and no cell is degenerate (the
    // surfaces above are regular, with cells of 3.5 × 50 mm).
    TriMesh::new(positions, triangles).expect("a regular grid over a regular surface is valid")
}

/// The paper's example on the bent panel (see the module header).
pub fn paper_example() -> PaperExample {
    let actual = |t: Real, z: Real| paper_deformed(t, z, 0.0);
    let references = paper_corner_params().map(|(t, z)| ReferenceHole {
        nominal: paper_nominal_surface(t, z),
        actual: actual(t, z),
        normal: normal_of(&actual, t, z),
        nominal_normal: Some(normal_of(&paper_nominal_surface, t, z)),
    });
    let params = paper_hole_params();
    PaperExample {
        panel: paper_panel_mesh(&actual),
        references,
        ids: (1..=params.len()).map(|i| format!("H{i:02}")).collect(),
        holes: params
            .iter()
            .map(|&(t, z)| paper_nominal_surface(t, z))
            .collect(),
        truth: params.iter().map(|&(t, z)| actual(t, z)).collect(),
    }
}
