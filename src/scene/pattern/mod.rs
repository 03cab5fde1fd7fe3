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
                // Two inlined lookups, not one of a point that is either:
                // the point then went through memory, stored in two parts
                // and read back across them (a stalled store-to-load
                // forward, a third of a checkered floor's lookup).
                let q = self.solid_point(p);
                if self.turbulence == 0.0 {
                    solid_value(kind, q)
                } else {
                    solid_value(kind, warp(q, self.turbulence))
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

/// The value of a solid pattern (one that reads the point, not (u, v))
/// at pattern-space point `q`.
#[inline(always)]
fn solid_value(kind: &Kind, q: DVec3) -> f64 {
    match kind {
        Kind::Checker3d(c) => c.value(q),
        Kind::Gradient(g) => g.value(q),
        Kind::Noise(n) => n.value(q),
        Kind::Granite(g) => g.value(q),
        Kind::Sectors(s) => s.value_solid(q),
        _ => unreachable!("surface patterns, marble and wood are looked up apart"),
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

    fn image_pattern() -> ImagePattern {
        let mut img = ::image::RgbImage::new(2, 1);
        img.put_pixel(0, 0, ::image::Rgb([255, 0, 0]));
        img.put_pixel(1, 0, ::image::Rgb([0, 0, 255]));
        ImagePattern {
            image: std::sync::Arc::new(super::super::texture::ImageTexture::from_rgb8(
                &img,
                super::super::Transfer::Linear,
                Default::default(),
            )),
        }
    }

    /// Surface patterns (checker, image, sectors with `uv`) read (u, v),
    /// the others the point; and `Pattern::value` without placement is
    /// the kind's own value, clamped, read from the right one of the two.
    #[test]
    fn each_kind_reads_uv_or_the_point_as_documented() {
        let sectors = |uv| Sectors {
            count: 5,
            uv,
            alternate: false,
        };
        let surface = [
            Kind::Checker(Checker {
                scale: DVec2::new(4.0, 3.0),
            }),
            Kind::Image(image_pattern()),
            Kind::Sectors(sectors(true)),
        ];
        let solid = [
            Kind::Checker3d(Checker3d::new(0.7)),
            Kind::Gradient(Gradient {
                axis: DVec3::new(0.3, 0.2, 0.1),
                mirror: false,
            }),
            Kind::Noise(Noise { octaves: 2 }),
            Kind::Granite(Granite),
            Kind::Marble(Marble),
            Kind::Wood(Wood),
            Kind::Sectors(sectors(false)),
        ];
        for k in &surface {
            assert!(Pattern::new(k.clone()).reads_uv(), "{k:?}");
        }
        for k in &solid {
            assert!(!Pattern::new(k.clone()).reads_uv(), "{k:?}");
        }
        for i in 0..60 {
            let t = i as f64;
            let p = DVec3::new((0.7 * t).sin() * 2.0, 0.3 * t - 5.0, (1.3 * t).cos() * 3.0);
            let uv = DVec2::new((0.9 * t).cos(), (0.4 * t).sin() + 0.1 * t);
            for k in surface.iter().chain(&solid) {
                let own = match k {
                    Kind::Checker(c) => c.value(uv),
                    Kind::Image(im) => im.value(uv),
                    Kind::Sectors(s) if s.uv => s.value_uv(uv),
                    Kind::Sectors(s) => s.value_solid(p),
                    Kind::Checker3d(c) => c.value(p),
                    Kind::Gradient(g) => g.value(p),
                    Kind::Noise(n) => n.value(p),
                    Kind::Granite(g) => g.value(p),
                    Kind::Marble(m) => m.value(p, 0.0),
                    Kind::Wood(w) => w.value(p, 0.0),
                };
                let got = Pattern::new(k.clone()).value(p, uv);
                assert_eq!(got, own.clamp(0.0, 1.0), "{k:?} at {p}, {uv}");
            }
        }
    }

    /// A surface pattern's `translate` moves it on (u, v): the placed
    /// checker at uv is the unplaced one at uv − (x, y).
    #[test]
    fn translate_moves_a_surface_pattern_in_uv() {
        let kind = Kind::Checker(Checker {
            scale: DVec2::splat(4.0),
        });
        let mut placed = Pattern::new(kind.clone());
        let t = DVec2::new(0.3, -0.1);
        placed.place = Some(Transform::translate(DVec3::new(t.x, t.y, 0.0)));
        let unplaced = Pattern::new(kind);
        let (mut zeros, mut ones) = (0, 0);
        for i in -6..6 {
            for j in -6..6 {
                // Cell centres of the unplaced checker, moved by t.
                let c = DVec2::new((i as f64 + 0.5) / 4.0, (j as f64 + 0.5) / 4.0);
                let want = unplaced.value(DVec3::ZERO, c);
                assert_eq!(placed.value(DVec3::ZERO, c + t), want, "{c}");
                if want == 0.0 { zeros += 1 } else { ones += 1 }
            }
        }
        assert!(zeros > 50 && ones > 50);
    }

    /// Turbulence displaces the point by `amount` times three turbulence
    /// sums (six octaves, centred by −0.3), read at the point and at two
    /// far offsets: pinned, since every turbulent picture depends on it.
    #[test]
    fn warp_is_the_documented_displacement() {
        for i in 0..40 {
            let p = DVec3::new(0.37 * i as f64, 1.0 - 0.21 * i as f64, (i as f64).sin());
            let a = 0.25 + 0.1 * i as f64;
            let t = |o: DVec3| perlin::turbulence(p + o, 6) - 0.3;
            let want = p + a * DVec3::new(
                t(DVec3::ZERO),
                t(DVec3::new(31.4, 17.3, -9.2)),
                t(DVec3::new(-23.9, 41.1, 12.7)),
            );
            assert_eq!(warp(p, a), want);
        }
        assert_eq!(
            warp(DVec3::new(0.1, 0.2, 0.3), 0.0),
            DVec3::new(0.1, 0.2, 0.3)
        );
    }

    #[test]
    fn a_colour_pattern_is_its_map_at_its_value() {
        let map = ColourMap::two(Colour::new(1.0, 0.5, 0.0), Colour::new(0.0, 0.25, 1.0));
        let cp = ColourPattern {
            pattern: Pattern::new(Kind::Gradient(Gradient {
                axis: DVec3::X,
                mirror: false,
            })),
            map: map.clone(),
        };
        for x in [0.0, 0.25, 0.5, 0.875] {
            let p = DVec3::new(x, 3.0, -1.0);
            assert_eq!(cp.colour(p, DVec2::ZERO), map.at(x));
        }
    }
}
