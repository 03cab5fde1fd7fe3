//! Root finder speed by degree: the nearest root (what a camera or shadow
//! ray asks) and all roots (what CSG asks) of ray-like polynomials on
//! [−1, 1]: two real roots inside, the rest complex, as a ray through a
//! bounded surface's box gives them. Also the power cube along a chord.
//!
//! `cargo bench --bench solver`

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use raytrace::implicit::solve::{no_root_in_unit, roots_in};
use std::hint::black_box;

fn mul(c: &[f64], f: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; c.len() + f.len() - 1];
    for (i, a) in c.iter().enumerate() {
        for (j, b) in f.iter().enumerate() {
            out[i + j] += a * b;
        }
    }
    out
}

/// 64 polynomials of degree `deg`: (t − r1)(t − r2) · Π (1 + s·(t − m)²).
fn family(deg: usize) -> Vec<Vec<f64>> {
    let mut seed = 0x2545F4914F6CDD1Du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..64)
        .map(|_| {
            let mut c = vec![1.0];
            let real = if deg.is_multiple_of(2) { 2 } else { 1 };
            for _ in 0..real {
                c = mul(&c, &[-(rnd() * 1.8 - 0.9), 1.0]);
            }
            while c.len() < deg + 1 {
                let (s, m) = (1.0 + 4.0 * rnd(), rnd() * 2.0 - 1.0);
                c = mul(&c, &[1.0 + s * m * m, -2.0 * s * m, s]);
            }
            c
        })
        .collect()
}

fn power_cube(n: usize) -> Vec<f64> {
    // Chord from (−1.01, 0.3, 0.2) to (1.01, −0.2, 0.5), about its midpoint.
    let (a, b) = ([-1.01, 0.3, 0.2], [1.01, -0.2, 0.5]);
    let mut c = vec![0.0; n + 1];
    for i in 0..3 {
        let (o, d): (f64, f64) = (0.5 * (a[i] + b[i]), 0.5 * (b[i] - a[i]));
        let mut binom = 1.0;
        for (j, cj) in c.iter_mut().enumerate() {
            *cj += binom * o.powi((n - j) as i32) * d.powi(j as i32);
            binom = binom * (n - j) as f64 / (j + 1) as f64;
        }
    }
    c[0] -= 1.0;
    c
}

fn bench(cr: &mut Criterion) {
    let mut g = cr.benchmark_group("nearest_root");
    for deg in [2, 3, 4, 6, 8, 12, 20, 40] {
        let polys = family(deg);
        g.bench_with_input(BenchmarkId::from_parameter(deg), &polys, |b, polys| {
            b.iter(|| {
                let mut sum = 0.0;
                for p in polys {
                    roots_in(black_box(p), -1.0, 1.0, 1e-13, |t| {
                        sum += t;
                        true
                    });
                }
                sum
            })
        });
    }
    g.finish();
    let mut g = cr.benchmark_group("all_roots");
    for deg in [4, 6, 20, 40] {
        let polys = family(deg);
        g.bench_with_input(BenchmarkId::from_parameter(deg), &polys, |b, polys| {
            b.iter(|| {
                let mut sum = 0.0;
                for p in polys {
                    roots_in(black_box(p), -1.0, 1.0, 1e-13, |t| {
                        sum += t;
                        false
                    });
                }
                sum
            })
        });
    }
    g.finish();
    let mut g = cr.benchmark_group("power_cube_chord");
    for n in [4, 10, 20, 40] {
        let c = power_cube(n);
        g.bench_with_input(BenchmarkId::from_parameter(n), &c, |b, c| {
            b.iter(|| {
                let mut first = f64::NAN;
                roots_in(black_box(c), -1.0, 1.0, 1e-13, |t| {
                    first = t;
                    true
                });
                first
            })
        });
    }
    g.finish();
    let mut g = cr.benchmark_group("bernstein_cull");
    for deg in [4, 6, 12] {
        let polys = family(deg);
        g.bench_with_input(BenchmarkId::from_parameter(deg), &polys, |b, polys| {
            b.iter(|| {
                polys
                    .iter()
                    .filter(|p| no_root_in_unit(black_box(p)))
                    .count()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
