//! Tool-path exports through the public API: every format is parsed back by the small parsers
//! below and every pose must survive (position, tool axis, travel direction, kind, process
//! state, speed), with the parts of the robot programs called in order.

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

/// The process state of the move to pose `i` in the robot programs.
fn expected_on(path: &ToolPath, i: usize) -> bool {
    i > 0 && path.poses[i].kind.process_on()
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
    assert_eq!(doc["version"], 1);
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
// ABB RAPID
// ---------------------------------------------------------------------------------------

#[derive(Debug)]
struct RapidMove {
    position: [f64; 3],
    q: [f64; 4],
    speed: String,
    zone: String,
}

#[derive(Debug)]
enum RapidItem {
    Move(RapidMove),
    SetDo(String, bool),
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

fn parse_robtarget_move(stmt: &str) -> RapidMove {
    let s: String = stmt.chars().filter(|c| !c.is_whitespace()).collect();
    let rest = s.strip_prefix("MoveL[[").expect("MoveL [[");
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
    assert_eq!(args[2], "tSkinpath\\WObj:=wSkinpath");
    RapidMove {
        position: [p[0], p[1], p[2]],
        q: [q[0], q[1], q[2], q[3]],
        speed: args[0].into(),
        zone: args[1].into(),
    }
}

fn parse_rapid(text: &str) -> RapidModule {
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
            let item = if stmt.starts_with("MoveL ") {
                RapidItem::Move(parse_robtarget_move(&stmt))
            } else if let Some(rest) = stmt.strip_prefix("SetDO ") {
                let (signal, value) = rest.trim_end_matches(';').split_once(',').unwrap();
                RapidItem::SetDo(signal.trim().into(), value.trim() == "1")
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
/// procedure's statements in order. Checks everything the path implies and returns the number
/// of procedures.
fn check_rapid(path: &ToolPath, opts: &ExportOptions, max_moves: usize) -> usize {
    let files = rapid_files(path, opts).unwrap();
    let texts = to_rapid(path, opts).unwrap();
    assert_eq!(
        files.iter().map(|f| &f.text).collect::<Vec<_>>(),
        texts.iter().collect::<Vec<_>>()
    );
    let modules: Vec<RapidModule> = texts.iter().map(|t| parse_rapid(t)).collect();
    for (f, m) in files.iter().zip(&modules) {
        assert_eq!(f.file_name, format!("{}.mod", m.name));
    }
    let main = &modules[0];
    assert_eq!(main.name, opts.name);
    let decl = main.declarations.join("\n");
    assert!(decl.contains("PERS tooldata tSkinpath :="));
    assert!(decl.contains("PERS wobjdata wSkinpath :="));
    let k = opts.mm_per_unit;
    let speed_decl = |name: &str| {
        let stmt = main
            .declarations
            .iter()
            .find(|d| d.starts_with(&format!("CONST speeddata {name} := [")))
            .unwrap();
        let inner = stmt.split('[').nth(1).unwrap();
        plain_number(inner.split(',').next().unwrap())
    };
    assert!((speed_decl("v_process") - path.speed * k).abs() < 1e-3);
    assert!((speed_decl("v_link") - path.link_speed * k).abs() < 1e-3);

    let procs: std::collections::HashMap<&str, &Vec<RapidItem>> = modules
        .iter()
        .flat_map(|m| m.procs.iter().map(|(n, items)| (n.as_str(), items)))
        .collect();
    // Expand the entry routine's calls into one statement stream.
    let mut calls = Vec::new();
    let mut stream: Vec<&RapidItem> = Vec::new();
    for item in procs["main"] {
        match item {
            RapidItem::Call(name) => {
                calls.push(name.clone());
                let body = procs[name.as_str()];
                let count = body
                    .iter()
                    .filter(|s| matches!(s, RapidItem::Move(_)))
                    .count();
                assert!(count <= max_moves && count > 0, "{name} has {count} moves");
                stream.extend(body.iter());
            }
            RapidItem::SetDo(..) => stream.push(item),
            other => panic!("unexpected in main: {other:?}"),
        }
    }
    let mut moves: Vec<&RapidMove> = Vec::new();
    let mut signal_on: Option<bool> = None;
    let mut state_at_move = Vec::new();
    for item in stream {
        match item {
            RapidItem::SetDo(signal, v) => {
                assert_eq!(signal, "doProcess");
                // A hook only where the state changes (the first one resets it).
                if let Some(s) = signal_on {
                    assert_ne!(s, *v, "redundant SetDO at move {}", moves.len());
                } else {
                    assert!(!v, "the entry routine starts by switching the process off");
                }
                signal_on = Some(*v);
            }
            RapidItem::Move(m) => {
                moves.push(m);
                state_at_move.push(signal_on.expect("signal reset before the first move"));
            }
            RapidItem::Call(c) => panic!("nested call {c}"),
            RapidItem::Other(s) => panic!("unexpected statement {s}"),
        }
    }
    let expected_calls: Vec<String> = (1..=calls.len())
        .map(|k| format!("{}_{k}", opts.name))
        .collect();
    assert_eq!(calls, expected_calls);
    assert_eq!(calls.len(), path.poses.len().div_ceil(max_moves));
    assert_eq!(
        signal_on,
        Some(false),
        "the program ends with the process off"
    );
    assert_eq!(moves.len(), path.poses.len());
    assert_eq!(
        texts.len(),
        if calls.len() == 1 { 1 } else { calls.len() + 1 }
    );

    let xs = expected_xs(path);
    let mut previous_q: Option<[f64; 4]> = None;
    for (i, (m, p)) in moves.iter().zip(&path.poses).enumerate() {
        assert_position(m.position, &p.position, k, i);
        let norm: f64 = m.q.iter().map(|c| c * c).sum();
        assert!(
            (norm - 1.0).abs() < 1e-8,
            "pose {i}: quaternion not normalised"
        );
        let r = rotation_from_quaternion(m.q);
        assert_direction(&r.matrix().column(2).into_owned(), &p.axis, "axis (Z)", i);
        assert_direction(&r.matrix().column(0).into_owned(), &xs[i], "travel (X)", i);
        if let Some(prev) = previous_q {
            let dot: f64 = prev.iter().zip(&m.q).map(|(a, b)| a * b).sum();
            assert!(dot >= -1e-9, "pose {i}: quaternion sign flipped");
        }
        previous_q = Some(m.q);
        let on = expected_on(path, i);
        assert_eq!(state_at_move[i], on, "pose {i}: process state");
        assert_eq!(m.speed, if on { "v_process" } else { "v_link" });
        let zone = if i + 1 == path.poses.len() {
            "fine"
        } else if on {
            "z1"
        } else {
            "z10"
        };
        assert_eq!(m.zone, zone, "pose {i}");
    }
    calls.len()
}

#[test]
fn rapid_round_trip_of_awkward_poses_split_into_procedures() {
    let path = awkward_path(500, 3, 2.5);
    for max in [37, 100, 499, 500] {
        let parts = check_rapid(&path, &options(1000.0, Some(max)), max);
        assert_eq!(parts, 500usize.div_ceil(max));
    }
    // Default budget: one procedure, one file.
    assert_eq!(check_rapid(&path, &options(1000.0, None), 5000), 1);
}

#[test]
fn rapid_default_budget_is_5000_moves_per_procedure() {
    let path = awkward_path(5001, 5, 1000.0);
    assert_eq!(check_rapid(&path, &options(1.0, None), 5000), 2);
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
    Lin {
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
        if line == "END" {
            ended = true;
        } else if let Some(rest) = line.strip_prefix("LIN {") {
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
            items.push(KrlItem::Lin {
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

/// Runs the KRL program: main's settings and calls, each sub-program in order. Returns the
/// number of sub-programs and the A/B/C of every move.
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
    let mut state: Option<bool> = None;
    let mut calls = Vec::new();
    for item in main_items {
        match item {
            KrlItem::Out(v) => {
                assert!(state.is_none() && !v, "main switches the process off once");
                state = Some(*v);
            }
            KrlItem::Call(c) => calls.push(c.clone()),
            KrlItem::Other(s) => assert!(
                [
                    "BAS(#INITMOV,0)",
                    "$TOOL = TOOL_DATA[1]",
                    "$LOAD = LOAD_DATA[1]",
                    "$BASE = BASE_DATA[1]",
                    "$ORI_TYPE = #VAR"
                ]
                .contains(&s.as_str()),
                "unexpected in main: {s}"
            ),
            other => panic!("unexpected in main: {other:?}"),
        }
    }
    let expected: Vec<String> = (1..=calls.len())
        .map(|k| format!("{}_{k}", opts.name))
        .collect();
    assert_eq!(calls, expected);
    assert_eq!(calls.len(), path.poses.len().div_ceil(max_moves));
    assert_eq!(parsed.len(), calls.len() + 1);

    let k = opts.mm_per_unit;
    let xs = expected_xs(path);
    let mut i = 0;
    let mut abcs = Vec::new();
    for (call, (name, items)) in calls.iter().zip(&parsed[1..]) {
        assert_eq!(call, name);
        let first = i;
        let (mut vel, mut apo) = (None, None);
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
                    assert_ne!(state, Some(*v), "redundant trigger before move {i}");
                    state = Some(*v);
                }
                KrlItem::Out(v) => {
                    assert_eq!(i, path.poses.len(), "plain $OUT only after the last move");
                    assert!(!v);
                    state = Some(false);
                }
                KrlItem::Lin { xyz, abc, c_dis } => {
                    let p = &path.poses[i];
                    let on = expected_on(path, i);
                    assert_eq!(state, Some(on), "pose {i}: process state");
                    let speed = if on { path.speed } else { path.link_speed } * k / 1000.0;
                    assert!(
                        (vel.expect("$VEL.CP set") - speed).abs() < 1e-9,
                        "pose {i}: speed"
                    );
                    let last = i + 1 == path.poses.len();
                    assert_eq!(*c_dis, !last);
                    if !last {
                        assert_eq!(apo, Some(if on { 1.0 } else { 10.0 }), "pose {i}");
                    }
                    assert_position(*xyz, &p.position, k, i);
                    let r = rotation_from_abc_deg(*abc);
                    assert_direction(&r.matrix().column(2).into_owned(), &p.axis, "axis (Z)", i);
                    assert_direction(&r.matrix().column(0).into_owned(), &xs[i], "travel (X)", i);
                    assert!(abc[1].abs() <= 90.0);
                    abcs.push(*abc);
                    i += 1;
                }
                other => panic!("unexpected in {name}: {other:?}"),
            }
        }
        assert!(
            i - first <= max_moves && i > first,
            "{name}: {} moves",
            i - first
        );
    }
    assert_eq!(i, path.poses.len());
    assert_eq!(state, Some(false), "the program ends with the process off");
    (calls.len(), abcs)
}

#[test]
fn krl_round_trip_of_awkward_poses_split_into_files() {
    let path = awkward_path(500, 9, 4000.0);
    for max in [1, 37, 499, 500] {
        let (parts, abcs) = check_krl(&path, &options(1.0, Some(max)), max);
        assert_eq!(parts, 500usize.div_ceil(max));
        // Continuity: A and C never jump by more than 180° unless they would leave ±360°.
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
}

#[test]
fn krl_default_budget_is_1400_moves_per_file() {
    let path = awkward_path(2801, 13, 500.0);
    let (parts, _) = check_krl(&path, &options(1.0, None), 1400);
    assert_eq!(parts, 3);
    let names: Vec<String> = krl_files(&path, &options(1.0, None))
        .unwrap()
        .into_iter()
        .map(|f| f.file_name)
        .collect();
    assert_eq!(
        names,
        [
            "skinpath.src",
            "skinpath_1.src",
            "skinpath_2.src",
            "skinpath_3.src"
        ]
    );
}

#[test]
fn krl_keeps_a_through_gimbal_lock_and_unwraps_across_180() {
    // Travel along ±Z puts the ZYX angles at B = ∓90°: only A ∓ C is defined, A must stay.
    let down = -Vector3::z();
    let mut poses = Vec::new();
    let push = |poses: &mut Vec<Pose>, axis: Vector3, travel: Vector3| {
        poses.push(Pose {
            position: Point3::origin(),
            axis,
            travel,
            kind: PoseKind::Pass,
            pass: 0,
        })
    };
    // A rotation about Z of the frame (travel turning in the XY plane, axis down) through
    // 400°: A must grow continuously past 180°.
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
    let (_, abcs) = check_krl(&path, &ExportOptions::default(), 1400);
    for w in abcs[..gimbal_start].windows(2) {
        let step = w[1][0] - w[0][0];
        assert!(
            (step - 5.0).abs() < 1e-6 || (step + 355.0).abs() < 1e-6,
            "A steps {step}"
        );
    }
    assert!(
        abcs[..gimbal_start].iter().any(|a| a[0] > 180.0),
        "A unwrapped past 180°"
    );
    for j in gimbal_start..abcs.len() {
        assert!(
            (abcs[j][1].abs() - 90.0).abs() < 1e-6,
            "B = ±90° at gimbal lock"
        );
        assert_eq!(abcs[j][0], abcs[j - 1][0], "A kept at gimbal lock");
    }
    // Without unwrapping A and C stay in (−180°, 180°].
    let mut opts = ExportOptions::default();
    opts.krl.unwrap_angles = false;
    let (_, abcs) = check_krl(&path, &opts, 1400);
    assert!(abcs
        .iter()
        .all(|a| a[0] > -180.0 && a[0] <= 180.0 && a[2] > -180.0 && a[2] <= 180.0));
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
    assert_eq!(rapid.matches("SetDO doProcess,1;").count(), 7);
    assert_eq!(
        rapid.matches("SetDO doProcess,0;").count(),
        8,
        "7 + the reset in main"
    );
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
    assert!(krl.last().unwrap().contains("$OUT[1] = FALSE\nEND\n"));
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
    assert_eq!(option_error(to_rapid(&path, &o)), "rapid.zone_process");
    let mut o = ExportOptions::default();
    o.rapid.work_object = o.rapid.tool.clone();
    assert_eq!(option_error(to_rapid(&path, &o)), "rapid.work_object");
    let mut o = ExportOptions::default();
    o.rapid.process_signal = "PROC".into();
    assert_eq!(option_error(to_rapid(&path, &o)), "rapid.process_signal");
    let mut o = ExportOptions::default();
    o.krl.process_output = 0;
    assert_eq!(option_error(to_krl(&path, &o)), "krl.process_output");
    let mut o = ExportOptions::default();
    o.krl.approximation_link_mm = f64::NAN;
    assert_eq!(option_error(to_krl(&path, &o)), "krl.approximation_link_mm");
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
    let krl_main = &a[a.len() - 4]; // main + 3 parts of at most 25 moves
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
    assert_eq!(fnv1a(&texts), 16380081563057754159, "fingerprint");
}
