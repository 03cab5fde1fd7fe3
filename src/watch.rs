//! `--watch`: write, save, see. `raytrace scene.rt -o out.png --watch`
//! renders, then waits; when the scene or any file it names changes it
//! renders again, first a coarse pass (a quarter of the resolution, one
//! sample a pixel, each pixel drawn as a 4×4 block) written at once, then
//! the full picture. Each pass replaces the output atomically (the
//! temporary file and rename of [`crate::output`]), so an image viewer that
//! reloads on change shows it.
//!
//! - A change while a pass renders cancels it (`RenderOptions::cancel`,
//!   checked per row) and starts again.
//! - Saves are debounced: editors write a file two or three times (a
//!   backup, a truncation, the text), so a render starts only once the
//!   files have been quiet for [`DEBOUNCE`].
//! - A scene with mistakes prints all its diagnostics, as a plain run
//!   does, and the last good picture stays.
//! - What is watched is every file the scene names, read from its text and
//!   its includes' by a tolerant scan ([`named_files`]) that works while
//!   the scene does not parse, and including files that do not exist yet:
//!   creating a missing include re-renders. Folders, not files, are
//!   watched (an editor that saves by renaming a new file over the old one
//!   replaces the inode a file watch would follow).
//! - Ctrl-C ends it as it ends a plain run (src/signals.rs): the temporary
//!   image is removed, the last complete one stays, the status is 130.

use crate::cli::{Args, Failure};
use crate::{FrameTime, accel, output, render, scene};
use notify::event::{AccessKind, AccessMode};
use notify::{EventKind, RecursiveMode, Watcher};
use std::collections::{BTreeSet, HashSet};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, channel};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

#[cfg(feature = "preview")]
use crate::preview::Preview as Window;

/// Without the `preview` feature there is no window (and `--preview` is
/// refused before anything is rendered).
#[cfg(not(feature = "preview"))]
#[derive(Default)]
struct Window {}

#[cfg(not(feature = "preview"))]
impl Window {
    fn show(&mut self, _: &render::Film, _: scene::Transfer, _: &str) -> Result<(), String> {
        Ok(())
    }
}

/// How long the files must be quiet after a change before rendering: long
/// enough to cover an editor's burst of writes, short enough not to be
/// felt.
pub const DEBOUNCE: Duration = Duration::from_millis(100);

/// The coarse pass renders every `COARSE`-th pixel in each direction.
pub const COARSE: u32 = 4;

/// Renders `args.scene` to `args.output`, then again on every change, until
/// the process is stopped. Returns only when watching cannot go on: the
/// output cannot be written, or the system refuses to watch files.
pub fn watch(args: &Args) -> Result<(), Failure> {
    crate::check_output_name(args)?;
    let Some(path) = args.output.clone() else {
        return Err(Failure::usage(miette::miette!(
            "--watch needs an output image: -o OUT.png"
        )));
    };
    if args.preview && !cfg!(feature = "preview") {
        return Err(Failure::usage(miette::miette!(
            help = "build it with the window: cargo install --path . --features preview",
            "this raytrace was built without the --preview window"
        )));
    }
    let pool = crate::thread_pool(args).map_err(Failure::system)?;
    let cancel = Arc::new(AtomicBool::new(false));
    let mut window = Window::default();
    let mut files = Files::new(cancel.clone()).map_err(Failure::system)?;
    let show = |line: String| {
        if !args.quiet {
            eprintln!("{line}");
        }
    };
    let mut watched = BTreeSet::new();
    loop {
        cancel.store(false, Ordering::SeqCst);
        let named = named_files(&args.scene);
        files.follow(&named);
        if named != watched {
            show(match named.len() - 1 {
                0 => format!("watching {}; Ctrl-C to stop", args.scene.display()),
                n => format!(
                    "watching {} and {n} file name{} in it; Ctrl-C to stop",
                    args.scene.display(),
                    if n == 1 { "" } else { "s" }
                ),
            });
            watched = named;
        }
        let title = format!("raytrace: {}", args.scene.display());
        let mut shown = |film: &render::Film, transfer: scene::Transfer| {
            if !args.preview {
                return Ok(());
            }
            window.show(film, transfer, &title).map_err(|e| {
                Failure::system(miette::miette!(
                    help = "--preview needs a display (is DISPLAY set?); --watch alone needs none",
                    "cannot open the preview window: {e}"
                ))
            })
        };
        match render_once(args, &pool, &path, &cancel, &mut shown) {
            Ok(Outcome::Done) => {}
            Ok(Outcome::Cancelled) => show("changed while rendering; starting again".to_string()),
            // The system refused to write the image or open the window:
            // editing the scene cannot mend that.
            Err(failure) if failure.exit == crate::cli::Exit::System => return Err(failure),
            Err(failure) => {
                // Every diagnostic, as a plain run prints them; the last
                // good picture is left where it is.
                eprintln!("{:?}", failure.report);
                show(if path.exists() {
                    format!("{} is unchanged; waiting for a change", path.display())
                } else {
                    "no picture yet; waiting for a change".to_string()
                });
            }
        }
        files.wait_for_change();
    }
}

/// How a round of rendering ended, when it did not fail.
#[derive(Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Both passes were written.
    Done,
    /// A file changed mid-render; what was written so far stays.
    Cancelled,
}

/// One round: parse, build, then the coarse and the full pass, each
/// written when done and then handed to `shown`; a set `cancel` stops it
/// between rows.
pub fn render_once(
    args: &Args,
    pool: &rayon::ThreadPool,
    path: &Path,
    cancel: &AtomicBool,
    shown: &mut dyn FnMut(&render::Film, scene::Transfer) -> Result<(), Failure>,
) -> Result<Outcome, Failure> {
    // A scene that cannot be read (an editor deleting it to save it anew)
    // is waited out like a mistake in it.
    let program = crate::load(args).map_err(|f| Failure::scene(f.report))?;
    let frame = FrameTime {
        clock: args.clock,
        frame: args.frame.unwrap_or(0) as f64,
    };
    let mut built = crate::build(args, &program, frame)?.scene;
    let inputs = crate::inputs(&program);
    let full = built.settings.clone();
    let region = crate::picture_region(args, &full).map_err(Failure::usage)?;
    // Checked before any ray, as a plain run does.
    drop(
        output::Target::prepare(path, region.width, region.height, &inputs)
            .map_err(Failure::output)?,
    );
    let world = accel::World::build(std::mem::take(&mut built.objects));
    let opts = render::RenderOptions {
        progress: None,
        cancel: Some(cancel),
    };
    let mut passes = vec![Pass::Full];
    if let Some(coarse) = Pass::coarse(&full, region) {
        passes.insert(0, coarse);
    }
    for pass in passes {
        let start = Instant::now();
        built.settings = pass.settings(&full);
        let film =
            pool.install(|| pass.render((full.width, full.height), &built, &world, &opts, region));
        if cancel.load(Ordering::SeqCst) {
            return Ok(Outcome::Cancelled);
        }
        let film =
            film.ok_or_else(|| Failure::scene(miette::miette!("the camera has no valid frame")))?;
        output::Target::prepare(path, region.width, region.height, &inputs)
            .and_then(|t| t.write(&film, full.transfer))
            .map_err(Failure::output)?;
        shown(&film, full.transfer)?;
        if !args.quiet {
            eprintln!(
                "rendered {}{} in {:.2} s",
                path.display(),
                pass.label(),
                start.elapsed().as_secs_f64()
            );
        }
    }
    Ok(Outcome::Done)
}

/// A pass of a round: the quick look, or the picture itself.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pass {
    /// The picture at `width`×`height` (a `COARSE`-th of the full size,
    /// rounded up), one sample a pixel, drawn back at full size by
    /// repeating each pixel.
    Coarse {
        width: u32,
        height: u32,
    },
    Full,
}

impl Pass {
    /// The coarse pass for a picture, when there is one worth making (the
    /// picture is at least two coarse pixels each way).
    fn coarse(full: &scene::RenderSettings, region: render::Region) -> Option<Pass> {
        let side = |n: u32| n.div_ceil(COARSE);
        if region.width < 2 * COARSE || region.height < 2 * COARSE {
            return None;
        }
        Some(Pass::Coarse {
            width: side(full.width),
            height: side(full.height),
        })
    }

    fn label(self) -> &'static str {
        match self {
            Pass::Coarse { .. } => " (coarse)",
            Pass::Full => "",
        }
    }

    /// The render settings of this pass.
    fn settings(self, full: &scene::RenderSettings) -> scene::RenderSettings {
        match self {
            Pass::Full => full.clone(),
            Pass::Coarse { width, height } => {
                let mut s = scene::RenderSettings {
                    width,
                    height,
                    adaptive: None,
                    ..full.clone()
                };
                s.set_square_grid(1);
                s
            }
        }
    }

    /// Renders `region` of the full picture with `scene`'s settings (this
    /// pass's); the film has the region's full size either way.
    fn render(
        self,
        full: (u32, u32),
        scene: &scene::Scene,
        world: &accel::World,
        opts: &render::RenderOptions,
        region: render::Region,
    ) -> Option<render::Film> {
        let Pass::Coarse { width, height } = self else {
            return render::render_region(scene, world, opts, region).map(|r| r.0);
        };
        let map = CoarseMap::new(region, full, (width, height));
        let (small, _) = render::render_region(scene, world, opts, map.coarse)?;
        Some(map.upscale(&small))
    }
}

/// Where each pixel of a full-size region finds its colour in the coarse
/// picture: the coarse pixel whose square holds the full pixel's centre.
#[derive(Clone, Copy, Debug)]
struct CoarseMap {
    /// The full picture's region.
    region: render::Region,
    /// The coarse picture's region that covers it.
    coarse: render::Region,
    /// Full pixels per coarse pixel, each way (≈ `COARSE`).
    sx: f64,
    sy: f64,
}

impl CoarseMap {
    /// The map for `region` of a `full`-sized picture (width, height)
    /// whose coarse version is `small` (width, height).
    fn new(region: render::Region, full: (u32, u32), small: (u32, u32)) -> CoarseMap {
        // Both pictures show the same frame, so a coarse pixel spans
        // full/small full pixels (COARSE, or a little less where the full
        // size is not a multiple of it).
        let sx = full.0 as f64 / small.0 as f64;
        let sy = full.1 as f64 / small.1 as f64;
        let at = |v: u32, s: f64| ((v as f64 + 0.5) / s).floor() as u32;
        let x0 = at(region.x, sx).min(small.0 - 1);
        let y0 = at(region.y, sy).min(small.1 - 1);
        let x1 = (at(region.x + region.width - 1, sx) + 1).min(small.0);
        let y1 = (at(region.y + region.height - 1, sy) + 1).min(small.1);
        CoarseMap {
            region,
            coarse: render::Region {
                x: x0,
                y: y0,
                width: x1 - x0,
                height: y1 - y0,
            },
            sx,
            sy,
        }
    }

    /// The coarse film drawn at the region's full size.
    fn upscale(&self, small: &render::Film) -> render::Film {
        let r = self.region;
        let at = |v: u32, s: f64, origin: u32, len: u32| {
            (((v as f64 + 0.5) / s).floor() as u32)
                .saturating_sub(origin)
                .min(len - 1)
        };
        let mut pixels = Vec::with_capacity(r.width as usize * r.height as usize);
        for y in r.y..r.y + r.height {
            let cy = at(y, self.sy, self.coarse.y, small.height);
            for x in r.x..r.x + r.width {
                let cx = at(x, self.sx, self.coarse.x, small.width);
                pixels.push(small.get(cx, cy));
            }
        }
        render::Film::new(r.width, r.height, pixels)
    }
}

/// The files being watched, and the events about them: a change to any of
/// them sets `cancel` at once (so that a render in progress stops) and
/// wakes [`Files::wait_for_change`].
struct Files {
    watcher: notify::RecommendedWatcher,
    /// The file names the scene reads, shared with the watcher's thread.
    names: Arc<Mutex<HashSet<PathBuf>>>,
    /// The folders watched for them.
    folders: BTreeSet<PathBuf>,
    changes: Receiver<PathBuf>,
}

impl Files {
    fn new(cancel: Arc<AtomicBool>) -> miette::Result<Files> {
        let names: Arc<Mutex<HashSet<PathBuf>>> = Arc::default();
        let (tx, changes) = channel();
        let shared = names.clone();
        let watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            let Ok(event) = event else { return };
            if !is_change(&event.kind) {
                return;
            }
            let names = shared.lock().unwrap_or_else(|e| e.into_inner());
            if let Some(p) = event.paths.iter().find(|p| concerns(p, &names)) {
                cancel.store(true, Ordering::SeqCst);
                let _ = tx.send(p.clone());
            }
        })
        .map_err(|e| miette::miette!("cannot watch files for changes: {e}"))?;
        Ok(Files {
            watcher,
            names,
            folders: BTreeSet::new(),
            changes,
        })
    }

    /// Watches `named` from now on (and no longer what it was before): the
    /// folder of each, or its nearest folder that exists.
    fn follow(&mut self, named: &BTreeSet<PathBuf>) {
        let folders: BTreeSet<PathBuf> = named.iter().filter_map(|p| nearest_folder(p)).collect();
        for gone in self.folders.difference(&folders) {
            let _ = self.watcher.unwatch(gone);
        }
        // Every folder is watched again each round, not only new ones: a
        // folder deleted and made again is a new one to the system, and
        // asking again follows it (for one still watched it is a no-op).
        for folder in &folders {
            // A folder that cannot be watched (gone a moment ago, no
            // permission) is skipped: the rest still are.
            let _ = self.watcher.watch(folder, RecursiveMode::NonRecursive);
        }
        self.folders = folders;
        *self.names.lock().unwrap_or_else(|e| e.into_inner()) = named.iter().cloned().collect();
    }

    /// Blocks until a watched file changes and then stays quiet for
    /// [`DEBOUNCE`].
    fn wait_for_change(&self) {
        if self.changes.recv().is_err() {
            // The watcher is gone; nothing will ever change again.
            loop {
                std::thread::park();
            }
        }
        loop {
            match self.changes.recv_timeout(DEBOUNCE) {
                Ok(_) => continue,
                Err(RecvTimeoutError::Timeout) => return,
                Err(RecvTimeoutError::Disconnected) => return,
            }
        }
    }
}

/// Whether an event can change what a file holds: reading one (our own
/// reads included) cannot.
fn is_change(kind: &EventKind) -> bool {
    match kind {
        EventKind::Access(AccessKind::Close(AccessMode::Write)) => true,
        EventKind::Access(_) => false,
        _ => true,
    }
}

/// Whether a changed path is one of the watched names, or a folder on the
/// way to one (a folder created or renamed into place).
fn concerns(path: &Path, names: &HashSet<PathBuf>) -> bool {
    let path = normal(path);
    names.contains(&path) || names.iter().any(|n| n.starts_with(&path) && *n != path)
}

/// The folder to watch for `file`: its own, or the nearest one above it
/// that exists.
fn nearest_folder(file: &Path) -> Option<PathBuf> {
    file.ancestors()
        .skip(1)
        .find(|d| d.is_dir())
        .map(Path::to_path_buf)
}

/// The most files [`named_files`] reads, and the most names it returns: a
/// scene's own include budget, and a bound on the watcher's work.
const MAX_SCANNED_FILES: usize = crate::lang::MAX_INCLUDES;
const MAX_NAMES: usize = 100_000;

/// Every file the scene at `scene` may read: itself, and each string in its
/// text resolved against its folder, existing or not; includes (existing
/// ones) are read and scanned the same way. The scan needs no parse, so it
/// works while the scene has mistakes, and it looks at every string (a
/// string that names no file costs a name in a set).
pub fn named_files(scene: &Path) -> BTreeSet<PathBuf> {
    let mut names = BTreeSet::new();
    let root = normal(scene);
    names.insert(root.clone());
    let mut queue = vec![root];
    let mut read = HashSet::new();
    while let Some(file) = queue.pop() {
        if read.len() >= MAX_SCANNED_FILES || !read.insert(file.clone()) {
            continue;
        }
        let Ok(bytes) = crate::lang::source::read_bounded(&file, crate::lang::MAX_TOTAL_BYTES)
        else {
            continue;
        };
        let text = String::from_utf8_lossy(&bytes);
        let dir = file.parent().map(Path::to_path_buf).unwrap_or_default();
        for s in strings(&text) {
            if names.len() >= MAX_NAMES {
                break;
            }
            if s.text.is_empty() || s.text.starts_with(crate::stdlib::PREFIX) {
                continue;
            }
            let p = normal(&dir.join(s.text));
            if s.included && p.is_file() {
                queue.push(p.clone());
            }
            names.insert(p);
        }
    }
    names
}

/// A string literal in scene text, and whether `include` precedes it.
#[derive(Debug, PartialEq)]
struct Str<'a> {
    text: &'a str,
    included: bool,
}

/// The string literals of scene text, outside comments, as the grammar
/// has them: `"` to `"` on one line, no escapes. Malformed text (an
/// unclosed string or comment) ends the scan where it goes wrong.
fn strings(text: &str) -> Vec<Str<'_>> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut word: &str = "";
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                i = text[i..].find('\n').map_or(b.len(), |k| i + k);
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i = text[i + 2..].find("*/").map_or(b.len(), |k| i + 2 + k + 2);
            }
            b'"' => {
                let rest = &text[i + 1..];
                let Some(k) = rest.find(['"', '\n']) else {
                    break;
                };
                if rest.as_bytes()[k] == b'"' {
                    out.push(Str {
                        text: &rest[..k],
                        included: word == "include",
                    });
                }
                word = "";
                i += k + 2;
            }
            c if c.is_ascii_alphanumeric() || c == b'_' => {
                let len = text[i..]
                    .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                    .unwrap_or(b.len() - i);
                word = &text[i..i + len];
                i += len;
            }
            c if c.is_ascii_whitespace() => i += 1,
            _ => {
                word = "";
                i += 1;
            }
        }
    }
    out
}

/// An absolute path with `.` and `..` resolved by their names (not by the
/// file system, so that names of files that do not exist yet compare equal
/// to the paths the watcher reports for them).
fn normal(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for c in absolute.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(src: &str) -> Vec<(&str, bool)> {
        strings(src).iter().map(|s| (s.text, s.included)).collect()
    }

    #[test]
    fn strings_are_found_outside_comments_with_their_include() {
        let src = "include \"a.rt\"\n// include \"no.rt\"\n/* \"no\" */ mesh { file \"m.ply\" }\n\
                   include/* c */\"b.rt\" x = \"eq\" include 3 \"c\"";
        assert_eq!(
            texts(src),
            vec![
                ("a.rt", true),
                ("m.ply", false),
                ("b.rt", true),
                ("eq", false),
                ("c", false)
            ]
        );
    }

    #[test]
    fn a_broken_string_or_comment_ends_the_scan_without_a_panic() {
        assert_eq!(
            texts("\"a\" \"unclosed\n\"b\""),
            vec![("a", false), ("b", false)]
        );
        assert_eq!(texts("\"a\" /* open"), vec![("a", false)]);
        assert_eq!(texts("\"a\" \"no end"), vec![("a", false)]);
        assert_eq!(texts("é \"ü\" /"), vec![("ü", false)]);
    }

    #[test]
    fn named_files_follow_includes_and_keep_names_that_do_not_exist() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::create_dir(d.join("sub")).unwrap();
        std::fs::write(
            d.join("scene.rt"),
            "include \"sub/part.rt\" include \"missing.rt\" include \"std/metals.rt\" {",
        )
        .unwrap();
        std::fs::write(d.join("sub/part.rt"), "mesh { file \"../m/bunny.ply\" }").unwrap();
        let names = named_files(&d.join("scene.rt"));
        let d = normal(d);
        let want: BTreeSet<PathBuf> = ["scene.rt", "sub/part.rt", "missing.rt", "m/bunny.ply"]
            .iter()
            .map(|p| d.join(p))
            .collect();
        assert_eq!(names, want);
        // `m/` does not exist: its nearest folder is watched, and creating
        // `m` there concerns the name inside it.
        assert_eq!(nearest_folder(&d.join("m/bunny.ply")), Some(d.clone()));
        let set: HashSet<PathBuf> = names.into_iter().collect();
        assert!(concerns(&d.join("m"), &set));
        assert!(concerns(&d.join("sub/./part.rt"), &set));
        assert!(!concerns(&d.join("out.png"), &set));
        assert!(!concerns(&d.join("sub/other.rt"), &set));
    }

    #[test]
    fn include_cycles_are_scanned_once() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("a.rt"), "include \"b.rt\"").unwrap();
        std::fs::write(d.join("b.rt"), "include \"a.rt\" include \"./a.rt\"").unwrap();
        assert_eq!(named_files(&d.join("a.rt")).len(), 2);
    }

    #[test]
    fn reading_is_not_a_change_and_writing_is() {
        use notify::event::{CreateKind, ModifyKind};
        assert!(!is_change(&EventKind::Access(AccessKind::Open(
            AccessMode::Any
        ))));
        assert!(!is_change(&EventKind::Access(AccessKind::Close(
            AccessMode::Read
        ))));
        assert!(is_change(&EventKind::Access(AccessKind::Close(
            AccessMode::Write
        ))));
        assert!(is_change(&EventKind::Modify(ModifyKind::Any)));
        assert!(is_change(&EventKind::Create(CreateKind::File)));
    }

    fn region(x: u32, y: u32, width: u32, height: u32) -> render::Region {
        render::Region {
            x,
            y,
            width,
            height,
        }
    }

    #[test]
    fn the_coarse_picture_covers_the_region_and_upscales_to_its_size() {
        for (w, h, r) in [
            (100u32, 75u32, region(0, 0, 100, 75)),
            (101, 37, region(0, 0, 101, 37)),
            (100, 75, region(13, 9, 40, 30)),
            (64, 64, region(60, 60, 4, 4)),
        ] {
            let (cw, ch) = (w.div_ceil(COARSE), h.div_ceil(COARSE));
            let map = CoarseMap::new(r, (w, h), (cw, ch));
            let c = map.coarse;
            assert!(c.x + c.width <= cw && c.y + c.height <= ch, "{r:?}: {c:?}");
            // Each coarse pixel gets its own colour: the upscaled film
            // must show every one of them, in order, and no other.
            let pixels = (0..c.width * c.height)
                .map(|i| [i as f32, 0.0, 0.0])
                .collect();
            let small = render::Film::new(c.width, c.height, pixels);
            let big = map.upscale(&small);
            assert_eq!((big.width, big.height), (r.width, r.height));
            let mut seen = BTreeSet::new();
            for y in 0..r.height {
                for x in 0..r.width {
                    let v = big.get(x, y)[0] as u32;
                    let (cx, cy) = (v % c.width, v / c.width);
                    // The full pixel's centre lies in the coarse pixel's
                    // square (in the full picture's coordinates).
                    let fx = (r.x + x) as f64 + 0.5;
                    let fy = (r.y + y) as f64 + 0.5;
                    let (sx, sy) = (w as f64 / cw as f64, h as f64 / ch as f64);
                    assert!(((c.x + cx) as f64 * sx..(c.x + cx + 1) as f64 * sx).contains(&fx));
                    assert!(((c.y + cy) as f64 * sy..(c.y + cy + 1) as f64 * sy).contains(&fy));
                    seen.insert(v);
                }
            }
            assert_eq!(seen.len() as u32, c.width * c.height, "{r:?}");
        }
    }
}
