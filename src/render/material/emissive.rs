//! Emissive surfaces: radiance colour × intensity leaving the front side
//! (the side the outward normal points to), seen by any ray that hits it.
//!
//! ```text
//! material lamp { emit rgb(1, 0.9, 0.7)  intensity 25 }
//! sphere { centre <0, 5, 0>  radius 0.3  material lamp }   // also an area light
//! ```
//! An emissive sphere, disc or rectangle also lights the scene as an area
//! light (`render/light/area.rs`); emission seen in a mirror or through
//! glass is this term.

use crate::scene::{Colour, Material};

/// What the surface sends back along a ray that hit its `front` side.
pub fn emitted(m: &Material, front: bool) -> Colour {
    if front { m.emit } else { Colour::ZERO }
}
