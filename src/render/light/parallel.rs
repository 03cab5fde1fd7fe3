//! A parallel (directional) light: the same direction l everywhere, no
//! falloff, and a shadow ray without length limit.
//!
//! ```text
//! light { direction <-1, -2, -1>  intensity 0.8 }   // shining along the vector
//! ```

use super::LightSample;
use crate::geometry::DVec3;
use crate::scene::Colour;

/// `direction` is the unit vector the light travels along.
pub fn sample(direction: DVec3, colour: Colour) -> LightSample {
    LightSample {
        dir: -direction,
        dist: f64::INFINITY,
        radiance: colour,
    }
}
