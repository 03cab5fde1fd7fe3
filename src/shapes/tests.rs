//! Unit tests of the code every shape shares (`shapes/mod.rs`): hits and
//! crossings, the default light route, the watertight triangle test, the
//! barycentric point and the quadratic.

use super::*;
use crate::geometry::rounding::gamma;
use crate::shapes::testing::{Bare, numbers};

#[test]
fn quadratic_is_stable_for_tiny_roots() {
    // Roots 1e-9 and 1e9: the naive formula loses the small one.
    let (a, b) = solve_quadratic(1.0, -(1e9 + 1e-9), 1.0).unwrap();
    assert!((a - 1e-9).abs() / 1e-9 < 1e-6);
    assert!((b - 1e9).abs() / 1e9 < 1e-12);
    assert!(solve_quadratic(1.0, 0.0, 1.0).is_none());
}

/// a(t − r₀)(t − r₁) gives back r₀ and r₁, smaller first, each to a few
/// roundings of its own size: roots of either sign and of sizes far
/// apart, a leading coefficient of either sign and of any size, b = 0
/// (roots ±r). A double root (the discriminant exactly 0) is found
/// twice; t² = 0 gives 0 twice; no real roots or a = 0 give none.
#[test]
fn quadratic_gives_back_the_roots_it_was_made_from() {
    let mut rnd = numbers(5);
    for i in 0..400 {
        let r0 = rnd() * 10f64.powi((i % 7) - 3);
        let r1 = rnd() * 10f64.powi((i / 7 % 5) - 2);
        let a = rnd().signum() * 10f64.powi((i % 3) * 3 - 3);
        let (b, c) = (-a * (r0 + r1), a * r0 * r1);
        let (t0, t1) = solve_quadratic(a, b, c).expect("real roots");
        let (lo, hi) = (r0.min(r1), r0.max(r1));
        // Each root to a few roundings of its own size (the small one
        // too: c/q keeps it), more where the two are close, which the
        // rounding of b and c moves apart or together.
        let close = 1.0 + lo.abs().max(hi.abs()) / (hi - lo);
        assert!(t0 <= t1, "{t0} {t1}");
        for (got, want) in [(t0, lo), (t1, hi)] {
            assert!(
                (got - want).abs() <= 1e-14 * want.abs() * close,
                "{a}·(t − {r0})(t − {r1}): {t0} {t1}"
            );
        }
    }
    for (a, r) in [(1.0, 2.5), (-3.0, 0.75), (2.0, -1.5)] {
        assert_eq!(solve_quadratic(a, -2.0 * a * r, a * r * r), Some((r, r)));
        assert_eq!(
            solve_quadratic(a, 0.0, -a * r * r),
            Some((-r.abs(), r.abs()))
        );
    }
    assert_eq!(solve_quadratic(1.0, -2.0, 1.0), Some((1.0, 1.0)));
    assert_eq!(solve_quadratic(2.0, 0.0, 0.0), Some((0.0, 0.0)));
    assert_eq!(solve_quadratic(-2.0, 0.0, 0.0), Some((0.0, 0.0)));
    assert_eq!(solve_quadratic(1.0, 1.0, 1.0), None);
    assert_eq!(solve_quadratic(-1.0, 0.0, -1e-300), None);
    assert_eq!(solve_quadratic(0.0, 2.0, -4.0), None);
    assert_eq!(solve_quadratic(0.0, 0.0, 0.0), None);
}

/// Seen from the other side, a hit keeps everything but its normals,
/// which both turn round; flipping in place is the same, and twice is
/// nothing.
#[test]
fn a_flipped_hit_turns_both_normals_only() {
    let h = Hit {
        t: 2.5,
        normal: DVec3::new(0.1, -0.2, 0.9),
        uv: DVec2::new(0.3, 0.7),
        local: DVec3::new(1.0, 2.0, 3.0),
        point: DVec3::new(4.0, 5.0, 6.0),
        p_error: DVec3::splat(1e-15),
        geo_normal: DVec3::new(0.0, 0.3, 0.8),
        material: 7,
        path: 5,
    };
    let f = h.flipped();
    assert_eq!(f.normal, -h.normal);
    assert_eq!(f.geo_normal, -h.geo_normal);
    assert_eq!(
        Hit {
            normal: h.normal,
            geo_normal: h.geo_normal,
            ..f
        },
        h
    );
    let mut g = h;
    g.flip();
    assert_eq!(g, f);
    g.flip();
    assert_eq!(g, h);
}

/// The exact error of o + t·d (t·d's product error by fma, the sum's by
/// two-sum) lies within `ray_point_error`, which is a few roundings of
/// the magnitudes: at least the rounding of the result, at most γ₂ of
/// |o| + |t·d| — for origins and directions of sizes far apart, t of
/// either sign, and sums that cancel.
#[test]
fn the_ray_points_error_bound_holds_the_exact_error() {
    let mut rnd = numbers(9);
    let mut inexact = 0;
    for i in 0..3000 {
        let o = DVec3::new(rnd(), rnd(), rnd()) * 10f64.powi((i % 5) * 2 - 4);
        let d = DVec3::new(rnd(), rnd(), rnd()) * 10f64.powi((i / 5 % 5) * 2 - 4);
        let t = rnd() * 10f64.powi((i / 25 % 3) * 2 - 2);
        let ray = Ray::new(o, d);
        let p = ray.at(t);
        let e = ray_point_error(&ray, t);
        for k in 0..3 {
            let prod = t * d[k];
            let prod_err = t.mul_add(d[k], -prod);
            let sum = o[k] + prod;
            let bv = sum - o[k];
            let sum_err = (o[k] - (sum - bv)) + (prod - bv);
            assert_eq!(sum, p[k]);
            let exact_err = (prod_err + sum_err).abs();
            assert!(exact_err <= e[k], "{o} + {t}·{d}: {exact_err} vs {}", e[k]);
            assert!(e[k] >= 0.5 * f64::EPSILON * p[k].abs(), "{}", e[k]);
            assert!(e[k] <= gamma(2) * (o[k].abs() + prod.abs()) * (1.0 + 1e-12));
            inexact += (exact_err > 0.0) as usize;
        }
    }
    assert!(inexact > 3000, "{inexact}");
}

/// A crossing's facing is normal·dir, whatever their lengths; it is
/// grazing when the angle's cosine is within 1e-9 of 0 (the sign is
/// rounding noise there) and not a little beyond, for normals and
/// directions from 1e-3 to 1e3 long.
#[test]
fn a_crossing_faces_by_the_normal_and_grazes_only_edge_on() {
    let ray_along = |d: DVec3| Ray::new(DVec3::new(1.0, 2.0, 3.0), d);
    for (ln, ld) in [(1.0, 1.0), (1e3, 1e-3), (1e-3, 1e3), (7.0, 0.01)] {
        for cos in [0.0f64, 1e-12, -3e-10, 9e-10, -1.1e-9, 3e-9, 1e-6, -0.5, 1.0] {
            let n = DVec3::Y * ln;
            let sin = (1.0 - cos * cos).sqrt();
            let d = DVec3::new(sin, cos, 0.0) * ld;
            let c = Crossing::new(4.0, n, &ray_along(d), 9);
            assert_eq!((c.t, c.key), (4.0, 9));
            assert_eq!(c.facing, n.dot(d));
            assert_eq!(c.grazing, cos.abs() < 1e-9, "cos {cos}, |n| {ln}, |d| {ld}");
        }
    }
}

/// The default light route, as triangles and rectangles take it: each
/// crossing of `crossings_lite` is the full hit's t, facing and place in
/// the list, and `hit_of` gives that hit back. A crossing it cannot find
/// again (a key past the list: CSG's last resort) still gives a hit at
/// its t, on the ray, facing as the crossing did, with the ray point's
/// error bound.
#[test]
fn the_default_light_route_gives_back_the_full_hits() {
    let _watchdog = crate::watchdog::start();
    let shapes: [Box<dyn Shape>; 2] = [
        Box::new(Triangle::new(
            DVec3::new(-1.0, -1.0, 0.2),
            DVec3::new(1.0, -0.7, -0.1),
            DVec3::new(0.1, 1.0, 0.3),
            4,
        )),
        Box::new(Rectangle::new(
            DVec3::new(-1.0, -1.0, 0.1),
            DVec3::new(-0.8, 1.0, 0.3),
            DVec3::new(1.0, -1.0, -0.2),
            4,
        )),
    ];
    for s in &shapes {
        let mut met = 0;
        for r in testing::rays_towards(DVec3::ZERO, 1.0, 600, 3) {
            let mut xs = Vec::new();
            s.crossings(&r, &mut xs);
            let mut lite = vec![Crossing::new(-1.0, DVec3::X, &r, 99)];
            s.crossings_lite(&r, &mut lite);
            assert_eq!(lite.len(), xs.len() + 1, "appends");
            for (k, (x, l)) in xs.iter().zip(&lite[1..]).enumerate() {
                assert_eq!(*l, Crossing::new(x.t, x.normal, &r, k as u64));
                assert_eq!(s.hit_of(&r, l), *x);
            }
            met += xs.len();
            for (t, facing) in [(2.5, -0.3), (7.0, 0.2)] {
                let c = Crossing {
                    t,
                    facing,
                    grazing: false,
                    key: 5,
                };
                let h = s.hit_of(&r, &c);
                assert_eq!((h.t, h.point), (t, r.at(t)));
                assert_eq!(h.p_error, ray_point_error(&r, t));
                assert_eq!(h.normal.dot(r.dir).signum(), facing.signum());
                assert_eq!(h.geo_normal, h.normal);
                assert!((h.normal.normalize() - r.dir * facing.signum()).length() < 1e-12);
            }
        }
        assert!(met > 100, "{met}");
    }
}

/// The barycentric point is b₀v₀ + b₁v₁ + b₂v₂ to its rounding, and its
/// error bound holds the exact point (each product's error by fma, the
/// sums' by two-sum) yet stays γ₇ of the terms' magnitudes. At least the
/// largest term's rounding, even where the terms cancel: the bound must
/// not shrink with the point (terms like 1/3 − 2/3 + 1/3, or 1e-3 ·
/// 1e-3 against a tiny third).
#[test]
fn the_barycentric_points_bound_holds_the_exact_point() {
    let mut rnd = numbers(21);
    let two_sum = |a: f64, b: f64| {
        let s = a + b;
        let bv = s - a;
        (s, (a - (s - bv)) + (b - bv))
    };
    let mut cases: Vec<([DVec3; 3], [f64; 3])> = (0..2000)
        .map(|i| {
            let scale = 10f64.powi((i % 5) * 2 - 4);
            let v = [(); 3].map(|_| DVec3::new(rnd(), rnd(), rnd()) * scale);
            let b = [rnd().abs(), rnd().abs(), rnd().abs()];
            let sum = b[0] + b[1] + b[2];
            (v, b.map(|x| x / sum))
        })
        .collect();
    let third = 1.0 / 3.0;
    cases.push(([DVec3::ONE, -2.0 * DVec3::ONE, DVec3::ONE], [third; 3]));
    cases.push(([DVec3::ONE, DVec3::ONE, -2.0 * DVec3::ONE], [third; 3]));
    cases.push(([-2.0 * DVec3::ONE, DVec3::ONE, DVec3::ONE], [third; 3]));
    cases.push((
        [DVec3::splat(1e-3), DVec3::splat(-1e-3), DVec3::splat(1e-9)],
        [1e-3, 1e-3, 1.0],
    ));
    cases.push((
        [DVec3::splat(1e-9), DVec3::splat(1e-3), DVec3::splat(-1e-3)],
        [1.0, 1e-3, 1e-3],
    ));
    for (v, b) in cases {
        let (p, e) = barycentric_point(v, b);
        for k in 0..3 {
            let terms = [v[0][k] * b[0], v[1][k] * b[1], v[2][k] * b[2]];
            let errs = [0, 1, 2].map(|i| v[i][k].mul_add(b[i], -terms[i]));
            let (s01, e01) = two_sum(terms[0], terms[1]);
            let (s, e2) = two_sum(s01, terms[2]);
            assert_eq!(s, p[k]);
            let exact_err = (errs[0] + errs[1] + errs[2] + e01 + e2).abs();
            assert!(exact_err <= e[k], "{v:?} {b:?}: {exact_err} vs {}", e[k]);
            let mags = terms.map(f64::abs);
            let largest = mags[0].max(mags[1]).max(mags[2]);
            assert!(e[k] >= f64::EPSILON * largest, "{v:?} {b:?}: {}", e[k]);
            assert!(e[k] <= gamma(7) * (mags[0] + mags[1] + mags[2]) * (1.0 + 1e-12));
        }
    }
}

/// The trait's defaults: a shadow ray is blocked exactly when the nearest
/// hit is in the window; a shape is never said to miss a shadow shaft it
/// may meet (the default is "unsure"), even one it cuts through; no
/// point is enclosed (only unbounded shapes answer that); (u, v) are the
/// hit's own; a normal from the shape's space is the world's as it is.
#[test]
fn the_traits_defaults_answer_from_the_required_methods() {
    let _watchdog = crate::watchdog::start();
    let sphere = Sphere::new(DVec3::new(0.2, -0.1, 0.3), 1.0, 6);
    let s = Bare(&sphere);
    let mut blocked = 0;
    for r in testing::rays_towards(DVec3::ZERO, 1.5, 300, 8) {
        let first = s.intersect(&r, 0.0, f64::INFINITY).map(|h| h.t);
        let t = first.unwrap_or(10.0);
        for (lo, hi) in [(0.0, f64::INFINITY), (0.0, 0.999 * t), (0.0, 1.001 * t)] {
            let want = s.intersect(&r, lo, hi).is_some();
            assert_eq!(s.occludes(&r, lo, hi), want, "({lo}, {hi}) {r:?}");
            blocked += want as usize;
        }
        if let Some(h) = s.intersect(&r, 0.0, f64::INFINITY) {
            let h = Hit {
                uv: DVec2::new(0.25, 0.5),
                ..h
            };
            assert_eq!(s.uv(&h), DVec2::new(0.25, 0.5));
            let v = DVec3::new(0.3, -2.0, 0.7);
            assert_eq!(s.normal_to_world(&h, v), v);
        }
    }
    assert!(blocked > 200, "{blocked}");
    let (a, b) = (DVec3::new(0.2, 3.0, 0.3), DVec3::new(0.2, -3.0, 0.3));
    assert!(!s.misses_hull(&[a, b]));
    assert!(!s.misses_hull(&[a, b, DVec3::new(2.0, 0.0, 0.0)]));
    assert!(!s.encloses(DVec3::new(0.2, -0.1, 0.3)));
}

/// The watertight test's answer is a point of the triangle: weights that
/// are each at least 0 and sum to 1, whose blend of the corners is the
/// line's point at t, for random triangles at several scales and lines
/// through them from every side (all six permutations of the axes).
#[test]
fn the_watertight_tests_weights_give_the_point_at_t() {
    let _watchdog = crate::watchdog::start();
    let mut rnd = numbers(22);
    let mut hits = 0;
    for i in 0..3000 {
        let scale = 10f64.powi((i % 5) * 2 - 4);
        let v = [(); 3].map(|_| DVec3::new(rnd(), rnd(), rnd()) * scale);
        let b = [rnd().abs() + 0.01, rnd().abs() + 0.01, rnd().abs() + 0.01];
        let sum = b[0] + b[1] + b[2];
        let aim = (v[0] * b[0] + v[1] * b[1] + v[2] * b[2]) / sum;
        let dir = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::Z);
        let ray = Ray::new(aim - dir * (3.0 * scale), dir);
        let Some((t, w)) = ShearedRay::new(&ray).triangle(v[0], v[1], v[2]) else {
            continue;
        };
        hits += 1;
        assert!(w.iter().all(|&x| x >= 0.0), "{w:?}");
        assert!((w[0] + w[1] + w[2] - 1.0).abs() < 1e-12, "{w:?}");
        let p = v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
        let err = (p - ray.at(t)).length();
        // Far from edge-on, the point is well conditioned in t.
        let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
        if n.dot(dir).abs() > 0.1 {
            assert!(err < 1e-9 * scale, "{err} at scale {scale}: {w:?}");
        }
    }
    assert!(hits > 2500, "{hits}");
}

/// A triangle so large (corners 0.8e154 from the line) that the sum of
/// its edge functions overflows, though each is finite: the test cannot
/// place the crossing and reports none, rather than a made-up one (t = 0
/// with zero weights, off the triangle's plane).
#[test]
fn a_triangle_whose_edge_functions_overflow_is_not_hit_anywhere_else() {
    let _watchdog = crate::watchdog::start();
    let s = 0.8e154;
    let (v0, v1, v2) = (
        DVec3::new(-s, -s, 0.1),
        DVec3::new(s, -s, 0.1),
        DVec3::new(0.0, s, 0.1),
    );
    for dir in [DVec3::Z, -DVec3::Z] {
        let ray = Ray::new(DVec3::new(0.0, 0.0, 0.1) - 0.1 * dir, dir);
        if let Some((t, w)) = ShearedRay::new(&ray).triangle(v0, v1, v2) {
            assert!((t - 0.1).abs() < 1e-12, "{t} {w:?}");
            assert!((w[0] + w[1] + w[2] - 1.0).abs() < 1e-12, "{t} {w:?}");
        }
    }
}
