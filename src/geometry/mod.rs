//! Shared maths for every stage after the parser: rays, hits, bounding boxes
//! and affine transforms. Everything is `f64` (glam's `DVec3`).

mod aabb;
mod ray;
mod transform;

pub use aabb::Aabb;
pub use glam::{DMat3, DMat4, DVec2, DVec3};
pub use ray::Ray;
pub use transform::Transform;

/// How far secondary rays start from the surface they leave, relative to the
/// size of the coordinates (an absolute epsilon fails far from the origin).
pub fn surface_epsilon(p: DVec3) -> f64 {
    1e-7 * (1.0 + p.abs().max_element())
}
