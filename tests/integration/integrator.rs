//! The Whitted recursion end to end (src/render/integrator.rs): how many
//! rays of each kind a picture needs, and what crossing into a medium does
//! to the radiance seen there, against counts and physics known by
//! construction.

use crate::support::*;
use raytrace::render::{Film, Region, RenderOptions, RenderStats, render_region};

/// The film and statistics of a scene given as text, on one thread.
fn render_stats(src: &str) -> (Film, RenderStats) {
    let mut scene = build_src(src);
    let world = raytrace::accel::World::build(std::mem::take(&mut scene.objects));
    let all = Region {
        x: 0,
        y: 0,
        width: scene.settings.width,
        height: scene.settings.height,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| render_region(&scene, &world, &RenderOptions { progress: None }, all))
        .unwrap()
}

/// A mirror floor filling the view from straight above, showing a white
/// ceiling lit by one point light between the two: each pixel's camera
/// ray meets the mirror (no light is sampled there: it reflects nothing
/// diffusely), its reflected ray meets the ceiling, and one shadow ray
/// goes from there to the light. `extra` adds to the scene.
fn mirror_and_ceiling(extra: &str) -> String {
    format!(
        "
camera {{ position <0, 1, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 40 }}
render {{ width 6  height 4  max_depth 3  gamma linear }}
light {{ position <0, 1.5, 0> }}
plane {{ normal <0, 1, 0>  material {{ colour black  diffuse 0  ambient 0  mirror 1 }} }}
plane {{ normal <0, -1, 0>  offset -2  material {{ colour white  ambient 0 }} }}
{extra}
"
    )
}

#[test]
fn ray_counts_are_one_camera_one_mirror_and_one_shadow_ray_per_pixel() {
    let _watchdog = crate::watchdog::start();
    let (film, stats) = render_stats(&mirror_and_ceiling(""));
    let pixels = 6 * 4;
    assert_eq!(stats.rays.primary, pixels);
    assert_eq!(stats.rays.reflected, pixels);
    assert_eq!(stats.rays.shadow, pixels);
    // And the picture is the lit ceiling: nothing in the view is black.
    assert!(film.pixels.iter().all(|p| p[0] > 0.01), "{:?}", film.pixels);
    // Ambient occlusion traces its own shadow rays: `samples` per
    // shading point lit by lights (the ceiling).
    let (_, ao) = render_stats(&mirror_and_ceiling(
        "ambient white intensity 0.1 occlusion { samples 5  min 0.5  distance 1 }",
    ));
    assert_eq!(ao.rays.shadow, pixels + 5 * pixels);
    // A sky gathered by a diffuse surface: `samples` rays per shading
    // point, besides the light's.
    let (_, sky) = render_stats(&mirror_and_ceiling(
        "environment { colour white  intensity 0.1  samples 3 }",
    ));
    assert_eq!(sky.rays.shadow, pixels + 3 * pixels);
}

/// A white floor seen from straight above, lit from straight above, with
/// `extra` (objects) added.
fn floor_under(extra: &str) -> Film {
    render_src(&format!(
        "
camera {{ position <0, 3, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 20 }}
render {{ width 16  height 16  gamma linear }}
light {{ position <0, 50, 0> }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
{extra}
"
    ))
}

/// Radiance is not conserved across an interface: L/η² is (the basic
/// radiance theorem). A floor sunk in clear glass, seen from the air at
/// normal incidence, shows its radiance times the Fresnel transmittance
/// 1 − ((η − 1)/(η + 1))² and divided by η². (A slab in front would not
/// tell: entering and leaving, η² and 1/η² cancel.) Its light arrives
/// undimmed: shadow rays through clear glass are not bent or weakened.
#[test]
fn a_floor_sunk_in_glass_is_seen_through_fresnel_and_one_over_eta_squared() {
    let _watchdog = crate::watchdog::start();
    let open = floor_under("");
    for ior in [1.5f64, 2.0] {
        let sunk = floor_under(&format!(
            "box {{ min <-20, -1, -20>  max <20, 1, 20>  material {{ refract {{ ior {ior} }} }} }}"
        ));
        let r0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let want = (1.0 - r0) / (ior * ior);
        for (x, y) in [(8, 8), (7, 8), (8, 7)] {
            let ratio = sunk.get(x, y)[1] as f64 / open.get(x, y)[1] as f64;
            assert!(
                (ratio - want).abs() < 2e-3 * want,
                "ior {ior} at ({x}, {y}): {ratio} vs {want}"
            );
        }
    }
}
