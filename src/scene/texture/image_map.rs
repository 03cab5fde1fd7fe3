//! Image textures: a PNG or JPEG file wrapped onto a shape's (u, v).

use super::super::{Colour, Transfer};
use crate::geometry::DVec2;
use std::path::Path;

/// How (u, v) is turned into image coordinates: first `swap` exchanges u
/// and v, then `flip_u`/`flip_v` mirror them (u → 1 − u), then
/// `scale` repeats the image and `offset` shifts it. v = 0 is the image's
/// bottom row, so a picture is upright on a shape whose v grows upwards.
#[derive(Clone, Debug, PartialEq)]
pub struct UvMapping {
    pub scale: DVec2,
    pub offset: DVec2,
    pub swap: bool,
    pub flip_u: bool,
    pub flip_v: bool,
}

impl Default for UvMapping {
    fn default() -> Self {
        UvMapping {
            scale: DVec2::ONE,
            offset: DVec2::ZERO,
            swap: false,
            flip_u: false,
            flip_v: false,
        }
    }
}

/// Pixels decoded to linear colour once, at scene load.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    pub width: u32,
    pub height: u32,
    /// Row 0 at the top, as in the file.
    pixels: Vec<[f32; 3]>,
    pub mapping: UvMapping,
}

/// Why an image could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("cannot open the image: {0}")]
    Io(String),
    #[error("cannot decode the image: {0}")]
    Decode(String),
    #[error("the image is {width}x{height}; textures are limited to {limit}x{limit} pixels")]
    TooLarge { width: u32, height: u32, limit: u32 },
}

/// Larger images are refused before their pixels are allocated.
pub const MAX_TEXTURE_SIDE: u32 = 16384;

impl ImageTexture {
    /// Reads a PNG or JPEG (any format the `image` crate was built with),
    /// decoding its display-encoded values with the scene's transfer curve.
    pub fn load(path: &Path, transfer: Transfer, mapping: UvMapping) -> Result<Self, ImageError> {
        // A device or pipe would be read forever; a folder gives a poor message.
        let meta = std::fs::metadata(path).map_err(|e| ImageError::Io(e.to_string()))?;
        if !meta.is_file() {
            return Err(ImageError::Io("it is not a regular file".into()));
        }
        let reader = image::ImageReader::open(path)
            .map_err(|e| ImageError::Io(e.to_string()))?
            .with_guessed_format()
            .map_err(|e| ImageError::Io(e.to_string()))?;
        let (width, height) = reader
            .into_dimensions()
            .map_err(|e| ImageError::Decode(e.to_string()))?;
        if width == 0 || height == 0 {
            return Err(ImageError::Decode(format!(
                "the image is {width}x{height}: it has no pixels"
            )));
        }
        if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
            return Err(ImageError::TooLarge {
                width,
                height,
                limit: MAX_TEXTURE_SIDE,
            });
        }
        let mut reader = image::ImageReader::open(path)
            .map_err(|e| ImageError::Io(e.to_string()))?
            .with_guessed_format()
            .map_err(|e| ImageError::Io(e.to_string()))?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_TEXTURE_SIDE);
        limits.max_image_height = Some(MAX_TEXTURE_SIDE);
        reader.limits(limits);
        // The decoders are third-party code fed user bytes, and one has
        // panicked on a mangled palette (a fuzz find): a panic would take the
        // whole render down, so it is caught and reported as a bad file.
        let decoded = crate::guard::catch_quietly(|| reader.decode()).ok_or_else(|| {
            ImageError::Decode("the file is malformed (the decoder gave up)".into())
        })?;
        let decoded = decoded.map_err(|e| ImageError::Decode(e.to_string()))?;
        // Floating-point images (EXR, Radiance HDR) hold linear radiance:
        // kept as they are, above 1 too (a sky's sun).
        if matches!(
            decoded,
            image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_)
        ) {
            let img = decoded.to_rgb32f();
            return Ok(ImageTexture {
                width: img.width(),
                height: img.height(),
                pixels: img.pixels().map(|p| p.0).collect(),
                mapping,
            });
        }
        Ok(Self::from_rgb8(&decoded.to_rgb8(), transfer, mapping))
    }

    pub fn from_rgb8(img: &image::RgbImage, transfer: Transfer, mapping: UvMapping) -> Self {
        let lut: Vec<f32> = (0..=255u8)
            .map(|i| transfer.decode(i as f64 / 255.0) as f32)
            .collect();
        let pixels = img.pixels().map(|p| p.0.map(|c| lut[c as usize])).collect();
        ImageTexture {
            width: img.width(),
            height: img.height(),
            pixels,
            mapping,
        }
    }

    /// Bilinear lookup with wrap-around; at a pixel's centre it returns that
    /// pixel exactly.
    pub fn sample(&self, uv: DVec2) -> Colour {
        let m = &self.mapping;
        let mut uv = if m.swap { DVec2::new(uv.y, uv.x) } else { uv };
        if m.flip_u {
            uv.x = 1.0 - uv.x;
        }
        if m.flip_v {
            uv.y = 1.0 - uv.y;
        }
        let uv = uv * m.scale + m.offset;
        // An empty image (only `from_rgb8` can make one) has nothing to show.
        if !uv.is_finite() || self.pixels.is_empty() {
            return Colour::ZERO;
        }
        // Image x grows with u; image rows grow downwards while v grows up.
        let x = uv.x * self.width as f64 - 0.5;
        let y = (1.0 - uv.y) * self.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let px = |i: f64, j: f64| {
            let i = (i as i64).rem_euclid(self.width as i64) as u32;
            let j = (j as i64).rem_euclid(self.height as i64) as u32;
            let p = self.pixels[(j * self.width + i) as usize];
            Colour::new(p[0] as f64, p[1] as f64, p[2] as f64)
        };
        let top = px(x0, y0).lerp(px(x0 + 1.0, y0), fx);
        let bottom = px(x0, y0 + 1.0).lerp(px(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_two() -> image::RgbImage {
        let mut img = image::RgbImage::new(2, 2);
        img.put_pixel(0, 0, image::Rgb([255, 0, 0])); // top left
        img.put_pixel(1, 0, image::Rgb([0, 255, 0])); // top right
        img.put_pixel(0, 1, image::Rgb([0, 0, 255])); // bottom left
        img.put_pixel(1, 1, image::Rgb([255, 255, 255]));
        img
    }

    #[test]
    fn pixel_centres_give_the_pixels() {
        let t = ImageTexture::from_rgb8(&two_by_two(), Transfer::Linear, UvMapping::default());
        assert_eq!(t.sample(DVec2::new(0.25, 0.75)), Colour::X);
        assert_eq!(t.sample(DVec2::new(0.75, 0.75)), Colour::Y);
        assert_eq!(t.sample(DVec2::new(0.25, 0.25)), Colour::Z);
        assert_eq!(t.sample(DVec2::new(0.75, 0.25)), Colour::ONE);
    }

    #[test]
    fn mapping_swaps_flips_scales_and_offsets() {
        let img = two_by_two();
        let at = |m: UvMapping, u, v| {
            ImageTexture::from_rgb8(&img, Transfer::Linear, m).sample(DVec2::new(u, v))
        };
        let flip = UvMapping {
            flip_u: true,
            ..Default::default()
        };
        assert_eq!(at(flip, 0.25, 0.75), Colour::Y);
        let swap = UvMapping {
            swap: true,
            ..Default::default()
        };
        assert_eq!(at(swap, 0.25, 0.75), Colour::ONE);
        let scale = UvMapping {
            scale: DVec2::splat(2.0),
            ..Default::default()
        };
        assert_eq!(at(scale, 0.125 + 0.5, 0.375 + 0.5), Colour::X);
        let offset = UvMapping {
            offset: DVec2::new(0.5, 0.0),
            ..Default::default()
        };
        assert_eq!(at(offset, 0.25, 0.75), Colour::Y);
    }

    #[test]
    fn missing_and_corrupt_files_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let missing = ImageTexture::load(
            &dir.path().join("nope.png"),
            Transfer::Srgb,
            UvMapping::default(),
        );
        assert!(matches!(missing, Err(ImageError::Io(_))));
        let bad = dir.path().join("bad.png");
        std::fs::write(&bad, b"\x89PNG\r\n\x1a\nnot really").unwrap();
        assert!(ImageTexture::load(&bad, Transfer::Srgb, UvMapping::default()).is_err());
        let good = dir.path().join("good.png");
        two_by_two().save(&good).unwrap();
        let t = ImageTexture::load(&good, Transfer::Linear, UvMapping::default()).unwrap();
        assert_eq!((t.width, t.height), (2, 2));
    }

    /// Fuzz find: a PPM of width 0 decoded, then sampling divided by zero.
    #[test]
    fn an_image_without_pixels_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let empty = dir.path().join("empty.ppm");
        std::fs::write(&empty, b"P35\n0 1\t\xc4\xff+ 3050\n").unwrap();
        let r = ImageTexture::load(&empty, Transfer::Srgb, UvMapping::default());
        assert!(matches!(r, Err(ImageError::Decode(m)) if m.contains("no pixels")));
        let none = ImageTexture::from_rgb8(
            &image::RgbImage::new(0, 3),
            Transfer::Srgb,
            UvMapping::default(),
        );
        assert_eq!(none.sample(DVec2::new(0.5, 0.5)), Colour::ZERO);
    }

    /// Fuzz find: a PNG whose palette holds one byte made the png crate
    /// panic while decoding.
    #[test]
    fn a_decoder_panic_is_a_decode_error() {
        let dir = tempfile::tempdir().unwrap();
        let bad = dir.path().join("bad.png");
        std::fs::write(
            &bad,
            include_bytes!("../../../tests/data/png_short_palette.png"),
        )
        .unwrap();
        let r = ImageTexture::load(&bad, Transfer::Srgb, UvMapping::default());
        assert!(matches!(r, Err(ImageError::Decode(_))));
    }
}
