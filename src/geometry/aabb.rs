use super::{Ray, Transform};
use glam::DVec3;

/// An axis-aligned bounding box. `Aabb::EMPTY` has min > max; unbounded
/// shapes (planes, some implicit surfaces) report infinite extents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: DVec3,
    pub max: DVec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };
    pub const INFINITE: Aabb = Aabb {
        min: DVec3::splat(f64::NEG_INFINITY),
        max: DVec3::splat(f64::INFINITY),
    };

    pub fn new(a: DVec3, b: DVec3) -> Self {
        Aabb {
            min: a.min(b),
            max: a.max(b),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn intersection(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.max(o.min),
            max: self.max.min(o.max),
        }
    }

    /// Whether the two boxes share no interior point: on some axis one
    /// ends where or before the other begins (boxes that only touch are
    /// apart; an empty box is apart from everything).
    pub fn apart(&self, o: &Aabb) -> bool {
        self.max.cmple(o.min).any()
            || o.max.cmple(self.min).any()
            || self.is_empty()
            || o.is_empty()
    }

    /// The box widened by `pad` on every side.
    pub fn padded(&self, pad: f64) -> Aabb {
        let pad = DVec3::splat(pad);
        Aabb {
            min: self.min - pad,
            max: self.max + pad,
        }
    }

    pub fn grow(&self, p: DVec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    pub fn centre(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    pub fn extent(&self) -> DVec3 {
        self.max - self.min
    }

    /// Surface area, the cost measure of the SAH.
    pub fn area(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.extent();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    pub fn contains(&self, p: DVec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// The parametric interval where the ray is inside the box, clipped to
    /// `[t_min, t_max]`; slab test. Zero direction components give ±inf
    /// reciprocals, which the min/max ordering handles. A ray lying in a
    /// face's plane (a zero component, the origin on that face) gives
    /// 0·inf = NaN for that plane: it is inside that slab along its whole
    /// length. (Left to `min`/`max`, the NaN would be dropped in favour of
    /// the other plane's ±inf, and the ray lost.)
    #[inline]
    pub fn clip(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
        self.clip_with(ray, ray.dir.recip(), t_min, t_max)
    }

    /// [`Aabb::clip`] with `inv = ray.dir.recip()` worked out by the
    /// caller (once for several boxes). Plain comparisons, not `f64::min`
    /// and `max`, whose NaN handling costs several instructions each:
    /// nothing here is NaN by then (a NaN slab is skipped), so they give
    /// the same values.
    #[inline(always)]
    pub fn clip_with(&self, ray: &Ray, inv: DVec3, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
        let t0 = (self.min - ray.origin) * inv;
        let t1 = (self.max - ray.origin) * inv;
        let (mut lo, mut hi) = (t_min, t_max);
        slab(t0.x, t1.x, &mut lo, &mut hi);
        slab(t0.y, t1.y, &mut lo, &mut hi);
        slab(t0.z, t1.z, &mut lo, &mut hi);
        (lo <= hi).then_some((lo, hi))
    }

    /// The box around the eight transformed corners.
    pub fn transformed(&self, xf: &Transform) -> Aabb {
        if !self.is_finite() {
            return if self.is_empty() {
                *self
            } else {
                Aabb::INFINITE
            };
        }
        self.corners()
            .into_iter()
            .fold(Aabb::EMPTY, |out, c| out.grow(xf.point(c)))
    }

    /// The eight corners: bit 0 of the index picks max over min in x,
    /// bit 1 in y, bit 2 in z.
    pub fn corners(&self) -> [DVec3; 8] {
        std::array::from_fn(|i| {
            DVec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }
}

/// Narrows (lo, hi) to one slab's stretch (a, c) in either order; a NaN
/// (0·∞: the ray runs in the plane of a face) leaves it as it is, the ray
/// being inside that slab all along.
#[inline(always)]
fn slab(a: f64, c: f64, lo: &mut f64, hi: &mut f64) {
    if a.is_nan() || c.is_nan() {
        return;
    }
    let (near, far) = if a < c { (a, c) } else { (c, a) };
    if near > *lo {
        *lo = near;
    }
    if far < *hi {
        *hi = far;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Apart means no shared interior: separated or touching on a face,
    /// edge or corner; any overlap, however thin, is not apart.
    #[test]
    fn boxes_apart_share_no_interior() {
        let unit = Aabb::new(DVec3::ZERO, DVec3::ONE);
        let moved = |d: DVec3| Aabb::new(d, d + DVec3::ONE);
        for d in [
            DVec3::X,
            -DVec3::Y,
            DVec3::Z * 2.0,
            DVec3::ONE,
            DVec3::new(1.0, 0.5, 0.5),
        ] {
            assert!(unit.apart(&moved(d)) && moved(d).apart(&unit), "{d}");
        }
        let thin = DVec3::new(1.0 - 1e-12, 0.5, -0.5);
        for d in [DVec3::ZERO, thin, DVec3::splat(0.5), -thin] {
            assert!(!unit.apart(&moved(d)) && !moved(d).apart(&unit), "{d}");
        }
        assert!(!unit.apart(&Aabb::INFINITE));
        assert!(unit.apart(&Aabb::EMPTY) && Aabb::EMPTY.apart(&Aabb::INFINITE));
        // Empty by one axis turned inside out, inside the other's range on
        // every axis: no comparison of faces says so, emptiness does.
        let inverted = Aabb {
            min: DVec3::new(0.4, 0.8, 0.4),
            max: DVec3::new(0.6, 0.2, 0.6),
        };
        assert!(unit.apart(&inverted) && inverted.apart(&unit));
    }

    /// The clip as it was written with `f64::min`/`max` and a NaN mask
    /// (a slab in a face's plane taken as −∞..∞), before the plain
    /// comparisons: the same stretch for every ray, a face's plane
    /// included.
    fn clip_by_min_max(b: &Aabb, ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
        let inv = ray.dir.recip();
        let t0 = (b.min - ray.origin) * inv;
        let t1 = (b.max - ray.origin) * inv;
        let in_plane = t0.is_nan_mask() | t1.is_nan_mask();
        let near = DVec3::select(in_plane, DVec3::NEG_INFINITY, t0.min(t1));
        let far = DVec3::select(in_plane, DVec3::INFINITY, t0.max(t1));
        let lo = t_min.max(near.x).max(near.y).max(near.z);
        let hi = t_max.min(far.x).min(far.y).min(far.z);
        (lo <= hi).then_some((lo, hi))
    }

    #[test]
    fn plain_comparisons_clip_as_min_and_max_did() {
        let b = Aabb::new(DVec3::new(-1.0, 0.0, -0.5), DVec3::new(1.0, 2.0, 0.5));
        let mut rays =
            crate::shapes::testing::rays_towards(DVec3::new(0.0, 1.0, 0.0), 2.0, 500, 71);
        // Axis-parallel: inside, in the plane of a face, beside the box.
        for x in [0.0, 1.0, 3.0] {
            rays.push(Ray::new(DVec3::new(x, 1.0, -5.0), DVec3::Z));
            rays.push(Ray::new(DVec3::new(x, 1.0, 5.0), -DVec3::Z));
        }
        let mut hits = 0;
        for r in &rays {
            for (lo, hi) in [(0.0, f64::INFINITY), (9.0, 10.0), (f64::NEG_INFINITY, 9.5)] {
                let got = b.clip(r, lo, hi);
                assert_eq!(got, clip_by_min_max(&b, r, lo, hi), "{r:?} {lo}..{hi}");
                assert_eq!(got, b.clip_with(r, r.dir.recip(), lo, hi));
                hits += got.is_some() as usize;
            }
        }
        assert!(hits > 300, "{hits}");
        // The line in the plane x = 1 (of the face) still meets the box.
        let along = Ray::new(DVec3::new(1.0, 1.0, -5.0), DVec3::Z);
        assert_eq!(b.clip(&along, 0.0, 99.0), Some((4.5, 5.5)));
    }

    #[test]
    fn a_padded_box_and_the_corners_of_one() {
        let b = Aabb::new(DVec3::new(1.0, -2.0, 3.0), DVec3::new(4.0, 5.0, 6.0));
        let p = b.padded(0.5);
        assert_eq!(p.min, DVec3::new(0.5, -2.5, 2.5));
        assert_eq!(p.max, DVec3::new(4.5, 5.5, 6.5));
        let c = b.corners();
        assert_eq!(c[0], b.min);
        assert_eq!(c[7], b.max);
        assert_eq!(c[1], DVec3::new(4.0, -2.0, 3.0));
        assert_eq!(c[2], DVec3::new(1.0, 5.0, 3.0));
        assert_eq!(c[4], DVec3::new(1.0, -2.0, 6.0));
    }

    #[test]
    fn clip_hits_and_misses() {
        let b = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
        let r = Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0));
        assert_eq!(b.clip(&r, 0.0, f64::INFINITY), Some((4.0, 6.0)));
        let miss = Ray::new(DVec3::new(2.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0));
        assert_eq!(b.clip(&miss, 0.0, f64::INFINITY), None);
        assert_eq!(b.clip(&r, 0.0, 3.0), None);
    }

    /// A box flat in one axis (a triangle lying in x = c) is not empty: the
    /// kd-tree would drop every flat shape in such a plane.
    #[test]
    fn flat_boxes_are_not_empty_and_inverted_ones_are() {
        for axis in 0..3 {
            let mut hi = DVec3::ONE;
            hi[axis] = 0.0;
            let flat = Aabb::new(DVec3::new(0.0, 0.0, 0.0), hi);
            assert!(!flat.is_empty(), "flat in axis {axis}");
            let mut inverted = Aabb::new(DVec3::ZERO, DVec3::ONE);
            inverted.min[axis] = 2.0;
            assert!(inverted.is_empty(), "inverted in axis {axis}");
        }
        assert!(Aabb::EMPTY.is_empty());
        assert!(!Aabb::INFINITE.is_empty());
        assert!(!Aabb::new(DVec3::splat(3.0), DVec3::splat(3.0)).is_empty());
    }

    #[test]
    fn intersection_and_contains() {
        let a = Aabb::new(DVec3::ZERO, DVec3::new(2.0, 2.0, 2.0));
        let b = Aabb::new(DVec3::new(1.0, -1.0, 0.5), DVec3::new(3.0, 1.0, 1.5));
        let i = a.intersection(&b);
        assert_eq!(i.min, DVec3::new(1.0, 0.0, 0.5));
        assert_eq!(i.max, DVec3::new(2.0, 1.0, 1.5));
        // Touching boxes meet in a flat box; apart ones in an empty one.
        let touch = a.intersection(&Aabb::new(DVec3::new(2.0, 0.0, 0.0), DVec3::splat(3.0)));
        assert!(!touch.is_empty() && touch.extent().x == 0.0);
        let apart = a.intersection(&Aabb::new(DVec3::splat(5.0), DVec3::splat(6.0)));
        assert!(apart.is_empty());
        // contains: closed on every face, false just outside each.
        assert!(a.contains(DVec3::ZERO) && a.contains(DVec3::splat(2.0)));
        assert!(a.contains(DVec3::new(1.0, 2.0, 0.0)));
        for axis in 0..3 {
            for (v, inside) in [(-1e-12, false), (2.0 + 1e-12, false), (1.0, true)] {
                let mut p = DVec3::ONE;
                p[axis] = v;
                assert_eq!(a.contains(p), inside, "{p:?}");
            }
        }
        assert!(!Aabb::EMPTY.contains(DVec3::ZERO));
        // union and grow take the hull.
        let u = a.union(&b);
        assert_eq!(
            (u.min, u.max),
            (DVec3::new(0.0, -1.0, 0.0), DVec3::new(3.0, 2.0, 2.0))
        );
        assert_eq!(
            Aabb::EMPTY.grow(DVec3::ONE),
            Aabb::new(DVec3::ONE, DVec3::ONE)
        );
        assert_eq!(a.centre(), DVec3::ONE);
    }

    #[test]
    fn clip_of_a_ray_in_a_face_plane_and_from_inside() {
        let b = Aabb::new(DVec3::splat(-1.0), DVec3::splat(1.0));
        let inside = Ray::new(DVec3::ZERO, DVec3::X);
        assert_eq!(b.clip(&inside, 0.0, f64::INFINITY), Some((0.0, 1.0)));
        // A flat box (a rectangle in x = 0) is still hit across.
        let flat = Aabb::new(DVec3::new(0.0, -1.0, -1.0), DVec3::new(0.0, 1.0, 1.0));
        let across = Ray::new(DVec3::new(-3.0, 0.2, 0.1), DVec3::X);
        assert_eq!(flat.clip(&across, 0.0, f64::INFINITY), Some((3.0, 3.0)));
        // Rays lying in a face's plane, on the low or the high face of each
        // axis (either sign of zero), run along the face: inside from
        // where they cross the other slabs; one beside the face misses.
        for axis in 0..3 {
            let along = (axis + 1) % 3;
            for (face, zero) in [(-1.0, 0.0), (1.0, 0.0), (-1.0, -0.0), (1.0, -0.0)] {
                let mut o = DVec3::splat(0.25);
                o[axis] = face;
                o[along] = -4.0;
                let mut d = DVec3::ZERO;
                d[axis] = zero;
                d[along] = 2.0;
                let r = Ray::new(o, d);
                assert_eq!(b.clip(&r, 0.0, f64::INFINITY), Some((1.5, 2.5)), "{r:?}");
                assert_eq!(flat_in(axis, face).clip(&r, 0.0, 2.0), Some((1.5, 2.0)));
                o[axis] = face * 1.5;
                assert_eq!(b.clip(&Ray::new(o, d), 0.0, f64::INFINITY), None);
            }
        }
    }

    /// The face of the 2-wide cube in the plane `axis = c`, as a flat box.
    fn flat_in(axis: usize, c: f64) -> Aabb {
        let (mut lo, mut hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
        lo[axis] = c;
        hi[axis] = c;
        Aabb::new(lo, hi)
    }

    /// `is_finite`: every one of the six bounds finite; a box open on one
    /// side only (an infinite max, or a −∞ min) is not.
    #[test]
    fn a_box_is_finite_only_with_all_six_bounds_finite() {
        let unit = Aabb::new(DVec3::ZERO, DVec3::ONE);
        assert!(unit.is_finite());
        assert!(!Aabb::INFINITE.is_finite());
        assert!(!Aabb::EMPTY.is_finite());
        for axis in 0..3 {
            let mut open_above = unit;
            open_above.max[axis] = f64::INFINITY;
            assert!(!open_above.is_finite(), "max of axis {axis}");
            let mut open_below = unit;
            open_below.min[axis] = f64::NEG_INFINITY;
            assert!(!open_below.is_finite(), "min of axis {axis}");
        }
    }

    /// `centre`, `extent`, `union`, `intersection` and `grow` on a box with
    /// a different size in each axis, against their values worked out by
    /// hand (all exact in binary).
    #[test]
    fn centre_extent_and_hulls_by_hand() {
        let a = Aabb::new(DVec3::new(1.0, -2.0, 3.0), DVec3::new(4.0, 6.0, 3.5));
        assert_eq!(a.centre(), DVec3::new(2.5, 2.0, 3.25));
        assert_eq!(a.extent(), DVec3::new(3.0, 8.0, 0.5));
        let b = Aabb::new(DVec3::new(2.0, -3.0, 0.0), DVec3::new(5.0, 1.0, 3.25));
        let u = a.union(&b);
        assert_eq!(u.min, DVec3::new(1.0, -3.0, 0.0));
        assert_eq!(u.max, DVec3::new(5.0, 6.0, 3.5));
        let i = a.intersection(&b);
        assert_eq!(i.min, DVec3::new(2.0, -2.0, 3.0));
        assert_eq!(i.max, DVec3::new(4.0, 1.0, 3.25));
        let g = a.grow(DVec3::new(0.0, 7.0, 3.25));
        assert_eq!(g.min, DVec3::new(0.0, -2.0, 3.0));
        assert_eq!(g.max, DVec3::new(4.0, 7.0, 3.5));
    }

    /// `transformed` is the hull of the eight moved corners. The matrix
    /// (x − y + 10, y − z + 20, z + x + 30) takes each of its extremes at a
    /// different corner of the unit cube, so a corner left out (or one
    /// taken twice) shows: x′ is least at (0, 1, ·) and most at (1, 0, ·),
    /// y′ least at (·, 0, 1), z′ most at (1, ·, 1). Integer entries: exact.
    #[test]
    fn a_moved_box_is_the_hull_of_its_eight_moved_corners() {
        let xf = Transform::from_rows([
            1.0, -1.0, 0.0, 10.0, //
            0.0, 1.0, -1.0, 20.0, //
            1.0, 0.0, 1.0, 30.0,
        ])
        .unwrap();
        let unit = Aabb::new(DVec3::ZERO, DVec3::ONE);
        let moved = unit.transformed(&xf);
        assert_eq!(moved.min, DVec3::new(9.0, 19.0, 30.0));
        assert_eq!(moved.max, DVec3::new(11.0, 21.0, 32.0));
        // The same box by its corners, one by one.
        let mut hull = Aabb::EMPTY;
        for x in [0.0, 1.0] {
            for y in [0.0, 1.0] {
                for z in [0.0, 1.0] {
                    hull = hull.grow(DVec3::new(x - y + 10.0, y - z + 20.0, z + x + 30.0));
                }
            }
        }
        assert_eq!(moved, hull);
        // An unbounded box stays unbounded (the corners would give NaN
        // from ∞ − ∞), an empty one stays empty.
        let mut half = unit;
        half.max.x = f64::INFINITY;
        assert_eq!(half.transformed(&xf), Aabb::INFINITE);
        assert_eq!(Aabb::INFINITE.transformed(&xf), Aabb::INFINITE);
        assert!(Aabb::EMPTY.transformed(&xf).is_empty());
        assert_eq!(Aabb::EMPTY.transformed(&xf), Aabb::EMPTY);
    }

    #[test]
    fn area_of_unit_cube() {
        assert_eq!(Aabb::new(DVec3::ZERO, DVec3::ONE).area(), 6.0);
        assert_eq!(Aabb::EMPTY.area(), 0.0);
    }
}
