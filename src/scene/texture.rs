//! Textures: what colour a material has at a hit.
//!
//! A plain colour, an image's colours, or a pattern (`super::pattern`)
//! through a colour map. Surface patterns (`checker`, `image`) read the
//! hit's (u, v); solid patterns (`checker3d`, `marble`, `wood`, …) read the
//! hit's point in the object's own space, so every texture moves with its
//! object.
//!
//! ```text
//! material floor { colour checker   { a white  b rgb(0.2, 0.2, 0.2)  scale 4 } }
//! material tiles { colour checker3d { a white  b black  size 0.5 } }
//! material earth { colour image "earth.png" { scale <1, 1>  offset <0, 0>  swap  flip_u  flip_v } }
//! material stone { colour marble    { a white  b rgb(0.1, 0.1, 0.3)  scale 2  turbulence 4 } }
//! material oak   { colour wood      { a #c8a060  b #704018  scale 6  turbulence 0.5 } }
//! ```

mod image_map;
pub(super) mod noise;

pub use image_map::{ImageError, ImageTexture, UvMapping};

use super::Colour;
use super::pattern::ColourPattern;
use crate::shapes::Hit;
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    Solid(Colour),
    /// A picture's colours on (u, v).
    Image(Arc<ImageTexture>),
    /// Any pattern through a colour map (`checker`, `marble`, …: see
    /// [`super::pattern`]).
    Pattern(Arc<ColourPattern>),
}

impl Texture {
    /// Whether the texture reads the hit's (u, v), which some shapes
    /// compute only on request ([`crate::shapes::Shape::uv`]).
    pub fn reads_uv(&self) -> bool {
        match self {
            Texture::Solid(_) => false,
            Texture::Image(_) => true,
            Texture::Pattern(p) => p.pattern.reads_uv(),
        }
    }

    pub fn colour_at(&self, hit: &Hit) -> Colour {
        match self {
            Texture::Solid(c) => *c,
            Texture::Image(img) => img.sample(hit.uv),
            Texture::Pattern(p) => p.colour(hit.local, hit.uv),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{DVec2, DVec3};
    use crate::scene::pattern::{Checker, ColourMap, Kind, Marble, Pattern, Wood};

    fn hit(p: DVec3, uv: DVec2) -> Hit {
        Hit {
            local: p,
            uv,
            ..Hit::default()
        }
    }

    fn mapped(kind: Kind, a: Colour, b: Colour, scale: f64, turbulence: f64) -> Texture {
        Texture::Pattern(Arc::new(ColourPattern {
            pattern: Pattern {
                scale: DVec3::splat(scale),
                turbulence,
                ..Pattern::new(kind)
            },
            map: ColourMap::two(a, b),
        }))
    }

    #[test]
    fn a_checker_gives_exactly_its_two_colours_and_reads_uv() {
        let (a, b) = (Colour::new(0.9, 0.8, 0.7), Colour::new(0.1, 0.2, 0.3));
        let t = mapped(
            Kind::Checker(Checker {
                scale: DVec2::splat(2.0),
            }),
            a,
            b,
            1.0,
            0.0,
        );
        assert!(t.reads_uv());
        assert_eq!(t.colour_at(&hit(DVec3::ZERO, DVec2::new(0.1, 0.1))), a);
        assert_eq!(t.colour_at(&hit(DVec3::ZERO, DVec2::new(0.6, 0.1))), b);
    }

    #[test]
    fn marble_and_wood_stay_between_their_colours() {
        let (a, b) = (Colour::new(1.0, 0.9, 0.8), Colour::new(0.1, 0.2, 0.3));
        for t in [
            mapped(Kind::Marble(Marble), a, b, 3.0, 4.0),
            mapped(Kind::Wood(Wood), a, b, 3.0, 0.5),
        ] {
            assert!(!t.reads_uv());
            let mut seen = Vec::new();
            for i in 0..200 {
                let p = DVec3::new(
                    i as f64 * 0.037,
                    (i % 7) as f64 * 0.11,
                    (i % 13) as f64 * 0.05,
                );
                let c = t.colour_at(&hit(p, DVec2::ZERO));
                assert!(c.cmpge(b.min(a) - 1e-9).all() && c.cmple(a.max(b) + 1e-9).all());
                seen.push(c.x);
            }
            let spread = seen.iter().cloned().fold(f64::NAN, f64::max)
                - seen.iter().cloned().fold(f64::NAN, f64::min);
            assert!(spread > 0.3, "{t:?} hardly varies: {spread}");
        }
    }
}
