//! The course's Whitted shading:
//!
//! ```text
//! local = c ⊙ (ambient + Σ visible lights: colour · intensity · max(0, n·l))
//! pixel = (1 − R)·local + R·reflected
//! ```
//! Surfaces are two-sided: the geometric normal is turned towards the ray,
//! and the shading normal into the geometric normal's hemisphere. Shadow
//! and reflection rays start from the hit point moved off the surface by
//! its error bound (`offset_ray_origin`, see docs/architecture.md,
//! "Rounding error and ray offsets"), so they neither re-hit the surface
//! nor leak through it at any scale.

use super::stats::RayCounts;
use crate::accel::World;
use crate::geometry::rounding::reflect;
use crate::geometry::{Ray, offset_ray_origin, shadow_ray_to, valid_reflection_normal};
use crate::scene::{Colour, Scene};

pub struct Tracer<'a> {
    scene: &'a Scene,
    world: &'a World,
}

impl<'a> Tracer<'a> {
    pub fn new(scene: &'a Scene, world: &'a World) -> Self {
        Tracer { scene, world }
    }

    /// Colour seen along `ray` (unit direction), after `depth` bounces.
    pub fn trace(&self, ray: &Ray, depth: u32, counts: &mut RayCounts) -> Colour {
        if depth == 0 {
            counts.primary += 1;
        } else {
            counts.reflected += 1;
        }
        let Some((mut hit, object)) = self.world.nearest(ray, 0.0, f64::INFINITY) else {
            return self.scene.settings.background;
        };
        let material = &self.scene.materials[hit.material as usize];
        if material.texture.reads_uv() {
            hit.uv = object.uv(&hit);
        }
        let (p, p_err) = (hit.point, hit.p_error);
        // The geometric normal decides the side; the shading normal is kept
        // in its hemisphere.
        let mut ng = hit.geo_normal.normalize_or_zero();
        if ng.dot(ray.dir) > 0.0 {
            ng = -ng;
        }
        let mut n = hit.normal.normalize_or(ng);
        if n.dot(ng) < 0.0 {
            n = -n;
        }

        let mut light = self.scene.ambient;
        for l in &self.scene.lights {
            let (origin, dir, reach) = shadow_ray_to(p, p_err, ng, l.position);
            let cos = n.dot(dir);
            if cos <= 0.0 {
                continue;
            }
            counts.shadow += 1;
            if !self.world.occludes(&Ray::new(origin, dir), 0.0, reach) {
                light += l.colour * cos;
            }
        }
        let local = material.texture.colour_at(&hit) * light;
        let r = material.reflect;
        if r <= 0.0 {
            return local;
        }
        let reflected = if depth < self.scene.settings.max_depth {
            let out = reflect(ray.dir, valid_reflection_normal(ng, -ray.dir, n));
            let origin = offset_ray_origin(p, p_err, ng, out);
            self.trace(&Ray::new(origin, out), depth + 1, counts)
        } else {
            Colour::ZERO
        };
        (1.0 - r) * local + r * reflected
    }
}
