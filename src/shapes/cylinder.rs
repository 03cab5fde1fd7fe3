//! A cylinder along y: an open tube, or a solid capped by two discs that may
//! carry their own materials. The geometry is the cone's frustum with equal
//! radii.
//!
//! ```text
//! cylinder { centre <0, 1, 0>  radius 0.5  height 2  material steel }            // solid
//! cylinder { radius 0.5  height 2  material steel  top red  bottom blue }       // cap materials
//! cylinder { radius 0.5  height 2  open  material glass }                       // a tube
//! ```
//! Texture space: side u = atan2(x − c.x, z − c.z)/2π wrapped to [0, 1),
//! v = (y − c.y)/h + 0.5; caps like discs in the x-z plane,
//! u = (x − c.x + r)/2r, v = (z − c.z + r)/2r.

use super::Cone;
use crate::geometry::DVec3;
use crate::scene::MaterialId;

/// A cylinder is a [`Cone`] whose radii are equal: the cone's code
/// (intersection, crossings for CSG, shadow rays, texture space) serves both.
impl Cone {
    /// `caps`: `Some([top, bottom])` for a solid cylinder, `None` for an open tube.
    pub fn cylinder(
        centre: DVec3,
        radius: f64,
        height: f64,
        side: MaterialId,
        caps: Option<[MaterialId; 2]>,
    ) -> Cone {
        Cone::new(centre, radius, radius, height, side, caps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{DVec2, Ray};
    use crate::shapes::{Hit, Shape, testing};

    fn hit(s: &dyn Shape, o: DVec3, d: DVec3) -> Option<Hit> {
        s.intersect(&Ray::new(o, d), 1e-9, f64::INFINITY)
    }

    #[test]
    fn side_caps_and_materials() {
        let c = Cone::cylinder(DVec3::new(0.0, 1.0, 0.0), 0.5, 2.0, 1, Some([2, 3]));
        let h = hit(&c, DVec3::new(0.0, 1.5, 5.0), -DVec3::Z).unwrap();
        assert!((h.t - 4.5).abs() < 1e-12 && h.normal == DVec3::Z && h.material == 1);
        // Side uv: +z is u = 0; y = 1.5 is three quarters up.
        assert!((c.uv(&h) - DVec2::new(0.0, 0.75)).length() < 1e-12);
        let h = hit(&c, DVec3::new(-5.0, 0.0, 0.0), DVec3::X).unwrap();
        assert!((c.uv(&h).x - 0.75).abs() < 1e-12);
        let h = hit(&c, DVec3::new(0.25, 5.0, 0.0), -DVec3::Y).unwrap();
        assert!((h.t - 3.0).abs() < 1e-12 && h.normal == DVec3::Y && h.material == 2);
        assert!((c.uv(&h) - DVec2::new(0.75, 0.5)).length() < 1e-12);
        let h = hit(&c, DVec3::new(0.0, -5.0, -0.25), DVec3::Y).unwrap();
        assert!((h.t - 5.0).abs() < 1e-12 && h.normal == -DVec3::Y && h.material == 3);
        assert!((c.uv(&h) - DVec2::new(0.5, 0.25)).length() < 1e-12);
        // Non-unit direction: same t parameterisation.
        let h = hit(&c, DVec3::new(0.0, 1.0, 5.0), DVec3::new(0.0, 0.0, -4.0)).unwrap();
        assert!((h.t - 1.125).abs() < 1e-12);
    }

    #[test]
    fn open_tube() {
        let c = Cone::cylinder(DVec3::ZERO, 1.0, 2.0, 1, None);
        assert!(!c.is_solid());
        assert!(hit(&c, DVec3::new(0.0, 5.0, 0.0), -DVec3::Y).is_none());
        // Slanting in through the open top, out through the wall.
        let mut xs = Vec::new();
        c.crossings(
            &Ray::new(DVec3::new(0.0, 2.0, 0.0), DVec3::new(1.0, -1.0, 0.0)),
            &mut xs,
        );
        assert_eq!(xs.len(), 1);
        assert!((xs[0].t - 1.0).abs() < 1e-12 && xs[0].normal.x > 0.0);
    }

    #[test]
    fn solid_crossings_at_rim_are_two() {
        let c = Cone::cylinder(DVec3::ZERO, 1.0, 2.0, 1, Some([2, 3]));
        // Exactly through the top rim and out of the bottom cap.
        let r = Ray::new(DVec3::new(-2.0, 2.0, 0.0), DVec3::new(1.0, -1.0, 0.0));
        let mut xs = Vec::new();
        c.crossings(&r, &mut xs);
        assert_eq!(xs.len(), 2);
        assert!((xs[0].t - 1.0).abs() < 1e-9 && (xs[1].t - 3.0).abs() < 1e-9);
    }

    #[test]
    fn degenerate_never_hits() {
        let c = Cone::cylinder(DVec3::ZERO, 0.0, 1.0, 0, Some([0, 0]));
        for r in testing::rays_towards(DVec3::ZERO, 0.5, 50, 5) {
            assert!(c.intersect(&r, 0.0, f64::INFINITY).is_none());
        }
    }

    #[test]
    fn properties() {
        let centre = DVec3::new(-1.0, 0.5, 2.0);
        let solid = Cone::cylinder(centre, 1.0, 3.0, 1, Some([2, 3]));
        let open = Cone::cylinder(centre, 1.0, 3.0, 1, None);
        for c in [&solid, &open] {
            let rays = testing::rays_towards(centre, 2.0, 500, 21);
            testing::check_consistency(c, &rays);
            testing::check_no_rehit(c, &rays);
            assert!(testing::check_normals(c, &rays) > 100);
        }
        testing::check_alternation(&solid, &testing::rays_towards(centre, 2.0, 500, 22));
    }
}
