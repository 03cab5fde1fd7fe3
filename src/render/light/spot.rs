//! A spot light: a point light whose light is full inside a cone of
//! half-angle `angle` about its axis, fades with a smoothstep of the cosine
//! to nothing at `falloff`, and is zero outside.
//!
//! ```text
//! light { position <0, 8, 0>  look_at <0, 0, 0>  angle 25  falloff 35  intensity 1.5 }
//! ```

use super::LightSample;
use crate::geometry::DVec3;
use crate::scene::Colour;

/// The fraction of the spot's light sent along a direction whose cosine
/// to the axis is `cos`.
pub fn cone(cos: f64, cos_angle: f64, cos_falloff: f64) -> f64 {
    if cos >= cos_angle {
        1.0
    } else if cos <= cos_falloff {
        0.0
    } else {
        let t = (cos - cos_falloff) / (cos_angle - cos_falloff);
        t * t * (3.0 - 2.0 * t)
    }
}

pub fn sample(
    position: DVec3,
    axis: DVec3,
    cos_angle: f64,
    cos_falloff: f64,
    colour: Colour,
    from: DVec3,
) -> Option<LightSample> {
    let to_light = position - from;
    let dist = to_light.length();
    let dir = to_light / dist;
    let k = cone(-dir.dot(axis), cos_angle, cos_falloff);
    (k > 0.0).then_some(LightSample {
        dir,
        dist,
        radiance: colour * k,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_inside_nothing_outside_smooth_between() {
        let (a, f) = (25f64.to_radians().cos(), 35f64.to_radians().cos());
        assert_eq!(cone(1.0, a, f), 1.0);
        assert_eq!(cone(40f64.to_radians().cos(), a, f), 0.0);
        let mid = cone(30f64.to_radians().cos(), a, f);
        assert!(mid > 0.0 && mid < 1.0);
        let s = sample(DVec3::Y * 8.0, -DVec3::Y, a, f, Colour::ONE, DVec3::ZERO).unwrap();
        assert_eq!(s.radiance, Colour::ONE);
        assert!(sample(DVec3::Y * 8.0, -DVec3::Y, a, f, Colour::ONE, DVec3::X * 8.0).is_none());
    }
}

/// The fade between `angle` and `falloff` is the smoothstep 3t² − 2t³ of
/// t, the cosine's place between the two (mutation testing: "between 0 and
/// 1" alone let t²/(3 − 2t) through).
#[cfg(test)]
mod fade {
    use super::*;

    #[test]
    fn the_fade_is_the_smoothstep_of_the_cosine() {
        let (a, f) = (25f64.to_radians().cos(), 35f64.to_radians().cos());
        for i in 1..20 {
            let t = i as f64 / 20.0;
            let k = cone(f + t * (a - f), a, f);
            assert!(
                (k - (3.0 * t * t - 2.0 * t * t * t)).abs() < 1e-12,
                "t {t}: {k}"
            );
            // Symmetric about the middle, where it is one half.
            let mirror = cone(f + (1.0 - t) * (a - f), a, f);
            assert!((k + mirror - 1.0).abs() < 1e-12, "t {t}");
        }
    }
}

/// A sample's direction and distance are those from the shading point to
/// the light, whatever the point (the other tests shade at the origin,
/// where position − from and position + from agree).
#[cfg(test)]
mod towards {
    use super::*;

    #[test]
    fn the_sample_points_from_the_shading_point_to_the_light() {
        let (a, f) = (25f64.to_radians().cos(), 35f64.to_radians().cos());
        let from = DVec3::new(1.0, 0.5, -2.0);
        let s = sample(DVec3::Y * 8.0, -DVec3::Y, a, f, Colour::ONE, from).unwrap();
        let to = DVec3::new(-1.0, 7.5, 2.0);
        assert!((s.dist - to.length()).abs() < 1e-12);
        assert!((s.dir - to / to.length()).length() < 1e-12);
        // Inside the cone (17° off the axis, the cone is 25°): full colour.
        assert_eq!(s.radiance, Colour::ONE);
    }
}
