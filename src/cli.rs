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

    /// Antialiasing: N × N rays per pixel (overrides the scene's
    /// `render { samples }`).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub samples: Option<u32>,

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

    /// Replace the value of a top-level `let`: `-D R=2`, `-D C=<1,0,0>`
    /// (may be repeated).
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE")]
    pub defines: Vec<String>,

    /// The scene's `clock` (0 to 1 over an animation; 0 for a still).
    #[arg(long, default_value_t = 0.0)]
    pub clock: f64,

    /// The scene's `frame` number (0 for a still).
    #[arg(long, default_value_t = 0)]
    pub frame: u32,

    /// Most iterations of one `for` loop.
    #[arg(long, value_name = "N", default_value_t = crate::eval::Limits::default().iterations)]
    pub max_iterations: u64,

    /// Most objects a scene program may make.
    #[arg(long, value_name = "N", default_value_t = crate::eval::Limits::default().objects)]
    pub max_objects: u64,

    /// Most nested function calls.
    #[arg(long, value_name = "N", default_value_t = crate::eval::Limits::default().depth)]
    pub max_recursion: usize,

    /// Most evaluation steps of the scene program.
    #[arg(long, value_name = "N", default_value_t = crate::eval::Limits::default().steps)]
    pub max_steps: u64,
}

impl Args {
    /// What the evaluator gets from the command line; a malformed `-D`
    /// is a message.
    pub fn eval_options(&self) -> Result<crate::eval::Options, String> {
        let mut defines = Vec::new();
        for d in &self.defines {
            let Some((name, value)) = d.split_once('=') else {
                return Err(format!("`-D {d}`: write `-D NAME=VALUE`, e.g. `-D R=2`"));
            };
            let name = name.trim();
            if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(format!("`-D {d}`: `{name}` is not a name"));
            }
            let v = crate::eval::define_value(value).map_err(|e| format!("`-D {d}`: {e}"))?;
            defines.push((name.to_string(), v));
        }
        Ok(crate::eval::Options {
            defines,
            clock: self.clock,
            frame: self.frame as f64,
            limits: crate::eval::Limits {
                iterations: self.max_iterations,
                objects: self.max_objects,
                depth: self.max_recursion,
                steps: self.max_steps,
            },
        })
    }
}
