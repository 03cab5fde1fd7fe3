//! A point light: colour × intensity from one position, with no distance
//! falloff (the course's rule).
//!
//! ```text
//! light { position <5, 10, 5>  colour white  intensity 1 }
//! ```

use super::LightSample;
use crate::geometry::DVec3;
use crate::scene::Colour;

/// The light at `position` as seen from `from`.
#[inline]
pub fn sample(position: DVec3, colour: Colour, from: DVec3) -> LightSample {
    let to_light = position - from;
    let dist = to_light.length();
    LightSample {
        dir: to_light / dist,
        dist,
        radiance: colour,
    }
}
