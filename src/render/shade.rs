//! The course's Whitted shading:
//!
//! ```text
//! local = c ⊙ (ambient + Σ visible lights: colour · intensity · max(0, n·l))
//! pixel = (1 − R)·local + R·reflected
//! ```
//! Surfaces are two-sided (the normal is turned towards the ray); shadow and
//! reflection rays start a small epsilon off the surface on the side the
//! ray came from, so they neither re-hit the surface nor leak through it.

use super::stats::RayCounts;
use crate::accel::World;
use crate::geometry::{Ray, surface_epsilon};
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
        let p = ray.at(hit.t);
        let mut n = hit.normal.normalize_or_zero();
        if n.dot(ray.dir) > 0.0 {
            n = -n;
        }
        let lifted = p + n * surface_epsilon(p);

        let mut light = self.scene.ambient;
        for l in &self.scene.lights {
            let to_light = l.position - lifted;
            let dist = to_light.length();
            let dir = to_light / dist;
            let cos = n.dot(dir);
            if cos <= 0.0 {
                continue;
            }
            counts.shadow += 1;
            if !self.world.occludes(&Ray::new(lifted, dir), 0.0, dist) {
                light += l.colour * cos;
            }
        }
        let local = material.texture.colour_at(&hit) * light;
        let r = material.reflect;
        if r <= 0.0 {
            return local;
        }
        let reflected = if depth < self.scene.settings.max_depth {
            let out = ray.dir - 2.0 * ray.dir.dot(n) * n;
            self.trace(&Ray::new(lifted, out), depth + 1, counts)
        } else {
            Colour::ZERO
        };
        (1.0 - r) * local + r * reflected
    }
}
