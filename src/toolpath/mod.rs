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
//! { "format": "skinpath-toolpath", "version": 1, "name": "skinpath",
//!   "unit": "mm", "speedUnit": "mm/s", "speed": 400, "linkSpeed": 1000,
//!   "poseCount": 2, "passCount": 1, "frame": "Z = axis …", "notes": ["…"],
//!   "poses": [ { "position": [x, y, z], "axis": [ax, ay, az], "travel": [tx, ty, tz],
//!                "kind": "pass", "kindCode": 0, "pass": 0, "processOn": true }, … ] }
//! ```
//! Numbers are the shortest decimals that read back to the same `f64` (no exponents).
//! `kindCode` is [`PoseKind::code`]; `version` grows when the schema changes.
//!
//! # Robot programs (both)
//! One move per pose. The move to the first pose runs with the process off at the link speed
//! (the robot comes from wherever it stands); the move to any later pose runs with the process
//! on when its kind is a process kind ([`PoseKind::process_on`]) at the path's speed, else off
//! at the link speed. The process hook is written exactly where the state changes, before
//! the move; the main routine switches it off first and the program ends with it off. The
//! last move is an exact stop. Long paths are cut into parts of at most
//! [`ExportOptions::max_moves`] moves (defaults 5000 for RAPID, 1400 for KRL) that the main
//! routine calls in order; a part boundary never switches the process. Notes (generator,
//! counts, speeds, conventions, what to set in the cell, then [`ToolPath::notes`]) are
//! comments at the top of the main file.
//!
//! # ABB RAPID ([`to_rapid`], [`rapid_files`])
//! `MoveL [[x,y,z],[q1,q2,q3,q4],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],v_process,z1,
//! tSkinpath\WObj:=wSkinpath;` with the quaternion `[w,x,y,z]` of the tool frame (signs
//! continuous from move to move), `confdata` and `extjoint` placeholders, speeds as
//! `CONST speeddata v_process/v_link := [v,500,5000,1000]` (mm/s), zones from
//! [`RapidOptions`] (`z1` with the process on, `z10` off, `fine` at the end), `PERS tooldata`
//! and `PERS wobjdata` placeholders the cell sets, and `SetDO doProcess,1|0;` as the process
//! hook (signal name an option). Parts are procedures `<name>_<k>`; a single part shares the
//! module `<name>.mod` with the data and the entry routine (`main`), several parts get one
//! module each (`<name>_mod<k>.mod`) so no file exceeds one part. Lines stay within 80
//! characters; numbers are fixed-point (positions 1e-6 mm, quaternions 1e-9).
//!
//! # KUKA KRL ([`to_krl`], [`krl_files`])
//! `<name>.src` runs `BAS(#INITMOV,0)`, sets `$TOOL`/`$LOAD`/`$BASE` from the numbered cell
//! data (placeholders in [`KrlOptions`]), `$ORI_TYPE = #VAR`, switches `$OUT[n]` off and calls
//! `<name>_1()` … in order; each `<name>_<k>.src` (`DEF <name>_<k>()` … `END`, no `.dat`) holds
//! `LIN {X x,Y y,Z z,A a,B b,C c} C_DIS` moves with `R = Rz(A)·Ry(B)·Rx(C)` in degrees,
//! `$VEL.CP` (m/s) and `$APO.CDIS` (mm) set at the top of each file and whenever they change,
//! and `TRIGGER WHEN DISTANCE=0 DELAY=0 DO $OUT[n]=TRUE|FALSE` as the process hook (it keeps
//! the approximation, a bare `$OUT` would stop the advance run). A/B/C stay continuous: B in
//! [−90°, 90°], A unchanged through gimbal lock, A and C unwrapped across ±180° while
//! within ±360° (`krl.unwrap_angles`; the controller interpolates the orientation between
//! frames, so the representation never changes the motion).

mod csv;
mod export;
pub mod frames;
mod json;
mod krl;
mod path;
mod rapid;

pub use csv::{to_csv, CSV_HEADER};
pub use export::{
    ExportFile, ExportOptions, KrlOptions, LineEnding, RapidOptions, KRL_DEFAULT_MAX_MOVES,
    RAPID_DEFAULT_MAX_MOVES,
};
pub use json::{to_json, JSON_FORMAT, JSON_VERSION};
pub use krl::{krl_files, to_krl};
pub use path::{Pose, PoseKind, ToolPath, ToolPathError};
pub use rapid::{rapid_files, to_rapid, RAPID_LINK_SPEED, RAPID_PROCESS_SPEED};
