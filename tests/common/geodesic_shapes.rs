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

/// Spherical cap of radius `r` and half-angle `theta0` around +z, in `rings` rings of
/// 6·i vertices (about 6·rings² triangles of even size): ring i at polar angle θ0·i/rings.
pub fn cap(rings: usize, r: Real, theta0: Real) -> Shape {
    let mut pos = vec![Point3::new(0.0, 0.0, r)];
    let mut start = vec![0usize];
    for i in 1..=rings {
        start.push(pos.len());
        let th = theta0 * i as Real / rings as Real;
        for k in 0..6 * i {
            let ph = 2.0 * PI * k as Real / (6 * i) as Real;
            let s = r * libm::sin(th);
            pos.push(Point3::new(
                s * libm::cos(ph),
                s * libm::sin(ph),
                r * libm::cos(th),
            ));
        }
    }
    let mut tri = Vec::new();
    for i in 1..=rings {
        // Merge ring i − 1 (m vertices) and ring i (n vertices) by azimuth.
        let (m, n) = (if i == 1 { 1 } else { 6 * (i - 1) }, 6 * i);
        let (a0, b0) = (start[i - 1], start[i]);
        let (mut a, mut b) = (if i == 1 { 1 } else { 0 }, 0usize);
        while a < m || b < n {
            let fa = (a as Real + 0.5) / m as Real;
            let fb = (b as Real + 0.5) / n as Real;
            let ia = (a0 + a % m) as u32;
            let ib = (b0 + b % n) as u32;
            if b < n && (a >= m || fb <= fa) {
                tri.push([ia, ib, (b0 + (b + 1) % n) as u32]);
                b += 1;
            } else {
                tri.push([ia, ib, (a0 + (a + 1) % m) as u32]);
                a += 1;
            }
        }
    }
    shape(pos, tri)
}

/// Sphere of radius `r` from a cube of `n × n` cells a face (12·n² triangles), projected
/// equi-angularly; `n` even puts a vertex at (0, 0, −r).
pub fn cube_sphere(n: usize, r: Real) -> Shape {
    let mut index = std::collections::HashMap::new();
    let mut pos = Vec::new();
    let mut id = |c: [i64; 3]| -> u32 {
        *index.entry(c).or_insert_with(|| {
            let t = |x: i64| libm::tan(PI / 4.0 * (2.0 * x as Real / n as Real - 1.0));
            let p = Point3::new(t(c[0]), t(c[1]), t(c[2]));
            pos.push(Point3::from(p.coords.normalize() * r));
            (pos.len() - 1) as u32
        })
    };
    let n64 = n as i64;
    let mut tri = Vec::new();
    // Each face: axis `ax` fixed at 0 or n; (u, v) span the other two, wound outwards.
    for ax in 0..3 {
        for side in [0, n64] {
            let (ua, va) = ((ax + 1) % 3, (ax + 2) % 3);
            for i in 0..n64 {
                for j in 0..n64 {
                    let at = |di: i64, dj: i64| {
                        let mut c = [0i64; 3];
                        c[ax] = side;
                        c[ua] = i + di;
                        c[va] = j + dj;
                        c
                    };
                    let q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)].map(&mut id);
                    let (t0, t1) = if (i + j) % 2 == 0 {
                        ([q[0], q[1], q[2]], [q[0], q[2], q[3]])
                    } else {
                        ([q[0], q[1], q[3]], [q[1], q[2], q[3]])
                    };
                    let flip = |t: [u32; 3]| if side == 0 { [t[0], t[2], t[1]] } else { t };
                    tri.push(flip(t0));
                    tri.push(flip(t1));
                }
            }
        }
    }
    shape(pos, tri)
}

/// A plate of `w` × `l` unit squares (diagonals alternating) without the squares whose
/// centres lie within `radius` of `centre` (a hole with a jagged rim), and the id of the
/// vertex at `(i, j)`.
pub fn holed_plate(
    w: u32,
    l: u32,
    centre: (Real, Real),
    radius: Real,
) -> (Shape, impl Fn(u32, u32) -> u32) {
    holed_surface(w, l, centre, radius, |_, _| 0.0)
}

/// [`holed_plate`] with its vertex `(x, y)` lifted to `height(x, y)`.
pub fn holed_surface(
    w: u32,
    l: u32,
    centre: (Real, Real),
    radius: Real,
    height: impl Fn(Real, Real) -> Real,
) -> (Shape, impl Fn(u32, u32) -> u32) {
    let at = move |i: u32, j: u32| j * (w + 1) + i;
    let positions = (0..=l)
        .flat_map(|j| (0..=w).map(move |i| (i as Real, j as Real)))
        .map(|(x, y)| Point3::new(x, y, height(x, y)))
        .collect();
    let mut triangles = Vec::new();
    for j in 0..l {
        for i in 0..w {
            let c = Point3::new(i as Real + 0.5, j as Real + 0.5, 0.0);
            if (c - Point3::new(centre.0, centre.1, 0.0)).norm() < radius {
                continue;
            }
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if (i + j) % 2 == 0 {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    (shape(positions, triangles), at)
}
