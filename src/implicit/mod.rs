//! Implicit surfaces from equation strings, compiled once at scene load.
//!
//! ```text
//! let R = 2
//! let r = 0.5
//! implicit "(x^2+y^2+z^2+R^2-r^2)^2 - 4R^2(x^2+y^2)" { bounded_by <-3,-3,-1> <3,3,1>  material gold }
//! implicit "x^2 + y^2 + z^2 = 1" { material red }     // automatic bounding box
//! ```
//!
//! The pipeline: `parse` (text → tree with spans) → `expand` (constants
//! substituted, roots eliminated, one polynomial in x, y, z) → `ray_poly`
//! (nested Horner form: per ray only the coefficients of t are evaluated;
//! the gradient is three more such forms) → `solve` (roots in an interval)
//! → `surface` (the shape: bounds, branch test, normals). `bounds` finds a
//! box for surfaces that are bounded.

mod bounds;
mod expand;
mod memo;
mod parse;
mod poly;
mod ray_poly;
pub mod scenes;
pub mod solve;
mod surface;

pub use expand::{MAX_DEGREE, MAX_ROOT};
pub use surface::{BoundSource, ImplicitSurface};

use crate::geometry::{Aabb, DVec3};
use expand::Tree;
use ray_poly::Compact;
use std::ops::Range;
use std::sync::{Arc, OnceLock};

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
pub struct Equation {
    degree: u32,
    /// The polynomial, scaled so its largest coefficient is ±1 (the sign is
    /// kept: inside is where it is negative).
    value: Compact,
    gradient: [Compact; 3],
    /// The original expression, kept when it had roots, to reject points of
    /// the branches that raising to powers added.
    branch: Option<Tree>,
    /// The terms for bounds and tests: (exponents of x, y, z, coefficient).
    terms: Vec<([u16; 3], f64)>,
    /// The automatic box, found on first use (thousands of solves at high
    /// degree) and shared by every clone: the equation memo hands out
    /// clones, so twenty objects with one equation search once.
    auto_box: Arc<OnceLock<Option<Aabb>>>,
}

impl Equation {
    /// `constant` resolves names other than x, y, z (from `let`).
    pub fn compile(
        text: &str,
        constant: &dyn Fn(&str) -> Option<f64>,
    ) -> Result<Equation, Vec<EquationError>> {
        let parsed = parse::parse(text)?;
        let key = memo::Key::new(text, &parsed, constant);
        if let Some(eq) = memo::get(&key) {
            return Ok(eq);
        }
        let expanded = expand::expand(&parsed, constant)?;
        let scale = expanded.poly.max_abs();
        let poly = expanded.poly.scale(1.0 / scale);
        let eq = Equation {
            degree: poly.degree(),
            value: Compact::new(&poly),
            gradient: [0, 1, 2].map(|i| Compact::new(&poly.derivative(i))),
            branch: expanded.has_roots.then_some(expanded.tree),
            terms: poly
                .terms
                .iter()
                .map(|(e, c)| ([e[0], e[1], e[2]], *c))
                .collect(),
            auto_box: Arc::default(),
        };
        memo::put(key, &eq);
        Ok(eq)
    }

    /// The degree of the polynomial the equation became.
    pub fn degree(&self) -> u32 {
        self.degree
    }

    /// The polynomial's value at a point (negative inside).
    pub fn value(&self, p: DVec3) -> f64 {
        self.value.eval(p)
    }

    /// The polynomial's gradient at a point.
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        DVec3::new(
            self.gradient[0].eval(p),
            self.gradient[1].eval(p),
            self.gradient[2].eval(p),
        )
    }

    /// Σ |c|·|x|^i·|y|^j·|z|^k over the polynomial's terms: the size of the
    /// sums that evaluating it at (or near) `p` adds, which scales the
    /// rounding error of the value (Higham's running error bound).
    pub fn magnitude(&self, p: DVec3) -> f64 {
        let a = p.abs();
        self.terms
            .iter()
            .map(|(e, c)| {
                c.abs() * a.x.powi(e[0] as i32) * a.y.powi(e[1] as i32) * a.z.powi(e[2] as i32)
            })
            .sum()
    }

    /// Whether a point of the polynomial's zero set lies on the branch the
    /// written equation describes (always true without roots).
    pub fn on_written_branch(&self, p: DVec3) -> bool {
        match &self.branch {
            None => true,
            Some(t) => expand::eval(t, p)
                .is_some_and(|d| d.v.abs() <= 1e-6 * d.mag.max(1e-300) || d.v == 0.0),
        }
    }

    /// A box holding the whole surface, when one can be found.
    pub fn auto_bounds(&self) -> Option<Aabb> {
        *self.auto_box.get_or_init(|| bounds::auto_box(self))
    }
}

#[cfg(test)]
pub(crate) mod tests;

#[cfg(test)]
mod render_tests;
