//! Adaptive sampling and regions: more samples only where a pixel's
//! samples disagree, exactly the pictures of the fixed sample counts where
//! it decides, and any rectangle of a picture rendered alone is the same
//! pixels.

use crate::support::*;
use raytrace::render::{Film, Region};

/// A grey disc on a darker background, lit by a small sphere light (its
/// shading noise) and seen through a lens, with `render` settings.
fn disc_scene(render: &str) -> String {
    format!(
        "
camera {{ position <0, 0, 5>  look_at <0, 0, 0>  fov 40  aperture 0.02  focus 5 }}
render {{ width 40  height 30  gamma linear  background rgb(0.2, 0.2, 0.2)  {render} }}
light {{ position <0, 0, 10> }}
disc {{ radius 1  material {{ colour rgb(0.7, 0.7, 0.7)  ambient 0 }} }}
"
    )
}

#[test]
fn adaptive_sampling_refines_only_where_samples_disagree() {
    let _watchdog = crate::watchdog::start();
    let base = "sampler multijittered  seed 3";
    let two = disc_scene(&format!("{base}  samples 2"));
    let six = disc_scene(&format!("{base}  samples 6"));
    let adaptive = disc_scene(&format!(
        "{base}  samples 2  adaptive {{ threshold 0.05  max_samples 6 }}"
    ));
    let (f2, s2) = render_stats(&two, None, 2);
    let (f6, _) = render_stats(&six, None, 2);
    let (fa, sa) = render_stats(&adaptive, None, 2);
    let pixels = 40 * 30;
    assert_eq!(s2.rays.primary, 4 * pixels);
    assert_eq!(s2.rays.refined, 0);
    // Each refined pixel took its 4 first samples and then 36.
    let refined = sa.rays.refined;
    assert_eq!(sa.rays.primary, 4 * pixels + 36 * refined);
    // Only pixels on the rim of the disc disagree (its circumference, 2π·1
    // units at 40 / (2·5·tan 20°) = 11 pixels a unit, crosses about 70;
    // those whose four samples all fall on one side cannot tell): a few
    // of the 1200.
    assert!(refined > 25 && refined < 150, "{refined} refined");
    // Every pixel is exactly the 2 × 2 picture's or the 6 × 6 one's, and
    // the refined ones are those whose 2 × 2 samples straddle the rim.
    let (mut as_two, mut as_six) = (0, 0);
    for i in 0..fa.pixels.len() {
        let p = fa.pixels[i];
        if p == f2.pixels[i] {
            as_two += 1;
        } else {
            assert_eq!(p, f6.pixels[i], "pixel {i} is neither");
            as_six += 1;
            // The 2 × 2 value there is a mixture of disc and background.
            let v = f2.pixels[i][0];
            assert!(v > 0.2 + 0.02 && v < 0.7 - 0.02, "{v} at {i}");
        }
    }
    assert_eq!(as_six as u64, refined, "{as_two} + {as_six}");
    // So the adaptive picture is much nearer the 6 × 6 one than the 2 × 2
    // one is.
    let (near, far) = (max_difference_sum(&fa, &f6), max_difference_sum(&f2, &f6));
    assert!(near < 0.5 * far, "{near} vs {far}");
    // A picture without edges refines nothing.
    let (_, flat) = render_stats(
        &disc_scene(&format!(
            "{base}  samples 2  adaptive {{ threshold 0.05  max_samples 6 }}"
        ))
        .replace("fov 40", "fov 5")
        .replace("width 40  height 30", "width 4  height 4"),
        None,
        1,
    );
    assert_eq!((flat.rays.refined, flat.rays.primary), (0, 4 * 16));
}

#[test]
fn adaptive_pictures_converge_to_the_max_samples_picture_with_noise() {
    let _watchdog = crate::watchdog::start();
    // A soft shadow of a disc light: noisy everywhere in the penumbra. A
    // lower threshold refines more pixels and brings the picture closer to
    // the 8 × 8 one; threshold 1 (nothing can differ by more) refines none.
    let scene = |render: &str| {
        format!(
            "
camera {{ position <0, 4, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 90 }}
render {{ width 40  height 20  gamma linear  sampler multijittered  {render} }}
material lamp {{ emit white  intensity 20 }}
disc {{ radius 1  rotate x 90  translate <0, 6, 0>  material lamp }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
rectangle {{ bottom_left <-30, 3, -30>  top_left <-30, 3, 30>  bottom_right <0, 3, -30> }}
"
        )
    };
    let (f8, _) = render_stats(&scene("samples 8"), None, 2);
    let (f2, _) = render_stats(&scene("samples 2"), None, 2);
    let mut last = max_difference_sum(&f2, &f8);
    let mut last_refined = 0;
    for t in [0.2, 0.05, 0.001] {
        let (fa, sa) = render_stats(
            &scene(&format!(
                "samples 2  adaptive {{ threshold {t}  max_samples 8 }}"
            )),
            None,
            2,
        );
        let d = max_difference_sum(&fa, &f8);
        assert!(d < last, "threshold {t}: {d} vs {last}");
        assert!(sa.rays.refined > last_refined);
        (last, last_refined) = (d, sa.rays.refined);
    }
    let (none, s) = render_stats(
        &scene("samples 2  adaptive { threshold 1  max_samples 8 }"),
        None,
        2,
    );
    assert_eq!((none.clone(), s.rays.refined), (f2, 0));
}

/// The summed absolute difference of two films.
fn max_difference_sum(a: &Film, b: &Film) -> f64 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (0..3).map(|i| (p[i] - q[i]).abs() as f64).sum::<f64>())
        .sum()
}

#[test]
fn a_region_renders_the_full_pictures_pixels_for_any_thread_count() {
    let _watchdog = crate::watchdog::start();
    // Every random part at once: lens, glossy, area light, occlusion,
    // adaptive refinement.
    let src = "
camera { position <0, 2, 6>  look_at <0, 0.5, 0>  fov 50  aperture 0.1  focus 6 }
render { width 40  height 30  samples 2  sampler multijittered  seed 11  max_depth 4  adaptive { threshold 0.1  max_samples 4 } }
ambient rgb(1, 1, 1) intensity 0.2 occlusion { samples 2  min 0.2 }
material lamp { emit white  intensity 20 }
sphere { centre <0, 4, 0>  radius 0.5  material lamp }
sphere { centre <-1, 0.7, 0>  radius 0.7  material { colour rgb(0.8, 0.6, 0.2)  mirror 0.6  glossy 40 } }
sphere { centre <1, 0.7, 0>  radius 0.7  material { refract { ior 1.5  filter rgb(0.6, 0.9, 0.7) } } }
plane { normal <0, 1, 0>  material { colour rgb(0.9, 0.9, 0.9) } }
";
    // And with one sample a pixel (never refined): those pictures make
    // a few neighbours' camera rays together from where each chunk of the
    // row starts, which a region moves (13 here, 8 and 16 in the full
    // picture), so each pixel must still draw its own numbers.
    let single = src.replace(
        "samples 2  sampler multijittered  seed 11  max_depth 4  adaptive { threshold 0.1  max_samples 4 }",
        "samples 1  sampler multijittered  seed 11  max_depth 4",
    );
    assert_ne!(single, src);
    for (src, refined) in [(src, true), (single.as_str(), false)] {
        let (full, stats) = render_stats(src, None, 2);
        assert_eq!(stats.rays.refined > 0, refined);
        let (one, _) = render_stats(src, None, 1);
        assert_eq!(full, one);
        let r = Region {
            x: 13,
            y: 7,
            width: 11,
            height: 9,
        };
        let (part, _) = render_stats(src, Some(r), 2);
        assert_eq!((part.width, part.height), (11, 9));
        for b in 0..9 {
            for a in 0..11 {
                assert_eq!(part.get(a, b), full.get(13 + a, 7 + b), "({a}, {b})");
            }
        }
        // A region past the edge is clipped to the picture.
        let edge = Region {
            x: 35,
            y: 25,
            width: 100,
            height: 100,
        };
        let (corner, _) = render_stats(src, Some(edge), 1);
        assert_eq!((corner.width, corner.height), (5, 5));
        assert_eq!(corner.get(4, 4), full.get(39, 29));
    }
}

#[test]
fn adaptive_mistakes_are_diagnosed() {
    let _watchdog = crate::watchdog::start();
    let err = build_error;
    let e = err("render { adaptive { threshold 0.1 } }");
    assert!(e.contains("samples 2` or more"), "{e}");
    let e = err("render { samples 4  adaptive { max_samples 3 } }");
    assert!(e.contains("must exceed `samples` (4)"), "{e}");
    let e = err("render { samples 2  adaptive { treshold 0.1 } }");
    assert!(e.contains("did you mean `threshold`"), "{e}");
    let e = err("render { samples 2  adaptive { threshold 0 } }");
    assert!(e.contains("greater than 0"), "{e}");
    let e = err("render { samples 2  adaptive 3 }");
    assert!(e.contains("expected a block"), "{e}");
}

fn raytrace(args: &[&std::ffi::OsStr]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_raytrace"))
        .args(args)
        .output()
        .expect("run raytrace")
}

#[test]
fn the_command_line_reports_refined_pixels_and_renders_regions() {
    let _watchdog = crate::watchdog::start();
    // A white square on black, 0.4 units a pixel: x and y from −1.2 to 1.2
    // is pixels 3 to 8 each way, its edges on pixel boundaries. The regular
    // 2 × 2 samples sit at a quarter and three quarters of a pixel, so no
    // pixel sees both colours and none is refined.
    let scene_with = |lo: f64, hi: f64| {
        format!(
            "
camera {{ position <0, 0, 4>  look_at <0, 0, 0>  distance 1  width 1.2  height 1.2 }}
render {{ width 12  height 12  samples 2  adaptive {{ threshold 0.5  max_samples 5 }} }}
rectangle {{ bottom_left <{lo}, {lo}, 0>  top_left <{lo}, {hi}, 0>  bottom_right <{hi}, {lo}, 0>  material {{ emit white }} }}
"
        )
    };
    let (dir, scene) = scene_file(&scene_with(-1.2, 1.2));
    let run = |scene: &std::path::Path, extra: &[&str], out: &std::path::Path| {
        let mut args: Vec<&std::ffi::OsStr> =
            vec![scene.as_os_str(), "-o".as_ref(), out.as_os_str()];
        args.extend(extra.iter().map(|s| s.as_ref() as &std::ffi::OsStr));
        raytrace(&args)
    };
    let out = dir.path().join("full.png");
    let o = run(&scene, &["--stats"], &out);
    assert!(o.status.success(), "{o:?}");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("144  (4.00 samples each on average, 0 refined"),
        "{err}"
    );
    // Moved by half a pixel (x and y from −1 to 1.4), its edges run
    // through pixel centres: the border of the 7 × 7 block of pixels it
    // touches, 24 pixels, has samples on both sides, and each takes 25
    // more: (144·4 + 24·25)/144 = 8.17 samples a pixel.
    let (_d2, moved) = scene_file(&scene_with(-1.0, 1.4));
    let o = run(&moved, &["--stats"], &dir.path().join("moved.png"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("144  (8.17 samples each on average, 24 refined"),
        "{err}"
    );
    // `--samples 5` reaches `max_samples`: nothing left to refine.
    let o = run(
        &moved,
        &["--stats", "--samples", "5"],
        &dir.path().join("five.png"),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("144  (25.00 samples each on average, 0 refined"),
        "{err}"
    );
    // A region is those pixels of the full picture.
    let part = dir.path().join("part.png");
    let o = run(&moved, &["--region", "2,7,3,7"], &part);
    assert!(o.status.success(), "{o:?}");
    let full = image::open(dir.path().join("moved.png")).unwrap().to_rgb8();
    let cut = image::open(&part).unwrap().to_rgb8();
    assert_eq!(cut.dimensions(), (5, 4));
    for y in 0..4 {
        for x in 0..5 {
            assert_eq!(cut.get_pixel(x, y), full.get_pixel(2 + x, 3 + y));
        }
    }
    // Past the picture, or malformed: a usage error (2), nothing written.
    let none = dir.path().join("none.png");
    let o = run(&scene, &["--region", "8,13,8,12"], &none);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("reaches past the 12x12 picture"), "{err}");
    let o = run(&scene, &["--region", "1,2,3"], &none);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("four bounds"));
    // Reversed or empty bounds are refused, never rendered as nothing.
    for bad in ["5,2,0,4", "3,3,0,4", "0.5,0.25,0,1"] {
        let o = run(&scene, &["--region", bad], &none);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("is empty"), "{bad}: {err}");
    }
    // Fractions: the right half, rows 0.25..0.75, are the full picture's.
    let half = dir.path().join("half.png");
    let o = run(&moved, &["--region", "0.5,1,0.25,0.75"], &half);
    assert!(o.status.success(), "{o:?}");
    let cut = image::open(&half).unwrap().to_rgb8();
    assert_eq!(cut.dimensions(), (6, 6));
    for y in 0..6 {
        for x in 0..6 {
            assert_eq!(cut.get_pixel(x, y), full.get_pixel(6 + x, 3 + y));
        }
    }
    assert!(!none.exists());
}

/// `samples <columns, rows>`: a grid of their product (POV-Ray's
/// `blur_samples 32` is `<8, 4>`), a square one the same picture as
/// `samples n`, refined only where `max_samples`² is more; `--samples`
/// replaces the whole grid; bad grids are refused where they stand.
#[test]
fn a_grid_of_columns_and_rows_casts_their_product() {
    let _watchdog = crate::watchdog::start();
    let base = "sampler multijittered  seed 3";
    let pixels = 40 * 30;
    let (f84, s84) = render_stats(&disc_scene(&format!("{base}  samples <8, 4>")), None, 2);
    assert_eq!(s84.rays.primary, 32 * pixels);
    let (f33, s33) = render_stats(&disc_scene(&format!("{base}  samples <3, 3>")), None, 2);
    let (f3, _) = render_stats(&disc_scene(&format!("{base}  samples 3")), None, 2);
    assert_eq!(
        (f33.pixels == f3.pixels, s33.rays.primary),
        (true, 9 * pixels)
    );
    // 32 samples come nearer 6 × 6 than 2 × 2 do.
    let (f6, _) = render_stats(&disc_scene(&format!("{base}  samples 6")), None, 2);
    let (f2, _) = render_stats(&disc_scene(&format!("{base}  samples 2")), None, 2);
    let (near, far) = (max_difference_sum(&f84, &f6), max_difference_sum(&f2, &f6));
    assert!(near < 0.5 * far, "{near} vs {far}");
    let adaptive = |max: u32| {
        format!("{base}  samples <8, 4>  adaptive {{ threshold 0.05  max_samples {max} }}")
    };
    let (_, s) = render_stats(&disc_scene(&adaptive(6)), None, 1);
    assert!(s.rays.refined > 0);
    assert_eq!(s.rays.primary, 32 * pixels + 36 * s.rays.refined);
    // 5 × 5 is fewer than the 32 already taken.
    let e = build_error(&disc_scene(&adaptive(5)));
    assert!(
        e.contains("nothing to do") && e.contains("32 samples of `<8, 4>`"),
        "{e}"
    );
    let (dir, path) = scene_file(&disc_scene(&format!("{base}  samples <8, 4>")));
    let o = render_to(
        &path,
        &dir.path().join("o.png"),
        &["--samples", "2", "--stats"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("(4.00 samples each"), "{}", stderr(&o));
    for bad in [
        "0",
        "2.5",
        "17",
        "<0, 4>",
        "<8, 4.5>",
        "<8, 17>",
        "<1, 2, 3>",
        "rgb(1, 1, 1)",
    ] {
        let e = build_error(&disc_scene(&format!("{base}  samples {bad}")));
        assert!(
            e.contains("whole number") && e.contains("1 to 16"),
            "{bad}: {e}"
        );
    }
}
