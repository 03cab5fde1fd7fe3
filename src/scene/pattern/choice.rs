//! Material patterns: a pattern choosing whole materials at each hit.
//!
//! ```text
//! material tiles { checker { a marble_white  b { colour black  mirror 0.8 }  scale <8, 8> } }
//! material camo  { noise { material_map { 0 olive  0.45 sand  0.6 moss }  scale 3 } }
//! ```
//!
//! The value picks a band, never a blend: each key starts its material's
//! band, so `a`/`b` are the map `{ 0 a  0.5 b }` (a checker's 0 and 1 are
//! `a` and `b`). Each chosen material keeps all its parts (reflection,
//! glass, highlights, its own colour pattern and normal), and may itself be
//! a material pattern. [`resolve`] is the one place a hit's material is
//! looked up for shading.

use super::Pattern;
use crate::geometry::DVec2;
use crate::scene::{Material, MaterialId};
use crate::shapes::Hit;

#[derive(Clone, Debug, PartialEq)]
pub struct MaterialPick {
    pub pattern: Pattern,
    /// (key, material), sorted by key, at least one.
    pub bands: Vec<(f64, MaterialId)>,
}

/// Nested material patterns deeper than this stop (the builder only lets a
/// pattern choose materials made before it, so nesting is finite anyway).
const MAX_NESTING: usize = 64;

impl MaterialPick {
    pub fn choose(&self, value: f64) -> MaterialId {
        let i = self.bands.partition_point(|(k, _)| *k <= value);
        self.bands[i.saturating_sub(1)].1
    }
}

impl Material {
    /// Whether shading it reads the hit's (u, v), which some shapes
    /// compute only on request ([`crate::shapes::Shape::uv`]).
    pub fn reads_uv(&self) -> bool {
        self.texture.reads_uv() || self.pick.as_ref().is_some_and(|p| p.pattern.reads_uv())
    }
}

/// The material that shades `hit`: its own, or what its material patterns
/// choose at the hit. Fills `hit.uv` through `uv` when something reads it.
pub fn resolve<'m>(
    materials: &'m [Material],
    hit: &mut Hit,
    uv: impl Fn(&Hit) -> DVec2,
) -> &'m Material {
    let mut m = &materials[hit.material as usize];
    let mut have_uv = false;
    for _ in 0..MAX_NESTING {
        if !have_uv && m.reads_uv() {
            hit.uv = uv(hit);
            have_uv = true;
        }
        match &m.pick {
            Some(pick) => {
                let v = pick.pattern.value(hit.local, hit.uv);
                m = &materials[pick.choose(v) as usize];
            }
            None => return m,
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::super::{Checker, Kind};
    use super::*;
    use crate::geometry::DVec3;
    use crate::scene::{Colour, Texture};
    use std::sync::Arc;

    #[test]
    fn bands_start_at_their_keys() {
        let p = MaterialPick {
            pattern: Pattern::new(Kind::Checker(Checker { scale: DVec2::ONE })),
            bands: vec![(0.0, 1), (0.5, 2), (0.8, 3)],
        };
        assert_eq!(p.choose(0.0), 1);
        assert_eq!(p.choose(0.49), 1);
        assert_eq!(p.choose(0.5), 2);
        assert_eq!(p.choose(1.0), 3);
        assert_eq!(p.choose(-1.0), 1);
    }

    #[test]
    fn resolve_follows_the_checker_and_reads_uv_once() {
        let matte = |c| Material::matte(Texture::Solid(Colour::splat(c)), 0.0);
        let pick = Material {
            pick: Some(Arc::new(MaterialPick {
                pattern: Pattern::new(Kind::Checker(Checker { scale: DVec2::ONE })),
                bands: vec![(0.0, 1), (0.5, 2)],
            })),
            ..Material::default()
        };
        let materials = [Material::default(), matte(0.1), matte(0.9), pick];
        let calls = std::cell::Cell::new(0);
        let mut hit = Hit {
            material: 3,
            local: DVec3::ZERO,
            ..Hit::default()
        };
        let at = |u: f64, hit: &mut Hit| {
            let m = resolve(&materials, hit, |_| {
                calls.set(calls.get() + 1);
                DVec2::new(u, 0.5)
            });
            m.texture.clone()
        };
        assert_eq!(at(0.5, &mut hit), Texture::Solid(Colour::splat(0.1)));
        assert_eq!(at(1.5, &mut hit), Texture::Solid(Colour::splat(0.9)));
        assert_eq!(calls.get(), 2, "once per resolve");
    }

    /// (u, v) is computed only when something reads it, and once per
    /// resolve: not for a plain material, nor for a pick by a solid
    /// pattern of plain materials; once for a uv pick whose chosen
    /// material reads uv too (a checker colour).
    #[test]
    fn uv_is_read_only_when_needed_and_once() {
        use super::super::{ColourMap, ColourPattern, Gradient};
        let plain = Material::matte(Texture::Solid(Colour::splat(0.5)), 0.0);
        let checker = Pattern::new(Kind::Checker(Checker { scale: DVec2::ONE }));
        let striped = Material::matte(
            Texture::Pattern(Arc::new(ColourPattern {
                pattern: checker.clone(),
                map: ColourMap::two(Colour::ZERO, Colour::ONE),
            })),
            0.0,
        );
        let solid_pick = Material {
            pick: Some(Arc::new(MaterialPick {
                pattern: Pattern::new(Kind::Gradient(Gradient {
                    axis: DVec3::X,
                    mirror: false,
                })),
                bands: vec![(0.0, 0)],
            })),
            ..Material::default()
        };
        let uv_pick = Material {
            pick: Some(Arc::new(MaterialPick {
                pattern: checker,
                bands: vec![(0.0, 1)],
            })),
            ..Material::default()
        };
        assert!(!plain.reads_uv());
        assert!(striped.reads_uv());
        assert!(!solid_pick.reads_uv());
        assert!(uv_pick.reads_uv());
        let materials = [plain, striped, solid_pick, uv_pick];
        for (start, calls_wanted, chosen) in [(0, 0, 0), (2, 0, 0), (1, 1, 1), (3, 1, 1)] {
            let calls = std::cell::Cell::new(0);
            let mut hit = Hit {
                material: start,
                local: DVec3::new(0.3, 0.0, 0.0),
                ..Hit::default()
            };
            let m = resolve(&materials, &mut hit, |_| {
                calls.set(calls.get() + 1);
                DVec2::new(0.25, 0.25)
            });
            assert_eq!(calls.get(), calls_wanted, "from material {start}");
            assert_eq!(m, &materials[chosen], "from material {start}");
        }
    }
}
