//! `DistanceField`: the result of `Mesh.geodesicDistance` (JavaScript must call `free()`),
//! with its iso-distance paths and the tool path linking them.
//!
//! Every JavaScript input (the source, the parameters, the path options, the callback) is
//! read through the bounded reader of `params.rs` before the mesh is used.

use super::params::{integer, read_callback, read_index_list, read_number_list, ParamReader};
use super::progress_fn;
use super::toolpath::ToolPathHandle;
use crate::geodesic::{
    geodesic_distance_cached, DistanceParams, GeodesicSource, LinkOrder, Method, PathParams,
    SurfaceCache,
};
use crate::math::{Point3, Vector3};
use crate::mesh::ImportedMesh;
use js_sys::{Array, Float64Array, Object, Reflect};
use std::rc::Rc;
use wasm_bindgen::prelude::*;

#[wasm_bindgen(typescript_custom_section)]
const GEODESIC_TYPES: &str = r#"
/** Where the geodesic distance is measured from: points on or near the surface (xyz, snapped,
 *  joined by segments; closed joins the last to the first), mesh vertices, a boundary loop
 *  (of the mesh, or with a patch id of the face set given in params.faces; loops numbered
 *  longest first, default every loop), or the section by a plane (the piece nearest point). */
export type GeodesicSource =
  | { polyline: Float64Array | number[]; closed?: boolean }
  | { vertices: Uint32Array | number[] }
  | { boundaryOf: "mesh" | number; loop?: number }
  | { plane: { point: [number, number, number]; normal: [number, number, number] } };
/** method "accurate" (default: virtual sources carried vertex to vertex, near the exact
 *  polyhedral distance at the cost of fast marching; on a surface of at most 100k triangles
 *  with a corner or a hole, the exact distance when it takes at most 192 windows per
 *  triangle (at least 4M), and the field's method is then "exact"), "exact" (window
 *  propagation, the exact
 *  polyhedral distance, the reference; slow on large doubly curved meshes), "fast" (unfolded
 *  wavefronts, approximate: millimetres off on large doubly curved panels; "mesh" is its
 *  former name, accepted for one release) or "voxel" (the paper); voxelSize in the file's
 *  unit (default mean edge / 4); faces: restrict to these triangles (a patch). */
export interface GeodesicParams {
  method?: "accurate" | "exact" | "fast" | "mesh" | "voxel"; voxelSize?: number;
  faces?: Uint32Array | number[];
}
/** Path options: pointSpacing (default spacing / 4), maxLevel (levels 1..maxLevel), order
 *  (default "zigzag"), speed / linkSpeed (file unit per s; defaults 10 and 100). With
 *  spacing null, beadWidth × overlapFactor gives it (the paper: 6.4 × 0.738). */
export interface GeodesicPathOptions {
  pointSpacing?: number; maxLevel?: number; order?: "zigzag" | "oneWay";
  speed?: number; linkSpeed?: number; beadWidth?: number; overlapFactor?: number;
}
/** One iso-distance pass: level k, distance k·spacing, xyz points and unit normals. */
export interface IsoPath { level: number; distance: number; closed: boolean; points: Float64Array; normals: Float64Array }
"#;

/// Keys of a `GeodesicSource`.
const SOURCE_KEYS: &[&str] = &[
    "polyline",
    "closed",
    "vertices",
    "boundaryOf",
    "loop",
    "plane",
];
/// The keys that choose the source form.
const SOURCE_FORMS: &[&str] = &["polyline", "vertices", "boundaryOf", "plane"];
/// Keys of `GeodesicParams`.
const PARAM_KEYS: &[&str] = &["method", "voxelSize", "faces"];
/// Keys of `GeodesicPathOptions`.
const PATH_KEYS: &[&str] = &[
    "pointSpacing",
    "maxLevel",
    "order",
    "speed",
    "linkSpeed",
    "beadWidth",
    "overlapFactor",
];

/// How the source named its boundary.
enum BoundaryOf {
    Mesh,
    Patch(i64),
}

/// A source read from JavaScript, before the face set is known to fit it.
struct SourceArg {
    source: GeodesicSource,
    boundary_of: Option<BoundaryOf>,
}

/// Reads a `GeodesicSource`: exactly one form key, and the keys of that form only.
fn source_from_js(value: &JsValue) -> Result<SourceArg, JsError> {
    let r = ParamReader::object(value, "geodesic source", SOURCE_KEYS)?;
    let mut given = Vec::new();
    for &key in SOURCE_FORMS {
        if let Some(v) = r.optional_value(key)? {
            given.push((key, v));
        }
    }
    let (form, value) =
        match given.as_slice() {
            [(key, value)] => (*key, value.clone()),
            [] => return Err(JsError::new(
                "the geodesic source needs one of 'polyline', 'vertices', 'boundaryOf', 'plane'",
            )),
            _ => {
                return Err(JsError::new(&format!(
                    "the geodesic source has {}; give exactly one of them",
                    given
                        .iter()
                        .map(|(k, _)| format!("'{k}'"))
                        .collect::<Vec<_>>()
                        .join(" and ")
                )))
            }
        };
    let refuse_extra = |key: &'static str, belongs: &str| -> Result<(), JsError> {
        if r.optional_value(key)?.is_some() {
            return Err(JsError::new(&format!(
                "geodesic source '{key}' only goes with '{belongs}', not with '{form}'"
            )));
        }
        Ok(())
    };
    if form != "polyline" {
        refuse_extra("closed", "polyline")?;
    }
    if form != "boundaryOf" {
        refuse_extra("loop", "boundaryOf")?;
    }
    let mut boundary_of = None;
    let source = match form {
        "polyline" => {
            let coords = read_number_list(&value, "source.polyline", 3)?;
            if coords.is_empty() {
                return Err(JsError::new("source.polyline has no points"));
            }
            let points = coords
                .chunks_exact(3)
                .map(|c| Point3::new(c[0], c[1], c[2]))
                .collect();
            GeodesicSource::Polyline {
                points,
                closed: r.optional_bool("closed")?.unwrap_or(false),
            }
        }
        "vertices" => {
            let ids = read_index_list(Some(value), "source.vertices")?.unwrap_or_default();
            if ids.is_empty() {
                return Err(JsError::new("source.vertices is empty"));
            }
            GeodesicSource::Vertices(ids)
        }
        "boundaryOf" => {
            let v = value;
            boundary_of = Some(if v.as_string().as_deref() == Some("mesh") {
                BoundaryOf::Mesh
            } else if v.as_f64().is_some() {
                BoundaryOf::Patch(integer(&v, "source.boundaryOf", 0, u32::MAX as i64)?)
            } else {
                return Err(JsError::new(&format!(
                    "source.boundaryOf must be \"mesh\" or a patch id, got {}",
                    super::params::describe(&v)
                )));
            });
            let loop_index = r.optional_integer("loop", 0, u32::MAX as i64)?;
            GeodesicSource::Boundary {
                loop_index: loop_index.map(|i| i as usize),
            }
        }
        _ => {
            let plane = r
                .optional_object("plane", &["point", "normal"])?
                .ok_or_else(|| JsError::new("geodesic source 'plane' is missing"))?;
            let point = plane
                .optional_vector3("point")?
                .ok_or_else(|| JsError::new("geodesic source 'plane.point' is missing"))?;
            let normal = plane
                .optional_vector3("normal")?
                .ok_or_else(|| JsError::new("geodesic source 'plane.normal' is missing"))?;
            GeodesicSource::Plane {
                point: Point3::from(point),
                normal: Vector3::from(normal),
            }
        }
    };
    Ok(SourceArg {
        source,
        boundary_of,
    })
}

/// Reads `GeodesicParams` (`undefined` for the defaults).
fn params_from_js(value: &JsValue) -> Result<DistanceParams, JsError> {
    let mut params = DistanceParams::default();
    let Some(r) = ParamReader::optional_argument(value, "geodesic parameter", PARAM_KEYS)? else {
        return Ok(params);
    };
    let methods = ["accurate", "exact", "fast", "mesh", "voxel"];
    if let Some(m) = r.optional_choice("method", &methods)? {
        params.method = match m {
            "voxel" => Method::Voxel,
            "exact" => Method::Exact,
            // "mesh": the former name of "fast", accepted for one release.
            "fast" | "mesh" => Method::Fast,
            _ => Method::Accurate,
        };
    }
    params.voxel_size = r.optional_number("voxelSize")?;
    if params.voxel_size.is_some() && params.method != Method::Voxel {
        return Err(JsError::new(
            "geodesic parameter 'voxelSize' needs method \"voxel\"",
        ));
    }
    if let Some(faces) = read_index_list(r.optional_value("faces")?, "faces")? {
        if faces.is_empty() {
            return Err(JsError::new(
                "faces is empty: give at least one triangle, or leave it out for the whole mesh",
            ));
        }
        params.faces = Some(faces);
    }
    Ok(params)
}

/// Reads the spacing argument and `GeodesicPathOptions` into the core's `PathParams`.
fn path_params_from_js(spacing: &JsValue, opts: &JsValue) -> Result<PathParams, JsError> {
    let r = ParamReader::optional_argument(opts, "path option", PATH_KEYS)?;
    let bead = match &r {
        Some(r) => (
            r.optional_number("beadWidth")?,
            r.optional_number("overlapFactor")?,
        ),
        None => (None, None),
    };
    let mut params = if spacing.is_undefined() || spacing.is_null() {
        match bead {
            (Some(w), Some(f)) => PathParams::from_bead(w, f)?,
            _ => {
                return Err(JsError::new(
                    "spacing is missing: give a number, or null with both path options \
                     'beadWidth' and 'overlapFactor'",
                ))
            }
        }
    } else {
        let Some(s) = spacing.as_f64() else {
            return Err(JsError::new(&format!(
                "spacing must be a number (or null with beadWidth and overlapFactor), got {}",
                super::params::describe(spacing)
            )));
        };
        if bead.0.is_some() || bead.1.is_some() {
            return Err(JsError::new(
                "give either spacing or the path options 'beadWidth' and 'overlapFactor', not both",
            ));
        }
        PathParams {
            spacing: s,
            ..PathParams::default()
        }
    };
    if let Some(r) = r {
        params.point_spacing = r.optional_number("pointSpacing")?;
        if let Some(k) = r.optional_integer("maxLevel", 1, crate::geodesic::MAX_LEVELS as i64)? {
            params.max_level = Some(k as u32);
        }
        if let Some(order) = r.optional_choice("order", &["zigzag", "oneWay"])? {
            params.order = if order == "oneWay" {
                LinkOrder::OneDirection
            } else {
                LinkOrder::ZigZag
            };
        }
        if let Some(speed) = r.optional_number("speed")? {
            params.speed = speed;
        }
        if let Some(speed) = r.optional_number("linkSpeed")? {
            params.link_speed = speed;
        }
    }
    params.validate()?;
    Ok(params)
}

/// Computes the field: the `Mesh.geodesicDistance` binding.
pub(crate) fn distance_field(
    mesh: &Rc<ImportedMesh>,
    surfaces: &SurfaceCache,
    source: &JsValue,
    params: &JsValue,
    on_progress: Option<JsValue>,
) -> Result<DistanceField, JsError> {
    // All JavaScript input is read (through imports that catch exceptions) before any work.
    let source = source_from_js(source)?;
    let params = params_from_js(params)?;
    let on_progress = read_callback(on_progress, "onProgress")?;
    match (&source.boundary_of, &params.faces) {
        (Some(BoundaryOf::Patch(id)), None) => {
            return Err(JsError::new(&format!(
                "source.boundaryOf = {id} names a patch: give its triangles as params.faces"
            )))
        }
        (Some(BoundaryOf::Mesh), Some(_)) => {
            return Err(JsError::new(
                "source.boundaryOf = \"mesh\" with params.faces: the distance is measured on the \
                 faces only; give boundaryOf the patch id for the boundary of the faces",
            ))
        }
        _ => {}
    }
    let field = geodesic_distance_cached(
        &mesh.mesh,
        &mesh.adjacency,
        Some(surfaces),
        &source.source,
        &params,
        &mut progress_fn(on_progress),
    )?;
    Ok(DistanceField {
        mesh: mesh.clone(),
        inner: field,
    })
}

/// `mesh.prepareGeodesic(params)`: derives and keeps what a distance on `params.faces` needs.
pub(crate) fn prepare(
    mesh: &ImportedMesh,
    surfaces: &SurfaceCache,
    params: &JsValue,
) -> Result<(), JsError> {
    let params = params_from_js(params)?;
    surfaces.prepare(&mesh.mesh, &mesh.adjacency, params.faces.as_deref())?;
    Ok(())
}

/// Geodesic distance from a source over the mesh (or a patch), by the method it names.
#[wasm_bindgen]
pub struct DistanceField {
    mesh: Rc<ImportedMesh>,
    inner: crate::geodesic::DistanceField,
}

#[wasm_bindgen]
impl DistanceField {
    /// The method that ran: `"accurate"`, `"exact"` (also when `"accurate"` was asked and the
    /// exact method finished within its budget on a small surface with corners or holes),
    /// `"fast"` (also when asked as `"mesh"`) or `"voxel"`.
    #[wasm_bindgen(getter)]
    pub fn method(&self) -> String {
        self.inner.method.name().into()
    }

    /// Largest finite distance, file unit.
    #[wasm_bindgen(getter, js_name = maxDistance)]
    pub fn max_distance(&self) -> f64 {
        self.inner.max_distance
    }

    /// Source samples the distance was propagated from (curve points + vertices).
    #[wasm_bindgen(getter, js_name = sourceSamples)]
    pub fn source_samples(&self) -> u32 {
        self.inner.source_samples as u32
    }

    /// Number of voxels (0 for the other methods).
    #[wasm_bindgen(getter, js_name = voxelCount)]
    pub fn voxel_count(&self) -> u32 {
        self.inner
            .voxels
            .as_ref()
            .map_or(0, |v| v.cells.len() as u32)
    }

    /// Bytes held by the voxels and their lookup table (0 for the other methods).
    #[wasm_bindgen(getter, js_name = voxelMemoryBytes)]
    pub fn voxel_memory_bytes(&self) -> f64 {
        self.inner
            .voxels
            .as_ref()
            .map_or(0.0, |v| v.memory_bytes as f64)
    }

    /// Distance per welded vertex (`Infinity` where unreached or outside the faces; voxel
    /// method: the distance of the voxel holding the vertex or its nearest neighbour).
    #[wasm_bindgen(js_name = vertexDistance)]
    pub fn vertex_distance(&self) -> Vec<f64> {
        self.inner.vertex_distance.clone()
    }

    /// Voxel centres, flat xyz (voxel method; empty otherwise).
    #[wasm_bindgen(js_name = voxelCenters)]
    pub fn voxel_centers(&self) -> Vec<f32> {
        let Some(v) = &self.inner.voxels else {
            return Vec::new();
        };
        let mut out = Vec::with_capacity(3 * v.cells.len());
        for i in 0..v.cells.len() {
            let c = v.centre(i);
            out.extend_from_slice(&[c.x as f32, c.y as f32, c.z as f32]);
        }
        out
    }

    /// Distance per voxel (voxel method; empty otherwise; `Infinity` where unreached).
    #[wasm_bindgen(js_name = voxelDistance)]
    pub fn voxel_distance(&self) -> Vec<f32> {
        self.inner
            .voxels
            .as_ref()
            .map_or_else(Vec::new, |v| v.distance.iter().map(|&d| d as f32).collect())
    }

    /// Iso-distance passes at `k · spacing`, in increasing level:
    /// `{ level, distance, closed, points, normals }[]`. Throws an `Error` naming a bad
    /// spacing or option.
    #[wasm_bindgen(js_name = isoPaths, unchecked_return_type = "IsoPath[]")]
    pub fn iso_paths(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number | null")] spacing: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "GeodesicPathOptions")] opts: JsValue,
    ) -> Result<Array, JsError> {
        let params = path_params_from_js(&spacing, &opts)?;
        let lines = self
            .inner
            .iso_lines(&self.mesh.mesh, &self.mesh.adjacency, &params)?;
        let out = Array::new();
        for line in &lines {
            let flat = |v: &mut dyn Iterator<Item = [f64; 3]>| -> Float64Array {
                let data: Vec<f64> = v.flatten().collect();
                Float64Array::from(data.as_slice())
            };
            let points = flat(&mut line.points.iter().map(|p| [p.x, p.y, p.z]));
            let normals = flat(&mut line.normals.iter().map(|n| [n.x, n.y, n.z]));
            let item = Object::new();
            let set = |key: &str, value: JsValue| -> Result<(), JsError> {
                // A fresh plain object takes any data property; the error path is only here
                // because `Reflect.set` is declared fallible.
                Reflect::set(&item, &JsValue::from_str(key), &value)
                    .map(|_| ())
                    .map_err(|_| JsError::new("could not build an iso-path object"))
            };
            set("level", JsValue::from(line.level))?;
            set("distance", JsValue::from(line.distance))?;
            set("closed", JsValue::from(line.closed))?;
            set("points", points.into())?;
            set("normals", normals.into())?;
            out.push(&item);
        }
        Ok(out)
    }

    /// The passes ordered and linked into a `ToolPath` (tool axis = −surface normal), with
    /// the same exports as a spray plan. Throws an `Error` naming a bad spacing or option.
    #[wasm_bindgen(js_name = toolPath)]
    pub fn tool_path(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number | null")] spacing: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "GeodesicPathOptions")] opts: JsValue,
    ) -> Result<ToolPathHandle, JsError> {
        let params = path_params_from_js(&spacing, &opts)?;
        let path = self
            .inner
            .tool_path(&self.mesh.mesh, &self.mesh.adjacency, &params)?;
        Ok(ToolPathHandle(path))
    }
}
