//! Matte (Lambert): k_a c ⊙ L_ambient + Σ unshadowed lights k_d c ⊙ E (n·l)⁺.
//!
//! ```text
//! material chalk { colour rgb(0.9, 0.9, 0.85)  diffuse 0.9  ambient 0.1 }
//! ```
//! `diffuse` is the plain weight k_d, without the 1/π of the course's 2018
//! scenes (the 2017 scenes and POV-Ray have none; write `diffuse kd / pi`).
//! The integrator sums the light arriving (ambient, then each light) and
//! multiplies by the colour once, in that order, which keeps every 2017
//! picture bit for bit.

use crate::scene::{Colour, Material};

/// The ambient light a surface takes: k_a · L_ambient (times occlusion).
#[inline]
pub fn ambient(m: &Material, ambient: Colour) -> Colour {
    ambient * m.ambient
}

/// One light's diffuse share before the colour: E · (n·l) · k_d, for
/// n·l > 0 (the caller has culled the rest).
#[inline]
pub fn diffuse(m: &Material, e: Colour, cos: f64) -> Colour {
    e * (cos * m.diffuse)
}

/// Whether the material reflects any light diffusely or ambiently (glass
/// and lamps do not, so their lights need not be sampled).
#[inline]
pub fn reflects(m: &Material) -> bool {
    m.diffuse > 0.0 || m.ambient > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_scale_each_term() {
        let m = Material {
            diffuse: 0.5,
            ambient: 0.25,
            ..Material::default()
        };
        assert_eq!(ambient(&m, Colour::splat(2.0)), Colour::splat(0.5));
        assert_eq!(diffuse(&m, Colour::ONE, 0.5), Colour::splat(0.25));
        // The defaults leave a 2017 value unchanged, bit for bit.
        let d = Material::default();
        let e = Colour::new(0.3, 0.7, 0.11);
        assert_eq!(diffuse(&d, e, 0.123), e * 0.123);
    }
}
