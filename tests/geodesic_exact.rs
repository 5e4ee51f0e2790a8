//! The exact (window propagation) geodesic method against analytic polyhedral distances, an
//! independent brute-force computation on a bumpy mesh, and the unfolding mesh method.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skinpath::geodesic::{
    geodesic_distance, DistanceField, DistanceParams, GeodesicError, GeodesicSource, Method,
};
use skinpath::math::{Point3, Real};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::f64::consts::PI;

#[path = "common/geodesic_shapes.rs"]
mod shapes;
use shapes::*;

/// Relative agreement with analytic polyhedral distances.
const REL: Real = 1e-9;

/// B unfolded into A's plane: (x, 0, z) → (x, −z).
fn unfold_plates(p: &Point3) -> (Real, Real) {
    if p.z > 1e-12 {
        (p.x, -p.z)
    } else {
        (p.x, p.y)
    }
}

fn params(method: Method) -> DistanceParams {
    DistanceParams {
        method,
        ..DistanceParams::default()
    }
}

fn distance(s: &Shape, source: &GeodesicSource, method: Method) -> DistanceField {
    geodesic_distance(
        &s.mesh,
        &s.adjacency,
        source,
        &params(method),
        &mut |_, _| {},
    )
    .unwrap()
}

fn vertex_at(s: &Shape, p: Point3) -> u32 {
    s.mesh
        .positions()
        .iter()
        .position(|q| (q - p).norm() < 1e-9)
        .unwrap() as u32
}

/// Largest |d − analytic| / max(analytic, 1) over the vertices.
fn worst_relative(s: &Shape, d: &[Real], analytic: impl Fn(&Point3) -> Real) -> Real {
    s.mesh
        .positions()
        .iter()
        .zip(d)
        .map(|(p, d)| {
            let a = analytic(p);
            (d - a).abs() / a.max(1.0)
        })
        .fold(0.0, Real::max)
}

fn segment_distance_2d(p: (Real, Real), a: (Real, Real), b: (Real, Real)) -> Real {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

#[test]
fn flat_plate_point_sources_are_euclidean() {
    let (p, t) = grid(24, 16, false, |u, v| Point3::new(60.0 * u, 40.0 * v, 0.0));
    let s = shape(p, t);
    let v = vertex_at(&s, Point3::new(20.0, 15.0, 0.0));
    let f = distance(&s, &GeodesicSource::Vertices(vec![v]), Method::Exact);
    check_field(&s, &f.vertex_distance);
    let c = Point3::new(20.0, 15.0, 0.0);
    let err = worst_relative(&s, &f.vertex_distance, |p| (p - c).norm());
    assert!(err < REL, "vertex source: {err}");
    // A point inside a face, not a vertex.
    let c = Point3::new(33.3, 7.7, 0.0);
    let src = GeodesicSource::Polyline {
        points: vec![c],
        closed: false,
    };
    let f = distance(&s, &src, Method::Exact);
    let err = worst_relative(&s, &f.vertex_distance, |p| (p - c).norm());
    assert!(err < REL, "face-point source: {err}");
}

#[test]
fn degenerate_faces_give_finite_distances() {
    // A flat plate where one vertex is moved onto the border of its star (two zero-area
    // faces, one with its far corner between the others, one beyond them) and another onto
    // its neighbour (a zero-length edge): still a planar tiling, so the distance is Euclidean.
    let (mut p, t) = grid(12, 10, false, |u, v| Point3::new(24.0 * u, 20.0 * v, 0.0));
    let id = |i: usize, j: usize| j * 13 + i;
    p[id(4, 4)] = Point3::new(10.0, 9.0, 0.0);
    p[id(8, 6)] = p[id(7, 6)];
    let s = shape(p, t);
    let c = s.mesh.positions()[id(2, 2)];
    let f = distance(
        &s,
        &GeodesicSource::Vertices(vec![id(2, 2) as u32]),
        Method::Exact,
    );
    let mut worst: Real = 0.0;
    for (q, d) in s.mesh.positions().iter().zip(&f.vertex_distance) {
        assert!(d.is_finite(), "vertex at {q:?}: {d}");
        let e = (q - c).norm();
        assert!(*d >= e - 1e-9, "below the Euclidean distance at {q:?}");
        worst = worst.max(d - e);
    }
    eprintln!("degenerate plate: exact − Euclidean ≤ {worst:.3e}");
    assert!(worst < 1e-6, "exact − Euclidean = {worst}");
}

#[test]
fn plates_point_sources_unfold_across_the_fold() {
    let s = plates(2.5);
    // A vertex on A and a point inside a face of B; the unfolded plates are convex, so the
    // distance is Euclidean in the unfolding, across the fold for half the vertices.
    for (c, src) in [
        (
            (75.0, 25.0),
            GeodesicSource::Vertices(vec![vertex_at(&s, Point3::new(75.0, 25.0, 0.0))]),
        ),
        (
            (41.3, -17.9),
            GeodesicSource::Polyline {
                points: vec![Point3::new(41.3, 0.0, 17.9)],
                closed: false,
            },
        ),
    ] {
        let f = distance(&s, &src, Method::Exact);
        check_field(&s, &f.vertex_distance);
        let err = worst_relative(&s, &f.vertex_distance, |p| {
            let u = unfold_plates(p);
            (u.0 - c.0).hypot(u.1 - c.1)
        });
        assert!(err < REL, "point source {c:?}: {err}");
    }
}

#[test]
fn plates_line_sources_are_exact() {
    let s = plates(2.5);
    // The outer edge of A (the paper's model 1), and a slanted segment inside A whose ends
    // are reached by point windows.
    for (a, b) in [((0.0, 50.0), (150.0, 50.0)), ((10.0, 40.0), (140.0, 30.3))] {
        let src = GeodesicSource::Polyline {
            points: vec![Point3::new(a.0, a.1, 0.0), Point3::new(b.0, b.1, 0.0)],
            closed: false,
        };
        let f = distance(&s, &src, Method::Exact);
        check_field(&s, &f.vertex_distance);
        let err = worst_relative(&s, &f.vertex_distance, |p| {
            segment_distance_2d(unfold_plates(p), a, b)
        });
        assert!(err < REL, "line source {a:?}–{b:?}: {err}");
    }
}

/// Three squares [0, 10]² meeting at a convex cube corner: faces z = 0, x = 0, y = 0.
fn cube_corner(n: usize) -> Shape {
    let mut pos = Vec::new();
    let mut tri = Vec::new();
    let maps: [fn(Real, Real) -> Point3; 3] = [
        |u, v| Point3::new(10.0 * u, 10.0 * v, 0.0),
        |u, v| Point3::new(0.0, 10.0 * u, 10.0 * v),
        |u, v| Point3::new(10.0 * v, 0.0, 10.0 * u),
    ];
    for m in maps {
        let (p, t) = grid(n, n, false, m);
        let base = pos.len() as u32;
        pos.extend(p);
        tri.extend(t.iter().map(|t| t.map(|i| i + base)));
    }
    // Weld the shared edges.
    let mut id: Vec<u32> = Vec::new();
    let mut welded: Vec<Point3> = Vec::new();
    for p in &pos {
        match welded.iter().position(|q| (q - p).norm() < 1e-9) {
            Some(i) => id.push(i as u32),
            None => {
                id.push(welded.len() as u32);
                welded.push(*p);
            }
        }
    }
    let tri = tri.iter().map(|t| t.map(|i| id[i as usize])).collect();
    shape(welded, tri)
}

/// Surface distance on the cube corner from `p` on face z = 0 to `q`: the shortest valid
/// unfolding (direct across a shared edge, or through the third face).
fn cube_corner_distance(p: (Real, Real), q: &Point3) -> Real {
    let a = 10.0;
    let inside = |v: Real| (-1e-12..=a + 1e-12).contains(&v);
    if q.z.abs() < 1e-12 {
        return (q.x - p.0).hypot(q.y - p.1);
    }
    let mut best = Real::INFINITY;
    // Crossing of segment p → t with the line x = 0 (y coordinate), or y = 0 (x coordinate).
    let at_x0 = |t: (Real, Real)| p.1 + (t.1 - p.1) * p.0 / (p.0 - t.0);
    let at_y0 = |t: (Real, Real)| p.0 + (t.0 - p.0) * p.1 / (p.1 - t.1);
    if q.x.abs() < 1e-12 {
        // Face x = 0: direct (0, y, z) → (−z, y); through y = 0: → (−y, −z).
        let t = (-q.z, q.y);
        if inside(at_x0(t)) {
            best = best.min((t.0 - p.0).hypot(t.1 - p.1));
        }
        let t = (-q.y, -q.z);
        let xc = at_y0(t);
        let yc = at_x0(t);
        if inside(xc) && inside(-yc) {
            best = best.min((t.0 - p.0).hypot(t.1 - p.1));
        }
    } else {
        // Face y = 0: direct (x, 0, z) → (x, −z); through x = 0: → (−z, −x).
        let t = (q.x, -q.z);
        if inside(at_y0(t)) {
            best = best.min((t.0 - p.0).hypot(t.1 - p.1));
        }
        let t = (-q.z, -q.x);
        if inside(at_x0(t)) && inside(-at_y0(t)) {
            best = best.min((t.0 - p.0).hypot(t.1 - p.1));
        }
    }
    best
}

#[test]
fn cube_corner_paths_go_around_the_corner() {
    let s = cube_corner(10);
    assert_eq!(s.mesh.vertex_count(), 3 * 121 - 3 * 11 + 1);
    for p in [(3.0, 2.0), (1.0, 6.0), (5.0, 5.0)] {
        let v = vertex_at(&s, Point3::new(p.0, p.1, 0.0));
        let f = distance(&s, &GeodesicSource::Vertices(vec![v]), Method::Exact);
        check_field(&s, &f.vertex_distance);
        let err = worst_relative(&s, &f.vertex_distance, |q| cube_corner_distance(p, q));
        assert!(err < REL, "source {p:?}: {err}");
    }
}

/// A saddle: six planar sectors of 75° around a vertex (total angle 450°), pleated up and
/// down; `m` triangles a sector around, rings of radius 1..=12. Returns the shape and each
/// vertex's intrinsic polar coordinates (radius, angle).
fn saddle(m: usize) -> (Shape, Vec<(Real, Real)>) {
    let beta = 75.0 * PI / 180.0;
    // Unit rays d_i at 75° from their neighbours, alternately above and below z = 0.
    let c2 = (1.0 + libm::cos(beta)) / 1.5;
    let (c, s) = (c2.sqrt(), (1.0 - c2).sqrt());
    let d: Vec<nalgebra::Vector3<Real>> = (0..6)
        .map(|i| {
            let a = PI * i as Real / 3.0;
            let z = if i % 2 == 0 { s } else { -s };
            nalgebra::Vector3::new(c * libm::cos(a), c * libm::sin(a), z)
        })
        .collect();
    let around = 6 * m;
    let mut pos = vec![Point3::origin()];
    let mut polar = vec![(0.0, 0.0)];
    for j in 1..=12 {
        let r = j as Real;
        for a in 0..around {
            let (sec, t) = (a / m, (a % m) as Real / m as Real);
            let (d0, d1) = (d[sec], d[(sec + 1) % 6]);
            let perp = (d1 - d0 * d0.dot(&d1)).normalize();
            let dir = d0 * libm::cos(t * beta) + perp * libm::sin(t * beta);
            pos.push(Point3::from(dir * r));
            polar.push((r, a as Real * beta / m as Real));
        }
    }
    let id = |j: usize, a: usize| (1 + (j - 1) * around + a % around) as u32;
    let mut tri = Vec::new();
    for a in 0..around {
        tri.push([0, id(1, a), id(1, a + 1)]);
        for j in 1..12 {
            tri.push([id(j, a), id(j + 1, a), id(j + 1, a + 1)]);
            tri.push([id(j, a), id(j + 1, a + 1), id(j, a + 1)]);
        }
    }
    (shape(pos, tri), polar)
}

#[test]
fn saddle_cone_paths_bend_at_the_vertex_beyond_pi() {
    let (s, polar) = saddle(6);
    let total = 6.0 * 75.0 * PI / 180.0;
    // Every sector is planar: the intrinsic angle of each ray pair is 75°.
    let p = (1 + 2 * 36) as u32; // ring 3, angle 0
    let (rp, tp) = polar[p as usize];
    let f = distance(&s, &GeodesicSource::Vertices(vec![p]), Method::Exact);
    check_field(&s, &f.vertex_distance);
    let (mut worst, mut bent) = (0.0 as Real, 0);
    for (v, &(r, t)) in polar.iter().enumerate() {
        if r > 6.0 {
            continue; // the outer boundary is a polygon: keep to the disk it contains
        }
        let mut phi = (t - tp).abs() % total;
        phi = phi.min(total - phi);
        // On a cone of angle 450°: straight in the unfolding below π, through the apex beyond.
        let exact = if phi < PI {
            (r * r + rp * rp - 2.0 * r * rp * libm::cos(phi))
                .max(0.0)
                .sqrt()
        } else {
            bent += 1;
            r + rp
        };
        worst = worst.max((f.vertex_distance[v] - exact).abs() / exact.max(1.0));
    }
    let m = distance(&s, &GeodesicSource::Vertices(vec![p]), Method::Fast);
    eprintln!(
        "saddle: exact vs analytic {worst:.3e} (relative), mesh vs exact {:.3e}",
        max_difference(&f.vertex_distance, &m.vertex_distance)
    );
    assert!(
        bent > 10,
        "the test reaches the shadow of the apex ({bent} vertices)"
    );
    assert!(worst < REL, "saddle: {worst}");
}

fn max_difference(a: &[Real], b: &[Real]) -> Real {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, Real::max)
}

#[test]
fn cylinder_matches_the_unfolding_and_the_mesh_method() {
    let n = 160;
    let s = cylinder(n, 60);
    let ring_src = GeodesicSource::Polyline {
        points: ring(0.0, 64, 0.3),
        closed: true,
    };
    let a0 = 2.0 * PI * 0.37 / n as Real;
    let generator = GeodesicSource::Polyline {
        points: vec![
            Point3::new(R * libm::cos(a0), R * libm::sin(a0), 0.0),
            Point3::new(R * libm::cos(a0), R * libm::sin(a0), LEN),
        ],
        closed: false,
    };
    // Unfolded, the polygon's perimeter is a straight line: vertex i sits at i·chord, the
    // generator (snapped onto the facet between vertices 0 and 1) at s0.
    let chord = 2.0 * R * libm::sin(PI / n as Real);
    let (v0, v1) = (
        nalgebra::Vector2::new(R, 0.0),
        nalgebra::Vector2::new(
            R * libm::cos(2.0 * PI / n as Real),
            R * libm::sin(2.0 * PI / n as Real),
        ),
    );
    let pa = nalgebra::Vector2::new(R * libm::cos(a0), R * libm::sin(a0));
    let s0 = (pa - v0).dot(&(v1 - v0)) / chord;
    let around = move |p: &Point3| {
        let i = (libm::atan2(p.y, p.x) / (2.0 * PI / n as Real)).round() as i64;
        let x = i.rem_euclid(n as i64) as Real * chord - s0;
        x.abs().min(n as Real * chord - x)
    };
    type Analytic<'a> = &'a dyn Fn(&Point3) -> Real;
    let cases: [(&str, GeodesicSource, Analytic); 2] = [
        ("ring", ring_src, &|p: &Point3| p.z),
        ("generator", generator, &around),
    ];
    for (name, src, analytic) in cases {
        let e = distance(&s, &src, Method::Exact);
        let m = distance(&s, &src, Method::Fast);
        check_field(&s, &e.vertex_distance);
        let err = worst_relative(&s, &e.vertex_distance, analytic);
        let diff = max_difference(&e.vertex_distance, &m.vertex_distance);
        for (v, p) in s.mesh.positions().iter().enumerate() {
            let a = analytic(p);
            if (e.vertex_distance[v] - a).abs() > 1e-6 {
                eprintln!(
                    "DBG v {v} {p:?} exact {} mesh {} analytic {a}",
                    e.vertex_distance[v], m.vertex_distance[v]
                );
            }
        }
        eprintln!(
            "cylinder {name}: exact vs unfolded {err:.3e} (relative), mesh vs exact {diff:.3e}, \
             {} windows ({:.2} per edge)",
            e.windows,
            e.windows as Real / (1.5 * s.mesh.triangle_count() as Real)
        );
        assert!(err < REL, "{name}: exact vs unfolded {err}");
        // The mesh method's bound on this mesh (tests/geodesic.rs).
        assert!(diff < 0.02, "{name}: mesh vs exact {diff}");
    }
}

#[test]
fn sphere_is_close_to_the_mesh_method_and_the_latitude() {
    let s = sphere(64, 32);
    let src = GeodesicSource::Plane {
        point: Point3::new(R, 0.0, 0.0),
        normal: nalgebra::Vector3::z(),
    };
    let e = distance(&s, &src, Method::Exact);
    let m = distance(&s, &src, Method::Fast);
    check_field(&s, &e.vertex_distance);
    let diff = max_difference(&e.vertex_distance, &m.vertex_distance);
    let latitude = |p: &Point3| R * libm::atan2(p.z.abs(), (p.x * p.x + p.y * p.y).sqrt());
    let err = s
        .mesh
        .positions()
        .iter()
        .zip(&e.vertex_distance)
        .map(|(p, d)| (d - latitude(p)).abs())
        .fold(0.0, Real::max);
    eprintln!("sphere: exact vs mesh {diff:.3e}, exact vs latitude {err:.3e}");
    // The polyhedral distance is shorter than the arc by the faceting (~R·h²/24 a row).
    assert!(err < 0.1, "exact vs latitude {err}");
    assert!(diff < 0.05, "exact vs mesh {diff}");
    // On the equator itself both are 0.
    for (p, d) in s.mesh.positions().iter().zip(&e.vertex_distance) {
        if p.z.abs() < 1e-9 {
            assert!(*d < 1e-9, "0 on the source");
        }
    }
}

/// A bumpy, irregular height field of (n + 1)² vertices with jittered positions.
fn bumpy(n: usize) -> Shape {
    let (p, t) = grid(n, n, false, |u, v| {
        let (i, j) = ((u * n as Real).round(), (v * n as Real).round());
        let inner = |k: Real| k > 0.0 && k < n as Real;
        let jx = if inner(i) && inner(j) {
            0.3 * libm::sin(7.1 * i + 3.3 * j)
        } else {
            0.0
        };
        let jy = if inner(i) && inner(j) {
            0.3 * libm::cos(5.3 * i - 2.9 * j)
        } else {
            0.0
        };
        let (x, y) = (i + jx, j + jy);
        let z = 1.2 * libm::sin(0.9 * x) * libm::cos(0.7 * y) + 0.4 * libm::sin(1.7 * x + 1.1 * y);
        Point3::new(x, y, z)
    });
    shape(p, t)
}

/// Dijkstra on vertices + `k` Steiner points per edge, every pair of points on the boundary
/// of a face joined by a straight segment: an upper bound of the surface distance that
/// converges from above as `k` grows.
fn steiner_distance(s: &Shape, source: &[u32], k: usize) -> Vec<Real> {
    let mesh = &s.mesh;
    let nv = mesh.vertex_count();
    let mut edge_id = std::collections::HashMap::new();
    let mut points: Vec<Point3> = mesh.positions().to_vec();
    let mut face_nodes: Vec<Vec<usize>> = Vec::new();
    for t in mesh.triangles() {
        let mut nodes: Vec<usize> = t.iter().map(|&v| v as usize).collect();
        for e in 0..3 {
            let (a, b) = (t[e].min(t[(e + 1) % 3]), t[e].max(t[(e + 1) % 3]));
            let first = *edge_id.entry((a, b)).or_insert_with(|| {
                let first = points.len();
                let (pa, pb) = (mesh.positions()[a as usize], mesh.positions()[b as usize]);
                for i in 1..=k {
                    points.push(pa + (pb - pa) * (i as Real / (k + 1) as Real));
                }
                first
            });
            nodes.extend(first..first + k);
        }
        face_nodes.push(nodes);
    }
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); points.len()];
    for (f, nodes) in face_nodes.iter().enumerate() {
        for &n in nodes {
            adj[n].push(f);
        }
    }
    let mut d = vec![Real::INFINITY; points.len()];
    let mut heap = BinaryHeap::new();
    // Source vertices, and the Steiner points of the edges joining two of them.
    for &v in source {
        d[v as usize] = 0.0;
        heap.push((Reverse(0u64), v as usize));
    }
    for (&(a, b), &first) in &edge_id {
        if source.contains(&a) && source.contains(&b) {
            for (n, dn) in d.iter_mut().enumerate().skip(first).take(k) {
                *dn = 0.0;
                heap.push((Reverse(0u64), n));
            }
        }
    }
    while let Some((Reverse(bits), n)) = heap.pop() {
        let dn = Real::from_bits(bits);
        if dn > d[n] {
            continue;
        }
        for &f in &adj[n] {
            for &m in &face_nodes[f] {
                let dm = dn + (points[m] - points[n]).norm();
                if dm < d[m] {
                    d[m] = dm;
                    heap.push((Reverse(dm.to_bits()), m));
                }
            }
        }
    }
    d.truncate(nv);
    d
}

/// Checks the exact distance from `source` against the Steiner bound for k = 7, 15, 31.
fn check_against_steiner(s: &Shape, e: &DistanceField, source: &[u32], what: &str) {
    let mut gaps = Vec::new();
    for k in [7, 15, 31] {
        let r = steiner_distance(s, source, k);
        let mut gap: Real = 0.0;
        for (x, y) in e.vertex_distance.iter().zip(&r) {
            // The Steiner graph holds surface paths only: never shorter than the exact one.
            assert!(
                *x <= y + 1e-9,
                "exact {x} above the Steiner bound {y} (k = {k})"
            );
            gap = gap.max(y - x);
        }
        eprintln!("bumpy, {what}: Steiner (k = {k}) − exact ≤ {gap:.3e}");
        gaps.push(gap);
    }
    // The bound closes in on the exact distance as k doubles (nested point sets).
    assert!(
        gaps[1] < 0.6 * gaps[0] && gaps[2] < 0.6 * gaps[1],
        "{what}: gaps {gaps:?}"
    );
    assert!(
        gaps[2] < 0.01,
        "{what}: Steiner k = 31 − exact = {}",
        gaps[2]
    );
}

#[test]
fn bumpy_mesh_matches_a_steiner_graph_bound() {
    let s = bumpy(14);
    assert_eq!(s.mesh.vertex_count(), 225);
    // A point source (saddles and convex vertices around it).
    let src = 7 * 15 + 6;
    let e = distance(&s, &GeodesicSource::Vertices(vec![src]), Method::Exact);
    check_field(&s, &e.vertex_distance);
    check_against_steiner(&s, &e, &[src], "vertex source");
    // A curve source along a row of edges (line windows on a curved mesh).
    let row: Vec<u32> = (2..=12).map(|i| 7 * 15 + i).collect();
    let src = GeodesicSource::Polyline {
        points: row
            .iter()
            .map(|&v| s.mesh.positions()[v as usize])
            .collect(),
        closed: false,
    };
    let e = distance(&s, &src, Method::Exact);
    check_field(&s, &e.vertex_distance);
    for &v in &row {
        assert!(e.vertex_distance[v as usize] < 1e-12, "0 on the source");
    }
    check_against_steiner(&s, &e, &row, "curve source");
}

#[test]
fn height_field_exact_against_finer_exact_and_the_mesh_method() {
    let src_points: Vec<Point3> = (0..=10)
        .map(|i| {
            let y = 5.0 * i as Real;
            Point3::new(30.0, y, height(30.0, y))
        })
        .collect();
    let src = GeodesicSource::Polyline {
        points: src_points,
        closed: false,
    };
    let coarse = height_field(1.0);
    let fine = height_field(0.5);
    let ec = distance(&coarse, &src, Method::Exact);
    let mc = distance(&coarse, &src, Method::Fast);
    let ef = distance(&fine, &src, Method::Exact);
    check_field(&coarse, &ec.vertex_distance);
    let (cols_c, cols_f) = (61, 121);
    let mut refine: Real = 0.0;
    for (v, d) in ec.vertex_distance.iter().enumerate() {
        let (i, j) = (v % cols_c, v / cols_c);
        let w = 2 * j * cols_f + 2 * i;
        assert!((coarse.mesh.positions()[v] - fine.mesh.positions()[w]).norm() < 1e-9);
        refine = refine.max((d - ef.vertex_distance[w]).abs());
    }
    let (mut mesh_err, mut at) = (0.0, 0);
    for (v, (m, e)) in mc
        .vertex_distance
        .iter()
        .zip(&ec.vertex_distance)
        .enumerate()
    {
        if (m - e).abs() > mesh_err {
            mesh_err = (m - e).abs();
            at = v;
        }
    }
    eprintln!(
        "height field: exact 1 mm vs 0.5 mm {refine:.4}; mesh vs exact (1 mm) {mesh_err:.4} at {:?}; \
         windows {:.2} per edge (1 mm), {:.2} (0.5 mm)",
        coarse.mesh.positions()[at],
        ec.windows as Real / (1.5 * coarse.mesh.triangle_count() as Real),
        ef.windows as Real / (1.5 * fine.mesh.triangle_count() as Real)
    );
    assert!(refine < 0.01, "exact 1 mm vs 0.5 mm: {refine}");
    // The unfolding method's first-order updates where fronts meet: 0.23 mm on this mesh,
    // near the steep side x = 60 (measured; the bound records it).
    assert!(mesh_err < 0.25, "mesh vs exact: {mesh_err}");
}

#[test]
fn exact_method_refuses_bad_input() {
    let s = cylinder(40, 10);
    let run = |src: &GeodesicSource, p: &DistanceParams| {
        geodesic_distance(&s.mesh, &s.adjacency, src, p, &mut |_, _| {}).unwrap_err()
    };
    let far = GeodesicSource::Polyline {
        points: vec![Point3::new(0.0, 0.0, 500.0)],
        closed: false,
    };
    let e = run(&far, &params(Method::Exact));
    assert!(matches!(e, GeodesicError::SourceMissesSurface(_)), "{e}");
    let e = run(
        &GeodesicSource::Vertices(vec![u32::MAX]),
        &params(Method::Exact),
    );
    assert!(e.to_string().contains("vertex"), "{e}");
    let src = GeodesicSource::Polyline {
        points: ring(0.0, 16, 0.0),
        closed: true,
    };
    let e = run(
        &src,
        &DistanceParams {
            faces: Some(vec![]),
            ..params(Method::Exact)
        },
    );
    assert!(matches!(e, GeodesicError::BadFaces(_)), "{e}");
    let e = run(
        &src,
        &DistanceParams {
            max_windows: Some(50),
            ..params(Method::Exact)
        },
    );
    assert!(
        matches!(e, GeodesicError::LimitExceeded(_)) && e.to_string().contains("max_windows"),
        "{e}"
    );
    let e = run(
        &src,
        &DistanceParams {
            max_windows: Some(0),
            ..params(Method::Exact)
        },
    );
    assert!(e.to_string().contains("max_windows"), "{e}");
    // A face subset: the distance stays on it.
    let half: Vec<u32> = (0..s.mesh.triangle_count() as u32 / 2).collect();
    let f = geodesic_distance(
        &s.mesh,
        &s.adjacency,
        &src,
        &DistanceParams {
            faces: Some(half.clone()),
            ..params(Method::Exact)
        },
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(f.method.name(), "exact");
    let on: std::collections::HashSet<u32> = half
        .iter()
        .flat_map(|&t| s.mesh.triangles()[t as usize])
        .collect();
    for (v, d) in f.vertex_distance.iter().enumerate() {
        assert_eq!(d.is_finite(), on.contains(&(v as u32)), "vertex {v}");
    }
}

#[test]
fn random_triangle_soups_never_give_nan_or_hang() {
    // Deterministic pseudo-random soups: repeated corners, coincident and collinear points,
    // non-manifold edges, flipped faces. Every run ends (Ok or a named error) and every
    // distance is +∞ or a finite number ≥ 0.
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move |n: u64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n
    };
    for round in 0..40 {
        let nv = 6 + next(30) as usize;
        let pos: Vec<Point3> = (0..nv)
            .map(|_| {
                // A coarse lattice: many coincident and collinear points.
                let c = |x: u64| x as Real * 0.5;
                Point3::new(c(next(5)), c(next(5)), c(next(3)))
            })
            .collect();
        let tri: Vec<[u32; 3]> = (0..8 + next(40))
            .map(|_| {
                [
                    next(nv as u64) as u32,
                    next(nv as u64) as u32,
                    next(nv as u64) as u32,
                ]
            })
            .collect();
        let s = shape(pos, tri);
        let src = GeodesicSource::Vertices(vec![s.mesh.triangles()[0][0]]);
        match geodesic_distance(
            &s.mesh,
            &s.adjacency,
            &src,
            &params(Method::Exact),
            &mut |_, _| {},
        ) {
            Ok(f) => {
                for d in &f.vertex_distance {
                    assert!(!d.is_nan() && *d >= 0.0, "round {round}: distance {d}");
                }
            }
            Err(e) => assert!(!e.to_string().is_empty(), "round {round}"),
        }
    }
}
