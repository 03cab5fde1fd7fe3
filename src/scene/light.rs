//! Lights as the scene states them (data only; `render/light/` samples them).
//!
//! ```text
//! light { position <5, 10, 5>  colour white  intensity 1 }                 // point
//! light { direction <-1, -2, -1>  intensity 0.8 }                           // parallel
//! light { position <0, 8, 0>  look_at <0, 0, 0>  angle 25  falloff 35 }     // spot
//! ```
//! Point, parallel and spot lights have no distance falloff (the course's
//! rule). Area lights are emissive shapes ([`AreaLight`]).

use super::Colour;
use glam::DVec3;

/// A light without area: point (the course's model), parallel or spot.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub position: DVec3,
    /// Colour already multiplied by intensity.
    pub colour: Colour,
    pub kind: LightKind,
}

#[derive(Clone, Debug, PartialEq)]
pub enum LightKind {
    /// From `position` in every direction.
    Point,
    /// Along `direction` (unit) everywhere; `position` is unused.
    Parallel { direction: DVec3 },
    /// From `position` around the unit `axis`: full inside the cone of
    /// half-angle `angle`, fading smoothly to nothing at `falloff` (cosines).
    Spot {
        axis: DVec3,
        cos_angle: f64,
        cos_falloff: f64,
    },
}

impl Light {
    /// The 2017 point light.
    pub fn point(position: DVec3, colour: Colour) -> Light {
        Light {
            position,
            colour,
            kind: LightKind::Point,
        }
    }
}

/// The surface of an emissive sphere, disc or rectangle, in world space.
#[derive(Clone, Debug, PartialEq)]
pub enum LightSurface {
    Sphere {
        centre: DVec3,
        radius: f64,
    },
    /// A disc of `radius` about `centre`, facing `normal` (unit), spanned by
    /// the unit vectors `u`, `v`.
    Disc {
        centre: DVec3,
        normal: DVec3,
        u: DVec3,
        v: DVec3,
        radius: f64,
    },
    /// The parallelogram corner + s·edge_u + t·edge_v, s, t ∈ [0, 1].
    Rectangle {
        corner: DVec3,
        edge_u: DVec3,
        edge_v: DVec3,
    },
}

/// An emissive shape lighting the scene, radiance `emit` from its front.
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    pub surface: LightSurface,
    pub emit: Colour,
    /// `None`: one point per pixel sample (the course's way); `Some(n)`: its
    /// own n × n stratified points per shading point (POV-Ray's grid).
    pub samples: Option<u32>,
    /// Whether both sides emit (a sphere's inside never shows; a disc or
    /// rectangle emits on its front only).
    pub two_sided: bool,
    /// Part of a CSG solid, so parts of its surface may be cut away (or
    /// turned inside out, for a cutter): a sample counts only where a ray
    /// to it meets an emitting surface there from its front
    /// (`render/light/area.rs`).
    pub clipped: bool,
    /// Its material is a pattern choosing among materials, some emitting:
    /// `emit` is one, and a sample takes the `emit` of the material chosen
    /// where a ray to it meets the surface (the same ray as a clipped
    /// light's, `render/light/area.rs`).
    pub chosen: bool,
}

/// Light from every direction: colour × intensity, or an image (an HDR or
/// EXR sky in latitude-longitude) times colour × intensity.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    pub colour: Colour,
    /// Cosine-distributed directions traced per shading point.
    pub samples: u32,
    pub image: Option<std::sync::Arc<super::texture::ImageTexture>>,
    /// Whether camera rays that miss see it (no `background` was set).
    pub visible: bool,
}

impl Environment {
    /// The radiance arriving from unit direction `d` (travelling along −d).
    /// The image is a latitude-longitude map: u = 1/2 + atan2(d.x, −d.z)/2π
    /// (the image's centre straight ahead along −z), v = 1/2 + asin(d.y)/π
    /// (its top row straight up).
    pub fn radiance(&self, d: DVec3) -> Colour {
        match &self.image {
            None => self.colour,
            Some(img) => {
                let u = 0.5 + d.x.atan2(-d.z) / std::f64::consts::TAU;
                let v = 0.5 + d.y.clamp(-1.0, 1.0).asin() / std::f64::consts::PI;
                // Wrap around in longitude only: near the poles stay within
                // the first and last rows' centres.
                let half = 0.5 / img.height as f64;
                let v = v.clamp(half, 1.0 - half);
                self.colour * img.sample(glam::DVec2::new(u, v))
            }
        }
    }
}

/// Ambient occlusion: the ambient term times 1 where a cosine-distributed
/// direction about n escapes within `distance`, else `min`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Occlusion {
    pub samples: u32,
    pub min: f64,
    pub distance: f64,
}
