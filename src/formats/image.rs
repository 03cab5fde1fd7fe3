//! Reading picture files (PNG, JPEG, EXR, HDR, PPM: whatever the `image`
//! crate was built with) for image textures: the header first, refused
//! when it is over the pixel budget before any pixel is allocated, then the
//! pixels under the crate's own allocation limits and the panic guard.
//! What the values mean (a transfer curve, wrapping, filtering) is the
//! texture's business (`scene::texture::image_map`).

use std::path::Path;

/// Why an image could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("cannot open the image: {0}")]
    Io(String),
    #[error("cannot decode the image: {0}")]
    Decode(String),
    #[error(
        "the image is {width}x{height}; textures are limited to {side}x{side} pixels and {} megapixels in all",
        MAX_TEXTURE_PIXELS / 1_000_000
    )]
    TooLarge { width: u32, height: u32, side: u32 },
}

/// Larger images are refused from their header, before their pixels are
/// allocated.
pub const MAX_TEXTURE_SIDE: u32 = 16384;
/// The pixel budget of one texture (an 8192×4096 picture fits): decoded
/// and converted to linear colour it takes 15 bytes a pixel, about 500 MB.
pub const MAX_TEXTURE_PIXELS: u64 = 1 << 25;

/// A file's pixels as stored: floating-point formats (EXR, Radiance HDR)
/// hold linear radiance, the rest display-encoded 8-bit values.
pub enum Pixels {
    Linear(image::Rgb32FImage),
    Encoded(image::RgbImage),
}

/// Reads the header, refuses what is over the pixel budget, then
/// decodes.
pub fn decode(path: &Path) -> Result<Pixels, ImageError> {
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
    if width > MAX_TEXTURE_SIDE
        || height > MAX_TEXTURE_SIDE
        || width as u64 * height as u64 > MAX_TEXTURE_PIXELS
    {
        return Err(ImageError::TooLarge {
            width,
            height,
            side: MAX_TEXTURE_SIDE,
        });
    }
    let mut reader = image::ImageReader::open(path)
        .map_err(|e| ImageError::Io(e.to_string()))?
        .with_guessed_format()
        .map_err(|e| ImageError::Io(e.to_string()))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    // Room for the largest image at 16 bits a channel with alpha; a
    // decoder that wants more than that is refused, not obeyed.
    limits.max_alloc = Some(MAX_TEXTURE_PIXELS * 8 + (64 << 20));
    reader.limits(limits);
    // The decoders are third-party code fed user bytes, and one has
    // panicked on a mangled palette (a fuzz find): a panic would take the
    // whole render down, so it is caught and reported as a bad file.
    let decoded = crate::guard::catch_quietly(|| reader.decode())
        .ok_or_else(|| ImageError::Decode("the file is malformed (the decoder gave up)".into()))?;
    let decoded = decoded.map_err(|e| ImageError::Decode(e.to_string()))?;
    // Floating-point images (EXR, Radiance HDR) hold linear radiance:
    // kept as they are, above 1 too (a sky's sun).
    if matches!(
        decoded,
        image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_)
    ) {
        return Ok(Pixels::Linear(decoded.to_rgb32f()));
    }
    Ok(Pixels::Encoded(decoded.to_rgb8()))
}
