//! CSV export: a header row, then one line per pose.
//!
//! Source: RFC 4180 layout (comma-separated, header row, no quoting needed: every field is a
//!         number or a fixed kind name).
//! Input:  a checked [`ToolPath`] and the unit scale.
//! Output: `index,pass,kind,x_mm,y_mm,z_mm,ax,ay,az,tx,ty,tz,process,speed_mm_s`.
//! Cost:   O(poses).
//! Deviations: no comment or note lines (a spreadsheet would read them as data); the notes go
//!         into the JSON and the robot programs.

use super::export::{check_common, finish, num, ExportOptions, MM_DECIMALS, UNIT_DECIMALS};
use super::path::{ToolPath, ToolPathError};
use std::fmt::Write;

/// The CSV header row (without the line ending).
pub const CSV_HEADER: &str = "index,pass,kind,x_mm,y_mm,z_mm,ax,ay,az,tx,ty,tz,process,speed_mm_s";

/// CSV with a header row ([`CSV_HEADER`]) and one line per pose: positions in mm to 1e-6 mm,
/// unit axis and travel to 1e-9, `process` 1/0 from the pose kind, and the speed (mm/s) of the
/// move to the pose ([`ToolPath::move_speed`]: the plan's per-move speed when it has them,
/// else the process speed when the process is on and the link speed when it is off).
pub fn to_csv(path: &ToolPath, options: &ExportOptions) -> Result<String, ToolPathError> {
    check_common(path, options)?;
    let k = options.mm_per_unit;
    let mut out = String::with_capacity(120 * (path.poses.len() + 1));
    out.push_str(CSV_HEADER);
    out.push('\n');
    for (i, p) in path.poses.iter().enumerate() {
        let on = p.kind.process_on();
        let speed = path.move_speed(i) * k;
        let mm = |c: f64| num(c * k, MM_DECIMALS);
        let unit = |c: f64| num(c, UNIT_DECIMALS);
        // Writing to a String cannot fail.
        let _ = writeln!(
            out,
            "{i},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            p.pass,
            p.kind.name(),
            mm(p.position.x),
            mm(p.position.y),
            mm(p.position.z),
            unit(p.axis.x),
            unit(p.axis.y),
            unit(p.axis.z),
            unit(p.travel.x),
            unit(p.travel.y),
            unit(p.travel.z),
            u8::from(on),
            num(speed, MM_DECIMALS),
        );
    }
    Ok(finish(out, options.line_ending))
}
