//! A cone (or frustum) along y (placeholder: the constructor's signature is fixed, the geometry is
//! not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Cone {
    _material: MaterialId,
}

impl Cone {
    /// Base radius `radius` at centre.y − height/2, `top_radius` at centre.y + height/2.
    pub fn new(
        _centre: DVec3,
        _radius: f64,
        _top_radius: f64,
        _height: f64,
        side: MaterialId,
        _caps: Option<[MaterialId; 2]>,
    ) -> Self {
        Cone { _material: side }
    }
}

impl Shape for Cone {
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
