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

    #[test]
    fn singular_matrices_are_refused() {
        assert!(Transform::scale(DVec3::new(1.0, 0.0, 1.0)).is_none());
        assert!(Transform::rotate(DVec3::ZERO, 10.0).is_none());
    }
}
