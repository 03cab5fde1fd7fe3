//! An axis-aligned box (placeholder: the constructor's signature is fixed, the geometry is
//! not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Cuboid {
    _material: MaterialId,
}

impl Cuboid {
    /// `materials` per face: front (+z), back (−z), top (+y), bottom (−y), left (−x), right (+x).
    pub fn new(_min: DVec3, _max: DVec3, materials: [MaterialId; 6]) -> Self {
        Cuboid {
            _material: materials[0],
        }
    }
}

impl Shape for Cuboid {
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
