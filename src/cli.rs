//! The command line: its flags, their allowed ranges, and the exit codes
//! the program ends with (stated in `--help` and the README, tested in
//! tests/integration/cli.rs).

use clap::Parser;
use std::path::PathBuf;

/// The widest and tallest image, from the command line or a scene's
/// `render` block: JPEG's 16-bit limit, applied to every format so that a
/// size works whatever the extension.
pub const MAX_SIDE: u32 = 65_535;

/// The most worker threads: far more than any machine's cores, and few
/// enough that starting them cannot run into the system's process limit.
pub const MAX_THREADS: u32 = 256;

const EXIT_CODES: &str = "\
Exit status:
  0    the image was written (or, with --check, the scene is valid)
  1    the scene has an error (syntax, meaning, or a file it names)
  2    the command line is wrong (a flag, a value out of range, an output
       name that cannot be used)
  3    the system refused (the scene cannot be read, the image cannot be
       written, threads cannot be started)
  128+N  stopped by signal N (130 for Ctrl-C, 143 for SIGTERM); nothing
       is left half-written

A scheduler may retry 3 and 128+N; 1 and 2 fail the same way again.

Other commands:
  raytrace merge TILES... -o FULL [--average]
       put tiles from --tile or --region back together (see docs/farm.md)
  raytrace fmt [--check] FILE...
       lay out .rt files canonically, in place (`-` for stdin to stdout)
  raytrace lsp
       a language server for editors, over stdin/stdout: mistakes as you
       type, hover, completion, definitions (docs/editors.md)";

/// Render a .rt scene to an image.
#[derive(Parser, Debug, Clone)]
#[command(name = "raytrace", version, about, after_help = EXIT_CODES)]
pub struct Args {
    /// The scene file to render.
    pub scene: PathBuf,

    /// The image to write; the extension picks the format
    /// (.png, .jpg, .exr, .hdr, .ppm).
    #[arg(short, long, required_unless_present = "check")]
    pub output: Option<PathBuf>,

    /// Image width in pixels, 1 to 65535, as in a scene's `render` block
    /// (overrides it).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE as i64))]
    pub width: Option<u32>,

    /// Image height in pixels, 1 to 65535, as in a scene's `render` block
    /// (overrides it).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_SIDE as i64))]
    pub height: Option<u32>,

    /// The acceleration structure for meshes and the scene's objects:
    /// `auto` (the default: the wide BVH for meshes, the kd-tree for the
    /// scene's objects), `bvh` or `kdtree` for both (overrides the scene's
    /// `render { accel }`).
    #[arg(long, value_name = "auto|kdtree|bvh", value_parser = clap::builder::PossibleValuesParser::new(crate::accel::Accel::NAMES))]
    pub accel: Option<String>,

    /// Antialiasing: N × N rays per pixel, 1 to 16 (overrides the scene's
    /// `render { samples }`).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16))]
    pub samples: Option<u32>,

    /// Render only the columns x0..x1 and rows y0..y1 of the picture:
    /// whole pixels from the top-left corner (x1 and y1 not included), or
    /// fractions of the width and height when any bound has a `.`
    /// (`0,0.5,0,1` is the left half). The image holds exactly those
    /// pixels of the full picture.
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = parse_region)]
    pub region: Option<RegionArg>,

    /// Worker threads, 1 to 256 (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_THREADS as i64))]
    pub threads: Option<u32>,

    /// Parse and build the scene, report any errors, render nothing; on
    /// success print a one-line summary.
    #[arg(long)]
    pub check: bool,

    /// Render, then render again whenever the scene or a file it reads
    /// changes (a quick coarse pass first, then the full picture), until
    /// Ctrl-C; a scene with mistakes keeps the last good picture.
    #[arg(long, conflicts_with = "check")]
    pub watch: bool,

    /// As --watch, and show each pass in a window (closing it stops);
    /// needs a raytrace built with `--features preview`.
    #[arg(long, conflicts_with = "check")]
    pub preview: bool,

    /// Print timings and ray counts to stderr.
    #[arg(long)]
    pub stats: bool,

    /// No progress bar, warnings or summary.
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
    /// With --frames the clock comes from the range instead.
    #[arg(long, default_value_t = 0.0, conflicts_with = "frames")]
    pub clock: f64,

    /// The scene's `frame` number (0 for a still); with --frames, the one
    /// frame of the range to render (its clock still from the whole range).
    #[arg(long, value_name = "N")]
    pub frame: Option<u32>,

    /// Render an animation: `1-240`, `3,5,9-20:2` (a step of 2), `7`. The
    /// clock is 0 at the lowest frame and 1 at the highest; the output
    /// name has `####` where the frame number goes (`-o out_####.png`).
    #[arg(long, value_name = "LIST", value_parser = crate::farm::frames::FrameList::parse)]
    pub frames: Option<crate::farm::frames::FrameList>,

    /// This task's number in a job array ($SLURM_ARRAY_TASK_ID,
    /// $JOB_COMPLETION_INDEX), counted from --index-base: with --tasks N
    /// or --frames-per-task K it picks a contiguous chunk of the frames,
    /// with --tiles N a tile (and, with --frames, the frame).
    #[arg(long, value_name = "I")]
    pub task_index: Option<u64>,

    /// How many tasks share the frames (each gets a contiguous chunk,
    /// the sizes differing by at most one).
    #[arg(long, value_name = "N", requires = "task_index", conflicts_with = "frames_per_task",
          value_parser = clap::value_parser!(u64).range(1..))]
    pub tasks: Option<u64>,

    /// Frames each task renders: task I renders frames I·K to I·K+K−1 of
    /// the list (counted from 0).
    #[arg(long, value_name = "K", requires = "task_index",
          value_parser = clap::value_parser!(u64).range(1..))]
    pub frames_per_task: Option<u64>,

    /// Render tile I of N of the picture (I from --index-base), on the
    /// most square grid of N tiles; the image holds just that tile.
    #[arg(long, value_name = "I/N", value_parser = crate::farm::tiles::parse_tile,
          conflicts_with_all = ["region", "tiles"])]
    pub tile: Option<crate::farm::tiles::TileArg>,

    /// Cut the picture into N tiles and render the one --task-index picks
    /// (task I: frame I / N of the list, tile I mod N).
    #[arg(long, value_name = "N", requires = "task_index", conflicts_with_all = ["region", "tasks", "frames_per_task"],
          value_parser = clap::value_parser!(u32).range(1..))]
    pub tiles: Option<u32>,

    /// What --task-index and --tile count from: 0 (Kubernetes, GNU
    /// parallel's {%}-1, `--array=0-…`) or 1 (SGE, `--array=1-…`).
    #[arg(long, value_name = "0|1", default_value_t = 0,
          value_parser = clap::value_parser!(u8).range(0..=1))]
    pub index_base: u8,

    /// Skip a frame or tile whose output file already exists (outputs are
    /// written under a temporary name and renamed, so one that exists is
    /// complete): a rerun of a failed job redoes only what is missing.
    #[arg(long)]
    pub skip_existing: bool,

    /// Write one JSON line to stderr per finished (or skipped) frame or
    /// tile: output, frame, region, seconds, rays, peak memory.
    #[arg(long, value_name = "FORMAT")]
    pub log: Option<LogFormat>,

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
            frame: self.frame.unwrap_or(0) as f64,
            limits: crate::eval::Limits {
                iterations: self.max_iterations,
                objects: self.max_objects,
                depth: self.max_recursion,
                steps: self.max_steps,
            },
            cancel: None,
            accel: self
                .accel
                .as_deref()
                .and_then(crate::accel::Accel::from_name),
        })
    }
}

/// `--log`'s formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum LogFormat {
    /// One JSON object a line.
    Json,
}

/// `--region` as written: the picture's size is known only once the scene
/// is read, so fractions are turned into pixels by [`RegionArg::resolve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RegionArg {
    /// Whole pixels: x0, x1, y0, y1 (x1 and y1 not included).
    Pixels([u32; 4]),
    /// Fractions of the width and height, each in [0, 1].
    Fractions([f64; 4]),
}

impl RegionArg {
    /// The pixels of a `width` × `height` picture this region covers;
    /// an error that says why when it is empty or reaches past the picture.
    pub fn resolve(self, width: u32, height: u32) -> Result<crate::render::Region, String> {
        let [x0, x1, y0, y1] = match self {
            RegionArg::Pixels(b) => b.map(u64::from),
            RegionArg::Fractions(f) => {
                // Rounded to the nearest pixel edge, so tiles of 1/3 and 2/3
                // meet without a gap or an overlap.
                let at = |t: f64, n: u32| (t * n as f64).round() as u64;
                [
                    at(f[0], width),
                    at(f[1], width),
                    at(f[2], height),
                    at(f[3], height),
                ]
            }
        };
        let shown = match self {
            RegionArg::Pixels(_) => format!("{x0},{x1},{y0},{y1}"),
            RegionArg::Fractions(_) => format!("{x0},{x1},{y0},{y1} (in pixels)"),
        };
        if x1 > width as u64 || y1 > height as u64 {
            return Err(format!(
                "the region {shown} reaches past the {width}x{height} picture: columns run \
                 to {width} and rows to {height}"
            ));
        }
        if x0 >= x1 || y0 >= y1 {
            return Err(format!(
                "the region {shown} is empty: x0 must be less than x1 and y0 less than y1"
            ));
        }
        Ok(crate::render::Region {
            x: x0 as u32,
            y: y0 as u32,
            width: (x1 - x0) as u32,
            height: (y1 - y0) as u32,
        })
    }
}

/// `X0,X1,Y0,Y1`: four whole numbers of pixels, or four fractions in
/// [0, 1] when any of them has a `.`.
fn parse_region(s: &str) -> Result<RegionArg, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 4 {
        return Err(format!(
            "`{s}`: write four bounds X0,X1,Y0,Y1, e.g. 0,100,0,50 (pixels) or 0,0.5,0,1 (fractions)"
        ));
    }
    if parts.iter().any(|t| t.contains('.')) {
        let mut f = [0.0; 4];
        for (slot, t) in f.iter_mut().zip(&parts) {
            *slot = t
                .parse::<f64>()
                .ok()
                .filter(|x| (0.0..=1.0).contains(x))
                .ok_or_else(|| format!("`{t}` in `{s}` is not a fraction from 0 to 1"))?;
        }
        return Ok(RegionArg::Fractions(f));
    }
    let mut b = [0u32; 4];
    for (slot, t) in b.iter_mut().zip(&parts) {
        *slot = t
            .parse::<u32>()
            .map_err(|_| format!("`{t}` in `{s}` is not a whole number of pixels"))?;
    }
    Ok(RegionArg::Pixels(b))
}

/// What kind of failure ended the program: its exit status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exit {
    /// The scene has an error.
    Scene = 1,
    /// The command line is wrong (clap uses 2 for its own errors too).
    Usage = 2,
    /// The system refused: a read, a write, threads.
    System = 3,
}

/// A report and the exit status it ends the program with.
pub struct Failure {
    pub exit: Exit,
    pub report: miette::Report,
}

impl Failure {
    pub fn scene(e: impl Into<miette::Report>) -> Failure {
        Failure {
            exit: Exit::Scene,
            report: e.into(),
        }
    }

    pub fn usage(e: impl Into<miette::Report>) -> Failure {
        Failure {
            exit: Exit::Usage,
            report: e.into(),
        }
    }

    pub fn system(e: impl Into<miette::Report>) -> Failure {
        Failure {
            exit: Exit::System,
            report: e.into(),
        }
    }

    /// An output problem: the command line's, or the system's.
    pub fn output(e: crate::output::OutputError) -> Failure {
        if e.is_usage() {
            Failure::usage(e)
        } else {
            Failure::system(e)
        }
    }
}

impl std::fmt::Debug for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}", self.report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fractional_regions_tile_the_picture_exactly_once() {
        // Thirds of 100 columns round to 0..33, 33..67, 67..100: every
        // column in exactly one tile, whatever the rounding.
        for n in [2u32, 3, 7] {
            let mut next = 0;
            for i in 0..n {
                let f = |k: u32| k as f64 / n as f64;
                let r = parse_region(&format!("{:.17},{:.17},0.0,1.0", f(i), f(i + 1)))
                    .unwrap()
                    .resolve(100, 10)
                    .unwrap();
                assert_eq!(r.x, next, "tile {i} of {n}");
                next = r.x + r.width;
                assert_eq!((r.y, r.height), (0, 10));
            }
            assert_eq!(next, 100);
        }
    }

    #[test]
    fn pixel_regions_are_half_open_and_checked() {
        let r = parse_region("2,7,3,7").unwrap().resolve(12, 12).unwrap();
        assert_eq!((r.x, r.y, r.width, r.height), (2, 3, 5, 4));
        let whole = parse_region("0,12,0,12").unwrap().resolve(12, 12).unwrap();
        assert_eq!((whole.width, whole.height), (12, 12));
        assert!(parse_region("0,13,0,12").unwrap().resolve(12, 12).is_err());
        assert!(parse_region("4,4,0,12").unwrap().resolve(12, 12).is_err());
        assert!(parse_region("0,1.5,0,1").is_err());
        assert!(parse_region("0,-1,0,1").is_err());
        assert!(parse_region("a,1,0,1").is_err());
    }
}
