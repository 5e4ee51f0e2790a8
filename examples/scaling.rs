//! Runs every planner on meshes that are legal but hard on the data structures, at `n` and
//! `4n` triangles, natively, and prints each stage's time and the ratio of the two: about 4
//! where a stage is linear, 16 where it is quadratic.
//! `cargo run --release --example scaling -- [n]` (default 2,000).
//! The meshes (metres, the page's spray defaults):
//! - `fan`: a unit disc of `n` triangles round its centre (a vertex of valence `n`, as CAD
//!   exports cap cylinders);
//! - `book`: `n` unit pages on one edge (an edge of `n` faces);
//! - `thrice`: a unit plate of `n / 3` triangles, each written three times, once the other
//!   way round (every edge of three faces or more);
//! - `soup`: `n` triangles 5 mm across, 10 mm apart (no two share an edge).
//!
//! Per mesh: import and segmentation, one spray plan over every face (speeds optimised),
//! the fast and accurate distances from vertex 0, and passes every 0.05 m from each.
//! A refusal is printed by its message instead of a time; it must be the same at both sizes.

use skinpath::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, Method, PathParams};
use skinpath::mesh::{prepare_mesh, read_stl_with_progress, ImportedMesh};
use skinpath::segment::{segment, SegmentParams};
use skinpath::spray::{plan_spray, SprayParams};
use std::time::Instant;

#[path = "../tests/common/mod.rs"]
mod common;
use common::{binary_stl, Tri as Corners};

/// A mesh generator: the triangles of a mesh of about `n`.
type Generator = fn(usize) -> Vec<Corners>;

fn fan(n: usize) -> Vec<Corners> {
    let rim = |k: usize| {
        let t = std::f32::consts::TAU * (k % n) as f32 / n as f32;
        [t.cos(), t.sin(), 0.0]
    };
    (0..n).map(|i| [[0.0; 3], rim(i), rim(i + 1)]).collect()
}

fn book(n: usize) -> Vec<Corners> {
    (0..n)
        .map(|i| {
            let t = std::f32::consts::PI * i as f32 / n as f32;
            [[0.0; 3], [1.0, 0.0, 0.0], [0.5, t.cos(), t.sin()]]
        })
        .collect()
}

fn thrice(n: usize) -> Vec<Corners> {
    let m = ((n / 6) as f64).sqrt().max(1.0) as usize;
    common::plate_written_thrice(m, 1.0 / m as f32)
}

fn soup(n: usize) -> Vec<Corners> {
    let columns = (n / 10).max(1);
    (0..n)
        .map(|i| {
            let (x, y) = ((i % columns) as f32 * 0.01, (i / columns) as f32 * 0.01);
            [[x, y, 0.0], [x + 0.005, y, 0.0], [x, y + 0.005, 0.0]]
        })
        .collect()
}

/// Milliseconds of `f`, or its refusal.
fn timed<T, E: std::fmt::Display>(
    f: impl FnOnce() -> Result<T, E>,
) -> (Result<f64, String>, Option<T>) {
    let t = Instant::now();
    match f() {
        Ok(v) => (Ok(t.elapsed().as_secs_f64() * 1e3), Some(v)),
        Err(e) => (Err(e.to_string()), None),
    }
}

/// Every stage's time (or refusal) on `triangles`.
fn stages(triangles: &[Corners]) -> Vec<(&'static str, Result<f64, String>)> {
    let bytes = binary_stl(triangles);
    let (import, imported) = timed(|| {
        prepare_mesh(
            read_stl_with_progress(&bytes, &mut |_, _| {})?,
            &mut |_, _| {},
        )
    });
    let Some(ImportedMesh {
        mesh,
        adjacency,
        geometry,
        ..
    }) = imported
    else {
        return vec![("import", import)];
    };
    let mut out = vec![("import", import)];
    out.push((
        "segment",
        timed(|| segment(&adjacency, &geometry, &SegmentParams::default())).0,
    ));
    let faces: Vec<u32> = (0..mesh.triangle_count() as u32).collect();
    let spray = SprayParams {
        spacing: 0.09,
        standoff: 0.25,
        speed: 0.4,
        flow_rate: 150e-6 / 60.0,
        cone_angle: 40f64.to_radians(),
        transition_angle: 20f64.to_radians(),
        efficiency: 0.6,
        ..SprayParams::default()
    };
    out.push((
        "spray",
        timed(|| plan_spray(&mesh, &adjacency, &geometry, &faces, &spray, &mut |_, _| {})).0,
    ));
    let source = GeodesicSource::Vertices(vec![0]);
    let passes = PathParams {
        spacing: 0.05,
        ..PathParams::default()
    };
    for (name, paths, method) in [
        ("fast", "fast passes", Method::Fast),
        ("accurate", "accurate passes", Method::Accurate),
    ] {
        let params = DistanceParams {
            method,
            ..DistanceParams::default()
        };
        let (t, field) =
            timed(|| geodesic_distance(&mesh, &adjacency, &source, &params, &mut |_, _| {}));
        out.push((name, t));
        if let Some(field) = field {
            out.push((
                paths,
                timed(|| field.tool_path(&mesh, &adjacency, &passes)).0,
            ));
        }
    }
    out
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(2000);
    let meshes: [(&str, Generator); 4] = [
        ("fan", fan),
        ("book", book),
        ("thrice", thrice),
        ("soup", soup),
    ];
    for (name, make) in meshes {
        let (small, large) = (make(n), make(4 * n));
        println!("{name}: {} and {} triangles", small.len(), large.len());
        for ((stage, a), (_, b)) in stages(&small).into_iter().zip(stages(&large)) {
            match (a, b) {
                (Ok(a), Ok(b)) => println!(
                    "  {stage:16} {a:10.1} ms {b:10.1} ms  ×{:.1}",
                    b / a.max(1e-3)
                ),
                (a, b) => println!(
                    "  {stage:16} {}  |  {}",
                    a.map_or_else(|e| e, |ms| format!("{ms:.1} ms")),
                    b.map_or_else(|e| e, |ms| format!("{ms:.1} ms"))
                ),
            }
        }
    }
}
