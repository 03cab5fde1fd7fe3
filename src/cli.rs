//! The command line.

use clap::Parser;
use std::num::NonZeroU32;
use std::path::PathBuf;

/// Render a .rt scene to an image.
#[derive(Parser, Debug, Clone)]
#[command(name = "raytrace", version, about)]
pub struct Args {
    /// The scene file to render.
    pub scene: PathBuf,

    /// The image to write; the extension picks the format
    /// (.png, .jpg, .exr, .hdr, .ppm).
    #[arg(short, long, required_unless_present = "check")]
    pub output: Option<PathBuf>,

    /// Image width in pixels (overrides the scene's `render` block).
    #[arg(long)]
    pub width: Option<NonZeroU32>,

    /// Image height in pixels (overrides the scene's `render` block).
    #[arg(long)]
    pub height: Option<NonZeroU32>,

    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<NonZeroU32>,

    /// Parse and build the scene, report any errors, render nothing.
    #[arg(long)]
    pub check: bool,

    /// Print timings and ray counts to stderr.
    #[arg(long)]
    pub stats: bool,

    /// No progress bar.
    #[arg(short, long)]
    pub quiet: bool,

    /// Render images larger than 100 megapixels (which need over a
    /// gigabyte of memory).
    #[arg(long)]
    pub allow_large: bool,
}
