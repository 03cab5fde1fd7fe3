use super::*;
use proptest::prelude::*;

/// Coefficients of ∏(t − r_i) · (1 + s·t²)^m, lowest first.
fn from_roots(roots: &[f64], s: f64, m: usize) -> Vec<f64> {
    let mut c = vec![1.0];
    let mul = |c: &Vec<f64>, f: &[f64]| {
        let mut out = vec![0.0; c.len() + f.len() - 1];
        for (i, a) in c.iter().enumerate() {
            for (j, b) in f.iter().enumerate() {
                out[i + j] += a * b;
            }
        }
        out
    };
    for &r in roots {
        c = mul(&c, &[-r, 1.0]);
    }
    for _ in 0..m {
        c = mul(&c, &[1.0, 0.0, s]);
    }
    c
}

fn check(roots: &[f64], found: &[f64], tol: f64) {
    let mut want: Vec<f64> = roots.to_vec();
    want.sort_by(f64::total_cmp);
    assert_eq!(found.len(), want.len(), "want {want:?}, found {found:?}");
    for (w, f) in want.iter().zip(found) {
        assert!((w - f).abs() < tol, "want {want:?}, found {found:?}");
    }
}

#[test]
fn low_degrees() {
    let _watchdog = crate::watchdog::start();
    check(
        &[0.5],
        &all_roots(&from_roots(&[0.5], 0.0, 0), -1.0, 1.0, 1e-14),
        1e-12,
    );
    check(
        &[-0.3, 0.7],
        &all_roots(&from_roots(&[-0.3, 0.7], 0.0, 0), -1.0, 1.0, 1e-14),
        1e-12,
    );
    let r = [-0.9, 0.1, 0.2];
    check(
        &r,
        &all_roots(&from_roots(&r, 0.0, 0), -1.0, 1.0, 1e-14),
        1e-10,
    );
    let r = [-0.5, -0.49, 0.3, 0.95];
    check(
        &r,
        &all_roots(&from_roots(&r, 0.0, 0), -1.0, 1.0, 1e-14),
        1e-10,
    );
    // Outside the interval: ignored.
    check(
        &[0.5],
        &all_roots(&from_roots(&[0.5, 3.0, -2.0], 0.0, 0), -1.0, 1.0, 1e-14),
        1e-10,
    );
}

#[test]
fn close_and_repeated_roots() {
    let _watchdog = crate::watchdog::start();
    // Two roots 1e-6 apart are still told apart.
    let r = [0.25, 0.250001, -0.6];
    check(
        &r,
        &all_roots(&from_roots(&r, 0.0, 0), -1.0, 1.0, 1e-15),
        1e-9,
    );
    // A triple root changes sign: found once, to about eps^(1/3).
    let c = from_roots(&[0.4, 0.4, 0.4, -0.2], 0.0, 0);
    let f = all_roots(&c, -1.0, 1.0, 1e-15);
    assert_eq!(f.len(), 2, "{f:?}");
    assert!(
        (f[0] + 0.2).abs() < 1e-9 && (f[1] - 0.4).abs() < 1e-4,
        "{f:?}"
    );
    // A double root (a grazing ray) may be reported or not, but no false
    // root may appear and the simple roots must be found.
    let c = from_roots(&[0.1, 0.1, 0.7, -0.8], 0.0, 0);
    let f = all_roots(&c, -1.0, 1.0, 1e-15);
    assert!(f.iter().any(|t| (t - 0.7).abs() < 1e-9));
    assert!(f.iter().any(|t| (t + 0.8).abs() < 1e-9));
    assert!(
        f.iter()
            .all(|t| [0.1, 0.7, -0.8].iter().any(|r| (t - r).abs() < 1e-5))
    );
}

/// Critical points are taken as soon as the sign of the level above is
/// sure there (`Cascade::next`), not at full precision: a pair of roots
/// 1e-6 apart, the dip between them 2.5e-13 deep, is still told from a
/// miss at every place in the interval and at degrees 4 to 8, where those
/// early stops happen on two or more levels.
#[test]
fn close_pairs_survive_rough_critical_points() {
    let _watchdog = crate::watchdog::start();
    for degree in 4..=8usize {
        for k in 0..19 {
            let at = -0.9 + 0.1 * k as f64;
            let mut r = vec![at, at + 1e-6];
            // The other roots spread over the interval, clear of the pair.
            for i in 0..degree - 2 {
                let x = -0.95 + 1.9 * (i as f64 + 0.5) / (degree - 2) as f64;
                r.push(if (x - at).abs() < 0.02 { x + 0.04 } else { x });
            }
            let found = all_roots(&from_roots(&r, 0.0, 0), -1.0, 1.0, 1e-15);
            // The pair is ill-conditioned: its roots are good to ~1e-8
            // (with or without the early stops); that both are there is
            // the point.
            check(&r, &found, 1e-7);
        }
    }
}

/// The early stop does stop early: a critical point whose level above is
/// far from zero there is handed out before Newton's steps would have
/// pinned it down (here after the first, 0.013 off), with the sign
/// of the level above that the exact one has.
#[test]
fn a_critical_point_is_refined_only_until_its_sign_is_sure() {
    let _watchdog = crate::watchdog::start();
    // Roots ±0.3, ±0.8: P' vanishes at 0 and ±√0.365, where P is −0.0756.
    let c = from_roots(&[-0.8, -0.3, 0.3, 0.8], 0.0, 0);
    let mut s = Cascade::<5> {
        deg: 4,
        derivs: [[0.0; 5]; 5],
        hi: 1.0,
        eps: 1e-15,
        a: [-1.0; 5],
        fa: [0.0; 5],
        b: [1.0; 5],
        fb: [0.0; 5],
        fetched: [false; 5],
        done: [false; 5],
        quad: [0.0; 2],
        quad_count: 0,
        quad_next: 0,
    };
    s.fill(&c, -1.0);
    let x = s.next(1).expect("a critical point");
    let exact = -0.365f64.sqrt();
    assert!((x - exact).abs() < 0.05, "{x}");
    assert!((x - exact).abs() > 1e-9, "refined to {x}, as if to the end");
    assert!(horner(&c, x) < 0.0 && horner(&c, exact) < 0.0);
}

/// A root exactly on a critical point (a double root at a piece's end, as
/// where a ray grazes a surface at a pixel's exact centre): reported once,
/// never twice and never beside itself. Duplicated crossings flip CSG's
/// inside and outside, so "no false root" is checked as an exact list.
#[test]
fn a_root_on_a_critical_point_is_reported_once() {
    let _watchdog = crate::watchdog::start();
    // t²(t − 0.5): a double root at 0 (where P' = 0) and a simple one.
    let c = from_roots(&[0.0, 0.0, 0.5], 0.0, 0);
    assert_eq!(c, vec![0.0, 0.0, -0.5, 1.0]);
    // And the same upside down, so the piece ending at 0 starts positive.
    let neg: Vec<f64> = c.iter().map(|k| -k).collect();
    for (lo, hi, c) in [
        (-1.0, 1.0, &c),
        (0.0, 1.0, &c),
        (-0.7, 0.6, &c),
        (-1.0, 1.0, &neg),
    ] {
        let f = all_roots(c, lo, hi, 1e-15);
        assert_eq!(f.len(), 2, "on [{lo}, {hi}]: {f:?}");
        assert_eq!(f[0], 0.0, "on [{lo}, {hi}]: {f:?}");
        assert!((f[1] - 0.5).abs() < 1e-12, "on [{lo}, {hi}]: {f:?}");
    }
    // Degree 4: t²(t − 0.5)(t + 0.25), the double root between two pieces.
    let c = from_roots(&[0.0, 0.0, 0.5, -0.25], 0.0, 0);
    // Here the critical point 0 comes from bisecting P' (not exact), so the
    // double root may be missed, as a grazing ray may; never doubled.
    let f = all_roots(&c, -1.0, 1.0, 1e-15);
    assert!((f[0] + 0.25).abs() < 1e-12 && (f[f.len() - 1] - 0.5).abs() < 1e-12);
    assert!(f.len() == 2 || (f.len() == 3 && f[1].abs() < 1e-6), "{f:?}");
    // t³: a root where every derivative down to the quadratic vanishes.
    let f = all_roots(&[0.0, 0.0, 0.0, 1.0], -1.0, 1.0, 1e-15);
    assert_eq!(f, vec![0.0]);
    // (t − 0.25)³ (t + 0.5): a triple root away from the origin, found once.
    let c = from_roots(&[0.25, 0.25, 0.25, -0.5], 0.0, 0);
    let f = all_roots(&c, -1.0, 1.0, 1e-15);
    assert_eq!(f.len(), 2, "{f:?}");
}

/// A window of zero width ([t, t], allowed by `roots_in`) on a root: the
/// root is reported once. The cascade's first piece is then [t, t] with
/// P(t) = 0 at both ends; only `b > a` in `Cascade::next` keeps it from
/// being reported again after `cascade` has already reported the root at
/// `lo` (a doubled crossing flips CSG's inside and outside). Elsewhere a
/// piece has b = a only if a level hands out one critical point twice in
/// a row; each level's roots come out increasing and above `lo`.
#[test]
fn a_root_in_a_window_of_zero_width_is_reported_once() {
    let _watchdog = crate::watchdog::start();
    // t(t − 1)(t − 2) and t(t − 1)(t − 2)(t + 3): exact at t = 1.
    let cubic = from_roots(&[0.0, 1.0, 2.0], 0.0, 0);
    let quartic = from_roots(&[0.0, 1.0, 2.0, -3.0], 0.0, 0);
    for c in [&cubic, &quartic] {
        assert_eq!(horner(c, 1.0), 0.0);
        assert_eq!(all_roots(c, 1.0, 1.0, 1e-12), vec![1.0], "{c:?}");
        // And a zero-width window off the roots finds nothing.
        assert!(all_roots(c, 0.5, 0.5, 1e-12).is_empty(), "{c:?}");
    }
}

/// The bracketed solver's bisection start: when the secant guess does not
/// fall inside the bracket (here a bracket whose ends give no usable
/// secant), it starts from the midpoint and still converges.
#[test]
fn bracketed_root_from_every_start() {
    let _watchdog = crate::watchdog::start();
    // p = t³ − 0.001 on [−1, 1]: the secant from (−1, −1.001), (1, 0.999)
    // lands at 0.001, inside; on [0.05, 1] it lands far off.
    let p = [-0.001, 0.0, 0.0, 1.0];
    for (a, b) in [(-1.0, 1.0), (0.05, 1.0), (-1.0, 0.2), (0.0999, 0.1001)] {
        let (fa, fb) = (horner(&p, a), horner(&p, b));
        if (fa < 0.0) == (fb < 0.0) {
            continue;
        }
        let x = bracketed(&p, (a, b), (fa, fb), 1e-15, |_, _| false);
        assert!((x - 0.1).abs() < 1e-12, "[{a}, {b}]: {x}");
    }
    // A huge slope ratio: the secant guess is 1e-300, just inside.
    let p = [-1e-300, 1.0];
    let x = bracketed(&p, (0.0, 1.0), (-1e-300, 1.0), 1e-15, |_, _| false);
    assert!((x - 1e-300).abs() < 1e-15, "{x}");
    // A secant guess that rounds onto an end: the bracket's left end is
    // one ulp below the middle root of a cubic, where p is 5e-20, so the
    // secant's step from it is far below an ulp. The search starts at the
    // bracket's midpoint instead; a start outside the bracket (the other
    // roots lie on either side of it) would lead Newton to another root.
    let r = [
        0.016852976499963646,
        0.041876835226290376,
        0.5568852300002916,
    ];
    let p = from_roots(&r, 0.0, 0);
    let (a, b) = (r[1].next_down(), 0.5 * (r[1] + r[2]));
    let (fa, fb) = (horner(&p, a), horner(&p, b));
    assert!(fa > 0.0 && fb < 0.0, "{fa} {fb}");
    assert_eq!(a - fa * (b - a) / (fb - fa), a, "the guess rounds onto a");
    let x = bracketed(&p, (a, b), (fa, fb), 1e-15, |_, _| false);
    assert!((x - r[1]).abs() < 1e-12, "[{a}, {b}]: {x}");
    // Newton stops when its step is small, not when it lands near 0: on
    // t³ − 1/4 (root 0.63), the secant guess from [−1, b] is −1/2, whose
    // Newton step (2x³ + 1/4)/(3x²) lands on 0, a long step to a point
    // that is no root.
    let p = [-0.25, 0.0, 0.0, 1.0];
    let (a, b) = (-1.0, 1.8228756555323);
    let (fa, fb) = (horner(&p, a), horner(&p, b));
    assert!((a - fa * (b - a) / (fb - fa) + 0.5).abs() < 1e-12);
    let x = bracketed(&p, (a, b), (fa, fb), 1e-15, |_, _| false);
    assert!((x - 0.25f64.cbrt()).abs() < 1e-12, "[{a}, {b}]: {x}");
    // Nor when a step lands on minus its start: on t³ − 5t (roots 0 and
    // ±√5) Newton from 1 lands on −1 and from −1 on 1, a 2-cycle across
    // the root 0. The bracket [−3/2, b] is chosen so that the secant guess
    // is 1 (b a root of b³ − 3.35b − 1.65, from the secant's formula with
    // p(−3/2) = 33/8); its only root is 0.
    let p = [0.0, -5.0, 0.0, 1.0];
    let (a, b) = (-1.5, 2.039379695822763);
    let (fa, fb) = (horner(&p, a), horner(&p, b));
    assert!(fa > 0.0 && fb < 0.0 && b < 5f64.sqrt(), "{fa} {fb}");
    let guess = a - fa * (b - a) / (fb - fa);
    assert!((guess - 1.0).abs() < 1e-12, "{guess}");
    let x = bracketed(&p, (a, b), (fa, fb), 1e-15, |_, _| false);
    assert!(x.abs() < 1e-12, "[{a}, {b}]: {x}");
}

#[test]
fn degree_40_with_few_real_roots() {
    let _watchdog = crate::watchdog::start();
    let r = [-0.7, 0.05, 0.9];
    let c = from_roots(&r, 3.0, 18);
    assert_eq!(c.len(), 40);
    check(&r, &all_roots(&c, -1.0, 1.0, 1e-15), 1e-9);
}

#[test]
fn bernstein_cull_tells_clear_cases() {
    let _watchdog = crate::watchdog::start();
    // 2 + t² has no root; t² − 0.25 has two.
    assert!(no_root_in_unit(&[2.0, 0.0, 1.0]));
    assert!(!no_root_in_unit(&[-0.25, 0.0, 1.0]));
    assert!(no_root_in_unit(&from_roots(&[1.5, -1.2, 3.0, 2.0], 0.0, 0)));
    assert!(!no_root_in_unit(&from_roots(
        &[1.5, -1.2, 0.3, 2.0],
        0.0,
        0
    )));
}

/// A root exactly at an end of [−1, 1] is a root in it: p(t) = (1 − t)·s(t)
/// with s > 0 there is positive on [−1, 1) and zero at 1, so every
/// Bernstein coefficient is positive but the last, which is 0 and comes
/// out of the change of basis (its Taylor shift rounds) as noise of either
/// sign. The cull's margin, relative to the terms summed, keeps such a
/// polynomial as "maybe"; without it, or with a margin that shrinks as the
/// coefficients grow, a root on the box's face (a ray leaving the box on
/// the surface) would be culled. s has full-precision coefficients each
/// 0.55 to 0.95 of the one before (so s > 0 on [−1, 1]: an alternating sum
/// of decreasing terms), which makes each p_k = s_k − s_(k−1) exact
/// (Sterbenz) and so p(1) = 0 exactly; and scaled by 2²⁰ as well.
#[test]
fn a_root_at_an_end_of_the_interval_is_never_culled() {
    let _watchdog = crate::watchdog::start();
    let mut rnd = crate::shapes::testing::numbers(0x5eed);
    for trial in 0..3000 {
        let deg = 2 + trial % 11;
        let mut s = vec![1.0 + 0.5 * rnd().abs()];
        for k in 1..deg {
            let ratio = 0.75 + 0.2 * rnd();
            s.push(s[k - 1] * ratio);
        }
        let scale = if trial % 2 == 0 { 1.0 } else { 2f64.powi(20) };
        // p = (1 − t)·s, exactly (times a power of two).
        let mut p = vec![0.0; deg + 1];
        p[0] = s[0];
        for k in 1..deg {
            p[k] = s[k] - s[k - 1];
        }
        p[deg] = -s[deg - 1];
        let p: Vec<f64> = p.iter().map(|v| v * scale).collect();
        let minus: Vec<f64> = p.iter().map(|v| -v).collect();
        for c in [p, minus] {
            assert!(!no_root_in_unit(&c), "culled a root at 1: {c:?}");
            // And mirrored (t → −t), a root at −1.
            let m: Vec<f64> = c
                .iter()
                .enumerate()
                .map(|(k, v)| if k % 2 == 1 { -v } else { *v })
                .collect();
            assert!(!no_root_in_unit(&m), "culled a root at −1: {m:?}");
        }
    }
}

#[test]
fn nothing_on_a_zero_polynomial() {
    let _watchdog = crate::watchdog::start();
    assert!(all_roots(&[0.0, 0.0, 0.0], -1.0, 1.0, 1e-12).is_empty());
    assert!(all_roots(&[1.0, 0.0, 0.0, 0.0, 0.0], -1.0, 1.0, 1e-12).is_empty());
}

/// Zero leading coefficients are trimmed first: a line written with a zero
/// t² term is a line (one root, not the quadratic formula's "double root"
/// of a = 0), and a quadratic or cubic padded with zeros keeps its roots.
#[test]
fn zero_leading_coefficients_are_not_a_higher_degree() {
    let _watchdog = crate::watchdog::start();
    assert_eq!(all_roots(&[-0.5, 1.0, 0.0], -1.0, 1.0, 1e-14), vec![0.5]);
    let mut c = from_roots(&[-0.3, 0.7], 0.0, 0);
    c.extend([0.0; 3]);
    check(&[-0.3, 0.7], &all_roots(&c, -1.0, 1.0, 1e-14), 1e-12);
    let mut c = from_roots(&[-0.9, 0.1, 0.2], 0.0, 0);
    c.extend([0.0; 10]);
    check(&[-0.9, 0.1, 0.2], &all_roots(&c, -1.0, 1.0, 1e-14), 1e-10);
}

/// An empty window (lo > hi) or one with a NaN end holds no root, at every
/// degree, though [−1, 1] holds them all; a line's root beyond either end
/// of the window is not reported.
#[test]
fn empty_or_nan_windows_hold_no_root() {
    let _watchdog = crate::watchdog::start();
    let polys = [
        vec![-0.25, 1.0],
        from_roots(&[0.25, 0.5], 0.0, 0),
        from_roots(&[-0.5, 0.25, 0.75], 0.0, 0),
        from_roots(&[-0.5, -0.1, 0.25, 0.75, 0.9], 0.0, 0),
    ];
    for c in &polys {
        assert!(!all_roots(c, -1.0, 1.0, 1e-12).is_empty(), "{c:?}");
        assert!(all_roots(c, 1.0, -1.0, 1e-12).is_empty(), "{c:?}: lo > hi");
        assert!(all_roots(c, 0.8, 0.2, 1e-12).is_empty(), "{c:?}: lo > hi");
        assert!(
            all_roots(c, f64::NAN, 1.0, 1e-12).is_empty(),
            "{c:?}: lo NaN"
        );
        assert!(
            all_roots(c, -1.0, f64::NAN, 1e-12).is_empty(),
            "{c:?}: hi NaN"
        );
    }
    assert!(all_roots(&[-5.0, 1.0], 0.0, 1.0, 1e-12).is_empty());
    assert!(all_roots(&[5.0, 1.0], 0.0, 1.0, 1e-12).is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn the_bernstein_cull_never_hides_a_root(c in prop::collection::vec(-2.0f64..2.0, 2..13), shift in -1.5f64..1.5) {
        let _watchdog = crate::watchdog::start();
        // Shift the constant so that roots are likely near the interval.
        let mut c = c;
        c[0] += shift;
        if no_root_in_unit(&c) {
            let dense = (0..=2000).map(|i| horner(&c, -1.0 + i as f64 / 1000.0));
            let (mut pos, mut neg) = (false, false);
            for v in dense {
                pos |= v >= 0.0;
                neg |= v <= 0.0;
            }
            prop_assert!(!(pos && neg), "culled a polynomial with a sign change: {c:?}");
        }
    }

    #[test]
    fn finds_known_roots(
        roots in prop::collection::vec(-0.95f64..0.95, 1..7),
        m in 0usize..17,
        s in 0.5f64..4.0,
    ) {
        let _watchdog = crate::watchdog::start();
        // Separated simple roots (closeness is tested above), times a factor
        // without real roots to reach up to degree 40.
        let mut rs = roots.clone();
        rs.sort_by(f64::total_cmp);
        prop_assume!(rs.windows(2).all(|w| w[1] - w[0] > 1e-3));
        let c = from_roots(&rs, s, m);
        let f = all_roots(&c, -1.0, 1.0, 1e-15);
        check(&rs, &f, 1e-7);
    }

    #[test]
    fn power_cube_lines(n in 2u32..21, a in prop::array::uniform4(-1.01f64..1.01)) {
        let _watchdog = crate::watchdog::start();
        // x^2n + y^2n − 1 along a chord of the box [−1.01, 1.01]² between
        // (a0, a1) and (a2, a3), parameterised as the surface does it
        // (midpoint o, half-chord d, s in [−1, 1]): every reported root is a
        // root, and the count matches sign changes on a fine grid.
        let (ox, oy) = (0.5 * (a[0] + a[2]), 0.5 * (a[1] + a[3]));
        let (dx, dy) = (0.5 * (a[2] - a[0]), 0.5 * (a[3] - a[1]));
        let n = 2 * n as usize;
        let mut c = vec![0.0; n + 1];
        for (o, d) in [(ox, dx), (oy, dy)] {
            let mut binom = 1.0;
            for (j, cj) in c.iter_mut().enumerate() {
                *cj += binom * o.powi((n - j) as i32) * d.powi(j as i32);
                binom = binom * (n - j) as f64 / (j + 1) as f64;
            }
        }
        c[0] -= 1.0;
        let f = |t: f64| (ox + t * dx).powi(n as i32) + (oy + t * dy).powi(n as i32) - 1.0;
        let found = all_roots(&c, -1.0, 1.0, 1e-14);
        for t in &found {
            // Near a root the direct form changes sign within a small step.
            let h = 1e-6;
            prop_assert!(f(t - h) * f(t + h) <= 0.0 || f(*t).abs() < 1e-6, "t={t} f={}", f(*t));
        }
        let mut changes = 0;
        let steps = 4000;
        let mut prev = f(-1.0);
        for i in 1..=steps {
            let v = f(-1.0 + 2.0 * i as f64 / steps as f64);
            if (prev < 0.0) != (v < 0.0) { changes += 1; }
            prev = v;
        }
        // A grid may skip a pair of roots closer than its step, never add.
        prop_assert!(found.len() >= changes, "found {found:?}, grid sign changes {changes}");
    }
}
