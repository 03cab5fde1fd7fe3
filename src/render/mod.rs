//! Stage 4, RENDER: the course's Whitted model, traced in parallel over rows.
//!
//! Each pixel's colour depends only on its own rays, so the image is the
//! same for any number of threads.

mod film;
mod shade;
mod stats;

pub use film::Film;
pub use stats::RenderStats;

use crate::accel::World;
use crate::scene::Scene;
use rayon::prelude::*;
use shade::Tracer;
use std::sync::atomic::{AtomicU64, Ordering};

/// What the caller wants to see while rendering.
pub struct RenderOptions<'a> {
    /// Called with the number of finished rows (from worker threads).
    pub progress: Option<&'a (dyn Fn(u64) + Sync)>,
}

/// Renders the scene at `scene.settings` size. Fails only when the camera
/// has no frame (which the builder already reports), so it returns `None`
/// then.
pub fn render(scene: &Scene, world: &World, opts: &RenderOptions) -> Option<(Film, RenderStats)> {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let rays = scene.camera.pixel_rays(w, h)?;
    let tracer = Tracer::new(scene, world);
    // Antialiasing: an n × n grid of sub-pixel rays, averaged. A regular
    // grid (not random jitter) keeps the picture the same on every run.
    let n = scene.settings.samples.max(1);
    let weight = 1.0 / (n * n) as f64;
    let start = std::time::Instant::now();
    let done = AtomicU64::new(0);
    let rows: Vec<(Vec<[f32; 3]>, stats::RayCounts)> = (0..h)
        .into_par_iter()
        .map(|b| {
            let mut counts = stats::RayCounts::default();
            let row = (0..w)
                .map(|a| {
                    let c = if n == 1 {
                        tracer.trace(&rays.ray(a, b), 0, &mut counts)
                    } else {
                        let mut sum = crate::scene::Colour::ZERO;
                        for j in 0..n {
                            for i in 0..n {
                                let x = a as f64 + (i as f64 + 0.5) / n as f64;
                                let y = b as f64 + (j as f64 + 0.5) / n as f64;
                                sum += tracer.trace(&rays.ray_at(x, y), 0, &mut counts);
                            }
                        }
                        sum * weight
                    };
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
