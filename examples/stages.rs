//! Times each stage of import and segmentation on one STL file, natively, through the same
//! calls the WebAssembly `Mesh.fromStl` and `segment` make:
//! `cargo run --release --example stages -- FILE.stl [RUNS]`
//! Stage times are medians over RUNS runs (default 5) in one process, so that, as in the
//! browser, later runs reuse memory the first one obtained. (`npm run bench` measures the
//! WebAssembly build end to end.)

use skinpath::mesh::{prepare_mesh, read_stl_with_progress};
use skinpath::segment::{segment_with_progress, SegmentParams};
use std::time::Instant;

fn main() {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: cargo run --release --example stages -- FILE.stl [RUNS]");
        std::process::exit(2);
    };
    let runs: usize = args.next().and_then(|r| r.parse().ok()).unwrap_or(5).max(1);
    let bytes = match std::fs::read(&path) {
        Ok(bytes) => bytes,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
    };
    // The defaults are the bench's parameters.
    let params = SegmentParams::default();
    let mut all: Vec<(String, Vec<f64>)> = Vec::new();
    let mut summary = String::new();
    for _ in 0..runs {
        let mut marks: Vec<(String, Instant)> = vec![("start".into(), Instant::now())];
        let mut last = String::new();
        let mut progress = |stage: &str, fraction: f64| {
            let repeat = stage == "planarise" && fraction == 0.0 && last == "planarise";
            if stage != last || repeat {
                let name = if repeat {
                    "planarise"
                } else if stage == "planarise" {
                    "seeds"
                } else {
                    stage
                };
                marks.push((name.to_string(), Instant::now()));
            }
            last = stage.to_string();
        };
        let import = read_stl_with_progress(&bytes, &mut progress).unwrap_or_else(|e| {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        });
        let imported = prepare_mesh(import, &mut progress).expect("prepared");
        let seg = segment_with_progress(
            &imported.adjacency,
            &imported.geometry,
            &params,
            &mut progress,
        )
        .expect("valid parameters");
        marks.push(("end".into(), Instant::now()));
        // Each mark names the stage that starts there; `start` begins the parse.
        marks[0].0 = "parse".into();
        if marks.len() > 1 && marks[1].0 == "parse" {
            marks.remove(1);
        }
        for w in marks.windows(2) {
            let ms = (w[1].1 - w[0].1).as_secs_f64() * 1e3;
            match all.iter_mut().find(|(n, _)| *n == w[0].0) {
                Some((_, v)) => v.push(ms),
                None => all.push((w[0].0.clone(), vec![ms])),
            }
        }
        let total = (marks[marks.len() - 1].1 - marks[0].1).as_secs_f64() * 1e3;
        match all.iter_mut().find(|(n, _)| n == "total") {
            Some((_, v)) => v.push(total),
            None => all.push(("total".into(), vec![total])),
        }
        summary = format!(
            "{} faces, {} vertices, {} regions, {} planar patches, {} kept",
            imported.mesh.triangle_count(),
            imported.mesh.vertex_count(),
            seg.region_count,
            seg.planar_patch_count,
            seg.patches.len()
        );
    }
    for (name, mut v) in all {
        v.sort_by(f64::total_cmp);
        println!("{name:>12}: {:8.1} ms", v[v.len() / 2]);
    }
    println!("{summary}");
}
