//! Colours are linear RGB in `f64`, unclamped until the image is written.

/// Linear RGB.
pub type Colour = glam::DVec3;

/// How linear values are encoded into the image (and how `#rrggbb` and named
/// colours, which are display-encoded, are decoded).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Transfer {
    /// The sRGB curve (the default).
    Srgb,
    /// Values stored as they are.
    Linear,
    /// A power law: encoded = linear^(1/g). `gamma 2` is the course's
    /// square-root output.
    Gamma(f64),
}

impl Transfer {
    /// Linear value → display value in [0, 1].
    pub fn encode(self, x: f64) -> f64 {
        let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
        match self {
            Transfer::Srgb => {
                if x <= 0.0031308 {
                    12.92 * x
                } else {
                    1.055 * x.powf(1.0 / 2.4) - 0.055
                }
            }
            Transfer::Linear => x,
            Transfer::Gamma(g) => x.powf(1.0 / g),
        }
    }

    /// Display value in [0, 1] → linear value.
    pub fn decode(self, x: f64) -> f64 {
        match self {
            Transfer::Srgb => {
                if x <= 0.04045 {
                    x / 12.92
                } else {
                    ((x + 0.055) / 1.055).powf(2.4)
                }
            }
            Transfer::Linear => x,
            Transfer::Gamma(g) => x.powf(g),
        }
    }

    pub fn decode_rgb8(self, r: u8, g: u8, b: u8) -> Colour {
        Colour::new(
            self.decode(r as f64 / 255.0),
            self.decode(g as f64 / 255.0),
            self.decode(b as f64 / 255.0),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_round_trip() {
        for t in [Transfer::Srgb, Transfer::Linear, Transfer::Gamma(2.0)] {
            for i in 0..=20 {
                let x = i as f64 / 20.0;
                assert!((t.encode(t.decode(x)) - x).abs() < 1e-12, "{t:?} {x}");
            }
        }
        assert!((Transfer::Gamma(2.0).encode(0.25) - 0.5).abs() < 1e-12);
        assert!((Transfer::Srgb.encode(0.5) - 0.7354).abs() < 1e-3);
    }
}
