//! The wide BVH against brute force (the kd-tree joins in
//! `shapes::mesh`'s tests, with the mesh's own clipped tree): the same nearest hit
//! (t bit for bit, and a triangle at that t), any-hit agreeing with
//! nearest, on random meshes and rays, on both the AVX2 and the scalar
//! path.

use super::*;
use crate::geometry::DVec3;
use proptest::prelude::*;

pub(crate) type Tri = [DVec3; 3];

/// Brute force: the first triangle in index order at the least t.
pub(crate) fn brute(tris: &[Tri], ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, u32)> {
    let s = ShearedRay::new(ray);
    let mut best: Option<(f64, u32)> = None;
    let mut limit = t_max;
    for (i, t) in tris.iter().enumerate() {
        if let Some((th, _)) = s.triangle(t[0], t[1], t[2])
            && th > t_min
            && th < limit
        {
            limit = th;
            best = Some((th, i as u32));
        }
    }
    best
}

/// The BVH on each path it can run here.
fn paths(tris: &[Tri]) -> Vec<TriangleBvh> {
    let mut out = Vec::new();
    for simd in [Simd::Scalar, Simd::Avx2] {
        let mut b = TriangleBvh::build(tris);
        b.set_simd(simd);
        if b.bvh.simd == simd {
            out.push(b);
        }
    }
    out
}

/// `got` is the nearest hit `want`: the same t, and a triangle that is
/// crossed at that t (two triangles sharing an edge tie).
fn same_hit(
    tris: &[Tri],
    ray: &Ray,
    got: Option<(f64, u32)>,
    want: Option<(f64, u32)>,
) -> Result<(), String> {
    match (got, want) {
        (None, None) => Ok(()),
        (Some((tg, ig)), Some((tw, iw))) => {
            let s = ShearedRay::new(ray);
            let t = &tris[ig as usize];
            let own = s.triangle(t[0], t[1], t[2]).map(|h| h.0);
            if tg.to_bits() == tw.to_bits() && (ig == iw || own == Some(tw)) {
                Ok(())
            } else {
                Err(format!(
                    "got t {tg} on {ig} (its own t {own:?}), want t {tw} on {iw}"
                ))
            }
        }
        _ => Err(format!("got {got:?}, want {want:?}")),
    }
}

fn check_all(tris: &[Tri], rays: &[(Ray, f64, f64)]) -> Result<(), String> {
    let bvhs = paths(tris);
    for (ray, t_min, t_max) in rays {
        let want = brute(tris, ray, *t_min, *t_max);
        let s = ShearedRay::new(ray);
        // The window as given, and windows ending or starting exactly at
        // the nearest hit (both ends are open: the hit is then outside).
        // Not at a hit within rounding of the origin (a ray leaving a
        // surface meets it again at t ≈ 1e-18, where the box, exact for
        // the real ray, rightly sees t = 0 and no window above 0 can
        // promise to find it).
        let mut windows = vec![(*t_min, *t_max)];
        if let Some((th, _)) = want.filter(|w| w.0 > 1e-6) {
            windows.push((*t_min, th));
            windows.push((th, *t_max));
            windows.push((th.next_down(), th.next_up()));
        }
        for b in &bvhs {
            for &(lo, hi) in &windows {
                let want = brute(tris, ray, lo, hi);
                let got = b.nearest(ray, &s, lo, hi);
                same_hit(tris, ray, got, want).map_err(|e| {
                    format!("{:?} bvh, ray {ray:?} in ({lo}, {hi}): {e}", b.bvh.simd)
                })?;
                if b.any(ray, &s, lo, hi) != want.is_some() {
                    return Err(format!(
                        "{:?} any-hit in ({lo}, {hi}) disagrees with nearest {want:?}",
                        b.bvh.simd
                    ));
                }
            }
            let mut line: Vec<u32> = Vec::new();
            b.along_line(ray, &s, |_, i| line.push(i));
            line.sort();
            let mut all: Vec<u32> = (0..tris.len() as u32)
                .filter(|&i| {
                    let t = &tris[i as usize];
                    s.triangle(t[0], t[1], t[2]).is_some()
                })
                .collect();
            all.sort();
            if line != all {
                return Err(format!("{:?} along_line {line:?} want {all:?}", b.bvh.simd));
            }
        }
    }
    Ok(())
}

/// Coordinates from a coarse grid (so that corners, edges and planes are
/// shared exactly) or anywhere.
fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![(-4i32..=4).prop_map(|k| k as f64 * 0.5), -2.0f64..2.0]
}

pub(crate) fn point() -> impl Strategy<Value = DVec3> {
    (coord(), coord(), coord()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// Triangles: general, flat in an x, y or z plane, or degenerate (a
/// repeated corner, or a point).
pub(crate) fn triangle() -> impl Strategy<Value = Tri> {
    prop_oneof![
        4 => [point(), point(), point()].prop_filter("corners in line but apart", |t| {
            (t[1] - t[0]).cross(t[2] - t[0]) != DVec3::ZERO
                || t[0] == t[1]
                || t[1] == t[2]
                || t[0] == t[2]
        }),
        // (Not with its corners exactly in line but apart: that is the
        // sliver below, which the grid makes often.)
        2 => (0usize..3, coord(), [point(), point(), point()])
            .prop_map(|(a, c, mut t)| {
                for v in &mut t {
                    v[a] = c;
                }
                t
            })
            .prop_filter("corners in line but apart", |t| {
                (t[1] - t[0]).cross(t[2] - t[0]) != DVec3::ZERO
                    || t[0] == t[1]
                    || t[1] == t[2]
                    || t[0] == t[2]
            }),
        // A repeated corner: exactly no area. (A sliver whose corners
        // are only nearly in line is not degenerate to the f64 test, and
        // its t can then lie off the triangle's own box, where no box
        // structure could promise to look.)
        1 => (point(), point()).prop_map(|(a, b)| [a, b, a]),
        1 => point().prop_map(|a| [a, a, a]),
    ]
}

/// Directions: general, or with any one or two components zero (parallel
/// to the flat triangles' planes, or along an axis), of either sign.
pub(crate) fn direction() -> impl Strategy<Value = DVec3> {
    (point(), 0u8..12, any::<bool>()).prop_map(|(d, zero, neg)| {
        let mut d = d;
        let z = if neg { -0.0 } else { 0.0 };
        for a in 0..3 {
            // 0..7: that subset of the axes zeroed; 8..11: none.
            if zero < 8 && zero & (1 << a) != 0 {
                d[a] = z;
            }
        }
        if d.x == 0.0 && d.y == 0.0 && d.z == 0.0 {
            DVec3::Z
        } else {
            d
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn nearest_agrees_with_brute_force(
        tris in prop::collection::vec(triangle(), 1..80),
        rays in prop::collection::vec((point(), direction()), 1..40),
        on_surface in prop::collection::vec((0usize..80, 0.0f64..1.0, 0.0f64..1.0, direction()), 0..20),
    ) {
        let _watchdog = crate::watchdog::start();
        let mut all: Vec<(Ray, f64, f64)> = rays
            .iter()
            .map(|&(o, d)| (Ray::new(o * 2.0, d), 0.0, f64::INFINITY))
            .collect();
        // Rays leaving a point on a triangle, as secondary rays do.
        for &(k, a, b, d) in &on_surface {
            let t = tris[k % tris.len()];
            let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
            let p = t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]);
            all.push((Ray::new(p, d), 1e-9, f64::INFINITY));
            all.push((Ray::new(p, d), 0.0, 1.5));
        }
        check_all(&tris, &all).map_err(TestCaseError::fail)?;
    }
}

#[test]
fn one_triangle() {
    let _watchdog = crate::watchdog::start();
    let tris = [[DVec3::ZERO, DVec3::X, DVec3::Y]];
    let b = TriangleBvh::build(&tris);
    assert_eq!(b.stats().leaves, 1);
    let ray = Ray::new(DVec3::new(0.25, 0.25, 1.0), -DVec3::Z);
    let s = ShearedRay::new(&ray);
    assert_eq!(b.nearest(&ray, &s, 0.0, f64::INFINITY), Some((1.0, 0)));
    assert_eq!(b.nearest(&ray, &s, 0.0, 1.0), None);
    let miss = Ray::new(DVec3::new(0.75, 0.75, 1.0), -DVec3::Z);
    assert_eq!(
        b.nearest(&miss, &ShearedRay::new(&miss), 0.0, f64::INFINITY),
        None
    );
}

#[test]
fn no_triangles_and_only_degenerate_ones() {
    let _watchdog = crate::watchdog::start();
    let ray = Ray::new(DVec3::new(0.1, 0.1, 1.0), -DVec3::Z);
    let s = ShearedRay::new(&ray);
    let b = TriangleBvh::build(&[]);
    assert_eq!(b.nearest(&ray, &s, 0.0, f64::INFINITY), None);
    let p = DVec3::new(0.1, 0.1, 0.0);
    let b = TriangleBvh::build(&[[p, p, p]; 5]);
    assert_eq!(b.nearest(&ray, &s, 0.0, f64::INFINITY), None);
}

#[test]
fn identical_triangles_all_found() {
    let _watchdog = crate::watchdog::start();
    let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let tris = vec![t; 1000];
    for b in paths(&tris) {
        // No plane separates them: they are halved by index down to
        // leaves of at most eight.
        assert!(b.stats().slots <= 1024 && b.stats().leaves >= 125);
        let ray = Ray::new(DVec3::new(0.2, 0.2, -3.0), DVec3::Z);
        let s = ShearedRay::new(&ray);
        let got = b.nearest(&ray, &s, 0.0, f64::INFINITY);
        same_hit(&tris, &ray, got, brute(&tris, &ray, 0.0, f64::INFINITY)).unwrap();
        let mut n = 0;
        b.along_line(&ray, &s, |_, _| n += 1);
        assert_eq!(n, 1000);
    }
}

#[test]
fn huge_and_tiny_coordinates() {
    let _watchdog = crate::watchdog::start();
    for scale in [1e-30, 1e-8, 1.0, 1e8, 1e30] {
        let tris: Vec<Tri> = (0..50)
            .map(|i| {
                let o = DVec3::new(i as f64, (i * 7 % 11) as f64, (i * 3 % 5) as f64) * scale;
                [o, o + DVec3::X * scale, o + DVec3::Y * scale]
            })
            .collect();
        let rays: Vec<(Ray, f64, f64)> = (0..50)
            .map(|i| {
                let target = tris[i][0] + DVec3::new(0.3, 0.3, 0.0) * scale;
                let o = target + DVec3::new(0.1, -0.2, 2.0) * scale;
                (Ray::new(o, target - o), 0.0, f64::INFINITY)
            })
            .collect();
        check_all(&tris, &rays).unwrap_or_else(|e| panic!("scale {scale}: {e}"));
        // Every ray aims at a triangle: it must find one.
        let b = TriangleBvh::build(&tris);
        for (r, _, _) in &rays {
            assert!(
                b.nearest(r, &ShearedRay::new(r), 0.0, f64::INFINITY)
                    .is_some()
            );
        }
    }
}

#[test]
fn the_box_test_is_conservative_at_grazing_angles() {
    let _watchdog = crate::watchdog::start();
    // Thin triangles met edge-on and rays barely tilted off an axis: the
    // f32 boxes must never lose what the f64 test finds.
    let mut tris = Vec::new();
    for i in 0..200 {
        let x = i as f64 * 0.01;
        tris.push([
            DVec3::new(x, 0.0, 0.0),
            DVec3::new(x, 1.0, 0.0),
            DVec3::new(x, 0.0, 1.0),
        ]);
        tris.push([
            DVec3::new(0.0, x, 0.0),
            DVec3::new(1.0, x, 1e-7),
            DVec3::new(0.0, x, 1.0),
        ]);
    }
    let mut rays = Vec::new();
    for i in 0..400 {
        let f = i as f64 / 400.0;
        rays.push((
            Ray::new(DVec3::new(-1.0, f, 0.5), DVec3::new(1.0, 1e-9 * f, 0.0)),
            0.0,
            f64::INFINITY,
        ));
        rays.push((
            Ray::new(DVec3::new(f, -1.0, 0.5), DVec3::new(0.0, 1.0, 1e-12)),
            0.0,
            f64::INFINITY,
        ));
        rays.push((
            Ray::new(DVec3::new(f * 2.0, f, 0.5), DVec3::new(-1.0, 0.0, 0.0)),
            1e-9,
            f64::INFINITY,
        ));
    }
    check_all(&tris, &rays).unwrap();
}

/// The box query finds every item whose box meets the query box (a
/// superset is allowed: boxes are stored rounded outwards), skips the
/// padding, and stops when told to.
#[test]
fn overlapping_finds_every_box_that_meets_the_query() {
    let _watchdog = crate::watchdog::start();
    let mut seed = 0x5eed_u64;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let boxes: Vec<Aabb> = (0..500)
        .map(|_| {
            let c = DVec3::new(next(), next(), next()) * 20.0 - 10.0;
            let h = DVec3::new(next(), next(), next()) * 0.8;
            Aabb::new(c - h, c + h)
        })
        .collect();
    for params in [
        BvhParams {
            group_cost: 4.0,
            group: 1,
            max_leaf: 4,
        },
        BvhParams {
            group_cost: 1.0,
            group: 4,
            max_leaf: 8,
        },
    ] {
        let bvh = Bvh::build(&boxes, params);
        for _ in 0..200 {
            let c = DVec3::new(next(), next(), next()) * 24.0 - 12.0;
            let h = DVec3::new(next(), next(), next()) * 3.0;
            let q = Aabb::new(c - h, c + h);
            let mut seen = vec![false; boxes.len()];
            assert!(bvh.overlapping(&q, |i| {
                seen[i as usize] = true;
                true
            }));
            for (i, b) in boxes.iter().enumerate() {
                let meets = b.min.cmple(q.max).all() && b.max.cmpge(q.min).all();
                assert!(
                    !meets || seen[i],
                    "box {i} meets the query but was not visited"
                );
            }
        }
        // Stopping: the first visit that says no ends the query.
        let all = Aabb::new(DVec3::splat(-20.0), DVec3::splat(20.0));
        let mut visits = 0;
        assert!(!bvh.overlapping(&all, |_| {
            visits += 1;
            visits < 3
        }));
        assert_eq!(visits, 3);
    }
}

/// Both paths run here where the CPU has AVX2 (and the scalar one always).
#[test]
fn the_tests_run_both_paths() {
    let _watchdog = crate::watchdog::start();
    let tris = [[DVec3::ZERO, DVec3::X, DVec3::Y]];
    let got: Vec<Simd> = paths(&tris).iter().map(|b| b.bvh.simd()).collect();
    if Simd::avx2_available() {
        assert_eq!(got, [Simd::Scalar, Simd::Avx2]);
    } else {
        assert_eq!(got, [Simd::Scalar]);
    }
}

/// Of several triangles crossed at the same t, the nearest hit is the
/// first met: the first in leaf order (`items()`), on both paths.
#[test]
fn of_equal_hits_the_first_in_leaf_order_wins() {
    let _watchdog = crate::watchdog::start();
    let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
    for n in [2, 3, 5, 8] {
        let tris = vec![t; n];
        for b in paths(&tris) {
            let first = b.bvh.items()[0];
            let ray = Ray::new(DVec3::new(0.25, 0.25, 2.0), -DVec3::Z);
            let s = ShearedRay::new(&ray);
            assert_eq!(
                b.nearest(&ray, &s, 0.0, f64::INFINITY),
                Some((2.0, first)),
                "{n} copies, {:?}",
                b.bvh.simd()
            );
        }
    }
}

/// The mesh's box is the box of every corner, exactly.
#[test]
fn bounds_hold_every_corner() {
    let _watchdog = crate::watchdog::start();
    let tris: Vec<Tri> = (0..40)
        .map(|i| {
            let f = i as f64;
            [
                DVec3::new(f * 0.3 - 2.0, (f * 0.7).sin(), 0.1),
                DVec3::new(f * 0.1, -f * 0.05, (f * 0.2).cos() * 3.0),
                DVec3::new(-f, 0.5, f * 0.01 - 1.0),
            ]
        })
        .collect();
    let want = tris
        .iter()
        .fold(Aabb::EMPTY, |b, t| b.grow(t[0]).grow(t[1]).grow(t[2]));
    let b = TriangleBvh::build(&tris);
    assert_eq!(b.bounds(), want);
    assert_eq!(b.bvh.bounds(), want);
    // Degenerate triangles have boxes too; empty input has none.
    assert!(TriangleBvh::build(&[]).bounds().is_empty());
}

/// The collapse opens inner children until a wide node holds eight: a
/// node with fewer holds only leaves. Every slot used has a box around
/// what is below it, and every item is in exactly one leaf.
#[test]
fn wide_nodes_are_full_and_their_boxes_hold_what_is_below() {
    let _watchdog = crate::watchdog::start();
    let boxes: Vec<Aabb> = (0..3000)
        .map(|i| {
            let p = DVec3::new(
                (i % 17) as f64,
                (i / 17 % 13) as f64,
                (i / 221) as f64 * 1.5,
            );
            Aabb::new(p, p + DVec3::new(0.4, 0.7, 0.2))
        })
        .collect();
    for params in [TRIANGLES, crate::accel::OBJECTS] {
        let bvh = Bvh::build(&boxes, params);
        assert!(bvh.nodes.len() > 10);
        let mut seen = vec![0u32; boxes.len()];
        // (node, the box its parent stores for it)
        let mut todo = vec![(0usize, None::<Aabb>)];
        while let Some((at, parent)) = todo.pop() {
            let n = &bvh.nodes[at];
            let mut used = 0;
            let mut inner = 0;
            let mut around = Aabb::EMPTY;
            for k in 0..8 {
                let b = Aabb::new(
                    DVec3::new(n.lo[0][k] as f64, n.lo[1][k] as f64, n.lo[2][k] as f64),
                    DVec3::new(n.hi[0][k] as f64, n.hi[1][k] as f64, n.hi[2][k] as f64),
                );
                if n.lo[0][k] > n.hi[0][k] {
                    continue;
                }
                used += 1;
                around = around.union(&b);
                let child = n.child[k];
                if child & LEAF == 0 {
                    inner += 1;
                    todo.push((child as usize, Some(b)));
                    continue;
                }
                let first = (child & !LEAF) as usize;
                let count = n.count[k] as usize;
                let leaf = &bvh.items[first..first + count];
                // Padded to whole groups, the padding last.
                let real = leaf.iter().take_while(|&&i| i != u32::MAX).count();
                assert!(real > 0 && count == real.div_ceil(params.group) * params.group);
                // Distinct centres: no leaf past the cap.
                assert!(real <= params.max_leaf, "a leaf of {real}");
                for &i in leaf {
                    if i == u32::MAX {
                        continue;
                    }
                    seen[i as usize] += 1;
                    let ib = boxes[i as usize];
                    assert_eq!(b.union(&ib), b, "item {i} outside its leaf's box");
                }
            }
            assert!(
                inner == 0 || used == 8,
                "node {at}: {used} slots, {inner} inner"
            );
            if let Some(p) = parent {
                assert_eq!(p.union(&around), p, "node {at} outside its box");
            }
        }
        assert!(
            seen.iter().all(|&c| c == 1),
            "an item not in exactly one leaf"
        );
    }
}

/// The traversal stack holds the deepest walk the build allows: a path of
/// `MAX_BINARY_DEPTH` wide nodes, each with eight children crossing the
/// ray, the inner one entered first (so seven wait at every level).
#[test]
fn the_stack_holds_the_deepest_walk() {
    let _watchdog = crate::watchdog::start();
    let depth = build::MAX_BINARY_DEPTH;
    let mut nodes = Vec::new();
    for level in 0..depth {
        let mut n = Node8::empty();
        for k in 0..8 {
            // Leaves span x in [0, 1]; the inner child from -1, so it is
            // entered first.
            let inner = k == 0 && level + 1 < depth;
            n.lo[0][k] = if inner { -1.0 } else { 0.0 };
            n.hi[0][k] = 1.0;
            for a in 1..3 {
                n.lo[a][k] = -1.0;
                n.hi[a][k] = 1.0;
            }
            n.child[k] = if inner {
                (level + 1) as u32
            } else {
                LEAF | (8 * level + k) as u32
            };
            n.count[k] = if inner { 0 } else { 1 };
        }
        nodes.push(n);
    }
    let items: Vec<u32> = (0..8 * depth as u32).collect();
    for simd in [Simd::Scalar, Simd::Avx2] {
        let mut bvh = Bvh {
            nodes: nodes.clone(),
            items: items.clone(),
            bounds: Aabb::new(DVec3::splat(-1.0), DVec3::ONE),
            simd: Simd::Scalar,
            stats: BvhStats::default(),
        };
        bvh.set_simd(simd);
        let mut leaves = 0;
        let ray = Ray::new(DVec3::new(-5.0, 0.0, 0.0), DVec3::X);
        bvh.walk(&ray, 0.0, f64::INFINITY, |first, count, limit| {
            assert_eq!(count, 1);
            assert!(first < items.len());
            leaves += 1;
            limit
        });
        assert_eq!(leaves, 7 * (depth - 1) + 8);
    }
}

/// The box query takes boxes as closed: a box that only touches the query
/// (a shared face, edge or corner, or a flat box on its face) is visited.
#[test]
fn overlapping_counts_touching_boxes() {
    let _watchdog = crate::watchdog::start();
    // Unit cells of a 6×6×6 grid and flat squares on the grid's planes.
    let mut boxes = Vec::new();
    for i in 0..216 {
        let p = DVec3::new((i % 6) as f64, (i / 6 % 6) as f64, (i / 36) as f64);
        boxes.push(Aabb::new(p, p + DVec3::ONE));
        let a = i % 3;
        let mut q = p + DVec3::ONE;
        q[a] = p[a];
        boxes.push(Aabb::new(p, q));
    }
    for params in [TRIANGLES, crate::accel::OBJECTS] {
        let bvh = Bvh::build(&boxes, params);
        for i in 0..300 {
            // Queries whose faces lie on the grid's planes, some flat.
            let c = |k: usize| ((i * 7 + k * 5) % 7) as f64;
            let lo = DVec3::new(c(0), c(1), c(2));
            let mut hi = lo + DVec3::new((i % 3) as f64, (i / 3 % 2) as f64, (i / 6 % 3) as f64);
            if i % 5 == 0 {
                hi = lo;
            }
            let q = Aabb::new(lo, hi);
            let mut seen = vec![false; boxes.len()];
            assert!(bvh.overlapping(&q, |k| {
                seen[k as usize] = true;
                true
            }));
            for (k, b) in boxes.iter().enumerate() {
                let meets = b.min.cmple(q.max).all() && b.max.cmpge(q.min).all();
                assert!(
                    !meets || seen[k],
                    "box {k} {b:?} touches {q:?} but was not visited"
                );
            }
        }
        // A query clear of every box (beyond the grid in one axis and
        // overlapping it in the others) visits nothing.
        for a in 0..3 {
            for side in [-1.0, 1.0] {
                let mut c = DVec3::splat(3.0);
                c[a] = 3.0 + side * 4.0;
                let q = Aabb::new(c - DVec3::splat(0.5), c + DVec3::splat(0.5));
                assert!(bvh.overlapping(&q, |k| panic!("box {k} visited for {q:?}")));
            }
        }
    }
}
