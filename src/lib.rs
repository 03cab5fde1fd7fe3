//! raytrace: a Whitted-style ray tracer driven by a scene-description
//! language.
//!
//! ```text
//!  scene.rt ──parse──▶ lang::Program ──build──▶ scene::Scene ──accelerate──▶ accel::World
//!     (lang/)              (scene/)                                (accel/)
//!                    ──render──▶ render::Film ──write──▶ out.png
//!                      (render/)                 (output.rs)
//! ```
//!
//! [`run`] is the whole program, one line per stage.

pub mod accel;
pub mod cli;
pub mod geometry;
pub mod guard;
pub mod implicit;
pub mod lang;
pub mod output;
pub mod render;
pub mod scene;
pub mod shapes;
#[cfg(test)]
pub(crate) mod shared_data;
#[cfg(test)]
pub(crate) mod watchdog;

use cli::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use miette::{IntoDiagnostic, Result};
use std::time::{Duration, Instant};

/// Runs the command line: parse, build, accelerate, render, write.
pub fn run(args: &Args) -> Result<()> {
    let format = args
        .output
        .as_deref()
        .map(output::Format::from_path)
        .transpose()?;
    let clock = Instant::now();
    let program = lang::load(&args.scene)?;
    let parsed = clock.elapsed();
    let (mut scene, warnings) = scene::build_with_warnings(&program)?;
    if !args.quiet {
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    }
    apply_overrides(args, &mut scene);
    check_size(args, &scene.settings)?;
    let built = clock.elapsed();
    if args.check {
        return Ok(());
    }
    let (Some(path), Some(format)) = (&args.output, format) else {
        return Ok(());
    };
    let transfer = scene.settings.transfer;
    let world = accel::World::build(std::mem::take(&mut scene.objects));
    let (film, stats) = render_with_progress(args, &scene, &world)?;
    output::write(&film, path, format, transfer)?;
    if args.stats {
        print_stats(parsed, built - parsed, &world, &stats, clock.elapsed());
    }
    Ok(())
}

fn apply_overrides(args: &Args, scene: &mut scene::Scene) {
    if let Some(w) = args.width {
        scene.settings.width = w.get();
    }
    if let Some(h) = args.height {
        scene.settings.height = h.get();
    }
    if let Some(n) = args.samples {
        scene.settings.samples = n;
    }
}

/// Images above this many pixels need `--allow-large`: the film alone
/// takes 12 bytes a pixel.
pub const MAX_PIXELS: u64 = 100_000_000;

fn check_size(args: &Args, settings: &scene::RenderSettings) -> Result<()> {
    let pixels = settings.width as u64 * settings.height as u64;
    if pixels > MAX_PIXELS && !args.allow_large {
        return Err(miette::miette!(
            help = "pass --allow-large to render it anyway, or choose a smaller --width/--height",
            "a {}x{} image has {} megapixels and needs about {} MiB of memory",
            settings.width,
            settings.height,
            pixels / 1_000_000,
            pixels * 12 / (1 << 20)
        ));
    }
    Ok(())
}

fn render_with_progress(
    args: &Args,
    scene: &scene::Scene,
    world: &accel::World,
) -> Result<(render::Film, render::RenderStats)> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        pool = pool.num_threads(n.get() as usize);
    }
    let pool = pool.build().into_diagnostic()?;
    // The bar stays hidden for quick renders and when stderr is not a
    // terminal (indicatif's stderr target hides itself then).
    let bar = ProgressBar::with_draw_target(
        Some(scene.settings.height as u64),
        ProgressDrawTarget::hidden(),
    );
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
    };
    let out = pool.install(|| render::render(scene, world, &opts));
    bar.finish_and_clear();
    out.ok_or_else(|| miette::miette!("the camera has no valid frame"))
}

fn print_stats(
    parse: Duration,
    build: Duration,
    world: &accel::World,
    stats: &render::RenderStats,
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
    let t = &a.tree;
    eprintln!(
        "  kd-tree  {:>10}  leaves ({} empty), {} refs, max leaf {}, depth {}",
        t.leaves, t.empty_leaves, t.references, t.max_leaf, t.max_depth
    );
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
    eprintln!("render     {:>10.3} s", stats.seconds);
    eprintln!("total      {:>10.3} s", total.as_secs_f64());
    eprintln!(
        "rays       {:>10}  (primary {}, reflected {}, shadow {})",
        r.total(),
        r.primary,
        r.reflected,
        r.shadow
    );
    eprintln!(
        "rays/s     {:>10.0}",
        r.total() as f64 / stats.seconds.max(1e-9)
    );
}
