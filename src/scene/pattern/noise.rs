//! `noise { … }`: Perlin's improved gradient noise as a value,
//! 0.5 + 0.5·n(p) clamped to [0, 1] (n is about ±0.7 at most, so values
//! gather around 0.5; a `colour_map` with keys near the middle sharpens
//! it). `octaves k` sums k octaves, each twice the frequency and half the
//! weight (fractal noise; default 1).

use super::perlin;
use crate::geometry::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Noise {
    pub octaves: u32,
}

impl Noise {
    pub fn value(&self, p: DVec3) -> f64 {
        let mut sum = 0.0;
        let mut f = 1.0;
        for _ in 0..self.octaves {
            sum += perlin::noise(p * f) / f;
            f *= 2.0;
        }
        0.5 + 0.5 * sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_on_lattice_points_and_varies_between() {
        let n = Noise { octaves: 1 };
        assert_eq!(n.value(DVec3::new(2.0, -3.0, 5.0)), 0.5);
        let vals: Vec<f64> = (0..300)
            .map(|i| n.value(DVec3::new(i as f64 * 0.137, i as f64 * 0.05, 0.3)))
            .collect();
        let lo = vals.iter().cloned().fold(1.0, f64::min);
        let hi = vals.iter().cloned().fold(0.0, f64::max);
        assert!(lo < 0.3 && hi > 0.7, "{lo}..{hi}");
    }

    /// k octaves: 0.5 + 0.5·Σ n(2ⁱ·p)/2ⁱ over i < k, as documented.
    #[test]
    fn octaves_double_the_frequency_and_halve_the_weight() {
        for p in (0..50).map(|i| {
            let t = i as f64;
            DVec3::new(0.31 * t - 4.0, (0.7 * t).sin() * 2.0, 1.5 - 0.13 * t)
        }) {
            for k in [1, 2, 4] {
                let sum: f64 = (0..k)
                    .map(|i| {
                        let f = 2f64.powi(i);
                        perlin::noise(p * f) / f
                    })
                    .sum();
                let want = 0.5 + 0.5 * sum;
                let got = Noise { octaves: k as u32 }.value(p);
                assert!((got - want).abs() < 1e-12, "{p} {k}: {got} vs {want}");
            }
        }
    }
}
