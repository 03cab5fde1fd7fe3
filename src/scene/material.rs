use super::{Colour, Texture};

/// Index into [`super::Scene::materials`]. Shapes carry it so that a hit
/// knows its material even inside CSG (a cut shows the cutter's material).
pub type MaterialId = u32;

/// The course's material: a colour (or texture) and a reflectivity R that
/// mixes `(1 − R)·local + R·reflected`.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub texture: Texture,
    pub reflect: f64,
}

impl Default for Material {
    /// What an object without a material gets: light grey, no reflection.
    fn default() -> Self {
        Material {
            texture: Texture::Solid(Colour::splat(0.8)),
            reflect: 0.0,
        }
    }
}
