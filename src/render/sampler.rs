//! Samplers: where a pixel's samples fall, where they cross the lens, and
//! every other random number a path needs.
//!
//! Each number is a pure function of (pixel, sample index, dimension, seed)
//! (a hash, no state carried between pixels), so a picture is the same for
//! any number of threads and a region renders exactly the full picture's
//! pixels. Dimensions 0–1 place the sample in the pixel, 2–3 on the lens,
//! and a path draws the rest in order from [`SampleStream`].

use crate::scene::{MAX_SAMPLES, SamplerKind};

/// The first dimension a path's own random numbers use.
const PATH_DIMS: u32 = 4;

/// A 64-bit mix (SplitMix64's finaliser): every input bit reaches every
/// output bit.
const fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The per-column and per-row key offsets of the multi-jittered sampler,
/// `mix(1 + i)` and `mix(0x1_0000 + j)`: the same for every pixel, so
/// worked out at compile time rather than twice per column per pattern.
const COLUMN_KEYS: [u64; MAX_SAMPLES as usize] = key_table(1);
const ROW_KEYS: [u64; MAX_SAMPLES as usize] = key_table(0x1_0000);

const fn key_table(base: u64) -> [u64; MAX_SAMPLES as usize] {
    let mut t = [0; MAX_SAMPLES as usize];
    let mut i = 0;
    while i < t.len() {
        t[i] = mix(base + i as u64);
        i += 1;
    }
    t
}

/// Which pixel a number belongs to, in the full picture's coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pixel {
    pub x: u32,
    pub y: u32,
}

/// The hash of (pixel, seed) that every number of one pixel starts from:
/// worked out once per pixel, not once per number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelKey(u64);

impl PixelKey {
    pub fn new(p: Pixel, seed: u64) -> PixelKey {
        PixelKey(mix(
            mix(seed ^ 0x9e37_79b9_7f4a_7c15) ^ ((p.x as u64) << 32 | p.y as u64)
        ))
    }

    /// The 64 hashed bits for (sample, dimension).
    #[inline]
    fn bits(self, sample: u32, dim: u32) -> u64 {
        mix(self.input(sample, dim))
    }

    /// What [`PixelKey::bits`] mixes.
    #[inline]
    fn input(self, sample: u32, dim: u32) -> u64 {
        self.0 ^ ((sample as u64) << 32 | dim as u64)
    }

    /// [`uniform`].
    #[inline]
    pub fn uniform(self, sample: u32, dim: u32) -> f64 {
        (self.bits(sample, dim) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Two uniform numbers in [0, 1) from one hash (32 bits each: plenty
    /// for a position inside a pixel or on a lens, and half the hashing).
    #[inline]
    fn uniform_pair(self, sample: u32, dim: u32) -> (f64, f64) {
        pair(self.bits(sample, dim))
    }
}

/// [`PixelKey::uniform_pair`] of hashed bits `h`.
#[inline]
fn pair(h: u64) -> (f64, f64) {
    const SCALE: f64 = 1.0 / (1u64 << 32) as f64;
    ((h >> 32) as f64 * SCALE, (h & 0xffff_ffff) as f64 * SCALE)
}

/// A uniform number in [0, 1) for (pixel, sample, dimension, seed).
pub fn uniform(p: Pixel, sample: u32, dim: u32, seed: u64) -> f64 {
    PixelKey::new(p, seed).uniform(sample, dim)
}

/// Fills `p` with a random permutation of 0..p.len() for one key, by
/// Fisher–Yates on hashed numbers.
#[cfg(test)]
fn permutation(p: &mut [u16], key: u64) {
    let mut h: Vec<u64> = (1..p.len()).rev().map(|i| draw_input(key, i)).collect();
    mix_all(&mut h);
    shuffle(p, &h);
}

/// What is mixed for the Fisher–Yates draw that picks p[i]'s partner.
#[inline]
fn draw_input(key: u64, i: usize) -> u64 {
    key ^ (i as u64).wrapping_mul(0x2545_f491_4f6c_dd1d)
}

/// Fills `p` with the permutation of 0..p.len() that Fisher–Yates makes
/// from `draws` (mixed [`draw_input`]s for i = len − 1 down to 1); returns
/// the draws left over.
#[inline]
fn shuffle<'d>(p: &mut [u16], draws: &'d [u64]) -> &'d [u64] {
    for (i, v) in p.iter_mut().enumerate() {
        *v = i as u16;
    }
    let used = p.len().saturating_sub(1);
    let (mine, rest) = draws.split_at(used);
    for (i, &r) in (1..p.len()).rev().zip(mine) {
        // An index in 0..=i from the high 32 bits, without a division.
        let j = (((r >> 32) * (i as u64 + 1)) >> 32) as usize;
        // j ≤ i already; the `min` says so to the compiler, which then drops
        // a bounds check from this, the sampler's hottest loop.
        p.swap(i, j.min(i));
    }
    rest
}

/// `mix` of every element, in place: the AVX-512 lanes multiply eight
/// 64-bit numbers at once where the CPU has them (AVX2 has no 64-bit
/// multiply), else one after another. The same bits either way.
fn mix_all(xs: &mut [u64]) {
    #[cfg(target_arch = "x86_64")]
    if avx512_mix_available() {
        // SAFETY: the CPU has the features `mix_all_avx512` is built for.
        return unsafe { mix_all_avx512(xs) };
    }
    mix_all_scalar(xs);
}

/// Whether the CPU has what [`mix_all_avx512`] is built for.
#[cfg(target_arch = "x86_64")]
fn avx512_mix_available() -> bool {
    std::arch::is_x86_feature_detected!("avx512dq")
        && std::arch::is_x86_feature_detected!("avx512vl")
}

#[inline(always)]
fn mix_all_scalar(xs: &mut [u64]) {
    for x in xs {
        *x = mix(*x);
    }
}

/// [`mix_all_scalar`] compiled for AVX-512 (inlined here, the compiler
/// vectorises it with the 64-bit multiply).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512dq,avx512vl")]
unsafe fn mix_all_avx512(xs: &mut [u64]) {
    mix_all_scalar(xs);
}

/// Division by a sample count n: a multiplication by 1/n when n is a
/// power of two (1/n is then exact, and so is the product: the same bits
/// as the quotient), else a true division. A pattern's points divide by n
/// and m twice each, and for the common 2, 4, 8 and 16 the divider was
/// the multi-jittered pattern's hottest spot.
#[derive(Clone, Copy, Debug)]
struct Divisor {
    n: f64,
    inverse: f64,
    exact: bool,
}

impl Divisor {
    fn new(n: u32) -> Divisor {
        Divisor {
            n: n as f64,
            inverse: 1.0 / n as f64,
            exact: n.is_power_of_two(),
        }
    }

    /// x/n when n is a power of two.
    #[inline(always)]
    fn times_inverse(self, x: f64) -> f64 {
        x * self.inverse
    }
}

/// The n × m points of one pixel (or one lens) in [0, 1)²: n columns, m
/// rows.
#[derive(Clone, Copy, Debug)]
pub struct PixelSampler {
    pub kind: SamplerKind,
    /// Samples per row (columns).
    pub n: u32,
    /// Rows of samples (`n` for a square grid).
    pub rows: u32,
    pub seed: u64,
}

impl PixelSampler {
    /// An n × n grid.
    pub fn square(kind: SamplerKind, n: u32, seed: u64) -> PixelSampler {
        PixelSampler {
            kind,
            n,
            rows: n,
            seed,
        }
    }

    pub fn count(&self) -> u32 {
        self.n.clamp(1, MAX_SAMPLES) * self.rows.clamp(1, MAX_SAMPLES)
    }

    /// [`PixelSampler::pattern_with`] with a scratch buffer of its own.
    #[cfg(test)]
    pub fn pattern(&self, pixel: Pixel, dim: u32, out: &mut Vec<(f64, f64)>) {
        self.pattern_with(pixel, dim, out, &mut Vec::new());
    }

    /// Writes the n × m points for `pixel` from dimensions `dim`, `dim + 1`
    /// into `out`, indexed by sample. Regular points are the cell centres
    /// in row order (the 2017 grid). `hashes` is scratch space, kept by
    /// the caller from pixel to pixel.
    pub fn pattern_with(
        &self,
        pixel: Pixel,
        dim: u32,
        out: &mut Vec<(f64, f64)>,
        hashes: &mut Vec<u64>,
    ) {
        out.clear();
        let n = self.n.clamp(1, MAX_SAMPLES);
        let m = self.rows.clamp(1, MAX_SAMPLES);
        if n == 1 && m == 1 && self.kind == SamplerKind::Regular {
            // The 2017 pixel centre, without the hashing set up below:
            // every row of a one-sample picture comes through here.
            out.push((0.5, 0.5));
            return;
        }
        let (nf, mf) = (n as f64, m as f64);
        let key = PixelKey::new(pixel, self.seed);
        let r = |s: u32| key.uniform_pair(s, dim);
        match self.kind {
            SamplerKind::Regular => {
                for j in 0..m {
                    for i in 0..n {
                        out.push(((i as f64 + 0.5) / nf, (j as f64 + 0.5) / mf));
                    }
                }
            }
            SamplerKind::Random => out.extend((0..n * m).map(r)),
            SamplerKind::Jittered => {
                for j in 0..m {
                    for i in 0..n {
                        let (a, b) = r(j * n + i);
                        out.push(((i as f64 + a) / nf, (j as f64 + b) / mf));
                    }
                }
            }
            SamplerKind::MultiJittered => self.multijittered(pixel, dim, (n, m), key, out, hashes),
        }
    }

    /// Cell (i, j) of the n columns and m rows takes fine column σ_i(j)
    /// of the m inside its column i and fine row τ_j(i) of the n inside
    /// its row j: with a permutation per column and per row every fine
    /// column and row of the nm × nm grid holds exactly one point. The
    /// points are then shuffled, so that sample k's pixel and lens points
    /// are not paired by grid position.
    ///
    /// Every hash the pattern needs (the Fisher–Yates draws of its
    /// 1 + n + m permutations, then one per point) is independent of the
    /// others, so all are gathered first and mixed in one pass
    /// ([`mix_all`], eight at a time where the CPU can); only the swaps
    /// and the sums are left in order. The numbers are the same as one
    /// `mix` after another (sampler_tests.rs holds them to that).
    fn multijittered(
        &self,
        pixel: Pixel,
        dim: u32,
        (n, m): (u32, u32),
        key: PixelKey,
        out: &mut Vec<(f64, f64)>,
        hashes: &mut Vec<u64>,
    ) {
        let (nf, mf) = (Divisor::new(n), Divisor::new(m));
        let (nu, mu) = (n as usize, m as usize);
        let nm = nu * mu;
        let mkey = mix(self.seed ^ mix(((pixel.x as u64) << 32) | pixel.y as u64) ^ dim as u64);
        let h = hashes;
        h.clear();
        let draws = |key: u64, count: usize| (1..count).rev().map(move |i| draw_input(key, i));
        h.extend(draws(mkey ^ 0x5bd1_e995, nm));
        for row_key in &ROW_KEYS[..mu] {
            h.extend(draws(mkey ^ row_key, nu));
        }
        for column_key in &COLUMN_KEYS[..nu] {
            h.extend(draws(mkey ^ column_key, mu));
        }
        let points = h.len();
        h.extend((0..nm as u32).map(|s| key.input(s, dim)));
        mix_all(h);
        let (mut draws, pairs) = h.split_at(points);
        let mut order = [0u16; (MAX_SAMPLES * MAX_SAMPLES) as usize];
        draws = shuffle(&mut order[..nm], draws);
        let mut taus = [[0u16; MAX_SAMPLES as usize]; MAX_SAMPLES as usize];
        for tau in &mut taus[..mu] {
            draws = shuffle(&mut tau[..nu], draws);
        }
        let mut sigmas = [[0u16; MAX_SAMPLES as usize]; MAX_SAMPLES as usize];
        for sigma in &mut sigmas[..nu] {
            draws = shuffle(&mut sigma[..mu], draws);
        }
        out.resize(nm, (0.0, 0.0));
        // The choice of divide made once, outside the loop: left inside,
        // the compiler works out both and picks one per point.
        #[inline(always)]
        fn place(
            out: &mut [(f64, f64)],
            (sigmas, taus): (
                &[[u16; MAX_SAMPLES as usize]],
                &[[u16; MAX_SAMPLES as usize]],
            ),
            order: &[u16],
            pairs: &[u64],
            (nf, mf): (Divisor, Divisor),
            div: impl Fn(Divisor, f64) -> f64,
        ) {
            let nu = sigmas.len();
            for (i, sigma) in sigmas.iter().enumerate() {
                for (j, tau) in taus.iter().enumerate() {
                    let s = j * nu + i;
                    let (a, b) = pair(pairs[s]);
                    let x = div(nf, i as f64 + div(mf, sigma[j] as f64 + a));
                    let y = div(mf, j as f64 + div(nf, tau[i] as f64 + b));
                    out[order[s] as usize] = (x, y);
                }
            }
        }
        let cells = (&sigmas[..nu], &taus[..mu]);
        if nf.exact && mf.exact {
            place(out, cells, &order, pairs, (nf, mf), Divisor::times_inverse);
        } else {
            place(out, cells, &order, pairs, (nf, mf), |d, x| x / d.n);
        }
    }
}

/// The random numbers one path of one sample draws, in order.
#[derive(Clone, Debug)]
pub struct SampleStream {
    key: PixelKey,
    sample: u32,
    dim: u32,
}

impl SampleStream {
    pub fn new(key: PixelKey, sample: u32) -> SampleStream {
        SampleStream {
            key,
            sample,
            dim: PATH_DIMS,
        }
    }

    pub fn next1(&mut self) -> f64 {
        let u = self.key.uniform(self.sample, self.dim);
        self.dim += 1;
        u
    }

    pub fn next2(&mut self) -> (f64, f64) {
        (self.next1(), self.next1())
    }
}

/// Square → unit disc, Shirley and Chiu's concentric map (keeps strata
/// compact, unlike r = √a).
#[inline(always)]
pub fn concentric_disc((a, b): (f64, f64)) -> (f64, f64) {
    let (x, y) = (2.0 * a - 1.0, 2.0 * b - 1.0);
    if x == 0.0 && y == 0.0 {
        return (0.0, 0.0);
    }
    // φ = π/4·(y/x) in the wedges about the x axis, π/2 − π/4·(x/y) in
    // those about y: both read through one angle θ in [−π/4, π/4], where
    // cos(π/2 − θ) = sin θ.
    if x.abs() > y.abs() {
        let (s, c) = sin_cos_octant(std::f64::consts::FRAC_PI_4 * (y / x));
        (x * c, x * s)
    } else {
        let (s, c) = sin_cos_octant(std::f64::consts::FRAC_PI_4 * (x / y));
        (y * s, y * c)
    }
}

/// The minimax coefficients of [`sin_cos_octant`]'s odd (sine) and even
/// (cosine) tails.
// The coefficients are written as fdlibm publishes them, digits beyond
// f64's included, so that they can be checked against the source.
#[allow(clippy::excessive_precision)]
const SIN_TAIL: [f64; 6] = [
    -1.666_666_666_666_663_243_48e-1,
    8.333_333_333_322_489_461_24e-3,
    -1.984_126_982_985_794_931_34e-4,
    2.755_731_370_707_006_767_89e-6,
    -2.505_076_025_340_686_341_95e-8,
    1.589_690_995_211_550_102_21e-10,
];
#[allow(clippy::excessive_precision)]
const COS_TAIL: [f64; 6] = [
    4.166_666_666_666_660_190_37e-2,
    -1.388_888_888_887_410_957_49e-3,
    2.480_158_728_947_672_941_78e-5,
    -2.755_731_435_139_066_330_35e-7,
    2.087_572_321_298_174_827_90e-9,
    -1.135_964_755_778_819_482_65e-11,
];

/// (sin θ, cos θ) for |θ| ≤ π/4, within an ulp or so: the minimax
/// polynomials of fdlibm's `__kernel_sin` and `__kernel_cos` (FreeBSD's
/// k_sin.c and k_cos.c), which need no range reduction on this interval.
/// Every lens sample of a depth-of-field picture comes through here, and
/// libm's general `sincos` (reduction, quadrant tests) took a tenth of
/// such a render.
#[inline]
fn sin_cos_octant(t: f64) -> (f64, f64) {
    let z = t * t;
    let (s, c) = (SIN_TAIL, COS_TAIL);
    let rs = s[1] + z * (s[2] + z * (s[3] + z * (s[4] + z * s[5])));
    let sin = t + (z * t) * (s[0] + z * rs);
    let rc = z * (c[0] + z * (c[1] + z * (c[2] + z * (c[3] + z * (c[4] + z * c[5])))));
    // 1 − z/2 rounded, then what that rounding lost, then the tail.
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let cos = w + (((1.0 - w) - hz) + z * rc);
    (sin, cos)
}

/// [`concentric_disc`] of four squares' points (a lane each): the two
/// wedges' branches become a blend, the same operations in the same order
/// (so each lane has the scalar map's bits).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
pub(crate) fn concentric_disc4(
    a: std::arch::x86_64::__m256d,
    b: std::arch::x86_64::__m256d,
) -> [std::arch::x86_64::__m256d; 2] {
    use std::arch::x86_64::*;
    let (two, one) = (_mm256_set1_pd(2.0), _mm256_set1_pd(1.0));
    let x = _mm256_sub_pd(_mm256_mul_pd(two, a), one);
    let y = _mm256_sub_pd(_mm256_mul_pd(two, b), one);
    let abs = |v| _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
    let about_x = _mm256_cmp_pd::<_CMP_GT_OQ>(abs(x), abs(y));
    // About x: θ = π/4·(y/x), the point x·(cos θ, sin θ); about y:
    // θ = π/4·(x/y), the point y·(sin θ, cos θ).
    let (num, den) = (
        _mm256_blendv_pd(x, y, about_x),
        _mm256_blendv_pd(y, x, about_x),
    );
    let t = _mm256_mul_pd(
        _mm256_set1_pd(std::f64::consts::FRAC_PI_4),
        _mm256_div_pd(num, den),
    );
    let [s, c] = sin_cos_octant4(t);
    let centre = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_EQ_OQ>(x, _mm256_setzero_pd()),
        _mm256_cmp_pd::<_CMP_EQ_OQ>(y, _mm256_setzero_pd()),
    );
    let (fx, fy) = (
        _mm256_blendv_pd(s, c, about_x),
        _mm256_blendv_pd(c, s, about_x),
    );
    // The centre is (0, 0) (its θ is 0/0).
    [fx, fy].map(|f| _mm256_andnot_pd(centre, _mm256_mul_pd(den, f)))
}

/// [`sin_cos_octant`] lane by lane, in its order.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn sin_cos_octant4(t: std::arch::x86_64::__m256d) -> [std::arch::x86_64::__m256d; 2] {
    use std::arch::x86_64::*;
    let (add, sub, mul, k) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd, _mm256_set1_pd);
    // z·(c + z·(… )) from the last coefficient in, as the scalar Horner.
    let horner = |z, cs: &[f64]| {
        let (last, rest) = cs.split_last().expect("coefficients");
        rest.iter()
            .rev()
            .fold(k(*last), |acc, &c| add(k(c), mul(z, acc)))
    };
    let z = mul(t, t);
    let rs = horner(z, &SIN_TAIL[1..]);
    let sin = add(t, mul(mul(z, t), add(k(SIN_TAIL[0]), mul(z, rs))));
    let rc = mul(z, horner(z, &COS_TAIL));
    let hz = mul(k(0.5), z);
    let w = sub(k(1.0), hz);
    let cos = add(w, add(sub(sub(k(1.0), w), hz), mul(z, rc)));
    [sin, cos]
}

/// Square → direction about +z with density ∝ cos^e θ: φ = 2πa,
/// cos θ = (1 − b)^(1/(e+1)). e = 1 is the cosine (Lambert) lobe.
pub fn cos_power_lobe((a, b): (f64, f64), e: f64) -> glam::DVec3 {
    let cos_t = (1.0 - b).powf(1.0 / (e + 1.0));
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = std::f64::consts::TAU * a;
    glam::DVec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// `local` (about +z) turned to be about the unit vector `w`.
pub fn about(w: glam::DVec3, local: glam::DVec3) -> glam::DVec3 {
    let (u, v) = w.any_orthonormal_pair();
    local.x * u + local.y * v + local.z * w
}

#[cfg(test)]
#[path = "sampler_tests.rs"]
mod tests;
