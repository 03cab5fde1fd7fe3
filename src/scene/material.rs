//! Materials as the scene states them: plain data, checked by the builder.
//! How each part reflects, transmits or emits light lives in
//! `render/material/`, one file per kind.
//!
//! ```text
//! material red_plastic { colour rgb(0.7, 0.05, 0.05)  diffuse 0.9  ambient 1  specular 0.6  shininess 80 }
//! material brushed     { colour #b0b0b0  mirror 0.8  mirror_colour #ffd080  glossy 500 }
//! material old_mirror  { colour white  reflect 0.7 }      // 2017: (1 − R)·local + R·reflected
//! material glass       { refract { ior 1.5  filter rgb(0.9, 1, 0.95) }  specular 1  shininess 300 }
//! material lamp        { emit rgb(1, 0.9, 0.7)  intensity 25 }
//! ```

use super::pattern::{MaterialPick, NormalPattern};
use super::{Colour, Texture};
use std::sync::Arc;

/// Index into [`super::Scene::materials`]. Shapes carry it so that a hit
/// knows its material even inside CSG (a cut shows the cutter's material).
pub type MaterialId = u32;

/// Every part is optional and additive (Suffern's model), except `reflect`,
/// the 2017 rule that mixes `(1 − R)·rest + R·reflected`.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// c_d: the diffuse (and ambient) colour.
    pub texture: Texture,
    /// R of the 2017 mix.
    pub reflect: f64,
    /// k_d: Lambert weight (no 1/π: write `diffuse kd / pi` for that).
    pub diffuse: f64,
    /// k_a: weight of the scene's ambient light.
    pub ambient: f64,
    pub phong: Option<Phong>,
    /// k_r · c_r of the additive mirror (zero: none).
    pub mirror: Colour,
    /// The exponent of a glossy lobe that replaces the perfect mirror ray.
    pub glossy: Option<f64>,
    pub refract: Option<Dielectric>,
    /// Radiance leaving the front side (colour × intensity); zero: none.
    pub emit: Colour,
    /// A material pattern: the materials it chooses shade the hit instead
    /// (see [`super::pattern::resolve`]).
    pub pick: Option<Arc<MaterialPick>>,
    /// `normal bumps { … }`: tilts the shading normal.
    pub normal: Option<Arc<NormalPattern>>,
}

/// A Phong highlight: k_s c_s (r·v)⁺^e E (n·l)⁺.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phong {
    /// k_s · c_s.
    pub colour: Colour,
    pub shininess: f64,
}

/// A transparent medium inside the surface, another outside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    pub ior: f64,
    /// Per-channel transmittance per unit length inside (Beer: filter^t).
    pub filter: Filter,
    pub outside_ior: f64,
    pub outside_filter: Filter,
}

impl Default for Dielectric {
    fn default() -> Self {
        Dielectric {
            ior: 1.5,
            filter: Filter::CLEAR,
            outside_ior: 1.0,
            outside_filter: Filter::CLEAR,
        }
    }
}

/// A medium's per-channel transmittance per unit length, f in [0, 1]³,
/// with ln f worked out once: Beer's f^s for a path of length s is then
/// e^(s·ln f), one `exp` where `powf` costs a logarithm and an `exp` again
/// for every ray through glass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter {
    per_unit: Colour,
    ln: Colour,
}

impl Filter {
    /// Lets everything through.
    pub const CLEAR: Filter = Filter {
        per_unit: Colour::ONE,
        ln: Colour::ZERO,
    };

    pub fn new(per_unit: Colour) -> Filter {
        Filter {
            per_unit,
            ln: Colour::new(per_unit.x.ln(), per_unit.y.ln(), per_unit.z.ln()),
        }
    }

    /// f, as written.
    pub fn per_unit(&self) -> Colour {
        self.per_unit
    }

    /// ln f per channel (0 for a clear channel, −∞ for an opaque one).
    pub fn ln(&self) -> Colour {
        self.ln
    }
}

impl Material {
    /// A material in the 2017 model: a colour and a reflectivity.
    pub fn matte(texture: Texture, reflect: f64) -> Material {
        Material {
            texture,
            reflect,
            ..Material::default()
        }
    }

    /// Whether it emits light (and so, on a sphere, disc or rectangle, is
    /// an area light).
    pub fn emits(&self) -> bool {
        self.emit != Colour::ZERO
    }
}

impl Default for Material {
    /// What an object without a material gets: light grey, no reflection.
    fn default() -> Self {
        Material {
            texture: Texture::Solid(Colour::splat(0.8)),
            reflect: 0.0,
            diffuse: 1.0,
            ambient: 1.0,
            phong: None,
            mirror: Colour::ZERO,
            glossy: None,
            refract: None,
            emit: Colour::ZERO,
            pick: None,
            normal: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_2017_material_keeps_its_colour_and_reflectivity_and_nothing_else() {
        let c = Colour::new(0.2, 0.4, 0.6);
        let m = Material::matte(Texture::Solid(c), 0.3);
        assert_eq!(m.texture, Texture::Solid(c));
        assert_eq!(m.reflect, 0.3);
        let rest = Material {
            texture: m.texture.clone(),
            reflect: 0.3,
            ..Material::default()
        };
        assert_eq!(m, rest);
    }

    #[test]
    fn a_filter_keeps_its_logarithm() {
        let f = Filter::new(Colour::new(1.0, 0.5, 0.0));
        assert_eq!(f.per_unit(), Colour::new(1.0, 0.5, 0.0));
        assert_eq!(f.ln(), Colour::new(0.0, 0.5f64.ln(), f64::NEG_INFINITY));
        assert_eq!(Filter::CLEAR, Filter::new(Colour::ONE));
    }
}
