//! Light from every direction, and ambient occlusion.
//!
//! ```text
//! environment { colour skyblue  intensity 0.5  samples 4 }
//! ambient rgb(1, 1, 1) intensity 0.2 occlusion { samples 16  min 0.1  distance 5 }
//! ```
//! Environment: L_env arriving from every direction, estimated with
//! cosine-distributed directions about n that escape the scene, so a
//! surface of `diffuse` k_d and colour c gets k_d c ⊙ L_env × (the fraction
//! that escapes): a white object in a uniform sky shows the sky's radiance
//! (the white furnace). A camera ray that hits nothing sees it unless the
//! scene sets a `background`.
//!
//! Ambient occlusion: the ambient term times 1 where a cosine-distributed
//! direction about n escapes within `distance`, else `min`, averaged over
//! `samples` directions per shading point.

use crate::geometry::DVec3;
use crate::render::sampler::{SampleStream, about, cos_power_lobe};
use crate::scene::{Colour, Environment};

/// The environment's light at a point with facing normal `n`, before the
/// surface's colour: the mean over `env.samples` cosine-distributed
/// directions of the sky's radiance where the direction escapes.
pub fn gather(
    env: &Environment,
    n: DVec3,
    stream: &mut SampleStream,
    mut blocked: impl FnMut(DVec3) -> bool,
) -> Colour {
    let mut sum = Colour::ZERO;
    for _ in 0..env.samples {
        let dir = about(n, cos_power_lobe(stream.next2(), 1.0));
        if !blocked(dir) {
            sum += env.radiance(dir);
        }
    }
    sum / env.samples as f64
}

/// The mean over `samples` cosine-distributed directions about `n` of
/// `hit_value` (when `blocked(dir)`) or 1.
pub fn escaping(
    n: DVec3,
    samples: u32,
    stream: &mut SampleStream,
    hit_value: f64,
    mut blocked: impl FnMut(DVec3) -> bool,
) -> f64 {
    let mut sum = 0.0;
    for _ in 0..samples {
        let dir = about(n, cos_power_lobe(stream.next2(), 1.0));
        sum += if blocked(dir) { hit_value } else { 1.0 };
    }
    sum / samples as f64
}
