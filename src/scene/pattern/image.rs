//! `image "file.png" { a …  b … }` or with a `colour_map`: a picture on
//! the shape's (u, v) used as a pattern, its value the pixel's luminance
//! 0.2126 r + 0.7152 g + 0.0722 b (linear, clamped to [0, 1]); a height
//! map, a mask for a material pattern. Without a map the image is the
//! colour itself (see `texture::ImageTexture`).

use super::super::texture::ImageTexture;
use crate::geometry::DVec2;
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub struct ImagePattern {
    pub image: Arc<ImageTexture>,
}

impl ImagePattern {
    pub fn value(&self, uv: DVec2) -> f64 {
        let c = self.image.sample(uv);
        0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Transfer;

    fn one_pixel(rgb: [u8; 3]) -> ImagePattern {
        let mut img = image::RgbImage::new(1, 1);
        img.put_pixel(0, 0, image::Rgb(rgb));
        ImagePattern {
            image: Arc::new(ImageTexture::from_rgb8(
                &img,
                Transfer::Linear,
                Default::default(),
            )),
        }
    }

    /// The value is the luminance 0.2126 r + 0.7152 g + 0.0722 b: each
    /// primary gives its own weight, white 1, black 0, mixtures the sums.
    #[test]
    fn the_value_is_the_pixels_luminance() {
        let uv = DVec2::new(0.3, 0.8);
        let near = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(near(one_pixel([255, 0, 0]).value(uv), 0.2126));
        assert!(near(one_pixel([0, 255, 0]).value(uv), 0.7152));
        assert!(near(one_pixel([0, 0, 255]).value(uv), 0.0722));
        assert!(near(one_pixel([255, 255, 0]).value(uv), 0.9278));
        assert!(near(one_pixel([0, 255, 255]).value(uv), 0.7874));
        assert!(near(one_pixel([255, 0, 255]).value(uv), 0.2848));
        assert!(near(one_pixel([255, 255, 255]).value(uv), 1.0));
        assert_eq!(one_pixel([0, 0, 0]).value(uv), 0.0);
    }
}
