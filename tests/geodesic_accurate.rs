//! The accurate (virtual source) geodesic method, the default: against analytic distances on a
//! spherical cap, a sphere, a cylinder and folded plates, against the exact method on irregular
//! doubly curved meshes, and the order of its error checked as the edges shrink.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skinpath::geodesic::{
    geodesic_distance, DistanceField, DistanceParams, GeodesicSource, Method,
};
use skinpath::math::{Point3, Real};
use std::f64::consts::PI;

#[path = "common/geodesic_shapes.rs"]
mod shapes;
use shapes::*;

/// The distance by `method`; the accurate method without its exact first try on small
/// surfaces with corners or holes, so these tests check the virtual sources themselves.
fn distance(s: &Shape, source: &GeodesicSource, method: Method) -> DistanceField {
    let params = DistanceParams {
        method,
        exact_first_windows: Some(0),
        ..DistanceParams::default()
    };
    geodesic_distance(&s.mesh, &s.adjacency, source, &params, &mut |_, _| {}).unwrap()
}

/// Largest and mean |d − analytic| over the vertices.
fn errors(s: &Shape, d: &[Real], analytic: impl Fn(&Point3) -> Real) -> (Real, Real) {
    let e: Vec<Real> = s
        .mesh
        .positions()
        .iter()
        .zip(d)
        .map(|(p, d)| (d - analytic(p)).abs())
        .collect();
    (
        e.iter().copied().fold(0.0, Real::max),
        e.iter().sum::<Real>() / e.len() as Real,
    )
}

const CAP_R: Real = 1000.0;
const SPHERE_R: Real = 100.0;

/// Distance from the rim of the cap (half-angle 1 rad): R·(θ0 − θ).
fn cap_distance(p: &Point3) -> Real {
    CAP_R * (1.0 - libm::acos((p.z / CAP_R).clamp(-1.0, 1.0)))
}

fn boundary() -> GeodesicSource {
    GeodesicSource::Boundary { loop_index: None }
}

/// The cube sphere with its point source at the south pole, and the great-circle distance.
fn sphere_case(n: usize) -> (Shape, GeodesicSource, impl Fn(&Point3) -> Real) {
    let s = cube_sphere(n, SPHERE_R);
    let south = s
        .mesh
        .positions()
        .iter()
        .position(|p| (p.z + SPHERE_R).abs() < 1e-9)
        .unwrap() as u32;
    let great_circle = |p: &Point3| SPHERE_R * libm::acos((-p.z / SPHERE_R).clamp(-1.0, 1.0));
    (s, GeodesicSource::Vertices(vec![south]), great_circle)
}

#[test]
fn is_the_default_and_reports_its_name() {
    assert_eq!(DistanceParams::default().method, Method::Accurate);
    let s = cap(8, CAP_R, 1.0);
    let f = geodesic_distance(
        &s.mesh,
        &s.adjacency,
        &boundary(),
        &DistanceParams::default(),
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(f.method, Method::Accurate);
    assert_eq!(f.method.name(), "accurate");
    assert_eq!(Method::Fast.name(), "fast");
}

#[test]
fn spherical_cap_from_its_rim_is_near_the_analytic_distance() {
    // 20 rings, 2400 triangles, edges of about 50 mm on R 1000.
    let s = cap(20, CAP_R, 1.0);
    let a = distance(&s, &boundary(), Method::Accurate);
    check_field(&s, &a.vertex_distance);
    let (max, mean) = errors(&s, &a.vertex_distance, cap_distance);
    let (fmax, fmean) = errors(
        &s,
        &distance(&s, &boundary(), Method::Fast).vertex_distance,
        cap_distance,
    );
    eprintln!(
        "cap 20 rings: accurate max {max:.4} mean {mean:.5}; fast max {fmax:.4} mean {fmean:.5}"
    );
    // Away from the pole (where all fronts meet) the error is second order; it is largest
    // there. The fast method is millimetres off on the same mesh.
    assert!(max < 6.0 && mean < 0.25, "accurate: max {max}, mean {mean}");
    assert!(mean * 5.0 < fmean, "accurate mean {mean} vs fast {fmean}");
    // Within a face of the rim the distance is the straight-line one: 0 on the rim.
    for (p, d) in s.mesh.positions().iter().zip(&a.vertex_distance) {
        if cap_distance(p).abs() < 1e-9 {
            assert!(d.abs() < 1e-9, "rim vertex at {d}");
        }
    }
}

#[test]
fn sphere_point_source_is_near_the_great_circle_distance() {
    let (s, src, exact) = sphere_case(12); // 1728 triangles
    let a = distance(&s, &src, Method::Accurate);
    check_field(&s, &a.vertex_distance);
    let (max, mean) = errors(&s, &a.vertex_distance, &exact);
    let (fmax, fmean) = errors(
        &s,
        &distance(&s, &src, Method::Fast).vertex_distance,
        &exact,
    );
    eprintln!(
        "sphere n 12: accurate max {max:.4} mean {mean:.5}; fast max {fmax:.4} mean {fmean:.5}"
    );
    assert!(max < 2.0 && mean < 0.3, "accurate: max {max}, mean {mean}");
    assert!(
        max < fmax && mean < fmean,
        "accurate ({max}, {mean}) vs fast ({fmax}, {fmean})"
    );
}

#[test]
fn error_on_the_sphere_is_second_order_away_from_the_antipode() {
    // The stated order: away from where fronts meet, halving the edges divides the error by
    // about four (second order); checked as at least 3 on the mean error over the vertices
    // within 3/4 of the half circumference, and at least 1.5 (first order) on the largest.
    let measure = |n: usize| {
        let (s, src, exact) = sphere_case(n);
        let d = distance(&s, &src, Method::Accurate).vertex_distance;
        let (mut near, mut count, mut max) = (0.0, 0usize, 0.0 as Real);
        for (p, d) in s.mesh.positions().iter().zip(&d) {
            let e = (d - exact(p)).abs();
            max = max.max(e);
            if exact(p) < 0.75 * PI * SPHERE_R {
                near += e;
                count += 1;
            }
        }
        (near / count as Real, max)
    };
    let (coarse, coarse_max) = measure(8);
    let (fine, fine_max) = measure(16);
    eprintln!("sphere mean error (away from the antipode) {coarse:.5} → {fine:.5}; max {coarse_max:.4} → {fine_max:.4}");
    assert!(fine * 3.0 < coarse, "mean {coarse} → {fine}");
    assert!(fine_max * 1.5 < coarse_max, "max {coarse_max} → {fine_max}");
}

#[test]
fn cylinder_ring_and_generator_sources_are_exact() {
    let s = cylinder(48, 24);
    let ring = GeodesicSource::Polyline {
        points: ring(0.0, 48, 0.0),
        closed: true,
    };
    let d = distance(&s, &ring, Method::Accurate).vertex_distance;
    check_field(&s, &d);
    let (max, _) = errors(&s, &d, |p| p.z);
    assert!(max < 1e-9, "ring source: {max}");
    // A generator through vertices: the distance is the unfolded arc of the 48-gon.
    let generator = GeodesicSource::Polyline {
        points: vec![Point3::new(R, 0.0, 0.0), Point3::new(R, 0.0, LEN)],
        closed: false,
    };
    let chord = 2.0 * R * libm::sin(PI / 48.0);
    let d = distance(&s, &generator, Method::Accurate).vertex_distance;
    check_field(&s, &d);
    let (max, _) = errors(&s, &d, |p| {
        let k = (libm::atan2(p.y, p.x) / (2.0 * PI / 48.0)).round().abs();
        k.min(48.0 - k) * chord
    });
    assert!(max < 1e-9, "generator source: {max}");
}

#[test]
fn folded_plates_line_and_point_sources_are_exact() {
    let s = plates(2.5);
    // B unfolded into A's plane: (x, 0, z) → (x, −z).
    let unfold = |p: &Point3| if p.z > 1e-12 { (p.x, -p.z) } else { (p.x, p.y) };
    let edge = GeodesicSource::Polyline {
        points: vec![Point3::new(0.0, 50.0, 0.0), Point3::new(150.0, 50.0, 0.0)],
        closed: false,
    };
    let d = distance(&s, &edge, Method::Accurate).vertex_distance;
    check_field(&s, &d);
    let (max, _) = errors(&s, &d, |p| 50.0 - unfold(p).1);
    assert!(max < 1e-9, "outer edge of A: {max}");
    let v = s
        .mesh
        .positions()
        .iter()
        .position(|p| (p - Point3::new(75.0, 25.0, 0.0)).norm() < 1e-9)
        .unwrap() as u32;
    let d = distance(&s, &GeodesicSource::Vertices(vec![v]), Method::Accurate).vertex_distance;
    let (max, _) = errors(&s, &d, |p| {
        let u = unfold(p);
        (u.0 - 75.0).hypot(u.1 - 25.0)
    });
    assert!(max < 1e-9, "point on A: {max}");
}

/// A jittered grid on a doubly curved bump (irregular triangles, no symmetry); coarse for its
/// curvature (edges of about 2 against radii of 10–20), where fronts focus behind the bump.
fn irregular(n: usize) -> Shape {
    let (p, t) = grid(n, n, false, |u, v| {
        let (i, j) = ((u * n as Real).round(), (v * n as Real).round());
        let inner = |k: Real| k > 0.0 && k < n as Real;
        let jitter = if inner(i) && inner(j) { 0.3 } else { 0.0 };
        let x = 2.0 * (i + jitter * libm::sin(5.7 * i + 2.3 * j));
        let y = 2.0 * (j + jitter * libm::cos(3.1 * i - 4.7 * j));
        let z =
            6.0 * libm::exp(
                -((x - n as Real) * (x - n as Real) + (y - 0.8 * n as Real).powi(2))
                    / (0.3 * (n * n) as Real),
            ) + 1.5 * libm::sin(0.21 * x) * libm::cos(0.17 * y);
        Point3::new(x, y, z)
    });
    shape(p, t)
}

#[test]
fn irregular_meshes_agree_with_the_exact_method() {
    for (name, s, src) in [
        (
            "jittered bump, point source",
            irregular(24),
            GeodesicSource::Vertices(vec![7 * 25 + 5]),
        ),
        (
            "jittered bump, curve source",
            irregular(24),
            GeodesicSource::Polyline {
                points: vec![Point3::new(4.0, 3.0, 10.0), Point3::new(40.0, 9.0, 10.0)],
                closed: false,
            },
        ),
        (
            "height field, plane section",
            height_field(2.0),
            GeodesicSource::Plane {
                point: Point3::new(30.0, 25.0, 0.0),
                normal: nalgebra::Vector3::new(1.0, 0.3, 0.0),
            },
        ),
    ] {
        let e = distance(&s, &src, Method::Exact).vertex_distance;
        let a = distance(&s, &src, Method::Accurate).vertex_distance;
        let f = distance(&s, &src, Method::Fast).vertex_distance;
        check_field(&s, &a);
        let diff = |d: &[Real]| {
            let v: Vec<Real> = d.iter().zip(&e).map(|(d, e)| (d - e).abs()).collect();
            (
                v.iter().copied().fold(0.0, Real::max),
                v.iter().sum::<Real>() / v.len() as Real,
            )
        };
        let ((amax, amean), (fmax, fmean)) = (diff(&a), diff(&f));
        let scale = e.iter().copied().fold(0.0, Real::max);
        eprintln!("{name}: |accurate − exact| max {amax:.4} mean {amean:.5}; |fast − exact| max {fmax:.4} mean {fmean:.5} (largest distance {scale:.1})");
        assert!(
            amax < 0.03 * scale && amean < 4e-3 * scale,
            "{name}: {amax}, {amean}"
        );
        assert!(
            amean <= fmean,
            "{name}: accurate mean {amean} vs fast {fmean}"
        );
    }
}

#[test]
fn focal_point_of_the_cap_is_refined() {
    // 40 rings, 9600 triangles, edges of 25 mm. All fronts from the rim meet at the pole; the
    // vertices there were offered only their neighbours' sources (1.8 mm off within 200 mm
    // of the pole before the focal patches were subdivided, 0.2 mm after).
    let s = cap(40, CAP_R, 1.0);
    let d = distance(&s, &boundary(), Method::Accurate).vertex_distance;
    check_field(&s, &d);
    let (mut near, mut far) = (0.0 as Real, 0.0 as Real);
    for (p, d) in s.mesh.positions().iter().zip(&d) {
        let e = (d - cap_distance(p)).abs();
        if cap_distance(p) > 800.0 {
            near = near.max(e);
        } else {
            far = far.max(e);
        }
    }
    eprintln!("cap 40 rings: max error within 200 mm of the pole {near:.4}, elsewhere {far:.4}");
    assert!(near < 0.4, "near the pole: {near}");
    assert!(
        near < far,
        "the pole ({near}) is no worse than the rest ({far})"
    );
}

#[test]
fn focal_point_of_the_sphere_is_near_the_exact_distance() {
    // 3072 triangles, edges of about 10 mm on R 100: against the exact polyhedral distance
    // the accurate method was 0.99 mm off near the antipode before its focal patch was
    // subdivided, and is 0.2 mm off there now. Elsewhere on so coarse a sphere (faces 6° apart,
    // where point sources are unfolded around each vertex) it may differ from the exact
    // polyhedral distance by more (0.41 mm at 233 mm), but is no further from the analytic
    // distance than the exact method is.
    let (s, src, analytic) = sphere_case(16);
    let e = distance(&s, &src, Method::Exact).vertex_distance;
    let a = distance(&s, &src, Method::Accurate).vertex_distance;
    let near_antipode = |p: &Point3| p.z > SPHERE_R * libm::cos(0.5);
    let diff = s
        .mesh
        .positions()
        .iter()
        .zip(a.iter().zip(&e))
        .filter(|(p, _)| near_antipode(p))
        .map(|(_, (a, e))| (a - e).abs())
        .fold(0.0, Real::max);
    let (a_max, a_mean) = errors(&s, &a, &analytic);
    let (e_max, e_mean) = errors(&s, &e, &analytic);
    eprintln!(
        "sphere n 16: max |accurate − exact| within 0.5 rad of the antipode {diff:.4}; against \
         the analytic distance accurate {a_max:.4} / {a_mean:.4}, exact {e_max:.4} / {e_mean:.4}"
    );
    assert!(diff < 0.3, "{diff}");
    assert!(
        a_max < e_max * 1.05 && a_mean < e_mean * 1.05,
        "{a_max} {a_mean}"
    );
}

#[test]
fn error_at_the_antipode_is_second_order_too() {
    // With the focal patches the largest error, at the antipode's side, falls as the square
    // of the edge length like the rest (n 16 → 32: 0.42 → 0.11 mm; 0.66 → 0.27 without).
    let max_error = |n: usize| {
        let (s, src, exact) = sphere_case(n);
        let d = distance(&s, &src, Method::Accurate).vertex_distance;
        errors(&s, &d, &exact).0
    };
    let (coarse, fine) = (max_error(16), max_error(32));
    eprintln!("sphere max error n 16 → 32: {coarse:.4} → {fine:.4}");
    assert!(fine * 3.0 < coarse, "{coarse} → {fine}");
}

/// Largest and mean error at `from..to` mm from the centre of a cap of `rings` rings (from
/// its rim), or of the same mesh flattened into a disk (`flat`: against the distance to the
/// rim polygon, computed over every rim edge).
fn converging_error(rings: usize, flat: bool, from: Real, to: Real) -> (Real, Real) {
    let mut s = cap(rings, CAP_R, 1.0);
    if flat {
        let p = s
            .mesh
            .positions()
            .iter()
            .map(|p| Point3::new(p.x, p.y, 0.0))
            .collect();
        s = shape(p, s.mesh.triangles().to_vec());
    }
    let d = distance(&s, &boundary(), Method::Accurate).vertex_distance;
    check_field(&s, &d);
    let pos = s.mesh.positions();
    let rim: Vec<Point3> = pos[pos.len() - 6 * rings..].to_vec();
    let exact = |p: &Point3| {
        if !flat {
            return cap_distance(p);
        }
        (0..rim.len())
            .map(|i| {
                let (a, b) = (rim[i], rim[(i + 1) % rim.len()]);
                let t = ((p - a).dot(&(b - a)) / (b - a).norm_squared()).clamp(0.0, 1.0);
                (p - (a + (b - a) * t)).norm()
            })
            .fold(Real::INFINITY, Real::min)
    };
    let centre = pos[0];
    let (mut worst, mut sum, mut n): (Real, Real, usize) = (0.0, 0.0, 0);
    for (p, d) in pos.iter().zip(&d) {
        let rho = if flat {
            (p - centre).norm()
        } else {
            CAP_R - cap_distance(p)
        };
        if (from..to).contains(&rho) {
            let e = (d - exact(p)).abs();
            worst = worst.max(e);
            sum += e;
            n += 1;
        }
    }
    (worst, sum / n as Real)
}

#[test]
fn fronts_converging_on_the_cap_are_interpolated_between_the_sources_held() {
    // 100 rings, 60 000 triangles, edges of 10 mm. Between 150 and 400 mm from the pole,
    // fronts from the whole rim converge and each vertex was offered only the pieces of the
    // rim its neighbours held, often the same piece for several of them. Before the distances
    // there were interpolated between those pieces (`fronts.rs`) the error was up to 0.21 mm
    // (mean 0.019) on the cap and 0.22 mm (mean 0.023) on the same mesh flattened into a
    // disk, where every unfolding is exact; now 0.03 (0.009) and 0.08 (0.008). What is left
    // is mostly the unfolding's own error on the cap, and on the disk the rim's 600 straight
    // pieces, which the parabola through three samples smooths over.
    let (worst, mean) = converging_error(100, false, 150.0, 400.0);
    eprintln!("cap 100 rings, 150–400 mm from the pole: max error {worst:.4}, mean {mean:.5}");
    let (flat_worst, flat_mean) = converging_error(100, true, 150.0, 400.0);
    eprintln!("disk 100 rings, 150–400 mm from the centre: max error {flat_worst:.4}, mean {flat_mean:.5}");
    assert!(worst < 0.14 && mean < 0.012, "cap: {worst}, mean {mean}");
    assert!(
        flat_worst < 0.11 && flat_mean < 0.011,
        "disk: {flat_worst}, mean {flat_mean}"
    );
}

/// `s` with its positions rounded to f32, as an STL stores them.
fn rounded_to_f32(s: &Shape) -> Shape {
    let positions = s.mesh.positions().iter();
    shape(
        positions.map(|p| p.map(|c| c as f32 as Real)).collect(),
        s.mesh.triangles().to_vec(),
    )
}

/// The accurate distance on a cap of radius `CAP_R` from its section by the plane
/// z = R cos 0.6 (checked as a field), against the analytic R·|θ − 0.6|: the largest error
/// within 50 mm of the section, and anywhere.
fn errors_from_the_plane_at_0_6(s: &Shape) -> (Real, Real) {
    let theta0: Real = 0.6;
    let src = GeodesicSource::Plane {
        point: Point3::new(CAP_R * libm::sin(theta0), 0.0, CAP_R * libm::cos(theta0)),
        normal: skinpath::math::Vector3::z(),
    };
    let analytic = |p: &Point3| CAP_R * (libm::acos((p.z / CAP_R).clamp(-1.0, 1.0)) - theta0).abs();
    let d = distance(s, &src, Method::Accurate).vertex_distance;
    check_field(s, &d);
    let (mut near, mut all): (Real, Real) = (0.0, 0.0);
    for (p, d) in s.mesh.positions().iter().zip(&d) {
        let e = (d - analytic(p)).abs();
        all = all.max(e);
        if analytic(p) < 50.0 {
            near = near.max(e);
        }
    }
    (near, all)
}

#[test]
fn plane_section_source_is_accurate_on_its_convex_side_too() {
    // The cap of 100 rings (60 000 triangles, edges of 10 mm) from its section by the plane
    // z = R cos 0.6 (through a ring of vertices): distance R·|θ − 0.6|. The section is
    // sampled where it crosses edges and at vertices, so two pieces often lie on one
    // straight line; rounded either way, the test of whether the curve turns towards a
    // vertex used to stop such a piece at that joint, and on the convex side, where the
    // fronts spread, vertices between the pieces their neighbours held were offered only
    // the pieces' ends: 0.56 mm too far within 50 mm of the section, then 0.16 mm; 0.047 mm
    // now (what is left is the same spreading between pieces that do turn, second order in
    // the edge: 0.043 mm at 500k triangles).
    // Rounded to f32 (as an STL stores them), the ring's vertices lie within rounding of the
    // plane, on either side: the section then passes within 1e-5 mm of each, sampled on
    // them, and each sample's face lies on one side of the curve. Only that face's corners
    // were seeded, so corners on the other side waited for a neighbour's piece that ended
    // short of them: 0.40 mm too far 3.5 mm from the section at 500k triangles (now 0.014),
    // here 0.067 mm within 50 mm of it (now 0.047, as with f64 positions), since the corners
    // of every face around such a sample are seeded.
    // Anywhere, with f32 positions: front interpolation around the pole went on only while
    // three quarters of a ring's distances were lowered; 31 rings out it lowered 54 of 186,
    // by up to 0.070 mm, and stopped, leaving the rings beyond 0.091 mm too long (0.058 now
    // that it goes on while the gain does). With f64 positions the ring's vertices lie on
    // the plane exactly, and the section touched each face round one of them at that vertex
    // only: a piece of no length, which the propagation takes for a point source (0.093 mm
    // too far; 0.070 mm 20 mm from the section at 500k triangles). Such pieces are dropped
    // now.
    let exact = cap(100, CAP_R, 1.0);
    let rounded = rounded_to_f32(&exact);
    for (name, s) in [("f64", exact), ("f32", rounded)] {
        let (near, all) = errors_from_the_plane_at_0_6(&s);
        eprintln!(
            "cap 100 rings ({name}) from a plane section: max error within 50 mm {near:.4}, \
             anywhere {all:.4}"
        );
        assert!(near < 0.055 && all < 0.07, "{name}: {near}, anywhere {all}");
    }
}

#[test]
fn plane_sections_between_vertices_follow_the_curve_past_short_pieces() {
    // The cap of 108 rings (70 000 triangles) from its section by the plane z = R cos 0.6,
    // between its rings 64 and 65: distance R·|θ − 0.6|. A piece of the section shorter than
    // the spacing of the vertices can be the nearest to a vertex a ring or two out on the
    // convex side while each of that vertex's neighbours holds a nearer piece of its own;
    // the piece they hold stops at its end there (the curve turns away), and the vertex got
    // that end: 0.60 mm too far 11 mm from the section. Vertices settled past such an end
    // now follow the curve's next pieces, carried with the one they hold.
    let (near, all) = from_the_plane_between_rings(108);
    assert!(near < 0.05 && all < 0.08, "{near}, anywhere {all}");
}

/// [`errors_from_the_plane_at_0_6`] on the cap of `rings` rings with f32 positions (the plane
/// then lies between rings), printed.
fn from_the_plane_between_rings(rings: usize) -> (Real, Real) {
    let s = rounded_to_f32(&cap(rings, CAP_R, 1.0));
    let (near, all) = errors_from_the_plane_at_0_6(&s);
    eprintln!(
        "cap {rings} rings from a plane between rings: max error within 50 mm {near:.4}, \
         anywhere {all:.4}"
    );
    (near, all)
}

/// From vertex `src`, the largest |accurate − exact| and the most the accurate distance falls
/// below exact (the accurate field checked as a field first).
fn against_exact(s: &Shape, src: u32) -> (Real, Real) {
    let source = GeodesicSource::Vertices(vec![src]);
    let e = distance(s, &source, Method::Exact).vertex_distance;
    let a = distance(s, &source, Method::Accurate).vertex_distance;
    check_field(s, &a);
    let off = a
        .iter()
        .zip(&e)
        .map(|(a, e)| (a - e).abs())
        .fold(0.0, Real::max);
    let below = a.iter().zip(&e).map(|(a, e)| e - a).fold(0.0, Real::max);
    (off, below)
}

/// The index in `pos` of each of `points`, points at the same place (to 1e-6) made one.
fn weld(
    points: &[Point3],
    pos: &mut Vec<Point3>,
    ids: &mut std::collections::HashMap<[i64; 3], u32>,
) -> Vec<u32> {
    points
        .iter()
        .map(|q| {
            let key = [q.x, q.y, q.z].map(|x| (x * 1e6).round() as i64);
            *ids.entry(key).or_insert_with(|| {
                pos.push(*q);
                pos.len() as u32 - 1
            })
        })
        .collect()
}

/// A closed box `a × b × c` (a thin plate when `c` is small), each face an `n × n` grid,
/// vertices shared along its edges, outward.
fn boxed(a: Real, b: Real, c: Real, n: usize) -> Shape {
    let faces: [([Real; 3], [Real; 3], [Real; 3]); 6] = [
        ([0., 0., 0.], [0., b, 0.], [a, 0., 0.]),
        ([0., 0., c], [a, 0., 0.], [0., b, 0.]),
        ([0., 0., 0.], [a, 0., 0.], [0., 0., c]),
        ([0., b, 0.], [0., 0., c], [a, 0., 0.]),
        ([0., 0., 0.], [0., 0., c], [0., b, 0.]),
        ([a, 0., 0.], [0., b, 0.], [0., 0., c]),
    ];
    let (mut pos, mut tri) = (Vec::<Point3>::new(), Vec::new());
    let mut ids = std::collections::HashMap::new();
    for (o, e1, e2) in faces {
        let (p, t) = grid(n, n, false, |u, v| {
            Point3::new(
                o[0] + u * e1[0] + v * e2[0],
                o[1] + u * e1[1] + v * e2[1],
                o[2] + u * e1[2] + v * e2[2],
            )
        });
        let map = weld(&p, &mut pos, &mut ids);
        tri.extend(t.iter().map(|t| t.map(|v| map[v as usize])));
    }
    shape(pos, tri)
}

#[test]
fn point_sources_on_boxes_never_undercut_the_exact_distance() {
    // Every shortest path on a cube is an unfolding across its edges, past its corners (cone
    // vertices, where turning a source about the vertex in one rotation misplaces it by a
    // right angle). The accurate method runs long near the corners (bends where no unfolded
    // ray is offered: up to 0.056 of a side at 3 × 3 cells a face, 0.029 at 8 × 8; before
    // the unfolding around sharp vertices, 0.081 from vertex 1 of the 3 × 3 cube) but never
    // short. (The real models' test checks a thin box of the 747 model, exact now.)
    for (name, s, max_off) in [
        ("cube 3", boxed(1.0, 1.0, 1.0, 3), 0.06),
        ("cube 8", boxed(1.0, 1.0, 1.0, 8), 0.03),
    ] {
        for src in [0, 1, 5] {
            let (off, below) = against_exact(&s, src);
            eprintln!("{name} from v{src}: max |accurate − exact| {off:.2e}, below {below:.2e}");
            assert!(below < 1e-9, "{name} from v{src}: {below} below exact");
            assert!(off <= max_off, "{name} from v{src}: {off} off exact");
        }
    }
}

#[test]
fn small_cornered_surfaces_get_the_exact_distance_and_smooth_ones_virtual_sources() {
    let run = |s: &Shape, method, exact_first_windows| {
        let params = DistanceParams {
            method,
            exact_first_windows,
            ..DistanceParams::default()
        };
        let src = GeodesicSource::Vertices(vec![1]);
        geodesic_distance(&s.mesh, &s.adjacency, &src, &params, &mut |_, _| {}).unwrap()
    };
    // A cube has corners (angle defect π/2): the exact method runs, and the field says so.
    let cube = boxed(1.0, 1.0, 1.0, 6);
    let exact = run(&cube, Method::Exact, None);
    let default = run(&cube, Method::Accurate, None);
    assert_eq!(default.method, Method::Exact);
    assert_eq!(default.windows, exact.windows);
    assert!(default.windows > 0);
    assert_eq!(default.vertex_distance, exact.vertex_distance);
    // Over its budget, the virtual sources answer, as when the exact method is not tried.
    let over = run(&cube, Method::Accurate, Some(exact.windows / 2));
    let virtual_only = run(&cube, Method::Accurate, Some(0));
    assert_eq!(over.method, Method::Accurate);
    assert_eq!(virtual_only.method, Method::Accurate);
    assert_eq!(over.windows, 0);
    assert_eq!(over.vertex_distance, virtual_only.vertex_distance);
    assert_ne!(virtual_only.vertex_distance, exact.vertex_distance);
    // A budget given is used as given (it counts the vertex events too).
    let given = run(&cube, Method::Accurate, Some(2 * exact.windows));
    assert_eq!(given.method, Method::Exact);
    // A sphere fine enough to have no corner: virtual sources.
    let sphere = cube_sphere(16, 100.0);
    let smooth = run(&sphere, Method::Accurate, None);
    assert_eq!(smooth.method, Method::Accurate);
    assert_eq!(smooth.windows, 0);
    assert_eq!(
        smooth.vertex_distance,
        run(&sphere, Method::Accurate, Some(0)).vertex_distance
    );
    assert_eq!(
        run(&sphere, Method::Accurate, Some(1 << 40)).method,
        Method::Exact
    );
}

/// The cap of `rings` rings without its faces whose centroids lie within 60 mm of the point
/// at θ = 0.5 (a hole 120 mm across), and the cap itself.
fn holed_cap(rings: usize) -> (Shape, Shape) {
    let s = cap(rings, CAP_R, 1.0);
    let centre = Point3::new(CAP_R * libm::sin(0.5), 0.0, CAP_R * libm::cos(0.5));
    let pos = s.mesh.positions().to_vec();
    let kept: Vec<[u32; 3]> = s
        .mesh
        .triangles()
        .iter()
        .copied()
        .filter(|t| {
            let m =
                (pos[t[0] as usize].coords + pos[t[1] as usize].coords + pos[t[2] as usize].coords)
                    / 3.0;
            (Point3::from(m) - centre).norm() > 60.0
        })
        .collect();
    (shape(pos, kept), s)
}

/// The point at θ = 0.8, φ = 0 of the caps above (beyond the hole from the pole), and the
/// section by the plane through it normal to the axis.
fn far_side() -> (Point3, GeodesicSource) {
    let point = Point3::new(CAP_R * libm::sin(0.8), 0.0, CAP_R * libm::cos(0.8));
    let plane = GeodesicSource::Plane {
        point,
        normal: skinpath::math::Vector3::z(),
    };
    (point, plane)
}

#[test]
fn small_surfaces_with_a_hole_get_the_exact_distance_and_tubes_virtual_sources() {
    // Virtual sources are held to the shadow a hole casts only near its rim (see the next
    // test), so a small surface with one gets the exact method first. The rim of a hole
    // turns the other way from an outer boundary. (Here 40 rings, 9,600 faces, to keep the
    // exact method quick in an unoptimised build.)
    let (holed, s) = holed_cap(40);
    let plane = far_side().1;
    let run = |s: &Shape, src: &GeodesicSource, method| {
        let params = DistanceParams {
            method,
            ..DistanceParams::default()
        };
        geodesic_distance(&s.mesh, &s.adjacency, src, &params, &mut |_, _| {}).unwrap()
    };
    let default = run(&holed, &plane, Method::Accurate);
    assert_eq!(default.method, Method::Exact);
    assert_eq!(
        default.vertex_distance,
        run(&holed, &plane, Method::Exact).vertex_distance
    );
    // A tube's rims do not turn: virtual sources, exact there.
    let tube = cylinder(48, 12);
    let field = run(
        &tube,
        &GeodesicSource::Boundary {
            loop_index: Some(0),
        },
        Method::Accurate,
    );
    assert_eq!(field.method, Method::Accurate);
    // Nor does the cap without its hole.
    assert_eq!(run(&s, &plane, Method::Accurate).method, Method::Accurate);
}

#[test]
fn virtual_sources_go_round_a_hole_not_across_it() {
    // Virtual sources alone (no exact first try), from the far side of the hole, against
    // the exact method. Before their rays were walked back near the rim and bends at the
    // rim held to its faces (see `virtual_source/shadow.rs`), they went straight across the
    // hole: 16.7 mm short behind it from the plane section, 6.1 mm from the vertex (now
    // 0.22 and 0.10). What is left is the rim's jaggedness (the exact paths wrap round its
    // notches; the distances too long by up to 0.35 mm were so before).
    let (holed, _) = holed_cap(40);
    let (point, plane) = far_side();
    let p = holed.mesh.positions();
    let vertex = (0..p.len())
        .min_by(|&a, &b| (p[a] - point).norm().total_cmp(&(p[b] - point).norm()))
        .unwrap();
    for (name, source, most_short) in [
        ("plane", plane, 0.3),
        ("vertex", GeodesicSource::Vertices(vec![vertex as u32]), 0.2),
    ] {
        let run = |method, exact_first_windows| {
            let params = DistanceParams {
                method,
                exact_first_windows,
                ..DistanceParams::default()
            };
            geodesic_distance(
                &holed.mesh,
                &holed.adjacency,
                &source,
                &params,
                &mut |_, _| {},
            )
            .unwrap()
        };
        let exact = run(Method::Exact, None).vertex_distance;
        let field = run(Method::Accurate, Some(0));
        assert_eq!(field.method, Method::Accurate);
        let (mut short, mut long, mut reached) = (0.0 as Real, 0.0 as Real, 0);
        for (a, e) in field.vertex_distance.iter().zip(&exact) {
            if e.is_finite() {
                assert!(
                    a.is_finite(),
                    "{name}: a vertex the exact method reaches is reached"
                );
                short = short.max(e - a);
                long = long.max(a - e);
                reached += 1;
            }
        }
        assert!(reached > 4000, "{name}: {reached}");
        assert!(short < most_short, "{name}: {short} mm short of exact");
        assert!(long < 0.5, "{name}: {long} mm beyond exact");
    }
}

/// The accurate method's distances on `s` from `source` (virtual sources: no exact first
/// try) against the exact method's: most short, most beyond, and how many vertices the
/// exact path reaches longer than `straight` (the shadow of a hole).
fn against_exact_in_the_shadow(
    s: &Shape,
    source: &GeodesicSource,
    straight: impl Fn(&Point3) -> Real,
) -> (Real, Real, usize) {
    let exact = distance(s, source, Method::Exact).vertex_distance;
    let field = distance(s, source, Method::Accurate);
    assert_eq!(field.method, Method::Accurate);
    let (mut short, mut long, mut shadowed) = (0.0 as Real, 0.0 as Real, 0);
    let p = s.mesh.positions();
    for (v, (a, e)) in field.vertex_distance.iter().zip(&exact).enumerate() {
        if e.is_finite() {
            short = short.max(e - a);
            long = long.max(a - e);
            shadowed += usize::from(*e > straight(&p[v]) + 1e-6);
        }
    }
    (short, long, shadowed)
}

#[test]
fn a_point_source_keeps_to_a_holes_shadow_far_beyond_its_rim() {
    // A plate of 40 × 80 unit squares without the squares whose centres lie within 3 of
    // (20, 20); the source is the vertex (20, 12), so the hole's shadow runs on for some 57
    // rings, beyond the rings near the rim where every offer is walked back. At its edges a
    // vertex was offered the source straight through the hole by a lit neighbour and handed
    // it on inwards (0.0098 short of the exact distance at (2, 53)); now an offer whose
    // crossed edge ends at a vertex whose path bent at a rim the offer's did not is walked
    // back all the way (see `virtual_source/shadow.rs`).
    let (s, at) = holed_plate(40, 80, (20.0, 20.0), 3.0);
    let source = GeodesicSource::Vertices(vec![at(20, 12)]);
    // Behind the hole the exact path goes round it: longer than the straight line.
    let (short, long, shadowed) =
        against_exact_in_the_shadow(&s, &source, |p| (p - Point3::new(20.0, 12.0, 0.0)).norm());
    assert!(shadowed > 1000, "{shadowed} vertices in the shadow");
    assert!(short < 1e-3, "{short} short of exact");
    assert!(long < 1e-3, "{long} beyond exact");
}

#[test]
fn a_source_curve_keeps_to_a_holes_shadow_far_beyond_its_rim() {
    // The plate above with a wider hole (radius 6, its centre off the grid's lines), and a
    // source curve: its section by a plane at a slant to the grid. The shadow runs on for
    // some 55 rings beyond the rim, beyond the rings near it where every offer is walked
    // back. Lit vertices at the shadow's edges handed the curve's rays straight through the
    // hole inwards (0.70 short of the exact distance at (21, 46)); the walk all the way back
    // at a shadow's edge now holds source curves as it holds point sources (0.003). The
    // jagged rim's notches leave distances up to 0.11 too long, before and after.
    let (s, _) = holed_plate(40, 80, (20.35, 20.0), 6.0);
    let normal = skinpath::math::Vector3::new(0.03, 1.0, 0.0).normalize();
    let point = Point3::new(0.0, 8.5, 0.0);
    let source = GeodesicSource::Plane { point, normal };
    let (short, long, shadowed) =
        against_exact_in_the_shadow(&s, &source, |p| (p - point).dot(&normal).abs());
    assert!(shadowed > 500, "{shadowed} vertices in the shadow");
    assert!(short < 0.01, "{short} short of exact");
    assert!(long < 0.2, "{long} beyond exact");
}

#[test]
fn rays_along_a_row_of_edges_are_held_to_a_holes_shadow() {
    // A plate of 60 × 80 with a hole of radius 10, from its section by the plane y = 6.5,
    // parallel to the rows of the grid: the rays from the curve to the vertices run along
    // the columns of edges, through vertices, and the walk back found no edge to cross
    // beyond the first vertex, so it let every such ray through: distances 3.6 short of the
    // exact ones behind the hole (a point source at (25, 8) beside it, 0.073). A ray through
    // a vertex is now walked as if it passed beside it.
    let (s, at) = holed_plate(60, 80, (30.35, 30.0), 10.0);
    let point = Point3::new(0.0, 6.5, 0.0);
    let plane = GeodesicSource::Plane {
        point,
        normal: skinpath::math::Vector3::y(),
    };
    let (short, long, shadowed) = against_exact_in_the_shadow(&s, &plane, |p| (p.y - 6.5).abs());
    assert!(shadowed > 500, "{shadowed} vertices in the shadow");
    assert!(short < 1e-3, "{short} short of exact");
    assert!(long < 1e-3, "{long} beyond exact");
    let from = Point3::new(25.0, 8.0, 0.0);
    let vertex = GeodesicSource::Vertices(vec![at(25, 8)]);
    let (short, long, shadowed) = against_exact_in_the_shadow(&s, &vertex, |p| (p - from).norm());
    assert!(shadowed > 500, "{shadowed} vertices in the shadow");
    assert!(short < 1e-3, "{short} short of exact");
    assert!(long < 0.2, "{long} beyond exact");
}

#[test]
fn a_path_round_a_hole_does_not_hold_off_a_shorter_one() {
    // A plate of 60 × 80 with a hole of radius 6, from the vertex (31, 12) before it. A
    // vertex beside the shadow whose path went round the hole a little too long made the
    // check against the crossed edge's other end refuse every better source offered past
    // it, and the excess spread: 0.118 too long, 183 vertices by more than 0.01. The check
    // now leaves out an other end whose path bent at a hole's rim: 0.019, 17 vertices.
    let (s, at) = holed_plate(60, 80, (30.35, 30.0), 6.0);
    let from = Point3::new(31.0, 12.0, 0.0);
    let source = GeodesicSource::Vertices(vec![at(31, 12)]);
    let (short, long, shadowed) = against_exact_in_the_shadow(&s, &source, |p| (p - from).norm());
    assert!(shadowed > 1000, "{shadowed} vertices in the shadow");
    assert!(short < 1e-3, "{short} short of exact");
    assert!(long < 0.05, "{long} beyond exact");
}

/// A flat annulus between a hole of radius 10 with `rim` sides and an outer polygon of
/// radius 40 with `outer` sides, the vertices of the outer polygon turned by half a side,
/// triangulated in one band of long triangles (fans from each outer vertex to the rim, as
/// CAD exports the faces round a hole).
fn fanned_annulus(rim: usize, outer: usize) -> Shape {
    let polygon = |n: usize, r: Real, turn: Real| -> Vec<Point3> {
        (0..n)
            .map(|i| {
                let t = 2.0 * PI * (i as Real + turn) / n as Real;
                Point3::new(r * t.cos(), r * t.sin(), 0.0)
            })
            .collect()
    };
    let mut positions = polygon(rim, 10.0, 0.0);
    positions.extend(polygon(outer, 40.0, 0.5));
    // Zip the two polygons by angle: each step takes the next vertex of the one whose next
    // vertex comes first, so every vertex is taken once and the loop ends.
    let angle = |i: usize, n: usize, turn: Real| 2.0 * PI * (i as Real + turn) / n as Real;
    let (mut i, mut j) = (0, 0);
    let mut triangles = Vec::new();
    let (a, b) = (
        |i: usize| (i % rim) as u32,
        |j: usize| (rim + j % outer) as u32,
    );
    while i < rim || j < outer {
        if j == outer || (i < rim && angle(i + 1, rim, 0.0) < angle(j + 1, outer, 0.5)) {
            triangles.push([a(i), a(i + 1), b(j)]);
            i += 1;
        } else {
            triangles.push([a(i), b(j + 1), b(j)]);
            j += 1;
        }
    }
    shape(positions, triangles)
}

#[test]
fn a_hole_meshed_as_a_fan_of_long_triangles_is_passed_along_its_rim() {
    // From an outer vertex, the paths to the far side go round the hole, bending at its
    // rim, and leave it towards each outer vertex at a rim vertex far from the rim vertices
    // beside it. A vertex behind the hole was offered the path bending at a rim vertex by a
    // neighbour across a long edge whose other end lies further along the rim; the straight
    // line to that end crosses the hole, so the offer seemed to undercut the distance settled
    // there and was refused as an unfolding past a cone vertex: 3.03 beyond the exact
    // distance (of up to 78) with 48 sides, 4.0 with 96. With that check leaving out the rims
    // of holes, 0.27 and 0.28: the path that leaves the rim where it should was held by no
    // neighbour. Now rim vertices offer it too.
    for (rim, outer) in [(48, 8), (96, 8)] {
        let s = fanned_annulus(rim, outer);
        let source = GeodesicSource::Vertices(vec![rim as u32]);
        let exact = distance(&s, &source, Method::Exact).vertex_distance;
        let field = distance(&s, &source, Method::Accurate);
        assert_eq!(field.method, Method::Accurate);
        let (mut short, mut long) = (0.0 as Real, 0.0 as Real);
        for (a, e) in field.vertex_distance.iter().zip(&exact) {
            short = short.max(e - a);
            long = long.max(a - e);
        }
        assert!(short < 1e-6, "{rim} sides: {short} short of exact");
        assert!(long < 1e-6, "{rim} sides: {long} beyond exact");
    }
}

/// A closed can of radius 1 and height `h` around z with `around` sides, its caps in `caps`
/// rings, its side in `rings`; each ring turned by `twist` radians from the one before (the
/// side's quads then fold along their diagonals, and the rim is a crease of varying angle).
fn can(around: usize, caps: usize, rings: usize, h: Real, twist: Real) -> Shape {
    let rows = 2 * caps + rings;
    let (p, t) = grid(around, rows, true, |u, v| {
        let j = (v * rows as Real).round() as usize;
        let (r, z) = if j <= caps {
            (j as Real / caps as Real, 0.0)
        } else if j <= caps + rings {
            (1.0, h * (j - caps) as Real / rings as Real)
        } else {
            ((rows - j) as Real / caps as Real, h)
        };
        let a = 2.0 * PI * u + twist * j as Real;
        Point3::new(r * libm::cos(a), r * libm::sin(a), z)
    });
    // The rings of radius 0 are the caps' centres: one vertex each, their faces dropped.
    let (mut pos, mut ids) = (Vec::new(), std::collections::HashMap::new());
    let map = weld(&p, &mut pos, &mut ids);
    let tri = t
        .iter()
        .map(|t| t.map(|v| map[v as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect();
    shape(pos, tri)
}

#[test]
fn point_sources_over_the_rim_of_twisted_cans_keep_near_the_exact_distance() {
    // Paths from the cap cross its rim, a crease of 90° whose vertices have large angle
    // defects (cones), onto a side whose faces fold. A point source unfolded round a rim
    // vertex holds only for the rays between the rim vertices (its wedge), and a settled rim
    // vertex's source is not turned about it to be offered again (it was offered unfolded):
    // before both, the accurate distances fell up to 0.146 below exact on the 7-sided can
    // (radius 1, edges about 0.5) and 0.030 below on the 16-sided one. What is left below
    // comes from the folds of the side, each within the misplacement the wedges allow (half
    // a mean edge); bends where no unfolded ray reaches a vertex run long instead.
    for (name, s, most_below) in [
        ("7 sides", can(7, 2, 3, 0.7, 0.2), 0.075),
        ("16 sides", can(16, 3, 5, 1.0, 0.1), 0.01),
    ] {
        for src in [0, 5, 17, 40] {
            let (off, below) = against_exact(&s, src);
            eprintln!(
                "can of {name} from v{src}: max |accurate − exact| {off:.4}, below {below:.4}"
            );
            assert!(
                below < most_below,
                "can of {name} from v{src}: {below} below exact"
            );
            assert!(off < 0.2, "can of {name} from v{src}: {off} off exact");
        }
    }
}

/// The largest patches of the real aircraft meshes, segmented with the paper's parameters,
/// their boundary as the source: against independent bounds (no path on the surface is shorter
/// than the straight line to the nearest boundary point) and against the exact method.
#[cfg(not(target_arch = "wasm32"))]
mod real_models {
    use super::*;
    use skinpath::geodesic::boundary_loops;
    use skinpath::mesh::{prepare_mesh, read_stl_with_progress, ImportedMesh};
    use skinpath::segment::{segment, SegmentParams};

    /// A real model from the shared model folder, read and prepared as the page does.
    fn load(name: &str) -> ImportedMesh {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/models")
            .join(name);
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        prepare_mesh(
            read_stl_with_progress(&bytes, &mut |_, _| {}).unwrap(),
            &mut |_, _| {},
        )
        .unwrap()
    }

    /// The distance from `source` on the whole model by `method`, the accurate method's exact
    /// try given `exact_first_windows` (see [`DistanceParams`]).
    fn distance(
        m: &ImportedMesh,
        source: &GeodesicSource,
        method: Method,
        exact_first_windows: Option<u64>,
    ) -> skinpath::geodesic::DistanceField {
        let params = DistanceParams {
            method,
            exact_first_windows,
            ..DistanceParams::default()
        };
        geodesic_distance(&m.mesh, &m.adjacency, source, &params, &mut |_, _| {}).unwrap()
    }

    /// Shortest distance from `x` to the segment `a`–`b`.
    fn to_segment(x: &Point3, a: &Point3, b: &Point3) -> Real {
        let ab = b - a;
        let t = ((x - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
        (x - (a + ab * t)).norm()
    }

    #[test]
    fn a_heat_shield_with_holes_gets_the_exact_distance_from_a_plane_section() {
        // Orion's largest patch is its heat shield: 5,694 faces, smooth (no corner), with six
        // holes about 1.3 ft across. From its section by the plane x = 0 the virtual sources
        // went straight across a hole, up to 1.2 ft short of the exact distance behind it
        // (0.50 ft since their rays are walked back near the rims: the holes span a few faces,
        // and sources carried on past them turn into their shadows further on); the holes
        // send the accurate method to the exact one first (71 windows a face here, within
        // the budget of a small surface).
        let m = load("orion_51736_nasa.stl");
        let seg = segment(&m.adjacency, &m.geometry, &SegmentParams::default()).unwrap();
        let faces: Vec<u32> = (0..seg.patch_of.len() as u32)
            .filter(|&f| seg.patch_of[f as usize] == 0)
            .collect();
        assert_eq!(faces.len(), 5694);
        let p = m.mesh.positions();
        let near = faces
            .iter()
            .flat_map(|&f| m.mesh.triangles()[f as usize])
            .min_by(|&a, &b| p[a as usize].x.abs().total_cmp(&p[b as usize].x.abs()))
            .unwrap();
        let point = Point3::new(0.0, p[near as usize].y, p[near as usize].z);
        let source = GeodesicSource::Plane {
            point,
            normal: skinpath::math::Vector3::x(),
        };
        let run = |method, exact_first_windows| {
            let params = DistanceParams {
                method,
                faces: Some(faces.clone()),
                exact_first_windows,
                ..DistanceParams::default()
            };
            geodesic_distance(&m.mesh, &m.adjacency, &source, &params, &mut |_, _| {}).unwrap()
        };
        let exact = run(Method::Exact, None);
        let default = run(Method::Accurate, None);
        assert_eq!(default.method, Method::Exact);
        assert_eq!(default.vertex_distance, exact.vertex_distance);
        let virtual_only = run(Method::Accurate, Some(0));
        let short = virtual_only
            .vertex_distance
            .iter()
            .zip(&exact.vertex_distance)
            .filter(|(a, e)| a.is_finite() && e.is_finite())
            .map(|(a, e)| e - a)
            .fold(0.0, Real::max);
        eprintln!("Orion heat shield from x = 0: virtual sources alone up to {short:.3} ft short");
        assert!(short < 0.6, "{short} ft short");
    }

    #[test]
    fn patch_distances_never_undercut_the_straight_line_and_stay_near_exact() {
        // Before the run-on of source pieces was bounded by the curve beyond their ends, the
        // accurate distances fell below the straight line by up to 0.8 (wing-body), 0.36
        // (BWB) and 0.30 (747) of a mean edge, and their mean distance from exact was up
        // to 0.06 of an edge.
        for name in [
            "airplane_10796_pymeshlab.stl",
            "wingbody_79868_flow360.stl",
            "b747_14062_flightgear.stl",
            "bwb_4464_pygeo_ascii.stl",
            "orion_51736_nasa.stl",
        ] {
            let m = load(name);
            let seg = segment(&m.adjacency, &m.geometry, &SegmentParams::default()).unwrap();
            let p = m.mesh.positions();
            for id in 0..seg.patches.len().min(2) {
                let faces: Vec<u32> = (0..seg.patch_of.len() as u32)
                    .filter(|&f| seg.patch_of[f as usize] == id as i32)
                    .collect();
                let mut used = vec![false; p.len()];
                let (mut edge_sum, mut edges) = (0.0, 0);
                for &f in &faces {
                    let t = m.mesh.triangles()[f as usize];
                    for k in 0..3 {
                        used[t[k] as usize] = true;
                        edge_sum += (p[t[k] as usize] - p[t[(k + 1) % 3] as usize]).norm();
                        edges += 1;
                    }
                }
                let edge = edge_sum / edges as Real;
                let loops = boundary_loops(&m.mesh, &m.adjacency, Some(&faces)).unwrap();
                let run = |method| {
                    let params = DistanceParams {
                        method,
                        faces: Some(faces.clone()),
                        exact_first_windows: Some(0),
                        ..DistanceParams::default()
                    };
                    geodesic_distance(&m.mesh, &m.adjacency, &boundary(), &params, &mut |_, _| {})
                        .unwrap()
                        .vertex_distance
                };
                let (accurate, exact) = (run(Method::Accurate), run(Method::Exact));
                let (mut below, mut off_max, mut off_sum, mut n) =
                    (0.0 as Real, 0.0 as Real, 0.0, 0);
                for v in (0..p.len()).filter(|&v| used[v]) {
                    let straight = loops
                        .iter()
                        .flat_map(|l| (0..l.len()).map(move |i| (l[i], l[(i + 1) % l.len()])))
                        .map(|(a, b)| to_segment(&p[v], &p[a as usize], &p[b as usize]))
                        .fold(Real::INFINITY, Real::min);
                    below = below.max(straight - accurate[v]);
                    assert!(
                        exact[v] >= straight - 1e-9 * edge,
                        "{name} patch {id}: exact undercuts"
                    );
                    let off = (accurate[v] - exact[v]).abs();
                    off_max = off_max.max(off);
                    off_sum += off;
                    n += 1;
                }
                let off_mean = off_sum / n as Real;
                println!(
                    "{name} patch {id} ({} faces, edge {edge:.3}): below the straight line {:.4} \
                     edge, off exact max {:.4} / mean {:.5} edge",
                    faces.len(),
                    below / edge,
                    off_max / edge,
                    off_mean / edge
                );
                assert!(
                    below <= 0.02 * edge,
                    "{name} patch {id}: {below} below the straight line"
                );
                assert!(
                    off_mean <= 0.02 * edge,
                    "{name} patch {id}: mean {off_mean} off exact"
                );
                assert!(
                    off_max <= 0.35 * edge,
                    "{name} patch {id}: {off_max} off exact"
                );
            }
        }
    }

    #[test]
    fn plane_sections_across_whole_coarse_models_keep_near_the_exact_distance() {
        // Pieces of a section carried along a fuselage and turned about the vertices of a
        // wing root drifted: before a sharp vertex far from the curve took its piece as a
        // point source at the piece's foot, the virtual sources fell short of the exact
        // distance by up to 5.8–19.0 mean edges on the airplane (now 0.09–2.3) and 0.14–2.1
        // on the 747 (now 0.02–0.10), and lay a mean 0.81–2.30 edge off exact on the
        // airplane (now 0.05–0.15), planes at a tenth to nine tenths of the length. Bounds
        // in mean edges: the most short, the mean off.
        for (name, max_short, max_mean) in [
            ("airplane_10796_pymeshlab.stl", 3.0, 0.2),
            ("b747_14062_flightgear.stl", 0.25, 0.05),
        ] {
            let m = load(name);
            let p = m.mesh.positions();
            let (lo, hi) = m.mesh.bounding_box();
            let (mut edge_sum, mut edges) = (0.0, 0);
            for t in m.mesh.triangles() {
                for k in 0..3 {
                    edge_sum += (p[t[k] as usize] - p[t[(k + 1) % 3] as usize]).norm();
                    edges += 1;
                }
            }
            let edge = edge_sum / edges as Real;
            for f in [0.1, 0.3, 0.5, 0.7, 0.9] {
                let source = GeodesicSource::Plane {
                    point: Point3::new(
                        lo.x + f * (hi.x - lo.x),
                        0.5 * (lo.y + hi.y),
                        0.5 * (lo.z + hi.z),
                    ),
                    normal: skinpath::math::Vector3::x(),
                };
                let (accurate, exact) = (
                    distance(&m, &source, Method::Accurate, Some(0)).vertex_distance,
                    distance(&m, &source, Method::Exact, None).vertex_distance,
                );
                let (mut short, mut off_sum, mut n) = (0.0 as Real, 0.0, 0);
                for (a, e) in accurate.iter().zip(&exact) {
                    assert_eq!(a.is_finite(), e.is_finite(), "{name} at {f}");
                    if e.is_finite() {
                        short = short.max(e - a);
                        off_sum += (a - e).abs();
                        n += 1;
                    }
                }
                let off_mean = off_sum / n as Real;
                println!(
                    "{name}, plane at {f} of the length (edge {edge:.3}): short of exact by \
                     {:.3} edge at most, off by {:.4} edge on average",
                    short / edge,
                    off_mean / edge
                );
                assert!(short <= max_short * edge, "{name} at {f}: {short} short");
                assert!(
                    off_mean <= max_mean * edge,
                    "{name} at {f}: mean {off_mean} off"
                );
            }
        }
    }

    #[test]
    fn a_small_cornered_model_gets_the_exact_distance_from_a_plane_section() {
        // Orion (51,736 faces) from its section by the plane at three tenths of its length:
        // the exact method takes 98 windows per face, over the accurate method's budget
        // before it was 192 per face (64, at least 2²²), and the virtual sources answered
        // up to 1.97 ft short.
        let m = load("orion_51736_nasa.stl");
        let (lo, hi) = m.mesh.bounding_box();
        let source = GeodesicSource::Plane {
            point: Point3::new(
                lo.x + 0.3 * (hi.x - lo.x),
                0.5 * (lo.y + hi.y),
                0.5 * (lo.z + hi.z),
            ),
            normal: skinpath::math::Vector3::x(),
        };
        let (default, exact) = (
            distance(&m, &source, Method::Accurate, None),
            distance(&m, &source, Method::Exact, None),
        );
        assert_eq!(default.method, Method::Exact);
        assert!(default.windows > 64 * m.mesh.triangle_count() as u64);
        assert!(default
            .vertex_distance
            .iter()
            .zip(&exact.vertex_distance)
            .all(|(a, b)| a == b || !a.is_finite() && !b.is_finite()));
    }

    /// Bounds (in mean edges) for a point source carried across a whole coarse model: no
    /// distance below the straight line from the source vertex (the solver keeps to it, up
    /// to rounding), and a mean near the exact method.
    const MEAN_BOUND: Real = 0.2;
    const BELOW_BOUND: Real = 1e-6;

    #[test]
    fn an_exact_try_on_course_to_overrun_its_budget_gives_way_early() {
        // From vertex 0 (the nose) of the wing-body model the exact method takes 161 windows
        // per face: given a budget of 64 per face (the accurate method's before it was 192),
        // virtual sources answer. The exact try gives up once on course for 1.5 times its
        // budget, with about a quarter of the vertices reached (at the budget itself it would
        // have reached half).
        let m = load("wingbody_79868_flow360.stl");
        let source = GeodesicSource::Vertices(vec![0]);
        let mut fractions = Vec::new();
        let budget = DistanceParams {
            exact_first_windows: Some(64 * m.mesh.triangle_count() as u64),
            ..DistanceParams::default()
        };
        let field = geodesic_distance(&m.mesh, &m.adjacency, &source, &budget, &mut |_, f| {
            fractions.push(f)
        })
        .unwrap();
        assert_eq!(field.method, Method::Accurate);
        assert_eq!(field.windows, 0);
        // The exact try reports the share of vertices it reached; the virtual sources then
        // report their end (this mesh has too few vertices for reports between).
        assert_eq!(fractions.last(), Some(&1.0));
        let given_up_at = fractions
            .iter()
            .copied()
            .filter(|&f| f < 1.0)
            .fold(0.0, f64::max);
        assert!(
            given_up_at > 0.1 && given_up_at < 0.35,
            "the exact try reached {given_up_at} of the vertices"
        );
        let virtual_only = DistanceParams {
            exact_first_windows: Some(0),
            ..DistanceParams::default()
        };
        let v = geodesic_distance(
            &m.mesh,
            &m.adjacency,
            &source,
            &virtual_only,
            &mut |_, _| {},
        )
        .unwrap();
        assert_eq!(field.vertex_distance, v.vertex_distance);
    }

    #[test]
    fn point_sources_on_whole_coarse_models_never_undercut_the_straight_line() {
        // Before point sources were unfolded across the faces around sharp vertices and
        // offers were checked against the far end of the edge they cross, the accurate
        // distances from vertex 0 of the airplane fell 3.1 edges below the straight line and
        // lay a mean 0.91 edge off exact (now 0.08); on the BWB from vertex 500 7.6 edges
        // below (an unfolding carried round the trailing edge of its wing, then the focal
        // patches), on the 747's thin box (vertex 0) 0.29 (now exact).
        for (name, sources) in [
            ("airplane_10796_pymeshlab.stl", vec![0u32, 1000, 3000]),
            ("bwb_4464_pygeo_ascii.stl", vec![0, 10, 500, 1000, 2000]),
            ("b747_14062_flightgear.stl", vec![0, 1000, 3000]),
        ] {
            let m = load(name);
            let p = m.mesh.positions();
            for src in sources {
                let source = GeodesicSource::Vertices(vec![src]);
                let run = |method, exact_first_windows| {
                    distance(&m, &source, method, exact_first_windows)
                };
                let (accurate, exact) = (
                    run(Method::Accurate, Some(0)).vertex_distance,
                    run(Method::Exact, None).vertex_distance,
                );
                // Left to itself, the accurate method answers with the exact distance on
                // these small cornered models.
                let default = run(Method::Accurate, None);
                assert_eq!(default.method, Method::Exact, "{name} from {src}");
                assert!(
                    default
                        .vertex_distance
                        .iter()
                        .zip(&exact)
                        .all(|(a, b)| a == b || !a.is_finite() && !b.is_finite()),
                    "{name} from {src}: not the exact distance"
                );
                // Mean edge of the faces reached.
                let (mut edge_sum, mut edges) = (0.0, 0);
                for t in m.mesh.triangles() {
                    if t.iter().all(|&v| exact[v as usize].is_finite()) {
                        for k in 0..3 {
                            edge_sum += (p[t[k] as usize] - p[t[(k + 1) % 3] as usize]).norm();
                            edges += 1;
                        }
                    }
                }
                let edge = edge_sum / edges as Real;
                let (mut below, mut off_sum, mut off_max, mut n) =
                    (0.0 as Real, 0.0, 0.0 as Real, 0);
                for v in (0..p.len()).filter(|&v| exact[v].is_finite()) {
                    assert!(
                        accurate[v].is_finite(),
                        "{name} from {src}: v{v} not reached"
                    );
                    let straight = (p[v] - p[src as usize]).norm();
                    below = below.max(straight - accurate[v]);
                    let off = (accurate[v] - exact[v]).abs();
                    off_sum += off;
                    off_max = off_max.max(off);
                    n += 1;
                }
                let off_mean = off_sum / n as Real;
                println!(
                    "{name} from v{src} ({n} vertices, edge {edge:.3}): below the straight line \
                     {:.2e} edge, off exact max {:.4} / mean {:.5} edge",
                    below / edge,
                    off_max / edge,
                    off_mean / edge
                );
                assert!(
                    below <= BELOW_BOUND * edge,
                    "{name} from {src}: {below} below the straight line"
                );
                assert!(
                    off_mean <= MEAN_BOUND * edge,
                    "{name} from {src}: mean {off_mean} off exact"
                );
            }
        }
    }
}

#[test]
fn carried_pieces_do_not_outrun_the_curve_far_from_it() {
    // The cap of 158 rings (150 000 triangles, f32 positions) from its section by the plane
    // at θ = 0.6, between rings. A vertex settled past the end of its piece takes the next
    // piece of the curve carried rigidly with the one it holds (see `follow.rs`); taking it
    // for any gain let such carried copies win by the difference between two copies of a
    // piece, ever further from the curve: 0.031 mm too far beyond 50 mm of it, where the
    // error within 50 mm is 0.017; a carry now has to gain a thousandth of an edge, and the
    // far side keeps below the near one (0.018 mm anywhere).
    let (near, all) = from_the_plane_between_rings(158);
    assert!(all < 0.024, "{near}, anywhere {all}");
}

// Native only: 500k triangles take half a minute in an unoptimised WebAssembly build; the
// WebAssembly tests run the same code on the smaller caps above.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn plane_section_between_vertices_keeps_to_a_hundredth_of_a_millimetre_at_500k() {
    // The cap of 289 rings (500 000 triangles, f32 positions) from its section by the plane
    // at θ = 0.6, between rings: where the exact method is within 0.0052 mm of R·|θ − 0.6|,
    // the accurate one must keep within 0.01 mm (the bar where the mesh is that fine).
    // On the concave side a piece runs on along its line past its end, which lies about
    // u²/2ρ further from the vertex than the curve u past it: 0.0094 mm too far where a
    // vertex's foot lay a few pieces past its own; vertices past any end now follow the
    // curve (0.0083 mm).
    let (near, all) = from_the_plane_between_rings(289);
    assert!(all < 0.009, "{near}, anywhere {all}");
}

#[test]
fn a_section_across_a_hole_is_not_carried_over_its_rim() {
    // A plate of 50 × 70 with a hole of radius 11.9, and its section by a plane that passes
    // through the hole near its rim: the curve stops at the rim on both sides of the hole.
    // The rays from a piece's end on the rim cut across the hole's corner and came back to
    // the surface within a mean edge of the piece, which the walk back allowed to every foot
    // on a source curve (for a piece run on past its end, which lies off the surface): 0.27
    // short of the exact distance along the rim beyond. A foot on the piece itself now gets
    // a tenth of that where the ray leaves through a hole's rim: 0.000.
    let (s, _) = holed_plate(50, 70, (32.7, 55.6), 11.9);
    let angle: Real = 2.909;
    let normal = skinpath::math::Vector3::new(angle.cos(), angle.sin(), 0.0);
    let point = Point3::new(24.28, 69.21, 0.0);
    let source = GeodesicSource::Plane { point, normal };
    let (short, long, shadowed) =
        against_exact_in_the_shadow(&s, &source, |p| (p - point).dot(&normal).abs());
    assert!(shadowed > 100, "{shadowed} vertices in the shadow");
    assert!(short < 0.01, "{short} short of exact");
    assert!(long < 0.2, "{long} beyond exact");
}

#[test]
fn a_point_sources_ray_across_a_corner_of_a_hole_is_refused() {
    // A gently curved plate (a paraboloid) of 50 × 70 with a hole of radius 4.8, from the
    // vertex (45, 61). A rim vertex's point source was offered across a corner of the hole:
    // its ray left the surface a little over an edge from the source, within the mean edge
    // the walk back allowed every foot, and the distances behind the corner came out 0.179
    // short of the exact ones. A point source's ray that leaves the surface is now kept only
    // where going round the end of the edge it left by would cost under 0.05 mean edge.
    let (s, at) = holed_surface(50, 70, (34.0, 57.6), 4.8, |x, y| {
        0.002 * ((x - 25.0).powi(2) + (y - 35.0).powi(2))
    });
    let source = GeodesicSource::Vertices(vec![at(45, 61)]);
    let from = s.mesh.positions()[at(45, 61) as usize];
    // (On a curved plate every geodesic is longer than the chord: no shadow count here.)
    let (short, long, _) = against_exact_in_the_shadow(&s, &source, |p| (p - from).norm());
    assert!(short < 0.01, "{short} short of exact");
    assert!(long < 0.2, "{long} beyond exact");
}
