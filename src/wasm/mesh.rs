//! `Mesh`: an imported STL held on the Rust side (JavaScript must call `free()`).

use super::index::{hit_to_js, index_of, read_ray, SharedIndex};
use super::params::{byte_array, copy_bytes, integer, read_callback, read_index_list};
use super::{progress_fn, DistanceField, Segmentation, SprayPlan};
use crate::geodesic::SurfaceCache;
use crate::math::Real;
use crate::mesh::{
    prepare_mesh, read_stl_with_progress, FaceGroups, ImportedMesh, StlImport, StlStream,
    STL_RECORD_BYTES,
};
use crate::spray::SampleCache;
use js_sys::Uint8Array;
use std::rc::Rc;
use wasm_bindgen::prelude::*;

/// Bytes copied from JavaScript at a time (800 KiB: the copies stay in cache).
const STREAM_BYTES: usize = 16_384 * STL_RECORD_BYTES;

/// Feeds the bytes of `array` to `stream`, copied through a small buffer: a binary file's
/// records are parsed as they come and never held whole in the engine's memory, which only
/// grows (a copy of the file raised every later peak by its size, and copying it meant writing
/// it twice: zeroed, then filled). Any other file (ASCII, or one only the whole of it tells
/// apart) is gathered whole by the stream.
fn push_from_js(
    stream: &mut StlStream,
    array: &Uint8Array,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<(), JsError> {
    let len = array.length() as usize;
    let mut buffer = vec![0; STREAM_BYTES.min(len)];
    let mut at = 0;
    // Each pass reads at least one byte, so the loop ends.
    while at < len {
        // The progress callback runs between the copies and could detach or shrink the
        // buffer (its view then reports fewer bytes): refused, never read past.
        if array.length() as usize != len {
            return Err(JsError::new(
                "the STL file's bytes changed while they were read: its buffer was detached or \
                 resized (by the progress callback?)",
            ));
        }
        let n = (len - at).min(buffer.len());
        copy_bytes(array, at as u32, &mut buffer[..n]);
        stream.push(&buffer[..n], progress)?;
        at += n;
    }
    Ok(())
}

/// Reads STL bytes held by JavaScript (see [`push_from_js`]).
fn read_stl_from_js(
    array: &Uint8Array,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<StlImport, JsError> {
    let mut stream = StlStream::new(array.length() as usize);
    push_from_js(&mut stream, array, progress)?;
    Ok(stream.finish(progress)?)
}

/// An STL file read piece by piece as it comes (a `File`'s stream in a worker), so that it
/// is never held whole: `new StlReader(file.size, onProgress)`, `push(bytes)` for each piece
/// in order, then `finish()` gives the `Mesh` (the reader is then used up). A binary file is
/// parsed as it comes; any other is gathered and read at the end. The result is
/// `Mesh.fromStl`'s for the same bytes.
#[wasm_bindgen]
pub struct StlReader {
    /// `None` once finished or failed.
    stream: Option<StlStream>,
    progress: Option<js_sys::Function>,
}

#[wasm_bindgen]
impl StlReader {
    /// A reader of a file of `byteLength` bytes (a whole number up to 2^31 − 1);
    /// `onProgress(stage, fraction)` is optional.
    #[wasm_bindgen(constructor)]
    pub fn new(
        #[wasm_bindgen(js_name = byteLength, unchecked_param_type = "number")] byte_length: JsValue,
        #[wasm_bindgen(js_name = onProgress, unchecked_optional_param_type = "ProgressCallback")]
        on_progress: Option<JsValue>,
    ) -> Result<StlReader, JsError> {
        let len = integer(&byte_length, "byteLength", 0, i64::from(i32::MAX))?;
        Ok(StlReader {
            stream: Some(StlStream::new(len as usize)),
            progress: read_callback(on_progress, "onProgress")?,
        })
    }

    /// Bytes pushed so far.
    #[wasm_bindgen(getter)]
    pub fn received(&self) -> f64 {
        self.stream.as_ref().map_or(0.0, |s| s.received() as f64)
    }

    /// Reads the next piece of the file (a `Uint8Array` or an `ArrayBuffer`). Throws an
    /// `Error` when the pieces hold more bytes than the file's length (it changed while being
    /// read); after an error the reader is used up.
    pub fn push(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Uint8Array | ArrayBuffer")] bytes: JsValue,
    ) -> Result<(), JsError> {
        let array = byte_array(&bytes, "the piece of the file")?;
        let mut stream = self.stream.take().ok_or_else(used_up)?;
        let mut progress = progress_fn(self.progress.clone());
        if let Some(array) = array {
            push_from_js(&mut stream, &array, &mut progress)?;
        }
        self.stream = Some(stream);
        Ok(())
    }

    /// The mesh read from every byte pushed, prepared as `Mesh.fromStl` prepares it. Throws
    /// an `Error` naming what is wrong with the file, or when fewer bytes came than its
    /// length; the reader is used up either way.
    pub fn finish(&mut self) -> Result<Mesh, JsError> {
        let stream = self.stream.take().ok_or_else(used_up)?;
        let mut progress = progress_fn(self.progress.take());
        let import = stream.finish(&mut progress)?;
        let imported = prepare_mesh(import, &mut progress)?;
        Ok(Mesh {
            inner: Rc::new(imported),
            index: SharedIndex::default(),
            surfaces: SurfaceCache::new(),
            spray_samples: SampleCache::new(),
        })
    }
}

fn used_up() -> JsError {
    JsError::new(
        "this StlReader is used up (finish() was called, or a push failed); create a new one",
    )
}

/// A welded, consistently wound triangle mesh read from STL.
#[wasm_bindgen]
pub struct Mesh {
    pub(super) inner: Rc<ImportedMesh>,
    /// Ray-cast and closest-point index, built by the first query that needs it.
    pub(super) index: SharedIndex,
    /// What the last geodesic distance derived from the mesh for its faces, for the next.
    pub(super) surfaces: SurfaceCache,
    /// The evaluation samples of the last spray plan, for the next on the same faces.
    pub(super) spray_samples: SampleCache,
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
            surfaces: SurfaceCache::new(),
            spray_samples: SampleCache::new(),
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
        let groups = FaceGroups::new(self.inner.mesh.triangle_count(), 1, |_| 0);
        super::display::display_buffers(&self.inner, &groups, on_progress)
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
        let plan = crate::spray::plan_spray_cached(
            &m.mesh,
            &m.adjacency,
            &m.geometry,
            &faces,
            &params,
            Some(&self.spray_samples),
            &mut progress_fn(on_progress),
        )?;
        Ok(SprayPlan::new(plan))
    }

    /// Geodesic distance from `source` (see `GeodesicSource`) over the mesh or
    /// `params.faces`, by `params.method` (see `GeodesicParams`: "accurate" by default,
    /// "exact", "fast", or "voxel" with `voxelSize`).
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
        super::geodesic::distance_field(&self.inner, &self.surfaces, &source, &params, on_progress)
    }

    /// Derives from the mesh what a geodesic distance with `params` (its `faces`, see
    /// `GeodesicParams`) needs before it starts (the faces around each vertex, the face
    /// normals), and keeps it for the distances on those faces: the Paths tool asks when it is
    /// opened, so that its first distance starts at once. Throws an `Error` naming a bad
    /// parameter.
    #[wasm_bindgen(js_name = prepareGeodesic)]
    pub fn prepare_geodesic(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "GeodesicParams")] params: JsValue,
    ) -> Result<(), JsError> {
        super::geodesic::prepare(&self.inner, &self.surfaces, &params)
    }
}
