//! Meshes end to end: the example icosphere the project writes itself, PLY
//! files on disk, and instancing through `Transformed`.

use raytrace::accel::World;
use raytrace::geometry::{DVec3, Ray, Transform};
use raytrace::shapes::ply::{icosphere, write_ascii};
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
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/icosphere.ply");
    let want = icosphere_ply();
    match std::fs::read_to_string(&path) {
        Ok(have) => assert!(
            have == want,
            "examples/meshes/icosphere.ply is stale: delete it and rerun the tests"
        ),
        Err(_) => std::fs::write(&path, &want).expect("write the example icosphere"),
    }
    let d = MeshData::load(&path).unwrap();
    assert_eq!(d.triangle_count(), 1280);
    assert!(d.is_closed());
}

#[test]
fn meshes_load_from_disk_with_crlf_and_report_bad_files() {
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
