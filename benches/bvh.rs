//! The wide BVH against the kd-tree on the bunny (build, nearest hits,
//! occlusion) and the four-triangle block test against one triangle at a
//! time, on both the AVX2 and the scalar path (criterion):
//! `cargo bench --features bench --bench bvh`. Needs
//! `../shared/data/bunny.ply` (or `BUNNY=path`); the bunny benches skip
//! without it.

use criterion::{Criterion, criterion_group, criterion_main};
use raytrace::accel::Accel;
use raytrace::accel::bvh::Simd;
use raytrace::accel::bvh::triangles::{Block, LaneRay, hits};
use raytrace::geometry::{DVec3, Ray};
use raytrace::shapes::{Mesh, MeshData, Shape, Triangle};
use std::hint::black_box;
use std::sync::Arc;

fn bunny_bytes() -> Option<Vec<u8>> {
    let path = std::env::var("BUNNY").unwrap_or_else(|_| "../shared/data/bunny.ply".into());
    match std::fs::read(&path) {
        Ok(b) => Some(b),
        Err(e) => {
            eprintln!("skipping the bunny benches: {path}: {e}");
            None
        }
    }
}

/// A 256x256 grid of camera rays through the bunny's box.
fn camera_rays(data: &MeshData) -> Vec<Ray> {
    let bb = data.bounds();
    let eye = bb.centre() + DVec3::new(0.0, 0.05, 0.4);
    (0..256 * 256)
        .map(|k| {
            let (i, j) = ((k % 256) as f64 / 255.0, (k / 256) as f64 / 255.0);
            let target = DVec3::new(
                bb.min.x + i * (bb.max.x - bb.min.x),
                bb.min.y + j * (bb.max.y - bb.min.y),
                bb.centre().z,
            );
            Ray::new(eye, (target - eye).normalize())
        })
        .collect()
}

fn bunny(c: &mut Criterion) {
    let Some(bytes) = bunny_bytes() else { return };
    for accel in [Accel::KdTree, Accel::Bvh] {
        let name = accel.name();
        c.bench_function(&format!("bunny parse + {name} build"), |b| {
            b.iter(|| MeshData::from_bytes_with(black_box(&bytes), accel).unwrap())
        });
        let data = Arc::new(MeshData::from_bytes_with(&bytes, accel).unwrap());
        let mesh = Mesh::new(data.clone(), true, 0);
        let rays = camera_rays(&data);
        c.bench_function(&format!("bunny {name} 65536 nearest hits"), |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|r| mesh.intersect(r, 0.0, f64::INFINITY).is_some())
                    .count()
            })
        });
        c.bench_function(&format!("bunny {name} 65536 occlusion tests"), |b| {
            b.iter(|| {
                rays.iter()
                    .filter(|r| mesh.occludes(r, 0.0, f64::INFINITY))
                    .count()
            })
        });
    }
}

fn triangle_test(c: &mut Criterion) {
    // 1024 blocks of four random small triangles near the origin, and rays
    // through the origin region: about half the lanes hit.
    let mut s = 0x2545f4914f6cdd1du64;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut tris = Vec::new();
    for _ in 0..4096 {
        let c = DVec3::new(rnd(), rnd(), 0.0) * 0.5;
        tris.push([
            c + DVec3::new(rnd(), rnd(), rnd()),
            c + DVec3::new(rnd(), rnd(), rnd()),
            c + DVec3::new(rnd(), rnd(), rnd()),
        ]);
    }
    let blocks: Vec<Block> = tris
        .chunks(4)
        .map(|q| Block::new(std::array::from_fn(|k| Some(q[k]))))
        .collect();
    let singles: Vec<Triangle> = tris
        .iter()
        .map(|t| Triangle::new(t[0], t[1], t[2], 0))
        .collect();
    let ray = Ray::new(DVec3::new(0.1, -0.2, 5.0), DVec3::new(-0.01, 0.02, -1.0));
    let lane = LaneRay::from_ray(&ray);
    for simd in [Simd::Scalar, Simd::Avx2] {
        if simd == Simd::Avx2 && !Simd::avx2_available() {
            continue;
        }
        c.bench_function(&format!("4096 triangles, blocks of 4, {simd:?}"), |b| {
            b.iter(|| {
                blocks
                    .iter()
                    .map(|q| {
                        hits(q, black_box(&lane), 0.0, f64::INFINITY, simd)
                            .0
                            .count_ones()
                    })
                    .sum::<u32>()
            })
        });
    }
    c.bench_function("4096 triangles, one at a time (Triangle::intersect)", |b| {
        b.iter(|| {
            singles
                .iter()
                .filter(|t| t.intersect(black_box(&ray), 0.0, f64::INFINITY).is_some())
                .count()
        })
    });
}

criterion_group! {
    name = bvh;
    config = Criterion::default().sample_size(20);
    targets = triangle_test, bunny
}
criterion_main!(bvh);
