//! Reading Wavefront OBJ files into a [`TriangleSoup`]: our own reader, so
//! that every error names its line and quotes the offending text.
//!
//! ```text
//! # a square with texture coordinates
//! v 0 0 0
//! v 1 0 0
//! v 1 1 0
//! v 0 1 0
//! vt 0 0
//! vt 1 0
//! vt 1 1
//! vt 0 1
//! f 1/1 2/2 3/3 4/4
//! ```
//! Read: `v x y z` (a fourth `w` or vertex colours after it are read past),
//! `vt u v` (`vt u` alone means v = 0), `vn x y z`, and `f` with corners
//! `v`, `v/vt`, `v//vn` or `v/vt/vn`; indices count from 1, and negative
//! ones count back from the last element defined above the line (-1 is the
//! latest). Polygons are cut into triangles as PLY's are ([`triangulate`]).
//! Grouping and material statements (`o`, `g`, `s`, `usemtl`, `mtllib`)
//! and points and lines (`p`, `l`) are ignored: a mesh gets its material
//! from the scene. Free-form curves and surfaces are refused by name.
//!
//! OBJ indexes positions, texture coordinates and normals separately; a
//! mesh has one index per corner, so each distinct (v, vt, vn) triple
//! becomes one vertex. Texture coordinates (normals) are kept when every
//! corner of every face names one, as PLY's are kept when every vertex has
//! them; a file whose faces name only positions keeps its vertices as
//! they are.

use super::soup::{MeshFileError, TriangleSoup, text_or_bad_line, triangulate};
use crate::geometry::{DVec2, DVec3};
use std::collections::HashMap;

/// No texture coordinate or normal at a corner.
const NONE: u32 = u32::MAX;

/// Reads a whole OBJ file from memory.
pub fn parse(bytes: &[u8]) -> Result<TriangleSoup, MeshFileError> {
    if bytes.is_empty() {
        return Err(err("the file is empty, not an OBJ file", None));
    }
    let text = text_or_bad_line(bytes).map_err(|line| {
        err(
            "the file is not text (an OBJ file is UTF-8 or ASCII)",
            Some(line),
        )
    })?;
    // A byte-order mark, as some Windows tools write, is no text.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut r = Reader::default();
    for (i, line) in lines(text).enumerate() {
        r.statement(line, i + 1)?;
    }
    r.finish()
}

fn err(message: impl Into<String>, line: Option<usize>) -> MeshFileError {
    MeshFileError {
        message: message.into(),
        line,
        element: None,
    }
}

/// Text from the file as quoted in messages: at most 60 characters.
fn quote(s: &str) -> String {
    let s = s.trim();
    match s.char_indices().nth(60) {
        Some((i, _)) => format!("`{}…`", &s[..i]),
        None => format!("`{s}`"),
    }
}

/// Lines ending in `\n`, `\r\n` or a lone `\r`.
fn lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let s = rest?;
        match s.find(['\n', '\r']) {
            Some(i) => {
                let skip = if s[i..].starts_with("\r\n") { 2 } else { 1 };
                rest = Some(&s[i + skip..]);
                Some(&s[..i])
            }
            None => {
                rest = None;
                (!s.is_empty()).then_some(s)
            }
        }
    })
}

/// One face corner: indices (from 0) into the file's positions, texture
/// coordinates and normals, [`NONE`] where the corner names none.
type Corner = [u32; 3];

/// What has been read so far.
#[derive(Default)]
struct Reader {
    positions: Vec<DVec3>,
    uvs: Vec<DVec2>,
    normals: Vec<DVec3>,
    corners: Vec<Corner>,
    /// Face `i`'s corners are `corners[starts[i]..starts[i + 1]]`, and it
    /// was written on line `face_lines[i]`.
    starts: Vec<usize>,
    face_lines: Vec<usize>,
}

impl Reader {
    fn statement(&mut self, line: &str, n: usize) -> Result<(), MeshFileError> {
        let body = line.split_once('#').map_or(line, |(b, _)| b);
        let mut words = body.split_ascii_whitespace();
        let Some(key) = words.next() else {
            return Ok(());
        };
        let bad = |what: String| Err(err(format!("{}: {what}", quote(body)), Some(n)));
        match key {
            "v" => {
                let v = numbers(words, 3, 7).map_err(|w| err(w.say(body, "x y z"), Some(n)))?;
                let p = DVec3::new(v[0], v[1], v[2]);
                if !p.is_finite() {
                    return bad("a coordinate is not a finite number".into());
                }
                self.positions.push(p);
            }
            "vt" => {
                let v = numbers(words, 1, 3).map_err(|w| err(w.say(body, "u v"), Some(n)))?;
                let uv = DVec2::new(v[0], v.get(1).copied().unwrap_or(0.0));
                self.uvs.push(if uv.is_finite() { uv } else { DVec2::ZERO });
            }
            "vn" => {
                let v = numbers(words, 3, 3).map_err(|w| err(w.say(body, "x y z"), Some(n)))?;
                let nrm = DVec3::new(v[0], v[1], v[2]);
                self.normals
                    .push(if nrm.is_finite() { nrm } else { DVec3::ZERO });
            }
            "f" => {
                if self.starts.is_empty() {
                    self.starts.push(0);
                }
                let first = self.corners.len();
                for word in words {
                    match self.corner(word) {
                        Ok(c) => self.corners.push(c),
                        Err(why) => return bad(format!("in the corner {}, {why}", quote(word))),
                    }
                }
                let count = self.corners.len() - first;
                if count < 3 {
                    return bad(format!(
                        "a face needs at least 3 corners, this one has {count}"
                    ));
                }
                self.starts.push(self.corners.len());
                self.face_lines.push(n);
            }
            "o" | "g" | "s" | "usemtl" | "mtllib" | "p" | "l" => {}
            "vp" | "cstype" | "deg" | "bmat" | "step" | "curv" | "curv2" | "surf" | "parm"
            | "trim" | "hole" | "scrv" | "sp" | "end" | "con" => {
                return bad(format!(
                    "free-form curves and surfaces (`{key}`) are not supported; \
                     export the model as polygons"
                ));
            }
            _ => return bad(format!("`{key}` is not an OBJ statement this reads")),
        }
        Ok(())
    }

    /// A corner `v`, `v/vt`, `v//vn` or `v/vt/vn`, resolved against the
    /// elements defined so far.
    fn corner(&self, word: &str) -> Result<Corner, String> {
        let mut parts = word.split('/');
        let v = parts.next().unwrap_or("");
        let vt = parts.next().unwrap_or("");
        let vn = parts.next().unwrap_or("");
        if parts.next().is_some() {
            return Err("has more than three parts (v/vt/vn)".into());
        }
        let p = resolve(v, self.positions.len(), "vertex")?;
        if p == NONE {
            return Err("names no vertex".into());
        }
        let t = resolve(vt, self.uvs.len(), "texture coordinate")?;
        let nrm = resolve(vn, self.normals.len(), "normal")?;
        Ok([p, t, nrm])
    }

    fn finish(self) -> Result<TriangleSoup, MeshFileError> {
        if self.face_lines.is_empty() {
            return Err(err("the file has no faces (`f` lines)", None));
        }
        // Positive indices may name elements defined further down; each is
        // checked now, against the whole file, at its face's line.
        let counts = [self.positions.len(), self.uvs.len(), self.normals.len()];
        const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
        for (f, &line) in self.face_lines.iter().enumerate() {
            for c in &self.corners[self.starts[f]..self.starts[f + 1]] {
                for k in 0..3 {
                    if c[k] != NONE && c[k] as usize >= counts[k] {
                        return Err(err(
                            format!(
                                "{} index {} is out of range (the file has {} of them)",
                                WHAT[k],
                                c[k] as u64 + 1,
                                counts[k]
                            ),
                            Some(line),
                        ));
                    }
                }
            }
        }
        let has_uv = self.corners.iter().all(|c| c[1] != NONE);
        let has_n = self.corners.iter().all(|c| c[2] != NONE);
        let mut out = TriangleSoup::default();
        let mut indices: Vec<u32> = Vec::with_capacity(self.corners.len());
        if !has_uv && !has_n {
            // Positions only: the file's own vertices, as they are.
            indices.extend(self.corners.iter().map(|c| c[0]));
            out.positions = self.positions;
        } else {
            let mut uvs = Vec::new();
            let mut normals = Vec::new();
            let mut seen: HashMap<Corner, u32> = HashMap::new();
            for c in &self.corners {
                let key = [
                    c[0],
                    if has_uv { c[1] } else { NONE },
                    if has_n { c[2] } else { NONE },
                ];
                let k = *seen.entry(key).or_insert_with(|| {
                    out.positions.push(self.positions[c[0] as usize]);
                    if has_uv {
                        uvs.push(self.uvs[c[1] as usize]);
                    }
                    if has_n {
                        normals.push(self.normals[c[2] as usize]);
                    }
                    out.positions.len() as u32 - 1
                });
                indices.push(k);
            }
            out.uvs = has_uv.then_some(uvs);
            out.normals = has_n.then_some(normals);
        }
        out.triangles.reserve(self.face_lines.len());
        for f in 0..self.face_lines.len() {
            triangulate(
                &indices[self.starts[f]..self.starts[f + 1]],
                &mut out.triangles,
            );
        }
        Ok(out)
    }
}

/// An index as written (from 1, or negative from the end of the `len`
/// defined so far) made an index from 0; empty is [`NONE`].
fn resolve(s: &str, len: usize, what: &str) -> Result<u32, String> {
    if s.is_empty() {
        return Ok(NONE);
    }
    let k: i64 = s
        .parse()
        .map_err(|_| format!("{} is not a {what} index", quote(s)))?;
    let k = match k {
        0 => return Err(format!("{what} index 0: OBJ counts from 1")),
        k if k > 0 => k - 1,
        k => {
            let back = len as i64 + k;
            if back < 0 {
                return Err(format!(
                    "{what} index {k} reaches back before the first (only {len} defined above)"
                ));
            }
            back
        }
    };
    // u32::MAX is NONE; a larger file would be over the size budget anyway.
    u32::try_from(k)
        .ok()
        .filter(|&k| k != NONE)
        .ok_or_else(|| format!("{what} index {} is out of range", quote(s)))
}

/// Why a statement's numbers were refused.
enum Numbers {
    Count(usize),
    NotANumber(String),
}

impl Numbers {
    fn say(&self, line: &str, wanted: &str) -> String {
        match self {
            Numbers::Count(n) => format!("{}: expected `{wanted}`, found {n} numbers", quote(line)),
            Numbers::NotANumber(w) => {
                format!("{}: cannot read {} as a number", quote(line), quote(w))
            }
        }
    }
}

/// `min..=max` numbers; the first `min` are returned (those past them are
/// read for validity and dropped).
fn numbers<'a>(
    words: impl Iterator<Item = &'a str>,
    min: usize,
    max: usize,
) -> Result<Vec<f64>, Numbers> {
    let mut out = Vec::with_capacity(max);
    for w in words {
        out.push(
            w.parse::<f64>()
                .map_err(|_| Numbers::NotANumber(w.to_string()))?,
        );
    }
    if out.len() < min || out.len() > max {
        return Err(Numbers::Count(out.len()));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: &str = "\
# a unit cube
o cube
mtllib cube.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
g sides
usemtl grey
s off
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
";

    #[test]
    fn a_cube_of_quads_reads_as_twelve_triangles() {
        let m = parse(CUBE.as_bytes()).unwrap();
        assert_eq!(m.positions.len(), 8);
        assert_eq!(m.triangles.len(), 12);
        assert_eq!(m.triangles[0], [0, 3, 2]);
        assert_eq!(m.triangles[1], [0, 2, 1]);
        assert_eq!(m.positions[6], DVec3::ONE);
        assert!(m.uvs.is_none() && m.normals.is_none());
    }

    #[test]
    fn negative_indices_count_back_from_the_latest() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf 1 -3 -2\n";
        let m = parse(text.as_bytes()).unwrap();
        // The second face: -3 is vertex 2 (from 1) once four are defined.
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 1, 2]]);
    }

    #[test]
    fn texture_coordinates_and_normals_make_one_vertex_per_triple() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                    vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
                    f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
        let m = parse(text.as_bytes()).unwrap();
        assert_eq!(m.positions.len(), 4, "shared corners are one vertex");
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.uvs.as_ref().unwrap()[2], DVec2::ONE);
        assert_eq!(m.normals.as_ref().unwrap()[3], DVec3::Z);
        // One position with two texture coordinates (a seam) is two vertices.
        let seam = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n\
                    f 1/1 2/2 3/3\nf 1/4 3/3 2/2\n";
        let m = parse(seam.as_bytes()).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.positions[3], DVec3::ZERO);
        assert_eq!(m.uvs.as_ref().unwrap()[3], DVec2::splat(0.5));
        // `v//vn`: normals without texture coordinates.
        let m = parse(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nf 1//1 2//1 3//1\n").unwrap();
        assert!(m.uvs.is_none());
        assert_eq!(m.normals.unwrap()[1], -DVec3::Z);
        // Some corners without: neither is kept (as PLY keeps a property
        // only when every vertex has it).
        let m = parse(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3\n").unwrap();
        assert!(m.uvs.is_none());
        assert_eq!(m.positions.len(), 3);
    }

    #[test]
    fn line_endings_and_comments() {
        let want = parse(CUBE.as_bytes()).unwrap();
        assert_eq!(parse(CUBE.replace('\n', "\r\n").as_bytes()).unwrap(), want);
        assert_eq!(parse(CUBE.replace('\n', "\r").as_bytes()).unwrap(), want);
        let commented = CUBE.replace("f 1 4 3 2", "f 1 4 3 2 # bottom");
        assert_eq!(parse(commented.as_bytes()).unwrap(), want);
        assert_eq!(parse(format!("\u{feff}{CUBE}").as_bytes()).unwrap(), want);
    }

    /// Every malformed file says its line and quotes what is wrong.
    #[test]
    fn malformed_files_give_their_line_and_text() {
        let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        let cases: &[(&str, usize, &str)] = &[
            ("v 0 0 0\nv 1 zero 0\n", 2, "`zero`"),
            ("v 0 0\n", 1, "found 2 numbers"),
            ("v 0 0 inf\n", 1, "finite"),
            ("vn 0 1\n", 1, "`vn 0 1`"),
            ("vt 0 x\n", 1, "`x`"),
            ("v 0 0 0\nf 1 2\n", 2, "at least 3"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n",
                5,
                "vertex index 4 is out of range",
            ),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "counts from 1"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", 4, "`-4`"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n",
                4,
                "`a` is not a texture",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n",
                4,
                "texture coordinate index 1",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//2 3//2\n",
                4,
                "normal index 2",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n",
                4,
                "three parts",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 2 3\n",
                4,
                "names no vertex",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n",
                4,
                "99999999999",
            ),
            ("cstype bspline\n", 1, "free-form"),
            (
                "v 0 0 0\nvertex 1 2 3\n",
                2,
                "`vertex` is not an OBJ statement",
            ),
        ];
        for &(text, line, says) in cases {
            let e = parse(text.as_bytes()).unwrap_err();
            assert_eq!(e.line, Some(line), "{text:?}: {e}");
            assert!(e.message.contains(says), "{text:?}: {e}");
        }
        let e = parse(format!("{tri}f 1 2 3\nf 1 2 3 x\n").as_bytes()).unwrap_err();
        assert!(e.message.contains("`f 1 2 3 x`"), "the line is quoted: {e}");
        // Whole-file mistakes.
        assert!(parse(b"").unwrap_err().message.contains("empty"));
        assert!(
            parse(tri.as_bytes())
                .unwrap_err()
                .message
                .contains("no faces")
        );
        let e = parse(b"v 0 0 0\nv 1 \xff 0\n").unwrap_err();
        assert_eq!(e.line, Some(2));
        assert!(e.message.contains("not text"));
    }

    #[test]
    fn long_lines_are_quoted_short() {
        let long = format!("v 0 0 {}x\n", "1".repeat(500));
        let e = parse(long.as_bytes()).unwrap_err();
        assert!(e.message.len() < 200, "{e}");
        assert!(e.message.contains('…'));
    }

    /// A face of 200,000 corners is cut by halving, not a fan of slivers,
    /// and read at once.
    #[test]
    fn a_huge_polygon_reads_quickly() {
        let n = 200_000;
        let mut text = String::new();
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            text += &format!("v {} {} 0\n", a.cos(), a.sin());
        }
        text += "f";
        for k in 1..=n {
            text += &format!(" {k}");
        }
        let start = std::time::Instant::now();
        let m = parse(text.as_bytes()).unwrap();
        assert_eq!(m.triangles.len(), n - 2);
        assert!(start.elapsed().as_secs_f64() < 5.0);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
        /// Mangled files never panic: each is read or refused.
        #[test]
        fn mangled_files_never_panic(
            edits in proptest::collection::vec(
                (proptest::prelude::any::<proptest::sample::Index>(), proptest::prelude::any::<u8>(), 0u8..3),
                1..8,
            ),
        ) {
            let mut b = format!("{CUBE}vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 -1/-1/-1\n").into_bytes();
            super::super::mangle(&mut b, edits);
            let _ = parse(&b);
        }
    }

    /// Files the project writes (the icosphere as OBJ) read back as their
    /// PLY twin does.
    #[test]
    fn agrees_with_ply_on_the_icosphere() {
        let (p, t) = super::super::ply::icosphere(2);
        let faces: Vec<Vec<u32>> = t.iter().map(|f| f.to_vec()).collect();
        let ply = super::super::ply::parse(super::super::ply::write_ascii(&p, &faces).as_bytes())
            .unwrap();
        let obj = parse(write(&p, &t).as_bytes()).unwrap();
        assert_eq!(obj, ply);
    }

    /// An OBJ with the given vertices and triangles, rounded to `f32`
    /// like the PLY writer's (and written exactly), so both read back alike.
    fn write(p: &[DVec3], t: &[[u32; 3]]) -> String {
        let mut s = String::new();
        let r = |x: f64| x as f32 as f64;
        for v in p {
            s += &format!("v {} {} {}\n", r(v.x), r(v.y), r(v.z));
        }
        for f in t {
            s += &format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
        }
        s
    }
}
