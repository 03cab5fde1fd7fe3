//! Stage 4, RENDER: one room per concept, as in pbrt-v4.
//!
//! - `camera`: the ray for an image point and a lens point (pinhole, thin lens);
//! - `sampler`: where samples fall, and every random number, as pure
//!   functions of (pixel, sample, dimension, seed);
//! - `material/`: what each kind of material reflects, transmits and emits;
//! - `light/`: what each kind of light sends to a point;
//! - `integrator`: the Whitted recursion that asks materials and lights;
//! - `film`: the pixels.
//!
//! Each pixel's colour depends only on its own samples, so the image is
//! the same for any number of threads.

mod camera;
mod film;
mod integrator;
pub mod light;
pub mod material;
pub mod sampler;
mod stats;

pub use film::Film;
pub use stats::RenderStats;

use crate::accel::World;
use crate::scene::{Colour, Scene};
use camera::CameraRays;
use integrator::{Integrator, Path};
use rayon::prelude::*;
use sampler::{Pixel, PixelSampler, SampleStream};
use std::sync::atomic::{AtomicU64, Ordering};

/// What the caller wants to see while rendering.
pub struct RenderOptions<'a> {
    /// Called with the number of finished rows (from worker threads).
    pub progress: Option<&'a (dyn Fn(u64) + Sync)>,
}

/// The dimensions of a sample that place it in the pixel and on the lens.
const PIXEL_DIM: u32 = 0;
const LENS_DIM: u32 = 2;

/// Renders the scene at `scene.settings` size. Fails only when the camera
/// has no frame (which the builder already reports), so it returns `None`
/// then.
pub fn render(scene: &Scene, world: &World, opts: &RenderOptions) -> Option<(Film, RenderStats)> {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let camera = CameraRays::new(&scene.camera, w, h)?;
    let integrator = Integrator::new(scene, world);
    // Each pixel averages n × n samples; the regular sampler puts them at
    // the cell centres (the 2017 rule, the same picture on every run).
    let sampler = PixelSampler {
        kind: scene.settings.sampler,
        n: scene.settings.samples.clamp(1, crate::scene::MAX_SAMPLES),
        seed: scene.settings.seed,
    };
    let weight = 1.0 / sampler.count() as f64;
    let start = std::time::Instant::now();
    let done = AtomicU64::new(0);
    let rows: Vec<(Vec<[f32; 3]>, stats::RayCounts)> = (0..h)
        .into_par_iter()
        .map(|b| {
            let mut counts = stats::RayCounts::default();
            let (mut spots, mut lens) = (Vec::new(), Vec::new());
            let row = (0..w)
                .map(|a| {
                    let pixel = Pixel { x: a, y: b };
                    sampler.pattern(pixel, PIXEL_DIM, &mut spots);
                    if camera.has_lens() {
                        sampler.pattern(pixel, LENS_DIM, &mut lens);
                    }
                    let mut sum = Colour::ZERO;
                    for (s, &(dx, dy)) in spots.iter().enumerate() {
                        let q = lens.get(s).copied().unwrap_or((0.5, 0.5));
                        let ray = camera.ray(a as f64 + dx, b as f64 + dy, q);
                        let mut path = Path {
                            stream: SampleStream::new(pixel, s as u32, sampler.seed),
                            counts: &mut counts,
                        };
                        sum += integrator.trace(&ray, 0, &mut path);
                    }
                    let c = if spots.len() == 1 { sum } else { sum * weight };
                    [c.x as f32, c.y as f32, c.z as f32]
                })
                .collect();
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(p) = opts.progress {
                p(n);
            }
            (row, counts)
        })
        .collect();
    let mut counts = stats::RayCounts::default();
    let mut pixels = Vec::with_capacity((w * h) as usize);
    for (row, c) in rows {
        pixels.extend(row);
        counts.add(&c);
    }
    let stats = RenderStats {
        seconds: start.elapsed().as_secs_f64(),
        rays: counts,
    };
    Some((Film::new(w, h, pixels), stats))
}
