//! `marble { a …  b …  scale k  turbulence t }` (defaults k 1, t 4):
//! veins along x. With s = sin(x + t·T(p)), T the six-octave turbulence,
//! the value is 1 − ((1 + s)/2)^0.6: 0 (`a`) over most of the stone,
//! rising to 1 (`b`) in narrow veins where s nears −1.

use super::perlin;
use crate::geometry::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Marble;

impl Marble {
    /// `p` already scaled; `turbulence` is the pattern's own.
    pub fn value(&self, p: DVec3, turbulence: f64) -> f64 {
        let s = (p.x + turbulence * perlin::turbulence(p, 6)).sin();
        let t = (0.5 + 0.5 * s).powf(0.6);
        1.0 - t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_turbulence_veins_are_planes_of_x() {
        let x = 1.5 * std::f64::consts::PI; // sin = −1: the vein's centre
        let m = Marble;
        assert!((m.value(DVec3::new(x, 0.3, -2.0), 0.0) - 1.0).abs() < 1e-6);
        assert_eq!(
            m.value(DVec3::new(0.5 * std::f64::consts::PI, 9.0, 1.0), 0.0),
            0.0
        );
        assert_eq!(
            m.value(DVec3::new(1.0, 0.0, 0.0), 0.0),
            m.value(DVec3::new(1.0, 5.0, -3.0), 0.0)
        );
    }

    /// With turbulence the value is 1 − ((1 + s)/2)^0.6, s = sin(x +
    /// t·T(p)), T the six-octave turbulence, as documented.
    #[test]
    fn turbulence_shifts_the_phase_by_t_times_the_six_octave_sum() {
        for p in (0..50).map(|i| {
            let t = i as f64;
            DVec3::new(0.31 * t - 4.0, (0.7 * t).sin() * 2.0, 1.5 - 0.13 * t)
        }) {
            for t in [0.5, 4.0] {
                let s = (p.x + t * perlin::turbulence(p, 6)).sin();
                let want = 1.0 - ((1.0 + s) / 2.0).powf(0.6);
                let got = Marble.value(p, t);
                assert!((got - want).abs() < 1e-12, "{p} {t}: {got} vs {want}");
            }
        }
        // Half way between crest and vein (s = 0): 1 − 0.5^0.6.
        let v = Marble.value(DVec3::new(0.0, 2.0, 3.0), 0.0);
        assert!((v - (1.0 - 0.5f64.powf(0.6))).abs() < 1e-12, "{v}");
    }
}
