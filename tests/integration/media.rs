//! Nested media end to end (the glass of water): light through glass, then
//! water, then glass is attenuated by each medium's filter to the distance
//! travelled in it, and the water's surface bends rays by Snell's law.

use crate::support::*;

/// Fresnel reflectance at normal incidence between indices a and b.
fn r0(a: f64, b: f64) -> f64 {
    ((a - b) / (a + b)).powi(2)
}

/// A wall of glass 0.5 thick, 2 units of water, another 0.5 of glass, as a
/// glass block with a cavity whose walls are glass/water interfaces (the
/// way examples/glass_of_water.rt builds it), its faces along z.
const MEDIA: &str = "
material glass { refract { ior 1.5  filter rgb(0.8, 0.9, 0.6) } }
material glass_water { refract { ior 1.5  filter rgb(0.8, 0.9, 0.6)  outside_ior 1.33  outside_filter rgb(0.5, 0.95, 0.7) } }
";
const TANK: &str = "
difference {
  box { min <-5, -5, -1.5>  max <5, 5, 1.5>  material glass }
  box { min <-4, -4, -1>  max <4, 4, 1>  material glass_water }
}
";

#[test]
fn light_through_glass_water_glass_falls_by_each_filter_to_its_length() {
    let _watchdog = crate::watchdog::start();
    // Seen straight through: a glowing wall of radiance 1 behind the tank,
    // nothing else. Each of the four faces passes 1 − R₀ (the 1/η² of the
    // way in and the η² of the way out cancel: 1.5, 1.33/1.5, 1.5/1.33,
    // 1/1.5 multiply to 1); glass filters over 0.5 + 0.5, water over 2.
    let film = render_src(&format!(
        "
camera {{ position <0, 0, 10>  look_at <0, 0, 0>  fov 2 }}
render {{ width 3  height 3  gamma linear  max_depth 8 }}
rectangle {{ bottom_left <-20, -20, -6>  top_left <-20, 20, -6>  bottom_right <20, -20, -6>  material {{ emit white }} }}
{MEDIA} {TANK}"
    ));
    let (ag, gw) = (r0(1.0, 1.5), r0(1.5, 1.33));
    let fresnel = (1.0 - ag).powi(2) * (1.0 - gw).powi(2);
    let (glass, water) = ([0.8, 0.9, 0.6], [0.5, 0.95, 0.7]);
    let p = film.get(1, 1);
    for c in 0..3 {
        let want = fresnel * glass[c] * water[c] * water[c];
        // Light reflected twice between faces and sent on adds at most
        // R₀² ≈ 0.2%.
        let got = p[c] as f64;
        assert!(
            got >= want * (1.0 - 1e-6) && got < want * 1.003,
            "channel {c}: {got} vs {want}"
        );
    }
    // The shadow it casts (straight down onto a white floor, the tank
    // turned flat): no Fresnel loss and no bending in shadow rays, only
    // the filters.
    let floor = render_src(&format!(
        "
camera {{ position <0, -7, 0>  look_at <0, -8, 0>  up <0, 0, -1>  fov 10 }}
render {{ width 3  height 3  gamma linear }}
light {{ position <0, 50, 0> }}
plane {{ normal <0, 1, 0>  offset -8  material {{ colour rgb(1, 1, 1) }} }}
{MEDIA}
group {{ {TANK}  rotate x 90 }}
"
    ));
    let p = floor.get(1, 1);
    for c in 0..3 {
        let want = glass[c] * water[c] * water[c];
        assert!(
            (p[c] as f64 - want).abs() < 1e-5,
            "shadow channel {c}: {} vs {want}",
            p[c]
        );
    }
}

#[test]
fn the_water_surface_moves_what_lies_under_it_by_snells_law() {
    let _watchdog = crate::watchdog::start();
    // Looking down at 45° onto still water (ior 1.33, surface y = 0); one
    // unit under it a glowing floor ends at x = 2.6. A column of 201
    // pixels, each its own ray (one sample at the pixel's centre): a ray
    // meeting the surface at s with incidence θᵢ reaches the floor at
    // s.x + tan θₜ (sin θᵢ = 1.33 sin θₜ), and shows the glow when that is
    // under 2.6.
    let src = "
camera { position <0, 2, 0>  look_at <2, 0, 0>  distance 1  width 0.003  height 0.2 }
render { width 3  height 201  gamma linear  max_depth 4 }
box { min <-10, -3, -10>  max <10, 0, 10>  material { refract { ior 1.33 } } }
rectangle { bottom_left <-10, -1, 10>  top_left <-10, -1, -10>  bottom_right <2.6, -1, 10>  material { emit white } }
";
    let film = render_src(src);
    let (_d, path) = scene_file(src);
    let program = raytrace::lang::load(&path).unwrap();
    let scene = raytrace::scene::build(&program).unwrap();
    let rays = scene.camera.pixel_rays(3, 201).unwrap();
    let (mut bent, mut straight, mut wrong) = (0, 0, Vec::new());
    for b in 0..201 {
        let ray = rays.ray_at(1.5, b as f64 + 0.5);
        let (o, d) = (ray.origin, ray.dir);
        let s = o + d * (-o.y / d.y);
        let across = (d.x * d.x + d.z * d.z).sqrt();
        let sin_t = across / 1.33;
        let tan_t = sin_t / (1.0 - sin_t * sin_t).sqrt();
        let lands = s.x + tan_t * d.x / across;
        let straight_lands = o.x + d.x * ((-1.0 - o.y) / d.y);
        let glows = film.get(1, b)[0] > 0.3;
        if glows != (lands < 2.6) {
            wrong.push(b);
        }
        bent += (lands < 2.6) as u32;
        straight += (straight_lands < 2.6) as u32;
    }
    assert!(wrong.is_empty(), "rows against Snell's law: {wrong:?}");
    // The test can tell: without bending, the edge would sit far away.
    assert!(
        (bent as i32 - straight as i32).abs() > 40,
        "{bent} vs {straight} glowing rows"
    );
    assert!(
        bent > 20 && bent < 180,
        "the edge is in the picture: {bent}"
    );
}

#[test]
fn a_thin_tinted_sheet_far_from_the_origin_tints_its_shadow() {
    let _watchdog = crate::watchdog::start();
    // A sheet 0.0005 thick whose filter lets no red through, 20 000 units
    // from the origin, between a floor and the light. A shadow ray must
    // meet both its faces: stepping past the first by a fixed share of the
    // coordinates (1e-7 · 20 000 = 0.002) would jump over the second, and
    // the red would get through.
    let film = render_src(
        "
camera { position <20000, 3, 0>  look_at <20000, 0, 0>  up <0, 0, -1>  fov 30 }
render { width 3  height 3  gamma linear }
light { position <20000, 50, 0> }
plane { normal <0, 1, 0>  material { colour rgb(1, 1, 1) } }
box { min <19990, 10, -10>  max <20010, 10.0005, 10>  material { refract { ior 1.5  filter rgb(0, 1, 1) } } }
",
    );
    let p = film.get(1, 1);
    assert_eq!(p[0], 0.0, "{p:?}");
    assert!(p[1] > 0.999 && p[2] > 0.999, "{p:?}");
}
