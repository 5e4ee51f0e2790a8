//! Segmentation (seed 000) against known answers and invariants, through the public API.

mod common;

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use common::{binary_stl, check_invariants, cylinder, import, plane, refined_cube, Tri};
use skinpath::segment::{
    grind_curvature_threshold, grow_regions, planarise, seed_order, segment, spray_angle_threshold,
    Criterion, GrindParams, GrowthThreshold, ParamError, ParamsSpec, SeedRule, SegmentParams,
    SprayParams, MIN_ANGLE_RAD,
};
use std::f64::consts::PI;

fn params(criterion: Criterion, theta_max_rad: f64, min_area_ratio: f64) -> SegmentParams {
    SegmentParams {
        criterion,
        theta_max_rad,
        min_area_ratio,
        ..SegmentParams::default()
    }
}

#[test]
fn cubes_coarse_and_refined_give_six_patches() {
    for bytes in [
        fixture!("cube_binary.stl").to_vec(),
        fixture!("flipped_faces.stl").to_vec(),
        binary_stl(&refined_cube(8)),
    ] {
        let m = import(&bytes);
        let seg = segment(&m.adjacency, &m.geometry, &SegmentParams::default()).unwrap();
        assert_eq!(check_invariants(&m, &seg, 1.0, 0.1), 6);
        assert_eq!(seg.region_count, 6);
        for p in &seg.patches {
            assert_near!(p.area, 1.0, 1e-9);
            assert_near!(p.max_deviation, 0.0, 1e-9);
        }
    }
}

#[test]
fn open_cylinder_splits_into_about_pi_over_theta_max_patches() {
    let m = import(&binary_stl(&cylinder(1.0, 3.0, 96, 12)));
    for theta in [1.2, 1.0, 0.7, 0.5, 0.3] {
        // α above the facet angle 2π/96: the whole tube is one step-1 region.
        let p = params(Criterion::Angle { alpha_rad: 0.35 }, theta, 0.0);
        let seg = segment(&m.adjacency, &m.geometry, &p).unwrap();
        assert_eq!(seg.region_count, 1);
        check_invariants(&m, &seg, theta, 0.0);
        // The patches covering 95 % of the area.
        let total: f64 = seg.patches.iter().map(|p| p.area).sum();
        let mut covered = 0.0;
        let main = seg
            .patches
            .iter()
            .take_while(|p| {
                let before = covered;
                covered += p.area;
                before < 0.95 * total
            })
            .count();
        let expected = (PI / theta).ceil() as usize;
        assert!(
            (expected..=expected + 1).contains(&main),
            "θmax {theta}: {main} main patches, expected about {expected}"
        );
    }
}

#[test]
fn curvature_threshold_grows_around_a_tube_only_above_one_over_radius() {
    let (r, n) = (2.0, 64);
    let m = import(&binary_stl(&cylinder(r, 5.0, n, 10)));
    let below = params(Criterion::Curvature { kappa: 0.9 / r }, PI, 0.0);
    let seg = segment(&m.adjacency, &m.geometry, &below).unwrap();
    assert_eq!(seg.region_count, n, "one axial strip per facet column");
    let above = params(Criterion::Curvature { kappa: 1.1 / r }, PI, 0.0);
    let seg = segment(&m.adjacency, &m.geometry, &above).unwrap();
    assert_eq!(seg.region_count, 1, "the whole tube");
}

#[test]
fn derived_thresholds_follow_equations_4_and_9() {
    let spray = SprayParams {
        mean_thickness: 100.0,
        allowed_deviation: 6.0,
        min_thickness: 97.0,
    };
    assert_near!(
        spray_angle_threshold(&spray).unwrap(),
        (94.0f64 / 97.0).acos(),
        1e-12
    );
    let grind = GrindParams {
        indentation_depth: 0.2,
        min_pressure_ratio: 0.6,
        contact_width: 8.0,
    };
    assert_near!(
        grind_curvature_threshold(&grind).unwrap(),
        2.0 * 0.2 * (1.0 - 0.36) / 64.0,
        1e-12
    );
    assert_eq!(
        Criterion::Grind(grind).threshold().unwrap(),
        GrowthThreshold::Curvature(2.0 * 0.2 * (1.0 - 0.36) / 64.0)
    );
}

#[test]
fn bad_parameters_are_refused_with_the_parameter_named() {
    let spray = |qd, dq, qmin| {
        Criterion::Spray(SprayParams {
            mean_thickness: qd,
            allowed_deviation: dq,
            min_thickness: qmin,
        })
    };
    let grind = |d, delta, lc| {
        Criterion::Grind(GrindParams {
            indentation_depth: d,
            min_pressure_ratio: delta,
            contact_width: lc,
        })
    };
    let angle = Criterion::Angle { alpha_rad: 0.35 };
    let cases = [
        (
            params(grind(0.1, 1.0, 5.0), 1.0, 0.1),
            "minPressureRatio must be strictly between 0 and 1, got 1",
        ),
        (
            params(grind(0.1, 0.0, 5.0), 1.0, 0.1),
            "minPressureRatio must be strictly between 0 and 1",
        ),
        (
            params(grind(-0.1, 0.5, 5.0), 1.0, 0.1),
            "indentationDepth must be greater than 0",
        ),
        (
            params(spray(100.0, 10.0, 80.0), 1.0, 0.1),
            "outside [−1, 1]",
        ),
        (
            params(spray(100.0, 0.0, 100.0), 1.0, 0.1),
            "derived angle threshold is 0 rad",
        ),
        (
            params(spray(100.0, 120.0, 80.0), 1.0, 0.1),
            "allowedDeviation must be at least 0 and less than the mean thickness",
        ),
        (
            params(angle, 0.0, 0.1),
            "thetaMax must be in (0, π] radians, got 0",
        ),
        (
            params(angle, 3.5, 0.1),
            "thetaMax must be in (0, π] radians",
        ),
        (
            params(angle, 1.0, 1.0),
            "minAreaRatio must be at least 0 and less than 1, got 1",
        ),
        (
            params(angle, 1.0, -0.1),
            "minAreaRatio must be at least 0 and less than 1",
        ),
        (
            params(angle, f64::NAN, 0.1),
            "thetaMax must be a finite number, got NaN",
        ),
        (
            params(Criterion::Angle { alpha_rad: 4.0 }, 1.0, 0.1),
            "angleThreshold must be in (0, π] radians",
        ),
        (
            params(Criterion::Curvature { kappa: 0.0 }, 1.0, 0.1),
            "curvatureThreshold must be greater than 0",
        ),
    ];
    let m = import(fixture!("cube_binary.stl"));
    for (p, expected) in cases {
        let message = segment(&m.adjacency, &m.geometry, &p)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(expected),
            "got {message:?}, expected {expected:?}"
        );
    }
    let two = ParamsSpec {
        angle_threshold: Some(0.3),
        spray: Some(
            SprayParams {
                mean_thickness: 1.0,
                allowed_deviation: 0.1,
                min_thickness: 1.0,
            }
            .into(),
        ),
        ..ParamsSpec::default()
    };
    assert_eq!(
        SegmentParams::try_from(two).unwrap_err(),
        ParamError::CriterionCount {
            given: "angleThreshold, spray".into()
        }
    );
}

#[test]
fn small_patches_are_dropped_by_area_ratio() {
    // A big plane and a small one, far apart: at ε = 10 % the small one (1 %) goes.
    let mut triangles = plane(10.0, 10.0, 4);
    triangles.extend(
        plane(1.0, 1.0, 1)
            .into_iter()
            .map(|t| t.map(|[x, y, z]| [x + 20.0, y, z])),
    );
    let m = import(&binary_stl(&triangles));
    let seg = segment(&m.adjacency, &m.geometry, &SegmentParams::default()).unwrap();
    assert_eq!(check_invariants(&m, &seg, 1.0, 0.1), 1);
    assert_eq!(seg.dropped_count(), 2);
    assert_eq!(seg.patch_of[32..], [-1, -1]);
    let keep_all = params(Criterion::Angle { alpha_rad: 0.35 }, 1.0, 0.0);
    assert_eq!(
        segment(&m.adjacency, &m.geometry, &keep_all)
            .unwrap()
            .patches
            .len(),
        2
    );
}

#[test]
fn patch_stl_holds_exactly_the_patch_faces() {
    let m = import(fixture!("cube_ascii.stl"));
    let seg = segment(&m.adjacency, &m.geometry, &SegmentParams::default()).unwrap();
    let stl = seg.patch_stl(&m.mesh, 0).unwrap();
    let back = import(&stl);
    assert_eq!(back.report.triangles, 2);
    assert_near!(back.report.area, 1.0, 1e-12);
    assert!(seg.patch_stl(&m.mesh, 6).is_none());
    // Every cube edge is a border between two different patches: 12 segments.
    let borders = seg.border_edges(&m.mesh, &m.adjacency);
    assert_eq!(borders.len(), 12);
    assert!(borders
        .iter()
        .all(|e| e.patches[0] != e.patches[1] && e.patches.iter().all(|&p| p >= 0)));
    assert_eq!(seg.border_patches(&m.mesh, &m.adjacency).len(), 24);
}

#[test]
fn every_seed_rule_keeps_the_invariants_and_is_deterministic() {
    let m = import(&binary_stl(&common::sphere(1.0, 48, 24)));
    for rule in [
        SeedRule::LowestIndex,
        SeedRule::Flattest,
        SeedRule::LargestArea,
    ] {
        for theta in [0.4, 1.0, PI] {
            let p = SegmentParams {
                seed_rule: rule,
                ..params(Criterion::Angle { alpha_rad: 0.35 }, theta, 0.0)
            };
            let a = segment(&m.adjacency, &m.geometry, &p).unwrap();
            check_invariants(&m, &a, theta, 0.0);
            assert_eq!(
                a,
                segment(&m.adjacency, &m.geometry, &p).unwrap(),
                "{rule:?} is deterministic"
            );
        }
    }
}

/// The paper's run and the invariants on the real models (native only: no file system in wasm).
#[cfg(not(target_arch = "wasm32"))]
mod real_models {
    use super::*;

    const MODELS: [&str; 5] = [
        "airplane_10796_pymeshlab.stl",
        "wingbody_79868_flow360.stl",
        "b747_14062_flightgear.stl",
        "bwb_4464_pygeo_ascii.stl",
        "orion_51736_nasa.stl",
    ];

    #[test]
    fn invariants_hold_on_every_real_model_for_several_settings() {
        for name in MODELS {
            let m = import(&common::model(name));
            for (criterion, theta, ratio) in [
                (Criterion::Angle { alpha_rad: 0.35 }, 1.0, 0.1),
                (Criterion::Angle { alpha_rad: 0.2 }, 0.5, 0.0),
                (Criterion::Curvature { kappa: 2.0 }, 0.8, 0.01),
            ] {
                for rule in [
                    SeedRule::LowestIndex,
                    SeedRule::Flattest,
                    SeedRule::LargestArea,
                ] {
                    let p = SegmentParams {
                        seed_rule: rule,
                        ..params(criterion, theta, ratio)
                    };
                    let seg = segment(&m.adjacency, &m.geometry, &p).unwrap();
                    check_invariants(&m, &seg, theta, ratio);
                }
            }
        }
    }

    #[test]
    fn paper_parameters_on_the_aircraft_models() {
        // α_th = 0.35 rad, θmax = 1 rad, ε = 10 % (the paper reports 7 patches on its model).
        for name in MODELS {
            let m = import(&common::model(name));
            let mut counts = Vec::new();
            for rule in [
                SeedRule::LowestIndex,
                SeedRule::Flattest,
                SeedRule::LargestArea,
            ] {
                let p = SegmentParams {
                    seed_rule: rule,
                    ..SegmentParams::default()
                };
                let seg = segment(&m.adjacency, &m.geometry, &p).unwrap();
                let n = check_invariants(&m, &seg, 1.0, 0.1);
                let kept: f64 = seg.patches.iter().map(|p| p.area).sum::<f64>() / m.report.area;
                counts.push(format!(
                    "{rule:?}: {n} patches ({} before ε, {:.0} % of the area kept)",
                    seg.planar_patch_count,
                    100.0 * kept
                ));
                assert!((1..=10).contains(&n), "{name} {rule:?}: {n} patches");
            }
            eprintln!("{name}: {}", counts.join("; "));
        }
    }

    #[test]
    fn the_wing_body_splits_like_the_papers_aircraft() {
        // The paper: wing upper/lower, tail upper/lower and a fuselage in 3 near-planar parts.
        // This model has no tail: its two wings give 4 skins (mirror pairs of equal area,
        // normals ±z) and the fuselage 3 parts.
        let m = import(&common::model("wingbody_79868_flow360.stl"));
        let seg = segment(&m.adjacency, &m.geometry, &SegmentParams::default()).unwrap();
        assert_eq!(seg.patches.len(), 7);
        let wings: Vec<_> = seg
            .patches
            .iter()
            .filter(|p| p.normal[2].abs() > 0.99 && p.centroid[1].abs() > 1.0)
            .collect();
        assert_eq!(
            wings.len(),
            4,
            "four wing skins away from the fuselage axis"
        );
        let up = wings.iter().filter(|p| p.normal[2] > 0.0).count();
        assert_eq!(up, 2, "two upper and two lower skins");
        for p in &wings {
            assert_near!(p.area, wings[0].area, 0.01 * wings[0].area);
        }
    }
}

#[test]
fn a_theta_max_below_the_precision_of_normals_is_refused() {
    // The file that hung: a small closed sphere, every face in one region, θmax ≈ 2e-8.
    let m = import(&binary_stl(&common::sphere(1.0, 10, 5)));
    for theta in [2e-8, 1e-8, 1e-12, 5e-324, 0.999e-6] {
        let p = params(
            Criterion::Angle {
                alpha_rad: PI - 1e-5,
            },
            theta,
            0.0,
        );
        let message = segment(&m.adjacency, &m.geometry, &p)
            .unwrap_err()
            .to_string();
        assert!(
            message.starts_with("thetaMax must be at least 1e-6 radians (allowed: 1e-6 to π;"),
            "{theta}: {message}"
        );
    }
    let message = segment(
        &m.adjacency,
        &m.geometry,
        &params(Criterion::Angle { alpha_rad: 2e-8 }, 1.0, 0.0),
    )
    .unwrap_err()
    .to_string();
    assert!(
        message.contains("angleThreshold must be at least 1e-6 radians"),
        "{message}"
    );
    // At the limit the promise holds: every face within θmax of its patch's mean normal.
    let p = params(
        Criterion::Angle {
            alpha_rad: PI - 1e-5,
        },
        MIN_ANGLE_RAD,
        0.0,
    );
    let seg = segment(&m.adjacency, &m.geometry, &p).unwrap();
    // 80 faces: 20 at the poles, 60 in planar quads whose halves may pair up.
    let count = check_invariants(&m, &seg, MIN_ANGLE_RAD, 0.0);
    assert!((50..=80).contains(&count), "{count} patches");
    // The cube's coplanar pairs have bit-identical normals and still pair up.
    let cube = import(fixture!("cube_binary.stl"));
    let seg = segment(&cube.adjacency, &cube.geometry, &p).unwrap();
    assert_eq!(check_invariants(&cube, &seg, MIN_ANGLE_RAD, 0.0), 6);
}

#[test]
fn planarisation_ends_for_any_theta_max_even_unvalidated() {
    // planarise is public: below the precision (or NaN) it cannot keep the θmax promise,
    // but it must still end, with every face in exactly one non-empty patch.
    let m = import(&binary_stl(&common::sphere(1.0, 10, 5)));
    let regions = grow_regions(&m.adjacency, &m.geometry, GrowthThreshold::Angle(PI - 1e-5));
    assert_eq!(regions.count, 1);
    let n = m.report.triangles;
    for rule in [SeedRule::LowestIndex, SeedRule::Flattest] {
        let order = seed_order(&m.adjacency, &m.geometry, rule);
        for theta in [0.0, 5e-324, 1e-12, 1e-8, 2e-8, f64::NAN, MIN_ANGLE_RAD] {
            let patches = planarise(
                &m.adjacency,
                &m.geometry,
                &regions,
                theta,
                &order,
                &mut |_, _| {},
            );
            assert!(
                (1..=n).contains(&patches.count),
                "{theta}: {} patches",
                patches.count
            );
            let mut size = vec![0usize; patches.count];
            for &p in &patches.patch_of {
                size[p as usize] += 1;
            }
            assert!(size.iter().all(|&s| s > 0), "{theta}: an empty patch");
        }
    }
}

#[test]
fn grinding_parameters_that_derive_zero_or_infinity_are_refused() {
    let m = import(fixture!("cube_binary.stl"));
    for (d, delta, lc, value) in [
        (1e-300, 0.5, 1e150, "0"),
        (1e300, 0.5, 1e-300, "Infinity"),
        (f64::MAX, 0.1, 0.5, "Infinity"),
        (5e-324, 0.999, 1.0, "0"),
    ] {
        let p = params(
            Criterion::Grind(GrindParams {
                indentation_depth: d,
                min_pressure_ratio: delta,
                contact_width: lc,
            }),
            1.0,
            0.1,
        );
        let message = segment(&m.adjacency, &m.geometry, &p)
            .unwrap_err()
            .to_string();
        assert!(
            message.starts_with(
                "the curvature threshold (1 / mesh unit) derived from grind (indentationDepth "
            ) && message.contains(&format!(
                "is {value}, but it must be a finite number greater than 0"
            )),
            "{message}"
        );
    }
    // A tiny spray angle is refused as an angle is.
    let p = params(
        Criterion::Spray(SprayParams {
            mean_thickness: 100.0,
            allowed_deviation: 1e-12,
            min_thickness: 100.0,
        }),
        1.0,
        0.1,
    );
    let message = segment(&m.adjacency, &m.geometry, &p)
        .unwrap_err()
        .to_string();
    assert!(message.contains("angle threshold (rad) derived from spray (meanThickness 100, allowedDeviation 1e-12, minThickness 100)"), "{message}");
}

#[test]
fn theta_max_of_pi_keeps_its_promise_on_a_nearly_closed_patch() {
    // Found by tests/fuzz.rs: an open tube with one corner pulled down is one patch at
    // θmax = π; its mean normal is short, and a face almost opposite it was reported at
    // exactly π.
    let mut tube = common::cylinder(1.0, 3.0, 16, 3);
    tube[56][1][2] = 1e-20;
    let m = import(&binary_stl(&tube));
    for rule in [
        SeedRule::Flattest,
        SeedRule::LowestIndex,
        SeedRule::LargestArea,
    ] {
        let p = SegmentParams {
            seed_rule: rule,
            ..params(Criterion::Angle { alpha_rad: PI }, PI, 0.0)
        };
        let seg = segment(&m.adjacency, &m.geometry, &p).unwrap();
        check_invariants(&m, &seg, PI, 0.0);
    }
}

#[test]
fn a_patch_of_degenerate_faces_is_dropped_and_every_patch_reads_back() {
    // A needle far larger in area than the healthy faces but 4e-8 of its length thick, and
    // a small open fan: with no area threshold, the needle alone used to be patch 0, whose
    // STL no reader accepts (all its triangles degenerate).
    let needle: Tri = [[0.0, 0.0, 5.0], [1000.0, 0.0, 5.0], [500.0, 4e-5, 5.0]];
    let mut triangles = vec![needle];
    triangles.extend(plane(0.1, 0.1, 2));
    let m = import(&binary_stl(&triangles));
    assert_eq!(m.report.degenerate_triangles, 1);
    let f = (0..m.mesh.triangle_count())
        .find(|&f| m.geometry.is_degenerate(f))
        .unwrap();
    assert!(m.geometry.areas()[f] > 0.5 * m.geometry.total_area());
    let p = params(Criterion::Angle { alpha_rad: 0.1 }, 0.2, 0.0);
    let seg = segment(&m.adjacency, &m.geometry, &p).unwrap();
    assert_eq!(seg.patch_of[f], skinpath::segment::DROPPED);
    assert_eq!(seg.dropped_count(), 1);
    check_invariants(&m, &seg, p.theta_max_rad, p.min_area_ratio);
    assert!(!seg.patches.is_empty());
    for patch in &seg.patches {
        let back = import(&seg.patch_stl(&m.mesh, patch.id).unwrap());
        assert_eq!(back.report.triangles, patch.triangle_count);
        assert_eq!(back.report.area.to_bits(), patch.area.to_bits());
    }
}

/// FNV-1a, 64 bit, over 64-bit words.
fn fnv1a(words: impl IntoIterator<Item = u64>) -> u64 {
    words.into_iter().fold(0xcbf2_9ce4_8422_2325, |h, w| {
        w.to_le_bytes()
            .iter()
            .fold(h, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
    })
}

/// Import and segmentation of a file of several shells with mixed windings (the winding
/// propagation path), a sliver and an open tube give the same bits natively and in
/// WebAssembly: face geometry, report, patch ids and patch statistics. The constant was
/// computed natively; the same test runs in WebAssembly.
#[test]
fn a_mixed_multi_shell_file_segments_bit_identically_natively_and_in_webassembly() {
    let mut triangles: Vec<Tri> = common::sphere(1.0, 24, 12)
        .into_iter()
        .enumerate()
        .map(|(i, [a, b, c])| if i % 7 == 3 { [a, c, b] } else { [a, b, c] })
        .collect();
    triangles.extend(
        cylinder(0.4, 2.0, 16, 6)
            .into_iter()
            .map(|t| t.map(|p| [p[0] + 3.0, p[1], p[2]])),
    );
    triangles.push([[3.4, 0.0, 0.0], [3.4, 0.0, 2.0], [3.4, 1e-9, 1.0]]);
    let m = import(&binary_stl(&triangles));
    assert!(m.report.flipped_triangles > 0 && m.report.boundary_edges > 0);
    let mut words: Vec<u64> = vec![
        m.report.triangles as u64,
        m.report.vertices as u64,
        m.report.area.to_bits(),
        m.report.flipped_triangles as u64,
        m.report.degenerate_triangles as u64,
    ];
    words.extend(m.mesh.triangles().iter().flatten().map(|&v| u64::from(v)));
    let g = &m.geometry;
    words.extend(
        g.normals()
            .iter()
            .flat_map(|n| [n.x, n.y, n.z])
            .map(f64::to_bits),
    );
    words.extend(g.areas().iter().map(|a| a.to_bits()));
    words.extend(
        g.centroids()
            .iter()
            .flat_map(|c| [c.x, c.y, c.z])
            .map(f64::to_bits),
    );
    for p in [
        SegmentParams::default(),
        params(Criterion::Curvature { kappa: 2.0 }, 0.8, 0.0),
    ] {
        let seg = segment(&m.adjacency, &m.geometry, &p).unwrap();
        check_invariants(&m, &seg, p.theta_max_rad, p.min_area_ratio);
        words.extend(seg.patch_of.iter().map(|&id| id as u64));
        for patch in &seg.patches {
            words.extend(patch.normal.map(f64::to_bits));
            words.extend(patch.centroid.map(f64::to_bits));
            words.extend([patch.area.to_bits(), patch.max_deviation.to_bits()]);
        }
    }
    assert_eq!(fnv1a(words), 1777039588872582601, "fingerprint");
}
