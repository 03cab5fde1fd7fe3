//! A flat disc parallel to the x-y plane, facing +z (turn it with `rotate`).
//! An open surface: not allowed in CSG.
//!
//! ```text
//! disc { centre <0, 0, 0>  radius 2  material floor  rotate x -90 }   // now facing +y
//! ```
//! Texture space: u = (x − c.x + r)/2r, v = (y − c.y + r)/2r.

use super::{Hit, Shape, ray_point_error};
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Disc {
    pub centre: DVec3,
    pub radius: f64,
    pub material: MaterialId,
}

impl Disc {
    pub fn new(centre: DVec3, radius: f64, material: MaterialId) -> Self {
        Disc {
            centre,
            radius,
            material,
        }
    }

    /// The crossing along the whole line, if any.
    fn root(&self, ray: &Ray) -> Option<Hit> {
        let t = self.root_t(ray)?;
        Some(self.hit(ray, t))
    }

    /// The crossing's t alone (shadow rays).
    fn root_t(&self, ray: &Ray) -> Option<f64> {
        if ray.dir.z == 0.0 || self.radius.is_nan() || self.radius <= 0.0 {
            return None;
        }
        let t = (self.centre.z - ray.origin.z) / ray.dir.z;
        let q = ray.at(t) - self.centre;
        let r = self.radius;
        (q.x * q.x + q.y * q.y <= r * r && t.is_finite()).then_some(t)
    }

    fn hit(&self, ray: &Ray, t: f64) -> Hit {
        let p = ray.at(t);
        let q = p - self.centre;
        let r = self.radius;
        Hit {
            t,
            normal: DVec3::Z,
            uv: DVec2::new((q.x + r) / (2.0 * r), (q.y + r) / (2.0 * r)),
            local: p,
            // Snapped into the disc's plane: exact in z, rounding elsewhere.
            point: DVec3::new(p.x, p.y, self.centre.z),
            p_error: ray_point_error(ray, t) * DVec3::new(1.0, 1.0, 0.0),
            geo_normal: DVec3::Z,
            material: self.material,
            path: 0,
        }
    }
}

impl Shape for Disc {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let t = self.root_t(ray)?;
        (t > t_min && t < t_max).then(|| self.hit(ray, t))
    }

    /// Shadow rays: the same test, no hit built.
    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.root_t(ray).is_some_and(|t| t > t_min && t < t_max)
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        out.extend(self.root(ray));
    }

    fn bounds(&self) -> Aabb {
        let e = DVec3::new(self.radius, self.radius, 0.0);
        Aabb::new(self.centre - e, self.centre + e)
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
    fn hits_uv_and_edges() {
        let d = Disc::new(DVec3::new(1.0, 2.0, 3.0), 2.0, 4);
        let h = d
            .intersect(&Ray::new(DVec3::new(2.0, 1.0, 5.0), -DVec3::Z), 0.0, 9.0)
            .unwrap();
        assert!((h.t - 2.0).abs() < 1e-12 && h.normal == DVec3::Z && h.material == 4);
        assert!((h.uv - DVec2::new(0.75, 0.25)).length() < 1e-12);
        // From behind: same outward normal (the renderer turns it).
        let h = d
            .intersect(
                &Ray::new(DVec3::new(1.0, 2.0, 0.0), DVec3::new(0.0, 0.0, 2.0)),
                0.0,
                9.0,
            )
            .unwrap();
        assert!((h.t - 1.5).abs() < 1e-12 && h.normal == DVec3::Z);
        // Just outside the rim, and parallel.
        let miss = Ray::new(DVec3::new(3.01, 2.0, 5.0), -DVec3::Z);
        assert!(d.intersect(&miss, 0.0, 9.0).is_none());
        assert!(
            d.intersect(&Ray::new(DVec3::new(1.0, 2.0, 3.0), DVec3::X), 0.0, 9.0)
                .is_none()
        );
        assert!(!d.is_solid());
        let none = Disc::new(DVec3::ZERO, 0.0, 0);
        assert!(
            none.intersect(&Ray::new(DVec3::Z, -DVec3::Z), 0.0, 9.0)
                .is_none()
        );
    }

    #[test]
    fn properties() {
        let d = Disc::new(DVec3::new(1.0, 2.0, 3.0), 2.0, 4);
        let rays = testing::rays_towards(d.centre, 2.0, 500, 31);
        testing::check_consistency(&d, &rays);
        testing::check_no_rehit(&d, &rays);
        assert!(testing::check_normals(&d, &rays) > 50);
        assert!(testing::check_occludes_agrees(&d, &rays) > 100);
    }

    /// Texture space spans the disc's bounding square whatever its radius:
    /// u = (x − c.x + r)/2r, v = (y − c.y + r)/2r, so the centre is
    /// (0.5, 0.5) and the rim's four extreme points are the square's edge
    /// midpoints.
    #[test]
    fn uv_spans_the_bounding_square_at_any_radius() {
        for r in [0.5, 3.0] {
            let d = Disc::new(DVec3::new(1.0, -2.0, 0.5), r, 0);
            for (a, b) in [(0.0, 0.0), (0.5, -0.25), (-0.999, 0.0), (0.0, 0.999)] {
                let o = d.centre + DVec3::new(a * r, b * r, 4.0);
                let h = d.intersect(&Ray::new(o, -DVec3::Z), 0.0, 9.0).unwrap();
                let want = DVec2::new((a + 1.0) / 2.0, (b + 1.0) / 2.0);
                assert!(
                    (h.uv - want).length() < 1e-12,
                    "r {r}: {:?} vs {want:?}",
                    h.uv
                );
            }
        }
    }

    /// The box holds every hit, and is the disc's own square (flat in z):
    /// a box too small would let the kd-tree skip the disc.
    #[test]
    fn bounds_hold_every_hit_and_are_tight() {
        let d = Disc::new(DVec3::new(1.0, 2.0, 3.0), 2.0, 0);
        let b = d.bounds();
        assert_eq!(
            b,
            Aabb::new(DVec3::new(-1.0, 0.0, 3.0), DVec3::new(3.0, 4.0, 3.0))
        );
        let hits =
            testing::check_bounds_hold_hits(&d, &testing::rays_towards(d.centre, 2.5, 400, 37));
        assert!(hits > 100, "{hits}");
    }

    /// The hit point is snapped into the disc's plane, exact in z (no
    /// error there), and its error in x and y is a few roundings of the
    /// ray's magnitudes, not more.
    #[test]
    fn hit_point_is_in_the_plane_with_a_rounding_sized_error() {
        let d = Disc::new(DVec3::new(0.1, -0.2, 0.7), 1.5, 0);
        for r in testing::rays_towards(d.centre, 1.5, 300, 39) {
            let Some(h) = d.intersect(&r, 0.0, f64::INFINITY) else {
                continue;
            };
            assert_eq!(h.point.z, d.centre.z);
            assert_eq!(h.p_error.z, 0.0);
            let mag = r
                .origin
                .abs()
                .max_element()
                .max(h.point.abs().max_element());
            let e = h.p_error;
            assert!(e.min_element() >= 0.0 && e.max_element() <= 64.0 * f64::EPSILON * mag);
            assert!((h.point - r.at(h.t)).truncate().abs().max_element() <= e.max_element());
        }
    }

    /// The disc is the points of its plane within r of its centre, in
    /// every direction: a grid of rays straight down hits exactly those
    /// (rays within 1e-9 of the rim are skipped), from either side.
    #[test]
    fn hits_exactly_the_points_within_the_radius() {
        let (c, r) = (DVec3::new(0.4, -1.1, 2.0), 1.3);
        let d = Disc::new(c, r, 0);
        let mut inside = 0;
        for i in -30..=30 {
            for j in -30..=30 {
                let q = DVec3::new(i as f64, j as f64, 0.0) * (r / 20.0);
                let dist = q.length();
                if (dist - r).abs() < 1e-9 {
                    continue;
                }
                for dz in [1.0, -1.0] {
                    let ray = Ray::new(c + q + DVec3::Z * 3.0 * dz, -DVec3::Z * dz);
                    let hit = d.intersect(&ray, 0.0, 9.0).is_some();
                    assert_eq!(hit, dist < r, "q {q:?} ({dist} vs r {r})");
                    inside += hit as usize;
                }
            }
        }
        assert!(inside > 1000, "{inside}");
    }

    /// The window is open at both ends (`t_min < t < t_max`): a hit
    /// exactly at either end is outside it, for the nearest hit and the
    /// shadow test alike (a shadow ray ending on the disc is not blocked).
    #[test]
    fn a_hit_exactly_at_either_window_end_is_outside() {
        let d = Disc::new(DVec3::new(0.0, 0.0, 1.0), 1.0, 0);
        let r = Ray::new(DVec3::new(0.1, 0.2, 4.0), -DVec3::Z);
        assert_eq!(d.intersect(&r, 0.0, 9.0).map(|h| h.t), Some(3.0));
        for (lo, hi) in [(0.0, 3.0), (3.0, 9.0)] {
            assert!(d.intersect(&r, lo, hi).is_none(), "({lo}, {hi})");
            assert!(!d.occludes(&r, lo, hi), "({lo}, {hi})");
        }
        assert!(d.occludes(&r, 3.0 - 1e-9, 3.0 + 1e-9));
    }
}
