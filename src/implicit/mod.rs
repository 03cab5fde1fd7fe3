//! Implicit surfaces from equation strings, compiled once at scene load
//! (placeholder: the signatures are fixed, the compiler is not written yet).

use crate::geometry::{Aabb, Ray};
use crate::scene::MaterialId;
use crate::shapes::{Hit, Shape};
use std::ops::Range;

/// A mistake inside an equation string; `span` is in bytes within the
/// string's text (the builder shifts it into the scene file).
#[derive(Clone, Debug, PartialEq)]
pub struct EquationError {
    pub span: Range<usize>,
    pub message: String,
    pub help: Option<String>,
}

/// An equation compiled to a polynomial in x, y, z.
#[derive(Clone, Debug)]
pub struct Equation {}

impl Equation {
    /// `constant` resolves names other than x, y, z (from `let`).
    pub fn compile(
        text: &str,
        _constant: &dyn Fn(&str) -> Option<f64>,
    ) -> Result<Equation, Vec<EquationError>> {
        Err(vec![EquationError {
            span: 0..text.len(),
            message: "implicit surfaces are not supported yet".into(),
            help: None,
        }])
    }
}

/// The shape: an equation plus its bounds.
#[derive(Debug)]
pub struct ImplicitSurface {
    _material: MaterialId,
}

impl ImplicitSurface {
    /// With `bounded_by: None` a bound is searched for automatically.
    pub fn new(_equation: Equation, _bounded_by: Option<Aabb>, material: MaterialId) -> Self {
        ImplicitSurface {
            _material: material,
        }
    }
}

impl Shape for ImplicitSurface {
    fn intersect(&self, _ray: &Ray, _t_min: f64, _t_max: f64) -> Option<Hit> {
        None
    }
    fn crossings(&self, _ray: &Ray, _out: &mut Vec<Hit>) {}
    fn bounds(&self) -> Aabb {
        Aabb::INFINITE
    }
    fn is_solid(&self) -> bool {
        true
    }
}
