//! The acceleration structures end to end: `--accel` and `render { accel }`
//! choose the kd-tree or the wide BVH, both give byte-identical pictures,
//! `--stats` reports the one chosen, and a misspelt name is a diagnostic.

use crate::support::{build_error, project_root, render_to, scene_file, stderr};

/// Icospheres (flat and smooth, one of them reflective) and spheres on a
/// floor, lit by a point light: mesh hits, shadow rays through meshes and
/// the scene-level structure all matter to the picture.
fn scene(render_extra: &str) -> String {
    let ico = project_root().join("examples/meshes/icosphere.ply");
    let ico = ico.display();
    format!(
        r#"
camera {{ position <0, 2, 7>  look_at <0, 0.6, 0>  fov 45 }}
render {{ width 96  height 72  max_depth 3  {render_extra} }}
light {{ position <4, 8, 5>  intensity 0.9 }}
ambient rgb(1, 1, 1) intensity 0.1
plane {{ normal <0, 1, 0>  offset -0.5  material {{ colour rgb(0.6, 0.6, 0.6) }} }}
mesh "{ico}" {{ smooth  translate <-1.2, 0.6, 0>  material {{ colour rgb(0.8, 0.3, 0.2)  reflect 0.4 }} }}
mesh "{ico}" {{ flat  scale 0.6  translate <1.2, 0.2, 0.5> }}
mesh "{ico}" {{ smooth  scale 0.4  translate <0, 1.8, -1> }}
sphere {{ centre <0, 0, 1>  radius 0.4  material {{ colour rgb(0.2, 0.5, 0.9) }} }}
sphere {{ centre <0.5, 0.3, -1.5>  radius 0.5 }}
"#
    )
}

#[test]
fn kd_tree_and_bvh_give_the_same_picture() {
    let _watchdog = crate::watchdog::start();
    let (dir, path) = scene_file(&scene(""));
    let mut pictures = Vec::new();
    for (flags, line) in [
        (["--accel", "kdtree", "--stats"], "meshes"),
        (["--accel", "bvh", "--stats"], "mesh bvh"),
    ] {
        let out = dir.path().join(format!("{}.png", flags[1]));
        let o = render_to(&path, &out, &flags);
        assert!(o.status.success(), "{}", stderr(&o));
        // --stats names the structure the meshes were given.
        assert!(stderr(&o).contains(line), "{flags:?}: {}", stderr(&o));
        pictures.push(std::fs::read(&out).unwrap());
    }
    assert!(
        pictures[0] == pictures[1],
        "the two structures drew different pictures"
    );
    // Not a blank picture: the meshes are there.
    let img = image::load_from_memory(&pictures[1]).unwrap().to_rgb8();
    let distinct: std::collections::HashSet<_> = img.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 50, "{}", distinct.len());
}

#[test]
fn the_scene_chooses_and_the_command_line_overrides() {
    let _watchdog = crate::watchdog::start();
    let (dir, path) = scene_file(&scene("accel kdtree"));
    let out = dir.path().join("a.png");
    let o = render_to(&path, &out, &["--stats"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("mesh bvh"), "{}", stderr(&o));
    let o = render_to(&path, &out, &["--stats", "--accel", "bvh"]);
    assert!(stderr(&o).contains("mesh bvh"), "{}", stderr(&o));
    // The default, `auto`: the BVH for the meshes, the kd-tree for the
    // scene's objects.
    let (dir, path) = scene_file(&scene(""));
    let o = render_to(&path, &dir.path().join("a.png"), &["--stats"]);
    let e = stderr(&o);
    assert!(e.contains("mesh bvh"), "{e}");
    assert!(
        e.contains("scene BVH 0 B") && e.contains("mesh trees 0 B"),
        "{e}"
    );
    assert!(!e.contains("scene tree 0 B"), "{e}");
}

#[test]
fn a_misspelt_structure_is_a_diagnostic() {
    let e = build_error("render { accel bvhh }");
    assert!(e.contains("unknown acceleration structure"), "{e}");
    assert!(e.contains("did you mean `bvh`?"), "{e}");
    let e = build_error("render { accel 3 }");
    assert!(e.contains("unknown acceleration structure"), "{e}");
    let (dir, path) = scene_file(&scene(""));
    let o = render_to(&path, &dir.path().join("a.png"), &["--accel", "octree"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("kdtree"), "{}", stderr(&o));
}
