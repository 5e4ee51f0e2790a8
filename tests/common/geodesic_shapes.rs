//! Generated meshes with known geodesic answers, shared by the geodesic test files: the
//! paper's test shapes (cylinder R 50 × 120 mm, two perpendicular plates, a 60 × 50 × 40 mm
//! height field) and a sphere.
#![allow(dead_code)]

use skinpath::math::{Point3, Real};
use skinpath::mesh::{FaceAdjacency, TriMesh};
use std::f64::consts::PI;

pub const R: Real = 50.0;
pub const LEN: Real = 120.0;

pub struct Shape {
    pub mesh: TriMesh,
    pub adjacency: FaceAdjacency,
}

pub fn shape(positions: Vec<Point3>, triangles: Vec<[u32; 3]>) -> Shape {
    let mesh = TriMesh::new(positions, triangles).unwrap();
    let adjacency = FaceAdjacency::new(&mesh);
    Shape { mesh, adjacency }
}

/// Grid of `nu × nv` cells from `f(u, v)`, u, v ∈ [0, 1], diagonals alternating; `wrap_u`
/// joins the last column to the first.
pub fn grid(
    nu: usize,
    nv: usize,
    wrap_u: bool,
    f: impl Fn(Real, Real) -> Point3,
) -> (Vec<Point3>, Vec<[u32; 3]>) {
    let cols = if wrap_u { nu } else { nu + 1 };
    let mut pos = Vec::new();
    for j in 0..=nv {
        for i in 0..cols {
            pos.push(f(i as Real / nu as Real, j as Real / nv as Real));
        }
    }
    let id = |i: usize, j: usize| (j * cols + i % cols) as u32;
    let mut tri = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                tri.push([a, b, c]);
                tri.push([a, c, d]);
            } else {
                tri.push([a, b, d]);
                tri.push([b, c, d]);
            }
        }
    }
    (pos, tri)
}

/// Open cylinder of radius R and length LEN around z, normals outward.
pub fn cylinder(around: usize, along: usize) -> Shape {
    let (p, t) = grid(around, along, true, |u, v| {
        let a = 2.0 * PI * u;
        Point3::new(R * libm::cos(a), R * libm::sin(a), LEN * v)
    });
    shape(p, t)
}

/// Two 150 × 50 plates: A in z = 0 (y ∈ [0, 50]), B in y = 0 (z ∈ [0, 50]), meeting along x.
pub fn plates(cell: Real) -> Shape {
    let (nu, nv) = ((150.0 / cell) as usize, (100.0 / cell) as usize);
    let (p, t) = grid(nu, nv, false, |u, v| {
        let s = 100.0 * v; // unfolded coordinate: 0..50 on A (from its outer edge), 50..100 on B
        if s <= 50.0 {
            Point3::new(150.0 * u, 50.0 - s, 0.0)
        } else {
            Point3::new(150.0 * u, 0.0, s - 50.0)
        }
    });
    shape(p, t)
}

/// UV sphere of radius R with an equator row of vertices.
pub fn sphere(around: usize, rows: usize) -> Shape {
    let mut pos = vec![Point3::new(0.0, 0.0, -R)];
    for j in 1..rows {
        let lat = -PI / 2.0 + PI * j as Real / rows as Real;
        for i in 0..around {
            let a = 2.0 * PI * i as Real / around as Real;
            let (cl, sl) = (libm::cos(lat), libm::sin(lat));
            pos.push(Point3::new(
                R * cl * libm::cos(a),
                R * cl * libm::sin(a),
                R * sl,
            ));
        }
    }
    pos.push(Point3::new(0.0, 0.0, R));
    let top = (pos.len() - 1) as u32;
    let id = |i: usize, j: usize| (1 + (j - 1) * around + i % around) as u32;
    let mut tri = Vec::new();
    for i in 0..around {
        tri.push([0, id(i + 1, 1), id(i, 1)]);
        tri.push([top, id(i, rows - 1), id(i + 1, rows - 1)]);
    }
    for j in 1..rows - 1 {
        for i in 0..around {
            tri.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tri.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    shape(pos, tri)
}

/// Height field 60 × 50 with heights 0..40 (the paper's model 3 size).
pub fn height(x: Real, y: Real) -> Real {
    40.0 * 0.5 * (1.0 - libm::cos(PI * x / 60.0)) * (0.6 + 0.4 * libm::sin(PI * y / 50.0))
}
pub fn height_field(cell: Real) -> Shape {
    let (nu, nv) = ((60.0 / cell) as usize, (50.0 / cell) as usize);
    let (p, t) = grid(nu, nv, false, |u, v| {
        let (x, y) = (60.0 * u, 50.0 * v);
        Point3::new(x, y, height(x, y))
    });
    shape(p, t)
}

/// `n` points of the circle of radius R at height `z`, turned by `phase` of a step.
pub fn ring(z: Real, n: usize, phase: Real) -> Vec<Point3> {
    (0..n)
        .map(|i| {
            let a = 2.0 * PI * (i as Real + phase) / n as Real;
            Point3::new(R * libm::cos(a), R * libm::sin(a), z)
        })
        .collect()
}

/// Distances are ≥ 0 and 1-Lipschitz along every edge.
pub fn check_field(s: &Shape, d: &[Real]) {
    for t in s.mesh.triangles() {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            assert!(d[a] >= 0.0 && d[a].is_finite(), "vertex {a}: {}", d[a]);
            let len = (s.mesh.positions()[a] - s.mesh.positions()[b]).norm();
            assert!(
                (d[a] - d[b]).abs() <= len * (1.0 + 1e-9) + 1e-9,
                "edge {a}-{b} not 1-Lipschitz"
            );
        }
    }
}
