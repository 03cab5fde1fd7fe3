use glam::{DMat3, DMat4, DVec3, DVec4};

/// An affine transform with its inverse kept beside it, so that rays go into
/// object space and normals come out (by the inverse transpose) without
/// inverting per ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub matrix: DMat4,
    pub inverse: DMat4,
}

impl Default for Transform {
    fn default() -> Self {
        Transform::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        matrix: DMat4::IDENTITY,
        inverse: DMat4::IDENTITY,
    };

    /// `None` when the matrix is singular (e.g. `scale 0`) or not finite.
    pub fn from_matrix(matrix: DMat4) -> Option<Transform> {
        let det = matrix.determinant();
        if !det.is_finite() || det.abs() < 1e-300 {
            return None;
        }
        let inverse = matrix.inverse();
        inverse.is_finite().then_some(Transform { matrix, inverse })
    }

    pub fn translate(v: DVec3) -> Transform {
        Transform {
            matrix: DMat4::from_translation(v),
            inverse: DMat4::from_translation(-v),
        }
    }

    /// Rotation by `degrees` about `axis` (right-handed, counter-clockwise
    /// looking down the axis towards the origin).
    pub fn rotate(axis: DVec3, degrees: f64) -> Option<Transform> {
        let axis = axis.try_normalize()?;
        let m = DMat4::from_axis_angle(axis, degrees.to_radians());
        Some(Transform {
            matrix: m,
            inverse: m.transpose(),
        })
    }

    pub fn scale(s: DVec3) -> Option<Transform> {
        Transform::from_matrix(DMat4::from_scale(s))
    }

    /// `shear AB d` moves coordinate B by d times coordinate A
    /// (the course's convention: `xy` gives y' = y + d·x).
    pub fn shear(from: usize, to: usize, d: f64) -> Transform {
        let mut m = DMat4::IDENTITY;
        // Column `from`, row `to`.
        m.col_mut(from)[to] = d;
        let mut inv = DMat4::IDENTITY;
        inv.col_mut(from)[to] = -d;
        Transform {
            matrix: m,
            inverse: inv,
        }
    }

    /// Reflection in the plane where coordinate `axis` is zero.
    pub fn mirror(axis: usize) -> Transform {
        let mut s = DVec3::ONE;
        s[axis] = -1.0;
        let m = DMat4::from_scale(s);
        Transform {
            matrix: m,
            inverse: m,
        }
    }

    /// First `self`, then `next` (transforms compose in the order written).
    pub fn then(&self, next: &Transform) -> Transform {
        // Most objects have no transform and sit at the top level: the
        // identity after the identity is the identity, bit for bit,
        // without two matrix products (100,000 times in a loop-built scene).
        if self.is_identity_both_ways() && next.is_identity_both_ways() {
            return Transform::IDENTITY;
        }
        Transform {
            matrix: next.matrix * self.matrix,
            inverse: self.inverse * next.inverse,
        }
    }

    pub fn is_identity(&self) -> bool {
        self.matrix == DMat4::IDENTITY
    }

    /// The identity and its inverse the identity, bit for bit (compared
    /// as bits: 32 float compares cost as much as the product saved), in
    /// place and stopping at the first difference (copying both matrices
    /// out as arrays of bits first made this a twentieth of `many`'s
    /// building).
    fn is_identity_both_ways(&self) -> bool {
        let identity = |m: &DMat4| {
            m.as_ref()
                .iter()
                .zip(DMat4::IDENTITY.as_ref())
                .all(|(a, b)| a.to_bits() == b.to_bits())
        };
        identity(&self.matrix) && identity(&self.inverse)
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.matrix.transform_point3(p)
    }

    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.matrix.transform_vector3(v)
    }

    pub fn inverse_point(&self, p: DVec3) -> DVec3 {
        self.inverse.transform_point3(p)
    }

    pub fn inverse_vector(&self, v: DVec3) -> DVec3 {
        self.inverse.transform_vector3(v)
    }

    /// Object-space normal to world space: the inverse transpose, so that
    /// normals stay perpendicular under non-uniform scale and shear.
    /// Not normalised.
    pub fn normal(&self, n: DVec3) -> DVec3 {
        let inv3 = DMat3::from_mat4(self.inverse);
        inv3.transpose() * n
    }

    /// The upper 3x4 rows as written in `matrix [ ... ]`.
    pub fn from_rows(rows: [f64; 12]) -> Option<Transform> {
        let r = rows;
        let m = DMat4::from_cols(
            DVec4::new(r[0], r[4], r[8], 0.0),
            DVec4::new(r[1], r[5], r[9], 0.0),
            DVec4::new(r[2], r[6], r[10], 0.0),
            DVec4::new(r[3], r[7], r[11], 1.0),
        );
        Transform::from_matrix(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn the_identity_composes_to_what_is_on_either_side() {
        let i = Transform::IDENTITY;
        assert_eq!(i.then(&i), i);
        // Positive entries and +0s, so the products are exact.
        let t = Transform::translate(DVec3::new(1.0, 2.0, 3.0))
            .then(&Transform::scale(DVec3::new(2.0, 4.0, 0.5)).unwrap());
        assert!(!t.is_identity());
        assert_eq!(t.then(&i), t);
        assert_eq!(i.then(&t), t);
        // Only the matrix is the identity: not taken for the identity.
        let odd = Transform {
            matrix: DMat4::IDENTITY,
            inverse: t.inverse,
        };
        assert_eq!(odd.then(&i).inverse, t.inverse);
        assert_eq!(i.then(&odd).inverse, t.inverse);
    }

    #[test]
    fn order_is_as_written() {
        // Translate then rotate: the point swings around the origin.
        let t = Transform::translate(DVec3::X).then(&Transform::rotate(DVec3::Z, 90.0).unwrap());
        assert!(close(t.point(DVec3::ZERO), DVec3::Y));
        assert!(close(t.inverse_point(DVec3::Y), DVec3::ZERO));
    }

    #[test]
    fn shear_follows_course_convention() {
        // xy: y' = y + d·x
        let s = Transform::shear(0, 1, 0.5);
        assert!(close(
            s.point(DVec3::new(2.0, 1.0, 0.0)),
            DVec3::new(2.0, 2.0, 0.0)
        ));
        // zx: x' = x + d·z
        let s = Transform::shear(2, 0, 2.0);
        assert!(close(
            s.point(DVec3::new(0.0, 0.0, 1.0)),
            DVec3::new(2.0, 0.0, 1.0)
        ));
        assert!(close(
            s.inverse_point(s.point(DVec3::new(1.0, 2.0, 3.0))),
            DVec3::new(1.0, 2.0, 3.0)
        ));
    }

    #[test]
    fn normals_stay_perpendicular_under_scale() {
        let s = Transform::scale(DVec3::new(1.0, 4.0, 1.0)).unwrap();
        // Plane x + y = 0 has normal (1,1,0); tangent (1,-1,0).
        let tangent = s.vector(DVec3::new(1.0, -1.0, 0.0));
        let n = s.normal(DVec3::new(1.0, 1.0, 0.0));
        assert!(tangent.dot(n).abs() < 1e-12);
    }

    #[test]
    fn rotate_y_matches_right_handed_convention() {
        // rotate y θ: x' = x cosθ + z sinθ, z' = -x sinθ + z cosθ
        let r = Transform::rotate(DVec3::Y, 90.0).unwrap();
        assert!(close(r.point(DVec3::Z), DVec3::X));
    }

    /// `matrix [ … ]` rows: row r is (x′, y′ or z′) = a·x + b·y + c·z + d,
    /// applied to a point and (without d) to a vector; the inverse undoes
    /// both. Integer entries, so the forward results are exact.
    #[test]
    fn rows_are_the_matrix_as_written() {
        let t = Transform::from_rows([
            1.0, -1.0, 0.0, 10.0, //
            0.0, 2.0, -1.0, 20.0, //
            1.0, 0.0, 1.0, 30.0,
        ])
        .unwrap();
        let p = DVec3::new(1.0, 2.0, 3.0);
        assert_eq!(
            t.point(p),
            DVec3::new(1.0 - 2.0 + 10.0, 4.0 - 3.0 + 20.0, 3.0 + 1.0 + 30.0)
        );
        assert_eq!(t.vector(p), DVec3::new(1.0 - 2.0, 4.0 - 3.0, 3.0 + 1.0));
        assert!(close(t.inverse_point(t.point(p)), p));
        assert!(close(t.inverse_vector(t.vector(p)), p));
        assert!(!t.is_identity());
        // A singular one (the third row the sum of the first two) is not.
        assert!(
            Transform::from_rows([
                1.0, 0.0, 0.0, 0.0, //
                0.0, 1.0, 0.0, 0.0, //
                1.0, 1.0, 0.0, 0.0,
            ])
            .is_none()
        );
    }

    /// Refused below |det| = 1e-300, taken above it: a scale of 1e-101 per
    /// axis (det 1e-303, though its inverse, 1e101, would be finite) is
    /// refused, one of 1e-99 (det 1e-297) is kept; so is a reflection
    /// (det −1), and a matrix holding ∞ or NaN is not.
    #[test]
    fn the_determinant_threshold() {
        assert!(Transform::scale(DVec3::splat(1e-101)).is_none());
        let tiny = Transform::scale(DVec3::splat(1e-99)).unwrap();
        assert_eq!(tiny.point(DVec3::ONE), DVec3::splat(1e-99));
        assert!(close(tiny.inverse_point(DVec3::splat(1e-99)), DVec3::ONE));
        assert!(Transform::scale(DVec3::new(1.0, -1.0, 1.0)).is_some());
        assert!(Transform::scale(DVec3::new(1.0, f64::INFINITY, 1.0)).is_none());
        assert!(Transform::scale(DVec3::new(1.0, f64::NAN, 1.0)).is_none());
    }

    /// Each elementary transform and its stored inverse, against the
    /// matrix written out.
    #[test]
    fn elementary_transforms_and_their_inverses() {
        let p = DVec3::new(1.0, 2.0, 3.0);
        let t = Transform::translate(DVec3::new(0.5, -4.0, 8.0));
        assert_eq!(t.point(p), DVec3::new(1.5, -2.0, 11.0));
        assert_eq!(t.inverse_point(p), DVec3::new(0.5, 6.0, -5.0));
        assert_eq!(t.vector(p), p);
        assert_eq!(t.inverse_vector(p), p);
        let s = Transform::scale(DVec3::new(2.0, 4.0, 0.5)).unwrap();
        assert_eq!(s.point(p), DVec3::new(2.0, 8.0, 1.5));
        assert_eq!(s.inverse_point(p), DVec3::new(0.5, 0.5, 6.0));
        for axis in 0..3 {
            let m = Transform::mirror(axis);
            let mut q = p;
            q[axis] = -q[axis];
            assert_eq!(m.point(p), q, "mirror {axis}");
            assert_eq!(m.inverse_point(p), q, "mirror {axis}");
        }
        // shear xy 3: y′ = y + 3x; its inverse y = y′ − 3x.
        let h = Transform::shear(0, 1, 3.0);
        assert_eq!(h.point(p), DVec3::new(1.0, 5.0, 3.0));
        assert_eq!(h.inverse_point(p), DVec3::new(1.0, -1.0, 3.0));
        // rotate z 90: (x, y) → (−y, x); the inverse (its transpose) back.
        let r = Transform::rotate(DVec3::new(0.0, 0.0, 2.0), 90.0).unwrap();
        assert!(close(r.point(p), DVec3::new(-2.0, 1.0, 3.0)));
        assert!(close(r.inverse_point(p), DVec3::new(2.0, -1.0, 3.0)));
    }

    /// The normal goes by the inverse transpose: under scale (2, 4, 0.5)
    /// it is (x/2, y/4, 2z), exactly.
    #[test]
    fn normals_by_the_inverse_transpose() {
        let s = Transform::scale(DVec3::new(2.0, 4.0, 0.5)).unwrap();
        assert_eq!(
            s.normal(DVec3::new(1.0, 1.0, 1.0)),
            DVec3::new(0.5, 0.25, 2.0)
        );
        // Under shear xy 3 (y′ = y + 3x) the plane y = 0's normal (0, 1, 0)
        // becomes (−3, 1, 0): the sheared plane is y′ = 3x′.
        let h = Transform::shear(0, 1, 3.0);
        assert_eq!(h.normal(DVec3::Y), DVec3::new(-3.0, 1.0, 0.0));
    }

    /// `then` composes both halves: a pair whose inverse is the identity
    /// but whose matrix is not (or the other way round) is not the
    /// identity, and is multiplied out like any other.
    #[test]
    fn then_takes_the_identity_shortcut_only_for_the_identity_both_ways() {
        let t = Transform::translate(DVec3::new(1.0, 2.0, 4.0));
        let forward_only = Transform {
            matrix: t.matrix,
            inverse: DMat4::IDENTITY,
        };
        let twice = forward_only.then(&forward_only);
        assert_eq!(twice.matrix, t.matrix * t.matrix);
        assert_eq!(twice.inverse, DMat4::IDENTITY);
        assert_eq!(twice.point(DVec3::ZERO), DVec3::new(2.0, 4.0, 8.0));
        let inverse_only = Transform {
            matrix: DMat4::IDENTITY,
            inverse: t.inverse,
        };
        let twice = inverse_only.then(&inverse_only);
        assert_eq!(twice.matrix, DMat4::IDENTITY);
        assert_eq!(
            twice.inverse_point(DVec3::ZERO),
            DVec3::new(-2.0, -4.0, -8.0)
        );
        assert!(Transform::IDENTITY.is_identity());
        assert!(Transform::default().is_identity());
        assert!(inverse_only.is_identity());
        assert!(!forward_only.is_identity());
    }

    #[test]
    fn singular_matrices_are_refused() {
        assert!(Transform::scale(DVec3::new(1.0, 0.0, 1.0)).is_none());
        assert!(Transform::rotate(DVec3::ZERO, 10.0).is_none());
    }

    /// `then` is the product for any two transforms, also those whose
    /// matrices and inverses share no entry with the identity (dense,
    /// projective ones, as `Transform::from_matrix` accepts): the shortcut
    /// for two identities must see that they are not, entry by entry.
    #[test]
    fn then_is_the_product_when_no_entry_is_the_identitys() {
        let m = DMat4::from_cols_array(&[
            2.0, 1.0, 1.0, 1.0, 1.0, 3.0, 1.0, 1.0, 1.0, 1.0, 4.0, 1.0, 1.0, 1.0, 1.0, 5.0,
        ]);
        let a = Transform::from_matrix(m).expect("invertible");
        let b = Transform::from_matrix(m.transpose() * 0.75).expect("invertible");
        for t in [&a, &b] {
            for x in [t.matrix, t.inverse] {
                let differ = x
                    .as_ref()
                    .iter()
                    .zip(DMat4::IDENTITY.as_ref())
                    .all(|(p, q)| p.to_bits() != q.to_bits());
                assert!(differ, "{x:?} shares an entry with the identity");
            }
        }
        let ab = a.then(&b);
        assert_eq!(ab.matrix, b.matrix * a.matrix);
        assert_eq!(ab.inverse, a.inverse * b.inverse);
    }
}
