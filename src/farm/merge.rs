//! `raytrace merge TILES... -o full.png`: puts the tiles of a picture back
//! together, or with `--average` takes the mean of sub-frame EXRs.
//!
//! ```text
//! raytrace merge tile_*.png -o full.png
//! raytrace merge tile_*.exr -o full.exr
//! raytrace merge --average sub_*.exr -o blurred.exr
//! ```
//!
//! Before writing anything it checks that the tiles came from one scene
//! with the same settings, frame and clock (their records, see `stamp`)
//! and cover the picture exactly once; otherwise it names the tiles that
//! overlap and where, or the pixels no tile holds. The merged picture is
//! written by the same encoder as a full render, so it is that render byte
//! for byte. EXR tiles merge into any format (the transfer curve is in
//! their records); PNG tiles hold 8-bit colour and merge into 8-bit
//! formats only.

use super::image_io::{Tile, read_tile};
use super::stamp::Stamp;
use crate::cli::{Exit, Failure};
use crate::output::{Format, Pixels, Target};
use crate::render::Region;
use clap::Parser;
use std::path::PathBuf;

const AFTER_HELP: &str = "\
Exit status:
  0    the merged image was written
  2    the tiles do not make one picture (a gap, an overlap, different
       scenes, settings or frames, a file that is not a raytrace tile)
  3    a tile cannot be read or the output cannot be written";

/// Assemble tiles (from --tile or --region) into the full picture, or
/// average sub-frame EXRs.
#[derive(Parser, Debug, Clone)]
#[command(name = "raytrace merge", bin_name = "raytrace merge", after_help = AFTER_HELP)]
pub struct MergeArgs {
    /// The tiles: PNG or EXR images written with --tile or --region.
    #[arg(required = true)]
    pub tiles: Vec<PathBuf>,

    /// The merged image; the extension picks the format.
    #[arg(short, long)]
    pub output: PathBuf,

    /// Average the inputs (EXR images of the same size and place, e.g.
    /// one frame at several clocks) instead of placing them side by side.
    #[arg(long)]
    pub average: bool,

    /// Print nothing on success.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `raytrace merge ...` from the process's own arguments.
pub fn merge_main() -> std::process::ExitCode {
    let args = MergeArgs::parse_from(std::env::args().skip(1));
    match merge(&args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("{:?}", failure.report);
            std::process::ExitCode::from(failure.exit as u8)
        }
    }
}

fn mismatch(text: String, help: &str) -> Failure {
    Failure::usage(miette::miette!(help = help.to_string(), "{text}"))
}

/// A tile read back, with its name for messages.
struct Named {
    path: PathBuf,
    tile: Tile,
}

impl Named {
    fn name(&self) -> String {
        self.path.display().to_string()
    }

    fn stamp(&self) -> Result<&Stamp, Failure> {
        self.tile.stamp.as_ref().ok_or_else(|| {
            mismatch(
                format!("`{}` has no raytrace tile record", self.name()),
                "merge takes the images `raytrace --tile I/N` or `--region` writes (.png or .exr)",
            )
        })
    }

    fn size(&self) -> (u32, u32) {
        match &self.tile.pixels {
            Pixels::Rgb8(i) => i.dimensions(),
            Pixels::Float(i) => i.dimensions(),
        }
    }
}

/// Reads, checks and writes; the whole of `raytrace merge`.
pub fn merge(args: &MergeArgs) -> Result<(), Failure> {
    let format = Format::from_path(&args.output).map_err(Failure::output)?;
    let tiles = args
        .tiles
        .iter()
        .map(|p| {
            let tile = read_tile(p).map_err(|e| {
                let exit = if p.is_file() {
                    Exit::Usage
                } else {
                    Exit::System
                };
                Failure {
                    exit,
                    report: miette::miette!("cannot read the tile `{}`: {e}", p.display()),
                }
            })?;
            Ok(Named {
                path: p.clone(),
                tile,
            })
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    let (pixels, full, stamp) = if args.average {
        average(&tiles, format)?
    } else {
        assemble(&tiles, format)?
    };
    let target =
        Target::prepare(&args.output, full.0, full.1, &args.tiles).map_err(Failure::output)?;
    target
        .write_pixels(&pixels, stamp.as_ref())
        .map_err(Failure::output)?;
    if !args.quiet {
        let (w, h) = match &pixels {
            Pixels::Rgb8(i) => i.dimensions(),
            Pixels::Float(i) => i.dimensions(),
        };
        let of = match &stamp {
            Some(_) => format!(" (a tile of the {}x{} picture)", full.0, full.1),
            None => String::new(),
        };
        eprintln!(
            "{}: {} {} into {w}x{h}{of}",
            args.output.display(),
            if args.average { "averaged" } else { "merged" },
            tiles.len(),
        );
    }
    Ok(())
}

/// The records must agree on everything but the region.
fn check_same_picture(tiles: &[Named]) -> Result<&Stamp, Failure> {
    let first = tiles[0].stamp()?;
    for t in &tiles[1..] {
        let s = t.stamp()?;
        let differ = |what: &str, a: String, b: String| {
            mismatch(
                format!(
                    "`{}` and `{}` are tiles of different pictures: {what} {a} and {b}",
                    tiles[0].name(),
                    t.name()
                ),
                "merge the tiles of one render: the same scene file, -D, --width, --height, \
                 --samples and frame",
            )
        };
        if (s.full_width, s.full_height) != (first.full_width, first.full_height) {
            return Err(differ(
                "sizes",
                format!("{}x{}", first.full_width, first.full_height),
                format!("{}x{}", s.full_width, s.full_height),
            ));
        }
        if s.scene != first.scene {
            return Err(differ(
                "scenes or settings",
                format!("{:016x}", first.scene),
                format!("{:016x}", s.scene),
            ));
        }
        if s.frame != first.frame || s.clock.to_bits() != first.clock.to_bits() {
            return Err(differ(
                "frames",
                format!("{} (clock {})", first.frame, first.clock),
                format!("{} (clock {})", s.frame, s.clock),
            ));
        }
        if s.transfer != first.transfer {
            return Err(differ(
                "transfer curves",
                format!("{:?}", first.transfer),
                format!("{:?}", s.transfer),
            ));
        }
    }
    Ok(first)
}

fn overlap(a: Region, b: Region) -> Option<Region> {
    let x0 = a.x.max(b.x);
    let y0 = a.y.max(b.y);
    let x1 = (a.x + a.width).min(b.x + b.width);
    let y1 = (a.y + a.height).min(b.y + b.height);
    (x0 < x1 && y0 < y1).then(|| Region {
        x: x0,
        y: y0,
        width: x1 - x0,
        height: y1 - y0,
    })
}

/// `x 24..48, y 16..32`
fn span(r: Region) -> String {
    format!(
        "x {}..{}, y {}..{} ({} pixels)",
        r.x,
        r.x + r.width,
        r.y,
        r.y + r.height,
        r.width as u64 * r.height as u64
    )
}

/// Every pixel in exactly one tile, or a message naming the overlap or the
/// gap.
fn check_cover(tiles: &[Named], w: u32, h: u32) -> Result<(), Failure> {
    let regions: Vec<Region> = tiles
        .iter()
        .map(|t| t.stamp().map(|s| s.region))
        .collect::<Result<_, _>>()?;
    for (i, a) in regions.iter().enumerate() {
        for (j, b) in regions.iter().enumerate().skip(i + 1) {
            if let Some(o) = overlap(*a, *b) {
                return Err(mismatch(
                    format!(
                        "the tiles `{}` and `{}` overlap at {}",
                        tiles[i].name(),
                        tiles[j].name(),
                        span(o)
                    ),
                    "each pixel must come from exactly one tile: drop the duplicate, or render \
                     the tiles with one --tile count",
                ));
            }
        }
    }
    // No overlaps: the tiles cover the picture when their areas add up.
    let covered: u64 = regions
        .iter()
        .map(|r| r.width as u64 * r.height as u64)
        .sum();
    let total = w as u64 * h as u64;
    if covered == total {
        return Ok(());
    }
    // The missing pixels' bounding box, found row by row.
    let mut missing = 0u64;
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    let mut row = vec![false; w as usize];
    for y in 0..h {
        row.fill(false);
        for r in regions.iter().filter(|r| y >= r.y && y < r.y + r.height) {
            row[r.x as usize..(r.x + r.width) as usize].fill(true);
        }
        for (x, _) in row.iter().enumerate().filter(|(_, c)| !**c) {
            missing += 1;
            (x0, y0) = (x0.min(x as u32), y0.min(y));
            (x1, y1) = (x1.max(x as u32 + 1), y1.max(y + 1));
        }
    }
    let bounds = Region {
        x: x0,
        y: y0,
        width: x1 - x0,
        height: y1 - y0,
    };
    let place = if missing == bounds.width as u64 * bounds.height as u64 {
        format!(
            "the rectangle {} is missing (a tile such as --region {},{},{},{})",
            span(bounds),
            x0,
            x1,
            y0,
            y1
        )
    } else {
        format!("{missing} pixels are missing, within {}", span(bounds))
    };
    Err(mismatch(
        format!(
            "the {} tiles leave a gap in the {w}x{h} picture: {place}",
            tiles.len()
        ),
        "render the missing tile and merge again",
    ))
}

type Merged = (Pixels, (u32, u32), Option<Stamp>);

fn assemble(tiles: &[Named], format: Format) -> Result<Merged, Failure> {
    let first = check_same_picture(tiles)?;
    let (w, h) = (first.full_width, first.full_height);
    for t in tiles {
        let r = t.stamp()?.region;
        if t.size() != (r.width, r.height) {
            return Err(mismatch(
                format!(
                    "`{}` is {}x{} but its record says {}x{}",
                    t.name(),
                    t.size().0,
                    t.size().1,
                    r.width,
                    r.height
                ),
                "the file was changed after raytrace wrote it",
            ));
        }
    }
    check_cover(tiles, w, h)?;
    let float = matches!(format, Format::Exr | Format::Hdr);
    let pixels = if float {
        let mut out = image::Rgb32FImage::new(w, h);
        for t in tiles {
            let Pixels::Float(img) = &t.tile.pixels else {
                return Err(mismatch(
                    format!(
                        "`{}` holds 8-bit colour, which cannot make a linear float image",
                        t.name()
                    ),
                    "merge PNG tiles into a .png (or render the tiles as .exr)",
                ));
            };
            let r = t.stamp()?.region;
            image::GenericImage::copy_from(&mut out, img, r.x, r.y).expect("checked to fit");
        }
        Pixels::Float(out)
    } else {
        let mut out = image::RgbImage::new(w, h);
        for t in tiles {
            let r = t.stamp()?.region;
            match &t.tile.pixels {
                Pixels::Rgb8(img) => {
                    image::GenericImage::copy_from(&mut out, img, r.x, r.y)
                        .expect("checked to fit");
                }
                Pixels::Float(img) => {
                    for (x, y, p) in img.enumerate_pixels() {
                        let q = p.0.map(|c| first.transfer.encode8(c as f64));
                        out.put_pixel(r.x + x, r.y + y, image::Rgb(q));
                    }
                }
            }
        }
        Pixels::Rgb8(out)
    };
    Ok((pixels, (w, h), None))
}

fn average(tiles: &[Named], format: Format) -> Result<Merged, Failure> {
    let size = tiles[0].size();
    let stamps: Vec<Option<&Stamp>> = tiles.iter().map(|t| t.tile.stamp.as_ref()).collect();
    let mut sum = vec![0f64; size.0 as usize * size.1 as usize * 3];
    for (t, s) in tiles.iter().zip(&stamps) {
        let Pixels::Float(img) = &t.tile.pixels else {
            return Err(mismatch(
                format!("`{}` holds 8-bit colour", t.name()),
                "--average takes linear .exr images: render the sub-frames as .exr",
            ));
        };
        if t.size() != size {
            return Err(mismatch(
                format!(
                    "`{}` is {}x{} but `{}` is {}x{}",
                    t.name(),
                    t.size().0,
                    t.size().1,
                    tiles[0].name(),
                    size.0,
                    size.1
                ),
                "--average takes images of one size and place",
            ));
        }
        if let (Some(a), Some(b)) = (stamps[0], s)
            && (a.scene != b.scene || a.region != b.region)
        {
            return Err(mismatch(
                format!(
                    "`{}` and `{}` are not the same picture at another moment (their scenes, \
                     settings or regions differ)",
                    tiles[0].name(),
                    t.name()
                ),
                "--average takes renders of one scene that differ only in clock and frame",
            ));
        }
        for (acc, v) in sum.iter_mut().zip(img.as_raw()) {
            *acc += *v as f64;
        }
    }
    let n = tiles.len() as f64;
    let mean: Vec<f32> = sum.iter().map(|s| (s / n) as f32).collect();
    let img = image::Rgb32FImage::from_raw(size.0, size.1, mean).expect("sized above");
    // A tile stays a tile (with its record), so averaged tiles can merge.
    let stamp = stamps[0].cloned().filter(|s| !s.is_full());
    let pixels = match format {
        Format::Exr | Format::Hdr => Pixels::Float(img),
        _ => {
            let Some(s) = stamps[0] else {
                return Err(mismatch(
                    "the images carry no transfer curve to make 8-bit colour with".into(),
                    "write the average to .exr",
                ));
            };
            let raw = img
                .as_raw()
                .iter()
                .map(|&c| s.transfer.encode8(c as f64))
                .collect();
            Pixels::Rgb8(image::RgbImage::from_raw(size.0, size.1, raw).expect("sized"))
        }
    };
    let full = stamp
        .as_ref()
        .map_or(size, |s| (s.full_width, s.full_height));
    Ok((pixels, full, stamp))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tile(name: &str, x: u32, y: u32, w: u32, h: u32) -> Named {
        Named {
            path: PathBuf::from(name),
            tile: Tile {
                pixels: Pixels::Rgb8(image::RgbImage::new(w, h)),
                stamp: Some(Stamp {
                    full_width: 48,
                    full_height: 32,
                    region: Region {
                        x,
                        y,
                        width: w,
                        height: h,
                    },
                    scene: 7,
                    frame: 0,
                    clock: 0.0,
                    transfer: crate::scene::Transfer::Srgb,
                }),
            },
        }
    }

    fn message(r: Result<(), Failure>) -> String {
        let f = r.unwrap_err();
        assert_eq!(f.exit, Exit::Usage);
        f.report.to_string()
    }

    #[test]
    fn a_cover_is_checked_exactly() {
        let quarters = || {
            vec![
                tile("a", 0, 0, 24, 16),
                tile("b", 24, 0, 24, 16),
                tile("c", 0, 16, 24, 16),
                tile("d", 24, 16, 24, 16),
            ]
        };
        assert!(check_cover(&quarters(), 48, 32).is_ok());
        // A missing quarter is named as the rectangle it is.
        let mut t = quarters();
        t.pop();
        let e = message(check_cover(&t, 48, 32));
        assert!(e.contains("x 24..48, y 16..32 (384 pixels)"), "{e}");
        assert!(e.contains("--region 24,48,16,32"), "{e}");
        // A ragged gap: its size and bounding box.
        let t = vec![
            tile("a", 0, 0, 48, 16),
            tile("c", 0, 16, 47, 16),
            tile("d", 47, 17, 1, 15),
        ];
        let e = message(check_cover(&t, 48, 32));
        assert!(e.contains("x 47..48, y 16..17 (1 pixels)"), "{e}");
        // An overlap names both tiles and the shared pixels.
        let mut t = quarters();
        t.push(tile("e", 20, 10, 8, 8));
        let e = message(check_cover(&t, 48, 32));
        assert!(
            e.contains("`a` and `e` overlap at x 20..24, y 10..16 (24 pixels)"),
            "{e}"
        );
    }

    #[test]
    fn tiles_of_other_pictures_are_refused() {
        let mut b = tile("b", 24, 0, 24, 32);
        b.tile.stamp.as_mut().unwrap().frame = 3;
        let e = check_same_picture(&[tile("a", 0, 0, 24, 32), b])
            .map(|_| ())
            .unwrap_err()
            .report
            .to_string();
        assert!(e.contains("different pictures: frames 0"), "{e}");
        let mut b = tile("b", 24, 0, 24, 32);
        b.tile.stamp.as_mut().unwrap().scene = 8;
        assert!(check_same_picture(&[tile("a", 0, 0, 24, 32), b]).is_err());
    }
}
