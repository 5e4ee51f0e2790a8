//! KUKA KRL export: `.src` programs of inline `LIN {X,Y,Z,A,B,C} C_DIS` moves, split into
//! sub-programs called in order from a main program.
//!
//! Source: KUKA "KUKA System Software 8.x – Operating and programming instructions for system
//!         integrators" (LIN with inline FRAME/POS, `$VEL.CP` in m/s, `$APO.CDIS` in mm,
//!         `C_DIS`, `TRIGGER WHEN DISTANCE`, `$TOOL`/`$BASE`, names of at most 24 characters,
//!         `;` comments); orientation `R = Rz(A)·Ry(B)·Rx(C)` in degrees.
//! Input:  a checked [`ToolPath`], [`ExportOptions`] (with [`super::KrlOptions`]).
//! Output: one `.src` text per file, the main program first; no `.dat` files.
//! Cost:   O(poses).
//! Deviations (choices of this crate, documented in the `toolpath` module doc):
//!   - A/B/C are continuous where possible (see `frames`): B in [−90°, 90°], A kept at gimbal
//!     lock, A and C unwrapped across ±180° while within ±360° (option `krl.unwrap_angles`);
//!   - the process hook is `TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[n]=TRUE|FALSE` before the
//!     first move of a different state: it fires at the start of that move, and unlike a bare
//!     `$OUT[n]=…` it does not stop the advance run, so `C_DIS` approximation is kept;
//!   - `$VEL.CP` and `$APO.CDIS` are set at the start of every file and before any move whose
//!     value differs; the last move of the path is an exact stop (no `C_DIS`);
//!   - the main program sets `$TOOL`, `$LOAD` and `$BASE` from the cell's numbered data
//!     (placeholders: options `krl.tool`, `krl.base`) after `BAS(#INITMOV,0)`.

use super::export::{
    bad_option, check_common, check_identifier, comment_lines, finish, header_notes, max_moves,
    moves, num, parts, ExportFile, ExportOptions, DEG_DECIMALS, KRL_DEFAULT_MAX_MOVES, MM_DECIMALS,
    ROBOT_LINE_WIDTH,
};
use super::frames::continuous_euler_zyx_deg;
use super::path::{ToolPath, ToolPathError};
use crate::math::Real;
use std::fmt::Write;

/// Longest KRL name.
const KRL_MAX_IDENTIFIER: usize = 24;
/// Highest output number accepted for `$OUT[n]`.
const KRL_MAX_OUTPUT: u32 = 4096;
/// Highest tool number (`TOOL_DATA[1..16]`).
const KRL_MAX_TOOL: u32 = 16;
/// Highest base number (`BASE_DATA[1..32]`).
const KRL_MAX_BASE: u32 = 32;

/// Reserved words of KRL, refused as names.
const KRL_RESERVED: &[&str] = &[
    "AND",
    "ANIN",
    "ANOUT",
    "B_AND",
    "B_EXOR",
    "B_NOT",
    "B_OR",
    "BOOL",
    "BRAKE",
    "C_DIS",
    "C_ORI",
    "C_PTP",
    "C_VEL",
    "CASE",
    "CAST_FROM",
    "CAST_TO",
    "CHAR",
    "CIRC",
    "CIRC_REL",
    "CONST",
    "CONTINUE",
    "DECL",
    "DEF",
    "DEFAULT",
    "DEFDAT",
    "DEFFCT",
    "DELAY",
    "DO",
    "ELSE",
    "END",
    "ENDDAT",
    "ENDFCT",
    "ENDFOR",
    "ENDIF",
    "ENDLOOP",
    "ENDSWITCH",
    "ENDWHILE",
    "ENUM",
    "EXIT",
    "EXOR",
    "EXT",
    "EXTFCT",
    "FALSE",
    "FOR",
    "GLOBAL",
    "GOTO",
    "HALT",
    "IF",
    "IMPORT",
    "INT",
    "INTERRUPT",
    "INVERSE",
    "IS",
    "LIN",
    "LIN_REL",
    "LOOP",
    "MAXIMUM",
    "MINIMUM",
    "NOT",
    "OR",
    "PRIO",
    "PTP",
    "PTP_REL",
    "PUBLIC",
    "REAL",
    "REPEAT",
    "RESUME",
    "RETURN",
    "SEC",
    "SIGNAL",
    "STRUC",
    "SWITCH",
    "THEN",
    "TO",
    "TRIGGER",
    "TRUE",
    "UNTIL",
    "WAIT",
    "WHEN",
    "WHILE",
];

/// KUKA KRL `.src` files: one text per file, the main program first (see [`krl_files`]).
pub fn to_krl(path: &ToolPath, options: &ExportOptions) -> Result<Vec<String>, ToolPathError> {
    Ok(krl_files(path, options)?
        .into_iter()
        .map(|f| f.text)
        .collect())
}

/// KUKA KRL files: `<name>.src` (main program: settings, then calls) and `<name>_<k>.src`
/// (sub-program `<name>_<k>()` with at most `max_moves` moves), all in one folder.
pub fn krl_files(
    path: &ToolPath,
    options: &ExportOptions,
) -> Result<Vec<ExportFile>, ToolPathError> {
    check_common(path, options)?;
    let max = max_moves(options, KRL_DEFAULT_MAX_MOVES)?;
    let o = &options.krl;
    let name = &options.name;
    let ranges = parts(path.poses.len(), max);
    let last = ranges.len();
    let part_name = |k: usize| format!("{name}_{k}");
    let id = |value: &str| check_identifier("name", value, KRL_MAX_IDENTIFIER, KRL_RESERVED, "KRL");
    id(name)?;
    id(&part_name(last))?;
    for (option, value, max) in [
        ("krl.process_output", o.process_output, KRL_MAX_OUTPUT),
        ("krl.tool", o.tool, KRL_MAX_TOOL),
        ("krl.base", o.base, KRL_MAX_BASE),
    ] {
        if !(1..=max).contains(&value) {
            return Err(bad_option(
                option,
                format!("must be in 1..={max}, got {value}"),
            ));
        }
    }
    for (option, value) in [
        ("krl.approximation_process_mm", o.approximation_process_mm),
        ("krl.approximation_link_mm", o.approximation_link_mm),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(bad_option(
                option,
                format!("must be finite and ≥ 0 mm, got {value}"),
            ));
        }
    }

    let (moves, frames) = moves(path, options.mm_per_unit);
    let angles = continuous_euler_zyx_deg(&frames, o.unwrap_angles);
    let width = ROBOT_LINE_WIDTH;
    let out_n = o.process_output;
    let mut files = Vec::with_capacity(last + 1);

    let mut main = String::new();
    let _ = writeln!(main, "DEF {name}()");
    let extra = [
        format!(
            "Set TOOL_DATA[{}], LOAD_DATA[{}] and BASE_DATA[{}] in the cell (tool and part \
             frames); the numbers are placeholders.",
            o.tool, o.tool, o.base
        ),
        format!(
            "$OUT[{out_n}] switches the process: a TRIGGER at the start of the first move with a \
             different state sets it TRUE or FALSE."
        ),
        "Orientation A, B, C in degrees, R = Rz(A)*Ry(B)*Rx(C); $VEL.CP in m/s.".into(),
        format!("{last} sub-programs of at most {max} moves, called in order below."),
    ];
    for line in header_notes(path, options, &extra) {
        for l in comment_lines(&line, width - 4) {
            let _ = writeln!(main, "  ; {l}");
        }
    }
    main.push_str("  BAS(#INITMOV,0)\n");
    let _ = writeln!(main, "  $TOOL = TOOL_DATA[{}]", o.tool);
    let _ = writeln!(main, "  $LOAD = LOAD_DATA[{}]", o.tool);
    let _ = writeln!(main, "  $BASE = BASE_DATA[{}]", o.base);
    main.push_str("  $ORI_TYPE = #VAR\n");
    let _ = writeln!(main, "  $OUT[{out_n}] = FALSE");
    for k in 1..=last {
        let _ = writeln!(main, "  {}()", part_name(k));
    }
    main.push_str("END\n");
    files.push(ExportFile {
        file_name: format!("{name}.src"),
        text: finish(main, options.line_ending),
    });

    let mut process_on = false;
    for (index, range) in ranges.iter().enumerate() {
        let k = index + 1;
        let mut text = String::new();
        let _ = writeln!(text, "DEF {}()", part_name(k));
        let _ = writeln!(
            text,
            "  ; Part {k} of {last} of {name}: moves {} to {} of {}; run {name}.src.",
            range.start + 1,
            range.end,
            moves.len()
        );
        let mut speed: Option<Real> = None;
        let mut apo: Option<Real> = None;
        for i in range.clone() {
            let m = &moves[i];
            let v = m.speed_mm_s / 1000.0;
            if speed != Some(v) {
                let _ = writeln!(text, "  $VEL.CP = {}", num(v, MM_DECIMALS));
                speed = Some(v);
            }
            let end = i + 1 == moves.len();
            let a = if m.process_on {
                o.approximation_process_mm
            } else {
                o.approximation_link_mm
            };
            if !end && apo != Some(a) {
                let _ = writeln!(text, "  $APO.CDIS = {}", num(a, MM_DECIMALS));
                apo = Some(a);
            }
            if m.process_on != process_on {
                process_on = m.process_on;
                let state = if process_on { "TRUE" } else { "FALSE" };
                let _ = writeln!(
                    text,
                    "  TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[{out_n}]={state}"
                );
            }
            let [x, y, z] = m.position_mm.map(|c| num(c, MM_DECIMALS));
            let [a, b, c] = angles[i].map(|c| num(c, DEG_DECIMALS));
            let approximation = if end { "" } else { " C_DIS" };
            let _ = writeln!(
                text,
                "  LIN {{X {x},Y {y},Z {z},A {a},B {b},C {c}}}{approximation}"
            );
        }
        if k == last && process_on {
            let _ = writeln!(text, "  $OUT[{out_n}] = FALSE");
        }
        text.push_str("END\n");
        files.push(ExportFile {
            file_name: format!("{}.src", part_name(k)),
            text: finish(text, options.line_ending),
        });
    }
    Ok(files)
}
