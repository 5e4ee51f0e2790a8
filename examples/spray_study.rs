//! Plans a spray job on one patch of a real model with the page's defaults (h 250 mm, α 40°,
//! v 400 mm/s, Q 150 cm³/min, η 0.6, δ ≤ 15 %, E ≤ 5 µm, target 40 µm, speeds 200–800 mm/s)
//! and prints what the Spray tool would show:
//! `cargo run --release --example spray_study -- FILE.stl MM_PER_UNIT [PATCH] [off] [best]`.
//! `PATCH` is the patch id of the paper-default segmentation (0 = largest); `off` turns the
//! speed optimisation off; `best` tries the other pass directions. Environment: `SAMPLES`
//! (evaluation sample budget, default 100,000 as the page), `SPACING` (mm: plan at that
//! spacing, no search), `RASTER` (degrees: turn the pass direction), `DUMP` (a path prefix:
//! write the samples and poses as CSV).

use skinpath::mesh::{orient_consistently, read_stl, FaceAdjacency, FaceGeometry};
use skinpath::segment::{segment, SegmentParams};
use skinpath::spray::{plan_spray, QualityLimits, SprayParams};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        eprintln!("usage: spray_study FILE.stl MM_PER_UNIT [PATCH] [off] [best]");
        std::process::exit(2);
    }
    let bytes = std::fs::read(&args[1]).unwrap_or_else(|e| {
        eprintln!("{}: {e}", args[1]);
        std::process::exit(1)
    });
    let mm_per_unit: f64 = args[2].parse().expect("MM_PER_UNIT is a number");
    let patch: usize = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(0);
    let optimise = !args.iter().any(|a| a == "off");
    let best = args.iter().any(|a| a == "best");
    let import = read_stl(&bytes).expect("readable STL");
    let mut mesh = import.mesh;
    let mut adjacency = FaceAdjacency::new(&mesh);
    orient_consistently(&mut mesh, &mut adjacency);
    let geometry = FaceGeometry::new(&mesh);
    let seg = segment(&adjacency, &geometry, &SegmentParams::default()).expect("segmentation");
    let faces: Vec<u32> = seg.faces_of(patch).map(|f| f as u32).collect();
    let mm = 1.0 / mm_per_unit;
    // The page keeps about 100,000 evaluation samples: about 1.3·area/resolution² of them.
    let area = seg.patches[patch].area;
    let radius = 250.0 * mm * 20f64.to_radians().tan();
    let budget: f64 = std::env::var("SAMPLES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100_000.0);
    let resolution = (radius / 8.0).max((1.3 * area / budget).sqrt());
    let p = SprayParams {
        resolution: Some(resolution),
        spacing: 100.0 * mm,
        standoff: 250.0 * mm,
        speed: 400.0 * mm,
        flow_rate: 150.0 * 1000.0 / 60.0 * mm * mm * mm,
        cone_angle: 40f64.to_radians(),
        transition_angle: 20f64.to_radians(),
        efficiency: 0.6,
        quality: Some(QualityLimits {
            max_std_dev: Some(0.005 * mm),
            max_error: Some(0.15),
            ..QualityLimits::default()
        }),
        target_thickness: Some(0.040 * mm),
        optimise_speed: optimise,
        min_speed: Some(200.0 * mm),
        max_speed: Some(800.0 * mm),
        best_direction: best,
        ..SprayParams::default()
    };
    let mut p = p;
    // RASTER=DEG turns the pass direction (as the page's typed angle).
    if let Some(a) = std::env::var("RASTER")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
    {
        p.raster_angle = a.to_radians();
    }
    if let Some(b) = std::env::var("SPACING")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
    {
        p.spacing = b * mm;
        p.quality = None;
    }
    let t = Instant::now();
    let plan = plan_spray(&mesh, &adjacency, &geometry, &faces, &p, &mut |_, _| {})
        .unwrap_or_else(|e| panic!("plan failed: {e}"));
    let ms = t.elapsed().as_secs_f64() * 1e3;
    let q = plan.quality.interior;
    let um = 1000.0 * mm_per_unit;
    // Share of the interior area within ±10 % of the interior mean.
    let (mut inside, mut total) = (0.0, 0.0);
    for (i, &t) in plan.thickness.iter().enumerate() {
        if plan.interior[i] {
            total += plan.samples.weights[i];
            if (t - q.mean).abs() <= 0.1 * q.mean {
                inside += plan.samples.weights[i];
            }
        }
    }
    let mut speeds: Vec<f64> = (1..plan.path.poses.len())
        .filter(|&k| plan.path.poses[k].kind.process_on())
        .map(|k| plan.path.move_speed(k) * mm_per_unit)
        .collect();
    speeds.sort_by(f64::total_cmp);
    let pct = |f: f64| speeds[((speeds.len() - 1) as f64 * f) as usize];
    println!(
        "{} patch {patch}: {} faces, {:.2} m²; {} samples every {:.1} mm; optimise {optimise}; {ms:.0} ms",
        args[1],
        faces.len(),
        seg.patches[patch].area / (1e6 * mm * mm),
        plan.samples.positions.len(),
        resolution * mm_per_unit
    );
    println!(
        "  spacing {:.1} mm, {} passes, met {}; interior δ {:.1} %, E {:.2} µm, mean {:.2} µm, within ±10 %: {:.2} %",
        plan.spacing * mm_per_unit,
        plan.pass_count,
        plan.limits_met,
        100.0 * q.error,
        q.std_dev * um,
        q.mean * um,
        100.0 * inside / total.max(1e-300)
    );
    println!(
        "  speeds {:.0}–{:.0} mm/s (5–50–95 %: {:.0} {:.0} {:.0}); cycle {:.1} s; spray path {:.1} m, whole {:.1} m; raster angle {:.0}°",
        plan.speed_range.0 * mm_per_unit,
        plan.speed_range.1 * mm_per_unit,
        pct(0.05),
        pct(0.5),
        pct(0.95),
        plan.cycle_time,
        plan.spray_length * mm_per_unit / 1000.0,
        plan.path_length * mm_per_unit / 1000.0,
        plan.raster_angle.to_degrees()
    );
    // Gun-on reversals inside passes (consecutive moves turning by more than 150°, the first
    // with the gun on): a robot stops there, spraying.
    let poses = &plan.path.poses;
    let mut reversals = Vec::new();
    for k in 1..poses.len().saturating_sub(1) {
        let (a, b) = (
            poses[k].position - poses[k - 1].position,
            poses[k + 1].position - poses[k].position,
        );
        if poses[k].kind.process_on()
            && poses[k + 1].pass == poses[k].pass
            && a.norm() > 0.0
            && b.norm() > 0.0
            && a.dot(&b) < (150f64).to_radians().cos() * a.norm() * b.norm()
        {
            reversals.push((
                k,
                a.norm() * mm_per_unit,
                b.norm() * mm_per_unit,
                poses[k].kind,
                poses[k + 1].kind,
            ));
        }
    }
    // The gun switched off inside a pass (a gun-off move between gun-on moves of one pass).
    let mut toggles = 0;
    for k in 2..poses.len() {
        if poses[k].pass == poses[k - 1].pass
            && poses[k - 1].kind.process_on()
            && !poses[k].kind.process_on()
        {
            toggles += 1;
        }
    }
    println!("  gun switched off inside passes: {toggles} times");
    println!(
        "  gun-on reversals: {}; first: {:?}",
        reversals.len(),
        &reversals[..reversals.len().min(6)]
    );
    for it in &plan.iterations {
        println!(
            "    b {:7.1} mm δ {:5.1} % E {:5.2} µm {} {}",
            it.spacing * mm_per_unit,
            100.0 * it.error,
            it.std_dev * um,
            if it.full { "full  " } else { "coarse" },
            if it.met { "met" } else { "" }
        );
    }
    for d in &plan.directions {
        println!(
            "    direction {:+.0}°: δ {:.1} % E {:.2} µm cycle {:.1} s {}",
            d.raster_angle.to_degrees(),
            100.0 * d.error,
            d.std_dev * um,
            d.cycle_time,
            if d.chosen { "chosen" } else { "" }
        );
    }
    for h in &plan.hotspots {
        println!(
            "    hotspot {:+.1} % {:?} at ({:.0}, {:.0}, {:.0}) mm",
            100.0 * h.deviation,
            h.cause,
            h.position.x * mm_per_unit,
            h.position.y * mm_per_unit,
            h.position.z * mm_per_unit
        );
    }
    for m in &plan.messages {
        println!("  • {m}");
    }
    // DUMP=PREFIX writes PREFIX.samples.csv and PREFIX.poses.csv (mm, µm, mm/s) for study.
    if let Ok(prefix) = std::env::var("DUMP") {
        use std::fmt::Write as _;
        let mut out = String::from("x,y,z,nx,ny,nz,um,interior,weight\n");
        for (i, p) in plan.samples.positions.iter().enumerate() {
            let n = plan.samples.normals[i];
            let _ = writeln!(
                out,
                "{:.1},{:.1},{:.1},{:.4},{:.4},{:.4},{:.3},{},{:.1}",
                p.x * mm_per_unit,
                p.y * mm_per_unit,
                p.z * mm_per_unit,
                n.x,
                n.y,
                n.z,
                plan.thickness[i] * um,
                u8::from(plan.interior[i]),
                plan.samples.weights[i] * mm_per_unit * mm_per_unit
            );
        }
        std::fs::write(format!("{prefix}.samples.csv"), out).expect("writable dump");
        let mut out = String::from("x,y,z,ax,ay,az,kind,pass,speed\n");
        for (k, p) in plan.path.poses.iter().enumerate() {
            let _ = writeln!(
                out,
                "{:.1},{:.1},{:.1},{:.4},{:.4},{:.4},{},{},{:.1}",
                p.position.x * mm_per_unit,
                p.position.y * mm_per_unit,
                p.position.z * mm_per_unit,
                p.axis.x,
                p.axis.y,
                p.axis.z,
                p.kind.code(),
                p.pass,
                plan.path.move_speed(k.max(1)) * mm_per_unit
            );
        }
        std::fs::write(format!("{prefix}.poses.csv"), out).expect("writable dump");
    }
}
