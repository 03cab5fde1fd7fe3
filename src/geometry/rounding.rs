//! Rounding error and ray offsets: where a secondary ray may start so that
//! it neither meets the surface it leaves nor starts on its far side.
//!
//! Every hit carries its point and a bound on that point's absolute error,
//! per coordinate ([`crate::shapes::Hit::p_error`]), in the manner of
//! pbrt-v4 ("Managing Rounding Error", `pError` and `OffsetRayOrigin`).
//! The true surface lies within that box around the computed point, so a
//! point moved along the geometric normal by the box's extent along the
//! normal, `|n|·p_error`, and then one more ulp away from the surface in
//! each coordinate, is on the chosen side whatever the rounding. The
//! offset follows the hit's own error, not its distance from the origin:
//! a scene keeps its contact shadows at any scale and anywhere.
//!
//! Error bounds use Higham's γₙ = n·u/(1 − n·u) (u = 2⁻⁵³), the bound on
//! the relative error of n rounded operations.

use glam::{DMat4, DVec3};

/// γₙ: a bound on the relative error of `n` chained f64 operations.
pub const fn gamma(n: u32) -> f64 {
    let nu = n as f64 * (f64::EPSILON * 0.5);
    nu / (1.0 - nu)
}

/// The start of a secondary ray leaving the hit point `p` along `dir`:
/// `p` moved along the geometric normal `n_geo` (any length, either
/// orientation) to the side `dir` goes to, far enough that the box of
/// half-sizes `p_error` around `p` (which holds the true surface point) is
/// left behind, then rounded one ulp further away in each coordinate.
///
/// The side is `dir`'s side of the *geometric* surface, never of a shading
/// normal. With a zero normal (no surface) `p` comes back unchanged.
#[inline]
pub fn offset_ray_origin(p: DVec3, p_error: DVec3, n_geo: DVec3, dir: DVec3) -> DVec3 {
    offset_along_unit(p, p_error, normalize_near_unit(n_geo), dir)
}

/// `v.normalize_or_zero()` to the bit, without its square root and
/// division when `v` is already within 2²⁰ ulp of unit length (a normal
/// that a shape made unit, normalised again by the renderer). Every
/// shading point normalises its normal twice, and that chain of two
/// square roots and two divisions was a tenth of a depth-of-field render.
#[inline(always)]
pub fn normalize_near_unit(v: DVec3) -> DVec3 {
    near_unit_or(v, DVec3::normalize_or_zero)
}

/// `v.normalize()` to the bit (glam's, which makes a zero vector NaN),
/// as [`normalize_near_unit`]: a refracted direction, unit but for
/// rounding, is normalised again.
#[inline(always)]
pub fn renormalize(v: DVec3) -> DVec3 {
    near_unit_or(v, DVec3::normalize)
}

/// `v` scaled by the rounded 1/|v| when |v|² is within reach of 1,
/// otherwise what `far` (glam's own normalisation) makes of it.
#[inline(always)]
fn near_unit_or(v: DVec3, far: impl FnOnce(DVec3) -> DVec3) -> DVec3 {
    match recip_sqrt_near_one(v.length_squared()) {
        Some(f) => v * f,
        None => far(v),
    }
}

/// `1 / √x` rounded as `1.0 / x.sqrt()` rounds it, for `x` within 2²⁰ ulp
/// of 1; `None` further out. Near 1 both roundings follow from the bits:
/// for x = 1 + d·ε (d ≥ 0, ε = 2⁻⁵² the spacing above 1) the root rounds
/// to 1 + ⌊d/2⌋·ε and its reciprocal to 1 − ⌊d/2⌋·ε (the spacing below 1
/// is ε/2); for x = 1 − m·ε/2 the root rounds to 1 − c·ε/2 with
/// c = ⌈m/2⌉ and the reciprocal to 1 + ⌈c/2⌉·ε. The terms left out
/// (d²ε²/8 and the like) stay below a quarter of the spacing while
/// |d| < 2²⁷, so no rounding is a tie; a test checks every x in reach.
#[inline(always)]
fn recip_sqrt_near_one(x: f64) -> Option<f64> {
    const ONE: i64 = 0x3ff0_0000_0000_0000;
    const REACH: u64 = 1 << 20;
    let d = x.to_bits() as i64 - ONE;
    if d.unsigned_abs() >= REACH {
        return None;
    }
    let bits = if d >= 0 {
        ONE - (d & !1)
    } else {
        let c = (1 - d) >> 1;
        ONE + ((c + 1) >> 1)
    };
    Some(f64::from_bits(bits as u64))
}

/// [`offset_ray_origin`] for a normal already through `normalize_or_zero`
/// (unit or zero), so that a caller spawning several rays from one hit
/// normalises once; the result is the same to the bit.
#[inline(always)]
pub fn offset_along_unit(p: DVec3, p_error: DVec3, unit_normal: DVec3, dir: DVec3) -> DVec3 {
    let mut n = unit_normal;
    if dir.dot(n) < 0.0 {
        n = -n;
    }
    offset_towards(p, p_error, n)
}

/// [`offset_along_unit`] to the side `n` itself faces (`n` unit or zero,
/// already turned towards where the ray goes): the point every ray leaving
/// on the normal's side starts from. Asked for that side, with `dir` a
/// positive multiple of `n`, `offset_along_unit` never turns `n` (n·n ≥ 0),
/// and every shading point asks once.
#[inline(always)]
pub fn offset_towards(p: DVec3, p_error: DVec3, n: DVec3) -> DVec3 {
    let po = p + n * n.abs().dot(p_error);
    // Rounding `p + offset` may land back towards the surface, and a point
    // with no error (snapped onto an axis-aligned face) would not move at
    // all: step one ulp further away in every coordinate the normal has.
    // (Written out per field: this runs for every shading point and every
    // secondary ray, and indexing a DVec3 costs a bounds check each.)
    DVec3::new(
        ulp_away(po.x, n.x),
        ulp_away(po.y, n.y),
        ulp_away(po.z, n.z),
    )
}

/// `x` one ulp further along the sign of `n` (unchanged when `n` is 0),
/// but never onto a subnormal number: from 0 (a point snapped onto the
/// plane y = 0 with no error) the next float is 5e-324, and every
/// operation that reads or makes a subnormal takes a microcode assist
/// (around a hundred cycles). A shadow ray starting there made a plane's
/// test through the origin several times slower than the rest of the
/// render (spheres.rt: 0.106 s before round 2, 0.28 s after). The smallest
/// normal number, or 0 when stepping up from below it, is further along
/// `n` still, so the ray starts on the same side.
#[inline(always)]
fn ulp_away(x: f64, n: f64) -> f64 {
    let y = if n > 0.0 {
        x.next_up()
    } else if n < 0.0 {
        x.next_down()
    } else {
        return x;
    };
    if y != 0.0 && y.abs() < f64::MIN_POSITIVE {
        return if (y > 0.0) == (n > 0.0) {
            f64::MIN_POSITIVE.copysign(y)
        } else {
            0.0
        };
    }
    y
}

/// How much of the way to a target point a shadow ray may look: the far
/// end is pulled in by this fraction (pbrt's `ShadowEpsilon`), so that a
/// light lying on a surface (an area light's sample, later) is not hidden
/// by that surface itself.
pub const SHADOW_EPSILON: f64 = 1e-4;

/// A shadow ray from a hit towards `target`: its origin (offset as
/// [`offset_ray_origin`] does, to the target's side of the geometric
/// surface), its unit direction, and how far along it an occluder counts:
/// the distance to `target` less [`SHADOW_EPSILON`] of it.
pub fn shadow_ray_to(p: DVec3, p_error: DVec3, n_geo: DVec3, target: DVec3) -> (DVec3, DVec3, f64) {
    let origin = offset_ray_origin(p, p_error, n_geo, target - p);
    let to = target - origin;
    let dist = to.length();
    (origin, to / dist, dist * (1.0 - SHADOW_EPSILON))
}

/// A point and its error bound moved by an affine matrix (pbrt-v4's
/// `Transform::operator()(Point3fi)`): the error already there grows by
/// the matrix's absolute value, and the product itself adds rounding of
/// γ₃ times the magnitudes it sums.
pub fn transform_point_error(m: &DMat4, p: DVec3, p_error: DVec3) -> (DVec3, DVec3) {
    let abs = |v: glam::DVec4| v.abs().truncate();
    let (c0, c1, c2, c3) = (abs(m.x_axis), abs(m.y_axis), abs(m.z_axis), abs(m.w_axis));
    let mag = c0 * p.x.abs() + c1 * p.y.abs() + c2 * p.z.abs() + c3;
    let carried = c0 * p_error.x + c1 * p_error.y + c2 * p_error.z;
    let err = (gamma(3) + 1.0) * carried + gamma(3) * mag;
    (m.transform_point3(p), err)
}

/// A shading normal that a mirror reflection may use: `ns` itself, unless
/// the ray it reflects would go below the geometric surface (or closer to
/// it than a small threshold), in which case `ns` is tilted towards `ng`
/// just enough to lift the reflection to that threshold. This is Cycles'
/// rule (`ensure_valid_specular_reflection`): the reflection may always be
/// at least as shallow as the incoming ray, and never below the surface.
///
/// `ng`: unit geometric normal on the viewer's side; `wo`: unit direction
/// towards the viewer (`wo·ng ≥ 0`); `ns`: unit shading normal.
pub fn valid_reflection_normal(ng: DVec3, wo: DVec3, ns: DVec3) -> DVec3 {
    let iz = wo.dot(ng);
    // No separate shading normal (the common case): the reflection is as
    // far above the surface as the view, r·ng = iz(2|n|² − 1) ≈ iz, and the
    // test below keeps ns. Its rounding (a few ulp of 1) could only matter
    // for iz within ~1e-15 of zero, which takes the full route.
    if ns == ng && iz > 1e-12 {
        return ns;
    }
    let r = 2.0 * ns.dot(wo) * ns - wo;
    let threshold = (0.9 * iz).min(0.01);
    if ng.dot(r) >= threshold {
        return ns;
    }
    // A frame with ng as z and ns in the x-z plane: find the tilt of ns
    // that makes the reflection's z exactly the threshold.
    let x = (ns - ns.dot(ng) * ng).try_normalize().unwrap_or(ns);
    let ix = wo.dot(x);
    let a = ix * ix + iz * iz;
    let b = 2.0 * (a + iz * threshold);
    let c = (threshold + iz) * (threshold + iz);
    let root = (b * b - 4.0 * a * c).max(0.0).sqrt();
    let nz2 = if ix < 0.0 {
        0.25 * (b + root) / a
    } else {
        0.25 * (b - root) / a
    };
    let nx = (1.0 - nz2).max(0.0).sqrt();
    let nz = nz2.max(0.0).sqrt();
    nx * x + nz * ng
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every x within the shortcut's reach gives the factor that the
    /// square root and division give, and just past it the full route
    /// takes over.
    #[test]
    fn near_one_the_reciprocal_root_follows_from_the_bits() {
        let one = 1.0f64.to_bits() as i64;
        let reach = 1i64 << 20;
        for d in -reach - 2..reach + 2 {
            let x = f64::from_bits((one + d) as u64);
            match recip_sqrt_near_one(x) {
                Some(f) => assert_eq!(f, 1.0 / x.sqrt(), "d {d}"),
                None => assert!(d.abs() >= reach, "d {d}"),
            }
        }
        assert_eq!(recip_sqrt_near_one(f64::NAN), None);
        assert_eq!(recip_sqrt_near_one(0.0), None);
    }

    /// Whole vectors: unit normals as shapes make them (normalised, or
    /// scaled and divided back), far from unit, tiny, zero and not finite
    /// all come out as `normalize_or_zero` gives them, to the bit.
    #[test]
    fn a_near_unit_vector_normalises_as_glam_does() {
        let same = |v: DVec3| {
            let (got, want) = (normalize_near_unit(v), v.normalize_or_zero());
            assert_eq!(
                got.to_array().map(f64::to_bits),
                want.to_array().map(f64::to_bits),
                "{v}"
            );
        };
        let mut next = crate::shapes::testing::numbers(0x2545_f491_4f6c_dd1d);
        let mut near = 0;
        for _ in 0..200_000 {
            let raw = DVec3::new(next(), next(), next());
            let r = 0.1 + next().abs() * 10.0;
            let unit = raw.normalize_or_zero();
            for v in [raw, unit, unit * r / r, raw * 1e-9] {
                near += usize::from(recip_sqrt_near_one(v.length_squared()).is_some());
                same(v);
            }
        }
        // The unit ones took the shortcut.
        assert!(near >= 400_000, "{near}");
        for v in [DVec3::Y, -DVec3::X, DVec3::ZERO, DVec3::splat(f64::NAN)] {
            same(v);
        }
        same(DVec3::new(f64::INFINITY, 0.0, 0.0));
        // And `renormalize` as glam's `normalize`, zero (NaN) included.
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        let tilted = DVec3::new(0.3, -0.5, 0.7).normalize();
        for v in [
            DVec3::new(1.0, 2e-8, 0.0),
            tilted,
            tilted * (1.0 + 4e-16),
            DVec3::new(3.0, 4.0, 0.0),
            DVec3::ZERO,
        ] {
            assert_eq!(bits(renormalize(v)), bits(v.normalize()), "{v}");
        }
        // Within reach and not exactly unit: the factor is not 1.
        assert_ne!(renormalize(DVec3::new(1.0, 2e-8, 0.0)).x, 1.0);
    }
    use crate::render::material::mirror::reflect;

    #[test]
    fn ulp_away_steps_exactly_one_ulp_between_normal_numbers() {
        for x in [1.0, -1.0, 3.5e-300, -7.25e300, f64::MIN_POSITIVE * 4.0] {
            assert_eq!(ulp_away(x, 1.0), x.next_up(), "{x}");
            assert_eq!(ulp_away(x, -0.5), x.next_down(), "{x}");
            assert_eq!(ulp_away(x, 0.0), x, "{x}");
        }
        // Down onto the smallest normal number is a normal step, kept: not
        // a jump to 0 (that is only for results below it).
        let above = f64::MIN_POSITIVE.next_up();
        assert_eq!(ulp_away(above, -1.0), f64::MIN_POSITIVE);
        assert_eq!(ulp_away(-above, 1.0), -f64::MIN_POSITIVE);
    }

    #[test]
    fn offset_never_lands_on_a_subnormal() {
        // A point on y = 0 with no error in y: the step is to the smallest
        // normal number, not to 5e-324, and still to the side asked for.
        let p = DVec3::new(3.0, 0.0, -2.0);
        let up = offset_ray_origin(p, DVec3::ZERO, DVec3::Y, DVec3::Y);
        assert_eq!(up.y, f64::MIN_POSITIVE);
        let down = offset_ray_origin(p, DVec3::ZERO, DVec3::Y, -DVec3::Y);
        assert_eq!(down.y, -f64::MIN_POSITIVE);
        // From just below zero, stepping up: zero is above it, and normal.
        let below = DVec3::new(0.0, -f64::MIN_POSITIVE, 0.0);
        let o = offset_ray_origin(below, DVec3::ZERO, DVec3::Y, DVec3::Y);
        assert!(o.y > below.y && !o.y.is_subnormal(), "{}", o.y);
        for x in [
            0.0,
            -0.0,
            1e-310,
            -1e-310,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
        ] {
            for n in [1.0, -1.0] {
                let y = ulp_away(x, n);
                assert!(!y.is_subnormal(), "{x:e} along {n}: {y:e}");
                assert!(
                    if n > 0.0 { y > x } else { y < x },
                    "{x:e} along {n}: {y:e}"
                );
            }
        }
    }

    #[test]
    fn offset_from_a_unit_normal_is_the_same_to_the_bit() {
        let mut s = 7u64;
        let mut rnd = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 4.0
        };
        for _ in 0..2000 {
            let p = DVec3::new(rnd() * 1e3, rnd(), rnd() * 1e-3);
            let err = DVec3::new(rnd().abs(), rnd().abs(), rnd().abs()) * 1e-12;
            let n = DVec3::new(rnd(), rnd(), rnd());
            let d = DVec3::new(rnd(), rnd(), rnd());
            let a = offset_ray_origin(p, err, n, d);
            let b = offset_along_unit(p, err, n.normalize_or_zero(), d);
            assert_eq!(
                a.to_array().map(f64::to_bits),
                b.to_array().map(f64::to_bits)
            );
            assert_ne!(a, p, "the point must move");
            // Towards the normal's own side (a shading point's lift): the
            // side test is never needed, whatever the normal's length,
            // and the other side is another point.
            for n in [n, n * 1e-9, n * 1e9, n.normalize()] {
                let unit = normalize_near_unit(n);
                let along = offset_along_unit(p, err, unit, n);
                let towards = offset_towards(p, err, unit);
                assert_eq!(
                    along.to_array().map(f64::to_bits),
                    towards.to_array().map(f64::to_bits)
                );
                assert_ne!(towards, offset_towards(p, err, -unit));
            }
        }
    }

    #[test]
    fn offset_goes_to_the_side_of_the_direction_and_past_the_error() {
        let p = DVec3::new(1e6, 2.0, -3.0);
        let err = DVec3::splat(1e-9);
        let n = DVec3::new(0.0, 2.0, 0.0);
        let up = offset_ray_origin(p, err, n, DVec3::new(0.3, 1.0, 0.0));
        let down = offset_ray_origin(p, err, n, DVec3::new(0.3, -1.0, 0.0));
        assert!(up.y >= p.y + 1e-9 && up.y < p.y + 2e-9, "{up:?}");
        assert!(down.y <= p.y - 1e-9 && down.y > p.y - 2e-9, "{down:?}");
        // Along a normal with no error the point still moves by an ulp.
        let tight = offset_ray_origin(p, DVec3::ZERO, n, DVec3::Y);
        assert!(tight.y > p.y && tight.x == p.x);
    }

    #[test]
    fn shadow_ray_stops_short_of_its_target() {
        let (o, d, t_max) = shadow_ray_to(DVec3::ZERO, DVec3::ZERO, DVec3::Y, DVec3::Y * 10.0);
        assert!(o.y > 0.0 && (d - DVec3::Y).length() < 1e-12);
        assert!(t_max < 10.0 && t_max > 10.0 * (1.0 - 2.0 * SHADOW_EPSILON));
    }

    #[test]
    fn transformed_error_bounds_the_difference() {
        let m = DMat4::from_scale_rotation_translation(
            DVec3::new(3.0, 0.5, 2.0),
            glam::DQuat::from_rotation_y(0.7),
            DVec3::new(1e5, -2.0, 7.0),
        );
        let p = DVec3::new(0.3, -1.7, 2.2);
        let (q, err) = transform_point_error(&m, p, DVec3::ZERO);
        // The exact image, by a longer route, differs by less than the bound.
        let exact = m.x_axis.truncate() * p.x
            + m.y_axis.truncate() * p.y
            + m.z_axis.truncate() * p.z
            + m.w_axis.truncate();
        assert!(((q - exact).abs() - err).max_element() <= 0.0);
        assert!(err.max_element() < 1e-9 && err.max_element() > 0.0);
    }

    #[test]
    fn reflection_below_the_surface_is_bent_back() {
        let ng = DVec3::Z;
        // A shading normal tilted far from ng; a grazing view from the side
        // it tilts away from reflects below the surface.
        let ns = DVec3::new(0.8, 0.0, 0.6);
        let wo = DVec3::new(-0.9, 0.0, 0.2).normalize();
        assert!(reflect(-wo, ns).dot(ng) < 0.0);
        let fixed = valid_reflection_normal(ng, wo, ns);
        assert!((fixed.length() - 1.0).abs() < 1e-12);
        let r = reflect(-wo, fixed);
        let threshold = (0.9 * wo.dot(ng)).min(0.01);
        assert!((r.dot(ng) - threshold).abs() < 1e-9, "{r:?}");
        // A reflection already above the surface keeps its normal.
        let easy = DVec3::new(0.0, 0.0, 1.0);
        assert_eq!(valid_reflection_normal(ng, wo, easy), easy);
    }

    /// A small deterministic generator for the property tests below.
    fn lcg(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn gamma_is_n_u_over_one_less_n_u() {
        // Higham's γₙ = nu/(1 − nu) with u = 2⁻⁵³: strictly above nu, and
        // nu recovered as γ/(1 + γ).
        let u = 2f64.powi(-53);
        assert_eq!(gamma(0), 0.0);
        for n in [1u32, 2, 3, 5, 16, 160] {
            let nu = n as f64 * u;
            let g = gamma(n);
            assert!(g > nu, "γ{n} = {g:e} not above {nu:e}");
            assert!((g - nu / (1.0 - nu)).abs() <= nu * 1e-15, "γ{n} = {g:e}");
            assert!((g / (1.0 + g) - nu).abs() <= nu * 1e-15, "γ{n}");
        }
        assert!(gamma(4) > gamma(3));
    }

    #[test]
    fn a_shadow_ray_from_anywhere_reaches_just_short_of_its_target() {
        let mut r = lcg(3);
        for _ in 0..500 {
            let mut v = |k: f64| DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * k;
            let p = v(20.0);
            let n = v(2.0);
            let target = p + v(30.0);
            let err = v(1e-9).abs();
            let (o, d, reach) = shadow_ray_to(p, err, n, target);
            // The origin is the offset point, on the target's side.
            assert_eq!(o, offset_ray_origin(p, err, n, target - p));
            assert!((o - p).length() < 1e-6);
            assert!((o - p).dot(n) * (target - p).dot(n) >= 0.0);
            // A unit direction that reaches the target at (nearly) reach/(1 − ε).
            assert!((d.length() - 1.0).abs() < 1e-12);
            let dist = (target - o).length();
            assert!((reach - dist * (1.0 - SHADOW_EPSILON)).abs() < 1e-9 * dist.max(1.0));
            assert!((o + d * dist - target).length() < 1e-9 * dist.max(1.0));
        }
    }

    #[test]
    fn the_transformed_error_is_pbrts_bound_and_holds_the_moved_box() {
        let mut r = lcg(11);
        for _ in 0..300 {
            let mut v = |k: f64| DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * k;
            let m = DMat4::from_cols(
                v(4.0).extend(0.0),
                v(4.0).extend(0.0),
                v(4.0).extend(0.0),
                v(200.0).extend(1.0),
            );
            let p = v(10.0);
            let e = v(1e-6).abs();
            let (q, err) = transform_point_error(&m, p, e);
            assert_eq!(q, m.transform_point3(p));
            // pbrt-v4's bound, summed here entry by entry:
            // (1 + γ₃) Σⱼ |m_ij| eⱼ + γ₃ (Σⱼ |m_ij| |pⱼ| + |t_i|).
            let g = gamma(3);
            for i in 0..3 {
                let (mut carried, mut mag) = (0.0, m.col(3)[i].abs());
                for j in 0..3 {
                    carried += m.col(j)[i].abs() * e[j];
                    mag += m.col(j)[i].abs() * p[j].abs();
                }
                let want = (1.0 + g) * carried + g * mag;
                assert!(
                    (err[i] - want).abs() <= want * 1e-12,
                    "{i}: {} vs {want}",
                    err[i]
                );
            }
            // Every corner of the error box lands inside the moved box.
            for k in 0..8 {
                let s = DVec3::new(
                    if k & 1 == 0 { -1.0 } else { 1.0 },
                    if k & 2 == 0 { -1.0 } else { 1.0 },
                    if k & 4 == 0 { -1.0 } else { 1.0 },
                );
                let c = m.transform_point3(p + s * e);
                assert!(((c - q).abs() - err).max_element() <= 0.0, "corner {k}");
            }
        }
    }

    #[test]
    fn a_valid_reflection_stays_above_the_surface_by_the_threshold() {
        let mut r = lcg(5);
        let (mut kept, mut tilted) = (0, 0);
        let (mut toward, mut away) = (0, 0);
        for _ in 0..4000 {
            let mut v = || DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5);
            let ng = v().normalize();
            let wo = {
                let w = v().normalize();
                if w.dot(ng) < 0.0 { -w } else { w }
            };
            let ns = {
                let s = (ng + v() * 1.6).normalize();
                if s.dot(ng) < 0.05 { continue } else { s }
            };
            let iz = wo.dot(ng);
            if iz < 1e-3 {
                continue;
            }
            let threshold = (0.9 * iz).min(0.01);
            let fixed = valid_reflection_normal(ng, wo, ns);
            assert!((fixed.length() - 1.0).abs() < 1e-9);
            let before = reflect(-wo, ns).dot(ng);
            let after = reflect(-wo, fixed).dot(ng);
            if before >= threshold {
                assert_eq!(fixed, ns);
                kept += 1;
                continue;
            }
            tilted += 1;
            // Lifted exactly to the threshold, by a normal between ns and
            // ng (in their plane, closer to ng).
            assert!((after - threshold).abs() < 1e-7, "{after} vs {threshold}");
            assert!(fixed.dot(ns.cross(ng)).abs() < 1e-9);
            assert!(fixed.dot(ng) >= ns.dot(ng) - 1e-12);
            let x = (ns - ns.dot(ng) * ng).normalize();
            assert!(fixed.dot(x) >= -1e-9, "tilted past ng");
            if wo.dot(x) < 0.0 {
                toward += 1
            } else {
                away += 1
            }
        }
        assert!(kept > 100 && tilted > 100, "{kept} kept, {tilted} tilted");
        assert!(toward > 20 && away > 20, "{toward} / {away}");
        // No shading normal of its own: ng itself, however grazing.
        let ng = DVec3::new(0.0, 0.6, 0.8);
        for wo in [
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.3, 0.8, 0.6).normalize(),
        ] {
            let wo = (wo + ng * 1e-9).normalize();
            assert_eq!(valid_reflection_normal(ng, wo, ng), ng);
        }
    }
}
