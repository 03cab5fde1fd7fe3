//! Shared maths for every stage after the parser: rays, hits, bounding boxes
//! and affine transforms. Everything is `f64` (glam's `DVec3`).

mod aabb;
#[cfg(target_arch = "x86_64")]
pub(crate) mod lanes;
mod ray;
pub mod rounding;
mod transform;

pub use aabb::Aabb;
pub use glam::{DMat3, DMat4, DVec2, DVec3};
pub use ray::Ray;
pub use rounding::{
    normalize_near_unit, offset_along_unit, offset_ray_origin, offset_towards, renormalize,
    shadow_ray_to, valid_reflection_normal,
};
pub use transform::Transform;

#[cfg(test)]
mod tests {
    use super::*;

    /// `origin + t·dir`, with a direction that is not unit length.
    #[test]
    fn a_ray_at_t() {
        let r = Ray::new(DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.5, -2.0, 4.0));
        assert_eq!(r.at(0.0), DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(r.at(2.0), DVec3::new(2.0, -2.0, 11.0));
        assert_eq!(r.at(-1.0), DVec3::new(0.5, 4.0, -1.0));
    }
}
