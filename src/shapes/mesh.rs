//! Triangle meshes from PLY files (placeholder: the signatures are fixed,
//! the reader and the kd-tree are not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, Ray};
use crate::scene::MaterialId;
use std::path::Path;
use std::sync::Arc;

/// A PLY file that could not be read; `line` or `element` where known.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct PlyError {
    pub message: String,
    pub line: Option<usize>,
    pub element: Option<String>,
}

/// Triangles loaded once and shared by every placement (instancing).
#[derive(Debug)]
pub struct MeshData {}

impl MeshData {
    pub fn load(path: &Path) -> Result<MeshData, PlyError> {
        Err(PlyError {
            message: format!("cannot read meshes yet ({})", path.display()),
            line: None,
            element: None,
        })
    }
}

#[derive(Debug)]
pub struct Mesh {
    _data: Arc<MeshData>,
    _smooth: bool,
    _material: MaterialId,
}

impl Mesh {
    pub fn new(data: Arc<MeshData>, smooth: bool, material: MaterialId) -> Self {
        Mesh {
            _data: data,
            _smooth: smooth,
            _material: material,
        }
    }
}

impl Shape for Mesh {
    fn intersect(&self, _ray: &Ray, _t_min: f64, _t_max: f64) -> Option<Hit> {
        None
    }
    fn crossings(&self, _ray: &Ray, _out: &mut Vec<Hit>) {}
    fn bounds(&self) -> Aabb {
        Aabb::EMPTY
    }
    fn is_solid(&self) -> bool {
        false
    }
}
