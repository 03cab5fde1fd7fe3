//! Image textures: a PNG or JPEG file wrapped onto a shape's (u, v).
//! Reading the file (and its pixel budget) is `formats::image`; this is the
//! transfer curve, the cache of decoded files and the lookup.

pub use crate::formats::image::ImageError;

use super::super::{Colour, Transfer};
use crate::formats::{self, image::Pixels};
use crate::geometry::DVec2;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, Weak};

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
    /// Row 0 at the top, as in the file. Shared by every texture made from
    /// the same file (see [`DECODED`]).
    pixels: Arc<[[f32; 3]]>,
    pub mapping: UvMapping,
}

/// What a decoded file is known by: its real path, size and modification
/// time (an edited file is decoded afresh), and the transfer curve used.
type DecodedKey = (PathBuf, u64, Option<std::time::SystemTime>, String);

/// Files already decoded, so that a picture used by many materials is
/// decoded once. Weak: the pixels live only as long as a scene uses them.
static DECODED: Mutex<Option<HashMap<DecodedKey, Decoded>>> = Mutex::new(None);

/// Width, height and the shared pixels of a decoded file.
type Decoded = (u32, u32, Weak<[[f32; 3]]>);

impl ImageTexture {
    /// Reads a PNG or JPEG (any format the `image` crate was built with),
    /// decoding its display-encoded values with the scene's transfer curve.
    pub fn load(path: &Path, transfer: Transfer, mapping: UvMapping) -> Result<Self, ImageError> {
        // A device or pipe would be read forever; a folder gives a poor message.
        let meta = std::fs::metadata(path).map_err(|e| ImageError::Io(e.to_string()))?;
        if !meta.is_file() {
            return Err(ImageError::Io("it is not a regular file".into()));
        }
        let key: DecodedKey = (
            path.canonicalize().unwrap_or_else(|_| path.to_owned()),
            meta.len(),
            meta.modified().ok(),
            format!("{transfer:?}"),
        );
        let mut cache = DECODED.lock().unwrap_or_else(|e| e.into_inner());
        let cache = cache.get_or_insert_with(HashMap::new);
        cache.retain(|_, (_, _, w)| w.strong_count() > 0);
        if let Some((width, height, pixels)) = cache
            .get(&key)
            .and_then(|(w, h, p)| Some((*w, *h, p.upgrade()?)))
        {
            return Ok(ImageTexture {
                width,
                height,
                pixels,
                mapping,
            });
        }
        let img = Self::decode(path, transfer, mapping)?;
        cache.insert(key, (img.width, img.height, Arc::downgrade(&img.pixels)));
        Ok(img)
    }

    /// Decodes a file's pixels ([`formats::image`]) to linear colour:
    /// display-encoded values through the scene's transfer curve.
    fn decode(path: &Path, transfer: Transfer, mapping: UvMapping) -> Result<Self, ImageError> {
        match formats::image::decode(path)? {
            Pixels::Linear(img) => Ok(ImageTexture {
                width: img.width(),
                height: img.height(),
                pixels: img.pixels().map(|p| p.0).collect(),
                mapping,
            }),
            Pixels::Encoded(img) => Ok(Self::from_rgb8(&img, transfer, mapping)),
        }
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

    /// Issue 17: a small file whose header declares 16384×16384 (268
    /// megapixels) or 12000×12000 was decoded (gigabytes, tens of seconds).
    /// The header is read first and the pixel budget refuses it at once.
    #[test]
    fn a_header_over_the_pixel_budget_is_refused_before_decoding() {
        let dir = tempfile::tempdir().unwrap();
        for (w, h) in [(16384, 16384), (12000, 12000), (16384, 2049)] {
            let p = dir.path().join(format!("{w}x{h}.ppm"));
            std::fs::write(&p, format!("P6\n{w} {h}\n255\n\0\0\0")).unwrap();
            let start = std::time::Instant::now();
            let r = ImageTexture::load(&p, Transfer::Srgb, UvMapping::default());
            assert!(
                matches!(r, Err(ImageError::TooLarge { width, height, .. }) if (width, height) == (w, h)),
                "{r:?}"
            );
            assert!(start.elapsed().as_secs_f64() < 1.0);
        }
        // Within the budget, a truncated file is a decode error, not a
        // budget one: the check is the product, not the side.
        let p = dir.path().join("ok.ppm");
        std::fs::write(&p, "P6\n8192 4096\n255\n\0\0\0").unwrap();
        let r = ImageTexture::load(&p, Transfer::Srgb, UvMapping::default());
        assert!(matches!(r, Err(ImageError::Decode(_))), "{r:?}");
    }

    /// Issue 17: one file used by many materials is decoded once; a changed
    /// transfer curve or an edited file is decoded afresh.
    #[test]
    fn each_image_file_is_decoded_once() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("once.png");
        two_by_two().save(&p).unwrap();
        let a = ImageTexture::load(&p, Transfer::Srgb, UvMapping::default()).unwrap();
        let mapping = UvMapping {
            flip_u: true,
            ..UvMapping::default()
        };
        let b = ImageTexture::load(&p, Transfer::Srgb, mapping.clone()).unwrap();
        assert!(Arc::ptr_eq(&a.pixels, &b.pixels));
        assert_eq!(b.mapping, mapping);
        let c = ImageTexture::load(&p, Transfer::Linear, UvMapping::default()).unwrap();
        assert!(!Arc::ptr_eq(&a.pixels, &c.pixels));
        // Once no texture holds the pixels, they are freed, and a later
        // load decodes again.
        let weak = Arc::downgrade(&a.pixels);
        drop((a, b));
        assert!(weak.upgrade().is_none());
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

    /// A 4×3 picture, each pixel's channels distinct, linear: pixel (i, j)
    /// (column, row from the top) is (10 + 40i + 7j, 20j + 3i, 200 − 30i − 50j)/255.
    /// Three rows, so that the row above and the row below differ.
    fn four_by_three() -> ImageTexture {
        let mut img = image::RgbImage::new(4, 3);
        for i in 0..4u8 {
            for j in 0..3u8 {
                img.put_pixel(
                    i as u32,
                    j as u32,
                    image::Rgb([10 + 40 * i + 7 * j, 20 * j + 3 * i, 200 - 30 * i - 50 * j]),
                );
            }
        }
        ImageTexture::from_rgb8(&img, Transfer::Linear, UvMapping::default())
    }

    fn pixel(i: i64, j: i64) -> Colour {
        let (i, j) = (i.rem_euclid(4) as f64, j.rem_euclid(3) as f64);
        Colour::new(
            (10.0 + 40.0 * i + 7.0 * j) / 255.0,
            (20.0 * j + 3.0 * i) / 255.0,
            (200.0 - 30.0 * i - 50.0 * j) / 255.0,
        )
    }

    /// Pixel (i, j) has its centre at u = (i + ½)/w, v = 1 − (j + ½)/h on
    /// a picture that is not square; halfway between two centres is their
    /// mean (bilinear), and the picture repeats in u and v (wrapping
    /// across its edges too).
    #[test]
    fn centres_bilinear_between_and_wrap_around_on_a_non_square_picture() {
        let t = four_by_three();
        let centre = |i: f64, j: f64| DVec2::new((i + 0.5) / 4.0, 1.0 - (j + 0.5) / 3.0);
        let near = |a: Colour, b: Colour| (a - b).abs().max_element() < 1e-6;
        for i in -4..8 {
            for j in -3..6 {
                let (fi, fj) = (i as f64, j as f64);
                let c = t.sample(centre(fi, fj));
                assert!(near(c, pixel(i, j)), "({i}, {j}): {c}");
                let right = t.sample(centre(fi + 0.5, fj));
                let want = (pixel(i, j) + pixel(i + 1, j)) / 2.0;
                assert!(near(right, want), "right of ({i}, {j}): {right} vs {want}");
                let below = t.sample(centre(fi, fj + 0.5));
                let want = (pixel(i, j) + pixel(i, j + 1)) / 2.0;
                assert!(near(below, want), "below ({i}, {j}): {below} vs {want}");
                let quarter = t.sample(centre(fi + 0.25, fj + 0.75));
                let want = (pixel(i, j) * 0.75 + pixel(i + 1, j) * 0.25) * 0.25
                    + (pixel(i, j + 1) * 0.75 + pixel(i + 1, j + 1) * 0.25) * 0.75;
                assert!(
                    near(quarter, want),
                    "({i}, {j}) + ¼, ¾: {quarter} vs {want}"
                );
            }
        }
    }

    /// swap, then flip_u / flip_v (s → 1 − s), then scale, then offset:
    /// the mapped texture at (u, v) is the plain one at the mapped point.
    #[test]
    fn mapping_is_swap_then_flips_then_scale_then_offset() {
        let plain = four_by_three();
        for swap in [false, true] {
            for flip_u in [false, true] {
                for flip_v in [false, true] {
                    let mapping = UvMapping {
                        scale: DVec2::new(2.0, 3.0),
                        offset: DVec2::new(0.1, -0.35),
                        swap,
                        flip_u,
                        flip_v,
                    };
                    let t = ImageTexture {
                        mapping: mapping.clone(),
                        ..plain.clone()
                    };
                    for k in 0..50 {
                        let uv = DVec2::new(0.037 * k as f64 - 0.4, (0.3 * k as f64).sin());
                        let mut q = if swap { DVec2::new(uv.y, uv.x) } else { uv };
                        if flip_u {
                            q.x = 1.0 - q.x;
                        }
                        if flip_v {
                            q.y = 1.0 - q.y;
                        }
                        let q = q * mapping.scale + mapping.offset;
                        let (got, want) = (t.sample(uv), plain.sample(q));
                        assert!(
                            (got - want).abs().max_element() < 1e-6,
                            "{mapping:?} at {uv}: {got} vs {want}"
                        );
                    }
                }
            }
        }
    }

    /// A point that is not finite (a NaN or infinite uv) shows nothing.
    #[test]
    fn a_point_that_is_not_finite_is_black() {
        let t = four_by_three();
        for uv in [
            DVec2::new(f64::NAN, 0.5),
            DVec2::new(0.5, f64::INFINITY),
            DVec2::new(f64::NEG_INFINITY, 0.2),
        ] {
            assert_eq!(t.sample(uv), Colour::ZERO, "{uv}");
        }
    }

    /// A load sweeps out the cache entries no texture holds any more: their
    /// `Weak` would keep the pixels' allocation alive (an `Arc<[T]>`'s
    /// memory goes only with its last weak pointer).
    #[test]
    fn a_load_forgets_files_no_texture_holds() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
        two_by_two().save(&a).unwrap();
        two_by_two().save(&b).unwrap();
        let a = a.canonicalize().unwrap();
        let held = |p: &Path| {
            let cache = DECODED.lock().unwrap_or_else(|e| e.into_inner());
            cache.as_ref().is_some_and(|c| c.keys().any(|k| k.0 == p))
        };
        let t = ImageTexture::load(&a, Transfer::Linear, UvMapping::default()).unwrap();
        assert!(held(&a));
        drop(t);
        let _b = ImageTexture::load(&b, Transfer::Linear, UvMapping::default()).unwrap();
        assert!(!held(&a), "a's entry outlived its pixels");
    }
}
