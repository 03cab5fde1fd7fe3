//! Textures as pictures show them: checker cells, image pixels, patterns
//! that move with their objects, and bad image files as diagnostics.

use crate::support::*;

/// The picture `examples/textures.rt` wraps around its globe: made here,
/// so the gallery needs no downloads. A blue "ocean" with a warm band of
/// "land" blobs, a white pole cap at the top, and a red meridian at u = 0.
pub fn globe_image() -> image::RgbImage {
    image::RgbImage::from_fn(256, 128, |x, y| {
        let u = (x as f64 + 0.5) / 256.0;
        let v = 1.0 - (y as f64 + 0.5) / 128.0;
        let (lon, lat) = (u * std::f64::consts::TAU, (v - 0.5) * std::f64::consts::PI);
        if !(0.08..=0.9).contains(&v) {
            return image::Rgb([240, 245, 250]);
        }
        if x < 3 {
            return image::Rgb([200, 30, 30]);
        }
        let land = (3.0 * lon).sin() * (2.0 * lat).cos()
            + 0.5 * (5.0 * lon + 1.0).sin() * (3.0 * lat).sin();
        if land > 0.35 {
            image::Rgb([(90.0 + 80.0 * land) as u8, (140.0 - 20.0 * land) as u8, 60])
        } else {
            image::Rgb([20, (60.0 + 60.0 * (lat.cos())) as u8, 160])
        }
    })
}

#[test]
fn example_image_is_the_generated_one() {
    let _watchdog = crate::watchdog::start();
    let path = project_root().join("examples/images/globe.png");
    let want = globe_image();
    // Written only on request: a fixture written when missing would then be
    // compared with itself, and the test could not fail.
    if regenerate_fixtures() {
        want.save(&path).expect("write examples/images/globe.png");
    }
    let have = image::open(&path)
        .unwrap_or_else(|e| {
            panic!(
                "examples/images/globe.png: {e}; run the tests with \
                 RAYTRACE_REGENERATE_FIXTURES=1 to write it"
            )
        })
        .to_rgb8();
    assert!(
        have == want,
        "examples/images/globe.png differs from globe_image(); rerun the tests with \
         RAYTRACE_REGENERATE_FIXTURES=1 to rewrite it"
    );
}

const TOP_DOWN: &str = "
camera { position <0, 10, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 90 }
render { width 40  height 40  gamma linear }
ambient white intensity 1
";

#[test]
fn checker_cells_fall_where_the_course_formula_puts_them() {
    let _watchdog = crate::watchdog::start();
    // A plane y = 0 seen from above, fov 90: the image spans x, z ∈ [−10, 10].
    // Its canonical frame turned onto +y maps u = x and v = −z; with scale
    // 0.5 the cells are 2 units wide.
    let film = render_src(&format!(
        "{TOP_DOWN}
plane {{ normal <0, 1, 0>  material {{ colour checker {{ a rgb(1, 1, 1)  b rgb(0, 0, 0)  scale 0.5 }} }} }}
"
    ));
    // Pixel (a, b) centre looks at x = (a + 0.5)/2 − 10, z = (b + 0.5)/2 − 10.
    let mut checked = 0;
    for b in (1..40).step_by(3) {
        for a in (1..40).step_by(3) {
            let x = (a as f64 + 0.5) / 2.0 - 10.0;
            let z = (b as f64 + 0.5) / 2.0 - 10.0;
            let f = |s: f64| if s >= 0.0 { 0.5 * s } else { 1.0 - 0.5 * s };
            let even = ((f(x).floor() + f(-z).floor()) as i64).rem_euclid(2) == 0;
            let lum = luminance(film.get(a, b));
            assert_eq!(lum > 0.5, even, "pixel ({a}, {b}) at x {x}, z {z}");
            checked += 1;
        }
    }
    assert!(checked > 100);
}

#[test]
fn image_texture_shows_the_image_on_a_rectangle() {
    let _watchdog = crate::watchdog::start();
    let film = render_quad_image("image \"quad.png\"");
    // The rectangle fills the view. Near the centre of each quadrant (where
    // bilinear filtering blends in only 2.5% of a neighbour) the picture
    // shows that quadrant of the image, upright.
    let at = |a, b| film.get(a, b).map(|c| (c * 10.0).round() / 10.0);
    assert_eq!(at(10, 10), [1.0, 0.0, 0.0], "top left is red");
    assert_eq!(at(29, 10), [0.0, 1.0, 0.0], "top right is green");
    assert_eq!(at(10, 29), [0.0, 0.0, 1.0], "bottom left is blue");
    assert_eq!(at(29, 29), [1.0, 1.0, 1.0], "bottom right is white");
}

#[test]
fn solid_textures_move_with_their_object() {
    let _watchdog = crate::watchdog::start();
    // A marble sphere at the origin, and the same sphere moved by
    // <5, 0, 0> with the camera and light moved alike: the same picture.
    let scene = |offset: f64| {
        format!(
            "
camera {{ position <{cx}, 0, 4>  look_at <{cx}, 0, 0>  fov 40 }}
render {{ width 32  height 32  gamma linear }}
ambient white intensity 0.3
light {{ position <{lx}, 3, 4> }}
sphere {{ radius 1  material {{ colour marble {{ a white  b rgb(0.1, 0.1, 0.4)  scale 3 }} }}
         rotate y 30  translate <{offset}, 0, 0> }}
",
            cx = offset,
            lx = offset + 2.0
        )
    };
    let here = render_src(&scene(0.0));
    let there = render_src(&scene(5.0));
    assert!(max_difference(&here, &there) < 1e-3);
    // And the marble is not uniform.
    let lums: Vec<f32> = here
        .pixels
        .iter()
        .map(|p| luminance(*p))
        .filter(|l| *l > 0.05)
        .collect();
    let (lo, hi) = lums
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), l| (lo.min(*l), hi.max(*l)));
    assert!(hi - lo > 0.2, "veins visible: {lo}..{hi}");
}

#[test]
fn a_missing_or_corrupt_image_is_a_diagnostic_at_its_name() {
    let _watchdog = crate::watchdog::start();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.png"), b"\x89PNG\r\n\x1a\ngarbage").unwrap();
    for (file, words) in [("nope.png", "nope.png"), ("bad.png", "decode")] {
        let scene = dir.path().join("scene.rt");
        std::fs::write(
            &scene,
            format!("sphere {{ material {{ colour image \"{file}\" }} }}\n"),
        )
        .unwrap();
        let program = raytrace::lang::load(&scene).unwrap();
        let err = match raytrace::scene::build(&program) {
            Ok(_) => panic!("{file} accepted"),
            Err(e) => format!("{:?}", miette::Report::new(e)),
        };
        assert!(err.contains(words), "{err}");
        assert!(
            err.contains("1:38") || err.contains(":1:"),
            "names the place: {err}"
        );
    }
}
