//! The segmentation pipeline (steps 1–3) and its result: patches with their statistics.
//!
//! Source: Wang, Zhao, Tao 2019, §2.1–2.3. Step 3 (§2.3) drops patches with
//! `A_fin < ε·A`; their faces get [`DROPPED`].
//! Deviation: a patch whose faces are all degenerate is dropped whatever its area (it has
//! no usable normal, and its STL would not read back).
//! Cost: linear in faces, plus a sort of the patches by area.

use super::planarise::flattest_order;
use super::region_growing::grow_regions_and_bends;
use super::{planarise, seed_order, GrowthThreshold, ParamError, SeedRule, SegmentParams};
use crate::math::{acos_clamped, Point3, Real, Vector3};
use crate::mesh::{write_stl, FaceAdjacency, FaceGeometry, TriMesh};

/// Patch id of faces in dropped (too small) patches.
pub const DROPPED: i32 = -1;

/// One kept patch (serialised for JavaScript in camelCase).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Patch {
    /// Id: patches are numbered by area, largest first.
    pub id: usize,
    /// Faces in the patch.
    pub triangle_count: usize,
    /// Area, squared mesh units.
    pub area: Real,
    /// Area-weighted mean normal (unit; zero if the patch has no area).
    pub normal: [Real; 3],
    /// Largest angle between a face normal and `normal`, radians (< θmax).
    pub max_deviation: Real,
    /// Area-weighted centroid.
    pub centroid: [Real; 3],
}

/// An edge on a patch border.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BorderEdge {
    /// Its two vertices.
    pub vertices: [u32; 2],
    /// The patch ids on its two sides ([`DROPPED`] for a dropped patch or no face).
    pub patches: [i32; 2],
}

/// The result of [`segment`].
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    /// Patch id per face, or [`DROPPED`].
    pub patch_of: Vec<i32>,
    /// Kept patches, `patches[i].id == i`, by decreasing area.
    pub patches: Vec<Patch>,
    /// The growing threshold used in step 1.
    pub threshold: GrowthThreshold,
    /// Regions after step 1.
    pub region_count: usize,
    /// Patches after step 2, before small ones were dropped.
    pub planar_patch_count: usize,
}

/// Segments a mesh into patches: region growing, planarisation, small-patch removal.
pub fn segment(
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    params: &SegmentParams,
) -> Result<Segmentation, ParamError> {
    segment_with_progress(adjacency, geometry, params, &mut |_, _| {})
}

/// [`segment`] reporting `(stage, fraction)` for stages `regions`, `planarise`, `patches`.
pub fn segment_with_progress(
    adjacency: &FaceAdjacency,
    geometry: &FaceGeometry,
    params: &SegmentParams,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<Segmentation, ParamError> {
    let threshold = params.validate()?;
    assert_eq!(
        adjacency.face_count(),
        geometry.face_count(),
        "adjacency and geometry must describe the same mesh"
    );
    progress("regions", 0.0);
    // The flattest-first order's key comes from the dot products the regions compare.
    let (regions, bend) = grow_regions_and_bends(
        adjacency,
        geometry,
        threshold,
        params.seed_rule == SeedRule::Flattest,
    );
    progress("planarise", 0.0);
    let order = match bend {
        Some(bend) => flattest_order(geometry, &bend),
        None => seed_order(adjacency, geometry, params.seed_rule),
    };
    // Reported again so that the seed order's time can be told from the growing's.
    progress("planarise", 0.0);
    let planar = planarise(
        adjacency,
        geometry,
        &regions,
        params.theta_max_rad,
        &order,
        progress,
    );
    drop(order);
    progress("patches", 0.0);

    // Per step-2 patch: area and weighted sums, in one pass.
    let mut area = vec![0.0; planar.count];
    let mut normal_sum = vec![Vector3::zeros(); planar.count];
    let mut centroid_sum = vec![Vector3::zeros(); planar.count];
    let mut faces = vec![0usize; planar.count];
    let mut usable = vec![false; planar.count];
    for (f, &p) in planar.patch_of.iter().enumerate() {
        let (p, a) = (p as usize, geometry.areas()[f]);
        area[p] += a;
        normal_sum[p] += geometry.normals()[f] * a;
        centroid_sum[p] += geometry.centroids()[f].coords * a;
        faces[p] += 1;
        usable[p] |= !geometry.is_degenerate(f);
    }
    // Step 3 (§2.3): keep A_fin ≥ ε·A, numbered by decreasing area (ties: creation order).
    // A patch of degenerate faces only is dropped too (our addition): it has no normal to
    // process along, and exported alone it would be a file no reader accepts.
    let total: Real = area.iter().sum();
    let mut kept: Vec<usize> = (0..planar.count)
        .filter(|&p| usable[p] && area[p] >= params.min_area_ratio * total)
        .collect();
    kept.sort_by(|&a, &b| area[b].total_cmp(&area[a]).then(a.cmp(&b)));
    let mut new_id = vec![DROPPED; planar.count];
    for (id, &p) in kept.iter().enumerate() {
        new_id[p] = id as i32;
    }
    let mut patches: Vec<Patch> = kept
        .iter()
        .enumerate()
        .map(|(id, &p)| {
            let normal = normal_sum[p]
                .try_normalize(0.0)
                .unwrap_or_else(Vector3::zeros);
            let centroid = if area[p] > 0.0 {
                centroid_sum[p] / area[p]
            } else {
                Vector3::zeros()
            };
            Patch {
                id,
                triangle_count: faces[p],
                area: area[p],
                normal: normal.into(),
                max_deviation: 0.0,
                centroid: centroid.into(),
            }
        })
        .collect();
    // Largest deviation via the smallest cosine per patch, then one acos per patch; in the
    // same pass, the final ids.
    let mut min_cos = vec![1.0f64; patches.len()];
    let mean: Vec<Vector3> = patches.iter().map(|p| Vector3::from(p.normal)).collect();
    let mut patch_of = Vec::with_capacity(planar.patch_of.len());
    for (f, &p) in planar.patch_of.iter().enumerate() {
        let id = new_id[p as usize];
        patch_of.push(id);
        if id != DROPPED && !geometry.is_degenerate(f) {
            let c = &mut min_cos[id as usize];
            let dot = geometry.normals()[f].dot(&mean[id as usize]);
            // A comparison, not `f64::min` (a call on WebAssembly): the cosines are finite,
            // and for a ±0 pair either choice gives the same acos.
            if dot < *c {
                *c = dot;
            }
        }
    }
    for (patch, c) in patches.iter_mut().zip(min_cos) {
        patch.max_deviation = acos_clamped(c);
    }
    progress("patches", 1.0);
    Ok(Segmentation {
        patch_of,
        patches,
        threshold,
        region_count: regions.count,
        planar_patch_count: planar.count,
    })
}

impl Segmentation {
    /// Faces of patch `id`, in index order.
    pub fn faces_of(&self, id: usize) -> impl Iterator<Item = usize> + '_ {
        self.patch_of
            .iter()
            .enumerate()
            .filter(move |&(_, &p)| p == id as i32)
            .map(|(f, _)| f)
    }

    /// Faces in dropped patches.
    pub fn dropped_count(&self) -> usize {
        self.patch_of.iter().filter(|&&p| p == DROPPED).count()
    }

    /// Binary STL of patch `id` (its faces in the mesh's consistent winding), or `None` if
    /// there is no such patch.
    pub fn patch_stl(&self, mesh: &TriMesh, id: usize) -> Option<Vec<u8>> {
        let patch = self.patches.get(id)?;
        let faces: Vec<usize> = self.faces_of(id).collect();
        debug_assert_eq!(faces.len(), patch.triangle_count);
        Some(write_stl(faces.into_iter().map(|f| mesh.corners(f))))
    }

    /// Edges where the patch changes (or a kept patch meets an open or non-manifold edge),
    /// each once: its two vertices and the patch ids on either side ([`DROPPED`] for a
    /// dropped patch or no face at all).
    pub fn border_edges(&self, mesh: &TriMesh, adjacency: &FaceAdjacency) -> Vec<BorderEdge> {
        let mut edges = Vec::new();
        for (f, t) in mesh.triangles().iter().enumerate() {
            let p = self.patch_of[f];
            for (k, g) in adjacency.neighbours(f).into_iter().enumerate() {
                let other = if g == crate::mesh::NO_FACE {
                    if p == DROPPED {
                        continue;
                    }
                    DROPPED
                } else if (g as usize) > f && self.patch_of[g as usize] != p {
                    self.patch_of[g as usize]
                } else {
                    continue;
                };
                edges.push(BorderEdge {
                    vertices: [t[k], t[(k + 1) % 3]],
                    patches: [p, other],
                });
            }
        }
        edges
    }

    /// [`Segmentation::border_edges`] as flat line-segment endpoints
    /// `[x0, y0, z0, x1, y1, z1, …]` in `f32`, ready for a line renderer.
    pub fn border_segments(&self, mesh: &TriMesh, adjacency: &FaceAdjacency) -> Vec<f32> {
        let point = |v: u32| -> Point3 { mesh.positions()[v as usize] };
        self.border_edges(mesh, adjacency)
            .into_iter()
            .flat_map(|e| {
                let (a, b) = (point(e.vertices[0]), point(e.vertices[1]));
                [a.x, a.y, a.z, b.x, b.y, b.z].map(|c| c as f32)
            })
            .collect()
    }

    /// The patch ids on either side of each of [`Segmentation::border_segments`], flat
    /// `[p0, q0, p1, q1, …]`.
    pub fn border_patches(&self, mesh: &TriMesh, adjacency: &FaceAdjacency) -> Vec<i32> {
        self.border_edges(mesh, adjacency)
            .into_iter()
            .flat_map(|e| e.patches)
            .collect()
    }
}
