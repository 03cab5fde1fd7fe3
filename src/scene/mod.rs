//! Stage 2, BUILD: the typed, validated scene the renderer draws. Nothing here
//! knows about source text or spans; `build` turns the parser's AST into it
//! and reports every mistake with its place in the file.

mod build;
mod camera;
mod colour;
mod light;
mod material;
pub mod texture;

pub use build::{build, build_with, build_with_warnings, is_object};
pub use camera::{Camera, Projection};
pub use colour::{Colour, Transfer};
pub use light::Light;
pub use material::{Material, MaterialId};
pub use texture::Texture;

use crate::shapes::Shape;

/// Image size, recursion and output encoding.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Reflection bounces allowed after the primary hit.
    pub max_depth: u32,
    pub background: Colour,
    pub transfer: Transfer,
    /// Antialiasing: each pixel averages `samples × samples` rays on a
    /// regular grid (1 = one ray through the pixel's centre).
    pub samples: u32,
}

/// Most samples per pixel side (`samples 16` is 256 rays a pixel).
pub const MAX_SAMPLES: u32 = 16;

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 800,
            height: 600,
            max_depth: 5,
            background: Colour::ZERO,
            transfer: Transfer::Srgb,
            samples: 1,
        }
    }
}

/// Everything the renderer needs, in world space.
#[derive(Debug)]
pub struct Scene {
    pub camera: Camera,
    pub settings: RenderSettings,
    /// Ambient colour already multiplied by its intensity.
    pub ambient: Colour,
    pub lights: Vec<Light>,
    /// Indexed by [`MaterialId`]; index 0 is the default material.
    pub materials: Vec<Material>,
    pub objects: Vec<Box<dyn Shape>>,
}
