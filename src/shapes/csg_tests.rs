//! Unit tests of `csg.rs`, kept in their own file so the module reads
//! as the code alone.

use super::*;
use crate::geometry::Transform;
use crate::shapes::{Cone, Cuboid, Plane, Sphere, Transformed, testing};

fn sphere(c: DVec3, r: f64, m: u32) -> Box<dyn Shape> {
    Box::new(Sphere::new(c, r, m))
}

fn cube(lo: DVec3, hi: DVec3, m: u32) -> Box<dyn Shape> {
    Box::new(Cuboid::new(lo, hi, [m; 6]))
}

fn xs(s: &dyn Shape, r: &Ray) -> Vec<Hit> {
    let mut v = Vec::new();
    s.crossings(r, &mut v);
    v
}

/// Same crossings: same t and same outward normal direction.
fn assert_same(a: &[Hit], b: &[Hit], r: &Ray) {
    assert_eq!(a.len(), b.len(), "{a:?}\nvs\n{b:?}\nfor {r:?}");
    for (x, y) in a.iter().zip(b) {
        assert!((x.t - y.t).abs() < 1e-9, "{x:?} vs {y:?}");
        assert!(x.normal.normalize().dot(y.normal.normalize()) > 1.0 - 1e-9);
    }
}

#[test]
fn union_with_itself_is_itself() {
    let _watchdog = crate::watchdog::start();
    let a = || sphere(DVec3::new(0.2, 0.1, 0.0), 1.0, 1);
    let u = Csg::new(CsgOp::Union, vec![a(), a()]);
    let i = Csg::new(CsgOp::Intersection, vec![a(), a()]);
    // A result is a solid again (a crossing list, an inside), so it can be
    // a child of another block.
    assert!(u.is_solid() && i.is_solid());
    for r in testing::rays_towards(DVec3::ZERO, 1.5, 300, 61) {
        let direct = xs(&*a(), &r);
        assert_same(&xs(&u, &r), &direct, &r);
        assert_same(&xs(&i, &r), &direct, &r);
    }
}

#[test]
fn intersection_commutes() {
    let _watchdog = crate::watchdog::start();
    let ab = Csg::new(
        CsgOp::Intersection,
        vec![
            sphere(DVec3::ZERO, 1.2, 1),
            cube(-DVec3::ONE, DVec3::ONE, 2),
        ],
    );
    let ba = Csg::new(
        CsgOp::Intersection,
        vec![
            cube(-DVec3::ONE, DVec3::ONE, 2),
            sphere(DVec3::ZERO, 1.2, 1),
        ],
    );
    let mut seen = 0;
    for r in testing::rays_towards(DVec3::ZERO, 1.5, 500, 62) {
        let (x, y) = (xs(&ab, &r), xs(&ba, &r));
        assert_same(&x, &y, &r);
        for (h, k) in x.iter().zip(&y) {
            assert_eq!(h.material, k.material);
        }
        seen += x.len();
    }
    assert!(seen > 300);
}

#[test]
fn sphere_minus_larger_concentric_sphere_is_empty() {
    let _watchdog = crate::watchdog::start();
    let d = Csg::new(
        CsgOp::Difference,
        vec![sphere(DVec3::ZERO, 1.0, 1), sphere(DVec3::ZERO, 1.5, 2)],
    );
    let mut rays = testing::rays_towards(DVec3::ZERO, 2.0, 300, 63);
    rays.push(Ray::new(DVec3::ZERO, DVec3::X));
    for r in rays {
        assert!(xs(&d, &r).is_empty());
        assert!(d.intersect(&r, 0.0, f64::INFINITY).is_none());
    }
}

#[test]
fn difference_of_boxes_is_the_box_built_directly() {
    let _watchdog = crate::watchdog::start();
    let d = Csg::new(
        CsgOp::Difference,
        vec![
            cube(DVec3::ZERO, DVec3::splat(2.0), 1),
            cube(DVec3::new(1.0, -1.0, -1.0), DVec3::splat(3.0), 2),
        ],
    );
    let direct = Cuboid::new(DVec3::ZERO, DVec3::new(1.0, 2.0, 2.0), [1, 1, 1, 1, 1, 2]);
    assert_eq!(d.bounds(), Aabb::new(DVec3::ZERO, DVec3::splat(2.0)));
    let mut seen = 0;
    for r in testing::rays_towards(DVec3::new(0.5, 1.0, 1.0), 1.5, 500, 64) {
        let (x, y) = (xs(&d, &r), xs(&direct, &r));
        assert_same(&x, &y, &r);
        for (h, k) in x.iter().zip(&y) {
            // The cut face x = 1 shows the cutter's material.
            assert_eq!(h.material, k.material, "{h:?}");
        }
        let near = d.intersect(&r, 1e-9, f64::INFINITY);
        let want = direct.intersect(&r, 1e-9, f64::INFINITY);
        assert_eq!(near.map(|h| h.material), want.map(|h| h.material));
        seen += x.len();
    }
    assert!(seen > 300);
}

/// Inside-ness along a line from a crossing list, at parameter t.
fn inside_by_crossings(list: &[Hit], r: &Ray, t: f64) -> bool {
    // The last crossing before t tells: entering means inside.
    list.iter()
        .rev()
        .find(|h| h.t < t)
        .is_some_and(|h| h.normal.dot(r.dir) < 0.0)
}

#[test]
fn box_and_sphere_match_the_analytic_shape() {
    let _watchdog = crate::watchdog::start();
    let b = (DVec3::new(-1.0, -0.8, -1.0), DVec3::new(1.0, 0.8, 0.6));
    let (c, rad) = (DVec3::new(0.1, 0.0, 0.0), 1.2);
    let inside_box = |p: DVec3| p.cmpgt(b.0).all() && p.cmplt(b.1).all();
    let inside_ball = |p: DVec3| (p - c).length() < rad;
    let ops: [(CsgOp, &dyn Fn(DVec3) -> bool); 3] = [
        (CsgOp::Intersection, &|p| inside_box(p) && inside_ball(p)),
        (CsgOp::Union, &|p| inside_box(p) || inside_ball(p)),
        (CsgOp::Difference, &|p| inside_box(p) && !inside_ball(p)),
    ];
    for (op, inside) in ops {
        let s = Csg::new(op, vec![cube(b.0, b.1, 1), sphere(c, rad, 2)]);
        let rays = testing::rays_towards(DVec3::ZERO, 1.5, 300, 65);
        testing::check_consistency(&s, &rays);
        testing::check_alternation(&s, &rays);
        testing::check_no_rehit(&s, &rays);
        for r in &rays {
            let list = xs(&s, r);
            for k in 0..200 {
                let t = 5.0 + (k as f64) * 0.05 + 0.0123;
                let p = r.at(t);
                // Skip samples within a hair of a surface.
                if list.iter().any(|h| (h.t - t).abs() < 1e-6) {
                    continue;
                }
                assert_eq!(inside_by_crossings(&list, r, t), inside(p), "{op:?} {p:?}");
            }
        }
    }
}

#[test]
fn nearest_hit_in_any_window_is_the_first_crossing_there() {
    let _watchdog = crate::watchdog::start();
    // intersect() leaves out children that miss its window; the answer
    // must still be the whole line's crossing list cut to the window.
    let shapes = [
        Csg::new(
            CsgOp::Union,
            vec![
                sphere(DVec3::ZERO, 1.0, 1),
                cube(DVec3::splat(0.5), DVec3::splat(2.0), 2),
            ],
        ),
        Csg::new(
            CsgOp::Difference,
            vec![
                cube(-DVec3::ONE, DVec3::ONE, 1),
                sphere(DVec3::splat(0.8), 0.9, 2),
            ],
        ),
        Csg::new(
            CsgOp::Intersection,
            vec![
                sphere(DVec3::ZERO, 1.3, 1),
                cube(-DVec3::ONE, DVec3::ONE, 2),
            ],
        ),
    ];
    for s in &shapes {
        for (k, r) in testing::rays_towards(DVec3::ZERO, 1.5, 300, 67)
            .iter()
            .enumerate()
        {
            let list = xs(s, r);
            let lo = 8.0 + (k % 7) as f64 * 0.4;
            let hi = lo + 0.3 + (k % 5) as f64 * 0.5;
            let want = list.iter().find(|h| h.t > lo && h.t < hi);
            let got = s.intersect(r, lo, hi);
            assert_eq!(got.map(|h| h.t), want.map(|h| h.t), "window {lo}..{hi}");
            assert_eq!(got.map(|h| h.material), want.map(|h| h.material));
            assert_eq!(s.occludes(r, lo, hi), want.is_some());
        }
    }
}

#[test]
fn inside_a_union_only_the_outer_surface_shows() {
    let _watchdog = crate::watchdog::start();
    let u = Csg::new(
        CsgOp::Union,
        vec![
            sphere(DVec3::new(-0.5, 0.0, 0.0), 1.0, 1),
            sphere(DVec3::new(0.5, 0.0, 0.0), 1.0, 2),
        ],
    );
    let h = u
        .intersect(&Ray::new(DVec3::ZERO, DVec3::X), 1e-9, f64::INFINITY)
        .unwrap();
    assert!((h.t - 1.5).abs() < 1e-12 && h.material == 2 && h.normal.x > 0.0);
    let h = u
        .intersect(&Ray::new(DVec3::ZERO, -DVec3::X), 1e-9, f64::INFINITY)
        .unwrap();
    assert!((h.t - 1.5).abs() < 1e-12 && h.material == 1);
    // A shadow ray inside sees the same.
    assert!(!u.occludes(&Ray::new(DVec3::ZERO, DVec3::X), 1e-9, 1.4));
}

#[test]
fn plane_is_a_half_space() {
    let _watchdog = crate::watchdog::start();
    let cut = || Box::new(Plane::new(DVec3::Y, 0.0, 3)) as Box<dyn Shape>;
    // Sphere minus everything below y = 0: the upper hemisphere.
    let top = Csg::new(CsgOp::Difference, vec![sphere(DVec3::ZERO, 1.0, 1), cut()]);
    let down = Ray::new(DVec3::new(0.3, 5.0, 0.0), -DVec3::Y);
    let h = top.intersect(&down, 0.0, f64::INFINITY).unwrap();
    assert!((h.t - (5.0 - 0.91f64.sqrt())).abs() < 1e-12 && h.material == 1);
    let up = Ray::new(DVec3::new(0.3, -5.0, 0.0), DVec3::Y);
    let h = top.intersect(&up, 0.0, f64::INFINITY).unwrap();
    // The cut face: the plane's material, its normal reversed (−y).
    assert!((h.t - 5.0).abs() < 1e-12 && h.material == 3 && h.normal.y < 0.0);
    assert_eq!(xs(&top, &up).len(), 2);
    // Sphere ∩ half-space: the lower hemisphere, and lines parallel to
    // the plane are inside or outside it as a whole.
    let low = Csg::new(
        CsgOp::Intersection,
        vec![cut(), sphere(DVec3::ZERO, 1.0, 1)],
    );
    let below = Ray::new(DVec3::new(-5.0, -0.5, 0.0), DVec3::X);
    let above = Ray::new(DVec3::new(-5.0, 0.5, 0.0), DVec3::X);
    assert!((low.intersect(&below, 0.0, 99.0).unwrap().t - (5.0 - 0.75f64.sqrt())).abs() < 1e-12);
    assert!(low.intersect(&above, 0.0, 99.0).is_none());
    // A half-space minus a sphere is unbounded: a parallel line below
    // starts inside, leaves into the hole and comes back out of it.
    let holed = Csg::new(CsgOp::Difference, vec![cut(), sphere(DVec3::ZERO, 1.0, 1)]);
    assert!(!holed.bounds().is_finite());
    let list = xs(&holed, &below);
    assert_eq!(list.len(), 2, "{list:?}");
    assert!(list[0].normal.dot(below.dir) > 0.0 && list[1].normal.dot(below.dir) < 0.0);
    // Parallel lines that miss the hole are wholly inside or outside.
    assert!(xs(&holed, &Ray::new(DVec3::new(-5.0, -2.0, 0.0), DVec3::X)).is_empty());
    assert!(holed.encloses(DVec3::new(0.0, -2.0, 0.0)));
    assert!(!holed.encloses(DVec3::new(0.0, 2.0, 0.0)));
}

#[test]
fn tangent_rays_do_not_fill_the_line() {
    let _watchdog = crate::watchdog::start();
    let u = Csg::new(
        CsgOp::Union,
        vec![
            sphere(DVec3::ZERO, 1.0, 1),
            sphere(DVec3::new(5.0, 1.0, 0.0), 0.5, 2),
        ],
    );
    // Grazes the first sphere at (0, 1, 0), then meets the second.
    let r = Ray::new(DVec3::new(-3.0, 1.0, 0.0), DVec3::X);
    let list = xs(&u, &r);
    assert!(list.len().is_multiple_of(2), "{list:?}");
    let h = u.intersect(&r, 3.5, f64::INFINITY).unwrap();
    assert!((h.t - 7.5).abs() < 1e-9 && h.material == 2);
    assert!(u.intersect(&r, 8.6, f64::INFINITY).is_none());
}

#[test]
fn nested_and_transformed() {
    let _watchdog = crate::watchdog::start();
    // The lantern: (box ∩ sphere) minus three crossed cylinders, turned.
    let cyl = |t: Transform| -> Box<dyn Shape> {
        Box::new(Transformed::new(
            Box::new(Cone::cylinder(DVec3::ZERO, 0.5, 3.0, 2, Some([2, 2]))),
            t,
        ))
    };
    let body = Csg::new(
        CsgOp::Intersection,
        vec![
            cube(-DVec3::ONE, DVec3::ONE, 1),
            sphere(DVec3::ZERO, 1.4, 1),
        ],
    );
    let lantern = Csg::new(
        CsgOp::Difference,
        vec![
            Box::new(body),
            cyl(Transform::translate(DVec3::ZERO)),
            cyl(Transform::rotate(DVec3::X, 90.0).unwrap()),
            cyl(Transform::rotate(DVec3::Z, 90.0).unwrap()),
        ],
    );
    let turned = Transformed::new(
        Box::new(lantern),
        Transform::rotate(DVec3::Y, 30.0).unwrap(),
    );
    let rays = testing::rays_towards(DVec3::ZERO, 1.2, 500, 66);
    testing::check_consistency(&turned, &rays);
    testing::check_alternation(&turned, &rays);
    testing::check_no_rehit(&turned, &rays);
    // Straight down the y hole: nothing.
    let down = Ray::new(DVec3::new(0.0, 5.0, 0.0), -DVec3::Y);
    assert!(turned.intersect(&down, 0.0, 99.0).is_none());
    // Across at y = 0.7 (above the x hole): into the body, out into the y
    // hole through its wall, whose normal (reversed) leaves along the ray.
    let across = Ray::new(DVec3::new(-5.0, 0.7, 0.0), DVec3::X);
    let h = turned.intersect(&across, 0.0, 99.0).unwrap();
    assert_eq!(h.material, 1);
    let h = turned.intersect(&across, h.t + 1e-6, 99.0).unwrap();
    assert!(h.material == 2 && h.normal.dot(across.dir) > 0.0, "{h:?}");
    // A camera in the hollow centre sees the holes' walls, not the body.
    let h = turned
        .intersect(
            &Ray::new(DVec3::ZERO, DVec3::new(1.0, 1.0, 1.0)),
            1e-9,
            99.0,
        )
        .unwrap();
    assert_eq!(h.material, 2);
}

#[test]
fn uv_is_asked_of_the_shape_that_was_hit() {
    let _watchdog = crate::watchdog::start();
    // A bitten ball in a union with a moved cylinder: each hit's (u, v)
    // must be what the leaf itself gives for that point.
    let ball = Sphere::new(DVec3::ZERO, 1.0, 1);
    let tube = Cone::cylinder(DVec3::ZERO, 0.4, 2.0, 3, Some([4, 4]));
    let moved = Transform::translate(DVec3::new(1.5, 0.0, 0.0));
    let bitten = Csg::new(
        CsgOp::Difference,
        vec![
            Box::new(ball.clone()),
            cube(DVec3::splat(0.2), DVec3::splat(2.0), 2),
        ],
    );
    let u = Transformed::new(
        Box::new(Csg::new(
            CsgOp::Union,
            vec![
                Box::new(Transformed::new(Box::new(tube.clone()), moved)),
                Box::new(bitten),
            ],
        )),
        Transform::rotate(DVec3::Y, 20.0).unwrap(),
    );
    let mut seen = [0; 5];
    for r in testing::rays_towards(DVec3::new(0.7, 0.0, 0.0), 1.5, 400, 68) {
        let Some(h) = u.intersect(&r, 1e-9, f64::INFINITY) else {
            continue;
        };
        let leaf = Hit { path: 0, ..h };
        let want = match h.material {
            1 => ball.uv(&leaf),
            3 | 4 => tube.uv(&leaf),
            _ => h.uv,
        };
        assert_eq!(u.uv(&h), want, "{h:?}");
        assert!(want.cmpge(DVec2::ZERO).all() && want.cmple(DVec2::ONE).all());
        seen[h.material as usize] += 1;
    }
    assert!(seen[1] > 20 && seen[2] > 5 && seen[3] > 20, "{seen:?}");
}

/// A nested unbounded intersection (a quarter-space: two planes) that a
/// line runs inside of without crossing it: the parent learns from
/// `encloses` that the whole line is inside, so a ball minus the
/// quarter-space shows nothing along a line within the quarter, and
/// the ball along one outside it.
#[test]
fn a_nested_unbounded_intersection_encloses_the_lines_inside_it() {
    let _watchdog = crate::watchdog::start();
    let quarter = || {
        Box::new(Csg::new(
            CsgOp::Intersection,
            vec![
                Box::new(Plane::new(DVec3::Y, 0.0, 2)) as Box<dyn Shape>,
                Box::new(Plane::new(DVec3::X, 0.0, 2)),
            ],
        )) as Box<dyn Shape>
    };
    assert!(quarter().encloses(DVec3::new(-1.0, -1.0, 7.0)));
    assert!(!quarter().encloses(DVec3::new(1.0, -1.0, 7.0)));
    let ball_minus = Csg::new(
        CsgOp::Difference,
        vec![sphere(DVec3::ZERO, 5.0, 1), quarter()],
    );
    let ball_and = Csg::new(
        CsgOp::Intersection,
        vec![sphere(DVec3::ZERO, 5.0, 1), quarter()],
    );
    // Along z, parallel to both planes.
    let inside = Ray::new(DVec3::new(-1.0, -1.0, 20.0), -DVec3::Z);
    let outside = Ray::new(DVec3::new(1.0, -1.0, 20.0), -DVec3::Z);
    assert!(ball_minus.intersect(&inside, 0.0, f64::INFINITY).is_none());
    assert!(ball_minus.intersect(&outside, 0.0, f64::INFINITY).is_some());
    let h = ball_and
        .intersect(&inside, 0.0, f64::INFINITY)
        .expect("the ball's quarter");
    assert!((h.t - (20.0 - 23f64.sqrt())).abs() < 1e-9, "{h:?}");
    assert!(ball_and.intersect(&outside, 0.0, f64::INFINITY).is_none());
    assert_eq!(xs(&ball_and, &inside).len(), 2);
    assert!(xs(&ball_minus, &inside).is_empty());
}

#[test]
fn nesting_too_deep_for_the_key_keeps_the_material() {
    let _watchdog = crate::watchdog::start();
    // 70 unions of three children nest 3^70 > 2^64 keys deep: the key
    // overflows, and the hit must still be the right surface. The other
    // spheres lie further along the ray, so that every union sweeps.
    let mut s: Box<dyn Shape> = sphere(DVec3::ZERO, 1.0, 9);
    for k in 0..70 {
        let far = |m| sphere(DVec3::new(0.0, 0.0, -3.0 - k as f64), 0.5, m);
        s = Box::new(Csg::new(CsgOp::Union, vec![far(1), s, far(2)]));
    }
    let r = Ray::new(DVec3::new(0.3, 0.2, 5.0), DVec3::new(0.0, 0.0, -1.0));
    let h = s.intersect(&r, 1e-9, f64::INFINITY).expect("the sphere");
    assert_eq!(h.material, 9);
    let want = 5.0 - (1.0f64 - 0.09 - 0.04).sqrt();
    assert!((h.t - want).abs() < 1e-12, "{}", h.t);
    let p = r.at(h.t);
    assert!((h.normal.normalize() - p).length() < 1e-9, "{:?}", h.normal);
    // Its path did not fit: marked lost, so (u, v) reads as zero rather
    // than being asked of whichever child a wrapped path would name.
    assert_eq!(h.path, LOST);
}

/// A lost crossing found again on a cutter of a difference is the
/// cutter's surface turned inside out, as when the key fits.
#[test]
fn a_lost_crossing_on_a_cutter_faces_out_of_the_result() {
    let _watchdog = crate::watchdog::start();
    let d = Csg::new(
        CsgOp::Difference,
        vec![
            sphere(DVec3::ZERO, 2.0, 1),
            sphere(DVec3::new(0.0, 0.0, 2.0), 1.0, 2),
        ],
    );
    let r = Ray::new(DVec3::new(0.0, 0.0, 9.0), -DVec3::Z);
    // Entering the result at z = 1, on the cutter (its back face).
    let found = xs(&d, &r);
    let first = found.first().expect("a crossing");
    assert!((first.t - 8.0).abs() < 1e-12 && first.material == 2);
    let c = Crossing::new(first.t, first.normal, &r, LOST);
    let h = d.hit_of(&r, &c);
    assert_eq!((h.t, h.material, h.path), (first.t, 2, LOST));
    assert!(h.normal.dot(r.dir) < 0.0, "entering: {h:?}");
}

/// A union whose unbounded child (a half-space) holds the whole line
/// without crossing it: everything along the line is inside the union,
/// so the other children's surfaces there are inner ones, not seen.
#[test]
fn a_line_inside_an_unbounded_child_of_a_union_sees_no_inner_surfaces() {
    let _watchdog = crate::watchdog::start();
    let u = Csg::new(
        CsgOp::Union,
        vec![
            Box::new(Plane::new(DVec3::Y, 0.0, 1)) as Box<dyn Shape>,
            sphere(DVec3::ZERO, 1.0, 2),
        ],
    );
    let below = Ray::new(DVec3::new(0.0, -0.5, 9.0), -DVec3::Z);
    assert!(u.intersect(&below, 0.0, f64::INFINITY).is_none());
    assert!(!u.occludes(&below, 0.0, f64::INFINITY));
    let above = Ray::new(DVec3::new(0.0, 0.5, 9.0), -DVec3::Z);
    let h = u.intersect(&above, 0.0, f64::INFINITY).expect("the sphere");
    assert_eq!(h.material, 2);
}

/// The last resort of a lost crossing: no child has a crossing at its t
/// (it cannot be found again), so the hit is made from the crossing
/// alone: its t, a normal that says entering or leaving as `facing`
/// did, the point for solid textures, and the path marked lost.
#[test]
fn a_lost_crossing_no_child_has_is_still_a_consistent_hit() {
    let _watchdog = crate::watchdog::start();
    let u = Csg::new(CsgOp::Union, vec![sphere(DVec3::ZERO, 1.0, 4)]);
    let r = Ray::new(DVec3::new(0.0, 0.0, 9.0), DVec3::new(0.0, 0.0, -2.0));
    for facing in [-1.0, 1.0] {
        let c = Crossing {
            t: 2.5,
            facing,
            grazing: false,
            key: LOST,
        };
        let h = u.hit_of(&r, &c);
        assert_eq!(h.t, 2.5);
        assert_eq!(h.local, r.at(2.5));
        assert_eq!(h.path, LOST);
        assert_eq!(h.normal.dot(r.dir).signum(), facing, "{h:?}");
        assert_eq!(h.geo_normal.dot(r.dir).signum(), facing, "{h:?}");
        // The point on the line, with a bound on its rounding: not zero
        // (ray.at(t) is a rounded sum in z).
        assert_eq!(h.point, r.at(2.5));
        assert!(h.p_error.z > 0.0, "{h:?}");
        assert_eq!(u.uv(&h), DVec2::ZERO);
    }
}

#[test]
fn lite_crossings_rebuild_the_same_hits() {
    let _watchdog = crate::watchdog::start();
    // Each shape's crossings_lite, made into hits by hit_of, must be its
    // crossings exactly; the torus uses the trait's default bodies.
    use crate::shapes::Torus;
    let turned = |s: Box<dyn Shape>| -> Box<dyn Shape> {
        Box::new(Transformed::new(
            s,
            Transform::rotate(DVec3::new(1.0, 2.0, 0.5), 35.0).unwrap(),
        ))
    };
    let shapes: Vec<Box<dyn Shape>> = vec![
        sphere(DVec3::new(0.1, 0.0, 0.2), 1.0, 1),
        cube(-DVec3::ONE, DVec3::new(1.0, 0.5, 1.2), 2),
        Box::new(Cone::cylinder(DVec3::ZERO, 0.8, 1.5, 3, Some([4, 5]))),
        Box::new(Plane::new(DVec3::new(0.2, 1.0, 0.0), 0.1, 6)),
        Box::new(Torus::new(1.0, 0.3, 7)),
        turned(Box::new(Cone::cylinder(
            DVec3::ZERO,
            0.8,
            1.5,
            3,
            Some([4, 5]),
        ))),
        Box::new(Csg::new(
            CsgOp::Difference,
            vec![
                turned(cube(-DVec3::ONE, DVec3::ONE, 1)),
                sphere(DVec3::splat(0.6), 0.8, 2),
                Box::new(Torus::new(0.9, 0.2, 3)),
            ],
        )),
    ];
    let mut seen = 0;
    for s in &shapes {
        for r in testing::rays_towards(DVec3::ZERO, 1.2, 200, 69) {
            let mut lite = Vec::new();
            s.crossings_lite(&r, &mut lite);
            let full = xs(&**s, &r);
            assert_eq!(lite.len(), full.len(), "{s:?} {r:?}");
            for (c, h) in lite.iter().zip(&full) {
                assert_eq!(s.hit_of(&r, c), *h);
                assert_eq!(c.facing < 0.0, h.normal.dot(r.dir) < 0.0);
            }
            seen += full.len();
        }
    }
    assert!(seen > 1000, "{seen}");
}

#[test]
fn union_of_apart_children_agrees_with_the_sweep() {
    let _watchdog = crate::watchdog::start();
    // Children whose reaches along a ray do not overlap are asked for
    // their nearest hit directly; that must be what the full crossing
    // list says, in any window, floor included.
    let floor = || Box::new(Plane::new(DVec3::Y, 0.0, 3)) as Box<dyn Shape>;
    let u = Csg::new(
        CsgOp::Union,
        vec![
            sphere(DVec3::new(-1.5, 1.0, 0.0), 1.0, 1),
            cube(DVec3::new(0.5, 0.0, -0.5), DVec3::new(1.5, 2.0, 0.5), 2),
            floor(),
            sphere(DVec3::new(1.0, 1.5, 0.0), 0.7, 4),
        ],
    );
    let mut hits = 0;
    for (k, r) in testing::rays_towards(DVec3::new(0.0, 1.0, 0.0), 2.5, 600, 70)
        .iter()
        .enumerate()
    {
        let list = xs(&u, r);
        let lo = if k % 3 == 0 {
            1e-9
        } else {
            7.0 + (k % 7) as f64 * 0.5
        };
        let hi = if k % 2 == 0 {
            f64::INFINITY
        } else {
            lo + 1.0 + (k % 5) as f64
        };
        let want = list.iter().find(|h| h.t > lo && h.t < hi);
        let got = u.intersect(r, lo, hi);
        assert_eq!(got.map(|h| h.t), want.map(|h| h.t), "window {lo}..{hi}");
        assert_eq!(got.map(|h| h.material), want.map(|h| h.material));
        assert_eq!(got.map(|h| h.path), want.map(|h| h.path));
        assert_eq!(u.occludes(r, lo, hi), want.is_some());
        hits += got.is_some() as usize;
    }
    assert!(hits > 300, "{hits}");
}

#[test]
fn quick_clip_agrees_with_aabb_clip() {
    let _watchdog = crate::watchdog::start();
    let b = Aabb::new(DVec3::new(-1.0, 0.0, -0.5), DVec3::new(1.0, 2.0, 0.5));
    let mut rays = testing::rays_towards(DVec3::new(0.0, 1.0, 0.0), 2.0, 500, 71);
    // Axis-parallel, one of them in the plane of a face.
    rays.push(Ray::new(DVec3::new(0.0, 1.0, -5.0), DVec3::Z));
    rays.push(Ray::new(DVec3::new(1.0, 1.0, -5.0), DVec3::Z));
    rays.push(Ray::new(DVec3::new(3.0, 1.0, -5.0), DVec3::Z));
    let mut hits = 0;
    for r in &rays {
        for (lo, hi) in [(0.0, f64::INFINITY), (9.0, 10.0), (f64::NEG_INFINITY, 9.5)] {
            let (a, b2) = (clip(&b, r, r.dir.recip(), lo, hi), b.clip(r, lo, hi));
            if r.dir.cmpne(DVec3::ZERO).all() {
                assert_eq!(a, b2, "{r:?} {lo}..{hi}");
            } else if let Some((x, y)) = b2 {
                // Along a face's plane: at least Aabb::clip's stretch.
                let (p, q) = a.unwrap();
                assert!(p <= x && q >= y, "{r:?} {lo}..{hi}");
            }
            hits += a.is_some() as usize;
        }
    }
    // The line in the plane x = 1 (of the face) still meets the box.
    let along = Ray::new(DVec3::new(1.0, 1.0, -5.0), DVec3::Z);
    assert_eq!(
        clip(&b, &along, along.dir.recip(), 0.0, 99.0),
        Some((4.5, 5.5))
    );
    assert!(hits > 300, "{hits}");
}

/// Renders `objects` with a camera and a light at `eye`, looking along +x.
fn render(objects: Vec<Box<dyn Shape>>, eye: DVec3) -> crate::render::Film {
    use crate::scene::{Camera, Light, Material, Projection, RenderSettings, Scene, Texture};
    let solid = |r, g, b| Material::matte(Texture::Solid(DVec3::new(r, g, b)), 0.0);
    let scene = Scene {
        camera: Camera {
            position: eye,
            look_at: eye + DVec3::X,
            up: DVec3::Y,
            projection: Projection::Fov(60.0),
            lens: None,
        },
        settings: RenderSettings {
            width: 24,
            height: 16,
            ..RenderSettings::default()
        },
        ambient: DVec3::splat(0.1),
        lights: vec![Light::point(eye, DVec3::ONE)],
        materials: vec![
            Material::default(),
            solid(1.0, 0.0, 0.0),
            solid(0.0, 1.0, 0.0),
        ],
        ..Scene::default()
    };
    let world = crate::accel::World::build(objects);
    let opts = crate::render::RenderOptions {
        progress: None,
        cancel: None,
    };
    crate::render::render(&scene, &world, &opts).unwrap().0
}

#[test]
fn rendered_from_inside_a_union_and_a_group() {
    let _watchdog = crate::watchdog::start();
    let two = || {
        vec![
            sphere(DVec3::new(-0.5, 0.0, 0.0), 1.0, 1),
            sphere(DVec3::new(0.5, 0.0, 0.0), 1.0, 2),
        ]
    };
    // Union: every pixel sees the far, green wall, lit by the light
    // inside (no inner surface casts a shadow).
    let union = render(vec![Box::new(Csg::new(CsgOp::Union, two()))], DVec3::ZERO);
    for p in &union.pixels {
        assert!(p[0] == 0.0 && p[1] > 0.5 && p[2] == 0.0, "{p:?}");
    }
    // A group of the same two spheres shows the red sphere's inside.
    let group = render(two(), DVec3::ZERO);
    let centre = group.get(12, 8);
    assert!(centre[0] > 0.5 && centre[1] == 0.0, "{centre:?}");
}

#[test]
fn rendered_union_with_itself_is_the_shape() {
    let _watchdog = crate::watchdog::start();
    let lens = || -> Box<dyn Shape> {
        Box::new(Csg::new(
            CsgOp::Intersection,
            vec![
                sphere(DVec3::new(0.0, 0.0, 0.6), 1.0, 1),
                sphere(DVec3::new(0.0, 0.0, -0.6), 1.0, 2),
            ],
        ))
    };
    let eye = DVec3::new(-4.0, 0.3, 0.2);
    let alone = render(vec![lens()], eye);
    let doubled = render(
        vec![Box::new(Csg::new(CsgOp::Union, vec![lens(), lens()]))],
        eye,
    );
    assert_eq!(alone.pixels, doubled.pixels);
    // The lens is seen edge-on: both colours, and background around it.
    assert!(alone.pixels.iter().any(|p| p[0] > 0.0));
    assert!(alone.pixels.iter().any(|p| p[1] > 0.0));
    assert!(alone.pixels.contains(&[0.0; 3]));
}

#[test]
fn a_union_wider_than_64_children_shadows_through_every_child() {
    let _watchdog = crate::watchdog::start();
    // 70 small spheres in a row along x; a shadow ray crosses only the
    // last one, past the 64 bits a child mask holds.
    let u = Csg::new(
        CsgOp::Union,
        (0..70)
            .map(|i| sphere(DVec3::new(3.0 * i as f64, 0.0, 0.0), 1.0, 1))
            .collect(),
    );
    for i in [0, 63, 64, 69] {
        let x = 3.0 * i as f64;
        let r = Ray::new(DVec3::new(x, 5.0, 0.0), DVec3::new(0.0, -1.0, 0.0));
        assert!(u.occludes(&r, 1e-9, 10.0), "sphere {i} casts no shadow");
        assert!(
            u.intersect(&r, 1e-9, 10.0).is_some(),
            "sphere {i} is not hit"
        );
    }
    let between = Ray::new(DVec3::new(199.5, 5.0, 0.0), DVec3::new(0.0, -1.0, 0.0));
    assert!(!u.occludes(&between, 1e-9, 10.0));
}

/// Makes a fresh copy of a child.
type Maker<'a> = &'a dyn Fn() -> Box<dyn Shape>;

/// Coincident surfaces worked out by different arithmetic (a box and the
/// same box turned a quarter turn, whose matrix has cos 90° ≈ 6e-17 for 0;
/// a ball and the same ball turned) meet a line at t that differ by
/// rounding. The sweep takes such crossings as one event, so A ∪ A′ and
/// A ∩ A′ cross the line where A does and A − A′ is empty: no zero-width
/// slivers. At size 1 and at size 1e8, where the rounding of t (~1e-7)
/// is far above any absolute tolerance but far below a relative one.
#[test]
fn coincident_surfaces_by_different_arithmetic_are_one_surface() {
    let _watchdog = crate::watchdog::start();
    let turned = |s: Box<dyn Shape>, axis: DVec3, deg: f64| -> Box<dyn Shape> {
        Box::new(Transformed::new(s, Transform::rotate(axis, deg).unwrap()))
    };
    let mut differ = 0;
    for size in [1.0, 1e8] {
        let pairs: [(Maker, Maker); 2] = [
            (
                &|| cube(-DVec3::splat(size), DVec3::splat(size), 1),
                &|| {
                    turned(
                        cube(-DVec3::splat(size), DVec3::splat(size), 2),
                        DVec3::Y,
                        90.0,
                    )
                },
            ),
            (&|| sphere(DVec3::ZERO, size, 1), &|| {
                turned(
                    sphere(DVec3::ZERO, size, 2),
                    DVec3::new(1.0, 2.0, 3.0),
                    37.0,
                )
            }),
        ];
        for (a, a2) in pairs {
            let u = Csg::new(CsgOp::Union, vec![a(), a2()]);
            let i = Csg::new(CsgOp::Intersection, vec![a(), a2()]);
            let d = Csg::new(CsgOp::Difference, vec![a(), a2()]);
            let rays: Vec<Ray> = testing::rays_towards(DVec3::ZERO, 0.5, 300, 72)
                .into_iter()
                .map(|r| Ray::new(r.origin * size, r.dir))
                .collect();
            for r in &rays {
                let (one, other) = (xs(&*a(), r), xs(&*a2(), r));
                assert_eq!(one.len(), 2, "{r:?}");
                differ += one.iter().zip(&other).any(|(p, q)| p.t != q.t) as usize;
                for s in [&u, &i] {
                    let list = xs(s, r);
                    assert_eq!(list.len(), 2, "size {size}: {list:?}");
                    for (h, k) in list.iter().zip(&one) {
                        assert!((h.t - k.t).abs() <= 1e-9 * size * 20.0, "{h:?} vs {k:?}");
                        assert!(h.normal.dot(k.normal) > 0.0);
                    }
                }
                assert!(xs(&d, r).is_empty(), "size {size}: {:?}", xs(&d, r));
                assert!(d.intersect(r, 0.0, f64::INFINITY).is_none());
                assert!(!d.occludes(r, 0.0, f64::INFINITY));
            }
            testing::check_alternation(&u, &rays);
            testing::check_alternation(&i, &rays);
        }
    }
    // The case is real: most lines meet the two copies at different t.
    assert!(differ > 400, "{differ}");
}

/// The leaf crossing of `leaf` along `r` at (nearly) `t`, as a full hit.
fn leaf_hit_at(leaf: &dyn Shape, r: &Ray, t: f64) -> Hit {
    let list = xs(leaf, r);
    *list
        .iter()
        .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
        .filter(|h| (h.t - t).abs() < 1e-9)
        .unwrap_or_else(|| panic!("no crossing at {t} in {list:?}"))
}

/// Three balls, each turned its own way, nested two unions deep: a hit's
/// (u, v) and its `normal_to_world` (a pattern's slope at `local` taken
/// out to the world) are the leaf's own, found down the hit's path; and
/// with a texture space, a hit wearing the block's material has `local`
/// in the block's space (the point along the ray), its (u, v) still the
/// leaf's, and a slope at `local` already in that space, while a child
/// with its own material keeps its own space.
#[test]
fn uv_and_normal_to_world_follow_the_path_or_the_texture_space() {
    let _watchdog = crate::watchdog::start();
    let ball = |x: f64, axis: DVec3, m: u32| -> Box<dyn Shape> {
        Box::new(Transformed::new(
            sphere(DVec3::new(x, 0.0, 0.0), 0.8, m),
            Transform::rotate(axis, 50.0).unwrap(),
        ))
    };
    let leaves = || {
        [
            ball(-1.5, DVec3::Z, 1),
            ball(0.3, DVec3::new(1.0, 1.0, 0.0), 2),
            ball(1.5, DVec3::new(0.0, 1.0, 2.0), 3),
        ]
    };
    let nested = |space: Option<MaterialId>| {
        let [a, b, c] = leaves();
        let inner = Csg::new(CsgOp::Union, vec![a, b]);
        let outer = Csg::new(CsgOp::Union, vec![Box::new(inner), c]);
        match space {
            Some(m) => outer.texture_space(m),
            None => outer,
        }
    };
    let leaf = leaves();
    let v = DVec3::new(0.3, -0.5, 0.8);
    for space in [None, Some(2)] {
        let s = nested(space);
        let mut seen = [0; 4];
        for r in testing::rays_towards(DVec3::ZERO, 2.0, 400, 73) {
            let Some(h) = s.intersect(&r, 1e-9, f64::INFINITY) else {
                continue;
            };
            let m = h.material as usize;
            let own = leaf_hit_at(&*leaf[m - 1], &r, h.t);
            let want_uv = leaf[m - 1].uv(&own);
            assert!(want_uv != DVec2::ZERO);
            assert_eq!(s.uv(&h), want_uv, "{h:?}");
            if space == Some(h.material) {
                assert_eq!(h.local, r.at(h.t));
                assert_eq!(s.normal_to_world(&h, v), v);
            } else {
                assert_eq!(h.local, own.local);
                let want = leaf[m - 1].normal_to_world(&own, v);
                assert!((want - v).length() > 0.1);
                assert_eq!(s.normal_to_world(&h, v), want, "{h:?}");
            }
            seen[m] += 1;
        }
        assert!(seen[1] > 20 && seen[2] > 20 && seen[3] > 20, "{seen:?}");
    }
    // A lost path is not followed: no (u, v), and the slope is left as it
    // is rather than turned by whichever child a wrapped path would name.
    let s = nested(None);
    let b = leaf[2].bounds();
    let centre = (b.min + b.max) / 2.0;
    let r = Ray::new(centre + DVec3::new(0.0, 0.0, 9.0), -DVec3::Z);
    let mut lite = Vec::new();
    s.crossings_lite(&r, &mut lite);
    let first = lite.first().expect("the third ball");
    let h = s.hit_of(
        &r,
        &Crossing {
            key: LOST,
            ..*first
        },
    );
    assert_eq!((h.material, h.path), (3, LOST));
    assert_eq!(s.uv(&h), DVec2::ZERO);
    assert_eq!(s.normal_to_world(&h, v), v);
}

/// Inside-ness along a line at t from a crossing list that may start
/// inside (an unbounded result): the last crossing before t tells, or
/// else the first after it (leaving: inside until then).
fn inside_by_crossings_from_anywhere(list: &[Hit], r: &Ray, t: f64, none: bool) -> bool {
    match list.iter().rev().find(|h| h.t < t) {
        Some(h) => h.normal.dot(r.dir) < 0.0,
        None => list.first().map_or(none, |h| h.normal.dot(r.dir) > 0.0),
    }
}

/// A half-space whose plane runs within 1e-9 rad of the line (so its one
/// crossing is flagged grazing) still has an exact side: the line is
/// inside it before a leaving crossing and outside after, and the other
/// way round for an entering one. CSG with such a half-space agrees with
/// point membership all along the line, whichever way it crosses, where
/// the crossing is inside the ball or before it (a half-space entered
/// before the ball holds the whole ball; one left before it, none).
#[test]
fn a_half_space_nearly_along_the_line_keeps_its_sides() {
    let _watchdog = crate::watchdog::start();
    let mut grazing = 0;
    let mut crossings = 0;
    for tilt in [1e-10, -1e-10, 3e-12] {
        for x_cross in [-15.0, -3.0, 0.0, 4.0, 15.0] {
            for dir in [DVec3::X, -DVec3::X] {
                let cut =
                    || Box::new(Plane::new(DVec3::new(tilt, 1.0, 0.0), 0.0, 3)) as Box<dyn Shape>;
                let ball = || sphere(DVec3::ZERO, 8.0, 1);
                let r = Ray::new(DVec3::new(-20.0 * dir.x, -tilt * x_cross, 0.3), dir);
                let mut lite = Vec::new();
                cut().crossings_lite(&r, &mut lite);
                assert_eq!(lite.len(), 1);
                grazing += lite[0].grazing as usize;
                let in_cut = |p: DVec3| tilt * p.x + p.y <= 0.0;
                let in_ball = |p: DVec3| p.length() < 8.0;
                let cases: [(Csg, &dyn Fn(DVec3) -> bool); 5] = [
                    (Csg::new(CsgOp::Intersection, vec![cut(), ball()]), &|p| {
                        in_cut(p) && in_ball(p)
                    }),
                    (Csg::new(CsgOp::Intersection, vec![ball(), cut()]), &|p| {
                        in_cut(p) && in_ball(p)
                    }),
                    (Csg::new(CsgOp::Difference, vec![ball(), cut()]), &|p| {
                        in_ball(p) && !in_cut(p)
                    }),
                    (Csg::new(CsgOp::Difference, vec![cut(), ball()]), &|p| {
                        in_cut(p) && !in_ball(p)
                    }),
                    (Csg::new(CsgOp::Union, vec![cut(), ball()]), &|p| {
                        in_cut(p) || in_ball(p)
                    }),
                ];
                for (s, inside) in cases {
                    let list = xs(&s, &r);
                    crossings += list.len();
                    for w in list.windows(2) {
                        let enter = |h: &Hit| h.normal.dot(r.dir) < 0.0;
                        assert_ne!(enter(&w[0]), enter(&w[1]), "{:?} {list:?}", s.op);
                    }
                    let none = inside(r.origin);
                    for k in 0..400 {
                        let t = k as f64 * 0.1 + 0.0123;
                        if list.iter().any(|h| (h.t - t).abs() < 1e-6) {
                            continue;
                        }
                        assert_eq!(
                            inside_by_crossings_from_anywhere(&list, &r, t, none),
                            inside(r.at(t)),
                            "{:?} t {t}: {list:?}",
                            s.op
                        );
                    }
                    let near = s.intersect(&r, 0.0, f64::INFINITY).map(|h| h.t);
                    assert_eq!(near, list.first().map(|h| h.t));
                }
            }
        }
    }
    assert_eq!(grazing, 30);
    assert!(crossings > 100, "{crossings}");
}

/// Closed boxes as one mesh (twelve triangles each, wound outwards): the
/// boxes from `lo[k]` to `hi[k]`.
fn boxes_mesh(lo: &[DVec3], hi: &[DVec3], m: u32) -> Box<dyn Shape> {
    use crate::shapes::mesh::{Mesh, MeshData};
    let faces = crate::shapes::testing::BOX_FACES;
    let (mut pos, mut tris) = (Vec::new(), Vec::new());
    for (a, b) in lo.iter().zip(hi) {
        let base = pos.len() as u32;
        pos.extend((0..8).map(|i| {
            DVec3::new(
                if i & 1 == 0 { a.x } else { b.x },
                if i & 2 == 0 { a.y } else { b.y },
                if i & 4 == 0 { a.z } else { b.z },
            )
        }));
        for f in faces {
            tris.push([base + f[0], base + f[1], base + f[2]]);
            tris.push([base + f[0], base + f[2], base + f[3]]);
        }
    }
    let data = MeshData::from_parts(pos, None, None, tris);
    Box::new(Mesh::new(std::sync::Arc::new(data), false, m))
}

/// Features thinner than the sweep's tolerance (1e-9 of t) at a box's
/// faces change nothing, and the box's faces are reported as they are
/// (entering against the ray, leaving along it) although the same batch
/// of flips holds crossings facing the other way: a slab 2e-12 thick
/// straddling each x face adds nothing to a union (it is entered and left
/// within the batch), and a gap 2e-10 wide at each x face of a mesh of
/// three boxes (whose own tolerance, 1e-12, keeps the gap) takes nothing
/// from an intersection (the mesh is left and entered within the batch).
#[test]
fn hairline_slabs_and_gaps_at_a_face_leave_the_box_as_it_is() {
    let _watchdog = crate::watchdog::start();
    let (e, g) = (1e-12, 1e-10);
    let y = || cube(DVec3::new(0.0, -1.0, -1.0), DVec3::new(4.0, 1.0, 1.0), 1);
    let slab = |x: f64| {
        cube(
            DVec3::new(x - e, -1.5, -1.5),
            DVec3::new(x + e, 1.5, 1.5),
            2,
        )
    };
    let union = Csg::new(CsgOp::Union, vec![y(), slab(0.0), slab(4.0)]);
    let gapped = boxes_mesh(
        &[
            DVec3::new(-3.0, -1.5, -1.5),
            DVec3::new(g, -1.5, -1.5),
            DVec3::new(4.0 + g, -1.5, -1.5),
        ],
        &[
            DVec3::new(-g, 1.5, 1.5),
            DVec3::new(4.0 - g, 1.5, 1.5),
            DVec3::new(7.0, 1.5, 1.5),
        ],
        3,
    );
    assert!(gapped.is_solid());
    let inter = Csg::new(CsgOp::Intersection, vec![gapped, y()]);
    let mut rnd = testing::numbers(74);
    let mut rays = Vec::new();
    for _ in 0..100 {
        let o = DVec3::new(-6.0, 0.8 * rnd(), 0.8 * rnd());
        let d = DVec3::new(1.0, 0.02 * rnd(), 0.02 * rnd()).normalize();
        rays.push(Ray::new(o, d));
        rays.push(Ray::new(o + DVec3::new(16.0, 0.0, 0.0), -d));
    }
    for s in [&union, &inter] {
        testing::check_alternation(s, &rays);
        for r in &rays {
            let (list, want) = (xs(s, r), xs(&*y(), r));
            assert_eq!(list.len(), 2, "{:?} {list:?}", s.op);
            for (h, k) in list.iter().zip(&want) {
                assert!((h.t - k.t).abs() < 1e-9, "{h:?} vs {k:?}");
                assert!(h.normal.dot(k.normal) > 0.0, "{h:?} vs {k:?}");
            }
        }
    }
}

/// A box standing on the floor (a half-space) is one solid with it: a
/// line rising from inside the floor through the box's base meets no
/// surface there, only the box's top. The base and the floor's plane are
/// worked out by different arithmetic (a box's slab by the reciprocal, a
/// plane by division), so along the line they may be an ulp apart: at
/// size 1e8 (t ~ 1e9, an ulp ~ 1e-7) that is far above any absolute
/// tolerance, and the two must still count as touching.
#[test]
fn a_box_standing_on_the_floor_shows_no_base_at_any_scale() {
    let _watchdog = crate::watchdog::start();
    let mut rnd = testing::numbers(75);
    for size in [1.0, 1e8] {
        let u = Csg::new(
            CsgOp::Union,
            vec![
                Box::new(Plane::new(DVec3::Y, 0.0, 3)) as Box<dyn Shape>,
                cube(
                    DVec3::new(-size, 0.0, -size),
                    DVec3::new(size, 2.0 * size, size),
                    1,
                ),
            ],
        );
        for _ in 0..300 {
            let o = DVec3::new(0.8 * rnd(), -3.0 - rnd(), 0.8 * rnd()) * size;
            let d = DVec3::new(0.02 * rnd(), 1.0, 0.02 * rnd()).normalize();
            let r = Ray::new(o, d);
            let h = u.intersect(&r, 0.0, f64::INFINITY).expect("the box's top");
            assert_eq!(h.material, 1, "size {size}: {h:?}");
            let top = (2.0 * size - o.y) / d.y;
            assert!((h.t - top).abs() < 1e-9 * top, "size {size}: {h:?}");
            assert!(u.occludes(&r, 0.0, f64::INFINITY));
            assert!(!u.occludes(&r, 0.0, top * (1.0 - 1e-6)));
        }
    }
}

/// A union of two half-spaces (no bounded child at all): where the line
/// runs inside one of them, the other's plane is an inner surface and
/// does not show; where it runs outside both, the nearer plane does.
#[test]
fn a_union_of_half_spaces_hides_the_planes_inside_it() {
    let _watchdog = crate::watchdog::start();
    let u = Csg::new(
        CsgOp::Union,
        vec![
            Box::new(Plane::new(DVec3::Y, 0.0, 1)) as Box<dyn Shape>,
            Box::new(Plane::new(DVec3::X, 0.0, 2)),
        ],
    );
    // Inside y < 0 all along, across x = 0: nothing.
    let below = Ray::new(DVec3::new(-5.0, -1.0, 0.0), DVec3::X);
    assert!(u.intersect(&below, 0.0, f64::INFINITY).is_none());
    assert!(!u.occludes(&below, 0.0, f64::INFINITY));
    // Starting in x < 0 and rising out of y < 0 as well: inside x < 0
    // until x = 0 (t = 10), by then above y = 0 (t = 5): only x = 0.
    let rising = Ray::new(DVec3::new(-5.0, -2.5, 0.0), DVec3::new(0.5, 0.5, 0.0));
    let h = u
        .intersect(&rising, 0.0, f64::INFINITY)
        .expect("the plane x = 0");
    assert!((h.t - 10.0).abs() < 1e-12 && h.material == 2, "{h:?}");
    // Outside both, coming down: the nearer plane, y = 0, is entered.
    let falling = Ray::new(DVec3::new(5.0, 5.0, 0.0), DVec3::new(-0.5, -1.0, 0.0));
    let h = u
        .intersect(&falling, 0.0, f64::INFINITY)
        .expect("the plane y = 0");
    assert!((h.t - 5.0).abs() < 1e-12 && h.material == 1, "{h:?}");
}

/// A floor (a half-space) with a ball buried in it, one poking out of it
/// and one resting above it: lines rising out of the floor, or sinking
/// into it, through the buried ball. The ball's surface is inside the
/// floor, so it never shows; the nearest hit and the shadow test in any
/// window agree with the crossing list, which agrees with point
/// membership. (A union asks a child whose reach along the line overlaps
/// no other's directly: the floor's reach must run from where the line
/// is first inside it to where it is last, not from crossing to crossing.)
#[test]
fn a_floor_hides_what_is_buried_in_it_in_every_window() {
    let _watchdog = crate::watchdog::start();
    let u = Csg::new(
        CsgOp::Union,
        vec![
            Box::new(Plane::new(DVec3::Y, 0.0, 3)) as Box<dyn Shape>,
            sphere(DVec3::new(0.0, -3.0, 0.0), 1.0, 1),
            sphere(DVec3::new(3.0, 0.0, 0.0), 1.0, 2),
            sphere(DVec3::new(-3.0, 2.0, 0.0), 1.0, 4),
        ],
    );
    let inside = |p: DVec3| {
        p.y < 0.0
            || (p - DVec3::new(3.0, 0.0, 0.0)).length() < 1.0
            || (p - DVec3::new(-3.0, 2.0, 0.0)).length() < 1.0
    };
    let mut rnd = testing::numbers(76);
    let mut rays = Vec::new();
    for _ in 0..100 {
        let d = DVec3::new(0.3 * rnd(), 1.0, 0.3 * rnd()).normalize();
        let through = DVec3::new(0.5 * rnd(), -3.0, 0.5 * rnd());
        // Rising from 5 below the buried ball, and sinking from 8 above it.
        rays.push(Ray::new(through - 5.0 * d, d));
        rays.push(Ray::new(through + 8.0 * d, -d));
    }
    rays.extend(testing::rays_towards(
        DVec3::new(0.0, -1.0, 0.0),
        3.0,
        200,
        77,
    ));
    let mut shown = 0;
    for (k, r) in rays.iter().enumerate() {
        let list = xs(&u, r);
        for h in &list {
            // Every surface the union shows is outside the buried ball.
            assert!((r.at(h.t) - DVec3::new(0.0, -3.0, 0.0)).length() > 1.0 - 1e-9);
        }
        let start = inside(r.at(-1e3));
        for j in 0..120 {
            let t = j as f64 * 0.1 + 0.0123;
            if list.iter().any(|h| (h.t - t).abs() < 1e-6) {
                continue;
            }
            let by_list = list
                .iter()
                .rev()
                .find(|h| h.t < t)
                .map_or(start, |h| h.normal.dot(r.dir) < 0.0);
            assert_eq!(by_list, inside(r.at(t)), "t {t} {r:?}: {list:?}");
        }
        for (lo, hi) in [
            (1e-9, f64::INFINITY),
            (1.0 + (k % 5) as f64, f64::INFINITY),
            (3.0 + (k % 3) as f64, 9.0 + (k % 4) as f64),
            (-1e3, f64::INFINITY),
        ] {
            let want = list.iter().find(|h| h.t > lo && h.t < hi);
            let got = u.intersect(r, lo, hi);
            assert_eq!(got.map(|h| h.t), want.map(|h| h.t), "{lo}..{hi} {r:?}");
            assert_eq!(got.map(|h| h.material), want.map(|h| h.material));
            assert_eq!(u.occludes(r, lo, hi), want.is_some(), "{lo}..{hi} {r:?}");
            shown += want.is_some() as usize;
        }
    }
    assert!(shown > 400, "{shown}");
}

/// The window is open at both ends, as for every shape: a line starting
/// exactly on a union's face (t = 0 there, exactly) going in is not
/// hit there, and meets the far face, as the box the union makes does;
/// a window ending exactly at the far face does not hold it.
#[test]
fn a_union_does_not_report_a_crossing_at_the_window_start() {
    let _watchdog = crate::watchdog::start();
    let u = Csg::new(
        CsgOp::Union,
        vec![
            cube(DVec3::ZERO, DVec3::new(2.0, 1.0, 1.0), 1),
            cube(DVec3::new(1.0, 0.0, 0.0), DVec3::new(3.0, 1.0, 1.0), 1),
        ],
    );
    let whole = Cuboid::new(DVec3::ZERO, DVec3::new(3.0, 1.0, 1.0), [1; 6]);
    for (o, d) in [
        (DVec3::new(0.0, 0.5, 0.5), DVec3::X),
        (DVec3::new(3.0, 0.25, 0.5), -DVec3::X),
        (DVec3::new(0.0, 0.5, 0.25), DVec3::new(1.0, 0.1, 0.2)),
    ] {
        let r = Ray::new(o, d);
        assert_eq!(xs(&u, &r)[0].t, 0.0);
        let want = whole.intersect(&r, 0.0, f64::INFINITY).map(|h| h.t);
        assert!(want.is_some_and(|t| t > 1.0));
        // The far face is at t = 3 exactly: windows ending before it, and
        // at it, hold no crossing either.
        for (lo, hi) in [
            (0.0, f64::INFINITY),
            (0.0, 1.0),
            (0.0, 2.5),
            (0.5, 3.0),
            (0.0, 3.0),
        ] {
            let want = whole.intersect(&r, lo, hi).map(|h| h.t);
            assert_eq!(u.intersect(&r, lo, hi).map(|h| h.t), want, "{lo}..{hi}");
            assert_eq!(u.occludes(&r, lo, hi), want.is_some(), "{lo}..{hi}");
            assert_eq!(want.is_some(), hi == f64::INFINITY, "{lo}..{hi}");
        }
    }
}
