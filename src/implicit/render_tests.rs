//! Render-level tests of implicit surfaces, with scenes built in code.

use super::scenes::{self, TorusKind};
use super::tests::CONVENTIONS;
use super::*;
use crate::accel::World;
use crate::geometry::{DVec2, Ray, Transform};
use crate::render::{RenderOptions, render};
use crate::scene::{Camera, Projection, Scene};
use crate::shapes::{Hit, Shape, Sphere, Torus, Transformed, testing};

fn compile(s: &str) -> Equation {
    Equation::compile(s, &|_| None).unwrap_or_else(|e| panic!("{s}: {e:?}"))
}

fn draw(mut scene: Scene) -> (crate::render::Film, crate::render::RenderStats) {
    let world = World::build(std::mem::take(&mut scene.objects));
    render(
        &scene,
        &world,
        &RenderOptions {
            progress: None,
            cancel: None,
        },
    )
    .expect("the camera has a frame")
}

/// The power cube's solid contains the unit ball (Σ|p_i|^N ≤ Σ p_i² ≤ 1
/// there) and lies inside the cube [−1, 1]³. So a camera ray that enters
/// the ball must hit the surface, between entering the cube and entering
/// the ball; a ray that misses the cube must miss the surface. With the
/// normal facing the ray, that catches both missed roots (holes) and wrong
/// roots (speckle), for every pixel.
#[test]
fn power_cube_is_clean_to_order_40() {
    let _watchdog = crate::watchdog::start();
    let size = 160;
    let ball = Sphere::new(DVec3::ZERO, 1.0, 0);
    let cube = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
    for n in (4..=40).step_by(2) {
        let scene = scenes::power_cube(n, size);
        let shape = &scene.objects[0];
        let rays = scene.camera.pixel_rays(size, size).unwrap();
        let mut hits = 0;
        for b in 0..size {
            for a in 0..size {
                let ray = rays.ray(a, b);
                let hit = shape.intersect(&ray, 0.0, f64::INFINITY);
                let enter_cube = cube.clip(&ray, 0.0, f64::INFINITY).map(|(t, _)| t);
                let enter_ball = ball.intersect(&ray, 0.0, f64::INFINITY).map(|h| h.t);
                match (hit, enter_cube, enter_ball) {
                    (None, _, Some(_)) => panic!("N={n}: hole at pixel ({a}, {b})"),
                    (Some(h), None, _) => panic!("N={n}: stray hit at ({a}, {b}): {h:?}"),
                    (Some(h), Some(tc), tb) => {
                        hits += 1;
                        assert!(h.t >= tc - 1e-9, "N={n} ({a},{b}): hit before the cube");
                        if let Some(tb) = tb {
                            assert!(h.t <= tb + 1e-9, "N={n} ({a},{b}): hit behind the ball");
                        }
                        let p = ray.at(h.t);
                        let pn: f64 = (0..3).map(|i| p[i].powi(n as i32)).sum();
                        assert!((pn - 1.0).abs() < 1e-6, "N={n}: point off the surface");
                        assert!(
                            h.normal.is_finite() && h.normal.dot(ray.dir) < 0.0,
                            "N={n}: normal"
                        );
                    }
                    (None, _, None) => {}
                }
            }
        }
        assert!(
            hits > (size * size / 10) as usize,
            "N={n}: only {hits} hits"
        );
    }
}

fn look_at_origin(objects: Vec<Box<dyn Shape>>, position: DVec3) -> Scene {
    let mut s = scenes::power_cube(2, 64);
    s.camera = Camera {
        position,
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Fov(50.0),
        lens: None,
    };
    s.objects = objects;
    s
}

#[test]
fn every_conventions_equation_renders_a_picture() {
    let _watchdog = crate::watchdog::start();
    let consts = |n: &str| match n {
        "R" => Some(2.0),
        "r" => Some(0.5),
        _ => None,
    };
    for (text, _) in CONVENTIONS {
        let eq = Equation::compile(text, &consts).unwrap();
        let shape = ImplicitSurface::new(eq, None, 1);
        let (film, _) = draw(look_at_origin(
            vec![Box::new(shape)],
            DVec3::new(5.0, 4.0, 9.0),
        ));
        let bg = [0.05f32, 0.05, 0.1];
        let lit = film.pixels.iter().filter(|p| **p != bg).count();
        assert!(
            lit > film.pixels.len() / 50,
            "{text}: only {lit} pixels drawn"
        );
        assert!(
            film.pixels.iter().flatten().all(|v| v.is_finite()),
            "{text}: NaN pixel"
        );
    }
}

/// Same hits (within `tol` in t) and same unit normals over random rays.
fn agree(a: &dyn Shape, b: &dyn Shape, rays: &[Ray], tol: f64) {
    let mut hits = 0;
    for r in rays {
        let ha = a.intersect(r, 1e-9, f64::INFINITY);
        let hb = b.intersect(r, 1e-9, f64::INFINITY);
        match (ha, hb) {
            (None, None) => {}
            (Some(x), Some(y)) => {
                hits += 1;
                assert!((x.t - y.t).abs() < tol, "t {} vs {} on {r:?}", x.t, y.t);
                let (nx, ny) = (x.normal.normalize(), y.normal.normalize());
                assert!((nx - ny).length() < 1e-6, "normal {nx} vs {ny} on {r:?}");
            }
            (x, y) => panic!("{x:?} vs {y:?} on {r:?}"),
        }
        let (mut xa, mut xb) = (Vec::new(), Vec::new());
        a.crossings(r, &mut xa);
        b.crossings(r, &mut xb);
        assert_eq!(xa.len(), xb.len(), "crossings on {r:?}");
        // Each crossing at the same t, with the same outward normal.
        for (x, y) in xa.iter().zip(&xb) {
            assert!(
                (x.t - y.t).abs() < tol,
                "crossing t {} vs {} on {r:?}",
                x.t,
                y.t
            );
            let (nx, ny) = (x.normal.normalize(), y.normal.normalize());
            assert!(
                (nx - ny).length() < 1e-6,
                "crossing normal {nx} vs {ny} on {r:?}"
            );
        }
    }
    assert!(hits > rays.len() / 10, "too few hits to compare: {hits}");
}

#[test]
fn implicit_sphere_matches_the_primitive() {
    let _watchdog = crate::watchdog::start();
    let sphere = Sphere::new(DVec3::ZERO, 1.0, 0);
    let rays = testing::rays_towards(DVec3::ZERO, 1.5, 3000, 11);
    for text in ["x^2 + y^2 + z^2 - 1", "(x^2 + y^2 + z^2)_2 = 1"] {
        let auto = ImplicitSurface::new(compile(text), None, 0);
        assert_eq!(auto.bound_source(), BoundSource::Automatic);
        agree(&auto, &sphere, &rays, 1e-9);
        testing::check_consistency(&auto, &rays);
    }
}

#[test]
fn four_tori_agree() {
    let _watchdog = crate::watchdog::start();
    // The nested-root and textbook forms have their ring in the x-y plane
    // (about z); conventions.md's expanded form has it in the x-z plane
    // (about y), like the primitive.
    let about_z: Box<dyn Shape> = Box::new(Transformed::new(
        Box::new(Torus::new(1.5, 0.5, 0)),
        Transform::rotate(DVec3::X, 90.0).unwrap(),
    ));
    let about_y: Box<dyn Shape> = Box::new(Torus::new(1.5, 0.5, 0));
    let routes = [
        (
            "(((x^2 + y^2)_2 - 1.5)^2 + z^2)_2 - 0.5",
            &about_z,
            DVec3::new(2.0, 2.0, 0.5),
        ),
        (
            "x^4 + 2x^2*y^2 + 2x^2*z^2 - 2*(1.5^2 + 0.5^2)*x^2 + y^4 + 2y^2*z^2 + 2*(1.5^2 - 0.5^2)*y^2 + z^4 - 2*(1.5^2 + 0.5^2)*z^2 + (1.5^2 - 0.5^2)^2",
            &about_y,
            DVec3::new(2.0, 0.5, 2.0),
        ),
        (
            "(x^2+y^2+z^2+1.5^2-0.5^2)^2 - 4*1.5^2(x^2+y^2)",
            &about_z,
            DVec3::new(2.0, 2.0, 0.5),
        ),
    ];
    let rays = testing::rays_towards(DVec3::ZERO, 2.0, 3000, 5);
    for (text, native, half) in routes {
        let auto = ImplicitSurface::new(compile(text), None, 0);
        agree(&auto, native.as_ref(), &rays, 1e-8);
        testing::check_consistency(&auto, &rays);
        let given = ImplicitSurface::new(compile(text), Some(Aabb::new(-half, half)), 0);
        agree(&given, native.as_ref(), &rays, 1e-8);
        // And with no box (an infinite given one): the quartic in the
        // ray's own t, solved to the precision asked for unbounded roots.
        let open = ImplicitSurface::new(compile(text), Some(Aabb::INFINITE), 0);
        agree(&open, native.as_ref(), &rays, 1e-8);
    }
    // And the same picture: the benchmark scene both ways.
    let (a, _) = draw(scenes::torus(TorusKind::Implicit, 120));
    let (b, _) = draw(scenes::torus(TorusKind::Native, 120));
    let differ = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| (x - y).abs() > 1e-3))
        .count();
    assert!(differ <= 2, "{differ} pixels differ");
}

#[test]
fn unbounded_surfaces_say_so_and_render() {
    let _watchdog = crate::watchdog::start();
    let plane = ImplicitSurface::new(compile("x"), None, 0);
    assert_eq!(plane.bound_source(), BoundSource::Unbounded);
    assert!(plane.bound_note().is_some());
    let r = Ray::new(DVec3::new(3.0, 0.2, 0.1), DVec3::new(-2.0, 0.0, 0.0));
    let h = plane.intersect(&r, 0.0, f64::INFINITY).unwrap();
    assert!((h.t - 1.5).abs() < 1e-12);
    let bounded = ImplicitSurface::new(compile("x^2 + y^2 + z^2 - 1"), None, 0);
    assert!(bounded.bound_note().is_none());
}

#[test]
fn zero_gradient_points_get_a_normal() {
    let _watchdog = crate::watchdog::start();
    // The cone x² + y² − z² has a zero gradient at its apex.
    let cone = ImplicitSurface::new(compile("x^2 + y^2 - z^2"), None, 0);
    let r = Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0));
    let h = cone.intersect(&r, 0.0, f64::INFINITY).unwrap();
    assert!(h.t.is_finite() && (h.t - 5.0).abs() < 1e-6);
    assert!(h.normal.is_finite() && h.normal.length() > 0.0);
    // There the normal is the reversed ray direction, as the module says.
    assert_eq!(h.normal, -r.dir);
    // The heart renders without a NaN pixel.
    let (film, _) = draw(scenes::sextic(64));
    assert!(film.pixels.iter().flatten().all(|v| v.is_finite()));
}

/// Timings of the benchmark scenes (release build):
/// `cargo test --release --lib implicit::render_tests::timing -- --ignored --nocapture`
#[test]
#[ignore]
fn timing() {
    let _watchdog = crate::watchdog::start();
    let size = 1000;
    let run = |name: &str, scene: Scene| {
        let (_, stats) = draw(scene);
        let rays = stats.rays.total();
        eprintln!(
            "{name:<24} {:>7.3} s  {:>9} rays  {:>6.2} M rays/s",
            stats.seconds,
            rays,
            rays as f64 / stats.seconds / 1e6
        );
    };
    run("torus (implicit)", scenes::torus(TorusKind::Implicit, size));
    run(
        "torus (implicit, auto)",
        scenes::torus(TorusKind::ImplicitAutoBound, size),
    );
    run("torus (native)", scenes::torus(TorusKind::Native, size));
    run("sextic", scenes::sextic(size));
    for n in [4, 6, 8, 10, 12, 14, 16, 20, 30, 40] {
        run(
            &format!("power cube N={n} (300px)"),
            scenes::power_cube(n, 300),
        );
    }
}

/// One scene for profiling: `RT_SCENE=torus|sextic|native`.
#[test]
#[ignore]
fn profile_one() {
    let _watchdog = crate::watchdog::start();
    let scene = match std::env::var("RT_SCENE").as_deref() {
        Ok("sextic") => scenes::sextic(1000),
        Ok("native") => scenes::torus(TorusKind::Native, 1000),
        Ok("floor") => {
            let mut s = scenes::torus(TorusKind::Native, 1000);
            s.objects.truncate(1);
            s
        }
        _ => scenes::torus(TorusKind::Implicit, 1000),
    };
    let (_, stats) = draw(scene);
    eprintln!("{:.3} s, {} rays", stats.seconds, stats.rays.total());
}

/// The automatic box clips nothing: over random rays, the surface with it
/// is hit exactly where the surface in a huge given box is.
#[test]
fn automatic_boxes_clip_nothing() {
    let _watchdog = crate::watchdog::start();
    // Wide, but not absurdly: a box 50 times the surface's size makes the
    // coefficients over its chord lose the digits a singular point needs.
    let huge = Aabb::new(DVec3::splat(-6.0), DVec3::splat(6.0));
    let consts = |n: &str| match n {
        "R" => Some(2.0),
        "r" => Some(0.5),
        _ => None,
    };
    let mut checked = 0;
    for (text, _) in CONVENTIONS {
        let auto = ImplicitSurface::new(Equation::compile(text, &consts).unwrap(), None, 0);
        if auto.bound_source() != BoundSource::Automatic {
            continue;
        }
        checked += 1;
        let wide = ImplicitSurface::new(Equation::compile(text, &consts).unwrap(), Some(huge), 0);
        let rays = testing::rays_towards(DVec3::ZERO, 2.5, 1500, 17);
        for r in &rays {
            let a = auto.intersect(r, 1e-9, f64::INFINITY).map(|h| h.t);
            let b = wide.intersect(r, 1e-9, f64::INFINITY).map(|h| h.t);
            match (a, b) {
                (Some(x), Some(y)) => assert!((x - y).abs() < 1e-6, "{text}: {x} vs {y}"),
                (None, None) => {}
                _ => panic!("{text}: {a:?} vs {b:?} on {r:?}"),
            }
        }
    }
    assert!(checked >= 6, "only {checked} bounded equations");
}

/// The unit sphere's equation with no box at all (an infinite given box):
/// the unbounded route (the ray's own t over the Cauchy bound, the far
/// side read off the equation beyond the last root) finds the primitive's
/// hits and crossings, in every window.
#[test]
fn unbounded_sphere_matches_the_primitive() {
    let _watchdog = crate::watchdog::start();
    let sphere = Sphere::new(DVec3::ZERO, 1.0, 0);
    let rays = testing::rays_towards(DVec3::ZERO, 1.5, 1500, 23);
    let mut rnd = testing::numbers(47);
    let inside: Vec<Ray> = (0..500)
        .map(|_| {
            let o = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X) * (0.8 + 0.19 * rnd());
            let d = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::Y);
            Ray::new(o, d)
        })
        .collect();
    for text in ["x^2 + y^2 + z^2 - 1", "(x^2 + y^2 + z^2)_2 = 1"] {
        let open = ImplicitSurface::new(compile(text), Some(Aabb::INFINITE), 0);
        assert!(!open.bounds().is_finite());
        agree(&open, &sphere, &rays, 1e-9);
        testing::check_consistency(&open, &rays);
        testing::check_alternation(&open, &rays);
        assert!(testing::check_occludes_agrees(&open, &rays) > 100);
        // And from inside (a refracted ray): the far side lies beyond the
        // largest |c_k / c_n| of the ray's quadratic when the near root is
        // just behind the origin, so only the Cauchy bound's 1 + max
        // holds it.
        agree(&open, &sphere, &inside, 1e-9);
    }
    // A sphere of radius 6 whose near side is 4 or more along the rays:
    // what lies before the first root is read at a point before it, not
    // past it (past it, up to twice as far, is inside this sphere).
    let big = Sphere::new(DVec3::new(0.0, 0.0, 15.0), 6.0, 0);
    let open = ImplicitSurface::new(
        compile("x^2 + y^2 + (z - 15)^2 - 36"),
        Some(Aabb::INFINITE),
        0,
    );
    let rays = testing::rays_towards(DVec3::new(0.0, 0.0, 15.0), 8.0, 1000, 53);
    agree(&open, &big, &rays, 1e-8);
    testing::check_alternation(&open, &rays);
}

/// Hits lie on the surface: the box of ±`p_error` about a hit's point
/// reaches the unit sphere (along the normal, as the ray offset reads it),
/// and that bound is rounding-sized, not a cap; the normal is the unit
/// sphere's, the normalised gradient p. With an automatic box, a given
/// one, and none; and in a box, for rays from 10⁵ away too, where the
/// rounding of `ray.at(t)` (about 10⁻¹¹) is most of the point's error.
#[test]
fn sphere_hits_are_on_the_surface_within_their_error_bound() {
    let _watchdog = crate::watchdog::start();
    let near = testing::rays_towards(DVec3::ZERO, 1.5, 1500, 29);
    let far: Vec<Ray> = near
        .iter()
        .map(|r| Ray::new(r.origin - 1e5 * r.dir, r.dir))
        .collect();
    let cases = [
        (None, &near),
        (
            Some(Aabb::new(DVec3::splat(-1.5), DVec3::splat(1.5))),
            &near,
        ),
        (Some(Aabb::INFINITE), &near),
        (None, &far),
        (Some(Aabb::new(DVec3::splat(-1.5), DVec3::splat(1.5))), &far),
    ];
    for (bounded_by, rays) in cases {
        let s = ImplicitSurface::new(compile("x^2 + y^2 + z^2 - 1"), bounded_by, 0);
        let mut hits = 0;
        for r in rays {
            let mut xs = Vec::new();
            s.crossings(r, &mut xs);
            xs.extend(s.intersect(r, 1e-9, f64::INFINITY));
            for h in xs {
                hits += 1;
                // The box ±p_error about the point reaches the surface:
                // its reach along the normal (what the ray offset uses)
                // covers the point's distance from the sphere.
                let on = h.point.normalize();
                let off = (h.point.length() - 1.0).abs();
                let reach = on.abs().dot(h.p_error);
                assert!(
                    off <= reach,
                    "{bounded_by:?}: {:?} off by {off} > {reach}",
                    h.point,
                );
                assert!(
                    h.p_error.max_element() < 1e-9,
                    "{bounded_by:?}: p_error {}",
                    h.p_error
                );
                assert!((h.point - r.at(h.t)).length() < 1e-12);
                // Crossings turn the normal outward, the nearest hit
                // keeps it: either way ±p.
                let outward = if h.normal.dot(on) > 0.0 { 1.0 } else { -1.0 };
                assert!(
                    (h.normal.normalize() - outward * on).length() < 1e-9,
                    "normal {} at {on}",
                    h.normal
                );
            }
        }
        assert!(hits > 1000, "{bounded_by:?}: {hits} hits");
    }
}

/// The implicit cylinder x² + z² = 1 (radius 1 about the y axis), given
/// the box from `lo` to `hi`.
fn cylinder_in(lo: DVec3, hi: DVec3) -> ImplicitSurface {
    ImplicitSurface::new(compile("x^2 + z^2 - 1"), Some(Aabb::new(lo, hi)), 0)
}

/// An implicit cylinder whose given box cuts it (y from −1 to 1): alone
/// the open tube (the box only clips it), in CSG (`solid_in_box`) the
/// capped cylinder, its box faces crossings where they cut the solid.
/// Both against the primitive cylinder, open and capped.
#[test]
fn cylinder_cut_by_its_box_is_the_open_or_capped_primitive() {
    let _watchdog = crate::watchdog::start();
    let cut = || cylinder_in(DVec3::new(-2.0, -1.0, -2.0), DVec3::new(2.0, 1.0, 2.0));
    let tube = cut();
    let solid = cut().solid_in_box();
    let open = crate::shapes::Cone::new(DVec3::ZERO, 1.0, 1.0, 2.0, 0, None);
    let capped = crate::shapes::Cone::new(DVec3::ZERO, 1.0, 1.0, 2.0, 0, Some([0, 0]));
    let rays = testing::rays_towards(DVec3::ZERO, 1.3, 2000, 31);
    let mut caps = 0;
    for r in &rays {
        for (mine, twin) in [
            (&tube as &dyn Shape, &open as &dyn Shape),
            (&solid, &capped),
        ] {
            let a = mine.intersect(r, 1e-9, f64::INFINITY);
            let b = twin.intersect(r, 1e-9, f64::INFINITY);
            match (a, b) {
                (None, None) => {}
                (Some(x), Some(y)) => {
                    assert!((x.t - y.t).abs() < 1e-9, "t {} vs {} on {r:?}", x.t, y.t);
                    let (nx, ny) = (x.normal.normalize(), y.normal.normalize());
                    assert!((nx - ny).length() < 1e-6, "normal {nx} vs {ny} on {r:?}");
                    assert!((x.point - y.point).length() < 1e-9);
                    assert!(x.point.abs().cmple(DVec3::new(2.0, 1.0, 2.0) + 1e-9).all());
                }
                (x, y) => panic!("{x:?} vs {y:?} on {r:?}"),
            }
            assert_eq!(
                mine.occludes(r, 1e-9, f64::INFINITY),
                twin.occludes(r, 1e-9, f64::INFINITY)
            );
        }
        let (mut xa, mut xb) = (Vec::new(), Vec::new());
        solid.crossings(r, &mut xa);
        capped.crossings(r, &mut xb);
        assert_eq!(xa.len(), xb.len(), "crossings {xa:?} vs {xb:?} on {r:?}");
        for (x, y) in xa.iter().zip(&xb) {
            assert!(
                (x.t - y.t).abs() < 1e-9,
                "crossing t {} vs {} on {r:?}",
                x.t,
                y.t
            );
            let (nx, ny) = (x.normal.normalize(), y.normal.normalize());
            assert!(
                (nx - ny).length() < 1e-6,
                "crossing normal {nx} vs {ny} on {r:?}"
            );
            assert!(x.p_error.max_element() < 1e-9);
            caps += (nx.y.abs() == 1.0) as usize;
        }
    }
    assert!(caps > 200, "only {caps} cap crossings");
    testing::check_alternation(&solid, &rays);
    assert!(testing::check_occludes_agrees(&solid, &rays) > 200);
    // Inside: the solid cylinder within the box, nothing outside the box.
    let mut rnd = testing::numbers(37);
    for _ in 0..2000 {
        let p = DVec3::new(rnd(), rnd(), rnd()) * 2.5;
        let rho = (p.x * p.x + p.z * p.z).sqrt();
        if (rho - 1.0).abs() < 1e-6 || (p.y.abs() - 1.0).abs() < 1e-6 {
            continue;
        }
        let want = rho < 1.0 && p.y.abs() < 1.0;
        assert_eq!(solid.encloses(p), want, "{p}");
    }
}

/// A written branch with no real point: √(x² + y² + z²) + 1 is never 0,
/// though its square's zero set (the unit sphere) is met by most rays.
/// No hit, no crossing, bounded or not.
#[test]
fn a_branch_with_no_point_is_never_hit() {
    let _watchdog = crate::watchdog::start();
    let rays = testing::rays_towards(DVec3::ZERO, 1.0, 300, 41);
    for bounded_by in [
        Some(Aabb::new(DVec3::splat(-2.0), DVec3::splat(2.0))),
        Some(Aabb::INFINITE),
    ] {
        let s = ImplicitSurface::new(compile("(x^2 + y^2 + z^2)_2 + 1"), bounded_by, 0);
        for r in &rays {
            assert!(s.intersect(r, 0.0, f64::INFINITY).is_none(), "{r:?}");
            assert!(!s.occludes(r, 0.0, f64::INFINITY), "{r:?}");
            let mut xs = Vec::new();
            s.crossings(r, &mut xs);
            assert!(xs.is_empty(), "{xs:?}");
        }
    }
}

/// The window is open, t_min < t < t_max, as for every shape: a ray that
/// starts exactly on the surface (t_min = 0, as a secondary ray without
/// its offset) does not meet it again at t = 0, and a hit exactly at
/// t_max (a shadow ray ending on the surface) is not in the window. Here
/// the roots and box faces fall exactly on the window's ends: the unit
/// sphere from (0, 0, 1) straight down (roots t = 0 and 2, s = −1 and 1/3
/// on the chord through the box [−2, 2]³, all exact), and the solid
/// cylinder of `cylinder_cut_by_its_box_is_the_open_or_capped_primitive`
/// from the centre of its top cap (box face at t = 0, bottom at t = 2),
/// against the capped primitive.
#[test]
fn hits_on_the_window_ends_are_outside_it() {
    let _watchdog = crate::watchdog::start();
    let down = DVec3::new(0.0, 0.0, -1.0);
    for bounded_by in [
        Some(Aabb::new(DVec3::splat(-2.0), DVec3::splat(2.0))),
        Some(Aabb::INFINITE),
    ] {
        let s = ImplicitSurface::new(compile("x^2 + y^2 + z^2 - 1"), bounded_by, 0);
        let on = Ray::new(DVec3::new(0.0, 0.0, 1.0), down);
        let h = s.intersect(&on, 0.0, f64::INFINITY).expect("the far side");
        assert!((h.t - 2.0).abs() < 1e-12, "{bounded_by:?}: {}", h.t);
        let above = Ray::new(DVec3::new(0.0, 0.0, 3.0), down);
        assert!(s.intersect(&above, 0.0, 2.0).is_none(), "{bounded_by:?}");
        assert!(!s.occludes(&above, 0.0, 2.0), "{bounded_by:?}");
        let h = s.intersect(&above, 0.0, 2.5).expect("the near side");
        assert!((h.t - 2.0).abs() < 1e-12, "{bounded_by:?}: {}", h.t);
    }
    let solid = cylinder_in(DVec3::new(-2.0, -1.0, -2.0), DVec3::new(2.0, 1.0, 2.0)).solid_in_box();
    let capped = crate::shapes::Cone::new(DVec3::ZERO, 1.0, 1.0, 2.0, 0, Some([0, 0]));
    let y_down = DVec3::new(0.0, -1.0, 0.0);
    for shape in [&solid as &dyn Shape, &capped] {
        let on = Ray::new(DVec3::new(0.0, 1.0, 0.0), y_down);
        let h = shape
            .intersect(&on, 0.0, f64::INFINITY)
            .expect("the bottom");
        assert!((h.t - 2.0).abs() < 1e-12, "{}", h.t);
        let above = Ray::new(DVec3::new(0.0, 3.0, 0.0), y_down);
        assert!(shape.intersect(&above, 0.0, 2.0).is_none());
        assert!(!shape.occludes(&above, 0.0, 2.0));
    }
}

/// An unbounded surface is solved for the distance along the ray, so its
/// window [t_min, t_max] is scaled by the direction's length: with
/// directions of length 1, 4 and 1/4 (exact in binary), the unit sphere's
/// near side 2 and 20 away is found by a window around it, not by one
/// ending on it, and its crossings are both sides, at t = distance/|dir|.
#[test]
fn an_unbounded_surfaces_window_is_the_rays_whatever_its_length() {
    let _watchdog = crate::watchdog::start();
    let s = ImplicitSurface::new(compile("x^2 + y^2 + z^2 - 1"), Some(Aabb::INFINITE), 0);
    for len in [1.0, 4.0, 0.25] {
        for d in [2.0, 20.0] {
            let r = Ray::new(DVec3::new(0.0, 0.0, d + 1.0), DVec3::new(0.0, 0.0, -len));
            let at = |t: f64| (t * len - d).abs() < 1e-12 * d;
            assert!(
                s.intersect(&r, 0.0, d / len).is_none(),
                "|dir| {len}, {d} away"
            );
            assert!(!s.occludes(&r, 0.0, d / len), "|dir| {len}, {d} away");
            let h = s
                .intersect(&r, (d - 0.5) / len, (d + 0.5) / len)
                .unwrap_or_else(|| panic!("|dir| {len}, {d} away: no hit"));
            assert!(at(h.t), "|dir| {len}, {d} away: t = {}", h.t);
            let mut xs = Vec::new();
            s.crossings(&r, &mut xs);
            let ts: Vec<f64> = xs.iter().map(|h| h.t * len).collect();
            assert!(
                ts.len() == 2
                    && (ts[0] - d).abs() < 1e-12 * d
                    && (ts[1] - d - 2.0).abs() < 1e-12 * d,
                "|dir| {len}, {d} away: {ts:?}"
            );
        }
    }
}

/// The same solid cylinder in a box off-centre on every axis (y from −1
/// to 0.5, the side walls at unequal distances): the faces where the box
/// cuts it are found by the wall the point lies on, not by symmetry, and
/// the crossings and nearest hits are the capped primitive's.
#[test]
fn cylinder_cut_by_an_off_centre_box_is_the_capped_primitive() {
    let _watchdog = crate::watchdog::start();
    let solid = cylinder_in(DVec3::new(-2.0, -1.0, -3.0), DVec3::new(2.5, 0.5, 1.5)).solid_in_box();
    let capped =
        crate::shapes::Cone::new(DVec3::new(0.0, -0.25, 0.0), 1.0, 1.0, 1.5, 0, Some([0, 0]));
    let rays = testing::rays_towards(DVec3::new(0.0, -0.25, 0.0), 1.3, 2000, 43);
    // A solid, as its twin: CSG may use it.
    assert!(solid.is_solid() && capped.is_solid());
    agree(&solid, &capped, &rays, 1e-9);
    testing::check_alternation(&solid, &rays);
}

/// A singular point's hits lie within their error bound too: a line
/// through the cone x² + y² − z²'s apex meets it in a double root there,
/// which the solver finds only to about the square root of the rounding
/// (10⁻⁸ of the polynomial's scale), and where the gradient vanishes.
/// Lines through the apex from 0.15 to 150 away, in boxes of those sizes
/// and unbounded: the box ±p_error about each hit near the apex holds the
/// apex, the exact crossing. Unbounded, the polynomial is expanded about
/// the line's origin, so its rounding grows with the origin's distance:
/// a bound sized by the point alone (|p| ≈ 0 here) was 18 times too small
/// from 15 away and 1800 times from 150.
#[test]
fn hits_at_a_cones_apex_hold_the_apex_within_their_error_bound() {
    let _watchdog = crate::watchdog::start();
    for half in [0.5, 5.0, 50.0, 500.0] {
        for bounded in [true, false] {
            let b = bounded.then(|| Aabb::new(DVec3::splat(-half), DVec3::splat(half)));
            let cone = ImplicitSurface::new(compile("x^2 + y^2 - z^2"), b, 0);
            let mut near = 0;
            for i in 0..100 {
                let a = 0.1 + i as f64 * 0.731;
                let dir = DVec3::new(a.cos(), a.sin(), 0.3 + 0.004 * i as f64).normalize();
                let r = Ray::new(-0.3 * half * dir, dir);
                let mut xs = Vec::new();
                cone.crossings(&r, &mut xs);
                xs.extend(cone.intersect(&r, 0.0, f64::INFINITY));
                for h in xs {
                    // Roots elsewhere on the cone (the line meets it only
                    // at the apex, but a box's faces are crossings too).
                    if h.point.length() > 1e-3 * half {
                        continue;
                    }
                    near += 1;
                    assert!(
                        h.point.abs().cmple(h.p_error).all(),
                        "half {half}, bounded {bounded}, line {i}: {} off the apex, p_error {}",
                        h.point,
                        h.p_error
                    );
                }
            }
            assert!(near >= 50, "half {half}, bounded {bounded}: {near}");
        }
    }
}

/// Where the gradient vanishes the shell noise/|∇f| is unbounded and the
/// bound is capped: a point's error bound stays a small part of the
/// surface's scale (here at most 10⁻⁵ of the box's diagonal, or of the
/// ray's reach unbounded), or a secondary ray would start a visible
/// distance off the surface. The cone's apex met exactly along its axis
/// (the gradient there is 0): the bound holds the apex and is capped.
#[test]
fn the_bound_at_a_vanished_gradient_is_capped_at_a_small_part_of_the_scale() {
    let _watchdog = crate::watchdog::start();
    for half in [0.5, 5.0, 50.0] {
        for bounded in [true, false] {
            let b = bounded.then(|| Aabb::new(DVec3::splat(-half), DVec3::splat(half)));
            let cone = ImplicitSurface::new(compile("x^2 + y^2 - z^2"), b, 0);
            let from = 0.8 * half;
            // A direction of length 1, and one of 2⁻¹⁰ (a moved surface's
            // rays are not unit): t is then 1024 times the distance. (The
            // axis touches the apex, a double root without a change of
            // sign: exact powers of 2 keep its value there exactly 0.)
            for len in [1.0, 2f64.powi(-10)] {
                let r = Ray::new(DVec3::new(0.0, 0.0, from), -len * DVec3::Z);
                let h = cone
                    .intersect(&r, 0.0, f64::INFINITY)
                    .unwrap_or_else(|| panic!("half {half}, bounded {bounded}, |dir| {len}"));
                assert_eq!(cone.equation().gradient(h.point), DVec3::ZERO, "{h:?}");
                let scale = if bounded {
                    (2.0 * half) * 3f64.sqrt()
                } else {
                    1.0 + from
                };
                assert!(
                    h.point.abs().cmple(h.p_error).all() && h.p_error.max_element() <= 1e-5 * scale,
                    "half {half}, bounded {bounded}, |dir| {len}: {} with p_error {}",
                    h.point,
                    h.p_error
                );
            }
        }
    }
}

/// The thin torus of the unbounded tests: core radius 1, tube 1/16 (both
/// exact in binary), about the z axis, traced without a box.
const THIN: (f64, f64) = (1.0, 0.0625);

fn thin_torus() -> ImplicitSurface {
    ImplicitSurface::new(
        compile("(x^2 + y^2 + z^2 + 1 - 0.00390625)^2 - 4 * (x^2 + y^2)"),
        Some(Aabb::INFINITE),
        0,
    )
}

/// The thin torus's point at angle `a` about z and `b` about its core.
fn on_thin_torus(a: f64, b: f64) -> DVec3 {
    let ring = THIN.0 + THIN.1 * b.cos();
    DVec3::new(ring * a.cos(), ring * a.sin(), THIN.1 * b.sin())
}

/// The box ±p_error about `h`'s point reaches the thin torus along its
/// normal: the nearest point of the torus is on the circle of radius
/// `THIN.1` about the nearest point of its core. `what` names the ray.
fn assert_holds_thin_torus(h: &Hit, what: impl Fn() -> String) {
    let core = (DVec2::new(h.point.x, h.point.y).normalize() * THIN.0).extend(0.0);
    let out = h.point - core;
    let off = (out.length() - THIN.1).abs();
    let reach = out.normalize().abs().dot(h.p_error);
    assert!(
        off <= reach,
        "{}: {} off by {off:e} > {reach:e}",
        what(),
        h.point
    );
}

/// An unbounded surface's hits lie within their error bound of it,
/// whatever the length of the ray's direction (a moved surface's rays
/// are not unit): a thin torus (radii 1 and 1/16, exact in binary; it
/// bends fast, which is what makes Newton's last step count), traced
/// without a box, by rays aimed at points of it from 3 and from 0.01
/// away, with directions of length 1, 1024 and 2⁻¹⁰. The box ±p_error
/// about each crossing reaches the torus along its normal (what a
/// secondary ray's offset reads), as `sphere_hits_are_on_the_surface_…`
/// checks for the sphere.
#[test]
fn unbounded_hits_hold_the_surface_whatever_the_rays_length() {
    let _watchdog = crate::watchdog::start();
    let torus = thin_torus();
    let mut rnd = testing::numbers(41);
    for from in [3.0, 0.01] {
        for len in [1.0, 1024.0, 2f64.powi(-10)] {
            let mut hits = 0;
            for _ in 0..2000 {
                let aim = on_thin_torus(3.2 * rnd(), 3.2 * rnd());
                let o = aim + DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X) * from;
                let r = Ray::new(o, (aim - o).normalize() * len);
                let mut xs = Vec::new();
                torus.crossings(&r, &mut xs);
                for h in xs {
                    hits += 1;
                    assert_holds_thin_torus(&h, || format!("from {from}, |dir| {len}"));
                }
            }
            assert!(hits > 2000, "from {from}, |dir| {len}: {hits} hits");
        }
    }
}

/// Seen from far away (10³ to 10⁵ units), an unbounded surface's hits
/// still hold it within their bound, and the rays aimed at it find it:
/// the polynomial along a ray that far expanded about the ray's origin
/// kept too few digits for a tube 0.0625 thick.
#[test]
fn unbounded_hits_from_far_away_hold_the_surface() {
    let _watchdog = crate::watchdog::start();
    let torus = thin_torus();
    let mut rnd = testing::numbers(43);
    for from in [1e3, 1e4, 1e5] {
        for len in [1.0, 1024.0] {
            let (mut hits, mut aimed) = (0, 0);
            for _ in 0..500 {
                let aim =
                    on_thin_torus(std::f64::consts::TAU * rnd(), std::f64::consts::TAU * rnd());
                let o = aim
                    + DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize_or(DVec3::X)
                        * from;
                let r = Ray::new(o, (aim - o).normalize() * len);
                let mut xs = Vec::new();
                torus.crossings(&r, &mut xs);
                aimed += 1;
                hits += usize::from(!xs.is_empty());
                for h in xs {
                    assert_holds_thin_torus(&h, || format!("from {from}, |dir| {len}"));
                }
            }
            // A ray aimed at a point of the surface meets it (bar a few
            // that only graze it, within rounding of the aim).
            assert!(
                hits * 100 >= aimed * 98,
                "from {from}, |dir| {len}: {hits} of {aimed}"
            );
        }
    }
}

/// A ray that leaves the origin's side (the point of its line nearest the
/// origin lies behind it) with a short reach still finds what lies within
/// that reach: from the torus's core circle outwards, its tube's wall at
/// 0.0625, before a light at 0.5, and nothing within 0.05.
#[test]
fn an_unbounded_surface_is_found_by_a_short_ray_leaving_the_origins_side() {
    let _watchdog = crate::watchdog::start();
    let torus = thin_torus();
    for len in [1.0, 8.0] {
        let r = Ray::new(DVec3::new(1.0, 0.0, 0.0), DVec3::new(len, 0.0, 0.0));
        let h = torus
            .intersect(&r, 0.0, 0.5 / len)
            .expect("the tube's wall");
        assert!((h.t * len - 0.0625).abs() < 1e-12, "{}", h.t * len);
        assert!(torus.occludes(&r, 0.0, 0.5 / len));
        assert!(!torus.occludes(&r, 0.0, 0.05 / len));
    }
}
