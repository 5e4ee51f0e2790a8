//! Hash of the accurate method's distances (their bits) on the bench's doubly curved meshes,
//! to check that a change keeps results bit-identical: `cargo run --release --example
//! geodesic_hash -- cap|sphere TRIANGLES`. Positions are rounded to f32 as read from an STL.

use skinpath::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, Method};
use skinpath::math::Real;

#[path = "../tests/common/geodesic_shapes.rs"]
mod shapes;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let shape = args.get(1).map(String::as_str).unwrap_or("cap");
    let target: Real = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5e5);
    let (s, src) = if shape == "sphere" {
        let n = 2 * ((target / 12.0).sqrt() / 2.0).round() as usize;
        let s = shapes::cube_sphere(n, 100.0);
        let p = s.mesh.positions();
        let v = (0..p.len())
            .min_by(|&a, &b| p[a].z.total_cmp(&p[b].z))
            .unwrap();
        (s, GeodesicSource::Vertices(vec![v as u32]))
    } else {
        let rings = (target / 6.0).sqrt().round() as usize;
        (
            shapes::cap(rings, 1000.0, 1.0),
            GeodesicSource::Boundary { loop_index: None },
        )
    };
    let p = s
        .mesh
        .positions()
        .iter()
        .map(|p| p.map(|c| c as f32 as Real))
        .collect();
    let s = shapes::shape(p, s.mesh.triangles().to_vec());
    let params = DistanceParams {
        method: Method::Accurate,
        ..DistanceParams::default()
    };
    let f =
        geodesic_distance(&s.mesh, &s.adjacency, &src, &params, &mut |_, _| {}).expect("distance");
    // FNV-1a over the bits of every distance.
    let hash = f
        .vertex_distance
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, d| {
            d.to_bits()
                .to_le_bytes()
                .iter()
                .fold(h, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
        });
    println!(
        "{shape} {} triangles: {} vertices, hash {hash:016x}",
        s.mesh.triangle_count(),
        f.vertex_distance.len()
    );
}
