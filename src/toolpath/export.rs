//! Export options and the helpers every format shares: option checks, number formatting,
//! comment text for robot controllers, the per-move data and the split into parts.

use super::frames::{tool_frames, Matrix3};
use super::path::{ToolPath, ToolPathError};
use crate::math::Real;
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
    /// Unwrap A and C by whole turns so they do not jump across ±180° (within ±360°).
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
            unwrap_angles: true,
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
    for (s, what) in [(path.speed, "speed"), (path.link_speed, "link speed")] {
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

/// Consecutive ranges of at most `max` moves covering `0..n` (`max ≥ 1`).
pub(crate) fn parts(n: usize, max: usize) -> Vec<Range<usize>> {
    (0..n.div_ceil(max))
        .map(|k| k * max..(k + 1).saturating_mul(max).min(n))
        .collect()
}

/// Checks an identifier of a robot language: ASCII letter first, then ASCII letters, digits
/// and underscores, at most `max_len` characters, not a reserved word (case-insensitive).
pub(crate) fn check_identifier(
    option: &'static str,
    value: &str,
    max_len: usize,
    reserved: &[&str],
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
    if reserved.iter().any(|r| r.eq_ignore_ascii_case(value)) {
        return Err(bad_option(
            option,
            format!("{value:?} is a reserved word of {language}"),
        ));
    }
    Ok(())
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

/// One robot move: target in mm, tool frame, whether the process is on during the move, and
/// the speed in mm/s. The move to the first pose always runs with the process off at the link
/// speed: the robot arrives there from wherever it stands.
pub(crate) struct Move {
    pub position_mm: [Real; 3],
    pub process_on: bool,
    pub speed_mm_s: Real,
}

/// The moves and tool frames of a checked path.
pub(crate) fn moves(path: &ToolPath, mm_per_unit: Real) -> (Vec<Move>, Vec<Matrix3>) {
    let frames = tool_frames(path.poses.iter().map(|p| (&p.axis, &p.travel)));
    let moves = path
        .poses
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let process_on = i > 0 && p.kind.process_on();
            let speed = if process_on {
                path.speed
            } else {
                path.link_speed
            };
            Move {
                position_mm: (p.position.coords * mm_per_unit).into(),
                process_on,
                speed_mm_s: speed * mm_per_unit,
            }
        })
        .collect();
    (moves, frames)
}

/// Header lines shared by the robot programs: what the file is and the conventions.
pub(crate) fn header_notes(
    path: &ToolPath,
    options: &ExportOptions,
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
            "{} moves in {} passes. Positions in mm ({} mm per model unit).",
            path.poses.len(),
            path.pass_count(),
            num(k, UNIT_DECIMALS)
        ),
        format!(
            "Process speed {} mm/s, link speed {} mm/s.",
            num(path.speed * k, SPEED_DECIMALS),
            num(path.link_speed * k, SPEED_DECIMALS)
        ),
        "Tool frame: Z = tool axis towards the part, X = travel direction, Y = Z x X.".into(),
        "The first move runs with the process off from wherever the robot stands.".into(),
    ];
    lines.extend(extra.iter().cloned());
    lines.extend(path.notes.iter().cloned());
    lines
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

    #[test]
    fn parts_cover_the_moves_in_order() {
        assert_eq!(parts(5, 2), [0..2, 2..4, 4..5]);
        assert_eq!((parts(4, 4).len(), parts(4, 4)[0].clone()), (1, 0..4));
        assert_eq!((parts(1, 1400).len(), parts(1, 1400)[0].clone()), (1, 0..1));
    }
}
