//! A triangle (placeholder: the constructor's signature is fixed, the geometry is
//! not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Triangle {
    _material: MaterialId,
}

impl Triangle {
    pub fn new(_a: DVec3, _b: DVec3, _c: DVec3, material: MaterialId) -> Self {
        Triangle {
            _material: material,
        }
    }
}

impl Shape for Triangle {
    fn intersect(&self, _ray: &Ray, _t_min: f64, _t_max: f64) -> Option<Hit> {
        None
    }
    fn crossings(&self, _ray: &Ray, _out: &mut Vec<Hit>) {}
    fn bounds(&self) -> Aabb {
        Aabb::EMPTY
    }
    fn is_solid(&self) -> bool {
        true
    }
}
