//! The image-texture loader on arbitrary bytes (written to a file, since
//! the loader reads a path and guesses the format from the content).
#![no_main]

mod scratch;

use libfuzzer_sys::fuzz_target;
use raytrace::scene::Transfer;
use raytrace::scene::texture::{ImageTexture, UvMapping};
use std::path::PathBuf;
use std::sync::OnceLock;

fn file() -> &'static PathBuf {
    static FILE: OnceLock<PathBuf> = OnceLock::new();
    FILE.get_or_init(|| scratch::scratch_path("raytrace-fuzz-image"))
}

fuzz_target!(|data: &[u8]| {
    let path = file();
    std::fs::write(path, data).unwrap();
    if let Ok(tex) = ImageTexture::load(path, Transfer::Srgb, UvMapping::default()) {
        let _ = tex.sample(raytrace::geometry::DVec2::new(0.25, 0.75));
    }
});
