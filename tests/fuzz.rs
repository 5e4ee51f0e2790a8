//! Mutation fuzzing: mangled STL files through import and segmentation, random or extreme
//! segmentation parameters, and random spray plans, geodesic passes and drilling corrections
//! on generated surfaces and windows of the real models. Every call must return `Ok` or an
//! `Err` with a message, never panic or hang, and whatever is accepted must keep the
//! documented invariants.
//!
//! Fixed seed and a small case budget, so `cargo test` (debug build) and the WebAssembly run
//! stay at a few seconds. Natively, `SKINPATH_FUZZ_CASES=N` sets the number of cases per
//! test, `SKINPATH_FUZZ_SECONDS=S` runs each test for S seconds instead, and
//! `SKINPATH_FUZZ_SEED=X` changes the seed; `npm run fuzz` runs a long release-mode pass and
//! prints how many cases of each kind ran. A failing case is written to the Cargo target's
//! temporary folder and its seed, index and kind are printed.

mod common;

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use common::{binary_stl, check_adjacency, check_invariants};
use skinpath::mesh::{import_stl, ImportedMesh};
use skinpath::segment::{
    segment, Criterion, GrindParams, GrowthThreshold, ParamsSpec, SeedRule, SegmentParams,
    SprayParams, MIN_ANGLE_RAD,
};
use std::f64::consts::PI;

/// SplitMix64 (Steele, Lea, Flood 2014): tiny, full-period and good enough to pick mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (n > 0); the modulo bias is irrelevant here.
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

const DEFAULT_SEED: u64 = 0x5eed_f022_2026_0006;

/// How long a test runs: a number of cases, or (natively) a number of seconds.
struct Budget {
    cases: usize,
    #[cfg(not(target_arch = "wasm32"))]
    until: Option<std::time::Instant>,
}

impl Budget {
    /// `native` cases natively, `wasm` in WebAssembly, unless the environment says otherwise.
    fn new(native: usize, wasm: usize) -> Self {
        #[cfg(target_arch = "wasm32")]
        {
            let _ = native;
            Budget { cases: wasm }
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            let _ = wasm;
            let var = |name| std::env::var(name).ok().and_then(|v| v.parse::<u64>().ok());
            let until = var("SKINPATH_FUZZ_SECONDS")
                .map(|s| std::time::Instant::now() + std::time::Duration::from_secs(s));
            let cases = match (var("SKINPATH_FUZZ_CASES"), until) {
                (Some(n), _) => n as usize,
                (None, Some(_)) => usize::MAX,
                (None, None) => native,
            };
            Budget { cases, until }
        }
    }

    fn more(&self, done: usize) -> bool {
        #[cfg(not(target_arch = "wasm32"))]
        if let Some(until) = self.until {
            // Check the clock every 64 cases only.
            if done % 64 == 0 && std::time::Instant::now() >= until {
                return false;
            }
        }
        done < self.cases
    }
}

fn seed() -> u64 {
    #[cfg(not(target_arch = "wasm32"))]
    if let Some(seed) = std::env::var("SKINPATH_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        return seed;
    }
    DEFAULT_SEED
}

/// Prints (and natively saves) the case being run if it panics.
struct CaseGuard<'a> {
    what: String,
    bytes: &'a [u8],
}

impl Drop for CaseGuard<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!(
                "fuzz case failed: {} ({} bytes)",
                self.what,
                self.bytes.len()
            );
            #[cfg(not(target_arch = "wasm32"))]
            {
                let path =
                    std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failure.stl");
                if std::fs::write(&path, self.bytes).is_ok() {
                    eprintln!("the bytes are in {}", path.display());
                }
            }
        }
    }
}

/// The files mutations start from: every fixture, a few generated meshes, and natively
/// windows of the shared real models.
fn sources() -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = vec![];
    for (name, bytes) in common::fixtures() {
        out.push((name.into(), bytes.to_vec()));
    }
    out.push(("sphere".into(), binary_stl(&common::sphere(1.0, 12, 6))));
    out.push((
        "cylinder".into(),
        binary_stl(&common::cylinder(1.0, 3.0, 16, 3)),
    ));
    // A fan (one vertex of valence 40) and a book (one edge of 40 faces).
    let rim = |i: usize| {
        let a = std::f64::consts::TAU * (i % 40) as f64 / 40.0;
        [a.cos() as f32, a.sin() as f32, 0.0]
    };
    let fan: Vec<common::Tri> = (0..40)
        .map(|i| [[0.0, 0.0, 0.2], rim(i), rim(i + 1)])
        .collect();
    out.push(("fan".into(), binary_stl(&fan)));
    let book: Vec<common::Tri> = (0..40)
        .map(|i| {
            [
                [0.0, 0.0, 0.0],
                [0.0, 0.0, 1.0],
                [rim(i)[0], rim(i)[1], 0.5],
            ]
        })
        .collect();
    out.push(("book".into(), binary_stl(&book)));
    #[cfg(not(target_arch = "wasm32"))]
    out.extend(model_windows());
    out
}

/// Two windows of 400 triangles (start and middle) of each shared model, as files of their
/// own encoding.
#[cfg(not(target_arch = "wasm32"))]
fn model_windows() -> Vec<(String, Vec<u8>)> {
    const WINDOW: usize = 400;
    let mut out = vec![];
    for name in [
        "airplane_10796_pymeshlab.stl",
        "b747_14062_flightgear.stl",
        "bwb_4464_pygeo_ascii.stl",
        "orion_51736_nasa.stl",
        "wingbody_79868_flow360.stl",
    ] {
        let bytes = common::model(name);
        if bytes.starts_with(b"solid") {
            // ASCII: whole facets from the first and from the middle.
            let text = String::from_utf8_lossy(&bytes);
            let facets: Vec<&str> = text.split_inclusive("endfacet").collect();
            for start in [0, facets.len() / 2] {
                let end = (start + WINDOW).min(facets.len().saturating_sub(1));
                let mut window = String::from("solid window\n");
                for f in &facets[start..end] {
                    // Each piece starts with what precedes its facet (a line break, the header).
                    let at = f.to_ascii_lowercase().find("facet").unwrap_or(0);
                    window.push_str(&f[at..]);
                    window.push('\n');
                }
                window.push_str("endsolid window\n");
                out.push((format!("{name}@{start}"), window.into_bytes()));
            }
        } else {
            let count = (bytes.len() - 84) / 50;
            for start in [0, count / 2] {
                let n = WINDOW.min(count - start);
                let mut window = bytes[..80].to_vec();
                window.extend_from_slice(&(n as u32).to_le_bytes());
                window.extend_from_slice(&bytes[84 + 50 * start..84 + 50 * (start + n)]);
                out.push((format!("{name}@{start}"), window));
            }
        }
    }
    out
}

/// The kinds of mutation, applied one to three at a time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mutation {
    BitFlip,
    ByteOverwrite,
    Truncate,
    Splice,
    DuplicateRange,
    DeleteRange,
    HeaderCount,
    SpecialFloat,
    AsciiToken,
    LineEnds,
}

const MUTATIONS: [Mutation; 10] = [
    Mutation::BitFlip,
    Mutation::ByteOverwrite,
    Mutation::Truncate,
    Mutation::Splice,
    Mutation::DuplicateRange,
    Mutation::DeleteRange,
    Mutation::HeaderCount,
    Mutation::SpecialFloat,
    Mutation::AsciiToken,
    Mutation::LineEnds,
];

const SPECIAL_F32: [f32; 12] = [
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::MAX,
    -f32::MAX,
    f32::MIN_POSITIVE,
    1e-45,
    -0.0,
    0.0,
    1.0,
    1e20,
    1e-20,
];

const TOKENS: [&str; 26] = [
    "nan", "NaN", "inf", "-inf", "1e39", "-1e39", "1e-50", "0", "-0", "1e", "+", "0x10", "1,5",
    "1.0.0", "vertex", "facet", "endfacet", "outer", "loop", "endloop", "solid", "endsolid",
    "normal", "café", "\u{a0}", "",
];

/// Ranges `[start, end)` of the whitespace-separated tokens of `bytes`.
fn token_ranges(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut out = vec![];
    let mut start = None;
    for (i, b) in bytes.iter().enumerate() {
        match (b.is_ascii_whitespace(), start) {
            (true, Some(s)) => {
                out.push((s, i));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, bytes.len()));
    }
    out
}

fn mutate(rng: &mut Rng, kind: Mutation, bytes: &mut Vec<u8>, other: &[u8]) {
    let len = bytes.len();
    match kind {
        Mutation::BitFlip if len > 0 => {
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(len);
                bytes[i] ^= 1 << rng.below(8);
            }
        }
        Mutation::ByteOverwrite if len > 0 => {
            const INTERESTING: [u8; 12] = [
                0, 0xff, 0x7f, 0x80, b'\n', b'\r', b' ', b'-', b'.', b'e', 0xc2, 0xa0,
            ];
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(len);
                bytes[i] = if rng.below(2) == 0 {
                    *rng.pick(&INTERESTING)
                } else {
                    rng.next() as u8
                };
            }
        }
        Mutation::Truncate => bytes.truncate(rng.below(len + 1)),
        Mutation::Splice => {
            let cut = rng.below(len + 1);
            let from = rng.below(other.len() + 1);
            bytes.truncate(cut);
            bytes.extend_from_slice(&other[from..]);
        }
        Mutation::DuplicateRange if len > 0 => {
            let start = rng.below(len);
            let end = (start + 1 + rng.below(200)).min(len);
            let copy = bytes[start..end].to_vec();
            let at = rng.below(len + 1);
            for _ in 0..1 + rng.below(3) {
                bytes.splice(at..at, copy.iter().copied());
            }
        }
        Mutation::DeleteRange if len > 0 => {
            let start = rng.below(len);
            let end = (start + 1 + rng.below(200)).min(len);
            bytes.drain(start..end);
        }
        Mutation::HeaderCount if len >= 84 => {
            let count = (len.saturating_sub(84) / 50) as u32;
            let random = rng.next() as u32;
            let value = *rng.pick(&[
                0,
                1,
                count.wrapping_sub(1),
                count + 1,
                count.wrapping_mul(2),
                u32::MAX,
                u32::MAX / 50,
                random,
            ]);
            bytes[80..84].copy_from_slice(&value.to_le_bytes());
        }
        Mutation::SpecialFloat if len >= 84 + 50 => {
            // A corner or normal coordinate of a binary record (or any aligned word).
            let records = (len - 84) / 50;
            let i = 84 + 50 * rng.below(records) + 4 * rng.below(12);
            bytes[i..i + 4].copy_from_slice(&rng.pick(&SPECIAL_F32).to_le_bytes());
        }
        Mutation::AsciiToken => {
            let tokens = token_ranges(bytes);
            if tokens.is_empty() {
                return;
            }
            let (start, end) = *rng.pick(&tokens);
            match rng.below(4) {
                // Replace with a keyword, a special number or junk.
                0 | 1 => {
                    bytes.splice(start..end, rng.pick(&TOKENS).bytes());
                }
                // Delete it.
                2 => {
                    bytes.drain(start..end);
                }
                // Repeat it.
                _ => {
                    let copy: Vec<u8> = bytes[start..end].iter().copied().chain([b' ']).collect();
                    bytes.splice(start..start, copy);
                }
            }
        }
        Mutation::LineEnds => {
            let (from, to): (&[u8], &[u8]) = *rng.pick(&[
                (b"\n".as_slice(), b"\r".as_slice()),
                (b"\n", b"\r\n"),
                (b"\n", b" "),
                (b"\n", b""),
                (b" ", b"\t\xc2\xa0"),
            ]);
            let mut out = Vec::with_capacity(bytes.len());
            let mut i = 0;
            while i < bytes.len() {
                if bytes[i..].starts_with(from) {
                    out.extend_from_slice(to);
                    i += from.len();
                } else {
                    out.push(bytes[i]);
                    i += 1;
                }
            }
            *bytes = out;
        }
        _ => {}
    }
}

/// The parameter sets every accepted mesh is segmented with (one per case, in turn).
fn stl_case_params() -> [SegmentParams; 5] {
    let with = |criterion, theta_max_rad, min_area_ratio, seed_rule| SegmentParams {
        criterion,
        theta_max_rad,
        min_area_ratio,
        seed_rule,
    };
    [
        SegmentParams::default(),
        with(
            Criterion::Curvature { kappa: 2.0 },
            0.8,
            0.01,
            SeedRule::LargestArea,
        ),
        with(
            Criterion::Angle { alpha_rad: 0.2 },
            0.3,
            0.0,
            SeedRule::LowestIndex,
        ),
        with(
            Criterion::Angle { alpha_rad: PI },
            PI,
            0.0,
            SeedRule::Flattest,
        ),
        with(
            Criterion::Angle { alpha_rad: PI },
            1e-5,
            0.0,
            SeedRule::Flattest,
        ),
    ]
}

/// What import promises on success: a valid mesh, a report that matches it, symmetric
/// adjacency across shared edges.
fn check_import(m: &ImportedMesh) {
    m.mesh.validate().expect("an accepted mesh is valid");
    let r = &m.report;
    assert_eq!(r.triangles, m.mesh.triangle_count());
    assert_eq!(r.vertices, m.mesh.vertex_count());
    assert_eq!(r.area, m.geometry.total_area());
    assert!(r.area.is_finite() && r.area > 0.0, "area {}", r.area);
    assert_eq!(r.components, m.adjacency.components());
    assert_eq!(r.boundary_edges, m.adjacency.boundary_edges());
    assert_eq!(r.non_manifold_edges, m.adjacency.non_manifold_edges());
    assert_eq!(r.degenerate_triangles, m.geometry.degenerate_count());
    assert!(
        r.degenerate_triangles < r.triangles,
        "all degenerate accepted"
    );
    assert!((0..3).all(|k| r.bbox_min[k] <= r.bbox_max[k]));
    check_adjacency(m);
}

/// Every patch exported as STL reads back with the same triangles (corners bit for bit, in
/// order) and so the same area: nothing exported is unreadable.
fn check_patches_read_back(m: &ImportedMesh, seg: &skinpath::segment::Segmentation) {
    for patch in &seg.patches {
        let stl = seg.patch_stl(&m.mesh, patch.id).expect("a kept patch");
        let back = match import_stl(&stl, &mut |_, _| {}) {
            Ok(back) => back,
            Err(e) => panic!("patch {} does not read back: {e}", patch.id),
        };
        assert_eq!(back.report.triangles, patch.triangle_count);
        let mut written: Vec<[[u32; 3]; 3]> = seg
            .faces_of(patch.id)
            .map(|f| {
                m.mesh
                    .corners(f)
                    .map(|p| p.coords.map(|x| (x as f32).to_bits()).into())
            })
            .collect();
        let mut read: Vec<[[u32; 3]; 3]> = (0..back.mesh.triangle_count())
            .map(|f| {
                back.mesh
                    .corners(f)
                    .map(|p| p.coords.map(|x| (x as f32).to_bits()).into())
            })
            .collect();
        // The same triangles; the reader may turn a whole part (vertex 0 stays in place).
        let canonical = |t: &mut [[u32; 3]; 3]| {
            if t[1] > t[2] {
                t.swap(1, 2)
            }
        };
        written.iter_mut().for_each(canonical);
        read.iter_mut().for_each(canonical);
        assert_eq!(
            written, read,
            "patch {} reads back different triangles",
            patch.id
        );
    }
}

#[test]
fn mutated_stl_files_are_read_or_refused_and_what_is_read_segments_soundly() {
    let sources = sources();
    let params = stl_case_params();
    let budget = Budget::new(1500, 300);
    let mut rng = Rng(seed());
    // Per kind: cases, accepted by import.
    let mut tally = [(0usize, 0usize); MUTATIONS.len()];
    let (mut done, mut accepted, mut segmented) = (0, 0, 0);
    while budget.more(done) {
        let (name, source) = rng.pick(&sources);
        let (_, other) = rng.pick(&sources);
        let mut bytes = source.clone();
        let mut kinds = vec![];
        for _ in 0..1 + rng.below(3) {
            let kind = *rng.pick(&MUTATIONS);
            mutate(&mut rng, kind, &mut bytes, other);
            kinds.push(kind);
        }
        let _guard = CaseGuard {
            what: format!("seed {:#x}, case {done}, {name}, {kinds:?}", seed()),
            bytes: &bytes,
        };
        let mut last = 0.0;
        let mut progress = |_: &str, fraction: f64| {
            assert!((0.0..=1.0).contains(&fraction), "progress {fraction}");
            last = fraction;
        };
        let result = import_stl(&bytes, &mut progress);
        let ok = result.is_ok();
        for &kind in &kinds {
            let t = &mut tally[kind as usize];
            t.0 += 1;
            t.1 += usize::from(ok);
        }
        match result {
            Err(e) => assert!(!e.to_string().is_empty()),
            Ok(m) => {
                accepted += 1;
                check_import(&m);
                let p = &params[done % params.len()];
                let seg = segment(&m.adjacency, &m.geometry, p).expect("valid parameters");
                check_invariants(&m, &seg, p.theta_max_rad, p.min_area_ratio);
                check_patches_read_back(&m, &seg);
                segmented += 1;
            }
        }
        done += 1;
    }
    eprintln!(
        "STL mutation fuzz: {done} cases from {} sources, {accepted} imported and segmented ({segmented})",
        sources.len()
    );
    for (kind, (cases, ok)) in MUTATIONS.iter().zip(tally) {
        eprintln!("  {kind:?}: {cases} cases, {ok} imported");
    }
    if done >= 1000 {
        assert!(
            accepted * 10 > done,
            "mutations should leave many files readable ({accepted} of {done})"
        );
    }
}

/// A number from the edges of the domain or from the ordinary range.
fn wild(rng: &mut Rng) -> f64 {
    const EDGES: [f64; 22] = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -0.0,
        -1.0,
        5e-324,
        1e-300,
        1e-12,
        2e-8,
        MIN_ANGLE_RAD,
        0.999e-6,
        1e-3,
        0.5,
        1.0,
        PI,
        PI + 1e-12,
        4.0,
        1e9,
        1e300,
        f64::MAX,
        -f64::MAX,
    ];
    match rng.below(3) {
        0 => *rng.pick(&EDGES),
        1 => rng.unit() * PI,
        _ => libm_free_pow10(rng.below(40) as i32 - 20) * rng.unit(),
    }
}

/// `10^e` by repeated multiplication (exact enough for picking magnitudes).
fn libm_free_pow10(e: i32) -> f64 {
    let mut x = 1.0;
    for _ in 0..e.unsigned_abs() {
        x *= 10.0;
    }
    if e < 0 {
        1.0 / x
    } else {
        x
    }
}

#[test]
fn any_segmentation_parameters_give_a_result_or_an_error() {
    let meshes = [
        common::import(&binary_stl(&common::sphere(1.0, 10, 5))),
        common::import(fixture!("cube_binary.stl")),
        common::import(&binary_stl(&common::cylinder(1.0, 2.0, 12, 2))),
    ];
    let budget = Budget::new(3000, 600);
    let mut rng = Rng(seed() ^ 0x9a7a_3e7e_5000_0000);
    let rules = [
        SeedRule::LowestIndex,
        SeedRule::Flattest,
        SeedRule::LargestArea,
    ];
    let (mut done, mut accepted) = (0, 0);
    let mut by_criterion = [(0usize, 0usize); 4];
    while budget.more(done) {
        let kind = rng.below(4);
        let criterion = match kind {
            0 => Criterion::Angle {
                alpha_rad: wild(&mut rng),
            },
            1 => Criterion::Curvature {
                kappa: wild(&mut rng),
            },
            2 => Criterion::Spray(SprayParams {
                mean_thickness: wild(&mut rng),
                allowed_deviation: wild(&mut rng),
                min_thickness: wild(&mut rng),
            }),
            _ => Criterion::Grind(GrindParams {
                indentation_depth: wild(&mut rng),
                min_pressure_ratio: wild(&mut rng),
                contact_width: wild(&mut rng),
            }),
        };
        let p = SegmentParams {
            criterion,
            theta_max_rad: wild(&mut rng),
            min_area_ratio: if rng.below(2) == 0 {
                wild(&mut rng)
            } else {
                rng.unit() * 0.2
            },
            seed_rule: *rng.pick(&rules),
        };
        let m = rng.pick(&meshes);
        let _guard = CaseGuard {
            what: format!("seed {:#x}, parameter case {done}: {p:?}", seed()),
            bytes: &[],
        };
        by_criterion[kind].0 += 1;
        match segment(&m.adjacency, &m.geometry, &p) {
            Ok(seg) => {
                accepted += 1;
                by_criterion[kind].1 += 1;
                // Accepted values are the documented ranges, and the promises hold.
                assert!(p.theta_max_rad >= MIN_ANGLE_RAD && p.theta_max_rad <= PI);
                assert!((0.0..1.0).contains(&p.min_area_ratio));
                let t = seg.threshold.value();
                assert!(t.is_finite() && t > 0.0, "threshold {t}");
                if let GrowthThreshold::Angle(a) = seg.threshold {
                    assert!((MIN_ANGLE_RAD..=PI).contains(&a));
                }
                check_invariants(m, &seg, p.theta_max_rad, p.min_area_ratio);
            }
            Err(e) => assert!(!e.to_string().is_empty()),
        }
        // The same values spelled as the page sends them go through the same checks.
        let spec = ParamsSpec {
            angle_threshold: match criterion {
                Criterion::Angle { alpha_rad } => Some(alpha_rad),
                _ => None,
            },
            curvature_threshold: match criterion {
                Criterion::Curvature { kappa } => Some(kappa),
                _ => None,
            },
            spray: match criterion {
                Criterion::Spray(s) => Some(s.into()),
                _ => None,
            },
            grind: match criterion {
                Criterion::Grind(g) => Some(g.into()),
                _ => None,
            },
            theta_max: Some(p.theta_max_rad),
            min_area_ratio: Some(p.min_area_ratio),
            seed_rule: Some(p.seed_rule),
            ..ParamsSpec::default()
        };
        assert_eq!(
            SegmentParams::try_from(spec).ok(),
            p.validate().ok().map(|_| p)
        );
        done += 1;
    }
    eprintln!("parameter fuzz: {done} cases, {accepted} accepted");
    for (name, (cases, ok)) in ["angle", "curvature", "spray", "grind"]
        .iter()
        .zip(by_criterion)
    {
        eprintln!("  {name}: {cases} cases, {ok} accepted");
    }
}

/// Prints the case being run if it panics.
struct Announce(String);

impl Drop for Announce {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("fuzz case failed: {}", self.0);
        }
    }
}

/// Whether a refusal reads as a message: not empty, no number echoed in hundreds of digits,
/// no Rust spelling of infinity.
fn check_message(what: &str, message: &str) {
    assert!(!message.trim().is_empty(), "{what}: empty message");
    let longest = message
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    assert!(longest <= 25, "{what}: {message}");
    assert!(
        !message
            .split(|c: char| !c.is_ascii_alphabetic())
            .any(|w| w == "inf"),
        "{what}: {message}"
    );
}

/// The meshes the planners are tried on: generated surfaces (a plate, a curved panel, a
/// sphere, a cube) and natively the windows of the shared real models, with their sizes.
fn planner_meshes() -> Vec<(String, ImportedMesh, f64)> {
    let mut files: Vec<(String, Vec<u8>)> = vec![
        ("plate".into(), binary_stl(&common::plane(400.0, 300.0, 8))),
        (
            "panel".into(),
            binary_stl(&common::grid(12, 6, false, |u, v| {
                let a = 0.8 * (u - 0.5);
                [1500.0 * a.sin(), 800.0 * v, 1500.0 * a.cos()]
            })),
        ),
        ("sphere".into(), binary_stl(&common::sphere(2.0, 12, 6))),
        ("cube".into(), binary_stl(&common::refined_cube(3))),
    ];
    #[cfg(not(target_arch = "wasm32"))]
    files.extend(model_windows());
    files
        .into_iter()
        .filter_map(|(name, bytes)| {
            let m = import_stl(&bytes, &mut |_, _| {}).ok()?;
            let p = m.mesh.positions();
            let (lo, hi) = p
                .iter()
                .fold((p[0], p[0]), |(lo, hi), q| (lo.inf(q), hi.sup(q)));
            let size = (hi - lo).norm();
            (size > 0.0).then_some((name, m, size))
        })
        .collect()
}

/// Random spray plans, geodesic passes and drilling corrections on generated surfaces and
/// windows of the real models, with parameters drawn across their ranges and a little beyond:
/// each returns a result that keeps its promises (finite thickness, valid tool paths whose
/// exports are written or refused) or an `Err` whose message reads as one, never a panic.
#[test]
fn random_plans_give_sound_results_or_readable_errors() {
    use skinpath::drill::{correct_holes, CorrectionParams, MeshIndex, ReferenceHole};
    use skinpath::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, Method};
    use skinpath::math::{Point3, Vector3};
    use skinpath::spray::{plan_spray, QualityLimits};
    use skinpath::toolpath::{to_csv, to_json, to_krl, to_rapid, ExportOptions, ToolPath};

    let meshes = planner_meshes();
    let budget = Budget::new(20, 6);
    let mut rng = Rng(seed() ^ 0x91a7_5000_0000_0000);
    let log = |rng: &mut Rng, lo: f64, hi: f64| (lo.ln() + (hi.ln() - lo.ln()) * rng.unit()).exp();
    let exports = |path: &ToolPath, what: &str| {
        path.validate()
            .unwrap_or_else(|e| panic!("{what}: invalid path: {e}"));
        let o = ExportOptions::default();
        for out in [to_csv(path, &o).map(|_| ()), to_json(path, &o).map(|_| ())]
            .into_iter()
            .chain([to_rapid(path, &o).map(|_| ()), to_krl(path, &o).map(|_| ())])
        {
            if let Err(e) = out {
                check_message(what, &e.to_string());
            }
        }
    };
    let mut done = 0;
    let mut tally = [(0usize, 0usize); 3];
    while budget.more(done) {
        let (name, m, size) = rng.pick(&meshes);
        let n = m.mesh.triangle_count();
        // All faces, or a breadth-first blob from a random face.
        let faces: Vec<u32> = if rng.below(2) == 0 {
            (0..n as u32).collect()
        } else {
            let start = rng.below(n);
            let want = 1 + rng.below(n);
            let mut seen = vec![false; n];
            let mut blob = vec![start as u32];
            seen[start] = true;
            let mut head = 0;
            while head < blob.len() && blob.len() < want {
                let f = blob[head] as usize;
                head += 1;
                for g in m.adjacency.neighbours_of(f) {
                    if !seen[g] {
                        seen[g] = true;
                        blob.push(g as u32);
                    }
                }
            }
            blob
        };
        let kind = rng.below(3);
        let what = format!("seed {:#x}, case {done}, {name}, kind {kind}", seed());
        let _case = Announce(what.clone());
        tally[kind].0 += 1;
        match kind {
            0 => {
                let standoff = size * log(&mut rng, 0.01, 0.5);
                let cone = (5.0 + 115.0 * rng.unit()).to_radians();
                let radius = standoff * (0.5 * cone).tan();
                let p = skinpath::spray::SprayParams {
                    spacing: radius * log(&mut rng, 0.1, 4.0),
                    standoff,
                    speed: size * log(&mut rng, 0.01, 1.0),
                    flow_rate: size.powi(3) * log(&mut rng, 1e-9, 1e-5),
                    cone_angle: cone,
                    transition_angle: (89.0 * rng.unit()).to_radians(),
                    efficiency: 0.05 + 0.95 * rng.unit(),
                    raster_angle: 6.4 * rng.unit() - 3.2,
                    extension: (rng.below(3) == 0).then(|| radius * 3.0 * rng.unit()),
                    edge_exclusion: (rng.below(3) == 0).then(|| radius * 3.0 * rng.unit()),
                    sample_budget: Some(200 + rng.below(2000)),
                    quality: (rng.below(3) == 0).then(|| QualityLimits {
                        max_error: Some(0.05 + 0.5 * rng.unit()),
                        ..QualityLimits::default()
                    }),
                    target_thickness: (rng.below(5) == 0)
                        .then(|| size * 1e-6 * log(&mut rng, 1.0, 1e3)),
                    optimise_speed: rng.below(3) != 0,
                    best_direction: rng.below(5) == 0,
                    ..skinpath::spray::SprayParams::default()
                };
                let _case = Announce(format!("{what}: {p:?}"));
                match plan_spray(
                    &m.mesh,
                    &m.adjacency,
                    &m.geometry,
                    &faces,
                    &p,
                    &mut |_, _| {},
                ) {
                    Ok(plan) => {
                        tally[kind].1 += 1;
                        assert!(
                            plan.thickness.iter().all(|t| t.is_finite() && *t >= 0.0),
                            "{what}: thickness"
                        );
                        assert_eq!(plan.thickness.len(), plan.samples.positions.len());
                        exports(&plan.path, &what);
                    }
                    Err(e) => check_message(&what, &e.to_string()),
                }
            }
            1 => {
                let method =
                    *rng.pick(&[Method::Accurate, Method::Fast, Method::Exact, Method::Voxel]);
                let f = faces[rng.below(faces.len())] as usize;
                let source = match rng.below(3) {
                    0 => GeodesicSource::Boundary {
                        loop_index: (rng.below(2) == 0).then(|| rng.below(3)),
                    },
                    1 => GeodesicSource::Vertices(vec![m.mesh.triangles()[f][0]]),
                    _ => GeodesicSource::Plane {
                        point: m.geometry.centroids()[f],
                        normal: Vector3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5),
                    },
                };
                let params = DistanceParams {
                    method,
                    faces: (faces.len() < n).then(|| faces.clone()),
                    ..DistanceParams::default()
                };
                match geodesic_distance(&m.mesh, &m.adjacency, &source, &params, &mut |_, _| {}) {
                    Ok(field) => {
                        tally[kind].1 += 1;
                        assert!(
                            field.vertex_distance.iter().all(|d| *d >= 0.0),
                            "{what}: distances"
                        );
                        assert!(field.max_distance.is_finite(), "{what}: largest distance");
                        let pp = skinpath::geodesic::PathParams {
                            spacing: size * log(&mut rng, 0.005, 0.5),
                            ..skinpath::geodesic::PathParams::default()
                        };
                        match field.tool_path(&m.mesh, &m.adjacency, &pp) {
                            Ok(path) => exports(&path, &what),
                            Err(e) => check_message(&what, &e.to_string()),
                        }
                    }
                    Err(e) => check_message(&what, &e.to_string()),
                }
            }
            _ => {
                // Four references round a random face's neighbourhood, errors of a few per cent.
                let c = m.geometry.centroids()[faces[rng.below(faces.len())] as usize];
                let (w, h) = (size * 0.2 * rng.unit(), size * 0.2 * rng.unit());
                let corners = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
                let references: [ReferenceHole; 4] = std::array::from_fn(|k| {
                    let nominal = c + Vector3::new(corners[k].0 * w, corners[k].1 * h, 0.0);
                    ReferenceHole {
                        nominal,
                        actual: nominal
                            + Vector3::new(rng.unit(), rng.unit(), rng.unit()) * 0.02 * w,
                        normal: Vector3::new(0.2 * rng.unit(), 0.2 * rng.unit(), 1.0),
                        nominal_normal: None,
                    }
                });
                let holes: Vec<Point3> = (0..rng.below(8))
                    .map(|_| c + Vector3::new(rng.unit() * w, rng.unit() * h, 0.0))
                    .collect();
                let params = CorrectionParams {
                    references,
                    holes,
                    method: *rng.pick(&[
                        skinpath::drill::Method::Coons,
                        skinpath::drill::Method::Bilinear,
                    ]),
                    tangent_scale: None,
                    extrapolate: rng.below(2) == 0,
                };
                let index = MeshIndex::new(&m.mesh);
                let panel = (rng.below(2) == 0).then_some(&index);
                match correct_holes(&params, panel) {
                    Ok(out) => {
                        tally[kind].1 += 1;
                        assert!(
                            out.corrected
                                .iter()
                                .all(|p| p.iter().all(|x| x.is_finite())),
                            "{what}: corrected holes"
                        );
                    }
                    Err(e) => check_message(&what, &e.to_string()),
                }
            }
        }
        done += 1;
    }
    for (kind, (cases, ok)) in ["spray", "geodesic", "drill"].iter().zip(tally) {
        eprintln!("  {kind}: {cases} cases, {ok} planned");
    }
}
