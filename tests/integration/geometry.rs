//! Geometry that holds at every scale (issue 20): the same scene scaled and
//! moved far from the origin renders as at unit scale, a mirror smooth mesh
//! reflects nothing of itself, and meshes let no ray through.

use super::support::render_path;
use proptest::prelude::*;
use raytrace::formats::ply::{icosphere, write_ascii};
use raytrace::output::to_rgb8;
use raytrace::render::Film;
use raytrace::scene::Transfer;
use std::path::PathBuf;

/// A directory holding `scene.rt` and the icosphere meshes it may name.
fn scene_dir(src: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("temp dir");
    for level in [1, 3] {
        let (p, t) = icosphere(level);
        let faces: Vec<Vec<u32>> = t.iter().map(|f| f.to_vec()).collect();
        std::fs::write(
            dir.path().join(format!("ico{level}.ply")),
            write_ascii(&p, &faces),
        )
        .expect("write mesh");
    }
    let path = dir.path().join("scene.rt");
    std::fs::write(&path, src).expect("write scene");
    (dir, path)
}

fn v(p: [f64; 3]) -> String {
    format!("<{:e}, {:e}, {:e}>", p[0], p[1], p[2])
}

/// Every primitive kind resting on a mirror-ish floor (contact shadows and
/// reflections), with the camera and the light, all scaled by `s` and then
/// moved by `t`.
fn showroom(s: f64, t: [f64; 3]) -> String {
    let at = |p: [f64; 3]| v([p[0] * s + t[0], p[1] * s + t[1], p[2] * s + t[2]]);
    let x = format!("scale {s:e}  translate {}", v(t));
    format!(
        r#"
camera {{ position {cam}  look_at {look}  fov 50 }}
render {{ width 96  height 72  max_depth 2  background rgb(0.3, 0.4, 0.6) }}
ambient rgb(1, 1, 1) intensity 0.1
light {{ position {light} }}
material m {{ colour rgb(0.8, 0.5, 0.3)  reflect 0.2 }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(0.9, 0.9, 0.9)  reflect 0.3 }}  {x} }}
sphere {{ centre <-2.2, 1, 0>  radius 1  material m  {x} }}
box {{ min <-0.6, 0, 1.2>  max <0.6, 1.2, 2.2>  material m  {x} }}
cylinder {{ centre <2.2, 0.75, 0>  radius 0.6  height 1.5  material m  {x} }}
cone {{ centre <0.2, 0.9, -1.5>  radius 0.8  height 1.8  material m  {x} }}
torus {{ major 0.7  minor 0.25  material m  translate <-1.8, 0.25, 2.2>  {x} }}
implicit "x^4 + y^4 + z^4 - 0.4" {{ material m  translate <1.9, 0.8, 2.0>  {x} }}
mesh "ico1.ply" {{ smooth  material m  scale 0.6  translate <-0.5, 0.6, 0>  {x} }}
disc {{ centre <0, 0, 0>  radius 0.5  material m  rotate x -90  translate <0.9, 0.001, 3.2>  {x} }}
triangle {{ a <-3.9, 0, 1.2>  b <-3.2, 0, 0.8>  c <-3.6, 1.4, 1>  material m  {x} }}
rectangle {{ bottom_left <2.6, 0, -2.5>  top_left <2.6, 1.4, -2.5>  bottom_right <3.6, 0, -1.5>  material m  {x} }}
"#,
        cam = at([1.0, 4.0, 9.0]),
        look = at([0.0, 0.7, 0.0]),
        light = at([4.0, 9.0, 6.0]),
    )
}

fn render(src: &str) -> Film {
    let (_dir, path) = scene_dir(src);
    render_path(&path, None, 2)
}

/// Pixels (as written to an 8-bit sRGB file) more than 32 levels apart in
/// some channel.
fn far_apart(a: &Film, b: &Film) -> usize {
    let (a, b) = (to_rgb8(a, Transfer::Srgb), to_rgb8(b, Transfer::Srgb));
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| (0..3).any(|i| p[i].abs_diff(q[i]) > 32))
        .count()
}

fn assert_same_as_unit(s: f64, t: [f64; 3], unit: &Film) {
    let film = render(&showroom(s, t));
    let bad = far_apart(&film, unit);
    let allowed = (film.pixels.len() as f64 * 0.001).ceil() as usize;
    assert!(
        bad <= allowed,
        "scale {s:e} at {t:?}: {bad} pixels differ by more than 32 levels (allowed {allowed})"
    );
}

#[test]
fn a_scene_scaled_and_moved_far_away_renders_as_at_unit_scale() {
    let _watchdog = crate::watchdog::start();
    let unit = render(&showroom(1.0, [0.0; 3]));
    for (s, t) in [
        (1e-6, [0.0; 3]),
        (1e4, [0.0; 3]),
        (1.0, [1e6, -1e6, 1e6]),
        (1e-2, [1e5, 0.0, -1e5]),
        (1e-6, [1e6, 1e6, 0.0]),
    ] {
        assert_same_as_unit(s, t, &unit);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]
    #[test]
    fn any_scale_and_offset_renders_as_at_unit_scale(
        log_s in -6.0f64..4.0,
        t in prop::array::uniform3(-1e6f64..1e6),
    ) {
        let unit = render(&showroom(1.0, [0.0; 3]));
        assert_same_as_unit(10f64.powf(log_s), t, &unit);
    }
}

/// A perfect mirror in a white world shows white everywhere, however
/// coarse the smooth mesh: no reflected ray may go below the surface and
/// meet the mesh from inside (the shading normal alone used to decide).
#[test]
fn a_mirror_smooth_mesh_in_a_white_world_is_white() {
    let _watchdog = crate::watchdog::start();
    for level in [1, 3] {
        let film = render(&format!(
            r#"
camera {{ position <0, 0, 3.2>  look_at <0, 0, 0>  fov 45 }}
render {{ width 120  height 120  background rgb(1, 1, 1) }}
ambient rgb(1, 1, 1) intensity 0
mesh "ico{level}.ply" {{ smooth  material {{ colour rgb(0, 0, 0)  reflect 1 }} }}
"#
        ));
        let dark = film
            .pixels
            .iter()
            .filter(|p| p.iter().any(|&c| c < 0.999))
            .count();
        assert_eq!(dark, 0, "icosphere level {level}: {dark} dark pixels");
    }
}

/// A smooth sphere mesh lit from the side: where the analytic sphere is
/// clearly lit, the mesh must not be black. Shadow rays from the flat
/// facets used to be blocked by the neighbouring facets wherever the light
/// was below the facet but above the smooth normal's horizon, a jagged,
/// facet-shaped terminator (77 such pixels at 200×200 with 1,280 faces).
#[test]
fn the_terminator_of_a_smooth_sphere_mesh_follows_the_sphere() {
    let _watchdog = crate::watchdog::start();
    let scene = |object: &str| {
        format!(
            r#"
camera {{ position <0, 0, 4>  look_at <0, 0, 0>  fov 40 }}
render {{ width 160  height 160  background rgb(0, 0, 1) }}
ambient rgb(1, 1, 1) intensity 0
light {{ position <100, 30, 10> }}
{object}
"#
        )
    };
    for level in [1, 3] {
        let mesh = render(&scene(&format!(
            r#"mesh "ico{level}.ply" {{ smooth  material {{ colour rgb(1, 1, 1) }} }}"#
        )));
        let sphere = render(&scene(
            "sphere { radius 1  material { colour rgb(1, 1, 1) } }",
        ));
        let (m, s) = (
            to_rgb8(&mesh, Transfer::Srgb),
            to_rgb8(&sphere, Transfer::Srgb),
        );
        let wrong = m
            .pixels()
            .zip(s.pixels())
            .filter(|(m, s)| s[0] > 40 && m.0 == [0, 0, 0])
            .count();
        assert_eq!(
            wrong, 0,
            "icosphere level {level}: {wrong} pixels in false shadow"
        );
    }
}
