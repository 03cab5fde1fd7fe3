//! `--watch`, as a user runs it: the program started as a child process,
//! the scene edited on disk, the picture on disk looked at.

use crate::support;
use clap::Parser;
use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How long a change may take to show: generous, as the machine running
/// the tests is often busy compiling.
const BOUND: Duration = Duration::from_secs(20);

/// A 64×48 picture filled by a rectangle lit by ambient light alone, in
/// linear gamma: every pixel is the colour named by `colour` (a name the
/// scene or its includes define, or an expression).
fn flat(colour: &str) -> String {
    format!(
        "
camera {{ position <0, 0, 1>  look_at <0, 0, 0>  distance 1  width 2  height 2 }}
render {{ width 64  height 48  gamma linear  samples 2 }}
ambient white intensity 1
rectangle {{ bottom_left <-2, -2, 0>  top_left <-2, 2, 0>  bottom_right <2, -2, 0>
            material {{ colour {colour} }} }}
"
    )
}

/// The running `raytrace --watch`, killed if the test fails; its stderr
/// collected as it comes.
struct Watching {
    child: Child,
    stderr: Arc<Mutex<String>>,
}

impl Watching {
    fn start(scene: &Path, out: &Path) -> Watching {
        let mut child = Command::new(env!("CARGO_BIN_EXE_raytrace"))
            .args([
                scene.as_os_str(),
                "-o".as_ref(),
                out.as_os_str(),
                "--watch".as_ref(),
                "--threads".as_ref(),
                "2".as_ref(),
            ])
            .stderr(Stdio::piped())
            .spawn()
            .expect("start raytrace --watch");
        let stderr = Arc::new(Mutex::new(String::new()));
        let mut pipe = child.stderr.take().expect("stderr is piped");
        let sink = stderr.clone();
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while let Ok(n) = pipe.read(&mut buf) {
                if n == 0 {
                    break;
                }
                sink.lock()
                    .unwrap()
                    .push_str(&String::from_utf8_lossy(&buf[..n]));
            }
        });
        Watching { child, stderr }
    }

    fn stderr(&self) -> String {
        self.stderr.lock().unwrap().clone()
    }

    /// Waits until `ok` holds of the stderr so far, or fails the test.
    fn wait_for_stderr(&self, what: &str, ok: impl Fn(&str) -> bool) {
        let start = Instant::now();
        while !ok(&self.stderr()) {
            assert!(
                start.elapsed() < BOUND,
                "no {what} on stderr within {BOUND:?}; stderr:\n{}",
                self.stderr()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Watching {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The centre pixel of the image at `out`, if there is one to read.
fn centre(out: &Path) -> Option<[u8; 3]> {
    let img = image::open(out).ok()?.to_rgb8();
    Some(img.get_pixel(img.width() / 2, img.height() / 2).0)
}

/// Waits until the image at `out` is the full 64×48 picture with centre
/// pixel `want`, or fails the test.
fn wait_for_picture(w: &Watching, out: &Path, want: [u8; 3]) {
    let start = Instant::now();
    loop {
        let full = image::image_dimensions(out).is_ok_and(|d| d == (64, 48));
        if full && centre(out) == Some(want) {
            return;
        }
        assert!(
            start.elapsed() < BOUND,
            "{} did not show {want:?} within {BOUND:?} (centre {:?}); stderr:\n{}",
            out.display(),
            centre(out),
            w.stderr()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

const RED: [u8; 3] = [255, 0, 0];
const BLUE: [u8; 3] = [0, 0, 255];
const GREEN: [u8; 3] = [0, 255, 0];

#[test]
fn watch_re_renders_on_save_keeps_the_last_picture_through_mistakes_and_stops_on_ctrl_c() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.rt");
    let out = dir.path().join("out.png");
    std::fs::write(&scene, flat("rgb(1, 0, 0)")).unwrap();
    let w = Watching::start(&scene, &out);

    // The first picture, coarse pass first.
    wait_for_picture(&w, &out, RED);
    w.wait_for_stderr("line for the full pass", |e| {
        e.contains("rendered") && e.contains("out.png in ")
    });
    let err = w.stderr();
    let coarse = err
        .find("out.png (coarse) in ")
        .expect("a coarse pass line");
    assert!(coarse < err.find("out.png in ").unwrap(), "{err}");

    // An edit: the picture is replaced.
    std::fs::write(&scene, flat("rgb(0, 0, 1)")).unwrap();
    wait_for_picture(&w, &out, BLUE);
    let blue = std::fs::read(&out).unwrap();

    // Two mistakes: both reported, the picture kept.
    let bad = flat("rgb(0, 1, 0)")
        .replace("ambient white", "ambient whiet")
        .replace("bottom_right", "bottom_rihgt");
    std::fs::write(&scene, bad).unwrap();
    w.wait_for_stderr("diagnostics", |e| {
        e.contains("bottom_rihgt") && e.contains("whiet")
    });
    w.wait_for_stderr("note that the picture is kept", |e| {
        e.contains("out.png is unchanged")
    });
    assert_eq!(
        std::fs::read(&out).unwrap(),
        blue,
        "the last good picture stays"
    );

    // An include that does not exist yet: an error, then creating the
    // file is a change like any other.
    std::fs::write(&scene, format!("include \"colour.rt\"\n{}", flat("C"))).unwrap();
    w.wait_for_stderr("missing include", |e| {
        e.contains("cannot find the included file `colour.rt`")
    });
    assert_eq!(std::fs::read(&out).unwrap(), blue);
    std::fs::write(dir.path().join("colour.rt"), "let C = rgb(0, 1, 0)\n").unwrap();
    wait_for_picture(&w, &out, GREEN);

    // The included file is watched too.
    std::fs::write(dir.path().join("colour.rt"), "let C = rgb(1, 0, 0)\n").unwrap();
    wait_for_picture(&w, &out, RED);

    // Ctrl-C: the shell's status for it, and no temporary left.
    let mut w = w;
    support::send_signal("-INT", w.child.id());
    let start = Instant::now();
    let status = loop {
        if let Some(s) = w.child.try_wait().unwrap() {
            break s;
        }
        assert!(start.elapsed() < BOUND, "--watch did not stop on Ctrl-C");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(status.code(), Some(130));
    assert!(support::temporaries(dir.path()).is_empty());
    assert_eq!(centre(&out), Some(RED));
}

#[test]
fn a_cancelled_round_writes_nothing_and_a_whole_one_writes_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.rt");
    let out = dir.path().join("out.png");
    std::fs::write(&scene, flat("rgb(0, 1, 0)")).unwrap();
    let args = raytrace::cli::Args::parse_from([
        "raytrace".as_ref(),
        scene.as_os_str(),
        "-q".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let round = |cancel: bool| {
        raytrace::watch::render_once(&args, &pool, &out, &AtomicBool::new(cancel), &mut |_, _| {
            Ok(())
        })
        .unwrap_or_else(|f| panic!("{f:?}"))
    };
    assert_eq!(round(true), raytrace::watch::Outcome::Cancelled);
    assert!(!out.exists(), "a cancelled round writes no picture");
    assert!(support::temporaries(dir.path()).is_empty());
    assert_eq!(round(false), raytrace::watch::Outcome::Done);
    assert_eq!(centre(&out), Some(GREEN));
}

#[test]
fn a_set_cancel_flag_stops_a_render_and_a_clear_one_does_not() {
    let (_dir, path) = support::scene_file(&flat("rgb(1, 1, 1)"));
    let mut scene = support::build_path(&path);
    let world = raytrace::accel::World::build(std::mem::take(&mut scene.objects));
    let render = |flag: bool| {
        let cancel = AtomicBool::new(flag);
        let opts = raytrace::render::RenderOptions {
            progress: None,
            cancel: Some(&cancel),
        };
        raytrace::render::render(&scene, &world, &opts)
    };
    assert!(render(true).is_none());
    let (film, _) = render(false).expect("a picture");
    assert_eq!((film.width, film.height), (64, 48));
}

/// The README's first scene: each step's lines, added in order, give a
/// scene that builds, and together they are examples/first_scene.rt.
#[test]
fn the_readme_first_scene_builds_at_every_step_and_is_the_example() {
    let readme = std::fs::read_to_string(support::project_root().join("README.md")).unwrap();
    let start = readme.find("## Your first scene").expect("the section");
    let section = &readme[start..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |k| k + 3)];
    let blocks: Vec<&str> = section
        .split("```rt\n")
        .skip(1)
        .map(|b| &b[..b.find("```").expect("a closed block")])
        .collect();
    assert!(blocks.len() >= 4, "{blocks:?}");
    let mut scene = String::new();
    for (k, block) in blocks.iter().enumerate() {
        scene.push_str(block);
        let (_dir, path) = support::scene_file(&scene);
        let program = raytrace::lang::load(&path).unwrap_or_else(|e| panic!("step {k}: {e:?}"));
        raytrace::scene::build(&program).unwrap_or_else(|e| panic!("step {k}: {e:?}"));
    }
    // The example has every line of the steps, in order (its render block
    // with the last step's `samples 3` added).
    let example =
        std::fs::read_to_string(support::project_root().join("examples/first_scene.rt")).unwrap();
    let mut lines = example.lines();
    for want in scene.lines() {
        let want = want.replace("rgb(0.5, 0.7, 0.9) }", "rgb(0.5, 0.7, 0.9)  samples 3 }");
        assert!(
            lines.any(|l| l == want),
            "examples/first_scene.rt lacks, or has out of order: {want}"
        );
    }
}

#[cfg(not(feature = "preview"))]
#[test]
fn preview_without_the_feature_is_refused_before_any_work() {
    let (dir, scene) = support::scene_file(&flat("rgb(1, 0, 0)"));
    let out = dir.path().join("out.png");
    let o = support::render_to(&scene, &out, &["--preview"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(support::stderr(&o).contains("--features preview"));
    assert!(!out.exists());
}

/// The preview window, tried as a user would see it: under a virtual X
/// server (Xvfb), screenshots taken with `xwd` show the picture, then the
/// edited one. Skipped, saying so, where Xvfb or xwd is not installed
/// (`apt-get install xvfb x11-apps`).
#[cfg(feature = "preview")]
#[test]
fn preview_shows_the_picture_in_a_window_and_follows_edits() {
    let have = |tool: &str| {
        Command::new("sh")
            .args(["-c", &format!("command -v {tool}")])
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if !have("Xvfb") || !have("xwd") {
        eprintln!("skipped: the preview test needs Xvfb and xwd");
        return;
    }
    let display = format!(":{}", 50 + std::process::id() % 1000);
    struct Kill(Child);
    impl Drop for Kill {
        fn drop(&mut self) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
    let _xvfb = Kill(
        Command::new("Xvfb")
            .args([display.as_str(), "-screen", "0", "320x240x24"])
            .stderr(Stdio::null())
            .spawn()
            .expect("start Xvfb"),
    );
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.rt");
    let out = dir.path().join("out.png");
    std::fs::write(&scene, flat("rgb(1, 0, 0)")).unwrap();
    let shot = dir.path().join("shot.xwd");
    // How many pixels of the screen are `rgb`.
    let count = |rgb: [u8; 3]| -> usize {
        let ok = Command::new("xwd")
            .args(["-root", "-display", &display, "-out"])
            .arg(&shot)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            return 0;
        }
        xwd_pixels(&std::fs::read(&shot).unwrap())
            .iter()
            .filter(|p| **p == rgb)
            .count()
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_raytrace"))
        .args([
            scene.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            "--preview".as_ref(),
        ])
        .env("DISPLAY", &display)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let _stderr = child.stderr.take();
    let _child = Kill(child);
    let wait_for = |what: &str, ok: &dyn Fn() -> bool| {
        let start = Instant::now();
        while !ok() {
            assert!(start.elapsed() < BOUND, "the window never showed {what}");
            std::thread::sleep(Duration::from_millis(100));
        }
    };
    // The whole 64×48 picture is in the window, and more than most of
    // it is on screen (the window may be scaled, never smaller).
    wait_for("the red picture", &|| count(RED) >= 64 * 48 * 9 / 10);
    std::fs::write(&scene, flat("rgb(0, 0, 1)")).unwrap();
    wait_for("the edited picture", &|| {
        count(BLUE) >= 64 * 48 * 9 / 10 && count(RED) == 0
    });
}

/// The pixels of an X window dump (`xwd`, ZPixmap, 24 or 32 bits a
/// pixel) as RGB.
#[cfg(feature = "preview")]
fn xwd_pixels(data: &[u8]) -> Vec<[u8; 3]> {
    let field = |k: usize| u32::from_be_bytes(data[4 * k..4 * k + 4].try_into().unwrap()) as usize;
    let (header, width, height) = (field(0), field(4), field(5));
    let (lsb_first, bits, line, colours) = (field(7) == 0, field(11), field(12), field(19));
    assert!(bits == 32 || bits == 24, "{bits} bits a pixel");
    let start = header + colours * 12;
    let mut out = Vec::with_capacity(width * height);
    for y in 0..height {
        for x in 0..width {
            let at = start + y * line + x * (bits / 8);
            // Most significant byte first, a 32-bit pixel is pad, R, G, B.
            out.push(match (lsb_first, bits) {
                (true, _) => [data[at + 2], data[at + 1], data[at]],
                (false, 32) => [data[at + 1], data[at + 2], data[at + 3]],
                (false, _) => [data[at], data[at + 1], data[at + 2]],
            });
        }
    }
    out
}
