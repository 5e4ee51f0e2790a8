//! ABB RAPID export: a joint move to an approach pose, `MoveL` to inline robtargets, a
//! retract; split into procedures called from a main routine.
//!
//! Source: ABB "Technical reference manual – RAPID Instructions, Functions and Data types"
//!         (robtarget, orient, confdata, extjoint, speeddata, zonedata, tooldata, wobjdata,
//!         MoveJ, MoveL, SetDO, ConfJ, ConfL) and "RAPID kernel" (identifiers of at most 32
//!         characters, `!` comments, statements may span lines); reserved and predefined
//!         names in `names.rs`.
//! Input:  a checked [`ToolPath`], [`ExportOptions`] (with [`super::RapidOptions`]).
//! Output: one module text per file, main module first.
//! Cost:   O(poses).
//! Deviations (choices of this crate, documented in the `toolpath` module doc):
//!   - orientation `[q1,q2,q3,q4] = [w,x,y,z]` of the tool frame, signs kept continuous;
//!   - `confdata` `[0,0,0,0]` and `extjoint` `[9E9,…]` placeholders; so every part says
//!     `ConfJ\Off` and `ConfL\Off` before its first move (the controller's default, `\On`,
//!     stops at the first target whose configuration differs from the placeholder), unless
//!     `rapid.config_check` keeps the check for a cell that writes real confdata;
//!   - one procedure of at most `max_moves` path moves per part (plus its approach and
//!     retract); with more than one part every procedure gets its own module file;
//!   - the process hook is `SetDO signal,1|0;` before the first move of a different state
//!     (RAPID runs it as the robot starts rounding the previous target); a part that starts
//!     clean resets the signal first, and the program ends with the process off;
//!   - per-move speeds: one `speeddata` `v_<n>` per distinct rounded speed, each rounded to
//!     a step of ρ·v taken down to 1, 2 or 5 × 10^k mm/s and at least 1 mm/s (so whole mm/s,
//!     never below 1 mm/s), with the finest ρ of 0.5 %, 1 %, 2 %, 5 %, 10 %, 20 %, 50 % that
//!     declares at most [`RAPID_MAX_SPEEDDATA`]; wider ranges are refused;
//!   - lines stay within 80 characters (statements wrap after commas).

use super::export::{
    bad_option, check_common, check_identifier, comment_lines, finish, header_notes, num,
    part_note, program, ExportFile, ExportOptions, Motion, Move, MM_DECIMALS,
    RAPID_DEFAULT_MAX_MOVES, ROBOT_LINE_WIDTH, UNIT_DECIMALS,
};
use super::frames::continuous_quaternions;
use super::names::{rapid_clash, rapid_reserved_word};
use super::path::{ToolPath, ToolPathError};
use crate::math::Real;
use std::collections::BTreeSet;
use std::fmt::Write;

/// Longest RAPID identifier.
const RAPID_MAX_IDENTIFIER: usize = 32;
/// Orientation, external linear and rotational axis speeds of the generated `speeddata`
/// (deg/s, mm/s, deg/s): the values of ABB's predefined `v100`…`v1000`.
const RAPID_SPEED_TAIL: &str = "500,5000,1000";
/// Name of the process-speed `speeddata` constant.
pub const RAPID_PROCESS_SPEED: &str = "v_process";
/// Name of the link-speed `speeddata` constant (approach, retract, process-off moves).
pub const RAPID_LINK_SPEED: &str = "v_link";
/// At most this many per-move `speeddata` are declared (the resolution coarsens until
/// they fit).
pub const RAPID_MAX_SPEEDDATA: usize = 100;

/// ABB RAPID: one module text per file, the main module first (see [`rapid_files`]).
pub fn to_rapid(path: &ToolPath, options: &ExportOptions) -> Result<Vec<String>, ToolPathError> {
    Ok(rapid_files(path, options)?
        .into_iter()
        .map(|f| f.text)
        .collect())
}

/// The speeddata of each move: its name, and the declarations `(name, mm/s)` in order.
struct Speeds {
    names: Vec<String>,
    declared: Vec<(String, Real)>,
    /// With per-move speeds: the relative step (a fraction of the speed) they are rounded to.
    relative_step: Option<Real>,
}

/// Fastest per-move speed the export names (mm/s); faster ones are refused (a unit error).
const RAPID_MAX_SPEED_MM_S: Real = 1e12;
/// Relative steps tried for per-move speeds, finest first.
const SPEED_STEPS: [Real; 7] = [0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5];

/// `v` (mm/s) rounded to a step of `rho·v` taken down to 1, 2 or 5 × 10^k and at least
/// 1 mm/s; never below 1 mm/s. Returns whole mm/s.
fn round_speed(v: Real, rho: Real) -> u64 {
    let raw = rho * v;
    let step = if raw <= 1.0 {
        1.0
    } else {
        let decade = libm::pow(10.0, libm::floor(libm::log10(raw)));
        let mantissa = raw / decade;
        decade
            * if mantissa >= 5.0 {
                5.0
            } else if mantissa >= 2.0 {
                2.0
            } else {
                1.0
            }
    };
    ((libm::round(v / step) * step) as u64).max(1)
}

/// `v_process` / `v_link` for a path with one process speed; else one `v_<n>` per distinct
/// rounded speed of the path moves (approach and retract keep `v_link`).
fn speeddata(path: &ToolPath, moves: &[Move], k: Real) -> Result<Speeds, ToolPathError> {
    let mut declared = vec![
        (RAPID_PROCESS_SPEED.to_string(), path.speed * k),
        (RAPID_LINK_SPEED.to_string(), path.link_speed * k),
    ];
    if !path.has_varying_speed() {
        let names = moves
            .iter()
            .map(|m| {
                if m.process_on {
                    RAPID_PROCESS_SPEED
                } else {
                    RAPID_LINK_SPEED
                }
                .to_string()
            })
            .collect();
        return Ok(Speeds {
            names,
            declared,
            relative_step: None,
        });
    }
    let path_speeds = || {
        moves
            .iter()
            .filter(|m| m.pose.is_some())
            .map(|m| m.speed_mm_s)
    };
    if let Some(v) = path_speeds().find(|&v| v > RAPID_MAX_SPEED_MM_S) {
        return Err(bad_option(
            "speeds",
            format!(
                "a move at {} mm/s is beyond any robot (at most {RAPID_MAX_SPEED_MM_S:e} mm/s \
                 can be named): check the unit",
                crate::math::Compact(v)
            ),
        ));
    }
    // The finest relative step at which the distinct rounded speeds fit the bound. Speeds
    // from 1 to 1e12 mm/s round to at most 3 values per decade at the coarsest step (1, 2,
    // 5 × 10^k), 36 in all, so the last step always fits.
    let rho = SPEED_STEPS
        .into_iter()
        .find(|&rho| {
            let distinct: BTreeSet<u64> = path_speeds().map(|v| round_speed(v, rho)).collect();
            distinct.len() <= RAPID_MAX_SPEEDDATA
        })
        .unwrap_or(SPEED_STEPS[SPEED_STEPS.len() - 1]);
    let mut seen = BTreeSet::new();
    let names = moves
        .iter()
        .map(|m| {
            if m.pose.is_none() {
                return RAPID_LINK_SPEED.to_string();
            }
            let v = round_speed(m.speed_mm_s, rho);
            if seen.insert(v) {
                declared.push((format!("v_{v}"), v as Real));
            }
            format!("v_{v}")
        })
        .collect();
    Ok(Speeds {
        names,
        declared,
        relative_step: Some(rho),
    })
}

/// ABB RAPID files. The path is cut into procedures `<name>_1`, `<name>_2`, … of at most
/// `max_moves` path moves, called in order by the entry routine (default `main`). One part:
/// a single module `<name>.mod` holds everything. Several parts: `<name>.mod` holds the data
/// and the entry routine, and `<name>_mod<k>.mod` holds procedure `<name>_<k>`.
pub fn rapid_files(
    path: &ToolPath,
    options: &ExportOptions,
) -> Result<Vec<ExportFile>, ToolPathError> {
    check_common(path, options)?;
    let o = &options.rapid;
    let name = &options.name;
    let id = |option, value: &str| {
        check_identifier(option, value, RAPID_MAX_IDENTIFIER, rapid_clash, "RAPID")
    };
    // Zones name zonedata of the controller or the cell (z1, fine): only the syntax and the
    // reserved words are checked.
    for (option, value) in [
        ("rapidZoneProcess", &o.zone_process),
        ("rapidZoneLink", &o.zone_link),
    ] {
        check_identifier(
            option,
            value,
            RAPID_MAX_IDENTIFIER,
            rapid_reserved_word,
            "RAPID",
        )?;
    }
    id("name", name)?;
    for (option, value) in [
        ("rapidTool", &o.tool),
        ("rapidWorkObject", &o.work_object),
        ("rapidSignal", &o.process_signal),
        ("rapidEntry", &o.entry),
    ] {
        id(option, value)?;
    }
    let program = program(path, options, RAPID_DEFAULT_MAX_MOVES)?;
    let last = program.parts.len();
    let proc_name = |k: usize| format!("{name}_{k}");
    let module_name = |k: usize| format!("{name}_mod{k}");
    id("name", &proc_name(last))?;
    if last > 1 {
        id("name", &module_name(last))?;
    }
    // Names this program declares must differ (RAPID is case-insensitive).
    let declared = [
        ("rapidTool", &o.tool),
        ("rapidWorkObject", &o.work_object),
        ("rapidSignal", &o.process_signal),
        ("rapidEntry", &o.entry),
    ];
    for (i, (option, value)) in declared.iter().enumerate() {
        let clash = declared[..i]
            .iter()
            .map(|(_, v)| v.as_str())
            .chain([name.as_str()])
            .any(|v| v.eq_ignore_ascii_case(value))
            || starts_with_part_name(value, name);
        if clash {
            return Err(bad_option(
                option,
                format!("{value:?} clashes with another name the RAPID program declares"),
            ));
        }
    }

    let k = options.mm_per_unit;
    let moves = &program.moves;
    let speeds = speeddata(path, moves, k)?;
    let frames: Vec<_> = moves.iter().map(|m| m.frame).collect();
    let quaternions = continuous_quaternions(&frames);
    let width = ROBOT_LINE_WIDTH;
    let mut files = Vec::with_capacity(last + 1);

    // The main module: header, data, entry routine (and the only part when there is one).
    let mut main = String::new();
    let _ = writeln!(main, "MODULE {name}");
    let (sig, tool, wobj) = (&o.process_signal, &o.tool, &o.work_object);
    let mut extra = vec![
        format!(
            "Cell set-up: the digital output {sig} must exist in the I/O configuration; \
             it switches the process (SetDO {sig},1 before the first move with the process \
             on, {sig},0 before the first move with it off)."
        ),
        format!(
            "PERS {tool} is a placeholder with the TCP at the flange: set the tool's TCP \
             and load. PERS {wobj} is a placeholder at the world origin: set it to the \
             part's frame (the frame of the model's coordinates)."
        ),
        if o.config_check {
            "Robtargets carry confdata [0,0,0,0] placeholders and the program keeps the \
             configuration check (ConfJ\\On, ConfL\\On): replace them with the cell's \
             confdata before running."
                .into()
        } else {
            "Robtargets carry confdata [0,0,0,0] placeholders, so each part says ConfJ\\Off \
             and ConfL\\Off: with the check on (the controller's default) the robot would \
             stop at the first target whose configuration differs. The controller picks the \
             configuration nearest the current one."
                .into()
        },
        "extjoint 9E9: no external axes.".into(),
        format!(
            "{last} parts of at most {} path moves, called in order by {}.",
            program.max_moves, o.entry
        ),
    ];
    if let Some(rho) = speeds.relative_step {
        extra.push(format!(
            "Per-move speeds: speeddata v_<mm/s>, each the plan's speed rounded to a step of \
             at most {} % of it (1, 2 or 5 x 10^k mm/s, at least 1 mm/s; never below \
             1 mm/s); {} declared.",
            num(rho * 100.0, 3),
            speeds.declared.len() - 2
        ));
    }
    for line in header_notes(path, options, &program, &extra) {
        for l in comment_lines(&line, width - 4) {
            let _ = writeln!(main, "  ! {l}");
        }
    }
    let _ = writeln!(
        main,
        "  PERS tooldata {tool} := [TRUE,[[0,0,0],[1,0,0,0]],\n    [1,[0,0,1],[1,0,0,0],0,0,0]];"
    );
    let _ = writeln!(
        main,
        "  PERS wobjdata {wobj} := [FALSE,TRUE,\"\",[[0,0,0],[1,0,0,0]],\n    \
         [[0,0,0],[1,0,0,0]]];"
    );
    for (constant, speed) in &speeds.declared {
        let _ = writeln!(
            main,
            "  CONST speeddata {constant} := [{},{RAPID_SPEED_TAIL}];",
            num(*speed, MM_DECIMALS)
        );
    }
    let _ = writeln!(main, "\n  PROC {}()", o.entry);
    for k in 1..=last {
        let _ = writeln!(main, "    {};", proc_name(k));
    }
    let _ = writeln!(main, "  ENDPROC");

    let conf = if o.config_check { "On" } else { "Off" };
    let mut process_on = false;
    let mut part_texts = Vec::with_capacity(last);
    for (index, part) in program.parts.iter().enumerate() {
        let mut text = String::new();
        let _ = writeln!(text, "\n  PROC {}()", proc_name(index + 1));
        for l in comment_lines(&part_note(&program, index, &o.entry), width - 6) {
            let _ = writeln!(text, "    ! {l}");
        }
        if part.starts_clean {
            let _ = writeln!(text, "    ! Configuration check: see the header of {name}.");
            let _ = writeln!(text, "    ConfJ\\{conf};\n    ConfL\\{conf};");
            let _ = writeln!(text, "    SetDO {sig},0;");
            process_on = false;
        }
        for i in part.moves.clone() {
            let m = &moves[i];
            if m.process_on != process_on {
                process_on = m.process_on;
                let _ = writeln!(text, "    SetDO {sig},{};", u8::from(process_on));
            }
            let p = m.position_mm.map(|c| num(c, MM_DECIMALS));
            let q = quaternions[i].map(|c| num(c, UNIT_DECIMALS));
            let zone = if m.exact {
                "fine"
            } else if m.process_on {
                o.zone_process.as_str()
            } else {
                o.zone_link.as_str()
            };
            let instruction = match m.motion {
                Motion::Joint => "MoveJ",
                Motion::Linear => "MoveL",
            };
            let pieces = [
                format!("{instruction} [[{},", p[0]),
                format!("{},", p[1]),
                format!("{}],", p[2]),
                format!("[{},", q[0]),
                format!("{},", q[1]),
                format!("{},", q[2]),
                format!("{}],", q[3]),
                "[0,0,0,0],".into(),
                "[9E9,9E9,9E9,9E9,9E9,9E9]],".into(),
                format!("{},", speeds.names[i]),
                format!("{zone},"),
                tool.clone(),
                format!("\\WObj:={wobj};"),
            ];
            wrap_statement(&mut text, &pieces, 4, 6, width);
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
            "Part {} of {last} of {name}: load with {name}.mod (it declares the tool, work \
             object and speeds); {} calls the parts in order.",
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
