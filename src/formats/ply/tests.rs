//! The PLY reader's tests: every encoding and list type, the fast path
//! against the crate, line endings, malformed files and mangled bytes.

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
            ("ushort" | "short" | "uint16" | "int16", false) => (v as u16).to_le_bytes().to_vec(),
            ("ushort" | "short" | "uint16" | "int16", true) => (v as u16).to_be_bytes().to_vec(),
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
            let m = parse(&square(format, list)).unwrap_or_else(|e| panic!("{format} {list}: {e}"));
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
        let fast = parse_with(f, Some(fast::RUN_LINES)).unwrap();
        assert_eq!(fast, parse_with(f, None).unwrap());
        let text = String::from_utf8_lossy(f);
        assert!(
            !text.contains("format ascii") || fast::payload_is_fast(f, fast::RUN_LINES),
            "the fast path declined {text}"
        );
    }
}

/// An ASCII file read in runs of any length, each run within one element
/// (an element between the vertices and the faces among them), gives the
/// crate's mesh; a run that ends early, a line too many or too few, and
/// trailing data are refused as in one run.
#[test]
fn runs_of_any_length_read_the_same_mesh() {
    let (positions, triangles) = icosphere(2);
    let faces: Vec<Vec<u32>> = triangles.iter().map(|t| t.to_vec()).collect();
    let text = write_ascii(&positions, &faces);
    let (head, body) = text.split_once("end_header\n").unwrap();
    let (verts, faces_text) = body.split_at(body.find("\n3 ").unwrap() + 1);
    let head = head.replace(
        "element face",
        "element edge 3\nproperty int a\nproperty float b\nelement face",
    );
    let file = format!("{head}end_header\n{verts}1 0.5\n2 0.25\n3 1e2\n{faces_text}").into_bytes();
    let want = parse_with(&file, None).unwrap();
    assert_eq!(want.triangles, triangles);
    for lines in [1, 2, 3, 7, 100, 161, 162, 163, 1000] {
        assert_eq!(parse_with(&file, Some(lines)).unwrap(), want, "{lines}");
        assert!(fast::payload_is_fast(&file, lines), "{lines}");
    }
    // One line fewer, one more, the first face cut short (its indices on
    // the next line), something after the last.
    let lines: Vec<&str> = file
        .split_inclusive(|&b| b == b'\n')
        .map(|l| std::str::from_utf8(l).unwrap())
        .collect();
    let short: String = lines[..lines.len() - 1].concat();
    let long = format!("{}3 0 1 2\n", lines.concat());
    let cut = lines.concat().replacen("\n3 ", "\n3 1\n", 1);
    let tail = format!("{}x\n", lines.concat());
    for bad in [short, long, cut, tail] {
        for runs in [None, Some(1), Some(5), Some(fast::RUN_LINES)] {
            assert!(parse_with(bad.as_bytes(), runs).is_err(), "{runs:?}");
            if let Some(lines) = runs {
                assert!(!fast::payload_is_fast(bad.as_bytes(), lines), "{lines}");
            }
        }
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

#[test]
fn missing_file_is_an_error() {
    let e = crate::shapes::MeshData::load(std::path::Path::new("/nonexistent/x.ply")).unwrap_err();
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
        crate::formats::mangle(&mut b, edits);
        if !b.is_empty() && cut.index(4) == 0 {
            b.truncate(cut.index(b.len()));
        }
        let _ = read(&b, None);
        let _ = read(&b, Some(2));
        let _ = parse(&b);
    }
}
