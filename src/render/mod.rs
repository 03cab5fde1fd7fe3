//! Stage 4, RENDER: one room per concept, as in pbrt-v4.
//!
//! - `camera`: the ray for an image point and a lens point (pinhole, thin lens);
//! - `sampler`: where samples fall, and every random number, as pure
//!   functions of (pixel, sample, dimension, seed);
//! - `material/`: what each kind of material reflects, transmits and emits;
//! - `light/`: what each kind of light sends to a point;
//! - `integrator`: the Whitted recursion that asks materials and lights;
//! - `adaptive`: which pixels get more samples;
//! - `film`: the pixels.
//!
//! Each pixel's colour depends only on its own samples, so the image is
//! the same for any number of threads, and a region of it ([`render_region`])
//! is exactly those pixels of the full picture.

mod adaptive;
mod camera;
mod film;
mod integrator;
pub mod light;
pub mod material;
pub mod sampler;
mod stats;

pub use film::Film;
pub use stats::{RayCounts, RenderStats};

use crate::accel::World;
use crate::scene::{Colour, Scene};
use crate::shapes::{Hit, Shape};
use camera::CameraRays;
use integrator::{Integrator, Path};
use rayon::prelude::*;
use sampler::{Pixel, PixelKey, PixelSampler, SampleStream};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// What the caller wants to see while rendering.
pub struct RenderOptions<'a> {
    /// Called with the number of finished rows (from worker threads).
    pub progress: Option<&'a (dyn Fn(u64) + Sync)>,
    /// Set from another thread to give the render up (`--watch` when the
    /// scene changes mid-render): rows not yet started are skipped and the
    /// render returns `None`.
    pub cancel: Option<&'a AtomicBool>,
}

impl RenderOptions<'_> {
    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

/// The dimensions of a sample that place it in the pixel and on the lens.
const PIXEL_DIM: u32 = 0;
const LENS_DIM: u32 = 2;
/// A pixel with at least this many camera rays finds their first hits
/// through one beam (accel/beam.rs): with fewer, building it costs more
/// than the walks it saves.
const BEAM_RAYS: usize = 4;
/// With at least this many, the pixel's shadow rays to each light are
/// tested only against what lies between the light and the pixel's hits:
/// finding that costs a few hundred instructions more a pixel.
const LIGHT_SHAFT_RAYS: usize = 16;
/// Pictures of one sample a pixel make this many neighbours' camera rays
/// at a time (two fours of lanes).
const ROW_RAYS: usize = 8;

/// A rectangle of the picture, in the full picture's pixel coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Region {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// Renders the scene at `scene.settings` size. Fails only when the camera
/// has no frame (which the builder already reports), so it returns `None`
/// then.
pub fn render(scene: &Scene, world: &World, opts: &RenderOptions) -> Option<(Film, RenderStats)> {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let all = Region {
        x: 0,
        y: 0,
        width: w,
        height: h,
    };
    render_region(scene, world, opts, all)
}

/// Renders the pixels of `region` (clipped to the picture) exactly as the
/// full picture has them: every sample is a pure function of its pixel's
/// place in the full picture. `None` when the camera has no frame, the
/// region holds no pixel, or `opts.cancel` was set.
pub fn render_region(
    scene: &Scene,
    world: &World,
    opts: &RenderOptions,
    region: Region,
) -> Option<(Film, RenderStats)> {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let x1 = region.x.saturating_add(region.width).min(w);
    let y1 = region.y.saturating_add(region.height).min(h);
    if region.x >= x1 || region.y >= y1 {
        return None;
    }
    let camera = CameraRays::new(&scene.camera, w, h)?;
    let integrator = Integrator::new(scene, world);
    // Each pixel averages n × m samples; the regular sampler puts them at
    // the cell centres (the 2017 rule, the same picture on every run).
    let (n, rows) = scene.settings.grid();
    let sampler = PixelSampler {
        kind: scene.settings.sampler,
        n: n.clamp(1, crate::scene::MAX_SAMPLES),
        rows: rows.clamp(1, crate::scene::MAX_SAMPLES),
        seed: scene.settings.seed,
    };
    // Refining takes M × M samples where the first ones (at least two)
    // disagree: only where that is more.
    let refine = scene.settings.adaptive.and_then(|a| {
        let m = a.max_samples.min(crate::scene::MAX_SAMPLES);
        (m * m > sampler.count() && sampler.count() > 1).then(|| adaptive::Refine {
            threshold: a.threshold,
            sampler: PixelSampler::square(sampler.kind, m, sampler.seed),
        })
    });
    let pixels = PixelRenderer {
        camera: &camera,
        integrator: &integrator,
        keep_colours: refine.is_some(),
    };
    let start = std::time::Instant::now();
    let done = AtomicU64::new(0);
    // Each row is written where it stays in the film (rather than
    // collected and copied: 12 MB at 1000 × 1000).
    let width = (x1 - region.x) as usize;
    let mut film = vec![[0f32; 3]; width * (y1 - region.y) as usize];
    let row_counts: Vec<stats::RayCounts> = film
        .par_chunks_mut(width)
        .zip(region.y..y1)
        .map(|(row, b)| {
            let mut counts = stats::RayCounts::default();
            if opts.cancelled() {
                return counts;
            }
            let mut scratch = Scratch::default();
            // One sample a pixel (never refined: that needs two): a few
            // neighbours' camera rays at a time.
            if sampler.count() == 1 {
                let mut colours = [Colour::ZERO; ROW_RAYS];
                let starts = (region.x..x1).step_by(ROW_RAYS);
                for (outs, a) in row.chunks_mut(ROW_RAYS).zip(starts) {
                    let colours = &mut colours[..outs.len()];
                    pixels.render_row((a, b), &sampler, &mut scratch, &mut counts, colours);
                    for (out, c) in outs.iter_mut().zip(colours) {
                        *out = [c.x as f32, c.y as f32, c.z as f32];
                    }
                }
            } else {
                for (out, a) in row.iter_mut().zip(region.x..x1) {
                    let pixel = Pixel { x: a, y: b };
                    let first = pixels.render(pixel, &sampler, &mut scratch, &mut counts);
                    let c = match &refine {
                        Some(r) if r.disagree(&scratch.colours) => {
                            counts.refined += 1;
                            pixels.render(pixel, &r.sampler, &mut scratch, &mut counts)
                        }
                        _ => first,
                    };
                    *out = [c.x as f32, c.y as f32, c.z as f32];
                }
            }
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(p) = opts.progress {
                p(n);
            }
            counts
        })
        .collect();
    if opts.cancelled() {
        return None;
    }
    let mut counts = stats::RayCounts::default();
    for c in &row_counts {
        counts.add(c);
    }
    let stats = RenderStats {
        seconds: start.elapsed().as_secs_f64(),
        rays: counts,
    };
    Some((Film::new(x1 - region.x, y1 - region.y, film), stats))
}

/// A pixel's buffers, kept between pixels of a row.
#[derive(Default)]
struct Scratch<'w> {
    spots: Vec<(f64, f64)>,
    lens: Vec<(f64, f64)>,
    /// The sampler's hashes.
    hashes: Vec<u64>,
    /// Each sample's camera ray, and its first hit and the object hit.
    rays: Vec<crate::geometry::Ray>,
    hits: Vec<Hit>,
    objects: Vec<Option<&'w dyn Shape>>,
    /// What finding them all at once keeps.
    first: crate::accel::FirstHits,
    /// Per light, what may block the shadow rays from the pixel's hits.
    lights: Vec<Option<crate::accel::Blockers>>,
    /// Each sample's colour, for the adaptive test.
    colours: Vec<Colour>,
    /// A few neighbours' points in their pixels and on the lens, and their
    /// camera rays ([`PixelRenderer::render_row`]).
    row_spots: Vec<(f64, f64)>,
    row_lens: Vec<(f64, f64)>,
    row_rays: Vec<crate::geometry::Ray>,
}

/// One pixel's samples through the camera and the integrator.
struct PixelRenderer<'a> {
    camera: &'a CameraRays,
    integrator: &'a Integrator<'a>,
    /// Whether each sample's colour is kept for the adaptive test. Only
    /// then: the copy read the colour back 16 bytes at a time just after
    /// `shade_hit` had stored it 8 at a time (a stalled store-to-load
    /// forward at every sample), where adding it up reads 8 at a time.
    keep_colours: bool,
}

impl<'a> PixelRenderer<'a> {
    /// The mean of `sampler`'s samples of `pixel` (each one kept in
    /// `scratch.colours` when the adaptive test wants them).
    fn render(
        &self,
        pixel: Pixel,
        sampler: &PixelSampler,
        scratch: &mut Scratch<'a>,
        counts: &mut stats::RayCounts,
    ) -> Colour {
        self.points(pixel, sampler, scratch);
        // Every camera ray first, then every path: the rays are independent
        // of each other, so their square roots and divisions overlap in the
        // pipeline instead of each waiting at the head of its own path.
        self.camera
            .rays_into(pixel, &scratch.spots, &scratch.lens, &mut scratch.rays);
        self.trace(pixel, sampler, scratch, counts)
    }

    /// `pixel`'s points in the pixel and, with a lens, on the lens: into
    /// `scratch.spots` and `scratch.lens` (left empty without one).
    #[inline(always)]
    fn points(&self, pixel: Pixel, sampler: &PixelSampler, scratch: &mut Scratch<'a>) {
        sampler.pattern_with(pixel, PIXEL_DIM, &mut scratch.spots, &mut scratch.hashes);
        scratch.lens.clear();
        if self.camera.has_lens() {
            sampler.pattern_with(pixel, LENS_DIM, &mut scratch.lens, &mut scratch.hashes);
        }
    }

    /// [`PixelRenderer::render`] for pictures of one sample a pixel, the
    /// pixels (x0 + k, y) of a row into `out[k]`: their camera rays made
    /// together first ([`CameraRays::row_rays_into`]), then each traced
    /// alone. The same colours as `render` of each.
    fn render_row(
        &self,
        (x0, y): (u32, u32),
        sampler: &PixelSampler,
        scratch: &mut Scratch<'a>,
        counts: &mut stats::RayCounts,
        out: &mut [Colour],
    ) {
        debug_assert_eq!(sampler.count(), 1);
        scratch.row_spots.clear();
        scratch.row_lens.clear();
        if sampler.kind == crate::scene::SamplerKind::Regular {
            // A regular pattern does not depend on the pixel (its one
            // point is the centre, the 2017 rule): asked once for the
            // row's pixels, not a million times.
            self.points(Pixel { x: x0, y }, sampler, scratch);
            scratch.row_spots.resize(out.len(), scratch.spots[0]);
            if let Some(&q) = scratch.lens.first() {
                scratch.row_lens.resize(out.len(), q);
            }
        } else {
            for k in 0..out.len() as u32 {
                self.points(Pixel { x: x0 + k, y }, sampler, scratch);
                scratch.row_spots.push(scratch.spots[0]);
                if let Some(&q) = scratch.lens.first() {
                    scratch.row_lens.push(q);
                }
            }
        }
        let mut rays = std::mem::take(&mut scratch.row_rays);
        self.camera
            .row_rays_into((x0, y), &scratch.row_spots, &scratch.row_lens, &mut rays);
        for (k, (ray, c)) in rays.iter().zip(out).enumerate() {
            scratch.rays.clear();
            scratch.rays.push(*ray);
            *c = self.trace(
                Pixel {
                    x: x0 + k as u32,
                    y,
                },
                sampler,
                scratch,
                counts,
            );
        }
        scratch.row_rays = rays;
    }

    /// The mean of the paths of the camera rays in `scratch.rays`, the
    /// samples of `pixel`. Inlined in both callers: a colour handed back
    /// in memory is read back before its stores have landed (a stalled
    /// store-to-load forward, a quarter of an empty picture's time).
    #[inline(always)]
    fn trace(
        &self,
        pixel: Pixel,
        sampler: &PixelSampler,
        scratch: &mut Scratch<'a>,
        counts: &mut stats::RayCounts,
    ) -> Colour {
        scratch.colours.clear();
        let key = PixelKey::new(pixel, sampler.seed);
        let mut sum = Colour::ZERO;
        fn path(key: PixelKey, s: usize, counts: &mut stats::RayCounts) -> Path<'_> {
            Path {
                stream: SampleStream::new(key, s as u32),
                counts,
                weight: 1.0,
            }
        }
        let n = scratch.rays.len();
        // Many rays a pixel: their first hits are looked for among the few
        // objects their beam meets, not by a walk of the tree each.
        let among = (n >= BEAM_RAYS)
            .then(|| {
                self.integrator
                    .world()
                    .beam_candidates(&self.camera.family(pixel))
            })
            .flatten();
        // Each sample's colour, summed (and kept for the adaptive test)
        // where it arrives.
        let keep = self.keep_colours;
        let colours = &mut scratch.colours;
        let mut take = |c: Colour| {
            sum += c;
            if keep {
                colours.push(c);
            }
        };
        if n < LIGHT_SHAFT_RAYS {
            for (s, ray) in scratch.rays.iter().enumerate() {
                let path = &mut path(key, s, counts);
                match &among {
                    None => take(self.integrator.trace(ray, 0, path)),
                    Some(objects) => {
                        let mut hit = Hit::default();
                        let found = self.integrator.first_hit(ray, Some(objects), &mut hit);
                        let found = found.map(|o| (&mut hit, o));
                        self.integrator
                            .shade_first(ray, found, true, &[], path, &mut take)
                    }
                }
            }
        } else {
            // More still: every first hit is found before any is shaded,
            // so that the shadow rays to each light need only be tested
            // against what may lie between the light and those hits.
            // Each hit is written where it stays (a hit is 160 bytes).
            scratch.hits.resize(n, Hit::default());
            scratch.objects.clear();
            match &among {
                Some(objects) => self.integrator.world().first_hits(
                    objects,
                    &scratch.rays,
                    &mut scratch.hits,
                    &mut scratch.objects,
                    &mut scratch.first,
                ),
                None => {
                    for (ray, hit) in scratch.rays.iter().zip(&mut scratch.hits) {
                        let object = self.integrator.first_hit(ray, None, hit);
                        scratch.objects.push(object);
                    }
                }
            }
            let mut points = crate::geometry::Aabb::EMPTY;
            for (hit, object) in scratch.hits.iter().zip(&scratch.objects) {
                if object.is_some() {
                    // Wide enough for the shading point's offset too.
                    let pad = crate::geometry::DVec3::splat(4.0 * hit.p_error.max_element());
                    points.min = points.min.min(hit.point - pad);
                    points.max = points.max.max(hit.point + pad);
                }
            }
            self.integrator.light_blockers(&points, &mut scratch.lights);
            for (s, ray) in scratch.rays.iter().enumerate() {
                let found = scratch.objects[s].map(|o| (&mut scratch.hits[s], o));
                self.integrator.shade_first(
                    ray,
                    found,
                    among.is_some(),
                    &scratch.lights,
                    &mut path(key, s, counts),
                    &mut take,
                );
            }
        }
        if scratch.rays.len() == 1 {
            sum
        } else {
            sum * (1.0 / sampler.count() as f64)
        }
    }
}
