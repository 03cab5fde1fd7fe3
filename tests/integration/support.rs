//! Helpers shared by the end-to-end tests: scenes from text, rendered films.

use raytrace::render::{Film, Region, RenderOptions, RenderStats, render_region};
use raytrace::scene::Scene;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output};

/// Writes `src` to a temporary scene file and returns (dir guard, path).
pub fn scene_file(src: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("scene.rt");
    std::fs::write(&path, src).expect("write scene");
    (dir, path)
}

/// Parses and builds a scene file that must have no mistakes.
pub fn build_path(path: &Path) -> Scene {
    let program = raytrace::lang::load(path).unwrap_or_else(|e| panic!("{e:?}"));
    raytrace::scene::build(&program).unwrap_or_else(|e| panic!("{e:?}"))
}

/// [`build_path`] for a scene given as text.
pub fn build_src(src: &str) -> Scene {
    let (_dir, path) = scene_file(src);
    build_path(&path)
}

/// The diagnostics, as the user sees them, of a scene that parses but
/// must fail to build.
pub fn build_error(src: &str) -> String {
    let (_dir, path) = scene_file(src);
    let program = raytrace::lang::load(&path).unwrap_or_else(|e| panic!("{e:?}"));
    format!(
        "{:?}",
        raytrace::scene::build(&program).expect_err("an error")
    )
}

/// Parses, builds and renders a scene file at its own size (or the given
/// one) on a pool of `threads` threads.
pub fn render_path(path: &Path, size: Option<(u32, u32)>, threads: usize) -> Film {
    let mut scene = build_path(path);
    if let Some((w, h)) = size {
        scene.settings.width = w;
        scene.settings.height = h;
    }
    let world = raytrace::accel::World::build(std::mem::take(&mut scene.objects));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| {
        raytrace::render::render(
            &scene,
            &world,
            &RenderOptions {
                progress: None,
                cancel: None,
            },
        )
    })
    .expect("camera has a frame")
    .0
}

pub fn render_src(src: &str) -> Film {
    let (_dir, path) = scene_file(src);
    render_path(&path, None, 2)
}

pub fn luminance(p: [f32; 3]) -> f32 {
    (p[0] + p[1] + p[2]) / 3.0
}

/// The largest per-channel difference between two films of one size.
pub fn max_difference(a: &Film, b: &Film) -> f32 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |i| (p[i] - q[i]).abs()))
        .fold(0.0, f32::max)
}

pub fn project_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Whether `RAYTRACE_REGENERATE_FIXTURES=1` asks the fixture tests to
/// rewrite the generated files under examples/ (never done unasked).
pub fn regenerate_fixtures() -> bool {
    std::env::var("RAYTRACE_REGENERATE_FIXTURES").is_ok_and(|v| v == "1")
}

/// Runs the `raytrace` binary with `args` to the end, capturing its output.
pub fn raytrace(args: &[&OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raytrace"))
        .args(args)
        .output()
        .expect("run raytrace")
}

/// Runs `raytrace SCENE -o OUT FLAGS…` to the end.
pub fn render_to(scene: &Path, out: &Path, flags: &[&str]) -> Output {
    let mut args = vec![scene.as_os_str(), "-o".as_ref(), out.as_os_str()];
    args.extend(flags.iter().map(OsStr::new));
    raytrace(&args)
}

/// The number of pixels where two films of one size differ by more than
/// `tolerance` in some channel.
pub fn pixels_differing(a: &Film, b: &Film, tolerance: f32) -> usize {
    assert_eq!((a.width, a.height), (b.width, b.height));
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| (0..3).any(|k| (p[k] - q[k]).abs() > tolerance))
        .count()
}

/// Starts `raytrace SCENE -q -o OUT` and returns at once (for tests that
/// interrupt a render).
pub fn spawn_render(scene: &Path, out: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_raytrace"))
        .args([
            scene.as_os_str(),
            "-q".as_ref(),
            "-o".as_ref(),
            out.as_os_str(),
        ])
        .spawn()
        .expect("start raytrace")
}

/// Sends `signal` (as `kill` spells it: "-INT") to the process `pid`.
pub fn send_signal(signal: &str, pid: u32) {
    let sent = Command::new("kill")
        .args([signal, &pid.to_string()])
        .status()
        .expect("run kill");
    assert!(sent.success(), "kill {signal} {pid}");
}

/// The names of the temporary images (`*.tmp`) left in `dir`.
pub fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| {
            e.expect("dir entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// A run's stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A 2×2 image (red, green / blue, white, top row first) filling a
/// 40×40 picture on a rectangle lit by ambient light alone, seen through
/// `colour TEXTURE` (which names it `quad.png`).
pub fn render_quad_image(texture: &str) -> Film {
    let dir = tempfile::tempdir().unwrap();
    let mut img = image::RgbImage::new(2, 2);
    img.put_pixel(0, 0, image::Rgb([255, 0, 0]));
    img.put_pixel(1, 0, image::Rgb([0, 255, 0]));
    img.put_pixel(0, 1, image::Rgb([0, 0, 255]));
    img.put_pixel(1, 1, image::Rgb([255, 255, 255]));
    img.save(dir.path().join("quad.png")).unwrap();
    let scene = dir.path().join("scene.rt");
    let src = format!(
        "
camera {{ position <0, 0, 1>  look_at <0, 0, 0>  distance 1  width 2  height 2 }}
render {{ width 40  height 40  gamma linear }}
ambient white intensity 1
rectangle {{ bottom_left <-1, -1, 0>  top_left <-1, 1, 0>  bottom_right <1, -1, 0>
            material {{ colour {texture} }} }}
"
    );
    std::fs::write(&scene, src).unwrap();
    render_path(&scene, None, 2)
}

/// The film and statistics of `src` over `region` (the whole picture when
/// `None`), on `threads` threads.
pub fn render_stats(src: &str, region: Option<Region>, threads: usize) -> (Film, RenderStats) {
    let mut scene = build_src(src);
    let world = raytrace::accel::World::build(std::mem::take(&mut scene.objects));
    let all = Region {
        x: 0,
        y: 0,
        width: scene.settings.width,
        height: scene.settings.height,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        render_region(
            &scene,
            &world,
            &RenderOptions {
                progress: None,
                cancel: None,
            },
            region.unwrap_or(all),
        )
    })
    .unwrap()
}
