//! Drilling-hole correction for JavaScript: `normalFromLasers`, `correctHoles`, and the
//! `Mesh` methods `laserReadings`, `closestPoints`, `correctHoles` and `drillingProgram`, the
//! hole-list reader `parseHolesCsv` and the paper's example `drillPaperExample` (the mesh index is built
//! on first use and kept with the `Mesh`). Correction with and without a panel mesh is split
//! into the method and the free function because wasm-bindgen cannot borrow an optional
//! `Mesh` (`Option<&Mesh>`); taking `Option<Mesh>` would consume the caller's handle. The
//! glue refuses `correctHoles(params, mesh)` and points to `mesh.correctHoles(params)`.

use super::params::{describe, read_number_list, set, ParamReader};
use super::Mesh;
use crate::drill::{self, CorrectionParams, MeshIndex, Method, ReferenceHole};
use crate::math::{Point3, Vector3};
use crate::toolpath::{to_csv, to_json, to_krl, to_rapid};
use js_sys::{Array, Float64Array, Object, Uint32Array, Uint8Array};
use wasm_bindgen::prelude::*;

/// Keys of the `correctHoles` parameter object.
const CORRECTION_KEYS: &[&str] = &[
    "references",
    "holes",
    "method",
    "tangentScale",
    "extrapolate",
];
/// Keys of one reference hole.
const REFERENCE_KEYS: &[&str] = &["nominal", "actual", "normal", "nominalNormal"];
/// Keys of the drilling pose parameters.
const POSE_KEYS: &[&str] = &["approach", "retract", "feedSpeed", "linkSpeed"];

/// Reads the `correctHoles` parameters through the bounded reader (the one place that knows
/// their JavaScript shape): unknown keys, wrong types and `null` refused with their path.
fn correction_params_from_js(params: &JsValue) -> Result<CorrectionParams, JsError> {
    let r = ParamReader::object(params, "hole-correction parameter", CORRECTION_KEYS)?;
    let missing =
        |what: &str| JsError::new(&format!("hole-correction parameter '{what}' is missing"));
    let list = r
        .optional_objects("references", 4, REFERENCE_KEYS)?
        .ok_or_else(|| missing("references"))?;
    let mut references = Vec::with_capacity(4);
    for (i, item) in list.iter().enumerate() {
        let vector = |key: &'static str| -> Result<[f64; 3], JsError> {
            item.optional_vector3(key)?
                .ok_or_else(|| missing(&format!("references[{i}].{key}")))
        };
        references.push(ReferenceHole {
            nominal: Point3::from(vector("nominal")?),
            actual: Point3::from(vector("actual")?),
            normal: Vector3::from(vector("normal")?),
            nominal_normal: item.optional_vector3("nominalNormal")?.map(Vector3::from),
        });
    }
    let references: [ReferenceHole; 4] = references
        .try_into()
        .map_err(|_| JsError::new("references must list exactly 4 reference holes"))?;
    let holes = r.optional_value("holes")?.ok_or_else(|| missing("holes"))?;
    let holes = read_number_list(&holes, "holes", 3)?;
    Ok(CorrectionParams {
        references,
        holes: points(&holes, "holes")?,
        method: match r.optional_choice("method", &["coons", "bilinear"])? {
            Some("bilinear") => Method::Bilinear,
            _ => Method::Coons,
        },
        tangent_scale: r.optional_number("tangentScale")?,
        extrapolate: r.optional_bool("extrapolate")?.unwrap_or(false),
    })
}

/// Reads the optional drilling pose parameters (`undefined` for the defaults).
fn pose_params_from_js(value: &JsValue) -> Result<drill::PoseParams, JsError> {
    let d = drill::PoseParams::default();
    let Some(r) = ParamReader::optional_argument(value, "drilling pose parameter", POSE_KEYS)?
    else {
        return Ok(d);
    };
    Ok(drill::PoseParams {
        approach: r.optional_number("approach")?.unwrap_or(d.approach),
        retract: r.optional_number("retract")?.unwrap_or(d.retract),
        feed_speed: r.optional_number("feedSpeed")?.unwrap_or(d.feed_speed),
        link_speed: r.optional_number("linkSpeed")?.unwrap_or(d.link_speed),
    })
}

/// Flat `[x0, y0, z0, x1, …]` as points; `name` labels the error.
fn points(flat: &[f64], name: &str) -> Result<Vec<Point3>, JsError> {
    if flat.len() % 3 != 0 {
        return Err(JsError::new(&format!(
            "{name} must hold x, y, z triples, got {} numbers",
            flat.len()
        )));
    }
    Ok(flat
        .chunks_exact(3)
        .map(|c| Point3::new(c[0], c[1], c[2]))
        .collect())
}

/// Exactly four triples, for the laser functions.
fn four(flat: &[f64], name: &str) -> Result<[Point3; 4], JsError> {
    points(flat, name)?.try_into().map_err(|p: Vec<_>| {
        JsError::new(&format!(
            "{name} must hold 4 x, y, z triples, got {}",
            p.len()
        ))
    })
}

fn flat_f64<'a>(v: impl IntoIterator<Item = &'a [f64]>) -> Float64Array {
    let all: Vec<f64> = v.into_iter().flatten().copied().collect();
    Float64Array::from(all.as_slice())
}

/// Unit surface normal from four laser sensors: beam `origins` and unit `directions` (4 × xyz
/// each, in cyclic order around the head) and the 4 `readings`; points back towards the
/// sensors. Each a `Float64Array`, a `Float32Array` or an array of numbers; anything else (a
/// string, `null` entries, NaN) and degenerate input throw an `Error` naming it.
#[wasm_bindgen(js_name = normalFromLasers, unchecked_return_type = "[number, number, number]")]
pub fn normal_from_lasers(
    #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] origins: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] directions: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] readings: JsValue,
) -> Result<JsValue, JsError> {
    // Read as numbers, not coerced: an array's `null` would be 0 and a string's digits numbers.
    let o = four(&read_number_list(&origins, "origins", 3)?, "origins")?;
    let d = four(
        &read_number_list(&directions, "directions", 3)?,
        "directions",
    )?
    .map(|p| p.coords);
    let readings = read_number_list(&readings, "readings", 1)?;
    let r: [f64; 4] = readings.as_slice().try_into().map_err(|_| {
        JsError::new(&format!(
            "readings must hold 4 numbers, got {}",
            readings.len()
        ))
    })?;
    let n = drill::normal_from_lasers(&o, &d, &r)?;
    Ok(serde_wasm_bindgen::to_value(&[n.x, n.y, n.z])?)
}

/// Corrects the nominal holes from four reference holes (see `CorrectionParams`) without a
/// panel mesh (`mesh.correctHoles(params)` projects onto a mesh). Returns
/// `{ corrected, normals, u, w, outside }` (flat xyz, outward unit normals, patch parameters,
/// 1 where a hole was extrapolated). Throws an `Error` naming bad input.
#[wasm_bindgen(js_name = correctHoles, unchecked_return_type = "HoleCorrection")]
pub fn correct_holes(
    #[wasm_bindgen(unchecked_param_type = "CorrectionParams")] params: JsValue,
) -> Result<JsValue, JsError> {
    correction_to_js(params, None)
}

/// `correctHoles` for JavaScript, with or without the panel's index.
fn correction_to_js(params: JsValue, index: Option<&MeshIndex>) -> Result<JsValue, JsError> {
    let params = correction_params_from_js(&params)?;
    let c = drill::correct_holes(&params, index)?;
    let out = Object::new();
    set(
        &out,
        "corrected",
        &flat_f64(c.corrected.iter().map(|p| p.coords.as_slice())).into(),
    )?;
    set(
        &out,
        "normals",
        &flat_f64(c.normals.iter().map(|n| n.as_slice())).into(),
    )?;
    set(&out, "u", &Float64Array::from(c.u.as_slice()).into())?;
    set(&out, "w", &Float64Array::from(c.w.as_slice()).into())?;
    let outside: Vec<u8> = c.outside.iter().map(|&o| o as u8).collect();
    set(
        &out,
        "outside",
        &Uint8Array::from(outside.as_slice()).into(),
    )?;
    Ok(out.into())
}

#[wasm_bindgen(typescript_custom_section)]
const DRILL_TYPES: &str = r#"
/** Hole list read from `id,x,y,z` text: good rows (ids, flat xyz, 1-based line numbers) and one
 *  error per bad row; header: whether the first non-blank line was a header. */
export interface HoleList {
  ids: string[]; positions: Float64Array; lines: Uint32Array;
  errors: { line: number; message: string }[]; header: boolean;
}
/** Drilling cycle: approach and retract distances along the normal (≥ 0, default 20), feed and
 *  link speeds (> 0, default 5 and 100), in the mesh's unit and per second. */
export interface DrillPoseParams { approach?: number; retract?: number; feedSpeed?: number; linkSpeed?: number }
/** The paper's example: the actual panel as binary STL (mm), references A–D, hole ids, nominal
 *  holes and their true positions on the actual panel (flat xyz). */
export interface DrillPaperExample {
  stl: Uint8Array; references: ReferenceHole[]; ids: string[]; holes: Float64Array; truth: Float64Array;
}
"#;

/// Reads a hole list from `id,x,y,z` text (header optional; see `drill::parse_holes_csv`):
/// `{ ids, positions, lines, errors: [{ line, message }], header }`. Never throws on content.
#[wasm_bindgen(js_name = parseHolesCsv, unchecked_return_type = "HoleList")]
pub fn parse_holes_csv(
    #[wasm_bindgen(unchecked_param_type = "string")] text: JsValue,
) -> Result<JsValue, JsError> {
    // A string only: anything else made the generated glue write out of bounds (a trap).
    let Some(text) = text.as_string() else {
        return Err(JsError::new(&format!(
            "parseHolesCsv: text must be a string, got {}",
            describe(&text)
        )));
    };
    let list = drill::parse_holes_csv(&text);
    let out = Object::new();
    let ids: Array = list
        .holes
        .iter()
        .map(|h| JsValue::from_str(&h.id))
        .collect();
    set(&out, "ids", &ids.into())?;
    set(
        &out,
        "positions",
        &flat_f64(list.holes.iter().map(|h| h.position.coords.as_slice())).into(),
    )?;
    let lines: Vec<u32> = list.holes.iter().map(|h| h.line as u32).collect();
    set(&out, "lines", &Uint32Array::from(lines.as_slice()).into())?;
    let errors = Array::new();
    for e in &list.errors {
        let o = Object::new();
        set(&o, "line", &JsValue::from_f64(e.line as f64))?;
        set(&o, "message", &JsValue::from_str(&e.message))?;
        errors.push(&o);
    }
    set(&out, "errors", &errors.into())?;
    set(&out, "header", &JsValue::from_bool(list.header))?;
    Ok(out.into())
}

/// The paper's 60° example as data (`DrillPaperExample`): load `stl` as the model.
#[wasm_bindgen(js_name = drillPaperExample, unchecked_return_type = "DrillPaperExample")]
pub fn drill_paper_example() -> Result<JsValue, JsError> {
    let ex = drill::paper_example();
    let out = Object::new();
    let panel = &ex.panel;
    let stl = crate::mesh::write_stl((0..panel.triangle_count()).map(|f| panel.corners(f)));
    set(&out, "stl", &Uint8Array::from(stl.as_slice()).into())?;
    let references = Array::new();
    for r in &ex.references {
        let o = Object::new();
        let v = |p: &[f64]| serde_wasm_bindgen::to_value(&[p[0], p[1], p[2]]);
        set(&o, "nominal", &v(r.nominal.coords.as_slice())?)?;
        set(&o, "actual", &v(r.actual.coords.as_slice())?)?;
        set(&o, "normal", &v(r.normal.as_slice())?)?;
        if let Some(n) = r.nominal_normal {
            set(&o, "nominalNormal", &v(n.as_slice())?)?;
        }
        references.push(&o);
    }
    set(&out, "references", &references.into())?;
    let ids: Array = ex.ids.iter().map(|i| JsValue::from_str(i)).collect();
    set(&out, "ids", &ids.into())?;
    set(
        &out,
        "holes",
        &flat_f64(ex.holes.iter().map(|p| p.coords.as_slice())).into(),
    )?;
    set(
        &out,
        "truth",
        &flat_f64(ex.truth.iter().map(|p| p.coords.as_slice())).into(),
    )?;
    Ok(out.into())
}

#[wasm_bindgen]
impl Mesh {
    /// The drilling program of `correctHoles(params)` on this panel: approach, drill and
    /// retract poses per hole (`pose`: `DrillPoseParams`), written as `format` = "csv",
    /// "json" (one text) or "rapid", "krl" (one or more files) with `ExportOptions`.
    /// Throws an `Error` naming bad input.
    #[wasm_bindgen(js_name = drillingProgram)]
    pub fn drilling_program(
        &self,
        #[wasm_bindgen(unchecked_param_type = "CorrectionParams")] params: JsValue,
        #[wasm_bindgen(unchecked_param_type = "DrillPoseParams | undefined")] pose: JsValue,
        #[wasm_bindgen(unchecked_param_type = "string")] format: JsValue,
        #[wasm_bindgen(unchecked_param_type = "ExportOptions | undefined")] options: JsValue,
    ) -> Result<Vec<String>, JsError> {
        // All JavaScript input is read (through imports that catch exceptions) before any work.
        let params = correction_params_from_js(&params)?;
        let pose = pose_params_from_js(&pose)?;
        let options = super::toolpath::export_options_from_js(&options)?;
        const FORMATS: [&str; 4] = ["csv", "json", "rapid", "krl"];
        let Some(format) = format
            .as_string()
            .and_then(|f| FORMATS.into_iter().find(|&k| k == f))
        else {
            let given = match format.as_string() {
                Some(f) if f.chars().count() <= 40 => format!("{f:?}"),
                _ => describe(&format),
            };
            return Err(JsError::new(&format!(
                "unknown export format {given} (allowed: csv, json, rapid, krl)"
            )));
        };
        let correction = drill::correct_holes(&params, Some(&self.drill_index()))?;
        let path = drill::drilling_path(&correction, &pose, Vec::new())?;
        Ok(match format {
            "csv" => vec![to_csv(&path, &options)?],
            "json" => vec![to_json(&path, &options)?],
            "rapid" => to_rapid(&path, &options)?,
            _ => to_krl(&path, &options)?,
        })
    }

    /// `correctHoles` on this panel: corrected holes are projected onto the mesh, the drilling
    /// normals are the mesh's there, and missing `nominalNormal`s default to the mesh's normal
    /// at the nominal reference hole. Same result object; throws an `Error` on bad input.
    #[wasm_bindgen(js_name = correctHoles, unchecked_return_type = "HoleCorrection")]
    pub fn correct_holes(
        &self,
        #[wasm_bindgen(unchecked_param_type = "CorrectionParams")] params: JsValue,
    ) -> Result<JsValue, JsError> {
        correction_to_js(params, Some(&self.drill_index()))
    }

    /// Simulated laser readings: distance along each unit beam (flat xyz `origins` and
    /// `directions`, any count; each a `Float64Array`, a `Float32Array` or an array of
    /// numbers) to the first triangle hit, NaN where a beam misses.
    #[wasm_bindgen(js_name = laserReadings)]
    pub fn laser_readings(
        &self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] origins: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] directions: JsValue,
    ) -> Result<Vec<f64>, JsError> {
        let o = points(&read_number_list(&origins, "origins", 3)?, "origins")?;
        let d: Vec<Vector3> = points(
            &read_number_list(&directions, "directions", 3)?,
            "directions",
        )?
        .iter()
        .map(|p| p.coords)
        .collect();
        Ok(drill::laser_readings(&self.drill_index(), &o, &d)?)
    }

    /// Closest points of the mesh to flat xyz `points` (a `Float64Array`, a `Float32Array` or
    /// an array of numbers): `{ points, normals, distances }` (normals interpolated from the
    /// vertex normals, in the mesh's winding).
    #[wasm_bindgen(js_name = closestPoints, unchecked_return_type = "ClosestPoints")]
    pub fn closest_points(
        &self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] points: JsValue,
    ) -> Result<JsValue, JsError> {
        let points = read_number_list(&points, "points", 3)?;
        let index = self.drill_index();
        let found = self::points(&points, "points")?
            .iter()
            .enumerate()
            .map(|(i, p)| {
                index
                    .closest_point(p)
                    .ok_or_else(|| JsError::new(&format!("point {i} has a non-finite coordinate")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let out = Object::new();
        set(
            &out,
            "points",
            &flat_f64(found.iter().map(|c| c.point.coords.as_slice())).into(),
        )?;
        set(
            &out,
            "normals",
            &flat_f64(found.iter().map(|c| c.normal.as_slice())).into(),
        )?;
        let distances: Vec<f64> = found.iter().map(|c| c.distance).collect();
        set(
            &out,
            "distances",
            &Float64Array::from(distances.as_slice()).into(),
        )?;
        Ok(out.into())
    }
}

impl Mesh {
    /// The mesh index for ray casts and closest points, built on first use.
    pub(super) fn drill_index(&self) -> std::rc::Rc<MeshIndex> {
        super::index::index_of(&self.index, &self.inner)
    }
}
