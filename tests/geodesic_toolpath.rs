//! The linked tool path of geodesic passes: no process-on move of zero length (a controller
//! runs a turn on the spot as a dwell), each pass reached by one link, on a plate and a
//! cylinder, with levels through mesh vertices and closed lines.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use skinpath::geodesic::{
    geodesic_distance, DistanceParams, GeodesicSource, LinkOrder, Method, PathParams,
};
use skinpath::math::{Point3, Real};
use skinpath::toolpath::{PoseKind, ToolPath};

#[path = "common/geodesic_shapes.rs"]
mod shapes;
use shapes::*;

/// A 200 × 100 mm plate in z = 0 in cells of `cell` mm.
fn plate(cell: Real) -> Shape {
    let (nu, nv) = ((200.0 / cell) as usize, (100.0 / cell) as usize);
    let (p, t) = grid(nu, nv, false, |u, v| Point3::new(200.0 * u, 100.0 * v, 0.0));
    shape(p, t)
}

fn path(s: &Shape, source: GeodesicSource, method: Method, params: &PathParams) -> ToolPath {
    let dp = DistanceParams {
        method,
        ..DistanceParams::default()
    };
    let field = geodesic_distance(&s.mesh, &s.adjacency, &source, &dp, &mut |_, _| {}).unwrap();
    let tp = field.tool_path(&s.mesh, &s.adjacency, params).unwrap();
    tp.validate().unwrap();
    tp
}

/// Checks the path and returns its pass count: no process-on move shorter than a millionth of
/// the spacing, one link per pass after the first, each at its pass's first pose, and every
/// pass a real move.
fn check(tp: &ToolPath, spacing: Real, what: &str) -> usize {
    let passes = tp.pass_count();
    assert!(passes >= 2, "{what}: {passes} passes");
    for (i, w) in tp.poses.windows(2).enumerate() {
        if w[1].kind.process_on() {
            let step = (w[1].position - w[0].position).norm();
            assert!(
                step > 1e-6 * spacing,
                "{what}: move {} of length {step}",
                i + 1
            );
        }
    }
    let links: Vec<usize> = (0..tp.poses.len())
        .filter(|&i| tp.poses[i].kind == PoseKind::Link)
        .collect();
    assert_eq!(links.len(), passes - 1, "{what}");
    for &i in &links {
        assert_ne!(
            tp.poses[i].pass,
            tp.poses[i - 1].pass,
            "{what}: link inside a pass"
        );
        assert_eq!(
            tp.poses[i + 1].pass,
            tp.poses[i].pass,
            "{what}: a pass of one pose"
        );
    }
    passes
}

#[test]
fn passes_on_a_plate_never_turn_on_the_spot() {
    for cell in [10.0, 7.0] {
        let s = plate(cell);
        // Levels every 10 mm from the edge x = 0: on a 10 mm grid they run through vertices.
        let edge = GeodesicSource::Polyline {
            points: vec![Point3::new(0.0, 0.0, 0.0), Point3::new(0.0, 100.0, 0.0)],
            closed: false,
        };
        for order in [LinkOrder::ZigZag, LinkOrder::OneDirection] {
            let params = PathParams {
                spacing: 10.0,
                order,
                ..PathParams::default()
            };
            let tp = path(&s, edge.clone(), Method::Fast, &params);
            let passes = check(&tp, 10.0, &format!("plate {cell}, edge"));
            assert!(passes >= 18, "{passes}");
        }
        // Closed and open arcs around a corner vertex and a middle vertex.
        let middle = s
            .mesh
            .positions()
            .iter()
            .position(|p| (p.x - 100.0).abs() < cell && (p.y - 50.0).abs() < cell)
            .unwrap() as u32;
        let params = PathParams {
            spacing: 10.0,
            ..PathParams::default()
        };
        for source in [
            GeodesicSource::Vertices(vec![0]),
            GeodesicSource::Vertices(vec![middle]),
        ] {
            let tp = path(&s, source, Method::Fast, &params);
            check(&tp, 10.0, &format!("plate {cell}, vertex"));
        }
    }
}

#[test]
fn passes_on_a_cylinder_never_turn_on_the_spot() {
    // Rows every 10 mm along the axis: the rings at 10 mm levels lie on vertex rows.
    let s = cylinder(64, 12);
    let ring0 = GeodesicSource::Polyline {
        points: ring(0.0, 64, 0.0),
        closed: true,
    };
    for (spacing, method) in [
        (10.0, Method::Fast),
        (7.5, Method::Fast),
        (10.0, Method::Exact),
    ] {
        let params = PathParams {
            spacing,
            ..PathParams::default()
        };
        let tp = path(&s, ring0.clone(), method, &params);
        let passes = check(&tp, spacing, &format!("cylinder ring, spacing {spacing}"));
        assert_eq!(passes, (LEN / spacing).floor() as usize);
        // Closed rings end back at their first point: a full turn, not a repeated position.
        for k in 0..passes as u32 {
            let on: Vec<_> = tp.poses.iter().filter(|p| p.pass == k).collect();
            assert!((on[0].position - on[on.len() - 1].position).norm() < 1e-9);
        }
    }
    // Lines along the cylinder from a straight source: open passes.
    let line = GeodesicSource::Polyline {
        points: vec![Point3::new(R, 0.0, 0.0), Point3::new(R, 0.0, LEN)],
        closed: false,
    };
    let params = PathParams {
        spacing: 10.0,
        ..PathParams::default()
    };
    let tp = path(&s, line, Method::Fast, &params);
    check(&tp, 10.0, "cylinder line");
}
