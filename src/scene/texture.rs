//! Textures: what colour a material has at a hit.

use super::Colour;
use crate::shapes::Hit;

#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    Solid(Colour),
}

impl Texture {
    pub fn colour_at(&self, _hit: &Hit) -> Colour {
        match self {
            Texture::Solid(c) => *c,
        }
    }
}
