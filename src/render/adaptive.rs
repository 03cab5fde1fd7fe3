//! Adaptive sampling: a pixel whose first samples disagree is rendered
//! again with more.
//!
//! ```text
//! render { samples 2  sampler multijittered  adaptive { threshold 0.1  max_samples 6 } }
//! ```
//! A pixel's N × N samples disagree when, in some channel, the largest and
//! the smallest (each clamped to [0, 1], so that one very bright sample
//! does not count for more than a white one) differ by more than the
//! threshold T. Such a pixel takes the M × M samples that `samples M` would
//! give it, which replace the first ones: the pixel is then exactly the
//! M-sample picture's, and the others exactly the N-sample picture's.
//! Everything stays a pure function of (pixel, sample, seed), so the
//! picture is the same for any thread count and for a region.

use super::sampler::PixelSampler;
use crate::scene::Colour;

/// What refines a pixel, and with which samples.
pub struct Refine {
    pub threshold: f64,
    pub sampler: PixelSampler,
}

impl Refine {
    /// Whether `samples` (one pixel's colours) differ by more than the
    /// threshold in some channel, each clamped to [0, 1].
    pub fn disagree(&self, samples: &[Colour]) -> bool {
        let clamp = |c: Colour| c.clamp(Colour::ZERO, Colour::ONE);
        let Some(&first) = samples.first() else {
            return false;
        };
        let (mut lo, mut hi) = (clamp(first), clamp(first));
        for &c in &samples[1..] {
            let c = clamp(c);
            lo = lo.min(c);
            hi = hi.max(c);
        }
        (hi - lo).max_element() > self.threshold
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SamplerKind;

    fn refine(t: f64) -> Refine {
        Refine {
            threshold: t,
            sampler: PixelSampler::square(SamplerKind::Regular, 4, 0),
        }
    }

    #[test]
    fn samples_disagree_by_their_range_in_any_channel() {
        let flat = [Colour::splat(0.5); 4];
        assert!(!refine(0.01).disagree(&flat));
        let edge = [Colour::ZERO, Colour::new(0.0, 0.3, 0.0)];
        assert!(refine(0.25).disagree(&edge));
        assert!(!refine(0.35).disagree(&edge));
        // Above 1 counts as 1: a sun beside white is no edge.
        let bright = [Colour::ONE, Colour::splat(40.0)];
        assert!(!refine(0.01).disagree(&bright));
        assert!(!refine(0.01).disagree(&[]));
    }

    /// "More than the threshold", not "at least": samples exactly T apart
    /// keep their pixel, and a flat pixel is never refined, even at T = 0
    /// (which refines every pixel whose samples differ at all).
    #[test]
    fn a_range_equal_to_the_threshold_does_not_refine() {
        let edge = [Colour::ZERO, Colour::new(0.0, 0.25, 0.0)];
        assert!(!refine(0.25).disagree(&edge));
        assert!(refine(0.125).disagree(&edge));
        let flat = [Colour::splat(0.5); 4];
        assert!(!refine(0.0).disagree(&flat));
        assert!(refine(0.0).disagree(&[Colour::splat(0.5), Colour::splat(0.5 + 1e-9)]));
    }
}
