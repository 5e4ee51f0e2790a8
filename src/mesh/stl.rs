//! STL input (binary and ASCII) into a welded [`TriMesh`], and binary STL output.
//!
//! Source: the STL format as specified by 3D Systems (1989); binary layout: 80-byte header,
//! `u32` triangle count, then 50 bytes per triangle (normal, three corners as `f32` LE,
//! a `u16` attribute).
//! Format detection: a file is binary when `84 + 50·n` equals its size (some binary headers
//! start with `solid`); otherwise ASCII when it starts with `solid` (after an optional UTF-8
//! byte-order mark) and its first kilobyte has no control bytes; otherwise binary with
//! trailing bytes when `84 + 50·n` is smaller than the size.
//! Deviations: the file's normals are ignored (recomputed from the winding downstream);
//! triangles with a NaN or infinite coordinate are skipped and counted, not refused;
//! keywords are matched case-insensitively and a missing `endsolid` is tolerated; ASCII is
//! read as tokens, so LF, CRLF and CR line ends and files on one line all read alike, and
//! names may hold any bytes (UTF-8, non-breaking spaces).
//! Cost: one pass over the bytes; nothing is allocated from the header's count before the
//! file size confirms it. A binary file told from its head ([`binary_layout`]) can be read in
//! pieces as they come ([`BinaryStl`]), so a caller need not hold the whole file.
//!
//! Reading is our own because the error messages must name the line of a malformed ASCII
//! number and the counts of a truncated binary file, which `stl_io`'s readers do not report;
//! writing goes through `stl_io::write_stl`.

use super::{MeshError, TriMesh, Welder, PROGRESS_EVERY};
use crate::math::Point3;

const HEADER_BYTES: usize = 80;
/// Bytes before a binary STL file's first record: the header and the triangle count.
pub const STL_PREAMBLE_BYTES: usize = HEADER_BYTES + 4;
/// Bytes of a binary STL record: a normal and three corners as `f32` LE, a `u16` attribute.
pub const STL_RECORD_BYTES: usize = 50;

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
    /// A file read as it comes that must be held whole, with no memory left for it.
    #[error("the file is {len} bytes and there is not enough memory left to hold it")]
    NoMemory {
        /// File size in bytes.
        len: usize,
    },
    /// A file whose bytes, read as they came, were more or fewer than its length.
    #[error("the file's bytes changed while they were read: {received} bytes came for a file of {len} (was it changed or replaced meanwhile?)")]
    LengthMismatch {
        /// The file's length when reading began.
        len: usize,
        /// Bytes that came.
        received: usize,
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
    /// Every triangle read is degenerate: no area, or too thin for a usable normal.
    #[error("no usable triangles: all {count} are degenerate (zero area, or a height below {ratio:e} of the longest edge), so there is no surface to process", ratio = crate::math::DEGENERATE_HEIGHT_RATIO)]
    AllDegenerate {
        /// How many triangles there are (all degenerate).
        count: usize,
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
    // Text editors and some exporters begin UTF-8 text with a byte-order mark.
    let text = bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes);
    let starts_with_solid = starts_with_solid(text);
    if bytes.len() < STL_PREAMBLE_BYTES {
        return if starts_with_solid {
            read_ascii(text, progress)
        } else {
            Err(StlError::TooShort { len: bytes.len() })
        };
    }
    if let Some(count) = binary_layout(bytes, bytes.len()) {
        return read_binary(bytes, count, progress);
    }
    let declared = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    let needed = STL_PREAMBLE_BYTES as u64 + STL_RECORD_BYTES as u64 * declared;
    let len = bytes.len() as u64;
    if starts_with_solid && looks_like_text(text) {
        return read_ascii(text, progress);
    }
    if needed < len {
        return read_binary(bytes, declared as usize, progress);
    }
    let present = (len - STL_PREAMBLE_BYTES as u64) / STL_RECORD_BYTES as u64;
    let whole = (len - STL_PREAMBLE_BYTES as u64) % STL_RECORD_BYTES as u64 == 0;
    if !looks_like_triangles(&bytes[STL_PREAMBLE_BYTES..]) {
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

/// Bytes of a file's head that decide whether it is binary STL (see [`binary_layout`]).
pub const STL_HEAD_BYTES: usize = 4096;

/// The triangle count of a binary STL file of `len` bytes that begins with `head` (its first
/// `min(len, STL_HEAD_BYTES)` bytes or more), when [`read_stl`] reads the file as binary
/// and this much of it shows so: its header's count fills the file exactly, or leaves
/// trailing bytes and the file does not begin as text. `None` otherwise (an ASCII file, a
/// broken one, or binary with trailing bytes after a text-like start, which only the whole
/// file decides). So that a caller holding the file elsewhere can stream its triangles
/// through a [`BinaryStl`] instead of copying it whole first.
pub fn binary_layout(head: &[u8], len: usize) -> Option<usize> {
    if len < STL_PREAMBLE_BYTES || head.len() < len.min(STL_HEAD_BYTES) {
        return None;
    }
    let declared = u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64;
    let needed = STL_PREAMBLE_BYTES as u64 + STL_RECORD_BYTES as u64 * declared;
    let text = head.strip_prefix(UTF8_BOM).unwrap_or(head);
    // `read_stl` takes a file whose count leaves bytes over for ASCII when it begins with
    // `solid` and looks like text: only a start that is not text is sure to be binary here.
    (needed == len as u64 || (needed < len as u64 && !looks_like_text(text)))
        .then_some(declared as usize)
}

/// Whether the first (up to 256) 50-byte records after a binary header hold finite,
/// plausibly sized corners, as real triangles do and foreign bytes rarely do (no paper; a
/// plausibility test that tells a cut-off STL from another kind of file).
fn looks_like_triangles(data: &[u8]) -> bool {
    const PLAUSIBLE: f32 = 1e20;
    data.len() >= STL_RECORD_BYTES
        && data.chunks_exact(STL_RECORD_BYTES).take(256).all(|r| {
            r[12..48].chunks_exact(4).all(|b| {
                let c = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                c.is_finite() && c.abs() < PLAUSIBLE
            })
        })
}

const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// Whether the first token (after spaces, line breaks and non-breaking spaces) begins with
/// `solid`, in any case.
fn starts_with_solid(bytes: &[u8]) -> bool {
    Tokens::new(bytes)
        .next()
        .is_some_and(|t| t.text.len() >= 5 && t.text[..5].eq_ignore_ascii_case(b"solid"))
}

/// ASCII STL is text: no NUL or other control byte but whitespace in its first kilobyte.
/// Bytes above 127 are allowed (UTF-8 or Latin-1 names, non-breaking spaces). A binary
/// file is still told apart: its count at bytes 80–83 has a zero high byte below 16.7
/// million triangles, and its floats and attribute words are full of small bytes.
fn looks_like_text(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .take(1024)
        .all(|&b| b >= 0x80 || b.is_ascii_graphic() || b.is_ascii_whitespace())
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
        mesh: TriMesh::from_welded(positions, triangles)?,
        info,
    })
}

fn read_binary(
    bytes: &[u8],
    count: usize,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<StlImport, StlError> {
    let data_end = STL_PREAMBLE_BYTES + count * STL_RECORD_BYTES;
    let mut reader = BinaryStl::new(count);
    reader.feed(&bytes[STL_PREAMBLE_BYTES..data_end], progress);
    reader.finish(bytes.len() - data_end, progress)
}

/// The triangles of a binary STL file read record by record, in pieces as they come (the
/// WebAssembly build streams a file from JavaScript's memory through a small buffer, so that
/// the file is never copied whole into the engine's memory).
#[derive(Debug)]
pub struct BinaryStl {
    welder: Welder,
    count: usize,
    read: usize,
    skipped: usize,
}

impl BinaryStl {
    /// A reader of the `count` records (as the header gives it) of a binary file.
    pub fn new(count: usize) -> Self {
        BinaryStl {
            welder: Welder::with_capacity(count),
            count,
            read: 0,
            skipped: 0,
        }
    }

    /// Reads the next whole records (`records.len()` a multiple of [`STL_RECORD_BYTES`]; a
    /// partial record at the end is ignored), reporting `("parse", fraction)` now and then.
    pub fn feed(&mut self, records: &[u8], progress: &mut dyn FnMut(&str, f64)) {
        for chunk in records.chunks_exact(STL_RECORD_BYTES) {
            if self.read % PROGRESS_EVERY == 0 {
                progress("parse", self.read as f64 / self.count as f64);
            }
            self.read += 1;
            let Ok(record) = <&[u8; STL_RECORD_BYTES]>::try_from(chunk) else {
                continue; // chunks_exact yields whole records only
            };
            // Bytes 0..12 hold the file's normal, which is ignored. The corners are read as
            // bit patterns: a coordinate is finite unless its exponent bits are all ones.
            let bits: [[u32; 3]; 3] = std::array::from_fn(|c| {
                std::array::from_fn(|k| {
                    let at = 12 + 12 * c + 4 * k;
                    u32::from_le_bytes([record[at], record[at + 1], record[at + 2], record[at + 3]])
                })
            });
            const EXPONENT: u32 = 0x7f80_0000;
            if bits.iter().flatten().all(|&b| b & EXPONENT != EXPONENT) {
                self.welder.add_triangle_bits(&bits);
            } else {
                self.skipped += 1;
            }
        }
    }

    /// The welded mesh of the records fed, which must be the `count` given to [`Self::new`];
    /// `trailing_bytes` follow them in the file.
    pub fn finish(
        self,
        trailing_bytes: usize,
        progress: &mut dyn FnMut(&str, f64),
    ) -> Result<StlImport, StlError> {
        debug_assert_eq!(self.read, self.count, "every record is fed");
        progress("parse", 1.0);
        finish(
            self.welder,
            StlInfo {
                format: StlFormat::Binary,
                triangles_in_file: self.count,
                skipped_triangles: self.skipped,
                trailing_bytes,
            },
        )
    }
}

/// An STL file of a known length read from its bytes as they come, in pieces of any size
/// (a file read from disk as a stream, or copied from elsewhere through a small buffer): a
/// binary file's records are parsed as they arrive and never held whole; any other file (ASCII,
/// or binary that only its whole tells apart, see [`binary_layout`]) is gathered and read by
/// [`read_stl`] at the end. The result is [`read_stl`]'s for the same bytes.
#[derive(Debug)]
pub struct StlStream {
    len: usize,
    received: usize,
    state: StreamState,
}

#[derive(Debug)]
enum StreamState {
    /// The file's first `min(len, STL_HEAD_BYTES)` bytes, being gathered.
    Head(Vec<u8>),
    /// A binary file: its records, the bytes of a record begun, where the records end.
    Binary {
        reader: BinaryStl,
        partial: Vec<u8>,
        data_end: usize,
    },
    /// Any other file, gathered whole.
    Whole(Vec<u8>),
}

impl StlStream {
    /// A reader of a file of `len` bytes.
    pub fn new(len: usize) -> Self {
        StlStream {
            len,
            received: 0,
            state: StreamState::Head(Vec::with_capacity(len.min(STL_HEAD_BYTES))),
        }
    }

    /// Bytes received so far.
    pub fn received(&self) -> usize {
        self.received
    }

    /// Reads the next bytes of the file, reporting `("parse", fraction)` now and then. More
    /// bytes than the file's length are refused (and not read).
    pub fn push(
        &mut self,
        bytes: &[u8],
        progress: &mut dyn FnMut(&str, f64),
    ) -> Result<(), StlError> {
        if bytes.len() > self.len - self.received {
            return Err(StlError::LengthMismatch {
                len: self.len,
                received: self.received.saturating_add(bytes.len()),
            });
        }
        let at = self.received;
        self.received += bytes.len();
        match &mut self.state {
            StreamState::Head(head) => {
                let wanted = self.len.min(STL_HEAD_BYTES);
                let take = (wanted - head.len()).min(bytes.len());
                head.extend_from_slice(&bytes[..take]);
                if head.len() < wanted {
                    return Ok(());
                }
                let head = std::mem::take(head);
                let rest = &bytes[take..];
                match binary_layout(&head, self.len) {
                    Some(count) => {
                        self.state = StreamState::Binary {
                            reader: BinaryStl::new(count),
                            partial: Vec::with_capacity(STL_RECORD_BYTES),
                            data_end: STL_PREAMBLE_BYTES + count * STL_RECORD_BYTES,
                        };
                        // The head's records, then the rest, as if they came now.
                        self.feed_binary(STL_PREAMBLE_BYTES, &head[STL_PREAMBLE_BYTES..], progress);
                        self.feed_binary(head.len(), rest, progress);
                    }
                    None => {
                        let mut whole = head;
                        if whole.try_reserve_exact(self.len - whole.len()).is_err() {
                            return Err(StlError::NoMemory { len: self.len });
                        }
                        whole.extend_from_slice(rest);
                        self.state = StreamState::Whole(whole);
                    }
                }
            }
            StreamState::Binary { .. } => self.feed_binary(at, bytes, progress),
            StreamState::Whole(whole) => whole.extend_from_slice(bytes),
        }
        Ok(())
    }

    /// Feeds a binary file's bytes at offset `at` on: whole records to the reader, a record
    /// begun kept until it is whole, the bytes after the last record ignored.
    fn feed_binary(&mut self, at: usize, bytes: &[u8], progress: &mut dyn FnMut(&str, f64)) {
        let StreamState::Binary {
            reader,
            partial,
            data_end,
        } = &mut self.state
        else {
            return;
        };
        let bytes = &bytes[..bytes.len().min(data_end.saturating_sub(at))];
        let mut rest = bytes;
        if !partial.is_empty() {
            let take = (STL_RECORD_BYTES - partial.len()).min(rest.len());
            partial.extend_from_slice(&rest[..take]);
            rest = &rest[take..];
            if partial.len() < STL_RECORD_BYTES {
                return;
            }
            reader.feed(partial, progress);
            partial.clear();
        }
        let whole = rest.len() - rest.len() % STL_RECORD_BYTES;
        reader.feed(&rest[..whole], progress);
        partial.extend_from_slice(&rest[whole..]);
    }

    /// The file read, once all its bytes came; a file that ended early is refused.
    pub fn finish(self, progress: &mut dyn FnMut(&str, f64)) -> Result<StlImport, StlError> {
        if self.received != self.len {
            return Err(StlError::LengthMismatch {
                len: self.len,
                received: self.received,
            });
        }
        match self.state {
            StreamState::Head(head) | StreamState::Whole(head) => {
                read_stl_with_progress(&head, progress)
            }
            StreamState::Binary {
                reader, data_end, ..
            } => reader.finish(self.len - data_end, progress),
        }
    }
}

/// A whitespace-separated word of an ASCII file.
#[derive(Clone, Copy)]
struct Token<'a> {
    text: &'a [u8],
    /// 1-based line number.
    line: usize,
    /// Byte offset of its first byte.
    start: usize,
}

/// The UTF-8 encoding of U+00A0, the non-breaking space some exporters put in names.
const NBSP: [u8; 2] = [0xC2, 0xA0];

/// Tokens of an ASCII file with their line numbers. Lines end at LF, CRLF or a lone CR
/// (classic Mac exporters); a UTF-8 non-breaking space separates tokens like a space.
#[derive(Clone, Copy)]
struct Tokens<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Tokens<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Tokens {
            bytes,
            pos: 0,
            line: 1,
        }
    }

    /// Length of the separator at `at` (0 if none).
    #[inline]
    fn separator(&self, at: usize) -> usize {
        match self.bytes[at] {
            c if c.is_ascii_whitespace() => 1,
            0xC2 if self.bytes.get(at + 1) == Some(&NBSP[1]) => 2,
            _ => 0,
        }
    }

    /// The next token, or `None` at the end of the file. Each call consumes at least one
    /// byte or returns `None`, so a loop over it ends.
    fn next(&mut self) -> Option<Token<'a>> {
        while self.pos < self.bytes.len() {
            match self.bytes[self.pos] {
                b'\n' => self.line += 1,
                b'\r' if self.bytes.get(self.pos + 1) != Some(&b'\n') => self.line += 1,
                _ => {}
            }
            match self.separator(self.pos) {
                0 => break,
                len => self.pos += len,
            }
        }
        if self.pos == self.bytes.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < self.bytes.len() && self.separator(self.pos) == 0 {
            self.pos += 1;
        }
        Some(Token {
            text: &self.bytes[start..self.pos],
            line: self.line,
            start,
        })
    }

    /// The next token without consuming it.
    fn peek(&self) -> Option<Token<'a>> {
        let mut copy = *self;
        copy.next()
    }

    fn consumed_fraction(&self) -> f64 {
        self.pos as f64 / self.bytes.len().max(1) as f64
    }

    /// The line from `token` to its end, whitespace collapsed, cut to 40 characters.
    fn shown(&self, token: &Token) -> String {
        let rest = &self.bytes[token.start..];
        let end = rest
            .iter()
            .position(|&b| b == b'\n' || b == b'\r')
            .unwrap_or(rest.len());
        let words: Vec<_> = rest[..end]
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty())
            .map(String::from_utf8_lossy)
            .collect();
        words.join(" ").chars().take(40).collect()
    }
}

/// Number of lines of `bytes` as [`Tokens`] counts them (LF, CRLF or CR end a line).
fn line_count(bytes: &[u8]) -> usize {
    let lone_cr = bytes
        .windows(2)
        .filter(|w| w[0] == b'\r' && w[1] != b'\n')
        .count()
        + usize::from(bytes.last() == Some(&b'\r'));
    1 + bytes.iter().filter(|&&b| b == b'\n').count() + lone_cr
}

fn keyword(token: &Token, word: &str) -> bool {
    token.text.eq_ignore_ascii_case(word.as_bytes())
}

fn read_ascii(bytes: &[u8], progress: &mut dyn FnMut(&str, f64)) -> Result<StlImport, StlError> {
    parse_ascii(bytes, progress).map_err(|e| match e {
        // A bad last line with no line break is a file cut off mid-line.
        StlError::Syntax { line, .. } | StlError::BadNumber { line, .. }
            if !bytes.ends_with(b"\n") && !bytes.ends_with(b"\r") && line == line_count(bytes) =>
        {
            StlError::UnexpectedEnd { line }
        }
        e => e,
    })
}

/// Reads `solid name`, `facet [normal nx ny nz]`, `outer loop`, three `vertex x y z`,
/// `endloop`, `endfacet`, `endsolid [name]` as a stream of tokens, so a file on one line
/// reads like one on many. Names run to the end of their line (or, on a line that goes on,
/// to the next `facet`/`endsolid` after `solid` and the next `solid` after `endsolid`).
fn parse_ascii(bytes: &[u8], progress: &mut dyn FnMut(&str, f64)) -> Result<StlImport, StlError> {
    // A facet takes about 250 bytes of text; the hint only sizes the first allocation.
    let mut welder = Welder::with_capacity(bytes.len() / 250);
    let mut tokens = Tokens::new(bytes);
    let (mut in_file, mut skipped) = (0usize, 0usize);
    let syntax = |tokens: &Tokens, token: &Token, expected| StlError::Syntax {
        line: token.line,
        expected,
        found: tokens.shown(token),
    };
    // The next token, or the end of the file inside a facet.
    fn next<'a>(tokens: &mut Tokens<'a>, last_line: usize) -> Result<Token<'a>, StlError> {
        tokens
            .next()
            .ok_or(StlError::UnexpectedEnd { line: last_line })
    }
    // Skips a name: the rest of `line`, stopping early at one of `stops`.
    let skip_name = |tokens: &mut Tokens<'_>, line: usize, stops: &[&str]| {
        while let Some(t) = tokens.peek() {
            if t.line != line || stops.iter().any(|w| keyword(&t, w)) {
                break;
            }
            tokens.next();
        }
    };
    let mut in_solid = false;
    while let Some(token) = tokens.next() {
        if keyword(&token, "solid") {
            in_solid = true;
            skip_name(&mut tokens, token.line, &["facet", "endsolid"]);
            continue;
        }
        if keyword(&token, "endsolid") {
            in_solid = false;
            skip_name(&mut tokens, token.line, &["solid"]);
            continue;
        }
        if !keyword(&token, "facet") {
            let expected = if in_solid {
                "'facet' or 'endsolid'"
            } else {
                "'solid'"
            };
            return Err(syntax(&tokens, &token, expected));
        }
        let facet_line = token.line;
        // The file's normal is ignored (recomputed from the winding): skip the rest of the
        // facet's line up to `outer`.
        let outer = loop {
            let t = next(&mut tokens, facet_line)?;
            if keyword(&t, "outer") || t.line != facet_line {
                break t;
            }
        };
        if !keyword(&outer, "outer") {
            return Err(syntax(&tokens, &outer, "'outer'"));
        }
        if tokens.peek().is_some_and(|t| keyword(&t, "loop")) {
            tokens.next();
        }
        let mut corners = [[0f32; 3]; 3];
        let mut count = 0usize;
        let mut last_line = outer.line;
        loop {
            let t = next(&mut tokens, last_line)?;
            last_line = t.line;
            if keyword(&t, "endloop") {
                break;
            }
            if !keyword(&t, "vertex") {
                return Err(syntax(&tokens, &t, "'vertex' or 'endloop'"));
            }
            let mut xyz = [0f32; 3];
            for c in &mut xyz {
                let n = next(&mut tokens, last_line)?;
                if n.line != t.line {
                    return Err(syntax(&tokens, &t, "'vertex x y z'"));
                }
                *c = parse_number(&n)?;
            }
            if tokens.peek().is_some_and(|n| {
                n.line == t.line && !keyword(&n, "vertex") && !keyword(&n, "endloop")
            }) {
                return Err(syntax(&tokens, &t, "'vertex x y z'"));
            }
            if count < 3 {
                corners[count] = xyz;
            }
            count += 1;
        }
        let end = next(&mut tokens, last_line)?;
        if !keyword(&end, "endfacet") {
            return Err(syntax(&tokens, &end, "endfacet"));
        }
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
            progress("parse", tokens.consumed_fraction());
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

fn parse_number(token: &Token) -> Result<f32, StlError> {
    std::str::from_utf8(token.text)
        .ok()
        .and_then(|s| s.parse::<f32>().ok())
        .ok_or_else(|| StlError::BadNumber {
            line: token.line,
            token: String::from_utf8_lossy(token.text)
                .chars()
                .take(40)
                .collect(),
        })
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
    let mut out = Vec::with_capacity(STL_PREAMBLE_BYTES + STL_RECORD_BYTES * stl_triangles.len());
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
