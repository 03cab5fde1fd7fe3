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
}
