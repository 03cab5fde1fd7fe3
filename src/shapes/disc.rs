//! A disc parallel to the x-y plane (placeholder: the constructor's signature is fixed, the geometry is
//! not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Disc {
    _material: MaterialId,
}

impl Disc {
    pub fn new(_centre: DVec3, _radius: f64, material: MaterialId) -> Self {
        Disc {
            _material: material,
        }
    }
}

impl Shape for Disc {
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
