//! Unit tests of `cone.rs` (cones and cylinders), kept in their own file
//! so the module reads as the code alone.

use super::*;
use crate::shapes::testing;

fn hit(s: &dyn Shape, o: DVec3, d: DVec3) -> Option<Hit> {
    s.intersect(&Ray::new(o, d), 1e-9, f64::INFINITY)
}

#[test]
fn seen_from_1e8_covers_the_analytic_area() {
    // Side on, a capped cone of radius 1 and height 2 is a triangle of
    // area r·h = 2, and a cylinder a 2×2 square; the raw quadratic lost
    // the radius from far away.
    let cone = Cone::new(DVec3::ZERO, 1.0, 0.0, 2.0, 0, Some([0, 0]));
    let tube = Cone::new(DVec3::ZERO, 1.0, 1.0, 2.0, 0, Some([0, 0]));
    for eye in [1e2, 1e8, 1e12] {
        let at = DVec3::new(0.0, 0.0, eye);
        let a = testing::silhouette_area(&cone, at, 1.2, 300);
        assert!((a / 2.0 - 1.0).abs() < 0.01, "cone from {eye}: {a} vs 2");
        let a = testing::silhouette_area(&tube, at, 1.2, 300);
        assert!(
            (a / 4.0 - 1.0).abs() < 0.01,
            "cylinder from {eye}: {a} vs 4"
        );
    }
}

#[test]
fn pointed_cone_side_and_base() {
    // Base radius 1 at y = 0, apex at y = 2.
    let c = Cone::new(DVec3::new(0.0, 1.0, 0.0), 1.0, 0.0, 2.0, 1, Some([2, 3]));
    // At height 1 the radius is 0.5.
    let h = hit(&c, DVec3::new(5.0, 1.0, 0.0), -DVec3::X).unwrap();
    assert!((h.t - 4.5).abs() < 1e-12 && h.material == 1);
    // The side slopes: normal ∝ (1, 0.5, 0) (gradient of x² + z² − (1 − y/2)²).
    let expected = DVec3::new(1.0, 0.5, 0.0).normalize();
    assert!((h.normal.normalize() - expected).length() < 1e-12);
    let h = hit(&c, DVec3::new(0.2, -5.0, 0.3), DVec3::Y).unwrap();
    assert!((h.t - 5.0).abs() < 1e-12 && h.normal == -DVec3::Y && h.material == 3);
    // Cap uv like a disc in the x-z plane.
    assert!((c.uv(&h) - DVec2::new(0.6, 0.65)).length() < 1e-12);
    // Down the axis from above: the apex, then the base.
    let mut xs = Vec::new();
    c.crossings(&Ray::new(DVec3::new(0.0, 5.0, 0.0), -DVec3::Y), &mut xs);
    assert_eq!(xs.len(), 2);
    assert!((xs[0].t - 3.0).abs() < 1e-9 && (xs[1].t - 5.0).abs() < 1e-12);
    assert!(xs[0].normal.is_finite() && xs[0].normal.dot(DVec3::Y) > 0.0);
}

#[test]
fn frustum_side_uv_and_open() {
    let c = Cone::new(DVec3::ZERO, 1.0, 0.5, 1.0, 1, None);
    assert!(!c.is_solid());
    // At y = 0 the radius is 0.75; +z side is u = 0, mid height v = 0.5.
    let h = hit(&c, DVec3::new(0.0, 0.0, 5.0), -DVec3::Z).unwrap();
    assert!((h.t - 4.25).abs() < 1e-12);
    assert!((c.uv(&h) - DVec2::new(0.0, 0.5)).length() < 1e-12);
    // +x is a quarter turn.
    let h = hit(&c, DVec3::new(5.0, 0.25, 0.0), -DVec3::X).unwrap();
    assert!((c.uv(&h) - DVec2::new(0.25, 0.75)).length() < 1e-12);
    // Open: straight down the axis passes through.
    assert!(hit(&c, DVec3::new(0.0, 5.0, 0.0), -DVec3::Y).is_none());
    // From inside the open frustum, the inside of the wall.
    let h = hit(&c, DVec3::ZERO, DVec3::X).unwrap();
    assert!((h.t - 0.75).abs() < 1e-12 && h.normal.x > 0.0);
}

#[test]
fn degenerate_never_hits() {
    let rays = testing::rays_towards(DVec3::ZERO, 1.0, 50, 3);
    for c in [
        Cone::new(DVec3::ZERO, 0.0, 0.0, 1.0, 0, Some([0, 0])),
        Cone::new(DVec3::ZERO, 1.0, 0.0, 0.0, 0, Some([0, 0])),
        Cone::new(DVec3::ZERO, f64::NAN, 0.0, 1.0, 0, None),
    ] {
        for r in &rays {
            assert!(c.intersect(r, 0.0, f64::INFINITY).is_none());
        }
    }
}

#[test]
fn properties() {
    let centre = DVec3::new(1.0, 2.0, -1.0);
    let solid = Cone::new(centre, 1.5, 0.3, 2.0, 1, Some([2, 3]));
    let pointed = Cone::new(centre, 1.0, 0.0, 3.0, 1, Some([2, 3]));
    let open = Cone::new(centre, 0.5, 1.5, 2.0, 1, None);
    for (i, c) in [&solid, &pointed, &open].into_iter().enumerate() {
        let rays = testing::rays_towards(centre, 2.0, 500, 11 + i as u64);
        testing::check_consistency(c, &rays);
        testing::check_no_rehit(c, &rays);
        assert!(testing::check_normals(c, &rays) > 100);
        if c.is_solid() {
            testing::check_alternation(c, &rays);
        }
    }
}

/// The window is open at both ends (`t_min < t < t_max`, as for every
/// shape): a crossing exactly at either end is outside it. Across a
/// unit cylinder, solid and open, and a cone whose side is 1 from the
/// axis at y = 0, the ray meets the side at exactly t = 4 and t = 6.
#[test]
fn a_crossing_exactly_at_a_window_end_is_outside() {
    let r = Ray::new(DVec3::new(0.0, 0.0, 5.0), -DVec3::Z);
    for c in [
        Cone::new(DVec3::ZERO, 1.0, 1.0, 2.0, 0, Some([0, 0])),
        Cone::new(DVec3::ZERO, 1.0, 1.0, 2.0, 0, None),
        Cone::new(DVec3::ZERO, 1.5, 0.5, 2.0, 0, Some([0, 0])),
    ] {
        let mut xs = Vec::new();
        c.crossings(&r, &mut xs);
        assert_eq!(xs.iter().map(|h| h.t).collect::<Vec<_>>(), [4.0, 6.0]);
        let t = |lo: f64, hi: f64| c.intersect(&r, lo, hi).map(|h| h.t);
        assert_eq!(t(4.0, 99.0), Some(6.0));
        assert!(c.occludes(&r, 4.0, 99.0));
        for (lo, hi) in [(0.0, 4.0), (6.0, 99.0), (4.0, 6.0)] {
            assert_eq!(t(lo, hi), None, "({lo}, {hi})");
            assert!(!c.occludes(&r, lo, hi), "({lo}, {hi})");
        }
        assert_eq!(t(0.0, 4.0 + 1e-9), Some(4.0));
        assert_eq!(t(6.0 - 1e-9, 99.0), Some(6.0));
        assert!(c.occludes(&r, 6.0 - 1e-9, 99.0));
    }
}

/// The light route (`crossings_lite`, then `hit_of` for the one CSG
/// keeps) gives the same crossings as `crossings`: the same t, facing
/// in where the ray enters and out where it leaves (the outward
/// normal's side), and the same hit — surface, normal, point,
/// material. Solid, pointed and open, with the side and each cap in
/// their own material.
#[test]
fn crossings_lite_and_hit_of_agree_with_crossings() {
    let centre = DVec3::new(1.0, 2.0, -1.0);
    // (the shape, how many surfaces: a point has no top cap)
    for (c, surfaces) in [
        (Cone::new(centre, 1.5, 0.3, 2.0, 1, Some([2, 3])), 3),
        (Cone::new(centre, 1.0, 0.0, 3.0, 1, Some([2, 3])), 2),
        (Cone::new(centre, 0.5, 1.5, 2.0, 1, None), 1),
    ] {
        let mut materials = std::collections::HashSet::new();
        let mut met = 0;
        for r in testing::rays_towards(centre, 2.0, 400, 29) {
            let mut xs = Vec::new();
            c.crossings(&r, &mut xs);
            let mut lite = Vec::new();
            c.crossings_lite(&r, &mut lite);
            assert_eq!(xs.len(), lite.len());
            for (x, l) in xs.iter().zip(&lite) {
                assert_eq!(l.t, x.t);
                let h = c.hit_of(&r, l);
                assert_eq!(
                    (h.t, h.point, h.normal, h.material),
                    (x.t, x.point, x.normal, x.material)
                );
                if !l.grazing {
                    assert_eq!(l.facing.signum(), x.normal.dot(r.dir).signum());
                }
                materials.insert(x.material);
            }
            if c.is_solid() && !xs.is_empty() {
                assert!(lite[0].facing < 0.0 && lite[1].facing > 0.0, "{lite:?}");
            }
            met += !xs.is_empty() as usize;
        }
        assert!(met > 100, "{met}");
        assert_eq!(materials.len(), surfaces, "{materials:?}");
    }
}

/// The box is the wider end's radius across and the height tall about
/// the centre, and holds every hit; shadow rays agree with the
/// crossings in every window; capped is solid, open is not.
#[test]
fn bounds_shadows_and_solidity() {
    let centre = DVec3::new(1.0, 2.0, -1.0);
    for (c, solid) in [
        (Cone::new(centre, 1.5, 0.3, 2.0, 1, Some([2, 3])), true),
        (Cone::new(centre, 0.5, 1.5, 3.0, 1, None), false),
    ] {
        let (r, h) = if solid { (1.5, 1.0) } else { (1.5, 1.5) };
        let e = DVec3::new(r, h, r);
        assert_eq!(c.bounds(), Aabb::new(centre - e, centre + e));
        let rays = testing::rays_towards(centre, 2.0, 400, 31);
        assert!(testing::check_bounds_hold_hits(&c, &rays) > 100);
        assert!(testing::check_occludes_agrees(&c, &rays) > 100);
        assert_eq!(c.is_solid(), solid);
    }
}

/// A hit's point is put back on its surface: a side point's distance
/// from the axis is the radius at its height, a cap's point is on the
/// cap's plane within its rim, up to a few roundings; and its error
/// bound is a few roundings of the magnitudes involved (never
/// negative, never a multiple of the shape's size), near the origin
/// and far from it, for a frustum, a cylinder and a pointed cone.
#[test]
fn hit_points_are_on_the_surface_with_a_rounding_sized_error() {
    let eps = f64::EPSILON;
    for centre in [DVec3::new(0.1, -0.2, 0.3), DVec3::new(1e3, -2e3, 5e2)] {
        for (r0, r1) in [(1.5, 0.3), (0.8, 0.8), (1.0, 0.0)] {
            let c = Cone::new(centre, r0, r1, 2.0, 1, Some([2, 3]));
            let (y0, y1) = (centre.y - 1.0, centre.y + 1.0);
            let mag = centre.abs().max_element() + 2.0;
            let mut sides = 0;
            for ray in testing::rays_towards(centre, 2.0, 300, 37) {
                let mut xs = Vec::new();
                c.crossings(&ray, &mut xs);
                for h in &xs {
                    let e = h.p_error;
                    assert!(e.min_element() >= 0.0, "{e:?}");
                    assert!(e.max_element() <= 16.0 * eps * mag, "{e:?} vs {mag}");
                    let q = h.point - centre;
                    let rho = q.x.hypot(q.z);
                    match h.material {
                        1 => {
                            let r = r0 + (r1 - r0) * (h.point.y - y0) / 2.0;
                            let off = (rho - r).abs();
                            assert!(off <= 16.0 * eps * mag, "{off} off the side");
                            assert!(h.point.y >= y0 - 1e-9 && h.point.y <= y1 + 1e-9);
                            sides += 1;
                        }
                        2 => {
                            assert_eq!(h.point.y, y1);
                            assert!(rho <= r1 * (1.0 + 1e-9), "{rho}");
                        }
                        _ => {
                            assert_eq!(h.point.y, y0);
                            assert!(rho <= r0 * (1.0 + 1e-9), "{rho}");
                        }
                    }
                }
            }
            assert!(sides > 50, "{sides}");
        }
    }
}

/// The rims belong to the surface. A horizontal ray exactly at the
/// height of an open tube's rim meets the tube there; the same ray
/// against a solid cylinder meets its side at the rim, which is shaded
/// as side (v = 0 or 1), not cap; a ray straight down the wall of a
/// solid cylinder (at exactly the radius) meets both caps at their
/// rims.
#[test]
fn rims_belong_to_the_surface() {
    let open = Cone::cylinder(DVec3::ZERO, 1.0, 2.0, 1, None);
    let solid = Cone::cylinder(DVec3::ZERO, 1.0, 2.0, 1, Some([2, 3]));
    for (y, v) in [(1.0, 1.0), (-1.0, 0.0)] {
        let r = Ray::new(DVec3::new(0.0, y, 5.0), -DVec3::Z);
        let h = open.intersect(&r, 0.0, 99.0).expect("the open rim");
        assert_eq!((h.t, h.point), (4.0, DVec3::new(0.0, y, 1.0)));
        let h = solid.intersect(&r, 0.0, 99.0).expect("the solid's rim");
        assert_eq!((h.t, h.material, h.normal), (4.0, 1, DVec3::Z));
        assert!((solid.uv(&h) - DVec2::new(0.0, v)).length() < 1e-12);
    }
    for p in [DVec3::new(1.0, 5.0, 0.0), DVec3::new(0.0, 5.0, -1.0)] {
        let mut xs = Vec::new();
        solid.crossings(&Ray::new(p, -DVec3::Y), &mut xs);
        let got: Vec<_> = xs.iter().map(|h| (h.t, h.material)).collect();
        assert_eq!(got, [(4.0, 2), (6.0, 3)], "down the wall at {p:?}");
    }
}

/// A line parallel to one of a cone's generators (its quadratic term
/// vanishes) still meets the side once: here up the cone of radius 1
/// at y = −1 and apex at y = 1, through the base at x = 0.5 and out
/// of the side at (−0.25, 0.5, 0), where the radius is 0.25.
#[test]
fn a_line_along_a_generator_meets_the_side_once() {
    let c = Cone::new(DVec3::ZERO, 1.0, 0.0, 2.0, 1, Some([2, 3]));
    let open = Cone::new(DVec3::ZERO, 1.0, 0.0, 2.0, 1, None);
    // Directions of several lengths: t scales, the points do not.
    for k in [1.0, 3.0, 0.25] {
        let r = Ray::new(DVec3::new(1.5, -3.0, 0.0), DVec3::new(-1.0, 2.0, 0.0) * k);
        let mut xs = Vec::new();
        c.crossings(&r, &mut xs);
        assert_eq!(xs.len(), 2, "{k}");
        assert!((xs[0].t * k - 1.0).abs() < 1e-12 && xs[0].material == 3);
        assert!(
            (xs[1].t * k - 1.75).abs() < 1e-12 && xs[1].material == 1,
            "{xs:?}"
        );
        assert!((xs[1].point - DVec3::new(-0.25, 0.5, 0.0)).length() < 1e-12);
        let h = open.intersect(&r, 0.0, 99.0).unwrap();
        assert!((h.t * k - 1.75).abs() < 1e-12, "{k}");
    }
}

/// The side's u is in [0, 1): a point a hair west of +z (x = −1e−20)
/// has u = 1 − 1.6e−21, which rounds to 1 and is held just below it.
#[test]
fn side_u_stays_below_one_at_the_seam() {
    let c = Cone::cylinder(DVec3::ZERO, 1.0, 2.0, 1, None);
    let h = c
        .intersect(&Ray::new(DVec3::new(-1e-20, 0.0, 5.0), -DVec3::Z), 0.0, 9.0)
        .unwrap();
    let uv = c.uv(&h);
    assert!(uv.x < 1.0 && uv.x > 0.999, "{uv:?}");
}

/// At the apex the side has no normal of its own; the crossing there
/// still faces the way the ray goes in: down the axis of an upright
/// cone the apex is entered (facing < 0), the base left.
#[test]
fn the_apex_is_entered_from_above() {
    let c = Cone::new(DVec3::new(0.0, 1.0, 0.0), 1.0, 0.0, 2.0, 1, Some([2, 3]));
    let r = Ray::new(DVec3::new(0.0, 5.0, 0.0), -DVec3::Y);
    let mut lite = Vec::new();
    c.crossings_lite(&r, &mut lite);
    assert_eq!(lite.len(), 2);
    assert!(
        (lite[0].t - 3.0).abs() < 1e-9 && lite[0].facing < 0.0,
        "{lite:?}"
    );
    assert!(lite[1].t == 5.0 && lite[1].facing > 0.0, "{lite:?}");
    let h = c.hit_of(&r, &lite[0]);
    assert!(h.normal.is_finite() && h.normal.dot(DVec3::Y) > 0.0);
}

/// The rim's slack is relative to the shape's size: a ray passing 1%
/// of the height above the rim of a small open tube (height 1e−4)
/// misses it, and one 1e−9 of the height below it hits, as for a
/// tube of unit size.
#[test]
fn passing_just_above_a_small_tubes_rim_misses_it() {
    for size in [1e-4, 1.0, 1e3] {
        let tube = Cone::cylinder(DVec3::ZERO, size, 2.0 * size, 1, None);
        let at = |y: f64| {
            let r = Ray::new(DVec3::new(0.0, y, 5.0 * size), -DVec3::Z);
            tube.intersect(&r, 0.0, f64::INFINITY)
        };
        assert!(at(1.01 * size).is_none(), "{size}");
        assert!(at(-1.01 * size).is_none(), "{size}");
        assert!(at((1.0 - 1e-9) * size).is_some(), "{size}");
        assert!(at(-(1.0 - 1e-9) * size).is_some(), "{size}");
    }
}

/// A pointed cone has no top cap: a ray through its apex, from any
/// direction above, meets it there as side (the side's material), not
/// as a cap of radius 0 (the point within the double root's √ε of it).
#[test]
fn the_apex_of_a_pointed_cone_is_side_not_cap() {
    let c = Cone::new(DVec3::new(0.2, 1.0, -0.3), 1.0, 0.0, 2.0, 1, Some([2, 3]));
    let apex = DVec3::new(0.2, 2.0, -0.3);
    let mut met = 0;
    for i in 0..40 {
        let phi = 0.7 * i as f64;
        let up = 0.2 + 0.8 * (i as f64 / 40.0);
        let u = DVec3::new(
            phi.cos() * (1.0 - up * up).sqrt(),
            up,
            phi.sin() * (1.0 - up * up).sqrt(),
        );
        let r = Ray::new(apex + 5.0 * u, -u);
        let mut xs = Vec::new();
        c.crossings(&r, &mut xs);
        if let Some(h) = xs.first() {
            assert!((h.point - apex).length() < 1e-6, "{h:?}");
            assert_eq!(h.material, 1, "through the apex along {:?}", -u);
            met += 1;
        }
    }
    assert!(met > 10, "{met}");
}

/// An upside-down cone (radius 0 at the bottom) has its apex below:
/// up the axis from beneath, the apex is entered (facing < 0) with a
/// normal pointing down, out of the cone, and the top cap is left.
#[test]
fn the_apex_of_an_upside_down_cone_faces_down() {
    let c = Cone::new(DVec3::new(0.0, 1.0, 0.0), 0.0, 1.0, 2.0, 1, Some([2, 3]));
    let r = Ray::new(DVec3::new(0.0, -3.0, 0.0), DVec3::Y);
    let mut lite = Vec::new();
    c.crossings_lite(&r, &mut lite);
    assert_eq!(lite.len(), 2);
    assert!(
        (lite[0].t - 3.0).abs() < 1e-9 && lite[0].facing < 0.0,
        "{lite:?}"
    );
    assert!(lite[1].t == 5.0 && lite[1].facing > 0.0, "{lite:?}");
    let h = c.hit_of(&r, &lite[0]);
    assert!(h.normal.dot(-DVec3::Y) > 0.9, "{:?}", h.normal);
    let h = c.intersect(&r, 0.0, 9.0).unwrap();
    assert!(h.normal.dot(-DVec3::Y) > 0.9, "{:?}", h.normal);
}

/// A cap's hit carries its texture coordinates itself (some shading
/// reads `hit.uv` directly): the disc's (x − c.x + r)/2r,
/// (z − c.z + r)/2r, the same as the shape's `uv`, for a frustum away
/// from the origin with caps of different radii.
#[test]
fn a_caps_hit_carries_its_uv() {
    let centre = DVec3::new(2.0, -1.0, 3.0);
    let c = Cone::new(centre, 1.5, 0.5, 2.0, 1, Some([2, 3]));
    for (y, dir, r) in [(5.0, -DVec3::Y, 0.5), (-5.0, DVec3::Y, 1.5)] {
        for (x, z) in [(0.1, -0.3), (-0.4, 0.2)] {
            let o = centre + DVec3::new(x, y, z);
            let h = c.intersect(&Ray::new(o, dir), 0.0, 99.0).unwrap();
            let want = DVec2::new((x + r) / (2.0 * r), (z + r) / (2.0 * r));
            assert!((h.uv - want).length() < 1e-12, "{:?} vs {want:?}", h.uv);
            assert!((c.uv(&h) - want).length() < 1e-12);
        }
    }
}

/// A capped frustum's side near its wide end is side, not cap: its
/// points lie inside the wide cap's rim (seen from above), but 5% of
/// the height away from its plane, so their uv is the side's
/// (v = 0.05 above the base), at every size.
#[test]
fn side_near_the_wide_cap_has_the_sides_uv() {
    for size in [1e-4, 1.0, 1e3] {
        let c = Cone::new(DVec3::ZERO, 1.5 * size, 0.5 * size, size, 1, Some([2, 3]));
        let y = -0.45 * size;
        let r = Ray::new(DVec3::new(0.0, y, 5.0 * size), -DVec3::Z);
        let h = c.intersect(&r, 0.0, f64::INFINITY).unwrap();
        assert_eq!(h.material, 1);
        let uv = c.uv(&h);
        assert!(
            (uv - DVec2::new(0.0, 0.05)).length() < 1e-9,
            "{uv:?} at {size}"
        );
    }
}

/// Seen from far away (1e6 to 1e8), t carries a rounding of the
/// distance, and o + t·d is off the side by far more than the shape's
/// own rounding: the side's hit point is pulled back onto it (its
/// distance from the axis the radius at its height, to a few
/// roundings of the shape's size), with a bound of that size too.
#[test]
fn side_hits_from_far_away_are_pulled_onto_the_side() {
    let eps = f64::EPSILON;
    let centre = DVec3::new(0.1, -0.2, 0.3);
    for (r0, r1) in [(1.5, 0.3), (0.8, 0.8)] {
        let c = Cone::new(centre, r0, r1, 2.0, 1, Some([2, 3]));
        let mag = centre.abs().max_element() + 2.0;
        let mut sides = 0;
        for far in [1e6, 1e8] {
            for r in testing::rays_towards(centre, 1.5, 200, 41) {
                let o = centre + (r.origin - centre) * (far / 10.0);
                let aim = centre + (r.origin + r.dir * 10.0 - centre) * 1.0;
                let ray = Ray::new(o, (aim - o).normalize());
                let Some(h) = c.intersect(&ray, 0.0, f64::INFINITY) else {
                    continue;
                };
                if h.material != 1 {
                    continue;
                }
                let q = h.point - centre;
                let r = r0 + (r1 - r0) * (h.point.y - (centre.y - 1.0)) / 2.0;
                let off = (q.x.hypot(q.z) - r).abs();
                assert!(off <= 16.0 * eps * mag, "{off} off the side from {far:e}");
                let e = h.p_error;
                assert!(e.max_element() <= 16.0 * eps * mag, "{e:?} from {far:e}");
                sides += 1;
            }
        }
        assert!(sides > 100, "{sides}");
    }
}

/// At the apex the side point is not pulled anywhere (no direction
/// from the axis): its error bound must still be non-negative and a
/// few roundings of the cone's size, from near and from far above.
#[test]
fn the_apex_hit_has_a_rounding_sized_bound() {
    let c = Cone::new(DVec3::new(0.0, 1.0, 0.0), 2.0, 0.0, 2.0, 1, Some([2, 3]));
    for y in [2.5, 5.0, 1e3] {
        let r = Ray::new(DVec3::new(0.0, y, 0.0), -DVec3::Y);
        let h = c.intersect(&r, 0.0, f64::INFINITY).unwrap();
        assert_eq!(h.point, DVec3::new(0.0, 2.0, 0.0));
        let e = h.p_error;
        assert!(e.min_element() >= 0.0, "{e:?}");
        assert!(e.max_element() <= 16.0 * f64::EPSILON * y, "{e:?}");
    }
}

/// The side's error bound at other sizes and slopes: tiny (1e−3) near
/// the origin, widening upwards, and steep (height 0.2) far from the
/// origin. A side point's bound is non-negative and a few roundings of
/// the magnitudes involved (the centre's and the shape's own), and the
/// point is that close to the side.
#[test]
fn side_error_bounds_at_other_sizes_and_slopes() {
    let eps = f64::EPSILON;
    for (centre, r0, r1, h) in [
        (DVec3::new(2e-4, -1e-4, 3e-4), 1.5e-3, 0.3e-3, 2e-3),
        (DVec3::new(0.0, 1e-4, 0.0), 1e-4, 2e-3, 2e-3),
        (DVec3::new(0.0, 0.1, 0.0), 0.1, 2.0, 2.0),
        (DVec3::new(1e3, -2e3, 5e2), 1.5, 0.3, 0.2),
    ] {
        let c = Cone::new(centre, r0, r1, h, 1, Some([2, 3]));
        let size = r0.max(r1).max(h);
        let mag = centre.abs().max_element() + size;
        let mut sides = 0;
        for ray in testing::rays_towards(centre, size, 300, 43) {
            let mut xs = Vec::new();
            c.crossings(&ray, &mut xs);
            for hit in xs.iter().filter(|x| x.material == 1) {
                let e = hit.p_error;
                assert!(e.min_element() >= 0.0, "{e:?} on {c:?}");
                assert!(e.max_element() <= 16.0 * eps * mag, "{e:?} vs {mag}");
                let q = hit.point - centre;
                let r = r0 + (r1 - r0) * (hit.point.y - (centre.y - h / 2.0)) / h;
                let off = (q.x.hypot(q.z) - r).abs();
                assert!(off <= 16.0 * eps * mag, "{off} off the side");
                sides += 1;
            }
        }
        assert!(sides > 100, "{sides}");
    }
}

/// Hits near a cone's apex, exactly checked: a small cone (radius 2⁻¹⁰,
/// height 2⁻⁹) and a wide one (radius 2¹⁰, height 2¹¹, its apex 2¹⁰
/// from the origin), both of slope −1/2 with the apex on the y axis, so
/// the side at height y is |apex − y|/2 from the axis, exact in f64.
/// A ray along x from the axis at height y meets it there, at
/// x = ±|apex − y|/2: just below the apex (the radius the small
/// difference of r0 and slope·(y − y0), each rounded) and just past it
/// (within the rim's slack, on the surface extended through the apex,
/// where the point is kept and only bounded). Every hit's error box
/// must hold that exact crossing: the point on the ray's own side of
/// the axis, its bound covering the radius's rounding.
#[test]
fn error_boxes_near_the_apex_hold_the_exact_crossing() {
    for scale in [2f64.powi(-10), 2f64.powi(10)] {
        let c = Cone::new(DVec3::ZERO, scale, 0.0, 2.0 * scale, 1, None);
        let apex = scale;
        let mut checked = 0;
        for k in 1..=12 {
            let k = k as f64;
            // Below the apex by up to 1e−6 of the height, past it by
            // up to 6e−10 (the slack is 1e−9).
            // Each with its last bit set, so that y − y0 (about twice
            // as large, its ulp twice y's) rounds.
            let below = f64::from_bits((apex - k * 1.7e-7 * scale).to_bits() | 1);
            let past = f64::from_bits((apex + k * 1e-10 * scale).to_bits() | 1);
            for y in [below, past] {
                for dir in [DVec3::X, -DVec3::X] {
                    let ray = Ray::new(DVec3::new(0.0, y, 0.0), dir);
                    let mut xs = Vec::new();
                    c.crossings(&ray, &mut xs);
                    assert_eq!(xs.len(), 2, "at {y} on {c:?}");
                    for h in &xs {
                        let side = (h.t * dir.x).signum();
                        let exact = DVec3::new(side * (apex - y).abs() / 2.0, y, 0.0);
                        let e = h.p_error;
                        assert!(e.min_element() >= 0.0, "{e:?}");
                        assert!(
                            (h.point - exact).abs().cmple(e).all(),
                            "{:?} ± {e:?} misses {exact:?} (scale {scale})",
                            h.point
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 12 * 2 * 2 * 2);
    }
}

/// A ray passing close by the apex has a double root there, its t off
/// by up to √ε of the size, and its point may land exactly at the
/// apex's height (radius 0) yet off the axis. The only point of the
/// surface at that height is the apex: the point is put there, and its
/// box holds it (the point as it was, kept with a rounding-sized box,
/// would be 1e−6 of the size or more from the surface).
#[test]
fn a_point_at_the_apexs_height_off_the_axis_goes_to_the_apex() {
    for (centre, r0, h) in [
        (DVec3::new(0.0, 1.0, 0.0), 1.0, 2.0),
        (DVec3::new(3e3, -2e3, 1e3), 1e3, 3e3),
    ] {
        let c = Cone::new(centre, r0, 0.0, h, 1, Some([2, 3]));
        let apex = centre + DVec3::new(0.0, h / 2.0, 0.0);
        for off in [DVec3::new(1e-6, 0.0, 0.0), DVec3::new(-2e-6, 0.0, 3e-6)] {
            let off = off * r0;
            let ray = Ray::new(apex + off + DVec3::new(0.0, h, 0.0), -DVec3::Y);
            let p = ray.at(h);
            assert_eq!(p.y, apex.y);
            assert_ne!((p.x, p.z), (apex.x, apex.z));
            let (point, e) = c.frustum.reproject(&ray, h, Surface::Side);
            assert!(e.min_element() >= 0.0, "{e:?}");
            assert!(
                (point - apex).abs().cmple(e).all(),
                "{point:?} ± {e:?} misses the apex {apex:?}"
            );
        }
    }
}
