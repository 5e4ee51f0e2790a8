//! The geodesic methods on the patches of a real model: `cargo run --release --example
//! geodesic_real -- FILE.stl [PATCHES]`. Segments with the paper's parameters, then on each
//! of the PATCHES largest patches (default 1) measures the distance from the patch boundary
//! by the accurate, fast and exact methods, and checks each against two independent bounds:
//! no surface path is shorter than the straight line to the nearest boundary point, and none
//! needs to be longer than the shortest path along mesh edges. `WHOLE=v`: the whole mesh
//! instead, from vertex `v`. `virtual` is the accurate method without its exact first try
//! on small cornered surfaces.

use skinpath::geodesic::{
    boundary_loops, geodesic_distance, DistanceParams, GeodesicSource, Method,
};
use skinpath::math::{Point3, Real};
use skinpath::mesh::{prepare_mesh, read_stl_with_progress};
use skinpath::segment::{segment, SegmentParams};
use std::collections::BinaryHeap;
use std::time::Instant;

/// Shortest distance from `p` to the segment `a`–`b`.
fn to_segment(p: &Point3, a: &Point3, b: &Point3) -> Real {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared().max(1e-300)).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args
        .get(1)
        .expect("usage: geodesic_real FILE.stl [PATCHES]");
    let count: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    let bytes = std::fs::read(path).expect("readable file");
    let imported = prepare_mesh(
        read_stl_with_progress(&bytes, &mut |_, _| {}).unwrap(),
        &mut |_, _| {},
    )
    .unwrap();
    let (mesh, adjacency) = (&imported.mesh, &imported.adjacency);
    let seg = segment(adjacency, &imported.geometry, &SegmentParams::default()).unwrap();
    let p = mesh.positions();
    let whole: Option<u32> = std::env::var("WHOLE").ok().and_then(|w| w.parse().ok());
    if let Some(v) = whole {
        if v as usize >= p.len() {
            eprintln!("WHOLE={v}: the mesh has {} vertices", p.len());
            std::process::exit(2);
        }
    }
    for id in 0..count.min(seg.patches.len()) {
        let faces: Vec<u32> = (0..seg.patch_of.len())
            .filter(|&f| whole.is_some() || seg.patch_of[f] == id as i32)
            .map(|f| f as u32)
            .collect();
        let loops = match whole {
            Some(v) => vec![vec![v]],
            None => boundary_loops(mesh, adjacency, Some(&faces)).unwrap(),
        };
        let source = match whole {
            Some(v) => GeodesicSource::Vertices(vec![v]),
            None => GeodesicSource::Boundary { loop_index: None },
        };
        // Lower bound: straight line to the nearest boundary segment.
        let mut used = vec![false; p.len()];
        let mut graph: Vec<Vec<(usize, Real)>> = vec![Vec::new(); p.len()];
        for f in &faces {
            let t = mesh.triangles()[*f as usize];
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                used[a] = true;
                let l = (p[a] - p[b]).norm();
                graph[a].push((b, l));
                graph[b].push((a, l));
            }
        }
        let segs: Vec<(usize, usize)> = loops
            .iter()
            .flat_map(|l| (0..l.len()).map(move |i| (l[i] as usize, l[(i + 1) % l.len()] as usize)))
            .collect();
        let lower: Vec<Real> = (0..p.len())
            .map(|v| {
                if !used[v] {
                    return Real::INFINITY;
                }
                segs.iter()
                    .map(|&(a, b)| to_segment(&p[v], &p[a], &p[b]))
                    .fold(Real::INFINITY, Real::min)
            })
            .collect();
        // Upper bound: Dijkstra along edges from the boundary vertices.
        let mut upper = vec![Real::INFINITY; p.len()];
        let mut heap = BinaryHeap::new();
        for l in &loops {
            for &v in l {
                upper[v as usize] = 0.0;
                heap.push((std::cmp::Reverse(0u64), v as usize));
            }
        }
        while let Some((std::cmp::Reverse(d), v)) = heap.pop() {
            let d = Real::from_bits(d);
            if d > upper[v] {
                continue;
            }
            for &(w, l) in &graph[v] {
                if d + l < upper[w] {
                    upper[w] = d + l;
                    heap.push((std::cmp::Reverse((d + l).to_bits()), w));
                }
            }
        }
        println!(
            "patch {id}: {} faces, {} loops ({} boundary edges)",
            faces.len(),
            loops.len(),
            segs.len()
        );
        let mut fields = Vec::new();
        for (name, method, exact_first) in [
            ("accurate", Method::Accurate, None),
            ("virtual", Method::Accurate, Some(0)),
            ("fast", Method::Fast, None),
            ("exact", Method::Exact, None),
        ] {
            let params = DistanceParams {
                method,
                faces: Some(faces.clone()),
                exact_first_windows: exact_first,
                ..Default::default()
            };
            let t = Instant::now();
            let field = geodesic_distance(mesh, adjacency, &source, &params, &mut |_, _| {});
            let ms = t.elapsed().as_secs_f64() * 1e3;
            let Ok(field) = field else {
                println!("  {name}: {:?}", field.err());
                continue;
            };
            if field.method != method {
                println!("  {name}: ran the {} method", field.method.name());
            }
            if field.windows > 0 {
                println!(
                    "  windows {} ({:.1} per face)",
                    field.windows,
                    field.windows as f64 / faces.len() as f64
                );
            }
            let d = field.vertex_distance;
            let (mut below, mut above, mut wb, mut wa) = (0.0, 0.0, 0, 0);
            for v in 0..p.len() {
                if !used[v] {
                    continue;
                }
                if lower[v] - d[v] > below {
                    below = lower[v] - d[v];
                    wb = v;
                }
                if d[v] - upper[v] > above {
                    above = d[v] - upper[v];
                    wa = v;
                }
            }
            println!(
                "  {name:>8}: {ms:7.1} ms, below straight line by {below:.3} (v{wb}: {:.2} < {:.2}), above edge path by {above:.3} (v{wa}: {:.2} > {:.2})",
                d[wb], lower[wb], d[wa], upper[wa]
            );
            fields.push((name, d));
        }
        if let Some((_, e)) = fields.iter().find(|(n, _)| *n == "exact") {
            for (name, d) in &fields {
                let (mut m, mut w, mut sum, mut n, mut short) = (0.0, 0, 0.0, 0, 0.0 as Real);
                for v in 0..p.len() {
                    if used[v] && e[v].is_finite() {
                        short = short.max(e[v] - d[v]);
                        let x = (d[v] - e[v]).abs();
                        sum += x;
                        n += 1;
                        if x > m {
                            m = x;
                            w = v;
                        }
                    }
                }
                println!(
                    "  {name:>8} vs exact: max {m:.3} (v{w}: {:.2} vs {:.2}; lower {:.2}, upper {:.2}), mean {:.4}, short by {short:.3} at most",
                    d[w], e[w], lower[w], upper[w], sum / n as Real
                );
            }
        }
    }
}
