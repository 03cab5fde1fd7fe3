//! Every example scene renders at a small size and shows something.

use crate::support::*;

#[test]
fn every_example_renders() {
    let dir = project_root().join("examples");
    let mut scenes: Vec<_> = walk(&dir)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "rt"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 4, "{scenes:?}");
    for path in scenes {
        let film = render_path(&path, Some((48, 32)), 2);
        let first = film.pixels[0];
        let varied = film.pixels.iter().filter(|p| **p != first).count();
        assert!(varied > 48, "{} is nearly blank", path.display());
    }
}

fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}
