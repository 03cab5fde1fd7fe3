//! A few small golden images: example scenes rendered at 96x64 and compared
//! with reviewed pictures in tests/golden/, with a tolerance for rounding.
//! `RAYTRACE_UPDATE_GOLDEN=1 cargo test golden` rewrites them (look at the
//! new pictures before committing them).

use crate::support::*;

const SCENES: &[&str] = &["spheres", "primitives", "csg", "textures", "implicit/torus"];

#[test]
fn examples_match_their_golden_images() {
    let _watchdog = crate::watchdog::start();
    let update = std::env::var_os("RAYTRACE_UPDATE_GOLDEN").is_some();
    let mut failures = Vec::new();
    for name in SCENES {
        let scene = project_root().join(format!("examples/{name}.rt"));
        let film = render_path(&scene, Some((96, 64)), 2);
        let program = raytrace::lang::load(&scene).unwrap();
        let transfer = raytrace::scene::build(&program).unwrap().settings.transfer;
        let got = raytrace::output::to_rgb8(&film, transfer);
        let path = project_root().join(format!("tests/golden/{}.png", name.replace('/', "_")));
        if update {
            got.save(&path).unwrap();
            continue;
        }
        let Ok(want) = image::open(&path) else {
            failures.push(format!("{name}: no golden image at {}", path.display()));
            continue;
        };
        let want = want.to_rgb8();
        // Off by a few levels from rounding is fine; a shape moved or a
        // colour changed is not.
        let bad = got
            .pixels()
            .zip(want.pixels())
            .filter(|(a, b)| (0..3).any(|i| (a.0[i] as i32 - b.0[i] as i32).abs() > 4))
            .count();
        if bad > got.len() / 3 / 200 {
            failures.push(format!("{name}: {bad} pixels differ"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
