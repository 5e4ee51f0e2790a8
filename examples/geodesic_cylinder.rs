//! Accuracy and timing of both geodesic methods on a generated cylinder (R 50, length 120):
//! `cargo run --release --example geodesic_cylinder -- [around] [along] [voxel_size]`.
//! Source: the ring at z = 0, so the exact distance of a point is its z.

use skinpath::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, Method, PathParams};
use skinpath::math::{Point3, Real};
use std::f64::consts::PI;
use std::time::Instant;

#[path = "../tests/common/geodesic_shapes.rs"]
mod shapes;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: Real| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (around, along, voxel) = (arg(1, 500.0) as usize, arg(2, 200.0) as usize, arg(3, 0.5));
    let (r, len) = (shapes::R, shapes::LEN);
    let shapes::Shape { mesh, adjacency } = shapes::cylinder(around, along);
    println!("cylinder: {} triangles", mesh.triangle_count());
    let ring = shapes::ring(0.0, 64, 0.3);
    let a0 = 2.0 * PI * 0.37 / around as Real;
    let generator = vec![
        Point3::new(r * a0.cos(), r * a0.sin(), 0.0),
        Point3::new(r * a0.cos(), r * a0.sin(), len),
    ];
    let arc = move |p: &Point3| {
        let mut da = (p.y.atan2(p.x) - a0).rem_euclid(2.0 * PI);
        if da > PI {
            da = 2.0 * PI - da;
        }
        r * da
    };
    type Exact = Box<dyn Fn(&Point3) -> Real>;
    let cases: [(&str, GeodesicSource, Exact, Option<u32>); 2] = [
        (
            "ring",
            GeodesicSource::Polyline {
                points: ring,
                closed: true,
            },
            Box::new(|p: &Point3| p.z),
            Some(11),
        ),
        (
            "generator",
            GeodesicSource::Polyline {
                points: generator,
                closed: false,
            },
            Box::new(arc),
            None,
        ),
    ];
    for (name, source, exact, max_level) in &cases {
        for method in [Method::Fast, Method::Voxel] {
            let params = DistanceParams {
                method,
                voxel_size: Some(voxel),
                ..DistanceParams::default()
            };
            let t0 = Instant::now();
            let field = geodesic_distance(&mesh, &adjacency, source, &params, &mut |s, f| {
                if std::env::var("GEO_TRACE").is_ok() {
                    eprintln!("{s} {f:.2} {:.3}", t0.elapsed().as_secs_f64())
                }
            })
            .expect("distance");
            let t_dist = t0.elapsed().as_secs_f64();
            let t1 = Instant::now();
            let path = PathParams {
                spacing: 10.0,
                max_level: *max_level,
                ..PathParams::default()
            };
            let lines = field.iso_lines(&mesh, &adjacency, &path).expect("paths");
            let t_paths = t1.elapsed().as_secs_f64();
            let err = lines
                .iter()
                .flat_map(|l| l.points.iter().map(|p| (exact(p) - l.distance).abs()))
                .fold(0.0, Real::max);
            let vertex_err = mesh
                .positions()
                .iter()
                .zip(&field.vertex_distance)
                .map(|(p, d)| (exact(p) - d).abs())
                .fold(0.0, Real::max);
            let (count, bytes) = field
                .voxels
                .as_ref()
                .map_or((0, 0), |v| (v.cells.len(), v.memory_bytes));
            println!(
                "{name} {method:?}: distance {t_dist:.3} s, paths {t_paths:.3} s, {} lines ({} closed), \
                 path error {err:.5}, vertex error {vertex_err:.5}, voxels {count} ({bytes} bytes)",
                lines.len(),
                lines.iter().filter(|l| l.closed).count()
            );
        }
    }
}
