//! Textures: what colour a material has at a hit.
//!
//! Surface patterns (`checker`, `image`) read the hit's (u, v); solid
//! patterns (`checker3d`, `marble`, `wood`) read the hit's point in the
//! object's own space, so every texture moves with its object.
//!
//! ```text
//! material floor { colour checker   { a white  b rgb(0.2, 0.2, 0.2)  scale 4 } }
//! material tiles { colour checker3d { a white  b black  size 0.5 } }
//! material earth { colour image "earth.png" { scale <1, 1>  offset <0, 0>  swap  flip_u  flip_v } }
//! material stone { colour marble    { a white  b rgb(0.1, 0.1, 0.3)  scale 2  turbulence 4 } }
//! material oak   { colour wood      { a #c8a060  b #704018  scale 6  turbulence 0.5 } }
//! ```

mod image_map;
mod noise;

pub use image_map::{ImageError, ImageTexture, UvMapping};

use super::Colour;
use crate::geometry::DVec3;
use crate::shapes::Hit;
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    Solid(Colour),
    /// The course's checker on (u, v): with f(s) = k·s for s ≥ 0 and
    /// 1 − k·s otherwise, `a` where ⌊f(u)⌋ + ⌊f(v)⌋ is even.
    Checker {
        a: Colour,
        b: Colour,
        scale: f64,
    },
    /// Cubes of side `size` in object space; the one at [0, size)³ is `a`.
    Checker3d {
        a: Colour,
        b: Colour,
        size: f64,
    },
    Image(Arc<ImageTexture>),
    /// Veins of `b` through `a` along x, disturbed by turbulence.
    Marble {
        a: Colour,
        b: Colour,
        scale: f64,
        turbulence: f64,
    },
    /// Rings around the y axis, disturbed by turbulence.
    Wood {
        a: Colour,
        b: Colour,
        scale: f64,
        turbulence: f64,
    },
}

/// Cell borders are nudged by this fraction of a cell so that a floor at
/// y = 0 (whose hits land at ±1e-17) does not speckle between two cells.
const CELL_NUDGE: f64 = 1e-6;

fn course_checker_coordinate(s: f64, k: f64) -> i64 {
    let f = if s >= 0.0 { k * s } else { 1.0 - k * s };
    (f + CELL_NUDGE).floor() as i64
}

impl Texture {
    /// Whether the texture reads the hit's (u, v), which some shapes
    /// compute only on request ([`crate::shapes::Shape::uv`]).
    pub fn reads_uv(&self) -> bool {
        matches!(self, Texture::Checker { .. } | Texture::Image(_))
    }

    pub fn colour_at(&self, hit: &Hit) -> Colour {
        match self {
            Texture::Solid(c) => *c,
            Texture::Checker { a, b, scale } => {
                let i = course_checker_coordinate(hit.uv.x, *scale)
                    + course_checker_coordinate(hit.uv.y, *scale);
                if i.rem_euclid(2) == 0 { *a } else { *b }
            }
            Texture::Checker3d { a, b, size } => {
                let c = (hit.local / *size + DVec3::splat(CELL_NUDGE)).floor();
                let i = c.x as i64 + c.y as i64 + c.z as i64;
                if i.rem_euclid(2) == 0 { *a } else { *b }
            }
            Texture::Image(img) => img.sample(hit.uv),
            Texture::Marble {
                a,
                b,
                scale,
                turbulence,
            } => {
                let p = hit.local * *scale;
                let s = (p.x + turbulence * noise::turbulence(p, 6)).sin();
                let t = (0.5 + 0.5 * s).powf(0.6);
                a.lerp(*b, 1.0 - t)
            }
            Texture::Wood {
                a,
                b,
                scale,
                turbulence,
            } => {
                let p = hit.local * *scale;
                let r = (p.x * p.x + p.z * p.z).sqrt() + turbulence * noise::turbulence(p, 4);
                let ring = r - r.floor();
                // Sharp dark late-wood edge, wide light early-wood.
                let t = ring.powf(3.0);
                a.lerp(*b, t)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DVec2;

    fn hit_uv(u: f64, v: f64) -> Hit {
        Hit {
            t: 1.0,
            normal: DVec3::Z,
            uv: DVec2::new(u, v),
            local: DVec3::ZERO,
            material: 0,
            path: 0,
            ..Hit::default()
        }
    }

    fn hit_at(p: DVec3) -> Hit {
        Hit {
            local: p,
            ..hit_uv(0.0, 0.0)
        }
    }

    #[test]
    fn course_checker_cells() {
        let (a, b) = (Colour::ONE, Colour::ZERO);
        let t = Texture::Checker { a, b, scale: 2.0 };
        assert_eq!(t.colour_at(&hit_uv(0.1, 0.1)), a);
        assert_eq!(t.colour_at(&hit_uv(0.6, 0.1)), b);
        assert_eq!(t.colour_at(&hit_uv(0.6, 0.6)), a);
        // Negative side: f(s) = 1 − k·s, so (−0.1) gives 1.2 → cell 1.
        assert_eq!(t.colour_at(&hit_uv(-0.1, 0.1)), b);
    }

    #[test]
    fn solid_checker_is_light_at_the_origin_cell_and_stable_on_borders() {
        let (a, b) = (Colour::ONE, Colour::ZERO);
        let t = Texture::Checker3d { a, b, size: 1.0 };
        assert_eq!(t.colour_at(&hit_at(DVec3::new(0.5, 0.5, 0.5))), a);
        assert_eq!(t.colour_at(&hit_at(DVec3::new(1.5, 0.5, 0.5))), b);
        // A floor at y = 0 hit a hair below zero stays in the same cell.
        assert_eq!(
            t.colour_at(&hit_at(DVec3::new(0.5, -1e-15, 0.5))),
            t.colour_at(&hit_at(DVec3::new(0.5, 1e-15, 0.5)))
        );
    }

    #[test]
    fn marble_and_wood_stay_between_their_colours() {
        let (a, b) = (Colour::new(1.0, 0.9, 0.8), Colour::new(0.1, 0.2, 0.3));
        for t in [
            Texture::Marble {
                a,
                b,
                scale: 3.0,
                turbulence: 4.0,
            },
            Texture::Wood {
                a,
                b,
                scale: 3.0,
                turbulence: 0.5,
            },
        ] {
            let mut seen = Vec::new();
            for i in 0..200 {
                let p = DVec3::new(
                    i as f64 * 0.037,
                    (i % 7) as f64 * 0.11,
                    (i % 13) as f64 * 0.05,
                );
                let c = t.colour_at(&hit_at(p));
                assert!(c.cmpge(b.min(a) - 1e-9).all() && c.cmple(a.max(b) + 1e-9).all());
                seen.push(c.x);
            }
            let spread = seen.iter().cloned().fold(f64::NAN, f64::max)
                - seen.iter().cloned().fold(f64::NAN, f64::min);
            assert!(spread > 0.3, "{t:?} hardly varies: {spread}");
        }
    }
}
