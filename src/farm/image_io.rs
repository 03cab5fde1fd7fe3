//! Reading and writing the images of regions and tiles.
//!
//! - EXR: linear float; the file's data window is the region and its
//!   display window the full picture, so any EXR reader places the tile
//!   where it belongs. Written with increasing line order, so that the same
//!   pixels give the same bytes whatever the encoder's threads did (the
//!   `exr` crate's default, "unspecified", writes chunks in the order its
//!   threads finish).
//! - PNG: 8-bit with the transfer curve; the offset is in an `oFFs` chunk
//!   (x and y in pixels, which GIMP and ImageMagick read) and the whole
//!   [`Stamp`] in a `tEXt` chunk.

use super::stamp::{KEY, Stamp};
use crate::output::Pixels;
use std::io::{Seek, Write};
use std::path::Path;

type Error = Box<dyn std::error::Error + Send + Sync>;

/// An EXR of `img`: at the stamp's region in its full picture, or the
/// whole picture when there is no stamp.
pub fn write_exr(
    img: &image::Rgb32FImage,
    stamp: Option<&Stamp>,
    out: impl Write + Seek,
) -> Result<(), Error> {
    use exr::prelude::*;
    let (w, h) = img.dimensions();
    let (x, y, full_w, full_h) = match stamp {
        Some(s) => (s.region.x, s.region.y, s.full_width, s.full_height),
        None => (0, 0, w, h),
    };
    let mut attributes = LayerAttributes {
        layer_position: Vec2(x as i32, y as i32),
        ..LayerAttributes::default()
    };
    // A layer's attribute: the `exr` crate reads unknown attributes back
    // into the layer.
    if let Some(s) = stamp {
        attributes.other.insert(
            Text::from(KEY),
            AttributeValue::Text(Text::from(s.to_text().as_str())),
        );
    }
    let encoding = Encoding {
        compression: Compression::RLE,
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
        let [r, g, b] = img.get_pixel(p.x() as u32, p.y() as u32).0;
        (r, g, b)
    });
    let layer = Layer::new((w as usize, h as usize), attributes, encoding, channels);
    let mut image = Image::from_layer(layer);
    image.attributes.display_window =
        IntegerBounds::new(Vec2(0, 0), Vec2(full_w as usize, full_h as usize));
    image.write().to_buffered(out)?;
    Ok(())
}

/// A PNG of `img` with its offset and stamp.
pub fn write_png(img: &image::RgbImage, stamp: &Stamp, out: impl Write) -> Result<(), Error> {
    let mut enc = png::Encoder::new(out, img.width(), img.height());
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.add_text_chunk(KEY.to_string(), stamp.to_text())?;
    let mut writer = enc.write_header()?;
    // oFFs: x and y as signed 32-bit big-endian, then unit 0 (pixels).
    let mut offs = Vec::with_capacity(9);
    offs.extend_from_slice(&(stamp.region.x as i32).to_be_bytes());
    offs.extend_from_slice(&(stamp.region.y as i32).to_be_bytes());
    offs.push(0);
    writer.write_chunk(png::chunk::ChunkType(*b"oFFs"), &offs)?;
    writer.write_image_data(img.as_raw())?;
    writer.finish()?;
    Ok(())
}

/// An image read back for merging: its pixels as its file holds them
/// (8-bit for PNG, linear float for EXR) and its record.
pub struct Tile {
    pub pixels: Pixels,
    pub stamp: Option<Stamp>,
}

/// Reads a PNG or EXR tile and its stamp; a message says what is wrong.
pub fn read_tile(path: &Path) -> Result<Tile, String> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => read_png(path),
        Some("exr") => read_exr(path),
        _ => Err("only .png and .exr tiles can be merged".into()),
    }
}

fn read_png(path: &Path) -> Result<Tile, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_ignore_text_chunk(false);
    let reader = decoder.read_info().map_err(|e| e.to_string())?;
    let stamp = reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .find(|t| t.keyword == KEY)
        .map(|t| Stamp::parse(&t.text))
        .transpose()?;
    drop(reader);
    let img = image::open(path).map_err(|e| e.to_string())?;
    if img.color() != image::ColorType::Rgb8 {
        return Err(format!(
            "it holds {:?} pixels, not the 8-bit RGB raytrace writes",
            img.color()
        ));
    }
    Ok(Tile {
        pixels: Pixels::Rgb8(img.to_rgb8()),
        stamp,
    })
}

fn read_exr(path: &Path) -> Result<Tile, String> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| (size, vec![0f32; size.area() * 3]),
            |(size, px): &mut (Vec2<usize>, Vec<f32>),
             p: Vec2<usize>,
             (r, g, b): (f32, f32, f32)| {
                let i = (p.y() * size.width() + p.x()) * 3;
                px[i..i + 3].copy_from_slice(&[r, g, b]);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| e.to_string())?;
    let stamp = match image.layer_data.attributes.other.get(&Text::from(KEY)) {
        Some(AttributeValue::Text(t)) => Some(Stamp::parse(&t.to_string())?),
        _ => None,
    };
    let layer = image.layer_data;
    let (size, data) = layer.channel_data.pixels;
    let window = (
        layer.attributes.layer_position.x() as i64
            - image.attributes.display_window.position.x() as i64,
        layer.attributes.layer_position.y() as i64
            - image.attributes.display_window.position.y() as i64,
        size.width() as i64,
        size.height() as i64,
    );
    if let Some(s) = &stamp {
        let r = s.region;
        if window != (r.x as i64, r.y as i64, r.width as i64, r.height as i64) {
            return Err(format!(
                "its data window {window:?} disagrees with its record's region {},{},{},{}",
                r.x, r.y, r.width, r.height
            ));
        }
    }
    let img = image::Rgb32FImage::from_raw(size.width() as u32, size.height() as u32, data)
        .ok_or("its pixels do not fill its data window")?;
    Ok(Tile {
        pixels: Pixels::Float(img),
        stamp,
    })
}
