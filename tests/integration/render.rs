//! What pictures must show: shadows, silhouettes, transforms, reflections,
//! thread independence.

use crate::support::*;
use raytrace::render::Film;

const HEADER: &str = "
camera { position <0, 0, 4>  look_at <0, 0, 0>  up <0, 1, 0>  distance 1  width 2  height 2 }
render { width 64  height 64  max_depth 3  gamma linear }
";

#[test]
fn floor_under_a_sphere_is_in_shadow_and_elsewhere_lit() {
    let _watchdog = crate::watchdog::start();
    // A lamp high above a sphere at x = 3 casts a round shadow of radius
    // about 1.04 centred on (3, 0, 0). The camera hangs above x = −3 looking
    // straight down (fov 90: ten units either side), so it sees that shadow
    // past the sphere's rim. Floor colour 1 and ambient 0.1: a shadowed floor
    // pixel is exactly 0.1, a lit one 0.1 + cos(incidence).
    let film = render_src(
        "
camera { position <-3, 10, 0>  look_at <-3, 0, 0>  up <0, 0, -1>  fov 90 }
render { width 64  height 64  gamma linear }
ambient rgb(1, 1, 1) intensity 0.1
light { position <3, 50, 0> }
plane { normal <0, 1, 0>  material { colour rgb(1, 1, 1) } }
sphere { centre <3, 2, 0>  radius 1  material { colour rgb(1, 0, 0) } }
",
    );
    // Column 49's centre looks at x ≈ 2.47, row 32's at z ≈ 0.16: in the
    // shadow, 8° off the sphere's centre as the camera sees it (its rim is
    // at 5.7°).
    let shadowed = film.get(49, 32);
    assert!((shadowed[0] - 0.1).abs() < 1e-4, "shadow: {shadowed:?}");
    assert!(
        (shadowed[1] - 0.1).abs() < 1e-4,
        "shadowed floor is grey: {shadowed:?}"
    );
    // Straight below the camera the floor is lit almost head-on: by
    // conventions.md pixel (32, 32) fires through (a + 0.5)/32 − 1 =
    // 1/64 of the half-width (tan 45° · 10 = 10 units) right (+x, since
    // r = l × u' = (0,−1,0) × (0,0,−1)) and 1/64 down the image (−u' =
    // +z): the floor point (−3 + 10/64, 0, 10/64). Lit at cos = n·l̂.
    let p = glam::DVec3::new(-3.0 + 10.0 / 64.0, 0.0, 10.0 / 64.0);
    let to_light = glam::DVec3::new(3.0, 50.0, 0.0) - p;
    let want = 0.1 + to_light.normalize().y;
    let lit = film.get(32, 32);
    for (k, &c) in lit.iter().enumerate() {
        assert!(
            (c as f64 - want).abs() < 1e-5,
            "lit floor channel {k}: {lit:?} vs {want}"
        );
    }
}

#[test]
fn sphere_silhouette_matches_the_analytic_circle() {
    let _watchdog = crate::watchdog::start();
    let film = render_src(&format!(
        "{HEADER}
ambient rgb(1, 1, 1) intensity 1
sphere {{ radius 1  material {{ colour rgb(1, 1, 1) }} }}
"
    ));
    // Pixel centre (a, b) → direction (x, y, −1) with x, y in [−1, 1]; the ray
    // from (0,0,4) hits the unit sphere iff its distance from the origin < 1.
    let mut wrong = 0;
    for b in 0..64 {
        for a in 0..64 {
            let x = -1.0 + (a as f64 + 0.5) / 32.0;
            let y = 1.0 - (b as f64 + 0.5) / 32.0;
            let d = glam::DVec3::new(x, y, -1.0).normalize();
            let o = glam::DVec3::new(0.0, 0.0, 4.0);
            let dist = (o - o.dot(d) * d).length();
            if (dist - 1.0).abs() < 1e-9 {
                continue;
            }
            let hit = luminance(film.get(a, b)) > 0.5;
            if hit != (dist < 1.0) {
                wrong += 1;
            }
        }
    }
    assert_eq!(wrong, 0);
}

#[test]
fn transformed_box_equals_the_box_placed_by_hand() {
    let _watchdog = crate::watchdog::start();
    let by_transform = render_src(&format!(
        "{HEADER}
ambient rgb(1, 1, 1) intensity 0.2
light {{ position <3, 4, 5> }}
box {{ min <-1, -1, -1>  max <1, 1, 1>  scale <0.5, 0.25, 0.25>  rotate z 90  translate <0.3, 0.2, 0> }}
"
    ));
    let by_hand = render_src(&format!(
        "{HEADER}
ambient rgb(1, 1, 1) intensity 0.2
light {{ position <3, 4, 5> }}
box {{ min <0.05, -0.3, -0.25>  max <0.55, 0.7, 0.25> }}
"
    ));
    let lit = by_hand
        .pixels
        .iter()
        .filter(|p| luminance(**p) > 0.0)
        .count();
    assert!(lit > 30, "the box is visible: {lit} pixels");
    assert!(max_difference(&by_transform, &by_hand) < 1e-4);
}

#[test]
fn mirror_shows_the_sphere_in_front_of_it() {
    let _watchdog = crate::watchdog::start();
    // A mirror plane behind a red sphere, camera looking past the sphere at
    // the mirror: the red appears again, reflected, beside the real one.
    let film = render_src(
        "
camera { position <0, 0, 6>  look_at <0, 0, 0>  up <0, 1, 0>  fov 60 }
render { width 64  height 64  max_depth 2  gamma linear }
ambient rgb(1, 1, 1) intensity 1
plane { normal <-1, 0, 1>  offset -2  material { colour rgb(0, 0, 1)  reflect 1 } }
sphere { centre <-2, 0, 2>  radius 0.6  material { colour rgb(1, 0, 0) } }
",
    );
    // The mirror image of the sphere's centre C = (−2, 0, 2) in the plane
    // n̂·p = −2, n̂ = (−1, 0, 1)/√2 (the offset is a distance along the
    // unit normal): C' = C − 2(n̂·C + 2)n̂ = (2 + 2√2, 0, −2 − 2√2).
    // Projected through the camera (conventions.md: fov 60 horizontal,
    // r = +x, u' = +y, pixel a at tan 30°·((a + 0.5)/32 − 1)), it lands at
    // (col, row).
    let n = glam::DVec3::new(-1.0, 0.0, 1.0).normalize();
    let c = glam::DVec3::new(-2.0, 0.0, 2.0);
    let image = c - 2.0 * (n.dot(c) + 2.0) * n;
    let s = 2.0 + 2.0 * 2f64.sqrt();
    assert!((image - glam::DVec3::new(s, 0.0, -s)).length() < 1e-12);
    let d = image - glam::DVec3::new(0.0, 0.0, 6.0);
    let half = 30f64.to_radians().tan();
    let col = 32.0 * (1.0 + (d.x / -d.z) / half) - 0.5;
    let row = 32.0 * (1.0 - (d.y / -d.z) / half) - 0.5;
    // The red reflection, right of the real sphere (at column 32·(1 −
    // 0.5/tan 30°) − 0.5 ≈ 4): its pixels' centroid is the projected image
    // centre (a sphere's outline is symmetric about it to within a tenth
    // of a pixel at this size).
    let red: Vec<(f64, f64)> = (33..64)
        .flat_map(|a| (0..64).map(move |b| (a, b)))
        .filter(|&(a, b)| {
            let p = film.get(a, b);
            p[0] > 0.5 && p[2] < 0.1
        })
        .map(|(a, b)| (a as f64, b as f64))
        .collect();
    assert!(
        red.len() > 5,
        "reflection of the sphere visible: {}",
        red.len()
    );
    let n_red = red.len() as f64;
    let (ca, cb) = red
        .iter()
        .fold((0.0, 0.0), |(x, y), &(a, b)| (x + a / n_red, y + b / n_red));
    assert!(
        (ca - col).abs() < 0.35 && (cb - row).abs() < 0.35,
        "reflection centred at ({ca:.2}, {cb:.2}), the mirror says ({col:.2}, {row:.2})"
    );
}

#[test]
fn image_is_identical_for_one_and_two_threads() {
    let _watchdog = crate::watchdog::start();
    let (_dir, path) = scene_file(&format!(
        "{HEADER}
ambient rgb(1, 1, 1) intensity 0.1
light {{ position <2, 3, 4> }}
sphere {{ centre <-0.5, 0, 0>  radius 0.6  material {{ colour rgb(1, 0.5, 0.2)  reflect 0.4 }} }}
sphere {{ centre <0.6, 0.2, -0.5>  radius 0.5  material {{ colour rgb(0.2, 0.5, 1)  reflect 0.4 }} }}
plane {{ normal <0, 1, 0>  offset -0.6  material {{ colour rgb(0.8, 0.8, 0.8)  reflect 0.3 }} }}
"
    ));
    let one = render_path(&path, None, 1);
    let two = render_path(&path, None, 2);
    assert_eq!(one, two);
}

/// Two facing walls of material `wall` (a material block's body) at
/// z = ±1, seen from between them with `render { … }` settings `render`,
/// lit only by ambient light of intensity `a`.
fn between_walls(render: &str, a: f64, wall: &str) -> Film {
    render_src(&format!(
        "camera {{ position <0, 0, 0>  look_at <0, 0, -1>  up <0, 1, 0>  fov 60 }}
render {{ {render}  gamma linear }}
ambient rgb(1, 1, 1) intensity {a}
material wall {{ {wall} }}
plane {{ normal <0, 0, 1>  offset -1  material wall }}
plane {{ normal <0, 0, -1>  offset -1  material wall }}"
    ))
}

/// Every pixel of `film` is `want` in each channel, to within `tol`.
fn assert_every_pixel(film: &Film, want: [f64; 3], tol: f64, what: &str) {
    for (i, p) in film.pixels.iter().enumerate() {
        for k in 0..3 {
            assert!(
                (p[k] as f64 - want[k]).abs() < tol,
                "{what}, pixel {i}, channel {k}: {} vs {}",
                p[k],
                want[k]
            );
        }
    }
}

/// The recursion depth, exactly: between two facing mirrors lit only by
/// ambient light every camera ray bounces until `max_depth`, so each pixel
/// is (1 − R)·c·a·(1 + R + … + R^N) with N = max_depth (a reflection one
/// bounce too deep or too shallow adds or drops the term R^N).
#[test]
fn facing_mirrors_add_exactly_max_depth_reflections() {
    let _watchdog = crate::watchdog::start();
    let (r, a, c) = (0.5f64, 0.5f64, [1.0f64, 0.5, 0.25]);
    for n in 0..=4u32 {
        let film = between_walls(
            &format!("width 5  height 5  max_depth {n}"),
            a,
            &format!("colour rgb({}, {}, {})  reflect {r}", c[0], c[1], c[2]),
        );
        let series: f64 = (0..=n).map(|k| r.powi(k as i32)).sum();
        let want = c.map(|ck| (1.0 - r) * ck * a * series);
        assert_every_pixel(&film, want, 1e-5, &format!("max_depth {n}"));
    }
}

/// `render { bailout B }`: the k-th reflection between two facing mirrors
/// carries R^k of the pixel, so it is cast exactly while R^k ≥ B and the
/// pixel is (1 − R)·c·a·(1 + R + … + R^N) with N the last such k, however
/// deep `max_depth` allows. B = R³ exactly keeps the third reflection (the
/// test is "below", not "at or below"); a hair more drops it.
#[test]
fn bailout_stops_the_reflections_whose_share_is_below_it() {
    let _watchdog = crate::watchdog::start();
    let (r, a, c) = (0.5f64, 0.5f64, [1.0f64, 0.5, 0.25]);
    for (bailout, n) in [(0.0, 20), (0.1, 3), (0.125, 3), (0.126, 2), (0.6, 0)] {
        let film = between_walls(
            &format!("width 5  height 5  max_depth 20  bailout {bailout}"),
            a,
            &format!("colour rgb({}, {}, {})  reflect {r}", c[0], c[1], c[2]),
        );
        let series: f64 = (0..=n).map(|k| r.powi(k)).sum();
        let want = c.map(|ck| (1.0 - r) * ck * a * series);
        let what = format!("bailout {bailout} ({n} reflections)");
        assert_every_pixel(&film, want, 1e-6, &what);
    }
}

/// An additive mirror's weight is its strongest channel: with mirror
/// colour (0.5, 0.1, 0.1) the k-th reflection is cast while 0.5^k ≥ B,
/// though its red share is all that is left of it. Each pixel is
/// c·a·Σ m^j (j = 0 … N) per channel.
#[test]
fn bailout_weighs_a_coloured_mirror_by_its_strongest_channel() {
    let _watchdog = crate::watchdog::start();
    let (a, c, m) = (0.5f64, [0.2f64, 0.6, 0.9], [0.5f64, 0.1, 0.1]);
    for (bailout, n) in [(0.2, 2), (0.25, 2), (0.3, 1)] {
        let film = between_walls(
            &format!("width 3  height 3  max_depth 20  bailout {bailout}"),
            a,
            &format!(
                "colour rgb({}, {}, {})  mirror 1  mirror_colour rgb({}, {}, {})",
                c[0], c[1], c[2], m[0], m[1], m[2]
            ),
        );
        let want = [0, 1, 2].map(|k| c[k] * a * (0..=n).map(|j| m[k].powi(j)).sum::<f64>());
        let what = format!("bailout {bailout} ({n} reflections)");
        assert_every_pixel(&film, want, 1e-6, &what);
    }
}

/// The two torus benchmarks, the implicit quartic (turned and lifted) and
/// the torus shape, are one picture: two routes to one surface, through
/// the equation compiler and the shape's own chord tests.
#[test]
fn the_torus_benchmarks_implicit_and_native_agree() {
    let _watchdog = crate::watchdog::start();
    let root = project_root();
    let size = Some((120, 120));
    let implicit = render_path(&root.join("benches/scenes/torus.rt"), size, 2);
    let native = render_path(&root.join("benches/scenes/torus_native.rt"), size, 2);
    let gold = native
        .pixels
        .iter()
        .filter(|p| p[0] > 0.3 && p[2] < 0.5 * p[0])
        .count();
    assert!(
        gold > 1000,
        "the gold torus fills part of the picture: {gold}"
    );
    // A silhouette pixel may fall either way between the two routes.
    let differing = pixels_differing(&implicit, &native, 1e-3);
    assert_eq!(differing, 0, "{differing} pixels differ");
}
