//! A parallelogram (placeholder: the constructor's signature is fixed, the geometry is
//! not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Rectangle {
    _material: MaterialId,
}

impl Rectangle {
    pub fn new(
        _bottom_left: DVec3,
        _top_left: DVec3,
        _bottom_right: DVec3,
        material: MaterialId,
    ) -> Self {
        Rectangle {
            _material: material,
        }
    }
}

impl Shape for Rectangle {
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
