//! Constructive solid geometry (placeholder: the constructor's signature is
//! fixed, the interval logic is not written yet).

use super::{Hit, Shape};
use crate::geometry::{Aabb, Ray};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CsgOp {
    Union,
    Intersection,
    /// The first child minus all the others.
    Difference,
}

#[derive(Debug)]
pub struct Csg {
    _op: CsgOp,
    _children: Vec<Box<dyn Shape>>,
}

impl Csg {
    /// Every child must be solid (`is_solid()`); the builder checks that.
    pub fn new(op: CsgOp, children: Vec<Box<dyn Shape>>) -> Self {
        Csg {
            _op: op,
            _children: children,
        }
    }
}

impl Shape for Csg {
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
