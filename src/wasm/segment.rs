//! `Segmentation`: the patches of one `Mesh.segment` call (JavaScript must call `free()`).

use super::progress_fn;
use crate::mesh::ImportedMesh;
use crate::segment::{segment_with_progress, GrowthThreshold, ParamsSpec, SegmentParams};
use std::rc::Rc;
use wasm_bindgen::prelude::*;

/// Parses `{ angleThreshold | curvatureThreshold | spray | grind, thetaMax, minAreaRatio }`.
pub(crate) fn params_from_js(params: JsValue) -> Result<SegmentParams, JsError> {
    let spec: ParamsSpec = serde_wasm_bindgen::from_value(params)
        .map_err(|e| JsError::new(&format!("invalid segmentation parameters: {e}")))?;
    Ok(SegmentParams::try_from(spec)?)
}

/// Patches of a mesh: ids by decreasing area; faces of dropped patches have id −1.
#[wasm_bindgen]
pub struct Segmentation {
    mesh: Rc<ImportedMesh>,
    inner: crate::segment::Segmentation,
}

impl Segmentation {
    pub(crate) fn new(
        mesh: Rc<ImportedMesh>,
        params: &SegmentParams,
        on_progress: Option<js_sys::Function>,
    ) -> Result<Segmentation, JsError> {
        let inner = segment_with_progress(
            &mesh.adjacency,
            &mesh.geometry,
            params,
            &mut progress_fn(on_progress),
        )?;
        Ok(Segmentation { mesh, inner })
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

    /// Binary STL of patch `id`. Throws if there is no such patch.
    #[wasm_bindgen(js_name = patchStl)]
    pub fn patch_stl(&self, id: u32) -> Result<Vec<u8>, JsError> {
        self.inner
            .patch_stl(&self.mesh.mesh, id as usize)
            .ok_or_else(|| {
                JsError::new(&format!(
                    "no patch {id}: this segmentation has {} patches",
                    self.inner.patches.len()
                ))
            })
    }

    /// Triangle ids of patch `id`, in increasing order. Throws if there is no such patch.
    #[wasm_bindgen(js_name = patchFaces)]
    pub fn patch_faces(&self, id: u32) -> Result<Vec<u32>, JsError> {
        if id as usize >= self.inner.patches.len() {
            return Err(JsError::new(&format!(
                "no patch {id}: this segmentation has {} patches",
                self.inner.patches.len()
            )));
        }
        Ok(self.inner.faces_of(id as usize).map(|f| f as u32).collect())
    }
}
