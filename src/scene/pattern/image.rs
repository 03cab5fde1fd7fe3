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
