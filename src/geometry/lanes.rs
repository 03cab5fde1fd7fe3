//! Four rays (or four of anything) a lane each, in AVX registers: for the
//! routes that work on a pixel's many camera rays together (the sphere's
//! and the plane's roots, the camera's rays). Each lane does exactly the
//! scalar code's operations in its order (no fused multiply-add; division
//! and square root are correctly rounded either way), so a lane's result
//! has the scalar result's bits.

use super::Ray;
use std::arch::x86_64::*;

/// Whether the CPU has AVX (asked once, then read from a cache).
pub fn available() -> bool {
    std::arch::is_x86_feature_detected!("avx")
}

/// Origins and directions, coordinate by coordinate.
pub struct Rays {
    pub ox: __m256d,
    pub oy: __m256d,
    pub oz: __m256d,
    pub dx: __m256d,
    pub dy: __m256d,
    pub dz: __m256d,
}

impl Rays {
    /// The first four of `rays` (which holds four), ray i in lane i.
    /// Callable only where AVX is enabled (the shapes' four-lane
    /// routes).
    #[target_feature(enable = "avx")]
    #[inline]
    pub fn load(rays: &[Ray]) -> Rays {
        let lane =
            |f: fn(&Ray) -> f64| _mm256_set_pd(f(&rays[3]), f(&rays[2]), f(&rays[1]), f(&rays[0]));
        Rays {
            ox: lane(|r| r.origin.x),
            oy: lane(|r| r.origin.y),
            oz: lane(|r| r.origin.z),
            dx: lane(|r| r.dir.x),
            dy: lane(|r| r.dir.y),
            dz: lane(|r| r.dir.z),
        }
    }

    /// Lane i as ray i of `out` (which holds four): [`Rays::load`]'s
    /// inverse.
    #[target_feature(enable = "avx")]
    #[inline]
    pub fn store(&self, out: &mut [Ray]) {
        let [ox, oy, oz, dx, dy, dz] =
            [self.ox, self.oy, self.oz, self.dx, self.dy, self.dz].map(|v| {
                let mut a = [0.0; 4];
                // SAFETY: four f64 (an unaligned store).
                unsafe { _mm256_storeu_pd(a.as_mut_ptr(), v) };
                a
            });
        for (i, r) in out[..4].iter_mut().enumerate() {
            *r = Ray::new(
                super::DVec3::new(ox[i], oy[i], oz[i]),
                super::DVec3::new(dx[i], dy[i], dz[i]),
            );
        }
    }
}

/// A shape's nearest roots four rays at a time, for as many whole fours
/// as `rays` holds (their count is returned): `roots(rays, limits)` gives
/// each lane's root and, as a lane mask, whether it is kept (within the
/// shape's range and short of the lane's limit, `best[i]`). A kept root
/// is written over `best[i]` and sets `won[i]`; the other lanes keep
/// theirs. The loop every four-lane [`crate::shapes::Roots`] route shares.
#[target_feature(enable = "avx")]
#[inline]
pub fn each_four(
    rays: &[Ray],
    best: &mut [f64],
    won: &mut [bool],
    mut roots: impl FnMut(&Rays, __m256d) -> (__m256d, __m256d),
) -> usize {
    let mut done = 0;
    for ((four, best), won) in rays
        .chunks_exact(4)
        .zip(best.chunks_exact_mut(4))
        .zip(won.chunks_exact_mut(4))
    {
        // SAFETY: four f64 each way (unaligned loads and stores).
        let limit = unsafe { _mm256_loadu_pd(best.as_ptr()) };
        let (t, keep) = roots(&Rays::load(four), limit);
        unsafe { _mm256_storeu_pd(best.as_mut_ptr(), _mm256_blendv_pd(limit, t, keep)) };
        let kept = _mm256_movemask_pd(keep);
        for (i, w) in won.iter_mut().enumerate() {
            *w |= kept & (1 << i) != 0;
        }
        done += 4;
    }
    done
}

/// glam's `dot` lane by lane, in its order: (x·x' + y·y') + z·z'.
#[target_feature(enable = "avx")]
#[inline]
pub fn dot(a: [__m256d; 3], b: [__m256d; 3]) -> __m256d {
    _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(a[0], b[0]), _mm256_mul_pd(a[1], b[1])),
        _mm256_mul_pd(a[2], b[2]),
    )
}
