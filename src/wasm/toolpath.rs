//! Export options shared by every tool-path export (`toCsv`, `toJson`, `toRapid`, `toKrl` of
//! spray plans, geodesic passes and drilling poses).

use super::params::ParamReader;
use crate::toolpath::{
    ExportOptions, LineEnding, ToolPath, KRL_MAX_BASE, KRL_MAX_OUTPUT, KRL_MAX_TOOL,
};
use wasm_bindgen::prelude::*;

/// Keys of the JavaScript `ExportOptions`.
const EXPORT_KEYS: &[&str] = &[
    "mmPerUnit",
    "name",
    "maxMoves",
    "lineEnding",
    "approachClearanceMm",
    "rapidTool",
    "rapidWorkObject",
    "rapidSignal",
    "rapidZoneProcess",
    "rapidZoneLink",
    "rapidEntry",
    "rapidConfigCheck",
    "krlOutput",
    "krlTool",
    "krlBase",
    "krlApproximationProcessMm",
    "krlApproximationLinkMm",
    "krlUnwrapAngles",
];

/// The TypeScript declaration of [`EXPORT_KEYS`].
#[wasm_bindgen(typescript_custom_section)]
const EXPORT_OPTIONS_TS: &str = r#"
/** Export options (all optional): millimetres per file unit (default 1), program name,
 *  path moves per part, line endings, approach/retract clearance in mm (default 50), the
 *  RAPID tool, work object, process signal, zones and entry routine names, whether RAPID keeps
 *  the configuration check (default false: ConfJ\Off, ConfL\Off), the KRL process output,
 *  tool and base numbers, approximation distances in mm, and whether KRL writes A and C
 *  unwrapped beyond ±180° (default false). */
export interface ExportOptions {
  mmPerUnit?: number; name?: string; maxMoves?: number; lineEnding?: "lf" | "crlf";
  approachClearanceMm?: number;
  rapidTool?: string; rapidWorkObject?: string; rapidSignal?: string;
  rapidZoneProcess?: string; rapidZoneLink?: string; rapidEntry?: string;
  rapidConfigCheck?: boolean;
  krlOutput?: number; krlTool?: number; krlBase?: number;
  krlApproximationProcessMm?: number; krlApproximationLinkMm?: number;
  krlUnwrapAngles?: boolean;
}
"#;

/// Reads the JavaScript `ExportOptions` (`undefined` for the defaults); the exports
/// themselves refuse values out of range, naming the option by its JavaScript key.
pub(crate) fn export_options_from_js(value: &JsValue) -> Result<ExportOptions, JsError> {
    let mut o = ExportOptions::default();
    let Some(r) = ParamReader::optional_argument(value, "export option", EXPORT_KEYS)? else {
        return Ok(o);
    };
    if let Some(mm) = r.optional_number("mmPerUnit")? {
        o.mm_per_unit = mm;
    }
    if let Some(name) = r.optional_string("name")? {
        o.name = name;
    }
    if let Some(moves) = r.optional_integer("maxMoves", 1, 1 << 30)? {
        o.max_moves = Some(moves as usize);
    }
    if let Some(ending) = r.optional_choice("lineEnding", &["lf", "crlf"])? {
        o.line_ending = if ending == "crlf" {
            LineEnding::CrLf
        } else {
            LineEnding::Lf
        };
    }
    if let Some(mm) = r.optional_number("approachClearanceMm")? {
        o.approach_clearance_mm = mm;
    }
    for (key, slot) in [
        ("rapidTool", &mut o.rapid.tool),
        ("rapidWorkObject", &mut o.rapid.work_object),
        ("rapidSignal", &mut o.rapid.process_signal),
        ("rapidZoneProcess", &mut o.rapid.zone_process),
        ("rapidZoneLink", &mut o.rapid.zone_link),
        ("rapidEntry", &mut o.rapid.entry),
    ] {
        if let Some(v) = r.optional_string(key)? {
            *slot = v;
        }
    }
    // The ranges the KRL export takes, so a value out of them is named with them here.
    for (key, slot, max) in [
        ("krlOutput", &mut o.krl.process_output, KRL_MAX_OUTPUT),
        ("krlTool", &mut o.krl.tool, KRL_MAX_TOOL),
        ("krlBase", &mut o.krl.base, KRL_MAX_BASE),
    ] {
        if let Some(v) = r.optional_integer(key, 1, max as i64)? {
            *slot = v as u32;
        }
    }
    for (key, slot) in [
        (
            "krlApproximationProcessMm",
            &mut o.krl.approximation_process_mm,
        ),
        ("krlApproximationLinkMm", &mut o.krl.approximation_link_mm),
    ] {
        if let Some(v) = r.optional_number(key)? {
            *slot = v;
        }
    }
    if let Some(v) = r.optional_bool("rapidConfigCheck")? {
        o.rapid.config_check = v;
    }
    if let Some(v) = r.optional_bool("krlUnwrapAngles")? {
        o.krl.unwrap_angles = v;
    }
    Ok(o)
}

/// CSV of `path` with JavaScript export options (shared by every class that exports a path).
pub(crate) fn export_csv(path: &ToolPath, opts: &JsValue) -> Result<String, JsError> {
    Ok(crate::toolpath::to_csv(
        path,
        &export_options_from_js(opts)?,
    )?)
}

/// JSON of `path` with JavaScript export options.
pub(crate) fn export_json(path: &ToolPath, opts: &JsValue) -> Result<String, JsError> {
    Ok(crate::toolpath::to_json(
        path,
        &export_options_from_js(opts)?,
    )?)
}

/// ABB RAPID files of `path` (main module first) with JavaScript export options.
pub(crate) fn export_rapid(path: &ToolPath, opts: &JsValue) -> Result<Vec<String>, JsError> {
    Ok(crate::toolpath::to_rapid(
        path,
        &export_options_from_js(opts)?,
    )?)
}

/// KUKA KRL files of `path` (main program first) with JavaScript export options.
pub(crate) fn export_krl(path: &ToolPath, opts: &JsValue) -> Result<Vec<String>, JsError> {
    Ok(crate::toolpath::to_krl(
        path,
        &export_options_from_js(opts)?,
    )?)
}

/// A tool path (geodesic passes): poses with their kind and pass, and the robot exports.
#[wasm_bindgen(js_name = ToolPath)]
pub struct ToolPathHandle(pub(crate) crate::toolpath::ToolPath);

#[wasm_bindgen(js_class = ToolPath)]
impl ToolPathHandle {
    /// Number of poses.
    #[wasm_bindgen(getter, js_name = poseCount)]
    pub fn pose_count(&self) -> u32 {
        self.0.poses.len() as u32
    }

    /// Number of passes (one more than the largest pass index; 0 when empty).
    #[wasm_bindgen(getter, js_name = passCount)]
    pub fn pass_count(&self) -> u32 {
        self.0.poses.iter().map(|p| p.pass + 1).max().unwrap_or(0)
    }

    /// Positions, flat `[x0, y0, z0, x1, …]` in the mesh's unit.
    pub fn positions(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(3 * self.0.poses.len());
        for p in &self.0.poses {
            out.extend_from_slice(&[p.position.x, p.position.y, p.position.z]);
        }
        out
    }

    /// Unit tool axes (from the tool towards the part), flat xyz.
    pub fn axes(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(3 * self.0.poses.len());
        for p in &self.0.poses {
            out.extend_from_slice(&[p.axis.x, p.axis.y, p.axis.z]);
        }
        out
    }

    /// Kind code per pose: 0 pass, 1 straight transition, 2 arc, 3 extension, 4 link
    /// (process off), 5 approach, 6 retract.
    pub fn kinds(&self) -> Vec<u8> {
        self.0.poses.iter().map(|p| p.kind.code()).collect()
    }

    /// Pass index per pose.
    #[wasm_bindgen(js_name = passOf)]
    pub fn pass_of(&self) -> Vec<u32> {
        self.0.poses.iter().map(|p| p.pass).collect()
    }

    /// The path as CSV (positions in mm: give `mmPerUnit` for a file not in mm).
    #[wasm_bindgen(js_name = toCsv)]
    pub fn to_csv(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "ExportOptions")] opts: JsValue,
    ) -> Result<String, JsError> {
        export_csv(&self.0, &opts)
    }

    /// The path as JSON (positions in mm: give `mmPerUnit` for a file not in mm).
    #[wasm_bindgen(js_name = toJson)]
    pub fn to_json(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "ExportOptions")] opts: JsValue,
    ) -> Result<String, JsError> {
        export_json(&self.0, &opts)
    }

    /// ABB RAPID modules, one string per file (main module first).
    #[wasm_bindgen(js_name = toRapid)]
    pub fn to_rapid(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "ExportOptions")] opts: JsValue,
    ) -> Result<Vec<String>, JsError> {
        export_rapid(&self.0, &opts)
    }

    /// KUKA KRL `.src` files, one string per file (main program first).
    #[wasm_bindgen(js_name = toKrl)]
    pub fn to_krl(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "ExportOptions")] opts: JsValue,
    ) -> Result<Vec<String>, JsError> {
        export_krl(&self.0, &opts)
    }
}
