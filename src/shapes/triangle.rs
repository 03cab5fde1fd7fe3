//! A single triangle (the watertight test, [`ShearedRay`]), an open surface.
//!
//! ```text
//! triangle { a <0, 0, 0>  b <1, 0, 0>  c <0, 1, 0>  material red }
//! ```
//! The normal is (b − a) × (c − a): counter-clockwise points face the
//! viewer. Texture space: barycentric, u the weight of b and v of c (so a is
//! (0, 0), b is (1, 0), c is (0, 1)).

use super::{Hit, Shape, ShearedRay, barycentric_point};
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Triangle {
    /// The corners a, b, c as given (kept, not as edges, so that a
    /// triangle sharing an edge with another meets it exactly).
    corners: [DVec3; 3],
    normal: DVec3,
    pub material: MaterialId,
}

impl Triangle {
    pub fn new(a: DVec3, b: DVec3, c: DVec3, material: MaterialId) -> Self {
        Triangle {
            corners: [a, b, c],
            normal: (b - a).cross(c - a).normalize_or_zero(),
            material,
        }
    }

    /// The watertight test along the whole line. A zero-area triangle is
    /// never hit.
    fn root(&self, ray: &Ray) -> Option<Hit> {
        let (t, w) = self.root_t(ray)?;
        Some(self.hit(ray, t, w))
    }

    /// The hit at the crossing `root_t` found.
    fn hit(&self, ray: &Ray, t: f64, w: [f64; 3]) -> Hit {
        let (point, p_error) = barycentric_point(self.corners, w);
        Hit {
            t,
            normal: self.normal,
            uv: DVec2::new(w[1], w[2]),
            local: ray.at(t),
            point,
            p_error,
            geo_normal: self.normal,
            material: self.material,
            path: 0,
        }
    }
}

impl Triangle {
    /// The crossing's t and barycentric weights, without the hit.
    fn root_t(&self, ray: &Ray) -> Option<(f64, [f64; 3])> {
        if self.normal == DVec3::ZERO {
            return None;
        }
        let [a, b, c] = self.corners;
        ShearedRay::new(ray).triangle(a, b, c)
    }
}

impl Shape for Triangle {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let (t, w) = self.root_t(ray)?;
        (t > t_min && t < t_max).then(|| self.hit(ray, t, w))
    }

    /// Shadow rays: the same test, no hit built.
    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.root_t(ray)
            .is_some_and(|(t, _)| t > t_min && t < t_max)
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        out.extend(self.root(ray));
    }

    fn bounds(&self) -> Aabb {
        let [a, b, c] = self.corners;
        Aabb::new(a, b).grow(c)
    }

    fn is_solid(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::testing;

    #[test]
    fn hit_normal_and_barycentric_uv() {
        let tri = Triangle::new(DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 2.0, 3);
        let h = tri
            .intersect(&Ray::new(DVec3::new(0.5, 0.5, 2.0), -DVec3::Z), 0.0, 9.0)
            .unwrap();
        assert!((h.t - 2.0).abs() < 1e-12 && h.normal == DVec3::Z && h.material == 3);
        assert!((h.uv - DVec2::new(0.25, 0.25)).length() < 1e-12);
        // The corners are (0,0), (1,0), (0,1).
        let at = |x: f64, y: f64| {
            tri.intersect(&Ray::new(DVec3::new(x, y, 1.0), -DVec3::Z), 0.0, 9.0)
                .unwrap()
                .uv
        };
        assert!((at(2.0, 0.0) - DVec2::X).length() < 1e-12);
        assert!((at(0.0, 2.0) - DVec2::Y).length() < 1e-12);
        // Outside the hypotenuse.
        let miss = Ray::new(DVec3::new(1.1, 1.0, 1.0), -DVec3::Z);
        assert!(tri.intersect(&miss, 0.0, 9.0).is_none());
        // Clockwise winding faces the other way.
        let back = Triangle::new(DVec3::ZERO, DVec3::Y, DVec3::X, 0);
        let h = back
            .intersect(&Ray::new(DVec3::new(0.2, 0.2, 1.0), -DVec3::Z), 0.0, 9.0)
            .unwrap();
        assert_eq!(h.normal, -DVec3::Z);
    }

    #[test]
    fn degenerate_never_hits() {
        let line = Triangle::new(DVec3::ZERO, DVec3::X, DVec3::X * 2.0, 0);
        let point = Triangle::new(DVec3::ONE, DVec3::ONE, DVec3::ONE, 0);
        for r in testing::rays_towards(DVec3::X, 1.0, 200, 41) {
            assert!(line.intersect(&r, 0.0, f64::INFINITY).is_none());
            assert!(point.intersect(&r, 0.0, f64::INFINITY).is_none());
        }
    }

    #[test]
    fn properties() {
        let tri = Triangle::new(
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(-1.0, 2.0, 0.5),
            DVec3::new(0.0, -1.0, 2.0),
            1,
        );
        let rays = testing::rays_towards(DVec3::new(0.0, 0.3, 0.8), 1.0, 500, 43);
        testing::check_consistency(&tri, &rays);
        testing::check_no_rehit(&tri, &rays);
        assert!(testing::check_normals(&tri, &rays) > 50);
        assert!(testing::check_occludes_agrees(&tri, &rays) > 100);
    }

    #[test]
    fn the_interval_is_open_at_both_ends() {
        // `t_min < t < t_max`: a ray starting exactly on the triangle with
        // t_min = 0 does not meet it again at t = 0 (no self-shadowing),
        // and a triangle exactly at t_max is beyond the reach.
        let tri = Triangle::new(DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 2.0, 0);
        let on = Ray::new(DVec3::new(0.5, 0.25, 0.0), DVec3::Z);
        assert_eq!(tri.root_t(&on).map(|(t, _)| t), Some(0.0));
        assert!(tri.intersect(&on, 0.0, 9.0).is_none());
        assert!(!tri.occludes(&on, 0.0, 9.0));
        let above = Ray::new(DVec3::new(0.5, 0.25, 2.0), -DVec3::Z);
        assert_eq!(tri.root_t(&above).map(|(t, _)| t), Some(2.0));
        assert!(tri.intersect(&above, 0.0, 2.0).is_none());
        assert!(!tri.occludes(&above, 0.0, 2.0));
        assert!(tri.intersect(&above, 0.0, 2.0f64.next_up()).is_some());
        assert!(tri.occludes(&above, 0.0, 2.0f64.next_up()));
        // An open surface: it has no inside for CSG to use.
        assert!(!tri.is_solid());
    }
}
