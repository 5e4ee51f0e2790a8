//! KUKA KRL export: `.src` programs of a `PTP` to an approach pose, inline
//! `LIN {X,Y,Z,A,B,C} C_DIS` moves and a retract, split into sub-programs called in order
//! from a main program.
//!
//! Source: KUKA "KUKA System Software 8.x – Operating and programming instructions for system
//!         integrators" (PTP and LIN with inline FRAME, `$VEL.CP` in m/s, `$APO.CDIS` in mm,
//!         `C_DIS`, `TRIGGER WHEN DISTANCE`, `$TOOL`/`$BASE`, `BAS(#INITMOV,0)`,
//!         `BAS(#VEL_PTP,…)`, names of at most 24 characters, `;` comments, A and C in
//!         [−180°, 180°], B in [−90°, 90°]); orientation `R = Rz(A)·Ry(B)·Rx(C)` in degrees;
//!         reserved and predefined names in `names.rs`.
//! Input:  a checked [`ToolPath`], [`ExportOptions`] (with [`super::KrlOptions`]).
//! Output: one `.src` text per file, the main program first; no `.dat` files.
//! Cost:   O(poses).
//! Deviations (choices of this crate, documented in the `toolpath` module doc):
//!   - A/C in (−180°, 180°] and B in [−90°, 90°] by default, A kept at gimbal lock; with
//!     `krl.unwrap_angles` A and C are unwrapped across ±180° while within ±360°;
//!   - the process hook is `TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[n]=TRUE|FALSE` before the
//!     first move of a different state: it fires at the start of that move, and unlike a bare
//!     `$OUT[n]=…` it does not stop the advance run, so `C_DIS` approximation is kept;
//!   - `$VEL.CP` and `$APO.CDIS` are set at the start of every file and before any move whose
//!     value differs; exact stops (no `C_DIS`) where the program model asks for them;
//!   - a sub-program that starts clean initialises itself (`BAS(#INITMOV,0)`, `$TOOL`,
//!     `$LOAD`, `$BASE` from the cell's numbered data, `$ORI_TYPE`, process output off,
//!     `BAS(#VEL_PTP,`[`KRL_PTP_VELOCITY_PERCENT`]`)`), so it runs on its own.

use super::export::{
    bad_option, check_common, check_identifier, comment_lines, finish, header_notes, num,
    part_note, program, ExportFile, ExportOptions, Motion, DEG_DECIMALS, KRL_DEFAULT_MAX_MOVES,
    MM_DECIMALS, ROBOT_LINE_WIDTH,
};
use super::frames::continuous_euler_zyx_deg;
use super::names::krl_clash;
use super::path::{ToolPath, ToolPathError};
use crate::math::Real;
use std::fmt::Write;

/// Longest KRL name.
const KRL_MAX_IDENTIFIER: usize = 24;
/// Highest output number accepted for `$OUT[n]`.
pub const KRL_MAX_OUTPUT: u32 = 4096;
/// Highest tool number (`TOOL_DATA[1..16]`).
pub const KRL_MAX_TOOL: u32 = 16;
/// Highest base number (`BASE_DATA[1..32]`).
pub const KRL_MAX_BASE: u32 = 32;

/// Axis speed of the joint move to the approach pose, percent of the maximum
/// (`BAS(#VEL_PTP, …)`): a cautious first move from wherever the robot stands.
pub const KRL_PTP_VELOCITY_PERCENT: u32 = 20;

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
    let o = &options.krl;
    let name = &options.name;
    let part_name = |k: usize| format!("{name}_{k}");
    let id = |value: &str| check_identifier("name", value, KRL_MAX_IDENTIFIER, krl_clash, "KRL");
    id(name)?;
    for (option, value, max) in [
        ("krlOutput", o.process_output, KRL_MAX_OUTPUT),
        ("krlTool", o.tool, KRL_MAX_TOOL),
        ("krlBase", o.base, KRL_MAX_BASE),
    ] {
        if !(1..=max).contains(&value) {
            return Err(bad_option(
                option,
                format!("must be in 1..={max}, got {value}"),
            ));
        }
    }
    for (option, value) in [
        ("krlApproximationProcessMm", o.approximation_process_mm),
        ("krlApproximationLinkMm", o.approximation_link_mm),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(bad_option(
                option,
                format!(
                    "must be finite and ≥ 0 mm, got {}",
                    crate::math::Compact(value)
                ),
            ));
        }
    }
    let program = program(path, options, KRL_DEFAULT_MAX_MOVES)?;
    let last = program.parts.len();
    id(&part_name(last))?;

    let moves = &program.moves;
    let frames: Vec<_> = moves.iter().map(|m| m.frame).collect();
    let angles = continuous_euler_zyx_deg(&frames, o.unwrap_angles);
    let width = ROBOT_LINE_WIDTH;
    let out_n = o.process_output;
    let mut files = Vec::with_capacity(last + 1);

    let mut main = String::new();
    let _ = writeln!(main, "DEF {name}()");
    let extra = [
        format!(
            "Cell set-up: output $OUT[{out_n}] must be the process signal in the cell's I/O \
             configuration: a TRIGGER at the start of the first move with a different state \
             sets it TRUE or FALSE."
        ),
        format!(
            "TOOL_DATA[{t}] and LOAD_DATA[{t}] must hold the tool (TCP and load; unset, the \
             TCP is at the flange) and BASE_DATA[{b}] the part's frame (the frame of the \
             model's coordinates); the numbers are options.",
            t = o.tool,
            b = o.base
        ),
        if o.unwrap_angles {
            "Orientation A, B, C in degrees, R = Rz(A)*Ry(B)*Rx(C), B in [-90, 90]; A and C \
             unwrapped beyond +-180 deg (within +-360) for continuity: only for a controller \
             known to accept them. $VEL.CP in m/s."
                .into()
        } else {
            "Orientation A, B, C in degrees, R = Rz(A)*Ry(B)*Rx(C), A and C in [-180, 180], \
             B in [-90, 90]. $VEL.CP in m/s."
                .into()
        },
        format!(
            "The approach PTP runs at {KRL_PTP_VELOCITY_PERCENT} % axis speed \
             (BAS(#VEL_PTP,{KRL_PTP_VELOCITY_PERCENT}))."
        ),
        format!(
            "{last} sub-programs of at most {} path moves, called in order below.",
            program.max_moves
        ),
    ];
    for line in header_notes(path, options, &program, &extra) {
        for l in comment_lines(&line, width - 4) {
            let _ = writeln!(main, "  ; {l}");
        }
    }
    for k in 1..=last {
        let _ = writeln!(main, "  {}()", part_name(k));
    }
    main.push_str("END\n");
    files.push(ExportFile {
        file_name: format!("{name}.src"),
        text: finish(main, options.line_ending),
    });

    let mut process_on = false;
    for (index, part) in program.parts.iter().enumerate() {
        let k = index + 1;
        let mut text = String::new();
        let _ = writeln!(text, "DEF {}()", part_name(k));
        let note = format!(
            "{} Settings and cell set-up: see {name}.src.",
            part_note(&program, index, &format!("{name}.src"))
        );
        for l in comment_lines(&note, width - 4) {
            let _ = writeln!(text, "  ; {l}");
        }
        if part.starts_clean {
            text.push_str("  BAS(#INITMOV,0)\n");
            let _ = writeln!(text, "  $TOOL = TOOL_DATA[{}]", o.tool);
            let _ = writeln!(text, "  $LOAD = LOAD_DATA[{}]", o.tool);
            let _ = writeln!(text, "  $BASE = BASE_DATA[{}]", o.base);
            text.push_str("  $ORI_TYPE = #VAR\n");
            let _ = writeln!(text, "  $OUT[{out_n}] = FALSE");
            let _ = writeln!(text, "  BAS(#VEL_PTP,{KRL_PTP_VELOCITY_PERCENT})");
            process_on = false;
        }
        let mut speed: Option<String> = None;
        let mut apo: Option<Real> = None;
        for i in part.moves.clone() {
            let m = &moves[i];
            let [x, y, z] = m.position_mm.map(|c| num(c, MM_DECIMALS));
            let [a, b, c] = angles[i].map(|c| num(c, DEG_DECIMALS));
            let frame = format!("{{X {x},Y {y},Z {z},A {a},B {b},C {c}}}");
            if m.motion == Motion::Joint {
                // PTP speed comes from BAS(#VEL_PTP); the process is off (reset above).
                let _ = writeln!(text, "  PTP {frame}");
                continue;
            }
            // Compared as written: speeds that print alike are one speed to the controller.
            let v = num(m.speed_mm_s / 1000.0, MM_DECIMALS);
            if speed.as_ref() != Some(&v) {
                let _ = writeln!(text, "  $VEL.CP = {v}");
                speed = Some(v);
            }
            let a = if m.process_on {
                o.approximation_process_mm
            } else {
                o.approximation_link_mm
            };
            if !m.exact && apo != Some(a) {
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
            let approximation = if m.exact { "" } else { " C_DIS" };
            let _ = writeln!(text, "  LIN {frame}{approximation}");
        }
        text.push_str("END\n");
        files.push(ExportFile {
            file_name: format!("{}.src", part_name(k)),
            text: finish(text, options.line_ending),
        });
    }
    Ok(files)
}
