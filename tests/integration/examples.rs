//! Every example scene renders at a small size and shows something.

use crate::support::*;
use std::path::Path;

#[test]
fn every_example_renders() {
    let _watchdog = crate::watchdog::start();
    let dir = project_root().join("examples");
    let mut scenes: Vec<_> = walk(&dir)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "rt"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 4, "{scenes:?}");
    let mut rendered = 0;
    let total = scenes.len();
    for path in scenes {
        // A scene that needs a file the project does not ship says so in a
        // `// requires: PATH` line (relative to the scene); such a file is
        // taken from the shared data folder when it is not in the tree.
        let text = std::fs::read_to_string(&path).unwrap();
        let missing: Vec<&str> = text
            .lines()
            .filter_map(|l| l.strip_prefix("// requires: "))
            .map(str::trim)
            .filter(|r| !path.parent().unwrap().join(r).exists())
            .collect();
        let _staged;
        let path = if missing.is_empty() {
            path
        } else {
            let Some(dir) = stage_with_shared(&path, &missing) else {
                continue;
            };
            let scene = dir.path().join(path.file_name().unwrap());
            _staged = dir;
            scene
        };
        rendered += 1;
        let film = render_path(&path, Some((48, 32)), 2);
        let first = film.pixels[0];
        let varied = film.pixels.iter().filter(|p| **p != first).count();
        assert!(varied > 48, "{} is nearly blank", path.display());
    }
    // Only an explicit RAYTRACE_SKIP_SHARED=1 lets a scene go unrendered.
    assert!(rendered == total || crate::shared_data::skip_allowed());
}

/// A temporary copy of the scene's folder (links to its entries) in which
/// each missing required file links to the shared data file of the same
/// name; `None` when one is absent there and skipping is allowed.
fn stage_with_shared(scene: &Path, missing: &[&str]) -> Option<tempfile::TempDir> {
    let dir = tempfile::tempdir().expect("temp dir");
    for e in std::fs::read_dir(scene.parent().unwrap())
        .unwrap()
        .flatten()
    {
        link(&e.path(), &dir.path().join(e.file_name()));
    }
    for rel in missing {
        let name = Path::new(rel).file_name().unwrap().to_str().unwrap();
        let shared = crate::shared_data::file(name)?;
        let at = dir.path().join(rel);
        std::fs::create_dir_all(at.parent().unwrap()).unwrap();
        link(&shared, &at);
    }
    Some(dir)
}

fn link(from: &Path, to: &Path) {
    if !to.exists() {
        std::os::unix::fs::symlink(from, to)
            .unwrap_or_else(|e| panic!("link {} -> {}: {e}", to.display(), from.display()));
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
