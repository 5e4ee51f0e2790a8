//! Smoke tests of the JavaScript-facing API, run as WebAssembly by `wasm-pack test --node`.
#![cfg(all(feature = "wasm", target_arch = "wasm32"))]

use skinpath::wasm::{derive_threshold, wasm_memory_bytes, Mesh};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::wasm_bindgen_test;

fn json(text: &str) -> JsValue {
    js_sys::JSON::parse(text).expect("test JSON is valid")
}

fn bytes(data: &[u8]) -> JsValue {
    js_sys::Uint8Array::from(data).into()
}

fn message(error: wasm_bindgen::JsError) -> String {
    let value: JsValue = error.into();
    value.unchecked_into::<js_sys::Error>().message().into()
}

const CUBE: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/fixtures/cube_binary.stl"
));

#[wasm_bindgen_test]
fn a_failed_read_throws_a_plain_message_and_the_module_keeps_working() {
    let truncated = include_bytes!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/truncated.stl"
    ));
    let Err(e) = Mesh::from_stl(bytes(truncated), None) else {
        panic!("truncated file accepted")
    };
    assert!(message(e).starts_with("truncated binary STL: the header says 12 triangles but only 7"));
    let mesh = Mesh::from_stl(bytes(CUBE), None).unwrap();
    assert_eq!((mesh.triangle_count(), mesh.vertex_count()), (12, 8));
    assert_eq!(mesh.indices().len(), 36);
    assert_eq!(mesh.positions().len(), 24);
}

#[wasm_bindgen_test]
fn segment_takes_camel_case_params_and_refuses_bad_ones() {
    let mesh = Mesh::from_stl(bytes(CUBE), None).unwrap();
    let seg = mesh
        .segment(
            json(r#"{"angleThreshold": 0.35, "thetaMax": 1, "minAreaRatio": 0.1}"#),
            None,
        )
        .unwrap();
    assert_eq!(seg.patch_count(), 6);
    assert_eq!(seg.threshold_kind(), "angle");
    assert_eq!(seg.patch_of().len(), 12);
    assert_eq!(seg.border_segments().len(), 12 * 6);
    assert!(message(seg.patch_stl(6.into()).unwrap_err()).contains("no patch 6"));
    let bad = mesh.segment(
        json(r#"{"grind": {"indentationDepth": 1, "minPressureRatio": 1.5, "contactWidth": 3}}"#),
        None,
    );
    assert!(
        message(bad.err().unwrap()).contains("minPressureRatio must be strictly between 0 and 1")
    );
    let typo = mesh.segment(json(r#"{"angleThreshold": 0.3, "thetaMaks": 1}"#), None);
    assert!(message(typo.err().unwrap()).contains("thetaMaks"));
}

#[wasm_bindgen_test]
fn derive_threshold_and_memory_report_numbers() {
    let t = derive_threshold(json(
        r#"{"spray": {"meanThickness": 100, "allowedDeviation": 6, "minThickness": 97}}"#,
    ))
    .unwrap();
    let value = js_sys::Reflect::get(&t, &"value".into())
        .unwrap()
        .as_f64()
        .unwrap();
    assert!((value - (94.0f64 / 97.0).acos()).abs() < 1e-12);
    let none = derive_threshold(json("{}")).err().unwrap();
    assert!(message(none).contains(
        "give exactly one of angleThreshold, curvatureThreshold, spray or grind (got none)"
    ));
    assert!(wasm_memory_bytes() >= 65536.0);
}

fn reader_message(error: skinpath::wasm::ArgError) -> String {
    error.0
}

#[wasm_bindgen_test]
fn the_param_reader_names_paths_types_and_unknown_keys_without_recursing() {
    use skinpath::wasm::{ParamReader, MAX_DEPTH};
    let value = json(r#"{"spacing": 2, "passes": 3, "wet": true, "tool": {"width": "8"}}"#);
    let keys = ["spacing", "passes", "wet", "tool", "speed"];
    let r = ParamReader::object(&value, "spray parameter", &keys).unwrap();
    assert_eq!(r.number("spacing").unwrap(), 2.0);
    assert_eq!(r.optional_number("speed").unwrap(), None);
    assert_eq!(
        reader_message(r.number("speed").err().unwrap()),
        "spray parameter 'speed' is missing"
    );
    assert_eq!(r.optional_integer("passes", 1, 10).unwrap(), Some(3));
    assert_eq!(
        reader_message(r.optional_integer("passes", 5, 10).err().unwrap()),
        "passes must be a whole number from 5 to 10, got 3"
    );
    assert_eq!(r.optional_bool("wet").unwrap(), Some(true));
    assert_eq!(
        reader_message(r.optional_bool("spacing").err().unwrap()),
        "spacing must be true or false, got the number 2"
    );
    let tool = r.optional_object("tool", &["width"]).unwrap().unwrap();
    assert_eq!(
        reader_message(tool.number("width").err().unwrap()),
        "tool.width must be a number, got the string \"8\""
    );
    assert_eq!(
        reader_message(
            ParamReader::object(&value, "spray parameter", &["spacing"])
                .err()
                .unwrap()
        ),
        "unknown spray parameter 'passes'"
    );
    assert_eq!(
        reader_message(
            ParamReader::object(&JsValue::NULL, "spray parameter", &keys)
                .err()
                .unwrap()
        ),
        "spray parameters must be an object, got null"
    );
    // A cycle is read only as deep as the schema asks, and never past MAX_DEPTH.
    let cyclic = json(r#"{"next": null}"#);
    js_sys::Reflect::set(&cyclic, &"next".into(), &cyclic).unwrap();
    let mut r = ParamReader::object(&cyclic, "drilling parameter", &["next"]).unwrap();
    for _ in 0..MAX_DEPTH {
        r = r.optional_object("next", &["next"]).unwrap().unwrap();
    }
    assert_eq!(
        reader_message(r.optional_object("next", &["next"]).err().unwrap()),
        format!("next.next.next.next.next is nested more than {MAX_DEPTH} objects deep")
    );
}

/// A 400 × 200 plate of 2 × 1 squares as binary STL, normal +z.
fn plate_stl() -> Vec<u8> {
    let tris: [[[f32; 3]; 3]; 4] = [
        [[0., 0., 0.], [200., 0., 0.], [200., 200., 0.]],
        [[0., 0., 0.], [200., 200., 0.], [0., 200., 0.]],
        [[200., 0., 0.], [400., 0., 0.], [400., 200., 0.]],
        [[200., 0., 0.], [400., 200., 0.], [200., 200., 0.]],
    ];
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&4u32.to_le_bytes());
    for t in tris {
        out.extend_from_slice(&[0u8; 12]);
        t.iter()
            .flatten()
            .for_each(|c| out.extend_from_slice(&c.to_le_bytes()));
        out.extend_from_slice(&[0, 0]);
    }
    out
}

#[wasm_bindgen_test]
fn plan_spray_returns_flat_arrays_and_refuses_bad_params_by_name() {
    let mesh = Mesh::from_stl(bytes(&plate_stl()), None).unwrap();
    let params = r#"{"spacing": 50, "standoff": 100, "speed": 100, "flowRate": 1000,
        "coneAngle": 0.9272952180016122, "transitionAngle": 0.35, "resolution": 25}"#;
    let plan = mesh.plan_spray(json(params), None, None).unwrap();
    assert_eq!(plan.pass_count(), 4);
    let n = plan.point_kinds().len();
    assert_eq!(plan.trajectory().len(), 6 * n);
    assert_eq!(plan.pass_of().len(), n);
    let samples = plan.sample_thickness().len();
    assert_eq!(plan.sample_positions().len(), 3 * samples);
    assert!(plan
        .sample_triangles()
        .iter()
        .all(|&i| (i as usize) < samples));
    let Err(e) = mesh.plan_spray(
        json(&params.replace("\"speed\": 100", "\"speed\": -1")),
        None,
        None,
    ) else {
        panic!("negative speed accepted")
    };
    assert!(message(e).contains("speed"));
    let Err(e) = mesh.plan_spray(
        json(&params.replace("\"spacing\"", "\"spasing\"")),
        None,
        None,
    ) else {
        panic!("misspelt key accepted")
    };
    assert!(message(e).contains("spasing"));
    let Err(e) = mesh.plan_spray(json(params), Some(json("[7]")), None) else {
        panic!("unknown face accepted")
    };
    assert!(message(e).contains('7'));
    let Err(e) = mesh.plan_spray(json(params), Some(json("[0.5]")), None) else {
        panic!("a fractional face id accepted")
    };
    assert_eq!(
        message(e),
        "faces[0] must be a whole number from 0 to 4294967295, got 0.5"
    );
    let Err(e) = mesh.plan_spray(
        json(&params.replace("\"resolution\": 25", "\"direction\": [1, 0]")),
        None,
        None,
    ) else {
        panic!("a direction of two numbers accepted")
    };
    assert!(message(e).starts_with("direction must be three numbers [x, y, z]"));
    let csv = plan.to_csv(json(r#"{"mmPerUnit": 1000}"#)).unwrap();
    let first = csv.lines().nth(1).unwrap();
    let x_mm: f64 = first.split(',').nth(3).unwrap().parse().unwrap();
    let x_unit = plan.trajectory()[0];
    assert!((x_mm - 1000.0 * x_unit).abs() < 1e-3, "{x_mm} vs {x_unit}");
}

/// An open cylinder of radius `r` and length `h` about z (z from 0 to h), `n` facets round
/// and `m` rings along, as binary STL with outward normals.
fn cylinder_stl(r: f32, h: f32, n: usize, m: usize) -> Vec<u8> {
    let p = |i: usize, j: usize| -> [f32; 3] {
        let a = std::f32::consts::TAU * (i % n) as f32 / n as f32;
        [r * a.cos(), r * a.sin(), h * j as f32 / m as f32]
    };
    let mut tris = Vec::new();
    for j in 0..m {
        for i in 0..n {
            tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
            tris.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
        }
    }
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&(tris.len() as u32).to_le_bytes());
    for t in tris {
        out.extend_from_slice(&[0u8; 12]);
        t.iter()
            .flatten()
            .for_each(|c| out.extend_from_slice(&c.to_le_bytes()));
        out.extend_from_slice(&[0, 0]);
    }
    out
}

fn get(object: &JsValue, key: &str) -> JsValue {
    js_sys::Reflect::get(object, &key.into()).expect("a plain object")
}

#[wasm_bindgen_test]
fn geodesic_ring_source_on_a_cylinder_gives_closed_paths_at_their_heights() {
    let (n, r) = (48usize, 50.0f32);
    let mesh = Mesh::from_stl(bytes(&cylinder_stl(r, 120.0, n, 24)), None).unwrap();
    // The bottom ring through the mesh's own vertices: distance = z exactly on the facets.
    let ring: Vec<f64> = (0..n)
        .flat_map(|i| {
            let a = std::f32::consts::TAU * i as f32 / n as f32;
            [(r * a.cos()) as f64, (r * a.sin()) as f64, 0.0]
        })
        .collect();
    let source = js_sys::Object::new();
    js_sys::Reflect::set(
        &source,
        &"polyline".into(),
        &js_sys::Float64Array::from(ring.as_slice()),
    )
    .unwrap();
    js_sys::Reflect::set(&source, &"closed".into(), &true.into()).unwrap();
    let field = mesh
        .geodesic_distance(source.into(), JsValue::UNDEFINED, None)
        .unwrap();
    assert_eq!(field.method(), "accurate");
    assert!(
        (field.max_distance() - 120.0).abs() < 1e-3,
        "{}",
        field.max_distance()
    );
    let paths = field.iso_paths(10.0.into(), JsValue::UNDEFINED).unwrap();
    let mut levels = Vec::new();
    for path in paths.iter() {
        let level = get(&path, "level").as_f64().unwrap();
        assert_eq!(get(&path, "closed").as_bool(), Some(true));
        assert_eq!(get(&path, "distance").as_f64(), Some(10.0 * level));
        let points: js_sys::Float64Array = get(&path, "points").unchecked_into();
        let points = points.to_vec();
        assert!(points.len() >= 3 * 8);
        for p in points.chunks_exact(3) {
            assert!(
                (p[2] - 10.0 * level).abs() < 1e-3,
                "z {} at level {level}",
                p[2]
            );
        }
        levels.push(level as u32);
    }
    levels.dedup();
    assert_eq!(&levels[..11], &(1..=11).collect::<Vec<u32>>()[..]);
    let path = field.tool_path(10.0.into(), JsValue::UNDEFINED).unwrap();
    assert!(path.pass_count() >= 11);
    assert_eq!(path.positions().len(), 3 * path.pose_count() as usize);
    assert!(path.to_rapid(JsValue::UNDEFINED).unwrap()[0].contains("MoveL"));

    let far = json(r#"{"polyline": [0, 0, 1000]}"#);
    let Err(e) = mesh.geodesic_distance(far, JsValue::UNDEFINED, None) else {
        panic!("a source far off the surface accepted")
    };
    assert!(message(e).contains("misses the surface"));
    let Err(e) = mesh.geodesic_distance(json(r#"{"polyline": [0, 0]}"#), JsValue::UNDEFINED, None)
    else {
        panic!("two numbers accepted as points")
    };
    assert!(message(e).contains("source.polyline"));
    let Err(e) = mesh.geodesic_distance(json(r#"{"vertexes": [0]}"#), JsValue::UNDEFINED, None)
    else {
        panic!("a misspelt source accepted")
    };
    assert_eq!(message(e), "unknown geodesic source 'vertexes'");
    let Err(e) = field.iso_paths(0.0.into(), JsValue::UNDEFINED) else {
        panic!("spacing 0 accepted")
    };
    assert!(message(e).contains("spacing"));
    assert_eq!(mesh.triangle_count(), 2 * 48 * 24, "the mesh keeps working");
}
