//! The world's searches (nearest hit, occlusion, the area lights' shafts
//! and the pixels' beams) against a linear scan and the tree.

use super::*;
use crate::geometry::DVec3;
use crate::shapes::{Plane, Sphere};

#[test]
fn world_agrees_with_a_linear_scan() {
    let _watchdog = crate::watchdog::start();
    let mut unit = beam::tests::rng(0x9e37_79b9_7f4a_7c15);
    let mut rnd = move || unit() * 2.0 - 1.0;
    let spheres: Vec<Sphere> = (0..300)
        .map(|i| {
            let c = DVec3::new(rnd(), rnd(), rnd()) * 10.0;
            Sphere::new(c, 0.1 + rnd().abs(), i)
        })
        .collect();
    let mut objects: Vec<Box<dyn Shape>> = spheres
        .iter()
        .map(|s| Box::new(s.clone()) as Box<dyn Shape>)
        .collect();
    objects.push(Box::new(Plane::new(DVec3::Y, -9.0, 999)));
    let clone = |objects: &[Box<dyn Shape>]| -> Vec<Box<dyn Shape>> {
        (0..objects.len())
            .map(|i| match i {
                300 => Box::new(Plane::new(DVec3::Y, -9.0, 999)) as Box<dyn Shape>,
                _ => Box::new(spheres[i].clone()),
            })
            .collect()
    };
    let kd = World::build_with(clone(&objects), Accel::KdTree);
    assert_eq!(kd.stats.unbounded, 1);
    assert!(kd.stats.tree.leaves > 10, "{:?}", kd.stats.tree);
    let mut worlds = vec![kd];
    for simd in [bvh::Simd::Scalar, bvh::Simd::Avx2] {
        let mut w = World::build_with(clone(&objects), Accel::Bvh);
        assert!(w.stats.bvh.is_some_and(|b| b.nodes > 5 && b.items == 300));
        w.set_simd(simd);
        worlds.push(w);
    }
    let floor = Plane::new(DVec3::Y, -9.0, 999);
    for _ in 0..3000 {
        let o = DVec3::new(rnd(), rnd(), rnd()) * 15.0;
        let d = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X);
        let ray = Ray::new(o, d);
        let want = spheres
            .iter()
            .map(|s| s as &dyn Shape)
            .chain([&floor as &dyn Shape])
            .filter_map(|s| s.intersect(&ray, 1e-9, f64::INFINITY))
            .min_by(|a, b| a.t.total_cmp(&b.t));
        for world in &worlds {
            let got = world.intersect(&ray, 1e-9, f64::INFINITY);
            assert_eq!(
                got.map(|h| (h.t, h.material)),
                want.map(|h| (h.t, h.material))
            );
            // Shadow rays: blocked just past the nearest hit, free just before.
            let t = want.map_or(f64::INFINITY, |h| h.t);
            assert_eq!(world.occludes(&ray, 1e-9, t * 1.001), want.is_some());
            if want.is_some() {
                assert!(!world.occludes(&ray, 1e-9, t * 0.999));
            }
        }
    }
}

#[test]
fn shaft_blockers_decide_every_ray_as_the_tree_does() {
    let _watchdog = crate::watchdog::start();
    let mut rnd = beam::tests::rng(0x2545_f491_4f6c_dd1d);
    // Small spheres in a 10-wide box above a floor; lights over them.
    let balls = random_balls(60, 0.1, 0.3, &mut rnd);
    // Both indexes find the blockers (each its own box query).
    for accel in [Accel::KdTree, Accel::Bvh] {
        let world = balls_over_a_floor(&balls, accel);
        blockers_decide_every_ray(&world, &mut rnd);
    }
}

#[test]
fn a_pixels_rays_find_among_their_beams_objects_what_the_tree_finds() {
    let _watchdog = crate::watchdog::start();
    let mut rnd = beam::tests::rng(0x0bea_3c0d);
    // 20 balls (tested in a row for the beam) and 60 (found in the
    // tree), over a floor, seen through a lens from around them.
    for (count, accel) in [(20, Accel::KdTree), (60, Accel::KdTree), (60, Accel::Bvh)] {
        let balls = random_balls(count, 0.2, 0.6, &mut rnd);
        let world = balls_over_a_floor(&balls, accel);
        let (mut used, mut few, mut hits, mut misses) = (0, 0, 0, 0);
        for _ in 0..300 {
            let eye = DVec3::new(rnd() * 24.0 - 12.0, 1.0 + rnd() * 6.0, 14.0);
            let target = DVec3::new(rnd() * 8.0 - 4.0, rnd() * 12.0, rnd() * 8.0 - 4.0);
            let f = beam::tests::family(eye, target - eye, 0.3 * rnd(), 2.0 + 20.0 * rnd());
            let Some(among) = world.beam_candidates(&f) else {
                continue;
            };
            used += 1;
            few += (among.len() <= 3) as u32;
            for _ in 0..24 {
                let lens = (2.0 * rnd() - 1.0, 2.0 * rnd() - 1.0);
                let ray = beam::tests::ray_of(&f, lens, (rnd(), rnd()));
                let (mut a, mut b) = (Hit::default(), Hit::default());
                let want = world.nearest_into(&ray, 0.0, f64::INFINITY, &mut a);
                let got = world.nearest_among(&among, &ray, 0.0, f64::INFINITY, &mut b);
                assert_eq!(want.is_some(), got.is_some());
                if let (Some(w), Some(g)) = (want, got) {
                    assert!(std::ptr::addr_eq(w, g), "another object");
                    assert_eq!((a.t, a.point), (b.t, b.point));
                    hits += 1;
                } else {
                    misses += 1;
                }
            }
        }
        // Most beams hold a few objects, and rays hit and miss.
        assert!(used > 250 && few > 150, "{count}: {used} {few}");
        assert!(hits > 1000 && misses > 100, "{count}: {hits} {misses}");
    }
    // No bounded object: the unbounded ones alone. One: the tree, whose
    // walk is that one box test.
    let floor = || Box::new(Plane::new(DVec3::Y, 0.0, 0)) as Box<dyn Shape>;
    let f = beam::tests::family(DVec3::new(0.0, 2.0, 5.0), -DVec3::Z, 0.1, 5.0);
    assert_eq!(
        World::build(vec![floor()])
            .beam_candidates(&f)
            .map(|b| b.len()),
        Some(1)
    );
    let ball = Box::new(Sphere::new(DVec3::new(0.0, 1.0, 0.0), 1.0, 0));
    assert!(
        World::build(vec![floor(), ball])
            .beam_candidates(&f)
            .is_none()
    );
}

#[test]
fn a_lights_blockers_over_a_pixels_hits_decide_its_shadow_rays() {
    let _watchdog = crate::watchdog::start();
    let mut rnd = beam::tests::rng(0x5ad0_77e5);
    let balls = random_balls(40, 0.2, 0.5, &mut rnd);
    for accel in [Accel::KdTree, Accel::Bvh] {
        let world = balls_over_a_floor(&balls, accel);
        let (mut used, mut blocked, mut clear) = (0, 0, 0);
        for _ in 0..300 {
            // A pixel's hits: a small box on or over the floor.
            let c = DVec3::new(rnd() * 10.0 - 5.0, rnd() * 3.0 - 0.5, rnd() * 10.0 - 5.0);
            let points = Aabb::new(c, c + DVec3::new(rnd(), rnd(), rnd()) * 0.3);
            let light = DVec3::new(rnd() * 10.0 - 5.0, 7.0, rnd() * 10.0 - 5.0);
            let Some(mut b) = Shaft::towards_box(light, &points).and_then(|s| world.blockers(&s))
            else {
                continue;
            };
            used += 1;
            for _ in 0..16 {
                let p = points.min + (points.max - points.min) * DVec3::new(rnd(), rnd(), rnd());
                let d = light - p;
                let (ray, reach) = (Ray::new(p, d.normalize()), d.length() * (1.0 - 1e-4));
                let want = world.occludes(&ray, 0.0, reach);
                assert_eq!(world.occludes_among(&mut b, &ray, 0.0, reach), want);
                if want {
                    blocked += 1;
                } else {
                    clear += 1;
                }
            }
        }
        assert!(used > 250, "{used}");
        assert!(blocked > 300 && clear > 1000, "{blocked} {clear}");
    }
}

/// `n` balls (centre, radius) in a 10-wide, 4-high box: radii from
/// `r0` to `r0 + dr`.
fn random_balls(n: usize, r0: f64, dr: f64, rnd: &mut impl FnMut() -> f64) -> Vec<(DVec3, f64)> {
    (0..n)
        .map(|_| {
            let c = DVec3::new(rnd() * 10.0 - 5.0, rnd() * 4.0, rnd() * 10.0 - 5.0);
            (c, r0 + dr * rnd())
        })
        .collect()
}

/// Spheres (centre, radius) over the floor y = −0.5, indexed by `accel`.
fn balls_over_a_floor(balls: &[(DVec3, f64)], accel: Accel) -> World {
    let mut objects: Vec<Box<dyn Shape>> = balls
        .iter()
        .enumerate()
        .map(|(i, &(c, r))| Box::new(Sphere::new(c, r, i as u32)) as Box<dyn Shape>)
        .collect();
    objects.push(Box::new(Plane::new(DVec3::Y, -0.5, 999)));
    World::build_with(objects, accel)
}

fn blockers_decide_every_ray(world: &World, rnd: &mut impl FnMut() -> f64) {
    let (mut used, mut empty, mut blocked, mut clear) = (0, 0, 0, 0);
    for _ in 0..400 {
        let apex = DVec3::new(rnd() * 10.0 - 5.0, rnd() * 4.0 - 0.4, rnd() * 10.0 - 5.0);
        let corner = DVec3::new(rnd() * 8.0 - 4.0, 6.0 + rnd(), rnd() * 8.0 - 4.0);
        let (eu, ev) = (
            DVec3::new(0.5 + rnd(), 0.1, 0.0),
            DVec3::new(0.0, 0.0, 0.5 + rnd()),
        );
        let corners = [corner, corner + eu, corner + eu + ev, corner + ev];
        let Some(shaft) = Shaft::new(apex, corners) else {
            continue;
        };
        let Some(mut b) = world.blockers(&shaft) else {
            continue;
        };
        used += 1;
        empty += b.is_empty() as u32;
        for _ in 0..16 {
            let y = corner + rnd() * eu + rnd() * ev;
            let dist = (y - apex).length() * (1.0 - 1e-4);
            let ray = Ray::new(apex, (y - apex).normalize());
            let want = world.occludes(&ray, 0.0, dist);
            assert_eq!(world.occludes_among(&mut b, &ray, 0.0, dist), want);
            if want {
                blocked += 1;
            } else {
                clear += 1;
            }
        }
    }
    // Every case was met: shafts with and without blockers, rays
    // blocked and clear.
    assert!(used > 200 && empty > 20 && empty < used, "{used} {empty}");
    assert!(blocked > 200 && clear > 200, "{blocked} {clear}");
}

#[test]
fn a_floor_below_the_shaft_is_no_blocker_and_one_across_it_is() {
    let _watchdog = crate::watchdog::start();
    let corners = shaft::tests::light_square();
    let shaft = Shaft::new(DVec3::new(0.0, 1e-6, 0.0), corners).unwrap();
    let below = World::build(vec![Box::new(Plane::new(DVec3::Y, 0.0, 0))]);
    assert!(below.blockers(&shaft).unwrap().is_empty());
    let across = World::build(vec![Box::new(Plane::new(DVec3::Y, 3.0, 0))]);
    assert_eq!(across.blockers(&shaft).unwrap().len(), 1);
    // A tilted plane through the apex's side of the shaft.
    let tilted = World::build(vec![Box::new(Plane::new(
        DVec3::new(1.0, 0.2, 0.0),
        0.5,
        0,
    ))]);
    assert_eq!(tilted.blockers(&shaft).unwrap().len(), 1);
}

/// A ray through the boxes of a long row of balls, missing every
/// ball: each index tests them all (the kd-tree's mailbox sees far
/// more than it holds) and finds nothing; one a little lower hits the
/// first ball.
#[test]
fn a_ray_past_a_long_row_tests_every_object_and_finds_nothing() {
    let _watchdog = crate::watchdog::start();
    for accel in [Accel::KdTree, Accel::Bvh] {
        let objects: Vec<Box<dyn Shape>> = (0..200)
            .map(|i| {
                let c = DVec3::new(i as f64 * 1.25, 0.0, 0.0);
                Box::new(Sphere::new(c, 0.5, i)) as Box<dyn Shape>
            })
            .collect();
        let world = World::build_with(objects, accel);
        // At 0.45 from the axis in y and z: inside every box, 0.64
        // from every centre.
        let past = Ray::new(DVec3::new(-2.0, 0.45, 0.45), DVec3::X);
        assert!(world.intersect(&past, 0.0, f64::INFINITY).is_none());
        assert!(!world.occludes(&past, 0.0, f64::INFINITY));
        let hit = Ray::new(DVec3::new(-2.0, 0.3, 0.0), DVec3::X);
        let h = world.intersect(&hit, 0.0, f64::INFINITY).unwrap();
        assert_eq!(h.material, 0);
        assert!((h.t - (2.0 - (0.25f64 - 0.09).sqrt())).abs() < 1e-12);
    }
}

#[test]
fn accel_names_round_trip() {
    for (name, a) in Accel::NAMES
        .iter()
        .zip([Accel::Auto, Accel::KdTree, Accel::Bvh])
    {
        assert_eq!(Accel::from_name(name), Some(a));
        assert_eq!(a.name(), *name);
    }
    assert_eq!(Accel::from_name("kd-tree"), None);
    assert_eq!(Accel::from_name(""), None);
}

/// A plane across the shaft (unbounded, listed apart) and balls in it
/// and beside it: the listed blockers decide every ray of the grid as
/// the whole world does, the plane's rays and the balls' alike.
#[test]
fn unbounded_and_bounded_blockers_decide_the_rays() {
    let _watchdog = crate::watchdog::start();
    let corners = shaft::tests::light_square();
    let apex = DVec3::new(0.1, 0.0, -0.2);
    let shaft = Shaft::new(apex, corners).unwrap();
    for accel in [Accel::KdTree, Accel::Bvh] {
        // The plane tilted so that it blocks the rays to one side of
        // the light only; one ball inside the shaft, one beside it.
        let objects: Vec<Box<dyn Shape>> = vec![
            Box::new(Sphere::new(DVec3::new(5.0, 3.0, 0.0), 0.5, 0)),
            Box::new(Plane::new(DVec3::new(1.0, 0.3, 0.0).normalize(), 1.6, 1)),
            Box::new(Sphere::new(DVec3::new(-0.4, 4.0, 0.3), 0.3, 2)),
        ];
        let world = World::build_with(objects, accel);
        let mut b = world.blockers(&shaft).unwrap();
        assert_eq!(b.len(), 2, "{accel:?}");
        let (mut blocked, mut clear) = (0, 0);
        for i in 0..=20 {
            for j in 0..=20 {
                let y = DVec3::new(-1.0 + 0.1 * i as f64, 6.0, -1.0 + 0.1 * j as f64);
                let dist = (y - apex).length() * (1.0 - 1e-4);
                let ray = Ray::new(apex, (y - apex) / (y - apex).length());
                let want = world.occludes(&ray, 0.0, dist);
                assert_eq!(world.occludes_among(&mut b, &ray, 0.0, dist), want);
                if want {
                    blocked += 1;
                } else {
                    clear += 1;
                }
            }
        }
        assert!(blocked > 50 && clear > 50, "{blocked} {clear}");
    }
}

#[test]
fn more_blockers_than_the_list_holds_send_the_rays_to_the_tree() {
    let _watchdog = crate::watchdog::start();
    let corners = shaft::tests::light_square();
    let shaft = Shaft::new(DVec3::ZERO, corners).unwrap();
    for n in [Blockers::MAX, Blockers::MAX + 1] {
        for accel in [Accel::KdTree, Accel::Bvh] {
            let objects: Vec<Box<dyn Shape>> = (0..n)
                .map(|i| {
                    let c = DVec3::new(0.0, 1.0 + 0.5 * i as f64, 0.0);
                    Box::new(Sphere::new(c, 0.1, i as u32)) as Box<dyn Shape>
                })
                .collect();
            let world = World::build_with(objects, accel);
            let found = world.blockers(&shaft);
            // As many as the list holds are listed; one more, none.
            assert_eq!(found.map(|b| b.len()), (n == Blockers::MAX).then_some(n));
        }
    }
}

#[test]
fn a_few_objects_get_a_leaf_each_and_no_empty_cells() {
    // glass_full's five objects: the world's SAH constants (no bonus for
    // cutting off empty space) keep the tree to one leaf per object, not
    // a ladder of empty cells that every ray steps through.
    let balls = [
        (DVec3::new(-1.3, 1.0, 0.0), 1.0),
        (DVec3::new(1.3, 0.62, 0.6), 0.85),
        (DVec3::new(0.4, 0.4, 2.2), 0.4),
        (DVec3::new(0.1, 0.5, -1.8), 0.5),
        (DVec3::new(1.8, 1.2, -2.2), 0.7),
    ];
    let world = balls_over_a_floor(&balls, Accel::KdTree);
    let t = world.stats.tree;
    assert_eq!((t.leaves, t.empty_leaves, t.references), (5, 0, 5), "{t:?}");
    assert!(t.max_depth <= 3, "{t:?}");
}

/// A pixel's rays found together ([`World::first_hits`]) hit what each
/// finds alone among its beam's objects: the same object and the same hit
/// to the bit, for shapes with roots apart from their hits (balls, the
/// floor) and without (boxes), in any order the beam lists them, for
/// counts that fill the four lanes and leave a tail.
#[test]
fn a_pixels_rays_found_together_hit_what_each_finds_alone() {
    let _watchdog = crate::watchdog::start();
    let mut rnd = beam::tests::rng(0x00f1_25a7);
    let balls = random_balls(14, 0.2, 0.6, &mut rnd);
    let mut objects: Vec<Box<dyn Shape>> = balls
        .iter()
        .enumerate()
        .map(|(i, &(c, r))| -> Box<dyn Shape> {
            if i % 3 == 0 {
                let h = DVec3::splat(r);
                Box::new(crate::shapes::Cuboid::new(c - h, c + h, [i as u32; 6]))
            } else {
                Box::new(Sphere::new(c, r, i as u32))
            }
        })
        .collect();
    objects.push(Box::new(Plane::new(DVec3::Y, -0.5, 999)));
    let world = World::build(objects);
    let mut scratch = FirstHits::default();
    let (mut hits_seen, mut misses, mut boxes) = (0, 0, 0);
    for trial in 0..300 {
        let eye = DVec3::new(rnd() * 24.0 - 12.0, 1.0 + rnd() * 6.0, 14.0);
        let target = DVec3::new(rnd() * 8.0 - 4.0, rnd() * 4.0, rnd() * 8.0 - 4.0);
        let f = beam::tests::family(eye, target - eye, 0.3 * rnd(), 2.0 + 20.0 * rnd());
        let Some(among) = world.beam_candidates(&f) else {
            continue;
        };
        let n = [32, 9, 7, 16, 1][trial % 5];
        let rays: Vec<Ray> = (0..n)
            .map(|_| {
                let lens = (2.0 * rnd() - 1.0, 2.0 * rnd() - 1.0);
                beam::tests::ray_of(&f, lens, (rnd(), rnd()))
            })
            .collect();
        let mut hits = vec![Hit::default(); n];
        let mut objects = Vec::new();
        world.first_hits(&among, &rays, &mut hits, &mut objects, &mut scratch);
        assert_eq!(objects.len(), n);
        for (i, ray) in rays.iter().enumerate() {
            let mut want = Hit::default();
            match (
                world.nearest_among(&among, ray, 0.0, f64::INFINITY, &mut want),
                objects[i],
            ) {
                (Some(w), Some(g)) => {
                    assert!(std::ptr::addr_eq(w, g), "another object");
                    assert_eq!(format!("{:?}", hits[i]), format!("{want:?}"));
                    hits_seen += 1;
                    boxes += (want.material % 3 == 0 && want.material != 999) as u32;
                }
                (None, None) => misses += 1,
                (w, g) => panic!("alone {:?}, together {:?}", w.is_some(), g.is_some()),
            }
        }
    }
    assert!(
        hits_seen > 1000 && misses > 10 && boxes > 50,
        "{hits_seen} {misses} {boxes}"
    );
    // A box listed first holds the ray's hit, then a ball listed after it
    // comes nearer: the ball's hit is the one made.
    let world = World::build(vec![
        Box::new(crate::shapes::Cuboid::new(
            DVec3::new(-1.0, 0.0, -6.0),
            DVec3::new(1.0, 2.0, -4.0),
            [7; 6],
        )),
        Box::new(Sphere::new(DVec3::new(0.0, 1.0, 0.0), 1.0, 8)),
    ]);
    let mut among = Blockers::default();
    assert!(among.push(0) && among.push(1));
    let rays: Vec<Ray> = (0..6)
        .map(|i| Ray::new(DVec3::new(0.1 * i as f64, 1.0, 10.0), -DVec3::Z))
        .collect();
    let mut hits = vec![Hit::default(); rays.len()];
    let mut objects = Vec::new();
    world.first_hits(&among, &rays, &mut hits, &mut objects, &mut scratch);
    for (ray, hit) in rays.iter().zip(&hits) {
        let mut want = Hit::default();
        assert!(
            world
                .nearest_among(&among, ray, 0.0, f64::INFINITY, &mut want)
                .is_some()
        );
        assert_eq!((hit.material, format!("{hit:?}")), (8, format!("{want:?}")));
    }
}
