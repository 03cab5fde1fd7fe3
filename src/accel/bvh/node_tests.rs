//! The wide BVH's parts on their own: the `f32` rounding of boxes and
//! windows, the eight-box test against the exact slabs (conservative, and
//! tight within its slack), the front-to-back push, the four-triangle
//! block test against the watertight test it copies, and which path
//! (AVX2 or scalar) runs. Each SIMD routine is checked beside its scalar
//! twin, where the CPU has AVX2.

use super::node::{self, BoxRay, Node8, SLACK, round_down, round_up};
use super::tests::Tri;
use super::triangles::{self, Block, LaneRay};
use super::*;
use crate::geometry::DVec3;
use proptest::prelude::*;

#[test]
fn rounding_to_f32_goes_the_asked_way_by_at_most_one_step() {
    let _watchdog = crate::watchdog::start();
    let third = 1.0 / 3.0;
    let xs = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.1,
        -0.1,
        third,
        -third,
        1e-30,
        -1e-30,
        1e-50,
        -1e-50,
        3e38,
        -3e38,
        1e39,
        -1e39,
        f64::MAX,
        -f64::MAX,
        f32::MAX as f64,
        f32::MIN_POSITIVE as f64,
        16777217.0,
        -16777217.0,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for x in xs {
        let (d, u) = (round_down(x), round_up(x));
        // At or below (above) x, and the next f32 the other way is past
        // it: the nearest f32 on that side, so an exact f32 is kept.
        assert!(d as f64 <= x, "round_down({x}) = {d}");
        assert!(u as f64 >= x, "round_up({x}) = {u}");
        if d != f32::INFINITY {
            assert!(
                d.next_up() as f64 > x,
                "round_down({x}) = {d} is not the nearest"
            );
        }
        if u != f32::NEG_INFINITY {
            assert!(
                (u.next_down() as f64) < x,
                "round_up({x}) = {u} is not the nearest"
            );
        }
        if (x as f32) as f64 == x {
            assert_eq!(d.to_bits(), (x as f32).to_bits(), "{x} is an f32");
            assert_eq!(u.to_bits(), (x as f32).to_bits(), "{x} is an f32");
        }
    }
}

#[test]
fn the_path_is_avx2_where_the_cpu_has_it_unless_asked_for_scalar() {
    let _watchdog = crate::watchdog::start();
    assert_eq!(Simd::choose(None, true), Simd::Avx2);
    assert_eq!(Simd::choose(Some("avx2"), true), Simd::Avx2);
    assert_eq!(Simd::choose(Some(""), true), Simd::Avx2);
    assert_eq!(Simd::choose(Some("scalar"), true), Simd::Scalar);
    assert_eq!(Simd::choose(None, false), Simd::Scalar);
    assert_eq!(Simd::choose(Some("scalar"), false), Simd::Scalar);
    assert_eq!(Simd::choose(Some("avx2"), false), Simd::Scalar);
    let asked = std::env::var("RAYTRACE_SIMD").ok();
    assert_eq!(
        Simd::detect(),
        Simd::choose(asked.as_deref(), Simd::avx2_available())
    );
    // Where the CPU has AVX2, FMA, BMI1 and POPCNT, the AVX2 path is taken
    // (and these tests run it beside the scalar one).
    #[cfg(target_arch = "x86_64")]
    assert_eq!(
        Simd::avx2_available(),
        is_x86_feature_detected!("avx2")
            && is_x86_feature_detected!("fma")
            && is_x86_feature_detected!("bmi1")
            && is_x86_feature_detected!("popcnt")
    );
    let mut b = Bvh::build(&[Aabb::new(DVec3::ZERO, DVec3::ONE)], TRIANGLES);
    b.set_simd(Simd::Scalar);
    assert_eq!(b.simd(), Simd::Scalar);
    b.set_simd(Simd::Avx2);
    let want = if Simd::avx2_available() {
        Simd::Avx2
    } else {
        Simd::Scalar
    };
    assert_eq!(b.simd(), want);
    b.set_simd(Simd::Scalar);
    assert_eq!(b.simd(), Simd::Scalar);
}

/// Where the ray `o + t·d` is inside the box `[lo, hi]` in exact-enough
/// `f64`, clipped to `[t_min, t_max]`: `(entry, exit)`, entry > exit for a
/// miss. A zero direction component keeps the whole line if the origin is
/// within the slab (on a face included), and nothing otherwise.
fn exact_slabs(lo: [f32; 3], hi: [f32; 3], o: [f64; 3], d: [f64; 3], t: (f64, f64)) -> (f64, f64) {
    let (mut entry, mut exit) = t;
    for a in 0..3 {
        let (l, h) = (lo[a] as f64, hi[a] as f64);
        if d[a] == 0.0 {
            if o[a] < l || o[a] > h {
                return (f64::INFINITY, f64::NEG_INFINITY);
            }
            continue;
        }
        let (t0, t1) = ((l - o[a]) / d[a], (h - o[a]) / d[a]);
        entry = entry.max(t0.min(t1));
        exit = exit.min(t0.max(t1));
    }
    (entry, exit)
}

/// A node coordinate: a coarse grid (faces shared exactly, flat boxes,
/// origins on faces) or anywhere.
fn c32() -> impl Strategy<Value = f32> {
    prop_oneof![(-6i32..=6).prop_map(|k| k as f32 * 0.5), -3.0f32..3.0]
}

/// A child box: general, flat in one axis, or an unused (empty) slot.
fn child_box() -> impl Strategy<Value = Option<([f32; 3], [f32; 3])>> {
    prop_oneof![
        4 => ([c32(), c32(), c32()], [c32(), c32(), c32()]).prop_map(|(a, b)| {
            Some((
                [0, 1, 2].map(|i| a[i].min(b[i])),
                [0, 1, 2].map(|i| a[i].max(b[i])),
            ))
        }),
        2 => (0usize..3, [c32(), c32(), c32()], [c32(), c32(), c32()]).prop_map(|(f, a, b)| {
            let lo = [0, 1, 2].map(|i| a[i].min(b[i]));
            let mut hi = [0, 1, 2].map(|i| a[i].max(b[i]));
            hi[f] = lo[f];
            Some((lo, hi))
        }),
        1 => Just(None),
    ]
}

/// A direction with any of its components zero (either sign) or not.
fn dir64() -> impl Strategy<Value = [f64; 3]> {
    (
        [c32(), c32(), c32()],
        0u8..8,
        any::<bool>(),
        prop_oneof![Just(1.0), Just(1e-3), Just(1e3)],
    )
        .prop_map(|(d, zero, neg_zero, scale)| {
            let mut d = d.map(|x| x as f64 * scale);
            for (a, c) in d.iter_mut().enumerate() {
                if zero & (1 << a) != 0 {
                    *c = if neg_zero { -0.0 } else { 0.0 };
                }
            }
            if d.iter().all(|&c| c == 0.0) {
                d[2] = 1.0;
            }
            d
        })
}

/// A window: the whole line, from 0, or a random span.
fn window() -> impl Strategy<Value = (f32, f32)> {
    prop_oneof![
        Just((f32::NEG_INFINITY, f32::INFINITY)),
        Just((0.0, f32::INFINITY)),
        (c32(), c32()).prop_map(|(a, b)| (a.min(b), a.max(b))),
    ]
}

fn check_box_test(
    name: &str,
    kids: &[Option<([f32; 3], [f32; 3])>],
    o: [f64; 3],
    d: [f64; 3],
    w: (f32, f32),
    (mask, near): (u32, [f32; 8]),
) -> Result<(), TestCaseError> {
    // How far f32 rounding may move an entry or exit: the origin's and
    // the plane's rounding over the direction, and the entry's own size.
    let scale = (0..3)
        .filter(|&a| d[a] != 0.0)
        .map(|a| (o[a].abs() + 8.0) / d[a].abs())
        .fold(0.0, f64::max);
    for (k, kid) in kids.iter().enumerate() {
        let bit = mask & (1 << k) != 0;
        let Some((lo, hi)) = kid else {
            prop_assert!(!bit, "{name}: empty slot {} reported", k);
            continue;
        };
        let (entry, exit) = exact_slabs(*lo, *hi, o, d, (w.0 as f64, w.1 as f64));
        if entry <= exit {
            prop_assert!(
                bit,
                "{name}: box {k} {lo:?}..{hi:?} crossed at {entry}..{exit} missed"
            );
            prop_assert!(
                near[k] as f64 <= entry,
                "{name}: box {k} entered at {entry}, reported {}",
                near[k]
            );
        }
        if entry.is_finite() {
            let tol = 1e-5 * (scale + entry.abs());
            if entry <= exit {
                prop_assert!(
                    near[k] as f64 >= entry - tol,
                    "{name}: box {k} entered at {entry}, reported {} (too early)",
                    near[k]
                );
            }
            if exit.is_finite() && entry > exit + 1e-5 * (scale + entry.abs() + exit.abs()) {
                prop_assert!(!bit, "{name}: box {k} missed ({entry} > {exit}) reported");
            }
        } else if entry == f64::INFINITY && exit == f64::NEG_INFINITY {
            // Outside a slab the direction runs along: no rounding of an
            // f32 grid origin can put it inside.
            let exact_origin = o.iter().all(|&x| (x as f32) as f64 == x);
            if exact_origin {
                prop_assert!(!bit, "{name}: box {k} beside a parallel ray reported");
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    /// The eight-box test never misses a box the exact ray crosses within
    /// the window (flat boxes, origins on faces, zero components of either
    /// sign included), enters no later than the exact entry and at most
    /// its slack earlier, and reports no box clearly missed, on both paths.
    #[test]
    fn box_test_is_conservative_and_tight(
        kids in prop::collection::vec(child_box(), 8),
        o in [c32(), c32(), c32()],
        d in dir64(),
        w in window(),
        off in prop_oneof![Just(0.0f64), Just(1e-9), -1e-7f64..1e-7],
    ) {
        let _watchdog = crate::watchdog::start();
        let mut n = Node8::empty();
        for (k, kid) in kids.iter().enumerate() {
            if let Some((lo, hi)) = kid {
                for a in 0..3 {
                    n.lo[a][k] = lo[a];
                    n.hi[a][k] = hi[a];
                }
            }
        }
        // The origin on the grid, or just off it (not an f32).
        let o = o.map(|x| x as f64 + off);
        let r = BoxRay::new(o, d);
        check_box_test("scalar", &kids, o, d, w, node::hits_scalar(&n, &r, w.0, w.1))?;
        #[cfg(target_arch = "x86_64")]
        if Simd::avx2_available() {
            // SAFETY: the CPU has AVX2, FMA, BMI1 and POPCNT.
            let got = unsafe { node::hits_avx2(&n, &r, w.0, w.1) };
            check_box_test("avx2", &kids, o, d, w, got)?;
        }
    }
}

#[test]
fn the_slack_is_what_the_rounding_needs() {
    // Four f32 roundings (γ₄ = 4u/(1 − 4u), u = 2⁻²⁴) and the widening's
    // own, with room to spare; and small enough to keep boxes tight.
    let u = f32::EPSILON as f64 / 2.0;
    let gamma4 = 4.0 * u / (1.0 - 4.0 * u);
    assert!(SLACK as f64 >= 2.0 * gamma4 && (SLACK as f64) < 1e-5);
}

#[test]
fn children_are_popped_nearest_first() {
    let _watchdog = crate::watchdog::start();
    let mut seed = 0x0dd_ba11_u64;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 33) as u32
    };
    let mut n = Node8::empty();
    for k in 0..8 {
        n.child[k] = 100 + k as u32;
        n.count[k] = 7 * k as u32 + 1;
    }
    for _ in 0..2000 {
        let mask = next() & 0xff;
        // Few distinct values, so that ties are common.
        let near: [f32; 8] = std::array::from_fn(|_| (next() % 5) as f32 - 2.0);
        let mut stack = Stack::new();
        // Something below, which must stay below.
        stack.push(Entry {
            child: 7,
            count: 0,
            near: -100.0,
        });
        push_sorted(&mut stack, &n, mask, &near);
        let mut seen = 0u32;
        let mut last = f32::NEG_INFINITY;
        let mut last_k = usize::MAX;
        while let Some(e) = stack.pop() {
            if e.child == 7 {
                assert_eq!(stack.pop().map(|e| e.child), None);
                break;
            }
            let k = (e.child - 100) as usize;
            assert!(mask & (1 << k) != 0, "child {k} not in {mask:08b} pushed");
            assert!(seen & (1 << k) == 0, "child {k} pushed twice");
            seen |= 1 << k;
            assert_eq!(e.count, n.count[k]);
            assert_eq!(e.near.to_bits(), near[k].to_bits());
            assert!(e.near >= last, "{mask:08b} {near:?}: popped out of order");
            // Equal distances: the higher slot first, whatever the count
            // of children hit (the two-child path sorts as the loop does).
            assert!(
                e.near != last || k < last_k,
                "{mask:08b} {near:?}: a tie popped low slot first"
            );
            last = e.near;
            last_k = k;
        }
        assert_eq!(seen, mask, "{near:?}");
    }
}

/// Four triangles' lanes against the watertight test, lane for lane.
fn check_block(
    tris: &[Option<[DVec3; 3]>; 4],
    ray: &Ray,
    t_min: f64,
    t_max: f64,
) -> Result<(), String> {
    let b = Block::new(*tris);
    let r = LaneRay::from_ray(ray);
    let s = ShearedRay::new(ray);
    let mut results = vec![
        ("scalar", triangles::hits_scalar(&b, &r, t_min, t_max)),
        (
            "hits scalar",
            triangles::hits(&b, &r, t_min, t_max, Simd::Scalar),
        ),
        (
            "hits avx2",
            triangles::hits(&b, &r, t_min, t_max, Simd::Avx2),
        ),
    ];
    #[cfg(target_arch = "x86_64")]
    if Simd::avx2_available() {
        // SAFETY: the CPU has AVX2, FMA, BMI1 and POPCNT.
        results.push(("avx2", unsafe {
            triangles::hits_avx2(&b, &r, t_min, t_max)
        }));
    }
    for (name, (mask, ts)) in results {
        for (lane, t) in tris.iter().enumerate() {
            let want = t
                .and_then(|t| s.triangle(t[0], t[1], t[2]))
                .map(|h| h.0)
                .filter(|&th| th > t_min && th < t_max);
            let got = (mask & (1 << lane) != 0).then_some(ts[lane]);
            if got.map(f64::to_bits) != want.map(f64::to_bits) {
                return Err(format!(
                    "{name}, lane {lane} of {tris:?}, ray {ray:?} in ({t_min}, {t_max}): got {got:?}, want {want:?}"
                ));
            }
        }
        if mask >> 4 != 0 {
            return Err(format!("{name}: mask {mask:b} past four lanes"));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    /// Each lane of a block reports exactly the watertight test's t when it
    /// lies strictly inside the window, on every path; padding lanes never
    /// hit. The windows include each lane's own t as an end.
    #[test]
    fn block_lanes_agree_with_the_watertight_test(
        tris in prop::collection::vec(prop::option::weighted(0.85, super::tests::triangle()), 4),
        o in super::tests::point(),
        d in super::tests::direction(),
        aim in prop::option::of((0usize..4, 0.0f64..1.0, 0.0f64..1.0)),
    ) {
        let _watchdog = crate::watchdog::start();
        let tris: [Option<Tri>; 4] = std::array::from_fn(|i| tris[i]);
        // Often aim at a lane's triangle, so that lanes hit.
        let ray = match aim {
            Some((lane, a, b)) if tris[lane].is_some() => {
                let t = tris[lane].unwrap();
                let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
                let p = t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]);
                let o = o * 2.0;
                Ray::new(o, if p == o { d } else { p - o })
            }
            _ => Ray::new(o * 2.0, d),
        };
        let s = ShearedRay::new(&ray);
        let mut windows = vec![
            (0.0, f64::INFINITY),
            (f64::NEG_INFINITY, f64::INFINITY),
            (1e-9, 1.0),
        ];
        for t in tris.iter().flatten() {
            if let Some((th, _)) = s.triangle(t[0], t[1], t[2]) {
                windows.push((th, f64::INFINITY));
                windows.push((f64::NEG_INFINITY, th));
                windows.push((th.next_down(), th.next_up()));
            }
        }
        for (t_min, t_max) in windows {
            check_block(&tris, &ray, t_min, t_max).map_err(TestCaseError::fail)?;
        }
    }
}

/// Rays that only touch a box, along one of its edges: they enter by one
/// axis's plane and leave by another's at the same real t, which `f32`
/// rounds differently for each axis (3·(1/7) is 3 but 21·(1/7) rounds to
/// 3 + 2⁻²²), so the entry can come out above the exit; widening both
/// (the entry down, the exit up) keeps the box, on both paths, whichever
/// way the ray goes. The cases `(p, q, t)`: the leaving axis's direction
/// component, the entering one's, and where they touch.
#[test]
fn a_ray_touching_an_edge_keeps_the_box() {
    let _watchdog = crate::watchdog::start();
    let mut n = Node8::empty();
    for a in 0..3 {
        n.lo[a][3] = 0.0;
        n.hi[a][3] = 1.0;
    }
    let mut tried = 0;
    let cases = [
        (1.0, 7.0, 3.0),
        (2.0, 15.0, 5.0),
        (1.0, 13.0, 7.0),
        (1.0, 30.0, 10.0),
        (7.0, 1.0, 3.0),
    ];
    for (p, q, t) in cases {
        for flip in 0..4 {
            for (first, second) in [(0, 1), (1, 2), (2, 0)] {
                // Through the point on the edge where `first` = hi and
                // `second` = lo (flipped: lo, hi) at t, leaving by `first`
                // and entering by `second`.
                let (sf, ss) = (
                    if flip & 1 == 0 { 1.0 } else { -1.0 },
                    if flip & 2 == 0 { 1.0 } else { -1.0 },
                );
                let mut at = [0.5; 3];
                at[first] = if sf > 0.0 { 1.0 } else { 0.0 };
                at[second] = if ss > 0.0 { 0.0 } else { 1.0 };
                let mut d = [0.25; 3];
                d[first] = sf * p;
                d[second] = ss * q;
                let o = [0, 1, 2].map(|a| at[a] - t * d[a]);
                let (entry, exit) = exact_slabs([0.0; 3], [1.0; 3], o, d, (0.0, f64::INFINITY));
                assert_eq!((entry, exit), (t, t), "{o:?} {d:?}");
                let r = BoxRay::new(o, d);
                let t32 = t as f32;
                for w in [(0.0, f32::INFINITY), (0.0, t32), (t32, t32)] {
                    let (mask, near) = node::hits_scalar(&n, &r, w.0, w.1);
                    assert_eq!(mask, 1 << 3, "scalar: {o:?} {d:?} in {w:?}");
                    assert!(near[3] <= t32);
                    #[cfg(target_arch = "x86_64")]
                    if Simd::avx2_available() {
                        // SAFETY: the CPU has AVX2, FMA, BMI1 and POPCNT.
                        let (mask, _) = unsafe { node::hits_avx2(&n, &r, w.0, w.1) };
                        assert_eq!(mask, 1 << 3, "avx2: {o:?} {d:?} in {w:?}");
                    }
                    tried += 1;
                }
            }
        }
    }
    assert_eq!(tried, cases.len() * 4 * 3 * 3);
}

/// The AVX box ray is the scalar one, bit for bit (NaN lanes compared by
/// their bits too).
#[cfg(target_arch = "x86_64")]
fn same_box_ray(o: [f64; 3], d: [f64; 3]) -> Result<(), TestCaseError> {
    if !std::arch::is_x86_feature_detected!("avx") {
        return Ok(());
    }
    let want = BoxRay::new(o, d);
    // SAFETY: the CPU has AVX, checked just above.
    let got = unsafe { node::box_ray_avx(o, d) };
    let bits = |x: [f32; 3]| x.map(f32::to_bits);
    prop_assert_eq!(bits(got.o_near), bits(want.o_near), "near {:?} {:?}", o, d);
    prop_assert_eq!(bits(got.o_far), bits(want.o_far), "far {:?} {:?}", o, d);
    prop_assert_eq!(bits(got.inv), bits(want.inv), "inv {:?} {:?}", o, d);
    prop_assert_eq!(got.neg, want.neg, "neg {:?} {:?}", o, d);
    Ok(())
}

/// Coordinates where the rounding to `f32` is delicate: zeros of both
/// signs, f64s beside and between f32s, subnormals, beyond `f32::MAX`,
/// infinities and NaN.
fn awkward() -> impl Strategy<Value = f64> {
    let f32_subnormal = f32::from_bits(1) as f64;
    prop_oneof![
        Just(0.0),
        Just(-0.0),
        Just(f32_subnormal / 3.0),
        Just(-f32_subnormal / 3.0),
        Just(f32_subnormal * 2.5),
        Just(f32::MAX as f64 * 1.5),
        Just(-(f32::MAX as f64) * 1.5),
        Just(f32::MAX as f64),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(f64::NAN),
        Just(1e-300),
        (-1e6f64..1e6).prop_map(|x| x),
        (-1e6f32..1e6).prop_map(|x| x as f64),
        (-1e6f32..1e6).prop_map(|x| x as f64 + (x as f64).abs() * 1e-9),
    ]
}

#[cfg(target_arch = "x86_64")]
proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]
    #[test]
    fn the_avx_box_ray_is_the_scalar_one_bit_for_bit(
        o in [awkward(), awkward(), awkward()],
        d in [awkward(), awkward(), awkward()],
    ) {
        same_box_ray(o, d)?;
    }
}
