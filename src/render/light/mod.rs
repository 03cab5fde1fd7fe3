//! Lights as the integrator meets them: each kind gives, for a shading
//! point, samples of the light arriving there (a direction, how far a shadow
//! ray must go, and what arrives if nothing is in the way). The integrator
//! casts the shadow rays; these files know nothing of materials.

pub mod area;
pub mod environment;
pub mod parallel;
pub mod point;
pub mod spot;

use crate::geometry::DVec3;
use crate::scene::{Colour, Light, LightKind};

/// Light arriving at a point from one direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point toward the light.
    pub dir: DVec3,
    /// Length of the shadow ray (∞ for parallel light).
    pub dist: f64,
    /// What arrives when unshadowed (E, or L_e·geometry for area lights).
    pub radiance: Colour,
}

/// The sample of a light without area as seen from `from` (the point the
/// shadow ray will start at), or `None` when it sends nothing there.
#[inline]
pub fn sample(light: &Light, from: DVec3) -> Option<LightSample> {
    match &light.kind {
        LightKind::Point => Some(point::sample(light.position, light.colour, from)),
        LightKind::Parallel { direction } => Some(parallel::sample(*direction, light.colour)),
        LightKind::Spot {
            axis,
            cos_angle,
            cos_falloff,
        } => spot::sample(
            light.position,
            *axis,
            *cos_angle,
            *cos_falloff,
            light.colour,
            from,
        ),
    }
}
