//! Reading STL files (binary and ASCII) into a [`TriangleSoup`]: our own
//! reader, so that ASCII errors name their line and quote the text.
//!
//! ```text
//! solid tetra
//!   facet normal 0 0 -1
//!     outer loop
//!       vertex 0 0 0
//!       vertex 0 1 0
//!       vertex 1 0 0
//!     endloop
//!   endfacet
//! endsolid tetra
//! ```
//! A binary file is an 80-byte header, a little-endian `u32` triangle
//! count and 50 bytes a triangle (normal, three corners as `f32`, two
//! attribute bytes); it is told from ASCII by its length matching that
//! count exactly (some binary files begin with `solid` too). Keywords are
//! read in any case; several `solid` blocks may follow one another.
//!
//! STL stores every triangle's corners apart. Corners at the same point
//! (the same bits) are welded into one vertex, so a closed model is closed
//! (usable in CSG) and `smooth` can average normals across faces. The facet
//! normal is read (it must be numbers) and not used: the winding gives the
//! flat normal, as for every mesh.

use super::soup::{MeshFileError, TriangleSoup, text_or_bad_line};
use crate::geometry::DVec3;
use std::collections::HashMap;

/// Bytes before a binary file's triangles, and in each triangle.
const HEADER: usize = 84;
const RECORD: usize = 50;

/// Reads a whole STL file from memory.
pub fn parse(bytes: &[u8]) -> Result<TriangleSoup, MeshFileError> {
    if bytes.is_empty() {
        return Err(err("the file is empty, not an STL file", None, None));
    }
    let declared = bytes
        .get(80..84)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64);
    let binary_len = declared.map(|n| HEADER as u64 + RECORD as u64 * n);
    // Blank space (or a UTF-8 byte-order mark) before `solid` is allowed.
    let text = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let text = text.trim_ascii_start();
    let starts_solid = text.len() >= 5 && text[..5].eq_ignore_ascii_case(b"solid");
    if binary_len == Some(bytes.len() as u64) {
        binary(bytes)
    } else if starts_solid {
        ascii(bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes))
    } else {
        Err(match (declared, binary_len) {
            (Some(n), Some(want)) => err(
                format!(
                    "not an STL file: binary STL holds 84 + 50·N bytes, and this header \
                     declares N = {n} triangles ({want} bytes), but the file has {} \
                     (an ASCII STL starts with `solid`)",
                    bytes.len()
                ),
                None,
                None,
            ),
            _ => err(
                "not an STL file: too short for a binary STL's 84-byte header, \
                 and an ASCII STL starts with `solid`",
                None,
                None,
            ),
        })
    }
}

fn err(message: impl Into<String>, line: Option<usize>, element: Option<String>) -> MeshFileError {
    MeshFileError {
        message: message.into(),
        line,
        element,
    }
}

/// Welds corners at the same point into shared vertices.
#[derive(Default)]
struct Welder {
    out: TriangleSoup,
    seen: HashMap<[u64; 3], u32>,
}

impl Welder {
    fn vertex(&mut self, p: DVec3) -> u32 {
        // +0.0 turns -0.0 into 0.0: the same point either way.
        let key = [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits());
        *self.seen.entry(key).or_insert_with(|| {
            self.out.positions.push(p);
            self.out.positions.len() as u32 - 1
        })
    }

    fn triangle(&mut self, corners: [DVec3; 3]) {
        let t = corners.map(|p| self.vertex(p));
        self.out.triangles.push(t);
    }

    fn finish(self, line: Option<usize>) -> Result<TriangleSoup, MeshFileError> {
        if self.out.triangles.is_empty() {
            return Err(err("the file has no triangles", line, None));
        }
        Ok(self.out)
    }
}

fn binary(bytes: &[u8]) -> Result<TriangleSoup, MeshFileError> {
    let mut w = Welder::default();
    let count = (bytes.len() - HEADER) / RECORD;
    w.out.triangles.reserve(count);
    for (i, rec) in bytes[HEADER..].chunks_exact(RECORD).enumerate() {
        let f = |k: usize| {
            let b = &rec[4 * k..4 * k + 4];
            f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64
        };
        // Floats 0..3 are the facet normal, 3..12 the corners.
        let corner = |c: usize| DVec3::new(f(3 + 3 * c), f(4 + 3 * c), f(5 + 3 * c));
        let corners = [corner(0), corner(1), corner(2)];
        if corners.iter().any(|p| !p.is_finite()) {
            return Err(err(
                format!("triangle {i} has a coordinate that is not a finite number"),
                None,
                Some(format!("triangle {i}")),
            ));
        }
        w.triangle(corners);
    }
    w.finish(None)
}

/// The words of an ASCII file, one ahead, each with its line; read as
/// they are needed (a word list would take several times the file).
struct Words<'a> {
    text: &'a str,
    pos: usize,
    line: usize,
    cur: Option<(&'a str, usize)>,
    /// The line of the last word taken, for "ends early".
    last: usize,
}

impl<'a> Words<'a> {
    fn new(text: &'a str) -> Self {
        let mut w = Words {
            text,
            pos: 0,
            line: 1,
            cur: None,
            last: 1,
        };
        w.cur = w.scan();
        w
    }

    fn scan(&mut self) -> Option<(&'a str, usize)> {
        let bytes = self.text.as_bytes();
        while let Some(&b) = bytes.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            if b == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while bytes
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        (self.pos > start).then(|| (&self.text[start..self.pos], self.line))
    }

    /// Takes the current word.
    fn advance(&mut self) {
        if let Some((_, line)) = self.cur {
            self.last = line;
        }
        self.cur = self.scan();
    }

    /// Skips the rest of the line of the last word taken (a solid's name).
    fn skip_line(&mut self) {
        while self.cur.is_some_and(|(_, l)| l == self.last) {
            self.advance();
        }
    }

    fn peek(&self) -> Option<(&'a str, usize)> {
        self.cur
    }

    /// The next word, which must be `key` (in any case).
    fn expect(&mut self, key: &str, after: &str) -> Result<usize, MeshFileError> {
        match self.peek() {
            Some((w, line)) if w.eq_ignore_ascii_case(key) => {
                self.advance();
                Ok(line)
            }
            Some((w, line)) => Err(err(
                format!("expected `{key}` {after}, found `{}`", short(w)),
                Some(line),
                None,
            )),
            None => Err(self.early(key)),
        }
    }

    fn number(&mut self, what: &str) -> Result<f64, MeshFileError> {
        match self.peek() {
            Some((w, line)) => {
                self.advance();
                w.parse::<f64>().map_err(|_| {
                    err(
                        format!("cannot read `{}` as a number ({what})", short(w)),
                        Some(line),
                        None,
                    )
                })
            }
            None => Err(self.early(what)),
        }
    }

    fn point(&mut self, what: &str) -> Result<(DVec3, usize), MeshFileError> {
        let line = self.peek().map(|(_, l)| l);
        let p = DVec3::new(self.number(what)?, self.number(what)?, self.number(what)?);
        Ok((p, line.unwrap_or(self.last)))
    }

    fn early(&self, wanted: &str) -> MeshFileError {
        err(
            format!("the file ends early: expected `{wanted}`"),
            Some(self.last),
            None,
        )
    }
}

/// A word as quoted in messages: at most 40 characters.
fn short(w: &str) -> String {
    match w.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &w[..i]),
        None => w.to_string(),
    }
}

fn ascii(bytes: &[u8]) -> Result<TriangleSoup, MeshFileError> {
    let text = text_or_bad_line(bytes).map_err(|line| {
        err(
            "the file starts with `solid` but is not text, and its length does not \
             match a binary STL's triangle count",
            Some(line),
            None,
        )
    })?;
    // A lone `\r` ends a line too; `\r\n` is one line end.
    let text = if text.contains('\r') {
        std::borrow::Cow::Owned(text.replace("\r\n", "\n").replace('\r', "\n"))
    } else {
        std::borrow::Cow::Borrowed(text)
    };
    let mut words = Words::new(&text);
    let mut w = Welder::default();
    while words.peek().is_some() {
        words.expect("solid", "at the start of a solid")?;
        // The name: the rest of the line (it may be empty).
        words.skip_line();
        loop {
            match words.peek() {
                Some((k, _)) if k.eq_ignore_ascii_case("endsolid") => {
                    words.advance();
                    words.skip_line();
                    break;
                }
                Some((k, _)) if k.eq_ignore_ascii_case("facet") => {
                    words.advance();
                    facet(&mut words, &mut w)?;
                }
                Some((k, line)) => {
                    return Err(err(
                        format!("expected `facet` or `endsolid`, found `{}`", short(k)),
                        Some(line),
                        None,
                    ));
                }
                None => return Err(words.early("endsolid")),
            }
        }
    }
    w.finish(Some(words.last))
}

/// `normal n n n  outer loop  vertex … ×3  endloop  endfacet`, after
/// `facet`.
fn facet(words: &mut Words, w: &mut Welder) -> Result<(), MeshFileError> {
    words.expect("normal", "after `facet`")?;
    words.point("the facet normal")?;
    words.expect("outer", "before a facet's corners")?;
    words.expect("loop", "after `outer`")?;
    let mut corners = [DVec3::ZERO; 3];
    for c in &mut corners {
        words.expect("vertex", "(a facet has three corners)")?;
        let (p, line) = words.point("a vertex coordinate")?;
        if !p.is_finite() {
            return Err(err(
                "a vertex coordinate is not a finite number",
                Some(line),
                None,
            ));
        }
        *c = p;
    }
    words.expect("endloop", "after three vertices (STL facets are triangles)")?;
    words.expect("endfacet", "after `endloop`")?;
    w.triangle(corners);
    Ok(())
}

/// A binary STL of the given triangles (for tests and examples the
/// project writes itself); the facet normal is the winding's.
pub fn write_binary(triangles: &[[DVec3; 3]]) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out[..22].copy_from_slice(b"binary STL by raytrace");
    out.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
        for p in [n, t[0], t[1], t[2]] {
            for c in [p.x, p.y, p.z] {
                out.extend((c as f32).to_le_bytes());
            }
        }
        out.extend([0, 0]);
    }
    out
}

/// An ASCII STL of the given triangles, coordinates written as `f32`
/// exactly, so it reads back as its binary twin.
pub fn write_ascii(name: &str, triangles: &[[DVec3; 3]]) -> String {
    use std::fmt::Write;
    let r = |x: f64| x as f32;
    let mut s = format!("solid {name}\n");
    for t in triangles {
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
        let _ = writeln!(s, "  facet normal {} {} {}", r(n.x), r(n.y), r(n.z));
        s.push_str("    outer loop\n");
        for p in t {
            let _ = writeln!(s, "      vertex {} {} {}", r(p.x), r(p.y), r(p.z));
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    let _ = writeln!(s, "endsolid {name}");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tetrahedron wound outwards.
    fn tetra() -> Vec<[DVec3; 3]> {
        let (o, x, y, z) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
        vec![[o, y, x], [o, x, z], [o, z, y], [x, y, z]]
    }

    #[test]
    fn binary_and_ascii_read_alike_and_weld() {
        let b = parse(&write_binary(&tetra())).unwrap();
        let a = parse(write_ascii("tetra", &tetra()).as_bytes()).unwrap();
        assert_eq!(a, b);
        assert_eq!(b.positions.len(), 4, "twelve corners, four points");
        assert_eq!(b.triangles.len(), 4);
        assert_eq!(b.triangles[0], [0, 1, 2]);
        assert_eq!(b.triangles[3], [2, 1, 3]);
        assert!(b.normals.is_none() && b.uvs.is_none());
    }

    #[test]
    fn a_binary_file_that_starts_with_solid_is_binary() {
        let mut b = write_binary(&tetra());
        b[..5].copy_from_slice(b"solid");
        assert_eq!(parse(&b).unwrap().triangles.len(), 4);
    }

    #[test]
    fn ascii_variants_read() {
        let text = write_ascii("tetra", &tetra());
        let want = parse(text.as_bytes()).unwrap();
        // Upper case, CRLF, lone CR, no name, two solids.
        let upper = text.to_uppercase();
        assert_eq!(parse(upper.as_bytes()).unwrap(), want);
        assert_eq!(parse(text.replace('\n', "\r\n").as_bytes()).unwrap(), want);
        assert_eq!(parse(text.replace('\n', "\r").as_bytes()).unwrap(), want);
        let unnamed = text.replace("solid tetra", "solid");
        assert_eq!(parse(unnamed.as_bytes()).unwrap(), want);
        let indented = format!("\u{feff}\n  {text}");
        assert_eq!(parse(indented.as_bytes()).unwrap(), want);
        let t = tetra();
        let two = write_ascii("a", &t[..2]) + &write_ascii("b", &t[2..]);
        assert_eq!(parse(two.as_bytes()).unwrap(), want);
    }

    /// Every malformed ASCII file says its line and the offending word.
    #[test]
    fn malformed_ascii_files_give_their_line_and_text() {
        let good = write_ascii("t", &tetra()[..1]);
        // Lines: 1 solid, 2 facet, 3 outer loop, 4-6 vertex, 7 endloop,
        // 8 endfacet, 9 endsolid.
        let cases: &[(&str, &str, usize, &str)] = &[
            ("vertex 0 1 0", "vertex 0 one 0", 5, "`one`"),
            ("vertex 0 1 0", "vertex 0 1 inf", 5, "finite"),
            ("facet normal", "facet norml", 2, "`norml`"),
            ("outer loop", "outer lop", 3, "`lop`"),
            (
                "endloop",
                "vertex 1 1 1\n    endloop",
                7,
                "facets are triangles",
            ),
            ("endfacet\n", "", 8, "`endfacet`"),
            ("endsolid t\n", "", 8, "ends early"),
            ("  facet", "  facte", 2, "`facte`"),
        ];
        for &(from, to, line, says) in cases {
            let text = good.replacen(from, to, 1);
            let e = parse(text.as_bytes()).unwrap_err();
            assert_eq!(e.line, Some(line), "{text}: {e}");
            assert!(e.message.contains(says), "{text}: {e}");
        }
        let e = parse(b"solid empty\nendsolid empty\n").unwrap_err();
        assert!(e.message.contains("no triangles"), "{e}");
    }

    #[test]
    fn malformed_binary_files_are_refused() {
        let b = write_binary(&tetra());
        // Truncated: the length no longer matches the count (and it does
        // not start with `solid`).
        let e = parse(&b[..b.len() - 1]).unwrap_err();
        assert!(e.message.contains("declares N = 4"), "{e}");
        // A count far past the file: refused from the length, no allocation.
        let mut huge = b.clone();
        huge[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(parse(&huge).is_err());
        // NaN corner.
        let mut nan = b.clone();
        nan[HEADER + RECORD + 12..HEADER + RECORD + 16].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = parse(&nan).unwrap_err();
        assert_eq!(e.element.as_deref(), Some("triangle 1"), "{e}");
        // No triangles, empty, too short.
        let mut none = b[..HEADER].to_vec();
        none[80..84].copy_from_slice(&0u32.to_le_bytes());
        assert!(parse(&none).unwrap_err().message.contains("no triangles"));
        assert!(parse(b"").unwrap_err().message.contains("empty"));
        assert!(parse(b"abc").unwrap_err().message.contains("too short"));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
        /// Mangled files, binary and ASCII, never panic.
        #[test]
        fn mangled_files_never_panic(
            ascii: bool,
            edits in proptest::collection::vec(
                (proptest::prelude::any::<proptest::sample::Index>(), proptest::prelude::any::<u8>(), 0u8..3),
                1..8,
            ),
        ) {
            let mut b = if ascii {
                write_ascii("t", &tetra()).into_bytes()
            } else {
                write_binary(&tetra())
            };
            super::super::mangle(&mut b, edits);
            let _ = parse(&b);
        }
    }

    #[test]
    fn negative_zero_welds_with_zero() {
        let mut t = tetra();
        t[1][0] = DVec3::new(-0.0, 0.0, -0.0);
        let m = parse(&write_binary(&t)).unwrap();
        assert_eq!(m.positions.len(), 4);
    }
}
