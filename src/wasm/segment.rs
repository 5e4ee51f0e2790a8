//! `Segmentation`: the patches of one `Mesh.segment` call (JavaScript must call `free()`).

use super::index::{hit_to_js, index_of, read_ray, SharedIndex};
use super::params::{describe, integer, read_number_list, ParamReader};
use super::progress_fn;
use crate::math::{Compact, Real};
use crate::mesh::{FaceGroups, ImportedMesh};
use crate::segment::{
    segment_with_progress, Checked, GrindParams, GrowthThreshold, ParamsSpec, SeedRule,
    SegmentParams, SprayParams,
};
use std::rc::Rc;
use wasm_bindgen::prelude::*;

const TOP_KEYS: [&str; 7] = [
    "angleThreshold",
    "curvatureThreshold",
    "spray",
    "grind",
    "thetaMax",
    "minAreaRatio",
    "seedRule",
];
const SPRAY_KEYS: [&str; 3] = ["meanThickness", "allowedDeviation", "minThickness"];
const GRIND_KEYS: [&str; 3] = ["indentationDepth", "minPressureRatio", "contactWidth"];

/// Reads `{ angleThreshold | curvatureThreshold | spray | grind, thetaMax, minAreaRatio,
/// seedRule }` with [`ParamReader`] (only these keys, no recursion, nothing coerced), then
/// lets the core check ranges and the single criterion.
pub(crate) fn params_from_js(params: &JsValue) -> Result<SegmentParams, JsError> {
    let r = ParamReader::object(params, "segmentation parameter", &TOP_KEYS)?;
    let angle_threshold = r.optional_number("angleThreshold")?;
    let curvature_threshold = r.optional_number("curvatureThreshold")?;
    let spray = match r.optional_object("spray", &SPRAY_KEYS)? {
        Some(p) => {
            let value = SprayParams {
                mean_thickness: p.number("meanThickness")?,
                allowed_deviation: p.number("allowedDeviation")?,
                min_thickness: p.number("minThickness")?,
            };
            Some(Checked::from(value))
        }
        None => None,
    };
    let grind = match r.optional_object("grind", &GRIND_KEYS)? {
        Some(p) => {
            let value = GrindParams {
                indentation_depth: p.number("indentationDepth")?,
                min_pressure_ratio: p.number("minPressureRatio")?,
                contact_width: p.number("contactWidth")?,
            };
            Some(Checked::from(value))
        }
        None => None,
    };
    let theta_max = r.optional_number("thetaMax")?;
    let min_area_ratio = r.optional_number("minAreaRatio")?;
    let seed_rule = r
        .optional_choice("seedRule", &["lowestIndex", "flattest", "largestArea"])?
        .map(|rule| match rule {
            "lowestIndex" => SeedRule::LowestIndex,
            "largestArea" => SeedRule::LargestArea,
            _ => SeedRule::Flattest,
        });
    let spec = ParamsSpec {
        angle_threshold,
        curvature_threshold,
        spray,
        grind,
        theta_max,
        min_area_ratio,
        seed_rule,
        unknown: Default::default(),
    };
    Ok(SegmentParams::try_from(spec)?)
}

/// Patches of a mesh: ids by decreasing area; faces of dropped patches have id −1.
#[wasm_bindgen]
pub struct Segmentation {
    mesh: Rc<ImportedMesh>,
    /// The mesh's ray-cast index, shared with the `Mesh` (built by the first pick).
    index: SharedIndex,
    inner: crate::segment::Segmentation,
}

impl Segmentation {
    pub(crate) fn new(
        mesh: Rc<ImportedMesh>,
        index: SharedIndex,
        params: &SegmentParams,
        on_progress: Option<js_sys::Function>,
    ) -> Result<Segmentation, JsError> {
        let inner = segment_with_progress(
            &mesh.adjacency,
            &mesh.geometry,
            params,
            &mut progress_fn(on_progress),
        )?;
        Ok(Segmentation { mesh, index, inner })
    }

    /// "no patch `id`" and the ids there are.
    fn no_patch(&self, id: &dyn std::fmt::Display) -> JsError {
        let ids = match self.inner.patches.len() {
            0 => "this segmentation has no patches".to_string(),
            1 => "this segmentation has 1 patch, id 0".to_string(),
            n => format!("this segmentation has {n} patches, ids 0 to {}", n - 1),
        };
        JsError::new(&format!("no patch {id}: {ids}"))
    }

    /// A patch id given from JavaScript: a whole number from 0 to `patchCount − 1`; anything
    /// else is refused, naming it (a whole number out of range with the ids there are).
    fn patch_id(&self, id: &JsValue) -> Result<usize, JsError> {
        let count = self.inner.patches.len();
        match id.as_f64() {
            Some(x) if x.fract() == 0.0 && !(0.0..count as f64).contains(&x) => {
                Err(self.no_patch(&Compact(x)))
            }
            _ if count == 0 => Err(self.no_patch(&describe(id))),
            _ => Ok(integer(id, "patch id", 0, count as i64 - 1)? as usize),
        }
    }
}

#[wasm_bindgen]
impl Segmentation {
    /// Number of kept patches.
    #[wasm_bindgen(getter, js_name = patchCount)]
    pub fn patch_count(&self) -> u32 {
        self.inner.patches.len() as u32
    }

    /// The growing threshold used: radians for "angle", 1 / mesh unit for "curvature".
    #[wasm_bindgen(getter)]
    pub fn threshold(&self) -> f64 {
        self.inner.threshold.value()
    }

    /// "angle" or "curvature".
    #[wasm_bindgen(getter, js_name = thresholdKind)]
    pub fn threshold_kind(&self) -> String {
        match self.inner.threshold {
            GrowthThreshold::Angle(_) => "angle".into(),
            GrowthThreshold::Curvature(_) => "curvature".into(),
        }
    }

    /// Patch id per triangle, or −1 where the triangle's patch was dropped as too small.
    #[wasm_bindgen(js_name = patchOf)]
    pub fn patch_of(&self) -> Vec<i32> {
        self.inner.patch_of.clone()
    }

    /// Draw buffers grouped by patch: group `id` for each kept patch, then one for the
    /// dropped triangles (see `DisplayBuffers`); `onProgress(stage, fraction)` is optional.
    #[wasm_bindgen(js_name = displayBuffers, unchecked_return_type = "DisplayBuffers")]
    pub fn display_buffers(
        &self,
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<JsValue>,
    ) -> Result<JsValue, JsError> {
        let patch_of = &self.inner.patch_of;
        let dropped = self.inner.patches.len();
        let groups = FaceGroups::new(patch_of.len(), dropped + 1, |f| {
            usize::try_from(patch_of[f]).unwrap_or(dropped)
        });
        super::display::display_buffers(&self.mesh, &groups, on_progress)
    }

    /// `{ id, triangleCount, area, normal: [x,y,z], maxDeviation, centroid: [x,y,z] }[]`,
    /// largest area first.
    #[wasm_bindgen(unchecked_return_type = "Patch[]")]
    pub fn patches(&self) -> Result<JsValue, JsError> {
        Ok(serde_wasm_bindgen::to_value(&self.inner.patches)?)
    }

    /// Patch borders as line segments, flat `[x0, y0, z0, x1, y1, z1, …]`.
    #[wasm_bindgen(js_name = borderSegments)]
    pub fn border_segments(&self) -> Vec<f32> {
        self.inner
            .border_segments(&self.mesh.mesh, &self.mesh.adjacency)
    }

    /// The two patch ids beside each border segment, flat `[p0, q0, p1, q1, …]`; −1 for a
    /// dropped patch or an open edge.
    #[wasm_bindgen(js_name = borderPatches)]
    pub fn border_patches(&self) -> Vec<i32> {
        self.inner
            .border_patches(&self.mesh.mesh, &self.mesh.adjacency)
    }

    /// Binary STL of patch `id`, a whole number from 0 to `patchCount − 1`; anything else
    /// (NaN, 0.5, a string, −1, 2^32) throws an `Error` naming it.
    #[wasm_bindgen(js_name = patchStl)]
    pub fn patch_stl(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number")] id: JsValue,
    ) -> Result<Vec<u8>, JsError> {
        let id = self.patch_id(&id)?;
        self.inner
            .patch_stl(&self.mesh.mesh, id)
            .ok_or_else(|| self.no_patch(&id))
    }

    /// Picking: the first triangle hit by the ray `origin + t·direction`, t ≥ 0, whose patch
    /// is not in `hidden` (patch ids; −1 stands for the dropped triangles): `{ face, point:
    /// [x, y, z], distance, patch }` (patch −1 for a dropped triangle), or `null`. Rays pass
    /// through hidden patches. Arguments as in `Mesh.raycast`; `hidden` is an array of whole
    /// numbers from −1 to `patchCount − 1` (default none), anything else throws an `Error`
    /// naming it. Shares the mesh's index, built by the first call.
    #[wasm_bindgen(unchecked_return_type = "RayHit | null")]
    pub fn raycast(
        &self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] origin: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] direction: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "number[]")] hidden: Option<JsValue>,
    ) -> Result<JsValue, JsError> {
        let (origin, direction) = read_ray(&origin, &direction)?;
        let count = self.inner.patches.len();
        // Slot 0 stands for the dropped triangles, slot p + 1 for patch p.
        let mut hide = vec![false; count + 1];
        if let Some(list) = hidden.filter(|v| !v.is_undefined() && !v.is_null()) {
            for (i, x) in read_number_list(&list, "hidden", 1)?
                .into_iter()
                .enumerate()
            {
                let id = integer(
                    &JsValue::from(x),
                    &format!("hidden[{i}]"),
                    -1,
                    count as i64 - 1,
                )?;
                hide[(id + 1) as usize] = true;
            }
        }
        let patch_of = &self.inner.patch_of;
        let slot = |face: usize| (patch_of[face] + 1) as usize;
        let index = index_of(&self.index, &self.mesh);
        let hit = index.cast_ray_where(&origin, &direction, Real::INFINITY, |face| {
            !hide[slot(face)]
        });
        match hit {
            Some(hit) => hit_to_js(&hit, Some(patch_of[hit.face])),
            None => Ok(JsValue::NULL),
        }
    }

    /// Triangle ids of patch `id`, in increasing order; `id` as in `patchStl` (anything but a
    /// patch's id throws an `Error` naming it).
    #[wasm_bindgen(js_name = patchFaces)]
    pub fn patch_faces(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number")] id: JsValue,
    ) -> Result<Vec<u32>, JsError> {
        let id = self.patch_id(&id)?;
        Ok(self.inner.faces_of(id).map(|f| f as u32).collect())
    }
}
