//! Shared maths for every stage after the parser: rays, hits, bounding boxes
//! and affine transforms. Everything is `f64` (glam's `DVec3`).

mod aabb;
mod ray;
pub mod rounding;
mod transform;

pub use aabb::Aabb;
pub use glam::{DMat3, DMat4, DVec2, DVec3};
pub use ray::Ray;
pub use rounding::{offset_along_unit, offset_ray_origin, shadow_ray_to, valid_reflection_normal};
pub use transform::Transform;

/// The old fixed offset, relative to the size of the coordinates. It does
/// not follow a hit's own rounding error (see [`offset_ray_origin`]), and
/// no renderer path uses it any more.
pub fn surface_epsilon(p: DVec3) -> f64 {
    1e-7 * (1.0 + p.abs().max_element())
}
