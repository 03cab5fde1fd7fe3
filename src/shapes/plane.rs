//! An infinite plane, a half-space for CSG (the solid side is behind the
//! normal).
//!
//! ```text
//! plane { normal <0, 1, 0>  offset 0  material floor }   // y = 0
//! plane { material floor }                             // z = 0, normal +z
//! plane { normal <0, 2, 0>  offset 1 }                  // y = 1
//! ```
//! The normal is normalised and the offset kept: the plane is n̂·p = d, d
//! being the signed distance from the origin along the normal, whatever
//! the length of the normal written (as in POV-Ray).
//! Texture space: u = x, v = y in the plane's own frame (unbounded).

use super::{Crossing, Hit, Shape};
use crate::geometry::rounding::gamma;
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Plane {
    /// Unit normal.
    pub normal: DVec3,
    /// Points p with normal·p = offset lie on the plane.
    pub offset: f64,
    pub material: MaterialId,
    /// In-plane axes for u and v: for the canonical z = 0 plane these are x
    /// and y, otherwise the canonical frame rotated onto `normal`.
    u_axis: DVec3,
    v_axis: DVec3,
}

impl Plane {
    /// `normal` must be non-zero (the builder reports a zero normal).
    pub fn new(normal: DVec3, offset: f64, material: MaterialId) -> Self {
        let n = normal.normalize();
        let rot = glam::DQuat::from_rotation_arc(DVec3::Z, n);
        Plane {
            normal: n,
            offset,
            material,
            u_axis: rot * DVec3::X,
            v_axis: rot * DVec3::Y,
        }
    }

    fn hit_at(&self, ray: &Ray, t: f64) -> Hit {
        let p = ray.at(t);
        // Projected onto the plane; the residual n·p − d carries γ₃ of the
        // magnitudes it sums, and the projection two more roundings.
        let residual = self.normal.dot(p) - self.offset;
        let point = p - residual * self.normal;
        let scale = self.normal.abs().dot(p.abs()) + self.offset.abs();
        let p_error = gamma(4) * scale * self.normal.abs() + gamma(2) * point.abs();
        Hit {
            t,
            normal: self.normal,
            uv: DVec2::new(p.dot(self.u_axis), p.dot(self.v_axis)),
            local: p,
            point,
            p_error,
            geo_normal: self.normal,
            material: self.material,
            path: 0,
        }
    }

    fn root(&self, ray: &Ray) -> Option<f64> {
        let denom = self.normal.dot(ray.dir);
        if denom == 0.0 {
            return None;
        }
        Some((self.offset - self.normal.dot(ray.origin)) / denom)
    }

    /// [`Plane::root`] within (t_min, t_max). Every ray meets the plane (it
    /// is unbounded, so tested beside the kd-tree), and most leave it
    /// behind: when t_min ≥ 0 and the numerator and denominator of the
    /// root differ in sign, t < 0 (or −0) is out of range whatever the
    /// division gives, so it is skipped. Otherwise the same arithmetic.
    #[inline]
    fn root_in(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<f64> {
        let denom = self.normal.dot(ray.dir);
        let num = self.offset - self.normal.dot(ray.origin);
        if t_min >= 0.0 && ((num < 0.0 && denom > 0.0) || (num > 0.0 && denom < 0.0)) {
            return None;
        }
        if denom == 0.0 {
            return None;
        }
        let t = num / denom;
        (t > t_min && t < t_max).then_some(t)
    }
}

impl super::Roots for Plane {
    fn nearest_roots(&self, rays: &[Ray], t_min: f64, best: &mut [f64], won: &mut [bool]) {
        let mut done = 0;
        #[cfg(target_arch = "x86_64")]
        if crate::geometry::lanes::available() {
            // SAFETY: the CPU has AVX.
            done = unsafe { self.nearest_roots_avx(rays, t_min, best, won) };
        }
        self.nearest_roots_scalar(&rays[done..], t_min, &mut best[done..], &mut won[done..]);
    }

    /// A floor is asked for every ray: its root straight away, not
    /// through the many-ray route's lanes.
    fn root_within(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<f64> {
        self.root_in(ray, t_min, t_max)
    }

    fn hit_at_root(&self, ray: &Ray, t: f64, hit: &mut Hit) {
        *hit = self.hit_at(ray, t);
    }
}

impl Plane {
    /// [`super::Roots::nearest_roots`] one ray after another.
    fn nearest_roots_scalar(&self, rays: &[Ray], t_min: f64, best: &mut [f64], won: &mut [bool]) {
        super::nearest_roots_each(rays, best, won, |ray, limit| {
            self.root_in(ray, t_min, limit)
        });
    }

    /// [`Plane::nearest_roots_scalar`] four rays at a time, for as many
    /// whole fours as `rays` holds (their count is returned): the steps of
    /// [`Plane::root_in`] in the same order and rounding, its early
    /// returns as lane masks, so every lane has the scalar bits.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn nearest_roots_avx(
        &self,
        rays: &[Ray],
        t_min: f64,
        best: &mut [f64],
        won: &mut [bool],
    ) -> usize {
        use std::arch::x86_64::*;
        let n = [self.normal.x, self.normal.y, self.normal.z].map(|v| _mm256_set1_pd(v));
        let zero = _mm256_setzero_pd();
        let lo = _mm256_set1_pd(t_min);
        crate::geometry::lanes::each_four(rays, best, won, |r, limit| {
            let denom = crate::geometry::lanes::dot(n, [r.dx, r.dy, r.dz]);
            let num = _mm256_sub_pd(
                _mm256_set1_pd(self.offset),
                crate::geometry::lanes::dot(n, [r.ox, r.oy, r.oz]),
            );
            // Behind the origin for sure (signs apart), with t_min ≥ 0.
            let lt = |x, y| _mm256_cmp_pd::<_CMP_LT_OQ>(x, y);
            let apart = _mm256_or_pd(
                _mm256_and_pd(lt(num, zero), lt(zero, denom)),
                _mm256_and_pd(lt(zero, num), lt(denom, zero)),
            );
            let behind = if t_min >= 0.0 { apart } else { zero };
            let t = _mm256_div_pd(num, denom);
            let keep = _mm256_andnot_pd(
                _mm256_or_pd(behind, _mm256_cmp_pd::<_CMP_EQ_OQ>(denom, zero)),
                _mm256_and_pd(lt(lo, t), lt(t, limit)),
            );
            (t, keep)
        })
    }
}

impl Shape for Plane {
    fn roots(&self) -> Option<&dyn super::Roots> {
        Some(self)
    }

    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let t = self.root_in(ray, t_min, t_max)?;
        Some(self.hit_at(ray, t))
    }

    fn intersect_into(&self, ray: &Ray, t_min: f64, t_max: f64, hit: &mut Hit) -> bool {
        super::write_hit(self.root_in(ray, t_min, t_max), hit, |t| {
            self.hit_at(ray, t)
        })
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        if let Some(t) = self.root(ray) {
            out.push(self.hit_at(ray, t));
        }
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.root_in(ray, t_min, t_max).is_some()
    }

    /// Every point clearly on one side (by far more than the rounding of
    /// n·p − d): the hull lies in an open half-space.
    fn misses_hull(&self, points: &[DVec3]) -> bool {
        let side = |p: &DVec3| {
            let s = self.normal.dot(*p) - self.offset;
            let slack = 1e-9 * (self.normal.abs().dot(p.abs()) + self.offset.abs());
            if s > slack {
                1
            } else if s < -slack {
                -1
            } else {
                0
            }
        };
        let first = points.first().map_or(0, side);
        first != 0 && points.iter().all(|p| side(p) == first)
    }

    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        if let Some(t) = self.root(ray) {
            out.push(Crossing::new(t, self.normal, ray, 0));
        }
    }

    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        self.hit_at(ray, c.t)
    }

    fn bounds(&self) -> Aabb {
        Aabb::INFINITE
    }

    fn is_solid(&self) -> bool {
        true
    }

    /// The solid side is behind the normal.
    fn encloses(&self, p: DVec3) -> bool {
        self.normal.dot(p) <= self.offset
    }

    /// Every corner of `b` on or in front of the plane, with a margin of
    /// four times the rounding bound of n·c (zero for a corner whose
    /// products are all zero, so that a box standing on an axis-aligned
    /// floor counts as clear of it).
    fn clear_of(&self, b: &Aabb) -> bool {
        if b.is_empty() {
            return true;
        }
        b.is_finite()
            && b.corners().iter().all(|c| {
                let margin = 4.0 * gamma(3) * self.normal.abs().dot(c.abs());
                self.normal.dot(*c) >= self.offset + margin
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::testing;

    /// The rays of a pixel meet a plane four at a time (with AVX) or one
    /// after another, and both give each ray what `intersect_into` gives:
    /// from above and below, along it, and tilted.
    #[test]
    fn roots_of_many_rays_are_each_rays_own() {
        for (n, d) in [
            (DVec3::Y, 0.0),
            (DVec3::new(1.0, 1.0, 0.0), 2f64.sqrt()),
            (-DVec3::Z, 0.5),
        ] {
            let p = Plane::new(n, d, 2);
            let mut rays = testing::awkward_rays(DVec3::new(0.2, 0.1, -0.3));
            rays.push(Ray::new(DVec3::new(0.0, d, 0.0), DVec3::X));
            let kept = testing::check_roots_agree(&p, &rays);
            assert!(kept > 300, "{kept}");
            let (mut best, mut won) = (vec![f64::INFINITY; rays.len()], vec![false; rays.len()]);
            p.nearest_roots_scalar(&rays, 0.0, &mut best, &mut won);
            for (i, ray) in rays.iter().enumerate() {
                let want = p.root_in(ray, 0.0, f64::INFINITY);
                assert_eq!(want.map(f64::to_bits), won[i].then(|| best[i].to_bits()));
            }
        }
    }

    /// A box is clear of the half-space when it stands on or in front of
    /// the plane: touching a floor counts, dipping into it by a hair does
    /// not, and a tilted plane's rounding is allowed for.
    #[test]
    fn a_box_in_front_of_the_plane_is_clear_of_it() {
        let floor = Plane::new(DVec3::Y, 0.0, 0);
        let on = Aabb::new(DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 2.0, 1.0));
        assert!(floor.clear_of(&on));
        let dipping = Aabb::new(DVec3::new(-1.0, -1e-12, -1.0), DVec3::new(1.0, 2.0, 1.0));
        assert!(!floor.clear_of(&dipping));
        assert!(!floor.clear_of(&Aabb::new(DVec3::splat(-3.0), DVec3::splat(-1.0))));
        assert!(floor.clear_of(&Aabb::EMPTY));
        assert!(!floor.clear_of(&Aabb::INFINITE));
        // The solid is behind the normal: flipped, the same box is inside.
        let ceiling = Plane::new(-DVec3::Y, 0.0, 0);
        assert!(!ceiling.clear_of(&on.padded(-0.5)));
        // A tilted plane x + y = 2 (offset √2 along the unit normal): a box
        // whose nearest corner is well in front is clear; one whose corner
        // lies exactly on the plane is not claimed (rounding could put it
        // either side), nor one crossing it.
        let tilted = Plane::new(DVec3::new(1.0, 1.0, 0.0), 2f64.sqrt(), 0);
        assert!(tilted.clear_of(&Aabb::new(DVec3::new(1.5, 1.5, 0.0), DVec3::splat(3.0))));
        assert!(!tilted.clear_of(&Aabb::new(DVec3::new(1.0, 1.0, 0.0), DVec3::splat(3.0))));
        assert!(!tilted.clear_of(&Aabb::new(DVec3::ZERO, DVec3::splat(3.0))));
    }

    #[test]
    fn floor_hit_and_uv() {
        let p = Plane::new(DVec3::Y, 0.0, 0);
        let r = Ray::new(DVec3::new(2.0, 3.0, 1.0), -DVec3::Y);
        let h = p.intersect(&r, 1e-9, f64::INFINITY).unwrap();
        assert!((h.t - 3.0).abs() < 1e-12);
        assert!(
            p.intersect(&Ray::new(DVec3::Y, DVec3::X), 0.0, f64::INFINITY)
                .is_none()
        );
        // Canonical plane: u = x, v = y.
        let z = Plane::new(DVec3::Z, 0.0, 0);
        let h = z
            .intersect(&Ray::new(DVec3::new(0.3, 0.7, 1.0), -DVec3::Z), 0.0, 9.0)
            .unwrap();
        assert!((h.uv - DVec2::new(0.3, 0.7)).length() < 1e-12);
    }

    /// The offset is a distance along the unit normal, whatever the length
    /// of the normal given: `normal <0, 2, 0>  offset 1` is y = 1, and a
    /// tilted normal puts the plane `offset` from the origin.
    #[test]
    fn offset_is_the_distance_along_the_normalised_normal() {
        let p = Plane::new(DVec3::new(0.0, 2.0, 0.0), 1.0, 0);
        let h = p
            .intersect(&Ray::new(DVec3::new(0.5, 5.0, -2.0), -DVec3::Y), 0.0, 99.0)
            .unwrap();
        assert!((h.t - 4.0).abs() < 1e-12, "{h:?}");
        assert!(p.encloses(DVec3::new(0.0, 0.9, 0.0)) && !p.encloses(DVec3::new(0.0, 1.1, 0.0)));
        // Normal (1, 1, 0) with offset √2: the plane through (1, 1, 0), whose
        // nearest point to the origin lies √2 away.
        let tilted = Plane::new(DVec3::new(3.0, 3.0, 0.0), 2f64.sqrt(), 0);
        let r = Ray::new(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0).normalize());
        let h = tilted.intersect(&r, 0.0, 99.0).unwrap();
        assert!((h.t - 2f64.sqrt()).abs() < 1e-12, "{h:?}");
    }

    /// Shadow rays and nearest hits skip the division when the plane is
    /// behind the ray: the answer must be what the division gives, for
    /// origins on either side and on the plane, and windows starting at,
    /// before and after 0 (−0 too).
    #[test]
    fn skipping_the_division_changes_no_answer() {
        let planes = [
            Plane::new(DVec3::Y, 0.0, 0),
            Plane::new(DVec3::new(1.0, 2.0, -0.5), 0.7, 0),
        ];
        let mut rays = crate::shapes::testing::rays_towards(DVec3::ZERO, 3.0, 400, 61);
        // On the plane y = 0, and just off it, going up, down and along.
        for y in [0.0, f64::MIN_POSITIVE, -f64::MIN_POSITIVE, 1e-12] {
            for d in [DVec3::Y, -DVec3::Y, DVec3::X, DVec3::new(1.0, 1e-9, 0.0)] {
                rays.push(Ray::new(DVec3::new(0.3, y, -0.2), d));
            }
        }
        for p in &planes {
            for r in &rays {
                for (lo, hi) in [(0.0, f64::INFINITY), (-0.0, 5.0), (1e-3, 2.0), (-5.0, 5.0)] {
                    let want = p.root(r).filter(|&t| t > lo && t < hi);
                    assert_eq!(p.root_in(r, lo, hi), want, "({lo}, {hi}) {r:?}");
                    assert_eq!(p.occludes(r, lo, hi), want.is_some());
                    assert_eq!(p.intersect(r, lo, hi).map(|h| h.t), want);
                }
            }
        }
    }

    /// n·p − d with only the last rounding: each product's error recovered
    /// with a fused multiply-add, each sum's with two-sum.
    fn exact_residual(n: DVec3, p: DVec3, d: f64) -> f64 {
        let (mut sum, mut err) = (0.0f64, 0.0f64);
        let mut add = |x: f64| {
            let s = sum + x;
            let bp = s - sum;
            err += (sum - (s - bp)) + (x - bp);
            sum = s;
        };
        for (a, b) in [(n.x, p.x), (n.y, p.y), (n.z, p.z)] {
            let m = a * b;
            add(m);
            add(a.mul_add(b, -m));
        }
        add(-d);
        sum + err
    }

    /// A hit's point is where the ray meets the plane, snapped onto it: the
    /// exact n·point − d is within what its error bound allows along the
    /// normal, the snap moves the ray's point by a few roundings only, and
    /// the bound itself is a few roundings of the magnitudes involved
    /// (never negative, never a multiple of the scene's size) — near the
    /// origin, far from it, and on tilted planes.
    #[test]
    fn hit_points_lie_on_the_plane_within_their_error_bound() {
        let planes = [
            Plane::new(DVec3::new(0.3, 1.0, -0.2), 0.4, 0),
            Plane::new(DVec3::new(1.0, 2.0, -0.5), 1e3, 0),
            Plane::new(DVec3::new(-2.0, 0.5, 3.0), -7.5, 0),
            Plane::new(DVec3::Y, 0.0, 0),
            Plane::new(DVec3::new(0.0, 1.0, 1.0), 0.0, 0),
        ];
        let eps = f64::EPSILON;
        let mut checked = 0;
        for p in &planes {
            let on = p.normal * p.offset;
            let mut rays = crate::shapes::testing::rays_towards(on, 3.0, 300, 71);
            // Hits within 1e-3 of the origin (or of the plane's nearest
            // point to it): small magnitudes.
            rays.extend(crate::shapes::testing::rays_towards(on, 1e-3, 100, 73));
            for r in &rays {
                let Some(h) = p.intersect(r, 0.0, f64::INFINITY) else {
                    continue;
                };
                let at = r.at(h.t);
                // The ray's point carries the rounding of o + t·d: the
                // magnitudes are the origin's as well as the point's.
                let mag = r.origin.abs().max_element().max(at.abs().max_element()) + p.offset.abs();
                let e = h.p_error;
                assert!(e.min_element() >= 0.0, "{e:?} for {r:?}");
                assert!(
                    e.max_element() <= 16.0 * eps * mag,
                    "{e:?} vs {mag} for {r:?}"
                );
                let moved = (h.point - at).abs().max_element();
                assert!(
                    moved <= 16.0 * eps * mag,
                    "moved {moved} of {mag} for {r:?}"
                );
                let off = exact_residual(p.normal, h.point, p.offset).abs();
                assert!(
                    off <= p.normal.abs().dot(e),
                    "{off} off the plane, bound {e:?}, for {r:?}"
                );
                checked += 1;
            }
        }
        assert!(checked > 1000, "{checked}");
    }

    /// Rays from far away (1e14 to 1e17 from the plane, aimed at its
    /// nearest point to the origin): o + t·d then carries a rounding of
    /// the origin's size, so the ray's point may lie off the plane by as
    /// much as the plane's own offset, on either side. Snapped back, the
    /// hit point must still lie on the plane within its error bound, and
    /// the bound must never be negative: the magnitudes it covers are
    /// |n|·|p| and |d| added, not one less the other.
    #[test]
    fn rays_from_far_away_keep_the_error_bound_sound() {
        let planes = [
            Plane::new(DVec3::new(0.3, 1.0, 0.2), 5.0, 0),
            Plane::new(DVec3::new(1.0, 2.0, 0.5), 1e3, 0),
            Plane::new(DVec3::new(-2.0, 0.5, 3.0), -7.5, 0),
        ];
        let mut checked = 0;
        for p in &planes {
            let on = p.normal * p.offset;
            for far in [1e14, 1e15, 1e16, 1e17] {
                for r in crate::shapes::testing::rays_towards(on, 1.0, 300, 5) {
                    let out = r.origin - on;
                    let o = on + out * (far / 10.0);
                    let aim = on + out.cross(DVec3::X) * 0.1;
                    let ray = Ray::new(o, (aim - o).normalize());
                    let Some(t) = p.root(&ray) else {
                        continue;
                    };
                    let mut xs = Vec::new();
                    p.crossings(&ray, &mut xs);
                    let h = &xs[0];
                    assert_eq!(h.t, t);
                    let e = h.p_error;
                    assert!(e.min_element() >= 0.0, "{e:?} for {ray:?}");
                    let off = exact_residual(p.normal, h.point, p.offset).abs();
                    assert!(
                        off <= p.normal.abs().dot(e),
                        "{off} off the plane, bound {e:?}, for {ray:?}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 3000, "{checked}");
    }

    /// The shadow-shaft cull: a hull surely misses the plane only when all
    /// its points are clearly on one side; a point on the plane, within
    /// rounding of it, or points on both sides keep the plane in.
    #[test]
    fn misses_hull_only_when_every_point_is_clearly_on_one_side() {
        let floor = Plane::new(DVec3::Y, 0.0, 0);
        let up = |y: f64| DVec3::new(0.5, y, -0.25);
        assert!(floor.misses_hull(&[up(1.0), up(2.0), DVec3::new(-3.0, 0.5, 4.0)]));
        assert!(floor.misses_hull(&[up(-1.0), up(-2.0)]));
        assert!(!floor.misses_hull(&[up(1.0), up(-1.0)]));
        assert!(!floor.misses_hull(&[up(-1.0), up(1.0)]));
        assert!(!floor.misses_hull(&[DVec3::ZERO, up(1.0)]));
        assert!(!floor.misses_hull(&[up(1.0), DVec3::ZERO]));
        assert!(!floor.misses_hull(&[DVec3::ZERO, up(-1.0)]));
        assert!(!floor.misses_hull(&[]));
        // y = 2, written with a longer normal: above, below, both, and
        // points within rounding of the plane (1e-12 of magnitudes ~2)
        // on either side.
        let shelf = Plane::new(DVec3::new(0.0, 4.0, 0.0), 2.0, 0);
        assert!(shelf.misses_hull(&[up(3.0), up(2.5)]));
        assert!(shelf.misses_hull(&[up(1.0), up(-1.0)]));
        assert!(!shelf.misses_hull(&[up(1.0), up(3.0)]));
        assert!(!shelf.misses_hull(&[up(3.0), up(1.0)]));
        assert!(!shelf.misses_hull(&[up(2.0 - 1e-12), up(2.0 - 2e-12)]));
        assert!(!shelf.misses_hull(&[up(2.0 + 1e-12), up(2.0 + 2e-12)]));
        assert!(!shelf.misses_hull(&[up(1.0), up(2.0 - 1e-12)]));
        assert!(!shelf.misses_hull(&[up(3.0), up(2.0 + 1e-12)]));
        // Far from the origin the rounding grows with the magnitudes: a
        // few ulps off a plane at 1e6 is still unsure, while a unit off it
        // (1e-6 of the magnitudes, 1e10 roundings) is clearly off.
        let far = Plane::new(DVec3::Y, 1e6, 0);
        let ulps = |k: f64| up(1e6 * (1.0 + k * f64::EPSILON));
        assert!(!far.misses_hull(&[ulps(4.0), ulps(8.0)]));
        assert!(!far.misses_hull(&[ulps(-4.0), ulps(-8.0)]));
        assert!(far.misses_hull(&[up(1e6 + 1.0), up(1e6 + 2.0)]));
        assert!(far.misses_hull(&[up(1e6 - 1.0), up(1e6 - 2.0)]));
    }

    /// The window is open at both ends (`t_min < t < t_max`, as for every
    /// shape): a hit exactly at t_max is not in it — a shadow ray to a
    /// point on the plane is not blocked by that plane.
    #[test]
    fn a_hit_exactly_at_the_window_end_is_outside() {
        let floor = Plane::new(DVec3::Y, 0.0, 0);
        let r = Ray::new(DVec3::new(0.5, 3.0, -1.0), -DVec3::Y);
        assert_eq!(floor.root(&r), Some(3.0));
        assert!(floor.intersect(&r, 0.0, 3.0).is_none());
        assert!(!floor.occludes(&r, 0.0, 3.0));
        assert!(floor.intersect(&r, 3.0, 9.0).is_none());
        assert_eq!(floor.intersect(&r, 0.0, 3.0 + 1e-9).map(|h| h.t), Some(3.0));
    }

    /// The shared properties, and the whole line's single crossing (behind
    /// the origin too, which CSG asks for), the same through the light
    /// route (`crossings_lite` then `hit_of`).
    #[test]
    fn properties_and_crossings() {
        let p = Plane::new(DVec3::new(0.3, 1.0, -0.2), 0.4, 0);
        // A half-space: CSG may take it as a solid.
        assert!(p.is_solid());
        let rays = crate::shapes::testing::rays_towards(DVec3::new(0.0, 0.4, 0.0), 3.0, 400, 67);
        crate::shapes::testing::check_consistency(&p, &rays);
        crate::shapes::testing::check_no_rehit(&p, &rays);
        assert!(crate::shapes::testing::check_normals(&p, &rays) > 50);
        assert!(crate::shapes::testing::check_occludes_agrees(&p, &rays) > 100);
        for r in &rays {
            let mut xs = Vec::new();
            p.crossings(r, &mut xs);
            let mut lite = Vec::new();
            p.crossings_lite(r, &mut lite);
            let t = p.root(r).unwrap();
            assert_eq!(xs.len(), 1);
            assert_eq!(xs[0].t, t);
            assert_eq!(lite.len(), 1);
            assert_eq!(lite[0].t, t);
            assert_eq!(lite[0].facing.signum(), p.normal.dot(r.dir).signum());
            let h = p.hit_of(r, &lite[0]);
            assert_eq!(
                (h.t, h.point, h.normal),
                (xs[0].t, xs[0].point, xs[0].normal)
            );
            // Backwards along the same line: the crossing is at −t.
            let back = Ray::new(r.origin, -r.dir);
            let mut xs = Vec::new();
            p.crossings(&back, &mut xs);
            assert_eq!(xs.len(), 1);
            assert!((xs[0].t + t).abs() <= 1e-12 * t.abs().max(1.0));
        }
    }
}
