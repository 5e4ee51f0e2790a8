//! The draw buffers of a mesh, grouped by patch, in indexed chunks: what the page's viewer
//! hands to WebGL.

use super::params::{read_callback, set};
use super::progress_fn;
use crate::mesh::{bounding_sphere, DrawWriter, FaceGroups, ImportedMesh};
use js_sys::{Float32Array, Object, Uint16Array, Uint32Array};
use wasm_bindgen::prelude::*;

/// Most faces of a draw chunk. WebGL copies a chunk's buffers in one call on the first frame
/// that draws it, and the page cannot go on until the GPU process has taken them, so the
/// viewer adds chunks to the scene one at a time: 2^17 faces are about 1.5 MB of indices and
/// vertices (4 million non-indexed triangles handed over at once held the page for about
/// 280 ms in headless SwiftShader).
const CHUNK_FACES: usize = 1 << 17;
/// Most vertices of a draw chunk: its indices are 16-bit.
const CHUNK_VERTICES: usize = 1 << 16;

#[wasm_bindgen(typescript_custom_section)]
const TYPES: &str = r#"
/** Draw buffers, the faces grouped by patch (the last group: faces in no kept patch, or all
 *  of them without a segmentation) and cut into chunks of at most 2^17 faces and 2^16
 *  vertices, each with vertices of its own. positions: f32 xyz per vertex; indices: 3 per
 *  face, into its chunk's vertices; chunks: [firstFace, faces, firstVertex, vertices] per
 *  chunk; runs: [firstVertex, group] where the group of the vertices changes (a vertex on a
 *  patch border is copied for each patch); ranges: [start, count] in faces per group;
 *  boxes: [min xyz, max xyz] per group (an empty group: +∞ then −∞); sphere: [cx, cy, cz, r],
 *  the centre of the boxes and the largest distance of a vertex from it. */
export interface DisplayBuffers {
  positions: Float32Array; indices: Uint16Array; chunks: Uint32Array; runs: Uint32Array;
  ranges: Uint32Array; boxes: Float32Array; sphere: [number, number, number, number];
}
"#;

/// The draw buffers of `mesh` for `groups`, reporting `("display", fraction)` to the optional
/// `onProgress` callback. Each chunk is
/// written in the engine's memory and copied out at once: the arrays are built in
/// JavaScript's memory, never whole in the engine's, whose memory only grows.
pub(super) fn display_buffers(
    mesh: &ImportedMesh,
    groups: &FaceGroups,
    on_progress: Option<JsValue>,
) -> Result<JsValue, JsError> {
    let mut progress = progress_fn(read_callback(on_progress, "onProgress")?);
    let mesh = &mesh.mesh;
    progress("display", 0.0);
    let chunks = groups.draw_chunks(mesh, CHUNK_FACES, CHUNK_VERTICES);
    let vertices = chunks.last().map_or(0, |c| c.first_vertex + c.vertices);
    let faces = groups.face_count();
    let positions = Float32Array::new_with_length((3 * vertices) as u32);
    let indices = Uint16Array::new_with_length((3 * faces) as u32);
    let mut writer = DrawWriter::new(mesh, groups);
    for c in &chunks {
        groups.write_chunk(mesh, c, &mut writer);
        let (v, f) = (3 * c.first_vertex as u32, 3 * c.first_face as u32);
        positions
            .subarray(v, v + writer.positions.len() as u32)
            .copy_from(&writer.positions);
        indices
            .subarray(f, f + writer.indices.len() as u32)
            .copy_from(&writer.indices);
        progress("display", (c.first_face + c.faces) as f64 / faces as f64);
    }
    let table: Vec<u32> = chunks
        .iter()
        .flat_map(|c| [c.first_face, c.faces, c.first_vertex, c.vertices].map(|x| x as u32))
        .collect();
    let out = Object::new();
    set(&out, "positions", &positions)?;
    set(&out, "indices", &indices)?;
    set(&out, "chunks", &Uint32Array::from(table.as_slice()))?;
    set(&out, "runs", &Uint32Array::from(writer.runs.as_slice()))?;
    set(
        &out,
        "ranges",
        &Uint32Array::from(groups.ranges().as_slice()),
    )?;
    set(
        &out,
        "boxes",
        &Float32Array::from(writer.boxes.as_flattened()),
    )?;
    let sphere: js_sys::Array = bounding_sphere(mesh, &writer.boxes)
        .iter()
        .map(|&x| JsValue::from_f64(x))
        .collect();
    set(&out, "sphere", &sphere)?;
    Ok(out.into())
}
