//! The Whitted recursion end to end (src/render/integrator.rs): how many
//! rays of each kind a picture needs, and what crossing into a medium does
//! to the radiance seen there, against counts and physics known by
//! construction.

use crate::support::*;
use raytrace::render::{Film, Region, RenderOptions, RenderStats, render_region};

/// The film and statistics of a scene given as text, on one thread.
fn render_stats(src: &str) -> (Film, RenderStats) {
    crate::support::render_stats(src, None, 1)
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
    // A surface with no diffuse part gathers no sky (its ambient part
    // still asks for the light, which it then does not use: a light sample
    // is a shadow ray whatever the weights; the sky's are not).
    let (_, sky) = render_stats(
        &mirror_and_ceiling("environment { colour white  intensity 0.1  samples 3 }").replace(
            "diffuse 0  ambient 0  mirror 1",
            "diffuse 0  ambient 1  mirror 1",
        ),
    );
    assert_eq!(sky.rays.shadow, 2 * pixels + 3 * pixels);
}

/// The white furnace with a weight: a convex object alone in a uniform
/// sky sees the sky in every direction about its normal, so a surface of
/// `diffuse` k_d and colour c shows exactly k_d c L_env.
#[test]
fn a_diffuse_weight_scales_the_sky_a_surface_gathers() {
    let _watchdog = crate::watchdog::start();
    for kd in [0.5, 0.25] {
        let film = render_src(&format!(
            "
camera {{ position <0, 0, 5>  look_at <0, 0, 0>  fov 10 }}
render {{ width 3  height 3  gamma linear  background black }}
environment {{ colour rgb(1, 0.5, 0.25)  intensity 0.8  samples 4 }}
sphere {{ radius 1  material {{ colour rgb(1, 1, 0.5)  diffuse {kd}  ambient 0 }} }}
"
        ));
        let want = [kd * 0.8, kd * 0.4, kd * 0.1];
        for p in &film.pixels {
            for c in 0..3 {
                assert!(
                    (p[c] as f64 - want[c]).abs() < 1e-6,
                    "kd {kd}: {p:?} vs {want:?}"
                );
            }
        }
    }
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

/// A dielectric's two rays weigh POV-Ray's way under `bailout`: the
/// reflected one F, the refracted one 1 − F. A clear slab seen at normal
/// incidence (F = 0.04 for ior 1.5) against a white background: with
/// bailout 0.05 only the straight path is cast, (1 − F)² of the background
/// (η² in and 1/η² out cancel); with 0.039 the front face's reflection
/// (weight 0.04, seeing the background behind the camera) comes back, F
/// more, while the first reflection inside (0.96 · 0.04 = 0.0384) is
/// still cut.
#[test]
fn bailout_weighs_a_dielectric_s_rays_by_fresnel() {
    let _watchdog = crate::watchdog::start();
    let f = 0.04f64;
    for (bailout, want) in [
        (0.05, (1.0 - f) * (1.0 - f)),
        (0.039, (1.0 - f) * (1.0 - f) + f),
    ] {
        let film = render_src(&format!(
            "camera {{ position <0, 0, 5>  look_at <0, 0, 0>  up <0, 1, 0>  fov 10 }}
render {{ width 1  height 1  max_depth 10  bailout {bailout}  background rgb(1, 1, 1)  gamma linear }}
ambient rgb(1, 1, 1) intensity 0
box {{ min <-5, -5, -0.5>  max <5, 5, 0.5>  material {{ refract {{ ior 1.5 }} }} }}"
        ));
        for (k, &v) in film.get(0, 0).iter().enumerate() {
            assert!(
                (v as f64 - want).abs() < 1e-6,
                "bailout {bailout}, channel {k}: {v} vs {want}"
            );
        }
    }
}

/// The project's unit icosphere (642 vertices), by absolute path.
fn icosphere() -> String {
    project_root()
        .join("examples/meshes/icosphere.ply")
        .display()
        .to_string()
}

/// Smooth shading turns the interpolated normal to the viewer's side of
/// the surface, as the geometric normal is: seen from inside, a smooth
/// sphere lit from its centre is lit everywhere (n·l ≈ 1), not black.
#[test]
fn a_smooth_mesh_seen_from_inside_is_lit_from_its_centre() {
    let _watchdog = crate::watchdog::start();
    let film = render_src(&format!(
        "
camera {{ position <0, 0, 0>  look_at <0, 0, -1>  up <0, 1, 0>  fov 60 }}
render {{ width 12  height 12  gamma linear }}
light {{ position <0, 0, 0> }}
mesh \"{}\" {{ smooth  material {{ colour white  ambient 0 }} }}
",
        icosphere()
    ));
    for (i, p) in film.pixels.iter().enumerate() {
        assert!(p[1] > 0.99 && p[1] <= 1.0 + 1e-6, "pixel {i}: {p:?}");
    }
}

/// Under a parallel light (no falloff) a flat face has one n·l: pixels
/// on one face are equal. Smooth shading varies across every face, and
/// agrees with the true sphere it approximates.
#[test]
fn smooth_shading_varies_across_faces_and_follows_the_sphere() {
    let _watchdog = crate::watchdog::start();
    let scene = |shape: &str| {
        render_src(&format!(
            "
camera {{ position <0, 0, 6>  look_at <0, 0, 0>  up <0, 1, 0>  fov 22 }}
render {{ width 80  height 80  gamma linear }}
light {{ direction <-1, -0.3, -0.2> }}
{shape}
"
        ))
    };
    let mat = "material { colour white  ambient 0 }";
    let sphere = scene(&format!("sphere {{ radius 1  {mat} }}"));
    let equal_neighbours = |f: &Film| {
        let (mut equal, mut lit) = (0, 0);
        for y in 0..f.height {
            for x in 0..f.width - 1 {
                let (a, b) = (f.get(x, y)[1], f.get(x + 1, y)[1]);
                if a > 0.05
                    && b > 0.05
                    && sphere.get(x, y)[1] > 0.05
                    && sphere.get(x + 1, y)[1] > 0.05
                {
                    lit += 1;
                    equal += (a == b) as u32;
                }
            }
        }
        assert!(lit > 1000, "{lit} lit pairs");
        equal as f64 / lit as f64
    };
    let smooth = scene(&format!("mesh \"{}\" {{ smooth  {mat} }}", icosphere()));
    let flat = scene(&format!("mesh \"{}\" {{ flat  {mat} }}", icosphere()));
    assert!(
        equal_neighbours(&flat) > 0.4,
        "flat: {}",
        equal_neighbours(&flat)
    );
    assert!(
        equal_neighbours(&smooth) < 0.05,
        "smooth: {}",
        equal_neighbours(&smooth)
    );
    // Inside the silhouette (away from its edge), the smooth mesh shows
    // the sphere's n·l to within the facets' small error.
    let mut worst = 0.0f32;
    for y in 0..80 {
        for x in 0..80 {
            let (dx, dy) = (x as f32 - 39.5, y as f32 - 39.5);
            if (dx * dx + dy * dy).sqrt() < 25.0 {
                worst = worst.max((smooth.get(x, y)[1] - sphere.get(x, y)[1]).abs());
            }
        }
    }
    assert!(worst < 0.02, "smooth mesh vs sphere: {worst}");
}

/// A sky without an image lights the scene but a `background` given in
/// `render` is what camera rays that miss see.
#[test]
fn a_given_background_hides_a_plain_sky_from_the_camera() {
    let _watchdog = crate::watchdog::start();
    let film = render_src(
        "
camera { position <0, 0, 5>  look_at <0, 0, 0>  fov 40 }
render { width 8  height 8  gamma linear  background rgb(0, 0, 1) }
environment { colour rgb(1, 0.5, 0)  intensity 0.5 }
",
    );
    for p in &film.pixels {
        assert_eq!(*p, [0.0, 0.0, 1.0]);
    }
    // Nor does a picture sky show where a background is given.
    let globe = project_root().join("examples/images/globe.png");
    let film = render_src(&format!(
        "
camera {{ position <0, 0, 5>  look_at <0, 0, 0>  fov 40 }}
render {{ width 8  height 8  gamma linear  background rgb(0, 0, 1) }}
environment {{ image \"{}\" }}
",
        globe.display()
    ));
    for p in &film.pixels {
        assert_eq!(*p, [0.0, 0.0, 1.0]);
    }
    // Without a background the misses see the sky's colour × intensity.
    let film = render_src(
        "
camera { position <0, 0, 5>  look_at <0, 0, 0>  fov 40 }
render { width 8  height 8  gamma linear }
environment { colour rgb(1, 0.5, 0)  intensity 0.5 }
",
    );
    for p in &film.pixels {
        assert_eq!(*p, [0.5, 0.25, 0.0]);
    }
}

/// An area light with its own k × k grid (`samples k`) lights a point
/// with the mean over the grid's cell centres y of
/// L (n_y·(−l)) (n·l) / |x − y|² × area: for a 2 × 2 lamp 4 above the
/// floor, facing down, each centre gives L·(A/k²)·16/r⁴. A wall hiding
/// the lamp's half x < 0 from the floor point under its middle hides
/// exactly half the grid's points: half the light.
#[test]
fn an_area_lights_own_grid_is_its_cell_centres_averaged() {
    let _watchdog = crate::watchdog::start();
    let (l, k) = (10.0f64, 4u32);
    let floor_point = |wall: &str| {
        let film = render_src(&format!(
            "
camera {{ position <0.6, 0.3, 0>  look_at <0, 0, 0>  fov 1 }}
render {{ width 3  height 3  gamma linear }}
rectangle {{ bottom_left <-1, 4, -1>  top_left <-1, 4, 1>  bottom_right <1, 4, -1>
  material {{ emit white  intensity {l} }}  samples {k} }}
plane {{ normal <0, 1, 0>  material {{ colour white  ambient 0 }} }}
{wall}
"
        ));
        film.get(1, 1)[1] as f64
    };
    let centre = |i: u32| -1.0 + 2.0 * (i as f64 + 0.5) / k as f64;
    let mut want = 0.0;
    for i in 0..k {
        for j in 0..k {
            let r2 = centre(i).powi(2) + 16.0 + centre(j).powi(2);
            want += l * (4.0 / (k * k) as f64) * 16.0 / (r2 * r2);
        }
    }
    let open = floor_point("");
    assert!((open - want).abs() < 1e-5 * want, "{open} vs {want}");
    let half = floor_point("box { min <-5, 1, -5>  max <0, 3, 5> }");
    assert!((half / open - 0.5).abs() < 1e-5, "{half} of {open}");
}

/// A reflection inside coloured glass travels in the glass, and Beer's
/// law dims it: from inside a slab of filter f per unit (a floor sunk 1
/// below its top face, lit from above through that unit of glass, so its
/// radiance is f), looking straight up at the top face, the camera sees
/// only the Fresnel reflection R₀ = 0.04 of the floor, f¹ away: R₀ f².
/// (The light refracted out goes to a black sky.)
#[test]
fn a_reflection_inside_coloured_glass_is_dimmed_along_its_way() {
    let _watchdog = crate::watchdog::start();
    let film = render_src(
        "
camera { position <0, 0.5, 0>  look_at <0, 1, 0>  up <0, 0, -1>  fov 2 }
render { width 3  height 3  gamma linear  background black }
light { position <0, 50, 0> }
plane { normal <0, 1, 0>  material { colour white  ambient 0 } }
box { min <-20, -1, -20>  max <20, 1, 20>  material { refract { ior 1.5  filter rgb(0.5, 0.8, 1) } } }
",
    );
    let r0 = 0.04;
    let p = film.get(1, 1);
    for (c, f) in [0.5f64, 0.8, 1.0].into_iter().enumerate() {
        let want = r0 * f * f;
        assert!(
            (p[c] as f64 - want).abs() < 1e-4 * want,
            "channel {c}: {p:?} vs {want}"
        );
    }
}

/// Refracted rays count toward `max_depth` as reflected ones do: seeing a
/// floor through a glass slab takes two (in at the top, out at the
/// bottom), so with `max_depth 1` the floor is not seen through it and
/// with 2 it is, dimmed by Fresnel at both faces, (1 − R₀)².
#[test]
fn seeing_through_glass_takes_one_bounce_per_face() {
    let _watchdog = crate::watchdog::start();
    let through = |depth: u32| {
        render_src(&format!(
            "
camera {{ position <0, 3, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 2 }}
render {{ width 3  height 3  gamma linear  background black  max_depth {depth} }}
light {{ position <0, 50, 0> }}
plane {{ normal <0, 1, 0>  material {{ colour white  ambient 0 }} }}
box {{ min <-20, 1, -20>  max <20, 2, 20>  material {{ refract {{ ior 1.5 }} }} }}
"
        ))
        .get(1, 1)[1] as f64
    };
    assert_eq!(through(1), 0.0);
    let want = (1.0f64 - 0.04).powi(2);
    assert!((through(2) - want).abs() < 1e-4, "{} vs {want}", through(2));
}

/// A shadow ray through glass goes on to the light, and only to it: an
/// opaque slab between the glass and the light still shadows the floor,
/// and one beyond the light does not.
#[test]
fn a_shadow_ray_through_glass_is_blocked_by_what_lies_before_the_light_only() {
    let _watchdog = crate::watchdog::start();
    let glass = "box { min <-20, 20, -20>  max <20, 21, 20>  material { refract { ior 1.5  filter rgb(0.5, 0.5, 0.5) } } }";
    let lit = floor_under(glass).get(8, 8)[1] as f64;
    assert!((lit - 0.5).abs() < 1e-4, "{lit}");
    let before = floor_under(&format!(
        "{glass}\nbox {{ min <-20, 40, -20>  max <20, 41, 20> }}"
    ));
    assert_eq!(before.get(8, 8), [0.0, 0.0, 0.0]);
    let beyond = floor_under(&format!(
        "{glass}\nbox {{ min <-20, 60, -20>  max <20, 61, 20> }}"
    ));
    assert!((beyond.get(8, 8)[1] as f64 - lit).abs() < 1e-6);
}

/// A region with no pixel is no picture, whichever side is empty: none
/// across (x past the right edge, or zero width) or none down.
#[test]
fn a_region_without_pixels_renders_nothing() {
    let _watchdog = crate::watchdog::start();
    let mut scene = build_src(&mirror_and_ceiling(""));
    let world = raytrace::accel::World::build(std::mem::take(&mut scene.objects));
    let opts = RenderOptions {
        progress: None,
        cancel: None,
    };
    let region = |x, y, width, height| Region {
        x,
        y,
        width,
        height,
    };
    for r in [
        region(6, 0, 2, 4),
        region(2, 0, 0, 4),
        region(0, 4, 6, 2),
        region(0, 1, 6, 0),
    ] {
        assert!(render_region(&scene, &world, &opts, r).is_none(), "{r:?}");
    }
    let one = render_region(&scene, &world, &opts, region(5, 3, 9, 9))
        .unwrap()
        .0;
    assert_eq!((one.width, one.height), (1, 1));
}

/// The progress callback counts finished rows: once each, up to the
/// region's height (the bar reaches its end).
#[test]
fn progress_counts_every_row_once() {
    let _watchdog = crate::watchdog::start();
    let mut scene = build_src(&mirror_and_ceiling(""));
    let world = raytrace::accel::World::build(std::mem::take(&mut scene.objects));
    let seen = std::sync::Mutex::new(Vec::new());
    let progress = |n: u64| seen.lock().unwrap().push(n);
    let opts = RenderOptions {
        progress: Some(&progress),
        cancel: None,
    };
    let all = Region {
        x: 0,
        y: 0,
        width: 6,
        height: 4,
    };
    render_region(&scene, &world, &opts, all).unwrap();
    let mut seen = seen.into_inner().unwrap();
    seen.sort();
    assert_eq!(seen, [1, 2, 3, 4]);
}

/// A sphere light emits outwards: "a sphere's inside never shows", so a
/// floor inside a big emitting sphere is not lit by it. The same sphere in
/// CSG (a union with a box far outside it) is a clipped light, sampled
/// over its whole surface from both sides; a sample there counts only
/// where the ray to it meets an emitting surface from its front, and from
/// inside every sample is met from behind: the floor stays unlit as with
/// the lone sphere (a light on the other side of the surface than the
/// shaded point must not reach it).
#[test]
fn a_clipped_sphere_light_does_not_light_its_inside() {
    let _watchdog = crate::watchdog::start();
    let floor_inside = |lamp: &str| {
        render_src(&format!(
            "
material lamp {{ emit white  intensity 10 }}
camera {{ position <0.3, 0.5, 0>  look_at <0, 0, 0>  fov 2 }}
render {{ width 3  height 3  gamma linear }}
plane {{ normal <0, 1, 0>  material {{ colour rgb(1, 1, 1) }} }}
{lamp}
"
        ))
        .get(1, 1)
    };
    let sphere = "sphere { centre <0, 2, 0>  radius 5  material lamp  samples 4 }";
    assert_eq!(floor_inside(sphere), [0.0, 0.0, 0.0]);
    let clipped = format!("union {{ {sphere}  box {{ min <20, 0, 20>  max <21, 1, 21> }} }}");
    assert_eq!(floor_inside(&clipped), [0.0, 0.0, 0.0]);
    // Outside it, the same sphere in the same union lights the floor.
    let above = "sphere { centre <0, 9, 0>  radius 5  material lamp  samples 4 }";
    let lit = format!("union {{ {above}  box {{ min <20, 0, 20>  max <21, 1, 21> }} }}");
    assert!(floor_inside(&lit)[0] > 0.5, "{:?}", floor_inside(&lit));
}
