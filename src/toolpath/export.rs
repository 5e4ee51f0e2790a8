//! Exports of a [`ToolPath`]: CSV, JSON, ABB RAPID, KUKA KRL. (Skeleton: the formats are
//! being written; signatures are fixed.)

use super::path::{ToolPath, ToolPathError};
use crate::math::Real;

/// Options shared by the exports.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportOptions {
    /// Millimetres per mesh unit (1000 for a file in metres). Robot programs are in mm.
    pub mm_per_unit: Real,
    /// Module / program name (letters, digits, underscore; starts with a letter).
    pub name: String,
    /// At most this many moves per procedure (RAPID) or file (KRL); default 5000 / 1400.
    pub max_moves: Option<usize>,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            mm_per_unit: 1.0,
            name: "skinpath".into(),
            max_moves: None,
        }
    }
}

/// CSV with a header row: one line per pose.
pub fn to_csv(path: &ToolPath, options: &ExportOptions) -> Result<String, ToolPathError> {
    path.validate()?;
    let _ = options;
    Ok(String::new())
}

/// JSON document of the path.
pub fn to_json(path: &ToolPath, options: &ExportOptions) -> Result<String, ToolPathError> {
    path.validate()?;
    let _ = options;
    Ok(String::new())
}

/// ABB RAPID: one string per file (the main module first).
pub fn to_rapid(path: &ToolPath, options: &ExportOptions) -> Result<Vec<String>, ToolPathError> {
    path.validate()?;
    let _ = options;
    Ok(Vec::new())
}

/// KUKA KRL `.src` files: one string per file (the main program first).
pub fn to_krl(path: &ToolPath, options: &ExportOptions) -> Result<Vec<String>, ToolPathError> {
    path.validate()?;
    let _ = options;
    Ok(Vec::new())
}
