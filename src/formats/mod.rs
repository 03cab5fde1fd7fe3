//! Readers of the file formats a scene names, kept together and apart from
//! the shapes and textures that use what they read: meshes (PLY, OBJ, STL)
//! come out
//! as a [`TriangleSoup`], pictures as [`image::Pixels`]. Each reader checks
//! everything the file controls (sizes against the budgets, counts,
//! indices, finite numbers) and reports what is wrong with a line where
//! the format has lines.

pub mod image;
pub mod obj;
pub mod ply;
mod soup;
pub mod stl;

pub use soup::{FAN_MAX, MeshFileError, TriangleSoup, triangulate};

use std::path::Path;

/// Largest mesh file read: 2 GiB holds some 60 million triangles.
pub const MAX_MESH_BYTES: u64 = 2 << 30;

/// The mesh formats, told by the file's extension (in any case).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    Ply,
    Obj,
    Stl,
}

impl MeshFormat {
    /// The format a file name says. Any other extension, or none, is read
    /// as PLY when the file says so (`mesh "bunny"` always has been).
    pub fn of(path: &Path) -> Option<MeshFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "ply" => Some(MeshFormat::Ply),
            "obj" => Some(MeshFormat::Obj),
            "stl" => Some(MeshFormat::Stl),
            _ => None,
        }
    }

    pub fn parse(self, bytes: &[u8]) -> Result<TriangleSoup, MeshFileError> {
        match self {
            MeshFormat::Ply => ply::parse(bytes),
            MeshFormat::Obj => obj::parse(bytes),
            MeshFormat::Stl => stl::parse(bytes),
        }
    }
}

/// Reads a mesh file, within [`MAX_MESH_BYTES`], in the format its
/// extension names.
pub fn read_mesh(path: &Path) -> Result<TriangleSoup, MeshFileError> {
    let bytes =
        crate::lang::source::read_bounded(path, MAX_MESH_BYTES).map_err(|e| MeshFileError {
            message: format!("cannot read the file: {e}"),
            line: None,
            element: None,
        })?;
    match MeshFormat::of(path) {
        Some(format) => format.parse(&bytes),
        None if bytes.starts_with(b"ply") => ply::parse(&bytes),
        None => Err(MeshFileError {
            message: "not a mesh file this reads: the name should end in .ply, .obj or .stl".into(),
            line: None,
            element: None,
        }),
    }
}

/// For the readers' property tests: applies byte edits (0 overwrite,
/// 1 insert, 2 remove, each at an index into the current bytes), stopping
/// if the bytes run out.
#[cfg(test)]
pub(crate) fn mangle(b: &mut Vec<u8>, edits: Vec<(proptest::sample::Index, u8, u8)>) {
    for (at, byte, op) in edits {
        if b.is_empty() {
            break;
        }
        let i = at.index(b.len());
        match op {
            0 => b[i] = byte,
            1 => b.insert(i, byte),
            _ => {
                b.remove(i);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The extension picks the reader in any case; a file named otherwise
    /// is read as PLY only when it says so.
    #[test]
    fn the_extension_picks_the_reader() {
        let dir = tempfile::tempdir().unwrap();
        let (p, t) = ply::icosphere(0);
        let faces: Vec<Vec<u32>> = t.iter().map(|f| f.to_vec()).collect();
        let ply_text = ply::write_ascii(&p, &faces);
        let obj_text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let cases: &[(&str, &str, Result<usize, &str>)] = &[
            ("a.ply", &ply_text, Ok(20)),
            ("a.PLY", &ply_text, Ok(20)),
            ("bunny", &ply_text, Ok(20)),
            ("a.Obj", obj_text, Ok(1)),
            // OBJ text in a file named .ply is refused by the PLY reader.
            ("b.ply", obj_text, Err("not a PLY")),
            ("c.stl", obj_text, Err("not an STL")),
            ("d.off", "OFF\n", Err(".ply, .obj or .stl")),
        ];
        for (name, text, want) in cases {
            let path = dir.path().join(name);
            std::fs::write(&path, text).unwrap();
            match (read_mesh(&path), want) {
                (Ok(m), Ok(n)) => assert_eq!(m.triangles.len(), *n, "{name}"),
                (Err(e), Err(says)) => assert!(e.message.contains(says), "{name}: {e}"),
                (got, _) => panic!("{name}: {got:?}"),
            }
        }
        let e = read_mesh(&dir.path().join("missing.obj")).unwrap_err();
        assert!(e.message.contains("cannot read"), "{e}");
    }
}
