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
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
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
        mix(self.0 ^ ((sample as u64) << 32 | dim as u64))
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
        let h = self.bits(sample, dim);
        const SCALE: f64 = 1.0 / (1u64 << 32) as f64;
        ((h >> 32) as f64 * SCALE, (h & 0xffff_ffff) as f64 * SCALE)
    }
}

/// A uniform number in [0, 1) for (pixel, sample, dimension, seed).
pub fn uniform(p: Pixel, sample: u32, dim: u32, seed: u64) -> f64 {
    PixelKey::new(p, seed).uniform(sample, dim)
}

/// Fills `p` with a random permutation of 0..p.len() for one key, by
/// Fisher–Yates on hashed numbers.
fn permutation(p: &mut [u16], key: u64) {
    for (i, v) in p.iter_mut().enumerate() {
        *v = i as u16;
    }
    for i in (1..p.len()).rev() {
        let r = mix(key ^ (i as u64).wrapping_mul(0x2545_f491_4f6c_dd1d));
        // An index in 0..=i from the high 32 bits, without a division.
        let j = (((r >> 32) * (i as u64 + 1)) >> 32) as usize;
        p.swap(i, j);
    }
}

/// The n × n points of one pixel (or one lens) in [0, 1)².
#[derive(Clone, Copy, Debug)]
pub struct PixelSampler {
    pub kind: SamplerKind,
    /// Samples per side.
    pub n: u32,
    pub seed: u64,
}

impl PixelSampler {
    pub fn count(&self) -> u32 {
        self.n * self.n
    }

    /// Writes the n² points for `pixel` from dimensions `dim`, `dim + 1`
    /// into `out`, indexed by sample. Regular points are the cell centres
    /// in row order (the 2017 grid).
    pub fn pattern(&self, pixel: Pixel, dim: u32, out: &mut Vec<(f64, f64)>) {
        out.clear();
        let n = self.n.clamp(1, MAX_SAMPLES);
        let nf = n as f64;
        let key = PixelKey::new(pixel, self.seed);
        let r = |s: u32| key.uniform_pair(s, dim);
        match self.kind {
            SamplerKind::Regular => {
                for j in 0..n {
                    for i in 0..n {
                        out.push(((i as f64 + 0.5) / nf, (j as f64 + 0.5) / nf));
                    }
                }
            }
            SamplerKind::Random => out.extend((0..n * n).map(r)),
            SamplerKind::Jittered => {
                for j in 0..n {
                    for i in 0..n {
                        let (a, b) = r(j * n + i);
                        out.push(((i as f64 + a) / nf, (j as f64 + b) / nf));
                    }
                }
            }
            SamplerKind::MultiJittered => {
                // Cell (i, j) takes fine column σ_i(j) inside its column i
                // and fine row τ_j(i) inside its row j: with a permutation
                // per column and per row every fine column and row of the
                // n² × n² grid holds exactly one point.
                let key =
                    mix(self.seed ^ mix(((pixel.x as u64) << 32) | pixel.y as u64) ^ dim as u64);
                let nu = n as usize;
                let mut order = [0u16; (MAX_SAMPLES * MAX_SAMPLES) as usize];
                permutation(&mut order[..nu * nu], key ^ 0x5bd1_e995);
                out.resize(nu * nu, (0.0, 0.0));
                let mut taus = [[0u16; MAX_SAMPLES as usize]; MAX_SAMPLES as usize];
                for (j, tau) in taus.iter_mut().enumerate().take(nu) {
                    permutation(&mut tau[..nu], key ^ mix(0x1_0000 + j as u64));
                }
                let mut sigma = [0u16; MAX_SAMPLES as usize];
                for i in 0..n {
                    permutation(&mut sigma[..nu], key ^ mix(1 + i as u64));
                    for (j, tau) in taus.iter().enumerate().take(nu) {
                        let s = j as u32 * n + i;
                        let (a, b) = r(s);
                        let x = (i as f64 + (sigma[j] as f64 + a) / nf) / nf;
                        let y = (j as f64 + (tau[i as usize] as f64 + b) / nf) / nf;
                        // Shuffled, so that sample k's pixel and lens points
                        // are not paired by grid position.
                        out[order[s as usize] as usize] = (x, y);
                    }
                }
            }
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
pub fn concentric_disc((a, b): (f64, f64)) -> (f64, f64) {
    let (x, y) = (2.0 * a - 1.0, 2.0 * b - 1.0);
    if x == 0.0 && y == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if x.abs() > y.abs() {
        (x, std::f64::consts::FRAC_PI_4 * (y / x))
    } else {
        (
            y,
            std::f64::consts::FRAC_PI_2 - std::f64::consts::FRAC_PI_4 * (x / y),
        )
    };
    (r * phi.cos(), r * phi.sin())
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
mod tests {
    use super::*;

    #[test]
    fn a_pixels_key_gives_the_numbers_of_the_whole_hash() {
        // uniform(p, s, d, seed) = mix(mix(mix(seed ^ C) ^ (x, y)) ^ (s, d)),
        // written out: the key only moves the first two mixes out of the loop.
        for (x, y, s, d, seed) in [(0, 0, 0, 0, 0), (7, 3, 5, 9, 42), (999, 1, 63, 2, u64::MAX)] {
            let p = Pixel { x, y };
            let h = mix(
                mix(mix(seed ^ 0x9e37_79b9_7f4a_7c15) ^ ((x as u64) << 32 | y as u64))
                    ^ ((s as u64) << 32 | d as u64),
            );
            let key = PixelKey::new(p, seed);
            assert_eq!(key.uniform(s, d), (h >> 11) as f64 / (1u64 << 53) as f64);
            let pair = key.uniform_pair(s, d);
            assert_eq!(pair.0, (h >> 32) as f64 / (1u64 << 32) as f64);
            assert_eq!(pair.1, (h & 0xffff_ffff) as f64 / (1u64 << 32) as f64);
        }
    }

    fn points(kind: SamplerKind, n: u32, seed: u64) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        PixelSampler { kind, n, seed }.pattern(Pixel { x: 3, y: 7 }, 0, &mut out);
        out
    }

    #[test]
    fn numbers_are_pure_and_depend_on_every_input() {
        let p = Pixel { x: 10, y: 20 };
        let u = uniform(p, 3, 5, 1);
        assert_eq!(u, uniform(p, 3, 5, 1));
        assert_ne!(u, uniform(Pixel { x: 11, y: 20 }, 3, 5, 1));
        assert_ne!(u, uniform(Pixel { x: 10, y: 21 }, 3, 5, 1));
        assert_ne!(u, uniform(p, 4, 5, 1));
        assert_ne!(u, uniform(p, 3, 6, 1));
        assert_ne!(u, uniform(p, 3, 5, 2));
        // Uniform: the mean of many is 1/2 and none leaves [0, 1).
        let xs: Vec<f64> = (0..20000).map(|s| uniform(p, s, 0, 9)).collect();
        assert!(xs.iter().all(|x| (0.0..1.0).contains(x)));
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
    }

    #[test]
    fn regular_is_the_grid_of_cell_centres_in_row_order() {
        let p = points(SamplerKind::Regular, 2, 0);
        assert_eq!(p, [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]);
    }

    #[test]
    fn jittered_puts_one_point_in_each_cell() {
        let n = 5;
        for kind in [SamplerKind::Jittered, SamplerKind::MultiJittered] {
            let p = points(kind, n, 4);
            let mut cells: Vec<(u32, u32)> = p
                .iter()
                .map(|&(x, y)| ((x * n as f64) as u32, (y * n as f64) as u32))
                .collect();
            cells.sort();
            cells.dedup();
            assert_eq!(cells.len(), (n * n) as usize, "{kind:?}");
        }
    }

    #[test]
    fn multijittered_has_one_point_per_fine_row_and_column() {
        for n in [1, 4, MAX_SAMPLES] {
            fine_rows_and_columns(n);
        }
    }

    fn fine_rows_and_columns(n: u32) {
        let p = points(SamplerKind::MultiJittered, n, 7);
        let fine = (n * n) as f64;
        let mut cols: Vec<u32> = p.iter().map(|&(x, _)| (x * fine) as u32).collect();
        let mut rows: Vec<u32> = p.iter().map(|&(_, y)| (y * fine) as u32).collect();
        cols.sort();
        rows.sort();
        let all: Vec<u32> = (0..n * n).collect();
        assert_eq!(cols, all);
        assert_eq!(rows, all);
    }

    #[test]
    fn concentric_map_stays_in_the_disc_and_fills_it_evenly() {
        let mut inner = 0;
        let n = 100;
        for i in 0..n {
            for j in 0..n {
                let (x, y) =
                    concentric_disc(((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64));
                let r2 = x * x + y * y;
                assert!(r2 <= 1.0 + 1e-12);
                inner += (r2 < 0.25) as u32;
            }
        }
        // The disc of radius 1/2 has a quarter of the area.
        let frac = inner as f64 / (n * n) as f64;
        assert!((frac - 0.25).abs() < 0.01, "{frac}");
    }

    #[test]
    fn cosine_lobe_has_the_analytic_mean_cosine() {
        // For density ∝ cos^e, E[cos θ] = (e + 1)/(e + 2).
        for e in [1.0, 10.0] {
            let n = 200;
            let mut sum = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let d = cos_power_lobe(
                        ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64),
                        e,
                    );
                    assert!((d.length() - 1.0).abs() < 1e-12);
                    sum += d.z;
                }
            }
            let mean = sum / (n * n) as f64;
            assert!((mean - (e + 1.0) / (e + 2.0)).abs() < 1e-3, "{e}: {mean}");
        }
    }
}
