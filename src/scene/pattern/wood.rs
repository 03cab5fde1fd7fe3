//! `wood { a …  b …  scale k  turbulence t }` (defaults k 1, t 0.5):
//! rings around the y axis. With r = √(x² + z²) + t·T(p) (T: four-octave
//! turbulence), the value is frac(r)³: wide light early wood (`a`) ending
//! in a sharp dark late-wood edge (`b`).

use super::perlin;
use crate::geometry::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Wood;

impl Wood {
    /// `p` already scaled; `turbulence` is the pattern's own.
    pub fn value(&self, p: DVec3, turbulence: f64) -> f64 {
        let r = (p.x * p.x + p.z * p.z).sqrt() + turbulence * perlin::turbulence(p, 4);
        let ring = r - r.floor();
        ring.powf(3.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_turbulence_rings_are_circles_around_y() {
        let w = Wood;
        assert_eq!(w.value(DVec3::new(0.5, 0.0, 0.0), 0.0), 0.125);
        assert_eq!(
            w.value(DVec3::new(0.3, 2.0, 0.4), 0.0),
            w.value(DVec3::new(0.5, -1.0, 0.0), 0.0),
            "same radius, same value"
        );
        assert_eq!(w.value(DVec3::new(1.0, 0.0, 0.0), 0.0), 0.0, "a new ring");
    }

    /// With turbulence the radius is √(x² + z²) + t·T(p), T the
    /// four-octave turbulence, and the value frac(r)³, as documented.
    #[test]
    fn turbulence_adds_t_times_the_four_octave_sum_to_the_radius() {
        for p in (0..50).map(|i| {
            let t = i as f64;
            DVec3::new(0.31 * t - 4.0, (0.7 * t).sin() * 2.0, 1.5 - 0.13 * t)
        }) {
            for t in [0.5, 2.0] {
                let r = (p.x * p.x + p.z * p.z).sqrt() + t * perlin::turbulence(p, 4);
                let want = (r - r.floor()).powi(3);
                let got = Wood.value(p, t);
                assert!((got - want).abs() < 1e-12, "{p} {t}: {got} vs {want}");
            }
        }
    }
}
