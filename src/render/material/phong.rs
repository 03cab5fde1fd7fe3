//! The Phong highlight of the 2018 model:
//! k_s c_s (r·v)⁺^e ⊙ E (n·l)⁺, with r = 2(n·l)n − l the light mirrored
//! about the normal. Note the (n·l) factor (POV-Ray's `phong` has none).
//!
//! ```text
//! material red_plastic { colour rgb(0.7, 0.05, 0.05)  specular 0.6  shininess 80  specular_colour white }
//! ```

use crate::geometry::DVec3;
use crate::scene::{Colour, Phong};

/// The highlight for one light: E arriving from unit direction `l` at a
/// point with facing normal `n`, seen from unit direction `v`.
pub fn highlight(p: &Phong, n: DVec3, v: DVec3, l: DVec3, e: Colour) -> Colour {
    let cos = n.dot(l);
    if cos <= 0.0 {
        return Colour::ZERO;
    }
    let r = 2.0 * cos * n - l;
    let rv = r.dot(v);
    if rv <= 0.0 {
        return Colour::ZERO;
    }
    p.colour * e * (rv.powf(p.shininess) * cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn phong(e: f64) -> Phong {
        Phong {
            colour: Colour::ONE,
            shininess: e,
        }
    }

    #[test]
    fn peak_in_the_mirror_direction_is_ks_times_n_dot_l() {
        let n = DVec3::Y;
        let l = DVec3::new(1.0, 1.0, 0.0).normalize();
        let v = DVec3::new(-1.0, 1.0, 0.0).normalize();
        let h = highlight(&phong(50.0), n, v, l, Colour::ONE);
        assert!((h.x - l.y).abs() < 1e-12, "{h}");
    }

    #[test]
    fn falls_as_cos_to_the_power_e_off_the_mirror_direction() {
        let n = DVec3::Y;
        let l = DVec3::Y;
        let a: f64 = 0.2;
        let v = DVec3::new(a.sin(), a.cos(), 0.0);
        let h = highlight(&phong(20.0), n, v, l, Colour::ONE);
        assert!((h.x - a.cos().powf(20.0)).abs() < 1e-12);
        // Nothing from behind the surface.
        assert_eq!(highlight(&phong(20.0), n, v, -l, Colour::ONE), Colour::ZERO);
    }
}

/// The highlight's colour is the product of the specular colour and the
/// light's (mutation testing: with white for both, c_s / E equals c_s ⊙ E).
#[cfg(test)]
mod coloured {
    use super::*;

    #[test]
    fn specular_colour_and_light_colour_multiply_per_channel() {
        let p = Phong {
            colour: Colour::new(0.5, 0.25, 1.0),
            shininess: 10.0,
        };
        let e = Colour::new(2.0, 4.0, 0.5);
        // Light and eye on the normal: r·v = 1 and n·l = 1.
        let h = highlight(&p, DVec3::Y, DVec3::Y, DVec3::Y, e);
        assert_eq!(h, Colour::new(1.0, 1.0, 0.5));
    }
}
