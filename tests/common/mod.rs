//! Shared test helpers: fixture loading, generated meshes with known answers, and the
//! invariants every segmentation must satisfy.
#![allow(dead_code)]

use skinpath::math::{angle_between, Vector3};
use skinpath::mesh::{import_stl, ImportedMesh};
use skinpath::segment::{Segmentation, DROPPED};
use std::f64::consts::PI;

/// Bytes of a fixture in `tests/fixtures/`, embedded so the test also runs as WebAssembly.
#[macro_export]
macro_rules! fixture {
    ($name:literal) => {
        include_bytes!(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/",
            $name
        ))
        .as_slice()
    };
}

/// Every fixture in `tests/fixtures/` (its file name and bytes), for tests that run them all.
pub fn fixtures() -> [(&'static str, &'static [u8]); 25] {
    [
        ("all_nan.stl", fixture!("all_nan.stl")),
        ("ascii_truncated.stl", fixture!("ascii_truncated.stl")),
        ("bad_number.stl", fixture!("bad_number.stl")),
        (
            "binary_header_starts_with_solid.stl",
            fixture!("binary_header_starts_with_solid.stl"),
        ),
        ("count_too_large.stl", fixture!("count_too_large.stl")),
        ("cube_ascii.stl", fixture!("cube_ascii.stl")),
        ("cube_binary.stl", fixture!("cube_binary.stl")),
        (
            "cube_crlf_uppercase.stl",
            fixture!("cube_crlf_uppercase.stl"),
        ),
        (
            "degenerate_triangle.stl",
            fixture!("degenerate_triangle.stl"),
        ),
        ("empty.stl", fixture!("empty.stl")),
        ("flipped_faces.stl", fixture!("flipped_faces.stl")),
        ("four_vertices.stl", fixture!("four_vertices.stl")),
        ("inf_vertex_ascii.stl", fixture!("inf_vertex_ascii.stl")),
        ("inside_out_cube.stl", fixture!("inside_out_cube.stl")),
        ("nan_vertex.stl", fixture!("nan_vertex.stl")),
        ("no_endsolid.stl", fixture!("no_endsolid.stl")),
        ("no_triangles.stl", fixture!("no_triangles.stl")),
        ("nonmanifold_edge.stl", fixture!("nonmanifold_edge.stl")),
        ("not_stl.txt", fixture!("not_stl.txt")),
        ("open_strip.stl", fixture!("open_strip.stl")),
        ("png_header.stl", fixture!("png_header.stl")),
        ("single_triangle.stl", fixture!("single_triangle.stl")),
        ("trailing_bytes.stl", fixture!("trailing_bytes.stl")),
        ("truncated.stl", fixture!("truncated.stl")),
        ("two_components.stl", fixture!("two_components.stl")),
    ]
}

/// `assert!((a - b).abs() <= tol)` with the values in the message.
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            (a - b).abs() <= tol,
            "{a} and {b} differ by more than {tol}"
        );
    }};
}

/// Bytes of a real mesh from the shared model folder beside the repository (native only:
/// WebAssembly tests have no file system).
#[cfg(not(target_arch = "wasm32"))]
pub fn model(name: &str) -> Vec<u8> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/models")
        .join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A triangle as three corners.
pub type Tri = [[f32; 3]; 3];

/// A plate of `m × m` squares of side `h` in z = 0, each of its triangles written three
/// times, the second the other way round (a careless export): every edge has three faces
/// or more.
pub fn plate_written_thrice(m: usize, h: f32) -> Vec<Tri> {
    let corner = |i: usize, j: usize| [h * i as f32, h * j as f32, 0.0];
    let mut out = Vec::with_capacity(6 * m * m);
    for j in 0..m {
        for i in 0..m {
            let [a, b, c, d] = [
                corner(i, j),
                corner(i + 1, j),
                corner(i + 1, j + 1),
                corner(i, j + 1),
            ];
            for [p, q, r] in [[a, b, c], [a, c, d]] {
                out.extend([[p, q, r], [p, r, q], [p, q, r]]);
            }
        }
    }
    out
}

/// Binary STL of the given triangles.
pub fn binary_stl(triangles: &[Tri]) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        out.extend_from_slice(&[0u8; 12]);
        for c in t.iter().flatten() {
            out.extend_from_slice(&c.to_le_bytes());
        }
        out.extend_from_slice(&[0, 0]);
    }
    out
}

/// Imports STL bytes, panicking with the error message on failure.
pub fn import(bytes: &[u8]) -> ImportedMesh {
    import_stl(bytes, &mut |_, _| {}).unwrap_or_else(|e| panic!("import failed: {e}"))
}

/// Two triangles per grid cell of a parametric surface `f(u, v)`, u, v ∈ [0, 1];
/// `wrap_u` closes the surface in u (cylinders).
pub fn grid(nu: usize, nv: usize, wrap_u: bool, f: impl Fn(f64, f64) -> [f64; 3]) -> Vec<Tri> {
    let point = |i: usize, j: usize| -> [f32; 3] {
        let i = if wrap_u { i % nu } else { i };
        f(i as f64 / nu as f64, j as f64 / nv as f64).map(|c| c as f32)
    };
    let mut out = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            out.push([a, b, c]);
            out.push([a, c, d]);
        }
    }
    out
}

/// Open tube of radius `r` and length `h` along z, `n` facets around, `m` rings, outward.
pub fn cylinder(r: f64, h: f64, n: usize, m: usize) -> Vec<Tri> {
    grid(n, m, true, |u, v| {
        let a = 2.0 * PI * u;
        [r * a.cos(), r * a.sin(), h * v]
    })
}

/// Plane `z = 0` of size `w × d` split into `n × n` cells.
pub fn plane(w: f64, d: f64, n: usize) -> Vec<Tri> {
    grid(n, n, false, |u, v| [w * u, d * v, 0.0])
}

/// Unit cube with each face split into `n × n` cells, outward.
pub fn refined_cube(n: usize) -> Vec<Tri> {
    let mut out = Vec::new();
    // Each face: origin and two edge vectors whose cross product points outwards.
    let faces: [([f64; 3], [f64; 3], [f64; 3]); 6] = [
        ([0., 0., 0.], [0., 1., 0.], [1., 0., 0.]),
        ([0., 0., 1.], [1., 0., 0.], [0., 1., 0.]),
        ([0., 0., 0.], [1., 0., 0.], [0., 0., 1.]),
        ([0., 1., 0.], [0., 0., 1.], [1., 0., 0.]),
        ([0., 0., 0.], [0., 0., 1.], [0., 1., 0.]),
        ([1., 0., 0.], [0., 1., 0.], [0., 0., 1.]),
    ];
    for (o, e1, e2) in faces {
        out.extend(grid(n, n, false, |u, v| {
            std::array::from_fn(|k| o[k] + u * e1[k] + v * e2[k])
        }));
    }
    out
}

/// UV sphere of radius `r` (poles as fans), outward.
pub fn sphere(r: f64, n: usize, m: usize) -> Vec<Tri> {
    grid(n, m, true, |u, v| {
        let (a, b) = (2.0 * PI * u, PI * v);
        // Exact zeros at the poles, so the pole vertices weld.
        let s = if v == 0.0 || v == 1.0 { 0.0 } else { b.sin() };
        [r * s * a.cos(), r * s * a.sin(), -r * b.cos()]
    })
    .into_iter()
    .filter(|t| {
        // Cells at the poles have two coincident corners; keep only proper triangles.
        t[0] != t[1] && t[1] != t[2] && t[2] != t[0]
    })
    .collect()
}

/// Checks what every segmentation promises and returns the patch count:
/// ids in range and sorted by area, a partition, edge-connected patches, normals strictly
/// within `theta_max` of the patch normal, area ratio respected.
pub fn check_invariants(
    m: &ImportedMesh,
    seg: &Segmentation,
    theta_max: f64,
    min_ratio: f64,
) -> usize {
    let n = m.mesh.triangle_count();
    assert_eq!(seg.patch_of.len(), n, "one patch id per face");
    let count = seg.patches.len();
    let total = m.geometry.total_area();
    let mut faces = vec![0usize; count];
    for &p in &seg.patch_of {
        assert!(
            p == DROPPED || (0..count as i32).contains(&p),
            "patch id {p} out of range"
        );
        if p >= 0 {
            faces[p as usize] += 1;
        }
    }
    for (i, patch) in seg.patches.iter().enumerate() {
        assert_eq!(patch.id, i);
        assert_eq!(patch.triangle_count, faces[i], "patch {i} face count");
        assert!(faces[i] > 0, "patch {i} is empty");
        assert!(
            patch.area >= min_ratio * total * (1.0 - 1e-12),
            "patch {i} is below the area ratio"
        );
        if i > 0 {
            assert!(
                seg.patches[i - 1].area >= patch.area,
                "patches not sorted by area"
            );
        }
        let normal = Vector3::from(patch.normal);
        assert!(
            patch.max_deviation < theta_max,
            "patch {i} deviates {}",
            patch.max_deviation
        );
        for f in seg.faces_of(i) {
            if !m.geometry.is_degenerate(f) {
                let dev = angle_between(&m.geometry.normals()[f], &normal);
                assert!(
                    dev < theta_max + 1e-12,
                    "face {f} is {dev} rad from patch {i}'s normal"
                );
            }
        }
    }
    // Connectivity: a flood fill from each patch's first face reaches all its faces.
    let mut seen = vec![false; n];
    for (i, &expected) in faces.iter().enumerate() {
        let start = seg.faces_of(i).next().unwrap();
        let mut stack = vec![start];
        seen[start] = true;
        let mut reached = 0;
        while let Some(f) = stack.pop() {
            reached += 1;
            for g in m.adjacency.neighbours_of(f) {
                if !seen[g] && seg.patch_of[g] == i as i32 {
                    seen[g] = true;
                    stack.push(g);
                }
            }
        }
        assert_eq!(reached, expected, "patch {i} is not edge-connected");
    }
    count
}

/// Adjacency is symmetric and matches the winding: neighbours traverse a shared edge in
/// opposite directions unless the mesh reported inconsistent edges.
pub fn check_adjacency(m: &ImportedMesh) {
    let t = m.mesh.triangles();
    for f in 0..m.mesh.triangle_count() {
        for (k, g) in m.adjacency.neighbours(f).into_iter().enumerate() {
            if g == skinpath::mesh::NO_FACE {
                continue;
            }
            let g = g as usize;
            assert!(
                m.adjacency.neighbours(g).contains(&(f as u32)),
                "adjacency not symmetric at {f}-{g}"
            );
            let (a, b) = (t[f][k], t[f][(k + 1) % 3]);
            assert!(
                t[g].contains(&a) && t[g].contains(&b),
                "neighbours {f}, {g} share no edge"
            );
            if m.report.inconsistent_edges == 0 {
                let same = (0..3).any(|j| t[g][j] == a && t[g][(j + 1) % 3] == b);
                assert!(
                    !same,
                    "faces {f} and {g} wind their shared edge the same way"
                );
            }
        }
    }
}
