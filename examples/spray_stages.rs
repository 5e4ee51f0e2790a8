//! Times the spray planner's stages on one STL file, natively, with the page defaults
//! (metres): `cargo run --release --example spray_stages -- FILE.stl [patch]`.
//! With `patch`, plans the largest patch of the default segmentation instead of all faces.
//! (`npm run bench -- spray` measures the WebAssembly build end to end.)
//! Environment: `MAX_ERROR`, `MIN_SPACING`, `MAX_SPACING` set the search's limits (default
//! maxError 0.2); `CPU_TIME=1` reports process CPU time (steadier than wall time on a shared
//! machine; Linux); `ONLY_PLAN=1` stops after the single plan, `ONLY_SEARCH=1` skips it;
//! `SAMPLE_BUDGET=N` coarsens the resolution to fit N samples, as the page does (100,000).
//! Each plan's line ends with a fingerprint of its results bit for bit (thickness, samples,
//! poses and speeds, figures, spacings tried), so that two builds can be compared.

use skinpath::mesh::{orient_consistently, read_stl, FaceAdjacency, FaceGeometry};
use skinpath::segment::{segment, SegmentParams};
use skinpath::spray::{patch_frame, plan_spray, QualityLimits, SprayParams, SprayPlan};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: cargo run --release --example spray_stages -- FILE.stl [patch]");
        std::process::exit(2);
    };
    let bytes = std::fs::read(path).unwrap_or_else(|e| {
        eprintln!("{path}: {e}");
        std::process::exit(1)
    });
    let t = Instant::now();
    let import = read_stl(&bytes).unwrap_or_else(|e| {
        eprintln!("{path}: {e}");
        std::process::exit(1)
    });
    let mut mesh = import.mesh;
    let mut adjacency = FaceAdjacency::new(&mesh);
    orient_consistently(&mut mesh, &mut adjacency);
    let geometry = FaceGeometry::new(&mesh);
    println!("import: {:8.1} ms", t.elapsed().as_secs_f64() * 1e3);
    let faces: Vec<u32> = if args.get(2).is_some_and(|a| a == "patch") {
        let seg = segment(&adjacency, &geometry, &SegmentParams::default())
            .unwrap_or_else(|e| panic!("segmentation failed: {e}"));
        seg.faces_of(0).map(|f| f as u32).collect()
    } else {
        (0..mesh.triangle_count() as u32).collect()
    };
    let mm = 1e-3;
    let p = SprayParams {
        spacing: 0.09,
        standoff: 250.0 * mm,
        speed: 400.0 * mm,
        flow_rate: 150.0 * 1e-6 / 60.0,
        cone_angle: 40f64.to_radians(),
        transition_angle: 20f64.to_radians(),
        efficiency: 0.6,
        resolution: args.get(3).and_then(|r| r.parse().ok()),
        sample_budget: std::env::var("SAMPLE_BUDGET")
            .ok()
            .and_then(|b| b.parse().ok()),
        ..SprayParams::default()
    };
    let report = |what: &str, plan: &SprayPlan, ms: f64| {
        let ms = if std::env::var_os("CPU_TIME").is_some() {
            cpu_ms() - ms
        } else {
            ms
        };
        let (i, w) = (plan.quality.interior, plan.quality.whole);
        println!(
            "{what}: {ms:8.1} ms; {} faces, {} samples; spacing {:.4}, {} passes, cycle {:.1} s, spray path {:.2}, {} tried; interior δ {:.3} E {:.3} µm mean {:.2} µm; whole δ {:.3} E {:.3} µm min {:.2} max {:.2} µm",
            faces.len(), plan.samples.positions.len(), plan.spacing, plan.pass_count, plan.cycle_time, plan.spray_length, plan.iterations.len(),
            i.error, i.std_dev * 1e6, i.mean * 1e6, w.error, w.std_dev * 1e6, w.min * 1e6, w.max * 1e6
        );
        println!("  fingerprint {:016x}", fingerprint(plan));
    };
    let cpu = std::env::var_os("CPU_TIME").is_some();
    // `ONLY_SEARCH=1` skips the single plan.
    if std::env::var_os("ONLY_SEARCH").is_none() {
        let t = Instant::now();
        let c0 = cpu_ms();
        let one = plan_spray(&mesh, &adjacency, &geometry, &faces, &p, &mut |_, _| {})
            .unwrap_or_else(|e| panic!("plan failed: {e}"));
        report(
            "one plan",
            &one,
            if cpu {
                c0
            } else {
                t.elapsed().as_secs_f64() * 1e3
            },
        );
        if std::env::var_os("SPRAY_WHERE").is_some() {
            let frame = patch_frame(&mesh, &geometry, &faces, None, p.raster_angle)
                .unwrap_or_else(|e| panic!("frame failed: {e}"));
            where_extremes(&one, &frame.across);
            let n = frame.arc.len() - 1;
            println!(
            "  width {:.3}, arc {:.3}; arc at quarters {:.3} {:.3} {:.3}; offsets at 0.09: {:?}",
            frame.width(),
            frame.arc[n],
            frame.arc[n / 4],
            frame.arc[n / 2],
            frame.arc[3 * n / 4],
            frame.plane_offsets(0.09).map(|o| o.len())
        );
        }
        if std::env::var_os("ONLY_PLAN").is_some() {
            return;
        }
    }
    let max_error = env_or("MAX_ERROR", 0.2);
    let q = SprayParams {
        quality: Some(QualityLimits {
            max_error: Some(max_error),
            min_spacing: std::env::var("MIN_SPACING")
                .ok()
                .and_then(|v| v.parse().ok()),
            max_spacing: std::env::var("MAX_SPACING")
                .ok()
                .and_then(|v| v.parse().ok()),
            ..QualityLimits::default()
        }),
        ..p
    };
    let t = Instant::now();
    let c0 = cpu_ms();
    let best = plan_spray(&mesh, &adjacency, &geometry, &faces, &q, &mut |_, _| {})
        .unwrap_or_else(|e| panic!("search failed: {e}"));
    report(
        &format!("search δ≤{max_error}"),
        &best,
        if cpu {
            c0
        } else {
            t.elapsed().as_secs_f64() * 1e3
        },
    );
    for it in &best.iterations {
        println!(
            "  b {:.4} δ {:.3} E {:.3} µm met {}",
            it.spacing,
            it.error,
            it.std_dev * 1e6,
            it.met
        );
    }
}

/// Prints where the thinnest and thickest interior and whole-patch samples lie.
fn where_extremes(plan: &SprayPlan, across: &skinpath::math::Vector3) {
    let n = plan.thickness.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| plan.thickness[a].total_cmp(&plan.thickness[b]));
    let near = |i: usize| {
        let x = plan.samples.positions[i];
        plan.path
            .poses
            .iter()
            .filter(|q| q.kind.process_on())
            .map(|q| {
                (
                    (q.position - x).norm(),
                    -q.axis.dot(&plan.samples.normals[i]),
                )
            })
            .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a })
    };
    for (label, ids) in [
        (
            "thinnest",
            order.iter().take(5).copied().collect::<Vec<_>>(),
        ),
        ("thickest", order.iter().rev().take(5).copied().collect()),
        (
            "thinnest interior",
            order
                .iter()
                .filter(|&&i| plan.interior[i])
                .take(5)
                .copied()
                .collect(),
        ),
        (
            "thickest interior",
            order
                .iter()
                .rev()
                .filter(|&&i| plan.interior[i])
                .take(5)
                .copied()
                .collect(),
        ),
    ] {
        for i in ids {
            let (d, c) = near(i);
            let p = plan.samples.positions[i];
            let m = plan.samples.normals[i];
            // Pass spacing along the surface over the spacing in space.
            let pass_dir = m.cross(across).normalize();
            let stretch = 1.0 / m.cross(&pass_dir).dot(across).abs();
            println!(
                "  {label}: {:.2} µm at ({:.3}, {:.3}, {:.3}) n ({:.2}, {:.2}, {:.2}) interior {}; nearest pose {:.3} away, −axis·n {:.2}, passes {stretch:.2}× farther apart on the surface",
                plan.thickness[i] * 1e6, p.x, p.y, p.z, m.x, m.y, m.z, plan.interior[i], d, c
            );
        }
    }
}

/// FNV-1a (64 bit) over a plan's results, bit for bit.
fn fingerprint(plan: &SprayPlan) -> u64 {
    let (i, w) = (plan.quality.interior, plan.quality.whole);
    let figures = [
        plan.spacing,
        plan.speed,
        plan.cycle_time,
        plan.spray_length,
        i.mean,
        i.std_dev,
        i.error,
        w.mean,
        w.std_dev,
        w.error,
        w.min,
        w.max,
    ];
    let points = plan
        .samples
        .positions
        .iter()
        .chain(plan.path.poses.iter().map(|p| &p.position));
    let axes = plan.path.poses.iter().map(|p| &p.axis);
    let tried = plan
        .iterations
        .iter()
        .flat_map(|it| [it.spacing, it.mean, it.std_dev, it.error]);
    let words = plan
        .thickness
        .iter()
        .chain(&plan.path.speeds)
        .chain(&figures)
        .copied()
        .chain(points.flat_map(|p| [p.x, p.y, p.z]))
        .chain(axes.flat_map(|a| [a.x, a.y, a.z]))
        .chain(tried)
        .map(f64::to_bits);
    words.fold(0xcbf2_9ce4_8422_2325_u64, |h, word| {
        word.to_le_bytes().iter().fold(h, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        })
    })
}

fn env_or(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// CPU time of this process so far, ms (Linux; 0 elsewhere): steadier than wall time on a
/// shared machine.
fn cpu_ms() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|s| {
            let rest = s.rsplit_once(')')?.1;
            let f: Vec<&str> = rest.split_whitespace().collect();
            let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
            Some(ticks * 10.0)
        })
        .unwrap_or(0.0)
}
