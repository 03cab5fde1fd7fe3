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

    /// Linear value → the 8-bit value an image stores: the display value
    /// times 255, rounded half away from zero.
    #[inline]
    pub fn encode8(self, x: f64) -> u8 {
        round_unit_byte(self.encode(x) * 255.0)
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

/// `v.round() as u8` for v in [0, 255], as the truncation plus the
/// exactly computed fraction: `f64::round` is a library call on the
/// baseline x86-64 (no SSE4.1), and it was a tenth of an empty picture's
/// cost. v − trunc(v) is exact below 2^52, so this is the same rounding
/// (half away from zero); NaN and values outside [0, 255] never occur here
/// ([`Transfer::encode`] clamps), and would saturate as `as u8` does.
#[inline]
fn round_unit_byte(v: f64) -> u8 {
    let t = v as u32;
    let up = v - t as f64 >= 0.5;
    t.saturating_add(up as u32).min(255) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast rounding is `round() as u8` exactly: at every half-way
    /// point k + 0.5 and the ULPs around it, at the binade edges where
    /// adding 0.5 would itself round (0.49999999999999994), on a fine
    /// sweep, and outside [0, 255] and at NaN, where both saturate.
    #[test]
    fn the_byte_rounding_is_the_standard_rounding() {
        let mut values = vec![
            f64::NAN,
            -0.0,
            -0.7,
            -1e300,
            255.49,
            255.5,
            256.0,
            1e10,
            1e300,
        ];
        values.push(f64::INFINITY);
        values.push(f64::NEG_INFINITY);
        for k in 0..=256 {
            let mut v = k as f64 + 0.5;
            let mut w = v;
            for _ in 0..64 {
                values.extend([v, w]);
                v = v.next_up();
                w = w.next_down();
            }
            values.push(k as f64);
        }
        values.extend((0..=2_560_000).map(|i| i as f64 * 1e-4));
        for v in values {
            assert_eq!(round_unit_byte(v), v.round() as u8, "{v:e}");
        }
        assert_eq!(round_unit_byte(0.5f64.next_down()), 0);
    }

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
