//! Perfect mirrors, two ways.
//!
//! ```text
//! material chrome     { colour white  mirror 0.9  mirror_colour #ffe0b0 }  // adds k_r c_r ⊙ L(out)
//! material old_mirror { colour white  reflect 0.7 }                       // 2017: (1 − R)·rest + R·L(out)
//! ```
//! out = d − 2(d·n)n. `mirror` *adds* its reflection to the rest of the
//! material (the 2018 course and POV-Ray rule); `reflect` keeps its 2017
//! meaning, a mix.

use crate::geometry::DVec3;
use crate::scene::Colour;

/// The mirror direction of `d` about the unit normal `n`.
#[inline]
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - 2.0 * d.dot(n) * n
}

/// The 2017 mix of the rest of the shading with the reflected colour.
#[inline]
pub fn mix(rest: Colour, reflected: Colour, r: f64) -> Colour {
    (1.0 - r) * rest + r * reflected
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_keeps_the_tangent_part_and_flips_the_normal_part() {
        let d = DVec3::new(0.6, -0.8, 0.0);
        assert_eq!(reflect(d, DVec3::Y), DVec3::new(0.6, 0.8, 0.0));
        assert_eq!(mix(Colour::ONE, Colour::ZERO, 0.25), Colour::splat(0.75));
    }
}
