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
}
