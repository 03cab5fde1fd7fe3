//! Renders a farm splits: frames and tiles rendered by separate processes
//! running at once (as GNU parallel or a job array starts them), merged,
//! and compared byte for byte with one full render; the errors a
//! scheduler's user meets; motion blur.

use crate::support::stderr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_raytrace"))
}

fn run(args: &[&str], dir: &Path) -> Output {
    bin()
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run raytrace")
}

fn ok(args: &[&str], dir: &Path) -> Output {
    let o = run(args, dir);
    assert!(o.status.success(), "raytrace {args:?}: {}", stderr(&o));
    o
}

/// Runs every command line at once, as separate processes, and waits for
/// all of them.
fn parallel(commands: &[Vec<String>], dir: &Path) {
    let children: Vec<_> = commands
        .iter()
        .map(|a| {
            let child = bin()
                .args(a)
                .current_dir(dir)
                .stderr(std::process::Stdio::piped())
                .spawn()
                .expect("start raytrace");
            (a, child)
        })
        .collect();
    for (a, c) in children {
        let o = c.wait_with_output().unwrap();
        assert!(o.status.success(), "raytrace {a:?}: {}", stderr(&o));
    }
}

fn bytes(p: impl AsRef<Path>) -> Vec<u8> {
    std::fs::read(p.as_ref()).unwrap_or_else(|e| panic!("{}: {e}", p.as_ref().display()))
}

/// Spheres on a checker floor whose red sphere moves with `clock`, with a
/// `render` line of the test's choosing.
fn scene(dir: &Path, render: &str) -> PathBuf {
    let path = dir.join("scene.rt");
    let text = format!(
        "camera {{ position <0, 1.5, 8>  look_at <0, 0.8, 0>  fov 40 {camera} }}\n\
         render {{ width 48  height 32 {render} }}\n\
         ambient rgb(1, 1, 1) intensity 0.1\n\
         light {{ position <5, 10, 5> }}\n\
         plane {{ normal <0, 1, 0>  material {{ colour checker {{ a rgb(0.9, 0.9, 0.9)  b rgb(0.3, 0.3, 0.3)  scale 1 }} }} }}\n\
         sphere {{ centre <-2 + 4 * clock, 0.6, 2>  radius 0.6  material {{ colour rgb(0.9, 0.2, 0.1)  specular 0.5  shininess 60 }} }}\n\
         sphere {{ centre <1, 0.6, -2>  radius 0.6  material {{ colour rgb(0.3, 0.3, 0.8)  reflect 0.3 }} }}\n",
        camera = if render.contains("multijittered") {
            "aperture 0.1  focus 6"
        } else {
            ""
        }
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

#[test]
fn tiles_from_parallel_processes_merge_into_the_full_render() {
    // A jittered sampler; multi-jittered with depth of field; adaptive
    // sampling: every random number is a pure function of the pixel.
    for render in [
        "samples 2  sampler jittered",
        "samples 3  sampler multijittered",
        "samples 2  sampler random  adaptive { threshold 0.05  max_samples 4 }",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        scene(d, render);
        ok(&["scene.rt", "-o", "full.png", "--threads", "2", "-q"], d);
        ok(&["scene.rt", "-o", "full.exr", "--threads", "1", "-q"], d);
        for (n, ext, threads) in [(6, "png", "1"), (4, "exr", "2"), (5, "png", "2")] {
            let cmds: Vec<Vec<String>> = (0..n)
                .map(|i| {
                    strings(&["scene.rt", "--tile", &format!("{i}/{n}"), "-o"])
                        .into_iter()
                        .chain([
                            format!("t{n}_{i}.{ext}"),
                            "--threads".into(),
                            threads.into(),
                        ])
                        .chain(["-q".to_string()])
                        .collect()
                })
                .collect();
            parallel(&cmds, d);
            let tiles: Vec<String> = (0..n).map(|i| format!("t{n}_{i}.{ext}")).collect();
            let mut merge = vec!["merge".to_string()];
            merge.extend(tiles.iter().cloned());
            for out in [format!("m{n}.{ext}"), format!("m{n}_from_{ext}.png")] {
                let mut m = merge.clone();
                m.extend(["-o".into(), out.clone(), "-q".into()]);
                ok(&m.iter().map(String::as_str).collect::<Vec<_>>(), d);
                let full = if out.ends_with(".exr") {
                    "full.exr"
                } else {
                    "full.png"
                };
                assert!(
                    bytes(d.join(&out)) == bytes(d.join(full)),
                    "{render}: {n} {ext} tiles merged into {out} differ from {full}"
                );
            }
        }
    }
}

#[test]
fn a_region_image_holds_exactly_the_region_and_where_it_lies() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d, "samples 2  sampler jittered");
    ok(&["scene.rt", "-o", "full.exr", "-q"], d);
    ok(
        &["scene.rt", "-o", "r.exr", "--region", "10,30,4,20", "-q"],
        d,
    );
    ok(
        &["scene.rt", "-o", "r.png", "--region", "10,30,4,20", "-q"],
        d,
    );
    // EXR: a reader places the data window in the full display window.
    let full = image::open(d.join("full.exr")).unwrap().to_rgb32f();
    let r = image::open(d.join("r.exr")).unwrap().to_rgb32f();
    assert_eq!(r.dimensions(), (48, 32));
    for (x, y, p) in r.enumerate_pixels() {
        let inside = (10..30).contains(&x) && (4..20).contains(&y);
        let want = if inside {
            full.get_pixel(x, y).0
        } else {
            [0.0; 3]
        };
        assert_eq!(p.0, want, "pixel {x},{y}");
    }
    assert!(full.get_pixel(20, 10).0.iter().any(|&c| c > 0.0));
    // PNG: just the region, with its offset in oFFs.
    let png = bytes(d.join("r.png"));
    let img = image::load_from_memory(&png).unwrap();
    assert_eq!((img.width(), img.height()), (20, 16));
    let at = png
        .windows(4)
        .position(|w| w == b"oFFs")
        .expect("an oFFs chunk");
    assert_eq!(&png[at + 4..at + 13], &[0, 0, 0, 10, 0, 0, 0, 4, 0]);
}

#[test]
fn frames_split_over_tasks_equal_one_run_and_a_frame_alone() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d, "samples 2  sampler jittered");
    std::fs::create_dir(d.join("seq")).unwrap();
    std::fs::create_dir(d.join("par")).unwrap();
    ok(
        &["scene.rt", "--frames", "3-9:2", "-o", "seq/f_###.png", "-q"],
        d,
    );
    // Tasks 1 and 2 of 2 (1-based, as `--array=1-2` counts), at once.
    let cmds: Vec<Vec<String>> = (1..=2)
        .map(|i| {
            strings(&[
                "scene.rt",
                "--frames",
                "3-9:2",
                "--tasks",
                "2",
                "--index-base",
                "1",
                "-o",
                "par/f_###.png",
                "-q",
                "--threads",
                "1",
                "--task-index",
            ])
            .into_iter()
            .chain([i.to_string()])
            .collect()
        })
        .collect();
    parallel(&cmds, d);
    ok(
        &[
            "scene.rt",
            "--frames",
            "3-9:2",
            "--frame",
            "7",
            "-o",
            "alone_#.png",
            "-q",
        ],
        d,
    );
    let mut seen = Vec::new();
    for f in [3, 5, 7, 9] {
        let a = bytes(d.join(format!("seq/f_{f:03}.png")));
        assert!(a == bytes(d.join(format!("par/f_{f:03}.png"))), "frame {f}");
        seen.push(a);
    }
    assert!(bytes(d.join("alone_7.png")) == seen[2]);
    // The clock moved the sphere: every frame is a different picture.
    for i in 1..seen.len() {
        assert!(
            seen[i] != seen[i - 1],
            "frames {i} and {} are the same",
            i - 1
        );
    }
    // Frame 7 of 3-9 has clock 2/3, as a still rendered at that clock.
    ok(
        &[
            "scene.rt",
            "--clock",
            "0.6666666666666666",
            "--frame",
            "7",
            "-o",
            "still.png",
            "-q",
        ],
        d,
    );
    assert!(bytes(d.join("still.png")) == seen[2]);
}

#[test]
fn a_rerun_skips_what_exists_and_logs_json_lines() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d, "");
    ok(
        &[
            "scene.rt", "--frames", "0-2", "-o", "f#.png", "--frame", "1", "-q",
        ],
        d,
    );
    let o = ok(
        &[
            "scene.rt",
            "--frames",
            "0-2",
            "-o",
            "f#.png",
            "--skip-existing",
            "--log",
            "json",
            "-q",
        ],
        d,
    );
    let log = stderr(&o);
    let lines: Vec<&str> = log.lines().collect();
    assert_eq!(lines.len(), 3, "{log}");
    assert!(
        lines[0].starts_with(r#"{"event":"finished","output":"f0.png","frame":0,"clock":0.0"#),
        "{log}"
    );
    assert!(
        lines[1].starts_with(r#"{"event":"skipped","output":"f1.png","frame":1"#),
        "{log}"
    );
    assert!(lines[2].contains(r#""clock":1.0"#), "{log}");
    for l in [lines[0], lines[2]] {
        for key in [
            r#""rays":"#,
            r#""seconds":"#,
            r#""peak_rss_bytes":"#,
            r#""region":[0,0,48,32]"#,
        ] {
            assert!(l.contains(key), "{key} in {l}");
        }
        assert!(l.ends_with('}'));
    }
    // A failure is a line too, with the exit status.
    let o = run(
        &[
            "scene.rt", "--frames", "0-2", "--frame", "5", "-o", "f#.png", "--log", "json",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains(r#"{"event":"failed""#),
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains(r#""exit":2"#));
}

/// The words of a report, whatever miette's line wrapping did to them.
fn words(s: &str) -> String {
    s.replace('│', " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// Exit 2 and a message that says what is wrong.
fn refused(args: &[&str], dir: &Path, wanted: &str) {
    let o = run(args, dir);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    assert!(
        words(&stderr(&o)).contains(wanted),
        "{args:?}: {}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("panicked"));
}

#[test]
fn bad_frames_regions_and_tiles_are_usage_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d, "");
    refused(
        &["scene.rt", "--region", "30,10,0,32", "-o", "x.png"],
        d,
        "empty",
    );
    refused(
        &["scene.rt", "--region", "10,10,0,32", "-o", "x.png"],
        d,
        "empty",
    );
    refused(
        &["scene.rt", "--region", "0,49,0,32", "-o", "x.png"],
        d,
        "reaches past",
    );
    refused(
        &["scene.rt", "--frames", "9-3", "-o", "x#.png"],
        d,
        "backwards",
    );
    refused(&["scene.rt", "--frames", "", "-o", "x#.png"], d, "empty");
    refused(
        &["scene.rt", "--frames", "1-9:0", "-o", "x#.png"],
        d,
        "step",
    );
    refused(
        &[
            "scene.rt", "--frames", "1-9", "--frame", "10", "-o", "x#.png",
        ],
        d,
        "not one of",
    );
    refused(&["scene.rt", "--frames", "1-9", "-o", "x.png"], d, "####");
    refused(
        &["scene.rt", "--tile", "6/6", "-o", "x.png"],
        d,
        "no tile 6 of 6",
    );
    refused(
        &["scene.rt", "--tile", "0/2000", "-o", "x.png"],
        d,
        "cannot be cut into 2000",
    );
    refused(
        &["scene.rt", "--tile", "0/4000000000", "-o", "x.png"],
        d,
        "cannot be cut into 4000000000",
    );
    refused(
        &["scene.rt", "--frames", "0-4000000000", "-o", "x#.png"],
        d,
        "more than",
    );
    assert!(
        std::fs::read_dir(d).unwrap().count() == 1,
        "nothing written"
    );
}

#[test]
fn merge_names_the_gap_the_overlap_and_strangers() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d, "");
    for i in 0..4 {
        ok(
            &[
                "scene.rt",
                "--tile",
                &format!("{i}/4"),
                "-o",
                &format!("t{i}.png"),
                "-q",
            ],
            d,
        );
    }
    ok(
        &[
            "scene.rt",
            "--tile",
            "1/4",
            "--clock",
            "0.5",
            "-o",
            "later.png",
            "-q",
        ],
        d,
    );
    ok(
        &[
            "scene.rt",
            "--region",
            "20,30,10,20",
            "-o",
            "extra.png",
            "-q",
        ],
        d,
    );
    ok(&["scene.rt", "-o", "whole.png", "-q"], d);
    refused(
        &["merge", "t0.png", "t1.png", "t2.png", "-o", "m.png"],
        d,
        "the rectangle x 24..48, y 16..32 (384 pixels) is missing",
    );
    refused(
        &[
            "merge",
            "t0.png",
            "t1.png",
            "t2.png",
            "t3.png",
            "extra.png",
            "-o",
            "m.png",
        ],
        d,
        "`t0.png` and `extra.png` overlap at x 20..24, y 10..16 (24 pixels)",
    );
    refused(
        &[
            "merge",
            "t0.png",
            "later.png",
            "t2.png",
            "t3.png",
            "-o",
            "m.png",
        ],
        d,
        "different pictures: frames",
    );
    refused(
        &["merge", "t0.png", "whole.png", "-o", "m.png"],
        d,
        "no raytrace tile record",
    );
    refused(
        &[
            "merge", "t0.png", "t1.png", "t2.png", "t3.png", "-o", "m.exr",
        ],
        d,
        "8-bit",
    );
    let o = run(&["merge", "t0.png", "gone.png", "-o", "m.png"], d);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(!d.join("m.png").exists() && !d.join("m.exr").exists());
    ok(
        &[
            "merge", "t3.png", "t1.png", "t2.png", "t0.png", "-o", "m.png", "-q",
        ],
        d,
    );
    assert!(bytes(d.join("m.png")) == bytes(d.join("whole.png")));
}

/// A white emissive ball of radius 1 on black, seen from straight ahead,
/// moving 3 units along x as the clock goes 0 to 1.
fn moving_ball(dir: &Path, blur: &str) -> PathBuf {
    let path = dir.join(format!("ball{}.rt", blur.len()));
    std::fs::write(
        &path,
        format!(
            "camera {{ position <0, 0, 40>  look_at <0, 0, 0>  fov 15 }}\n\
             render {{ width 96  height 48  samples 4  gamma linear {blur} }}\n\
             sphere {{ centre <-1.5 + 3 * clock, 0, 0>  radius 1  material {{ emit rgb(1, 1, 1) intensity 1 }} }}\n"
        ),
    )
    .unwrap();
    path
}

fn film(path: &Path) -> image::Rgb32FImage {
    image::open(path).unwrap().to_rgb32f()
}

fn lit(img: &image::Rgb32FImage) -> f64 {
    img.pixels().map(|p| p.0[0] as f64).sum()
}

#[test]
fn motion_blur_sweeps_the_ball_with_the_right_mean_coverage() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 8;
    let blurred = moving_ball(d, &format!("motion_blur {n}  shutter 1"));
    ok(&[blurred.to_str().unwrap(), "-o", "blur.exr", "-q"], d);
    let blur = film(&d.join("blur.exr"));
    // The sharp ball at each sub-frame's moment, k/n of the way.
    let sharp = moving_ball(d, "");
    let subs: Vec<image::Rgb32FImage> = (0..n)
        .map(|k| {
            let out = format!("s{k}.exr");
            let clock = format!("{}", k as f64 / n as f64);
            ok(
                &[sharp.to_str().unwrap(), "--clock", &clock, "-o", &out, "-q"],
                d,
            );
            film(&d.join(out))
        })
        .collect();
    // Energy: each sub-frame shows one ball's area, so the blurred picture
    // has the same total light as one sharp picture.
    let one = lit(&subs[0]);
    assert!(one > 100.0, "the ball is visible: {one}");
    assert!(
        (lit(&blur) - one).abs() < 0.01 * one,
        "{} vs {one}",
        lit(&blur)
    );
    // The streak spans from the first ball's left edge to the last one's
    // right edge.
    let extent = |img: &image::Rgb32FImage| {
        let cols: Vec<u32> = (0..img.width())
            .filter(|&x| (0..img.height()).any(|y| img.get_pixel(x, y).0[0] > 0.0))
            .collect();
        (cols[0], *cols.last().unwrap())
    };
    let (l0, _) = extent(&subs[0]);
    let (_, r1) = extent(&subs[n - 1]);
    assert_eq!(extent(&blur), (l0, r1));
    let (a, b) = extent(&subs[0]);
    assert!(
        r1 - l0 > 2 * (b - a),
        "the ball moves farther than its width"
    );
    // Mean coverage: each pixel is lit by the fraction of sub-frames whose
    // ball covers it (the mean of the sharp pictures, to rounding).
    for (x, y, p) in blur.enumerate_pixels() {
        let mean: f64 = subs
            .iter()
            .map(|s| s.get_pixel(x, y).0[0] as f64)
            .sum::<f64>()
            / n as f64;
        assert!(
            (p.0[0] as f64 - mean).abs() < 1e-6,
            "{x},{y}: {} vs {mean}",
            p.0[0]
        );
    }
    // On the centre row, a pixel in the middle of the streak is covered by
    // a ball in (ball width / step) of the n sub-frames: 2 / (3/8) of 8,
    // two thirds.
    let y = blur.height() / 2;
    let mid = (l0 + r1) / 2;
    let row: Vec<f32> = (mid - 3..=mid + 3)
        .map(|x| blur.get_pixel(x, y).0[0])
        .collect();
    let mean = row.iter().sum::<f32>() / row.len() as f32;
    let expected = (2.0 / (3.0 / 8.0)) / 8.0;
    assert!(
        (mean - expected).abs() < 0.08,
        "{mean} vs {expected}: {row:?}"
    );
}

#[test]
fn one_sub_frame_is_no_blur_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let plain = moving_ball(d, "");
    let one = moving_ball(d, "motion_blur 1  shutter 0.5");
    for ext in ["png", "exr"] {
        let a = format!("plain.{ext}");
        let b = format!("one.{ext}");
        ok(
            &[plain.to_str().unwrap(), "--clock", "0.3", "-o", &a, "-q"],
            d,
        );
        ok(
            &[one.to_str().unwrap(), "--clock", "0.3", "-o", &b, "-q"],
            d,
        );
        assert!(bytes(d.join(a)) == bytes(d.join(b)), "{ext}");
    }
    // A blurred picture's tiles still merge into it exactly.
    let blurred = moving_ball(d, "motion_blur 3");
    let b = blurred.to_str().unwrap();
    ok(&[b, "-o", "blur.png", "-q"], d);
    for i in 0..3 {
        ok(
            &[
                b,
                "--tile",
                &format!("{i}/3"),
                "-o",
                &format!("b{i}.png"),
                "-q",
            ],
            d,
        );
    }
    ok(
        &["merge", "b0.png", "b1.png", "b2.png", "-o", "mb.png", "-q"],
        d,
    );
    assert!(bytes(d.join("mb.png")) == bytes(d.join("blur.png")));
}

#[test]
fn averaged_sub_frames_equal_the_built_in_motion_blur() {
    // Two routes to one picture: four sharp renders at clocks 0, 1/4, 2/4,
    // 3/4 averaged by `merge --average`, and `motion_blur 4  shutter 1`.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sharp = moving_ball(d, "");
    let s = sharp.to_str().unwrap();
    let mut merge = vec!["merge".to_string(), "--average".into()];
    for k in 0..4 {
        let out = format!("c{k}.exr");
        ok(
            &[
                s,
                "--clock",
                &format!("{}", k as f64 / 4.0),
                "-o",
                &out,
                "-q",
            ],
            d,
        );
        merge.push(out);
    }
    merge.extend(["-o".into(), "mean.exr".into(), "-q".into()]);
    ok(&merge.iter().map(String::as_str).collect::<Vec<_>>(), d);
    let blurred = moving_ball(d, "motion_blur 4  shutter 1");
    ok(&[blurred.to_str().unwrap(), "-o", "blur.exr", "-q"], d);
    assert!(bytes(d.join("mean.exr")) == bytes(d.join("blur.exr")));
    // Whole pictures carry no transfer curve for an 8-bit average...
    let mut png = merge.clone();
    png.splice(png.len() - 2..png.len() - 1, ["mean.png".to_string()]);
    refused(
        &png.iter().map(String::as_str).collect::<Vec<_>>(),
        d,
        "transfer curve",
    );
    // ...and pictures of another size are refused.
    ok(&[s, "--width", "48", "-o", "small.exr", "-q"], d);
    refused(
        &["merge", "--average", "c0.exr", "small.exr", "-o", "m.exr"],
        d,
        "is 48x48 but",
    );
}

#[test]
fn one_task_per_tile_of_every_frame_merges_frame_by_frame() {
    // `--frames 0-1 --tiles 4`: tasks 1-8 (1-based, as GNU parallel's {#})
    // are the four tiles of frame 0, then those of frame 1.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d, "samples 2  sampler multijittered");
    let cmds: Vec<Vec<String>> = (1..=8)
        .map(|i| {
            strings(&[
                "scene.rt",
                "--frames",
                "0-1",
                "--tiles",
                "4",
                "--index-base",
                "1",
                "-o",
                "f#_t@.exr",
                "-q",
                "--threads",
                "1",
                "--task-index",
            ])
            .into_iter()
            .chain([i.to_string()])
            .collect()
        })
        .collect();
    parallel(&cmds, d);
    ok(
        &["scene.rt", "--frames", "0-1", "-o", "full_#.png", "-q"],
        d,
    );
    for f in 0..2 {
        let mut m = vec!["merge".to_string()];
        m.extend((1..=4).map(|t| format!("f{f}_t{t}.exr")));
        m.extend(["-o".into(), format!("m{f}.png"), "-q".into()]);
        ok(&m.iter().map(String::as_str).collect::<Vec<_>>(), d);
        assert!(bytes(d.join(format!("m{f}.png"))) == bytes(d.join(format!("full_{f}.png"))));
    }
    // Tiles of two frames are not one picture.
    refused(
        &[
            "merge",
            "f0_t1.exr",
            "f1_t2.exr",
            "f0_t3.exr",
            "f0_t4.exr",
            "-o",
            "x.png",
        ],
        d,
        "different pictures: frames 0",
    );
}
