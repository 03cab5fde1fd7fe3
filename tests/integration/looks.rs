//! The 2018 model end to end: what glass, lenses, area lights, spots and
//! skies must do to a picture, checked against the physics they follow.

use crate::support::*;
use raytrace::render::Film;

/// A pixel's channels as f64.
fn px(f: &Film, a: u32, b: u32) -> [f64; 3] {
    let p = f.get(a, b);
    [p[0] as f64, p[1] as f64, p[2] as f64]
}

/// A white floor seen from straight above, lit from straight above, with
/// `slab` (objects) between the floor and the light but out of sight.
fn floor_under(slab: &str) -> Film {
    render_src(&format!(
        "
camera {{ position <0, 3, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 60 }}
render {{ width 16  height 16  gamma linear }}
light {{ position <0, 50, 0> }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
{slab}
"
    ))
}

#[test]
fn light_through_a_glass_slab_falls_as_filter_to_the_thickness() {
    let _watchdog = crate::watchdog::start();
    let open = px(&floor_under(""), 8, 8);
    assert!(open[0] > 0.99, "lit head-on: {open:?}");
    let f: [f64; 3] = [0.5, 0.25, 1.0];
    let slab = |thick: f64| {
        floor_under(&format!(
            "box {{ min <-20, 20, -20>  max <20, {}, 20>  material {{ refract {{ ior 1.5  filter rgb(0.5, 0.25, 1) }} }} }}",
            20.0 + thick
        ))
    };
    for thick in [1.0, 2.0] {
        let under = px(&slab(thick), 8, 8);
        for c in 0..3 {
            let want = open[c] * f[c].powf(thick);
            assert!(
                (under[c] - want).abs() < 1e-4,
                "thickness {thick}, channel {c}: {under:?} vs {want}"
            );
        }
    }
    // Clear glass casts no shadow; an opaque slab a full one.
    let clear = floor_under(
        "box { min <-20, 20, -20>  max <20, 21, 20>  material { refract { ior 1.5 } } }",
    );
    assert!((px(&clear, 8, 8)[1] - open[1]).abs() < 1e-6);
    let opaque = floor_under("box { min <-20, 20, -20>  max <20, 21, 20> }");
    assert_eq!(px(&opaque, 8, 8), [0.0, 0.0, 0.0]);
}

#[test]
fn white_furnace_a_white_object_in_a_uniform_sky_shows_the_sky() {
    let _watchdog = crate::watchdog::start();
    let film = render_src(
        "
camera { position <0, 0, 4>  look_at <0, 0, 0>  fov 40 }
render { width 24  height 24  gamma linear  samples 2  sampler jittered }
environment { colour rgb(0.5, 0.5, 0.5)  samples 4 }
sphere { radius 1  material { colour rgb(1, 1, 1)  ambient 0 } }
",
    );
    for p in &film.pixels {
        for c in p {
            assert!((c - 0.5).abs() < 1e-6, "{p:?}");
        }
    }
    // A floor under the sphere hides part of the sky from its lower half.
    let shaded = render_src(
        "
camera { position <0, 0, 4>  look_at <0, 0, 0>  fov 40 }
render { width 24  height 24  gamma linear  samples 2  sampler jittered  seed 3 }
environment { colour rgb(0.5, 0.5, 0.5)  samples 16 }
sphere { radius 1  material { colour rgb(1, 1, 1)  ambient 0 } }
plane { normal <0, 1, 0>  offset -1  material { colour black  diffuse 0 } }
",
    );
    let low = luminance(shaded.get(12, 16));
    assert!(low < 0.45, "{low}");
}

/// The width (in pixels) of row `y`'s rise from dark to bright.
fn edge_width(f: &Film, y: u32, bright: f32) -> u32 {
    (0..f.width)
        .filter(|&x| {
            let v = f.get(x, y)[0];
            v > 0.02 * bright && v < 0.98 * bright
        })
        .count() as u32
}

#[test]
fn thin_lens_keeps_the_focus_plane_sharp_and_blurs_by_the_circle_of_confusion() {
    let _watchdog = crate::watchdog::start();
    // Glowing plates left of x = 0: one at the focus distance 5 (top half
    // of the picture), one at 10 (bottom half). Lens radius 0.2.
    let film = render_src(
        "
camera { position <0, 0, 0>  look_at <0, 0, -1>  fov 20  aperture 0.2  focus 5 }
render { width 200  height 100  gamma linear  samples 8  sampler multijittered }
material glow { emit white }
rectangle { bottom_left <-10, 0.05, -5>  top_left <-10, 3, -5>  bottom_right <0, 0.05, -5>  material glow }
rectangle { bottom_left <-20, -6, -10>  top_left <-20, -0.1, -10>  bottom_right <0, -6, -10>  material glow }
",
    );
    let sharp = edge_width(&film, 25, 1.0);
    assert!(sharp <= 1, "in focus: {sharp} px");
    // At depth z the lens spreads a point over radius a·|1 − z/f| = 0.2,
    // which is 0.2/10 on the view plane: 11.3 pixels of 2·tan(10°)/200.
    let r = 0.02 / (2.0 * 10f64.to_radians().tan() / 200.0);
    // A disc's edge rises over 2r; the 2%–98% band is 90% of it.
    let blurred = edge_width(&film, 75, 1.0) as f64;
    assert!(
        (blurred - 0.9 * 2.0 * r).abs() < 0.12 * 2.0 * r,
        "blurred over {blurred} px, expected about {:.1}",
        0.9 * 2.0 * r
    );
}

/// One regular sample a pixel is the pixel's centre and the lens's
/// centre, so a lens camera sees what the pinhole sees (to rounding: the
/// ray is aimed through the focus point, not along the pinhole's
/// direction). Such pictures take the renderer's row route, which hands
/// out those centres without asking the sampler; a random lens point
/// instead draws a visibly different picture.
#[test]
fn one_regular_sample_through_a_lens_sees_what_the_pinhole_sees() {
    let _watchdog = crate::watchdog::start();
    let scene = |camera: &str, sampler: &str| {
        render_src(&format!(
            "
camera {{ position <0, 1, 6>  look_at <0, 0.5, 0>  fov 40 {camera} }}
render {{ width 48  height 32  gamma linear {sampler} }}
light {{ position <3, 5, 4> }}
sphere {{ centre <0, 0.6, 0>  radius 0.6  material {{ colour rgb(0.9, 0.3, 0.2) }} }}
sphere {{ centre <1.5, 0.6, -3>  radius 0.6 }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(0.8, 0.8, 0.8) }} }}
"
        ))
    };
    let lens = "aperture 0.5  focus 3";
    let pinhole = scene("", "");
    let centre = scene(lens, "");
    let far = |a: &Film, b: &Film| {
        a.pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(p, q)| (0..3).any(|c| (p[c] - q[c]).abs() > 1e-3))
            .count()
    };
    // Silhouette pixels may tip either way on a rounding.
    assert!(far(&pinhole, &centre) <= 8, "{}", far(&pinhole, &centre));
    let random = scene(lens, "sampler random");
    assert!(far(&pinhole, &random) > 50, "{}", far(&pinhole, &random));
}

#[test]
fn penumbra_of_a_disc_light_has_the_analytic_width() {
    let _watchdog = crate::watchdog::start();
    // A disc light of radius 1 at height 10 facing down, an opaque half
    // plane (x < 0) at height 5: on the floor the penumbra spans
    // 2R·h/(H − h) = 2 units, centred on x = 0. The camera, below the
    // occluder, sees x in [−4, 4] over 200 pixels.
    let scene = |occluder: &str| {
        render_src(&format!(
            "
camera {{ position <0, 4, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 90 }}
render {{ width 200  height 3  gamma linear }}
material lamp {{ emit white  intensity 50 }}
disc {{ radius 1  rotate x 90  translate <0, 10, 0>  material lamp  samples 16 }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
{occluder}
"
        ))
    };
    let lit = scene("");
    let shadowed = scene(
        "rectangle { bottom_left <-30, 5, -30>  top_left <-30, 5, 30>  bottom_right <0, 5, -30> }",
    );
    let ratio: Vec<f32> = (0..200)
        .map(|x| shadowed.get(x, 1)[0] / lit.get(x, 1)[0])
        .collect();
    assert!(
        ratio[0] < 1e-6 && ratio[199] > 1.0 - 1e-6,
        "umbra and full light"
    );
    let partial = ratio
        .iter()
        .filter(|&&r| r > 1e-6 && r < 1.0 - 1e-6)
        .count();
    let width = partial as f64 * 8.0 / 200.0;
    // The 16 × 16 grid's outermost points sit at 15/16 of the radius.
    let want = 2.0 * 15.0 / 16.0;
    assert!(
        (width - want).abs() < 0.1,
        "penumbra {width} wide, want {want}"
    );
    // Half the light reaches the floor under the edge.
    assert!((ratio[100] - 0.5).abs() < 0.05 || (ratio[99] - 0.5).abs() < 0.05);
}

#[test]
fn a_small_far_area_light_gives_the_inverse_square_irradiance() {
    let _watchdog = crate::watchdog::start();
    // A disc of radius 0.05 and radiance 1000 straight above the floor
    // point the camera sees: E = L·A/r² (the camera is off to the side
    // at height 0.5 so it does not block the light).
    let at = |h: f64| {
        let film = render_src(&format!(
            "
camera {{ position <0.5, 0.5, 0>  look_at <0, 0, 0>  fov 2 }}
render {{ width 3  height 3  gamma linear }}
disc {{ radius 0.05  rotate x 90  translate <0, {h}, 0>  material {{ emit white  intensity 1000 }} }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
"
        ));
        px(&film, 1, 1)[0]
    };
    let area = std::f64::consts::PI * 0.05 * 0.05;
    for h in [5.0, 10.0] {
        let want = 1000.0 * area / (h * h);
        let got = at(h);
        assert!(
            (got - want).abs() < 0.01 * want,
            "height {h}: {got} vs {want}"
        );
    }
}

/// A lamp whose material is a pattern of materials lights the scene with
/// the emission the pattern chooses at each sample point: a checker of one
/// lamp with itself is that lamp; split into a lit and a dark half it gives
/// half the light at the point under its centre (the halves are mirror
/// images from there), and a lamp of 1 beside one of 3 gives twice the
/// light of the first alone.
#[test]
fn a_lamp_chosen_by_a_pattern_lights_with_what_it_chooses() {
    let _watchdog = crate::watchdog::start();
    let floor = |material: &str| {
        let film = render_src(&format!(
            "
camera {{ position <0.5, 0.5, 0>  look_at <0, 0, 0>  fov 2 }}
render {{ width 3  height 3  gamma linear }}
material one {{ emit white  intensity 10 }}
material three {{ emit white  intensity 30 }}
material dark {{ colour black }}
rectangle {{ bottom_left <-1, 3, -1>  top_left <-1, 3, 1>  bottom_right <1, 3, -1>
  samples 16  material {material} }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
"
        ));
        px(&film, 1, 1)[0] as f64
    };
    let uniform = floor("one");
    assert!(uniform > 0.1, "the plain lamp lights the floor: {uniform}");
    let same = floor("{ checker { a one  b one  scale <2, 1> } }");
    assert!(
        (same - uniform).abs() < 1e-5 * uniform,
        "{same} vs {uniform}"
    );
    let half = floor("{ checker { a one  b dark  scale <2, 1> } }");
    assert!(
        (half - uniform / 2.0).abs() < 0.02 * uniform,
        "{half} vs {}",
        uniform / 2.0
    );
    let mixed = floor("{ checker { a three  b one  scale <2, 1> } }");
    assert!(
        (mixed - 2.0 * uniform).abs() < 0.04 * uniform,
        "{mixed} vs {}",
        2.0 * uniform
    );
}

#[test]
fn one_and_two_threads_give_identical_pictures_with_every_random_part() {
    let _watchdog = crate::watchdog::start();
    let (_d, path) = scene_file(
        "
camera { position <0, 2, 6>  look_at <0, 0.5, 0>  fov 50  aperture 0.1  focus 6 }
render { width 40  height 30  samples 3  sampler multijittered  seed 11  max_depth 4 }
ambient rgb(1, 1, 1) intensity 0.2 occlusion { samples 2  min 0.2 }
material lamp { emit white  intensity 20 }
sphere { centre <0, 4, 0>  radius 0.5  material lamp }
sphere { centre <-1, 0.7, 0>  radius 0.7  material { colour rgb(0.8, 0.6, 0.2)  mirror 0.6  glossy 40 } }
sphere { centre <1, 0.7, 0>  radius 0.7  material { refract { ior 1.5  filter rgb(0.6, 0.9, 0.7) } } }
plane { normal <0, 1, 0>  material { colour rgb(0.9, 0.9, 0.9) } }
",
    );
    let one = render_path(&path, None, 1);
    let two = render_path(&path, None, 2);
    assert_eq!(one, two);
    // A region renders the full picture's pixels: the same film at a
    // different thread count and the same seed, and a new seed changes it.
    let other = render_src(
        &std::fs::read_to_string(&path)
            .unwrap()
            .replace("seed 11", "seed 12"),
    );
    assert!(max_difference(&one, &other) > 0.0);
}

#[test]
fn parallel_and_spot_lights_light_what_they_should() {
    let _watchdog = crate::watchdog::start();
    let floor = |light: &str| {
        render_src(&format!(
            "
camera {{ position <0, 10, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 90 }}
render {{ width 21  height 21  gamma linear }}
{light}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
"
        ))
    };
    // Parallel at 60° from the normal: cos = 0.5 everywhere.
    let par = floor("light { direction <0, -1, 1.7320508075688772> }");
    for p in [par.get(0, 0), par.get(10, 10), par.get(20, 3)] {
        assert!((p[0] - 0.5).abs() < 1e-5, "{p:?}");
    }
    // A spot at height 5 over the origin, full to 20°, nothing past 30°.
    let spot = floor("light { position <0, 5, 0>  look_at <0, 0, 0>  angle 20  falloff 30 }");
    let centre = spot.get(10, 10)[0];
    assert!((centre - 1.0).abs() < 1e-5, "{centre}");
    // Pixel column 20 looks at x = 9.5: 62° off the axis, dark.
    assert_eq!(spot.get(20, 10)[0], 0.0);
    // Column 12 looks at x = 1.9 (20.9° off) and 13 at x = 2.86 (29.7°):
    // both in the soft edge, the first near full, the second near nothing.
    let (near, far) = (spot.get(12, 10)[0], spot.get(13, 10)[0]);
    assert!(near > 0.5 && near < 0.999, "{near}");
    assert!(far > 0.0 && far < 0.05, "{far}");
}

#[test]
fn emission_is_seen_on_the_front_side_only() {
    let _watchdog = crate::watchdog::start();
    let film = render_src(
        "
camera { position <0, 0, 4>  look_at <0, 0, 0>  fov 30 }
render { width 8  height 8  gamma linear }
disc { radius 3  material { emit rgb(0.25, 0.5, 1)  intensity 2 } }
",
    );
    assert_eq!(film.get(4, 4), [0.5, 1.0, 2.0]);
    let back = render_src(
        "
camera { position <0, 0, -4>  look_at <0, 0, 0>  fov 30 }
render { width 8  height 8  gamma linear }
disc { radius 3  material { emit rgb(0.25, 0.5, 1)  intensity 2 } }
",
    );
    assert_eq!(back.get(4, 4), [0.0, 0.0, 0.0]);
}

#[test]
fn phong_and_mirror_add_to_the_matte_part() {
    let _watchdog = crate::watchdog::start();
    let base = "
camera { position <0, 0, 4>  look_at <0, 0, 0>  fov 20 }
render { width 9  height 9  gamma linear  background rgb(0.5, 0.5, 0.5) }
light { position <0, 0, 4> }
";
    let matte = render_src(&format!(
        "{base} sphere {{ material {{ colour rgb(0.2, 0.2, 0.2) }} }}"
    ));
    let shiny = render_src(&format!(
        "{base} sphere {{ material {{ colour rgb(0.2, 0.2, 0.2)  specular 0.5  shininess 10 }} }}"
    ));
    // Head-on, r·v = 1 and n·l = 1: the highlight adds exactly k_s.
    assert!((shiny.get(4, 4)[0] - matte.get(4, 4)[0] - 0.5).abs() < 1e-3);
    // An additive mirror adds k_r c_r times what it sees: the camera's
    // own direction leads back to the grey background.
    let mirror = render_src(&format!(
        "{base} sphere {{ material {{ colour rgb(0.2, 0.2, 0.2)  mirror 0.5  mirror_colour rgb(1, 0, 1) }} }}"
    ));
    let (m, p) = (mirror.get(4, 4), matte.get(4, 4));
    assert!((m[0] - p[0] - 0.25).abs() < 1e-5 && (m[1] - p[1]).abs() < 1e-6);
}

#[test]
fn ambient_occlusion_darkens_corners_and_min_1_changes_nothing() {
    let _watchdog = crate::watchdog::start();
    let scene = |occ: &str| {
        render_src(&format!(
            "
camera {{ position <2, 2, 4>  look_at <0, 0, 0>  fov 60 }}
render {{ width 24  height 24  gamma linear }}
ambient rgb(1, 1, 1) intensity 0.5 {occ}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
box {{ min <-1, 0, -1>  max <1, 1, 1>  material {{ colour rgb(1, 1, 1) }} }}
"
        ))
    };
    let plain = scene("");
    let same = scene("occlusion { samples 8  min 1 }");
    assert_eq!(plain, same);
    let ao = scene("occlusion { samples 16  min 0 }");
    let total = |f: &raytrace::render::Film| f.pixels.iter().map(|p| luminance(*p)).sum::<f32>();
    let (p, a) = (total(&plain), total(&ao));
    assert!(a < 0.95 * p && a > 0.3 * p, "{a} vs {p}");
    // Where the floor meets the box, most directions are blocked.
    let corner = (0..24).flat_map(|y| (0..24).map(move |x| (x, y)));
    let darkest = corner
        .map(|(x, y)| luminance(ao.get(x, y)) / luminance(plain.get(x, y)).max(1e-6))
        .fold(1.0, f32::min);
    assert!(darkest < 0.6, "{darkest}");
}

#[test]
fn mistakes_in_the_new_parameters_are_diagnosed() {
    let _watchdog = crate::watchdog::start();
    let err = build_error;
    let e = err("sphere { material { refract { ior 1.5  filtre rgb(1, 1, 1) } } }");
    assert!(
        e.contains("filtre") && e.contains("did you mean `filter`"),
        "{e}"
    );
    let e = err("camera { aperture 0.1 }");
    assert!(e.contains("needs a `focus`"), "{e}");
    let e = err("sphere { samples 4 }");
    assert!(e.contains("`samples` has no effect here"), "{e}");
    let e = err("render { sampler jitered }");
    assert!(e.contains("did you mean `jittered`"), "{e}");
    let e = err("material m { shininess 0 }");
    assert!(e.contains("greater than 0"), "{e}");
    let e = err("material m { refract { filter rgb(2, 1, 1) } }");
    assert!(e.contains("cannot exceed 1"), "{e}");
    let e = err("light { position <0, 1, 0>  angle 20 }");
    assert!(e.contains("needs a `look_at`"), "{e}");
}

#[test]
fn an_hdr_sky_lights_the_scene_and_is_seen_where_rays_escape() {
    let _watchdog = crate::watchdog::start();
    // A 4 × 2 EXR sky: radiance 3 in its top row (the upper hemisphere),
    // 0.5 in its bottom row. Above 1, as HDR allows.
    let dir = tempfile::tempdir().unwrap();
    let mut img = image::Rgb32FImage::new(4, 2);
    for x in 0..4 {
        img.put_pixel(x, 0, image::Rgb([3.0, 3.0, 3.0]));
        img.put_pixel(x, 1, image::Rgb([0.5, 0.5, 0.5]));
    }
    img.save(dir.path().join("sky.exr")).unwrap();
    let scene = |look: &str| {
        let path = dir.path().join("scene.rt");
        std::fs::write(
            &path,
            format!(
                "
camera {{ position <0, 0, 0>  look_at {look}  fov 10 }}
render {{ width 4  height 4  gamma linear }}
environment {{ image \"sky.exr\"  samples 64 }}
"
            ),
        )
        .unwrap();
        render_path(&path, None, 2)
    };
    // Straight up the camera sees the top row, straight down the bottom
    // (the sample lies at a pixel's centre row: exactly that value).
    let up = scene("<0.001, 1, 0>");
    assert!((up.get(2, 2)[0] - 3.0).abs() < 1e-3, "{:?}", up.get(2, 2));
    let down = scene("<0.001, -1, 0>");
    assert!(
        (down.get(2, 2)[0] - 0.5).abs() < 1e-3,
        "{:?}",
        down.get(2, 2)
    );
    // A white floor facing up takes light from the upper hemisphere only.
    let path = dir.path().join("floor.rt");
    std::fs::write(
        &path,
        "
camera { position <0, 1, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 10 }
render { width 4  height 4  gamma linear }
environment { image \"sky.exr\"  samples 16 }
plane { normal <0, 1, 0>  material { colour rgb(1, 1, 1) } }
",
    )
    .unwrap();
    let floor = render_path(&path, None, 2);
    // Bilinear lookups blend the two rows near the horizon, so the mean
    // lies a little under 3.
    let v = floor.get(1, 1)[0];
    assert!(v > 2.2 && v <= 3.0 + 1e-6, "{v}");
}

#[test]
fn an_emissive_object_value_lights_the_scene_wherever_it_is_placed() {
    let _watchdog = crate::watchdog::start();
    // One lamp value placed twice: the floor under each placement is lit
    // by it (inverse-square), the floor between them less.
    let film = render_src(
        "
camera { position <0, 1, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 120 }
render { width 41  height 3  gamma linear }
material lampm { emit white  intensity 100 }
let lamp = disc { radius 0.05  rotate x 90  material lampm }
lamp { translate <-1, 3, 0> }
lamp { translate <1, 3, 0> }
plane { normal <0, 1, 0>  material { colour rgb(1, 1, 1) } }
",
    );
    let row: Vec<f32> = (0..41).map(|x| film.get(x, 1)[0]).collect();
    let (left, mid, right) = (row[6], row[20], row[34]);
    assert!(left > 0.0 && right > 0.0, "{row:?}");
    // One random point of each small disc per pixel: equal within its noise.
    assert!(
        (left - right).abs() < 0.02 * left,
        "symmetric: {left} {right}"
    );
    // Under the middle both lamps shine from 3 up and 1 across:
    // 2 · L·A · cos·cos / r² = 2 · 100 · π·0.05² · 0.9 / 10.
    let want = 2.0 * 100.0 * std::f32::consts::PI * 0.0025 * 0.9 / 10.0;
    assert!((mid - want).abs() < 0.02 * want, "{mid} vs {want}");
}

/// A white floor seen from above at 3 × 3 pixels around the origin, under
/// `above` (objects), in linear output.
fn floor_lit_by(above: &str, render: &str) -> Film {
    render_src(&format!(
        "
camera {{ position <0.3, 0.5, 0>  look_at <0, 0, 0>  fov 2 }}
render {{ width 3  height 3  gamma linear  {render} }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
{above}
"
    ))
}

#[test]
fn a_sphere_light_is_sampled_over_the_cap_the_point_sees() {
    let _watchdog = crate::watchdog::start();
    // Radius 1 at height 5, radiance 10: E = π L (r/d)² = 0.4π straight
    // under it. Sampled over the cone it fills, one random point per pixel
    // already gives that within the spread of cos θ over the cone (2%);
    // points drawn over the whole sphere would miss half the time.
    let want = std::f64::consts::PI * 10.0 / 25.0;
    let film = floor_lit_by(
        "sphere { centre <0, 5, 0>  radius 1  material { emit white  intensity 10 } }",
        "seed 5",
    );
    for p in &film.pixels {
        let e = p[0] as f64;
        assert!((e - want).abs() < 0.02 * want, "{e} vs {want}");
    }
}

#[test]
fn an_emissive_sphere_inside_csg_lights_where_the_solid_kept_its_surface() {
    let _watchdog = crate::watchdog::start();
    let want = std::f64::consts::PI * 10.0 / 25.0;
    let lamp = "material lamp { emit white  intensity 10 }";
    // In a union with a box far away, it lights as the lone sphere does
    // (a 16 × 16 grid over its whole surface: within a few percent).
    let union = floor_lit_by(
        &format!(
            "{lamp} union {{ sphere {{ centre <0, 5, 0>  radius 1  material lamp  samples 16 }}  box {{ min <20, 0, 20>  max <21, 1, 21> }} }}"
        ),
        "",
    );
    let e = union.get(1, 1)[0] as f64;
    assert!((e - want).abs() < 0.03 * want, "{e} vs {want}");
    // With its lower half cut away (the cut face is the box's, dark), the
    // floor below sees no emitting surface: the samples on the missing
    // half must not count.
    let cut = floor_lit_by(
        &format!(
            "{lamp} difference {{ sphere {{ centre <0, 5, 0>  radius 1  material lamp  samples 16 }}  box {{ min <-2, 3, -2>  max <2, 5, 2>  material {{ colour black }} }} }}"
        ),
        "",
    );
    assert_eq!(cut.get(1, 1), [0.0, 0.0, 0.0]);
    // As a cutter it leaves a glowing dome in a slab (y from 4 to 6), open
    // below through a disc of radius 1 at height 4: every direction
    // through the opening meets the dome, so the floor under it gets the
    // disc's E = π L R²/(R² + h²) = 10π/17 (not the whole sphere's 10π/16).
    let dome = floor_lit_by(
        &format!(
            "{lamp} difference {{ box {{ min <-3, 4, -3>  max <3, 6, 3>  material {{ colour black }} }}  sphere {{ centre <0, 4, 0>  radius 1  material lamp  samples 16 }} }}"
        ),
        "",
    );
    let e_dome = dome.get(1, 1)[0] as f64;
    let want_dome = std::f64::consts::PI * 10.0 / 17.0;
    assert!(
        (e_dome - want_dome).abs() < 0.03 * want_dome,
        "{e_dome} vs {want_dome}"
    );
    // The same lamp, moved with the CSG: a translate on the operation
    // moves its light too.
    let moved = floor_lit_by(
        &format!(
            "{lamp} union {{ sphere {{ centre <0, 0, 0>  radius 1  material lamp  samples 16 }}  box {{ min <20, 0, 20>  max <21, 1, 21> }}  translate <0, 5, 0> }}"
        ),
        "",
    );
    assert!((moved.get(1, 1)[0] as f64 - e).abs() < 1e-6 * want);
}

#[test]
fn an_emissive_shape_that_cannot_light_is_warned_about() {
    let _watchdog = crate::watchdog::start();
    let warnings = |src: &str| {
        let (_d, path) = scene_file(src);
        let program = raytrace::lang::load(&path).unwrap();
        raytrace::scene::build_with_warnings(&program).unwrap().1
    };
    let w = warnings("box { min <0, 0, 0>  max <1, 1, 1>  material { emit white } }");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("emissive `box`") && w[0].contains("lights nothing"));
    // Inside CSG too; an emissive sphere there lights, and says nothing.
    let w = warnings(
        "union { torus { major 1  minor 0.2  material { emit white } }  sphere { radius 0.5  material { emit white } } }",
    );
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("emissive `torus`"), "{w:?}");
    assert!(warnings("disc { radius 1  material { emit white } }").is_empty());
    // A pattern choosing an emitting material glows too.
    let w = warnings(
        "material lamp { emit white }\nbox { min <0, 0, 0>  max <1, 1, 1>  material { checker { a lamp  b lamp } } }",
    );
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        warnings("material lamp { emit white }\ndisc { radius 1  material { checker { a lamp  b lamp } } }")
            .is_empty()
    );
}
