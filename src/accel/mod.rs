//! Stage 3, ACCELERATE: the index the renderer asks for the nearest hit.
//!
//! Bounded objects go into a spatial index; unbounded ones (planes, some
//! implicit surfaces) are tested one by one beside it.

use crate::geometry::{Aabb, Ray};
use crate::shapes::{Hit, Shape};

/// Counts for `--stats`.
#[derive(Clone, Debug, Default)]
pub struct AccelStats {
    pub objects: usize,
    pub unbounded: usize,
    pub nodes: usize,
    pub build_seconds: f64,
}

/// The scene's objects, indexed for ray queries.
#[derive(Debug)]
pub struct World {
    bounded: Vec<(Aabb, Box<dyn Shape>)>,
    unbounded: Vec<Box<dyn Shape>>,
    pub stats: AccelStats,
}

impl World {
    pub fn build(objects: Vec<Box<dyn Shape>>) -> World {
        let start = std::time::Instant::now();
        let (mut bounded, mut unbounded) = (Vec::new(), Vec::new());
        for o in objects {
            let b = o.bounds();
            if b.is_finite() {
                bounded.push((b, o));
            } else {
                unbounded.push(o);
            }
        }
        let stats = AccelStats {
            objects: bounded.len() + unbounded.len(),
            unbounded: unbounded.len(),
            nodes: 0,
            build_seconds: start.elapsed().as_secs_f64(),
        };
        World {
            bounded,
            unbounded,
            stats,
        }
    }

    pub fn intersect(&self, ray: &Ray, t_min: f64, mut t_max: f64) -> Option<Hit> {
        let mut best = None;
        for o in &self.unbounded {
            if let Some(h) = o.intersect(ray, t_min, t_max) {
                t_max = h.t;
                best = Some(h);
            }
        }
        for (b, o) in &self.bounded {
            if b.clip(ray, t_min, t_max).is_none() {
                continue;
            }
            if let Some(h) = o.intersect(ray, t_min, t_max) {
                t_max = h.t;
                best = Some(h);
            }
        }
        best
    }

    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.unbounded.iter().any(|o| o.occludes(ray, t_min, t_max))
            || self
                .bounded
                .iter()
                .any(|(b, o)| b.clip(ray, t_min, t_max).is_some() && o.occludes(ray, t_min, t_max))
    }
}
