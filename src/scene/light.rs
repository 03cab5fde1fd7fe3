use super::Colour;
use glam::DVec3;

/// A point light with no distance falloff (the course's model).
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub position: DVec3,
    /// Colour already multiplied by intensity.
    pub colour: Colour,
}
