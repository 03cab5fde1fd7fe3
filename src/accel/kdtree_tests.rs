//! The kd-tree's tests: an empty tree, a row of boxes walked front to back,
//! flat boxes in every axis, rays lying in a split plane.

use super::*;
use crate::geometry::DVec3;

fn unit_boxes(centres: &[DVec3]) -> Vec<Aabb> {
    centres
        .iter()
        .map(|&c| Aabb::new(c - DVec3::splat(0.5), c + DVec3::splat(0.5)))
        .collect()
}

#[test]
fn empty_tree_finds_nothing() {
    let _watchdog = crate::watchdog::start();
    let t = KdTree::build(&[]);
    let r = Ray::new(DVec3::ZERO, DVec3::X);
    assert!(
        t.nearest(&r, 0.0, f64::INFINITY, |_, _| Some(1.0))
            .is_none()
    );
    assert!(!t.any(&r, 0.0, f64::INFINITY, |_| true));
}

#[test]
fn splits_a_row_of_boxes_and_walks_front_to_back() {
    let _watchdog = crate::watchdog::start();
    let centres: Vec<DVec3> = (0..100)
        .map(|i| DVec3::new(i as f64 * 3.0, 0.0, 0.0))
        .collect();
    let boxes = unit_boxes(&centres);
    let t = KdTree::build(&boxes);
    assert!(t.stats.leaves > 10, "{:?}", t.stats);
    // Along +x the first box met is item 0; along -x from the far end, item 99.
    let mut order = Vec::new();
    t.along_line(&Ray::new(DVec3::new(-5.0, 0.0, 0.0), DVec3::X), |i| {
        order.push(i)
    });
    order.dedup();
    assert_eq!(order.first(), Some(&0));
    let mut seen = Vec::new();
    let hit = t.nearest(
        &Ray::new(DVec3::new(400.0, 0.0, 0.0), -DVec3::X),
        0.0,
        f64::INFINITY,
        |i, best| {
            seen.push(i);
            let tt = 400.0 - (centres[i as usize].x + 0.5);
            (tt < best).then_some(tt)
        },
    );
    assert_eq!(hit, Some(400.0 - 297.5));
    assert!(
        seen.len() < 10,
        "early exit failed: {} items tested",
        seen.len()
    );
}

/// Flat shapes (a rectangle in x = c) have boxes of zero thickness in
/// one axis: each must stay in the tree, in every axis.
#[test]
fn flat_boxes_in_every_axis_are_kept() {
    let _watchdog = crate::watchdog::start();
    for axis in 0..3 {
        let boxes: Vec<Aabb> = (0..40)
            .map(|i| {
                let (mut lo, mut hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
                lo[axis] = i as f64 * 2.0;
                hi[axis] = i as f64 * 2.0;
                Aabb::new(lo, hi)
            })
            .collect();
        let t = KdTree::build(&boxes);
        let mut dir = DVec3::ZERO;
        dir[axis] = 1.0;
        let mut seen = Vec::new();
        t.along_line(&Ray::new(dir * -5.0 + 0.1, dir), |i| seen.push(i));
        seen.sort();
        seen.dedup();
        assert_eq!(seen, (0..40).collect::<Vec<u32>>(), "axis {axis}");
        // And the nearest is the first plane along the ray.
        let hit = t.nearest(
            &Ray::new(dir * -5.0 + 0.1, dir),
            0.0,
            f64::INFINITY,
            |i, best| {
                let tt = 5.0 + i as f64 * 2.0;
                (tt < best).then_some(tt)
            },
        );
        assert_eq!(hit, Some(5.0), "axis {axis}");
    }
}

#[test]
fn rays_in_a_split_plane_see_both_sides() {
    let _watchdog = crate::watchdog::start();
    // Two boxes meeting at x = 0; a ray lying in that plane along y.
    let boxes = vec![
        Aabb::new(DVec3::new(-1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 1.0)),
        Aabb::new(DVec3::new(0.0, 5.0, 0.0), DVec3::new(1.0, 6.0, 1.0)),
    ];
    let t = KdTree::build(&boxes);
    let mut seen = Vec::new();
    t.along_line(&Ray::new(DVec3::new(0.0, -3.0, 0.5), DVec3::Y), |i| {
        seen.push(i)
    });
    seen.sort();
    seen.dedup();
    assert_eq!(seen, vec![0, 1]);
}

/// A ray lying in a face's plane of the tree's own box (the low or the
/// high face, in each axis) runs along that face: it meets the boxes
/// touching it. (`Aabb::clip` used to drop the face's NaN slab in favour
/// of the other plane's ±inf, and the walk saw nothing; the mesh test
/// `kd_tree_loses_a_ray_along_a_box_face` was this.)
#[test]
fn rays_along_the_trees_own_faces_meet_what_touches_them() {
    let _watchdog = crate::watchdog::start();
    for axis in 0..3 {
        let along = (axis + 1) % 3;
        // A row of unit boxes along `along`, spanning [0, 1] in `axis`.
        let centres: Vec<DVec3> = (0..20)
            .map(|i| {
                let mut c = DVec3::splat(0.5);
                c[along] = i as f64 * 2.0 + 0.5;
                c
            })
            .collect();
        let t = KdTree::build(&unit_boxes(&centres));
        for face in [0.0, 1.0] {
            let mut o = DVec3::splat(0.5);
            o[axis] = face;
            o[along] = -3.0;
            let mut d = DVec3::ZERO;
            d[along] = 1.0;
            let mut seen = Vec::new();
            t.along_line(&Ray::new(o, d), |i| seen.push(i));
            seen.sort();
            seen.dedup();
            assert_eq!(
                seen,
                (0..20).collect::<Vec<u32>>(),
                "axis {axis}, face {face}"
            );
            let hit = t.nearest(&Ray::new(o, d), 0.0, f64::INFINITY, |i, best| {
                let tt = 3.0 + i as f64 * 2.0;
                (tt < best).then_some(tt)
            });
            assert_eq!(hit, Some(3.0), "axis {axis}, face {face}");
        }
    }
}

/// A ray lying in a split plane is sent down both sides with the whole
/// segment, so the side walked first may hold only the farther hit: the
/// walk must still try the other (found by
/// `kd_tree_agrees_with_brute_force_on_boxes`; it used to stop at the
/// first side's hit, here the box at y = 0 instead of the nearer one at
/// y = 0.25).
#[test]
fn a_ray_in_a_split_plane_finds_the_nearer_side() {
    let _watchdog = crate::watchdog::start();
    let boxes = [
        Aabb::new(
            DVec3::new(-0.5, 0.2476203610301246, -1.353697931560444),
            DVec3::new(0.0, 0.2476203610301246, 0.0),
        ),
        Aabb::new(
            DVec3::new(-1.0, 0.0, -1.4404486195592168),
            DVec3::new(-0.5, 0.0, 0.0),
        ),
    ];
    let t = KdTree::build(&boxes);
    assert!(t.stats.leaves > 1, "{:?}", t.stats);
    // (+0 in x: the side below x = −0.5, with the farther box, is walked
    // first; −0 walks the other first.)
    for (o_y, t_min, dx) in [
        (1.0, 0.0, 0.0),
        (0.0, -1.0, 0.0),
        (0.5, 0.0, 0.0),
        (1.0, 0.0, -0.0),
    ] {
        let ray = Ray::new(
            DVec3::new(-0.5, o_y, -0.8378713849999211),
            DVec3::new(dx, -1.0, 0.0),
        );
        let enter = |i: u32, best: f64| {
            boxes[i as usize]
                .clip(&ray, t_min, f64::INFINITY)
                .map(|c| c.0)
                .filter(|&e| e > t_min && e < best)
        };
        let hit = t.nearest(&ray, t_min, f64::INFINITY, enter);
        assert_eq!(hit, Some(o_y - 0.2476203610301246), "from y = {o_y}");
    }
}

mod props {
    use super::*;
    use crate::accel::bvh::tests::{direction, point};
    use proptest::prelude::*;

    /// A box from two grid points, often flat in one axis.
    fn grid_box() -> impl Strategy<Value = Aabb> {
        (point(), point(), 0usize..4).prop_map(|(a, b, flat)| {
            let mut b = b;
            if flat < 3 {
                b[flat] = a[flat];
            }
            Aabb::new(a, b)
        })
    }

    /// Where the ray enters box `b` within `(t_min, t_max)`, as an item's
    /// hit: the box's own slab entry.
    fn entry(b: &Aabb, ray: &Ray, t_min: f64, t_max: f64) -> Option<f64> {
        b.clip(ray, t_min, f64::INFINITY)
            .map(|(lo, _)| lo)
            .filter(|&t| t > t_min && t < t_max)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

        /// The scene kd-tree against brute force over its boxes: rays with
        /// zero components (axis-parallel, or in a flat box's plane, of
        /// either sign), from inside boxes and on their faces, flat boxes
        /// in every axis, windows ending at the nearest entry. Every box
        /// the line crosses is visited; the nearest entry and any-hit
        /// agree.
        #[test]
        fn kd_tree_agrees_with_brute_force_on_boxes(
            boxes in prop::collection::vec(grid_box(), 1..60),
            rays in prop::collection::vec((point(), direction()), 1..30),
        ) {
            let _watchdog = crate::watchdog::start();
            let t = KdTree::build(&boxes);
            for &(o, d) in &rays {
                let ray = Ray::new(o, d);
                let mut seen = vec![false; boxes.len()];
                t.along_line(&ray, |i| seen[i as usize] = true);
                for (i, b) in boxes.iter().enumerate() {
                    if b.clip(&ray, f64::NEG_INFINITY, f64::INFINITY).is_some() {
                        prop_assert!(seen[i], "box {} {:?} on {:?} not visited", i, b, ray);
                    }
                }
                let brute = |lo: f64, hi: f64| {
                    boxes
                        .iter()
                        .filter_map(|b| entry(b, &ray, lo, hi))
                        .min_by(f64::total_cmp)
                };
                let mut windows = vec![(0.0, f64::INFINITY), (-1.0, f64::INFINITY)];
                if let Some(w) = brute(0.0, f64::INFINITY) {
                    windows.push((0.0, w));
                    windows.push((w, f64::INFINITY));
                }
                for (lo, hi) in windows {
                    let want = brute(lo, hi);
                    let got = t.nearest(&ray, lo, hi, |i, best| entry(&boxes[i as usize], &ray, lo, best));
                    prop_assert_eq!(got, want, "{:?} in ({}, {})", ray, lo, hi);
                    let any = t.any(&ray, lo, hi, |i| entry(&boxes[i as usize], &ray, lo, hi).is_some());
                    prop_assert_eq!(any, want.is_some(), "any-hit, {:?} in ({}, {})", ray, lo, hi);
                }
            }
        }
    }
}
