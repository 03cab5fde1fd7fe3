//! Reading PLY files (Stanford polygon format) into plain arrays, with
//! `ply-rs-bw` as the reader of record: it reads every header, and the
//! element data of any file the small fast path in `fast` declines (which
//! includes every malformed one, so its diagnostics are the crate's). The
//! fast path reads plain ASCII numbers and binary records directly, about
//! three times cheaper than the crate's per-token grammar on the bunny.
//!
//! What is taken from a file: the `vertex` element's `x y z` (any scalar
//! type), its normals `nx ny nz` and texture coordinates (`u v`, `s t`,
//! `texture_u texture_v` or `texture_s texture_t`) when every vertex has
//! them, and the `face` element's index list (`vertex_indices` or
//! `vertex_index`, any integer types). Other properties and elements are
//! read past. Polygons with more than three corners are cut into triangles
//! (see [`triangulate`]).
//!
//! Everything the file controls is checked here so that the rest of the
//! program may trust the arrays: counts, indices in range, finite numbers.
//! Line endings may be `\n`, `\r\n` or a lone `\r`: the crate splits lines
//! on `\n` only, so the text is normalised first (only the header of a
//! binary file, whose payload bytes must stay untouched).

mod fast;
#[cfg(test)]
mod tests;
mod write;

pub use write::{icosphere, write_ascii};

use super::soup::{MeshFileError, TriangleSoup, triangulate};
use crate::geometry::{DVec2, DVec3};
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{Encoding, PropertyAccess, PropertyAccessResult, PropertyType};

// Bits of `Elem::set` telling which vertex properties were present.
const X: u8 = 1;
const Y: u8 = 2;
const Z: u8 = 4;
const NX: u8 = 8;
const NY: u8 = 16;
const NZ: u8 = 32;
const U: u8 = 64;
const V: u8 = 128;

/// One element of any kind: the parser is generic over a single element
/// type, so vertices, faces and unknown elements share this record and
/// each fills the fields its properties name.
#[derive(Debug, Default)]
struct Elem {
    values: [f64; 8],
    set: u8,
    /// `int` index lists (the usual type) are filled in place.
    ints: Vec<i32>,
    /// Any other integer list type, widened.
    wide: Vec<i64>,
    /// Set when a negative or non-integer index list was seen.
    bad_list: bool,
}

impl Elem {
    fn scalar(&mut self, name: &str, v: f64) -> PropertyAccessResult {
        let (slot, bit) = match name {
            "x" => (0, X),
            "y" => (1, Y),
            "z" => (2, Z),
            "nx" => (3, NX),
            "ny" => (4, NY),
            "nz" => (5, NZ),
            "u" | "s" | "texture_u" | "texture_s" => (6, U),
            "v" | "t" | "texture_v" | "texture_t" => (7, V),
            _ => return PropertyAccessResult::Ignored,
        };
        self.values[slot] = v;
        self.set |= bit;
        PropertyAccessResult::Set
    }

    fn list<T: Copy + Into<i64>>(&mut self, name: &str, v: Vec<T>) -> PropertyAccessResult {
        if is_index_list(name) {
            self.wide = v.into_iter().map(Into::into).collect();
        }
        PropertyAccessResult::Ignored
    }
}

fn is_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

impl PropertyAccess for Elem {
    fn new() -> Self {
        Elem::default()
    }
    fn set_char(&mut self, n: &str, v: i8) -> PropertyAccessResult {
        self.scalar(n, v.into())
    }
    fn set_uchar(&mut self, n: &str, v: u8) -> PropertyAccessResult {
        self.scalar(n, v.into())
    }
    fn set_short(&mut self, n: &str, v: i16) -> PropertyAccessResult {
        self.scalar(n, v.into())
    }
    fn set_ushort(&mut self, n: &str, v: u16) -> PropertyAccessResult {
        self.scalar(n, v.into())
    }
    fn set_int(&mut self, n: &str, v: i32) -> PropertyAccessResult {
        self.scalar(n, v.into())
    }
    fn set_uint(&mut self, n: &str, v: u32) -> PropertyAccessResult {
        self.scalar(n, v.into())
    }
    fn set_float(&mut self, n: &str, v: f32) -> PropertyAccessResult {
        self.scalar(n, v.into())
    }
    fn set_double(&mut self, n: &str, v: f64) -> PropertyAccessResult {
        self.scalar(n, v)
    }
    fn begin_list_int(&mut self, name: &str, _len: usize) -> ply_rs_bw::ply::BeginList<'_, i32> {
        use ply_rs_bw::ply::BeginList;
        if is_index_list(name) {
            BeginList::Fill(&mut self.ints)
        } else {
            BeginList::UseSetter
        }
    }
    fn set_list_char(&mut self, n: &str, v: Vec<i8>) -> PropertyAccessResult {
        self.list(n, v)
    }
    fn set_list_uchar(&mut self, n: &str, v: Vec<u8>) -> PropertyAccessResult {
        self.list(n, v)
    }
    fn set_list_short(&mut self, n: &str, v: Vec<i16>) -> PropertyAccessResult {
        self.list(n, v)
    }
    fn set_list_ushort(&mut self, n: &str, v: Vec<u16>) -> PropertyAccessResult {
        self.list(n, v)
    }
    fn set_list_int(&mut self, n: &str, v: Vec<i32>) -> PropertyAccessResult {
        self.list(n, v)
    }
    fn set_list_uint(&mut self, n: &str, v: Vec<u32>) -> PropertyAccessResult {
        self.list(n, v)
    }
    fn set_list_float(&mut self, n: &str, _v: Vec<f32>) -> PropertyAccessResult {
        if is_index_list(n) {
            self.bad_list = true;
        }
        PropertyAccessResult::Ignored
    }
    fn set_list_double(&mut self, n: &str, v: Vec<f64>) -> PropertyAccessResult {
        self.set_list_float(n, v.into_iter().map(|x| x as f32).collect())
    }
}

fn err(message: impl Into<String>, line: Option<usize>, element: Option<String>) -> MeshFileError {
    MeshFileError {
        message: message.into(),
        line,
        element,
    }
}

/// How the first line ends; the header is assumed to use it throughout.
fn line_ending(bytes: &[u8]) -> &'static [u8] {
    match bytes.iter().position(|&b| b == b'\n' || b == b'\r') {
        Some(i) if bytes[i] == b'\r' && bytes.get(i + 1) == Some(&b'\n') => b"\r\n",
        Some(i) if bytes[i] == b'\r' => b"\r",
        _ => b"\n",
    }
}

/// The byte offset just past `end_header` and its line ending.
fn header_end(bytes: &[u8], eol: &[u8]) -> Option<usize> {
    let mut key = b"end_header".to_vec();
    key.extend_from_slice(eol);
    bytes
        .windows(key.len())
        .position(|w| w == key.as_slice())
        .map(|i| i + key.len())
}

/// Turns `\r\n` and lone `\r` into `\n`.
fn normalise(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if b == b'\r' {
            out.push(b'\n');
            if bytes.get(i + 1) == Some(&b'\n') {
                i += 1;
            }
        } else {
            out.push(b);
        }
        i += 1;
    }
    out
}

/// Reads a whole PLY file from memory.
pub fn parse(bytes: &[u8]) -> Result<TriangleSoup, MeshFileError> {
    parse_with(bytes, Some(fast::RUN_LINES))
}

/// `fast` lets the bulk data bypass the crate's grammar (see `fast`), an
/// ASCII file read in runs of at most that many lines; `None` reads it
/// all with the crate. The tests compare the ways.
fn parse_with(bytes: &[u8], fast: Option<usize>) -> Result<TriangleSoup, MeshFileError> {
    if bytes.is_empty() {
        return Err(err("the file is empty, not a PLY file", None, None));
    }
    if !bytes.starts_with(b"ply") || !matches!(bytes.get(3), Some(b'\n' | b'\r')) {
        return Err(err(
            "not a PLY file (it must start with a line `ply`)",
            Some(1),
            None,
        ));
    }
    let eol = line_ending(bytes);
    let Some(end) = header_end(bytes, eol) else {
        return Err(err(
            "the header has no `end_header` line (truncated or not a PLY file)",
            None,
            None,
        ));
    };
    let is_ascii = bytes[..end].windows(12).any(|w| w == b"format ascii");
    let text = if eol == b"\n" {
        std::borrow::Cow::Borrowed(bytes)
    } else if is_ascii {
        std::borrow::Cow::Owned(normalise(bytes))
    } else {
        let mut t = normalise(&bytes[..end]);
        t.extend_from_slice(&bytes[end..]);
        std::borrow::Cow::Owned(t)
    };
    // The crate has shown no panics on mangled input (see the property test),
    // but it is third-party code fed user bytes: a panic would take the
    // whole render down, so it is caught and reported as a bad file.
    crate::guard::catch_quietly(|| read(&text, fast)).unwrap_or_else(|| {
        Err(err(
            "the file is malformed (the PLY reader gave up)",
            None,
            None,
        ))
    })
}

fn read(bytes: &[u8], fast: Option<usize>) -> Result<TriangleSoup, MeshFileError> {
    let parser = Parser::<Elem>::new();
    let mut reader = Reader::new(bytes);
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| err(format!("bad header: {}", crate_message(&e)), e.line(), None))?;
    let header_lines = reader.line().saturating_sub(1);

    let vertex_def = header
        .elements
        .get("vertex")
        .ok_or_else(|| err("the header declares no `vertex` element", None, None))?;
    for axis in ["x", "y", "z"] {
        match vertex_def.properties.get(axis) {
            Some(p) if matches!(p.data_type, PropertyType::Scalar(_)) => {}
            _ => {
                return Err(err(
                    format!("the vertex element has no scalar property `{axis}`"),
                    None,
                    Some("vertex".into()),
                ));
            }
        }
    }
    let face_def = header.elements.get("face").ok_or_else(|| {
        err(
            "the header declares no `face` element (a point cloud cannot be drawn)",
            None,
            None,
        )
    })?;
    if !face_def
        .properties
        .iter()
        .any(|(name, p)| is_index_list(name) && matches!(p.data_type, PropertyType::List(..)))
    {
        return Err(err(
            "the face element has no list property `vertex_indices` (or `vertex_index`)",
            None,
            Some("face".into()),
        ));
    }

    // Where each element starts, for line numbers in ASCII files.
    let ascii = header.encoding == Encoding::Ascii;
    let mut first_line = std::collections::HashMap::new();
    let mut line = header_lines + 1;
    for (name, def) in &header.elements {
        first_line.insert(name.clone(), line);
        line = line.saturating_add(def.count);
    }
    let line_of = |element: &str, i: usize| ascii.then(|| first_line[element] + i);

    let payload: &[u8] = reader.get_ref();
    let raw = match fast.and_then(|lines| fast::payload(payload, &header, lines)) {
        Some(raw) => raw,
        None => slow_payload(&parser, &mut reader, &header, line)?,
    };
    finish(raw, line_of)
}

/// The payload as plain arrays, whichever reader produced it: runs of
/// records in file order (the fast reader reads an ASCII file's runs in
/// parallel and keeps them as they are, rather than copying them into one).
#[derive(Default)]
struct Raw {
    runs: Vec<Run>,
    /// The first face whose index list was not of integers.
    bad_list: Option<usize>,
}

/// Some of the file's vertices or faces (or both), in order.
#[derive(Default)]
struct Run {
    /// Per vertex: x y z nx ny nz u v, and bits telling which were present.
    values: Vec<[f64; 8]>,
    set: Vec<u8>,
    /// The run's face `j` has the indices `indices[ends[j - 1]..ends[j]]`
    /// (from 0 for the first).
    ends: Vec<usize>,
    indices: Vec<i64>,
}

impl Run {
    /// Each face's index list, in order.
    fn faces(&self) -> impl Iterator<Item = &[i64]> {
        let starts = std::iter::once(0).chain(self.ends.iter().copied());
        starts
            .zip(&self.ends)
            .map(|(start, &end)| &self.indices[start..end])
    }
}

/// The payload through the crate's per-token reader: every file the fast
/// path declines, and so every malformed one, with the crate's diagnostics.
fn slow_payload(
    parser: &Parser<Elem>,
    reader: &mut Reader<&[u8]>,
    header: &ply_rs_bw::ply::Header,
    end_line: usize,
) -> Result<Raw, MeshFileError> {
    let ascii = header.encoding == Encoding::Ascii;
    let mut raw = Raw::default();
    for (name, def) in &header.elements {
        let elems = parser
            .read_payload_for_element(reader, def, header)
            .map_err(|e| {
                let msg = match e.kind() {
                    std::io::ErrorKind::UnexpectedEof => format!(
                        "the file ends early: the header declares {} `{name}` elements",
                        def.count
                    ),
                    _ => format!("bad `{name}` data: {}", crate_message(&e)),
                };
                err(msg, e.line().filter(|_| ascii), Some(name.clone()))
            })?;
        match name.as_str() {
            "vertex" => raw.runs.push(Run {
                values: elems.iter().map(|v| v.values).collect(),
                set: elems.iter().map(|v| v.set).collect(),
                ..Run::default()
            }),
            "face" => {
                let mut run = Run::default();
                for (i, f) in elems.iter().enumerate() {
                    if f.bad_list && raw.bad_list.is_none() {
                        raw.bad_list = Some(i);
                    }
                    if f.ints.is_empty() {
                        run.indices.extend_from_slice(&f.wide);
                    } else {
                        run.indices.extend(f.ints.iter().map(|&x| x as i64));
                    }
                    run.ends.push(run.indices.len());
                }
                raw.runs.push(run);
            }
            _ => {}
        }
    }
    let rest = reader.get_ref();
    let trailing = if ascii {
        rest.iter().any(|b| !b.is_ascii_whitespace())
    } else {
        !rest.is_empty()
    };
    if trailing {
        return Err(err(
            "there is more data than the header declares (wrong element counts?)",
            ascii.then_some(end_line),
            None,
        ));
    }
    Ok(raw)
}

/// Checks the arrays and makes the mesh: finite positions, index ranges,
/// polygons cut into fans.
fn finish(
    raw: Raw,
    line_of: impl Fn(&str, usize) -> Option<usize>,
) -> Result<TriangleSoup, MeshFileError> {
    let vertices: usize = raw.runs.iter().map(|r| r.values.len()).sum();
    let mut out = TriangleSoup {
        positions: Vec::with_capacity(vertices),
        ..TriangleSoup::default()
    };
    let all = |bits: u8| {
        raw.runs
            .iter()
            .flat_map(|r| &r.set)
            .all(|s| s & bits == bits)
    };
    let (has_n, has_uv) = (all(NX | NY | NZ), all(U | V));
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for (i, v) in raw.runs.iter().flat_map(|r| &r.values).enumerate() {
        let p = DVec3::new(v[0], v[1], v[2]);
        if !p.is_finite() {
            return Err(err(
                format!("vertex {i} has a coordinate that is not a finite number"),
                line_of("vertex", i),
                Some(format!("vertex {i}")),
            ));
        }
        out.positions.push(p);
        if has_n {
            let n = DVec3::new(v[3], v[4], v[5]);
            normals.push(if n.is_finite() { n } else { DVec3::ZERO });
        }
        if has_uv {
            let uv = DVec2::new(v[6], v[7]);
            uvs.push(if uv.is_finite() { uv } else { DVec2::ZERO });
        }
    }
    let n = out.positions.len() as i64;
    out.triangles
        .reserve(raw.runs.iter().map(|r| r.ends.len()).sum());
    // One buffer for every face's corners (a face is usually a triangle;
    // a list per face was an allocation per face).
    let mut corners: Vec<u32> = Vec::new();
    for (i, idx) in raw.runs.iter().flat_map(Run::faces).enumerate() {
        let bad = |what: String| {
            err(
                format!("face {i}: {what}"),
                line_of("face", i),
                Some(format!("face {i}")),
            )
        };
        if raw.bad_list == Some(i) {
            return Err(bad("vertex indices must be integers".into()));
        }
        if idx.len() < 3 {
            return Err(bad(format!(
                "a face needs at least 3 vertices, this one has {}",
                idx.len()
            )));
        }
        if let Some(&k) = idx.iter().find(|&&k| k < 0 || k >= n) {
            return Err(bad(format!(
                "vertex index {k} is out of range (the file has {n} vertices)"
            )));
        }
        corners.clear();
        corners.extend(idx.iter().map(|&k| k as u32));
        triangulate(&corners, &mut out.triangles);
    }
    if out.triangles.is_empty() {
        return Err(err("the file has no faces", None, Some("face".into())));
    }
    out.normals = has_n.then_some(normals);
    out.uvs = has_uv.then_some(uvs);
    Ok(out)
}

/// The crate's message without its own "Line N:" prefix (the line is kept
/// separately) and with only its first line (the rest echoes raw input).
fn crate_message(e: &ply_rs_bw::parser::ParseError) -> String {
    let s = e.to_string();
    let s = match (e.line(), s.split_once(": ")) {
        (Some(_), Some((head, tail))) if head.starts_with("Line ") => tail.to_string(),
        _ => s,
    };
    let first = s.lines().next().unwrap_or("").trim();
    // The crate's detail is on later lines; the offending value is the useful part.
    let quoted = |key: &str| {
        s.split_once(key)
            .and_then(|(_, v)| v.split_once('\''))
            .map(|(v, _)| v.trim().to_string())
    };
    if let Some(value) = quoted("Value: '") {
        format!("{first} Cannot read `{value}` as a number.")
    } else if let Some(line) = quoted("String: '") {
        format!("{first} Expected numbers, found `{line}`.")
    } else {
        first.to_string()
    }
}
