//! Stage 5, WRITE: the film, encoded with the scene's transfer curve, into the
//! format the output file's extension names. The image goes to a temporary
//! file beside the target and is renamed over it only when complete, so an
//! error, a crash or Ctrl-C never leaves a partial file or destroys an
//! existing one.
//!
//! Everything that can be known about the output is checked before the
//! first ray ([`Target::prepare`]): the format, the size the format can
//! hold, the name's length, that it names none of the scene's own files,
//! and, by creating the temporary file there, that the folder exists and
//! is writable. A render is never thrown away for want of a place to put it.

use crate::farm::stamp::Stamp;
use crate::render::Film;
use crate::scene::Transfer;
use miette::Diagnostic;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use thiserror::Error;

/// The temporary file being written, if any, for [`remove_pending`] to
/// delete when the program is interrupted mid-write.
static PENDING: Mutex<Option<PathBuf>> = Mutex::new(None);

fn set_pending(p: Option<PathBuf>) {
    // A poisoned lock only means a panic elsewhere; the path is still good.
    *PENDING.lock().unwrap_or_else(|e| e.into_inner()) = p;
}

/// Deletes the temporary file of a write in progress. The binary's Ctrl-C
/// and SIGTERM handler calls it before exiting, so an interrupted write
/// leaves neither a partial image nor a stray temporary; the target is
/// untouched because the rename had not happened.
pub fn remove_pending() {
    if let Some(p) = PENDING.lock().unwrap_or_else(|e| e.into_inner()).take() {
        let _ = std::fs::remove_file(p);
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Jpeg,
    /// OpenEXR: linear floating point, no transfer curve.
    Exr,
    /// Radiance HDR: linear floating point, no transfer curve.
    Hdr,
    /// Binary PPM (P6).
    Ppm,
}

#[derive(Debug, Error, Diagnostic)]
pub enum OutputError {
    #[error("cannot tell the image format of `{}`", .0.display())]
    #[diagnostic(
        code(output::unknown_format),
        help("use one of the extensions .png, .jpg, .jpeg, .exr, .hdr, .ppm")
    )]
    UnknownFormat(PathBuf),
    #[error("`{}` is a directory, not an image file", .0.display())]
    #[diagnostic(code(output::is_directory))]
    IsDirectory(PathBuf),
    #[error("cannot write `{}`: {reason}", path.display())]
    #[diagnostic(code(output::write))]
    Write { path: PathBuf, reason: String },
    #[error("the output `{}` is the scene's own file `{}`", path.display(), input.display())]
    #[diagnostic(
        code(output::is_input),
        help("writing the image there would destroy it; choose another output name")
    )]
    IsInput { path: PathBuf, input: PathBuf },
    #[error("the output file name is {len} bytes long; the limit is {NAME_MAX} bytes")]
    #[diagnostic(code(output::name_too_long))]
    NameTooLong { len: usize },
    #[error("a {format} image can be at most {max}x{max} pixels; this one is {width}x{height}")]
    #[diagnostic(
        code(output::too_large_for_format),
        help("choose a smaller --width/--height, or write .png, .exr or .hdr")
    )]
    TooLargeForFormat {
        format: &'static str,
        max: u32,
        width: u32,
        height: u32,
    },
}

impl OutputError {
    /// Whether the mistake is in the command line (rather than the system
    /// refusing a well-formed request).
    pub fn is_usage(&self) -> bool {
        !matches!(self, OutputError::Write { .. })
    }
}

/// The longest file name (one path component) Linux and macOS accept.
pub const NAME_MAX: usize = 255;

/// The widest and tallest JPEG: its header stores each side in 16 bits.
pub const JPEG_MAX_SIDE: u32 = 65_535;

impl Format {
    /// The format named by the path's extension; checked before rendering
    /// starts so that a typo costs nothing.
    pub fn from_path(path: &Path) -> Result<Format, OutputError> {
        if path.is_dir() {
            return Err(OutputError::IsDirectory(path.to_owned()));
        }
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("jpg" | "jpeg") => Ok(Format::Jpeg),
            Some("exr") => Ok(Format::Exr),
            Some("hdr") => Ok(Format::Hdr),
            Some("ppm") => Ok(Format::Ppm),
            _ => Err(OutputError::UnknownFormat(path.to_owned())),
        }
    }

    fn image_format(self) -> image::ImageFormat {
        match self {
            Format::Png => image::ImageFormat::Png,
            Format::Jpeg => image::ImageFormat::Jpeg,
            Format::Exr => image::ImageFormat::OpenExr,
            Format::Hdr => image::ImageFormat::Hdr,
            Format::Ppm => image::ImageFormat::Pnm,
        }
    }

    /// The largest side this format can store, where it is smaller than
    /// the command line's own limit.
    fn max_side(self) -> Option<(&'static str, u32)> {
        match self {
            Format::Jpeg => Some(("JPEG", JPEG_MAX_SIDE)),
            _ => None,
        }
    }
}

/// The output file, checked before rendering (its folder has been shown
/// writable by creating the temporary file there once).
#[derive(Debug)]
pub struct Target {
    path: PathBuf,
    format: Format,
    tmp: PathBuf,
}

impl Target {
    /// Checks everything about writing a `width`×`height` image to `path`
    /// that can be checked without the picture; `inputs` are the files the
    /// scene reads, which the output must not overwrite, by any spelling.
    pub fn prepare(
        path: &Path,
        width: u32,
        height: u32,
        inputs: &[PathBuf],
    ) -> Result<Target, OutputError> {
        let format = Format::from_path(path)?;
        let name = path.file_name().map_or(0, |n| n.len());
        if name > NAME_MAX {
            return Err(OutputError::NameTooLong { len: name });
        }
        if let Some((format, max)) = format.max_side()
            && (width > max || height > max)
        {
            return Err(OutputError::TooLargeForFormat {
                format,
                max,
                width,
                height,
            });
        }
        if let Some(input) = inputs.iter().find(|i| same_file(path, i)) {
            return Err(OutputError::IsInput {
                path: path.to_owned(),
                input: input.clone(),
            });
        }
        Target::claim(path, format)
    }

    /// Tries the temporary file beside `path`: created, so the folder is
    /// known to exist and be writable, then removed again at once, so that
    /// a render killed by SIGKILL (which no handler sees) leaves nothing.
    /// Its name is short and fixed in length, so any target name the
    /// system accepts has a temporary it accepts too.
    fn claim(path: &Path, format: Format) -> Result<Target, OutputError> {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
            _ => PathBuf::from("."),
        };
        let tmp = dir.join(format!(".raytrace-{}.tmp", std::process::id()));
        set_pending(Some(tmp.clone()));
        let created = std::fs::File::create(&tmp);
        let _ = std::fs::remove_file(&tmp);
        set_pending(None);
        if let Err(e) = created {
            let reason = match e.kind() {
                std::io::ErrorKind::NotFound => {
                    format!("the folder `{}` does not exist", dir.display())
                }
                std::io::ErrorKind::PermissionDenied => {
                    format!("no permission to create files in `{}`", dir.display())
                }
                _ => format!("cannot create a file in `{}`: {e}", dir.display()),
            };
            return Err(OutputError::Write {
                path: path.to_owned(),
                reason,
            });
        }
        Ok(Target {
            path: path.to_owned(),
            format,
            tmp,
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Encodes the film into the temporary file and renames it over the
    /// target.
    pub fn write(self, film: &Film, transfer: Transfer) -> Result<(), OutputError> {
        self.write_stamped(film, transfer, None)
    }

    /// As [`Target::write`], for a region of a picture: a PNG records the
    /// stamp and offset, an EXR its data window in the full picture (see
    /// `farm::image_io`). Other formats hold just the region's pixels.
    pub fn write_stamped(
        self,
        film: &Film,
        transfer: Transfer,
        stamp: Option<&Stamp>,
    ) -> Result<(), OutputError> {
        let pixels = Pixels::of_film(film, self.format, transfer);
        self.write_pixels(&pixels, stamp)
    }

    /// Writes pixels already encoded for this target's format (those of
    /// [`Pixels::of_film`], or merged tiles).
    pub fn write_pixels(self, pixels: &Pixels, stamp: Option<&Stamp>) -> Result<(), OutputError> {
        self.write_with(pixels, stamp, |t| std::fs::File::create(t))
    }

    pub fn format(&self) -> Format {
        self.format
    }

    fn write_with<S: Sink>(
        self,
        pixels: &Pixels,
        stamp: Option<&Stamp>,
        create: impl FnOnce(&Path) -> std::io::Result<S>,
    ) -> Result<(), OutputError> {
        write_through(pixels, stamp, &self.path, &self.tmp, self.format, create)
    }
}

/// An image ready for its encoder: 8-bit colour after the transfer curve
/// (PNG, JPEG, PPM) or linear float (EXR, HDR).
pub enum Pixels {
    Rgb8(image::RgbImage),
    Float(image::Rgb32FImage),
}

impl Pixels {
    pub fn of_film(film: &Film, format: Format, transfer: Transfer) -> Pixels {
        match format {
            Format::Exr | Format::Hdr => Pixels::Float(to_rgb32f(film)),
            _ => Pixels::Rgb8(to_rgb8(film, transfer)),
        }
    }
}

impl Drop for Target {
    fn drop(&mut self) {
        // After a successful rename the temporary is gone and this fails
        // quietly; after a failed render it removes the empty claim.
        let _ = std::fs::remove_file(&self.tmp);
        set_pending(None);
    }
}

/// Whether `out` names the same file as `input`: the same inode where the
/// output exists (hard links, symbolic links, `./`, `..`), else never (an
/// input exists).
fn same_file(out: &Path, input: &Path) -> bool {
    let (Ok(a), Ok(b)) = (std::fs::metadata(out), std::fs::metadata(input)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        a.dev() == b.dev() && a.ino() == b.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (a, b);
        matches!((out.canonicalize(), input.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
}

/// The deepest cause's words: an encoder wraps the disk's "No space left
/// on device" in its own error, whose text can mislead ("decoding").
fn reason(e: &(dyn std::error::Error + 'static)) -> String {
    let mut cur: &(dyn std::error::Error + 'static) = e;
    let mut io = None;
    loop {
        if let Some(x) = cur.downcast_ref::<std::io::Error>() {
            io = Some(x);
        }
        match cur.source() {
            Some(next) => cur = next,
            None => break,
        }
    }
    // Some encoders (OpenEXR's) keep only the words of the system's error,
    // inside their own "Format error decoding …": take its number back.
    let text = e.to_string();
    let code = io.and_then(std::io::Error::raw_os_error).or_else(|| {
        let n = text.split("(os error ").nth(1)?;
        n[..n.find(')')?].parse().ok()
    });
    match (code, io) {
        (Some(28), _) => "No space left on device (the disk is full)".into(),
        (_, Some(x)) => x.to_string(),
        (Some(c), None) => std::io::Error::from_raw_os_error(c).to_string(),
        (None, None) => text,
    }
}

/// Encodes the film as 8-bit RGB with the transfer curve, rows in
/// parallel on the current rayon pool (the render's, sized by
/// `--threads`): three transfer curves per pixel are a few per cent of a
/// one-sample picture's time.
pub fn to_rgb8(film: &Film, transfer: Transfer) -> image::RgbImage {
    use rayon::prelude::*;
    let mut bytes = vec![0u8; film.pixels.len() * 3];
    let row = (film.width as usize).max(1);
    bytes
        .par_chunks_mut(3 * row)
        .zip(film.pixels.par_chunks(row))
        .for_each(|(out, pixels)| {
            let values = pixels.as_flattened();
            match transfer {
                // The linear curve (the benchmarks' `gamma linear`) as
                // plain arithmetic the compiler vectorises: the general
                // route was a third of writing a 1000 × 1000 picture.
                Transfer::Linear => {
                    for (o, &c) in out.iter_mut().zip(values) {
                        *o = linear8(c);
                    }
                }
                t => {
                    for (o, &c) in out.iter_mut().zip(values) {
                        *o = t.encode8(c as f64);
                    }
                }
            }
        });
    image::RgbImage::from_raw(film.width, film.height, bytes)
        .expect("film holds width × height pixels")
}

/// `Transfer::Linear.encode8(c)`: NaN and below 0 to 0, above 1 to 255,
/// else 255c rounded half away from zero, as the truncation and its exact
/// fraction. `f64::max` and `min` pass over a NaN, so the values stay in
/// [0, 255], where the unchecked conversion is one instruction for every
/// lane (`as i32` adds a NaN and range fix-up to each, unvectorised).
#[inline(always)]
#[allow(clippy::manual_clamp)] // `clamp` keeps a NaN, which this must not
fn linear8(c: f32) -> u8 {
    let v = (c as f64).max(0.0).min(1.0) * 255.0;
    // SAFETY: v is finite and in [0, 255] (see above), so it fits.
    let t = unsafe { v.to_int_unchecked::<i32>() };
    let up = (v - t as f64 >= 0.5) as i32;
    (t + up) as u8
}

fn to_rgb32f(film: &Film) -> image::Rgb32FImage {
    let data = film
        .pixels
        .iter()
        .flat_map(|p| p.map(|c| if c.is_finite() { c.max(0.0) } else { 0.0 }))
        .collect();
    image::Rgb32FImage::from_raw(film.width, film.height, data)
        .expect("film holds width × height pixels")
}

/// Writes the image to `path` through a temporary file and a rename.
pub fn write(
    film: &Film,
    path: &Path,
    format: Format,
    transfer: Transfer,
) -> Result<(), OutputError> {
    Target::claim(path, format)?.write(film, transfer)
}

/// Where the encoder writes: a file that can be flushed to the disk before
/// the rename makes it visible. Tests substitute a file whose disk fills up.
trait Sink: std::io::Write + std::io::Seek {
    fn sync(&self) -> std::io::Result<()>;
}

impl Sink for std::fs::File {
    fn sync(&self) -> std::io::Result<()> {
        self.sync_all()
    }
}

fn write_through<S: Sink>(
    pixels: &Pixels,
    stamp: Option<&Stamp>,
    path: &Path,
    tmp: &Path,
    format: Format,
    create: impl FnOnce(&Path) -> std::io::Result<S>,
) -> Result<(), OutputError> {
    let err = |reason: String| OutputError::Write {
        path: path.to_owned(),
        reason,
    };
    set_pending(Some(tmp.to_owned()));
    let result = (|| {
        let file = create(tmp).map_err(|e| err(reason(&e)))?;
        let mut out = std::io::BufWriter::new(file);
        encode(pixels, stamp, format, &mut out).map_err(|e| err(reason(&*e)))?;
        let file = out.into_inner().map_err(|e| err(reason(e.error())))?;
        file.sync().map_err(|e| err(reason(&e)))?;
        drop(file);
        std::fs::rename(tmp, path).map_err(|e| err(reason(&e)))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(tmp);
    }
    set_pending(None);
    result
}

type EncodeError = Box<dyn std::error::Error + Send + Sync>;

/// Encodes the pixels as `format`; a stamp adds a region's record where
/// the format can hold it.
fn encode(
    pixels: &Pixels,
    stamp: Option<&Stamp>,
    format: Format,
    out: &mut (impl std::io::Write + std::io::Seek),
) -> Result<(), EncodeError> {
    match (pixels, format) {
        (Pixels::Float(img), Format::Exr) => crate::farm::image_io::write_exr(img, stamp, out),
        (Pixels::Float(img), _) => Ok(img.write_to(out, format.image_format())?),
        (Pixels::Rgb8(img), Format::Png) => crate::farm::image_io::write_png(img, stamp, out),
        (Pixels::Rgb8(img), Format::Ppm) => Ok(write_ppm(img, out)?),
        (Pixels::Rgb8(_), Format::Exr | Format::Hdr) => {
            Err("8-bit colour cannot be written as linear float".into())
        }
        (Pixels::Rgb8(img), _) => Ok(img.write_to(out, format.image_format())?),
    }
}

/// Binary PPM (`P6`), which every viewer reads; the `image` crate's PNM
/// default for RGB is PAM (`P7`), which many do not.
fn write_ppm(img: &image::RgbImage, out: &mut impl std::io::Write) -> image::ImageResult<()> {
    use image::ImageEncoder;
    use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
    PnmEncoder::new(out)
        .with_subtype(PnmSubtype::Pixmap(SampleEncoding::Binary))
        .write_image(
            img.as_raw(),
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vectorised linear route writes the byte the transfer's own
    /// encoding does: at every f32 within 300 ulps of each rounding
    /// boundary (k + ½)/255 and each end, at special values, and at
    /// spread-out values (every 4099th bit pattern of [−2, 2]).
    #[test]
    fn the_linear_bytes_are_the_transfers() {
        let check = |c: f32| {
            assert_eq!(
                linear8(c),
                Transfer::Linear.encode8(c as f64),
                "{c:e} ({:#x})",
                c.to_bits()
            )
        };
        let mut centres: Vec<f32> = (0..=255).map(|k| (k as f32 + 0.5) / 255.0).collect();
        centres.extend([0.0, 1.0, -0.0, f32::MIN_POSITIVE]);
        for c in centres {
            for d in -300i32..=300 {
                check(f32::from_bits(c.to_bits().wrapping_add_signed(d)));
            }
        }
        for c in [
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            -1.0,
        ] {
            check(c);
        }
        let (lo, hi) = (2.0f32.to_bits(), (-2.0f32).to_bits());
        for b in (0..lo).step_by(4099).chain((1u32 << 31..hi).step_by(4099)) {
            check(f32::from_bits(b));
        }
        // And a film: the whole route, rows in parallel.
        let film = Film::new(
            3,
            2,
            vec![
                [0.5, 1.5, -1.0],
                [f32::NAN, 0.001, 0.998],
                [0.25; 3],
                [1.0; 3],
                [0.0; 3],
                [0.1, 0.2, 0.3],
            ],
        );
        let img = to_rgb8(&film, Transfer::Linear);
        let want: Vec<u8> = film
            .pixels
            .iter()
            .flatten()
            .map(|&c| Transfer::Linear.encode8(c as f64))
            .collect();
        assert_eq!(img.as_raw(), &want);
    }

    #[test]
    fn formats_follow_extensions() {
        assert_eq!(Format::from_path(Path::new("a.PNG")).unwrap(), Format::Png);
        assert_eq!(
            Format::from_path(Path::new("a.jpeg")).unwrap(),
            Format::Jpeg
        );
        assert!(Format::from_path(Path::new("a.gif")).is_err());
        assert!(Format::from_path(Path::new("noext")).is_err());
    }

    #[test]
    fn writes_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let film = Film::new(2, 1, vec![[1.0, 0.0, 0.0], [0.0, 0.5, 2.0]]);
        for ext in ["png", "jpg", "exr", "hdr", "ppm"] {
            let p = dir.path().join(format!("out.{ext}"));
            write(&film, &p, Format::from_path(&p).unwrap(), Transfer::Srgb).unwrap();
            assert!(p.metadata().unwrap().len() > 0);
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 5);
        let img = image::open(dir.path().join("out.png")).unwrap().to_rgb8();
        assert_eq!(img.get_pixel(0, 0).0, [255, 0, 0]);
        assert_eq!(img.get_pixel(1, 0).0[2], 255);
    }

    #[test]
    fn an_interrupted_write_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let tmp = dir.path().join(".out.png.1.tmp");
        std::fs::write(&tmp, b"half an image").unwrap();
        set_pending(Some(tmp.clone()));
        remove_pending();
        assert!(!tmp.exists());
        // Nothing pending: nothing to do, and no error.
        remove_pending();
    }

    /// A real file on a disk with `room` bytes left.
    struct NearlyFull {
        file: std::fs::File,
        room: usize,
    }

    impl std::io::Write for NearlyFull {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.room == 0 {
                return Err(std::io::Error::from_raw_os_error(28)); // ENOSPC
            }
            let n = buf.len().min(self.room);
            self.room -= n;
            self.file.write(&buf[..n])
        }
        fn flush(&mut self) -> std::io::Result<()> {
            self.file.flush()
        }
    }

    impl std::io::Seek for NearlyFull {
        fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
            self.file.seek(pos)
        }
    }

    impl Sink for NearlyFull {
        fn sync(&self) -> std::io::Result<()> {
            self.file.sync_all()
        }
    }

    #[test]
    fn a_full_disk_is_an_error_and_keeps_the_old_image() {
        let dir = tempfile::tempdir().unwrap();
        let film = Film::new(64, 64, vec![[0.3, 0.6, 0.9]; 64 * 64]);
        for ext in ["png", "jpg", "exr", "hdr", "ppm"] {
            let p = dir.path().join(format!("out.{ext}"));
            std::fs::write(&p, b"the old picture").unwrap();
            let target = Target::claim(&p, Format::from_path(&p).unwrap()).unwrap();
            let pixels = Pixels::of_film(&film, target.format(), Transfer::Srgb);
            let r = target.write_with(&pixels, None, |t| {
                Ok(NearlyFull {
                    file: std::fs::File::create(t)?,
                    room: 100,
                })
            });
            let Err(OutputError::Write { reason, .. }) = r else {
                panic!("{ext}: a full disk was not an error: {r:?}");
            };
            assert!(reason.contains("No space left"), "{ext}: {reason}");
            assert!(reason.contains("disk is full"), "{ext}: {reason}");
            assert!(!reason.contains("decod"), "{ext}: {reason}");
            assert_eq!(std::fs::read(&p).unwrap(), b"the old picture", "{ext}");
        }
        // Nothing but the five old pictures: every temporary was removed.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 5);
    }

    #[test]
    fn ppm_is_binary_p6() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.ppm");
        let film = Film::new(2, 1, vec![[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]);
        write(&film, &p, Format::Ppm, Transfer::Srgb).unwrap();
        let bytes = std::fs::read(&p).unwrap();
        assert!(bytes.starts_with(b"P6"), "{:?}", &bytes[..8]);
        // The header, then width × height × 3 bytes of samples.
        assert_eq!(&bytes[bytes.len() - 6..], &[255, 0, 0, 0, 0, 255]);
    }

    #[test]
    fn targets_are_checked_before_rendering() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("scene.png");
        std::fs::write(&scene, b"a texture").unwrap();
        // The input by another spelling, and through a symbolic link.
        let other = dir
            .path()
            .join(".")
            .join("sub")
            .join("..")
            .join("scene.png");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let link = dir.path().join("link.png");
        #[cfg(unix)]
        std::os::unix::fs::symlink(&scene, &link).unwrap();
        for p in [&scene, &other, &link] {
            let e = Target::prepare(p, 8, 8, std::slice::from_ref(&scene)).unwrap_err();
            assert!(matches!(e, OutputError::IsInput { .. }), "{e:?}");
        }
        assert_eq!(std::fs::read(&scene).unwrap(), b"a texture");
        // A name of 250 characters works (its temporary is short)...
        let long = dir.path().join(format!("{}.png", "n".repeat(246)));
        let film = Film::new(1, 1, vec![[0.5; 3]]);
        Target::prepare(&long, 1, 1, &[])
            .unwrap()
            .write(&film, Transfer::Srgb)
            .unwrap();
        assert!(long.exists());
        // ...and one over the system's limit is refused up front.
        let longer = dir.path().join(format!("{}.png", "n".repeat(NAME_MAX)));
        let e = Target::prepare(&longer, 1, 1, &[]).unwrap_err();
        assert!(matches!(e, OutputError::NameTooLong { .. }), "{e:?}");
        // JPEG stores sides in 16 bits.
        let jpg = dir.path().join("wide.jpg");
        let e = Target::prepare(&jpg, 65_536, 2, &[]).unwrap_err();
        assert!(e.to_string().contains("65535"), "{e}");
        assert!(Target::prepare(&dir.path().join("wide.png"), 65_536, 2, &[]).is_ok());
        // A missing folder is found before any work.
        let e = Target::prepare(&dir.path().join("nope/x.png"), 1, 1, &[]).unwrap_err();
        assert!(e.to_string().contains("does not exist"), "{e}");
        assert!(!e.is_usage());
        // A dropped, unwritten target leaves nothing behind.
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
    }

    #[test]
    fn unwritable_path_is_an_error_not_a_file() {
        let film = Film::new(1, 1, vec![[0.0; 3]]);
        let p = Path::new("/nonexistent-dir/x.png");
        assert!(write(&film, p, Format::Png, Transfer::Srgb).is_err());
    }
}
