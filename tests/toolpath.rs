//! Tool-path exports through the public API: every format is parsed back by the small parsers
//! below and every pose must survive (position, tool axis, travel direction, kind, process
//! state, speed), with the parts of the robot programs called in order.

mod common;

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use nalgebra::{Rotation3, UnitQuaternion};
use skinpath::math::{Point3, Vector3};
use skinpath::toolpath::{
    krl_files, rapid_files, to_csv, to_json, to_krl, to_rapid, ExportOptions, LineEnding, Pose,
    PoseKind, ToolPath, ToolPathError, CSV_HEADER,
};

const POSITION_TOL_MM: f64 = 1e-5;
const DIRECTION_TOL: f64 = 1e-6;

// ---------------------------------------------------------------------------------------
// Test data
// ---------------------------------------------------------------------------------------

/// SplitMix64: a fixed-seed generator so every run sees the same poses.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Uniform on the sphere (Archimedes: z uniform, longitude uniform).
    fn direction(&mut self) -> Vector3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).sqrt();
        Vector3::new(r * phi.cos(), r * phi.sin(), z)
    }
    fn perpendicular(&mut self, axis: &Vector3) -> Vector3 {
        loop {
            let r = self.direction();
            let p = r - axis * r.dot(axis);
            if p.norm() > 0.1 {
                return p.normalize();
            }
        }
    }
}

/// `(axis, travel)` pairs that stress the frame maths: random, travel parallel or opposite
/// to the axis, axes at and near ±Z, half turns, gimbal lock of the ZYX angles, travel just
/// above and just below the parallel tolerance.
fn awkward_directions(rng: &mut Rng, n: usize) -> Vec<(Vector3, Vector3)> {
    let mut out = Vec::with_capacity(n);
    let z = Vector3::z();
    let special = |rng: &mut Rng, i: usize| -> (Vector3, Vector3) {
        let tiny = 1e-9;
        match i % 16 {
            0 => {
                let a = rng.direction();
                (a, rng.perpendicular(&a))
            }
            1 => {
                let a = rng.direction();
                (a, a)
            }
            2 => {
                let a = rng.direction();
                (a, -a)
            }
            3 => (-z, Vector3::x()),
            4 => (z, -Vector3::x()),
            5 => (Vector3::new(tiny, -tiny, -1.0).normalize(), Vector3::y()),
            6 => (-z, Vector3::new(-1.0, tiny, 0.0).normalize()),
            7 => (-z, Vector3::new(-1.0, -tiny, 0.0).normalize()),
            8 => (Vector3::x(), z),  // X = +Z: B = −90°
            9 => (Vector3::y(), -z), // X = −Z: B = +90°
            10 => (-z, -z),          // drilling down
            11 => (
                Vector3::new(0.0, 0.0, -1.0),
                Vector3::new(2e-6, 0.0, -1.0).normalize(),
            ),
            12 => (
                Vector3::new(0.0, 0.0, -1.0),
                Vector3::new(1e-8, 0.0, -1.0).normalize(),
            ),
            13 => {
                let a = rng.direction();
                let t = rng.perpendicular(&a);
                // Not quite perpendicular: re-orthogonalisation must drop the axial part.
                (a, (t + a * 0.3).normalize())
            }
            14 => (-Vector3::x(), Vector3::y()),
            _ => {
                let a = Vector3::new(1e-7, 0.0, 1.0).normalize();
                (a, Vector3::new(-1.0, 0.0, 0.0))
            }
        }
    };
    for i in 0..n {
        // Random order of the special cases, so each follows many different predecessors.
        let pick = if i % 3 == 0 {
            0
        } else {
            (rng.next_u64() % 16) as usize
        };
        out.push(special(rng, pick));
    }
    out
}

fn awkward_path(n: usize, seed: u64, half_size: f64) -> ToolPath {
    let mut rng = Rng(seed);
    let dirs = awkward_directions(&mut rng, n);
    let mut pass = 0;
    let poses = dirs
        .into_iter()
        .map(|(axis, travel)| {
            let kind = PoseKind::ALL[(rng.next_u64() % 7) as usize];
            if rng.unit() < 0.1 {
                pass += 1;
            }
            Pose {
                position: Point3::new(
                    rng.range(-half_size, half_size),
                    rng.range(-half_size, half_size),
                    rng.range(-half_size, half_size),
                ),
                axis,
                travel,
                kind,
                pass,
            }
        })
        .collect();
    ToolPath {
        poses,
        speed: 0.4,
        link_speed: 1.25,
        speeds: Vec::new(),
        notes: vec![
            "Spray plan: b = 120 mm, h = 250 mm, α = 40°, thickness 30 µm.".into(),
            "A \"quoted\" note with a backslash \\ and a tab\tand a very long tail that must be \
             wrapped in the robot programs because it is far longer than eighty characters."
                .into(),
        ],
    }
}

fn options(mm_per_unit: f64, max_moves: Option<usize>) -> ExportOptions {
    ExportOptions {
        mm_per_unit,
        max_moves,
        ..ExportOptions::default()
    }
}

// ---------------------------------------------------------------------------------------
// The documented conventions, written independently of the crate
// ---------------------------------------------------------------------------------------

/// The documented tool-frame X: travel made perpendicular to the axis, else the previous X,
/// else the world axis least aligned with the tool axis (X, Y, Z on ties).
fn expected_x(axis: &Vector3, travel: &Vector3, previous: Option<&Vector3>) -> Vector3 {
    let z = axis.normalize();
    let perp = |v: &Vector3| {
        let v = v.normalize();
        let p = v - z * v.dot(&z);
        (p.norm() > 1e-6).then(|| p.normalize())
    };
    perp(travel)
        .or_else(|| previous.and_then(perp))
        .unwrap_or_else(|| {
            let c = [z.x.abs(), z.y.abs(), z.z.abs()];
            let i = if c[0] <= c[1] && c[0] <= c[2] {
                0
            } else if c[1] <= c[2] {
                1
            } else {
                2
            };
            perp(&Vector3::ith(i, 1.0)).expect("least aligned axis is never parallel")
        })
}

fn expected_xs(path: &ToolPath) -> Vec<Vector3> {
    let mut out: Vec<Vector3> = Vec::new();
    for p in &path.poses {
        let x = expected_x(&p.axis, &p.travel, out.last());
        out.push(x);
    }
    out
}

fn assert_direction(got: &Vector3, want: &Vector3, what: &str, i: usize) {
    assert!(
        (got - want).norm() <= DIRECTION_TOL,
        "pose {i}: {what} {got:?} differs from {want:?}"
    );
}

fn assert_position(got: [f64; 3], want: &Point3, k: f64, i: usize) {
    for (g, w) in got.iter().zip((want.coords * k).iter()) {
        assert!(
            (g - w).abs() <= POSITION_TOL_MM,
            "pose {i}: {got:?} vs {want:?}·{k}"
        );
    }
}

fn plain_number(s: &str) -> f64 {
    assert!(
        !s.is_empty()
            && s.bytes()
                .all(|b| b.is_ascii_digit() || b == b'-' || b == b'.'),
        "not a plain fixed-point number: {s:?}"
    );
    s.parse().expect("plain number")
}

// ---------------------------------------------------------------------------------------
// CSV and JSON
// ---------------------------------------------------------------------------------------

#[test]
fn csv_round_trip_keeps_every_pose() {
    let path = awkward_path(400, 7, 3.0);
    let k = 1000.0; // a file in metres
    let text = to_csv(&path, &options(k, None)).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(CSV_HEADER));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), path.poses.len());
    for (i, (row, p)) in rows.iter().zip(&path.poses).enumerate() {
        assert_eq!(row.len(), 14);
        let f: Vec<f64> = row[3..].iter().map(|s| plain_number(s)).collect();
        assert_eq!(row[0], i.to_string());
        assert_eq!(row[1], p.pass.to_string());
        assert_eq!(row[2], p.kind.name());
        assert_position([f[0], f[1], f[2]], &p.position, k, i);
        assert_direction(&Vector3::new(f[3], f[4], f[5]), &p.axis, "axis", i);
        assert_direction(&Vector3::new(f[6], f[7], f[8]), &p.travel, "travel", i);
        assert_eq!(f[9], if p.kind.process_on() { 1.0 } else { 0.0 });
        let speed = if p.kind.process_on() { 400.0 } else { 1250.0 };
        assert!((f[10] - speed).abs() < 1e-9);
    }
}

#[test]
fn json_round_trip_keeps_every_pose_and_describes_itself() {
    let path = awkward_path(300, 11, 2000.0);
    let k = 1.0;
    let text = to_json(&path, &options(k, None)).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["format"], "skinpath-toolpath");
    assert_eq!(doc["version"], 2);
    assert_eq!(doc["varyingSpeed"], false);
    assert_eq!(doc["unit"], "mm");
    assert_eq!(doc["speed"].as_f64(), Some(0.4));
    assert_eq!(doc["linkSpeed"].as_f64(), Some(1.25));
    assert_eq!(doc["poseCount"].as_u64(), Some(300));
    assert_eq!(doc["passCount"].as_u64(), Some(path.pass_count() as u64));
    let notes: Vec<&str> = doc["notes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    assert_eq!(
        notes,
        path.notes.iter().map(String::as_str).collect::<Vec<_>>()
    );
    let poses = doc["poses"].as_array().unwrap();
    assert_eq!(poses.len(), path.poses.len());
    let v3 = |v: &serde_json::Value| {
        let a: Vec<f64> = v
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_f64().unwrap())
            .collect();
        Vector3::new(a[0], a[1], a[2])
    };
    for (i, (j, p)) in poses.iter().zip(&path.poses).enumerate() {
        // Shortest round-trip decimals: exact.
        assert_eq!(v3(&j["position"]), p.position.coords * k, "pose {i}");
        assert_eq!(v3(&j["axis"]), p.axis);
        assert_eq!(v3(&j["travel"]), p.travel);
        assert_eq!(j["kind"], p.kind.name());
        assert_eq!(j["kindCode"].as_u64(), Some(p.kind.code() as u64));
        assert_eq!(j["pass"].as_u64(), Some(p.pass as u64));
        assert_eq!(j["processOn"].as_bool(), Some(p.kind.process_on()));
        assert_eq!(j["speed"].as_f64(), Some(path.move_speed(i) * k));
    }
    // Outside string literals only keys' quotes, punctuation, digits and true/false remain:
    // no exponent notation.
    let mut outside = String::new();
    let mut in_string = false;
    let mut escaped = false;
    for c in text.chars() {
        match (in_string, escaped, c) {
            (true, false, '\\') => escaped = true,
            (true, true, _) => escaped = false,
            (_, _, '"') => in_string = !in_string,
            (false, _, c) => outside.push(c),
            _ => {}
        }
    }
    let outside = outside.replace("true", "").replace("false", "");
    assert!(
        !outside.contains(['e', 'E']),
        "exponent notation in {outside}"
    );
}

// ---------------------------------------------------------------------------------------
// What a controller executes, and the checks every robot program must pass
// ---------------------------------------------------------------------------------------

/// One executed move, as the controller reads it from the program.
#[derive(Debug, Clone)]
struct Exec {
    joint: bool,
    position: [f64; 3],
    rotation: Rotation3<f64>,
    /// Speed in mm/s (RAPID: the speeddata's TCP speed; KRL: `$VEL.CP` × 1000).
    speed: f64,
    exact: bool,
    process_on: bool,
    /// Index of the part (procedure / sub-program) the move is written in.
    part: usize,
}

/// The path's targets as the documented merge rule makes them, computed independently:
/// `(first pose, last pose)` of each run of consecutive poses at one position.
fn expected_targets(path: &ToolPath, k: f64) -> Vec<(usize, usize)> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &path.poses {
        for c in 0..3 {
            lo[c] = lo[c].min(p.position[c]);
            hi[c] = hi[c].max(p.position[c]);
        }
    }
    let extent =
        ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt();
    let tol = (1e-6 * extent).max(1e-5 / k);
    let mut out: Vec<(usize, usize)> = Vec::new();
    for (i, p) in path.poses.iter().enumerate() {
        match out.last_mut() {
            Some(run) if (p.position - path.poses[run.0].position).norm() <= tol => run.1 = i,
            _ => out.push((i, i)),
        }
    }
    out
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// How a program rounds speeds: within `abs` mm/s, or with per-move speeds in RAPID to a
/// step of at most `rel` of the speed and at least 1 mm/s (never below 1 mm/s).
#[derive(Clone, Copy)]
struct SpeedRounding {
    abs: f64,
    rel: Option<f64>,
}

impl SpeedRounding {
    fn accepts(self, got: f64, want: f64) -> bool {
        match self.rel {
            Some(_) if want < 1.0 => got == 1.0,
            Some(rel) => (got - want).abs() <= (0.5f64).max(rel * want / 2.0) + 1e-9,
            None => (got - want).abs() <= self.abs.max(1e-9 * want),
        }
    }
}

/// Checks the executed moves against the path and the rules a controller needs; `speeds` is
/// the rounding of the speeds. Returns the number of merged poses.
fn check_motion(
    path: &ToolPath,
    opts: &ExportOptions,
    exec: &[Exec],
    speeds: SpeedRounding,
) -> usize {
    let k = opts.mm_per_unit;
    let clearance = opts.approach_clearance_mm;
    let targets = expected_targets(path, k);
    let xs = expected_xs(path);
    // A joint move first, process off, exact; a retract last, process off, exact.
    let first = &exec[0];
    assert!(
        first.joint && !first.process_on && first.exact,
        "first move: {first:?}"
    );
    let last = exec.last().unwrap();
    assert!(
        !last.joint && !last.process_on && last.exact,
        "last move: {last:?}"
    );
    let link = path.link_speed * k;
    // Clearance back along the kept (later) axis from the run's position.
    let back = |(f, l): (usize, usize)| {
        let at = path.poses[f].position.coords * k - path.poses[l].axis * clearance;
        Point3::from(at)
    };
    let mut j = 0; // next target
    for (m, e) in exec.iter().enumerate() {
        let rz = e.rotation.matrix().column(2).into_owned();
        let rx = e.rotation.matrix().column(0).into_owned();
        if e.joint {
            // Approach: clearance back along the next target's axis, orientation of its first
            // pose, then the target itself.
            let (f, l) = targets[j];
            assert!(!e.process_on && e.exact, "approach {m}");
            assert_position(e.position, &back((f, l)), 1.0, m);
            assert_direction(&rz, &path.poses[l].axis, "approach axis", m);
            assert!((e.speed - link).abs() <= 1e-3, "approach at the link speed");
            let next = &exec[m + 1];
            assert!(
                !next.joint && !next.process_on,
                "the approach leads to the path"
            );
            assert!(
                m == 0 || exec[m - 1].exact,
                "a clean part follows an exact stop"
            );
            continue;
        }
        let is_target = j < targets.len()
            && (0..3).all(|c| {
                (e.position[c] - path.poses[targets[j].0].position[c] * k).abs() <= POSITION_TOL_MM
            })
            && m > 0;
        if is_target {
            let (f, l) = targets[j];
            assert_position(e.position, &path.poses[f].position, k, m);
            // The later orientation of a merged run is kept.
            assert_direction(&rz, &path.poses[l].axis, "axis (Z)", l);
            assert_direction(&rx, &xs[l], "travel (X)", l);
            let after_approach = exec[m - 1].joint;
            let on = !after_approach && j > 0 && path.poses[f].kind.process_on();
            assert_eq!(e.process_on, on, "target {j} (pose {f}): process state");
            let want = if after_approach && !path.has_varying_speed() {
                link
            } else {
                path.move_speed(f) * k
            };
            assert!(
                speeds.accepts(e.speed, want),
                "target {j}: speed {} vs {want}",
                e.speed
            );
            // Drilled depth: a process pose followed by a retract pose is an exact stop.
            if path.poses[l].kind.process_on()
                && targets
                    .get(j + 1)
                    .is_some_and(|t| path.poses[t.0].kind == PoseKind::Retract)
            {
                assert!(
                    e.exact,
                    "target {j} (pose {l}) before a retract must be exact"
                );
            }
            j += 1;
        } else {
            // A retract: clearance back along the previous target's axis.
            assert!(j > 0, "move {m} is neither a target nor a retract");
            let (f, l) = targets[j - 1];
            assert!(!e.process_on && e.exact, "retract {m}");
            assert_position(e.position, &back((f, l)), 1.0, m);
            assert_direction(&rz, &path.poses[l].axis, "retract axis", m);
            assert!(
                exec.get(m + 1).is_none_or(|n| n.joint),
                "after a retract comes an approach"
            );
        }
    }
    assert_eq!(j, targets.len(), "every target is reached");
    // No fly-by move of zero length; an exact stop wherever the path turns back.
    let cos_limit = (150f64).to_radians().cos();
    for m in 1..exec.len() {
        let d = distance(exec[m].position, exec[m - 1].position);
        assert!(exec[m].exact || d > 0.0, "move {m}: zero-length fly-by");
        if m + 1 < exec.len() {
            let p = |i: usize| Vector3::from(exec[i].position);
            let (a, b) = (p(m) - p(m - 1), p(m + 1) - p(m));
            if a.norm() > 0.0 && b.norm() > 0.0 && a.dot(&b) < cos_limit * a.norm() * b.norm() {
                assert!(exec[m].exact, "move {m} turns back without an exact stop");
            }
        }
    }
    // Parts: each starts clean (an approach) or continues with the process on.
    for m in 1..exec.len() {
        if exec[m].part != exec[m - 1].part && !exec[m].joint {
            assert!(
                exec[m].process_on,
                "a chained part continues with the process on"
            );
        }
    }
    path.poses.len() - targets.len()
}

// ---------------------------------------------------------------------------------------
// ABB RAPID
// ---------------------------------------------------------------------------------------

#[derive(Debug)]
struct RapidMove {
    joint: bool,
    position: [f64; 3],
    q: [f64; 4],
    speed: String,
    zone: String,
}

#[derive(Debug)]
enum RapidItem {
    Move(RapidMove),
    SetDo(String, bool),
    Conf(String),
    Call(String),
    Other(String),
}

/// A RAPID module: its name and its procedures with their statements in order.
#[derive(Debug, Default)]
struct RapidModule {
    name: String,
    procs: Vec<(String, Vec<RapidItem>)>,
    declarations: Vec<String>,
}

fn parse_robtarget_move(stmt: &str, tool: &str) -> RapidMove {
    let s: String = stmt.chars().filter(|c| !c.is_whitespace()).collect();
    let (joint, rest) = match (s.strip_prefix("MoveL[["), s.strip_prefix("MoveJ[[")) {
        (Some(r), _) => (false, r),
        (_, Some(r)) => (true, r),
        _ => panic!("MoveL/MoveJ [[ in {stmt}"),
    };
    let (pos, rest) = rest.split_once("],[").unwrap();
    let (quat, rest) = rest.split_once("],[").unwrap();
    let (conf, rest) = rest.split_once("],[").unwrap();
    let (ext, rest) = rest.split_once("]],").unwrap();
    assert_eq!(conf, "0,0,0,0");
    assert_eq!(ext, "9E9,9E9,9E9,9E9,9E9,9E9");
    let nums = |s: &str| s.split(',').map(plain_number).collect::<Vec<f64>>();
    let p = nums(pos);
    let q = nums(quat);
    let args: Vec<&str> = rest.trim_end_matches(';').split(',').collect();
    assert_eq!(args.len(), 3, "{stmt}");
    assert_eq!(args[2], tool);
    RapidMove {
        joint,
        position: [p[0], p[1], p[2]],
        q: [q[0], q[1], q[2], q[3]],
        speed: args[0].into(),
        zone: args[1].into(),
    }
}

fn parse_rapid(text: &str, tool: &str) -> RapidModule {
    let mut module = RapidModule::default();
    let mut buffer = String::new();
    let mut in_proc = false;
    for raw in text.lines() {
        assert!(raw.len() <= 80, "line longer than 80 characters: {raw}");
        assert!(raw.is_ascii() && !raw.contains('\t'));
        let line = raw.split('!').next().unwrap().trim();
        if line.is_empty() {
            continue;
        }
        if buffer.is_empty() {
            if let Some(name) = line.strip_prefix("MODULE ") {
                module.name = name.into();
                continue;
            }
            if let Some(name) = line.strip_prefix("PROC ") {
                let name = name.strip_suffix("()").expect("PROC name()");
                module.procs.push((name.into(), Vec::new()));
                in_proc = true;
                continue;
            }
            if line == "ENDPROC" {
                in_proc = false;
                continue;
            }
            if line == "ENDMODULE" {
                continue;
            }
        }
        buffer.push_str(line);
        buffer.push(' ');
        if line.ends_with(';') {
            let stmt = buffer.trim().to_string();
            buffer.clear();
            if !in_proc {
                module.declarations.push(stmt);
                continue;
            }
            let item = if stmt.starts_with("MoveL ") || stmt.starts_with("MoveJ ") {
                RapidItem::Move(parse_robtarget_move(&stmt, tool))
            } else if let Some(rest) = stmt.strip_prefix("SetDO ") {
                let (signal, value) = rest.trim_end_matches(';').split_once(',').unwrap();
                RapidItem::SetDo(signal.trim().into(), value.trim() == "1")
            } else if stmt.starts_with("ConfL\\") || stmt.starts_with("ConfJ\\") {
                RapidItem::Conf(stmt.trim_end_matches(';').into())
            } else if stmt
                .split(';')
                .next()
                .unwrap()
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_')
            {
                RapidItem::Call(stmt.trim_end_matches(';').into())
            } else {
                RapidItem::Other(stmt)
            };
            module.procs.last_mut().unwrap().1.push(item);
        }
    }
    assert!(buffer.is_empty(), "unterminated statement {buffer}");
    assert!(text.ends_with("ENDMODULE\n"));
    module
}

fn rotation_from_quaternion(q: [f64; 4]) -> Rotation3<f64> {
    let uq = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
    uq.to_rotation_matrix()
}

/// Runs the RAPID program as a controller would: the entry routine's calls in order, each
/// procedure's statements in order, speeds and zones looked up in the declarations. Checks
/// everything the path implies and returns the number of procedures.
fn check_rapid(path: &ToolPath, opts: &ExportOptions, max_moves: usize) -> usize {
    let files = rapid_files(path, opts).unwrap();
    let texts = to_rapid(path, opts).unwrap();
    assert_eq!(
        files.iter().map(|f| &f.text).collect::<Vec<_>>(),
        texts.iter().collect::<Vec<_>>()
    );
    let o = &opts.rapid;
    let tool = format!("{}\\WObj:={}", o.tool, o.work_object);
    let modules: Vec<RapidModule> = texts.iter().map(|t| parse_rapid(t, &tool)).collect();
    for (f, m) in files.iter().zip(&modules) {
        assert_eq!(f.file_name, format!("{}.mod", m.name));
    }
    let main = &modules[0];
    assert_eq!(main.name, opts.name);
    let decl = main.declarations.join("\n");
    assert!(decl.contains(&format!("PERS tooldata {} :=", o.tool)));
    assert!(decl.contains(&format!("PERS wobjdata {} :=", o.work_object)));
    // speeddata name → TCP speed (mm/s).
    let mut speeds = std::collections::HashMap::new();
    for d in &main.declarations {
        if let Some(rest) = d.strip_prefix("CONST speeddata ") {
            let (name, value) = rest.split_once(" := [").unwrap();
            let v = plain_number(value.split(',').next().unwrap());
            assert!(speeds.insert(name.to_string(), v).is_none(), "{name} twice");
        }
    }
    let k = opts.mm_per_unit;
    assert!((speeds["v_process"] - path.speed * k).abs() < 1e-3);
    assert!((speeds["v_link"] - path.link_speed * k).abs() < 1e-3);
    assert!(speeds.len() <= 2 + 100, "bounded speeddata count");

    let procs: std::collections::HashMap<&str, &Vec<RapidItem>> = modules
        .iter()
        .flat_map(|m| m.procs.iter().map(|(n, items)| (n.as_str(), items)))
        .collect();
    let mut calls = Vec::new();
    let mut exec = Vec::new();
    let mut signal_on: Option<bool> = None;
    let (mut conf_l, mut conf_j) = (None::<String>, None::<String>);
    let want_conf = if o.config_check { "On" } else { "Off" };
    for item in procs[o.entry.as_str()] {
        let RapidItem::Call(name) = item else {
            panic!("unexpected in the entry routine: {item:?}")
        };
        calls.push(name.clone());
        let part = calls.len() - 1;
        let body = procs[name.as_str()];
        let count = body
            .iter()
            .filter(|s| matches!(s, RapidItem::Move(m) if !m.joint))
            .count();
        // Path moves within the budget; the approach and retract come on top.
        assert!(
            count <= max_moves + 1 && count > 0,
            "{name} has {count} moves"
        );
        let mut reset_here = false;
        let mut part_moves = 0;
        for item in body {
            match item {
                RapidItem::SetDo(signal, v) => {
                    assert_eq!(signal, &o.process_signal);
                    match signal_on {
                        Some(s) if s == *v => {
                            // Only a clean part's reset (once, to off) may repeat the state.
                            assert!(
                                !v && !reset_here && part_moves == 0,
                                "{name}: redundant SetDO"
                            );
                            reset_here = true;
                        }
                        None => assert!(!v, "the first hook switches the process off"),
                        _ => {}
                    }
                    signal_on = Some(*v);
                }
                RapidItem::Conf(c) => {
                    let (what, state) = c.split_once('\\').unwrap();
                    let slot = if what == "ConfL" {
                        &mut conf_l
                    } else {
                        &mut conf_j
                    };
                    *slot = Some(state.to_string());
                }
                RapidItem::Move(m) => {
                    if m.joint {
                        assert_eq!(conf_j.as_deref(), Some(want_conf), "ConfJ before MoveJ");
                    } else {
                        assert_eq!(conf_l.as_deref(), Some(want_conf), "ConfL before MoveL");
                    }
                    let norm: f64 = m.q.iter().map(|c| c * c).sum();
                    assert!((norm - 1.0).abs() < 1e-8, "quaternion not normalised");
                    let speed = *speeds
                        .get(&m.speed)
                        .unwrap_or_else(|| panic!("speeddata {} not declared", m.speed));
                    let exact = m.zone == "fine";
                    let on = signal_on.expect("signal reset before the first move");
                    let zone = if exact {
                        "fine"
                    } else if on {
                        o.zone_process.as_str()
                    } else {
                        o.zone_link.as_str()
                    };
                    assert_eq!(m.zone, zone);
                    part_moves += 1;
                    exec.push(Exec {
                        joint: m.joint,
                        position: m.position,
                        rotation: rotation_from_quaternion(m.q),
                        speed,
                        exact,
                        process_on: on,
                        part,
                    });
                }
                RapidItem::Call(c) => panic!("nested call {c}"),
                RapidItem::Other(s) => panic!("unexpected statement {s}"),
            }
        }
    }
    // Quaternion signs stay continuous from move to move.
    let mut previous: Option<[f64; 4]> = None;
    for item in calls.iter().flat_map(|c| procs[c.as_str()].iter()) {
        if let RapidItem::Move(m) = item {
            if let Some(p) = previous {
                let dot: f64 = p.iter().zip(&m.q).map(|(a, b)| a * b).sum();
                assert!(dot >= -1e-9, "quaternion sign flipped");
            }
            previous = Some(m.q);
        }
    }
    let expected_calls: Vec<String> = (1..=calls.len())
        .map(|k| format!("{}_{k}", opts.name))
        .collect();
    assert_eq!(calls, expected_calls);
    assert_eq!(
        signal_on,
        Some(false),
        "the program ends with the process off"
    );
    assert_eq!(
        texts.len(),
        if calls.len() == 1 { 1 } else { calls.len() + 1 }
    );
    // Per-move speeds are rounded to the relative step the header states.
    let header = texts[0].replace("\n  ! ", " ");
    let key = "rounded to a step of at most ";
    let rel = header.find(key).map(|at| {
        let rest = &header[at + key.len()..];
        plain_number(rest.split_whitespace().next().unwrap()) / 100.0
    });
    assert_eq!(rel.is_some(), path.has_varying_speed());
    check_motion(path, opts, &exec, SpeedRounding { abs: 1e-3, rel });
    calls.len()
}

#[test]
fn rapid_round_trip_of_awkward_poses_split_into_procedures() {
    let path = awkward_path(500, 3, 2.5);
    for max in [37, 100, 499, 500] {
        let parts = check_rapid(&path, &options(1000.0, Some(max)), max);
        assert!(parts >= 500usize.div_ceil(max), "{parts} parts");
    }
    // Default budget: one procedure, one file.
    assert_eq!(check_rapid(&path, &options(1000.0, None), 5000), 1);
}

#[test]
fn rapid_default_budget_is_5000_moves_per_procedure() {
    let path = awkward_path(5001, 5, 1000.0);
    let parts = check_rapid(&path, &options(1.0, None), 5000);
    assert_eq!(parts, 2);
    let files = rapid_files(&path, &options(1.0, None)).unwrap();
    let names: Vec<&str> = files.iter().map(|f| f.file_name.as_str()).collect();
    assert_eq!(
        names,
        ["skinpath.mod", "skinpath_mod1.mod", "skinpath_mod2.mod"]
    );
}

// ---------------------------------------------------------------------------------------
// KUKA KRL
// ---------------------------------------------------------------------------------------

#[derive(Debug)]
enum KrlItem {
    Move {
        ptp: bool,
        xyz: [f64; 3],
        abc: [f64; 3],
        c_dis: bool,
    },
    Vel(f64),
    Apo(f64),
    Trigger(bool),
    Out(bool),
    Call(String),
    Other(String),
}

fn parse_krl(text: &str) -> (String, Vec<KrlItem>) {
    let mut lines = text
        .lines()
        .map(|l| {
            assert!(l.is_ascii() && !l.contains('\t'));
            l.split(';').next().unwrap().trim()
        })
        .filter(|l| !l.is_empty());
    let def = lines.next().unwrap();
    let name = def
        .strip_prefix("DEF ")
        .and_then(|n| n.strip_suffix("()"))
        .expect("DEF name()")
        .to_string();
    let mut items = Vec::new();
    let mut ended = false;
    for line in lines {
        assert!(!ended, "text after END");
        let motion = line
            .strip_prefix("LIN {")
            .map(|r| (false, r))
            .or_else(|| line.strip_prefix("PTP {").map(|r| (true, r)));
        if line == "END" {
            ended = true;
        } else if let Some((ptp, rest)) = motion {
            let (frame, tail) = rest.split_once('}').unwrap();
            let mut v = [0.0; 6];
            for (j, (field, letter)) in frame
                .split(',')
                .zip(["X", "Y", "Z", "A", "B", "C"])
                .enumerate()
            {
                let (l, value) = field.split_once(' ').unwrap();
                assert_eq!(l, letter);
                v[j] = plain_number(value);
            }
            let c_dis = match tail.trim() {
                "C_DIS" => true,
                "" => false,
                t => panic!("unexpected {t}"),
            };
            items.push(KrlItem::Move {
                ptp,
                xyz: [v[0], v[1], v[2]],
                abc: [v[3], v[4], v[5]],
                c_dis,
            });
        } else if let Some(v) = line.strip_prefix("$VEL.CP = ") {
            items.push(KrlItem::Vel(plain_number(v)));
        } else if let Some(v) = line.strip_prefix("$APO.CDIS = ") {
            items.push(KrlItem::Apo(plain_number(v)));
        } else if let Some(v) = line.strip_prefix("TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[1]=") {
            items.push(KrlItem::Trigger(v == "TRUE"));
        } else if let Some(v) = line.strip_prefix("$OUT[1] = ") {
            items.push(KrlItem::Out(v == "TRUE"));
        } else if let Some(call) = line.strip_suffix("()") {
            items.push(KrlItem::Call(call.into()));
        } else {
            items.push(KrlItem::Other(line.into()));
        }
    }
    assert!(ended, "no END");
    (name, items)
}

fn rotation_from_abc_deg(abc: [f64; 3]) -> Rotation3<f64> {
    let [a, b, c] = abc.map(f64::to_radians);
    Rotation3::from_axis_angle(&Vector3::z_axis(), a)
        * Rotation3::from_axis_angle(&Vector3::y_axis(), b)
        * Rotation3::from_axis_angle(&Vector3::x_axis(), c)
}

/// Runs the KRL program: main's calls, each sub-program in order with its settings. Returns
/// the number of sub-programs and the A/B/C of every move.
fn check_krl(path: &ToolPath, opts: &ExportOptions, max_moves: usize) -> (usize, Vec<[f64; 3]>) {
    let files = krl_files(path, opts).unwrap();
    let texts = to_krl(path, opts).unwrap();
    assert_eq!(
        files.iter().map(|f| &f.text).collect::<Vec<_>>(),
        texts.iter().collect::<Vec<_>>()
    );
    let parsed: Vec<(String, Vec<KrlItem>)> = texts.iter().map(|t| parse_krl(t)).collect();
    for (f, (name, _)) in files.iter().zip(&parsed) {
        assert_eq!(f.file_name, format!("{name}.src"));
        assert!(name.len() <= 24);
    }
    let (main_name, main_items) = &parsed[0];
    assert_eq!(main_name, &opts.name);
    let mut calls = Vec::new();
    for item in main_items {
        match item {
            KrlItem::Call(c) => calls.push(c.clone()),
            other => panic!("unexpected in main: {other:?}"),
        }
    }
    let expected: Vec<String> = (1..=calls.len())
        .map(|k| format!("{}_{k}", opts.name))
        .collect();
    assert_eq!(calls, expected);
    assert_eq!(parsed.len(), calls.len() + 1);

    let o = &opts.krl;
    let init = [
        "BAS(#INITMOV,0)".to_string(),
        format!("$TOOL = TOOL_DATA[{}]", o.tool),
        format!("$LOAD = LOAD_DATA[{}]", o.tool),
        format!("$BASE = BASE_DATA[{}]", o.base),
        "$ORI_TYPE = #VAR".to_string(),
    ];
    let mut state: Option<bool> = None;
    let mut exec = Vec::new();
    let mut abcs = Vec::new();
    for (part, (call, (name, items))) in calls.iter().zip(&parsed[1..]).enumerate() {
        assert_eq!(call, name);
        let (mut vel, mut apo) = (None, None);
        let mut others: Vec<&str> = Vec::new();
        let mut path_moves = 0;
        for item in items {
            match item {
                KrlItem::Vel(v) => {
                    assert_ne!(vel, Some(*v), "redundant $VEL.CP");
                    vel = Some(*v);
                }
                KrlItem::Apo(v) => {
                    assert_ne!(apo, Some(*v), "redundant $APO.CDIS");
                    apo = Some(*v);
                }
                KrlItem::Trigger(v) => {
                    assert_ne!(state, Some(*v), "redundant trigger");
                    state = Some(*v);
                }
                KrlItem::Out(v) => {
                    assert!(!v, "a plain $OUT only resets the process");
                    state = Some(false);
                }
                KrlItem::Other(s) => others.push(s),
                KrlItem::Move {
                    ptp,
                    xyz,
                    abc,
                    c_dis,
                } => {
                    if *ptp {
                        // A clean start: the sub-program initialises itself first.
                        for line in &init {
                            assert!(others.contains(&line.as_str()), "{name}: no {line}");
                        }
                        assert!(others.contains(&"BAS(#VEL_PTP,20)"));
                        assert_eq!(state, Some(false), "PTP with the process off");
                    } else {
                        path_moves += 1;
                    }
                    if !o.unwrap_angles {
                        assert!(abc[0].abs() <= 180.0 && abc[2].abs() <= 180.0, "{abc:?}");
                    }
                    assert!(abc[1].abs() <= 90.0, "{abc:?}");
                    if *c_dis {
                        let on = state == Some(true);
                        let want = if on {
                            o.approximation_process_mm
                        } else {
                            o.approximation_link_mm
                        };
                        assert_eq!(apo, Some(want));
                    }
                    let speed = if *ptp {
                        path.link_speed * opts.mm_per_unit
                    } else {
                        vel.expect("$VEL.CP set") * 1000.0
                    };
                    exec.push(Exec {
                        joint: *ptp,
                        position: *xyz,
                        rotation: rotation_from_abc_deg(*abc),
                        speed,
                        exact: !c_dis,
                        process_on: state.expect("process state set"),
                        part,
                    });
                    abcs.push(*abc);
                }
                KrlItem::Call(c) => panic!("nested call {c}"),
            }
        }
        assert!(
            path_moves <= max_moves + 1 && path_moves > 0,
            "{name}: {path_moves}"
        );
        for s in others {
            assert!(
                init.iter().any(|l| l == s) || s == "BAS(#VEL_PTP,20)",
                "unexpected in {name}: {s}"
            );
        }
    }
    assert_eq!(state, Some(false), "the program ends with the process off");
    // $VEL.CP is written to 1e-6 m/s: within half of that.
    check_motion(
        path,
        opts,
        &exec,
        SpeedRounding {
            abs: 5.1e-4,
            rel: None,
        },
    );
    (calls.len(), abcs)
}

#[test]
fn krl_round_trip_of_awkward_poses_split_into_files() {
    let path = awkward_path(500, 9, 4000.0);
    for max in [1, 37, 499, 500] {
        let (parts, abcs) = check_krl(&path, &options(1.0, Some(max)), max);
        assert!(parts >= 500usize.div_ceil(max));
        // Default: A and C within ±180°, B within ±90° (checked by check_krl too).
        assert!(abcs
            .iter()
            .all(|a| a[0].abs() <= 180.0 && a[1].abs() <= 90.0 && a[2].abs() <= 180.0));
    }
    // Unwrapped on request: A and C never jump by more than 180° unless they would leave
    // ±360°.
    let mut opts = options(1.0, Some(100));
    opts.krl.unwrap_angles = true;
    let (_, abcs) = check_krl(&path, &opts, 100);
    for (j, w) in abcs.windows(2).enumerate() {
        for c in [0, 2] {
            let step = (w[1][c] - w[0][c]).abs();
            assert!(
                step <= 180.0 + 1e-6 || w[0][c].abs() + (360.0 - step) >= 360.0 - 1e-6,
                "move {j}: angle {c} jumps {step}°"
            );
            assert!(w[1][c].abs() < 360.0);
        }
    }
}

#[test]
fn krl_default_budget_is_1400_moves_per_file() {
    let path = awkward_path(2801, 13, 500.0);
    let (parts, _) = check_krl(&path, &options(1.0, None), 1400);
    let names: Vec<String> = krl_files(&path, &options(1.0, None))
        .unwrap()
        .into_iter()
        .map(|f| f.file_name)
        .collect();
    assert_eq!(names.len(), parts + 1);
    assert_eq!(names[0], "skinpath.src");
    assert_eq!(names[parts], format!("skinpath_{parts}.src"));
    assert!(parts >= 3);
}

#[test]
fn krl_keeps_a_through_gimbal_lock_and_unwraps_only_on_request() {
    // Travel along ±Z puts the ZYX angles at B = ∓90°: only A ∓ C is defined, A must stay.
    let down = -Vector3::z();
    let mut poses = Vec::new();
    let push = |poses: &mut Vec<Pose>, axis: Vector3, travel: Vector3| {
        let n = poses.len() as f64;
        poses.push(Pose {
            position: Point3::new(n, (n * 0.1).sin(), 0.0),
            axis,
            travel,
            kind: PoseKind::Pass,
            pass: 0,
        })
    };
    // A rotation about Z of the frame (travel turning in the XY plane, axis down) through
    // 400°: unwrapped, A grows continuously past 180°.
    for d in 0..=80 {
        let t = (d as f64 * 5.0).to_radians();
        push(&mut poses, down, Vector3::new(t.cos(), t.sin(), 0.0));
    }
    let gimbal_start = poses.len();
    push(&mut poses, Vector3::x(), Vector3::z());
    push(&mut poses, Vector3::y(), Vector3::z());
    push(&mut poses, -Vector3::x(), -Vector3::z());
    let path = ToolPath {
        poses,
        speed: 100.0,
        link_speed: 200.0,
        speeds: Vec::new(),
        notes: vec![],
    };
    // Moves: approach, the poses, retract: pose i is move i + 1.
    let mut opts = ExportOptions::default();
    opts.krl.unwrap_angles = true;
    let (_, abcs) = check_krl(&path, &opts, 1400);
    let poses = &abcs[1..abcs.len() - 1];
    for w in poses[..gimbal_start].windows(2) {
        let step = w[1][0] - w[0][0];
        assert!(
            (step - 5.0).abs() < 1e-6 || (step + 355.0).abs() < 1e-6,
            "A steps {step}"
        );
    }
    assert!(
        poses[..gimbal_start].iter().any(|a| a[0] > 180.0),
        "A unwrapped past 180°"
    );
    for j in gimbal_start..poses.len() {
        assert!(
            (poses[j][1].abs() - 90.0).abs() < 1e-6,
            "B = ±90° at gimbal lock"
        );
        assert_eq!(poses[j][0], poses[j - 1][0], "A kept at gimbal lock");
    }
    // By default A and C stay in [−180°, 180°] and still reproduce every pose.
    let (_, abcs) = check_krl(&path, &ExportOptions::default(), 1400);
    assert!(abcs
        .iter()
        .all(|a| a[0].abs() <= 180.0 && a[2].abs() <= 180.0));
}

// ---------------------------------------------------------------------------------------
// Process hooks on realistic shapes
// ---------------------------------------------------------------------------------------

/// Drilling poses: approach, hole, retract per hole, axis into the part, travel along it.
fn drilling_path(holes: usize) -> ToolPath {
    let axis = Vector3::new(0.0, -0.6, -0.8);
    let mut poses = Vec::new();
    for h in 0..holes {
        let hole = Point3::new(h as f64 * 25.0, 0.0, 0.0);
        for (kind, back) in [
            (PoseKind::Approach, 20.0),
            (PoseKind::Pass, 0.0),
            (PoseKind::Retract, 20.0),
        ] {
            poses.push(Pose {
                position: hole - axis * back,
                axis,
                travel: axis,
                kind,
                pass: h as u32,
            });
        }
    }
    ToolPath {
        poses,
        speed: 5.0,
        link_speed: 250.0,
        speeds: Vec::new(),
        notes: vec![format!("Drilling: {holes} holes.")],
    }
}

#[test]
fn process_hooks_appear_exactly_at_state_changes_for_drilling() {
    let path = drilling_path(7);
    // Every hole switches on for the hole move and off for the retract: 7 on, 7 off.
    let rapid = to_rapid(&path, &options(1.0, Some(4))).unwrap().join("\n");
    let procs = rapid.matches("\n  PROC skinpath_").count();
    assert_eq!(rapid.matches("SetDO doProcess,1;").count(), 7);
    assert_eq!(
        rapid.matches("SetDO doProcess,0;").count(),
        7 + procs,
        "7 + the reset at the start of every (clean) part"
    );
    // Every drilled depth is an exact stop: 7 holes + approach and retract of every part.
    assert_eq!(rapid.matches("fine,").count(), 7 + 2 * procs);
    let krl = to_krl(&path, &options(1.0, Some(4))).unwrap().join("\n");
    assert_eq!(krl.matches("DO $OUT[1]=TRUE").count(), 7);
    assert_eq!(krl.matches("DO $OUT[1]=FALSE").count(), 7);
    check_rapid(&path, &options(1.0, Some(4)), 4);
    check_krl(&path, &options(1.0, Some(4)), 4);
}

#[test]
fn a_pass_spanning_a_part_boundary_keeps_the_process_on() {
    // One long pass of 10 moves after a link, cut into parts of 3: one on, one off at the end.
    let mut poses = vec![Pose {
        position: Point3::new(-1.0, 0.0, 0.0),
        axis: -Vector3::z(),
        travel: Vector3::x(),
        kind: PoseKind::Link,
        pass: 0,
    }];
    for i in 0..10 {
        poses.push(Pose {
            position: Point3::new(i as f64, 0.0, 0.0),
            kind: if i == 0 {
                PoseKind::Extension
            } else {
                PoseKind::Pass
            },
            ..poses[0]
        });
    }
    let path = ToolPath {
        poses,
        speed: 400.0,
        link_speed: 800.0,
        speeds: Vec::new(),
        notes: vec![],
    };
    let rapid = to_rapid(&path, &options(1.0, Some(3))).unwrap().join("\n");
    assert_eq!(rapid.matches("SetDO doProcess,1;").count(), 1);
    assert_eq!(rapid.matches("SetDO doProcess,0;").count(), 2);
    let krl = to_krl(&path, &options(1.0, Some(3))).unwrap();
    assert_eq!(krl.join("\n").matches("$OUT[1]=TRUE").count(), 1);
    // Parts of 3 moves inside one pass are chained: only the first starts clean.
    assert_eq!(krl.join("\n").matches("\n  PTP {").count(), 1);
    assert!(krl.last().unwrap().contains("DO $OUT[1]=FALSE\n"));
    check_rapid(&path, &options(1.0, Some(3)), 3);
    check_krl(&path, &options(1.0, Some(3)), 3);
}

// ---------------------------------------------------------------------------------------
// Options, errors, text properties
// ---------------------------------------------------------------------------------------

fn option_error(result: Result<impl std::fmt::Debug, ToolPathError>) -> &'static str {
    match result {
        Err(ToolPathError::BadOption { name, why }) => {
            let message = ToolPathError::BadOption { name, why }.to_string();
            assert!(message.contains(name), "{message}");
            name
        }
        other => panic!("expected a BadOption error, got {other:?}"),
    }
}

#[test]
fn bad_options_are_refused_naming_the_option() {
    let path = drilling_path(2);
    for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let o = options(k, None);
        assert_eq!(option_error(to_csv(&path, &o)), "mmPerUnit");
        assert_eq!(option_error(to_json(&path, &o)), "mmPerUnit");
        assert_eq!(option_error(to_rapid(&path, &o)), "mmPerUnit");
        assert_eq!(option_error(to_krl(&path, &o)), "mmPerUnit");
    }
    assert_eq!(
        option_error(to_csv(&path, &options(1e308, None))),
        "mmPerUnit"
    );
    let o = options(1.0, Some(0));
    assert_eq!(option_error(to_rapid(&path, &o)), "maxMoves");
    assert_eq!(option_error(to_krl(&path, &o)), "maxMoves");
    // (name, valid for RAPID, valid for KRL)
    for (name, rapid_ok, krl_ok) in [
        ("", false, false),
        ("1path", false, false),
        ("my-path", false, false),
        ("my path", false, false),
        ("pässe", false, false),
        ("MODULE", false, true),
        ("Endproc", false, true),
        ("end", true, false),
        ("lin", true, false),
        ("a_very_long_program_name_x", true, false), // 26 + "_1": fits 32, not 24
        ("a_very_long_program_name_for_rapid", false, false),
        ("Path_2", true, true),
    ] {
        let o = ExportOptions {
            name: name.into(),
            ..ExportOptions::default()
        };
        for (ok, result) in [(rapid_ok, to_rapid(&path, &o)), (krl_ok, to_krl(&path, &o))] {
            if ok {
                assert!(result.is_ok(), "{name:?}: {result:?}");
            } else {
                assert_eq!(option_error(result), "name", "{name:?}");
            }
        }
        assert!(to_csv(&path, &o).is_ok() && to_json(&path, &o).is_ok());
    }
    // A name that fits alone but not with the part suffix.
    let o = ExportOptions {
        name: "x".repeat(23),
        max_moves: Some(1),
        ..ExportOptions::default()
    };
    assert_eq!(option_error(to_krl(&path, &o)), "name");
    let mut o = ExportOptions::default();
    o.rapid.zone_process = "z 1".into();
    assert_eq!(option_error(to_rapid(&path, &o)), "rapidZoneProcess");
    let mut o = ExportOptions::default();
    o.rapid.work_object = o.rapid.tool.clone();
    assert_eq!(option_error(to_rapid(&path, &o)), "rapidWorkObject");
    let mut o = ExportOptions::default();
    o.rapid.process_signal = "PROC".into();
    assert_eq!(option_error(to_rapid(&path, &o)), "rapidSignal");
    let mut o = ExportOptions::default();
    o.krl.process_output = 0;
    assert_eq!(option_error(to_krl(&path, &o)), "krlOutput");
    let mut o = ExportOptions::default();
    o.krl.approximation_link_mm = f64::NAN;
    assert_eq!(option_error(to_krl(&path, &o)), "krlApproximationLinkMm");
    // Options of one robot do not affect the other.
    assert!(to_krl(&path, &{
        let mut o = ExportOptions::default();
        o.rapid.entry = "9".into();
        o
    })
    .is_ok());
}

#[test]
fn empty_and_invalid_paths_are_refused() {
    let empty = ToolPath {
        poses: vec![],
        speed: 1.0,
        link_speed: 1.0,
        speeds: Vec::new(),
        notes: vec![],
    };
    let o = ExportOptions::default();
    assert_eq!(to_csv(&empty, &o), Err(ToolPathError::Empty));
    assert_eq!(to_json(&empty, &o), Err(ToolPathError::Empty));
    assert_eq!(to_rapid(&empty, &o), Err(ToolPathError::Empty));
    assert_eq!(to_krl(&empty, &o), Err(ToolPathError::Empty));
    assert_eq!(
        ToolPathError::Empty.to_string(),
        "the tool path has no poses"
    );
    let mut bad = drilling_path(1);
    bad.poses[1].position.y = f64::NAN;
    assert!(matches!(
        to_rapid(&bad, &o),
        Err(ToolPathError::BadPose { index: 1, .. })
    ));
    let mut bad = drilling_path(1);
    bad.speed = 0.0;
    assert!(matches!(to_krl(&bad, &o), Err(ToolPathError::BadSpeed(_))));
}

#[test]
fn text_is_deterministic_with_the_chosen_line_endings() {
    let path = awkward_path(60, 21, 10.0);
    let lf = options(25.4, Some(25));
    let crlf = ExportOptions {
        line_ending: LineEnding::CrLf,
        ..lf.clone()
    };
    let all = |o: &ExportOptions| {
        let mut v = vec![to_csv(&path, o).unwrap(), to_json(&path, o).unwrap()];
        v.extend(to_rapid(&path, o).unwrap());
        v.extend(to_krl(&path, o).unwrap());
        v
    };
    let a = all(&lf);
    assert_eq!(a, all(&lf));
    for (l, c) in a.iter().zip(all(&crlf)) {
        assert!(!l.contains('\r'));
        assert_eq!(l.replace('\n', "\r\n"), c);
    }
    // Notes reach the robot programs as ASCII comments and the JSON verbatim.
    assert!(a[2].contains("! Spray plan: b = 120 mm, h = 250 mm, alpha = 40 deg, thickness 30 um."));
    let krl_main = a.iter().find(|t| t.starts_with("DEF skinpath()")).unwrap();
    assert!(krl_main.contains("; Spray plan: b = 120 mm"));
    check_rapid(&path, &lf, 25);
    check_krl(&path, &lf, 25);
}

/// FNV-1a, 64 bit: a fingerprint of the exported text.
fn fnv1a(texts: &[String]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for t in texts {
        for b in t.bytes().chain([0]) {
            h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

#[test]
fn exports_are_bit_identical_natively_and_in_webassembly() {
    // Built with arithmetic and square roots only (correctly rounded everywhere), so the
    // input is the same on every platform; the exports must then match to the byte.
    let mut rng = Rng(2024);
    let mut poses = Vec::new();
    for i in 0..200u32 {
        let mut v = || Vector3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5);
        let axis = match i % 5 {
            0 => -Vector3::z(),
            _ => v().normalize(),
        };
        let travel = match i % 7 {
            0 => axis,
            _ => axis.cross(&v()).normalize(),
        };
        poses.push(Pose {
            position: Point3::from(v() * 3000.0),
            axis,
            travel,
            kind: PoseKind::ALL[i as usize % 7],
            pass: i / 10,
        });
    }
    let path = ToolPath {
        poses,
        speed: 350.0,
        link_speed: 900.0,
        speeds: Vec::new(),
        notes: vec!["fingerprint".into()],
    };
    let o = options(1.0, Some(64));
    let mut texts = vec![to_csv(&path, &o).unwrap(), to_json(&path, &o).unwrap()];
    texts.extend(to_rapid(&path, &o).unwrap());
    texts.extend(to_krl(&path, &o).unwrap());
    check_rapid(&path, &o, 64);
    check_krl(&path, &o, 64);
    // Regenerate (after reviewing the text) with `cargo test --test toolpath bit_identical`:
    // the failure message prints the new value.
    assert_eq!(fnv1a(&texts), 6845238506554583285, "fingerprint");
}

// ---------------------------------------------------------------------------------------
// The planners' own paths: drilling example, spray on a plate and a cylinder panel (both
// sides), geodesic passes, a long split plan
// ---------------------------------------------------------------------------------------

/// Both robot programs checked the way a controller reads them, plus the figures a header
/// reports; returns (merged poses, exact stops inside the path) from the RAPID header.
fn check_both(what: &str, path: &ToolPath, opts: &ExportOptions, max: usize) -> (usize, usize) {
    check_rapid(path, opts, max);
    check_krl(path, opts, max);
    let main = &to_rapid(path, opts).unwrap()[0];
    let figure = |after: &str| {
        main.find(after).map_or(0, |at| {
            let before = &main[..at];
            let word = before.trim_end().rsplit(' ').next().unwrap();
            word.parse::<usize>().unwrap()
        })
    };
    let merged = figure(" zero-length moves removed");
    let stops = figure(" inside the path");
    println!(
        "{what}: {} poses, {merged} zero-length moves merged, {stops} exact stops inside",
        path.poses.len()
    );
    (merged, stops)
}

/// `v` as the programs write a position: 6 decimals, trailing zeros dropped.
fn fixed6(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

fn spray_params(spacing: f64) -> skinpath::spray::SprayParams {
    skinpath::spray::SprayParams {
        spacing,
        standoff: 100.0,
        speed: 100.0,
        flow_rate: 1000.0,
        cone_angle: 2.0 * (0.5f64).atan(),
        transition_angle: 20f64.to_radians(),
        efficiency: 1.0,
        resolution: Some(10.0),
        ..skinpath::spray::SprayParams::default()
    }
}

fn spray_path(m: &skinpath::mesh::ImportedMesh, spacing: f64) -> ToolPath {
    let faces: Vec<u32> = (0..m.mesh.triangle_count() as u32).collect();
    skinpath::spray::plan_spray(
        &m.mesh,
        &m.adjacency,
        &m.geometry,
        &faces,
        &spray_params(spacing),
        &mut |_, _| {},
    )
    .unwrap()
    .path
}

/// Cylinder panel of radius 300 mm over ±40°, 600 mm long; `outside` picks the convex side
/// (normals outwards), else the concave one (winding reversed).
fn cylinder_panel(outside: bool) -> skinpath::mesh::ImportedMesh {
    let mut tris = common::grid(12, 24, false, |u, v| {
        let a = (-40.0 + 80.0 * v).to_radians();
        [300.0 * a.cos(), 300.0 * a.sin(), 600.0 * (1.0 - u)]
    });
    if !outside {
        for t in &mut tris {
            t.swap(1, 2);
        }
    }
    common::import(&common::binary_stl(&tris))
}

#[test]
fn the_drilling_example_stops_exactly_at_every_drilled_depth() {
    use skinpath::drill::{correct_holes, drilling_path, paper_example, CorrectionParams};
    use skinpath::drill::{MeshIndex, Method, PoseParams};
    let ex = paper_example();
    let index = MeshIndex::new(&ex.panel);
    let p = CorrectionParams {
        references: ex.references,
        holes: ex.holes.clone(),
        method: Method::Coons,
        tangent_scale: None,
        extrapolate: false,
    };
    let c = correct_holes(&p, Some(&index)).unwrap();
    let path = drilling_path(&c, &PoseParams::default(), vec![]).unwrap();
    let holes = c.corrected.len();
    for max in [5000, 7] {
        let o = options(1.0, Some(max));
        let (merged, stops) = check_both("drilling example", &path, &o, max);
        assert_eq!((merged, stops), (0, holes), "one exact stop per hole");
        // The depth is written with `fine` / without C_DIS: read back hole by hole.
        let rapid = to_rapid(&path, &o).unwrap().join("\n");
        let krl = to_krl(&path, &o).unwrap().join("\n");
        for hole in &c.corrected {
            let x = fixed6(hole.x);
            let at = rapid.find(&format!("MoveL [[{x},")).expect("hole written");
            let stmt = &rapid[at..at + rapid[at..].find(';').unwrap()];
            assert!(stmt.contains("fine,"), "{stmt}");
            let at = krl.find(&format!("LIN {{X {x},")).expect("hole written");
            let line = krl[at..].lines().next().unwrap();
            assert!(!line.contains("C_DIS"), "{line}");
        }
    }
}

#[test]
fn spray_plans_on_a_plate_and_a_cylinder_panel_run_as_planned() {
    let plate = common::import(&common::binary_stl(&common::grid(8, 4, false, |u, v| {
        [800.0 * u, 400.0 * v, 0.0]
    })));
    let path = spray_path(&plate, 60.0);
    check_both("spray on a plate", &path, &options(1.0, None), 5000);
    for outside in [true, false] {
        let path = spray_path(&cylinder_panel(outside), 50.0);
        let what = if outside { "convex" } else { "concave" };
        let (_, _) = check_both(
            &format!("spray on a cylinder panel, {what} side"),
            &path,
            &options(1.0, None),
            5000,
        );
        // In metres too: the tolerances and the clearance follow the unit.
        let metres = ToolPath {
            poses: path
                .poses
                .iter()
                .map(|p| Pose {
                    position: Point3::from(p.position.coords / 1000.0),
                    ..*p
                })
                .collect(),
            speed: path.speed / 1000.0,
            link_speed: path.link_speed / 1000.0,
            speeds: path.speeds.iter().map(|s| s / 1000.0).collect(),
            notes: vec![],
        };
        check_both(
            "the same in metres",
            &metres,
            &options(1000.0, Some(400)),
            400,
        );
    }
}

#[test]
fn a_long_split_plan_cuts_where_the_process_is_off_and_every_part_runs_alone() {
    let plate = common::import(&common::binary_stl(&common::grid(8, 4, false, |u, v| {
        [800.0 * u, 400.0 * v, 0.0]
    })));
    let path = spray_path(&plate, 20.0);
    let longest_on = path
        .poses
        .split(|p| !p.kind.process_on())
        .map(<[Pose]>::len)
        .max()
        .unwrap();
    let max = longest_on + 5;
    let parts = check_rapid(&path, &options(1.0, Some(max)), max);
    check_krl(&path, &options(1.0, Some(max)), max);
    assert!(parts > 3, "{parts} parts of {} poses", path.poses.len());
    // Every pass fits a part: every part starts clean (joint move, process off) and ends
    // with a retract.
    let krl = krl_files(&path, &options(1.0, Some(max))).unwrap();
    for f in &krl[1..] {
        let ptp = f.text.find("\n  PTP {").expect("a PTP in every part");
        let first_lin = f.text.find("\n  LIN {").unwrap();
        assert!(ptp < first_lin, "{}: PTP first", f.file_name);
        assert!(f.text.contains("BAS(#INITMOV,0)") && f.text.contains("$OUT[1] = FALSE"));
    }
    let rapid = rapid_files(&path, &options(1.0, Some(max))).unwrap();
    for f in &rapid[1..] {
        let text = &f.text;
        let conf = text.find("ConfL\\Off;").expect("ConfL\\Off in every part");
        let movej = text.find("MoveJ ").expect("a MoveJ in every part");
        assert!(conf < movej && movej < text.find("MoveL ").unwrap());
    }
}

#[test]
fn geodesic_passes_on_a_plate_and_a_cylinder_have_no_dwell() {
    use skinpath::geodesic::{geodesic_distance, DistanceParams, GeodesicSource, PathParams};
    let plate = common::import(&common::binary_stl(&common::grid(30, 20, false, |u, v| {
        [150.0 * u, 100.0 * v, 0.0]
    })));
    let tube = common::import(&common::binary_stl(&common::cylinder(50.0, 120.0, 48, 24)));
    let ring: Vec<Point3> = (0..32)
        .map(|i| {
            let a = i as f64 / 32.0 * std::f64::consts::TAU;
            Point3::new(50.0 * a.cos(), 50.0 * a.sin(), 0.0)
        })
        .collect();
    let cases = [
        (
            "geodesic passes on a plate",
            &plate,
            GeodesicSource::Polyline {
                points: vec![Point3::new(0.0, 0.0, 0.0), Point3::new(150.0, 0.0, 0.0)],
                closed: false,
            },
        ),
        (
            "geodesic passes on a cylinder",
            &tube,
            GeodesicSource::Polyline {
                points: ring,
                closed: true,
            },
        ),
    ];
    for (what, m, source) in cases {
        let field = geodesic_distance(
            &m.mesh,
            &m.adjacency,
            &source,
            &DistanceParams::default(),
            &mut |_, _| {},
        )
        .unwrap();
        let params = PathParams {
            spacing: 10.0,
            ..PathParams::default()
        };
        let path = field.tool_path(&m.mesh, &m.adjacency, &params).unwrap();
        check_both(what, &path, &options(1.0, None), 5000);
        check_both(what, &path, &options(1.0, Some(50)), 50);
    }
}

#[test]
fn zero_length_moves_are_merged_keeping_the_later_orientation() {
    // A pass with a reorientation on the spot at every other pose (the process on), a link
    // and a pass start at the same position, and a tiny step below the tolerance.
    let down = -Vector3::z();
    let tilted = Vector3::new(0.3, 0.0, -1.0).normalize();
    let mut poses = Vec::new();
    let pose = |x: f64, axis: Vector3, kind: PoseKind| Pose {
        position: Point3::new(x, 0.0, 0.0),
        axis,
        travel: Vector3::y(),
        kind,
        pass: 0,
    };
    poses.push(pose(0.0, down, PoseKind::Link));
    poses.push(pose(0.0, down, PoseKind::Pass)); // zero length, link then pass
    for i in 1..=10 {
        let x = i as f64 * 10.0;
        poses.push(pose(x, down, PoseKind::Pass));
        poses.push(pose(x, tilted, PoseKind::Pass)); // reorientation on the spot
    }
    poses.push(pose(100.0 + 1e-9, down, PoseKind::Pass)); // below the tolerance
    poses.push(pose(200.0, down, PoseKind::Pass));
    let path = ToolPath {
        poses,
        speed: 100.0,
        link_speed: 500.0,
        speeds: Vec::new(),
        notes: vec![],
    };
    let o = options(1.0, None);
    let (merged, _) = check_both("reorientations on the spot", &path, &o, 5000);
    assert_eq!(merged, 1 + 10 + 1);
    assert_eq!(expected_targets(&path, 1.0).len(), path.poses.len() - 12);
    // CSV and JSON keep every pose: they describe the plan, not a motion.
    assert_eq!(
        to_csv(&path, &o).unwrap().lines().count(),
        path.poses.len() + 1
    );
}

#[test]
fn reversals_get_exact_stops_and_gentle_turns_do_not() {
    // A zig-zag whose corners turn by 160° (exact) and a bend of 90° (fly-by).
    let mut poses = Vec::new();
    let mut push = |x: f64, y: f64| {
        poses.push(Pose {
            position: Point3::new(x, y, 0.0),
            axis: -Vector3::z(),
            travel: Vector3::x(),
            kind: PoseKind::Pass,
            pass: 0,
        })
    };
    let t = 10f64.to_radians().tan() * 100.0; // 100 mm legs, 20° apart: a 160° turn
    push(0.0, 0.0);
    push(100.0, 0.0);
    push(0.0, t);
    push(100.0, 2.0 * t);
    push(100.0, 2.0 * t + 100.0); // 90°
    push(200.0, 2.0 * t + 100.0);
    let path = ToolPath {
        poses,
        speed: 100.0,
        link_speed: 500.0,
        speeds: Vec::new(),
        notes: vec![],
    };
    let (_, stops) = check_both("zig-zag", &path, &options(1.0, None), 5000);
    assert_eq!(stops, 2, "the two 160° corners");
    let rapid = to_rapid(&path, &options(1.0, None)).unwrap()[0].clone();
    // Exact: the approach, the two corners and the retract.
    assert_eq!(rapid.matches("fine,").count(), 4);
}

#[test]
fn per_move_speeds_reach_every_export() {
    let mut path = awkward_path(300, 31, 500.0);
    // 60 distinct speeds from 100 to 395.59 mm/s, not on whole mm/s.
    path.speeds = (0..path.poses.len())
        .map(|i| 100.0 + 5.01 * (i % 60) as f64)
        .collect();
    let o = options(1.0, Some(120));
    // CSV and JSON: the speed of the move arriving at each pose.
    let csv = to_csv(&path, &o).unwrap();
    for (i, line) in csv.lines().skip(1).enumerate() {
        let v = plain_number(line.rsplit(',').next().unwrap());
        assert!((v - path.speeds[i]).abs() < 1e-6, "pose {i}");
    }
    let doc: serde_json::Value = serde_json::from_str(&to_json(&path, &o).unwrap()).unwrap();
    assert_eq!(doc["varyingSpeed"], true);
    for (i, p) in doc["poses"].as_array().unwrap().iter().enumerate() {
        assert_eq!(p["speed"].as_f64(), Some(path.speeds[i]));
    }
    // RAPID within 0.5 % (0.5 mm/s here), KRL within 5e-4 mm/s: check_* read the speed
    // the controller uses for every move back.
    check_rapid(&path, &o, 120);
    check_krl(&path, &o, 120);
    let main = &to_rapid(&path, &o).unwrap()[0];
    assert!(
        main.replace("\n  ! ", " ").contains("at most 0.5 % of it"),
        "{main}"
    );
    assert!(main.contains("CONST speeddata v_100 :=") && main.contains("v_396 :="));
    // KRL writes $VEL.CP only where it changes (check_krl refuses a redundant one).
    // Many distinct speeds: the step coarsens so at most 100 speeddata are declared, and
    // slow moves keep their precision (the step is relative).
    path.speeds = (0..path.poses.len())
        .map(|i| 1.0 + 7.3 * i as f64)
        .collect();
    let texts = to_rapid(&path, &o).unwrap();
    let declared = texts[0].matches("CONST speeddata v_").count();
    assert!(declared <= 2 + 100 && declared > 20, "{declared}");
    assert!(texts[0].contains("CONST speeddata v_1 :=") && texts[0].contains("v_8 :="));
    check_rapid(&path, &o, 120);
    // A speed below 1 mm/s still moves, at 1 mm/s.
    path.speeds = vec![0.2; path.poses.len()];
    check_rapid(&path, &o, 120);
    // Twelve decades still fit the bound; a speed beyond any robot is refused, naming it.
    path.speeds = (0..path.poses.len())
        .map(|i| 10f64.powi(i as i32 % 13))
        .collect();
    check_rapid(&path, &o, 120);
    path.speeds[7] = 1e13;
    assert_eq!(option_error(to_rapid(&path, &o)), "speeds");
}

#[test]
fn reserved_and_predefined_names_are_refused_case_insensitively() {
    let path = drilling_path(2);
    let rapid_only = [
        "MoveL",
        "MOVEJ",
        "movec",
        "SetDO",
        "WaitTime",
        "ConfL",
        "tool0",
        "WOBJ0",
        "load0",
        "v5",
        "v1000",
        "V7000",
        "vmax",
        "z0",
        "Z10",
        "z200",
        "fine",
        "Module",
        "proc",
        "if",
        "Offs",
        "robtarget",
        "v_process",
    ];
    let krl_only = [
        "BAS",
        "bas",
        "Ini",
        "TOOL_DATA",
        "base_data",
        "LOAD_DATA",
        "ptp",
        "Lin",
        "CIRC",
        "Def",
        "END",
        "SPLINE",
        "FRAME",
        "E6POS",
        "IR_STOPM",
    ];
    for name in rapid_only.iter().chain(&krl_only) {
        let o = ExportOptions {
            name: name.to_string(),
            ..ExportOptions::default()
        };
        let r = to_rapid(&path, &o);
        let k = to_krl(&path, &o);
        if rapid_only.contains(name) {
            assert_eq!(option_error(r), "name", "{name}");
        } else {
            assert!(r.is_ok(), "{name} is not RAPID's");
        }
        if krl_only.contains(name) || *name == "if" {
            assert_eq!(option_error(k), "name", "{name}");
        } else {
            assert!(k.is_ok(), "{name} is not KRL's");
        }
    }
    // The data names RAPID declares or calls are checked the same way.
    for (set, option) in [
        (0, "rapidTool"),
        (1, "rapidWorkObject"),
        (2, "rapidSignal"),
        (3, "rapidEntry"),
    ] {
        for bad in ["tool0", "WObj0", "MoveL", "v_link", "z50"] {
            let mut o = ExportOptions::default();
            let slot = match set {
                0 => &mut o.rapid.tool,
                1 => &mut o.rapid.work_object,
                2 => &mut o.rapid.process_signal,
                _ => &mut o.rapid.entry,
            };
            *slot = bad.into();
            assert_eq!(option_error(to_rapid(&path, &o)), option, "{bad}");
        }
    }
    // Zones name the controller's zonedata: predefined names are fine, reserved words not.
    let mut o = ExportOptions::default();
    o.rapid.zone_process = "z5".into();
    o.rapid.zone_link = "fine".into();
    assert!(to_rapid(&path, &o).is_ok());
    o.rapid.zone_link = "ENDPROC".into();
    assert_eq!(option_error(to_rapid(&path, &o)), "rapidZoneLink");
    // The message names the clash.
    let o = ExportOptions {
        name: "tool0".into(),
        ..ExportOptions::default()
    };
    let message = to_rapid(&path, &o).unwrap_err().to_string();
    assert!(
        message.contains("tool0") && message.contains("predefined"),
        "{message}"
    );
}

#[test]
fn configuration_check_and_clearance_are_options() {
    let path = drilling_path(3);
    let mut o = ExportOptions::default();
    let text = to_rapid(&path, &o).unwrap().join("\n");
    assert!(text.contains("ConfJ\\Off;") && text.contains("ConfL\\Off;"));
    o.rapid.config_check = true;
    let text = to_rapid(&path, &o).unwrap().join("\n");
    assert!(text.contains("ConfJ\\On;") && text.contains("ConfL\\On;"));
    assert!(!text.contains("\\Off;"));
    check_rapid(&path, &o, 5000);
    // Clearance in mm whatever the unit: read back by check_motion.
    for clearance in [1.0, 12.5, 300.0] {
        let o = ExportOptions {
            approach_clearance_mm: clearance,
            mm_per_unit: 25.4,
            ..ExportOptions::default()
        };
        check_rapid(&path, &o, 5000);
        check_krl(&path, &o, 1400);
    }
    for bad in [0.0, 0.5, -1.0, f64::NAN, f64::INFINITY] {
        let o = ExportOptions {
            approach_clearance_mm: bad,
            ..ExportOptions::default()
        };
        assert_eq!(option_error(to_rapid(&path, &o)), "approachClearanceMm");
        assert_eq!(option_error(to_krl(&path, &o)), "approachClearanceMm");
    }
}

/// The shared real models: spray plans on the largest patch (the paper's set-up, metres),
/// exported whole and split, read back as a controller runs them.
#[cfg(not(target_arch = "wasm32"))]
#[test]
#[ignore = "reads the shared real models: cargo test --release --test toolpath -- --ignored --nocapture"]
fn real_models_export_programs_that_run_as_planned() {
    use skinpath::segment::{segment, SegmentParams};
    for name in ["bwb_4464_pygeo_ascii.stl", "wingbody_79868_flow360.stl"] {
        let m = common::import(&common::model(name));
        let seg = segment(&m.adjacency, &m.geometry, &SegmentParams::default()).unwrap();
        let faces: Vec<u32> = seg.faces_of(0).map(|f| f as u32).collect();
        let mm = 1e-3;
        let p = skinpath::spray::SprayParams {
            spacing: 0.09,
            standoff: 250.0 * mm,
            speed: 400.0 * mm,
            flow_rate: 150.0 * 1e-6 / 60.0,
            cone_angle: 40f64.to_radians(),
            transition_angle: 20f64.to_radians(),
            efficiency: 0.6,
            resolution: Some(0.04),
            ..skinpath::spray::SprayParams::default()
        };
        let plan = skinpath::spray::plan_spray(
            &m.mesh,
            &m.adjacency,
            &m.geometry,
            &faces,
            &p,
            &mut |_, _| {},
        )
        .unwrap();
        let path = &plan.path;
        check_both(name, path, &options(1000.0, None), 5000);
        check_both(name, path, &options(1000.0, Some(1000)), 1000);
        let (_, abcs) = check_krl(path, &options(1000.0, None), 1400);
        let mut unwrapped = options(1000.0, None);
        unwrapped.krl.unwrap_angles = true;
        let (_, wide) = check_krl(path, &unwrapped, 1400);
        let outside = |a: &[[f64; 3]]| {
            a.iter()
                .filter(|x| x[0].abs() > 180.0 || x[2].abs() > 180.0)
                .count()
        };
        println!(
            "{name}: KRL frames with A or C beyond ±180°: {} by default, {} unwrapped (of {})",
            outside(&abcs),
            outside(&wide),
            abcs.len()
        );
    }
}
