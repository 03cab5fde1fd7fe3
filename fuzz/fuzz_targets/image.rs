//! The image-texture loader on arbitrary bytes (written to a file, since
//! the loader reads a path and guesses the format from the content).
#![no_main]

use libfuzzer_sys::fuzz_target;
use raytrace::scene::Transfer;
use raytrace::scene::texture::{ImageTexture, UvMapping};
use std::path::PathBuf;
use std::sync::OnceLock;

fn file() -> &'static PathBuf {
    static FILE: OnceLock<PathBuf> = OnceLock::new();
    FILE.get_or_init(|| {
        let base = if std::path::Path::new("/dev/shm").is_dir() {
            PathBuf::from("/dev/shm")
        } else {
            std::env::temp_dir()
        };
        base.join(format!("raytrace-fuzz-image-{}.img", std::process::id()))
    })
}

fuzz_target!(|data: &[u8]| {
    let path = file();
    std::fs::write(path, data).unwrap();
    if let Ok(tex) = ImageTexture::load(path, Transfer::Srgb, UvMapping::default()) {
        let _ = tex.sample(raytrace::geometry::DVec2::new(0.25, 0.75));
    }
});
