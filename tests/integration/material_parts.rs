//! Which parts of a material the integrator evaluates: a part a material
//! lacks must cost nothing and change nothing, and a part it has must show
//! on its own. Mutation testing of src/render/material found `reflects`
//! (whether a material needs its lights sampled) untested.

use crate::support::*;

/// A glossy mirror floor (no diffuse or ambient part) reflecting a wall of
/// emissive stripes (no diffuse or ambient part either), plus `extra`.
fn glossy_floor(extra: &str) -> raytrace::render::Film {
    render_src(&format!(
        "
camera {{ position <0, 1, 4>  look_at <0, 0.5, 0> fov 50 }}
render {{ width 24  height 16  samples 2  sampler random  gamma linear }}
material floor {{ colour white  diffuse 0  ambient 0  mirror 1  glossy 30 }}
plane {{ normal <0, 1, 0>  material floor }}
material red {{ emit rgb(1, 0.1, 0.1) }}
material blue {{ emit rgb(0.1, 0.2, 1) }}
for i in 0..6 {{
  rectangle {{ bottom_left <i - 3, 0, -2>  top_left <i - 3, 3, -2>  bottom_right <i - 2.5, 0, -2>  material red }}
  rectangle {{ bottom_left <i - 2.5, 0, -2>  top_left <i - 2.5, 3, -2>  bottom_right <i - 2, 0, -2>  material blue }}
}}
{extra}
"
    ))
}

/// A surface with no diffuse or ambient part is not lit: its lights are
/// not sampled, so a light that reaches nothing in view changes no pixel,
/// not even through the random numbers a sampled area light would use (the
/// glossy floor draws its mirror rays from the same stream).
#[test]
fn a_light_that_lights_nothing_in_view_changes_no_pixel() {
    let _watchdog = crate::watchdog::start();
    let without = glossy_floor("");
    // A lamp facing down under the floor, and a point light: they light
    // only what neither the camera nor the floor's mirror rays can see.
    let with = glossy_floor(
        "material lamp { emit white  intensity 5 }
         disc { radius 1  rotate x 90  translate <0, -3, 0>  material lamp }
         light { position <0, -2, 0> }",
    );
    // The floor does reflect the stripes (the test would be empty if not).
    let floor_px = without.get(12, 14);
    assert!(floor_px[0] + floor_px[2] > 0.05, "{floor_px:?}");
    assert_eq!(pixels_differing(&without, &with, 0.0), 0);
}

/// k_a c ⊙ L_ambient alone: a material with ambient but no diffuse part
/// shows exactly that, and lights add nothing to it.
#[test]
fn an_ambient_only_material_shows_ka_times_its_colour_times_the_ambient() {
    let _watchdog = crate::watchdog::start();
    let f = render_src(
        "camera { position <0, 0, 4>  look_at <0, 0, 0>  fov 30 }
         render { width 9  height 9  gamma linear }
         ambient rgb(1, 1, 0.5) intensity 0.6
         light { position <0, 0, 10> }
         sphere { radius 1  material { colour rgb(0.8, 0.4, 0.2)  diffuse 0  ambient 0.5 } }",
    );
    let want = [0.8 * 0.5 * 0.6, 0.4 * 0.5 * 0.6, 0.2 * 0.5 * 0.6 * 0.5];
    let got = f.get(4, 4);
    for k in 0..3 {
        assert!(
            (got[k] as f64 - want[k]).abs() < 1e-6,
            "{got:?} vs {want:?}"
        );
    }
    // The background stays black: the ambient light is not a sky.
    assert_eq!(f.get(0, 0), [0.0; 3]);
}
