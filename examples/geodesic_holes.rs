//! The accurate method's virtual sources against the exact method on random plates with a
//! hole: `cargo run --release --example geodesic_holes`. Each case is a plate of 50 × 70 unit
//! squares (diagonals alternating) without the squares whose centres lie within a random
//! radius (2 to 12) of a random centre (a hole with a jagged rim, kept inside the plate),
//! flat or gently curved (the paraboloid z = 0.002 r²), measured from a random vertex (not
//! on the hole) or from the section by a random vertical plane. Prints the cases short of
//! the exact distance by more than 0.01 edge, then their count, the most short and the most
//! too long over all cases, and the mean error. `N` cases (default 200) from seed `SEED`
//! (default 1); `CASE=k`: case k alone; `NOTCH=1`: the hole may cut into the border.

use skinpath::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, Method};
use skinpath::math::{Point3, Real, Vector3};

#[path = "../tests/common/geodesic_shapes.rs"]
mod shapes;
use shapes::holed_surface;

/// A linear congruential generator: the same cases on every machine.
struct Lcg(u64);

impl Lcg {
    /// The next number in [0, 1).
    fn next(&mut self) -> Real {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as Real / (1u64 << 53) as Real
    }
}

fn env<T: std::str::FromStr>(name: &str) -> Option<T> {
    std::env::var(name).ok().and_then(|v| v.parse().ok())
}

fn main() {
    let count: usize = env("N").unwrap_or(200);
    let only: Option<usize> = env("CASE");
    let notch = std::env::var_os("NOTCH").is_some();
    let mut rng = Lcg(env("SEED").unwrap_or(1));
    let (w, l) = (50u32, 70u32);
    let (mut bad, mut worst_short, mut worst_long, mut mean) = (0, 0.0 as Real, 0.0 as Real, 0.0);
    let mut measured = 0;
    for case in 0..count {
        let (u, v, radius) = (rng.next(), rng.next(), 2.0 + 10.0 * rng.next());
        let (hx, hy) = if notch {
            (5.0 + 40.0 * u, 5.0 + 60.0 * v)
        } else {
            let margin = radius + 2.0;
            (
                margin + (Real::from(w) - 2.0 * margin) * u,
                margin + (Real::from(l) - 2.0 * margin) * v,
            )
        };
        let curved = rng.next() < 0.5;
        let point = rng.next() < 0.5;
        let (sx, sy) = (rng.next() * Real::from(w), rng.next() * Real::from(l));
        let angle = rng.next() * std::f64::consts::PI;
        if only.is_some_and(|c| c != case) {
            continue;
        }
        let height = |x: Real, y: Real| {
            if curved {
                0.002 * ((x - 25.0).powi(2) + (y - 35.0).powi(2))
            } else {
                0.0
            }
        };
        let (s, at) = holed_surface(w, l, (hx, hy), radius, height);
        let (mesh, adjacency) = (&s.mesh, &s.adjacency);
        let source = if point {
            let v = at(sx as u32, sy as u32) as usize;
            let p = mesh.positions()[v];
            if (p.x - hx).hypot(p.y - hy) < radius + 1.5 {
                continue;
            }
            GeodesicSource::Vertices(vec![v as u32])
        } else {
            GeodesicSource::Plane {
                point: Point3::new(sx, sy, 0.0),
                normal: Vector3::new(angle.cos(), angle.sin(), 0.0),
            }
        };
        let run = |method, exact_first_windows| {
            let params = DistanceParams {
                method,
                exact_first_windows,
                ..DistanceParams::default()
            };
            geodesic_distance(mesh, adjacency, &source, &params, &mut |_, _| {})
                .map(|f| f.vertex_distance)
        };
        // Virtual sources alone: no exact first try.
        let (Ok(exact), Ok(accurate)) = (run(Method::Exact, None), run(Method::Accurate, Some(0)))
        else {
            continue;
        };
        let (mut short, mut long, mut sum, mut n, mut at_most) = (0.0, 0.0 as Real, 0.0, 0, 0);
        for (v, (a, e)) in accurate.iter().zip(&exact).enumerate() {
            if a.is_finite() && e.is_finite() {
                if e - a > short {
                    (short, at_most) = (e - a, v);
                }
                long = long.max(a - e);
                sum += (a - e).abs();
                n += 1;
            }
        }
        measured += 1;
        mean += sum / Real::from(n.max(1) as u32);
        worst_short = worst_short.max(short);
        worst_long = worst_long.max(long);
        if short > 0.01 || only.is_some() {
            bad += usize::from(short > 0.01);
            println!(
                "case {case}: {} plate, hole ({hx:.2}, {hy:.2}) radius {radius:.2}, {}: \
                 short {short:.3} at ({}, {}), long {long:.3}",
                if curved { "curved" } else { "flat" },
                if point {
                    format!("from the vertex ({}, {})", sx as u32, sy as u32)
                } else {
                    format!("from the plane through ({sx:.2}, {sy:.2}) at {angle:.3} rad")
                },
                at_most % (w as usize + 1),
                at_most / (w as usize + 1),
            );
        }
    }
    println!(
        "{measured} cases: {bad} short by more than 0.01 edge; most short {worst_short:.3}, \
         most long {worst_long:.3}, mean error {:.5}",
        mean / Real::from(measured.max(1) as u32)
    );
}
