//! Any shape moved by an affine transform. The ray goes into the shape's
//! space by the inverse (keeping `t`), the normal comes back by the inverse
//! transpose. Nested transforms are composed by the builder, so a shape has
//! at most one of these around it.

use super::{Crossing, Hit, Shape};
use crate::geometry::rounding::{gamma, transform_point_error};
use crate::geometry::{Aabb, Ray, Transform};
use glam::{DMat3, DMat4, DVec3, DVec4};

#[derive(Debug)]
pub struct Transformed {
    pub inner: Box<dyn Shape>,
    pub transform: Transform,
    bounds: Aabb,
    /// For a transform that only scales along the axes and moves (the
    /// bunny's `scale 20 translate ...`, any plain `translate`): the
    /// diagonals and translations of the matrix and its inverse.
    axes: Option<Axes>,
}

/// An axis-aligned transform, x ↦ scale ⊙ x + forward, and its inverse,
/// x ↦ inv ⊙ x + back, each read off its matrix.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Axes {
    scale: DVec3,
    forward: DVec3,
    inv: DVec3,
    back: DVec3,
}

impl Transformed {
    pub fn new(inner: Box<dyn Shape>, transform: Transform) -> Self {
        let bounds = inner.bounds().transformed(&transform);
        Transformed {
            inner,
            axes: Self::axes_of(&transform),
            transform,
            bounds,
        }
    }

    /// The diagonals and translations of a transform whose matrix and
    /// inverse are zero off the diagonal (and plain in the last row),
    /// exactly. Then each coordinate of the matrix products below is one
    /// product and one sum (adding a product by 0 changes nothing but the
    /// sign of a zero), so such a shape skips the matrices with the same
    /// bits, at a fraction of the cost.
    fn axes_of(t: &Transform) -> Option<Axes> {
        let diagonal = |m: &DMat4| DVec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z);
        let plain = |m: &DMat4| {
            DMat3::from_mat4(*m) == DMat3::from_diagonal(diagonal(m)) && m.row(3) == DVec4::W
        };
        (plain(&t.matrix) && plain(&t.inverse)).then(|| Axes {
            scale: diagonal(&t.matrix),
            forward: t.matrix.w_axis.truncate(),
            inv: diagonal(&t.inverse),
            back: t.inverse.w_axis.truncate(),
        })
    }

    #[inline]
    fn local_ray(&self, ray: &Ray) -> Ray {
        if let Some(a) = self.axes {
            // `transform_point3` and `transform_vector3` less the zeros.
            return Ray::new(a.back + a.inv * ray.origin, a.inv * ray.dir);
        }
        Ray::new(
            self.transform.inverse_point(ray.origin),
            self.transform.inverse_vector(ray.dir),
        )
    }

    /// The hit in world space: normals by the inverse transpose, the point
    /// and its error bound forward by the matrix (error grows by |M| and
    /// the product's own rounding, see `transform_point_error`).
    /// In place: a hit is 160 bytes, and each copy on the way out of a
    /// nearest-hit query is a `memcpy`.
    fn to_world(&self, h: &mut Hit) {
        // `Transform::normal` and `transform_point_error` less the zeros
        // along the axes: the inverse transpose of a diagonal is the
        // inverse.
        let normal = |n: DVec3| match self.axes {
            Some(a) => n * a.inv,
            None => self.transform.normal(n),
        };
        // Most shapes give one vector for both normals: map it once.
        let same = h.normal == h.geo_normal;
        h.normal = normal(h.normal);
        h.geo_normal = if same { h.normal } else { normal(h.geo_normal) };
        (h.point, h.p_error) = match self.axes {
            Some(a) => {
                let s = a.scale.abs();
                let mag = s * h.point.abs() + a.forward.abs();
                (
                    a.forward + a.scale * h.point,
                    (gamma(3) + 1.0) * (s * h.p_error) + gamma(3) * mag,
                )
            }
            None => transform_point_error(&self.transform.matrix, h.point, h.p_error),
        };
    }
}

impl Shape for Transformed {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let mut h = self.inner.intersect(&self.local_ray(ray), t_min, t_max)?;
        self.to_world(&mut h);
        Some(h)
    }

    fn intersect_into(&self, ray: &Ray, t_min: f64, t_max: f64, hit: &mut Hit) -> bool {
        if !self
            .inner
            .intersect_into(&self.local_ray(ray), t_min, t_max, hit)
        {
            return false;
        }
        self.to_world(hit);
        true
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.inner.occludes(&self.local_ray(ray), t_min, t_max)
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        let start = out.len();
        self.inner.crossings(&self.local_ray(ray), out);
        for h in &mut out[start..] {
            self.to_world(h);
        }
    }

    /// t and normal·dir are the same in both spaces, so the inner shape's
    /// crossings stand as they are.
    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        self.inner.crossings_lite(&self.local_ray(ray), out);
    }

    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        let mut h = self.inner.hit_of(&self.local_ray(ray), c);
        self.to_world(&mut h);
        h
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn is_solid(&self) -> bool {
        self.inner.is_solid()
    }

    fn encloses(&self, p: crate::geometry::DVec3) -> bool {
        self.inner.encloses(self.transform.inverse_point(p))
    }

    /// `local` is already in the inner shape's space.
    fn uv(&self, hit: &Hit) -> crate::geometry::DVec2 {
        self.inner.uv(hit)
    }

    fn normal_to_world(&self, hit: &Hit, v: crate::geometry::DVec3) -> crate::geometry::DVec3 {
        self.transform.normal(self.inner.normal_to_world(hit, v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DVec3;
    use crate::shapes::Sphere;

    #[test]
    fn scaled_sphere_is_an_ellipsoid() {
        let s = Transformed::new(
            Box::new(Sphere::new(DVec3::ZERO, 1.0, 0)),
            Transform::scale(DVec3::new(2.0, 1.0, 1.0)).unwrap(),
        );
        let r = Ray::new(DVec3::new(5.0, 0.0, 0.0), -DVec3::X);
        let h = s.intersect(&r, 0.0, f64::INFINITY).unwrap();
        assert!((h.t - 3.0).abs() < 1e-12);
        assert!((s.bounds().max - DVec3::new(2.0, 1.0, 1.0)).length() < 1e-12);
        // Normal at (√2, √0.5, 0) on the ellipsoid x²/4 + y² = 1 is ∝ (x/4, y).
        let p = DVec3::new(2f64.sqrt(), 0.5f64.sqrt(), 0.0);
        let r = Ray::new(p * 2.0, -p);
        let h = s.intersect(&r, 0.0, f64::INFINITY).unwrap();
        let expected = DVec3::new(p.x / 4.0, p.y, 0.0).normalize();
        assert!((h.normal.normalize() - expected).length() < 1e-9);
    }

    #[test]
    fn a_moved_shape_is_consistent_by_every_route() {
        // Nearest hit, the in-place nearest hit and the crossings agree
        // for a sphere and a plane seen through a stretch, a turn and a move.
        let m = Transform::scale(DVec3::new(2.0, 1.0, 0.5))
            .unwrap()
            .then(&Transform::rotate(DVec3::new(0.3, 1.0, 0.2), 40.0).unwrap())
            .then(&Transform::translate(DVec3::new(1.0, -2.0, 3.0)));
        let sphere = Transformed::new(Box::new(Sphere::new(DVec3::ZERO, 1.0, 0)), m);
        let target = DVec3::new(1.0, -2.0, 3.0);
        crate::shapes::testing::check_consistency(
            &sphere,
            &crate::shapes::testing::rays_towards(target, 2.5, 400, 5),
        );
        let plane = Transformed::new(Box::new(crate::shapes::Plane::new(DVec3::Y, 0.5, 0)), m);
        crate::shapes::testing::check_consistency(
            &plane,
            &crate::shapes::testing::rays_towards(target, 3.0, 400, 6),
        );
    }

    #[test]
    fn a_shape_scaled_and_moved_along_the_axes_skips_the_matrices_with_the_same_bits() {
        // A torus (solved in its own space, so any change in the local ray
        // shows in its roots), a box, a sphere (whose normal is not unit,
        // so the normal's mapping shows) and a smooth mesh (whose shading
        // normal is not its geometric one), moved, scaled along the axes
        // (evenly, as the bunny is, unevenly, and mirrored) and both: the
        // shortcut gives every hit exactly as the matrices do.
        let by = DVec3::new(0.37, -1.3, 2.9);
        let shapes: [fn() -> Box<dyn Shape>; 4] = [
            || Box::new(crate::shapes::Torus::new(1.0, 0.3, 0)),
            || {
                Box::new(crate::shapes::Cuboid::new(
                    DVec3::splat(-0.5),
                    DVec3::new(0.7, 0.4, 0.9),
                    [0; 6],
                ))
            },
            || Box::new(Sphere::new(DVec3::new(0.1, 0.0, -0.2), 0.8, 0)),
            || {
                let data = crate::shapes::mesh::tests::sphere_mesh(1);
                Box::new(crate::shapes::Mesh::new(data, true, 0))
            },
        ];
        let scale = |v: DVec3| Transform::scale(v).unwrap();
        let transforms = [
            Transform::translate(by),
            scale(DVec3::splat(20.0)).then(&Transform::translate(by)),
            scale(DVec3::new(0.3, 1.7, 2.5)).then(&Transform::translate(by)),
            scale(DVec3::new(-1.0, 0.5, 1.0)),
        ];
        for t in transforms {
            for make in shapes {
                let quick = Transformed::new(make(), t);
                assert!(quick.axes.is_some());
                let mut full = Transformed::new(make(), t);
                full.axes = None;
                // Rays about the unit shape, carried along with it.
                let rays = crate::shapes::testing::rays_towards(DVec3::ZERO, 1.5, 600, 11);
                let reach = 20.0 * t.vector(DVec3::ONE).abs().max_element();
                let (mut hits, mut misses) = (0, 0);
                for r in rays {
                    let ray = Ray::new(t.point(r.origin), t.vector(r.dir).normalize());
                    let (a, b) = (
                        quick.intersect(&ray, 0.0, f64::INFINITY),
                        full.intersect(&ray, 0.0, f64::INFINITY),
                    );
                    match (a, b) {
                        (Some(a), Some(b)) => {
                            hits += 1;
                            assert_eq!(
                                (a.t, a.point, a.p_error, a.normal, a.geo_normal, a.local),
                                (b.t, b.point, b.p_error, b.normal, b.geo_normal, b.local)
                            );
                        }
                        (None, None) => misses += 1,
                        _ => panic!("{ray:?}: one found a hit, the other none"),
                    }
                    assert_eq!(
                        quick.occludes(&ray, 0.0, reach),
                        full.occludes(&ray, 0.0, reach)
                    );
                }
                assert!(hits > 100 && misses > 20, "{hits} {misses}");
            }
        }
        // A turn, or a move after a turn, is not along the axes.
        for t in [
            Transform::rotate(DVec3::Y, 30.0).unwrap(),
            Transform::rotate(DVec3::X, 10.0)
                .unwrap()
                .then(&Transform::translate(by)),
            scale(DVec3::new(1.0, 2.0, 1.0)).then(&Transform::rotate(DVec3::Z, 90.0).unwrap()),
        ] {
            let s = Transformed::new(Box::new(Sphere::new(DVec3::ZERO, 1.0, 0)), t);
            assert!(s.axes.is_none());
        }
    }

    #[test]
    fn shadows_insides_and_solidity_move_with_the_shape() {
        // A unit sphere stretched ×2 along x and moved to x = 10: a shadow
        // ray is blocked where the ellipsoid lies, and nowhere else.
        let xf = Transform::scale(DVec3::new(2.0, 1.0, 1.0))
            .unwrap()
            .then(&Transform::translate(DVec3::new(10.0, 0.0, 0.0)));
        let s = Transformed::new(Box::new(Sphere::new(DVec3::ZERO, 1.0, 0)), xf);
        assert!(s.is_solid());
        let down = |x: f64| Ray::new(DVec3::new(x, 5.0, 0.0), -DVec3::Y);
        assert!(
            s.occludes(&down(11.5), 0.0, 9.0),
            "inside the stretched x range"
        );
        assert!(
            !s.occludes(&down(0.0), 0.0, 9.0),
            "where the unmoved sphere was"
        );
        assert!(!s.occludes(&down(12.5), 0.0, 9.0));
        assert!(!s.occludes(&down(11.5), 0.0, 3.0), "short of it");
        // An open shape stays open.
        let d = Transformed::new(Box::new(crate::shapes::Disc::new(DVec3::ZERO, 1.0, 0)), xf);
        assert!(!d.is_solid());
        // A half-space (the one kind that answers `encloses`) moved with
        // it: z < 0.5 before; x, y free; after the move z is unchanged.
        let h = Transformed::new(
            Box::new(crate::shapes::Plane::new(DVec3::Z, 0.5, 0)),
            Transform::translate(DVec3::new(0.0, 0.0, 2.0)),
        );
        assert!(h.encloses(DVec3::new(0.0, 0.0, 2.4)));
        assert!(!h.encloses(DVec3::new(0.0, 0.0, 2.6)));
    }

    #[test]
    fn a_smooth_meshs_two_normals_move_each_by_the_inverse_transpose() {
        // A smooth icosphere's hit has a shading normal (interpolated)
        // and a geometric one (its face's): moved, each must be the moved
        // version of its own, not one copied into the other.
        use crate::shapes::{Mesh, MeshData};
        let (p, t) = crate::formats::ply::icosphere(1);
        let data = std::sync::Arc::new(MeshData::from_parts(p, None, None, t));
        let mesh = Mesh::new(data.clone(), true, 0);
        let xf = Transform::scale(DVec3::new(3.0, 1.0, 0.5)).unwrap();
        let moved = Transformed::new(Box::new(Mesh::new(data, true, 0)), xf);
        let from = DVec3::new(0.31, 0.17, 5.0);
        let local = Ray::new(from, (DVec3::new(0.45, 0.33, 0.0) - from).normalize());
        let h = mesh.intersect(&local, 0.0, 1e9).unwrap();
        assert!((h.normal.normalize() - h.geo_normal.normalize()).length() > 1e-3);
        let world = Ray::new(xf.point(local.origin), xf.vector(local.dir));
        let w = moved.intersect(&world, 0.0, 1e9).unwrap();
        let same = |a: DVec3, b: DVec3| (a.normalize() - b.normalize()).length() < 1e-9;
        assert!(same(w.normal, xf.normal(h.normal)));
        assert!(same(w.geo_normal, xf.normal(h.geo_normal)));
    }
}
