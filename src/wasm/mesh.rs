//! `Mesh`: an imported STL held on the Rust side (JavaScript must call `free()`).

use super::index::{hit_to_js, index_of, read_ray, SharedIndex};
use super::params::{byte_array, copy_all, copy_bytes, read_callback, read_index_list};
use super::{progress_fn, DistanceField, Segmentation, SprayPlan};
use crate::math::Real;
use crate::mesh::{
    binary_layout, prepare_mesh, read_stl_with_progress, BinaryStl, FaceGroups, ImportedMesh,
    StlImport, STL_HEAD_BYTES, STL_PREAMBLE_BYTES, STL_RECORD_BYTES,
};
use js_sys::Uint8Array;
use std::rc::Rc;
use wasm_bindgen::prelude::*;

/// Binary STL records copied from JavaScript at a time (800 KiB: the copies stay in cache).
const STREAM_RECORDS: usize = 1 << 14;

/// Reads STL bytes held by JavaScript. A binary file is streamed through a small buffer,
/// record by record, never copied whole into the engine's memory: that memory only grows,
/// so a copy of the file raised every later peak by the file's size, and copying it meant
/// writing it twice (zeroed, then filled). Any other file (ASCII, or one only the whole of
/// it tells apart) is copied whole and read as before.
fn read_stl_from_js(
    array: &Uint8Array,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<StlImport, JsError> {
    let len = array.length() as usize;
    let mut head = vec![0; len.min(STL_HEAD_BYTES)];
    copy_bytes(array, 0, &mut head);
    let Some(count) = binary_layout(&head, len) else {
        let bytes = copy_all(array)?;
        return Ok(read_stl_with_progress(&bytes, progress)?);
    };
    let data_end = STL_PREAMBLE_BYTES + count * STL_RECORD_BYTES;
    let mut reader = BinaryStl::new(count);
    let mut buffer = vec![0; STREAM_RECORDS * STL_RECORD_BYTES];
    let mut at = STL_PREAMBLE_BYTES;
    // Each pass reads at least one record (`data_end − at` is a positive multiple of a
    // record), so the loop ends.
    while at < data_end {
        // The progress callback runs between the copies and could detach or shrink the
        // file's buffer (its view then reports fewer bytes): refused, never read past.
        if array.length() as usize != len {
            return Err(JsError::new(
                "the STL file's bytes changed while they were read: its buffer was detached or \
                 resized (by the progress callback?)",
            ));
        }
        let n = (data_end - at).min(buffer.len());
        copy_bytes(array, at as u32, &mut buffer[..n]);
        reader.feed(&buffer[..n], progress);
        at += n;
    }
    Ok(reader.finish(len - data_end, progress)?)
}

/// A welded, consistently wound triangle mesh read from STL.
#[wasm_bindgen]
pub struct Mesh {
    pub(super) inner: Rc<ImportedMesh>,
    /// Ray-cast and closest-point index, built by the first query that needs it.
    pub(super) index: SharedIndex,
}

#[wasm_bindgen]
impl Mesh {
    /// Reads binary or ASCII STL bytes (a `Uint8Array` or an `ArrayBuffer`, at most
    /// 2^31 − 1 bytes); `onProgress(stage, fraction)` is optional.
    /// Throws an `Error` naming what is wrong with the file or the arguments.
    #[wasm_bindgen(js_name = fromStl)]
    pub fn from_stl(
        #[wasm_bindgen(unchecked_param_type = "Uint8Array | ArrayBuffer")] bytes: JsValue,
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<JsValue>,
    ) -> Result<Mesh, JsError> {
        let array = byte_array(&bytes, "the STL file")?;
        let on_progress = read_callback(on_progress, "onProgress")?;
        let mut progress = progress_fn(on_progress);
        let import = match array {
            Some(array) => read_stl_from_js(&array, &mut progress)?,
            None => read_stl_with_progress(&[], &mut progress)?,
        };
        let imported = prepare_mesh(import, &mut progress)?;
        Ok(Mesh {
            inner: Rc::new(imported),
            index: SharedIndex::default(),
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

    /// Draw buffers with every face in one group (see `DisplayBuffers`);
    /// `onProgress(stage, fraction)` is optional.
    #[wasm_bindgen(js_name = displayBuffers, unchecked_return_type = "DisplayBuffers")]
    pub fn display_buffers(
        &self,
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<JsValue>,
    ) -> Result<JsValue, JsError> {
        let mut progress = progress_fn(read_callback(on_progress, "onProgress")?);
        let groups = FaceGroups::new(self.inner.mesh.triangle_count(), 1, |_| 0);
        super::display::display_buffers(&self.inner, &groups, &mut progress)
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
        on_progress: Option<JsValue>,
    ) -> Result<Segmentation, JsError> {
        // All JavaScript input is read (through imports that catch exceptions) before any work.
        let params = super::segment::params_from_js(&params)?;
        let on_progress = read_callback(on_progress, "onProgress")?;
        Segmentation::new(self.inner.clone(), self.index.clone(), &params, on_progress)
    }

    /// The first triangle hit by the ray `origin + t·direction`, t ≥ 0, from either side:
    /// `{ face, point: [x, y, z], distance }` (distance along the unit direction), or `null`
    /// on a miss. `origin` and `direction` are three finite numbers each (an array or a
    /// Float64Array), the direction not zero; anything else throws an `Error` naming it. The
    /// index it searches is built by the first call (O(n log n)) and kept until `free()`.
    #[wasm_bindgen(unchecked_return_type = "RayHit | null")]
    pub fn raycast(
        &self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] origin: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | number[]")] direction: JsValue,
    ) -> Result<JsValue, JsError> {
        let (origin, direction) = read_ray(&origin, &direction)?;
        let index = index_of(&self.index, &self.inner);
        match index.cast_ray(&origin, &direction, Real::INFINITY) {
            Some(hit) => hit_to_js(&hit, None),
            None => Ok(JsValue::NULL),
        }
    }

    /// Plans spray passes over `faces` (default: every triangle), predicts the coating and,
    /// given quality limits, searches the largest spacing meeting them. Throws an `Error`
    /// naming the bad parameter. `onProgress(stage, fraction)` is optional.
    #[wasm_bindgen(js_name = planSpray)]
    pub fn plan_spray(
        &self,
        #[wasm_bindgen(unchecked_param_type = "SprayPlanParams")] params: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Uint32Array | number[] | null")]
        faces: Option<JsValue>,
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<JsValue>,
    ) -> Result<SprayPlan, JsError> {
        // All JavaScript input is read (through imports that catch exceptions) before any work.
        let params = super::spray::spray_params_from_js(&params)?;
        let faces = read_index_list(faces, "faces")?;
        let on_progress = read_callback(on_progress, "onProgress")?;
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

    /// Geodesic distance from `source` (see `GeodesicSource`) over the mesh or
    /// `params.faces`, by `params.method` ("mesh", default, or "voxel" with `voxelSize`).
    /// Throws an `Error` naming a bad source or parameter. `onProgress(stage, fraction)` is
    /// optional.
    #[wasm_bindgen(js_name = geodesicDistance)]
    pub fn geodesic_distance(
        &self,
        #[wasm_bindgen(unchecked_param_type = "GeodesicSource")] source: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "GeodesicParams")] params: JsValue,
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<JsValue>,
    ) -> Result<DistanceField, JsError> {
        super::geodesic::distance_field(&self.inner, &source, &params, on_progress)
    }
}
