//! The JavaScript boundary (feature `wasm`): thin wrappers that convert, call one core
//! function and convert back. Names are camelCase through `js_name`. Every failure reaches
//! JavaScript as an `Error` whose message is the core's; a panic is a bug.

mod display;
mod drill;
mod geodesic;
mod index;
mod mesh;
mod params;
mod segment;
mod spray;
mod toolpath;

pub use geodesic::DistanceField;
pub use mesh::Mesh;
pub use params::{ArgError, ParamReader, MAX_DEPTH};
pub use segment::Segmentation;
pub use spray::SprayPlan;
pub use toolpath::ToolPathHandle;

use wasm_bindgen::prelude::*;

#[wasm_bindgen(typescript_custom_section)]
const TYPES: &str = r#"
/** Called now and then during long work with the stage's name and the fraction done (0..1). */
export type ProgressCallback = (stage: string, fraction: number) => void;
/** What reading an STL found. Lengths in the file's unit; area in its square. */
export interface MeshReport {
  format: "binary" | "ascii"; triangles: number; vertices: number; area: number;
  bboxMin: [number, number, number]; bboxMax: [number, number, number];
  boundaryEdges: number; nonManifoldEdges: number; degenerateTriangles: number;
  skippedTriangles: number; components: number; trailingBytes: number;
  flippedTriangles: number; inconsistentEdges: number;
}
/** Spraying parameters (eq. 9): thicknesses in one unit. */
export interface SprayParams { meanThickness: number; allowedDeviation: number; minThickness: number }
/** Grinding parameters (eq. 4): lengths in the mesh's unit; minPressureRatio in (0, 1). */
export interface GrindParams { indentationDepth: number; minPressureRatio: number; contactWidth: number }
/** Exactly one of angleThreshold (rad), curvatureThreshold (1/length), spray, grind;
 *  thetaMax (rad, default 1), minAreaRatio (default 0.1), seedRule (default "flattest"). */
export interface SegmentParams {
  angleThreshold?: number; curvatureThreshold?: number; spray?: SprayParams; grind?: GrindParams;
  thetaMax?: number; minAreaRatio?: number; seedRule?: "lowestIndex" | "flattest" | "largestArea";
}
/** The growing threshold: radians for "angle", 1 / length for "curvature". */
export interface Threshold { kind: "angle" | "curvature"; value: number }
/** One reference hole: nominal and measured position, measured outward normal, and the
 *  nominal (CAD) normal (default: the mesh's normal at `nominal` with `mesh.correctHoles`,
 *  else `normal`). Model units. */
export interface ReferenceHole {
  nominal: [number, number, number]; actual: [number, number, number];
  normal: [number, number, number]; nominalNormal?: [number, number, number];
}
/** Hole correction: references A, B, C, D in order (A→B across the flight direction), nominal
 *  holes as flat xyz; method (default "coons"); tangentScale: tangent length in chords, (0, 3]
 *  (default: the arc-matching length); extrapolate: correct holes outside the references. */
export interface CorrectionParams {
  references: ReferenceHole[]; holes: Float64Array | number[]; method?: "coons" | "bilinear";
  tangentScale?: number; extrapolate?: boolean;
}
/** Corrected holes (flat xyz), unit outward normals (the drilling axis is their opposite),
 *  patch parameters u (A→B) and w (A→D), and 1 where a hole lies outside (extrapolated). */
export interface HoleCorrection {
  corrected: Float64Array; normals: Float64Array; u: Float64Array; w: Float64Array;
  outside: Uint8Array;
}
/** Closest mesh points (flat xyz), interpolated unit normals (mesh winding), distances. */
export interface ClosestPoints { points: Float64Array; normals: Float64Array; distances: Float64Array }
/** A ray's first hit: face id, point, distance along the unit direction (model units), and
 *  with `Segmentation.raycast` the face's patch (−1 = dropped). */
export interface RayHit { face: number; point: [number, number, number]; distance: number; patch?: number }
/** One kept patch; ids by decreasing area. */
export interface Patch {
  id: number; triangleCount: number; area: number; normal: [number, number, number];
  maxDeviation: number; centroid: [number, number, number];
}
"#;

/// Runs once when the module is instantiated: panics (bugs) then log their message.
#[wasm_bindgen(start, js_name = installPanicHook)]
pub fn install_panic_hook() {
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
#[wasm_bindgen(js_name = deriveThreshold, unchecked_return_type = "Threshold")]
pub fn derive_threshold(
    #[wasm_bindgen(unchecked_param_type = "SegmentParams")] params: JsValue,
) -> Result<JsValue, JsError> {
    let params = segment::params_from_js(&params)?;
    let threshold = params.validate()?;
    Ok(serde_wasm_bindgen::to_value(&threshold)?)
}

/// Calls an optional JavaScript `(stage, fraction) => void`; what it throws is ignored, as a
/// progress display must not abort the work it reports on. `call2` is imported with `catch`,
/// so an exception never unwinds through the Rust frames (and borrows) below it.
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

/// Most bytes [`reserve_memory`] takes (WebAssembly's 32-bit memory holds 4 GiB at most).
const MAX_RESERVE_BYTES: f64 = 4_294_967_296.0;

/// Grows the engine's memory now so that `bytes` more can be allocated without growing it
/// again: a block of that size is allocated, written once and freed. WebAssembly memory never
/// shrinks and the allocator keeps freed pages for the next allocations; what costs is the
/// first write to fresh memory (the system hands each page over zeroed then), and that is
/// paid here. The Paths tool asks for what its first distance on the open model will take
/// (www/worker/warm-up.js), so that the distance does not wait on it. Returns false, and
/// changes nothing, when that much memory cannot be had.
#[wasm_bindgen(js_name = reserveMemory)]
pub fn reserve_memory(
    #[wasm_bindgen(unchecked_param_type = "number")] bytes: JsValue,
) -> Result<bool, JsError> {
    // A number only: a string of digits or `true` is not turned into one.
    let bytes = match bytes.as_f64() {
        Some(b) if b.is_finite() && (0.0..=MAX_RESERVE_BYTES).contains(&b) => b,
        _ => {
            return Err(JsError::new(&format!(
                "reserveMemory: bytes must be a number from 0 to {} (4 GiB), got {}",
                crate::math::Compact(MAX_RESERVE_BYTES),
                params::describe(&bytes)
            )))
        }
    };
    let mut block: Vec<u8> = Vec::new();
    if block.try_reserve_exact(bytes as usize).is_err() {
        return Ok(false);
    }
    // Every page written once (zero, as the allocator would have it for a calloc).
    block.resize(bytes as usize, 0);
    std::hint::black_box(&block);
    Ok(true)
}
