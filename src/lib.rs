//! raytrace: a Whitted-style ray tracer driven by a scene-description
//! language.
//!
//! ```text
//!  scene.rt ──parse──▶ lang::Program ──evaluate, build──▶ scene::Scene ──accelerate──▶ accel::World
//!     (lang/)              (eval/, scene/)                                 (accel/)
//!                    ──render──▶ render::Film ──write──▶ out.png
//!                      (render/)                 (output.rs)
//! ```
//!
//! [`run`] is the whole program, one line per stage.

pub mod accel;
pub mod cli;
pub mod eval;
pub mod farm;
pub mod fmt;
pub mod formats;
pub mod geometry;
pub mod guard;
pub mod implicit;
pub mod lang;
pub mod lsp;
pub mod output;
#[cfg(feature = "preview")]
pub mod preview;
pub mod render;
pub mod scene;
pub mod shapes;
#[cfg(test)]
pub(crate) mod shared_data;
pub mod signals;
pub mod stdlib;
pub mod watch;
#[cfg(test)]
pub(crate) mod watchdog;

use cli::{Args, Failure};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use miette::Result;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Runs the command line: parse, build, check the output, accelerate,
/// render, write. Each failure carries its exit status.
pub fn run(args: &Args) -> Result<(), Failure> {
    if args.watch || args.preview {
        return watch::watch(args);
    }
    if farm::wanted(args) {
        return farm::run(args);
    }
    let clock = Instant::now();
    check_output_name(args)?;
    let program = load(args)?;
    let parsed = clock.elapsed();
    let frame = FrameTime {
        clock: args.clock,
        frame: args.frame.unwrap_or(0) as f64,
    };
    let scene = build(args, &program, frame)?;
    let built = clock.elapsed();
    if args.check {
        if !args.quiet {
            println!("{}", check_summary(&program, &scene.scene, scene.warnings));
        }
        return Ok(());
    }
    let Some(path) = &args.output else {
        return Ok(());
    };
    let timings = Timings {
        start: clock,
        parse: parsed,
        build: built - parsed,
    };
    render_to(args, &program, scene.scene, path, timings)
}

/// Which moment of an animation a scene is built for: the scene's
/// `clock` and `frame` names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameTime {
    pub clock: f64,
    pub frame: f64,
}

/// A built scene and how many warnings building it printed.
pub struct Built {
    pub scene: scene::Scene,
    pub warnings: usize,
}

/// When the run started and what parsing and building took, for `--stats`.
#[derive(Clone, Copy, Debug)]
pub struct Timings {
    pub start: Instant,
    pub parse: Duration,
    pub build: Duration,
}

/// An output name whose extension names no format is refused before any
/// work.
pub fn check_output_name(args: &Args) -> Result<(), Failure> {
    if let Some(path) = &args.output {
        output::Format::from_path(path).map_err(Failure::output)?;
    }
    Ok(())
}

/// Parse: the scene file and its includes.
pub fn load(args: &Args) -> Result<lang::Program, Failure> {
    let text = read_scene(&args.scene).map_err(Failure::system)?;
    lang::load_text(&args.scene, text).map_err(Failure::scene)
}

/// Evaluate and build the scene for one moment, apply the command line's
/// overrides, and check the image size; warnings are printed unless
/// `--quiet`.
pub fn build(args: &Args, program: &lang::Program, at: FrameTime) -> Result<Built, Failure> {
    let mut options = args
        .eval_options()
        .map_err(|e| Failure::usage(miette::miette!("{e}")))?;
    options.clock = at.clock;
    options.frame = at.frame;
    let (mut scene, warnings) = scene::build_with(program, &options).map_err(Failure::scene)?;
    if !args.quiet {
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    }
    apply_overrides(args, &mut scene);
    check_size(args, &scene.settings).map_err(Failure::usage)?;
    Ok(Built {
        scene,
        warnings: warnings.len(),
    })
}

/// Accelerate, render and write one picture (or `--region` of it) to
/// `path`; `--stats` prints the timings.
pub fn render_to(
    args: &Args,
    program: &lang::Program,
    mut scene: scene::Scene,
    path: &std::path::Path,
    timings: Timings,
) -> Result<(), Failure> {
    let region = picture_region(args, &scene.settings).map_err(Failure::usage)?;
    let target = output::Target::prepare(path, region.width, region.height, &inputs(program))
        .map_err(Failure::output)?;
    let pool = thread_pool(args).map_err(Failure::system)?;
    let transfer = scene.settings.transfer;
    let world = accel::World::build_with(std::mem::take(&mut scene.objects), scene.settings.accel);
    let first =
        render_with_progress(args, &pool, &scene, &world, region).map_err(Failure::scene)?;
    let (film, stats) = farm::motion::blur(args, program, &scene, first, |mut sub| {
        let world = accel::World::build_with(std::mem::take(&mut sub.objects), sub.settings.accel);
        render_with_progress(args, &pool, &sub, &world, region).map_err(Failure::scene)
    })?;
    // A region's image records where it lies; a whole picture stays plain.
    let stamp = farm::stamp::Stamp::of(args, program, &scene.settings, region);
    pool.install(|| target.write_stamped(&film, transfer, args.region.is_some().then_some(&stamp)))
        .map_err(Failure::output)?;
    let picture = (scene.settings.width, scene.settings.height);
    let seconds = timings.start.elapsed().as_secs_f64();
    farm::log::finished(args, path, region, picture, &stats, seconds);
    if args.stats {
        let pixels = film.width as u64 * film.height as u64;
        print_stats(
            timings.parse,
            timings.build,
            &world,
            &stats,
            pixels,
            timings.start.elapsed(),
        );
    }
    Ok(())
}

/// The scene file's text; failing to read it is the system's refusal, not
/// a mistake in a scene.
fn read_scene(path: &std::path::Path) -> Result<String> {
    lang::source::read_text(path, lang::source::MAX_SCENE_BYTES)
        .map_err(|e| miette::miette!("cannot read {}: {e}", path.display()))
}

/// `scene.rt: ok, 12 objects, 2 lights, no warnings`
fn check_summary(program: &lang::Program, scene: &scene::Scene, warnings: usize) -> String {
    let n = |k: usize, one: &str, many: &str| match k {
        0 => format!("no {many}"),
        1 => format!("1 {one}"),
        k => format!("{k} {many}"),
    };
    format!(
        "{}: ok, {}, {}, {}",
        program.name(),
        n(scene.objects.len(), "object", "objects"),
        n(scene.lights.len(), "light", "lights"),
        n(warnings, "warning", "warnings")
    )
}

/// Every file the scene reads or may read, for the output to be checked
/// against: the scene, its includes, and each string that names an
/// existing file relative to the file it is written in (textures, meshes).
pub(crate) fn inputs(program: &lang::Program) -> Vec<PathBuf> {
    let sources = &program.sources;
    let mut out: Vec<PathBuf> = (0..sources.len())
        .map(|i| sources.get(lang::ast::FileId(i as u32)).path.clone())
        .collect();
    let mut stack: Vec<&lang::ast::Item> = program.items.iter().collect();
    while let Some(item) = stack.pop() {
        match item {
            lang::ast::Item::Str { text, span, .. } => {
                let p = sources.dir_of(span.file).join(text);
                if p.is_file() {
                    out.push(p);
                }
            }
            lang::ast::Item::Block(b) => stack.extend(b.items.iter()),
            _ => {}
        }
    }
    out
}

fn apply_overrides(args: &Args, scene: &mut scene::Scene) {
    if let Some(w) = args.width {
        scene.settings.width = w;
    }
    if let Some(h) = args.height {
        scene.settings.height = h;
    }
    if let Some(n) = args.samples {
        scene.settings.set_square_grid(n);
    }
}

/// Images above this many pixels need `--allow-large`: the film alone
/// takes 12 bytes a pixel.
pub const MAX_PIXELS: u64 = 100_000_000;

/// Memory a pixel costs while rendering and writing: the film's three
/// f32 (12 bytes) and the copy the encoder is given, 3 bytes of 8-bit
/// colour or, for .exr and .hdr, 12 of f32. Measured: 110 MP peaked at
/// 1.54 GiB for .png and .ppm (15 B/px) and 2.47 GiB for .exr (24 B/px).
pub fn bytes_per_pixel(format: Option<output::Format>) -> u64 {
    match format {
        Some(output::Format::Exr | output::Format::Hdr) => 24,
        _ => 15,
    }
}

fn check_size(args: &Args, settings: &scene::RenderSettings) -> Result<()> {
    let (w, h) = (settings.width, settings.height);
    if w > cli::MAX_SIDE || h > cli::MAX_SIDE {
        return Err(miette::miette!(
            help = format!("width and height may each be 1 to {}", cli::MAX_SIDE),
            "a {w}x{h} image is wider or taller than {} pixels",
            cli::MAX_SIDE
        ));
    }
    let pixels = w as u64 * h as u64;
    let format = args
        .output
        .as_deref()
        .and_then(|p| output::Format::from_path(p).ok());
    if pixels > MAX_PIXELS && !args.allow_large {
        return Err(miette::miette!(
            help = "pass --allow-large to render it anyway, or choose a smaller --width/--height",
            "a {w}x{h} image has {:.1} megapixels and needs about {:.1} GiB of memory",
            pixels as f64 / 1e6,
            (pixels * bytes_per_pixel(format)) as f64 / (1u64 << 30) as f64
        ));
    }
    Ok(())
}

/// The part of the picture to render: `--region`, which must lie inside
/// it, or all of it.
pub(crate) fn picture_region(
    args: &Args,
    settings: &scene::RenderSettings,
) -> Result<render::Region> {
    let (w, h) = (settings.width, settings.height);
    match args.region {
        None => Ok(render::Region {
            x: 0,
            y: 0,
            width: w,
            height: h,
        }),
        Some(r) => r.resolve(w, h).map_err(|e| {
            miette::miette!(
                help = "X0,X1,Y0,Y1: columns X0 to X1 and rows Y0 to Y1, X1 and Y1 not included",
                "{e}"
            )
        }),
    }
}

/// The render's worker threads, started before any work so that a refusal
/// (the system's thread limit) costs nothing.
pub(crate) fn thread_pool(args: &Args) -> Result<rayon::ThreadPool> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        pool = pool.num_threads(n as usize);
    }
    pool.build().map_err(|e| {
        miette::miette!(
            help = "ask for fewer with --threads (the default is one per core)",
            "cannot start {} worker threads: {e}",
            args.threads
                .map_or_else(|| "the".to_string(), |n| n.to_string())
        )
    })
}

fn render_with_progress(
    args: &Args,
    pool: &rayon::ThreadPool,
    scene: &scene::Scene,
    world: &accel::World,
    region: render::Region,
) -> Result<(render::Film, render::RenderStats)> {
    // The bar stays hidden for quick renders and when stderr is not a
    // terminal (indicatif's stderr target hides itself then).
    let bar =
        ProgressBar::with_draw_target(Some(region.height as u64), ProgressDrawTarget::hidden());
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {percent:>3}% rows, {elapsed} elapsed, {eta} left")
            .expect("template is valid"),
    );
    let start = Instant::now();
    let show = !args.quiet;
    let progress = |rows: u64| {
        if show && bar.is_hidden() && start.elapsed() > Duration::from_millis(300) {
            bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        bar.set_position(rows);
    };
    let opts = render::RenderOptions {
        progress: Some(&progress),
        cancel: None,
    };
    let out = pool.install(|| render::render_region(scene, world, &opts, region));
    bar.finish_and_clear();
    out.ok_or_else(|| miette::miette!("the camera has no valid frame"))
}

/// `812 B`, `3.4 KiB`, `2.27 MiB`.
fn bytes(n: usize) -> String {
    let n = n as f64;
    if n < 1024.0 {
        format!("{n} B")
    } else if n < 1024.0 * 1024.0 {
        format!("{:.1} KiB", n / 1024.0)
    } else {
        format!("{:.2} MiB", n / (1024.0 * 1024.0))
    }
}

fn print_stats(
    parse: Duration,
    build: Duration,
    world: &accel::World,
    stats: &render::RenderStats,
    pixels: u64,
    total: Duration,
) {
    let a = &world.stats;
    let r = &stats.rays;
    eprintln!("parse      {:>10.3} s", parse.as_secs_f64());
    eprintln!("build      {:>10.3} s", build.as_secs_f64());
    eprintln!(
        "accelerate {:>10.3} s  ({} objects, {} unbounded, {} nodes)",
        a.build_seconds, a.objects, a.unbounded, a.nodes
    );
    if let Some(b) = &a.bvh {
        eprintln!(
            "  bvh      {:>10}  leaves, {} wide nodes, depth {}, {:.1} KiB",
            b.leaves,
            b.nodes,
            b.depth,
            b.bytes as f64 / 1024.0
        );
    } else {
        let t = &a.tree;
        eprintln!(
            "  kd-tree  {:>10}  leaves ({} empty), {} refs, max leaf {}, depth {}",
            t.leaves, t.empty_leaves, t.references, t.max_leaf, t.max_depth
        );
    }
    let mb = &a.mesh_bvhs;
    if mb.trees > 0 {
        eprintln!(
            "  mesh bvh {:>10.3} s  ({} bvhs, {} triangles, {} wide nodes, {} leaves, depth {}, {:.1} MiB)",
            mb.build_seconds,
            mb.trees,
            mb.triangles,
            mb.nodes,
            mb.leaves,
            mb.max_depth,
            mb.bytes as f64 / (1024.0 * 1024.0)
        );
    }
    let m = &a.meshes;
    if m.trees > 0 {
        eprintln!(
            "  meshes   {:>10.3} s  ({} trees, {} triangles, {} nodes, {} leaves, {:.2} refs/triangle, depth {})",
            m.build_seconds,
            m.trees,
            m.triangles,
            m.nodes,
            m.leaves,
            m.references as f64 / m.triangles.max(1) as f64,
            m.max_depth
        );
    }
    let mem = &a.memory;
    eprintln!(
        "  memory   {:>10}  (scene tree {}, scene BVH {}, mesh trees {}, mesh BVHs {})",
        bytes(mem.total()),
        bytes(mem.scene_tree),
        bytes(mem.scene_bvh),
        bytes(mem.mesh_trees),
        bytes(mem.mesh_bvhs)
    );
    eprintln!("render     {:>10.3} s", stats.seconds);
    eprintln!("total      {:>10.3} s", total.as_secs_f64());
    eprintln!(
        "rays       {:>10}  (primary {}: beamed {}; reflected {}, refracted {}, shadow {}: {} settled by shaft culling; {} not cast, below the bailout)",
        r.total(),
        r.primary,
        r.beamed,
        r.reflected,
        r.refracted,
        r.shadow,
        r.settled,
        r.bailed
    );
    // Camera samples per pixel: N² everywhere, more where adaptive
    // sampling refined a pixel.
    eprintln!(
        "pixels     {:>10}  ({:.2} samples each on average, {} refined by adaptive sampling)",
        pixels,
        r.primary as f64 / pixels.max(1) as f64,
        r.refined
    );
    // Each kind's count over the whole render's time (the kinds share it).
    let per_s = |n: u64| n as f64 / stats.seconds.max(1e-9);
    eprintln!(
        "rays/s     {:>10.0}  (primary {:.0}, reflected {:.0}, refracted {:.0}, shadow {:.0})",
        per_s(r.total()),
        per_s(r.primary),
        per_s(r.reflected),
        per_s(r.refracted),
        per_s(r.shadow)
    );
}
