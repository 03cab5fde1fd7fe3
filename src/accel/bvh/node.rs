//! The wide node and its box test: eight child boxes stored
//! structure-of-arrays in `f32` and tested together against one ray.
//!
//! The test is conservative: it never misses a box the exact (real
//! number) ray crosses, so the `f64` tests of the items inside decide
//! every hit, as they do under the kd-tree. Three things make it so:
//! - boxes are rounded outwards to `f32`;
//! - the ray's origin is rounded per plane the way that moves each slab's
//!   entry earlier and its exit later (up for the entry plane when the
//!   direction is positive, down for the exit, and the other way round
//!   when it is negative);
//! - what rounding is left (the subtraction, the direction's rounding to
//!   `f32`, its reciprocal and the product: four roundings, at most
//!   γ₄ ≈ 4·2⁻²⁴ relative) is covered by widening the entry and exit by
//!   [`SLACK`] of their magnitude.
//!
//! A zero direction component gives an infinite reciprocal: a plane the
//! origin lies on then gives NaN, which the `max`/`min` below ignore
//! (they return their second operand, as `maxps`/`minps` do), so the slab
//! is the whole line, which is right for a ray lying in the plane.

/// Relative widening of each box's entry and exit: 2⁻²⁰ ≈ 9.5e-7, twice
/// what four `f32` roundings (γ₄ ≈ 2.4e-7) and the widening's own
/// rounding need.
pub(super) const SLACK: f32 = 1.0 / (1u32 << 20) as f32;

/// A child slot's reference: an inner node's index, or `LEAF | first`
/// with the item count in `count`. An unused slot has an empty box.
pub(super) const LEAF: u32 = 1 << 31;

/// Eight children: boxes as `lo[axis][child]`, `hi[axis][child]`.
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub(super) struct Node8 {
    pub lo: [[f32; 8]; 3],
    pub hi: [[f32; 8]; 3],
    pub child: [u32; 8],
    pub count: [u32; 8],
}

impl Node8 {
    pub(super) fn empty() -> Node8 {
        Node8 {
            lo: [[f32::INFINITY; 8]; 3],
            hi: [[f32::NEG_INFINITY; 8]; 3],
            child: [0; 8],
            count: [0; 8],
        }
    }
}

/// `f32` just at or below `x`.
#[inline]
pub(super) fn round_down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x { f.next_down() } else { f }
}

/// `f32` just at or above `x`.
#[inline]
pub(super) fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x { f.next_up() } else { f }
}

/// A ray prepared for box tests.
#[derive(Clone, Copy, Debug)]
pub(super) struct BoxRay {
    /// Per axis: the origin rounded for the entry plane and for the exit.
    pub o_near: [f32; 3],
    pub o_far: [f32; 3],
    /// 1 / direction, in `f32` (±∞ for a zero component).
    pub inv: [f32; 3],
    /// Bit `a` set: the direction along axis `a` is negative (its sign
    /// bit is set), so the entry plane is the box's `hi`. Bits in one
    /// word, not three `bool`s: the walk reads them as one load, which a
    /// store of three bytes cannot forward to (a stall on every query).
    pub neg: u32,
}

impl BoxRay {
    /// Whether the direction along `axis` is negative.
    #[inline(always)]
    pub(super) fn is_neg(&self, axis: usize) -> bool {
        self.neg >> axis & 1 != 0
    }

    pub(super) fn new(origin: [f64; 3], dir: [f64; 3]) -> BoxRay {
        let mut r = BoxRay {
            o_near: [0.0; 3],
            o_far: [0.0; 3],
            inv: [0.0; 3],
            neg: 0,
        };
        for a in 0..3 {
            let neg = dir[a].is_sign_negative();
            let (up, down) = (round_up(origin[a]), round_down(origin[a]));
            r.neg |= (neg as u32) << a;
            // t = (plane − o)·inv: for inv ≥ 0 a larger o gives a smaller t.
            (r.o_near[a], r.o_far[a]) = if neg { (down, up) } else { (up, down) };
            r.inv[a] = 1.0 / (dir[a] as f32);
        }
        r
    }
}

/// [`BoxRay::new`] with AVX: the three axes' roundings, reciprocals and
/// signs at once. The same bits: `f32` conversion rounds to nearest
/// either way, and one step up or down is one step of the bit pattern
/// (+1 away from zero, −1 towards it; from ±0 up to the least subnormal,
/// from ±∞ in to ±`f32::MAX`), as `next_up`/`next_down` take it.
///
/// # Safety
/// The CPU must support AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(super) unsafe fn box_ray_avx(origin: [f64; 3], dir: [f64; 3]) -> BoxRay {
    use std::arch::x86_64::*;
    let o = _mm256_set_pd(0.0, origin[2], origin[1], origin[0]);
    let d = _mm256_set_pd(0.0, dir[2], dir[1], dir[0]);
    let f = _mm256_cvtpd_ps(o);
    let back = _mm256_cvtps_pd(f);
    // Lanes whose f32 lies below the origin (step up) or above (down), as
    // 4-bit masks, widened to lane masks through a table.
    let below = lane_mask(_mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(back, o)) as u32);
    let above = lane_mask(_mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(back, o)) as u32);
    let bits = _mm_castps_si128(f);
    // +1 for a positive pattern, −1 for a negative one: a step away from
    // zero.
    let away = _mm_or_si128(_mm_set1_epi32(1), _mm_srai_epi32::<31>(bits));
    let up = _mm_castsi128_ps(_mm_add_epi32(bits, away));
    let down = _mm_castsi128_ps(_mm_sub_epi32(bits, away));
    let up = _mm_blendv_ps(f, up, below);
    let down = _mm_blendv_ps(f, down, above);
    let df = _mm256_cvtpd_ps(d);
    let inv = _mm_div_ps(_mm_set1_ps(1.0), df);
    let neg = _mm256_movemask_pd(d) as u32;
    let negs = lane_mask(neg);
    // Entry plane: rounded up when the direction is positive, down when
    // it is negative; the exit the other way.
    let near = _mm_blendv_ps(up, down, negs);
    let far = _mm_blendv_ps(down, up, negs);
    let mut lanes = [[0f32; 4]; 3];
    // SAFETY: each array holds four f32; unaligned stores.
    unsafe {
        _mm_storeu_ps(lanes[0].as_mut_ptr(), near);
        _mm_storeu_ps(lanes[1].as_mut_ptr(), far);
        _mm_storeu_ps(lanes[2].as_mut_ptr(), inv);
    }
    let first3 = |l: [f32; 4]| [l[0], l[1], l[2]];
    BoxRay {
        o_near: first3(lanes[0]),
        o_far: first3(lanes[1]),
        inv: first3(lanes[2]),
        neg: neg & 7,
    }
}

/// Lane k all ones where bit k of `m` (four bits) is set.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn lane_mask(m: u32) -> std::arch::x86_64::__m128 {
    const MASKS: [[i32; 4]; 16] = {
        let mut t = [[0; 4]; 16];
        let mut m = 0;
        while m < 16 {
            let mut k = 0;
            while k < 4 {
                t[m][k] = -((m >> k & 1) as i32);
                k += 1;
            }
            m += 1;
        }
        t
    };
    // SAFETY: the row holds four i32; unaligned load (SSE2, always there).
    unsafe {
        use std::arch::x86_64::*;
        _mm_castsi128_ps(_mm_loadu_si128(MASKS[(m & 15) as usize].as_ptr().cast()))
    }
}

/// `maxps`: `a` if it is greater, else `b` (so a NaN `a` gives `b`).
#[inline(always)]
fn max_ps(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// `minps`: `a` if it is less, else `b`.
#[inline(always)]
fn min_ps(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// Which of the eight boxes the ray crosses within `[t_min, t_max]`
/// (bit k for child k) and where it enters each (widened), one lane at a
/// time. The same arithmetic as [`hits_avx2`], lane for lane, except that
/// the final widening is fused there (one rounding fewer; both stay within
/// [`SLACK`]'s margin, so both are conservative).
#[inline(always)]
pub(super) fn hits_scalar(n: &Node8, r: &BoxRay, t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
    let mut mask = 0;
    let mut near = [0f32; 8];
    for (k, near_k) in near.iter_mut().enumerate() {
        let (mut tn, mut tf) = (t_min, t_max);
        for a in 0..3 {
            let (pn, pf) = if r.is_neg(a) {
                (n.hi[a][k], n.lo[a][k])
            } else {
                (n.lo[a][k], n.hi[a][k])
            };
            tn = max_ps((pn - r.o_near[a]) * r.inv[a], tn);
            tf = min_ps((pf - r.o_far[a]) * r.inv[a], tf);
        }
        let tn = tn - tn.abs() * SLACK;
        let tf = tf + tf.abs() * SLACK;
        *near_k = tn;
        if tn <= tf {
            mask |= 1 << k;
        }
    }
    (mask, near)
}

/// [`hits_scalar`] for the eight lanes at once with AVX2.
///
/// # Safety
/// The CPU must support AVX2, FMA, BMI1 and POPCNT.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,popcnt")]
#[inline]
pub(super) unsafe fn hits_avx2(n: &Node8, r: &BoxRay, t_min: f32, t_max: f32) -> (u32, [f32; 8]) {
    use std::arch::x86_64::*;
    let mut tn = _mm256_set1_ps(t_min);
    let mut tf = _mm256_set1_ps(t_max);
    for a in 0..3 {
        let (pn, pf) = if r.is_neg(a) {
            (&n.hi[a], &n.lo[a])
        } else {
            (&n.lo[a], &n.hi[a])
        };
        // SAFETY: the arrays hold eight f32; unaligned loads.
        let (pn, pf) = unsafe { (_mm256_loadu_ps(pn.as_ptr()), _mm256_loadu_ps(pf.as_ptr())) };
        let inv = _mm256_set1_ps(r.inv[a]);
        let on = _mm256_set1_ps(r.o_near[a]);
        let of = _mm256_set1_ps(r.o_far[a]);
        tn = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(pn, on), inv), tn);
        tf = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(pf, of), inv), tf);
    }
    // |x| by clearing the sign bit; x ∓ |x|·SLACK as a fused multiply-add
    // (one rounding fewer than the scalar lane's, within SLACK's margin).
    let abs = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fff_ffff));
    let slack = _mm256_set1_ps(SLACK);
    let tn = _mm256_fnmadd_ps(_mm256_and_ps(tn, abs), slack, tn);
    let tf = _mm256_fmadd_ps(_mm256_and_ps(tf, abs), slack, tf);
    let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(tn, tf)) as u32;
    let mut near = [0f32; 8];
    // SAFETY: `near` holds eight f32.
    unsafe { _mm256_storeu_ps(near.as_mut_ptr(), tn) };
    (mask, near)
}
