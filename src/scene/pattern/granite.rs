//! `granite { … }`: grains of many sizes, POV-Ray's granite: the sum over
//! six octaves of |n(4·2ⁱ·p)| / 2ⁱ (n: Perlin noise), clamped to [0, 1].
//! Mostly low values with sharp light flecks; map it with a `colour_map`
//! such as `{ 0 #303030  0.6 #808080  1 white }`.

use super::perlin;
use crate::geometry::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Granite;

impl Granite {
    pub fn value(&self, p: DVec3) -> f64 {
        perlin::turbulence(p * 4.0, 6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grains_are_small_and_varied() {
        // Neighbours 0.05 apart differ often: the grain is fine.
        let mut changes = 0;
        let mut prev = Granite.value(DVec3::ZERO);
        for i in 1..200 {
            let v = Granite.value(DVec3::new(i as f64 * 0.05, 0.37, 0.11));
            assert!((0.0..=1.5).contains(&v));
            if (v - prev).abs() > 0.05 {
                changes += 1;
            }
            prev = v;
        }
        assert!(changes > 50, "{changes}");
    }

    /// The sum over six octaves of |n(4·2ⁱ·p)| / 2ⁱ, as documented.
    #[test]
    fn six_octaves_of_noise_at_four_times_the_point() {
        for p in (0..50).map(|i| {
            let t = i as f64;
            DVec3::new(0.31 * t - 4.0, (0.7 * t).sin() * 2.0, 1.5 - 0.13 * t)
        }) {
            let want: f64 = (0..6)
                .map(|i| {
                    let f = 2f64.powi(i);
                    perlin::noise(p * 4.0 * f).abs() / f
                })
                .sum();
            let got = Granite.value(p);
            assert!((got - want).abs() < 1e-12, "{p}: {got} vs {want}");
        }
    }
}
