//! Smoke tests of the JavaScript-facing API, run as WebAssembly by `wasm-pack test --node`.
#![cfg(all(feature = "wasm", target_arch = "wasm32"))]

use skinpath::wasm::{derive_threshold, wasm_memory_bytes, Mesh};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::wasm_bindgen_test;

fn json(text: &str) -> JsValue {
    js_sys::JSON::parse(text).expect("test JSON is valid")
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
    let Err(e) = Mesh::from_stl(truncated, None) else {
        panic!("truncated file accepted")
    };
    assert!(message(e).starts_with("truncated binary STL: the header says 12 triangles but only 7"));
    let mesh = Mesh::from_stl(CUBE, None).unwrap();
    assert_eq!((mesh.triangle_count(), mesh.vertex_count()), (12, 8));
    assert_eq!(mesh.indices().len(), 36);
    assert_eq!(mesh.positions().len(), 24);
}

#[wasm_bindgen_test]
fn segment_takes_camel_case_params_and_refuses_bad_ones() {
    let mesh = Mesh::from_stl(CUBE, None).unwrap();
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
    assert!(message(seg.patch_stl(6).unwrap_err()).contains("no patch 6"));
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
