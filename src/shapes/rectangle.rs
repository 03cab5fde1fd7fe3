//! A parallelogram given by three corners, an open surface.
//!
//! ```text
//! rectangle { bottom_left <-1, 0, 0>  top_left <-1, 2, 0>  bottom_right <1, 0, 0>  material wall }
//! ```
//! The fourth corner is top_left + bottom_right − bottom_left. The normal is
//! (bottom_right − bottom_left) × (top_left − bottom_left), so the example
//! faces +z. Texture space: u runs from 0 to 1 along bottom_left →
//! bottom_right, v along bottom_left → top_left.

use super::{Hit, Shape, ShearedRay, barycentric_point};
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Rectangle {
    /// The corners at (u, v) = (0, 0), (1, 0), (1, 1), (0, 1): bottom left,
    /// bottom right, the fourth corner, top left.
    corners: [DVec3; 4],
    normal: DVec3,
    pub material: MaterialId,
}

impl Rectangle {
    pub fn new(
        bottom_left: DVec3,
        top_left: DVec3,
        bottom_right: DVec3,
        material: MaterialId,
    ) -> Self {
        let (u_edge, v_edge) = (bottom_right - bottom_left, top_left - bottom_left);
        let fourth = top_left + bottom_right - bottom_left;
        Rectangle {
            corners: [bottom_left, bottom_right, fourth, top_left],
            normal: u_edge.cross(v_edge).normalize_or_zero(),
            material,
        }
    }

    /// The watertight triangle test on the two halves either side of the
    /// diagonal from bottom left to the fourth corner; both halves share
    /// that diagonal exactly, so no ray slips between them. (u, v) follow
    /// from each half's barycentric weights.
    fn root(&self, ray: &Ray) -> Option<Hit> {
        let (t, half, w) = self.root_t(ray)?;
        Some(self.hit(ray, t, half, w))
    }

    /// The crossing's t, which half (0: p00 p10 p11, 1: p00 p11 p01) and
    /// its barycentric weights there, without the hit (shadow rays).
    fn root_t(&self, ray: &Ray) -> Option<(f64, usize, [f64; 3])> {
        if self.normal == DVec3::ZERO {
            return None;
        }
        let [p00, p10, p11, p01] = self.corners;
        let sheared = ShearedRay::new(ray);
        if let Some((t, w)) = sheared.triangle(p00, p10, p11) {
            return Some((t, 0, w));
        }
        let (t, w) = sheared.triangle(p00, p11, p01)?;
        Some((t, 1, w))
    }

    fn hit(&self, ray: &Ray, t: f64, half: usize, w: [f64; 3]) -> Hit {
        let [p00, p10, p11, p01] = self.corners;
        let (tri, uv) = if half == 0 {
            ([p00, p10, p11], DVec2::new(w[1] + w[2], w[2]))
        } else {
            ([p00, p11, p01], DVec2::new(w[1], w[1] + w[2]))
        };
        let (point, p_error) = barycentric_point(tri, w);
        Hit {
            t,
            normal: self.normal,
            uv,
            local: ray.at(t),
            point,
            p_error,
            geo_normal: self.normal,
            material: self.material,
            path: 0,
        }
    }
}

impl Shape for Rectangle {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let (t, half, w) = self.root_t(ray)?;
        (t > t_min && t < t_max).then(|| self.hit(ray, t, half, w))
    }

    /// Shadow rays (an area light's own rectangle is met by every one of
    /// them): the same test, no hit built.
    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.root_t(ray)
            .is_some_and(|(t, _, _)| t > t_min && t < t_max)
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        out.extend(self.root(ray));
    }

    fn bounds(&self) -> Aabb {
        let [a, b, c, d] = self.corners;
        Aabb::new(a, b).grow(c).grow(d)
    }

    fn is_solid(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::testing;

    fn wall() -> Rectangle {
        // A sheared parallelogram: the top edge is shifted by 1 in x.
        Rectangle::new(
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
            2,
        )
    }

    #[test]
    fn hit_uv_and_corners() {
        let r = wall();
        let at =
            |x: f64, y: f64| r.intersect(&Ray::new(DVec3::new(x, y, 3.0), -DVec3::Z), 0.0, 9.0);
        let h = at(2.5, 1.0).unwrap();
        assert!((h.t - 3.0).abs() < 1e-12 && h.normal == DVec3::Z && h.material == 2);
        // (2.5, 1) = 0.5·(1, 2) + 0.5·(4, 0)... u = 0.5, v = 0.5.
        assert!((h.uv - DVec2::new(0.5, 0.5)).length() < 1e-12);
        // The fourth corner (5, 2) is (1, 1).
        assert!((at(4.999, 1.999).unwrap().uv - DVec2::ONE).length() < 1e-3);
        // Beyond the slanted left edge, and beyond the top.
        assert!(at(0.2, 1.0).is_none());
        assert!(at(3.0, 2.1).is_none());
    }

    #[test]
    fn degenerate_never_hits() {
        let line = Rectangle::new(DVec3::ZERO, DVec3::X, DVec3::X * 3.0, 0);
        for r in testing::rays_towards(DVec3::X, 1.0, 200, 51) {
            assert!(line.intersect(&r, 0.0, f64::INFINITY).is_none());
        }
    }

    #[test]
    fn properties() {
        let r = Rectangle::new(
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(-1.0, 2.0, 1.0),
            DVec3::new(1.0, 0.0, 0.5),
            1,
        );
        let rays = testing::rays_towards(DVec3::new(0.0, 1.0, 0.5), 1.5, 500, 53);
        testing::check_consistency(&r, &rays);
        testing::check_no_rehit(&r, &rays);
        assert!(testing::check_normals(&r, &rays) > 50);
        assert!(testing::check_occludes_agrees(&r, &rays) > 100);
    }

    /// (u, v) are the point's coordinates along the two edges from the
    /// bottom left corner, p = bl + u·(br − bl) + v·(tl − bl), on both
    /// halves either side of the diagonal, and the hit is at that point.
    #[test]
    fn uv_are_the_edge_coordinates_on_both_halves() {
        let r = wall();
        let (bl, br, tl) = (
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
        );
        for i in 1..10 {
            for j in 1..10 {
                let (u, v) = (i as f64 * 0.1 - 0.03, j as f64 * 0.1 + 0.02);
                let p = bl + u * (br - bl) + v * (tl - bl);
                let ray = Ray::new(p + DVec3::Z * 3.0, -DVec3::Z);
                let h = r.intersect(&ray, 0.0, 9.0).unwrap();
                assert!(
                    (h.uv - DVec2::new(u, v)).length() < 1e-12,
                    "{:?} vs ({u}, {v})",
                    h.uv
                );
                assert!((h.point - p).length() < 1e-12, "{:?} vs {p:?}", h.point);
            }
        }
    }

    /// The box holds every hit and is the four corners' own box.
    #[test]
    fn bounds_hold_every_hit_and_are_tight() {
        let r = wall();
        // An open surface: not a solid for CSG.
        assert!(!r.is_solid());
        let b = r.bounds();
        assert_eq!(b, Aabb::new(DVec3::ZERO, DVec3::new(5.0, 2.0, 0.0)));
        let hits = testing::check_bounds_hold_hits(
            &r,
            &testing::rays_towards(DVec3::new(2.5, 1.0, 0.0), 1.5, 400, 41),
        );
        assert!(hits > 100, "{hits}");
    }

    /// The window is open at both ends (`t_min < t < t_max`): a hit exactly
    /// at either end is outside it, for the nearest hit and the shadow test
    /// alike (an area light's shadow ray ending on it is not blocked).
    #[test]
    fn a_hit_exactly_at_either_window_end_is_outside() {
        let r = wall();
        let ray = Ray::new(DVec3::new(2.5, 0.5, 3.0), -DVec3::Z);
        assert_eq!(r.intersect(&ray, 0.0, 9.0).map(|h| h.t), Some(3.0));
        for (lo, hi) in [(0.0, 3.0), (3.0, 9.0)] {
            assert!(r.intersect(&ray, lo, hi).is_none(), "({lo}, {hi})");
            assert!(!r.occludes(&ray, lo, hi), "({lo}, {hi})");
        }
        assert!(r.occludes(&ray, 3.0 - 1e-9, 3.0 + 1e-9));
    }
}
