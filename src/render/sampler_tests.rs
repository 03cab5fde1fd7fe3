//! The samplers' tests: pure numbers, each pattern's strata (square and
//! rectangular grids), the permutations, the disc and lobe maps.

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
    PixelSampler::square(kind, n, seed).pattern(Pixel { x: 3, y: 7 }, 0, &mut out);
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

/// An n × m grid (n columns, m rows): n·m points; every sampler but
/// random puts one in each of its cells (sample s in column s mod n of
/// row s div n, the regular one at the cell's centre), and the
/// multi-jittered one also one in each fine column and fine row of
/// the nm × nm grid.
#[test]
fn a_grid_of_n_columns_and_m_rows_has_its_cells_and_fine_strata() {
    for (n, m) in [(8, 4), (4, 8), (1, 5), (5, 1), (3, 16)] {
        for kind in [
            SamplerKind::Regular,
            SamplerKind::Random,
            SamplerKind::Jittered,
            SamplerKind::MultiJittered,
        ] {
            let s = PixelSampler {
                kind,
                n,
                rows: m,
                seed: 3,
            };
            let mut p = Vec::new();
            s.pattern(Pixel { x: 5, y: 2 }, 2, &mut p);
            assert_eq!((p.len(), s.count()), ((n * m) as usize, n * m));
            assert!(
                p.iter()
                    .all(|&(x, y)| (0.0..1.0).contains(&x) && (0.0..1.0).contains(&y))
            );
            let cell = |&(x, y): &(f64, f64)| (x * n as f64) as u32 + n * (y * m as f64) as u32;
            let mut cells: Vec<u32> = p.iter().map(cell).collect();
            if kind != SamplerKind::MultiJittered && kind != SamplerKind::Random {
                assert_eq!(cells, (0..n * m).collect::<Vec<_>>(), "{kind:?} {n}x{m}");
            }
            if kind == SamplerKind::Regular {
                let (i, j) = ((n * m - 1) % n, (n * m - 1) / n);
                let c = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / m as f64);
                assert_eq!(p[(n * m - 1) as usize], c);
            }
            if kind == SamplerKind::MultiJittered {
                cells.sort();
                assert_eq!(cells, (0..n * m).collect::<Vec<_>>(), "{n}x{m}");
                let fine = (n * m) as f64;
                let mut cols: Vec<u32> = p.iter().map(|&(x, _)| (x * fine) as u32).collect();
                let mut rows: Vec<u32> = p.iter().map(|&(_, y)| (y * fine) as u32).collect();
                cols.sort();
                rows.sort();
                assert_eq!(cols, (0..n * m).collect::<Vec<_>>(), "{n}x{m}");
                assert_eq!(rows, (0..n * m).collect::<Vec<_>>(), "{n}x{m}");
            }
        }
    }
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

// ---- Oracles added for the mutation run (docs/testing.md) ----

/// Mean, variance and the mean product of many pairs: a uniform pair
/// on [0, 1)² has 1/2, 1/12 per coordinate and E[xy] = 1/4.
fn moments(p: &[(f64, f64)]) -> [f64; 5] {
    let k = p.len() as f64;
    let mx = p.iter().map(|q| q.0).sum::<f64>() / k;
    let my = p.iter().map(|q| q.1).sum::<f64>() / k;
    let vx = p.iter().map(|q| (q.0 - mx).powi(2)).sum::<f64>() / k;
    let vy = p.iter().map(|q| (q.1 - my).powi(2)).sum::<f64>() / k;
    let xy = p.iter().map(|q| q.0 * q.1).sum::<f64>() / k;
    [mx, my, vx, vy, xy]
}

fn assert_uniform_pairs(p: &[(f64, f64)], what: &str) {
    assert!(
        p.iter()
            .all(|&(x, y)| (0.0..1.0).contains(&x) && (0.0..1.0).contains(&y)),
        "{what}: a point outside [0, 1)²"
    );
    let [mx, my, vx, vy, xy] = moments(p);
    let tol = 4.0 / (p.len() as f64).sqrt();
    assert!((mx - 0.5).abs() < tol * 0.3, "{what}: mean x {mx}");
    assert!((my - 0.5).abs() < tol * 0.3, "{what}: mean y {my}");
    assert!((vx - 1.0 / 12.0).abs() < tol * 0.1, "{what}: var x {vx}");
    assert!((vy - 1.0 / 12.0).abs() < tol * 0.1, "{what}: var y {vy}");
    assert!((xy - 0.25).abs() < tol * 0.1, "{what}: E[xy] {xy}");
}

#[test]
fn uniform_numbers_have_the_moments_of_the_uniform_distribution() {
    let p = Pixel { x: 5, y: 9 };
    let xs: Vec<(f64, f64)> = (0..20000)
        .map(|s| (uniform(p, s, 4, 3), uniform(p, s, 5, 3)))
        .collect();
    assert_uniform_pairs(&xs, "uniform");
    // 53 bits: numbers on a finer grid than 2⁻³², and below 1 - 2⁻⁵³.
    assert!(xs.iter().any(|q| (q.0 * 2f64.powi(32)).fract() != 0.0));
}

#[test]
fn a_pair_is_two_independent_uniform_numbers_of_every_input() {
    let p = Pixel { x: 12, y: 34 };
    let xs: Vec<(f64, f64)> = (0..20000)
        .map(|s| PixelKey::new(p, 11).uniform_pair(s, 2))
        .collect();
    assert_uniform_pairs(&xs, "uniform_pair");
    // 32 bits each: every coordinate is a multiple of 2⁻³².
    assert!(
        xs.iter()
            .all(|q| (q.0 * 2f64.powi(32)).fract() == 0.0 && (q.1 * 2f64.powi(32)).fract() == 0.0)
    );
    let a = PixelKey::new(p, 11).uniform_pair(3, 2);
    assert_eq!(a, PixelKey::new(p, 11).uniform_pair(3, 2));
    for b in [
        PixelKey::new(Pixel { x: 13, y: 34 }, 11).uniform_pair(3, 2),
        PixelKey::new(Pixel { x: 12, y: 35 }, 11).uniform_pair(3, 2),
        PixelKey::new(p, 11).uniform_pair(4, 2),
        PixelKey::new(p, 11).uniform_pair(3, 3),
        PixelKey::new(p, 12).uniform_pair(3, 2),
    ] {
        assert!(a.0 != b.0 && a.1 != b.1, "{a:?} {b:?}");
    }
}

/// The inverse of [`mix`], step by step: x ^ (x >> s) is undone by
/// repeating z = y ^ (z >> s), a product by an odd constant by the
/// product with its inverse mod 2⁶⁴ (Newton: x ← x(2 − ax)).
fn unmix(mut z: u64) -> u64 {
    let unshift = |y: u64, s: u32| {
        let mut z = y;
        for _ in 0..64 / s + 1 {
            z = y ^ (z >> s);
        }
        z
    };
    let inverse = |a: u64| {
        let mut x = a;
        for _ in 0..6 {
            x = x.wrapping_mul(2u64.wrapping_sub(a.wrapping_mul(x)));
        }
        assert_eq!(a.wrapping_mul(x), 1);
        x
    };
    z = unshift(z, 31);
    z = unshift(z.wrapping_mul(inverse(0x94d0_49bb_1331_11eb)), 27);
    unshift(z.wrapping_mul(inverse(0xbf58_476d_1ce4_e5b9)), 30)
}

#[test]
fn the_64_bit_mix_is_a_bijection_that_spreads_every_bit() {
    // SplitMix64's finaliser: invertible, so distinct inputs never meet
    // (the pixel, sample and dimension packed into one word stay
    // apart), and one flipped input bit flips about half the output
    // bits.
    for i in 0..4096u64 {
        for x in [i, i << 40, !i, i.wrapping_mul(0x9e37_79b9_7f4a_7c15)] {
            assert_eq!(unmix(mix(x)), x, "{x:#x}");
        }
    }
    assert_eq!(mix(0), 0);
    let mut flips = 0u64;
    let mut count = 0u64;
    for i in 0..64u64 {
        for bit in 0..64 {
            let x = i.wrapping_mul(0x9e37_79b9_7f4a_7c15);
            flips += (mix(x) ^ mix(x ^ (1 << bit))).count_ones() as u64;
            count += 1;
        }
    }
    let mean = flips as f64 / count as f64;
    assert!((mean - 32.0).abs() < 0.5, "{mean} bits flip of 64");
}

#[test]
fn every_bit_of_every_input_changes_the_numbers() {
    // A hash that dropped bits would give two pixels (or seeds,
    // samples, dimensions) the same noise.
    let (p, sample, dim, seed) = (
        Pixel {
            x: 0x1234_5678,
            y: 0x0bad_cafe,
        },
        0x55aa_33cc,
        0x0f0f_1234,
        0x0123_4567_89ab_cdef,
    );
    let u = uniform(p, sample, dim, seed);
    let v = PixelKey::new(p, seed).uniform_pair(sample, dim);
    let mut variants = Vec::new();
    for b in 0..32 {
        variants.push((
            Pixel {
                x: p.x ^ (1 << b),
                ..p
            },
            sample,
            dim,
            seed,
        ));
        variants.push((
            Pixel {
                y: p.y ^ (1 << b),
                ..p
            },
            sample,
            dim,
            seed,
        ));
        variants.push((p, sample ^ (1 << b), dim, seed));
        variants.push((p, sample, dim ^ (1 << b), seed));
    }
    for b in 0..64 {
        variants.push((p, sample, dim, seed ^ (1 << b)));
    }
    for (q, s, d, k) in variants {
        assert_ne!(u, uniform(q, s, d, k), "{q:?} {s:#x} {d:#x} {k:#x}");
        assert_ne!(
            v,
            PixelKey::new(q, k).uniform_pair(s, d),
            "{q:?} {s:#x} {d:#x} {k:#x}"
        );
    }
}

#[test]
fn a_permutation_holds_each_index_once_and_depends_on_its_key() {
    let mut seen = std::collections::HashSet::new();
    for len in [1usize, 2, 5, 16, 256] {
        let mut p = vec![0u16; len];
        permutation(&mut p, 77);
        let mut sorted = p.clone();
        sorted.sort();
        assert_eq!(sorted, (0..len as u16).collect::<Vec<_>>(), "{len}");
        if len == 256 {
            // Not the identity, and another key gives another order.
            assert_ne!(p, sorted);
            let mut q = vec![0u16; len];
            permutation(&mut q, 78);
            assert_ne!(p, q);
        }
    }
    // Uniform: over many keys, each of the 6 orders of 3 turns up
    // about a sixth of the time (a biased index choice skews this).
    let mut counts = std::collections::HashMap::new();
    for key in 0..6000u64 {
        let mut p = [0u16; 3];
        permutation(&mut p, mix(key));
        *counts.entry(p).or_insert(0u32) += 1;
        seen.insert(p);
    }
    assert_eq!(seen.len(), 6);
    for (p, c) in counts {
        assert!((c as f64 - 1000.0).abs() < 150.0, "{p:?}: {c}");
    }
}

#[test]
fn permutations_are_uniform_even_over_keys_of_one_bit() {
    // Keys one bit away from 0 or from all ones: a key folded into the
    // hash by | or & instead of ^ loses most of them. χ² over the 6
    // orders of 3 (5 degrees of freedom; 20.5 is the 0.1% point).
    let mut counts = std::collections::HashMap::new();
    let mut keys = Vec::new();
    for b in 0..64 {
        keys.push(1u64 << b);
        keys.push(!(1u64 << b));
    }
    for &key in &keys {
        let mut p = [0u16; 3];
        permutation(&mut p, key);
        *counts.entry(p).or_insert(0u32) += 1;
    }
    let e = keys.len() as f64 / 6.0;
    let chi2 = counts
        .values()
        .map(|&c| (c as f64 - e).powi(2) / e)
        .sum::<f64>()
        + (6 - counts.len()) as f64 * e;
    assert!(chi2 < 20.5, "χ² = {chi2}: {counts:?}");
}

#[test]
fn count_is_the_square_of_the_samples_per_side() {
    for n in [1, 2, 3, 7] {
        let s = PixelSampler::square(SamplerKind::Jittered, n, 0);
        assert_eq!(s.count(), n * n);
        let mut out = Vec::new();
        s.pattern(Pixel { x: 0, y: 0 }, 0, &mut out);
        assert_eq!(out.len() as u32, s.count());
    }
}

#[test]
fn regular_grids_of_every_size_are_cell_centres_and_n_is_clamped() {
    for n in [1, 3, 4] {
        let p = points(SamplerKind::Regular, n, 0);
        assert_eq!(p.len() as u32, n * n);
        for (s, &(x, y)) in p.iter().enumerate() {
            let (i, j) = (s as u32 % n, s as u32 / n);
            let c = |k: u32| (2 * k + 1) as f64 / (2 * n) as f64;
            assert!(
                (x - c(i)).abs() < 1e-15 && (y - c(j)).abs() < 1e-15,
                "{n}: {s}"
            );
        }
    }
    // No samples asked for is one; too many is the maximum.
    assert_eq!(points(SamplerKind::Regular, 0, 0), [(0.5, 0.5)]);
    let big = points(SamplerKind::Regular, MAX_SAMPLES + 3, 0);
    assert_eq!(big.len() as u32, MAX_SAMPLES * MAX_SAMPLES);
}

#[test]
fn random_points_are_uniform_in_the_pixel_and_differ_per_pixel() {
    let mut all = Vec::new();
    for x in 0..40 {
        let mut out = Vec::new();
        PixelSampler::square(SamplerKind::Random, 8, 5).pattern(Pixel { x, y: 1 }, 0, &mut out);
        assert_eq!(out.len(), 64);
        all.extend(out);
    }
    assert_uniform_pairs(&all, "random");
    assert_ne!(all[..64], all[64..128]);
}

#[test]
fn jittered_sample_s_lies_in_cell_s_in_row_order_and_fills_it() {
    // Sample s = j·n + i is in cell (i, j); across pixels its offset in
    // the cell is uniform.
    let n = 4;
    let mut offsets = Vec::new();
    for x in 0..200 {
        let mut out = Vec::new();
        PixelSampler::square(SamplerKind::Jittered, n, 2).pattern(Pixel { x, y: 3 }, 2, &mut out);
        for (s, &(px, py)) in out.iter().enumerate() {
            let (i, j) = (s as u32 % n, s as u32 / n);
            let (fx, fy) = (px * n as f64 - i as f64, py * n as f64 - j as f64);
            assert!(
                (0.0..1.0).contains(&fx) && (0.0..1.0).contains(&fy),
                "{s}: {px} {py}"
            );
            offsets.push((fx, fy));
        }
    }
    assert_uniform_pairs(&offsets, "jitter in a cell");
    // Each cell of one pixel has its own jitter (its own sample's
    // numbers), not a copy of another cell's.
    for px in offsets.chunks((n * n) as usize) {
        let mut xs: Vec<u64> = px.iter().map(|q| q.0.to_bits()).collect();
        xs.sort();
        xs.dedup();
        assert_eq!(xs.len(), px.len());
    }
}

#[test]
fn multijittered_points_are_uniform_and_differ_by_pixel_and_dimension() {
    let n = 4;
    let pattern = |x: u32, dim: u32, seed: u64| {
        let mut out = Vec::new();
        PixelSampler::square(SamplerKind::MultiJittered, n, seed).pattern(
            Pixel { x, y: 8 },
            dim,
            &mut out,
        );
        out
    };
    let mut all = Vec::new();
    for x in 0..100 {
        all.extend(pattern(x, 0, 1));
    }
    assert_uniform_pairs(&all, "multi-jittered");
    // Where in its fine cell a point sits is uniform too.
    let fine = (n * n) as f64;
    let inner: Vec<(f64, f64)> = all
        .iter()
        .map(|&(x, y)| ((x * fine).fract(), (y * fine).fract()))
        .collect();
    assert_uniform_pairs(&inner, "multi-jittered within a fine cell");
    // Another pixel, dimension or seed is another arrangement (the
    // fine cells used, not only the jitter inside them).
    let cells = |p: Vec<(f64, f64)>| -> Vec<(u32, u32)> {
        p.iter()
            .map(|&(x, y)| ((x * fine) as u32, (y * fine) as u32))
            .collect()
    };
    let a = cells(pattern(1, 0, 1));
    assert_ne!(a, cells(pattern(2, 0, 1)));
    assert_ne!(a, cells(pattern(1, 2, 1)));
    assert_ne!(a, cells(pattern(1, 0, 2)));
    // Every bit of the seed, the pixel and the dimension counts.
    let at = |x: u32, y: u32, dim: u32, seed: u64| {
        let mut out = Vec::new();
        PixelSampler::square(SamplerKind::MultiJittered, n, seed).pattern(
            Pixel { x, y },
            dim,
            &mut out,
        );
        cells(out)
    };
    let (x, y, dim, seed) = (0x0123_4567, 0x0765_4321, 0x00ab_cdef, 0x0f1e_2d3c_4b5a_6978);
    let base = at(x, y, dim, seed);
    for b in 0..32 {
        assert_ne!(base, at(x ^ (1 << b), y, dim, seed), "x bit {b}");
        assert_ne!(base, at(x, y ^ (1 << b), dim, seed), "y bit {b}");
        assert_ne!(base, at(x, y, dim ^ (1 << b), seed), "dim bit {b}");
    }
    for b in 0..64 {
        assert_ne!(base, at(x, y, dim, seed ^ (1 << b)), "seed bit {b}");
    }
    // The order of samples is shuffled, not the grid's: sample 0 is
    // not always in the first cell.
    let firsts: std::collections::HashSet<(u32, u32)> = (0..50)
        .map(|x| {
            let (px, py) = pattern(x, 0, 1)[0];
            ((px * n as f64) as u32, (py * n as f64) as u32)
        })
        .collect();
    assert!(firsts.len() > 8, "{firsts:?}");
}

#[test]
fn multijittered_sample_orders_do_not_repeat_across_pixels() {
    // Which cell sample k lands in is a permutation of 16 per pixel
    // (16! of them): 3000 pixels must not share one. (A key folded in
    // with `&` by a fixed mask leaves only 2¹⁸ orders, and some
    // pixels would.)
    let n = 4;
    let mut orders = std::collections::HashSet::new();
    for x in 0..3000 {
        let mut out = Vec::new();
        PixelSampler::square(SamplerKind::MultiJittered, n, 0).pattern(
            Pixel { x, y: x / 7 },
            0,
            &mut out,
        );
        let cells: Vec<u32> = out
            .iter()
            .map(|&(x, y)| (y * n as f64) as u32 * n + (x * n as f64) as u32)
            .collect();
        assert!(orders.insert(cells), "pixel {x} repeats an order");
    }
}

#[test]
fn a_stream_draws_the_path_dimensions_in_order() {
    let p = Pixel { x: 4, y: 2 };
    let mut s = SampleStream::new(PixelKey::new(p, 99), 6);
    let a = s.next1();
    let (b, c) = s.next2();
    let d = s.next1();
    for (k, v) in [a, b, c, d].into_iter().enumerate() {
        assert_eq!(v, uniform(p, 6, PATH_DIMS + k as u32, 99), "{k}");
    }
    // The camera's dimensions (0–3) are not reused.
    for k in 0..4 {
        assert_ne!(a, uniform(p, 6, k, 99));
    }
}

#[test]
fn the_concentric_map_sends_edges_and_corners_where_shirley_chiu_say() {
    let close =
        |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12;
    let h = std::f64::consts::FRAC_1_SQRT_2;
    for (u, want) in [
        ((0.5, 0.5), (0.0, 0.0)),
        ((1.0, 0.5), (1.0, 0.0)),
        ((0.0, 0.5), (-1.0, 0.0)),
        ((0.5, 1.0), (0.0, 1.0)),
        ((0.5, 0.0), (0.0, -1.0)),
        ((1.0, 1.0), (h, h)),
        ((0.0, 0.0), (-h, -h)),
        ((1.0, 0.0), (h, -h)),
        ((0.0, 1.0), (-h, h)),
        // Squares map to circles: x = 0.75 on the middle row is r = 1/2.
        ((0.75, 0.5), (0.5, 0.0)),
        // On the square of half-size 1/2, a third of the way from the
        // x axis to the corner: the angle π/4 · 1/3 at r = 1/2; and a
        // third of the way from the y axis: π/2 − π/12.
        (
            (0.75, 0.5 + 1.0 / 12.0),
            (
                0.5 * (std::f64::consts::PI / 12.0).cos(),
                0.5 * (std::f64::consts::PI / 12.0).sin(),
            ),
        ),
        (
            (0.5 + 1.0 / 12.0, 0.75),
            (
                0.5 * (5.0 * std::f64::consts::PI / 12.0).cos(),
                0.5 * (5.0 * std::f64::consts::PI / 12.0).sin(),
            ),
        ),
    ] {
        let got = concentric_disc(u);
        assert!(close(got, want), "{u:?}: {got:?}, want {want:?}");
    }
}

#[test]
fn the_octant_sine_and_cosine_agree_with_libm_to_an_ulp() {
    // Across [−π/4, π/4] and at its ends: within one ulp of the larger of
    // the value and 2⁻⁵³ (sin's tiny values are relative to themselves).
    let ulp = |v: f64| (v.abs().max(1.0 / (1u64 << 53) as f64)) * f64::EPSILON;
    let q = std::f64::consts::FRAC_PI_4;
    let mut worst = 0.0f64;
    for k in 0..=20_000 {
        let t = -q + 2.0 * q * k as f64 / 20_000.0;
        let (s, c) = sin_cos_octant(t);
        worst = worst.max((s - t.sin()).abs() / ulp(t.sin()));
        worst = worst.max((c - t.cos()).abs() / ulp(t.cos()));
    }
    for t in [q, -q, 1e-300, -1e-8, 0.0] {
        let (s, c) = sin_cos_octant(t);
        worst = worst.max((s - t.sin()).abs() / ulp(t.sin()));
        worst = worst.max((c - t.cos()).abs() / ulp(t.cos()));
    }
    assert!(worst <= 1.0, "{worst} ulp");
}

#[test]
fn a_lobe_direction_has_the_asked_angles() {
    // φ = 2πa, cos θ = (1 − b)^(1/(e+1)).
    for (a, b, e) in [(0.1, 0.3, 1.0), (0.6, 0.8, 5.0), (0.85, 0.05, 0.5)] {
        let d = cos_power_lobe((a, b), e);
        let cos_t = (1.0f64 - b).powf(1.0 / (e + 1.0));
        let sin_t = (1.0 - cos_t * cos_t).sqrt();
        let phi = std::f64::consts::TAU * a;
        let want = glam::DVec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
        assert!((d - want).length() < 1e-12, "{d:?} {want:?}");
    }
    // b = 0 is straight up.
    assert!((cos_power_lobe((0.3, 0.0), 2.0) - glam::DVec3::Z).length() < 1e-12);
}

#[test]
fn about_turns_z_onto_w_and_keeps_lengths_and_angles() {
    for w in [
        glam::DVec3::Z,
        -glam::DVec3::Z,
        glam::DVec3::new(0.3, -0.5, 0.8).normalize(),
        glam::DVec3::new(-1.0, 2.0, 0.1).normalize(),
    ] {
        assert!((about(w, glam::DVec3::Z) - w).length() < 1e-12);
        let a = glam::DVec3::new(0.2, -0.7, 0.4);
        let b = glam::DVec3::new(-0.9, 0.1, 0.3);
        let (ta, tb) = (about(w, a), about(w, b));
        assert!((ta.dot(tb) - a.dot(b)).abs() < 1e-12);
        assert!((ta.length() - a.length()).abs() < 1e-12);
        assert!((ta.dot(w) - a.z).abs() < 1e-12);
        // A rotation, not a reflection: handedness is kept.
        let c = a.cross(b);
        assert!((about(w, c) - ta.cross(tb)).length() < 1e-12);
    }
}

/// Each row of a multi-jittered grid places its points in its fine rows
/// by its own arrangement, and each column in its fine columns: were they
/// all one (the same key for every row or column), the points would line
/// up from cell to cell.
#[test]
fn multijittered_rows_and_columns_each_have_their_own_arrangement() {
    let (n, m) = (8u32, 6u32);
    for x in 0..4 {
        let mut p = Vec::new();
        PixelSampler {
            kind: SamplerKind::MultiJittered,
            n,
            rows: m,
            seed: 1,
        }
        .pattern(Pixel { x, y: 9 }, 0, &mut p);
        let fine = (n * m) as f64;
        let mut by_row = vec![vec![0; n as usize]; m as usize];
        let mut by_column = vec![vec![0; m as usize]; n as usize];
        for &(px, py) in &p {
            let (i, j) = ((px * n as f64) as usize, (py * m as f64) as usize);
            by_row[j][i] = (py * fine) as u32 - j as u32 * n;
            by_column[i][j] = (px * fine) as u32 - i as u32 * m;
        }
        assert!(by_row.iter().any(|r| *r != by_row[0]), "{by_row:?}");
        assert!(
            by_column.iter().any(|c| *c != by_column[0]),
            "{by_column:?}"
        );
    }
}

/// One sample a pixel: the regular sampler's is the centre (the 2017
/// rule), every other sampler's a point of its own in each pixel.
#[test]
fn a_single_sample_is_the_centre_only_for_the_regular_sampler() {
    for kind in [
        SamplerKind::Random,
        SamplerKind::Jittered,
        SamplerKind::MultiJittered,
    ] {
        let mut seen = Vec::new();
        for x in 0..8 {
            let mut p = Vec::new();
            PixelSampler::square(kind, 1, 4).pattern(Pixel { x, y: 0 }, 0, &mut p);
            assert_eq!(p.len(), 1);
            assert_ne!(p[0], (0.5, 0.5), "{kind:?}");
            seen.push(p[0]);
        }
        seen.dedup();
        assert_eq!(seen.len(), 8, "{kind:?}");
    }
    let mut p = Vec::new();
    PixelSampler::square(SamplerKind::Regular, 1, 4).pattern(Pixel { x: 3, y: 3 }, 0, &mut p);
    assert_eq!(p, [(0.5, 0.5)]);
}

/// The multi-jittered pattern as it was first written: one `mix` after
/// another, each permutation drawn as it is needed.
fn multijittered_one_mix_at_a_time(s: &PixelSampler, pixel: Pixel, dim: u32) -> Vec<(f64, f64)> {
    fn permutation(p: &mut [u16], key: u64) {
        for (i, v) in p.iter_mut().enumerate() {
            *v = i as u16;
        }
        for i in (1..p.len()).rev() {
            let r = mix(key ^ (i as u64).wrapping_mul(0x2545_f491_4f6c_dd1d));
            let j = (((r >> 32) * (i as u64 + 1)) >> 32) as usize;
            p.swap(i, j);
        }
    }
    let (n, m) = (s.n.clamp(1, MAX_SAMPLES), s.rows.clamp(1, MAX_SAMPLES));
    let (nf, mf) = (n as f64, m as f64);
    let r = |k: u32| PixelKey::new(pixel, s.seed).uniform_pair(k, dim);
    let key = mix(s.seed ^ mix(((pixel.x as u64) << 32) | pixel.y as u64) ^ dim as u64);
    let (nu, mu) = (n as usize, m as usize);
    let mut order = vec![0u16; nu * mu];
    permutation(&mut order, key ^ 0x5bd1_e995);
    let mut out = vec![(0.0, 0.0); nu * mu];
    let mut taus = vec![vec![0u16; nu]; mu];
    for (j, tau) in taus.iter_mut().enumerate() {
        permutation(tau, key ^ mix(0x1_0000 + j as u64));
    }
    let mut sigma = vec![0u16; mu];
    for i in 0..n {
        permutation(&mut sigma, key ^ mix(1 + i as u64));
        for (j, tau) in taus.iter().enumerate() {
            let s = j as u32 * n + i;
            let (a, b) = r(s);
            let x = (i as f64 + (sigma[j] as f64 + a) / mf) / nf;
            let y = (j as f64 + (tau[i as usize] as f64 + b) / nf) / mf;
            out[order[s as usize] as usize] = (x, y);
        }
    }
    out
}

#[test]
fn multijittered_points_are_those_of_one_mix_at_a_time_for_every_grid() {
    let mut out = Vec::new();
    for n in 1..=MAX_SAMPLES + 1 {
        for rows in 1..=MAX_SAMPLES + 1 {
            for (x, y, dim, seed) in [(0, 0, 0, 0), (417, 93, 2, 7), (u32::MAX, 5, 1, u64::MAX)] {
                let s = PixelSampler {
                    kind: SamplerKind::MultiJittered,
                    n,
                    rows,
                    seed,
                };
                let pixel = Pixel { x, y };
                s.pattern(pixel, dim, &mut out);
                let want = multijittered_one_mix_at_a_time(&s, pixel, dim);
                assert_eq!(
                    out, want,
                    "{n} × {rows} at {x}, {y}, dim {dim}, seed {seed}"
                );
            }
        }
    }
}

#[test]
fn mixing_all_at_once_is_mixing_each_by_either_path() {
    let mut next = 0x1234_5678_9abc_def0u64;
    for len in 0..40 {
        let xs: Vec<u64> = (0..len)
            .map(|_| {
                next = mix(next);
                next
            })
            .collect();
        let want: Vec<u64> = xs.iter().map(|&x| mix(x)).collect();
        let mut a = xs.clone();
        mix_all(&mut a);
        assert_eq!(a, want, "dispatched, {len}");
        let mut b = xs.clone();
        mix_all_scalar(&mut b);
        assert_eq!(b, want, "scalar, {len}");
        #[cfg(target_arch = "x86_64")]
        if avx512_mix_available() {
            let mut c = xs.clone();
            // SAFETY: the CPU has the features, checked just above.
            unsafe { mix_all_avx512(&mut c) };
            assert_eq!(c, want, "AVX-512, {len}");
        }
    }
}

#[test]
fn a_power_of_two_divisor_multiplies_to_the_quotients_bits() {
    let mut next = 0x0dd_ba11u64;
    for n in 1..=MAX_SAMPLES + 1 {
        let d = Divisor::new(n);
        assert_eq!(d.exact, n.is_power_of_two(), "{n}");
        let mut inexact = false;
        for _ in 0..2000 {
            next = mix(next);
            // Numerators as the patterns make them: a cell index plus a
            // number in [0, 1), and such sums over n again.
            let x = (next % 17) as f64 + (next >> 11) as f64 / (1u64 << 53) as f64;
            for x in [x, x / 17.0, 0.0, 0.5] {
                let same = d.times_inverse(x).to_bits() == (x / n as f64).to_bits();
                // Exact for a power of two; for the others (1/3 is
                // rounded) some products are off, which is why they divide.
                assert!(same || !d.exact, "{x} / {n}");
                inexact |= !same;
            }
        }
        assert_eq!(inexact, !d.exact, "{n}");
    }
}
