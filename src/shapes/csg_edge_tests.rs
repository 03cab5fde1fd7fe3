//! Unit tests of `csg.rs` at its edges: coincident surfaces worked out
//! by different arithmetic, features thinner than the sweep's tolerance,
//! half-spaces nearly along the line, and what a hit's path says (uv,
//! slopes, texture spaces). The shared helpers are `csg_tests.rs`'s.

use super::*;

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
            Some(m) => outer.texture_space(m, true),
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
