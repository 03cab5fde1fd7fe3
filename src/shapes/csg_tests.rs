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

/// The y = 0 floor (solid below) in material 3.
fn floor() -> Box<dyn Shape> {
    Box::new(Plane::new(DVec3::Y, 0.0, 3))
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

/// `u`'s answers in the window (lo, hi) against its crossing list
/// `list`: the nearest hit by value and written in place (on a miss the
/// caller's hit, a nearer one found elsewhere, stays as it was), and the
/// shadow test. Whether it hit.
fn agrees_with_the_list(u: &Csg, r: &Ray, list: &[Hit], lo: f64, hi: f64) -> bool {
    let want = list.iter().find(|h| h.t > lo && h.t < hi);
    let got = u.intersect(r, lo, hi);
    let key = |h: &Hit| (h.t, h.material, h.path);
    assert_eq!(
        got.as_ref().map(key),
        want.map(key),
        "{r:?} window {lo}..{hi}"
    );
    assert_eq!(
        u.occludes(r, lo, hi),
        want.is_some(),
        "{r:?} window {lo}..{hi}"
    );
    let before = Hit {
        t: -7.0,
        material: 99,
        path: 5,
        ..Hit::default()
    };
    let mut into = before;
    assert_eq!(u.intersect_into(r, lo, hi, &mut into), want.is_some());
    assert_eq!(
        key(&into),
        want.map_or(key(&before), key),
        "{r:?} window {lo}..{hi}"
    );
    want.is_some()
}

#[test]
fn union_of_apart_children_agrees_with_the_sweep() {
    let _watchdog = crate::watchdog::start();
    // Children whose reaches along a ray do not overlap are asked for
    // their nearest hit directly; that must be what the full crossing
    // list says, in any window, floor included.
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
        hits += usize::from(agrees_with_the_list(&u, r, &list, lo, hi));
    }
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

// Coincident surfaces, tolerances at faces, crossings nearly along the
// line and the hit's path: in a file of their own, beside these.
#[path = "csg_edge_tests.rs"]
mod edge;

/// Which unions count as made of clear children, and which of those
/// children may touch: balls and a box standing on the floor apart from
/// each other are clear, each touching the floor only; a box stacked on
/// another touches it; overlapping solids, or two planes, are not clear.
#[test]
fn a_union_knows_when_its_children_are_clear_of_each_other() {
    let standing = Csg::new(
        CsgOp::Union,
        vec![
            sphere(DVec3::new(-2.0, 1.0, 0.0), 1.0, 1),
            cube(DVec3::new(0.5, 0.0, -0.5), DVec3::new(1.5, 2.0, 0.5), 2),
            floor(),
            sphere(DVec3::new(0.0, 3.0, 0.0), 0.5, 4),
        ],
    );
    assert!(standing.disjoint);
    assert_eq!(standing.touch, vec![0b100, 0b100, 0b011, 0]);
    let stacked = Csg::new(
        CsgOp::Union,
        vec![
            cube(DVec3::ZERO, DVec3::ONE, 1),
            cube(DVec3::Y, DVec3::new(1.0, 2.0, 1.0), 2),
        ],
    );
    assert!(stacked.disjoint);
    assert_eq!(stacked.touch, vec![0b10, 0b01]);
    let overlapping = [
        vec![sphere(DVec3::ZERO, 1.0, 1), sphere(DVec3::X, 1.0, 2)],
        vec![sphere(DVec3::new(0.0, 0.9, 0.0), 1.0, 1), floor()],
        vec![
            floor(),
            Box::new(Plane::new(DVec3::X, 5.0, 3)) as Box<dyn Shape>,
        ],
    ];
    for children in overlapping {
        assert!(!Csg::new(CsgOp::Union, children).disjoint);
    }
    // Only a union takes the shortcut.
    let apart = || {
        vec![
            sphere(-DVec3::X * 3.0, 1.0, 1),
            sphere(DVec3::X * 3.0, 1.0, 2),
        ]
    };
    assert!(Csg::new(CsgOp::Union, apart()).disjoint);
    assert!(!Csg::new(CsgOp::Difference, apart()).disjoint);
    // Up to the 64 children a bit set holds, and no further.
    let row = |n: usize| {
        let balls = (0..n)
            .map(|i| sphere(DVec3::X * (3 * i) as f64, 1.0, 1))
            .collect();
        Csg::new(CsgOp::Union, balls)
    };
    assert!(row(64).disjoint);
    assert!(!row(65).disjoint);
    // Touching is judged with a little room, a billionth of the boxes'
    // size and distance from the origin (and a billionth): millimetre
    // boxes at the origin 1e-10 apart touch, 1e-6 apart do not; boxes a
    // thousand units out touch 1e-8 apart, not 1e-4.
    let cubes = |at: f64, size: f64, gap: f64| {
        let a = DVec3::splat(at);
        let b = a + DVec3::splat(size + gap);
        Csg::new(
            CsgOp::Union,
            vec![cube(a, a + size, 1), cube(b, b + size, 2)],
        )
    };
    for (at, size, gap, touch) in [
        (0.0, 1e-3, 1e-10, true),
        (0.0, 1e-3, 1e-6, false),
        (1000.0, 1.0, 1e-8, true),
        (1000.0, 1.0, 1e-4, false),
    ] {
        let pair = cubes(at, size, gap);
        assert!(pair.disjoint);
        let want = if touch { vec![0b10, 0b01] } else { vec![0, 0] };
        assert_eq!(pair.touch, want, "at {at} gap {gap}");
    }
}

/// A union of clear children answers from their own nearest hits; that
/// must be what the full crossing list says, in any window, for rays from
/// outside and from inside a child, and where children touch (a ray going
/// up through the face two stacked boxes share, which the union does not
/// have, or through the point where a ball touches the floor).
#[test]
fn union_of_clear_children_agrees_with_the_sweep() {
    let _watchdog = crate::watchdog::start();
    let u = Csg::new(
        CsgOp::Union,
        vec![
            sphere(DVec3::new(-1.5, 1.0, 0.0), 1.0, 1),
            cube(DVec3::new(0.5, 0.0, -0.5), DVec3::new(1.5, 1.0, 0.5), 2),
            floor(),
            cube(DVec3::new(0.5, 1.0, -0.5), DVec3::new(1.5, 2.0, 0.5), 4),
        ],
    );
    assert!(u.disjoint);
    let mut rays = testing::rays_towards(DVec3::new(0.0, 1.0, 0.0), 2.5, 600, 71);
    // From inside the lower box and the ball, straight up and aslant:
    // through the shared face, the ball's top, the contact with the floor.
    for (from, dir) in [
        (DVec3::new(1.0, 0.5, 0.0), DVec3::Y),
        (DVec3::new(1.2, 0.3, 0.1), DVec3::new(0.1, 1.0, -0.2)),
        (DVec3::new(-1.5, 1.0, 0.0), DVec3::Y),
        (DVec3::new(-1.5, 1.5, 0.0), -DVec3::Y),
        (DVec3::new(-1.5, 5.0, 0.0), -DVec3::Y),
        (DVec3::new(1.0, 5.0, 0.0), -DVec3::Y),
        (DVec3::new(1.0, -0.5, 0.0), DVec3::Y),
    ] {
        rays.push(Ray::new(from, dir.normalize()));
    }
    let mut hits = 0;
    for (k, r) in rays.iter().enumerate() {
        let list = xs(&u, r);
        for (lo, hi) in [
            (1e-9, f64::INFINITY),
            (-1.0, f64::INFINITY),
            (0.2 + (k % 7) as f64 * 0.5, 9.0 + (k % 5) as f64),
        ] {
            hits += usize::from(agrees_with_the_list(&u, r, &list, lo, hi));
        }
    }
    assert!(hits > 800, "{hits}");
}
