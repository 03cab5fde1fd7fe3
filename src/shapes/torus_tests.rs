//! Unit tests of `torus.rs`, kept in their own file so the module reads
//! as the code alone.

use super::*;
use crate::shapes::testing;
use crate::shapes::testing::numbers;

/// The torus's equation (R, r) at `p`, straight from its definition.
fn f(big: f64, small: f64, p: DVec3) -> f64 {
    let s = p.length_squared() + big * big - small * small;
    s * s - 4.0 * big * big * (p.x * p.x + p.z * p.z)
}

/// How far `p` is from the torus's surface: the points r from the tube's
/// centre circle, from its point nearest to `p` or (a spindle torus's
/// inner part, R < r) from the one across the axis.
fn gap(big: f64, small: f64, p: DVec3) -> f64 {
    let rho = p.x.hypot(p.z);
    let near = ((rho - big).hypot(p.y) - small).abs();
    let far = ((rho + big).hypot(p.y) - small).abs();
    near.min(far)
}

/// The point at angle `theta` around the y axis (from +z towards +x) and
/// `phi` around the tube (from the outer equator up), and the unit
/// outward normal there.
fn on_torus(big: f64, small: f64, theta: f64, phi: f64) -> (DVec3, DVec3) {
    let out = DVec3::new(theta.sin(), 0.0, theta.cos());
    let n = out * phi.cos() + DVec3::Y * phi.sin();
    (out * big + n * small, n)
}

/// Rays aimed at `n` points spread over the torus (R, r), from 10·(R + r)
/// away in every direction: at any size, most of them hit.
fn rays_at_the_surface(big: f64, small: f64, n: usize, seed: u64) -> Vec<Ray> {
    let mut rnd = numbers(seed);
    (0..n)
        .map(|_| {
            let (p, _) = on_torus(big, small, PI * rnd(), PI * rnd());
            let from = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X);
            let o = p + from * 10.0 * (big + small);
            Ray::new(o, (p - o).normalize())
        })
        .collect()
}

#[test]
fn hits_the_ring_in_the_xz_plane() {
    let _watchdog = crate::watchdog::start();
    let t = Torus::new(2.0, 0.5, 0);
    // Straight down onto the tube's top at x = 2.
    let r = Ray::new(DVec3::new(2.0, 5.0, 0.0), -DVec3::Y);
    let h = t.intersect(&r, 1e-9, f64::INFINITY).unwrap();
    assert!((h.t - 4.5).abs() < 1e-9);
    assert!((h.normal.normalize() - DVec3::Y).length() < 1e-9);
    assert!((t.uv(&h).y - 0.25).abs() < 1e-9);
    // Through the hole: nothing.
    let r = Ray::new(DVec3::new(0.0, 5.0, 0.0), -DVec3::Y);
    assert!(t.intersect(&r, 1e-9, f64::INFINITY).is_none());
    // Along the x axis: four crossings, alternating in and out.
    let r = Ray::new(DVec3::new(-5.0, 0.0, 0.0), DVec3::X * 2.0);
    let mut xs = Vec::new();
    t.crossings(&r, &mut xs);
    let want = [1.25, 1.75, 3.25, 3.75];
    assert_eq!(xs.len(), 4);
    for (h, w) in xs.iter().zip(want) {
        assert!((h.t - w).abs() < 1e-9, "{xs:?}");
    }
    assert!(xs[0].normal.dot(r.dir) < 0.0 && xs[1].normal.dot(r.dir) > 0.0);
}

/// The cylinder tests before the quartic throw away only chords that
/// truly miss: whenever they reject one, the torus's equation keeps
/// one sign along it (sampled densely, and the quartic's own roots
/// found without the tests agree); and they do reject the chords
/// through the box's corners and through the hole, or they would cost
/// without saving anything.
#[test]
fn the_cylinder_tests_reject_only_chords_that_miss() {
    let _watchdog = crate::watchdog::start();
    let (big, small) = (2.0, 0.5);
    let t = Torus::new(big, small, 0);
    let f = |p: DVec3| {
        let s = p.length_squared() + big * big - small * small;
        s * s - 4.0 * big * big * (p.x * p.x + p.z * p.z)
    };
    let (mut corners, mut hole, mut kept_hits) = (0, 0, 0);
    let mut rays = testing::rays_towards(DVec3::ZERO, 2.6, 3000, 11);
    // Grazing the outer equator and the hole's wall, just outside and
    // just inside: level rays past the outer equator, and vertical rays
    // down the hole at distances ρ about R − r from the axis.
    for k in 0..400 {
        let e = (k as f64 - 200.0) * 1e-4;
        let rho = big + small + e;
        rays.push(Ray::new(DVec3::new(rho, 0.0, -10.0), DVec3::Z));
        rays.push(Ray::new(DVec3::new(-10.0, 0.3 * e, rho), DVec3::X));
        let rho = big - small + e;
        rays.push(Ray::new(DVec3::new(rho * 0.6, 5.0, rho * 0.8), -DVec3::Y));
    }
    for r in &rays {
        let Some((_, _, o, d)) = t.chord(r, f64::NEG_INFINITY, f64::INFINITY) else {
            continue;
        };
        let sampled_root = (0..=4000)
            .map(|i| f(o + d * (i as f64 / 2000.0 - 1.0)))
            .collect::<Vec<_>>()
            .windows(2)
            .any(|w| w[0] * w[1] <= 0.0);
        let roots = crate::implicit::solve::all_roots(&t.quartic(o, d), -1.0, 1.0, 1e-13);
        if t.chord_misses(o, d) {
            assert!(
                !sampled_root && roots.is_empty(),
                "{r:?} rejected: {roots:?}"
            );
            let ends = [o - d, o + d].map(|p| p.x.hypot(p.z));
            if ends.iter().all(|&rho| rho < big - small) {
                hole += 1;
            } else {
                corners += 1;
            }
        } else if !roots.is_empty() {
            kept_hits += 1;
        }
    }
    assert!(corners > 50 && hole > 50, "corners {corners}, hole {hole}");
    assert!(kept_hits > 500, "{kept_hits}");
}

/// Secondary rays leaving the torus never meet it again where they
/// left: many more hits than the all-shapes offset test tries, because
/// the quartic's rounding at the chord's start found the surface left
/// behind for about one shadow ray in 50,000 (dark specks on the torus
/// benchmark before the t lower-bound test). Outward rays straight
/// out, at 26° and at 3°, and towards the benchmark's light.
#[test]
fn secondary_rays_never_find_the_surface_they_leave() {
    let _watchdog = crate::watchdog::start();
    let t = Torus::new(2.0, 0.5, 0);
    let light = DVec3::new(5.0, 9.5, 5.0);
    let (mut bad, mut tried) = (0, 0);
    for r in testing::rays_towards(DVec3::ZERO, 2.6, 25_000, 5) {
        let Some(h) = t.intersect(&r, 0.0, f64::INFINITY) else {
            continue;
        };
        let mut ng = h.geo_normal.normalize();
        if ng.dot(r.dir) > 0.0 {
            ng = -ng;
        }
        let side = ng.any_orthonormal_vector();
        let to_light = (light - h.point).normalize();
        let mut dirs = vec![
            ng,
            (ng + 2.0 * side).normalize(),
            (0.05 * ng + side).normalize(),
        ];
        if to_light.dot(ng) > 0.0 {
            dirs.push(to_light);
        }
        for dir in dirs {
            tried += 1;
            let o = crate::geometry::offset_ray_origin(h.point, h.p_error, h.geo_normal, dir);
            let ray = Ray::new(o, dir);
            if t.intersect(&ray, 0.0, f64::INFINITY)
                .is_some_and(|a| a.t < 1e-6)
                || t.occludes(&ray, 0.0, 1e-6)
            {
                bad += 1;
            }
        }
    }
    assert!(tried > 30_000, "{tried}");
    assert_eq!(
        bad, 0,
        "{bad} of {tried} secondary rays met the surface they left"
    );
}

#[test]
fn consistent() {
    let _watchdog = crate::watchdog::start();
    let t = Torus::new(1.5, 0.4, 0);
    testing::check_consistency(&t, &testing::rays_towards(DVec3::ZERO, 1.8, 2000, 3));
}

/// The quartic's coefficients are the torus's equation along the chord
/// o + s·d: evaluated at any s they give what the equation gives at that
/// point, for tori fat and thin, a spindle torus (R < r) among them, and
/// chords in every direction.
#[test]
fn the_quartic_is_the_equation_along_the_chord() {
    let mut rnd = numbers(3);
    for (big, small) in [(2.0, 0.5), (1.5, 0.4), (0.7, 1.3), (3.0, 0.25)] {
        let t = Torus::new(big, small, 0);
        for _ in 0..50 {
            let o = DVec3::new(rnd(), rnd(), rnd()) * 3.0;
            let d = DVec3::new(rnd(), rnd(), rnd()) * 2.0;
            let c = t.quartic(o, d);
            let mag = (o.length() + d.length() + big + small).powi(4);
            for s in [-1.0, -0.6, -0.1, 0.0, 0.35, 0.8, 1.0] {
                let want = f(big, small, o + d * s);
                let got = c[0] + s * (c[1] + s * (c[2] + s * (c[3] + s * c[4])));
                assert!(
                    (got - want).abs() <= 1e-12 * mag,
                    "R {big} r {small} o {o} d {d} s {s}: {got} vs {want}"
                );
            }
        }
    }
}

/// The normal points straight out of the tube: along the line from the
/// nearest point of the tube's centre circle, all around the ring and the
/// tube, for tori of several proportions; and a hit's normal is that
/// normal, the geometric one too.
#[test]
fn normals_point_straight_out_of_the_tube() {
    for (big, small) in [(2.0, 0.5), (1.5, 0.4), (3.0, 0.25)] {
        let t = Torus::new(big, small, 0);
        for i in 0..12 {
            for j in 0..12 {
                let theta = 2.0 * PI * (i as f64 + 0.3) / 12.0;
                let phi = 2.0 * PI * (j as f64 + 0.6) / 12.0 - PI;
                let (p, want) = on_torus(big, small, theta, phi);
                let n = t.normal(p).normalize();
                assert!((n - want).length() < 1e-9, "at {p}: {n} vs {want}");
            }
        }
        let _watchdog = crate::watchdog::start();
        let mut met = 0;
        for r in rays_at_the_surface(big, small, 200, 7) {
            let mut xs = Vec::new();
            t.crossings(&r, &mut xs);
            for h in &xs {
                let p = h.local;
                let rho = p.x.hypot(p.z);
                let ring = DVec3::new(p.x, 0.0, p.z) * (big / rho);
                let want = (p - ring).normalize();
                assert!((h.normal.normalize() - want).length() < 1e-6, "{h:?}");
                assert_eq!(h.geo_normal, h.normal);
                met += 1;
            }
        }
        assert!(met > 300, "{met}");
    }
}

/// (u, v) are the angles around the y axis (from +z towards +x) and
/// around the tube (from the outer equator up), as fractions of a turn
/// in [0, 1): all around both, for two tori; exactly 0 on each seam,
/// and below 1 just before it.
#[test]
fn uv_are_the_angles_around_the_axis_and_the_tube() {
    for (big, small) in [(2.0, 0.5), (1.5, 0.4)] {
        let t = Torus::new(big, small, 0);
        let at = |p: DVec3| {
            t.uv(&Hit {
                local: p,
                ..Hit::default()
            })
        };
        for i in 0..16 {
            for j in 0..16 {
                let (u, v) = ((i as f64 + 0.25) / 16.0, (j as f64 + 0.5) / 16.0);
                let (p, _) = on_torus(big, small, 2.0 * PI * u, 2.0 * PI * v);
                let uv = at(p);
                assert!((uv.x - u).abs() < 1e-12, "u at {p}: {uv} vs {u}");
                assert!((uv.y - v).abs() < 1e-12, "v at {p}: {uv} vs {v}");
            }
        }
        let outer = big + small;
        assert_eq!(at(DVec3::new(0.0, 0.1, big)).x, 0.0);
        let u = at(DVec3::new(-1e-300, 0.1, big)).x;
        assert!(u < 1.0 && u > 0.999, "{u}");
        assert_eq!(at(DVec3::new(0.0, 0.0, outer)).y, 0.0);
        let v = at(DVec3::new(0.0, -1e-300, outer)).y;
        assert!(v < 1.0 && v > 0.999, "{v}");
    }
}

/// A hit's point is put back on the tube: its distance from the tube's
/// centre circle is r up to a few roundings of the torus's size; its
/// error bound is never negative, no more than a few roundings of that
/// size, and at least the rounding of the point's own coordinates (the
/// last addition that makes it rounds). Fat and thin tori, tiny and
/// huge: R = 1000, r = 0.001 is where a bound of r's size alone falls
/// short, R = 4000, r = 1000 where one that multiplies the circle's
/// point by r is far too wide; and a spindle torus (R < r), whose inner
/// part lies r from the circle's point across the axis.
#[test]
fn hit_points_are_on_the_tube_with_a_rounding_sized_error() {
    let _watchdog = crate::watchdog::start();
    let eps = f64::EPSILON;
    for (big, small) in [
        (2.0, 0.5),
        (1e-3, 4e-4),
        (1e3, 1.0),
        (1e3, 1e-3),
        (4e3, 1e3),
        (0.7, 1.3),
    ] {
        let t = Torus::new(big, small, 3);
        let mag = big + small;
        let mut met = 0;
        for r in rays_at_the_surface(big, small, 300, 13) {
            let mut xs = Vec::new();
            t.crossings(&r, &mut xs);
            for h in &xs {
                assert_eq!(h.material, 3);
                assert_eq!(h.local, r.at(h.t));
                assert!((h.point - h.local).length() < 1e-9 * mag, "{h:?}");
                let off = gap(big, small, h.point).abs();
                assert!(off <= 8.0 * eps * mag, "{off} off the tube: {h:?}");
                let e = h.p_error;
                assert!(e.min_element() >= 0.0, "{e}");
                assert!(e.max_element() <= 32.0 * eps * mag, "{e} vs {mag}");
                let least = h.point.abs() * (0.5 * eps);
                assert!(e.cmpge(least).all(), "{e} below {least}");
                met += 1;
            }
        }
        assert!(met > 300, "R {big} r {small}: {met}");
    }
}

/// Two points with no single nearest point on the tube: a point on the
/// axis (a spindle torus, R < r, crosses it at y = ±√(r² − R²)) goes to
/// itself, and a point on the tube's centre circle, r from the surface
/// every way, stays finite with a box of r that holds a surface point.
/// A ray down the spindle's axis meets it there.
#[test]
fn points_on_the_axis_or_the_centre_circle_reproject_soundly() {
    let s = Torus::new(0.3, 0.5, 0);
    for y in [0.4, -0.4] {
        let (p, e) = s.reproject(DVec3::new(0.0, y, 0.0));
        assert!((p - DVec3::new(0.0, y, 0.0)).length() < 1e-15, "{p}");
        assert!(e.is_finite() && e.min_element() >= 0.0 && e.max_element() < 1e-14);
    }
    let _watchdog = crate::watchdog::start();
    let mut xs = Vec::new();
    s.crossings(&Ray::new(DVec3::new(0.0, 5.0, 0.0), -DVec3::Y), &mut xs);
    let ys = xs.iter().map(|h| h.point.y).collect::<Vec<_>>();
    assert!(
        ys.len() == 2 && (ys[0] - 0.4).abs() < 1e-12 && (ys[1] + 0.4).abs() < 1e-12,
        "{xs:?}"
    );
    let t = Torus::new(2.0, 0.5, 0);
    for c in [DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.0, 0.0, -2.0)] {
        let (p, e) = t.reproject(c);
        assert!(p.is_finite() && e.is_finite(), "{p} {e}");
        assert!(
            gap(2.0, 0.5, p).abs() <= 3f64.sqrt() * e.max_element() + 1e-15,
            "{p} {e}"
        );
    }
}

/// The window is open at both ends: along the x axis the crossings are
/// at exactly t = 1.25, 1.75, 3.25 and 3.75, and a window ending exactly
/// at one leaves it out, one ending just past it keeps it.
#[test]
fn a_crossing_exactly_at_a_window_end_is_outside() {
    let _watchdog = crate::watchdog::start();
    let t = Torus::new(2.0, 0.5, 0);
    let r = Ray::new(DVec3::new(-5.0, 0.0, 0.0), DVec3::X * 2.0);
    let mut xs = Vec::new();
    t.crossings(&r, &mut xs);
    assert_eq!(
        xs.iter().map(|h| h.t).collect::<Vec<_>>(),
        [1.25, 1.75, 3.25, 3.75]
    );
    let at = |lo: f64, hi: f64| t.intersect(&r, lo, hi).map(|h| h.t);
    for (lo, hi) in [
        (1.5, 1.75),
        (3.5, 3.75),
        (0.0, 1.25),
        (1.25, 1.75),
        (3.75, 9.0),
    ] {
        assert_eq!(at(lo, hi), None, "({lo}, {hi})");
        assert!(!t.occludes(&r, lo, hi), "({lo}, {hi})");
    }
    assert_eq!(at(1.5, 1.75 + 1e-9), Some(1.75));
    assert_eq!(at(3.5, 3.75 + 1e-9), Some(3.75));
    assert_eq!(at(1.0, 1.5), Some(1.25));
    assert!(t.occludes(&r, 3.5, 3.75 + 1e-9));
}

/// The light route (`crossings_lite`, then `hit_of` for the one CSG
/// keeps) gives the same crossings as `crossings`: the same t, facing in
/// where the ray enters and out where it leaves, and the same hit.
#[test]
fn crossings_lite_and_hit_of_agree_with_crossings() {
    let _watchdog = crate::watchdog::start();
    let t = Torus::new(1.5, 0.4, 2);
    let mut met = 0;
    for r in rays_at_the_surface(1.5, 0.4, 300, 29) {
        let mut xs = Vec::new();
        t.crossings(&r, &mut xs);
        let mut lite = Vec::new();
        t.crossings_lite(&r, &mut lite);
        assert_eq!(xs.len(), lite.len());
        for (i, (x, l)) in xs.iter().zip(&lite).enumerate() {
            assert_eq!(l.t, x.t);
            let h = t.hit_of(&r, l);
            assert_eq!(
                (h.t, h.point, h.p_error, h.normal, h.material),
                (x.t, x.point, x.p_error, x.normal, x.material)
            );
            if !l.grazing {
                assert_eq!(l.facing < 0.0, i % 2 == 0, "{lite:?}");
                assert_eq!(l.facing.signum(), x.normal.dot(r.dir).signum());
            }
        }
        met += !xs.is_empty() as usize;
    }
    assert!(met > 200, "{met}");
}

/// The box is R + r out from the axis and r above and below, and holds
/// every hit; shadow rays and nearest hits agree with the crossings in
/// every window; the crossings alternate in and out, the normals agree
/// with neighbouring hits, and a torus is a solid.
#[test]
fn bounds_shadows_and_the_shared_properties() {
    let _watchdog = crate::watchdog::start();
    for (big, small) in [(2.0, 0.5), (1.5, 0.4), (0.7, 1.3)] {
        let t = Torus::new(big, small, 0);
        let e = DVec3::new(big + small, small, big + small);
        assert_eq!(t.bounds(), Aabb::new(-e, e));
        let rays = testing::rays_towards(DVec3::ZERO, big + small, 400, 31);
        assert!(testing::check_bounds_hold_hits(&t, &rays) > 100);
        assert!(testing::check_occludes_agrees(&t, &rays) > 100);
        testing::check_no_rehit(&t, &rays);
        assert!(testing::check_normals(&t, &rays) > 100);
        testing::check_alternation(&t, &rays);
        assert!(t.is_solid());
    }
}

/// A line that passes just inside the outer equator (in the plane
/// y = 0, ρ = (R + r)(1 − ε) at its closest) or runs down just inside the
/// hole's wall (ρ = (R − r)(1 + ε)) enters the tube and must hit it, for
/// ε far below the cylinder tests' margin of 1e-9 but far above
/// rounding; just outside them by 1e-8 it misses. Tiny, unit and huge
/// tori, from several sides.
#[test]
fn lines_just_inside_the_outer_equator_or_the_holes_wall_hit() {
    let _watchdog = crate::watchdog::start();
    for (big, small) in [(2.0, 0.5), (1e3, 1.0), (1e-3, 2e-4)] {
        let t = Torus::new(big, small, 0);
        let (outer, inner) = (big + small, big - small);
        for a in [0.0f64, 0.7, 2.0, 4.1] {
            let (side, along) = (
                DVec3::new(a.cos(), 0.0, a.sin()),
                DVec3::new(-a.sin(), 0.0, a.cos()),
            );
            for (eps, hits) in [(1e-10, true), (1e-11, true), (-1e-8, false)] {
                let level = Ray::new(side * outer * (1.0 - eps) - along * 3.0 * outer, along);
                let down = Ray::new(
                    side * inner * (1.0 + eps) + DVec3::Y * 3.0 * outer,
                    -DVec3::Y,
                );
                for r in [level, down] {
                    let h = t.intersect(&r, 0.0, f64::INFINITY);
                    assert_eq!(h.is_some(), hits, "R {big} r {small} ε {eps}: {r:?}");
                    if let Some(h) = h {
                        assert!(gap(big, small, h.point).abs() < 1e-12 * outer, "{h:?}");
                    }
                }
            }
        }
    }
}

/// Vertical lines through the box's corners (outside the ring) and down
/// the hole are rejected before the quartic is solved: the cylinder
/// tests are there to save that work, and a vertical chord has no
/// vertex of its own to look at.
#[test]
fn vertical_chords_outside_the_ring_or_in_the_hole_are_rejected_early() {
    let t = Torus::new(2.0, 0.5, 0);
    for p in [
        DVec3::new(2.4, 3.0, 2.4),
        DVec3::new(-2.2, 3.0, 1.5),
        DVec3::new(0.3, 3.0, -0.4),
        DVec3::new(1.0, 3.0, 0.9),
    ] {
        let r = Ray::new(p, -DVec3::Y);
        let (_, _, o, d) = t.chord(&r, 0.0, f64::INFINITY).expect("in the box");
        assert!(t.chord_misses(o, d), "{p}");
    }
}

/// A ray starting just before the surface (a short way off it along the
/// way in) meets it there: only roots within rounding of the window's
/// start are taken for the surface a ray leaves. From 1e-6 to 1e-11 of
/// the torus's size before it (the rounding band is about 1e-13 of it),
/// at three sizes, all around the torus, from the window's start at 0
/// and from a ray whose origin lies further back.
#[test]
fn rays_starting_just_before_the_surface_meet_it() {
    let _watchdog = crate::watchdog::start();
    let mut rnd = numbers(17);
    for scale in [1e-3, 1.0, 1e3] {
        let (big, small) = (2.0 * scale, 0.5 * scale);
        let t = Torus::new(big, small, 0);
        for _ in 0..60 {
            let (p, n) = on_torus(big, small, PI * rnd(), PI * rnd());
            let side = n.any_orthonormal_vector();
            let dir = (-n + side * rnd()).normalize();
            for delta in [1e-6, 1e-9, 1e-11] {
                let delta = delta * scale;
                for back in [0.0, 10.0 * scale] {
                    let r = Ray::new(p - dir * (delta + back), dir);
                    let h = t.intersect(&r, back, f64::INFINITY);
                    let got = h.map(|h| h.t - back);
                    assert!(
                        got.is_some_and(|g| (g - delta).abs() < 1e-12 * scale),
                        "scale {scale}, {delta} before {p} along {dir}, from {back}: {got:?}"
                    );
                }
            }
        }
    }
}

/// The band at the window's start, two ways. `may_be_behind` takes a
/// root at s for the surface a ray leaves when it lies no more than the
/// band past the window's start: γ₁₆ of the magnitudes of the quartic's
/// terms there, over the quartic's slope, plus the solver's tolerance
/// 1e-13. The magnitudes, factored: the torus's equation along the
/// chord with every term made positive, (|o|² + R² + r² + 2Σ|oᵢdᵢ|·a +
/// |d|²a²)² + 4R²((|oₓ| + a|dₓ|)² + (|o_z| + a|d_z|)²) at a = |s|; the
/// slope is the equation's gradient along d. (Chords whose o and d have
/// one sign in each coordinate, so that 2|o·d| is the sum of the
/// products' magnitudes; slopes large enough to be known to 1e-9.) Just
/// inside the band a root is the surface left behind, just outside it
/// is not; and a root well past the start (1e-6 of the chord and more)
/// never is, even a tangent's, whose slope is 0.
#[test]
fn the_band_at_the_windows_start_is_the_rounding_of_the_terms() {
    let mut rnd = numbers(23);
    let g16 = gamma(16);
    let mut checked = 0;
    for (big, small) in [(2.0, 0.5), (1.5, 0.4), (0.7, 1.3), (3.0, 0.05)] {
        let t = Torus::new(big, small, 0);
        let k = 4.0 * big * big;
        for i in 0..120 {
            let o = DVec3::new(rnd(), rnd(), rnd()) * [0.1, 1.0, 4.0][i % 3];
            let mut along = |x: f64| rnd().abs() * x.signum();
            let d = DVec3::new(along(o.x), along(o.y), along(o.z)) * [0.05, 1.0, 5.0][i / 3 % 3];
            let c = t.quartic(o, d);
            for s in [-1.0, -0.7, -0.2, 0.0, 0.4, 1.0, rnd()] {
                let a = f64::abs(s);
                let p = o + d * s;
                let sq = p.length_squared() + big * big - small * small;
                let grad = 4.0 * (p * sq - DVec3::new(p.x, 0.0, p.z) * (2.0 * big * big));
                let slope = grad.dot(d);
                let od = (o * d).abs().element_sum();
                let terms = (o.length_squared()
                    + big * big
                    + small * small
                    + 2.0 * od * a
                    + d.length_squared() * a * a)
                    .powi(2)
                    + k * ((o.x.abs() + a * d.x.abs()).powi(2)
                        + (o.z.abs() + a * d.z.abs()).powi(2));
                if slope.abs() < 1e-5 * terms {
                    continue;
                }
                let band = g16 * terms / slope.abs() + 1e-13;
                assert!(
                    t.may_be_behind(o, d, &c, s, band * (1.0 - 1e-6)),
                    "R {big} r {small} o {o} d {d} s {s}: band {band}"
                );
                assert!(
                    !t.may_be_behind(o, d, &c, s, band * (1.0 + 1e-6)),
                    "R {big} r {small} o {o} d {d} s {s}: band {band}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 2000, "{checked}");
    // The line y = r, z = 0 touches the tube's top circle at x = ±R:
    // along o = (0, r, 0), d = (R, 0, 0) the equation is 16(s² − 1)²
    // for R = 2, r = 0.5, a double root at s = 1 with slope 0.
    let t = Torus::new(2.0, 0.5, 0);
    let (o, d) = (DVec3::new(0.0, 0.5, 0.0), DVec3::new(2.0, 0.0, 0.0));
    let c = t.quartic(o, d);
    assert_eq!(c, [16.0, 0.0, -32.0, 0.0, 16.0]);
    for ahead in [1.01e-6, 1e-3, 0.5, 2.0] {
        assert!(!t.may_be_behind(o, d, &c, 1.0, ahead), "{ahead}");
    }
    assert!(t.may_be_behind(o, d, &c, 1.0, 0.0));
}
