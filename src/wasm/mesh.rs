//! `Mesh`: an imported STL held on the Rust side (JavaScript must call `free()`).

use super::{progress_fn, Segmentation, SprayPlan};
use crate::mesh::{import_stl, ImportedMesh};
use std::rc::Rc;
use wasm_bindgen::prelude::*;

/// A welded, consistently wound triangle mesh read from STL.
#[wasm_bindgen]
pub struct Mesh {
    pub(super) inner: Rc<ImportedMesh>,
    /// Ray-cast and closest-point index, built by the first drilling query.
    pub(super) index: std::cell::OnceCell<Rc<crate::drill::MeshIndex>>,
}

#[wasm_bindgen]
impl Mesh {
    /// Reads binary or ASCII STL bytes; `onProgress(stage, fraction)` is optional.
    /// Throws an `Error` naming what is wrong with the file.
    #[wasm_bindgen(js_name = fromStl)]
    pub fn from_stl(
        bytes: &[u8],
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<js_sys::Function>,
    ) -> Result<Mesh, JsError> {
        let imported = import_stl(bytes, &mut progress_fn(on_progress))?;
        Ok(Mesh {
            inner: Rc::new(imported),
            index: std::cell::OnceCell::new(),
        })
    }

    /// Number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> u32 {
        self.inner.mesh.triangle_count() as u32
    }

    /// Number of welded vertices.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> u32 {
        self.inner.mesh.vertex_count() as u32
    }

    /// Welded vertex positions, flat `[x0, y0, z0, x1, …]` in the file's unit.
    pub fn positions(&self) -> Vec<f32> {
        self.inner.mesh.positions_f32()
    }

    /// Vertex indices, 3 per triangle, in the consistent winding the segmentation used.
    pub fn indices(&self) -> Vec<u32> {
        self.inner.mesh.triangles().as_flattened().to_vec()
    }

    /// What was found while reading: counts, area, bounding box, defects (see `MeshReport`).
    #[wasm_bindgen(unchecked_return_type = "MeshReport")]
    pub fn report(&self) -> Result<JsValue, JsError> {
        Ok(serde_wasm_bindgen::to_value(&self.inner.report)?)
    }

    /// Segments the surface into patches. `params` as in `deriveThreshold`; throws an
    /// `Error` on bad parameters. `onProgress(stage, fraction)` is optional.
    pub fn segment(
        &self,
        #[wasm_bindgen(unchecked_param_type = "SegmentParams")] params: JsValue,
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<js_sys::Function>,
    ) -> Result<Segmentation, JsError> {
        let params = super::segment::params_from_js(params)?;
        Segmentation::new(self.inner.clone(), &params, on_progress)
    }

    /// Plans spray passes over `faces` (default: every triangle), predicts the coating and,
    /// given quality limits, searches the largest spacing meeting them. Throws an `Error`
    /// naming the bad parameter. `onProgress(stage, fraction)` is optional.
    #[wasm_bindgen(js_name = planSpray)]
    pub fn plan_spray(
        &self,
        #[wasm_bindgen(unchecked_param_type = "SprayPlanParams")] params: JsValue,
        faces: Option<Vec<u32>>,
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<js_sys::Function>,
    ) -> Result<SprayPlan, JsError> {
        // Every JavaScript input is read before the mesh is used.
        let params = super::spray::spray_params_from_js(params)?;
        let faces = faces.unwrap_or_else(|| (0..self.inner.mesh.triangle_count() as u32).collect());
        let m = &self.inner;
        let plan = crate::spray::plan_spray(
            &m.mesh,
            &m.adjacency,
            &m.geometry,
            &faces,
            &params,
            &mut progress_fn(on_progress),
        )?;
        Ok(SprayPlan::new(plan))
    }
}
