//! Area lights: emissive spheres, discs and rectangles, sampled on their
//! surface. For a point y on the light (drawn uniformly over its area A;
//! discs through the concentric map) the light arriving at x is
//!
//! ```text
//! L_e · (n_y·(−l))⁺ / |x − y|² · A       (l the unit direction x → y)
//! ```
//! which the integrator weighs by k_d c (n·l)⁺ and one shadow ray to y:
//! area lights fall off with distance squared, unlike point lights. With
//! no `samples` each pixel sample draws one point (the course's way; the
//! noise averages out over the pixel's samples); `samples n` on the object
//! gives it its own n × n grid of cell centres per shading point (POV-Ray's
//! `area_light`, no randomness).
//!
//! ```text
//! material lamp { emit white  intensity 4 }
//! rectangle { bottom_left <-1, 6, 0>  top_left <-1, 6, 2>  bottom_right <1, 6, 0>  material lamp  samples 8 }
//! ```

use super::LightSample;
use crate::geometry::DVec3;
use crate::render::sampler::concentric_disc;
use crate::scene::{AreaLight, LightSurface};

/// A point on the surface for the square sample `u`, with the surface's
/// unit outward normal there.
pub fn point_on(s: &LightSurface, u: (f64, f64)) -> (DVec3, DVec3) {
    match s {
        LightSurface::Sphere { centre, radius } => {
            let z = 1.0 - 2.0 * u.0;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f64::consts::TAU * u.1;
            let n = DVec3::new(r * phi.cos(), r * phi.sin(), z);
            (*centre + *radius * n, n)
        }
        LightSurface::Disc {
            centre,
            normal,
            u: eu,
            v: ev,
            ..
        } => {
            let (x, y) = concentric_disc(u);
            (*centre + x * *eu + y * *ev, *normal)
        }
        LightSurface::Rectangle {
            corner,
            edge_u,
            edge_v,
        } => (
            *corner + u.0 * *edge_u + u.1 * *edge_v,
            edge_u.cross(*edge_v).normalize(),
        ),
    }
}

/// The surface's area.
pub fn area(s: &LightSurface) -> f64 {
    match s {
        LightSurface::Sphere { radius, .. } => 4.0 * std::f64::consts::PI * radius * radius,
        LightSurface::Disc { u, v, .. } => std::f64::consts::PI * u.cross(*v).length(),
        LightSurface::Rectangle { edge_u, edge_v, .. } => edge_u.cross(*edge_v).length(),
    }
}

/// The light from the point of `light` at square sample `u`, as seen from
/// `from`; `None` when that point faces away.
pub fn sample(light: &AreaLight, from: DVec3, u: (f64, f64)) -> Option<LightSample> {
    let (y, ny) = point_on(&light.surface, u);
    let to = y - from;
    let d2 = to.length_squared();
    let dist = d2.sqrt();
    let dir = to / dist;
    let mut cos_y = -ny.dot(dir);
    if light.two_sided {
        cos_y = cos_y.abs();
    }
    if cos_y <= 0.0 || d2 == 0.0 {
        return None;
    }
    Some(LightSample {
        dir,
        // Stop short of the light's own surface, which y lies on.
        dist: dist * (1.0 - 1e-9),
        radiance: light.emit * (cos_y / d2 * area(&light.surface)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Colour;

    #[test]
    fn points_lie_on_the_surface() {
        let s = LightSurface::Sphere {
            centre: DVec3::new(1.0, 2.0, 3.0),
            radius: 0.5,
        };
        for i in 0..10 {
            let (p, n) = point_on(&s, (i as f64 / 10.0, 0.37));
            assert!(((p - DVec3::new(1.0, 2.0, 3.0)).length() - 0.5).abs() < 1e-12);
            assert!((n.length() - 1.0).abs() < 1e-12);
        }
        let d = LightSurface::Disc {
            centre: DVec3::ZERO,
            normal: DVec3::Z,
            u: DVec3::X * 2.0,
            v: DVec3::Y * 2.0,
            radius: 2.0,
        };
        assert!((area(&d) - 4.0 * std::f64::consts::PI).abs() < 1e-12);
        let (p, _) = point_on(&d, (0.99, 0.5));
        assert!(p.length() <= 2.0 + 1e-12);
    }

    #[test]
    fn a_small_far_light_gives_the_inverse_square_irradiance() {
        // A 0.01 × 0.01 square of radiance 1 facing down, 5 above: L·A/r².
        let light = AreaLight {
            surface: LightSurface::Rectangle {
                corner: DVec3::new(-0.005, 5.0, -0.005),
                edge_u: DVec3::new(0.01, 0.0, 0.0),
                edge_v: DVec3::new(0.0, 0.0, 0.01),
            },
            emit: Colour::ONE,
            samples: None,
            two_sided: false,
        };
        let s = sample(&light, DVec3::ZERO, (0.5, 0.5)).unwrap();
        assert!(
            (s.radiance.x - 1e-4 / 25.0).abs() < 1e-12,
            "{}",
            s.radiance.x
        );
        assert!((s.dir - DVec3::Y).length() < 1e-12);
        // Seen from the back it sends nothing.
        assert!(sample(&light, DVec3::new(0.0, 10.0, 0.0), (0.5, 0.5)).is_none());
        // Twice as far, a quarter.
        let far = sample(&light, DVec3::new(0.0, -5.0, 0.0), (0.5, 0.5)).unwrap();
        assert!((far.dist - 10.0).abs() < 1e-6);
        assert!((far.radiance.x * 4.0 - s.radiance.x).abs() < 1e-15);
    }
}
