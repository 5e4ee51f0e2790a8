//! `SprayPlan`: the result of `Mesh.planSpray` (JavaScript must call `free()`).

use super::params::ParamReader;
use super::toolpath::{export_csv, export_json, export_krl, export_rapid};
use crate::spray::{QualityLimits, SprayParams};
use wasm_bindgen::prelude::*;

#[wasm_bindgen(typescript_custom_section)]
const SPRAY_TYPES: &str = r#"
/** Quality limits of the spacing search: stdDev and error of the interior thickness. */
export interface SprayQualityLimits { maxStdDev?: number; maxError?: number; minSpacing?: number; maxSpacing?: number }
/** Spray planning parameters: lengths in the file's unit, angles in rad, times in s,
 *  flowRate in (file unit)³/s. Defaults: efficiency 0.6, rasterAngle 0, extension R,
 *  timeStep R/(20·speed), resolution R/8, edgeExclusion R, with R = standoff·tan(coneAngle/2). */
export interface SprayPlanParams {
  spacing: number; standoff: number; speed: number; flowRate: number; coneAngle: number;
  transitionAngle: number; efficiency?: number; direction?: [number, number, number];
  rasterAngle?: number; extension?: number; timeStep?: number;
  /** Distance between evaluation samples: every point of the patch lies within
   *  resolution/√2 of one, as on a square grid that far apart. */
  resolution?: number;
  /** Most evaluation samples wanted: a finer resolution is coarsened to fit (plan.resolution). */
  sampleBudget?: number;
  edgeExclusion?: number; quality?: SprayQualityLimits; targetThickness?: number;
  /** Optimise the gun speed piece by piece along the passes (default true). */
  optimiseSpeed?: boolean;
  /** Slowest and fastest gun speed the plan may command (defaults speed/2 and 2·speed). */
  minSpeed?: number; maxSpeed?: number;
  /** Also try the pass direction turned by 90° and ±45°, keep the best (default false). */
  bestDirection?: boolean;
}
/** One of the worst regions of the interior coating: position (file unit), deviation from
 *  the interior mean as a fraction (signed), and what lies under it. */
export interface SprayHotspot { position: [number, number, number]; deviation: number; cause: "edge" | "fold" | "curvature" | "spacing" }
/** A pass direction tried with bestDirection, at the chosen spacing. */
export interface SprayDirectionTrial { rasterAngle: number; error: number; stdDev: number; cycleTime: number; chosen: boolean }
/** Thickness figures (file unit; error = max |T − mean| / mean; area in the unit's square). */
export interface ThicknessStats { mean: number; stdDev: number; error: number; min: number; max: number; area: number }
/** Figures over the interior (edgeExclusion from the boundary) and the whole patch;
 *  limitsMet false and a message when no spacing met the quality limits. */
export interface SprayQuality { interior: ThicknessStats; whole: ThicknessStats; limitsMet: boolean; messages: string[] }
/** One spacing tried by the search, with its interior figures. */
export interface SprayIteration { spacing: number; resolution: number; mean: number; stdDev: number; error: number; met: boolean; full: boolean }
"#;

/// Keys of `SprayPlanParams`.
const PARAM_KEYS: &[&str] = &[
    "spacing",
    "standoff",
    "speed",
    "flowRate",
    "coneAngle",
    "transitionAngle",
    "efficiency",
    "direction",
    "rasterAngle",
    "extension",
    "timeStep",
    "resolution",
    "sampleBudget",
    "edgeExclusion",
    "quality",
    "targetThickness",
    "optimiseSpeed",
    "minSpeed",
    "maxSpeed",
    "bestDirection",
];
/// Keys of `SprayQualityLimits`.
const QUALITY_KEYS: &[&str] = &["maxStdDev", "maxError", "minSpacing", "maxSpacing"];

/// Reads `SprayPlanParams` through the bounded reader (unknown keys, wrong types and `null`
/// refused by name); the core's `validate` then checks the ranges.
pub(crate) fn spray_params_from_js(value: &JsValue) -> Result<SprayParams, JsError> {
    let r = ParamReader::object(value, "spray parameter", PARAM_KEYS)?;
    let defaults = SprayParams::default();
    let quality = match r.optional_object("quality", QUALITY_KEYS)? {
        None => None,
        Some(q) => Some(QualityLimits {
            max_std_dev: q.optional_number("maxStdDev")?,
            max_error: q.optional_number("maxError")?,
            min_spacing: q.optional_number("minSpacing")?,
            max_spacing: q.optional_number("maxSpacing")?,
        }),
    };
    Ok(SprayParams {
        spacing: r.number("spacing")?,
        standoff: r.number("standoff")?,
        speed: r.number("speed")?,
        flow_rate: r.number("flowRate")?,
        cone_angle: r.number("coneAngle")?,
        transition_angle: r.number("transitionAngle")?,
        efficiency: r
            .optional_number("efficiency")?
            .unwrap_or(defaults.efficiency),
        direction: r.optional_vector3("direction")?,
        raster_angle: r
            .optional_number("rasterAngle")?
            .unwrap_or(defaults.raster_angle),
        extension: r.optional_number("extension")?,
        time_step: r.optional_number("timeStep")?,
        resolution: r.optional_number("resolution")?,
        sample_budget: r
            .optional_integer("sampleBudget", 1, i64::from(i32::MAX))?
            .map(|b| b as usize),
        edge_exclusion: r.optional_number("edgeExclusion")?,
        quality,
        target_thickness: r.optional_number("targetThickness")?,
        optimise_speed: r
            .optional_bool("optimiseSpeed")?
            .unwrap_or(defaults.optimise_speed),
        min_speed: r.optional_number("minSpeed")?,
        max_speed: r.optional_number("maxSpeed")?,
        best_direction: r
            .optional_bool("bestDirection")?
            .unwrap_or(defaults.best_direction),
    })
}

#[derive(serde::Serialize)]
#[serde(rename_all = "camelCase")]
struct QualityView<'a> {
    interior: crate::spray::ThicknessStats,
    whole: crate::spray::ThicknessStats,
    limits_met: bool,
    messages: &'a [String],
}

#[derive(serde::Serialize)]
struct HotspotView {
    position: [f64; 3],
    deviation: f64,
    cause: crate::spray::HotspotCause,
}

/// A planned spray job: trajectory, evaluation samples with thickness, quality, iterations.
#[wasm_bindgen]
pub struct SprayPlan {
    inner: crate::spray::SprayPlan,
}

impl SprayPlan {
    pub(crate) fn new(inner: crate::spray::SprayPlan) -> Self {
        SprayPlan { inner }
    }
}

#[wasm_bindgen]
impl SprayPlan {
    /// Pass spacing used, file unit.
    #[wasm_bindgen(getter)]
    pub fn spacing(&self) -> f64 {
        self.inner.spacing
    }

    /// Nominal gun speed, file unit per second (without speed optimisation: scaled when
    /// targetThickness was given).
    #[wasm_bindgen(getter)]
    pub fn speed(&self) -> f64 {
        self.inner.speed
    }

    /// Whether the gun speed was optimised piece by piece.
    #[wasm_bindgen(getter, js_name = speedOptimised)]
    pub fn speed_optimised(&self) -> bool {
        self.inner.speed_optimised
    }

    /// Slowest gun-on speed commanded, file unit per second.
    #[wasm_bindgen(getter, js_name = minSpeed)]
    pub fn min_speed(&self) -> f64 {
        self.inner.speed_range.0
    }

    /// Fastest gun-on speed commanded, file unit per second.
    #[wasm_bindgen(getter, js_name = maxSpeed)]
    pub fn max_speed(&self) -> f64 {
        self.inner.speed_range.1
    }

    /// Speed of the move arriving at each point, file unit per second (the first point's:
    /// the approach).
    pub fn speeds(&self) -> Vec<f64> {
        let path = &self.inner.path;
        (0..path.poses.len()).map(|k| path.move_speed(k)).collect()
    }

    /// Time to run the whole trajectory (gun on and links), seconds.
    #[wasm_bindgen(getter, js_name = cycleTime)]
    pub fn cycle_time(&self) -> f64 {
        self.inner.cycle_time
    }

    /// Length of the gun-on path, file unit.
    #[wasm_bindgen(getter, js_name = sprayLength)]
    pub fn spray_length(&self) -> f64 {
        self.inner.spray_length
    }

    /// Length of the whole path (gun on and links), file unit.
    #[wasm_bindgen(getter, js_name = pathLength)]
    pub fn path_length(&self) -> f64 {
        self.inner.path_length
    }

    /// Distance between evaluation samples used: `resolution`, or coarser to fit
    /// `sampleBudget`.
    #[wasm_bindgen(getter)]
    pub fn resolution(&self) -> f64 {
        self.inner.resolution
    }

    /// Turn of the pass direction used about the mean normal, radians.
    #[wasm_bindgen(getter, js_name = rasterAngle)]
    pub fn raster_angle(&self) -> f64 {
        self.inner.raster_angle
    }

    /// The pass directions tried with bestDirection (empty without).
    #[wasm_bindgen(unchecked_return_type = "SprayDirectionTrial[]")]
    pub fn directions(&self) -> Result<JsValue, JsError> {
        Ok(serde_wasm_bindgen::to_value(&self.inner.directions)?)
    }

    /// The worst regions of the interior coating, worst first.
    #[wasm_bindgen(unchecked_return_type = "SprayHotspot[]")]
    pub fn hotspots(&self) -> Result<JsValue, JsError> {
        let view: Vec<HotspotView> = self
            .inner
            .hotspots
            .iter()
            .map(|h| HotspotView {
                position: [h.position.x, h.position.y, h.position.z],
                deviation: h.deviation,
                cause: h.cause,
            })
            .collect();
        Ok(serde_wasm_bindgen::to_value(&view)?)
    }

    /// Number of passes.
    #[wasm_bindgen(getter, js_name = passCount)]
    pub fn pass_count(&self) -> u32 {
        self.inner.pass_count as u32
    }

    /// 6 numbers per point: x y z, then the unit gun axis (towards the part).
    pub fn trajectory(&self) -> Vec<f64> {
        let poses = &self.inner.path.poses;
        let mut out = Vec::with_capacity(6 * poses.len());
        for p in poses {
            out.extend_from_slice(&[
                p.position.x,
                p.position.y,
                p.position.z,
                p.axis.x,
                p.axis.y,
                p.axis.z,
            ]);
        }
        out
    }

    /// Kind per point: 0 pass, 1 straight transition, 2 arc, 3 extension, 4 link (gun off).
    #[wasm_bindgen(js_name = pointKinds)]
    pub fn point_kinds(&self) -> Vec<u8> {
        self.inner
            .path
            .poses
            .iter()
            .map(|p| p.kind.code())
            .collect()
    }

    /// Pass index per point.
    #[wasm_bindgen(js_name = passOf)]
    pub fn pass_of(&self) -> Vec<u32> {
        self.inner.path.poses.iter().map(|p| p.pass).collect()
    }

    /// Evaluation points, flat xyz.
    #[wasm_bindgen(js_name = samplePositions)]
    pub fn sample_positions(&self) -> Vec<f32> {
        let s = &self.inner.samples.positions;
        let mut out = Vec::with_capacity(3 * s.len());
        for p in s {
            out.extend_from_slice(&[p.x as f32, p.y as f32, p.z as f32]);
        }
        out
    }

    /// Thickness per evaluation point, file unit.
    #[wasm_bindgen(js_name = sampleThickness)]
    pub fn sample_thickness(&self) -> Vec<f32> {
        self.inner.thickness.iter().map(|&t| t as f32).collect()
    }

    /// Display mesh over the evaluation points, 3 indices per triangle.
    #[wasm_bindgen(js_name = sampleTriangles)]
    pub fn sample_triangles(&self) -> Vec<u32> {
        self.inner.samples.triangles.as_flattened().to_vec()
    }

    /// `{ interior, whole, limitsMet, messages }`.
    #[wasm_bindgen(unchecked_return_type = "SprayQuality")]
    pub fn quality(&self) -> Result<JsValue, JsError> {
        let view = QualityView {
            interior: self.inner.quality.interior,
            whole: self.inner.quality.whole,
            limits_met: self.inner.limits_met,
            messages: &self.inner.messages,
        };
        Ok(serde_wasm_bindgen::to_value(&view)?)
    }

    /// Every spacing tried: `{ spacing, mean, stdDev, error, met }[]`.
    #[wasm_bindgen(unchecked_return_type = "SprayIteration[]")]
    pub fn iterations(&self) -> Result<JsValue, JsError> {
        Ok(serde_wasm_bindgen::to_value(&self.inner.iterations)?)
    }

    /// The trajectory as CSV (positions in mm: give `mmPerUnit` for a file not in mm).
    #[wasm_bindgen(js_name = toCsv)]
    pub fn to_csv(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "ExportOptions")] opts: JsValue,
    ) -> Result<String, JsError> {
        export_csv(&self.inner.path, &opts)
    }

    /// The trajectory as JSON (positions in mm: give `mmPerUnit` for a file not in mm).
    #[wasm_bindgen(js_name = toJson)]
    pub fn to_json(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "ExportOptions")] opts: JsValue,
    ) -> Result<String, JsError> {
        export_json(&self.inner.path, &opts)
    }

    /// ABB RAPID modules, one string per file (main module first).
    #[wasm_bindgen(js_name = toRapid)]
    pub fn to_rapid(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "ExportOptions")] opts: JsValue,
    ) -> Result<Vec<String>, JsError> {
        export_rapid(&self.inner.path, &opts)
    }

    /// KUKA KRL `.src` files, one string per file (main program first).
    #[wasm_bindgen(js_name = toKrl)]
    pub fn to_krl(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "ExportOptions")] opts: JsValue,
    ) -> Result<Vec<String>, JsError> {
        export_krl(&self.inner.path, &opts)
    }
}
