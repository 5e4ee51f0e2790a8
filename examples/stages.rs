//! Times each stage of import and segmentation on one STL file, natively:
//! `cargo run --release --example stages -- FILE.stl`
//! (`npm run bench` measures the WebAssembly build end to end.)

use skinpath::mesh::{orient_consistently, read_stl, FaceAdjacency, FaceGeometry};
use skinpath::segment::{grow_regions, planarise, seed_order, SegmentParams};
use std::time::Instant;

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: cargo run --release --example stages -- FILE.stl");
        std::process::exit(2);
    };
    let bytes = match std::fs::read(&path) {
        Ok(bytes) => bytes,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
    };
    let mut t = Instant::now();
    let mut lap = |what: &str| {
        println!("{what:>12}: {:8.1} ms", t.elapsed().as_secs_f64() * 1e3);
        t = Instant::now();
    };
    let import = match read_stl(&bytes) {
        Ok(import) => import,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
    };
    lap("read + weld");
    let mut mesh = import.mesh;
    let mut adjacency = FaceAdjacency::new(&mesh);
    lap("adjacency");
    orient_consistently(&mut mesh, &mut adjacency);
    lap("orient");
    let geometry = FaceGeometry::new(&mesh);
    lap("geometry");
    let params = SegmentParams::default();
    let threshold = params.validate().expect("the default parameters are valid");
    let regions = grow_regions(&adjacency, &geometry, threshold);
    lap("regions");
    let order = seed_order(&adjacency, &geometry, params.seed_rule);
    lap("seed order");
    let patches = planarise(
        &adjacency,
        &geometry,
        &regions,
        params.theta_max_rad,
        &order,
        &mut |_, _| {},
    );
    lap("planarise");
    println!(
        "{} faces, {} vertices, {} regions, {} planar patches",
        mesh.triangle_count(),
        mesh.vertex_count(),
        regions.count,
        patches.count
    );
}
