//! A cylinder along y (placeholder: the constructor's signature is fixed, the geometry is
//! not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Cylinder {
    _material: MaterialId,
}

impl Cylinder {
    /// `caps`: `Some([top, bottom])` for a solid cylinder, `None` for an open tube.
    pub fn new(
        _centre: DVec3,
        _radius: f64,
        _height: f64,
        side: MaterialId,
        _caps: Option<[MaterialId; 2]>,
    ) -> Self {
        Cylinder { _material: side }
    }
}

impl Shape for Cylinder {
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
