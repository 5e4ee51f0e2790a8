//! ABB RAPID export: `MoveL` to inline robtargets, split into procedures called from a main
//! routine.
//!
//! Source: ABB "Technical reference manual – RAPID Instructions, Functions and Data types"
//!         (robtarget, orient, confdata, extjoint, speeddata, zonedata, tooldata, wobjdata,
//!         MoveL, SetDO) and "RAPID kernel" (identifiers of at most 32 characters, `!`
//!         comments, statements may span lines).
//! Input:  a checked [`ToolPath`], [`ExportOptions`] (with [`super::RapidOptions`]).
//! Output: one module text per file, main module first.
//! Cost:   O(poses).
//! Deviations (choices of this crate, documented in the `toolpath` module doc):
//!   - orientation `[q1,q2,q3,q4] = [w,x,y,z]` of the tool frame, signs kept continuous;
//!   - `confdata` `[0,0,0,0]` and `extjoint` `[9E9,…]` placeholders: linear moves do not need
//!     the configuration (ConfL is the cell's choice) and no external axes are driven;
//!   - one procedure of at most `max_moves` moves per part; with more than one part every
//!     procedure gets its own module file, so no file grows beyond one part;
//!   - the process hook is `SetDO signal,1|0;` before the first move of a different state
//!     (RAPID runs it as the robot starts rounding the previous target); the main routine
//!     resets the signal first and the program ends with the process off;
//!   - lines stay within 80 characters (statements wrap after commas).

use super::export::{
    bad_option, check_common, check_identifier, comment_lines, finish, header_notes, max_moves,
    moves, num, parts, ExportFile, ExportOptions, MM_DECIMALS, RAPID_DEFAULT_MAX_MOVES,
    ROBOT_LINE_WIDTH, UNIT_DECIMALS,
};
use super::frames::continuous_quaternions;
use super::path::{ToolPath, ToolPathError};
use std::fmt::Write;

/// Longest RAPID identifier.
const RAPID_MAX_IDENTIFIER: usize = 32;
/// Orientation, external linear and rotational axis speeds of the generated `speeddata`
/// (deg/s, mm/s, deg/s): the values of ABB's predefined `v100`…`v1000`.
const RAPID_SPEED_TAIL: &str = "500,5000,1000";
/// Name of the process-speed `speeddata` constant.
pub const RAPID_PROCESS_SPEED: &str = "v_process";
/// Name of the link-speed `speeddata` constant.
pub const RAPID_LINK_SPEED: &str = "v_link";

/// Reserved words of RAPID (kernel manual), refused as names.
const RAPID_RESERVED: &[&str] = &[
    "ALIAS",
    "AND",
    "BACKWARD",
    "CASE",
    "CONNECT",
    "CONST",
    "DEFAULT",
    "DIV",
    "DO",
    "ELSE",
    "ELSEIF",
    "ENDFOR",
    "ENDFUNC",
    "ENDIF",
    "ENDMODULE",
    "ENDPROC",
    "ENDRECORD",
    "ENDTEST",
    "ENDTRAP",
    "ENDWHILE",
    "ERROR",
    "EXIT",
    "FALSE",
    "FOR",
    "FROM",
    "FUNC",
    "GOTO",
    "IF",
    "INOUT",
    "LOCAL",
    "MOD",
    "MODULE",
    "NOSTEPIN",
    "NOT",
    "NOVIEW",
    "OR",
    "PERS",
    "PROC",
    "RAISE",
    "READONLY",
    "RECORD",
    "RETRY",
    "RETURN",
    "STEP",
    "SYSMODULE",
    "TEST",
    "THEN",
    "TO",
    "TRAP",
    "TRUE",
    "TRYNEXT",
    "UNDO",
    "VAR",
    "VIEWONLY",
    "WHILE",
    "WITH",
    "XOR",
];

/// ABB RAPID: one module text per file, the main module first (see [`rapid_files`]).
pub fn to_rapid(path: &ToolPath, options: &ExportOptions) -> Result<Vec<String>, ToolPathError> {
    Ok(rapid_files(path, options)?
        .into_iter()
        .map(|f| f.text)
        .collect())
}

/// ABB RAPID files. The path is cut into procedures `<name>_1`, `<name>_2`, … of at most
/// `max_moves` moves, called in order by the entry routine (default `main`). One part: a
/// single module `<name>.mod` holds everything. Several parts: `<name>.mod` holds the data
/// and the entry routine, and `<name>_mod<k>.mod` holds procedure `<name>_<k>`.
pub fn rapid_files(
    path: &ToolPath,
    options: &ExportOptions,
) -> Result<Vec<ExportFile>, ToolPathError> {
    check_common(path, options)?;
    let max = max_moves(options, RAPID_DEFAULT_MAX_MOVES)?;
    let o = &options.rapid;
    let ranges = parts(path.poses.len(), max);
    let name = &options.name;
    let id = |option, value: &str| {
        check_identifier(option, value, RAPID_MAX_IDENTIFIER, RAPID_RESERVED, "RAPID")
    };
    id("name", name)?;
    let last = ranges.len();
    let proc_name = |k: usize| format!("{name}_{k}");
    let module_name = |k: usize| format!("{name}_mod{k}");
    id("name", &proc_name(last))?;
    if last > 1 {
        id("name", &module_name(last))?;
    }
    for (option, value) in [
        ("rapid.tool", &o.tool),
        ("rapid.work_object", &o.work_object),
        ("rapid.process_signal", &o.process_signal),
        ("rapid.zone_process", &o.zone_process),
        ("rapid.zone_link", &o.zone_link),
        ("rapid.entry", &o.entry),
    ] {
        id(option, value)?;
    }
    // Names this program declares must differ (RAPID is case-insensitive).
    let declared = [
        ("rapid.tool", &o.tool),
        ("rapid.work_object", &o.work_object),
        ("rapid.entry", &o.entry),
    ];
    for (i, (option, value)) in declared.iter().enumerate() {
        let clash = declared[..i]
            .iter()
            .map(|(_, v)| v.as_str())
            .chain([RAPID_PROCESS_SPEED, RAPID_LINK_SPEED, name.as_str()])
            .any(|v| v.eq_ignore_ascii_case(value))
            || starts_with_part_name(value, name);
        if clash {
            return Err(bad_option(
                option,
                format!("{value:?} clashes with another name the RAPID program declares"),
            ));
        }
    }

    let (moves, frames) = moves(path, options.mm_per_unit);
    let quaternions = continuous_quaternions(&frames);
    let width = ROBOT_LINE_WIDTH;
    let mut files = Vec::with_capacity(last + 1);

    // The main module: header, data, entry routine (and the only part when there is one).
    let mut main = String::new();
    let _ = writeln!(main, "MODULE {name}");
    let extra = [
        format!(
            "Set PERS {} (TCP and load of the tool) and {} (frame of the part) in the \
             cell: the values below are placeholders.",
            o.tool, o.work_object
        ),
        format!(
            "{} switches the process: SetDO {},1 before the first move with the process on, \
             {},0 before the first move with it off.",
            o.process_signal, o.process_signal, o.process_signal
        ),
        "Robtargets: orient = [w,x,y,z] of the tool frame; confdata [0,0,0,0] and extjoint \
         9E9 are placeholders (no external axes)."
            .into(),
        format!(
            "{} parts of at most {max} moves, called in order by {}.",
            last, o.entry
        ),
    ];
    for line in header_notes(path, options, &extra) {
        for l in comment_lines(&line, width - 4) {
            let _ = writeln!(main, "  ! {l}");
        }
    }
    let _ = writeln!(
        main,
        "  PERS tooldata {} := [TRUE,[[0,0,0],[1,0,0,0]],\n    [1,[0,0,1],[1,0,0,0],0,0,0]];",
        o.tool
    );
    let _ = writeln!(
        main,
        "  PERS wobjdata {} := [FALSE,TRUE,\"\",[[0,0,0],[1,0,0,0]],\n    \
         [[0,0,0],[1,0,0,0]]];",
        o.work_object
    );
    let k = options.mm_per_unit;
    for (constant, speed) in [
        (RAPID_PROCESS_SPEED, path.speed * k),
        (RAPID_LINK_SPEED, path.link_speed * k),
    ] {
        let _ = writeln!(
            main,
            "  CONST speeddata {constant} := [{},{RAPID_SPEED_TAIL}];",
            num(speed, MM_DECIMALS)
        );
    }
    let _ = writeln!(main, "\n  PROC {}()", o.entry);
    let _ = writeln!(main, "    SetDO {},0;", o.process_signal);
    for k in 1..=last {
        let _ = writeln!(main, "    {};", proc_name(k));
    }
    let _ = writeln!(main, "  ENDPROC");

    let mut process_on = false;
    let mut part_texts = Vec::with_capacity(last);
    for (index, range) in ranges.iter().enumerate() {
        let k = index + 1;
        let mut text = String::new();
        let _ = writeln!(text, "\n  PROC {}()", proc_name(k));
        let _ = writeln!(
            text,
            "    ! Moves {} to {} of {}.",
            range.start + 1,
            range.end,
            moves.len()
        );
        for i in range.clone() {
            let m = &moves[i];
            if m.process_on != process_on {
                process_on = m.process_on;
                let _ = writeln!(
                    text,
                    "    SetDO {},{};",
                    o.process_signal,
                    u8::from(process_on)
                );
            }
            let p = m.position_mm.map(|c| num(c, MM_DECIMALS));
            let q = quaternions[i].map(|c| num(c, UNIT_DECIMALS));
            let (speed, zone) = if i + 1 == moves.len() {
                (speed_name(m.process_on), "fine")
            } else if m.process_on {
                (RAPID_PROCESS_SPEED, o.zone_process.as_str())
            } else {
                (RAPID_LINK_SPEED, o.zone_link.as_str())
            };
            let pieces = [
                format!("MoveL [[{},", p[0]),
                format!("{},", p[1]),
                format!("{}],", p[2]),
                format!("[{},", q[0]),
                format!("{},", q[1]),
                format!("{},", q[2]),
                format!("{}],", q[3]),
                "[0,0,0,0],".into(),
                "[9E9,9E9,9E9,9E9,9E9,9E9]],".into(),
                format!("{speed},"),
                format!("{zone},"),
                o.tool.clone(),
                format!("\\WObj:={};", o.work_object),
            ];
            wrap_statement(&mut text, &pieces, 4, 6, width);
        }
        if k == last && process_on {
            let _ = writeln!(text, "    SetDO {},0;", o.process_signal);
        }
        let _ = writeln!(text, "  ENDPROC");
        part_texts.push(text);
    }

    if last == 1 {
        main.push_str(&part_texts[0]);
        main.push_str("ENDMODULE\n");
        files.push(ExportFile {
            file_name: format!("{name}.mod"),
            text: finish(main, options.line_ending),
        });
        return Ok(files);
    }
    main.push_str("ENDMODULE\n");
    files.push(ExportFile {
        file_name: format!("{name}.mod"),
        text: finish(main, options.line_ending),
    });
    for (index, part) in part_texts.into_iter().enumerate() {
        let module = module_name(index + 1);
        let mut text = format!("MODULE {module}\n");
        let note = format!(
            "Part {} of {last} of {name}: run {} in {name}.mod, not this module alone.",
            index + 1,
            o.entry
        );
        for l in comment_lines(&note, width - 4) {
            let _ = writeln!(text, "  ! {l}");
        }
        text.push_str(&part);
        text.push_str("ENDMODULE\n");
        files.push(ExportFile {
            file_name: format!("{module}.mod"),
            text: finish(text, options.line_ending),
        });
    }
    Ok(files)
}

fn speed_name(process_on: bool) -> &'static str {
    if process_on {
        RAPID_PROCESS_SPEED
    } else {
        RAPID_LINK_SPEED
    }
}

/// Whether `value` looks like a generated part name `<name>_<digits>` or `<name>_mod<digits>`.
fn starts_with_part_name(value: &str, name: &str) -> bool {
    let lower = value.to_ascii_lowercase();
    let prefix = format!("{}_", name.to_ascii_lowercase());
    lower.strip_prefix(&prefix).is_some_and(|rest| {
        let digits = rest.strip_prefix("mod").unwrap_or(rest);
        !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
    })
}

/// Writes the pieces of one statement, filling lines up to `width` and breaking only between
/// pieces (RAPID allows a line break between any two tokens).
fn wrap_statement(out: &mut String, pieces: &[String], indent: usize, cont: usize, width: usize) {
    let mut line = " ".repeat(indent);
    let mut fresh = true;
    for piece in pieces {
        if !fresh && line.len() + piece.len() > width {
            out.push_str(&line);
            out.push('\n');
            line = " ".repeat(cont);
        }
        line.push_str(piece);
        fresh = false;
    }
    out.push_str(&line);
    out.push('\n');
}
