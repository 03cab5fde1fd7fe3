//! Where the language puts things: the plane's offset, and the space a
//! texture given to a CSG block is evaluated in.

use crate::support::{build_src, pixels_differing, render_src};
use raytrace::geometry::{DVec3, Ray};
use raytrace::shapes::Shape;

/// Builds a scene from text and returns its objects.
fn objects(src: &str) -> Vec<Box<dyn Shape>> {
    build_src(src).objects
}

/// docs/language.md: "`normal <0, 2, 0>  offset 1` is the plane y = 1".
#[test]
fn plane_offset_is_a_distance_along_the_unit_normal() {
    let _watchdog = crate::watchdog::start();
    let objs = objects("plane { normal <0, 2, 0>  offset 1 }");
    let down = Ray::new(DVec3::new(0.3, 5.0, -0.2), -DVec3::Y);
    let h = objs[0].intersect(&down, 0.0, f64::INFINITY).expect("hit");
    assert!(
        (down.at(h.t).y - 1.0).abs() < 1e-12,
        "plane at y = {}",
        down.at(h.t).y
    );
    // A tilted normal of any length: the nearest point to the origin is
    // `offset` away along it.
    let objs = objects("plane { normal <0, 5, 5>  offset 2 }");
    let along = Ray::new(DVec3::ZERO, DVec3::new(0.0, 1.0, 1.0).normalize());
    let h = objs[0].intersect(&along, 0.0, f64::INFINITY).expect("hit");
    assert!((h.t - 2.0).abs() < 1e-12, "t = {}", h.t);
}

/// A texture given to a CSG block is evaluated in the block's space, so a
/// solid pattern runs through the seams between children whatever places
/// them: the same block written with `translate` or with the children's own
/// `centre` / `min` / `max` is the same picture. (Before, each child read
/// the pattern in its own space: the translated sphere's marble was the
/// other's shifted by 1.6, a different picture on every pixel of it.)
#[test]
fn csg_texture_lives_in_the_block_space_whatever_places_the_children() {
    let _watchdog = crate::watchdog::start();
    let scene = |a: &str, b: &str, c: &str| {
        format!(
            "camera {{ position <0, 1, 6>  look_at <0, 0, 0>  fov 50 }}
render {{ width 64  height 48  gamma linear }}
ambient rgb(1, 1, 1) intensity 0.3
light {{ position <2, 5, 6> }}
material stone {{ colour marble {{ a white  b rgb(0.1, 0.1, 0.3)  scale 2  turbulence 2 }} }}
material tiles {{ colour checker3d {{ a white  b rgb(0.2, 0.6, 0.2)  size 0.37 }} }}
union {{ {a} {b}  material stone  rotate y 20  translate <0, 0.5, 0> }}
difference {{ box {{ min <-2, -1.5, -1>  max <2, -0.5, 1> }} {c}  material tiles }}"
        )
    };
    let by_translate = render_src(&scene(
        "sphere { radius 1  translate <-0.8, 0, 0> }",
        "sphere { radius 1  scale 0.9  translate <0.8, 0, 0> }",
        "box { min <-0.5, -0.5, -0.5>  max <0.5, 0.5, 0.5>  translate <0.3, -0.6, 0.8> }",
    ));
    let by_centre = render_src(&scene(
        "sphere { centre <-0.8, 0, 0>  radius 1 }",
        "sphere { centre <0.8, 0, 0>  radius 0.9 }",
        "box { min <-0.2, -1.1, 0.3>  max <0.8, -0.1, 1.3> }",
    ));
    let differ = pixels_differing(&by_translate, &by_centre, 1e-3);
    assert_eq!(differ, 0, "{differ} pixels differ");
    // Both patterns are in view: dark veins and green cells.
    let px = &by_centre.pixels;
    assert!(
        px.iter().any(|p| p[2] > 2.0 * p[0] && p[2] > 0.02),
        "marble veins"
    );
    assert!(
        px.iter().any(|p| p[1] > 2.0 * p[0] && p[1] > 0.05),
        "green cells"
    );
}

/// A child that names its own material keeps its own texture space (the
/// pattern moves with the child, as outside CSG); the block's space is for
/// the material the block gives.
#[test]
fn csg_child_with_its_own_material_keeps_its_own_texture_space() {
    let _watchdog = crate::watchdog::start();
    let scene = |body: &str| {
        format!(
            "camera {{ position <0, 0, 6>  look_at <0, 0, 0>  fov 40 }}
render {{ width 48  height 48  gamma linear }}
ambient rgb(1, 1, 1) intensity 1
material tiles {{ colour checker3d {{ a white  b rgb(0, 0, 0)  size 0.5 }} }}
{body}"
        )
    };
    // Moved by half a cell: the two readings differ on the sphere.
    let ball = "sphere { radius 1  translate <0.25, 0.25, 0> ";
    let alone = render_src(&scene(&format!("{ball} material tiles }}")));
    let own = render_src(&scene(&format!(
        "union {{ {ball} material tiles }}  sphere {{ centre <0, 9, 0> }} }}"
    )));
    let given = render_src(&scene(&format!(
        "union {{ {ball} }}  sphere {{ centre <0, 9, 0> }}  material tiles }}"
    )));
    let differ = |a: &raytrace::render::Film, b: &raytrace::render::Film| {
        a.pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(p, q)| (p[0] - q[0]).abs() > 0.5)
            .count()
    };
    assert_eq!(differ(&alone, &own), 0, "own material, own space");
    assert!(
        differ(&alone, &given) > 100,
        "block's material, block's space"
    );
}

/// Moving the solid-texture point to the block's space leaves (u, v)
/// alone: a surface pattern given to a CSG block still reads each child's
/// own (u, v), so a lone translated sphere inside a union looks as it does
/// outside one.
#[test]
fn csg_texture_space_leaves_uv_patterns_on_the_child() {
    let _watchdog = crate::watchdog::start();
    let scene = |body: &str| {
        format!(
            "camera {{ position <0, 0, 6>  look_at <0, 0, 0>  fov 40 }}
render {{ width 48  height 48  gamma linear  background rgb(0.5, 0.5, 0.5) }}
ambient rgb(1, 1, 1) intensity 1
material squares {{ colour checker {{ a white  b rgb(0, 0, 0)  scale 8 }} }}
{body}"
        )
    };
    let ball = "sphere { radius 1  rotate x 30  translate <0.3, 0.2, 0> }";
    // The pattern given straight, and only chosen by the block's material
    // (a solid pattern of materials, nested): the block works (u, v) out
    // for what its material may choose, not only for what it is.
    let chooser = "material picks { checker3d { a squares  b squares } }
material outer { checker3d { a picks  b squares  size 2 } }";
    for (prelude, material) in [("", "squares"), (chooser, "outer")] {
        let alone = render_src(&scene(&format!(
            "{prelude}\n{} material {material} }}",
            &ball[..ball.len() - 1]
        )));
        let in_union = render_src(&scene(&format!(
            "{prelude}\nunion {{ {ball}  sphere {{ centre <0, 9, 0> }}  material {material} }}"
        )));
        let dark = alone.pixels.iter().filter(|p| p[0] < 0.25).count();
        assert!(dark > 100, "{material}: {dark} dark pixels");
        assert_eq!(
            crate::support::max_difference(&alone, &in_union),
            0.0,
            "{material}"
        );
    }
}
