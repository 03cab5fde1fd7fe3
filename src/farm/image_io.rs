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

/// A PNG of `img`, with its offset and stamp when it has one (a region).
/// Every 8-bit PNG is written here: fast deflate after the Paeth filter
/// on every row, not the adaptive choice of five filters per row (a third
/// less time, and smaller files on every benchmark picture but one, 0.6%
/// larger there).
pub fn write_png(
    img: &image::RgbImage,
    stamp: Option<&Stamp>,
    out: impl Write,
) -> Result<(), Error> {
    let mut enc = png::Encoder::new(out, img.width(), img.height());
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    enc.set_filter(png::Filter::Paeth);
    if let Some(stamp) = stamp {
        enc.add_text_chunk(KEY.to_string(), stamp.to_text())?;
    }
    let mut writer = enc.write_header()?;
    if let Some(stamp) = stamp {
        // oFFs: x and y as signed 32-bit big-endian, then unit 0 (pixels).
        let mut offs = Vec::with_capacity(9);
        offs.extend_from_slice(&(stamp.region.x as i32).to_be_bytes());
        offs.extend_from_slice(&(stamp.region.y as i32).to_be_bytes());
        offs.push(0);
        writer.write_chunk(png::chunk::ChunkType(*b"oFFs"), &offs)?;
    }
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
    // As an EXR's data window must: merge copies the pixels to the
    // record's place, and they must fill exactly that rectangle.
    if let Some(s) = &stamp {
        let r = s.region;
        if (img.width(), img.height()) != (r.width, r.height) {
            return Err(format!(
                "its {}x{} pixels disagree with its record's region {},{},{},{}",
                img.width(),
                img.height(),
                r.x,
                r.y,
                r.width,
                r.height
            ));
        }
    }
    Ok(Tile {
        pixels: Pixels::Rgb8(img.to_rgb8()),
        stamp,
    })
}

fn read_exr(path: &Path) -> Result<Tile, String> {
    use exr::prelude::*;
    // The header first: a file that claims a huge picture is refused
    // before its pixels are given memory.
    let meta = exr::meta::MetaData::read_from_file(path, false).map_err(|e| e.to_string())?;
    for h in &meta.headers {
        let (w, ht) = (h.layer_size.width() as u64, h.layer_size.height() as u64);
        if w > crate::cli::MAX_SIDE as u64
            || ht > crate::cli::MAX_SIDE as u64
            || w * ht > crate::MAX_PIXELS
        {
            return Err(format!(
                "its {w}x{ht} pixels are more than a render can have (at most {} on a side, {} in all)",
                crate::cli::MAX_SIDE,
                crate::MAX_PIXELS
            ));
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Region;

    fn stamp(x: u32, y: u32, w: u32, h: u32) -> Stamp {
        Stamp {
            full_width: 40,
            full_height: 30,
            region: Region {
                x,
                y,
                width: w,
                height: h,
            },
            scene: 1,
            frame: 2,
            clock: 0.5,
            transfer: crate::scene::Transfer::Srgb,
        }
    }

    #[test]
    fn an_exr_tile_reads_back_with_its_place_and_record() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.exr");
        let img = image::Rgb32FImage::from_fn(7, 5, |x, y| image::Rgb([x as f32, y as f32, 0.25]));
        let s = stamp(30, 20, 7, 5);
        write_exr(&img, Some(&s), std::fs::File::create(&p).unwrap()).unwrap();
        let t = read_tile(&p).unwrap();
        assert_eq!(t.stamp, Some(s));
        let Pixels::Float(back) = t.pixels else {
            panic!("an EXR reads as float")
        };
        assert_eq!(back, img);
        // The same pixels make the same bytes, every time.
        let q = dir.path().join("u.exr");
        write_exr(
            &img,
            Some(&stamp(30, 20, 7, 5)),
            std::fs::File::create(&q).unwrap(),
        )
        .unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), std::fs::read(&q).unwrap());
    }

    #[test]
    fn a_png_tile_reads_back_with_its_record() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.png");
        let img = image::RgbImage::from_fn(4, 3, |x, y| image::Rgb([x as u8, y as u8, 9]));
        let s = stamp(1, 2, 4, 3);
        write_png(&img, Some(&s), std::fs::File::create(&p).unwrap()).unwrap();
        let t = read_tile(&p).unwrap();
        assert_eq!(t.stamp, Some(s));
        let Pixels::Rgb8(back) = t.pixels else {
            panic!("a PNG reads as 8-bit")
        };
        assert_eq!(back, img);
        assert!(read_tile(&dir.path().join("t.jpg")).is_err());
        // A record whose region is not the picture's size is refused (merge
        // would copy the pixels outside their place).
        let q = dir.path().join("wrong.png");
        write_png(
            &img,
            Some(&stamp(1, 2, 3, 3)),
            std::fs::File::create(&q).unwrap(),
        )
        .unwrap();
        let e = read_tile(&q).err().unwrap();
        assert!(
            e.contains("4x3 pixels disagree") && e.contains("1,2,3,3"),
            "{e}"
        );
    }

    #[test]
    fn an_exr_claiming_a_huge_picture_is_refused_before_reading_it() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.exr");
        let img = image::Rgb32FImage::new(2, 2);
        write_exr(&img, None, std::fs::File::create(&p).unwrap()).unwrap();
        // Patch the data window's max corner (two i32 after the min) to
        // claim 70000 x 70000 pixels.
        let mut bytes = std::fs::read(&p).unwrap();
        let at = bytes.windows(10).position(|w| w == b"dataWindow").unwrap();
        let values = at + b"dataWindow\0box2i\0".len() + 4;
        bytes[values + 8..values + 12].copy_from_slice(&69_999i32.to_le_bytes());
        bytes[values + 12..values + 16].copy_from_slice(&69_999i32.to_le_bytes());
        std::fs::write(&p, bytes).unwrap();
        let e = read_tile(&p).err().unwrap();
        assert!(e.contains("more than a render can have"), "{e}");
    }
}
