//! Secondary rays leave every kind of surface cleanly at any scale and any
//! distance from the origin: spawned by `offset_ray_origin` from a hit's
//! point, error bound and geometric normal, a ray heading above the surface
//! (straight out, at 26° and at 3° to it) never meets that surface again
//! at the point it left.

use super::*;
use crate::geometry::{Transform, offset_ray_origin};
use crate::implicit::{Equation, ImplicitSurface};
use std::sync::Arc;

/// Every shape kind, unit-sized around the origin, with its name.
fn kinds() -> Vec<(&'static str, Box<dyn Shape>)> {
    let compile = |s: &str| Equation::compile(s, &|_| None).expect("compiles");
    let (p, t) = crate::formats::ply::icosphere(1);
    let ico = Arc::new(MeshData::from_parts(p, None, None, t));
    let cube = |lo: f64, hi: f64| Cuboid::new(DVec3::splat(lo), DVec3::splat(hi), [0; 6]);
    vec![
        (
            "sphere",
            Box::new(Sphere::new(DVec3::new(0.1, -0.2, 0.3), 1.0, 0)),
        ),
        (
            "plane",
            Box::new(Plane::new(DVec3::new(0.3, 1.0, -0.2), 0.4, 0)),
        ),
        (
            "disc",
            Box::new(Disc::new(DVec3::new(0.1, 0.0, 0.2), 1.0, 0)),
        ),
        (
            "rectangle",
            Box::new(Rectangle::new(
                DVec3::new(-1.0, -1.0, 0.1),
                DVec3::new(-0.8, 1.0, 0.3),
                DVec3::new(1.0, -1.0, -0.2),
                0,
            )),
        ),
        (
            "triangle",
            Box::new(Triangle::new(
                DVec3::new(-1.0, -1.0, 0.2),
                DVec3::new(1.0, -0.7, -0.1),
                DVec3::new(0.1, 1.0, 0.3),
                0,
            )),
        ),
        ("box", Box::new(cube(-0.7, 0.9))),
        (
            "cylinder",
            Box::new(Cone::new(DVec3::ZERO, 0.8, 0.8, 1.6, 0, Some([0, 0]))),
        ),
        (
            "cone",
            Box::new(Cone::new(DVec3::ZERO, 1.0, 0.0, 1.8, 0, Some([0, 0]))),
        ),
        ("torus", Box::new(Torus::new(0.8, 0.3, 0))),
        ("flat mesh", Box::new(Mesh::new(ico.clone(), false, 0))),
        ("smooth mesh", Box::new(Mesh::new(ico, true, 0))),
        (
            "heart",
            Box::new(ImplicitSurface::new(
                compile("(x^2 + 9/4 y^2 + z^2 - 1)^3 - x^2 z^3 - 9/80 y^2 z^3"),
                Some(Aabb::new(
                    DVec3::new(-1.25, -0.75, -1.05),
                    DVec3::new(1.25, 0.75, 1.3),
                )),
                0,
            )),
        ),
        (
            "power cube",
            Box::new(ImplicitSurface::new(
                compile("x^8 + y^8 + z^8 - 1"),
                Some(Aabb::new(DVec3::splat(-1.01), DVec3::splat(1.01))),
                0,
            )),
        ),
        (
            "csg",
            Box::new(Csg::new(
                CsgOp::Difference,
                vec![
                    Box::new(cube(-0.8, 0.8)),
                    Box::new(Sphere::new(DVec3::new(0.5, 0.5, 0.5), 0.7, 0)),
                ],
            )),
        ),
    ]
}

/// The scales and offsets the issue names: 1e-6 … 1e4, up to 1e6 away.
const PLACES: [(f64, f64); 7] = [
    (1.0, 0.0),
    (1e-6, 0.0),
    (1e4, 0.0),
    (1.0, 1e6),
    (1e-2, 1e5),
    (1e-6, 1e6),
    (1e3, -1e6),
];

/// Re-hits of a secondary ray closer than `1e-4 · scale` to where it left.
fn self_hits(shape: &'static dyn Shape, scale: f64, offset: DVec3) -> (usize, usize) {
    let xf = Transform::scale(DVec3::splat(scale))
        .unwrap()
        .then(&Transform::translate(offset));
    let placed = Transformed::new(Box::new(testing::Bare(shape)), xf);
    let (mut bad, mut tried) = (0, 0);
    for r in testing::rays_towards(DVec3::ZERO, 1.0, 400, 77) {
        let ray = Ray::new(xf.point(r.origin), xf.vector(r.dir).normalize());
        let Some(h) = placed.intersect(&ray, 0.0, f64::INFINITY) else {
            continue;
        };
        let mut ng = h.geo_normal.normalize();
        if ng.dot(ray.dir) > 0.0 {
            ng = -ng;
        }
        let side = ng.any_orthonormal_vector();
        for dir in [
            ng,
            (ng + 2.0 * side).normalize(),
            (0.05 * ng + side).normalize(),
        ] {
            tried += 1;
            let o = offset_ray_origin(h.point, h.p_error, h.geo_normal, dir);
            if let Some(again) = placed.intersect(&Ray::new(o, dir), 0.0, f64::INFINITY)
                && again.t < 1e-4 * scale
            {
                bad += 1;
            }
        }
    }
    (bad, tried)
}

#[test]
fn secondary_rays_never_rehit_the_surface_they_leave() {
    let _watchdog = crate::watchdog::start();
    let kinds: &'static [(&'static str, Box<dyn Shape>)] = Vec::leak(kinds());
    let mut report = Vec::new();
    for (name, shape) in kinds {
        for (scale, off) in PLACES {
            let offset = DVec3::new(off, -0.6 * off, 0.3 * off);
            let (bad, tried) = self_hits(shape.as_ref(), scale, offset);
            assert!(tried > 100, "{name}: only {tried} hits");
            if bad > 0 {
                report.push(format!(
                    "{name} at scale {scale:e}, offset {off:e}: {bad}/{tried}"
                ));
            }
        }
    }
    assert!(
        report.is_empty(),
        "self-intersections:\n{}",
        report.join("\n")
    );
}
