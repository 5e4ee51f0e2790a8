//! Timing and window counts of the exact geodesic method beside the mesh method:
//! `cargo run --release --example geodesic_exact -- cylinder [around] [along]` (ring and
//! generator sources, error against the unfolded answer) or
//! `cargo run --release --example geodesic_exact -- height [cell]` (the 60 × 50 × 40 height
//! field, a source curve across it; mesh method against exact on the same mesh).

use skinpath::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, Method};
use skinpath::math::{Point3, Real};
use skinpath::mesh::{FaceAdjacency, TriMesh};
use std::f64::consts::PI;
use std::time::Instant;

#[path = "../tests/common/geodesic_shapes.rs"]
mod shapes;
use shapes::height;

/// The shared test grid as a mesh.
fn grid(nu: usize, nv: usize, wrap: bool, f: impl Fn(Real, Real) -> Point3) -> TriMesh {
    let (positions, triangles) = shapes::grid(nu, nv, wrap, f);
    TriMesh::new(positions, triangles).expect("valid mesh")
}

fn run(
    mesh: &TriMesh,
    adjacency: &FaceAdjacency,
    src: &GeodesicSource,
    method: Method,
) -> (Vec<Real>, f64, u64) {
    let params = DistanceParams {
        method,
        ..DistanceParams::default()
    };
    let t0 = Instant::now();
    let f = geodesic_distance(mesh, adjacency, src, &params, &mut |_, _| {}).expect("distance");
    (f.vertex_distance, t0.elapsed().as_secs_f64(), f.windows)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: Real| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (r, len) = (shapes::R, shapes::LEN);
    match args.get(1).map(String::as_str) {
        Some("height") => {
            let cell = arg(2, 1.0);
            let mesh = grid(
                (60.0 / cell) as usize,
                (50.0 / cell) as usize,
                false,
                |u, v| {
                    let (x, y) = (60.0 * u, 50.0 * v);
                    Point3::new(x, y, height(x, y))
                },
            );
            let adjacency = FaceAdjacency::new(&mesh);
            let points = (0..=10)
                .map(|i| Point3::new(30.0, 5.0 * i as Real, height(30.0, 5.0 * i as Real)))
                .collect();
            let src = if std::env::var("VERTEX_SOURCE").is_ok() {
                GeodesicSource::Vertices(vec![mesh.vertex_count() as u32 / 2])
            } else {
                GeodesicSource::Polyline {
                    points,
                    closed: false,
                }
            };
            let (e, te, w) = run(&mesh, &adjacency, &src, Method::Exact);
            let (m, tm, _) = run(&mesh, &adjacency, &src, Method::Fast);
            let (mut worst, mut at) = (0.0, 0);
            for v in 0..e.len() {
                if (e[v] - m[v]).abs() > worst {
                    worst = (e[v] - m[v]).abs();
                    at = v;
                }
            }
            let edges = 1.5 * mesh.triangle_count() as Real;
            println!(
                "height field {cell} mm: {} triangles; exact {te:.3} s, {w} windows ({:.2} per edge); \
                 mesh {tm:.3} s; |mesh − exact| max {worst:.4} at {:?} (mesh {:.4}, exact {:.4}); \
                 mesh below exact at {} vertices by up to {:.2e}; mean |mesh − exact| {:.4}, \
                 {} of {} vertices off by more than 0.1",
                mesh.triangle_count(),
                w as Real / edges,
                mesh.positions()[at],
                m[at],
                e[at],
                (0..e.len()).filter(|&v| m[v] < e[v] - 1e-9).count(),
                (0..e.len()).map(|v| e[v] - m[v]).fold(0.0, Real::max),
                (0..e.len()).map(|v| (e[v] - m[v]).abs()).sum::<Real>() / e.len() as Real,
                (0..e.len()).filter(|&v| (e[v] - m[v]).abs() > 0.1).count(),
                e.len()
            );
        }
        _ => {
            let (around, along) = (arg(2, 500.0) as usize, arg(3, 200.0) as usize);
            let shapes::Shape { mesh, adjacency } = shapes::cylinder(around, along);
            let ring = shapes::ring(0.0, 64, 0.3);
            let a0 = 2.0 * PI * 0.37 / around as Real;
            let generator = vec![
                Point3::new(r * a0.cos(), r * a0.sin(), 0.0),
                Point3::new(r * a0.cos(), r * a0.sin(), len),
            ];
            let chord = 2.0 * r * (PI / around as Real).sin();
            let s0 = {
                let (v1x, v1y) = (
                    (2.0 * PI / around as Real).cos(),
                    (2.0 * PI / around as Real).sin(),
                );
                ((a0.cos() - 1.0) * (v1x - 1.0) * r * r + a0.sin() * v1y * r * r) / chord
            };
            let unfolded = move |p: &Point3| {
                let i = (p.y.atan2(p.x) / (2.0 * PI / around as Real)).round() as i64;
                let x = i.rem_euclid(around as i64) as Real * chord - s0;
                x.abs().min(around as Real * chord - x)
            };
            type Exact = Box<dyn Fn(&Point3) -> Real>;
            let cases: [(&str, GeodesicSource, Exact); 2] = [
                (
                    "ring",
                    GeodesicSource::Polyline {
                        points: ring,
                        closed: true,
                    },
                    Box::new(|p: &Point3| p.z),
                ),
                (
                    "generator",
                    GeodesicSource::Polyline {
                        points: generator,
                        closed: false,
                    },
                    Box::new(unfolded),
                ),
            ];
            println!("cylinder: {} triangles", mesh.triangle_count());
            for (name, src, exact) in &cases {
                for method in [Method::Exact, Method::Fast] {
                    let (d, t, w) = run(&mesh, &adjacency, src, method);

                    let err = mesh
                        .positions()
                        .iter()
                        .zip(&d)
                        .map(|(p, d)| (exact(p) - d).abs())
                        .fold(0.0, Real::max);
                    println!(
                        "{name} {}: {t:.3} s, vertex error against the unfolding {err:.3e}, \
                         {w} windows ({:.2} per edge)",
                        method.name(),
                        w as Real / (1.5 * mesh.triangle_count() as Real)
                    );
                }
            }
        }
    }
}
