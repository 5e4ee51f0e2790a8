//! STL input (binary and ASCII) into a welded [`TriMesh`], and binary STL output.
//!
//! Source: the STL format as specified by 3D Systems (1989); binary layout: 80-byte header,
//! `u32` triangle count, then 50 bytes per triangle (normal, three corners as `f32` LE,
//! a `u16` attribute).
//! Format detection: a file is binary when `84 + 50·n` equals its size (some binary headers
//! start with `solid`); otherwise ASCII when it starts with `solid`; otherwise binary with
//! trailing bytes when `84 + 50·n` is smaller than the size.
//! Deviations: the file's normals are ignored (recomputed from the winding downstream);
//! triangles with a NaN or infinite coordinate are skipped and counted, not refused;
//! keywords are matched case-insensitively and a missing `endsolid` is tolerated.
//! Cost: one pass over the bytes; nothing is allocated from the header's count before the
//! file size confirms it.
//!
//! Reading is our own because the error messages must name the line of a malformed ASCII
//! number and the counts of a truncated binary file, which `stl_io`'s readers do not report;
//! writing goes through `stl_io::write_stl`.

use super::{MeshError, TriMesh, Welder, PROGRESS_EVERY};
use crate::math::Point3;

const HEADER_BYTES: usize = 80;
const BINARY_PREAMBLE: usize = HEADER_BYTES + 4;
const BINARY_TRIANGLE_BYTES: usize = 50;

/// Why bytes could not be read as STL. The messages are meant for the person who chose the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StlError {
    /// Zero bytes.
    #[error("the file is empty")]
    Empty,
    /// Neither ASCII (`solid …`) nor a binary layout that fits the file size.
    #[error("not an STL file: it does not start with 'solid' and is too short ({len} bytes) for a binary STL, which needs at least 84")]
    TooShort {
        /// File size in bytes.
        len: usize,
    },
    /// Neither ASCII nor binary: the binary header's count does not fit and the bytes after
    /// it are not triangles.
    #[error("not an STL file: it does not start with 'solid', and read as binary STL its header would claim {declared} triangles ({needed} bytes) for a file of {len} bytes")]
    NotStl {
        /// Triangle count in the header.
        declared: u64,
        /// Bytes that count needs.
        needed: u64,
        /// File size in bytes.
        len: usize,
    },
    /// A binary file of whole triangles whose header claims more of them than it holds.
    #[error("corrupt binary STL: the header says {declared} triangles, more than the file can hold ({present} whole triangles in {len} bytes); the count is wrong or the file was cut short")]
    CountTooLarge {
        /// Triangle count in the header.
        declared: u64,
        /// Whole triangles present.
        present: u64,
        /// File size in bytes.
        len: usize,
    },
    /// A binary file cut off before its last triangle.
    #[error("truncated binary STL: the header says {declared} triangles but only {present} are present (the file has {len} bytes, {needed} are needed)")]
    Truncated {
        /// Triangle count in the header.
        declared: u64,
        /// Whole triangles present.
        present: u64,
        /// File size in bytes.
        len: usize,
        /// Bytes the header's count needs.
        needed: u64,
    },
    /// An ASCII number that does not parse.
    #[error("malformed number '{token}' at line {line} of the ASCII STL")]
    BadNumber {
        /// 1-based line number.
        line: usize,
        /// The text that failed to parse (cut to 40 characters).
        token: String,
    },
    /// An ASCII line that breaks the grammar.
    #[error("ASCII STL syntax error at line {line}: expected {expected}, found '{found}'")]
    Syntax {
        /// 1-based line number.
        line: usize,
        /// What the grammar expected there.
        expected: &'static str,
        /// What the line holds (cut to 40 characters).
        found: String,
    },
    /// An ASCII file that ends inside a facet.
    #[error("the ASCII STL ends inside a facet (at line {line}): the file is truncated")]
    UnexpectedEnd {
        /// 1-based line number of the end.
        line: usize,
    },
    /// A facet with more or fewer than three vertices.
    #[error("the facet starting at line {line} has {count} vertices; STL facets are triangles")]
    NotATriangle {
        /// 1-based line of the facet's `facet` keyword.
        line: usize,
        /// Its vertex count.
        count: usize,
    },
    /// The file holds no triangles at all.
    #[error("the STL file contains no triangles")]
    NoTriangles,
    /// Every triangle had a NaN or infinite coordinate.
    #[error("no usable triangles: all {skipped} triangles have NaN or infinite coordinates")]
    NoUsableTriangles {
        /// How many were skipped.
        skipped: usize,
    },
    /// The welded mesh broke an invariant (too many vertices for 32-bit indices).
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// Which of the two STL encodings a file used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum StlFormat {
    /// 50 bytes per triangle.
    Binary,
    /// `solid … facet normal … endsolid` text.
    Ascii,
}

/// What the reader learnt about the file besides the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct StlInfo {
    /// The encoding.
    pub format: StlFormat,
    /// Triangles in the file, skipped ones included.
    pub triangles_in_file: usize,
    /// Triangles dropped for a NaN or infinite coordinate.
    pub skipped_triangles: usize,
    /// Bytes after a binary file's last triangle (0 for ASCII).
    pub trailing_bytes: usize,
}

/// A welded mesh and what the reader learnt about its file.
#[derive(Debug, Clone)]
pub struct StlImport {
    /// The welded mesh, in the file's winding.
    pub mesh: TriMesh,
    /// Format, counts, trailing bytes.
    pub info: StlInfo,
}

/// Reads binary or ASCII STL bytes into a welded mesh (bit-identical corners become one vertex).
pub fn read_stl(bytes: &[u8]) -> Result<StlImport, StlError> {
    read_stl_with_progress(bytes, &mut |_, _| {})
}

/// [`read_stl`] that reports `("parse", fraction)` now and then.
pub fn read_stl_with_progress(
    bytes: &[u8],
    progress: &mut dyn FnMut(&str, f64),
) -> Result<StlImport, StlError> {
    if bytes.is_empty() {
        return Err(StlError::Empty);
    }
    let starts_with_solid = starts_with_solid(bytes);
    if bytes.len() < BINARY_PREAMBLE {
        return if starts_with_solid {
            read_ascii(bytes, progress)
        } else {
            Err(StlError::TooShort { len: bytes.len() })
        };
    }
    let declared = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    let needed = BINARY_PREAMBLE as u64 + BINARY_TRIANGLE_BYTES as u64 * declared;
    let len = bytes.len() as u64;
    if needed == len {
        return read_binary(bytes, declared as usize, progress);
    }
    if starts_with_solid && looks_like_text(bytes) {
        return read_ascii(bytes, progress);
    }
    if needed < len {
        return read_binary(bytes, declared as usize, progress);
    }
    let present = (len - BINARY_PREAMBLE as u64) / BINARY_TRIANGLE_BYTES as u64;
    let whole = (len - BINARY_PREAMBLE as u64) % BINARY_TRIANGLE_BYTES as u64 == 0;
    if !looks_like_triangles(&bytes[BINARY_PREAMBLE..]) {
        Err(StlError::NotStl {
            declared,
            needed,
            len: bytes.len(),
        })
    } else if whole {
        Err(StlError::CountTooLarge {
            declared,
            present,
            len: bytes.len(),
        })
    } else {
        Err(StlError::Truncated {
            declared,
            present,
            len: bytes.len(),
            needed,
        })
    }
}

/// Whether the first (up to 256) 50-byte records after a binary header hold finite,
/// plausibly sized corners, as real triangles do and foreign bytes rarely do (no paper; a
/// plausibility test that tells a cut-off STL from another kind of file).
fn looks_like_triangles(data: &[u8]) -> bool {
    const PLAUSIBLE: f32 = 1e20;
    data.len() >= BINARY_TRIANGLE_BYTES
        && data.chunks_exact(BINARY_TRIANGLE_BYTES).take(256).all(|r| {
            r[12..48].chunks_exact(4).all(|b| {
                let c = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                c.is_finite() && c.abs() < PLAUSIBLE
            })
        })
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let trimmed = bytes.trim_ascii_start();
    trimmed.len() >= 5 && trimmed[..5].eq_ignore_ascii_case(b"solid")
}

/// ASCII STL is 7-bit text: no NUL or other control bytes but whitespace in its first kilobyte.
fn looks_like_text(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .take(1024)
        .all(|&b| b.is_ascii_graphic() || b.is_ascii_whitespace())
}

fn finish(welder: Welder, info: StlInfo) -> Result<StlImport, StlError> {
    if info.triangles_in_file == 0 {
        return Err(StlError::NoTriangles);
    }
    if welder.triangle_count() == 0 {
        return Err(StlError::NoUsableTriangles {
            skipped: info.skipped_triangles,
        });
    }
    let (positions, triangles) = welder.finish();
    Ok(StlImport {
        mesh: TriMesh::new(positions, triangles)?,
        info,
    })
}

fn read_binary(
    bytes: &[u8],
    count: usize,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<StlImport, StlError> {
    let data_end = BINARY_PREAMBLE + count * BINARY_TRIANGLE_BYTES;
    let mut welder = Welder::with_capacity(count);
    let mut skipped = 0;
    let f32_at = |chunk: &[u8], at: usize| {
        f32::from_le_bytes([chunk[at], chunk[at + 1], chunk[at + 2], chunk[at + 3]])
    };
    for (i, chunk) in bytes[BINARY_PREAMBLE..data_end]
        .chunks_exact(BINARY_TRIANGLE_BYTES)
        .enumerate()
    {
        if i % PROGRESS_EVERY == 0 {
            progress("parse", i as f64 / count as f64);
        }
        // Bytes 0..12 hold the file's normal, which is ignored.
        let corners: [[f32; 3]; 3] =
            std::array::from_fn(|c| std::array::from_fn(|k| f32_at(chunk, 12 + 12 * c + 4 * k)));
        if corners.iter().flatten().all(|c| c.is_finite()) {
            welder.add_triangle(&corners);
        } else {
            skipped += 1;
        }
    }
    progress("parse", 1.0);
    finish(
        welder,
        StlInfo {
            format: StlFormat::Binary,
            triangles_in_file: count,
            skipped_triangles: skipped,
            trailing_bytes: bytes.len() - data_end,
        },
    )
}

/// Lines of an ASCII file split into whitespace-separated tokens, with 1-based line numbers.
struct Lines<'a> {
    rest: &'a [u8],
    line: usize,
    total: usize,
}

impl<'a> Lines<'a> {
    /// The next non-blank line as (line number, tokens), or `None` at the end of the file.
    fn next_line(&mut self, tokens: &mut Vec<&'a [u8]>) -> Option<usize> {
        loop {
            if self.rest.is_empty() {
                return None;
            }
            let end = self
                .rest
                .iter()
                .position(|&b| b == b'\n')
                .unwrap_or(self.rest.len());
            let text = &self.rest[..end];
            self.rest = self.rest.get(end + 1..).unwrap_or(&[]);
            self.line += 1;
            tokens.clear();
            tokens.extend(
                text.split(|b| b.is_ascii_whitespace())
                    .filter(|t| !t.is_empty()),
            );
            if !tokens.is_empty() {
                return Some(self.line);
            }
        }
    }

    fn consumed_fraction(&self) -> f64 {
        1.0 - self.rest.len() as f64 / self.total.max(1) as f64
    }
}

fn shown(tokens: &[&[u8]]) -> String {
    let joined = tokens
        .iter()
        .map(|t| String::from_utf8_lossy(t))
        .collect::<Vec<_>>()
        .join(" ");
    joined.chars().take(40).collect()
}

fn keyword(token: Option<&&[u8]>, word: &str) -> bool {
    token.is_some_and(|t| t.eq_ignore_ascii_case(word.as_bytes()))
}

fn parse_number(token: &[u8], line: usize) -> Result<f32, StlError> {
    std::str::from_utf8(token)
        .ok()
        .and_then(|s| s.parse::<f32>().ok())
        .ok_or_else(|| StlError::BadNumber {
            line,
            token: shown(&[token]),
        })
}

/// Reads the next line and checks that it starts with `word`.
fn expect_line<'a>(
    lines: &mut Lines<'a>,
    tokens: &mut Vec<&'a [u8]>,
    word: &'static str,
) -> Result<usize, StlError> {
    match lines.next_line(tokens) {
        None => Err(StlError::UnexpectedEnd { line: lines.line }),
        Some(line) if keyword(tokens.first(), word) => Ok(line),
        Some(line) => Err(StlError::Syntax {
            line,
            expected: word,
            found: shown(tokens),
        }),
    }
}

fn read_ascii(bytes: &[u8], progress: &mut dyn FnMut(&str, f64)) -> Result<StlImport, StlError> {
    parse_ascii(bytes, progress).map_err(|e| match e {
        // A bad last line with no line break is a file cut off mid-line.
        StlError::Syntax { line, .. } | StlError::BadNumber { line, .. }
            if !bytes.ends_with(b"\n") && line == bytes.split(|&b| b == b'\n').count() =>
        {
            StlError::UnexpectedEnd { line }
        }
        e => e,
    })
}

fn parse_ascii(bytes: &[u8], progress: &mut dyn FnMut(&str, f64)) -> Result<StlImport, StlError> {
    // A facet takes about 250 bytes of text; the hint only sizes the first allocation.
    let mut welder = Welder::with_capacity(bytes.len() / 250);
    let mut lines = Lines {
        rest: bytes,
        line: 0,
        total: bytes.len(),
    };
    let mut tokens = Vec::with_capacity(8);
    let (mut in_file, mut skipped) = (0usize, 0usize);
    let syntax = |line, expected, tokens: &[&[u8]]| StlError::Syntax {
        line,
        expected,
        found: shown(tokens),
    };
    let mut in_solid = false;
    while let Some(line) = lines.next_line(&mut tokens) {
        let first = tokens.first();
        if keyword(first, "solid") {
            in_solid = true;
            continue;
        }
        if keyword(first, "endsolid") {
            in_solid = false;
            continue;
        }
        if !keyword(first, "facet") {
            let expected = if in_solid {
                "'facet' or 'endsolid'"
            } else {
                "'solid'"
            };
            return Err(syntax(line, expected, &tokens));
        }
        let facet_line = line;
        let mut corners = [[0f32; 3]; 3];
        let mut count = 0usize;
        expect_line(&mut lines, &mut tokens, "outer")?;
        loop {
            let Some(line) = lines.next_line(&mut tokens) else {
                return Err(StlError::UnexpectedEnd { line: lines.line });
            };
            if keyword(tokens.first(), "endloop") {
                break;
            }
            if !keyword(tokens.first(), "vertex") {
                return Err(syntax(line, "'vertex' or 'endloop'", &tokens));
            }
            if tokens.len() != 4 {
                return Err(syntax(line, "'vertex x y z'", &tokens));
            }
            let mut xyz = [0f32; 3];
            for (k, token) in tokens[1..4].iter().enumerate() {
                xyz[k] = parse_number(token, line)?;
            }
            if count < 3 {
                corners[count] = xyz;
            }
            count += 1;
        }
        expect_line(&mut lines, &mut tokens, "endfacet")?;
        if count != 3 {
            return Err(StlError::NotATriangle {
                line: facet_line,
                count,
            });
        }
        in_file += 1;
        if corners.iter().flatten().all(|c| c.is_finite()) {
            welder.add_triangle(&corners);
        } else {
            skipped += 1;
        }
        if in_file % PROGRESS_EVERY == 0 {
            progress("parse", lines.consumed_fraction());
        }
    }
    progress("parse", 1.0);
    finish(
        welder,
        StlInfo {
            format: StlFormat::Ascii,
            triangles_in_file: in_file,
            skipped_triangles: skipped,
            trailing_bytes: 0,
        },
    )
}

/// Writes the given triangles as a binary STL, each with its unit normal from the winding.
pub fn write_stl<I>(triangles: I) -> Vec<u8>
where
    I: ExactSizeIterator<Item = [Point3; 3]>,
{
    let to_vertex = |p: &Point3| stl_io::Vertex::new([p.x as f32, p.y as f32, p.z as f32]);
    let stl_triangles = triangles.map(|[a, b, c]| {
        let n = (b - a).cross(&(c - a));
        let n = n.try_normalize(0.0).unwrap_or_else(nalgebra::zero);
        stl_io::Triangle {
            normal: stl_io::Normal::new([n.x as f32, n.y as f32, n.z as f32]),
            vertices: [to_vertex(&a), to_vertex(&b), to_vertex(&c)],
        }
    });
    let mut out = Vec::with_capacity(BINARY_PREAMBLE + BINARY_TRIANGLE_BYTES * stl_triangles.len());
    stl_io::write_stl(&mut out, stl_triangles).expect("writing to a Vec<u8> cannot fail");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary(count_in_header: u32, triangles: usize, extra: usize) -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b.extend_from_slice(&count_in_header.to_le_bytes());
        for t in 0..triangles {
            let mut tri = [0f32; 12];
            tri[3..12].copy_from_slice(&[0.0, 0.0, t as f32, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
            tri.iter()
                .for_each(|f| b.extend_from_slice(&f.to_le_bytes()));
            b.extend_from_slice(&[0, 0]);
        }
        b.extend(std::iter::repeat_n(7u8, extra));
        b
    }

    #[test]
    fn binary_with_trailing_bytes_is_read_and_reported() {
        let import = read_stl(&binary(2, 2, 13)).unwrap();
        assert_eq!(import.mesh.triangle_count(), 2);
        assert_eq!(import.info.trailing_bytes, 13);
    }

    #[test]
    fn truncation_and_absurd_counts_are_told_apart() {
        let cut = &binary(3, 3, 0)[..84 + 50 * 2 + 10];
        assert!(matches!(
            read_stl(cut),
            Err(StlError::Truncated {
                declared: 3,
                present: 2,
                ..
            })
        ));
        assert!(matches!(
            read_stl(&binary(u32::MAX, 1, 0)),
            Err(StlError::CountTooLarge { present: 1, .. })
        ));
        let mut foreign = binary(1000, 0, 120);
        foreign[84..].fill(0xff);
        assert!(matches!(read_stl(&foreign), Err(StlError::NotStl { .. })));
    }

    #[test]
    fn ascii_errors_name_the_line() {
        let text = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 zero\n";
        assert_eq!(
            read_stl(text.as_bytes()).unwrap_err(),
            StlError::BadNumber {
                line: 5,
                token: "zero".into()
            }
        );
    }
}
