//! Faces grouped by a label (a patch id), for drawing a mesh one group at a time: the faces
//! in group order, each group's range, and indexed draw chunks with each group's bounding
//! box.
//!
//! No paper: a stable counting sort over the labels, then the face order cut into chunks that
//! each index vertices of their own (16-bit indices), a mesh vertex copied once per run of one
//! group in a chunk, so that a vertex's colour can be its group's. The page's viewer draws
//! each patch as one contiguous range of faces, hides a patch by skipping its range and culls
//! by the range's box. The worker used to expand every face's corners in JavaScript (36 bytes
//! a face, and as long as reading and segmenting the file took); chunks take about 6 bytes of
//! indices a face and 12 bytes a vertex copy (about half a copy a face on a closed mesh).
//! Input:  a label per face below the group count; the most faces and vertices of a chunk.
//! Output: the faces in order of their label (file order within a label), the range of each
//!         label; the chunks, and for each its vertices (`f32` xyz), its faces as indices into
//!         them, and where each run of one group starts; the box of each group's vertices; the
//!         bounding sphere of the vertices about the boxes' centre.
//! Cost:   O(F + G) time for F faces in G groups, 4 bytes a face; the chunks O(F) time twice
//!         (planned, then written), 6 bytes a mesh vertex of scratch.

use super::TriMesh;

/// Faces in order of their group.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FaceGroups {
    /// The faces, group 0's first (file order within a group).
    order: Vec<u32>,
    /// Group `g` holds `order[start[g]..start[g + 1]]`.
    start: Vec<u32>,
}

/// An empty box: `[min x, min y, min z, max x, max y, max z]` that any point widens.
pub const EMPTY_BOX: [f32; 6] = [
    f32::INFINITY,
    f32::INFINITY,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
];

impl FaceGroups {
    /// Groups `faces` faces into `groups` by `group_of(face)`, which must be below `groups`
    /// (checked: a label out of range panics, a caller's bug).
    pub fn new(faces: usize, groups: usize, group_of: impl Fn(usize) -> usize) -> FaceGroups {
        let mut start = vec![0u32; groups + 1];
        for f in 0..faces {
            start[group_of(f) + 1] += 1;
        }
        for g in 0..groups {
            start[g + 1] += start[g];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; faces];
        for f in 0..faces {
            let at = &mut fill[group_of(f)];
            order[*at as usize] = f as u32;
            *at += 1;
        }
        FaceGroups { order, start }
    }

    /// Number of groups.
    pub fn group_count(&self) -> usize {
        self.start.len() - 1
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.order.len()
    }

    /// The faces of group `g`, in file order.
    pub fn faces(&self, g: usize) -> &[u32] {
        &self.order[self.start[g] as usize..self.start[g + 1] as usize]
    }

    /// `[start, count]` of each group in the face order, flat (the viewer's ranges).
    pub fn ranges(&self) -> Vec<u32> {
        self.start
            .windows(2)
            .flat_map(|w| [w[0], w[1] - w[0]])
            .collect()
    }

    /// The group of each face position `at` in order, from `g` on (advanced past empty
    /// groups).
    fn group_at(&self, at: usize, mut g: usize) -> usize {
        // Empty groups have equal starts: skip them all.
        while self.start[g + 1] as usize <= at {
            g += 1;
        }
        g
    }

    /// Cuts the face order into draw chunks of at most `max_faces` faces and `max_vertices`
    /// vertices (at least 3, at most 2^16: the indices are 16-bit), as
    /// [`FaceGroups::write_chunk`] numbers them: each chunk has
    /// vertices of its own, one per mesh vertex and run of one group in the chunk (a vertex
    /// on a patch border is copied for each patch, so vertex colours can be the patch's).
    pub fn draw_chunks(
        &self,
        mesh: &TriMesh,
        max_faces: usize,
        max_vertices: usize,
    ) -> Vec<DrawChunk> {
        let (max_faces, max_vertices) = (max_faces.max(1), max_vertices.clamp(3, 1 << 16));
        let mut scratch = DrawScratch::new(mesh.vertex_count());
        let triangles = mesh.triangles();
        let mut chunks = Vec::new();
        let mut chunk = DrawChunk::default();
        let mut g = 0;
        scratch.next_run();
        for at in 0..self.order.len() {
            let group = self.group_at(at, g);
            if chunk.faces == max_faces || chunk.vertices + 3 > max_vertices {
                chunks.push(chunk);
                chunk = DrawChunk {
                    first_face: at,
                    first_vertex: chunk.first_vertex + chunk.vertices,
                    ..DrawChunk::default()
                };
                scratch.next_run();
            } else if group != g {
                scratch.next_run();
            }
            g = group;
            for &v in &triangles[self.order[at] as usize] {
                if scratch.take(v as usize, 0).is_none() {
                    chunk.vertices += 1;
                }
            }
            chunk.faces += 1;
        }
        if chunk.faces > 0 {
            chunks.push(chunk);
        }
        chunks
    }

    /// Writes draw chunk `chunk` (one of [`FaceGroups::draw_chunks`], in order, with one
    /// `writer` for them all) into `writer`: its vertices as `f32` xyz and its faces as
    /// indices into them (both replacing the previous chunk's), the first vertex (numbered
    /// across all chunks) and group of each run of one group (appended), and each group's box
    /// widened by its vertices.
    pub fn write_chunk(&self, mesh: &TriMesh, chunk: &DrawChunk, writer: &mut DrawWriter) {
        let DrawWriter {
            scratch,
            positions,
            indices,
            runs,
            boxes,
        } = writer;
        positions.clear();
        indices.clear();
        let (points, triangles) = (mesh.positions(), mesh.triangles());
        let mut g = self.group_at(chunk.first_face, 0);
        scratch.next_run();
        runs.extend([chunk.first_vertex as u32, g as u32]);
        let mut count = 0usize;
        for at in chunk.first_face..chunk.first_face + chunk.faces {
            let group = self.group_at(at, g);
            if group != g {
                g = group;
                scratch.next_run();
                runs.extend([(chunk.first_vertex + count) as u32, g as u32]);
            }
            for &v in &triangles[self.order[at] as usize] {
                let local = match scratch.take(v as usize, count as u16) {
                    Some(local) => local,
                    None => {
                        let b = &mut boxes[g];
                        for i in 0..3 {
                            let x = points[v as usize][i] as f32;
                            positions.push(x);
                            if x < b[i] {
                                b[i] = x;
                            }
                            if x > b[3 + i] {
                                b[3 + i] = x;
                            }
                        }
                        count += 1;
                        (count - 1) as u16
                    }
                };
                indices.push(local);
            }
        }
        debug_assert_eq!(count, chunk.vertices, "the chunk as planned");
    }
}

/// A run of faces drawn with vertices of their own (see [`FaceGroups::draw_chunks`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DrawChunk {
    /// Its first face, as a position in the face order.
    pub first_face: usize,
    /// Its number of faces.
    pub faces: usize,
    /// Its first vertex, numbered across all chunks.
    pub first_vertex: usize,
    /// Its number of vertices.
    pub vertices: usize,
}

/// What [`FaceGroups::write_chunk`] writes: the last chunk's vertices and indices, the runs
/// and group boxes so far.
#[derive(Debug, Clone)]
pub struct DrawWriter {
    scratch: DrawScratch,
    /// The chunk's vertices, `f32` xyz.
    pub positions: Vec<f32>,
    /// The chunk's faces, 3 indices into its vertices each.
    pub indices: Vec<u16>,
    /// `[first vertex, group]` of each run of one group, flat.
    pub runs: Vec<u32>,
    /// `[min xyz, max xyz]` of each group's vertices ([`EMPTY_BOX`] for none).
    pub boxes: Vec<[f32; 6]>,
}

impl DrawWriter {
    /// A writer for `groups` of the faces of `mesh`.
    pub fn new(mesh: &TriMesh, groups: &FaceGroups) -> DrawWriter {
        DrawWriter {
            scratch: DrawScratch::new(mesh.vertex_count()),
            positions: Vec::new(),
            indices: Vec::new(),
            runs: Vec::new(),
            boxes: vec![EMPTY_BOX; groups.group_count()],
        }
    }
}

/// Per mesh vertex, the run it last got a chunk vertex in and that vertex's index in its
/// chunk (6 bytes a vertex).
#[derive(Debug, Clone)]
struct DrawScratch {
    run_of: Vec<u32>,
    local: Vec<u16>,
    run: u32,
}

impl DrawScratch {
    /// Scratch for a mesh of `vertices` vertices.
    fn new(vertices: usize) -> DrawScratch {
        DrawScratch {
            run_of: vec![0; vertices],
            local: vec![0; vertices],
            run: 0,
        }
    }

    /// Starts a run: no mesh vertex has a chunk vertex in it yet.
    fn next_run(&mut self) {
        // Runs are at most one per face and chunk (each fewer than 2^30).
        self.run += 1;
    }

    /// Vertex `v`'s index in the current run's chunk if it has one, else gives it `local`.
    fn take(&mut self, v: usize, local: u16) -> Option<u16> {
        if self.run_of[v] == self.run {
            Some(self.local[v])
        } else {
            self.run_of[v] = self.run;
            self.local[v] = local;
            None
        }
    }
}

/// `[cx, cy, cz, r]`: the centre of the union of `boxes` and the largest distance from it of
/// a vertex as drawn (`f32`), as three.js's `computeBoundingSphere` finds it; zeros for a
/// mesh without vertices.
pub fn bounding_sphere(mesh: &TriMesh, boxes: &[[f32; 6]]) -> [f64; 4] {
    if mesh.vertex_count() == 0 {
        return [0.0; 4];
    }
    let mut union = EMPTY_BOX;
    for b in boxes {
        for i in 0..3 {
            union[i] = union[i].min(b[i]);
            union[3 + i] = union[3 + i].max(b[3 + i]);
        }
    }
    let c = [0, 1, 2].map(|i| (f64::from(union[i]) + f64::from(union[3 + i])) / 2.0);
    let mut r2: f64 = 0.0;
    for p in mesh.positions() {
        let d = [0, 1, 2].map(|i| f64::from(p[i] as f32) - c[i]);
        r2 = r2.max(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    [c[0], c[1], c[2], r2.sqrt()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point3;

    /// A strip of `n` triangles along x, at heights that need f32 rounding.
    fn strip(n: usize) -> TriMesh {
        let mut positions = Vec::new();
        for i in 0..=n {
            let x = i as f64 * 0.1;
            positions.push(Point3::new(x, 0.0, x * x / 3.0));
            positions.push(Point3::new(x, 1.0 / 3.0, -x / 7.0));
        }
        let triangles = (0..n as u32)
            .map(|i| {
                let (a, b) = (2 * (i / 2), 2 * (i / 2) + 1);
                if i % 2 == 0 {
                    [a, a + 2, b]
                } else {
                    [b, a + 2, b + 2]
                }
            })
            .collect();
        TriMesh::new(positions, triangles).unwrap()
    }

    /// Writes every chunk; returns (positions, indices, runs, boxes).
    fn written(
        mesh: &TriMesh,
        groups: &FaceGroups,
        chunks: &[DrawChunk],
    ) -> (Vec<f32>, Vec<u16>, Vec<u32>, Vec<[f32; 6]>) {
        let mut writer = DrawWriter::new(mesh, groups);
        let (mut positions, mut indices) = (Vec::new(), Vec::new());
        for chunk in chunks {
            groups.write_chunk(mesh, chunk, &mut writer);
            assert_eq!(writer.positions.len(), 3 * chunk.vertices);
            assert_eq!(writer.indices.len(), 3 * chunk.faces);
            positions.extend_from_slice(&writer.positions);
            indices.extend_from_slice(&writer.indices);
        }
        (positions, indices, writer.runs, writer.boxes)
    }

    #[test]
    fn faces_are_sorted_stably_by_group_and_drawn_in_chunks_with_their_boxes() {
        let mesh = strip(40);
        let label = |f: usize| [2, 0, 2, 3, 0][f % 5]; // group 1 stays empty
        let groups = FaceGroups::new(40, 4, label);
        assert_eq!(groups.group_count(), 4);
        assert_eq!(groups.face_count(), 40);
        for g in 0..4 {
            let expected: Vec<u32> = (0..40u32).filter(|&f| label(f as usize) == g).collect();
            assert_eq!(groups.faces(g), &expected[..], "group {g}");
        }
        assert_eq!(groups.ranges(), vec![0, 16, 16, 0, 16, 16, 32, 8]);
        let order: Vec<u32> = (0..4).flat_map(|g| groups.faces(g).to_vec()).collect();
        // One chunk, chunks cut by faces, and chunks cut by vertices.
        for (max_faces, max_vertices) in [(1000, 1000), (7, 1000), (1000, 10), (5, 4)] {
            let chunks = groups.draw_chunks(&mesh, max_faces, max_vertices);
            let (positions, indices, runs, boxes) = written(&mesh, &groups, &chunks);
            let what = format!("chunks of {max_faces} faces, {max_vertices} vertices");
            let (mut face, mut vertex) = (0, 0);
            for c in &chunks {
                assert_eq!((c.first_face, c.first_vertex), (face, vertex), "{what}");
                assert!(c.faces >= 1 && c.faces <= max_faces && c.vertices <= max_vertices);
                face += c.faces;
                vertex += c.vertices;
            }
            assert_eq!((face, 3 * vertex), (40, positions.len()), "{what}");
            // The group of each chunk vertex, from the runs.
            let mut group_of = vec![usize::MAX; vertex];
            for (r, run) in runs.chunks_exact(2).enumerate() {
                let end = runs.get(2 * r + 2).map_or(vertex, |&v| v as usize);
                assert!(run[0] as usize <= end);
                group_of[run[0] as usize..end].fill(run[1] as usize);
            }
            // Each face's corners, read through its chunk's indices, are the mesh's (f32),
            // in group order, and its vertices are its group's.
            let mut direct = vec![EMPTY_BOX; 4];
            for c in &chunks {
                for at in c.first_face..c.first_face + c.faces {
                    let f = order[at] as usize;
                    for (k, p) in mesh.corners(f).iter().enumerate() {
                        let v = c.first_vertex + indices[3 * at + k] as usize;
                        assert!(
                            v < c.first_vertex + c.vertices,
                            "{what}: index in the chunk"
                        );
                        assert_eq!(group_of[v], label(f), "{what}: vertex group");
                        for i in 0..3 {
                            let x = p[i] as f32;
                            assert_eq!(positions[3 * v + i], x, "{what}: corner");
                            direct[label(f)][i] = direct[label(f)][i].min(x);
                            direct[label(f)][3 + i] = direct[label(f)][3 + i].max(x);
                        }
                    }
                }
            }
            assert_eq!(boxes, direct, "{what}: boxes");
            assert_eq!(boxes[1], EMPTY_BOX);
            if max_vertices == 1000 && max_faces == 1000 {
                // One chunk: each mesh vertex once per group that uses it.
                let copies: usize = (0..4)
                    .map(|g| {
                        let mut used: Vec<u32> = groups
                            .faces(g)
                            .iter()
                            .flat_map(|&f| mesh.triangles()[f as usize])
                            .collect();
                        used.sort_unstable();
                        used.dedup();
                        used.len()
                    })
                    .sum();
                assert_eq!(vertex, copies);
            }
        }
    }

    #[test]
    fn the_sphere_holds_every_vertex_about_the_box_centre() {
        let mesh = strip(9);
        let groups = FaceGroups::new(9, 1, |_| 0);
        let chunks = groups.draw_chunks(&mesh, 1000, 1000);
        let (_, _, _, boxes) = written(&mesh, &groups, &chunks);
        let [cx, cy, cz, r] = bounding_sphere(&mesh, &boxes);
        let b = boxes[0];
        assert_eq!(
            [cx, cy, cz],
            [0, 1, 2].map(|i| (f64::from(b[i]) + f64::from(b[3 + i])) / 2.0)
        );
        let far = mesh
            .positions()
            .iter()
            .map(|p| {
                let d = [p.x as f32, p.y as f32, p.z as f32];
                ((f64::from(d[0]) - cx).powi(2)
                    + (f64::from(d[1]) - cy).powi(2)
                    + (f64::from(d[2]) - cz).powi(2))
                .sqrt()
            })
            .fold(0.0, f64::max);
        assert_eq!(r, far);
        assert!(r > 0.0);
    }
}
