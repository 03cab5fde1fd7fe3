//! Perlin's improved gradient noise (2002), for the marble and wood
//! patterns. Deterministic: the permutation is a fixed shuffle, so a picture
//! is the same on every run and machine.

use crate::geometry::DVec3;

const PERM: [u8; 256] = {
    // A fixed pseudo-random permutation of 0..=255 (an LCG shuffle computed
    // at compile time), so that no table of magic numbers is needed.
    let mut p = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        p[i] = i as u8;
        i += 1;
    }
    let mut state: u64 = 0x2545_F491_4F6C_DD1D;
    let mut i = 255;
    while i > 0 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let j = ((state >> 33) % (i as u64 + 1)) as usize;
        let t = p[i];
        p[i] = p[j];
        p[j] = t;
        i -= 1;
    }
    p
};

fn hash(i: i64) -> usize {
    PERM[(i & 255) as usize] as usize
}

fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

fn grad(h: usize, x: f64, y: f64, z: f64) -> f64 {
    let h = h & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Gradient noise in about [−1, 1].
pub fn noise(p: DVec3) -> f64 {
    let c = p.floor();
    let (xi, yi, zi) = (c.x as i64, c.y as i64, c.z as i64);
    let f = p - c;
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let a = hash(xi) + yi.rem_euclid(256) as usize;
    let (aa, ab) = (
        hash(a as i64) + zi.rem_euclid(256) as usize,
        hash(a as i64 + 1) + zi.rem_euclid(256) as usize,
    );
    let b = hash(xi.wrapping_add(1)) + yi.rem_euclid(256) as usize;
    let (ba, bb) = (
        hash(b as i64) + zi.rem_euclid(256) as usize,
        hash(b as i64 + 1) + zi.rem_euclid(256) as usize,
    );
    let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
    let (x, y, z) = (f.x, f.y, f.z);
    lerp(
        w,
        lerp(
            v,
            lerp(
                u,
                grad(hash(aa as i64), x, y, z),
                grad(hash(ba as i64), x - 1.0, y, z),
            ),
            lerp(
                u,
                grad(hash(ab as i64), x, y - 1.0, z),
                grad(hash(bb as i64), x - 1.0, y - 1.0, z),
            ),
        ),
        lerp(
            v,
            lerp(
                u,
                grad(hash(aa as i64 + 1), x, y, z - 1.0),
                grad(hash(ba as i64 + 1), x - 1.0, y, z - 1.0),
            ),
            lerp(
                u,
                grad(hash(ab as i64 + 1), x, y - 1.0, z - 1.0),
                grad(hash(bb as i64 + 1), x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    )
}

/// Sum of |noise| over octaves, each twice the frequency and half the weight.
pub fn turbulence(p: DVec3, octaves: u32) -> f64 {
    let mut sum = 0.0;
    let mut scale = 1.0;
    for _ in 0..octaves {
        sum += noise(p * scale).abs() / scale;
        scale *= 2.0;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_zero_on_lattice_points_and_bounded() {
        assert_eq!(noise(DVec3::new(3.0, -2.0, 7.0)), 0.0);
        let mut max: f64 = 0.0;
        for i in 0..1000 {
            let p = DVec3::new(
                i as f64 * 0.173,
                i as f64 * 0.071 - 20.0,
                (i * 7 % 31) as f64 * 0.3,
            );
            let n = noise(p);
            assert!(n.is_finite() && n.abs() <= 1.1);
            max = max.max(n.abs());
        }
        assert!(max > 0.3, "noise hardly varies: {max}");
    }

    #[test]
    fn huge_and_non_finite_points_are_no_panic() {
        // A pattern's scale may be as large as the user likes: the lattice
        // coordinate saturates at i64::MAX and its neighbour wraps.
        for p in [
            DVec3::splat(1e300),
            DVec3::splat(f64::INFINITY),
            DVec3::splat(f64::NAN),
        ] {
            let _ = noise(p);
            let _ = turbulence(p, 6);
        }
    }

    #[test]
    fn noise_is_continuous() {
        let p = DVec3::new(1.3, 2.7, -0.4);
        assert!((noise(p) - noise(p + DVec3::splat(1e-7))).abs() < 1e-5);
    }
}
