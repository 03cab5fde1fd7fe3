//! The bunny benchmark scene built by hand (the `.rt` parser lives on another
//! branch) and rendered once, for wall-time and peak-memory measurements:
//!
//! ```text
//! cargo bench --bench bunny_render -- [path/to/bunny.ply] [flat] [grid]
//! /usr/bin/time -v target/release/deps/bunny_render-* /work/shared/data/bunny.ply
//! ```
//! Same numbers as `benches/scenes/bunny.rt` (see ../shared/design/benchmarks.md).

use raytrace::accel::World;
use raytrace::geometry::{DVec3, Transform};
use raytrace::render::{RenderOptions, render};
use raytrace::scene::{
    Camera, Colour, Light, Material, Projection, RenderSettings, Scene, Texture, Transfer,
};
use raytrace::shapes::{Mesh, MeshData, Plane, Shape, Transformed};
use std::sync::Arc;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let path = args
        .iter()
        .find(|a| a.ends_with(".ply"))
        .cloned()
        .unwrap_or_else(|| "../shared/data/bunny.ply".into());
    let smooth = !args.iter().any(|a| a == "flat");
    let grid = args.iter().any(|a| a == "grid");
    let size: u32 = std::env::var("SIZE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000);
    let clock = Instant::now();
    let data = match MeshData::load(path.as_ref()) {
        Ok(d) => Arc::new(d),
        Err(e) => {
            eprintln!("cannot load {path}: {e}");
            return;
        }
    };
    let loaded = clock.elapsed().as_secs_f64();
    let mut objects: Vec<Box<dyn Shape>> = Vec::new();
    let place = |t: Transform, m: u32| -> Box<dyn Shape> {
        Box::new(Transformed::new(
            Box::new(Mesh::new(data.clone(), smooth, m)),
            t,
        ))
    };
    let base = Transform::scale(DVec3::splat(20.0))
        .unwrap()
        .then(&Transform::translate(DVec3::new(0.3368, -0.6597, 0.0308)));
    let mut camera = Camera {
        position: DVec3::new(0.0, 2.5, 9.0),
        look_at: DVec3::new(0.0, 1.3, 0.0),
        up: DVec3::Y,
        projection: Projection::Fov(36.0),
    };
    if grid {
        // 17 x 17 bunnies, each shrunk to fit a cell of side 1.
        for i in 0..17 {
            for j in 0..17 {
                let t = base
                    .then(&Transform::scale(DVec3::splat(0.3)).unwrap())
                    .then(&Transform::translate(DVec3::new(
                        i as f64 - 8.0,
                        0.0,
                        j as f64 - 8.0,
                    )));
                objects.push(place(t, 1));
            }
        }
        camera.position = DVec3::new(0.0, 12.0, 16.0);
        camera.look_at = DVec3::new(0.0, 0.0, 0.0);
        camera.projection = Projection::Fov(50.0);
    } else {
        objects.push(place(base, 1));
    }
    objects.push(Box::new(Plane::new(DVec3::Y, 0.0, 2)));
    let scene = Scene {
        camera,
        settings: RenderSettings {
            width: size,
            height: size,
            max_depth: 4,
            background: Colour::new(0.05, 0.05, 0.1),
            transfer: Transfer::Linear,
            samples: 1,
        },
        ambient: Colour::splat(0.1),
        lights: vec![Light {
            position: DVec3::new(5.0, 10.0, 7.0),
            colour: Colour::ONE,
        }],
        materials: vec![
            Material::default(),
            Material {
                texture: Texture::Solid(Colour::splat(0.8)),
                reflect: 0.5,
            },
            Material {
                texture: Texture::Solid(Colour::splat(0.6)),
                reflect: 0.3,
            },
        ],
        objects: Vec::new(),
    };
    let world = World::build(objects);
    let built = clock.elapsed().as_secs_f64();
    let (film, stats) = render(&scene, &world, &RenderOptions { progress: None }).expect("frame");
    let total = clock.elapsed().as_secs_f64();
    let mesh = data.tree_stats();
    eprintln!(
        "load+tree {loaded:.3} s (tree {:.3} s: {} nodes, {} leaves, {} refs, depth {}), world {:.4} s",
        mesh.build_seconds,
        mesh.nodes,
        mesh.leaves,
        mesh.references,
        mesh.max_depth,
        built - loaded
    );
    eprintln!(
        "render {:.3} s, {} rays ({} primary, {} reflected, {} shadow), {:.2} M rays/s; total {total:.3} s",
        stats.seconds,
        stats.rays.total(),
        stats.rays.primary,
        stats.rays.reflected,
        stats.rays.shadow,
        stats.rays.total() as f64 / stats.seconds / 1e6
    );
    eprintln!("mesh data ~{:.1} MiB", data.memory() as f64 / 1048576.0);
    if let Some(out) = args.iter().find(|a| a.ends_with(".png")) {
        let px: Vec<u8> = film
            .pixels
            .iter()
            .flat_map(|p| p.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect();
        image::save_buffer(out, &px, film.width, film.height, image::ColorType::Rgb8)
            .expect("write png");
    }
}
