//! Patterns: scalar fields f(point, uv) → [0, 1] that a material turns into
//! a colour (through a [`ColourMap`]), into a choice of whole materials
//! ([`MaterialPick`]), or that tilt the shading normal ([`NormalPattern`]).
//!
//! Solid patterns read the hit's point in the object's own space, surface
//! patterns its (u, v), so a pattern moves, turns and scales with its
//! object. Every pattern also has its own placement: `translate` and
//! `rotate` (applied like an object's, in the order written) and `scale`,
//! which multiplies the coordinates (a larger `scale`, more repeats per
//! unit), then, for solid patterns other than marble and wood (which have
//! their own), `turbulence` displaces the point by a vector of noise.
//!
//! ```text
//! colour checker   { a white  b black  scale <8, 4> }          // (u, v)
//! colour checker3d { a white  b black  size 0.5 }
//! colour gradient  { axis <0, 1, 0>  colour_map { 0 red  0.5 white  1 blue } }
//! colour noise     { a black  b white  scale 4 }
//! colour granite   { colour_map { 0 #303030  0.6 #808080  1 white }  scale 2 }
//! colour marble    { a white  b rgb(0.1, 0.1, 0.3)  scale 2  turbulence 4 }
//! colour wood      { a #c8a060  b #704018  scale 6  turbulence 0.5 }
//! colour sectors   { count 6  colour_map { 0 red  1 blue } }   // around y, or `uv`
//! colour quadrants { a white  b black  uv }
//! colour image "height.png" { a black  b white }               // grey value
//! ```

mod checker;
mod checker3d;
mod choice;
mod colour_map;
mod gradient;
mod granite;
mod image;
mod marble;
mod noise;
mod normal;
mod sectors;
mod wood;

pub use checker::Checker;
pub use checker3d::Checker3d;
pub use choice::{MaterialPick, resolve};
pub use colour_map::{ColourMap, MapError};
pub use gradient::Gradient;
pub use granite::Granite;
pub use image::ImagePattern;
pub use marble::Marble;
pub use noise::Noise;
pub use normal::{NormalKind, NormalPattern};
pub use sectors::Sectors;
pub use wood::Wood;

use super::Colour;
use super::texture::noise as perlin;
use crate::geometry::{DVec2, DVec3, Transform};

/// Names a pattern may be written with, for "did you mean".
pub const NAMES: &[&str] = &[
    "checker",
    "checker3d",
    "gradient",
    "noise",
    "granite",
    "marble",
    "wood",
    "sectors",
    "quadrants",
    "image",
];

/// What a pattern computes, before its placement.
#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    Checker(Checker),
    Checker3d(Checker3d),
    Gradient(Gradient),
    Noise(Noise),
    Granite(Granite),
    Marble(Marble),
    Wood(Wood),
    Sectors(Sectors),
    Image(ImagePattern),
}

/// A pattern and where it sits in its object's space.
#[derive(Clone, Debug, PartialEq)]
pub struct Pattern {
    pub kind: Kind,
    /// `translate` and `rotate`: the pattern is read at M⁻¹·p (None: identity).
    pub place: Option<Transform>,
    /// Multiplies the (placed) point of solid patterns: repeats per unit.
    pub scale: DVec3,
    /// Strength of the noise displacement of solid patterns (0: none).
    pub turbulence: f64,
}

impl Pattern {
    /// A pattern in its own space (no placement, scale 1, no turbulence).
    pub fn new(kind: Kind) -> Pattern {
        Pattern {
            kind,
            place: None,
            scale: DVec3::ONE,
            turbulence: 0.0,
        }
    }

    /// Whether it reads the hit's (u, v), which some shapes compute only on
    /// request ([`crate::shapes::Shape::uv`]).
    pub fn reads_uv(&self) -> bool {
        match &self.kind {
            Kind::Checker(_) | Kind::Image(_) => true,
            Kind::Sectors(s) => s.uv,
            _ => false,
        }
    }

    /// The value in [0, 1] at object-space point `p` with coordinates `uv`.
    pub fn value(&self, p: DVec3, uv: DVec2) -> f64 {
        let v = match &self.kind {
            Kind::Checker(c) => c.value(self.place_uv(uv)),
            Kind::Image(i) => i.value(self.place_uv(uv)),
            Kind::Sectors(s) if s.uv => s.value_uv(self.place_uv(uv)),
            Kind::Marble(m) => m.value(self.solid_point(p), self.turbulence),
            Kind::Wood(w) => w.value(self.solid_point(p), self.turbulence),
            kind => {
                let q = warp(self.solid_point(p), self.turbulence);
                match kind {
                    Kind::Checker3d(c) => c.value(q),
                    Kind::Gradient(g) => g.value(q),
                    Kind::Noise(n) => n.value(q),
                    Kind::Granite(g) => g.value(q),
                    Kind::Sectors(s) => s.value_solid(q),
                    _ => unreachable!("handled above"),
                }
            }
        };
        v.clamp(0.0, 1.0)
    }

    /// The object-space point in the pattern's space: M⁻¹·p, then scaled.
    fn solid_point(&self, p: DVec3) -> DVec3 {
        let p = match &self.place {
            Some(m) => m.inverse_point(p),
            None => p,
        };
        p * self.scale
    }

    /// (u, v) moved by the pattern's `translate` (its x and y); surface
    /// patterns take their scale themselves (the course's checker needs it
    /// apart from the coordinate).
    fn place_uv(&self, uv: DVec2) -> DVec2 {
        match &self.place {
            Some(m) => {
                let q = m.inverse_point(DVec3::new(uv.x, uv.y, 0.0));
                DVec2::new(q.x, q.y)
            }
            None => uv,
        }
    }
}

/// POV-Ray's turbulence: the point displaced by `amount` times a vector of
/// three decorrelated turbulence sums (sampled at far-apart offsets).
fn warp(p: DVec3, amount: f64) -> DVec3 {
    if amount == 0.0 {
        return p;
    }
    let t = |o: DVec3| perlin::turbulence(p + o, 6) - 0.3;
    p + amount
        * DVec3::new(
            t(DVec3::ZERO),
            t(DVec3::new(31.4, 17.3, -9.2)),
            t(DVec3::new(-23.9, 41.1, 12.7)),
        )
}

/// A pattern turned into colour by a map: what `colour PATTERN { … }` makes.
#[derive(Clone, Debug, PartialEq)]
pub struct ColourPattern {
    pub pattern: Pattern,
    pub map: ColourMap,
}

impl ColourPattern {
    pub fn colour(&self, p: DVec3, uv: DVec2) -> Colour {
        self.map.at(self.pattern.value(p, uv))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turbulence_moves_a_solid_pattern_and_zero_leaves_it() {
        let g = |t| Pattern {
            turbulence: t,
            ..Pattern::new(Kind::Gradient(Gradient {
                axis: DVec3::new(0.3, 0.0, 0.0),
                mirror: false,
            }))
        };
        let (calm, rough) = (g(0.0), g(0.8));
        let mut moved = 0;
        for i in 0..200 {
            let p = DVec3::new(i as f64 * 0.05, 0.3, -0.2);
            assert_eq!(calm.value(p, DVec2::ZERO), (0.3 * p.x).fract());
            let v = rough.value(p, DVec2::ZERO);
            assert!((0.0..=1.0).contains(&v));
            if (v - calm.value(p, DVec2::ZERO)).abs() > 0.02 {
                moved += 1;
            }
        }
        assert!(moved > 100, "{moved}");
    }

    #[test]
    fn placement_translates_then_scales_solid_points() {
        let mut p = Pattern::new(Kind::Gradient(Gradient {
            axis: DVec3::X,
            mirror: false,
        }));
        p.place = Some(Transform::translate(DVec3::new(0.25, 0.0, 0.0)));
        p.scale = DVec3::splat(0.5);
        // ((1 − 0.25) · 0.5) = 0.375
        assert_eq!(p.value(DVec3::new(1.0, 7.0, 7.0), DVec2::ZERO), 0.375);
    }
}
