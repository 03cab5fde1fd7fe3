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

    /// The table is a permutation of 0..=255 (each value once), and not
    /// the identity: a shuffle.
    #[test]
    fn the_table_is_a_shuffled_permutation() {
        let mut seen = [false; 256];
        for &v in PERM.iter() {
            assert!(!seen[v as usize], "{v} twice");
            seen[v as usize] = true;
        }
        let fixed = PERM
            .iter()
            .enumerate()
            .filter(|(i, v)| *i == **v as usize)
            .count();
        assert!(fixed < 10, "{fixed} fixed points");
    }

    /// Perlin's improved noise written the other way round: the sum over
    /// the cell's eight corners c of fade-weights times g(c)·(p − c), g
    /// from the paper's table of twelve edge directions (padded to 16)
    /// picked by the corner's hash P[P[P[X] + Y] + Z] (P the table
    /// repeated, coordinates mod 256). Agrees with the nested lerps to
    /// rounding, away from and on the lattice, at negative points too.
    #[test]
    fn noise_is_perlins_sum_over_the_corners() {
        const G: [[f64; 3]; 16] = [
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
            [1.0, -1.0, 0.0],
            [-1.0, -1.0, 0.0],
            [1.0, 0.0, 1.0],
            [-1.0, 0.0, 1.0],
            [1.0, 0.0, -1.0],
            [-1.0, 0.0, -1.0],
            [0.0, 1.0, 1.0],
            [0.0, -1.0, 1.0],
            [0.0, 1.0, -1.0],
            [0.0, -1.0, -1.0],
            [1.0, 1.0, 0.0],
            [0.0, -1.0, 1.0],
            [-1.0, 1.0, 0.0],
            [0.0, -1.0, -1.0],
        ];
        let p = |i: i64| PERM[i.rem_euclid(256) as usize] as i64;
        let fade = |t: f64| 6.0 * t.powi(5) - 15.0 * t.powi(4) + 10.0 * t.powi(3);
        let reference = |q: DVec3| {
            let c = q.floor();
            let f = q - c;
            let (x, y, z) = (c.x as i64, c.y as i64, c.z as i64);
            let mut sum = 0.0;
            for (dx, dy, dz) in [
                (0, 0, 0),
                (1, 0, 0),
                (0, 1, 0),
                (1, 1, 0),
                (0, 0, 1),
                (1, 0, 1),
                (0, 1, 1),
                (1, 1, 1),
            ] {
                let h = p(p(p(x + dx) + (y + dy).rem_euclid(256)) + (z + dz).rem_euclid(256));
                let g = G[(h & 15) as usize];
                let d = f - DVec3::new(dx as f64, dy as f64, dz as f64);
                let weight = |t: f64, side: i64| if side == 1 { fade(t) } else { 1.0 - fade(t) };
                sum += weight(f.x, dx)
                    * weight(f.y, dy)
                    * weight(f.z, dz)
                    * (g[0] * d.x + g[1] * d.y + g[2] * d.z);
            }
            sum
        };
        for i in 0..2000 {
            let t = i as f64;
            let q = DVec3::new(
                (0.37 * t).sin() * 300.0,
                0.173 * t - 170.0,
                (t * 0.051).cos() * 40.0 + 0.5 * (t * 1.7).sin(),
            );
            let (got, want) = (noise(q), reference(q));
            assert!((got - want).abs() < 1e-12, "{q}: {got} vs {want}");
        }
        // Near a lattice point noise is g·(p − c) to first order.
        for c in [DVec3::new(3.0, -2.0, 7.0), DVec3::new(-100.0, 255.0, 256.0)] {
            for e in [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.3, -0.5, 0.8)] {
                let q = c + e * 1e-4;
                assert!((noise(q) - reference(q)).abs() < 1e-12, "{q}");
            }
        }
    }

    /// Turbulence: Σ |n(2ⁱ·p)| / 2ⁱ over the octaves.
    #[test]
    fn turbulence_is_the_sum_of_octaves_of_absolute_noise() {
        for i in 0..100 {
            let q = DVec3::new(0.37 * i as f64, 1.3 - 0.11 * i as f64, (i as f64).sin());
            for k in [1, 3, 6] {
                let want: f64 = (0..k)
                    .map(|j| {
                        let f = 2f64.powi(j);
                        noise(q * f).abs() / f
                    })
                    .sum();
                let got = turbulence(q, k as u32);
                assert!((got - want).abs() < 1e-12, "{q} {k}: {got} vs {want}");
            }
        }
    }
}
