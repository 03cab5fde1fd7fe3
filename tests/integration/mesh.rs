//! Meshes end to end: the example icosphere the project writes itself, PLY
//! files on disk, and instancing through `Transformed`.

use raytrace::accel::World;
use raytrace::formats::ply::{icosphere, write_ascii};
use raytrace::geometry::{DVec3, Ray, Transform};
use raytrace::shapes::{Mesh, MeshData, Shape, Sphere, Transformed};
use std::path::Path;
use std::sync::Arc;

/// The icosphere of `examples/meshes/` (3 subdivisions, 1280 triangles).
fn icosphere_ply() -> String {
    let (p, t) = icosphere(3);
    let faces: Vec<Vec<u32>> = t.iter().map(|f| f.to_vec()).collect();
    write_ascii(&p, &faces)
}

#[test]
fn example_icosphere_is_generated_by_the_project() {
    let _watchdog = crate::watchdog::start();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/icosphere.ply");
    let want = icosphere_ply();
    // Written only on request: a fixture written when missing would then be
    // compared with itself, and the test could not fail.
    if crate::support::regenerate_fixtures() {
        std::fs::write(&path, &want).expect("write the example icosphere");
    }
    let have = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "examples/meshes/icosphere.ply: {e}; run the tests with \
             RAYTRACE_REGENERATE_FIXTURES=1 to write it"
        )
    });
    assert!(
        have == want,
        "examples/meshes/icosphere.ply is stale: rerun the tests with \
         RAYTRACE_REGENERATE_FIXTURES=1 to rewrite it"
    );
    let d = MeshData::load(&path).unwrap();
    assert_eq!(d.triangle_count(), 1280);
    assert!(d.is_closed());
}

#[test]
fn meshes_load_from_disk_with_crlf_and_report_bad_files() {
    let _watchdog = crate::watchdog::start();
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.ply");
    std::fs::write(&good, icosphere_ply().replace('\n', "\r\n")).unwrap();
    assert_eq!(MeshData::load(&good).unwrap().triangle_count(), 1280);
    let bad = dir.path().join("bad.ply");
    let text = icosphere_ply().replacen("3 0 ", "3 99999 ", 1);
    std::fs::write(&bad, text).unwrap();
    let e = MeshData::load(&bad).unwrap_err();
    assert!(e.message.contains("out of range"), "{e}");
    assert!(
        e.line.is_some() && e.element.as_deref() == Some("face 0"),
        "{e:?}"
    );
    assert!(e.to_string().contains("line"), "{e}");
}

#[test]
fn placed_instances_match_a_moved_sphere() {
    let _watchdog = crate::watchdog::start();
    let data = Arc::new(MeshData::from_bytes(icosphere_ply().as_bytes()).unwrap());
    let mut objects: Vec<Box<dyn Shape>> = Vec::new();
    for i in 0..5 {
        let t = Transform::scale(DVec3::splat(0.5))
            .unwrap()
            .then(&Transform::translate(DVec3::new(i as f64 * 2.0, 0.0, 0.0)));
        objects.push(Box::new(Transformed::new(
            Box::new(Mesh::new(data.clone(), true, 1)),
            t,
        )));
    }
    assert_eq!(
        Arc::strong_count(&data),
        6,
        "one MeshData shared by every placement"
    );
    let world = World::build(objects);
    for i in 0..5 {
        let centre = DVec3::new(i as f64 * 2.0, 0.0, 0.0);
        let exact = Sphere::new(centre, 0.5, 1);
        for k in 0..20 {
            let off = DVec3::new(0.0, (k as f64 - 10.0) * 0.045, 0.0);
            let ray = Ray::new(centre + off + DVec3::new(0.0, 0.0, 5.0), -DVec3::Z);
            let a = world.intersect(&ray, 0.0, f64::INFINITY);
            let b = exact.intersect(&ray, 0.0, f64::INFINITY);
            assert_eq!(a.is_some(), b.is_some(), "instance {i} ray {k}");
            if let (Some(a), Some(b)) = (a, b) {
                assert!((a.t - b.t).abs() < 0.02, "{} vs {}", a.t, b.t);
                assert!(a.normal.normalize().dot(b.normal.normalize()) > 0.99);
            }
        }
    }
}

/// The same triangles, once as a `mesh` and once as `triangle` objects,
/// draw the same picture (flat shading: both use each face's own normal).
#[test]
fn a_mesh_and_its_triangles_give_the_same_picture() {
    let _watchdog = crate::watchdog::start();
    let (p, t) = icosphere(2);
    // Squash and tilt it so that no face is axis-aligned by accident.
    let p: Vec<DVec3> = p
        .iter()
        .map(|v| DVec3::new(v.x * 1.3 + 0.2 * v.y, v.y * 0.8, v.z) + DVec3::new(0.0, 1.0, 0.0))
        .collect();
    let faces: Vec<Vec<u32>> = t.iter().map(|f| f.to_vec()).collect();
    let head = "camera { position <0.5, 2, 5>  look_at <0, 1, 0>  fov 40 }\n\
                render { width 96  height 96  max_depth 2 }\n\
                light { position <4, 6, 5> }\n\
                material m { colour rgb(0.8, 0.5, 0.3)  reflect 0.2 }\n\
                plane { normal <0, 1, 0>  material { colour rgb(0.6, 0.6, 0.6)  reflect 0.3 } }\n";
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("shape.ply"), write_ascii(&p, &faces)).unwrap();
    let mesh_scene = dir.path().join("mesh.rt");
    std::fs::write(
        &mesh_scene,
        format!("{head}mesh \"shape.ply\" {{ flat  material m }}\n"),
    )
    .unwrap();
    let mut tris = String::from(head);
    for f in &t {
        let [a, b, c] = f.map(|k| p[k as usize]);
        let v = |q: DVec3| format!("<{:?}, {:?}, {:?}>", q.x, q.y, q.z);
        tris += &format!(
            "triangle {{ a {}  b {}  c {}  material m }}\n",
            v(a),
            v(b),
            v(c)
        );
    }
    let tri_scene = dir.path().join("triangles.rt");
    std::fs::write(&tri_scene, tris).unwrap();

    let a = super::support::render_path(&mesh_scene, None, 2);
    let b = super::support::render_path(&tri_scene, None, 2);
    let floor_only = super::support::render_path(
        &{
            let f = dir.path().join("floor.rt");
            std::fs::write(&f, head).unwrap();
            f
        },
        None,
        2,
    );
    // The shape covers a good part of the picture...
    let covered = a
        .pixels
        .iter()
        .zip(&floor_only.pixels)
        .filter(|(p, q)| p != q)
        .count();
    assert!(
        covered > a.pixels.len() / 10,
        "only {covered} pixels show it"
    );
    // ...and both ways agree everywhere but, at most, a few pixels whose ray
    // grazes an edge shared by two faces (either face may then be taken).
    let differ = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| (0..3).any(|i| (p[i] - q[i]).abs() > 1e-4))
        .count();
    assert!(differ <= a.pixels.len() / 500, "{differ} pixels differ");
}
