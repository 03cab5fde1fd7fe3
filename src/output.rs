//! Stage 5, WRITE: the film, encoded with the scene's transfer curve, into the
//! format the output file's extension names. The image goes to a temporary
//! file beside the target and is renamed over it only when complete, so an
//! error, a crash or Ctrl-C never leaves a partial file or destroys an
//! existing one.

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
}

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
}

/// Encodes the film as 8-bit RGB with the transfer curve.
pub fn to_rgb8(film: &Film, transfer: Transfer) -> image::RgbImage {
    let mut lut_cache = Vec::with_capacity(film.pixels.len() * 3);
    for p in &film.pixels {
        for c in p {
            lut_cache.push((transfer.encode(*c as f64) * 255.0).round() as u8);
        }
    }
    image::RgbImage::from_raw(film.width, film.height, lut_cache)
        .expect("film holds width × height pixels")
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
    write_through(film, path, format, transfer, |t| std::fs::File::create(t))
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
    film: &Film,
    path: &Path,
    format: Format,
    transfer: Transfer,
    create: impl FnOnce(&Path) -> std::io::Result<S>,
) -> Result<(), OutputError> {
    let err = |reason: String| OutputError::Write {
        path: path.to_owned(),
        reason,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_owned(),
        _ => PathBuf::from("."),
    };
    let name = path.file_name().ok_or_else(|| err("no file name".into()))?;
    let tmp = dir.join(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    set_pending(Some(tmp.clone()));
    let result = (|| {
        let file = create(&tmp).map_err(|e| err(e.to_string()))?;
        let mut out = std::io::BufWriter::new(file);
        let encoded = match format {
            Format::Exr | Format::Hdr => to_rgb32f(film).write_to(&mut out, format.image_format()),
            _ => to_rgb8(film, transfer).write_to(&mut out, format.image_format()),
        };
        encoded.map_err(|e| err(e.to_string()))?;
        let file = out.into_inner().map_err(|e| err(e.error().to_string()))?;
        file.sync().map_err(|e| err(e.to_string()))?;
        drop(file);
        std::fs::rename(&tmp, path).map_err(|e| err(e.to_string()))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    set_pending(None);
    result
}

#[cfg(test)]
mod tests {
    use super::*;

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
            let r = write_through(
                &film,
                &p,
                Format::from_path(&p).unwrap(),
                Transfer::Srgb,
                |t| {
                    Ok(NearlyFull {
                        file: std::fs::File::create(t)?,
                        room: 100,
                    })
                },
            );
            let Err(OutputError::Write { reason, .. }) = r else {
                panic!("{ext}: a full disk was not an error: {r:?}");
            };
            assert!(reason.contains("No space left"), "{ext}: {reason}");
            assert_eq!(std::fs::read(&p).unwrap(), b"the old picture", "{ext}");
        }
        // Nothing but the five old pictures: every temporary was removed.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 5);
    }

    #[test]
    fn unwritable_path_is_an_error_not_a_file() {
        let film = Film::new(1, 1, vec![[0.0; 3]]);
        let p = Path::new("/nonexistent-dir/x.png");
        assert!(write(&film, p, Format::Png, Transfer::Srgb).is_err());
    }
}
