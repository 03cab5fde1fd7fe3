//! The camera as the renderer uses it: a ray for a point of the image and
//! a point on the lens. The pinhole part is the course's camera
//! ([`crate::scene::Camera`]); a thin lens of radius a focused at distance f
//! starts each ray at a point of its disc (the concentric map of the lens
//! sample) and aims it where the pinhole ray meets the plane of focus, so
//! a point at distance z blurs into a circle of radius a·|1 − z/f| there.

#[cfg(target_arch = "x86_64")]
use super::sampler::concentric_disc4;
use super::sampler::{Pixel, concentric_disc};
use crate::accel::beam::RayFamily;
use crate::geometry::Ray;
use crate::scene::{Camera, PixelRays, ThinLens};

pub struct CameraRays {
    rays: PixelRays,
    lens: Option<ThinLens>,
}

impl CameraRays {
    /// `None` when the camera has no frame (the builder reports that).
    pub fn new(camera: &Camera, width: u32, height: u32) -> Option<CameraRays> {
        Some(CameraRays {
            rays: camera.pixel_rays(width, height)?,
            lens: camera.lens.filter(|l| l.aperture > 0.0),
        })
    }

    /// Whether rays need lens samples.
    pub fn has_lens(&self) -> bool {
        self.lens.is_some()
    }

    /// Every ray [`CameraRays::ray`] makes for points of `pixel` (the
    /// lens's disc inside its square), for beam culling (accel/beam.rs).
    pub fn family(&self, pixel: Pixel) -> RayFamily {
        let (origin, [right, up, forward], distance) = self.rays.frame();
        let (lo, hi) = self.rays.footprint(pixel.x, pixel.y);
        let (lens, depth) = self.lens.map_or((0.0, distance), |l| (l.aperture, l.focus));
        // Through the view plane at d, so through (r, u')·depth/d at depth.
        let at = depth / distance;
        RayFamily {
            origin,
            right,
            up,
            forward,
            lens,
            depth,
            lo: lo.map(|v| v * at),
            hi: hi.map(|v| v * at),
        }
    }

    /// Every sample's ray for `pixel`: sample i through point `spots[i]`
    /// of the pixel (in [0, 1)², from its top-left corner) and point
    /// `lens[i]` of the lens ([`CameraRays::ray`] of each), into `out`.
    /// Four at a time where the CPU has AVX (the same bits).
    pub fn rays_into(
        &self,
        pixel: Pixel,
        spots: &[(f64, f64)],
        lens: &[(f64, f64)],
        out: &mut Vec<Ray>,
    ) {
        self.rays_for((pixel.x, pixel.y), 0, spots, lens, out)
    }

    /// One ray a pixel for the pixels (x0 + k, y) of a row: pixel k's
    /// through point `spots[k]` of it and `lens[k]` of the lens, as
    /// [`CameraRays::rays_into`] would make each alone (the same bits).
    /// Made together, four neighbours' square roots and divisions overlap
    /// instead of each waiting at the head of its pixel's path.
    pub fn row_rays_into(
        &self,
        (x0, y): (u32, u32),
        spots: &[(f64, f64)],
        lens: &[(f64, f64)],
        out: &mut Vec<Ray>,
    ) {
        self.rays_for((x0, y), 1, spots, lens, out)
    }

    /// Sample k's ray through point `spots[k]` of pixel (x0 + k·step, y).
    #[inline(always)]
    fn rays_for(
        &self,
        (x0, y): (u32, u32),
        step: u32,
        spots: &[(f64, f64)],
        lens: &[(f64, f64)],
        out: &mut Vec<Ray>,
    ) {
        out.clear();
        #[cfg(target_arch = "x86_64")]
        if crate::geometry::lanes::available() {
            // SAFETY: the CPU has AVX.
            unsafe { self.rays_avx((x0, y), step, spots, lens, out) };
        }
        let done = out.len();
        out.extend(spots[done..].iter().enumerate().map(|(k, &(dx, dy))| {
            let x = x0 + (done + k) as u32 * step;
            let q = lens.get(done + k).copied().unwrap_or((0.5, 0.5));
            self.ray(x as f64 + dx, y as f64 + dy, q)
        }));
    }

    /// [`CameraRays::rays_for`] for whole fours of samples (those with
    /// lens points, when the camera has a lens), in four lanes; the rest
    /// are left to the scalar route.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn rays_avx(
        &self,
        (x0, y): (u32, u32),
        step: u32,
        spots: &[(f64, f64)],
        lens: &[(f64, f64)],
        out: &mut Vec<Ray>,
    ) {
        use std::arch::x86_64::*;
        let fours = match self.lens {
            Some(_) => spots.len().min(lens.len()),
            None => spots.len(),
        } / 4;
        let lane = |v: &[(f64, f64)], f: fn(&(f64, f64)) -> f64| {
            _mm256_set_pd(f(&v[3]), f(&v[2]), f(&v[1]), f(&v[0]))
        };
        out.resize(4 * fours, Ray::new(Default::default(), Default::default()));
        let py = _mm256_set1_pd(y as f64);
        for (k, four) in out.chunks_exact_mut(4).enumerate() {
            let s = &spots[4 * k..4 * k + 4];
            // Lane i's pixel column, a whole number (exact in f64).
            let at = |i: u32| (x0 + (4 * k as u32 + i) * step) as f64;
            let px = _mm256_set_pd(at(3), at(2), at(1), at(0));
            let x = _mm256_add_pd(px, lane(s, |p| p.0));
            let y = _mm256_add_pd(py, lane(s, |p| p.1));
            let on_lens = self.lens.map(|l| {
                let q = &lens[4 * k..4 * k + 4];
                let a = _mm256_set1_pd(l.aperture);
                let [qx, qy] = concentric_disc4(lane(q, |p| p.0), lane(q, |p| p.1));
                ([_mm256_mul_pd(qx, a), _mm256_mul_pd(qy, a)], l.focus)
            });
            self.rays.rays_at4(x, y, on_lens).store(four);
        }
    }

    /// The ray through image point (x, y) (pixel units from the top-left
    /// corner) and lens sample `lens` in [0, 1)².
    pub fn ray(&self, x: f64, y: f64, lens: (f64, f64)) -> Ray {
        match self.lens {
            None => self.rays.ray_at(x, y),
            Some(l) => {
                let (qx, qy) = concentric_disc(lens);
                self.rays
                    .lens_ray_at(x, y, (qx * l.aperture, qy * l.aperture), l.focus)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DVec3;

    /// A camera with a lens looking askew and the same without it, each
    /// also with a view plane at distance 2 (not 1: the rectangle at the
    /// focus scales by focus/distance).
    fn askew_cameras() -> [Camera; 4] {
        let lensed = Camera {
            position: DVec3::new(1.0, 2.0, 7.0),
            look_at: DVec3::new(-0.5, 0.3, 0.0),
            lens: Some(ThinLens {
                aperture: 0.3,
                focus: 6.0,
            }),
            ..Camera::default()
        };
        let far_plane = Camera {
            projection: crate::scene::Projection::ViewPlane {
                distance: 2.0,
                width: 1.5,
                height: 1.2,
            },
            ..lensed.clone()
        };
        let pinhole = |c: &Camera| Camera {
            lens: None,
            ..c.clone()
        };
        [pinhole(&lensed), pinhole(&far_plane), lensed, far_plane]
    }

    #[test]
    fn every_ray_of_a_pixel_belongs_to_the_family_its_camera_gives() {
        // Each ray starts on the lens's square and passes through the
        // pixel's rectangle at the family's depth: what the beam bounds.
        let mut rnd = crate::accel::beam::tests::rng(0x2468_ace1);
        for cam in askew_cameras() {
            let rays = CameraRays::new(&cam, 40, 30).unwrap();
            for (x, y) in [(0, 0), (39, 29), (17, 5), (3, 22)] {
                let f = rays.family(Pixel { x, y });
                let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for _ in 0..200 {
                    let (dx, dy) = (rnd(), rnd());
                    let r = rays.ray(x as f64 + dx, y as f64 + dy, (rnd(), rnd()));
                    let o = r.origin - f.origin;
                    assert!(o.dot(f.forward).abs() < 1e-12);
                    assert!(o.dot(f.right).abs() <= f.lens + 1e-12);
                    assert!(o.dot(f.up).abs() <= f.lens + 1e-12);
                    let p = r.at((f.depth - o.dot(f.forward)) / r.dir.dot(f.forward)) - f.origin;
                    for (k, axis) in [f.right, f.up].into_iter().enumerate() {
                        let v = p.dot(axis);
                        assert!(v >= f.lo[k] - 1e-9 && v <= f.hi[k] + 1e-9, "{k}: {v} {f:?}");
                        lo[k] = lo[k].min(v);
                        hi[k] = hi[k].max(v);
                    }
                }
                // And the rectangle is the pixel's, not more: the rays
                // come near each of its sides.
                for k in 0..2 {
                    let size = f.hi[k] - f.lo[k];
                    assert!(size > 0.0);
                    assert!(lo[k] - f.lo[k] < 0.05 * size && f.hi[k] - hi[k] < 0.05 * size);
                }
            }
        }
    }

    #[test]
    fn a_pixels_rays_made_together_are_each_rays_own() {
        // rays_into and row_rays_into (four lanes where the CPU has AVX,
        // a scalar tail) against `ray` one sample at a time, to the bit: lensed and
        // pinhole cameras (view planes at distance 1 and 2), every count from 1 to 9 (tails of 0 to 3),
        // and lens points on the disc map's awkward places (the centre,
        // both diagonals, the edges) in every lane.
        let mut rnd = crate::accel::beam::tests::rng(0x1357_9bdf);
        let awkward = [
            (0.5, 0.5),
            (0.25, 0.25),
            (0.75, 0.25),
            (0.0, 0.0),
            (0.0, 0.5),
            (0.5, 0.0),
            (0.125, 0.875),
            (0.9999999999, 0.5),
        ];
        for cam in askew_cameras() {
            let rays = CameraRays::new(&cam, 40, 30).unwrap();
            for count in 1..=9 {
                for round in 0..12 {
                    let pixel = Pixel {
                        x: (rnd() * 40.0) as u32,
                        y: (rnd() * 30.0) as u32,
                    };
                    let spots: Vec<(f64, f64)> = (0..count).map(|_| (rnd(), rnd())).collect();
                    let lens: Vec<(f64, f64)> = (0..count)
                        .map(|i| match (round + i) % 3 {
                            0 => awkward[(round + i) % awkward.len()],
                            _ => (rnd(), rnd()),
                        })
                        .collect();
                    // Step 0: the samples of one pixel; step 1: one sample
                    // each of the pixels along a row from `pixel`.
                    for step in [0, 1] {
                        let mut got = vec![Ray::new(DVec3::NAN, DVec3::NAN)];
                        match step {
                            0 => rays.rays_into(pixel, &spots, &lens, &mut got),
                            _ => rays.row_rays_into((pixel.x, pixel.y), &spots, &lens, &mut got),
                        }
                        assert_eq!(got.len(), count);
                        for (s, r) in got.iter().enumerate() {
                            let column = pixel.x + step * s as u32;
                            let (x, y) = (column as f64 + spots[s].0, pixel.y as f64 + spots[s].1);
                            let want = rays.ray(x, y, lens[s]);
                            for (a, b) in [(r.origin, want.origin), (r.dir, want.dir)] {
                                assert_eq!(
                                    a.to_array().map(f64::to_bits),
                                    b.to_array().map(f64::to_bits),
                                    "sample {s} of {count}, step {step}"
                                );
                            }
                        }
                    }
                }
            }
            // Fewer lens points than spots (no lens pattern): the centre.
            let spots = [(0.3, 0.6); 5];
            let mut got = Vec::new();
            rays.rays_into(Pixel { x: 3, y: 4 }, &spots, &[], &mut got);
            let want = rays.ray(3.3, 4.6, (0.5, 0.5));
            assert!(got.iter().all(|r| *r == want));
        }
    }

    #[test]
    fn thin_lens_blurs_by_the_circle_of_confusion() {
        let (a, f) = (0.2, 5.0);
        let cam = Camera {
            position: DVec3::ZERO,
            look_at: -DVec3::Z,
            lens: Some(ThinLens {
                aperture: a,
                focus: f,
            }),
            ..Camera::default()
        };
        let rays = CameraRays::new(&cam, 100, 100).unwrap();
        // Where the rays of image point (30, 60) cross the plane at depth z.
        let spread = |z: f64| {
            let pts: Vec<DVec3> = (0..64)
                .map(|k| {
                    let lens = ((k % 8) as f64 / 8.0 + 0.0625, (k / 8) as f64 / 8.0 + 0.0625);
                    let r = rays.ray(30.0, 60.0, lens);
                    r.at((-z - r.origin.z) / r.dir.z)
                })
                .collect();
            let centre = pts.iter().copied().sum::<DVec3>() / pts.len() as f64;
            pts.iter()
                .map(|p| (*p - centre).length())
                .fold(0.0, f64::max)
        };
        // Sharp at the focus distance…
        assert!(spread(f) < 1e-12, "{}", spread(f));
        // …and off it, the analytic radius a·|1 − z/f| (the concentric map
        // reaches the lens rim at the grid's outer cells only up to 7/8).
        for z in [2.5, 10.0, 20.0] {
            let want = a * (1.0 - z / f).abs() * 7.0 / 8.0;
            assert!(
                (spread(z) - want).abs() < 0.02 * want,
                "z {z}: {} vs {want}",
                spread(z)
            );
        }
        // A pinhole camera starts every ray at the eye.
        let pin = CameraRays::new(&Camera::default(), 10, 10).unwrap();
        assert!(!pin.has_lens());
        assert_eq!(
            pin.ray(3.0, 4.0, (0.1, 0.9)).origin,
            Camera::default().position
        );
    }
}
