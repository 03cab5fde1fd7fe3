//! A torus: ring in the x-z plane around y (placeholder: the constructor's signature is fixed, the geometry is
//! not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Torus {
    _material: MaterialId,
}

impl Torus {
    pub fn new(_major: f64, _minor: f64, material: MaterialId) -> Self {
        Torus {
            _material: material,
        }
    }
}

impl Shape for Torus {
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
