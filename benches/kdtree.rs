//! kd-tree build for the bunny and traversal of its triangles (criterion).
//! Needs `../shared/data/bunny.ply` (or `BUNNY=path`); skips without it.

use criterion::{Criterion, criterion_group, criterion_main};
use raytrace::geometry::{DVec3, Ray};
use raytrace::shapes::{Mesh, MeshData, Shape};
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

fn benches(c: &mut Criterion) {
    let Some(bytes) = bunny_bytes() else { return };
    c.bench_function("bunny ply parse + kd-tree build", |b| {
        b.iter(|| MeshData::from_bytes(black_box(&bytes)).unwrap())
    });
    let data = Arc::new(MeshData::from_bytes(&bytes).unwrap());
    let boxes: Vec<_> = (0..data.triangle_count())
        .map(|i| {
            let [a, b, c] = data.triangle(i);
            raytrace::geometry::Aabb::new(a, b).grow(c)
        })
        .collect();
    c.bench_function("bunny kd-tree build", |b| {
        b.iter(|| raytrace::accel::KdTree::build(black_box(&boxes)))
    });
    // A 256x256 grid of camera rays through the bunny's box.
    let mesh = Mesh::new(data.clone(), true, 0);
    let bb = data.bounds();
    let eye = bb.centre() + DVec3::new(0.0, 0.05, 0.4);
    let rays: Vec<Ray> = (0..256 * 256)
        .map(|k| {
            let (i, j) = ((k % 256) as f64 / 255.0, (k / 256) as f64 / 255.0);
            let target = DVec3::new(
                bb.min.x + i * (bb.max.x - bb.min.x),
                bb.min.y + j * (bb.max.y - bb.min.y),
                bb.centre().z,
            );
            Ray::new(eye, (target - eye).normalize())
        })
        .collect();
    c.bench_function("bunny 65536 nearest hits", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| mesh.intersect(r, 0.0, f64::INFINITY).is_some())
                .count()
        })
    });
    c.bench_function("bunny 65536 occlusion tests", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|r| mesh.occludes(r, 0.0, f64::INFINITY))
                .count()
        })
    });
}

criterion_group! {
    name = kdtree;
    config = Criterion::default().sample_size(20);
    targets = benches
}
criterion_main!(kdtree);
