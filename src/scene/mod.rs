//! Stage 2, BUILD: the typed, validated scene the renderer draws. Nothing here
//! knows about source text or spans; `build` turns the parser's AST into it
//! and reports every mistake with its place in the file.

mod build;
mod camera;
mod colour;
mod light;
mod material;
pub mod pattern;
pub mod texture;

pub use build::{
    Checked, ParamInfo, block_parameters, build, build_with, build_with_warnings,
    canonical_parameter, check, is_object, is_transform,
};
pub use camera::{Camera, PixelRays, Projection, ThinLens};
pub use colour::{Colour, Transfer};
pub use light::{AreaLight, Environment, Light, LightKind, LightSurface, Occlusion};
pub use material::{Dielectric, Filter, Material, MaterialId, Phong};
pub use texture::Texture;

use crate::shapes::Shape;

/// Image size, recursion and output encoding.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Reflection bounces allowed after the primary hit.
    pub max_depth: u32,
    /// A reflected or refracted ray whose share of the pixel (the product
    /// of the reflectivities and transmissions along its path) is below
    /// this is not traced: POV-Ray's `adc_bailout`. 0 traces every ray.
    pub bailout: f64,
    pub background: Colour,
    pub transfer: Transfer,
    /// Antialiasing: each pixel averages `samples × samples` rays (1 = one
    /// ray through the pixel's centre), or `samples × sample_rows`.
    pub samples: u32,
    /// The rows of a grid that is not square (`samples <8, 4>`: 32 rays, as
    /// POV-Ray's `blur_samples 32`); `None` is `samples` rows.
    pub sample_rows: Option<u32>,
    /// Where in the pixel (and on the lens) the samples go.
    pub sampler: SamplerKind,
    /// Changes every random number of the picture (and nothing else).
    pub seed: u64,
    /// More samples only where a pixel's first ones disagree.
    pub adaptive: Option<Adaptive>,
    /// Sub-frames averaged over an open shutter (`farm::motion`).
    pub motion_blur: Option<MotionBlur>,
    /// The acceleration structure (`render { accel }`, `--accel`).
    pub accel: crate::accel::Accel,
}

/// `render { motion_blur N  shutter S }`: the picture is the mean of N
/// sub-frames, the k-th (k = 0 … N−1) built at `frame + S·k/N` (and the
/// clock that frame number has), so the shutter opens at the frame's own
/// moment and stays open for S of a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionBlur {
    /// Sub-frames, 1 to [`MAX_MOTION_SAMPLES`] (1 = no blur).
    pub samples: u32,
    /// How long the shutter is open, in frames: 0 (exclusive) to 1.
    pub shutter: f64,
}

/// Most sub-frames of `motion_blur` (each one is a whole scene build and
/// render).
pub const MAX_MOTION_SAMPLES: u32 = 64;

/// `render { samples N  adaptive { threshold T  max_samples M } }`: a pixel
/// whose N × N samples differ by more than T in some channel (each clamped
/// to [0, 1]) is rendered again with the M × M samples `samples M` would
/// take, which replace the first ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptive {
    pub threshold: f64,
    /// Samples per side where the first ones disagree.
    pub max_samples: u32,
}

/// How a pixel's n × n samples are placed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SamplerKind {
    /// Cell centres of the n × n grid (the 2017 rule; no randomness).
    #[default]
    Regular,
    /// n² independent uniform points.
    Random,
    /// One random point in each cell of the n × n grid.
    Jittered,
    /// Jittered, and also one point per row and column of the n² × n²
    /// grid (Chiu, Shirley and Wang), shuffled.
    MultiJittered,
}

/// Most samples per pixel side (`samples 16` is 256 rays a pixel).
pub const MAX_SAMPLES: u32 = 16;

impl RenderSettings {
    /// The sample grid's columns and rows.
    pub fn grid(&self) -> (u32, u32) {
        (self.samples, self.sample_rows.unwrap_or(self.samples))
    }

    /// An n × n grid, whatever grid was set before (`--samples n`, the
    /// preview's first pass).
    pub fn set_square_grid(&mut self, n: u32) {
        self.samples = n;
        self.sample_rows = None;
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 800,
            height: 600,
            max_depth: 5,
            bailout: 0.0,
            background: Colour::ZERO,
            transfer: Transfer::Srgb,
            samples: 1,
            sample_rows: None,
            sampler: SamplerKind::Regular,
            seed: 0,
            adaptive: None,
            motion_blur: None,
            accel: crate::accel::Accel::default(),
        }
    }
}

/// Everything the renderer needs, in world space.
#[derive(Debug, Default)]
pub struct Scene {
    pub camera: Camera,
    pub settings: RenderSettings,
    /// Ambient colour already multiplied by its intensity.
    pub ambient: Colour,
    pub lights: Vec<Light>,
    /// Emissive spheres, discs and rectangles, sampled for soft shadows.
    pub area_lights: Vec<AreaLight>,
    pub environment: Option<Environment>,
    pub occlusion: Option<Occlusion>,
    /// Indexed by [`MaterialId`]; index 0 is the default material.
    pub materials: Vec<Material>,
    pub objects: Vec<Box<dyn Shape>>,
}
