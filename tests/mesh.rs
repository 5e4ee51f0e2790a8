//! STL import, welding, adjacency, winding and the mesh report, through the public API.

mod common;

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use common::{binary_stl, check_adjacency, import, Tri};
use skinpath::mesh::{
    binary_layout, import_stl, read_stl, write_stl, BinaryStl, FaceGeometry, StlError, StlFormat,
    StlStream, STL_HEAD_BYTES, STL_PREAMBLE_BYTES, STL_RECORD_BYTES,
};

fn error(bytes: &[u8]) -> String {
    match import_stl(bytes, &mut |_, _| {}) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn cube_in_both_encodings_has_8_vertices_12_faces_and_no_defects() {
    for (bytes, format) in [
        (fixture!("cube_ascii.stl"), StlFormat::Ascii),
        (fixture!("cube_binary.stl"), StlFormat::Binary),
        (fixture!("cube_crlf_uppercase.stl"), StlFormat::Ascii),
        (
            fixture!("binary_header_starts_with_solid.stl"),
            StlFormat::Binary,
        ),
        (fixture!("no_endsolid.stl"), StlFormat::Ascii),
    ] {
        let m = import(bytes);
        let r = &m.report;
        assert_eq!(r.format, format);
        assert_eq!((r.triangles, r.vertices), (12, 8));
        assert_near!(r.area, 6.0, 1e-12);
        assert_eq!((r.boundary_edges, r.non_manifold_edges), (0, 0));
        assert_eq!(
            (r.components, r.degenerate_triangles, r.flipped_triangles),
            (1, 0, 0)
        );
        assert_eq!((r.bbox_min, r.bbox_max), ([0.0; 3], [1.0; 3]));
        check_adjacency(&m);
    }
}

#[test]
fn trailing_bytes_after_a_binary_file_are_reported() {
    let m = import(fixture!("trailing_bytes.stl"));
    assert_eq!(m.report.triangles, 12);
    assert_eq!(
        m.report.trailing_bytes,
        "exported by a tool that pads files\n".len()
    );
}

#[test]
fn open_strip_and_single_triangle_count_boundary_edges() {
    let strip = import(fixture!("open_strip.stl"));
    assert_eq!((strip.report.vertices, strip.report.boundary_edges), (8, 8));
    let one = import(fixture!("single_triangle.stl"));
    assert_eq!((one.report.triangles, one.report.boundary_edges), (1, 3));
}

#[test]
fn non_manifold_edge_links_nobody_and_is_counted_once() {
    let m = import(fixture!("nonmanifold_edge.stl"));
    assert_eq!(m.report.non_manifold_edges, 1);
    assert_eq!(m.report.components, 1);
    for f in 0..3 {
        assert_eq!(m.adjacency.neighbours_of(f).count(), 0);
    }
}

#[test]
fn two_cubes_are_two_components() {
    let m = import(fixture!("two_components.stl"));
    assert_eq!((m.report.components, m.report.vertices), (2, 16));
    check_adjacency(&m);
}

#[test]
fn flipped_and_inside_out_faces_are_rewound_outwards() {
    let reference = import(fixture!("cube_binary.stl"));
    for (bytes, flipped) in [
        (fixture!("flipped_faces.stl"), 3),
        (fixture!("inside_out_cube.stl"), 12),
    ] {
        let m = import(bytes);
        assert_eq!(m.report.flipped_triangles, flipped);
        check_adjacency(&m);
        for f in 0..12 {
            let dot = m.geometry.normals()[f].dot(&reference.geometry.normals()[f]);
            assert_near!(dot, 1.0, 1e-12);
        }
    }
}

#[test]
fn non_finite_triangles_are_skipped_and_counted() {
    let m = import(fixture!("nan_vertex.stl"));
    assert_eq!((m.report.triangles, m.report.skipped_triangles), (11, 1));
    let m = import(fixture!("inf_vertex_ascii.stl"));
    assert_eq!((m.report.triangles, m.report.skipped_triangles), (1, 1));
    assert_eq!(
        error(fixture!("all_nan.stl")),
        "no usable triangles: all 1 triangles have NaN or infinite coordinates"
    );
}

#[test]
fn degenerate_triangles_are_kept_counted_and_linked_to_nobody_if_collapsed() {
    let m = import(fixture!("degenerate_triangle.stl"));
    assert_eq!((m.report.triangles, m.report.degenerate_triangles), (3, 2));
    assert_eq!(
        m.adjacency.neighbours_of(1).count(),
        0,
        "a face with a repeated vertex"
    );
}

#[test]
fn malformed_files_get_messages_that_name_the_problem() {
    let cases: [(&[u8], &str); 9] = [
        (fixture!("empty.stl"), "the file is empty"),
        (
            fixture!("not_stl.txt"),
            "not an STL file: it does not start with 'solid' and is too short (33 bytes)",
        ),
        (
            fixture!("png_header.stl"),
            "not an STL file: it does not start with 'solid', and read as binary STL its header would claim",
        ),
        (
            fixture!("truncated.stl"),
            "truncated binary STL: the header says 12 triangles but only 7 are present",
        ),
        (
            fixture!("count_too_large.stl"),
            "corrupt binary STL: the header says 4000000000 triangles, more than the file can hold (12 whole triangles in 684 bytes)",
        ),
        (
            fixture!("bad_number.stl"),
            "malformed number '1.0.0' at line 5 of the ASCII STL",
        ),
        (
            fixture!("four_vertices.stl"),
            "the facet starting at line 2 has 4 vertices",
        ),
        (
            fixture!("no_triangles.stl"),
            "the STL file contains no triangles",
        ),
        (
            fixture!("ascii_truncated.stl"),
            "the ASCII STL ends inside a facet",
        ),
    ];
    for (bytes, expected) in cases {
        let message = error(bytes);
        assert!(
            message.contains(expected),
            "got {message:?}, expected {expected:?}"
        );
    }
}

#[test]
fn a_huge_declared_count_is_refused_before_anything_is_allocated() {
    // 84 bytes claiming u32::MAX triangles: reading must fail on the size check alone.
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&u32::MAX.to_le_bytes());
    assert!(matches!(read_stl(&bytes), Err(StlError::NotStl { .. })));
}

#[test]
fn written_stl_reads_back_identically() {
    let m = import(fixture!("cube_ascii.stl"));
    let bytes = write_stl((0..12).map(|f| m.mesh.corners(f)));
    assert_eq!(bytes.len(), 84 + 12 * 50);
    let back = import(&bytes);
    assert_eq!(back.mesh, m.mesh);
}

#[test]
fn generated_sphere_is_closed_and_outward() {
    let m = import(&binary_stl(&common::sphere(2.0, 32, 16)));
    assert_eq!(
        (m.report.boundary_edges, m.report.non_manifold_edges),
        (0, 0)
    );
    assert_eq!((m.report.components, m.report.flipped_triangles), (1, 0));
    // Euler characteristic of a sphere: V − E + F = 2, with E = 3F/2.
    let (v, f) = (m.report.vertices as i64, m.report.triangles as i64);
    assert_eq!(v - 3 * f / 2 + f, 2);
    check_adjacency(&m);
}

/// Real meshes from the shared model folder (native only: WebAssembly has no file system).
#[cfg(not(target_arch = "wasm32"))]
mod real_models {
    use super::*;

    #[test]
    fn vertex_counts_match_stl_io_and_the_model_notes() {
        // (file, triangles, unique vertices as listed in the models' SOURCES.md)
        for (name, triangles, vertices) in [
            ("airplane_10796_pymeshlab.stl", 10_796, 5_400),
            ("wingbody_79868_flow360.stl", 79_868, 39_936),
            ("b747_14062_flightgear.stl", 14_062, 7_647),
            ("bwb_4464_pygeo_ascii.stl", 4_464, 2_234),
        ] {
            let bytes = common::model(name);
            let m = import(&bytes);
            assert_eq!(
                (m.report.triangles, m.report.vertices),
                (triangles, vertices),
                "{name}"
            );
            let reference = stl_io::read_stl(&mut std::io::Cursor::new(&bytes)).unwrap();
            assert_eq!(reference.faces.len(), triangles, "{name} per stl_io");
            check_adjacency(&m);
        }
    }

    #[test]
    fn defects_of_the_messy_airliner_are_reported() {
        let m = import(&common::model("b747_14062_flightgear.stl"));
        let r = &m.report;
        assert_eq!((r.boundary_edges, r.non_manifold_edges), (1_141, 113));
        assert!(r.flipped_triangles > 0 && r.components > 1);
        for name in [
            "airplane_10796_pymeshlab.stl",
            "wingbody_79868_flow360.stl",
            "bwb_4464_pygeo_ascii.stl",
        ] {
            let m = import(&common::model(name));
            assert_eq!(
                (m.report.boundary_edges, m.report.non_manifold_edges),
                (0, 0),
                "{name}"
            );
            assert_eq!(
                (m.report.components, m.report.flipped_triangles),
                (1, 0),
                "{name} is clean"
            );
        }
        let orion = import(&common::model("orion_51736_nasa.stl"));
        assert_eq!(
            (orion.report.components, orion.report.boundary_edges),
            (3, 0)
        );
    }
}

/// A small deterministic generator (xorshift64*), so the robustness test needs no crate.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

#[test]
fn mangled_files_never_panic_and_never_yield_an_invalid_mesh() {
    let mut rng = Rng(0x5eed_1234_abcd_ef01);
    let sources: [&[u8]; 4] = [
        fixture!("cube_binary.stl"),
        fixture!("cube_ascii.stl"),
        fixture!("nonmanifold_edge.stl"),
        fixture!("degenerate_triangle.stl"),
    ];
    let mut accepted = 0;
    for round in 0..600 {
        let source = sources[round % sources.len()];
        let mut bytes = source.to_vec();
        match rng.below(4) {
            // Cut anywhere.
            0 => bytes.truncate(rng.below(bytes.len() + 1)),
            // Flip a few bytes (counts, coordinates, keywords, digits).
            1 => {
                for _ in 0..1 + rng.below(4) {
                    let i = rng.below(bytes.len());
                    bytes[i] = rng.next() as u8;
                }
            }
            // Plant NaN, infinity or huge values in binary coordinates.
            2 if bytes.len() > 84 => {
                let i = 84 + 12 + 4 * rng.below((bytes.len() - 96) / 4);
                let value = [f32::NAN, f32::INFINITY, -f32::MAX, 1e-45][rng.below(4)];
                bytes[i..i + 4].copy_from_slice(&value.to_le_bytes());
            }
            // Pure noise of any length.
            _ => bytes = (0..rng.below(400)).map(|_| rng.next() as u8).collect(),
        }
        if let Ok(m) = import_stl(&bytes, &mut |_, _| {}) {
            accepted += 1;
            m.mesh.validate().expect("an accepted mesh is valid");
            check_adjacency(&m);
            let params = skinpath::segment::SegmentParams::default();
            let seg = skinpath::segment::segment(&m.adjacency, &m.geometry, &params).unwrap();
            common::check_invariants(&m, &seg, params.theta_max_rad, params.min_area_ratio);
        }
    }
    assert!(
        accepted > 50,
        "the mutations should leave many files readable ({accepted})"
    );
}

/// The ASCII cube with its text rewritten by `edit`.
fn cube_text(edit: impl Fn(&str) -> Vec<u8>) -> Vec<u8> {
    edit(std::str::from_utf8(fixture!("cube_ascii.stl")).expect("the fixture is text"))
}

#[test]
fn ascii_files_as_real_exporters_write_them_are_read() {
    let reference = import(fixture!("cube_ascii.stl"));
    let renamed = |name: &[u8]| {
        cube_text(|s| {
            let mut out = name.to_vec();
            out.extend_from_slice(s.strip_prefix("solid cube").unwrap().as_bytes());
            out
        })
    };
    let cases: [(&str, Vec<u8>); 8] = [
        ("UTF-8 name", renamed("solid café".as_bytes())),
        ("Latin-1 name", renamed(b"solid caf\xe9")),
        ("byte-order mark", {
            let mut b = b"\xEF\xBB\xBF".to_vec();
            b.extend_from_slice(fixture!("cube_ascii.stl"));
            b
        }),
        (
            "non-breaking spaces",
            renamed("solid\u{a0}wing\u{a0}skin".as_bytes()),
        ),
        ("CR line ends", cube_text(|s| s.replace('\n', "\r").into())),
        ("one line", cube_text(|s| s.replace('\n', " ").into())),
        (
            "one line, name and no spaces to spare",
            cube_text(|s| s.split_whitespace().collect::<Vec<_>>().join(" ").into()),
        ),
        (
            "tabs and CRLF",
            cube_text(|s| s.replace("  ", "\t").replace('\n', "\r\n").into()),
        ),
    ];
    for (what, bytes) in cases {
        let m = import_stl(&bytes, &mut |_, _| {}).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(m.report.format, StlFormat::Ascii, "{what}");
        assert_eq!(m.mesh, reference.mesh, "{what}");
    }
}

#[test]
fn ascii_line_numbers_count_cr_crlf_and_lf_alike() {
    // Line 5 holds the second vertex of the first facet in every encoding.
    for ending in ["\n", "\r\n", "\r"] {
        let bytes = cube_text(|s| {
            s.replacen("vertex 1 1 0", "vertex 1 1 zero", 1)
                .replace('\n', ending)
                .into()
        });
        assert_eq!(
            read_stl(&bytes).unwrap_err(),
            StlError::BadNumber {
                line: 5,
                token: "zero".into()
            },
            "{ending:?}"
        );
    }
    // A missing number is a syntax error on the vertex line, not a bad 'vertex' number.
    let bytes = cube_text(|s| s.replacen("vertex 1 1 0", "vertex 1 1", 1).into());
    assert!(
        error(&bytes)
            .contains("syntax error at line 5: expected 'vertex x y z', found 'vertex 1 1'"),
        "{}",
        error(&bytes)
    );
    let bytes = cube_text(|s| s.replacen("vertex 1 1 0", "vertex 1 1 0 0", 1).into());
    assert!(error(&bytes).contains("syntax error at line 5: expected 'vertex x y z'"));
}

#[test]
fn binary_files_whose_header_reads_like_text_stay_binary() {
    // Headers starting with "solid" (with a UTF-8 name) and trailing bytes after the last
    // triangle: the count field and the floats are not text, so the file is binary.
    let mut bytes = binary_stl(&common::plane(1.0, 1.0, 2));
    let header = "solid café exported by a tool".as_bytes();
    bytes[..header.len()].copy_from_slice(header);
    bytes.extend_from_slice(b"\nsome trailing text\n");
    let m = import(&bytes);
    assert_eq!(m.report.format, StlFormat::Binary);
    assert_eq!((m.report.triangles, m.report.trailing_bytes), (8, 20));
}

/// Files for the streaming tests: every fixture, a binary file whose header begins like
/// text and has trailing text, a 7,200-triangle plane, the same cut to 83 bytes and short of
/// its last bytes, and no bytes at all.
fn streamed_files() -> Vec<(&'static str, Vec<u8>)> {
    let mut headed = binary_stl(&common::plane(1.0, 1.0, 2));
    headed[..11].copy_from_slice(b"solid x y z");
    headed.extend_from_slice(b"\nsome trailing text\n");
    let big = binary_stl(&common::plane(2.0, 1.0, 60));
    let mut files: Vec<(&str, Vec<u8>)> = common::fixtures()
        .iter()
        .map(|&(name, bytes)| (name, bytes.to_vec()))
        .collect();
    files.extend([
        ("headed plane", headed),
        ("short", big[..83].to_vec()),
        ("cut plane", big[..big.len() - 7].to_vec()),
        ("plane of 7200", big),
        ("empty", Vec::new()),
    ]);
    files
}

#[test]
fn a_binary_file_is_told_from_its_head_and_read_in_pieces_as_a_whole() {
    // The WebAssembly build streams a binary file from JavaScript through a small buffer
    // when its first STL_HEAD_BYTES say it is binary: that must be exactly when `read_stl`
    // reads it as binary, and the pieces must give the same mesh.
    let files = streamed_files();
    let mut streamed = 0;
    for (name, bytes) in files.iter().filter(|(name, _)| *name != "empty") {
        let (name, bytes) = (*name, bytes.as_slice());
        let layout = binary_layout(&bytes[..bytes.len().min(STL_HEAD_BYTES)], bytes.len());
        let whole = read_stl(bytes);
        let Some(count) = layout else {
            // Not told from the head: the caller reads the whole file, as `read_stl` does. A
            // binary file is missed only when its first kilobyte looks like text.
            if let Ok(w) = &whole {
                assert!(
                    w.info.format == StlFormat::Ascii,
                    "{name}: binary, not told from its head"
                );
            }
            continue;
        };
        let end = STL_PREAMBLE_BYTES + count * STL_RECORD_BYTES;
        for piece in [1, 7, 1000] {
            let mut reader = BinaryStl::new(count);
            let mut stages = Vec::new();
            for records in bytes[STL_PREAMBLE_BYTES..end].chunks(piece * STL_RECORD_BYTES) {
                reader.feed(records, &mut |stage, f| stages.push((stage.to_string(), f)));
            }
            let read = reader.finish(bytes.len() - end, &mut |stage, f| {
                stages.push((stage.to_string(), f))
            });
            assert_eq!(stages.first(), Some(&("parse".to_string(), 0.0)), "{name}");
            assert_eq!(stages.last(), Some(&("parse".to_string(), 1.0)), "{name}");
            match (&read, &whole) {
                (Ok(read), Ok(whole)) => {
                    assert_eq!(whole.info.format, StlFormat::Binary, "{name}");
                    assert_eq!(whole.info.triangles_in_file, count, "{name}");
                    assert_eq!(read.info, whole.info, "{name}, {piece} a piece");
                    assert_eq!(read.mesh.positions(), whole.mesh.positions(), "{name}");
                    assert_eq!(read.mesh.triangles(), whole.mesh.triangles(), "{name}");
                }
                // A binary file refused for what it holds (NaN or no triangles) is refused
                // alike; one refused for its layout is never told binary.
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{name}"),
                _ => panic!("{name}: streamed {read:?}, whole {whole:?}"),
            }
        }
        streamed += 1;
    }
    // The eleven binary fixtures (the cube, the solid header, trailing bytes, the flipped,
    // open, non-manifold and NaN ones...) and the two whole generated files.
    assert_eq!(streamed, 13);
}

#[test]
fn a_file_read_as_it_comes_in_pieces_of_any_size_is_read_stl_of_it() {
    // The page streams a file from disk into the engine (StlStream): whatever the pieces,
    // binary, ASCII or broken, the result (mesh, info or error) is `read_stl`'s of the whole.
    let files = streamed_files();
    for (name, bytes) in &files {
        let (name, bytes) = (*name, bytes.as_slice());
        let whole = read_stl(bytes);
        // Pieces of 1 byte, a record less one, a record and one, the head and one, and all.
        for piece in [1, 49, 51, STL_HEAD_BYTES + 1, bytes.len().max(1)] {
            let mut stream = StlStream::new(bytes.len());
            let mut parse = Vec::new();
            for chunk in bytes.chunks(piece) {
                stream
                    .push(chunk, &mut |_, f| parse.push(f))
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
            }
            assert_eq!(stream.received(), bytes.len());
            let read = stream.finish(&mut |_, f| parse.push(f));
            assert!(
                parse.windows(2).all(|w| w[0] <= w[1]),
                "{name}: progress grows"
            );
            match (&read, &whole) {
                (Ok(read), Ok(whole)) => {
                    assert_eq!(read.info, whole.info, "{name}, {piece} a piece");
                    assert_eq!(read.mesh.positions(), whole.mesh.positions(), "{name}");
                    assert_eq!(read.mesh.triangles(), whole.mesh.triangles(), "{name}");
                }
                (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{name}"),
                _ => panic!("{name}, {piece} a piece: streamed {read:?}, whole {whole:?}"),
            }
        }
    }
    // A file whose bytes change while they are read: more than its length are refused and
    // not read, fewer fail at the end; both say so.
    let big = binary_stl(&common::plane(2.0, 1.0, 60));
    let mut stream = StlStream::new(big.len() - 1);
    let mut ignore = |_: &str, _: f64| {};
    stream.push(&big[..1000], &mut ignore).unwrap();
    let more = stream.push(&big[1000..], &mut ignore).unwrap_err();
    assert!(matches!(more, StlError::LengthMismatch { received, .. } if received == big.len()));
    assert_eq!(stream.received(), 1000);
    let fewer = stream.finish(&mut ignore).unwrap_err();
    assert_eq!(
        fewer.to_string(),
        format!(
            "the file's bytes changed while they were read: 1000 bytes came for a file of {} (was it changed or replaced meanwhile?)",
            big.len() - 1
        )
    );
}

#[test]
fn a_file_of_only_degenerate_triangles_is_refused() {
    let point = [[1.0, 2.0, 3.0]; 3];
    let line = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    // Height 1e-9 over a longest edge of 1: below DEGENERATE_HEIGHT_RATIO.
    let sliver = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 1e-9, 0.0]];
    assert_eq!(
        error(&binary_stl(&[point, point, point, point])),
        "no usable triangles: all 4 are degenerate (zero area, or a height below 1e-7 of the longest edge), so there is no surface to process"
    );
    assert!(error(&binary_stl(&[line, sliver, point]))
        .starts_with("no usable triangles: all 3 are degenerate"));
    // One usable triangle is enough.
    let good = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let m = import(&binary_stl(&[line, sliver, point, good]));
    assert_eq!(m.report.degenerate_triangles, 3);
}

/// A fan of `n` triangles around one vertex (a disc), and a "book" of `n` triangles on one
/// edge, every other one wound the other way.
fn fan_and_book(n: usize) -> (Vec<common::Tri>, Vec<common::Tri>) {
    let rim = |i: usize| {
        let a = std::f64::consts::TAU * (i % n) as f64 / n as f64;
        [a.cos() as f32, a.sin() as f32, 0.0]
    };
    let fan = (0..n)
        .map(|i| [[0.0, 0.0, 0.3], rim(i), rim(i + 1)])
        .collect();
    let book = (0..n)
        .map(|i| {
            let page = [rim(i)[0], rim(i)[1], 0.5];
            if i % 2 == 0 {
                [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], page]
            } else {
                [[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], page]
            }
        })
        .collect();
    (fan, book)
}

#[test]
fn a_vertex_or_an_edge_shared_by_many_faces_is_linked_in_near_linear_time() {
    // Quadratic adjacency needs minutes on these in a debug build; n log n needs a blink.
    let n = 60_000;
    let (fan, book) = fan_and_book(n);
    let fan = import(&binary_stl(&fan));
    let r = &fan.report;
    assert_eq!((r.triangles, r.vertices, r.boundary_edges), (n, n + 1, n));
    assert_eq!(
        (r.non_manifold_edges, r.components, r.flipped_triangles),
        (0, 1, 0)
    );
    for f in 0..n {
        let across: Vec<usize> = fan.adjacency.neighbours_of(f).collect();
        assert_eq!(across.len(), 2, "face {f} has a spoke on each side");
        assert!(across.contains(&((f + 1) % n)) && across.contains(&((f + n - 1) % n)));
    }
    check_adjacency(&fan);
    let book = import(&binary_stl(&book));
    let r = &book.report;
    assert_eq!((r.triangles, r.vertices), (n, n + 2));
    assert_eq!(
        (r.non_manifold_edges, r.boundary_edges, r.components),
        (1, 2 * n, 1)
    );
    assert!((0..n).all(|f| book.adjacency.neighbours_of(f).next().is_none()));
}

#[test]
fn adjacency_matches_a_brute_force_edge_table_at_any_valence() {
    use skinpath::mesh::{FaceAdjacency, TriMesh, NO_FACE};
    use std::collections::BTreeMap;
    let mut rng = Rng(0xadac_e17c_0ffe_e000);
    // Few vertices and many faces: valences in the hundreds, non-manifold and wrongly wound
    // edges everywhere, collapsed faces too; and a sparse soup where valence stays small.
    for (vertices, faces) in [(12, 4000), (40, 3000), (300, 400), (2000, 3000)] {
        let positions = (0..vertices)
            .map(|v| skinpath::math::Point3::new(v as f64, (v * v % 7) as f64, (v % 5) as f64))
            .collect();
        let triangles: Vec<[u32; 3]> = (0..faces)
            .map(|_| std::array::from_fn(|_| rng.below(vertices) as u32))
            .collect();
        let mesh = TriMesh::new(positions, triangles.clone()).unwrap();
        let adj = FaceAdjacency::new(&mesh);

        let collapsed = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
        // Undirected edge → (face, slot, whether the face runs it from low to high vertex).
        type Users = Vec<(usize, usize, bool)>;
        let mut edges: BTreeMap<(u32, u32), Users> = BTreeMap::new();
        for (f, t) in triangles.iter().enumerate().filter(|(_, t)| !collapsed(t)) {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edges
                    .entry((a.min(b), a.max(b)))
                    .or_default()
                    .push((f, k, a < b));
            }
        }
        let mut expected = vec![[NO_FACE; 3]; faces];
        let (mut boundary, mut non_manifold, mut conflicts) = (0, 0, 0);
        let mut component: Vec<usize> = (0..faces).collect();
        fn root(c: &mut [usize], mut x: usize) -> usize {
            while c[x] != x {
                x = c[x];
            }
            x
        }
        for users in edges.values() {
            match users.as_slice() {
                [_] => boundary += 1,
                [(f, k, d), (g, l, e)] => {
                    expected[*f][*k] = *g as u32;
                    expected[*g][*l] = *f as u32;
                    conflicts += usize::from(d == e);
                }
                _ => non_manifold += 1,
            }
            for &(g, _, _) in &users[1..] {
                let (a, b) = (root(&mut component, users[0].0), root(&mut component, g));
                component[a.max(b)] = a.min(b);
            }
        }
        let components = (0..faces).filter(|&f| root(&mut component, f) == f).count();
        for (f, slots) in expected.iter().enumerate() {
            assert_eq!(
                adj.neighbours(f),
                *slots,
                "face {f} of {faces} on {vertices} vertices"
            );
        }
        assert_eq!(
            (
                adj.boundary_edges(),
                adj.non_manifold_edges(),
                adj.winding_conflicts(),
                adj.components()
            ),
            (boundary, non_manifold, conflicts, components),
            "{faces} faces on {vertices} vertices"
        );
    }
}

/// Welding numbers vertices in order of first appearance, even when a corner comes back
/// long after it was first seen (beyond any cache of recent corners): checked against a
/// plain map from bit pattern to id, built here.
#[test]
fn welding_numbers_vertices_in_order_of_first_appearance() {
    // A closed sphere whose triangles are listed in a scrambled order (a fixed
    // multiplicative permutation), so most corners recur far apart; a few -0.0 too.
    let mut tris = common::sphere(1.0, 160, 120);
    let n = tris.len();
    let step = (0..)
        .map(|k| 7919 + 2 * k)
        .find(|s| gcd(*s, n) == 1)
        .unwrap();
    tris = (0..n).map(|i| tris[i * step % n]).collect();
    for t in tris.iter_mut().step_by(7) {
        for c in t.iter_mut().flatten() {
            if *c == 0.0 {
                *c = -0.0;
            }
        }
    }
    let import = read_stl(&binary_stl(&tris)).unwrap();
    let mut ids = std::collections::HashMap::new();
    let mut positions = Vec::new();
    let expected: Vec<[u32; 3]> = tris
        .iter()
        .map(|t| {
            t.map(|c| {
                let key = c.map(|x| (x + 0.0).to_bits());
                *ids.entry(key).or_insert_with(|| {
                    positions.push(c.map(|x| (x + 0.0) as f64));
                    positions.len() as u32 - 1
                })
            })
        })
        .collect();
    assert!(
        positions.len() > 16_384,
        "enough vertices to leave any small cache"
    );
    assert_eq!(import.mesh.triangles(), expected.as_slice());
    let got: Vec<[f64; 3]> = import
        .mesh
        .positions()
        .iter()
        .map(|p| [p.x, p.y, p.z])
        .collect();
    assert_eq!(got, positions);
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// The face geometry the import computes along with the winding (and patches for the faces
/// it turns) is bit for bit what `FaceGeometry::new` computes on the final mesh: zero
/// signs of normal components included, on both orientation paths.
#[test]
fn imported_geometry_is_bit_identical_to_a_fresh_computation() {
    let bits = |g: &FaceGeometry| -> Vec<u64> {
        let n = g.normals().iter().flat_map(|v| [v.x, v.y, v.z]);
        let c = g.centroids().iter().flat_map(|p| [p.x, p.y, p.z]);
        n.chain(g.areas().iter().copied())
            .chain(c)
            .map(f64::to_bits)
            .collect()
    };
    // Inside out (every face turned, fast path), flipped faces (propagation), a degenerate
    // face, an axis-aligned box (many exact zeros) and an inside-out sphere.
    let inside_out_sphere: Vec<Tri> = common::sphere(2.0, 24, 16)
        .into_iter()
        .map(|[a, b, c]| [a, c, b])
        .collect();
    let sphere_bytes = binary_stl(&inside_out_sphere);
    // A tetrahedron with faces whose cross products have components `q − p` with `p = q`
    // (a +0 either way), in both windings: one of the two is turned.
    let [a, b, c, d] = [
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 1.0],
        [1.0, 1.0, 1.0],
        [1.0, 0.0, -1.0],
    ];
    let tetra: Vec<Tri> = vec![[a, c, b], [a, b, d], [b, c, d], [a, d, c]];
    let tetra_bytes = binary_stl(&tetra);
    let reversed: Vec<Tri> = tetra.iter().map(|&[a, b, c]| [a, c, b]).collect();
    let reversed_bytes = binary_stl(&reversed);
    for bytes in [
        fixture!("inside_out_cube.stl"),
        fixture!("flipped_faces.stl"),
        fixture!("degenerate_triangle.stl"),
        fixture!("cube_binary.stl"),
        &sphere_bytes[..],
        &tetra_bytes[..],
        &reversed_bytes[..],
    ] {
        let m = import(bytes);
        assert_eq!(bits(&m.geometry), bits(&FaceGeometry::new(&m.mesh)));
        assert_eq!(
            m.geometry.degenerate_count(),
            FaceGeometry::new(&m.mesh).degenerate_count()
        );
    }
    assert_eq!(
        import(&sphere_bytes).report.flipped_triangles,
        inside_out_sphere.len()
    );
    let turned = [&tetra_bytes, &reversed_bytes].map(|b| import(b).report.flipped_triangles);
    assert_eq!(turned.iter().sum::<usize>(), 4);
}

#[test]
fn slivers_are_judged_alike_in_every_vertex_order_and_after_writing_and_reading() {
    use skinpath::mesh::TriMesh;
    // Slivers around the degeneracy ratio (1e-7 of the longest edge) and a healthy face,
    // with corners that are not round numbers so the edge vectors from each corner round
    // differently.
    let (a, b, n) = ([0.1, 0.7, -0.3], [1.3, 1.1, 0.4], [0.2, -0.5, 0.1]);
    let length = (0..3)
        .map(|k| (b[k] - a[k]) * (b[k] - a[k]))
        .sum::<f64>()
        .sqrt();
    let n_length = n.iter().map(|x| x * x).sum::<f64>().sqrt();
    let orders = [
        [0, 1, 2],
        [1, 2, 0],
        [2, 0, 1],
        [0, 2, 1],
        [2, 1, 0],
        [1, 0, 2],
    ];
    for ratio in [0.3e-7, 0.5e-7, 1e-7, 1.5e-7, 2e-7, 1e-3] {
        let f32s = |p: [f64; 3]| p.map(|x| x as f32);
        let c =
            std::array::from_fn(|k| a[k] + 0.37 * (b[k] - a[k]) + ratio * length * n[k] / n_length);
        let corners: [[f32; 3]; 3] = [f32s(a), f32s(b), f32s(c)];
        let measured: Vec<(bool, u64, [u64; 3])> = orders
            .iter()
            .map(|order| {
                let positions = order
                    .iter()
                    .map(|&i| corners[i].map(f64::from).into())
                    .collect();
                let mesh = TriMesh::new(positions, vec![[0, 1, 2]]).unwrap();
                let g = FaceGeometry::new(&mesh);
                // Odd permutations reverse the winding: the normal is exactly negated.
                let sign = if order[1] == (order[0] + 1) % 3 {
                    1.0
                } else {
                    -1.0
                };
                let normal = (g.normals()[0] * sign).map(|x| (x + 0.0).to_bits());
                // Written as STL and read back (the f32 round trip a patch export makes).
                let back = read_stl(&write_stl(std::iter::once(mesh.corners(0)))).unwrap();
                let again = FaceGeometry::new(&back.mesh);
                assert_eq!(again.is_degenerate(0), g.is_degenerate(0), "ratio {ratio}");
                assert_eq!(again.areas()[0].to_bits(), g.areas()[0].to_bits());
                (g.is_degenerate(0), g.areas()[0].to_bits(), normal.into())
            })
            .collect();
        assert!(
            measured.iter().all(|m| *m == measured[0]),
            "ratio {ratio}: {measured:?}"
        );
        if ratio != 1e-7 {
            assert_eq!(measured[0].0, ratio < 1e-7, "ratio {ratio}");
        }
    }
}

/// A Möbius strip cannot be wound consistently: the import counts the links left
/// inconsistent, the adjacency reports as many winding conflicts, and turning the faces by
/// hand (`orient_consistently` on the file's mesh) agrees with the import.
#[test]
fn a_moebius_strip_keeps_its_inconsistent_links_counted_alike() {
    use skinpath::mesh::{orient_consistently, FaceAdjacency};
    let n = 24;
    let point = |i: usize, s: f64| {
        // The strip's centre circle has radius 2; the segment across it turns by half a
        // turn in one round (angle a/2), so the band closes on itself reversed.
        let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
        let (r, z) = (2.0 + s * (a / 2.0).cos(), s * (a / 2.0).sin());
        [r * a.cos(), r * a.sin(), z].map(|x| x as f32)
    };
    let triangles: Vec<Tri> = (0..n)
        .flat_map(|i| {
            // The last quad joins the end segment to the start one reversed.
            let (s0, s1) = if i + 1 == n { (-1.0, 1.0) } else { (1.0, -1.0) };
            let (a, b) = (point(i, 1.0), point(i, -1.0));
            let (c, d) = (point((i + 1) % n, s0), point((i + 1) % n, s1));
            [[a, b, d], [a, d, c]]
        })
        .collect();
    let m = import(&binary_stl(&triangles));
    assert_eq!(m.report.components, 1);
    assert_eq!(m.report.boundary_edges, 2 * n);
    assert!(m.report.inconsistent_edges >= 1);
    assert_eq!(m.adjacency.winding_conflicts(), m.report.inconsistent_edges);
    let mut mesh = read_stl(&binary_stl(&triangles)).unwrap().mesh;
    let mut adjacency = FaceAdjacency::new(&mesh);
    let report = orient_consistently(&mut mesh, &mut adjacency);
    assert_eq!(
        (report.flipped_faces, report.inconsistent_edges),
        (m.report.flipped_triangles, m.report.inconsistent_edges)
    );
    assert_eq!(mesh.triangles(), m.mesh.triangles());
    assert_eq!(adjacency, m.adjacency);
}
