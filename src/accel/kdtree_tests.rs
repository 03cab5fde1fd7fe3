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
            check_structure(&t, &boxes, depth_cap(boxes.len(), BuildParams::default()));
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

        /// `overlapping` against brute force over the boxes: it visits
        /// every box meeting the query (closed boxes: touching counts),
        /// only items of leaves whose cells come near the query (within
        /// 10⁻⁶, far above its 10⁻⁹ slack), nothing for a query apart from
        /// the tree, and stops at once, returning false, when `visit` does.
        #[test]
        fn overlapping_visits_every_box_that_meets_the_query(
            boxes in prop::collection::vec(grid_box(), 1..60),
            queries in prop::collection::vec(grid_box(), 1..20),
            stop in 0usize..6,
        ) {
            let _watchdog = crate::watchdog::start();
            let t = KdTree::build(&boxes);
            let meets = |a: &Aabb, b: &Aabb| a.min.cmple(b.max).all() && a.max.cmpge(b.min).all();
            let far = DVec3::new(0.0, 0.0, 10.0);
            let apart = queries.iter().map(|q| Aabb::new(q.min + far, q.max + far));
            for q in queries.iter().copied().chain(apart) {
                // The items of the leaves whose cells come near `q`.
                let near = Aabb::new(q.min - 1e-6, q.max + 1e-6);
                let mut allowed = vec![false; boxes.len()];
                let mut stack = vec![(0usize, t.bounds())];
                while let Some((i, cell)) = stack.pop() {
                    let n = t.nodes[i];
                    if !meets(&cell, &near) {
                        continue;
                    }
                    if n.is_leaf() {
                        let (count, off) = ((n.a >> 2) as usize, n.b as usize);
                        for &id in &t.items[off..off + count] {
                            allowed[id as usize] = true;
                        }
                    } else {
                        let (axis, split) = ((n.a & 3) as usize, f32::from_bits(n.b) as f64);
                        let (mut b, mut a) = (cell, cell);
                        b.max[axis] = split;
                        a.min[axis] = split;
                        stack.push((i + 1, b));
                        stack.push(((n.a >> 2) as usize, a));
                    }
                }
                let mut seen = vec![0usize; boxes.len()];
                let whole = t.overlapping(&q, |i| {
                    seen[i as usize] += 1;
                    true
                });
                prop_assert!(whole);
                for (i, b) in boxes.iter().enumerate() {
                    if meets(b, &q) {
                        prop_assert!(seen[i] > 0, "box {} {:?} meets {:?}, not visited", i, b, q);
                    }
                    if seen[i] > 0 {
                        prop_assert!(allowed[i], "box {} {:?} visited, its leaves far from {:?}", i, b, q);
                    }
                }
                let total: usize = seen.iter().sum();
                let mut calls = 0;
                let all = t.overlapping(&q, |_| {
                    calls += 1;
                    calls <= stop
                });
                prop_assert_eq!(all, total <= stop);
                prop_assert_eq!(calls, total.min(stop + 1));
            }
        }
    }
}

/// SplitMix64: the tests' scenes from a fixed seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    fn point(&mut self, a: f64, b: f64) -> DVec3 {
        DVec3::new(self.range(a, b), self.range(a, b), self.range(a, b))
    }
}

/// The documented depth cap, `depth_base + 1.3·log2 N` (rounded), for
/// `n` items, and never past `MAX_DEPTH`, which the walk's stack holds.
fn depth_cap(n: usize, p: BuildParams) -> usize {
    ((p.depth_base + 1.3 * (n.max(1) as f64).log2()).round() as usize).min(MAX_DEPTH)
}

/// Whether the leaves that `p` lies in hold `id`: below a plane goes
/// below, above goes above, and a point on the plane may be in either.
fn held_at(t: &KdTree, node: usize, p: DVec3, id: u32) -> bool {
    let n = t.nodes[node];
    if n.is_leaf() {
        let (count, off) = ((n.a >> 2) as usize, n.b as usize);
        return t.items[off..off + count].contains(&id);
    }
    let axis = (n.a & 3) as usize;
    let split = f32::from_bits(n.b) as f64;
    let (below, above) = (node + 1, (n.a >> 2) as usize);
    if p[axis] < split {
        held_at(t, below, p, id)
    } else if p[axis] > split {
        held_at(t, above, p, id)
    } else {
        held_at(t, below, p, id) || held_at(t, above, p, id)
    }
}

/// The tree built over `boxes` (without clipping, or clipping each box to
/// the cell) against its boxes, independently of the builder's choices:
/// its bounds are the union of the finite non-empty boxes; every node is
/// reached once from the root, each interior node splitting its cell
/// strictly inside it, within `cap` levels; the leaves hold consecutive
/// runs of the item list in the order they are reached, together all of
/// it; a leaf holds an item at most once and only where the item's box
/// (rounded outwards to `f32`) meets the leaf's cell; and every corner and
/// the centre of every box lies in a leaf holding it. Returns the depth.
fn check_structure(t: &KdTree, boxes: &[Aabb], cap: usize) -> usize {
    let kept: Vec<bool> = boxes
        .iter()
        .map(|b| !b.is_empty() && b.is_finite())
        .collect();
    let bounds = boxes
        .iter()
        .zip(&kept)
        .filter(|&(_, &k)| k)
        .fold(Aabb::EMPTY, |u, (b, _)| u.union(b));
    assert_eq!(t.bounds(), bounds);
    if !kept.contains(&true) {
        assert!(t.items.is_empty());
        return 0;
    }
    let mut reached = vec![false; t.nodes.len()];
    let (mut next_off, mut deepest) = (0, 0);
    let mut stack = vec![(0usize, bounds, 0usize)];
    while let Some((i, cell, depth)) = stack.pop() {
        assert!(!reached[i], "node {i} reached twice");
        reached[i] = true;
        deepest = deepest.max(depth);
        let n = t.nodes[i];
        if n.is_leaf() {
            let (count, off) = ((n.a >> 2) as usize, n.b as usize);
            assert_eq!(off, next_off, "leaf {i}: its run of the item list");
            next_off += count;
            let ids = &t.items[off..off + count];
            for (k, &id) in ids.iter().enumerate() {
                assert!(!ids[..k].contains(&id), "item {id} twice in leaf {i}");
                assert!(kept[id as usize], "item {id} has no box to be in the tree");
                let [lo, hi] = box6(&boxes[id as usize]);
                for a in 0..3 {
                    assert!(
                        lo[a] as f64 <= cell.max[a] && hi[a] as f64 >= cell.min[a],
                        "item {id} {:?} outside leaf {i}'s cell {cell:?}",
                        boxes[id as usize]
                    );
                }
            }
        } else {
            let axis = (n.a & 3) as usize;
            assert!(axis < 3, "node {i}: axis {axis}");
            let split = f32::from_bits(n.b) as f64;
            assert!(
                split > cell.min[axis] && split < cell.max[axis],
                "node {i}: plane {split} in axis {axis} outside its cell {cell:?}"
            );
            let above = (n.a >> 2) as usize;
            assert!(
                above > i + 1 && above < t.nodes.len(),
                "node {i}: above {above}"
            );
            let (mut b, mut a) = (cell, cell);
            b.max[axis] = split;
            a.min[axis] = split;
            stack.push((above, a, depth + 1));
            stack.push((i + 1, b, depth + 1));
        }
    }
    assert!(reached.iter().all(|&r| r), "nodes no path reaches");
    assert_eq!(next_off, t.items.len(), "items no leaf holds");
    assert!(deepest <= cap, "depth {deepest} past the cap {cap}");
    for (id, b) in boxes.iter().enumerate() {
        if !kept[id] {
            continue;
        }
        let corners = (0..8).map(|c| {
            DVec3::new(
                if c & 1 == 0 { b.min.x } else { b.max.x },
                if c & 2 == 0 { b.min.y } else { b.max.y },
                if c & 4 == 0 { b.min.z } else { b.max.z },
            )
        });
        for p in corners.chain([b.centre()]) {
            assert!(
                held_at(t, 0, p, id as u32),
                "item {id} {b:?}: no leaf at {p} holds it"
            );
        }
    }
    deepest
}

/// The nearest entry into a box within `(t_min, t_max)`, as an item's hit.
fn box_entry(b: &Aabb, ray: &Ray, t_min: f64, t_max: f64) -> Option<f64> {
    b.clip(ray, t_min, f64::INFINITY)
        .map(|(lo, _)| lo)
        .filter(|&t| t > t_min && t < t_max)
}

/// `nearest`, `any` and `along_line` against brute force over the boxes
/// (the finite non-empty ones: the others stay outside the tree).
fn check_rays(t: &KdTree, boxes: &[Aabb], rays: &[Ray]) {
    let kept = |b: &&Aabb| !b.is_empty() && b.is_finite();
    for ray in rays {
        let mut seen = vec![false; boxes.len()];
        t.along_line(ray, |i| seen[i as usize] = true);
        for (i, b) in boxes.iter().enumerate().filter(|(_, b)| kept(b)) {
            if b.clip(ray, f64::NEG_INFINITY, f64::INFINITY).is_some() {
                assert!(seen[i], "box {i} {b:?} on {ray:?} not visited");
            }
        }
        let brute = |lo: f64, hi: f64| {
            boxes
                .iter()
                .filter(kept)
                .filter_map(|b| box_entry(b, ray, lo, hi))
                .min_by(f64::total_cmp)
        };
        let want = brute(0.0, f64::INFINITY);
        let got = t.nearest(ray, 0.0, f64::INFINITY, |i, best| {
            box_entry(&boxes[i as usize], ray, 0.0, best)
        });
        assert_eq!(got, want, "{ray:?}");
        let any = t.any(ray, 0.0, f64::INFINITY, |i| {
            box_entry(&boxes[i as usize], ray, 0.0, f64::INFINITY).is_some()
        });
        assert_eq!(any, want.is_some(), "any-hit, {ray:?}");
    }
}

fn random_boxes(rng: &mut Rng, n: usize, world: f64, size: f64) -> Vec<Aabb> {
    (0..n)
        .map(|_| {
            let c = rng.point(0.0, world);
            Aabb::new(c, c + rng.point(0.0, size))
        })
        .collect()
}

fn random_rays(rng: &mut Rng, n: usize, world: f64) -> Vec<Ray> {
    (0..n)
        .map(|_| {
            let o = rng.point(-0.2 * world, 1.2 * world);
            let to = rng.point(0.0, world);
            Ray::new(o, (to - o).normalize())
        })
        .collect()
}

/// Rounding outwards to `f32`: the nearest `f32` at or below (above) `x`,
/// for numbers that are `f32`s themselves, numbers between two, either
/// sign and zero.
#[test]
fn boxes_round_outwards_to_the_nearest_f32() {
    let _watchdog = crate::watchdog::start();
    let mut rng = Rng(7);
    let mut xs = vec![0.0, -0.0, 1.0, -1.0, 0.1, -0.1, 1.0 / 3.0, 1e30, -1e-30];
    for _ in 0..2000 {
        let x = (rng.range(-1.0, 1.0) * 2f64.powi((rng.next() * 80.0) as i32 - 40)) as f32;
        let (up, down) = (x.next_up() as f64, x.next_down() as f64);
        let x = x as f64;
        xs.extend([x, (x + up) / 2.0, (x + down) / 2.0, x + (up - x) * 0.999]);
    }
    for x in xs {
        let (d, u) = (round_down(x), round_up(x));
        assert!(
            d as f64 <= x && d.next_up() as f64 > x,
            "round_down({x}) = {d}"
        );
        assert!(
            u as f64 >= x && (u.next_down() as f64) < x,
            "round_up({x}) = {u}"
        );
        let b = box6(&Aabb::new(DVec3::splat(x), DVec3::splat(x)));
        assert_eq!(b, [[d; 3], [u; 3]]);
    }
}

/// A tree of several thousand items: its top nodes are built in parallel
/// (more than `PARALLEL_ABOVE` items) and appended with their node and
/// item indices moved. Its structure and its answers against brute force.
#[test]
fn a_tree_built_in_parallel_holds_every_item_and_finds_the_nearest() {
    let _watchdog = crate::watchdog::start();
    let mut rng = Rng(1);
    let boxes = random_boxes(&mut rng, 3000, 100.0, 3.0);
    let t = KdTree::build(&boxes);
    check_structure(&t, &boxes, depth_cap(3000, BuildParams::default()));
    check_rays(&t, &boxes, &random_rays(&mut rng, 200, 100.0));
}

/// Items crowding towards a corner, ever more densely (at 0.99ᵏ in each
/// axis): the SAH keeps cutting the near side, so the tree goes as deep
/// as it may, and no deeper, on the parallel path (2000 items) and the
/// sequential one, with several depth bases.
#[test]
fn the_depth_is_capped() {
    let _watchdog = crate::watchdog::start();
    for (n, base) in [(2000, 8.0), (2000, 2.0), (300, 8.0), (300, 3.0), (100, 1.0)] {
        let boxes: Vec<Aabb> = (0..n)
            .map(|k| {
                let c = DVec3::splat(0.99f64.powi(k));
                Aabb::new(c, c * 1.001)
            })
            .collect();
        let params = BuildParams {
            depth_base: base,
            ..BuildParams::default()
        };
        let t = KdTree::build_with(&boxes, params);
        let cap = depth_cap(n as usize, params);
        let depth = check_structure(&t, &boxes, cap);
        assert_eq!(depth, cap, "{n} items, base {base}");
    }
}

/// The deepest tree the cap lets through (`MAX_DEPTH` levels, with a
/// depth base of 60): boxes at 2⁻ᵏ in each axis, down to the smallest
/// normal `f32`s. A box over everything goes down the near side of
/// every plane with the far side still to visit: `overlapping`'s stack
/// (the walk's size) holds that path; and rays along the diagonal and
/// across the tree are answered as brute force answers them.
#[test]
fn the_stacks_hold_the_deepest_tree() {
    let _watchdog = crate::watchdog::start();
    let boxes: Vec<Aabb> = (0..120)
        .map(|k| {
            let c = DVec3::splat(0.5f64.powi(k));
            Aabb::new(c, c * 1.001)
        })
        .collect();
    let params = BuildParams {
        depth_base: 60.0,
        ..BuildParams::default()
    };
    let t = KdTree::build_with(&boxes, params);
    assert_eq!(check_structure(&t, &boxes, MAX_DEPTH), MAX_DEPTH);
    let d = DVec3::ONE.normalize();
    let mut rays = vec![Ray::new(-d, d), Ray::new(DVec3::splat(2.0), -d)];
    rays.extend(random_rays(&mut Rng(3), 50, 1.0));
    check_rays(&t, &boxes, &rays);
    let mut seen = vec![false; boxes.len()];
    assert!(t.overlapping(&t.bounds(), |i| {
        seen[i as usize] = true;
        true
    }));
    assert!(seen.iter().all(|&s| s));
}

/// The items of the leaves whose cells meet `q` grown by `tol`.
fn leaf_items_near(t: &KdTree, q: &Aabb, tol: f64) -> Vec<u32> {
    let near = Aabb::new(q.min - tol, q.max + tol);
    let mut held = Vec::new();
    let mut stack = vec![(0usize, t.bounds())];
    while let Some((i, cell)) = stack.pop() {
        if !(cell.min.cmple(near.max).all() && cell.max.cmpge(near.min).all()) {
            continue;
        }
        let n = t.nodes[i];
        if n.is_leaf() {
            let (count, off) = ((n.a >> 2) as usize, n.b as usize);
            held.extend_from_slice(&t.items[off..off + count]);
        } else {
            let (axis, split) = ((n.a & 3) as usize, f32::from_bits(n.b) as f64);
            let (mut b, mut a) = (cell, cell);
            b.max[axis] = split;
            a.min[axis] = split;
            stack.extend([(i + 1, b), ((n.a >> 2) as usize, a)]);
        }
    }
    held.sort();
    held.dedup();
    held
}

/// `overlapping` compares a split plane with a slack relative to the
/// coordinates (1e-9 of them, 10⁻⁵ here): a box ending or starting within
/// rounding of the root's plane (10⁻⁷ from it) on the other side visits
/// the leaves across it that come within 10⁻⁶ of it; a box clear of it (a
/// thousandth) visits no leaf farther than 10⁻⁴ from it. Boxes near 10⁴,
/// so that the slack is far from both gaps.
#[test]
fn a_box_within_rounding_of_a_plane_visits_both_sides() {
    let _watchdog = crate::watchdog::start();
    let boxes = [
        Aabb::new(DVec3::splat(1e4), DVec3::splat(1e4 + 1.0)),
        Aabb::new(DVec3::splat(1e4 + 2.0), DVec3::splat(1e4 + 3.0)),
    ];
    let t = KdTree::build(&boxes);
    let n = t.nodes[0];
    assert!(!n.is_leaf());
    let (axis, s) = ((n.a & 3) as usize, f32::from_bits(n.b) as f64);
    assert!((1e4 + 1.0..=1e4 + 2.0).contains(&s), "{s}");
    let (near, clear) = (s * 1e-11, 1e-3);
    for (lo, hi) in [
        (s - 1.5, s - near),
        (s + near, s + 1.5),
        (s - 1.5, s - clear),
        (s + clear, s + 1.5),
    ] {
        let mut q = t.bounds();
        (q.min[axis], q.max[axis]) = (lo, hi);
        let mut seen = Vec::new();
        assert!(t.overlapping(&q, |i| {
            seen.push(i);
            true
        }));
        seen.sort();
        seen.dedup();
        let (must, may) = (leaf_items_near(&t, &q, 1e-6), leaf_items_near(&t, &q, 1e-4));
        assert!(
            must.iter().all(|i| seen.contains(i)) && seen.iter().all(|i| may.contains(i)),
            "[{lo}, {hi}] in axis {axis}: visits {seen:?}, must {must:?}, may {may:?}"
        );
    }
}

/// Boxes that are empty (min above max, finite or not) or unbounded (an
/// infinite or NaN side) stay outside the tree; the rest is walked as if
/// they were not there.
#[test]
fn empty_and_unbounded_boxes_stay_outside_the_tree() {
    let _watchdog = crate::watchdog::start();
    let mut boxes = random_boxes(&mut Rng(5), 40, 10.0, 2.0);
    let half = Aabb::new(DVec3::ZERO, DVec3::new(f64::INFINITY, 1.0, 1.0));
    let inverted = Aabb {
        min: DVec3::splat(3.0),
        max: DVec3::new(4.0, 2.0, 4.0),
    };
    let nan = Aabb::new(DVec3::ZERO, DVec3::new(1.0, f64::NAN, 1.0));
    for (k, b) in [Aabb::INFINITE, Aabb::EMPTY, half, inverted, nan]
        .into_iter()
        .enumerate()
    {
        boxes.insert(7 * k, b);
    }
    let t = KdTree::build(&boxes);
    check_structure(&t, &boxes, depth_cap(40, BuildParams::default()));
    assert_eq!(t.stats.items, 40, "the count `--stats` reports");
    check_rays(&t, &boxes, &random_rays(&mut Rng(6), 50, 10.0));
}

/// The part `[s0, s1]` of the segment from `a` to `b` inside the closed
/// box `c`, if any.
fn segment_in(a: DVec3, b: DVec3, c: &Aabb) -> Option<(f64, f64)> {
    let (mut s0, mut s1) = (0.0f64, 1.0f64);
    for k in 0..3 {
        let d = b[k] - a[k];
        if d == 0.0 {
            if a[k] < c.min[k] || a[k] > c.max[k] {
                return None;
            }
            continue;
        }
        let (t0, t1) = ((c.min[k] - a[k]) / d, (c.max[k] - a[k]) / d);
        s0 = s0.max(t0.min(t1));
        s1 = s1.min(t0.max(t1));
    }
    (s0 <= s1).then_some((s0, s1))
}

/// "Perfect splits" (`build_clipped`) over segments, each clipped exactly
/// to the cell and the side of the plane (its box padded by 10⁻⁹): every
/// point along a segment lies in a leaf holding it, no leaf holds a
/// segment that stays clear of its cell (only its box reaches there), and
/// so the clipped tree holds fewer references than the plain one over the
/// same boxes. On the parallel path (2000 segments) and the sequential one.
#[test]
fn clipped_builds_hold_each_segment_only_where_it_runs() {
    let _watchdog = crate::watchdog::start();
    for n in [2000, 300] {
        let mut rng = Rng(n as u64);
        let segs: Vec<[DVec3; 2]> = (0..n)
            .map(|_| {
                let a = rng.point(0.0, 10.0);
                [a, a + rng.point(-2.0, 2.0)]
            })
            .collect();
        let boxes: Vec<Aabb> = segs.iter().map(|s| Aabb::new(s[0], s[1])).collect();
        let clip = |id: u32, cell: &Aabb, axis: usize, split: f64| {
            let [a, b] = segs[id as usize];
            let (mut below, mut above) = (*cell, *cell);
            below.max[axis] = split;
            above.min[axis] = split;
            [below, above].map(|side| {
                segment_in(a, b, &side).map(|(s0, s1)| {
                    let (p, q) = (a + (b - a) * s0, a + (b - a) * s1);
                    let pad = 1e-9 * (1.0 + p.abs().max(q.abs()).max_element());
                    Aabb::new(p.min(q) - pad, p.max(q) + pad)
                })
            })
        };
        let params = BuildParams::default();
        let t = KdTree::build_clipped(&boxes, &clip, params);
        let plain = KdTree::build_with(&boxes, params);
        assert_eq!(t.bounds(), plain.bounds());
        let mut stack = vec![(0usize, t.bounds())];
        let (mut leaves_seen, mut off_seen) = (0, 0);
        while let Some((i, cell)) = stack.pop() {
            let node = t.nodes[i];
            if node.is_leaf() {
                let (count, off) = ((node.a >> 2) as usize, node.b as usize);
                assert_eq!(off, off_seen, "leaf {i}: its run of the item list");
                off_seen += count;
                leaves_seen += 1;
                let near = Aabb::new(cell.min - 1e-6, cell.max + 1e-6);
                for &id in &t.items[off..off + count] {
                    let [a, b] = segs[id as usize];
                    assert!(
                        segment_in(a, b, &near).is_some(),
                        "segment {id} {a} {b} held by leaf {i}, clear of {cell:?}"
                    );
                }
            } else {
                let (axis, split) = ((node.a & 3) as usize, f32::from_bits(node.b) as f64);
                let (mut b, mut a) = (cell, cell);
                b.max[axis] = split;
                a.min[axis] = split;
                stack.push(((node.a >> 2) as usize, a));
                stack.push((i + 1, b));
            }
        }
        assert_eq!(off_seen, t.items.len());
        assert!(leaves_seen > n / 10, "{leaves_seen} leaves");
        for (id, [a, b]) in segs.iter().enumerate() {
            for k in 0..=10 {
                let p = *a + (*b - *a) * (k as f64 / 10.0);
                assert!(
                    held_at(&t, 0, p, id as u32),
                    "segment {id}: no leaf at {p} holds it"
                );
            }
        }
        assert!(
            t.items.len() < plain.items.len(),
            "{} references clipped, {} plain",
            t.items.len(),
            plain.items.len()
        );
    }
}

/// A flat grid of cells in z = 0, each a half-open square `[x, x + 1) ×
/// [y, y + 1)` whose hit is found as a surface's would be (by division,
/// not the walk's reciprocal): rays aimed exactly at the grid's inner
/// corners, which lie on split planes, from near and far (10⁴, 10⁵
/// away). The tree's box is flat, so a ray's segment is a point, and the
/// plane's `t` rounds differently from the surface's: only the walk's
/// slack (1e-9 of the farthest `t`) sends such a ray to both sides, where
/// one cell holds the corner. Every ray hits, at brute force's `t`.
#[test]
fn rays_at_corners_on_split_planes_hit_a_flat_grid() {
    let _watchdog = crate::watchdog::start();
    let n = 8;
    let cell = |k: u32| {
        let (x, y) = ((k % n) as f64 + 0.5, (k / n) as f64 - 3.0);
        (x, y)
    };
    let boxes: Vec<Aabb> = (0..n * n)
        .map(|k| {
            let (x, y) = cell(k);
            Aabb::new(DVec3::new(x, y, 0.0), DVec3::new(x + 1.0, y + 1.0, 0.0))
        })
        .collect();
    let t = KdTree::build(&boxes);
    let hit = |k: u32, ray: &Ray, best: f64| {
        let s = -ray.origin.z / ray.dir.z;
        let p = ray.origin + ray.dir * s;
        let (x, y) = cell(k);
        (s > 0.0 && s < best && x <= p.x && p.x < x + 1.0 && y <= p.y && p.y < y + 1.0).then_some(s)
    };
    let mut rng = Rng(11);
    let (mut rays, mut missed) = (0, 0);
    for far in [5.0, 1e4, 1e5] {
        for _ in 0..40 {
            let eye = DVec3::new(
                rng.range(-far, far),
                rng.range(-far, far),
                far * rng.range(0.5, 1.5),
            );
            for i in 1..n {
                for j in 1..n {
                    let corner = DVec3::new(i as f64 + 0.5, j as f64 - 3.0, 0.0);
                    let ray = Ray::new(eye, (corner - eye).normalize());
                    let want = (0..n * n)
                        .filter_map(|k| hit(k, &ray, f64::INFINITY))
                        .min_by(f64::total_cmp);
                    assert!(want.is_some(), "{ray:?}: no cell holds the corner");
                    let got = t.nearest(&ray, 0.0, f64::INFINITY, |k, best| hit(k, &ray, best));
                    rays += 1;
                    missed += (got != want) as usize;
                }
            }
        }
    }
    assert_eq!(missed, 0, "of {rays} rays");
}
