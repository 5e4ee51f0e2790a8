//! Geodesically equidistant passes (seed 003) against analytic distances on the paper's test
//! shapes (cylinder, two perpendicular plates, a height field) and a sphere.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skinpath::geodesic::{
    boundary_loops, geodesic_distance, DistanceField, DistanceParams, GeodesicError,
    GeodesicSource, IsoLine, LinkOrder, Method, PathParams,
};
use skinpath::math::{Point3, Real};
use skinpath::mesh::{FaceAdjacency, TriMesh};
use skinpath::toolpath::PoseKind;
use std::f64::consts::PI;

const R: Real = 50.0;
const LEN: Real = 120.0;
/// Mesh-method error bound on the known-answer meshes (mm): well under the paper's 0.1 mm voxel.
const MESH_TOL: Real = 0.02;

struct Shape {
    mesh: TriMesh,
    adjacency: FaceAdjacency,
}

fn shape(positions: Vec<Point3>, triangles: Vec<[u32; 3]>) -> Shape {
    let mesh = TriMesh::new(positions, triangles).unwrap();
    let adjacency = FaceAdjacency::new(&mesh);
    Shape { mesh, adjacency }
}

/// Grid of `nu × nv` cells from `f(u, v)`, u, v ∈ [0, 1], diagonals alternating; `wrap_u`
/// joins the last column to the first.
fn grid(
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
fn cylinder(around: usize, along: usize) -> Shape {
    let (p, t) = grid(around, along, true, |u, v| {
        let a = 2.0 * PI * u;
        Point3::new(R * libm::cos(a), R * libm::sin(a), LEN * v)
    });
    shape(p, t)
}

/// Two 150 × 50 plates: A in z = 0 (y ∈ [0, 50]), B in y = 0 (z ∈ [0, 50]), meeting along x.
fn plates(cell: Real) -> Shape {
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
fn sphere(around: usize, rows: usize) -> Shape {
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
fn height(x: Real, y: Real) -> Real {
    40.0 * 0.5 * (1.0 - libm::cos(PI * x / 60.0)) * (0.6 + 0.4 * libm::sin(PI * y / 50.0))
}
fn height_field(cell: Real) -> Shape {
    let (nu, nv) = ((60.0 / cell) as usize, (50.0 / cell) as usize);
    let (p, t) = grid(nu, nv, false, |u, v| {
        let (x, y) = (60.0 * u, 50.0 * v);
        Point3::new(x, y, height(x, y))
    });
    shape(p, t)
}

fn polyline(points: Vec<Point3>, closed: bool) -> GeodesicSource {
    GeodesicSource::Polyline { points, closed }
}

fn ring(z: Real, n: usize, phase: Real) -> Vec<Point3> {
    (0..n)
        .map(|i| {
            let a = 2.0 * PI * (i as Real + phase) / n as Real;
            Point3::new(R * libm::cos(a), R * libm::sin(a), z)
        })
        .collect()
}

fn distance(s: &Shape, source: &GeodesicSource, params: &DistanceParams) -> DistanceField {
    geodesic_distance(&s.mesh, &s.adjacency, source, params, &mut |_, _| {}).unwrap()
}

fn lines(s: &Shape, field: &DistanceField, spacing: Real, max_level: Option<u32>) -> Vec<IsoLine> {
    let params = PathParams {
        spacing,
        max_level,
        ..PathParams::default()
    };
    field.iso_lines(&s.mesh, &s.adjacency, &params).unwrap()
}

/// Largest |analytic(p) − line distance| over every path point.
fn path_error(lines: &[IsoLine], analytic: impl Fn(&Point3) -> Real) -> Real {
    let mut worst: Real = 0.0;
    for l in lines {
        for p in &l.points {
            worst = worst.max((analytic(p) - l.distance).abs());
        }
    }
    worst
}

/// Distances are ≥ 0 and 1-Lipschitz along every edge.
fn check_field(s: &Shape, d: &[Real]) {
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

fn mesh_params() -> DistanceParams {
    DistanceParams::default()
}

fn voxel_params(size: Real) -> DistanceParams {
    DistanceParams {
        method: Method::Voxel,
        voxel_size: Some(size),
        ..DistanceParams::default()
    }
}

/// Arc distance on the cylinder from the generator at angle `a0`.
fn arc_from(p: &Point3, a0: Real) -> Real {
    let mut da = (libm::atan2(p.y, p.x) - a0).rem_euclid(2.0 * PI);
    if da > PI {
        da = 2.0 * PI - da;
    }
    R * da
}

#[test]
fn cylinder_ring_source_gives_circles_at_z_10k() {
    let s = cylinder(160, 60);
    let f = distance(&s, &polyline(ring(0.0, 64, 0.3), true), &mesh_params());
    check_field(&s, &f.vertex_distance);
    for (p, d) in s.mesh.positions().iter().zip(&f.vertex_distance) {
        assert!((d - p.z).abs() < MESH_TOL, "vertex at {p:?} has d = {d}");
    }
    let ls = lines(&s, &f, 10.0, Some(11));
    assert_eq!(ls.len(), 11);
    assert!(ls.iter().all(|l| l.closed));
    let err = path_error(&ls, |p| p.z);
    assert!(err < MESH_TOL, "path error {err}");
    for (k, l) in ls.iter().enumerate() {
        assert_eq!(l.level as usize, k + 1);
        assert!(
            (l.length() - 2.0 * PI * R).abs() < 0.2,
            "circle length {}",
            l.length()
        );
    }
}

#[test]
fn cylinder_generator_source_gives_lines_on_both_sides() {
    let s = cylinder(160, 60);
    // Between two vertex columns, so the source crosses faces.
    let a0 = 2.0 * PI * 0.37 / 160.0;
    let src = polyline(
        vec![
            Point3::new(R * libm::cos(a0), R * libm::sin(a0), 0.0),
            Point3::new(R * libm::cos(a0), R * libm::sin(a0), LEN),
        ],
        false,
    );
    let f = distance(&s, &src, &mesh_params());
    check_field(&s, &f.vertex_distance);
    let ls = lines(&s, &f, 10.0, None);
    assert_eq!(ls.len(), 30, "15 levels on both sides");
    assert!(ls.iter().all(|l| !l.closed));
    let err = path_error(&ls, |p| arc_from(p, a0));
    assert!(err < MESH_TOL, "path error {err}");
    for l in &ls {
        let z: Vec<Real> = l.points.iter().map(|p| p.z).collect();
        let (lo, hi) = (
            z.iter().copied().fold(Real::MAX, Real::min),
            z.iter().copied().fold(0.0, Real::max),
        );
        assert!(lo < 1e-6 && hi > LEN - 1e-6, "line spans z {lo}..{hi}");
    }
}

#[test]
fn plates_unfold_the_distance_across_the_fold() {
    let s = plates(2.5);
    let src = polyline(
        vec![Point3::new(0.0, 50.0, 0.0), Point3::new(150.0, 50.0, 0.0)],
        false,
    );
    let analytic = |p: &Point3| if p.z > 1e-9 { 50.0 + p.z } else { 50.0 - p.y };
    let f = distance(&s, &src, &mesh_params());
    check_field(&s, &f.vertex_distance);
    // 12 is not a divisor of 50, so no level runs along the fold itself.
    let ls = lines(&s, &f, 12.0, Some(8));
    assert_eq!(ls.len(), 8);
    assert!(ls.iter().all(|l| !l.closed));
    let err = path_error(&ls, analytic);
    assert!(err < 1e-6, "path error {err}");
    // Straight lines parallel to the source.
    for l in &ls {
        let (a, b) = (l.points[0], l.points[l.points.len() - 1]);
        assert!((b - a).normalize().x.abs() > 1.0 - 1e-9);
    }
}

#[test]
fn point_source_on_plates_matches_the_unfolded_plane() {
    let s = plates(2.5);
    let v = s
        .mesh
        .positions()
        .iter()
        .position(|p| (p - Point3::new(75.0, 25.0, 0.0)).norm() < 1e-9)
        .unwrap() as u32;
    let f = distance(&s, &GeodesicSource::Vertices(vec![v]), &mesh_params());
    check_field(&s, &f.vertex_distance);
    let mut worst: Real = 0.0;
    for (p, d) in s.mesh.positions().iter().zip(&f.vertex_distance) {
        // B unfolds to y = −z in A's plane; the unfolded plate is convex.
        let u = if p.z > 1e-9 { (p.x, -p.z) } else { (p.x, p.y) };
        let exact = ((u.0 - 75.0).powi(2) + (u.1 - 25.0).powi(2)).sqrt();
        worst = worst.max((d - exact).abs());
    }
    assert!(worst < 1e-6, "point-source error {worst}");
}

#[test]
fn sphere_equator_gives_latitude_circles() {
    let s = sphere(128, 64);
    let latitude = |p: &Point3| R * libm::atan2(p.z.abs(), (p.x * p.x + p.y * p.y).sqrt());
    for source in [
        polyline(ring(0.0, 64, 0.25), true),
        GeodesicSource::Plane {
            point: Point3::new(R, 0.0, 0.0),
            normal: nalgebra::Vector3::z(),
        },
    ] {
        let f = distance(&s, &source, &mesh_params());
        check_field(&s, &f.vertex_distance);
        let ls = lines(&s, &f, 10.0, None);
        assert_eq!(ls.len(), 14, "7 levels north and south");
        assert!(ls.iter().all(|l| l.closed));
        let err = path_error(&ls, latitude);
        // Faceting: the chords of 2.5 mm edges on R 50 shorten arcs by ~1e-4 relative.
        assert!(err < 0.03, "path error {err}");
    }
}

#[test]
fn height_field_matches_a_four_times_finer_mesh() {
    let src_points: Vec<Point3> = (0..=10)
        .map(|i| {
            let y = 5.0 * i as Real;
            Point3::new(30.0, y, height(30.0, y))
        })
        .collect();
    let coarse = height_field(1.0);
    let fine = height_field(0.25);
    let src = polyline(src_points, false);
    let fc = distance(&coarse, &src, &mesh_params());
    let ff = distance(&fine, &src, &mesh_params());
    check_field(&coarse, &fc.vertex_distance);
    // Coarse vertex (i, j) is fine vertex (4i, 4j).
    let (cols_c, cols_f) = (61, 241);
    let mut worst: Real = 0.0;
    for (v, d) in fc.vertex_distance.iter().enumerate() {
        let (i, j) = (v % cols_c, v / cols_c);
        let w = 4 * j * cols_f + 4 * i;
        assert!((coarse.mesh.positions()[v] - fine.mesh.positions()[w]).norm() < 1e-9);
        worst = worst.max((d - ff.vertex_distance[w]).abs());
    }
    eprintln!("height field coarse vs fine {worst}");
    // Steep (up to 45°) and saddle-shaped: where fronts meet, the update is fast marching's
    // plane wave, first order in the edge length.
    assert!(worst < 0.15, "coarse vs fine: {worst}");
    let ls = lines(&coarse, &fc, 10.0, None);
    assert!(!ls.is_empty() && ls.iter().all(|l| !l.closed));
}

#[test]
fn boundary_loop_source_measures_from_one_end() {
    let s = cylinder(80, 30);
    let loops = boundary_loops(&s.mesh, &s.adjacency, None).unwrap();
    assert_eq!(loops.len(), 2);
    let f = distance(
        &s,
        &GeodesicSource::Boundary {
            loop_index: Some(0),
        },
        &mesh_params(),
    );
    let z0 = s.mesh.positions()[loops[0][0] as usize].z;
    for (p, d) in s.mesh.positions().iter().zip(&f.vertex_distance) {
        assert!((d - (p.z - z0).abs()).abs() < MESH_TOL);
    }
    for &v in &loops[0] {
        assert!(f.vertex_distance[v as usize] < 1e-9, "0 on the source");
    }
}

#[test]
fn tool_path_links_the_passes() {
    let s = cylinder(80, 30);
    let f = distance(&s, &polyline(ring(0.0, 32, 0.0), true), &mesh_params());
    for order in [LinkOrder::ZigZag, LinkOrder::OneDirection] {
        let params = PathParams {
            spacing: 10.0,
            max_level: Some(11),
            order,
            ..PathParams::default()
        };
        let tp = f.tool_path(&s.mesh, &s.adjacency, &params).unwrap();
        tp.validate().unwrap();
        assert_eq!(tp.pass_count(), 11);
        assert_eq!(
            tp.poses.iter().filter(|p| p.kind == PoseKind::Link).count(),
            10
        );
        for p in &tp.poses {
            let radial = nalgebra::Vector3::new(p.position.x, p.position.y, 0.0).normalize();
            assert!(
                p.axis.dot(&radial) < -0.99,
                "tool axis points into the part"
            );
            assert!(p.travel.dot(&p.axis).abs() < 1e-6);
        }
        // Passes climb one level at a time.
        let z: Vec<Real> = (0..11)
            .map(|k| tp.poses.iter().find(|p| p.pass == k).unwrap().position.z)
            .collect();
        assert!(z.windows(2).all(|w| (w[1] - w[0] - 10.0).abs() < 0.05));
    }
    let bead = PathParams::from_bead(6.4, 0.738).unwrap();
    assert!((bead.spacing - 4.7232).abs() < 1e-9);
}

#[test]
fn voxel_method_is_within_two_voxels() {
    // A coarse 40-gon (sagitta 0.15 mm) keeps the debug-build run short; voxels do not
    // depend on the mesh resolution.
    let l = 2.0;
    let s = cylinder(40, 15);
    let f = distance(&s, &polyline(ring(0.0, 64, 0.3), true), &voxel_params(l));
    let vox = f.voxels.as_ref().unwrap();
    assert!(!vox.cells.is_empty() && vox.memory_bytes > 0);
    let ls = lines(&s, &f, 10.0, Some(11));
    assert_eq!(ls.len(), 11, "one closed circle per level");
    assert!(ls.iter().all(|l| l.closed));
    let err = path_error(&ls, |p| p.z);
    eprintln!(
        "voxel ring error {err}, {} voxels, {} bytes",
        vox.cells.len(),
        vox.memory_bytes
    );
    assert!(err < 2.0 * l, "voxel ring error {err}");

    let a0 = 0.1;
    let src = polyline(
        vec![
            Point3::new(R * libm::cos(a0), R * libm::sin(a0), 0.0),
            Point3::new(R * libm::cos(a0), R * libm::sin(a0), LEN),
        ],
        false,
    );
    let f = distance(&s, &src, &voxel_params(l));
    let ls = lines(&s, &f, 10.0, Some(14));
    assert_eq!(ls.len(), 28, "open lines on both sides");
    assert!(ls.iter().all(|l| !l.closed));
    let err = path_error(&ls, |p| arc_from(p, a0));
    eprintln!("voxel generator error {err}");
    assert!(err < 2.0 * l, "voxel generator error {err}");
}

#[test]
fn bad_input_is_refused_with_a_named_error() {
    let s = cylinder(40, 10);
    let run = |src: &GeodesicSource, p: &DistanceParams| {
        geodesic_distance(&s.mesh, &s.adjacency, src, p, &mut |_, _| {}).unwrap_err()
    };
    let far = polyline(vec![Point3::new(0.0, 0.0, 500.0)], false);
    let e = run(&far, &mesh_params());
    assert!(
        matches!(e, GeodesicError::SourceMissesSurface(_))
            && e.to_string().contains("source point 0"),
        "{e}"
    );
    let src = polyline(ring(0.0, 16, 0.0), true);
    let e = run(&src, &voxel_params(1e-4));
    assert!(
        matches!(e, GeodesicError::VoxelTooSmall { .. }) && e.to_string().contains("voxel size"),
        "{e}"
    );
    let e = run(&src, &voxel_params(Real::NAN));
    assert!(e.to_string().contains("voxel_size"), "{e}");
    let e = run(
        &src,
        &DistanceParams {
            faces: Some(vec![]),
            ..mesh_params()
        },
    );
    assert!(
        matches!(e, GeodesicError::BadFaces(_)) && e.to_string().contains("faces is empty"),
        "{e}"
    );
    let e = run(&GeodesicSource::Vertices(vec![u32::MAX]), &mesh_params());
    assert!(e.to_string().contains("vertex"), "{e}");
    let f = distance(&s, &src, &mesh_params());
    for spacing in [0.0, -1.0, Real::NAN] {
        let p = PathParams {
            spacing,
            ..PathParams::default()
        };
        let e = f.iso_lines(&s.mesh, &s.adjacency, &p).unwrap_err();
        assert!(e.to_string().contains("spacing"), "{e}");
    }
}
