//! Accuracy and timing of the geodesic methods on doubly curved meshes against the analytic
//! distance: `cargo run --release --example geodesic_accurate -- cap|sphere TRIANGLES
//! [methods…]`. Cap: R 1000, half-angle 1 rad, boundary source, distance R·(θ0 − θ).
//! Section: the same cap, the source its section by the plane z = R·cos 0.6 (a circle at
//! θ = 0.6), distance R·|θ − 0.6|; `ring`: the same through the ring of vertices nearest to
//! θ = 0.6.
//! Sphere: R 100 cube sphere, point source at (0, 0, −R), great-circle distance.
//! Environment: `F32=1` rounds positions to f32 as read from an STL (the bench's input);
//! `DIST_DUMP=path` writes each method's distances to `path.<method>`, one a line;
//! `HASH=1` prints a hash of each method's distances (their bits), to check that a change
//! keeps results bit-identical; `BINS=n`, `WORST=n` break the errors down.

use skinpath::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, Method};
use skinpath::math::Real;
use std::time::Instant;

#[path = "../tests/common/geodesic_shapes.rs"]
mod shapes;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let shape = args.get(1).map(String::as_str).unwrap_or("cap");
    let target: Real = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5e5);
    let methods: Vec<&str> = if args.len() > 3 {
        args[3..].iter().map(String::as_str).collect()
    } else {
        vec!["accurate", "fast"]
    };
    let (mut s, src, exact): (shapes::Shape, GeodesicSource, Box<dyn Fn(usize) -> Real>);
    let t0 = Instant::now();
    if shape == "sphere" {
        let n = 2 * ((target / 12.0).sqrt() / 2.0).round() as usize;
        s = shapes::cube_sphere(n, 100.0);
        let p = s.mesh.positions().to_vec();
        let v = (0..p.len())
            .min_by(|&a, &b| p[a].z.total_cmp(&p[b].z))
            .unwrap();
        let pv = p[v];
        src = GeodesicSource::Vertices(vec![v as u32]);
        exact = Box::new(move |i| {
            100.0 * libm::acos((p[i].coords.dot(&pv.coords) / 1e4).clamp(-1.0, 1.0))
        });
    } else if shape == "section" || shape == "ring" {
        let rings = (target / 6.0).sqrt().round() as usize;
        s = shapes::cap(rings, 1000.0, 1.0);
        let p = s.mesh.positions().to_vec();
        // `ring`: the plane through the ring of vertices nearest to θ = 0.6, as the bench
        // takes it (at the ring's angle: the f32 vertices lie within rounding of it).
        let theta_s = if shape == "ring" {
            (0.6 * rings as Real).round() / rings as Real
        } else {
            0.6
        };
        let z = 1000.0 * libm::cos(theta_s);
        let at = skinpath::math::Point3::new(1000.0 * libm::sin(theta_s), 0.0, z);
        src = GeodesicSource::Plane {
            point: at,
            normal: skinpath::math::Vector3::z(),
        };
        exact = Box::new(move |i| {
            1000.0 * (libm::acos((p[i].z / 1000.0).clamp(-1.0, 1.0)) - theta_s).abs()
        });
    } else {
        let rings = (target / 6.0).sqrt().round() as usize;
        s = shapes::cap(rings, 1000.0, 1.0);
        let p = s.mesh.positions().to_vec();
        src = GeodesicSource::Boundary { loop_index: None };
        exact = Box::new(move |i| 1000.0 * (1.0 - libm::acos((p[i].z / 1000.0).clamp(-1.0, 1.0))));
    }
    if std::env::var("F32").is_ok() {
        let p = s
            .mesh
            .positions()
            .iter()
            .map(|p| p.map(|c| c as f32 as Real))
            .collect();
        s = shapes::shape(p, s.mesh.triangles().to_vec());
    }
    println!(
        "{shape}: {} triangles (built in {:.2} s)",
        s.mesh.triangle_count(),
        t0.elapsed().as_secs_f64()
    );
    let mut previous: Vec<(String, Vec<Real>)> = Vec::new();
    for m in methods {
        let method = match m {
            "exact" => Method::Exact,
            "fast" => Method::Fast,
            _ => Method::Accurate,
        };
        let params = DistanceParams {
            method,
            ..DistanceParams::default()
        };
        let t = Instant::now();
        let f = geodesic_distance(&s.mesh, &s.adjacency, &src, &params, &mut |_, _| {})
            .expect("distance");
        let dt = t.elapsed().as_secs_f64();
        let d = &f.vertex_distance;
        let (mut max, mut sum, mut at) = (0.0 as Real, 0.0, 0);
        for (i, d) in d.iter().enumerate() {
            let e = (d - exact(i)).abs();
            if e > max {
                at = i;
            }
            max = max.max(e);
            sum += e;
        }
        println!(
            "  worst at {:?}: {} vs {}",
            s.mesh.positions()[at],
            d[at],
            exact(at)
        );
        // BINS=n: the largest error in n bins of the analytic distance.
        if let Some(n) = std::env::var("BINS")
            .ok()
            .and_then(|w| w.parse::<usize>().ok())
        {
            let top = (0..d.len()).map(&exact).fold(0.0, Real::max);
            let mut bins = vec![0.0 as Real; n];
            for (i, d) in d.iter().enumerate() {
                let b = ((exact(i) / top * n as Real) as usize).min(n - 1);
                bins[b] = bins[b].max((d - exact(i)).abs());
            }
            for (b, e) in bins.iter().enumerate() {
                println!(
                    "    distance {:8.2}..{:8.2}: max error {e:.5}",
                    b as Real * top / n as Real,
                    (b + 1) as Real * top / n as Real
                );
            }
        }
        // WORST=n: the n largest errors, with their analytic distance.
        if let Some(n) = std::env::var("WORST")
            .ok()
            .and_then(|w| w.parse::<usize>().ok())
        {
            let mut order: Vec<usize> = (0..d.len()).collect();
            order.sort_by(|&a, &b| (d[b] - exact(b)).abs().total_cmp(&(d[a] - exact(a)).abs()));
            for &i in order.iter().take(n) {
                println!(
                    "    {:+.5} at distance {:.3}, {:?}",
                    d[i] - exact(i),
                    exact(i),
                    s.mesh.positions()[i]
                );
            }
        }
        if let Ok(path) = std::env::var("DIST_DUMP") {
            let text: String = d.iter().map(|d| format!("{d}\n")).collect();
            std::fs::write(format!("{path}.{m}"), text).expect("dump");
        }
        if std::env::var_os("HASH").is_some() {
            // FNV-1a over the bits of every distance.
            let hash = d.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, d| {
                d.to_bits()
                    .to_le_bytes()
                    .iter()
                    .fold(h, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
            });
            println!("  hash {hash:016x} of {} distances", d.len());
        }
        println!(
            "{m}: {dt:.3} s, max error {max:.5}, mean {:.5}, windows {} ({:.2} per edge)",
            sum / d.len() as Real,
            f.windows,
            f.windows as Real / (1.5 * s.mesh.triangle_count() as Real)
        );
        for (name, other) in &previous {
            let (mut diff, mut at) = (0.0, 0);
            for (i, (a, b)) in d.iter().zip(other).enumerate() {
                if (a - b).abs() > diff {
                    (diff, at) = ((a - b).abs(), i);
                }
            }
            println!(
                "  max |{m} − {name}| {diff:.5} at distance {:.3}",
                exact(at)
            );
            // FOCUS=r: the largest difference within r of the farthest point (the focus).
            if let Some(r) = std::env::var("FOCUS")
                .ok()
                .and_then(|w| w.parse::<Real>().ok())
            {
                let top = (0..d.len()).map(&exact).fold(0.0, Real::max);
                let near = (0..d.len())
                    .filter(|&i| exact(i) > top - r)
                    .map(|i| (d[i] - other[i]).abs())
                    .fold(0.0, Real::max);
                println!("  within {r} of the focus: max |{m} − {name}| {near:.5}");
            }
        }
        previous.push((m.to_string(), d.clone()));
    }
}
