//! The course's pinhole camera: position p, look-at q, up u, and a view
//! plane at distance z of width w and height h (world units). A field of
//! view is the same camera with distance 1 and width 2·tan(A/2), its height
//! following the pixel aspect.
//!
//! A thin lens (`aperture` = lens radius a, `focus` = distance f) moves each
//! ray's start to eye + q_x·r + q_y·u' for a point q on the lens disc and
//! aims it at the point p·f/d (camera frame) its pinhole ray would reach at
//! the focus distance, so everything at distance f along the view
//! direction stays sharp.

use crate::geometry::{DVec3, Ray};

#[derive(Clone, Debug, PartialEq)]
pub enum Projection {
    /// Horizontal field of view in degrees.
    Fov(f64),
    /// The course's view plane.
    ViewPlane {
        distance: f64,
        width: f64,
        height: f64,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    pub projection: Projection,
    /// `None`: a pinhole.
    pub lens: Option<ThinLens>,
}

/// A thin lens: radius and the distance (along the view direction) that is sharp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinLens {
    pub aperture: f64,
    pub focus: f64,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            position: DVec3::new(0.0, 0.0, 4.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            projection: Projection::Fov(60.0),
            lens: None,
        }
    }
}

/// The camera prepared for one image size: everything per pixel is a
/// multiply-add.
#[derive(Clone, Debug)]
pub struct PixelRays {
    origin: DVec3,
    /// Centre of the view plane minus half its width and plus half its height
    /// (the top-left corner), then per-pixel steps.
    corner: DVec3,
    step_right: DVec3,
    step_down: DVec3,
    /// The unit frame vectors l, r and u', and the view-plane distance d.
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    distance: f64,
}

impl Camera {
    /// The orthonormal frame (view direction l, right r, up u'), or `None`
    /// when position = look-at or up is parallel to the view direction.
    pub fn frame(&self) -> Option<(DVec3, DVec3, DVec3)> {
        let l = (self.look_at - self.position).try_normalize()?;
        let r = l.cross(self.up).try_normalize()?;
        let u = r.cross(l);
        Some((l, r, u))
    }

    /// The view plane's distance, width and height for an image of `px_w` by
    /// `px_h` pixels.
    pub fn view_plane(&self, px_w: u32, px_h: u32) -> (f64, f64, f64) {
        match self.projection {
            Projection::Fov(a) => {
                let w = 2.0 * (a.to_radians() / 2.0).tan();
                (1.0, w, w * px_h as f64 / px_w as f64)
            }
            Projection::ViewPlane {
                distance,
                width,
                height,
            } => (distance, width, height),
        }
    }

    pub fn pixel_rays(&self, px_w: u32, px_h: u32) -> Option<PixelRays> {
        let (l, r, u) = self.frame()?;
        let (z, w, h) = self.view_plane(px_w, px_h);
        let centre = self.position + z * l;
        let step_right = r * (w / px_w as f64);
        let step_down = -u * (h / px_h as f64);
        Some(PixelRays {
            origin: self.position,
            corner: centre - r * (w / 2.0) + u * (h / 2.0),
            step_right,
            step_down,
            forward: l,
            right: r,
            up: u,
            distance: z,
        })
    }
}

impl PixelRays {
    /// The ray through the centre of pixel (column a, row b), row 0 at the top.
    pub fn ray(&self, a: u32, b: u32) -> Ray {
        self.ray_at(a as f64 + 0.5, b as f64 + 0.5)
    }

    /// The ray through a point of the image, in pixel units from the
    /// top-left corner.
    pub fn ray_at(&self, x: f64, y: f64) -> Ray {
        let p = self.corner + x * self.step_right + y * self.step_down;
        Ray::new(self.origin, (p - self.origin).normalize())
    }

    /// The eye, the unit frame (r, u', l) and the view plane's distance d.
    pub fn frame(&self) -> (DVec3, [DVec3; 3], f64) {
        (
            self.origin,
            [self.right, self.up, self.forward],
            self.distance,
        )
    }

    /// Where the view plane's pixel (column a, row b) lies, as (r, u')
    /// coordinates about the eye: the least and the greatest of each.
    pub fn footprint(&self, a: u32, b: u32) -> ([f64; 2], [f64; 2]) {
        let c = self.corner - self.origin;
        let x = |k: u32| c.dot(self.right) + k as f64 * self.step_right.dot(self.right);
        let y = |k: u32| c.dot(self.up) + k as f64 * self.step_down.dot(self.up);
        let (x0, x1) = (x(a), x(a + 1));
        let (y0, y1) = (y(b), y(b + 1));
        ([x0.min(x1), y0.min(y1)], [x0.max(x1), y0.max(y1)])
    }

    /// The thin-lens ray through image point (x, y) from lens point
    /// (q_x, q_y) (world units in the lens plane): it starts at
    /// eye + q_x·r + q_y·u' and passes through the pinhole ray's point at
    /// the focus distance, eye + (p − eye)·f/d.
    pub fn lens_ray_at(&self, x: f64, y: f64, q: (f64, f64), focus: f64) -> Ray {
        let p = self.corner + x * self.step_right + y * self.step_down;
        let sharp = self.origin + (p - self.origin) * (focus / self.distance);
        let start = self.origin + q.0 * self.right + q.1 * self.up;
        Ray::new(start, (sharp - start).normalize())
    }

    /// [`PixelRays::ray_at`] (`lens` None) or [`PixelRays::lens_ray_at`]
    /// (`lens` the points q and the focus) for four image points, a lane
    /// each, with their operations in their order: each lane has the
    /// scalar ray's bits.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    #[inline]
    pub(crate) fn rays_at4(
        &self,
        x: std::arch::x86_64::__m256d,
        y: std::arch::x86_64::__m256d,
        lens: Option<([std::arch::x86_64::__m256d; 2], f64)>,
    ) -> crate::geometry::lanes::Rays {
        use std::arch::x86_64::*;
        let (add, sub, mul, k) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd, _mm256_set1_pd);
        let lanes = |v: DVec3| v.to_array().map(|c| k(c));
        let (eye, corner) = (lanes(self.origin), lanes(self.corner));
        let (step_right, step_down) = (lanes(self.step_right), lanes(self.step_down));
        let p: [__m256d; 3] = std::array::from_fn(|i| {
            add(add(corner[i], mul(x, step_right[i])), mul(y, step_down[i]))
        });
        let (start, d) = match lens {
            None => (eye, std::array::from_fn(|i| sub(p[i], eye[i]))),
            Some(([qx, qy], focus)) => {
                let f = k(focus / self.distance);
                let (right, up) = (lanes(self.right), lanes(self.up));
                let start: [__m256d; 3] =
                    std::array::from_fn(|i| add(add(eye[i], mul(qx, right[i])), mul(qy, up[i])));
                let sharp: [__m256d; 3] =
                    std::array::from_fn(|i| add(eye[i], mul(sub(p[i], eye[i]), f)));
                (start, std::array::from_fn(|i| sub(sharp[i], start[i])))
            }
        };
        // glam's normalize: d · (1 / √((x² + y²) + z²)).
        let r = _mm256_div_pd(k(1.0), _mm256_sqrt_pd(crate::geometry::lanes::dot(d, d)));
        crate::geometry::lanes::Rays {
            ox: start[0],
            oy: start[1],
            oz: start[2],
            dx: mul(d[0], r),
            dy: mul(d[1], r),
            dz: mul(d[2], r),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn course_orientation() {
        // At <0,0,4> looking at the origin: +x right, +y up.
        let cam = Camera {
            projection: Projection::ViewPlane {
                distance: 1.0,
                width: 2.0,
                height: 2.0,
            },
            ..Camera::default()
        };
        let px = cam.pixel_rays(100, 100).unwrap();
        let right = px.ray(99, 50);
        assert!(right.dir.x > 0.0);
        let top = px.ray(50, 0);
        assert!(top.dir.y > 0.0);
        let c = px.ray(50, 50).dir;
        assert!(c.z < -0.99);
    }

    #[test]
    fn fov_width() {
        let cam = Camera {
            projection: Projection::Fov(90.0),
            ..Camera::default()
        };
        let (z, w, h) = cam.view_plane(200, 100);
        assert!((z - 1.0).abs() < 1e-12 && (w - 2.0).abs() < 1e-12 && (h - 1.0).abs() < 1e-12);
    }

    #[test]
    fn degenerate_frames_are_refused() {
        let cam = Camera {
            up: DVec3::new(0.0, 0.0, 1.0),
            ..Camera::default()
        };
        assert!(cam.frame().is_none());
    }
}
