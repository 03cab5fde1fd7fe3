//! The command line as a user meets it: exit codes, files written or not.

use crate::support::*;
use std::process::{Command, Output};

fn raytrace(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raytrace"))
        .args(args)
        .output()
        .expect("run raytrace")
}

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
    let o = raytrace(&[
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--width".as_ref(),
        "40".as_ref(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
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
        let o = raytrace(&[scene.as_os_str(), "-o".as_ref(), out.as_os_str()]);
        assert!(
            o.status.success(),
            "{ext}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
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
        let o = raytrace(&[scene.as_os_str(), "-o".as_ref(), out.as_os_str()]);
        assert!(
            o.status.success(),
            "{ext}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
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
    let o = raytrace(&[scene.as_os_str(), "-o".as_ref(), out.as_os_str()]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("out.gif") && err.contains(".png"), "{err}");
    assert!(!out.exists());
}

#[test]
fn a_bad_scene_leaves_an_existing_image_untouched() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file("sphere { radius 1 ");
    let out = dir.path().join("out.png");
    std::fs::write(&out, b"precious").unwrap();
    let o = raytrace(&[scene.as_os_str(), "-o".as_ref(), out.as_os_str()]);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&out).unwrap(), b"precious");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
}

#[test]
fn check_builds_without_rendering() {
    let _watchdog = crate::watchdog::start();
    let (_dir, scene) = scene_file(SCENE);
    let o = raytrace(&[scene.as_os_str(), "--check".as_ref()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (_dir, bad) = scene_file("sphere { radius -1 }");
    let o = raytrace(&[bad.as_os_str(), "--check".as_ref()]);
    assert!(!o.status.success());
}

#[test]
fn stats_report_rays() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(SCENE);
    let out = dir.path().join("out.png");
    let o = raytrace(&[
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--stats".as_ref(),
    ]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
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
        let mut args = vec![scene.as_os_str(), "-o".as_ref(), out.as_os_str()];
        args.extend(flags.iter().map(std::ffi::OsStr::new));
        let o = raytrace(&args);
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
    let o = raytrace(&[
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--width".as_ref(),
        "100000".as_ref(),
        "--height".as_ref(),
        "100000".as_ref(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--allow-large"), "{err}");
    assert!(!out.exists());
}

#[test]
fn an_unbounded_implicit_surface_renders_with_a_warning() {
    let _watchdog = crate::watchdog::start();
    let (dir, scene) = scene_file(
        "camera { position <0, 2, 5>  look_at <0, 0, 0> }\nrender { width 8  height 6 }\nimplicit \"y\" { }\n",
    );
    let out = dir.path().join("out.png");
    let o = raytrace(&[scene.as_os_str(), "-o".as_ref(), out.as_os_str()]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("scene.rt:3:11: no bounding box"), "{err}");
    assert!(out.exists());
    let o = raytrace(&[
        scene.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(o.stderr.is_empty(), "--quiet is quiet");
}
