//! Export options and what every format shares: option checks, number formatting, comment
//! text for robot controllers, and the program model both robot languages write.
//!
//! Source: no paper; the controllers' rules as ABB ("Technical reference manual – RAPID
//!         Instructions, Functions and Data types": zonedata, fine points, MoveJ/MoveL) and
//!         KUKA ("KUKA System Software 8.x", approximate positioning, PTP/LIN) document them:
//!         a fly-by zone shrinks to half the neighbouring segment (a zero-length move is a
//!         stop), a path that turns back inside a zone never reaches its target, the first
//!         move comes from an unknown place.
//! Input:  a checked [`ToolPath`] and [`ExportOptions`].
//! Output: [`Program`]: every move (joint approach, linear path targets, linear retract) with
//!         its frame, process state, speed and exact-stop flag, cut into [`Part`]s.
//! Cost:   O(poses): one pass to merge, cut scans amortised O(1) per target, one pass for
//!         the reversals.
//! Deviations (choices of this crate): the merge tolerance ([`ZERO_MOVE_REL_TOL`] of the
//!         extent, at least [`ZERO_MOVE_MIN_MM`]); the reversal angle
//!         ([`REVERSAL_ANGLE_DEG`]); cuts preferred before a process-off move so parts run on
//!         their own; exact stops at process poses followed by a retract pose.
use super::frames::{tool_frames, Matrix3};
use super::path::{PoseKind, ToolPath, ToolPathError};
use crate::math::{Real, Vector3};
use std::ops::Range;

/// Default [`ExportOptions::max_moves`] for ABB RAPID: moves per procedure.
pub const RAPID_DEFAULT_MAX_MOVES: usize = 5000;
/// Default [`ExportOptions::max_moves`] for KUKA KRL: moves per `.src` file.
pub const KRL_DEFAULT_MAX_MOVES: usize = 1400;
/// Digits after the point for millimetre positions (1e-6 mm).
pub(crate) const MM_DECIMALS: usize = 6;
/// Digits after the point for unit vectors and quaternion components (1e-9).
pub(crate) const UNIT_DECIMALS: usize = 9;
/// Digits after the point for angles in degrees (1e-6°, about 2e-8 rad).
pub(crate) const DEG_DECIMALS: usize = 6;
/// Digits after the point for speeds in mm/s in the robot programs (1e-3 mm/s).
pub(crate) const SPEED_DECIMALS: usize = 3;
/// Longest line the robot programs contain; statements and comments wrap before it.
pub(crate) const ROBOT_LINE_WIDTH: usize = 80;
/// Default [`ExportOptions::approach_clearance_mm`].
pub const DEFAULT_APPROACH_CLEARANCE_MM: Real = 50.0;
/// Smallest [`ExportOptions::approach_clearance_mm`] accepted: a shorter approach would be
/// a move the controller can hardly tell from a dwell.
pub const MIN_APPROACH_CLEARANCE_MM: Real = 1.0;
/// Consecutive poses closer than this fraction of the path's extent (bounding-box diagonal)
/// are one robot target (see [`ZERO_MOVE_MIN_MM`] for the floor).
pub const ZERO_MOVE_REL_TOL: Real = 1e-6;
/// Floor of the zero-length tolerance in mm: ten times the written resolution (1e-6 mm), so
/// two targets the programs keep apart never print at the same position.
pub const ZERO_MOVE_MIN_MM: Real = 1e-5;
/// A path turns back at a target when its incoming and outgoing moves make more than this
/// angle (degrees): the controller must stop there exactly, or it reverses inside the zone.
pub const REVERSAL_ANGLE_DEG: Real = 150.0;
/// Turns within this many degrees below [`REVERSAL_ANGLE_DEG`] get an exact stop too: the
/// written positions are rounded, which can turn them a little further.
pub const REVERSAL_MARGIN_DEG: Real = 2.0;

/// Options shared by the exports.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportOptions {
    /// Millimetres per mesh unit (1000 for a file in metres). Every export is in mm.
    pub mm_per_unit: Real,
    /// Module / program name (an identifier of the target language: ASCII letter first, then
    /// letters, digits, underscores; short enough that the part names derived from it fit).
    pub name: String,
    /// At most this many moves per procedure (RAPID) or file (KRL); `None` for the defaults
    /// [`RAPID_DEFAULT_MAX_MOVES`] and [`KRL_DEFAULT_MAX_MOVES`]. `Some(0)` is refused.
    pub max_moves: Option<usize>,
    /// Line endings of every export (default LF).
    pub line_ending: LineEnding,
    /// Robot programs: distance (mm, ≥ 1) of the approach pose before a part's first pose
    /// and of the retract pose after its last one, back along the tool axis (default 50 mm).
    pub approach_clearance_mm: Real,
    /// Options of the ABB RAPID export only.
    pub rapid: RapidOptions,
    /// Options of the KUKA KRL export only.
    pub krl: KrlOptions,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            mm_per_unit: 1.0,
            name: "skinpath".into(),
            max_moves: None,
            line_ending: LineEnding::Lf,
            approach_clearance_mm: DEFAULT_APPROACH_CLEARANCE_MM,
            rapid: RapidOptions::default(),
            krl: KrlOptions::default(),
        }
    }
}

/// Line endings of the exported text. Both controllers read either; LF is the default so the
/// text is identical on every platform, CRLF for Windows tools that insist.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LineEnding {
    /// `\n`.
    #[default]
    Lf,
    /// `\r\n`.
    CrLf,
}

/// Names the ABB RAPID export writes into the program; placeholders the cell replaces or sets.
#[derive(Clone, Debug, PartialEq)]
pub struct RapidOptions {
    /// `PERS tooldata` name (declared as a placeholder with an identity TCP: set it in the cell).
    pub tool: String,
    /// `PERS wobjdata` name (declared as a placeholder at the world origin: set it in the cell).
    pub work_object: String,
    /// Digital output switched with `SetDO` when the process turns on or off.
    pub process_signal: String,
    /// Zone on moves with the process on (`z1`, or a `zonedata` of the cell).
    pub zone_process: String,
    /// Zone on moves with the process off (links, approach, retract).
    pub zone_link: String,
    /// Name of the routine that calls the parts in order.
    pub entry: String,
    /// Keep the controller's configuration check (`ConfJ\On`, `ConfL\On`) for a cell that
    /// replaces the `[0,0,0,0]` confdata placeholders with real ones; by default the
    /// program says `ConfJ\Off` and `ConfL\Off` (the placeholders would stop the robot).
    pub config_check: bool,
}

impl Default for RapidOptions {
    fn default() -> Self {
        RapidOptions {
            tool: "tSkinpath".into(),
            work_object: "wSkinpath".into(),
            process_signal: "doProcess".into(),
            zone_process: "z1".into(),
            zone_link: "z10".into(),
            entry: "main".into(),
            config_check: false,
        }
    }
}

/// Settings of the KUKA KRL export.
#[derive(Clone, Debug, PartialEq)]
pub struct KrlOptions {
    /// Output `$OUT[n]` switched when the process turns on or off (1..=4096).
    pub process_output: u32,
    /// Tool number: `$TOOL = TOOL_DATA[n]` (1..=16); the cell measures that tool.
    pub tool: u32,
    /// Base number: `$BASE = BASE_DATA[n]` (1..=32); the cell measures that base.
    pub base: u32,
    /// `$APO.CDIS` (mm) on moves with the process on.
    pub approximation_process_mm: Real,
    /// `$APO.CDIS` (mm) on moves with the process off.
    pub approximation_link_mm: Real,
    /// Unwrap A and C by whole turns so they do not jump across ±180° (within ±360°), for
    /// controllers known to accept angles beyond the documented [−180°, 180°]; off by default.
    pub unwrap_angles: bool,
}

impl Default for KrlOptions {
    fn default() -> Self {
        KrlOptions {
            process_output: 1,
            tool: 1,
            base: 1,
            approximation_process_mm: 1.0,
            approximation_link_mm: 10.0,
            unwrap_angles: false,
        }
    }
}

/// One exported file: its name (with extension) and its text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExportFile {
    /// File name the program expects, e.g. `skinpath.mod` or `skinpath_2.src`.
    pub file_name: String,
    /// The file's text.
    pub text: String,
}

pub(crate) fn bad_option(name: &'static str, why: impl Into<String>) -> ToolPathError {
    ToolPathError::BadOption {
        name,
        why: why.into(),
    }
}

/// Checks the path (valid, not empty) and the options every export uses.
pub(crate) fn check_common(path: &ToolPath, options: &ExportOptions) -> Result<(), ToolPathError> {
    path.validate()?;
    if path.poses.is_empty() {
        return Err(ToolPathError::Empty);
    }
    let k = options.mm_per_unit;
    if !(k.is_finite() && k > 0.0) {
        return Err(bad_option(
            "mmPerUnit",
            format!("must be finite and positive, got {k}"),
        ));
    }
    for (index, p) in path.poses.iter().enumerate() {
        if !(p.position.coords * k).iter().all(|c| c.is_finite()) {
            return Err(bad_option(
                "mmPerUnit",
                format!("{k} scales pose {index} beyond the floating-point range"),
            ));
        }
    }
    let speeds = [(path.speed, "speed"), (path.link_speed, "link speed")];
    let per_move = path.speeds.iter().map(|&s| (s, "speed of a move"));
    for (s, what) in speeds.into_iter().chain(per_move) {
        if !(s * k).is_finite() {
            return Err(bad_option(
                "mmPerUnit",
                format!("{k} scales the {what} beyond the floating-point range"),
            ));
        }
    }
    Ok(())
}

/// The move budget per part, with the format's default.
pub(crate) fn max_moves(options: &ExportOptions, default: usize) -> Result<usize, ToolPathError> {
    match options.max_moves {
        Some(0) => Err(bad_option("maxMoves", "must be at least 1, got 0")),
        Some(n) => Ok(n),
        None => Ok(default),
    }
}

/// Checks an identifier of a robot language: ASCII letter first, then ASCII letters, digits
/// and underscores, at most `max_len` characters, and no clash that `clash` finds (reserved
/// words and predefined names, case-insensitive).
pub(crate) fn check_identifier(
    option: &'static str,
    value: &str,
    max_len: usize,
    clash: fn(&str) -> Option<String>,
    language: &str,
) -> Result<(), ToolPathError> {
    let mut chars = value.chars();
    let starts_with_letter = chars.next().is_some_and(|c| c.is_ascii_alphabetic());
    if !starts_with_letter || !chars.all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err(bad_option(
            option,
            format!(
                "{value:?} is not a {language} identifier (an ASCII letter, then letters, digits or _)"
            ),
        ));
    }
    if value.len() > max_len {
        return Err(bad_option(
            option,
            format!("{value:?} is longer than the {max_len} characters {language} allows here"),
        ));
    }
    match clash(value) {
        Some(why) => Err(bad_option(option, why)),
        None => Ok(()),
    }
}

/// `v` with `decimals` digits after the point, trailing zeros (and a bare point) removed,
/// never in exponent notation, and never `-0`.
pub(crate) fn num(v: Real, decimals: usize) -> String {
    let mut s = format!("{v:.decimals$}");
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" {
        s.remove(0);
    }
    s
}

/// Text for a robot-program comment: ASCII only (a few symbols spelt out, others `?`), one
/// entry per line of the input, each wrapped at word boundaries to `width` characters.
pub(crate) fn comment_lines(text: &str, width: usize) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let mut ascii = String::with_capacity(line.len());
        for c in line.chars() {
            match c {
                ' '..='~' => ascii.push(c),
                '\t' => ascii.push(' '),
                'µ' | 'μ' => ascii.push('u'),
                '°' => ascii.push_str(" deg"),
                '–' | '—' | '−' => ascii.push('-'),
                '·' | '×' => ascii.push('*'),
                '≤' => ascii.push_str("<="),
                '≥' => ascii.push_str(">="),
                'α' => ascii.push_str("alpha"),
                'β' => ascii.push_str("beta"),
                'δ' => ascii.push_str("delta"),
                'η' => ascii.push_str("eta"),
                'θ' => ascii.push_str("theta"),
                '²' => ascii.push('2'),
                '³' => ascii.push('3'),
                _ => ascii.push('?'),
            }
        }
        let mut current = String::new();
        for word in ascii.split_whitespace() {
            let mut word = word;
            // Words longer than a line are cut.
            while word.len() > width {
                if !current.is_empty() {
                    out.push(std::mem::take(&mut current));
                }
                out.push(word[..width].to_string());
                word = &word[width..];
            }
            if !current.is_empty() && current.len() + 1 + word.len() > width {
                out.push(std::mem::take(&mut current));
            }
            if !current.is_empty() {
                current.push(' ');
            }
            current.push_str(word);
        }
        out.push(current);
    }
    out
}

/// The text with the chosen line endings (the writers use `\n`).
pub(crate) fn finish(text: String, line_ending: LineEnding) -> String {
    match line_ending {
        LineEnding::Lf => text,
        LineEnding::CrLf => text.replace('\n', "\r\n"),
    }
}

/// How the controller interpolates a move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Motion {
    /// Joint interpolation (`MoveJ` / `PTP`): only the approach at the start of a part.
    Joint,
    /// Linear interpolation of the TCP (`MoveL` / `LIN`).
    Linear,
}

/// One robot move of a program: target in mm and its tool frame, the process state and the
/// speed (mm/s) during the move, and whether the robot stops exactly at the target.
pub(crate) struct Move {
    pub motion: Motion,
    pub position_mm: [Real; 3],
    pub frame: Matrix3,
    pub process_on: bool,
    pub speed_mm_s: Real,
    pub exact: bool,
    /// Index of the path pose this move reaches (the last of a merged run); `None` for the
    /// approach and retract moves the export adds.
    pub pose: Option<usize>,
}

/// One part of a program (a RAPID procedure, a KRL sub-program): `moves` indexes
/// [`Program::moves`]. A part that `starts_clean` begins with the process off and a joint
/// move to its approach pose, so it runs on its own; otherwise it continues the previous
/// part with the process on. `ends_clean` likewise (a retract, process off, exact stop).
pub(crate) struct Part {
    pub moves: Range<usize>,
    /// Path poses (0-based, of the original path) the part covers.
    pub poses: Range<usize>,
    pub starts_clean: bool,
    pub ends_clean: bool,
}

/// What the robot programs write: every move in order, cut into parts, and the figures the
/// headers report.
pub(crate) struct Program {
    pub moves: Vec<Move>,
    pub parts: Vec<Part>,
    /// Zero-length moves removed (consecutive poses at one position).
    pub merged: usize,
    /// The position tolerance of the merge, mm.
    pub merge_tol_mm: Real,
    /// Exact stops inside parts (reversals and process points before a retract).
    pub turn_stops: usize,
    /// The move budget per part (path moves; the approach and retract are added).
    pub max_moves: usize,
}

/// One robot target before the cut into parts: a run of consecutive poses at one position.
struct Target {
    position: crate::math::Point3,
    frame: Matrix3,
    /// Kind of the first pose of the run: the move arriving at the target is its move.
    first: usize,
    /// Last pose of the run: its orientation is kept.
    last: usize,
}

/// The moves of a checked path for the robot programs.
///
/// No paper; the rules a controller needs (documented in the `toolpath` module doc):
/// consecutive poses within the zero-length tolerance become one target (position and
/// process state of the first, orientation of the last); a part is cut preferably before a
/// move with the process off and then starts with a joint move to an approach pose and ends
/// with a retract, both `approach_clearance_mm` back along the tool axis; exact stops at
/// every target where the path turns back by more than [`REVERSAL_ANGLE_DEG`], at every
/// process pose followed by a retract pose (drilling depth), and at the end of every
/// clean part.
pub(crate) fn program(
    path: &ToolPath,
    options: &ExportOptions,
    default_max: usize,
) -> Result<Program, ToolPathError> {
    let max = max_moves(options, default_max)?;
    let clearance = options.approach_clearance_mm;
    if !(clearance.is_finite() && clearance >= MIN_APPROACH_CLEARANCE_MM) {
        return Err(bad_option(
            "approachClearanceMm",
            format!("must be finite and at least {MIN_APPROACH_CLEARANCE_MM} mm, got {clearance}"),
        ));
    }
    let k = options.mm_per_unit;
    let frames = tool_frames(path.poses.iter().map(|p| (&p.axis, &p.travel)));

    // Merge runs of poses at one position: a fly-by move of zero length makes the controller
    // slow down or stop there (a dwell).
    let (lo, hi) = path.poses.iter().fold(
        (
            Vector3::repeat(Real::INFINITY),
            Vector3::repeat(-Real::INFINITY),
        ),
        |(lo, hi), p| (lo.inf(&p.position.coords), hi.sup(&p.position.coords)),
    );
    let extent = (hi - lo).norm();
    let tol = (ZERO_MOVE_REL_TOL * extent).max(ZERO_MOVE_MIN_MM / k);
    let mut targets: Vec<Target> = Vec::with_capacity(path.poses.len());
    for (i, p) in path.poses.iter().enumerate() {
        match targets.last_mut() {
            Some(t) if (p.position - t.position).norm() <= tol => {
                t.frame = frames[i];
                t.last = i;
            }
            _ => targets.push(Target {
                position: p.position,
                frame: frames[i],
                first: i,
                last: i,
            }),
        }
    }
    let merged = path.poses.len() - targets.len();
    // The move arriving at target j: process state and speed of its first pose; the move to
    // the first target comes from the approach pose with the process off.
    let arrives_on = |j: usize| j > 0 && path.poses[targets[j].first].kind.process_on();

    // Cut into parts, preferring a cut before a move with the process off (the part after
    // it runs on its own). Each scan looks back from the budget's end and stops at the first
    // such move; the moves it passes all have the process on and are never scanned again as
    // candidates, so the total is O(targets).
    let n = targets.len();
    let mut cuts = vec![0];
    let mut start = 0;
    while start < n {
        let end_max = start.saturating_add(max).min(n);
        let end = if end_max == n {
            n
        } else {
            (start + 1..=end_max)
                .rev()
                .find(|&j| !arrives_on(j))
                .unwrap_or(end_max)
        };
        cuts.push(end);
        start = end;
    }

    let axis_mm = |t: &Target| t.frame.column(2).into_owned() * clearance;
    let at = |t: &Target| t.position.coords * k;
    let link = path.link_speed * k;
    let mut moves: Vec<Move> = Vec::with_capacity(n + 2 * cuts.len());
    let mut parts = Vec::with_capacity(cuts.len() - 1);
    for w in cuts.windows(2) {
        let (s, e) = (w[0], w[1]);
        let first_move = moves.len();
        let starts_clean = !arrives_on(s);
        let ends_clean = e == n || !arrives_on(e);
        if starts_clean {
            moves.push(Move {
                motion: Motion::Joint,
                position_mm: (at(&targets[s]) - axis_mm(&targets[s])).into(),
                frame: targets[s].frame,
                process_on: false,
                speed_mm_s: link,
                exact: true,
                pose: None,
            });
        }
        for (j, t) in targets.iter().enumerate().take(e).skip(s) {
            let process_on = arrives_on(j) && !(j == s && starts_clean);
            let speed = if process_on || path.has_varying_speed() {
                path.move_speed(t.first) * k
            } else {
                link
            };
            // A process pose followed by a retract: the tool must reach it (drilling depth).
            let before_retract = targets.get(j + 1).is_some_and(|next| {
                path.poses[next.first].kind == PoseKind::Retract
                    && path.poses[t.last].kind.process_on()
            });
            moves.push(Move {
                motion: Motion::Linear,
                position_mm: at(t).into(),
                frame: t.frame,
                process_on,
                speed_mm_s: speed,
                exact: before_retract,
                pose: Some(t.last),
            });
        }
        if ends_clean {
            let t = &targets[e - 1];
            moves.push(Move {
                motion: Motion::Linear,
                position_mm: (at(t) - axis_mm(t)).into(),
                frame: t.frame,
                process_on: false,
                speed_mm_s: link,
                exact: true,
                pose: None,
            });
        }
        parts.push(Part {
            moves: first_move..moves.len(),
            poses: targets[s].first..targets[e - 1].last + 1,
            starts_clean,
            ends_clean,
        });
    }

    // Reversals: the robot would turn back inside the zone and never reach the target.
    // A margin below the angle, so a turn just under it cannot exceed it once the positions
    // are rounded as written.
    let cos_limit = libm::cos((REVERSAL_ANGLE_DEG - REVERSAL_MARGIN_DEG).to_radians());
    let point = |m: &Move| Vector3::from(m.position_mm);
    let mut turn_stops = 0;
    for i in 1..moves.len().saturating_sub(1) {
        let d_in = point(&moves[i]) - point(&moves[i - 1]);
        let d_out = point(&moves[i + 1]) - point(&moves[i]);
        let norms = d_in.norm() * d_out.norm();
        let turns_back = norms > 0.0 && d_in.dot(&d_out) < cos_limit * norms;
        if turns_back && !moves[i].exact {
            moves[i].exact = true;
        }
        if moves[i].pose.is_some() && moves[i].exact {
            turn_stops += 1;
        }
    }
    Ok(Program {
        moves,
        parts,
        merged,
        merge_tol_mm: tol * k,
        turn_stops,
        max_moves: max,
    })
}

/// Header lines shared by the robot programs: what the file is, the conventions, the cell
/// set-up (`extra`, from the language) and the path's notes.
pub(crate) fn header_notes(
    path: &ToolPath,
    options: &ExportOptions,
    program: &Program,
    extra: &[String],
) -> Vec<String> {
    let k = options.mm_per_unit;
    let mut lines = vec![
        format!(
            "{}: tool path written by skinpath {}.",
            options.name,
            env!("CARGO_PKG_VERSION")
        ),
        format!(
            "{} poses in {} passes, {} moves. Positions in mm ({} mm per model unit).",
            path.poses.len(),
            path.pass_count(),
            program.moves.len(),
            num(k, UNIT_DECIMALS)
        ),
    ];
    lines.push(if path.has_varying_speed() {
        format!(
            "Speeds vary from move to move (the plan's); link speed {} mm/s.",
            num(path.link_speed * k, SPEED_DECIMALS)
        )
    } else {
        format!(
            "Process speed {} mm/s, link speed {} mm/s.",
            num(path.speed * k, SPEED_DECIMALS),
            num(path.link_speed * k, SPEED_DECIMALS)
        )
    });
    lines.push(
        "Tool frame: Z = tool axis towards the part, X = travel direction, Y = Z x X.".into(),
    );
    lines.push(format!(
        "Each part that starts with the process off begins with a joint move, process off,          to an approach pose {} mm back along the first pose's tool axis (from wherever the          robot stands: check the way is clear), and ends with a retract the same distance          back along the last pose's axis, process off, exact stop.",
        num(options.approach_clearance_mm, MM_DECIMALS)
    ));
    lines.push(format!(
        "Exact stops: {} inside the path (where it turns back by more than {} deg, and          every process point followed by a retract, e.g. a drilled depth), and at every          approach and retract.",
        program.turn_stops, REVERSAL_ANGLE_DEG
    ));
    if program.merged > 0 {
        lines.push(format!(
            "{} zero-length moves removed: consecutive poses within {} mm of each other are              one target with the later pose's orientation (the reorientation happens on the              move before instead of on the spot).",
            program.merged,
            num(program.merge_tol_mm, MM_DECIMALS)
        ));
    }
    lines.extend(extra.iter().cloned());
    lines.extend(path.notes.iter().cloned());
    lines
}

/// Comment lines that say how part `index` (0-based) of `program` runs.
pub(crate) fn part_note(program: &Program, index: usize, main: &str) -> String {
    let part = &program.parts[index];
    let count = program.parts.len();
    let mut note = format!(
        "Part {} of {count}: poses {} to {} of the path.",
        index + 1,
        part.poses.start + 1,
        part.poses.end
    );
    note.push_str(if part.starts_clean {
        " Starts with the process off and a joint move to its approach pose: it can run on          its own."
    } else {
        " Continues the previous part with the process on, from its last pose: run it only          through "
    });
    if !part.starts_clean {
        note.push_str(main);
        note.push('.');
    }
    if !part.ends_clean {
        note.push_str(" Ends with the process on; the next part continues the path.");
    }
    note
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_fixed_point_trimmed_and_never_negative_zero() {
        assert_eq!(num(1.5, 6), "1.5");
        assert_eq!(num(-1e-9, 6), "0");
        assert_eq!(num(400.0, 3), "400");
        assert_eq!(num(1e20, 6), "100000000000000000000");
        assert_eq!(num(-2.0000004, 6), "-2");
        assert_eq!(num(0.1234567, 6), "0.123457");
    }

    #[test]
    fn comments_are_ascii_and_wrapped() {
        let lines = comment_lines("β = 20° — thickness 30 µm\nsecond", 10);
        assert_eq!(
            lines,
            ["beta = 20", "deg -", "thickness", "30 um", "second"]
        );
        let long = comment_lines(&"x".repeat(25), 10);
        assert_eq!(
            long.iter().map(String::len).collect::<Vec<_>>(),
            [10, 10, 5]
        );
    }
}
