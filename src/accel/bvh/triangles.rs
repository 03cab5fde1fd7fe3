//! A mesh's triangles in the wide BVH's leaf order, four to a block,
//! tested four at a time.
//!
//! The test is the watertight one every triangle uses ([`ShearedRay`]),
//! in `f64`, lane for lane the same operations in the same order (no
//! fused multiply-adds): each lane's t is bit for bit the t that
//! [`ShearedRay::triangle`] gives, so the BVH finds the same nearest hit
//! as the kd-tree and brute force, and the mesh builds its hit from the
//! same numbers. (An `f32` test would be faster still, but its t and
//! barycentrics would differ from the kd-tree's in the last bits, and
//! with them every picture.) Leaves are padded to whole blocks with
//! degenerate triangles, which the test rejects (zero determinant).

use crate::geometry::DVec3;
use crate::shapes::ShearedRay;

/// Four triangles: `v[3·corner + axis][lane]`.
#[derive(Clone, Debug)]
#[repr(C, align(32))]
pub struct Block {
    v: [[f64; 4]; 9],
}

impl Block {
    /// A block from four triangles' corners (`None`: a padding lane).
    pub fn new(tris: [Option<[DVec3; 3]>; 4]) -> Block {
        let mut v = [[0.0; 4]; 9];
        for (lane, t) in tris.iter().enumerate() {
            if let Some(t) = t {
                for c in 0..3 {
                    for a in 0..3 {
                        v[3 * c + a][lane] = t[c][a];
                    }
                }
            }
        }
        Block { v }
    }

    fn corner(&self, c: usize, lane: usize) -> DVec3 {
        DVec3::new(
            self.v[3 * c][lane],
            self.v[3 * c + 1][lane],
            self.v[3 * c + 2][lane],
        )
    }
}

/// The ray as the four-lane test reads it.
#[derive(Clone, Copy, Debug)]
pub struct LaneRay {
    sheared: ShearedRay,
    origin: [f64; 3],
    k: [usize; 3],
    s: [f64; 3],
}

impl LaneRay {
    pub fn from_ray(ray: &crate::geometry::Ray) -> LaneRay {
        Self::new(ShearedRay::new(ray))
    }

    pub(crate) fn new(sheared: ShearedRay) -> LaneRay {
        let (o, k, s) = sheared.parts();
        LaneRay {
            sheared,
            origin: o.to_array(),
            k,
            s,
        }
    }
}

/// [`hits_scalar`] or [`hits_avx2`], as `simd` says (the scalar path
/// where the CPU lacks AVX2).
#[inline]
pub fn hits(b: &Block, r: &LaneRay, t_min: f64, t_max: f64, simd: super::Simd) -> (u32, [f64; 4]) {
    #[cfg(target_arch = "x86_64")]
    if simd == super::Simd::Avx2 && super::Simd::avx2_available() {
        // SAFETY: the CPU has AVX2, FMA, BMI1 and POPCNT (checked just above).
        return unsafe { hits_avx2(b, r, t_min, t_max) };
    }
    let _ = simd;
    hits_scalar(b, r, t_min, t_max)
}

/// The lanes whose triangle the ray crosses at `t_min < t < t_max` (bit
/// per lane) and their t, one lane at a time through
/// [`ShearedRay::triangle`] itself.
#[inline(always)]
pub fn hits_scalar(b: &Block, r: &LaneRay, t_min: f64, t_max: f64) -> (u32, [f64; 4]) {
    let mut mask = 0;
    let mut ts = [0.0; 4];
    for (lane, t_lane) in ts.iter_mut().enumerate() {
        if let Some((t, _)) =
            r.sheared
                .triangle(b.corner(0, lane), b.corner(1, lane), b.corner(2, lane))
            && t > t_min
            && t < t_max
        {
            mask |= 1 << lane;
            *t_lane = t;
        }
    }
    (mask, ts)
}

/// [`hits_scalar`] for four lanes at once with AVX2: the same operations
/// as `ShearedRay::test`, in the same order.
///
/// # Safety
/// The CPU must support AVX2, FMA, BMI1 and POPCNT.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,popcnt")]
#[inline]
pub unsafe fn hits_avx2(b: &Block, r: &LaneRay, t_min: f64, t_max: f64) -> (u32, [f64; 4]) {
    use std::arch::x86_64::*;
    // SAFETY: each row holds four f64, 32-byte aligned by `Block`'s repr.
    let ld = |i: usize| unsafe { _mm256_load_pd(b.v[i].as_ptr()) };
    let [kx, ky, kz] = r.k;
    let (ox, oy, oz) = (
        _mm256_set1_pd(r.origin[kx]),
        _mm256_set1_pd(r.origin[ky]),
        _mm256_set1_pd(r.origin[kz]),
    );
    let (sx, sy, sz) = (
        _mm256_set1_pd(r.s[0]),
        _mm256_set1_pd(r.s[1]),
        _mm256_set1_pd(r.s[2]),
    );
    // Corner c moved to the ray's frame: (x, y) sheared, and z.
    let corner = |c: usize| {
        let x = _mm256_sub_pd(ld(3 * c + kx), ox);
        let y = _mm256_sub_pd(ld(3 * c + ky), oy);
        let z = _mm256_sub_pd(ld(3 * c + kz), oz);
        (
            _mm256_sub_pd(x, _mm256_mul_pd(sx, z)),
            _mm256_sub_pd(y, _mm256_mul_pd(sy, z)),
            z,
        )
    };
    let (ax, ay, az) = corner(0);
    let (bx, by, bz) = corner(1);
    let (cx, cy, cz) = corner(2);
    let u = _mm256_sub_pd(_mm256_mul_pd(cx, by), _mm256_mul_pd(cy, bx));
    let v = _mm256_sub_pd(_mm256_mul_pd(ax, cy), _mm256_mul_pd(ay, cx));
    let w = _mm256_sub_pd(_mm256_mul_pd(bx, ay), _mm256_mul_pd(by, ax));
    let zero = _mm256_setzero_pd();
    let any_neg = _mm256_or_pd(
        _mm256_or_pd(
            _mm256_cmp_pd::<_CMP_LT_OQ>(u, zero),
            _mm256_cmp_pd::<_CMP_LT_OQ>(v, zero),
        ),
        _mm256_cmp_pd::<_CMP_LT_OQ>(w, zero),
    );
    let any_pos = _mm256_or_pd(
        _mm256_or_pd(
            _mm256_cmp_pd::<_CMP_GT_OQ>(u, zero),
            _mm256_cmp_pd::<_CMP_GT_OQ>(v, zero),
        ),
        _mm256_cmp_pd::<_CMP_GT_OQ>(w, zero),
    );
    let outside = _mm256_and_pd(any_neg, any_pos);
    let det = _mm256_add_pd(_mm256_add_pd(u, v), w);
    let abs = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fff_ffff_ffff_ffff));
    let inf = _mm256_set1_pd(f64::INFINITY);
    // det ≠ 0 and finite (both false for NaN).
    let det_ok = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_NEQ_OQ>(det, zero),
        _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_and_pd(det, abs), inf),
    );
    let t_scaled = _mm256_add_pd(
        _mm256_add_pd(
            _mm256_mul_pd(u, _mm256_mul_pd(sz, az)),
            _mm256_mul_pd(v, _mm256_mul_pd(sz, bz)),
        ),
        _mm256_mul_pd(w, _mm256_mul_pd(sz, cz)),
    );
    let inv = _mm256_div_pd(_mm256_set1_pd(1.0), det);
    let t = _mm256_mul_pd(t_scaled, inv);
    let t_ok = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_GT_OQ>(t, _mm256_set1_pd(t_min)),
        _mm256_cmp_pd::<_CMP_LT_OQ>(t, _mm256_set1_pd(t_max)),
    );
    // t within (t_min, t_max) also makes it finite unless a bound is
    // infinite: check that too, as the scalar test does.
    let finite = _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_and_pd(t, abs), inf);
    let ok = _mm256_andnot_pd(outside, _mm256_and_pd(det_ok, _mm256_and_pd(t_ok, finite)));
    let mask = _mm256_movemask_pd(ok) as u32;
    let mut ts = [0.0; 4];
    // SAFETY: `ts` holds four f64.
    unsafe { _mm256_storeu_pd(ts.as_mut_ptr(), t) };
    (mask, ts)
}
