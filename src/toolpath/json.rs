//! JSON export: a self-describing document, one pose per line.
//!
//! Source: RFC 8259 JSON; the schema is this crate's (documented in the module doc of
//!         `toolpath`).
//! Input:  a checked [`ToolPath`] and the unit scale.
//! Output: `{ format: "skinpath-toolpath", version: 2, …, poses: [...] }`.
//! Cost:   O(poses).
//! Deviations: numbers are the shortest decimal that reads back to the same `f64` (exact round
//!         trip), never in exponent notation.

use super::export::{check_common, finish, ExportOptions};
use super::path::{ToolPath, ToolPathError};
use crate::math::{Real, Vector3};
use std::fmt::Write;

/// The value of the document's `format` field.
pub const JSON_FORMAT: &str = "skinpath-toolpath";
/// The value of the document's `version` field; it grows when the schema changes.
pub const JSON_VERSION: u32 = 2;

/// The JSON document of the path (schema in the module doc of `toolpath`): positions and
/// speeds in mm and mm/s whatever the mesh unit, unit vectors as given.
pub fn to_json(path: &ToolPath, options: &ExportOptions) -> Result<String, ToolPathError> {
    check_common(path, options)?;
    let k = options.mm_per_unit;
    let mut out = String::with_capacity(200 * (path.poses.len() + 4));
    out.push_str("{\n");
    // Writing to a String cannot fail: the results of write! are ignored below.
    let _ = writeln!(out, "  \"format\": {},", string(JSON_FORMAT));
    let _ = writeln!(out, "  \"version\": {JSON_VERSION},");
    let _ = writeln!(out, "  \"name\": {},", string(&options.name));
    out.push_str("  \"unit\": \"mm\",\n  \"speedUnit\": \"mm/s\",\n");
    let _ = writeln!(out, "  \"speed\": {},", number(path.speed * k));
    let _ = writeln!(out, "  \"linkSpeed\": {},", number(path.link_speed * k));
    let _ = writeln!(out, "  \"varyingSpeed\": {},", path.has_varying_speed());
    let _ = writeln!(out, "  \"poseCount\": {},", path.poses.len());
    let _ = writeln!(out, "  \"passCount\": {},", path.pass_count());
    out.push_str(
        "  \"frame\": \"Z = axis (towards the part), X = travel re-orthogonalised against Z, \
         Y = Z x X\",\n",
    );
    out.push_str("  \"notes\": [");
    for (i, note) in path.notes.iter().enumerate() {
        out.push_str(if i == 0 { "\n    " } else { ",\n    " });
        out.push_str(&string(note));
    }
    out.push_str(if path.notes.is_empty() {
        "],\n"
    } else {
        "\n  ],\n"
    });
    out.push_str("  \"poses\": [\n");
    for (i, p) in path.poses.iter().enumerate() {
        let _ = write!(
            out,
            "    {{\"position\": {}, \"axis\": {}, \"travel\": {}, \"kind\": {}, \"kindCode\": {}, \
             \"pass\": {}, \"processOn\": {}, \"speed\": {}}}",
            vector(&(p.position.coords * k)),
            vector(&p.axis),
            vector(&p.travel),
            string(p.kind.name()),
            p.kind.code(),
            p.pass,
            p.kind.process_on(),
            number(path.move_speed(i) * k),
        );
        out.push_str(if i + 1 < path.poses.len() {
            ",\n"
        } else {
            "\n"
        });
    }
    out.push_str("  ]\n}\n");
    Ok(finish(out, options.line_ending))
}

/// The shortest decimal that reads back to `v` (finite by the path checks); `0` for `-0`.
fn number(v: Real) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v}")
    }
}

fn vector(v: &Vector3) -> String {
    format!("[{}, {}, {}]", number(v.x), number(v.y), number(v.z))
}

/// A JSON string literal with the escapes RFC 8259 requires.
fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_are_escaped() {
        assert_eq!(string("a\"b\\c\n\u{1}é"), "\"a\\\"b\\\\c\\n\\u0001é\"");
    }

    #[test]
    fn numbers_round_trip_without_exponent() {
        for v in [1e-7, 123456789.123, -0.0, 1e21, 0.1 + 0.2] {
            let s = number(v);
            assert!(!s.contains('e') && !s.contains('E'), "{s}");
            assert_eq!(s.parse::<f64>().unwrap(), v);
        }
    }
}
