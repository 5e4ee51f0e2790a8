//! Export options shared by every tool-path export (`toCsv`, `toJson`, `toRapid`, `toKrl` of
//! spray plans, geodesic passes and drilling poses).

use super::params::ParamReader;
use crate::toolpath::{ExportOptions, LineEnding};
use wasm_bindgen::prelude::*;

/// Keys of the JavaScript `ExportOptions`.
const EXPORT_KEYS: &[&str] = &["mmPerUnit", "name", "maxMoves", "lineEnding"];

/// Reads `{ mmPerUnit?, name?, maxMoves?, lineEnding? }` (`undefined` for the defaults);
/// the exports themselves refuse values out of range, naming the option.
pub(crate) fn export_options_from_js(value: &JsValue) -> Result<ExportOptions, JsError> {
    let mut options = ExportOptions::default();
    let Some(r) = ParamReader::optional_argument(value, "export option", EXPORT_KEYS)? else {
        return Ok(options);
    };
    if let Some(mm) = r.optional_number("mmPerUnit")? {
        options.mm_per_unit = mm;
    }
    if let Some(name) = r.optional_string("name")? {
        options.name = name;
    }
    if let Some(moves) = r.optional_integer("maxMoves", 0, 1 << 30)? {
        options.max_moves = Some(moves as usize);
    }
    if let Some(ending) = r.optional_choice("lineEnding", &["lf", "crlf"])? {
        options.line_ending = if ending == "crlf" {
            LineEnding::CrLf
        } else {
            LineEnding::Lf
        };
    }
    Ok(options)
}
