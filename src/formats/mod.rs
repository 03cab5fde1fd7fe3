//! Readers of the file formats a scene names, kept together and apart from
//! the shapes and textures that use what they read: meshes (PLY) come out
//! as a [`TriangleSoup`], pictures as [`image::Pixels`]. Each reader checks
//! everything the file controls (sizes against the budgets, counts,
//! indices, finite numbers) and reports what is wrong with a line where
//! the format has lines.

pub mod image;
pub mod ply;
mod soup;

pub use soup::{FAN_MAX, MeshFileError, TriangleSoup, triangulate};

use std::path::Path;

/// Largest mesh file read: 2 GiB holds some 60 million triangles.
pub const MAX_MESH_BYTES: u64 = 2 << 30;

/// Reads a mesh file, within [`MAX_MESH_BYTES`].
pub fn read_mesh(path: &Path) -> Result<TriangleSoup, MeshFileError> {
    let bytes =
        crate::lang::source::read_bounded(path, MAX_MESH_BYTES).map_err(|e| MeshFileError {
            message: format!("cannot read the file: {e}"),
            line: None,
            element: None,
        })?;
    ply::parse(&bytes)
}
