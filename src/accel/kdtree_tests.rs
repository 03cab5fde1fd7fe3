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
