//! Times each stage of import and segmentation on one STL file, natively, through the same
//! calls the WebAssembly `Mesh.fromStl` and `segment` make:
//! `cargo run --release --example stages -- FILE.stl [RUNS]`
//! Stage times are medians over RUNS runs (default 5) in one process, so that, as in the
//! browser, later runs reuse memory the first one obtained. (`npm run bench` measures the
//! WebAssembly build end to end.)

use skinpath::mesh::{prepare_mesh, read_stl_with_progress, ImportedMesh};
use skinpath::segment::{segment_with_progress, SegmentParams, Segmentation};
use std::time::Instant;

/// FNV-1a (64 bit) over the results, bit for bit: the report, the triangles in their final
/// winding, the face geometry and the segmentation, so that two builds can be compared.
fn fingerprint(imported: &ImportedMesh, seg: &Segmentation) -> u64 {
    let r = &imported.report;
    let g = &imported.geometry;
    let counts = [
        r.triangles,
        r.vertices,
        r.boundary_edges,
        r.non_manifold_edges,
        r.degenerate_triangles,
        r.components,
        r.flipped_triangles,
        r.inconsistent_edges,
    ];
    let words =
        counts
            .into_iter()
            .map(|c| c as u64)
            .chain([r.area.to_bits()])
            .chain(
                imported
                    .mesh
                    .triangles()
                    .iter()
                    .flatten()
                    .map(|&v| u64::from(v)),
            )
            .chain(
                g.normals()
                    .iter()
                    .flat_map(|n| [n.x, n.y, n.z].map(f64::to_bits)),
            )
            .chain(g.areas().iter().map(|a| a.to_bits()))
            .chain(
                g.centroids()
                    .iter()
                    .flat_map(|c| [c.x, c.y, c.z].map(f64::to_bits)),
            )
            .chain(seg.patch_of.iter().map(|&p| p as u64))
            .chain(seg.patches.iter().flat_map(|p| {
                [p.area, p.max_deviation, p.normal[0], p.centroid[0]].map(f64::to_bits)
            }));
    words.fold(0xcbf2_9ce4_8422_2325, |h, w| {
        w.to_le_bytes()
            .iter()
            .fold(h, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
    })
}

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
            "{} faces, {} vertices, {} regions, {} planar patches, {} kept; fingerprint {:016x}",
            imported.mesh.triangle_count(),
            imported.mesh.vertex_count(),
            seg.region_count,
            seg.planar_patch_count,
            seg.patches.len(),
            fingerprint(&imported, &seg)
        );
    }
    for (name, mut v) in all {
        v.sort_by(f64::total_cmp);
        println!("{name:>12}: {:8.1} ms", v[v.len() / 2]);
    }
    println!("{summary}");
}
