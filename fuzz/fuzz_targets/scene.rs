//! The scene parser and builder on arbitrary text, with include files: the
//! input is split at lines `#FILE`; the first part is `main.rt`, the next
//! ones `a.rt`, `b.rt`, `c.rt`, written beside it so that `include "a.rt"`
//! finds them. A tiny picture `tex.png` and mesh `cube.ply` sit there too.
//! What builds is accelerated and rendered at 3x2 pixels, so NaN and
//! degenerate geometry reach the shapes, the kd-tree and the shader.
#![no_main]

mod scratch;

use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

fn dir() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = scratch::scratch_path("raytrace-fuzz-scene");
        std::fs::create_dir_all(&d).unwrap();
        let img = image::RgbImage::from_fn(3, 2, |x, y| image::Rgb([x as u8 * 80, y as u8 * 120, 7]));
        img.save(d.join("tex.png")).unwrap();
        std::fs::write(d.join("cube.ply"), CUBE).unwrap();
        d
    })
}

const CUBE: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 1\n3 0 1 2\n3 0 2 3\n";

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let dir = dir();
    let mut parts = text.split("#FILE\n");
    let main = parts.next().unwrap_or("").to_owned();
    for name in ["a.rt", "b.rt", "c.rt"] {
        let p = dir.join(name);
        match parts.next() {
            Some(t) => std::fs::write(&p, t).unwrap(),
            None => {
                let _ = std::fs::remove_file(&p);
            }
        }
    }
    let Ok(program) = raytrace::lang::load_text(&dir.join("main.rt"), main) else {
        return;
    };
    let Ok(mut scene) = raytrace::scene::build(&program) else {
        return;
    };
    scene.settings.width = scene.settings.width.min(3);
    scene.settings.height = scene.settings.height.min(2);
    scene.settings.samples = scene.settings.samples.min(2);
    scene.settings.max_depth = scene.settings.max_depth.min(3);
    let world = raytrace::accel::World::build(std::mem::take(&mut scene.objects));
    let opts = raytrace::render::RenderOptions { progress: None, cancel: None };
    let _ = raytrace::render::render(&scene, &world, &opts);
});
