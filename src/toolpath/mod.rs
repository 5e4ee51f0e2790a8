//! Tool paths shared by every system (spray passes, geodesic passes, drilling poses) and their
//! exports for a robot cell or a colleague: CSV, JSON, ABB RAPID and KUKA KRL.
//!
//! A [`ToolPath`] is a sequence of [`Pose`]s in the mesh's own length unit; every export is in
//! millimetres (scaled by [`ExportOptions::mm_per_unit`]) and speeds in mm/s (m/s for KRL's
//! `$VEL.CP`). Exports refuse an invalid path ([`ToolPath::validate`]), an empty one
//! ([`ToolPathError::Empty`]) and bad options ([`ToolPathError::BadOption`] naming the option).
//! The text is deterministic (no dates), ASCII in the robot programs, with LF line endings
//! unless [`ExportOptions::line_ending`] asks for CRLF (both controllers read either).
//!
//! # Tool frame
//! Z is the tool axis (`pose.axis`, from the tool towards the part), X the travel direction
//! (`pose.travel`) made perpendicular to Z, Y = Z × X (right-handed). When the travel
//! direction is within 1e-6 rad of the axis (a drilling approach), X is the previous pose's X
//! made perpendicular to the new Z, or for the first pose (or if that is parallel too) the world
//! axis least aligned with Z (X, then Y, then Z). See [`frames`].
//!
//! # CSV
//! Header row `index,pass,kind,x_mm,y_mm,z_mm,ax,ay,az,tx,ty,tz,process,speed_mm_s`, then one
//! line per pose: positions in mm to 1e-6, unit axis and travel to 1e-9, the kind's name
//! (`pass`, `straightTransition`, `arc`, `extension`, `link`, `approach`, `retract`),
//! `process` 1/0 and the speed of the move to the pose. No comment lines (a spreadsheet would
//! take them for data); the decimal separator is `.`.
//!
//! # JSON
//! ```text
//! { "format": "skinpath-toolpath", "version": 2, "name": "skinpath",
//!   "unit": "mm", "speedUnit": "mm/s", "speed": 400, "linkSpeed": 1000,
//!   "varyingSpeed": false, "poseCount": 2, "passCount": 1, "frame": "Z = axis …",
//!   "notes": ["…"],
//!   "poses": [ { "position": [x, y, z], "axis": [ax, ay, az], "travel": [tx, ty, tz],
//!                "kind": "pass", "kindCode": 0, "pass": 0, "processOn": true,
//!                "speed": 400 }, … ] }
//! ```
//! `speed` of a pose is that of the move arriving at it ([`ToolPath::move_speed`]); version 2
//! added it and `varyingSpeed`.
//! Numbers are the shortest decimals that read back to the same `f64` (no exponents).
//! `kindCode` is [`PoseKind::code`]; `version` grows when the schema changes.
//!
//! # Robot programs (both)
//! What the controller runs, built once for both languages:
//! - **Targets.** One move per pose, except that consecutive poses at one position (within
//!   [`ZERO_MOVE_REL_TOL`] of the path's extent, at least [`ZERO_MOVE_MIN_MM`]) are one
//!   target: a fly-by move of zero length makes the controller slow down or stop (a paint
//!   dwell). The target keeps the first pose's position, process state and speed and the last
//!   pose's orientation; the header counts the merged moves.
//! - **Parts.** Long paths are cut into parts of at most [`ExportOptions::max_moves`] path
//!   moves (defaults 5000 for RAPID, 1400 for KRL), preferably before a move with the
//!   process off. Such a part *starts clean*: process off, then a joint move (`MoveJ` /
//!   `PTP`) to an approach pose [`ExportOptions::approach_clearance_mm`] (default 50 mm) back
//!   along the first pose's tool axis, then the linear path; and the part before it *ends
//!   clean*: a linear retract the same distance back along its last pose's axis, process
//!   off, exact stop. Clean parts run on their own. Only where a budget's worth of moves has
//!   the process on throughout is a part cut with the process on: it then continues the
//!   previous part and says so in its comments. The first part always starts clean and the
//!   last always ends clean. The approach and retract are not counted in the budget.
//! - **Process.** The move to a target runs with the process on when the first pose's kind
//!   is a process kind ([`PoseKind::process_on`]), except the move from an approach pose.
//!   The process hook is written exactly where the state changes, before the move.
//! - **Speeds.** [`ToolPath::move_speed`] of the target's first pose (the path's speed with
//!   the process on, the link speed off, unless the path has per-move speeds); approach and
//!   retract at the link speed.
//! - **Exact stops** (RAPID `fine`, KRL without `C_DIS`): every approach and retract, every
//!   target where the path turns back by more than [`REVERSAL_ANGLE_DEG`] (the robot would
//!   reverse inside the zone and never reach it), and every process target followed by a
//!   retract pose (a drilled depth). Other moves are fly-by.
//! - **Header.** Notes (generator, counts, speeds, conventions, the cell set-up, then
//!   [`ToolPath::notes`]) are comments at the top of the main file; each part says how it runs.
//!
//! # ABB RAPID ([`to_rapid`], [`rapid_files`])
//! `MoveL [[x,y,z],[q1,q2,q3,q4],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],v_process,z1,
//! tSkinpath\WObj:=wSkinpath;` with the quaternion `[w,x,y,z]` of the tool frame (signs
//! continuous from move to move), `confdata` and `extjoint` placeholders, speeds as
//! `CONST speeddata v_process/v_link := [v,500,5000,1000]` (mm/s) or, with per-move speeds,
//! one `v_<mm/s>` per distinct speed rounded to 1 mm/s (coarser when more than
//! [`RAPID_MAX_SPEEDDATA`] would be needed; the header states the resolution), zones from
//! [`RapidOptions`] (`z1` with the process on, `z10` off, `fine` at exact stops), `PERS
//! tooldata` and `PERS wobjdata` placeholders the cell sets, and `SetDO doProcess,1|0;` as the
//! process hook (signal name an option). Every clean part begins `ConfJ\Off; ConfL\Off;` (the
//! confdata are placeholders; `rapid.config_check` writes `\On` instead for a cell with real
//! confdata) and `SetDO doProcess,0;`, then `MoveJ` to its approach pose. Parts are
//! procedures `<name>_<k>`; a single part shares the module `<name>.mod` with the data and
//! the entry routine (`main`), several parts get one module each (`<name>_mod<k>.mod`) so no
//! file exceeds one part. Lines stay within 80 characters; numbers are fixed-point
//! (positions 1e-6 mm, quaternions 1e-9). Names that clash with RAPID's reserved words or
//! predefined names (`MoveL`, `tool0`, `v1000`, `z10`, `fine`, …, and the export's own `v_`
//! prefix) are refused, case-insensitively.
//!
//! # KUKA KRL ([`to_krl`], [`krl_files`])
//! `<name>.src` calls `<name>_1()` … in order; each `<name>_<k>.src` (`DEF <name>_<k>()` …
//! `END`, no `.dat`) that starts clean runs `BAS(#INITMOV,0)`, sets `$TOOL`/`$LOAD`/`$BASE`
//! from the numbered cell data (placeholders in [`KrlOptions`]), `$ORI_TYPE = #VAR`, switches
//! `$OUT[n]` off, sets `BAS(#VEL_PTP,`[`KRL_PTP_VELOCITY_PERCENT`]`)` and moves `PTP` to its
//! approach pose; then `LIN {X x,Y y,Z z,A a,B b,C c} C_DIS` moves with
//! `R = Rz(A)·Ry(B)·Rx(C)` in degrees, `$VEL.CP` (m/s) and `$APO.CDIS` (mm) set at the top
//! of each file and whenever they change, and `TRIGGER WHEN DISTANCE=0 DELAY=0 DO
//! $OUT[n]=TRUE|FALSE` as the process hook (it keeps the approximation, a bare `$OUT` would
//! stop the advance run). A and C are in (−180°, 180°] and B in [−90°, 90°] as KUKA
//! documents, A unchanged through gimbal lock; `krl.unwrap_angles` unwraps A and C across
//! ±180° while within ±360° for controllers known to accept it (the controller interpolates
//! the orientation between frames, so the representation never changes the motion). Names
//! that clash with KRL's keywords and predefined names (`BAS`, `INI`, `PTP`, `TOOL_DATA`,
//! …) are refused, case-insensitively.

mod csv;
mod export;
pub mod frames;
mod json;
mod krl;
mod names;
mod path;
mod rapid;

pub use csv::{to_csv, CSV_HEADER};
pub use export::{
    ExportFile, ExportOptions, KrlOptions, LineEnding, RapidOptions, DEFAULT_APPROACH_CLEARANCE_MM,
    KRL_DEFAULT_MAX_MOVES, MIN_APPROACH_CLEARANCE_MM, RAPID_DEFAULT_MAX_MOVES, REVERSAL_ANGLE_DEG,
    ZERO_MOVE_MIN_MM, ZERO_MOVE_REL_TOL,
};
pub use json::{to_json, JSON_FORMAT, JSON_VERSION};
pub use krl::{krl_files, to_krl};
pub use krl::{KRL_MAX_BASE, KRL_MAX_OUTPUT, KRL_MAX_TOOL, KRL_PTP_VELOCITY_PERCENT};
pub use path::{Pose, PoseKind, ToolPath, ToolPathError};
pub use rapid::{
    rapid_files, to_rapid, RAPID_LINK_SPEED, RAPID_MAX_SPEEDDATA, RAPID_PROCESS_SPEED,
};
