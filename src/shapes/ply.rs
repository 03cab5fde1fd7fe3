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

use super::mesh::PlyError;
use crate::geometry::{DVec2, DVec3};
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{Encoding, PropertyAccess, PropertyAccessResult, PropertyType};

/// The raw contents of a PLY file, validated.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    pub positions: Vec<DVec3>,
    pub normals: Option<Vec<DVec3>>,
    pub uvs: Option<Vec<DVec2>>,
    pub triangles: Vec<[u32; 3]>,
}

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

fn err(message: impl Into<String>, line: Option<usize>, element: Option<String>) -> PlyError {
    PlyError {
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
pub fn parse(bytes: &[u8]) -> Result<PlyMesh, PlyError> {
    parse_with(bytes, true)
}

/// `fast` lets the bulk data bypass the crate's grammar (see `fast`);
/// the tests compare both ways.
fn parse_with(bytes: &[u8], fast: bool) -> Result<PlyMesh, PlyError> {
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

fn read(bytes: &[u8], try_fast: bool) -> Result<PlyMesh, PlyError> {
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
    let raw = match try_fast.then(|| fast::payload(payload, &header)).flatten() {
        Some(raw) => raw,
        None => slow_payload(&parser, &mut reader, &header, line)?,
    };
    finish(raw, line_of)
}

/// The payload as plain arrays, whichever reader produced it.
#[derive(Default)]
struct Raw {
    /// Per vertex: x y z nx ny nz u v, and bits telling which were present.
    values: Vec<[f64; 8]>,
    set: Vec<u8>,
    /// Face `i`'s indices are `indices[starts[i]..starts[i + 1]]`.
    starts: Vec<usize>,
    indices: Vec<i64>,
    /// The first face whose index list was not of integers.
    bad_list: Option<usize>,
}

/// The payload through the crate's per-token reader: every file the fast
/// path declines, and so every malformed one, with the crate's diagnostics.
fn slow_payload(
    parser: &Parser<Elem>,
    reader: &mut Reader<&[u8]>,
    header: &ply_rs_bw::ply::Header,
    end_line: usize,
) -> Result<Raw, PlyError> {
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
            "vertex" => {
                raw.values = elems.iter().map(|v| v.values).collect();
                raw.set = elems.iter().map(|v| v.set).collect();
            }
            "face" => {
                raw.starts = Vec::with_capacity(elems.len() + 1);
                raw.starts.push(0);
                for (i, f) in elems.iter().enumerate() {
                    if f.bad_list && raw.bad_list.is_none() {
                        raw.bad_list = Some(i);
                    }
                    if f.ints.is_empty() {
                        raw.indices.extend_from_slice(&f.wide);
                    } else {
                        raw.indices.extend(f.ints.iter().map(|&x| x as i64));
                    }
                    raw.starts.push(raw.indices.len());
                }
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
fn finish(raw: Raw, line_of: impl Fn(&str, usize) -> Option<usize>) -> Result<PlyMesh, PlyError> {
    let mut out = PlyMesh {
        positions: Vec::with_capacity(raw.values.len()),
        ..PlyMesh::default()
    };
    let all = |bits: u8| raw.set.iter().all(|s| s & bits == bits);
    let (has_n, has_uv) = (all(NX | NY | NZ), all(U | V));
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for (i, v) in raw.values.iter().enumerate() {
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
    drop(raw.values);
    let n = out.positions.len() as i64;
    let faces = raw.starts.len().saturating_sub(1);
    out.triangles.reserve(faces);
    for i in 0..faces {
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
        let idx = &raw.indices[raw.starts[i]..raw.starts[i + 1]];
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
        let corners: Vec<u32> = idx.iter().map(|&k| k as u32).collect();
        triangulate(&corners, &mut out.triangles);
    }
    if out.triangles.is_empty() {
        return Err(err("the file has no faces", None, Some("face".into())));
    }
    out.normals = has_n.then_some(normals);
    out.uvs = has_uv.then_some(uvs);
    Ok(out)
}

/// Polygons up to this many corners are cut into a fan from corner 0.
pub const FAN_MAX: usize = 16;

/// Cuts a polygon (corners in order, at least three) into triangles with
/// its winding. A small one (the quads and pentagons of ordinary meshes)
/// becomes a fan from its first corner. A larger one is halved again and
/// again, (i, m, j) and then each side, with an explicit stack: a fan's
/// slivers all reach back to corner 0, so their boxes all overlap and no
/// kd-tree can separate them (a 100,000-corner face took over 15 s and
/// 1 GB to draw at 64×64); halving keeps triangles compact. Both cover a
/// convex polygon exactly.
pub fn triangulate(corners: &[u32], out: &mut Vec<[u32; 3]>) {
    let n = corners.len();
    if n <= FAN_MAX {
        for j in 1..n.saturating_sub(1) {
            out.push([corners[0], corners[j], corners[j + 1]]);
        }
        return;
    }
    out.reserve(n - 2);
    let mut stack = vec![(0, n - 1)];
    while let Some((i, j)) = stack.pop() {
        if j - i < 2 {
            continue;
        }
        let m = (i + j) / 2;
        out.push([corners[i], corners[m], corners[j]]);
        stack.push((i, m));
        stack.push((m, j));
    }
}

/// A fast reader for the bulk data of well-formed files. The crate reads
/// the header (it stays the reader of record); its grammar costs a few
/// hundred instructions per number, so the element data of a file this
/// module can read plainly is read here. Anything unusual (a token that is
/// not a plain number, a count that does not fit, data left over) makes it
/// give up, and the crate's reader then reads the file and reports.
mod fast {
    use super::{Raw, is_index_list};
    use ply_rs_bw::ply::{Encoding, Header, PropertyType, ScalarType};

    /// Where a property's values go.
    #[derive(Clone, Copy)]
    enum Sink {
        Skip,
        Vertex(usize),
        Indices,
    }

    pub(super) fn payload(bytes: &[u8], header: &Header) -> Option<Raw> {
        let mut raw = Raw::default();
        let mut src = match header.encoding {
            Encoding::Ascii => Source::Ascii(bytes, 0),
            Encoding::BinaryLittleEndian => Source::Binary(bytes, 0, false),
            Encoding::BinaryBigEndian => Source::Binary(bytes, 0, true),
        };
        for (name, def) in &header.elements {
            let is_vertex = name == "vertex";
            let is_face = name == "face";
            let props: Vec<(PropertyType, Sink)> = def
                .properties
                .iter()
                .map(|(pname, p)| {
                    let sink = if is_vertex {
                        slot(pname).map_or(Sink::Skip, Sink::Vertex)
                    } else if is_face && is_index_list(pname) {
                        Sink::Indices
                    } else {
                        Sink::Skip
                    };
                    (p.data_type.clone(), sink)
                })
                .collect();
            if is_face {
                // Exactly one index list, of integers: else the crate decides.
                let lists: Vec<_> = props
                    .iter()
                    .filter(|(_, s)| matches!(s, Sink::Indices))
                    .collect();
                match lists.as_slice() {
                    [(PropertyType::List(_, t), _)] if !is_float(t) => {}
                    _ => return None,
                }
                raw.starts = Vec::with_capacity(def.count.min(1 << 26) + 1);
                raw.starts.push(0);
                raw.indices.reserve(3 * def.count.min(1 << 26));
            }
            if is_vertex {
                raw.values = Vec::with_capacity(def.count.min(1 << 26));
                raw.set = Vec::with_capacity(def.count.min(1 << 26));
            }
            for _ in 0..def.count {
                src.begin_record()?;
                let mut values = [0f64; 8];
                let mut set = 0u8;
                for (ty, sink) in &props {
                    match ty {
                        PropertyType::Scalar(t) => {
                            let v = src.scalar(t)?;
                            if let Sink::Vertex(k) = sink {
                                values[*k] = v;
                                set |= 1 << *k;
                            }
                        }
                        PropertyType::List(count_type, t) => {
                            let count = src.count(count_type)?;
                            for _ in 0..count {
                                let v = src.scalar(t)?;
                                if let Sink::Indices = sink {
                                    raw.indices.push(v as i64);
                                }
                            }
                        }
                    }
                }
                src.end_record()?;
                if is_vertex {
                    raw.values.push(values);
                    raw.set.push(set);
                }
                if is_face {
                    raw.starts.push(raw.indices.len());
                }
            }
        }
        src.at_end().then_some(raw)
    }

    /// Whether a whole file's data goes through here (for the tests).
    #[cfg(test)]
    pub(super) fn payload_is_fast(bytes: &[u8]) -> bool {
        use ply_rs_bw::parser::{Parser, Reader};
        let mut reader = Reader::new(bytes);
        let Ok(header) = Parser::<super::Elem>::new().read_header(&mut reader) else {
            return false;
        };
        payload(reader.get_ref(), &header).is_some()
    }

    /// The slot of a vertex property in `Raw::values` (see `Elem::scalar`).
    fn slot(name: &str) -> Option<usize> {
        Some(match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            "nx" => 3,
            "ny" => 4,
            "nz" => 5,
            "u" | "s" | "texture_u" | "texture_s" => 6,
            "v" | "t" | "texture_v" | "texture_t" => 7,
            _ => return None,
        })
    }

    fn is_float(t: &ScalarType) -> bool {
        matches!(t, ScalarType::Float | ScalarType::Double)
    }

    /// A token read by the crate's number grammar,
    /// `[+-]? d+ (. d+)? ([eE] [+-]? d+)?`, in one pass that also gathers
    /// its digits: a token the grammar refuses must reach the crate, to be
    /// refused there.
    #[derive(Clone, Copy)]
    pub(super) struct Num<'a> {
        text: &'a [u8],
        neg: bool,
        /// Only `-`? digits, at most 18 of them: `mant` is the integer.
        int_ok: bool,
        /// No `+`, no exponent, at most 19 digits: the value is
        /// `mant · 10^exp10`.
        dec_ok: bool,
        mant: u64,
        exp10: i32,
    }

    /// Scans the token starting at `i`, which must end at a blank, a line
    /// end or the end of the text; returns it and the position after it.
    #[inline(always)]
    pub(super) fn scan(b: &[u8], mut i: usize) -> Option<(Num<'_>, usize)> {
        let start = i;
        let (mut neg, mut plus) = (false, false);
        match b.get(i) {
            Some(b'-') => (neg, i) = (true, i + 1),
            Some(b'+') => (plus, i) = (true, i + 1),
            _ => {}
        }
        // Digits go into `mant` unchecked: with at most 19 of them it is
        // exact, and a longer number goes to the standard parser.
        let digits = |i: &mut usize, mant: &mut u64| {
            let start = *i;
            while let Some(&c) = b.get(*i) {
                let d = c.wrapping_sub(b'0');
                if d > 9 {
                    break;
                }
                *mant = mant.wrapping_mul(10).wrapping_add(d as u64);
                *i += 1;
            }
            *i - start
        };
        let mut mant = 0u64;
        let int_digits = digits(&mut i, &mut mant);
        if int_digits == 0 {
            return None;
        }
        let dot = b.get(i) == Some(&b'.');
        let mut frac_digits = 0;
        if dot {
            i += 1;
            frac_digits = digits(&mut i, &mut mant);
            if frac_digits == 0 {
                return None;
            }
        }
        let exp = matches!(b.get(i), Some(b'e' | b'E'));
        if exp {
            i += 1;
            if matches!(b.get(i), Some(b'+' | b'-')) {
                i += 1;
            }
            let exp_start = i;
            while b.get(i).is_some_and(u8::is_ascii_digit) {
                i += 1;
            }
            if i == exp_start {
                return None;
            }
        }
        if !matches!(b.get(i), None | Some(b' ' | b'\t' | b'\n')) {
            return None;
        }
        let num = Num {
            text: &b[start..i],
            neg,
            int_ok: !plus && !dot && !exp && int_digits <= 18,
            dec_ok: !plus && !exp && int_digits + frac_digits <= 19,
            mant,
            exp10: -(frac_digits as i32),
        };
        Some((num, i))
    }

    /// Powers of ten that are exact in `f64` (up to 1e10 also in `f32`).
    const POW10: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
        1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
    ];

    impl Num<'_> {
        #[inline]
        fn int(&self) -> Option<i64> {
            let v = self.mant as i64;
            self.int_ok.then_some(if self.neg { -v } else { v })
        }

        /// Clinger's fast path: when the digits and the power of ten are
        /// both exact in the type, one multiplication or division rounds
        /// correctly, giving the standard parser's value. Other numbers go
        /// to that parser.
        #[inline]
        fn float32(&self) -> Option<f32> {
            let (m, e) = (self.mant, self.exp10);
            if self.dec_ok && m < (1 << 24) && (-10..=10).contains(&e) {
                let p = POW10[e.unsigned_abs() as usize] as f32;
                let v = if e < 0 { m as f32 / p } else { m as f32 * p };
                return Some(if self.neg { -v } else { v });
            }
            std::str::from_utf8(self.text).ok()?.parse().ok()
        }

        #[inline]
        fn float64(&self) -> Option<f64> {
            let (m, e) = (self.mant, self.exp10);
            if self.dec_ok && m < (1 << 53) && (-22..=22).contains(&e) {
                let p = POW10[e.unsigned_abs() as usize];
                let v = if e < 0 { m as f64 / p } else { m as f64 * p };
                return Some(if self.neg { -v } else { v });
            }
            std::str::from_utf8(self.text).ok()?.parse().ok()
        }
    }

    /// A whole string as a number (for the tests): by the fast path when
    /// the grammar takes it, else by the standard parser.
    #[cfg(test)]
    fn whole(s: &[u8]) -> Option<Num<'_>> {
        scan(s, 0)
            .filter(|&(_, end)| end == s.len())
            .map(|(n, _)| n)
    }

    #[cfg(test)]
    pub(super) fn float32(s: &[u8]) -> Option<f32> {
        match whole(s) {
            Some(n) => n.float32(),
            None => std::str::from_utf8(s).ok()?.parse().ok(),
        }
    }

    #[cfg(test)]
    pub(super) fn float64(s: &[u8]) -> Option<f64> {
        match whole(s) {
            Some(n) => n.float64(),
            None => std::str::from_utf8(s).ok()?.parse().ok(),
        }
    }

    enum Source<'a> {
        /// The text and the position in it.
        Ascii(&'a [u8], usize),
        /// The bytes, the position, big-endian.
        Binary(&'a [u8], usize, bool),
    }

    impl Source<'_> {
        /// ASCII: one record per line, nothing before it but blanks.
        fn begin_record(&mut self) -> Option<()> {
            match self {
                Source::Ascii(b, p) => {
                    while *p < b.len() && (b[*p] == b' ' || b[*p] == b'\t') {
                        *p += 1;
                    }
                    (*p < b.len()).then_some(())
                }
                Source::Binary(..) => Some(()),
            }
        }

        /// ASCII: the rest of the line must be blank, then a line end.
        fn end_record(&mut self) -> Option<()> {
            match self {
                Source::Ascii(b, p) => {
                    while *p < b.len() && (b[*p] == b' ' || b[*p] == b'\t') {
                        *p += 1;
                    }
                    if *p < b.len() && b[*p] == b'\n' {
                        *p += 1;
                        Some(())
                    } else {
                        None
                    }
                }
                Source::Binary(..) => Some(()),
            }
        }

        fn at_end(&self) -> bool {
            match self {
                Source::Ascii(b, p) => b[*p..].iter().all(|c| c.is_ascii_whitespace()),
                Source::Binary(b, p, _) => *p == b.len(),
            }
        }

        /// The next token of a line, a number by the crate's grammar.
        #[inline(always)]
        fn token<'b>(b: &'b [u8], p: &mut usize) -> Option<Num<'b>> {
            let mut i = *p;
            while i < b.len() && (b[i] == b' ' || b[i] == b'\t') {
                i += 1;
            }
            let (num, end) = scan(b, i)?;
            *p = end;
            Some(num)
        }

        fn bytes<const N: usize>(&mut self) -> Option<[u8; N]> {
            let Source::Binary(b, p, big) = self else {
                return None;
            };
            let mut a: [u8; N] = b.get(*p..*p + N)?.try_into().ok()?;
            *p += N;
            if *big {
                a.reverse();
            }
            Some(a)
        }

        /// A scalar of type `t`, widened to `f64` as the crate's setters do.
        #[inline(always)]
        fn scalar(&mut self, t: &ScalarType) -> Option<f64> {
            if let Source::Ascii(b, p) = self {
                let s = Self::token(b, p)?;
                return Some(match t {
                    ScalarType::Char => i8::try_from(s.int()?).ok()?.into(),
                    ScalarType::UChar => u8::try_from(s.int()?).ok()?.into(),
                    ScalarType::Short => i16::try_from(s.int()?).ok()?.into(),
                    ScalarType::UShort => u16::try_from(s.int()?).ok()?.into(),
                    ScalarType::Int => i32::try_from(s.int()?).ok()?.into(),
                    ScalarType::UInt => u32::try_from(s.int()?).ok()?.into(),
                    ScalarType::Float => s.float32()?.into(),
                    ScalarType::Double => s.float64()?,
                });
            }
            Some(match t {
                ScalarType::Char => i8::from_le_bytes(self.bytes()?).into(),
                ScalarType::UChar => u8::from_le_bytes(self.bytes()?).into(),
                ScalarType::Short => i16::from_le_bytes(self.bytes()?).into(),
                ScalarType::UShort => u16::from_le_bytes(self.bytes()?).into(),
                ScalarType::Int => i32::from_le_bytes(self.bytes()?).into(),
                ScalarType::UInt => u32::from_le_bytes(self.bytes()?).into(),
                ScalarType::Float => f32::from_le_bytes(self.bytes()?).into(),
                ScalarType::Double => f64::from_le_bytes(self.bytes()?),
            })
        }

        /// A list's length.
        fn count(&mut self, t: &ScalarType) -> Option<usize> {
            if let Source::Ascii(b, p) = self {
                return usize::try_from(Self::token(b, p)?.int()?).ok();
            }
            if is_float(t) {
                return None;
            }
            let v = self.scalar(t)?;
            (v >= 0.0).then_some(v as usize)
        }
    }
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

/// An ASCII PLY file with the given vertices and faces (for meshes the
/// project makes itself, such as the example icosphere, and for tests).
pub fn write_ascii(positions: &[DVec3], faces: &[Vec<u32>]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = write!(
        s,
        "ply\nformat ascii 1.0\ncomment written by raytrace\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        positions.len(),
        faces.len()
    );
    for p in positions {
        let _ = writeln!(s, "{} {} {}", p.x as f32, p.y as f32, p.z as f32);
    }
    for f in faces {
        let _ = write!(s, "{}", f.len());
        for i in f {
            let _ = write!(s, " {i}");
        }
        s.push('\n');
    }
    s
}

/// A sphere of radius 1 made by subdividing an icosahedron `levels` times
/// (20·4^levels triangles, wound counter-clockwise seen from outside).
pub fn icosphere(levels: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut pos: Vec<DVec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, pos: &mut Vec<DVec3>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                pos.push((pos[a as usize] + pos[b as usize]).normalize());
                pos.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(tris.len() * 4);
        for [a, b, c] in tris {
            let ab = midpoint(a, b, &mut pos);
            let bc = midpoint(b, c, &mut pos);
            let ca = midpoint(c, a, &mut pos);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    (pos, tris)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A unit square split as one quad, in the given encoding, with the
    /// given index-list type and extra properties.
    fn square(format: &str, list: &str) -> Vec<u8> {
        let mut out = format!(
            "ply\nformat {format} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
             property float z\nproperty float confidence\nelement face 1\n\
             property list {list} vertex_indices\nend_header\n"
        )
        .into_bytes();
        let verts = [
            [0.0f32, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let (count_ty, index_ty) = list.split_once(' ').unwrap();
        let int = |ty: &str, v: u32, big: bool| -> Vec<u8> {
            match (ty, big) {
                ("uchar" | "uint8" | "char" | "int8", _) => vec![v as u8],
                ("ushort" | "short" | "uint16" | "int16", false) => {
                    (v as u16).to_le_bytes().to_vec()
                }
                ("ushort" | "short" | "uint16" | "int16", true) => {
                    (v as u16).to_be_bytes().to_vec()
                }
                (_, false) => v.to_le_bytes().to_vec(),
                (_, true) => v.to_be_bytes().to_vec(),
            }
        };
        match format {
            "ascii" => {
                for v in verts {
                    out.extend(format!("{} {} {} 0.5\n", v[0], v[1], v[2]).bytes());
                }
                out.extend(b"4 0 1 2 3\n");
            }
            _ => {
                let big = format == "binary_big_endian";
                for v in verts {
                    for c in [v[0], v[1], v[2], 0.5] {
                        out.extend(if big {
                            c.to_be_bytes()
                        } else {
                            c.to_le_bytes()
                        });
                    }
                }
                out.extend(int(count_ty, 4, big));
                for i in 0..4 {
                    out.extend(int(index_ty, i, big));
                }
            }
        }
        out
    }

    #[test]
    fn every_encoding_and_list_type_reads_the_same_square() {
        for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
            for list in [
                "uchar int",
                "uint uint",
                "int int",
                "uchar uint",
                "ushort ushort",
                "uint8 int32",
                "char short",
            ] {
                let m =
                    parse(&square(format, list)).unwrap_or_else(|e| panic!("{format} {list}: {e}"));
                assert_eq!(m.positions.len(), 4);
                // A quad becomes a fan of two triangles.
                assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]], "{format} {list}");
                assert_eq!(m.positions[2], DVec3::new(1.0, 1.0, 0.0));
                assert!(m.normals.is_none() && m.uvs.is_none());
            }
        }
    }

    #[test]
    fn the_fast_reader_agrees_with_the_crate() {
        let mut files: Vec<Vec<u8>> = Vec::new();
        for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
            for list in ["uchar int", "uint uint", "ushort ushort", "char short"] {
                files.push(square(format, list));
            }
        }
        files.push(
            b"ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n\
              property double z\nproperty float nx\nproperty float ny\nproperty float nz\n\
              property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\n\
              end_header\n-0.0378297 0.12794 1e-3 0 0 1 0.25 0.5\n1.5 -0.000123456789 3 0 0 1 0.75 1\n\
              0.5 2.5E+1 +7 0 0 1 1 1\n3 0 1 2\n"
                .to_vec(),
        );
        let (positions, triangles) = icosphere(2);
        let faces: Vec<Vec<u32>> = triangles.iter().map(|t| t.to_vec()).collect();
        files.push(write_ascii(&positions, &faces).into_bytes());
        // Numbers the crate's grammar refuses stay refused.
        let bad = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                    property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                    end_header\n.5 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
        assert!(parse(bad).is_err());
        for f in &files {
            let fast = parse_with(f, true).unwrap();
            assert_eq!(fast, parse_with(f, false).unwrap());
            let text = String::from_utf8_lossy(f);
            assert!(
                !text.contains("format ascii") || fast::payload_is_fast(f),
                "the fast path declined {text}"
            );
        }
    }

    proptest! {
        #[test]
        fn fast_numbers_match_the_standard_parser(
            int in 0u64..100_000_000, frac in 0u64..10_000_000, digits in 0usize..9, neg: bool,
        ) {
            let frac = format!("{frac:07}");
            let s = format!("{}{int}.{}", if neg { "-" } else { "" }, &frac[..digits.min(7)]);
            prop_assert_eq!(fast::float32(s.as_bytes()), s.parse::<f32>().ok());
            prop_assert_eq!(fast::float64(s.as_bytes()), s.parse::<f64>().ok());
        }
    }

    #[test]
    fn line_endings_crlf_and_cr_only() {
        let lf = String::from_utf8(square("ascii", "uchar int")).unwrap();
        let want = parse(lf.as_bytes()).unwrap();
        assert_eq!(parse(lf.replace('\n', "\r\n").as_bytes()).unwrap(), want);
        assert_eq!(parse(lf.replace('\n', "\r").as_bytes()).unwrap(), want);
        // Binary: only the header's line ends change; payload bytes stay.
        let bin = square("binary_little_endian", "uchar int");
        let want = parse(&bin).unwrap();
        let end = header_end(&bin, b"\n").unwrap();
        let header = String::from_utf8(bin[..end].to_vec()).unwrap();
        for eol in ["\r\n", "\r"] {
            let mut b = header.replace('\n', eol).into_bytes();
            b.extend_from_slice(&bin[end..]);
            assert_eq!(parse(&b).unwrap(), want, "{eol:?}");
        }
    }

    #[test]
    fn normals_and_uvs_are_read() {
        for (u, v) in [("u", "v"), ("s", "t"), ("texture_u", "texture_v")] {
            let text = format!(
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n\
                 property double z\nproperty float nx\nproperty float ny\nproperty float nz\n\
                 property float intensity\nproperty float {u}\nproperty float {v}\n\
                 element face 1\nproperty list uchar uint vertex_index\nend_header\n\
                 0 0 0 0 0 1 9 0 0\n1 0 0 0 0 1 9 1 0\n0 1 0 0 0 1 9 0 1\n3 0 1 2\n"
            );
            let m = parse(text.as_bytes()).unwrap();
            assert_eq!(m.normals.as_ref().unwrap()[1], DVec3::Z);
            assert_eq!(m.uvs.as_ref().unwrap()[2], DVec2::new(0.0, 1.0), "{u} {v}");
        }
    }

    fn ascii(body: &str, nv: usize, nf: usize) -> Vec<u8> {
        format!(
            "ply\nformat ascii 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\n\
             property float z\nelement face {nf}\nproperty list uchar int vertex_indices\n\
             end_header\n{body}"
        )
        .into_bytes()
    }

    const TRI: &str = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

    #[test]
    fn malformed_files_are_errors_with_places() {
        assert!(parse(&ascii(TRI, 3, 1)).is_ok());
        // Truncated: the header promises two faces.
        let e = parse(&ascii(TRI, 3, 2)).unwrap_err();
        assert!(e.message.contains("ends early"), "{e}");
        assert_eq!(e.element.as_deref(), Some("face"));
        // Wrong counts the other way: data left over.
        let e = parse(&ascii(&format!("{TRI}3 0 2 1\n"), 3, 1)).unwrap_err();
        assert!(e.message.contains("more data"), "{e}");
        // Index out of range, on line 13 (9 header lines, 3 vertices, face 0).
        let e = parse(&ascii("0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", 3, 1)).unwrap_err();
        assert!(e.message.contains("out of range"), "{e}");
        assert_eq!(e.line, Some(13));
        assert_eq!(e.element.as_deref(), Some("face 0"));
        let e = parse(&ascii("0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", 3, 1)).unwrap_err();
        assert!(e.message.contains("out of range"), "{e}");
        // NaN coordinates (binary: ASCII "nan" is already not a number).
        let mut b = square("binary_little_endian", "uchar int");
        let end = header_end(&b, b"\n").unwrap();
        b[end + 16 + 4..end + 16 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = parse(&b).unwrap_err();
        assert!(e.message.contains("finite"), "{e}");
        assert_eq!(e.element.as_deref(), Some("vertex 1"));
        // A word where a number belongs.
        let e = parse(&ascii("0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", 3, 1)).unwrap_err();
        assert_eq!(e.line, Some(11), "{e}");
        assert!(e.message.contains("`1 zero 0`"), "{e}");
        // Faces with fewer than three corners.
        let e = parse(&ascii("0 0 0\n1 0 0\n0 1 0\n2 0 1\n", 3, 1)).unwrap_err();
        assert!(e.message.contains("at least 3"), "{e}");
        // Not a PLY at all, empty, no end_header, no faces, no x.
        assert!(
            parse(b"OFF\n3 1 0\n")
                .unwrap_err()
                .message
                .contains("not a PLY")
        );
        assert!(parse(b"").unwrap_err().message.contains("empty"));
        assert!(
            parse(b"ply\nformat ascii 1.0\n")
                .unwrap_err()
                .message
                .contains("end_header")
        );
        let e = parse(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap_err();
        assert!(e.message.contains("no `face`"), "{e}");
        let e = parse(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n").unwrap_err();
        assert!(e.message.contains("`x`"), "{e}");
        // A header line that is not PLY.
        let e = parse(b"ply\nformat ascii 1.0\nelephant vertex 1\nend_header\n").unwrap_err();
        assert_eq!(e.line, Some(3), "{e}");
        // Truncated binary.
        let mut b = square("binary_little_endian", "uchar int");
        b.truncate(b.len() - 3);
        assert!(parse(&b).unwrap_err().message.contains("ends early"));
    }

    /// A large convex polygon cut by halving covers exactly what a fan
    /// covers: the same area, the same winding, every corner used, n − 2
    /// triangles.
    #[test]
    fn large_polygons_are_halved_and_cover_the_polygon() {
        let n = 1000;
        let ring: Vec<DVec3> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let corners: Vec<u32> = (0..n as u32).collect();
        let mut tris = Vec::new();
        triangulate(&corners, &mut tris);
        assert_eq!(tris.len(), n - 2);
        let signed = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|k| ring[k as usize]);
            (b - a).cross(c - a).z / 2.0
        };
        assert!(tris.iter().all(|t| signed(t) > 0.0), "winding kept");
        let area: f64 = tris.iter().map(signed).sum();
        let exact = n as f64 / 2.0 * (std::f64::consts::TAU / n as f64).sin();
        assert!((area - exact).abs() < 1e-9 * exact, "{area} vs {exact}");
        let mut used = vec![false; n];
        tris.iter().flatten().for_each(|&k| used[k as usize] = true);
        assert!(used.iter().all(|&u| u));
        // Compact: no triangle of the halving reaches from every part of
        // the ring to corner 0 as a fan's do; most are small.
        let small = tris.iter().filter(|t| t[2] - t[0] <= 8).count();
        assert!(small > n / 2, "{small}");
        // Small polygons are still fans, as before.
        let mut quad = Vec::new();
        triangulate(&[0, 1, 2, 3], &mut quad);
        assert_eq!(quad, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn missing_file_is_an_error() {
        let e =
            crate::shapes::MeshData::load(std::path::Path::new("/nonexistent/x.ply")).unwrap_err();
        assert!(e.message.contains("cannot read"), "{e}");
    }

    #[test]
    fn written_files_read_back() {
        let (p, t) = icosphere(1);
        let faces: Vec<Vec<u32>> = t.iter().map(|f| f.to_vec()).collect();
        let m = parse(write_ascii(&p, &faces).as_bytes()).unwrap();
        assert_eq!(m.triangles, t);
        assert_eq!(m.positions.len(), 42);
        assert!((m.positions[7] - p[7]).length() < 1e-6);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(400))]
        /// Mangled files never panic, neither here nor inside the crate
        /// (`read` is called without the panic guard).
        #[test]
        fn mangled_files_never_panic(
            which in 0usize..4,
            edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0u8..3), 1..8),
            cut in any::<prop::sample::Index>(),
        ) {
            let mut b = match which {
                0 => square("ascii", "uchar int"),
                1 => square("binary_little_endian", "uint uint"),
                2 => square("binary_big_endian", "uchar int"),
                _ => ascii(TRI, 3, 1),
            };
            for (at, byte, op) in edits {
                let i = at.index(b.len());
                match op {
                    0 => b[i] = byte,
                    1 => b.insert(i, byte),
                    _ => { b.remove(i); }
                }
                if b.is_empty() { break; }
            }
            if !b.is_empty() && cut.index(4) == 0 {
                b.truncate(cut.index(b.len()));
            }
            let _ = read(&b, false);
            let _ = read(&b, true);
            let _ = parse(&b);
        }
    }
}
