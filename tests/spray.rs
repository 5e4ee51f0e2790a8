//! Spray trajectories and the coating model (seed 002) against closed forms, an independent
//! numerical integration and geometric invariants, through the public API.

mod common;

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use common::{binary_stl, import, Tri};
use skinpath::mesh::ImportedMesh;
use skinpath::spray::{
    patch_frame, plan_spray, QualityLimits, SprayError, SprayParams, SprayPlan,
    COARSE_RESOLUTION_RATIO, COARSE_STEPS, REFINE_STEPS,
};
use skinpath::toolpath::PoseKind;
use std::f64::consts::PI;

/// Standoff 100 and cone angle 2·atan(1/2): footprint radius R = 50.
const H: f64 = 100.0;
const R: f64 = 50.0;

fn params(spacing: f64) -> SprayParams {
    SprayParams {
        spacing,
        standoff: H,
        speed: 100.0,
        flow_rate: 1000.0,
        cone_angle: 2.0 * (0.5f64).atan(),
        transition_angle: 20f64.to_radians(),
        efficiency: 1.0,
        resolution: Some(R / 5.0),
        time_step: Some(R / 20.0 / 100.0),
        ..SprayParams::default()
    }
}

/// Peak rate A = 2ηQ/(πR²) of `params`.
fn peak_rate(p: &SprayParams) -> f64 {
    2.0 * p.efficiency * p.flow_rate / (PI * R * R)
}

/// Closed form of one straight pass on a plane: T(x) = (4AR/3v)(1 − x²/R²)^{3/2}.
fn single_pass(p: &SprayParams, x: f64) -> f64 {
    if x.abs() >= R {
        return 0.0;
    }
    4.0 * peak_rate(p) * R / (3.0 * p.speed) * (1.0 - x * x / (R * R)).powf(1.5)
}

/// A surface z-up over a grid `nu × nv` of `f(u, v)`, u, v in [0, 1], wound so the normals
/// point up (+z side) for a graph surface.
fn surface(nu: usize, nv: usize, f: impl Fn(f64, f64) -> [f64; 3]) -> Vec<Tri> {
    let p = |i: usize, j: usize| f(i as f64 / nu as f64, j as f64 / nv as f64).map(|c| c as f32);
    let mut out = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            out.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
            out.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
        }
    }
    out
}

fn plan(m: &ImportedMesh, p: &SprayParams) -> Result<SprayPlan, SprayError> {
    let faces: Vec<u32> = (0..m.mesh.triangle_count() as u32).collect();
    plan_spray(
        &m.mesh,
        &m.adjacency,
        &m.geometry,
        &faces,
        p,
        &mut |_, _| {},
    )
}

fn plate(w: f64, d: f64, nu: usize, nv: usize) -> ImportedMesh {
    let m = import(&binary_stl(&surface(nu, nv, |u, v| [w * u, d * v, 0.0])));
    assert!(m.geometry.normals().iter().all(|n| n.z > 0.99));
    m
}

/// Samples with x in `[x0, x1]` as (y, thickness).
fn samples_between(plan: &SprayPlan, x0: f64, x1: f64) -> Vec<(f64, f64)> {
    plan.samples
        .positions
        .iter()
        .zip(&plan.thickness)
        .filter(|(p, _)| p.x >= x0 && p.x <= x1)
        .map(|(p, &t)| (p.y, t))
        .collect()
}

#[test]
fn one_straight_pass_matches_the_closed_form() {
    // Two triangles per 100 × 100 cell: a coarse CAD-like plate, sampled finely by the plan.
    let m = plate(800.0, 200.0, 8, 2);
    let p = params(200.0);
    let plan = plan(&m, &p).unwrap();
    assert_eq!(plan.pass_count, 1);
    let peak = single_pass(&p, 0.0);
    let mut checked = 0;
    for (y, t) in samples_between(&plan, 250.0, 550.0) {
        let x = y - 100.0;
        if x.abs() <= 0.8 * R {
            assert_near!(t, single_pass(&p, x), 0.001 * peak);
            checked += 1;
        }
    }
    assert!(checked > 50, "only {checked} samples checked");
}

#[test]
fn parallel_passes_add_up_to_the_sum_of_closed_forms() {
    let m = plate(800.0, 400.0, 8, 4);
    let p = params(60.0);
    let plan = plan(&m, &p).unwrap();
    // ceil(400 / 60) = 7 planes, centred: y = 20, 80, …, 380.
    assert_eq!(plan.pass_count, 7);
    let ys: Vec<f64> = (0..7).map(|k| 20.0 + 60.0 * k as f64).collect();
    let peak = single_pass(&p, 0.0);
    let mut checked = 0;
    for (y, t) in samples_between(&plan, 250.0, 550.0) {
        let expected: f64 = ys.iter().map(|&yk| single_pass(&p, y - yk)).sum();
        assert_near!(t, expected, 0.002 * peak);
        checked += 1;
    }
    assert!(checked > 200);
    // The passes alternate direction (zig-zag).
    let direction = |pass: u32| {
        let poses: Vec<_> = plan.path.poses.iter().filter(|q| q.pass == pass).collect();
        (poses[poses.len() - 1].position - poses[0].position)
            .x
            .signum()
    };
    for pass in 1..7 {
        assert_eq!(direction(pass), -direction(pass - 1));
    }
}

/// Outward-facing cylinder panel of radius `rc` over angles ±`half` about +x, along z.
fn cylinder_panel(rc: f64, half: f64, length: f64, facets: usize, rows: usize) -> ImportedMesh {
    // Outward normals: u runs along −z.
    let m = import(&binary_stl(&surface(rows, facets, |u, v| {
        let a = -half + 2.0 * half * v;
        [rc * a.cos(), rc * a.sin(), length * (1.0 - u)]
    })));
    let n = m.geometry.normals()[0];
    let c = m.geometry.centroids()[0];
    assert!(n.x * c.x + n.y * c.y > 0.0, "normals must point outwards");
    m
}

/// The patch's width across the passes measured along the surface (the planner's table).
fn surface_width(m: &ImportedMesh) -> f64 {
    let faces: Vec<u32> = (0..m.mesh.triangle_count() as u32).collect();
    let frame = patch_frame(&m.mesh, &m.geometry, &faces, None, 0.0).unwrap();
    frame.arc[frame.arc.len() - 1]
}

#[test]
fn scan_planes_are_spaced_along_the_surface_on_a_cylinder() {
    // Radius 100, ±60°, facets of 2°: passes run along the axis (the longer side, 600).
    let (rc, half, facets) = (100.0, PI / 3.0, 60);
    let m = cylinder_panel(rc, half, 600.0, facets, 6);
    let polygon = facets as f64 * 2.0 * rc * (half / facets as f64).sin();
    assert_near!(surface_width(&m), polygon, 1e-3 * polygon);
    let b = 20.0;
    let plan = plan(&m, &params(b)).unwrap();
    // ceil(arc / b) planes, b apart along the surface: angles b / rc apart on the cylinder.
    assert_eq!(plan.pass_count, (polygon / b).ceil() as usize);
    let mut angles: Vec<f64> = (0..plan.pass_count as u32)
        .map(|k| {
            let q = plan
                .path
                .poses
                .iter()
                .find(|q| q.pass == k && q.kind == PoseKind::Pass)
                .unwrap();
            // The gun stands h off the surface along the axis: the surface point is below.
            let x = q.position + q.axis * H;
            x.y.atan2(x.x)
        })
        .collect();
    angles.sort_by(f64::total_cmp);
    for w in angles.windows(2) {
        // Facets flatten the arc: within 2% of b / rc.
        assert_near!(w[1] - w[0], b / rc, 0.02 * b / rc);
    }
}

#[test]
fn cylinder_panel_matches_a_direct_integration_and_the_curvature_matters() {
    let rc = 80.0;
    // An odd number of facets puts a facet centre at angle 0, where the single plane cuts.
    let m = cylinder_panel(rc, PI / 3.0, 600.0, 61, 6);
    // Planes are spaced along the surface: a spacing of the whole arc gives one plane.
    let width = surface_width(&m);
    let mut p = params(width);
    p.resolution = Some(R / 6.0);
    let plan = plan(&m, &p).unwrap();
    assert_eq!(plan.pass_count, 1);
    // The gun line from the trajectory: constant x, y and axis along the pass.
    let pass_pose = plan
        .path
        .poses
        .iter()
        .find(|q| q.kind == PoseKind::Pass)
        .unwrap();
    let (g, a) = (pass_pose.position, pass_pose.axis);
    assert_near!(a.z, 0.0, 1e-9);
    assert_near!(
        (g.x * g.x + g.y * g.y).sqrt(),
        rc * (0.5 * (120f64 / 61.0).to_radians()).cos() + H,
        1e-3
    );
    let (z0, z1) = {
        let zs: Vec<f64> = plan.path.poses.iter().map(|q| q.position.z).collect();
        (
            zs.iter().cloned().fold(f64::INFINITY, f64::min),
            zs.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        )
    };
    // Direct integration over the gun's travel: rate = A(1 − r²/R²)·(h/l)²·cos λ / cos θ with
    // r the radius where the ray meets the plane at distance h, λ from the facet normal.
    let a_rate = peak_rate(&p);
    let integrate = |x: [f64; 3], n: [f64; 3]| -> f64 {
        let steps = 1500;
        let dz = (z1 - z0) / steps as f64;
        let mut total = 0.0;
        for s in 0..steps {
            let gz = z0 + (s as f64 + 0.5) * dz;
            let w = [x[0] - g.x, x[1] - g.y, x[2] - gz];
            let l = w[0] * a.x + w[1] * a.y + w[2] * a.z;
            let dist = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            let tan_theta = ((dist * dist - l * l).max(0.0)).sqrt() / l;
            let r = H * tan_theta;
            let cos_lambda = -(w[0] * n[0] + w[1] * n[1] + w[2] * n[2]) / dist;
            if l <= 0.0 || r >= R || cos_lambda <= 0.0 {
                continue;
            }
            let cos_theta = l / dist;
            total += a_rate * (1.0 - r * r / (R * R)) * (H / l).powi(2) * cos_lambda / cos_theta
                * dz
                / p.speed;
        }
        total
    };
    let peak = single_pass(&p, 0.0);
    let (mut checked, mut largest_gap) = (0, 0.0f64);
    for ((x, n), &t) in plan
        .samples
        .positions
        .iter()
        .zip(&plan.samples.normals)
        .zip(&plan.thickness)
    {
        if x.z < 250.0 || x.z > 350.0 {
            continue;
        }
        let expected = integrate([x.x, x.y, x.z], [n.x, n.y, n.z]);
        assert_near!(t, expected, 0.003 * peak);
        // The flat closed form at the same lateral distance ignores the curvature.
        let flat = single_pass(&p, x.y);
        largest_gap = largest_gap.max((flat - expected).abs());
        checked += 1;
    }
    assert!(checked > 50);
    assert!(
        largest_gap > 0.05 * peak,
        "curvature changed the thickness by only {largest_gap}"
    );
}

/// A fold along the y axis: two planes of slope ±tan(β/2); `convex` makes a ridge.
fn fold(beta: f64, convex: bool) -> ImportedMesh {
    let s = (beta / 2.0).tan() * if convex { -1.0 } else { 1.0 };
    import(&binary_stl(&surface(8, 6, |u, v| {
        let x = -200.0 + 400.0 * u;
        [x, 300.0 * v, s * x.abs()]
    })))
}

#[test]
fn a_sharp_convex_fold_gets_arcs_of_radius_h_with_radial_axes() {
    let m = fold(40f64.to_radians(), true);
    let mut p = params(100.0);
    p.direction = Some([1.0, 0.0, 0.0]);
    let plan = plan(&m, &p).unwrap();
    assert_eq!(plan.counts.arcs, plan.pass_count);
    assert_eq!(plan.counts.straight + plan.counts.trimmed, 0);
    let arcs: Vec<_> = plan
        .path
        .poses
        .iter()
        .filter(|q| q.kind == PoseKind::Arc)
        .collect();
    assert!(arcs.len() >= 2 * plan.pass_count);
    for q in arcs {
        // The ridge is the y axis: distance h from it, axis pointing back at it.
        let radial = [q.position.x, 0.0, q.position.z];
        let d = (radial[0] * radial[0] + radial[2] * radial[2]).sqrt();
        assert_near!(d, H, 1e-6);
        assert_near!(q.axis.x, -radial[0] / d, 1e-9);
        assert_near!(q.axis.z, -radial[2] / d, 1e-9);
    }
}

#[test]
fn a_gentle_convex_fold_gets_straight_transitions_perpendicular_to_the_axis() {
    let m = fold(10f64.to_radians(), true);
    let mut p = params(100.0);
    p.direction = Some([1.0, 0.0, 0.0]);
    let plan = plan(&m, &p).unwrap();
    assert_eq!(plan.counts.straight, plan.pass_count);
    assert_eq!(plan.counts.arcs, 0);
    let poses = &plan.path.poses;
    let mut pairs = 0;
    for w in poses.windows(2) {
        if w[0].kind == PoseKind::StraightTransition && w[1].kind == PoseKind::StraightTransition {
            let chord = w[1].position - w[0].position;
            assert!(chord.norm() > 1.0);
            assert_near!(w[0].axis.dot(&chord), 0.0, 1e-9);
            assert_eq!(w[0].axis, w[1].axis);
            assert!(w[0].axis.z < -0.9, "towards the part");
            pairs += 1;
        }
    }
    assert_eq!(pairs, plan.pass_count);
}

#[test]
fn a_concave_fold_is_trimmed_without_moving_backwards() {
    let m = fold(60f64.to_radians(), false);
    let mut p = params(100.0);
    p.direction = Some([1.0, 0.0, 0.0]);
    let plan = plan(&m, &p).unwrap();
    assert_eq!(plan.counts.trimmed, plan.pass_count);
    assert_eq!(plan.counts.arcs + plan.counts.straight, 0);
    assert!(plan.path.notes.iter().any(|n| n.contains("concave")));
    for pass in 0..plan.pass_count as u32 {
        let on: Vec<_> = plan.path.poses.iter().filter(|q| q.pass == pass).collect();
        let dir = (on[on.len() - 1].position - on[0].position).x.signum();
        for w in on.windows(2) {
            assert!(
                (w[1].position - w[0].position).x * dir >= -1e-9,
                "moved backwards in pass {pass}"
            );
        }
        // The trim point lies over the valley, at the crossing of the offset lines: x = 0 and
        // z = h / cos(β/2) above the valley bottom.
        let trim = on
            .iter()
            .find(|q| q.position.x.abs() < 1e-6)
            .expect("a pose over the valley");
        assert_near!(trim.position.z, H / 30f64.to_radians().cos(), 1e-3);
    }
}

#[test]
fn outermost_passes_lie_within_half_a_spacing_of_the_boundary() {
    let m = plate(500.0, 300.0, 5, 3);
    for b in [70.0, 90.0, 133.0, 300.0] {
        let plan = plan(&m, &params(b)).unwrap();
        let ys: Vec<f64> = plan
            .path
            .poses
            .iter()
            .filter(|q| q.kind == PoseKind::Pass)
            .map(|q| q.position.y)
            .collect();
        let lo = ys.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = ys.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        assert!(
            lo > 0.0 && lo <= b / 2.0 + 1e-9,
            "b {b}: first pass at {lo}"
        );
        assert!(
            hi < 300.0 && hi >= 300.0 - b / 2.0 - 1e-9,
            "b {b}: last pass at {hi}"
        );
        assert_eq!(plan.pass_count, (300.0 / b).ceil() as usize);
        // Gun axis −n and standoff h on the passes.
        for q in plan.path.poses.iter().filter(|q| q.kind == PoseKind::Pass) {
            assert_near!(q.position.z, H, 1e-4);
            assert_near!(q.axis.z, -1.0, 1e-9);
        }
        // Links are the only gun-off moves and start each pass.
        let links = plan
            .path
            .poses
            .iter()
            .filter(|q| q.kind == PoseKind::Link)
            .count();
        assert_eq!(links, plan.pass_count);
    }
}

fn check_search(plan: &SprayPlan, max_error: f64, resolution: f64) {
    assert!(plan.limits_met, "{:?}", plan.messages);
    assert!(plan.quality.interior.error <= max_error);
    // The scan ran at the coarse resolution (these meshes are coarser than both), from the
    // widest spacing down until one met the limits; everything after it at full resolution.
    let coarse = COARSE_RESOLUTION_RATIO * resolution;
    let scan = plan
        .iterations
        .iter()
        .take_while(|it| it.resolution == coarse)
        .count();
    assert!((1..=COARSE_STEPS).contains(&scan), "{scan} coarse");
    assert!(plan.iterations[scan - 1].met);
    for w in plan.iterations[..scan].windows(2) {
        assert!(w[0].spacing > w[1].spacing && !w[0].met);
    }
    for it in &plan.iterations[scan..] {
        assert_eq!(it.resolution, resolution);
    }
    // One confirmation at full resolution, at least one refinement round.
    assert!(plan.iterations.len() >= scan + 1 + REFINE_STEPS);
    let full: Vec<_> = plan
        .iterations
        .iter()
        .filter(|it| it.resolution == resolution)
        .collect();
    assert!(full.iter().any(|it| it.spacing == plan.spacing && it.met));
    // The plan's figures are those of the chosen spacing at full resolution.
    let chosen = full
        .iter()
        .rev()
        .find(|it| it.spacing == plan.spacing)
        .unwrap();
    assert_eq!(chosen.error, plan.quality.interior.error);
    for it in &plan.iterations {
        assert_eq!(it.met, it.error <= max_error);
    }
    // The largest feasible spacing tried at full resolution is the one chosen.
    for it in &full {
        assert!(
            !(it.met && it.spacing > plan.spacing),
            "{} is feasible and larger",
            it.spacing
        );
    }
    // Wide spacings leave stripes: the search did find infeasible ones.
    assert!(plan.iterations.iter().any(|it| !it.met));
}

#[test]
fn the_spacing_search_meets_the_limits_on_a_plate() {
    let m = plate(400.0, 300.0, 4, 3);
    let mut p = params(50.0);
    p.resolution = Some(R / 4.0);
    p.time_step = Some(R / 10.0 / p.speed);
    p.quality = Some(QualityLimits {
        max_error: Some(0.1),
        min_spacing: Some(R / 2.0),
        ..QualityLimits::default()
    });
    let plan = plan(&m, &p).unwrap();
    check_search(&plan, 0.1, R / 4.0);
    assert!(
        plan.spacing > 0.5 * R && plan.spacing < 2.0 * R,
        "spacing {}",
        plan.spacing
    );
}

#[test]
fn the_spacing_search_meets_the_limits_on_a_curved_panel_and_scales_the_speed() {
    let m = cylinder_panel(300.0, PI / 6.0, 300.0, 20, 6);
    let mut p = params(50.0);
    p.resolution = Some(R / 3.0);
    p.time_step = Some(R / 6.0 / p.speed);
    p.quality = Some(QualityLimits {
        max_error: Some(0.15),
        max_std_dev: Some(1.0),
        min_spacing: Some(R / 2.0),
        ..QualityLimits::default()
    });
    p.target_thickness = Some(0.05);
    let plan = plan(&m, &p).unwrap();
    check_search(&plan, 0.15, R / 3.0);
    // Thickness ∝ 1/v: the interior mean is the target, at a speed that says so.
    assert_near!(plan.quality.interior.mean, 0.05, 1e-12);
    let chosen = plan
        .iterations
        .iter()
        .rfind(|it| it.spacing == plan.spacing && it.resolution == R / 3.0)
        .unwrap();
    assert_near!(plan.speed, p.speed * chosen.mean / 0.05, 1e-9 * plan.speed);
    assert_eq!(plan.path.speed, plan.speed);
}

#[test]
fn impossible_limits_return_the_closest_spacing_and_say_so() {
    let m = plate(300.0, 300.0, 3, 3);
    let mut p = params(50.0);
    p.resolution = Some(R / 3.0);
    p.time_step = Some(R / 8.0 / p.speed);
    p.quality = Some(QualityLimits {
        max_error: Some(1e-6),
        ..QualityLimits::default()
    });
    let plan = plan(&m, &p).unwrap();
    assert!(!plan.limits_met);
    assert!(plan.messages.iter().any(|s| s.contains("not met")));
    assert!(plan.iterations.iter().all(|it| !it.met));
    // The closest spacing among those tried at full resolution.
    assert!(plan.iterations.iter().any(|it| it.resolution == R / 3.0));
    let best = plan
        .iterations
        .iter()
        .filter(|it| it.resolution == R / 3.0)
        .map(|it| it.error)
        .fold(f64::INFINITY, f64::min);
    assert_near!(plan.quality.interior.error, best, 1e-12);
}

#[test]
fn bad_parameters_are_refused_by_name() {
    let m = plate(300.0, 300.0, 3, 3);
    type Change = Box<dyn Fn(&mut SprayParams)>;
    let cases: Vec<(&str, Change)> = vec![
        ("spacing", Box::new(|p| p.spacing = -1.0)),
        ("spacing", Box::new(|p| p.spacing = f64::NAN)),
        ("standoff", Box::new(|p| p.standoff = 0.0)),
        ("speed", Box::new(|p| p.speed = -3.0)),
        ("flowRate", Box::new(|p| p.flow_rate = 0.0)),
        ("coneAngle", Box::new(|p| p.cone_angle = PI)),
        ("coneAngle", Box::new(|p| p.cone_angle = 0.0)),
        ("transitionAngle", Box::new(|p| p.transition_angle = -0.1)),
        ("efficiency", Box::new(|p| p.efficiency = 1.5)),
        ("efficiency", Box::new(|p| p.efficiency = 0.0)),
        (
            "direction",
            Box::new(|p| p.direction = Some([0.0, 0.0, 0.0])),
        ),
        (
            "direction",
            Box::new(|p| p.direction = Some([0.0, 0.0, 1.0])),
        ),
        ("rasterAngle", Box::new(|p| p.raster_angle = f64::INFINITY)),
        ("extension", Box::new(|p| p.extension = Some(-1.0))),
        ("timeStep", Box::new(|p| p.time_step = Some(0.0))),
        ("resolution", Box::new(|p| p.resolution = Some(-2.0))),
        ("resolution", Box::new(|p| p.resolution = Some(1e-3))),
        (
            "edgeExclusion",
            Box::new(|p| p.edge_exclusion = Some(f64::NAN)),
        ),
        (
            "quality.maxStdDev",
            Box::new(|p| {
                p.quality = Some(QualityLimits {
                    max_std_dev: Some(0.0),
                    ..Default::default()
                })
            }),
        ),
        (
            "quality.maxError",
            Box::new(|p| {
                p.quality = Some(QualityLimits {
                    max_error: Some(-1.0),
                    ..Default::default()
                })
            }),
        ),
        (
            "quality.maxSpacing",
            Box::new(|p| {
                p.quality = Some(QualityLimits {
                    max_error: Some(0.1),
                    min_spacing: Some(50.0),
                    max_spacing: Some(10.0),
                    ..Default::default()
                })
            }),
        ),
        (
            "targetThickness",
            Box::new(|p| p.target_thickness = Some(0.0)),
        ),
        ("spacing", Box::new(|p| p.spacing = 301.0)),
    ];
    for (name, change) in cases {
        let mut p = params(60.0);
        p.direction = Some([1.0, 0.0, 0.0]);
        change(&mut p);
        let message = match plan(&m, &p) {
            Ok(_) => panic!("{name}: accepted"),
            Err(e) => e.to_string(),
        };
        assert!(message.contains(name), "'{message}' does not name {name}");
    }
}

#[test]
fn bad_face_lists_are_refused() {
    let m = plate(300.0, 300.0, 3, 3);
    let run = |faces: &[u32]| {
        plan_spray(
            &m.mesh,
            &m.adjacency,
            &m.geometry,
            faces,
            &params(60.0),
            &mut |_, _| {},
        )
        .unwrap_err()
    };
    assert_eq!(run(&[]), SprayError::NoFaces);
    assert_eq!(
        run(&[0, 18]),
        SprayError::UnknownFace {
            face: 18,
            count: 18
        }
    );
    assert!(run(&[0, 18]).to_string().contains("18"));
}

#[test]
fn planes_that_miss_the_patch_are_reported() {
    // Two triangles far apart across the passes: one plane in the middle misses both.
    let tris: Vec<Tri> = vec![
        [[0.0, 0.0, 0.0], [400.0, 0.0, 0.0], [400.0, 10.0, 0.0]],
        [[0.0, 290.0, 0.0], [400.0, 290.0, 0.0], [400.0, 300.0, 0.0]],
    ];
    let m = import(&binary_stl(&tris));
    let mut p = params(300.0);
    p.direction = Some([1.0, 0.0, 0.0]);
    let err = plan(&m, &p).unwrap_err();
    assert_eq!(err, SprayError::PlanesMissPatch);
    assert!(err.to_string().contains("miss"));
}

/// Runs the paper's set-up (h 250 mm, v 400 mm/s, α 40°, Q 150 cm³/min, η 0.6, β_T 20°) on
/// the largest patch of a real model in metres, with the limit δ ≤ 0.2 and prints the figures.
///
/// Figures (resolution 0.04 m here; the page's default R/8 ≈ 0.011 m gives similar ones).
/// Planes spaced b in space (before): bwb_4464 at b = 0.09 m: 382 passes, interior δ 1.18,
/// E 4.5 µm, whole δ 1.18; wingbody_79868 at 0.09 m: 23 passes, interior δ 0.93,
/// E 5.7 µm, whole δ 1.03 (samples with no paint: at the patch boundary where the surface
/// is inclined ~55° to the mean plane across the passes, passes 1.74× farther apart on the
/// surface than b). Planes spaced b along the surface (now): bwb_4464 398 passes,
/// interior δ 1.28, E 4.7 µm; wingbody_79868 22 passes, interior δ 0.63, E 4.3 µm, whole
/// δ 1.00. No spacing meets δ ≤ 0.2 on either patch: the thickest samples lie where the
/// surface turns by up to θmax = 1 rad under planar scan planes (the bwb nose, ~2.2× the
/// mean), which no spacing evens out.
#[cfg(not(target_arch = "wasm32"))]
fn real_model(name: &str) {
    use skinpath::segment::{segment, SegmentParams};
    let m = import(&common::model(name));
    let seg = segment(&m.adjacency, &m.geometry, &SegmentParams::default()).unwrap();
    let faces: Vec<u32> = seg.faces_of(0).map(|f| f as u32).collect();
    let mm = 1e-3;
    let p = SprayParams {
        spacing: 0.09,
        standoff: 250.0 * mm,
        speed: 400.0 * mm,
        flow_rate: 150.0 * 1e-6 / 60.0,
        cone_angle: 40f64.to_radians(),
        transition_angle: 20f64.to_radians(),
        efficiency: 0.6,
        resolution: Some(0.04),
        quality: Some(QualityLimits {
            max_error: Some(0.2),
            ..QualityLimits::default()
        }),
        ..SprayParams::default()
    };
    let plan = plan_spray(
        &m.mesh,
        &m.adjacency,
        &m.geometry,
        &faces,
        &p,
        &mut |_, _| {},
    )
    .unwrap();
    let q = plan.quality.interior;
    println!(
        "{name}: patch of {} faces, area {:.2} m²; spacing {:.4} m, {} passes, met {}, interior δ {:.3}, E {:.3} µm, mean {:.2} µm; {} samples, {} poses, {} iterations",
        faces.len(), seg.patches[0].area, plan.spacing, plan.pass_count, plan.limits_met, q.error, q.std_dev * 1e6, q.mean * 1e6,
        plan.samples.positions.len(), plan.path.poses.len(), plan.iterations.len()
    );
    assert!(plan.pass_count > 0 && q.mean > 0.0);
    let fixed = SprayParams { quality: None, ..p };
    let plan = plan_spray(
        &m.mesh,
        &m.adjacency,
        &m.geometry,
        &faces,
        &fixed,
        &mut |_, _| {},
    )
    .unwrap();
    let q = plan.quality.interior;
    println!(
        "{name} at spacing {} m without limits: {} passes, interior δ {:.3}, E {:.3} µm, mean {:.2} µm; whole δ {:.3}, E {:.3} µm",
        plan.spacing, plan.pass_count, q.error, q.std_dev * 1e6, q.mean * 1e6, plan.quality.whole.error, plan.quality.whole.std_dev * 1e6
    );
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
#[ignore = "slow in a debug build: cargo test --release --test spray -- --ignored --nocapture"]
fn real_models_with_the_paper_set_up() {
    real_model("bwb_4464_pygeo_ascii.stl");
    real_model("wingbody_79868_flow360.stl");
}
