//! Reading a list of holes to drill from CSV text: `id,x,y,z` per line.
//!
//! Source: no paper; the hole-list format of the issue.
//! Input:  text; fields separated by commas (spaces around them ignored); an optional header
//!         on the first non-blank line (any line whose x, y, z are not all numbers there);
//!         blank lines and lines starting with `#` are skipped.
//! Output: [`HoleList`]: the good rows (id, position, line number) and one [`CsvRowError`]
//!         per bad row (1-based line number and why), so one bad row never loses the others.
//! Cost:   O(length of the text).

use crate::math::Point3;

/// A hole read from CSV.
#[derive(Clone, Debug, PartialEq)]
pub struct HoleRow {
    /// The hole's identifier (first field, trimmed, non-empty).
    pub id: String,
    /// Nominal position, in the file's unit.
    pub position: Point3,
    /// 1-based line number in the text.
    pub line: usize,
}

/// A CSV row that could not be read.
#[derive(Clone, Debug, PartialEq)]
pub struct CsvRowError {
    /// 1-based line number.
    pub line: usize,
    /// What is wrong with it.
    pub message: String,
}

/// Everything read from a hole CSV.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HoleList {
    /// Rows read, in file order.
    pub holes: Vec<HoleRow>,
    /// Rows refused, in file order.
    pub errors: Vec<CsvRowError>,
    /// Whether the first non-blank line was taken as a header.
    pub header: bool,
}

/// Parses `id,x,y,z` rows (see the module header).
pub fn parse_holes_csv(text: &str) -> HoleList {
    let mut list = HoleList::default();
    let mut first = true;
    let mut seen = std::collections::HashSet::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let row = raw.trim();
        if row.is_empty() || row.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = row.split(',').map(str::trim).collect();
        let numbers: Vec<Option<f64>> = fields.iter().skip(1).map(|f| f.parse().ok()).collect();
        if std::mem::take(&mut first) && !numbers.iter().all(Option::is_some) {
            list.header = true;
            continue;
        }
        let fail = |message: String| CsvRowError { line, message };
        if fields.len() != 4 {
            list.errors.push(fail(format!(
                "expected 4 fields id,x,y,z, found {}",
                fields.len()
            )));
            continue;
        }
        if fields[0].is_empty() {
            list.errors.push(fail("the id is empty".into()));
            continue;
        }
        let mut xyz = [0.0; 3];
        let mut bad = None;
        for (k, name) in ["x", "y", "z"].iter().enumerate() {
            match numbers[k] {
                Some(v) if v.is_finite() => xyz[k] = v,
                _ => {
                    bad = Some(format!(
                        "{name} = {:?} is not a finite number",
                        fields[k + 1]
                    ));
                    break;
                }
            }
        }
        if let Some(message) = bad {
            list.errors.push(fail(message));
            continue;
        }
        if !seen.insert(fields[0].to_string()) {
            list.errors
                .push(fail(format!("id {:?} repeats an earlier row", fields[0])));
            continue;
        }
        list.holes.push(HoleRow {
            id: fields[0].to_string(),
            position: Point3::new(xyz[0], xyz[1], xyz[2]),
            line,
        });
    }
    list
}
