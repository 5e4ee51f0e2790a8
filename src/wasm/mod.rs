//! The JavaScript boundary (feature `wasm`): thin wrappers that convert, call one core
//! function and convert back. Names are camelCase through `js_name`. Every failure reaches
//! JavaScript as an `Error` whose message is the core's; a panic is a bug.

mod mesh;
mod segment;

pub use mesh::Mesh;
pub use segment::Segmentation;

use wasm_bindgen::prelude::*;

#[wasm_bindgen(start)]
fn start() {
    console_error_panic_hook::set_once();
}

/// Current size of the WebAssembly memory, in bytes (it only grows).
#[wasm_bindgen(js_name = wasmMemoryBytes)]
pub fn wasm_memory_bytes() -> f64 {
    let memory: js_sys::WebAssembly::Memory = wasm_bindgen::memory().unchecked_into();
    memory
        .buffer()
        .unchecked_into::<js_sys::ArrayBuffer>()
        .byte_length() as f64
}

/// The growing threshold the given segmentation parameters stand for:
/// `{ kind: "angle" | "curvature", value }`. Throws an `Error` naming the bad parameter.
#[wasm_bindgen(js_name = deriveThreshold)]
pub fn derive_threshold(params: JsValue) -> Result<JsValue, JsError> {
    let params = segment::params_from_js(params)?;
    let threshold = params.validate()?;
    Ok(serde_wasm_bindgen::to_value(&threshold)?)
}

/// Calls an optional JavaScript `(stage, fraction) => void`; what it throws is ignored, as a
/// progress display must not abort the work it reports on.
pub(crate) fn progress_fn(callback: Option<js_sys::Function>) -> impl FnMut(&str, f64) {
    move |stage: &str, fraction: f64| {
        if let Some(f) = &callback {
            let _ = f.call2(
                &JsValue::NULL,
                &JsValue::from_str(stage),
                &JsValue::from(fraction),
            );
        }
    }
}
