//! One shape placed many times: an object value (`let wheel = union { … }`)
//! is built once, and each placement (`wheel { translate <2, 0, 0> }`) is a
//! [`Shared`] handle on it under its own [`super::Transformed`]. Every
//! method forwards to the shared shape.

use super::{Crossing, Hit, Shape};
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use std::sync::Arc;

#[derive(Debug, Clone)]
pub struct Shared(pub Arc<dyn Shape>);

impl Shape for Shared {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        self.0.intersect(ray, t_min, t_max)
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.0.occludes(ray, t_min, t_max)
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        self.0.crossings(ray, out)
    }

    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        self.0.crossings_lite(ray, out)
    }

    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        self.0.hit_of(ray, c)
    }

    fn bounds(&self) -> Aabb {
        self.0.bounds()
    }

    fn is_solid(&self) -> bool {
        self.0.is_solid()
    }

    fn encloses(&self, p: DVec3) -> bool {
        self.0.encloses(p)
    }

    fn uv(&self, hit: &Hit) -> DVec2 {
        self.0.uv(hit)
    }

    fn normal_to_world(&self, hit: &Hit, v: DVec3) -> DVec3 {
        self.0.normal_to_world(hit, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Transform;
    use crate::shapes::{Sphere, Transformed};

    #[test]
    fn placements_of_one_shape_answer_as_copies_would() {
        let ball: Arc<dyn Shape> = Arc::new(Sphere::new(DVec3::ZERO, 1.0, 0));
        let xf = Transform::translate(DVec3::new(3.0, 0.0, 0.0));
        let shared = Transformed::new(Box::new(Shared(ball.clone())), xf);
        let copy = Transformed::new(Box::new(Sphere::new(DVec3::ZERO, 1.0, 0)), xf);
        let ray = Ray::new(DVec3::new(3.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0));
        let (a, b) = (
            shared.intersect(&ray, 0.0, 1e9),
            copy.intersect(&ray, 0.0, 1e9),
        );
        assert_eq!(a.map(|h| (h.t, h.normal)), b.map(|h| (h.t, h.normal)));
        assert_eq!(a.map(|h| h.t), Some(4.0));
        assert_eq!(shared.bounds(), copy.bounds());
        assert!(shared.is_solid());
        assert_eq!(Arc::strong_count(&ball), 2);
    }

    #[test]
    fn every_query_on_a_placement_is_the_shared_shapes_own() {
        // An open shape (a disc) and a solid one (a sphere), each asked
        // through a Shared handle and directly: every method agrees.
        let shapes: [Arc<dyn Shape>; 3] = [
            Arc::new(Sphere::new(DVec3::ZERO, 1.0, 0)),
            Arc::new(crate::shapes::Disc::new(DVec3::ZERO, 1.0, 0)),
            // Unbounded: the one kind that answers `encloses` (for CSG).
            Arc::new(crate::shapes::Plane::new(
                DVec3::new(0.0, 0.0, 1.0),
                0.15,
                0,
            )),
        ];
        let plane = Shared(shapes[2].clone());
        assert!(plane.encloses(DVec3::ZERO) && !plane.encloses(DVec3::Z));
        for shape in shapes {
            let shared = Shared(shape.clone());
            assert_eq!(shared.is_solid(), shape.is_solid());
            for p in [
                DVec3::ZERO,
                DVec3::new(0.3, 0.2, 0.1),
                DVec3::new(2.0, 0.0, 0.0),
            ] {
                assert_eq!(shared.encloses(p), shape.encloses(p), "{p}");
            }

            for (o, d) in [
                (DVec3::new(0.2, 0.1, 5.0), -DVec3::Z),
                (DVec3::new(0.2, 0.1, -5.0), DVec3::Z),
                (DVec3::new(3.0, 0.0, 5.0), -DVec3::Z),
            ] {
                let ray = Ray::new(o, d);
                for reach in [2.0, 9.0] {
                    assert_eq!(
                        shared.occludes(&ray, 0.0, reach),
                        shape.occludes(&ray, 0.0, reach)
                    );
                }
                let (mut a, mut b) = (Vec::new(), Vec::new());
                shared.crossings(&ray, &mut a);
                shape.crossings(&ray, &mut b);
                let key = |h: &Vec<Hit>| h.iter().map(|h| (h.t, h.normal)).collect::<Vec<_>>();
                assert_eq!(key(&a), key(&b));
                let (mut ca, mut cb) = (Vec::new(), Vec::new());
                shared.crossings_lite(&ray, &mut ca);
                shape.crossings_lite(&ray, &mut cb);
                assert_eq!(ca.len(), cb.len());
                for (x, y) in ca.iter().zip(&cb) {
                    assert_eq!(x.t, y.t);
                    let (hx, hy) = (shared.hit_of(&ray, x), shape.hit_of(&ray, y));
                    assert_eq!((hx.t, hx.normal, hx.point), (hy.t, hy.normal, hy.point));
                }
                for h in &b {
                    assert_eq!(shared.uv(h), shape.uv(h));
                }
                if o.x == 0.2 {
                    assert!(!b.is_empty() && !cb.is_empty() && shape.occludes(&ray, 0.0, 9.0));
                }
            }
        }
    }
}
