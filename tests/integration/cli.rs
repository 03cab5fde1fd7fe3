//! The command line as a user meets it: exit codes, files written or not.

use crate::support::*;

const SCENE: &str = "
camera { position <0, 0, 4>  look_at <0, 0, 0>  fov 40 }
render { width 32  height 24 }
light { position <1, 2, 3> }
sphere { radius 1 }
";

#[test]
fn renders_a_png_of_the_requested_size() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(SCENE);
    let out = dir.path().join("out.png");
    let o = render_to(&scene, &out, &["--width", "40"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (40, 24));
    // Nothing else left behind (no temporary files).
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
}

#[test]
fn every_output_format_is_written() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(SCENE);
    for ext in ["png", "jpg", "jpeg", "exr", "hdr", "ppm"] {
        let out = dir.path().join(format!("out.{ext}"));
        let o = render_to(&scene, &out, &[]);
        assert!(o.status.success(), "{ext}: {}", stderr(&o));
        assert!(image::open(&out).is_ok(), "{ext} decodes");
    }
}

/// Every format holds the requested size, and the float formats hold the
/// linear values the renderer computed (not display-encoded ones): a grey
/// of linear 0.2 under ambient light 1 is 0.2 in `.exr` and `.hdr`, and
/// sRGB-encoded (0.2 → 124/255) in the 8-bit formats.
#[test]
fn output_formats_keep_size_and_float_ones_keep_linear_values() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(
        "camera { position <0, 0, 4>  look_at <0, 0, 0>  fov 40 }
render { width 30  height 20  gamma srgb }
ambient rgb(1, 1, 1) intensity 1
sphere { radius 1  material { colour rgb(0.2, 0.2, 0.2) } }",
    );
    // The sRGB curve at 0.2: 1.055·0.2^(1/2.4) − 0.055 = 0.4845 → 124.
    let srgb = 1.055 * 0.2f32.powf(1.0 / 2.4) - 0.055;
    for ext in ["png", "jpg", "exr", "hdr", "ppm"] {
        let out = dir.path().join(format!("out.{ext}"));
        let o = render_to(&scene, &out, &[]);
        assert!(o.status.success(), "{ext}: {}", stderr(&o));
        let img = image::open(&out).unwrap_or_else(|e| panic!("{ext}: {e}"));
        assert_eq!((img.width(), img.height()), (30, 20), "{ext}");
        // The centre pixel looks at the sphere; the corner at the background.
        let centre = img.to_rgb32f().get_pixel(15, 10).0;
        let corner = img.to_rgb32f().get_pixel(0, 0).0;
        let (want, tol) = match ext {
            "exr" => (0.2, 1e-6),
            "hdr" => (0.2, 0.2 / 128.0),
            "jpg" => (srgb, 4.0 / 255.0),
            _ => (srgb, 0.5 / 255.0),
        };
        for k in 0..3 {
            assert!(
                (centre[k] - want).abs() <= tol,
                "{ext}: {centre:?} vs {want}"
            );
            assert!(corner[k].abs() <= tol, "{ext}: background {corner:?}");
        }
    }
}

#[test]
fn unknown_extension_fails_before_rendering_and_writes_nothing() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(SCENE);
    let out = dir.path().join("out.gif");
    let o = render_to(&scene, &out, &[]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.contains("out.gif") && err.contains(".png"), "{err}");
    assert!(!out.exists());
}

#[test]
fn a_bad_scene_leaves_an_existing_image_untouched() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file("sphere { radius 1 ");
    let out = dir.path().join("out.png");
    std::fs::write(&out, b"precious").unwrap();
    let o = render_to(&scene, &out, &[]);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&out).unwrap(), b"precious");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
}

#[test]
fn check_builds_without_rendering() {
    let _watchdog = crate::watchdog::start();
    let (_dir, scene) = scene_file(SCENE);
    let o = raytrace(&[scene.as_os_str(), "--check".as_ref()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (_dir, bad) = scene_file("sphere { radius -1 }");
    let o = raytrace(&[bad.as_os_str(), "--check".as_ref()]);
    assert!(!o.status.success());
}

#[test]
fn stats_report_rays() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(SCENE);
    let out = dir.path().join("out.png");
    let o = render_to(&scene, &out, &["--stats"]);
    assert!(o.status.success());
    let err = stderr(&o);
    // 32 x 24 primary rays, one per pixel.
    assert!(err.contains("primary 768"), "{err}");
    assert!(err.contains("rays/s"), "{err}");
}

#[test]
fn bad_flags_are_refused() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(SCENE);
    let out = dir.path().join("out.png");
    for flags in [
        &["--width", "0"][..],
        &["--height", "-3"],
        &["--threads", "0"],
        &["--width", "abc"],
        &["--frobnicate"],
    ] {
        let o = render_to(&scene, &out, flags);
        assert!(!o.status.success(), "{flags:?} accepted");
        assert!(!out.exists());
    }
    // Output path that is a directory.
    let o = raytrace(&[scene.as_os_str(), "-o".as_ref(), dir.path().as_os_str()]);
    assert!(!o.status.success());
    // Missing scene file.
    let o = raytrace(&["/no/such/scene.rt".as_ref(), "-o".as_ref(), out.as_os_str()]);
    assert!(!o.status.success());
    assert!(!out.exists());
}

#[test]
fn huge_images_are_refused_before_allocating() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(SCENE);
    let out = dir.path().join("out.png");
    let o = render_to(&scene, &out, &["--width", "60000", "--height", "60000"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(err.contains("--allow-large"), "{err}");
    // 3.6 gigapixels at 15 bytes each (film and 8-bit copy): 50.3 GiB.
    assert!(
        err.contains("3600.0 megapixels") && err.contains("50.3 GiB"),
        "{err}"
    );
    assert!(!out.exists());
    // An .exr's copy is f32: 24 bytes a pixel, 80.5 GiB.
    let exr = dir.path().join("out.exr");
    let o = render_to(&scene, &exr, &["--width=60000", "--height=60000"]);
    let err = stderr(&o);
    assert!(err.contains("80.5 GiB"), "{err}");
}

#[test]
fn an_unbounded_implicit_surface_renders_with_a_warning() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(
        "camera { position <0, 2, 5>  look_at <0, 0, 0> }\nrender { width 8  height 6 }\nimplicit \"y\" { }\n",
    );
    let out = dir.path().join("out.png");
    let o = render_to(&scene, &out, &[]);
    assert!(o.status.success());
    let err = stderr(&o);
    assert!(err.contains("scene.rt:3:11: no bounding box"), "{err}");
    assert!(out.exists());
    let o = render_to(&scene, &out, &["--quiet"]);
    assert!(o.stderr.is_empty(), "--quiet is quiet");
}

/// A render that takes many seconds: a refusal that comes quickly came
/// before it.
const SLOW: &str = "camera { position <0, 0, 5> look_at <0, 0, 0> up <0, 1, 0> fov 40 }
render { width 3000 height 3000 samples 16 max_depth 8 }
light { position <2, 5, 5> intensity 1 }
sphere { radius 1 material { colour rgb(1, 1, 1) reflect 0.5 } }
plane { normal <0, 1, 0> material { colour rgb(1, 1, 1) reflect 0.5 } translate <0, -1, 0> }
";

/// Issue 17: the exit codes are decided, stated in `--help` and the
/// README, and each is what the program does.
#[test]
fn exit_codes_are_documented_and_kept() {
    let (dir, scene) = scene_file(SCENE);
    let out = dir.path().join("out.png");
    let help = raytrace(&["--help".as_ref()]);
    let text = String::from_utf8_lossy(&help.stdout);
    let readme = std::fs::read_to_string(project_root().join("README.md")).unwrap();
    for code in ["0 ", "1 ", "2 ", "3 ", "128+N"] {
        assert!(
            text.contains(&format!("  {code}")),
            "--help lacks {code}: {text}"
        );
        assert!(
            readme.contains(&format!("| {}", code.trim())),
            "README lacks {code}"
        );
    }
    // 1: a mistake in the scene.
    let (_d, bad) = scene_file("sphere { radius -1 }");
    assert_eq!(
        raytrace(&[bad.as_os_str(), "--check".as_ref()])
            .status
            .code(),
        Some(1)
    );
    // 2: the command line (clap's and ours).
    let o = render_to(&scene, &out, &["--frob"]);
    assert_eq!(o.status.code(), Some(2));
    let o = raytrace(&[scene.as_os_str(), "-o".as_ref(), "x.gif".as_ref()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // 3: the system: an unreadable scene, an unwritable folder.
    let o = raytrace(&["/no/such/scene.rt".as_ref(), "--check".as_ref()]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot read"), "{}", stderr(&o));
    let o = raytrace(&[
        scene.as_os_str(),
        "-o".as_ref(),
        "/no/such/dir/x.png".as_ref(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    // 0.
    let o = render_to(&scene, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// Issue 17: `--width 0` and `--height -5` were refused without the range;
/// `--width 100000` started rendering; `--threads 10000` failed after
/// seconds with "Resource temporarily unavailable".
#[test]
fn flag_ranges_are_stated_and_checked_first() {
    let (dir, scene) = scene_file(SCENE);
    let out = dir.path().join("out.png");
    for (flag, value, range) in [
        ("--width", "0", "1..=65535"),
        ("--height", "-5", "1..=65535"),
        ("--width", "100000", "1..=65535"),
        ("--threads", "10000", "1..=256"),
        ("--samples", "17", "1..=16"),
    ] {
        let start = std::time::Instant::now();
        let o = raytrace(&[
            scene.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
            format!("{flag}={value}").as_ref(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}");
        let e = stderr(&o);
        assert!(e.contains(flag) && e.contains(range), "{flag} {value}: {e}");
        assert!(start.elapsed().as_secs() < 5);
    }
    // A scene's own `render` block has the same range: a scene error.
    let (_d, wide) = scene_file(&SCENE.replace("width 32", "width 70000"));
    let o = render_to(&wide, &out, &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("from 1 to 65535"), "{}", stderr(&o));
    assert!(!out.exists());
}

/// Issue 17: one set of size limits, whichever sets the size. The command
/// line allowed 65535 a side while a scene's `render` block stopped at
/// 16384; now both take 1 to 65535 a side and both meet the 100-megapixel
/// guard before the first ray. Each limit is checked at its edge.
#[test]
fn a_scene_and_the_command_line_share_the_size_limits() {
    let _watchdog = crate::watchdog::start();
    let render =
        |w: u32, h: u32| SCENE.replace("width 32  height 24", &format!("width {w}  height {h}"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png");
    let run = |src: &str, extra: &[&str]| {
        let scene = dir.path().join("scene.rt");
        std::fs::write(&scene, src).unwrap();
        let start = std::time::Instant::now();
        let o = render_to(&scene, &out, extra);
        (o, start.elapsed())
    };
    // The widest side both ways: a 65535 × 1 strip renders, from the scene
    // and from the command line alike.
    for (src, extra) in [
        (render(65535, 1), &[][..]),
        (SCENE.to_string(), &["--width=65535", "--height=1"][..]),
    ] {
        let (o, _) = run(&src, extra);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let img = image::open(&out).unwrap();
        assert_eq!((img.width(), img.height()), (65535, 1));
        std::fs::remove_file(&out).unwrap();
    }
    // One past it, each side, from the scene: the message states the range.
    for src in [render(65536, 1), render(1, 65536)] {
        let (o, _) = run(&src, &[]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(stderr(&o).contains("from 1 to 65535"), "{}", stderr(&o));
        assert!(!out.exists());
    }
    // Over 100 megapixels from the scene (20000 × 20000, within the side
    // limit, which 16384 refused before): the same guard as the flags,
    // quickly and writing nothing; `--check` renders nothing and passes.
    let (o, took) = run(&render(20000, 20000), &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("400.0 megapixels") && stderr(&o).contains("--allow-large"),
        "{}",
        stderr(&o)
    );
    assert!(took.as_secs() < 5 && !out.exists());
    // Exactly 100 megapixels is allowed (checked, not rendered).
    let (o, _) = run(&render(10000, 10000), &["--check"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// Issue 17: `-o` naming the scene, an include or a texture, by any
/// spelling, overwrote it. It is refused before any rendering.
#[test]
fn the_output_may_not_be_one_of_the_scenes_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("sub")).unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([200, 10, 10]))
        .save(d.join("tex.png"))
        .unwrap();
    std::fs::write(d.join("inc.ppm"), "light { position <1, 2, 3> }\n").unwrap();
    // A scene whose name has an image extension.
    let scene = d.join("scene.hdr");
    std::fs::write(
        &scene,
        format!(
            "{SCENE}include \"inc.ppm\"\nmaterial m {{ colour image \"sub/../tex.png\" }}\nsphere {{ radius 0.5 material m }}\n"
        ),
    )
    .unwrap();
    let before: Vec<Vec<u8>> = ["scene.hdr", "inc.ppm", "tex.png"]
        .iter()
        .map(|f| std::fs::read(d.join(f)).unwrap())
        .collect();
    for target in [
        d.join("scene.hdr"),
        d.join("sub/../scene.hdr"),
        d.join("./inc.ppm"),
        d.join("tex.png"),
        d.join("sub/../sub/../tex.png"),
    ] {
        let o = render_to(&scene, &target, &[]);
        assert_eq!(
            o.status.code(),
            Some(2),
            "{}: {}",
            target.display(),
            stderr(&o)
        );
        assert!(
            stderr(&o).contains("the scene's own file"),
            "{}",
            stderr(&o)
        );
    }
    let after: Vec<Vec<u8>> = ["scene.hdr", "inc.ppm", "tex.png"]
        .iter()
        .map(|f| std::fs::read(d.join(f)).unwrap())
        .collect();
    assert_eq!(before, after);
    // Another file in the same folder is fine.
    let o = raytrace(&[
        scene.as_os_str(),
        "-o".as_ref(),
        d.join("out.png").as_os_str(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Issue 17: everything about the output is known before the first ray:
/// a missing or read-only folder and a name too long are refused at once,
/// not after a long render; a 250-character name works.
#[test]
fn output_problems_are_found_before_rendering() {
    let (dir, scene) = scene_file(SLOW);
    let long = "n".repeat(300) + ".png";
    let missing = dir.path().join("missing/out.png");
    let too_long = dir.path().join(&long);
    for (target, code, words) in [
        (missing.as_os_str(), 3, "does not exist"),
        (too_long.as_os_str(), 2, "the limit is 255 bytes"),
    ] {
        let start = std::time::Instant::now();
        let o = raytrace(&[scene.as_os_str(), "-o".as_ref(), target]);
        assert_eq!(o.status.code(), Some(code), "{}", stderr(&o));
        assert!(stderr(&o).contains(words), "{}", stderr(&o));
        assert!(start.elapsed().as_secs() < 5, "{:?}", start.elapsed());
    }
    // A read-only folder (root may write anyway, so only when it refuses).
    let ro = tempfile::tempdir().unwrap();
    let mut perm = std::fs::metadata(ro.path()).unwrap().permissions();
    perm.set_readonly(true);
    std::fs::set_permissions(ro.path(), perm).unwrap();
    if std::fs::File::create(ro.path().join("probe")).is_err() {
        let start = std::time::Instant::now();
        let o = raytrace(&[
            scene.as_os_str(),
            "-o".as_ref(),
            ro.path().join("x.png").as_os_str(),
        ]);
        assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
        assert!(stderr(&o).contains("no permission"), "{}", stderr(&o));
        assert!(start.elapsed().as_secs() < 5);
    }
    // 250 characters: the temporary's name is short, so this is written.
    let (dir, small) = scene_file(SCENE);
    let fine = dir.path().join("m".repeat(246) + ".png");
    let o = render_to(&small, &fine, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(image::open(&fine).is_ok());
}

/// Whether process `pid` has a handler for signal `n` (Linux's
/// /proc/PID/status `SigCgt` mask; elsewhere, assume so after a moment).
fn catches(pid: u32, n: i32) -> bool {
    let Ok(status) = std::fs::read_to_string(format!("/proc/{pid}/status")) else {
        std::thread::sleep(std::time::Duration::from_millis(500));
        return true;
    };
    status
        .lines()
        .find_map(|l| l.strip_prefix("SigCgt:"))
        .and_then(|m| u64::from_str_radix(m.trim(), 16).ok())
        .is_some_and(|mask| mask & (1 << (n - 1)) != 0)
}

/// Issue 17: SIGTERM and SIGHUP exited with 130. Every catchable signal
/// removes the temporary image and exits with 128 + its number.
#[cfg(unix)]
#[test]
fn signals_exit_with_128_plus_their_number_and_clean_up() {
    let (dir, scene) = scene_file(SLOW);
    let out = dir.path().join("out.png");
    std::fs::write(&out, b"the previous image").unwrap();
    for (signal, number) in [("-INT", 2), ("-TERM", 15), ("-HUP", 1), ("-USR1", 10)] {
        let mut child = spawn_render(&scene, &out);
        // Wait until the handlers are installed (the process's caught-signal
        // mask shows it), so the signal meets them and not the default.
        let start = std::time::Instant::now();
        while !catches(child.id(), number) {
            assert!(start.elapsed().as_secs() < 20, "no handler appeared");
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        std::thread::sleep(std::time::Duration::from_millis(200));
        send_signal(signal, child.id());
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(128 + number), "{signal}: {status:?}");
        assert_eq!(std::fs::read(&out).unwrap(), b"the previous image");
        let left = temporaries(dir.path());
        assert!(left.is_empty(), "{signal}: {left:?}");
    }
}

/// Issue 17: `--check` said nothing on success.
#[test]
fn check_prints_a_one_line_summary() {
    let (_dir, scene) = scene_file(SCENE);
    let o = raytrace(&[scene.as_os_str(), "--check".as_ref()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(
        text.contains("scene.rt: ok, 1 object, 1 light, no warnings"),
        "{text}"
    );
    let o = raytrace(&[scene.as_os_str(), "--check".as_ref(), "-q".as_ref()]);
    assert!(o.stdout.is_empty());
}
