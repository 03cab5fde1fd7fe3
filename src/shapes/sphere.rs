//! A sphere.
//!
//! ```text
//! sphere { centre <0, 1, 0>  radius 1  material gold }
//! ```
//! Texture space: n = (p − c)/r; u = atan2(n.x, n.z)/2π wrapped to [0, 1),
//! v = 1 − acos(n.y)/π.

use super::{Crossing, Hit, Shape};
use crate::geometry::rounding::gamma;
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;
use std::f64::consts::PI;

#[derive(Clone, Debug)]
pub struct Sphere {
    pub centre: DVec3,
    pub radius: f64,
    pub material: MaterialId,
}

impl Sphere {
    pub fn new(centre: DVec3, radius: f64, material: MaterialId) -> Self {
        Sphere {
            centre,
            radius,
            material,
        }
    }

    fn hit_at(&self, ray: &Ray, t: f64) -> Hit {
        let p = ray.at(t);
        let n = (p - self.centre) / self.radius;
        let (point, p_error) = self.reproject(p);
        Hit {
            t,
            normal: n,
            uv: DVec2::ZERO,
            local: p,
            point,
            p_error,
            geo_normal: n,
            material: self.material,
            path: 0,
        }
    }

    /// `p` pulled onto the sphere along its radius, with the bound on the
    /// result's error (pbrt-v4: γ₅ of the offset from the centre, then one
    /// more rounding to add the centre back). Whatever error `t` had, the
    /// point is now on the surface up to that bound.
    fn reproject(&self, p: DVec3) -> (DVec3, DVec3) {
        let q = p - self.centre;
        let len = q.length();
        if len == 0.0 || !len.is_finite() {
            return (p, DVec3::splat(self.radius.abs()));
        }
        let q = q * (self.radius / len);
        let point = self.centre + q;
        (point, gamma(5) * q.abs() + gamma(1) * point.abs())
    }

    /// Whether no root of [`Sphere::roots`] can lie past `t_min`, told
    /// before its division and square root: the line starts outside
    /// (c = |f|² − r² > 0) and heads away from the centre (b = −f·d < 0),
    /// so both roots are behind. Bit for bit what `roots` would say, as
    /// its own c and b are these same expressions: there q = b −
    /// √discr < 0, so q/a and c/q are both ≤ −0, and neither exceeds a
    /// `t_min` ≥ 0. Every secondary ray that leaves a ball outwards (its
    /// shadow ray, its reflection, lifted off the surface) meets its own
    /// ball here first.
    #[inline(always)]
    fn surely_behind(&self, ray: &Ray, t_min: f64) -> bool {
        let f = ray.origin - self.centre;
        let b = -f.dot(ray.dir);
        t_min >= 0.0 && b < 0.0 && f.length_squared() - self.radius * self.radius > 0.0
    }

    /// The line's two crossings, in increasing t. The discriminant is the
    /// stable form of Haines et al. ("Precision Improvements for Ray/Sphere
    /// Intersection", Ray Tracing Gems ch. 7): b² − 4ac from the raw
    /// coefficients subtracts two numbers of size |o − c|² and loses the
    /// radius entirely from far away (a unit sphere seen from 1e8 turns
    /// octagonal); r² − |l|², with l the vector from the centre to the
    /// line's closest point, subtracts numbers of the sphere's own size.
    /// The nearer root in (t_min, t_max).
    #[inline]
    fn nearest_root(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<f64> {
        if self.surely_behind(ray, t_min) {
            return None;
        }
        let (t0, t1) = self.roots(ray)?;
        let t = if t0 > t_min { t0 } else { t1 };
        (t > t_min && t < t_max).then_some(t)
    }

    /// [`super::Roots::nearest_roots`] one ray after another.
    fn nearest_roots_scalar(&self, rays: &[Ray], t_min: f64, best: &mut [f64], won: &mut [bool]) {
        super::nearest_roots_each(rays, best, won, |ray, limit| {
            self.nearest_root(ray, t_min, limit)
        });
    }

    /// [`Sphere::nearest_roots_scalar`] four rays at a time, for as many
    /// whole fours as `rays` holds (their count is returned): the steps of
    /// [`Sphere::roots`] and [`Sphere::nearest_root`] in the same order, each
    /// rounded as the scalar one is (no fused multiply-adds; division and
    /// square root are correctly rounded either way), and its early
    /// returns as lane masks, so every lane comes out with the scalar
    /// bits. A pixel's camera rays meet each sphere its beam holds here:
    /// the four divisions and the square root of four rays overlap.
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
        let c = self.centre;
        let r2 = _mm256_set1_pd(self.radius * self.radius);
        let zero = _mm256_setzero_pd();
        let lo = _mm256_set1_pd(t_min);
        crate::geometry::lanes::each_four(rays, best, won, |r, limit| {
            let sub = |v: __m256d, k: f64| _mm256_sub_pd(v, _mm256_set1_pd(k));
            let (fx, fy, fz) = (sub(r.ox, c.x), sub(r.oy, c.y), sub(r.oz, c.z));
            let (dx, dy, dz) = (r.dx, r.dy, r.dz);
            let dot = crate::geometry::lanes::dot;
            let a = dot([dx, dy, dz], [dx, dy, dz]);
            // −(f·d): the sign bit flipped, as the scalar negation does.
            let b = _mm256_xor_pd(dot([fx, fy, fz], [dx, dy, dz]), _mm256_set1_pd(-0.0));
            let k = _mm256_div_pd(b, a);
            let l = |f: __m256d, d: __m256d| _mm256_add_pd(f, _mm256_mul_pd(k, d));
            let (lx, ly, lz) = (l(fx, dx), l(fy, dy), l(fz, dz));
            let discr = _mm256_mul_pd(a, _mm256_sub_pd(r2, dot([lx, ly, lz], [lx, ly, lz])));
            let cc = _mm256_sub_pd(dot([fx, fy, fz], [fx, fy, fz]), r2);
            // b.signum(): ±1 with b's sign (a NaN b makes q NaN either way).
            let sign = _mm256_or_pd(_mm256_and_pd(b, _mm256_set1_pd(-0.0)), _mm256_set1_pd(1.0));
            let q = _mm256_add_pd(b, _mm256_mul_pd(sign, _mm256_sqrt_pd(discr)));
            let (t0, t1) = (_mm256_div_pd(cc, q), _mm256_div_pd(q, a));
            let in_order = _mm256_cmp_pd::<_CMP_LE_OQ>(t0, t1);
            let near = _mm256_blendv_pd(t1, t0, in_order);
            let far = _mm256_blendv_pd(t0, t1, in_order);
            // q = 0: the line touches at its origin, both roots 0.
            let touch = _mm256_cmp_pd::<_CMP_EQ_OQ>(q, zero);
            let near = _mm256_blendv_pd(near, zero, touch);
            let far = _mm256_blendv_pd(far, zero, touch);
            // No roots where a = 0 or the discriminant is negative or NaN.
            let real = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_NEQ_UQ>(a, zero),
                _mm256_cmp_pd::<_CMP_GE_OQ>(discr, zero),
            );
            let t = _mm256_blendv_pd(far, near, _mm256_cmp_pd::<_CMP_GT_OQ>(near, lo));
            let keep = _mm256_and_pd(
                real,
                _mm256_and_pd(
                    _mm256_cmp_pd::<_CMP_GT_OQ>(t, lo),
                    _mm256_cmp_pd::<_CMP_LT_OQ>(t, limit),
                ),
            );
            (t, keep)
        })
    }

    fn roots(&self, ray: &Ray) -> Option<(f64, f64)> {
        let f = ray.origin - self.centre;
        let a = ray.dir.length_squared();
        if a == 0.0 {
            return None;
        }
        let b = -f.dot(ray.dir);
        let l = f + (b / a) * ray.dir;
        let r2 = self.radius * self.radius;
        let discr = a * (r2 - l.length_squared());
        if discr < 0.0 || discr.is_nan() {
            return None;
        }
        let c = f.length_squared() - r2;
        let q = b + b.signum() * discr.sqrt();
        if q == 0.0 {
            // b = 0 and no discriminant: the line touches the sphere at
            // its closest point to the centre, which is the origin (t = 0).
            return Some((0.0, 0.0));
        }
        let (t0, t1) = (c / q, q / a);
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }
}

/// Texture coordinates of a unit direction from a sphere's centre.
pub fn sphere_uv(n: DVec3) -> DVec2 {
    let mut u = n.x.atan2(n.z) / (2.0 * PI);
    if u < 0.0 {
        u += 1.0;
    }
    let v = 1.0 - n.y.clamp(-1.0, 1.0).acos() / PI;
    DVec2::new(u.min(1.0 - f64::EPSILON), v)
}

impl super::Roots for Sphere {
    fn nearest_roots(&self, rays: &[Ray], t_min: f64, best: &mut [f64], won: &mut [bool]) {
        let mut done = 0;
        #[cfg(target_arch = "x86_64")]
        if crate::geometry::lanes::available() {
            // SAFETY: the CPU has AVX.
            done = unsafe { self.nearest_roots_avx(rays, t_min, best, won) };
        }
        self.nearest_roots_scalar(&rays[done..], t_min, &mut best[done..], &mut won[done..]);
    }

    fn hit_at_root(&self, ray: &Ray, t: f64, hit: &mut Hit) {
        *hit = self.hit_at(ray, t);
    }
}

impl Shape for Sphere {
    fn roots(&self) -> Option<&dyn super::Roots> {
        Some(self)
    }

    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let t = self.nearest_root(ray, t_min, t_max)?;
        Some(self.hit_at(ray, t))
    }

    fn intersect_into(&self, ray: &Ray, t_min: f64, t_max: f64, hit: &mut Hit) -> bool {
        super::write_hit(self.nearest_root(ray, t_min, t_max), hit, |t| {
            self.hit_at(ray, t)
        })
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        if let Some((t0, t1)) = self.roots(ray) {
            out.push(self.hit_at(ray, t0));
            out.push(self.hit_at(ray, t1));
        }
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        !self.surely_behind(ray, t_min)
            && self
                .roots(ray)
                .is_some_and(|(t0, t1)| (t0 > t_min && t0 < t_max) || (t1 > t_min && t1 < t_max))
    }

    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        if let Some((t0, t1)) = self.roots(ray) {
            for t in [t0, t1] {
                out.push(Crossing::new(t, ray.at(t) - self.centre, ray, 0));
            }
        }
    }

    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        self.hit_at(ray, c.t)
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(
            self.centre - DVec3::splat(self.radius),
            self.centre + DVec3::splat(self.radius),
        )
    }

    fn is_solid(&self) -> bool {
        true
    }

    fn uv(&self, hit: &Hit) -> DVec2 {
        sphere_uv((hit.local - self.centre) / self.radius)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::testing;

    #[test]
    fn hit_from_outside_and_inside() {
        let s = Sphere::new(DVec3::ZERO, 1.0, 0);
        let r = Ray::new(DVec3::new(0.0, 0.0, 5.0), -DVec3::Z);
        let h = s.intersect(&r, 1e-9, f64::INFINITY).unwrap();
        assert!((h.t - 4.0).abs() < 1e-12);
        assert!((h.normal - DVec3::Z).length() < 1e-12);
        let inside = Ray::new(DVec3::ZERO, DVec3::X);
        assert!((s.intersect(&inside, 1e-9, f64::INFINITY).unwrap().t - 1.0).abs() < 1e-12);
    }

    /// The rays of a pixel meet a sphere four at a time (with AVX) or one
    /// after another, and both give each ray what `intersect_into` gives.
    #[test]
    fn roots_of_many_rays_are_each_rays_own() {
        for (c, r) in [
            (DVec3::ZERO, 1.0),
            (DVec3::new(0.3, -0.2, 0.1), 0.7),
            (DVec3::splat(1e6), 2.0),
        ] {
            let s = Sphere::new(c, r, 3);
            let rays = testing::awkward_rays(c);
            let kept = testing::check_roots_agree(&s, &rays);
            assert!(kept > 100, "{kept}");
            // And the scalar route alone, as machines without AVX take it.
            let (mut best, mut won) = (vec![f64::INFINITY; rays.len()], vec![false; rays.len()]);
            s.nearest_roots_scalar(&rays, 0.0, &mut best, &mut won);
            for (i, ray) in rays.iter().enumerate() {
                let want = s.nearest_root(ray, 0.0, f64::INFINITY);
                assert_eq!(want.map(f64::to_bits), won[i].then(|| best[i].to_bits()));
            }
        }
    }

    /// The roots as `roots` gives them, kept as `nearest_root` and
    /// `occludes` keep them, with no shortcut.
    fn by_the_roots(s: &Sphere, ray: &Ray, t_min: f64) -> (Option<u64>, bool) {
        let Some((t0, t1)) = s.roots(ray) else {
            return (None, false);
        };
        let t = if t0 > t_min { t0 } else { t1 };
        let ahead = |t: f64| t > t_min && t < f64::INFINITY;
        (ahead(t).then_some(t.to_bits()), ahead(t0) || ahead(t1))
    }

    /// Rays that leave a ball (lifted a little off it, as shadow rays and
    /// reflections are, or sunk a little into it, or exactly on it) in
    /// every direction: the shortcut for a ball behind the ray says
    /// nothing the roots would not, to the bit, for every `t_min` ≥ 0,
    /// and is not taken for a negative one (where the roots behind count).
    #[test]
    fn a_ball_behind_is_told_as_its_roots_tell_it() {
        let mut rnd = testing::numbers(0xba11);
        for (c, r) in [
            (DVec3::ZERO, 1.0),
            (DVec3::new(3.0, -1.0, 2.0), 0.4),
            (DVec3::splat(1e5), 7.0),
        ] {
            let s = Sphere::new(c, r, 0);
            let mut behind = 0;
            for k in 0..4000 {
                let u = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::Y);
                let lift = [0.0, 1e-12, -1e-12, 1e-6, 0.5, -0.5][k % 6];
                let origin = c + u * (r * (1.0 + lift));
                let dir = DVec3::new(rnd(), rnd(), rnd()) * [1.0, 1e-3, 1e3][k % 3];
                let ray = Ray::new(origin, dir);
                for t_min in [0.0, -0.0, 1e-9, 2.0, -1e-9, -3.0] {
                    let want = by_the_roots(&s, &ray, t_min);
                    let got = s.nearest_root(&ray, t_min, f64::INFINITY).map(f64::to_bits);
                    assert_eq!(got, want.0, "{ray:?} from {t_min}");
                    assert_eq!(s.occludes(&ray, t_min, f64::INFINITY), want.1, "{ray:?}");
                    if s.surely_behind(&ray, t_min) {
                        assert!(t_min >= 0.0 && want.0.is_none());
                        behind += 1;
                    }
                }
            }
            // The shortcut is taken often enough to be the one tested.
            assert!(behind > 2000, "{behind}");
        }
    }

    #[test]
    fn uv_convention() {
        // +z front is u = 0, top is v = 1.
        assert!(sphere_uv(DVec3::Z).x.abs() < 1e-12);
        assert!((sphere_uv(DVec3::Y).y - 1.0).abs() < 1e-12);
        assert!((sphere_uv(DVec3::X).x - 0.25).abs() < 1e-12);
    }

    #[test]
    fn seen_from_1e8_covers_the_analytic_area() {
        // The raw b² − 4ac gave 8% too much (and an octagon) from 1e8.
        let s = Sphere::new(DVec3::ZERO, 1.0, 0);
        for eye in [1e2, 1e8, 1e12] {
            let area = testing::silhouette_area(&s, DVec3::new(0.0, 0.0, eye), 1.2, 300);
            assert!((area / PI - 1.0).abs() < 0.01, "from {eye}: {area} vs π");
        }
    }

    #[test]
    fn consistent() {
        let s = Sphere::new(DVec3::new(1.0, 2.0, 3.0), 1.5, 0);
        testing::check_consistency(&s, &testing::rays_towards(s.centre, 2.0, 500, 1));
    }

    /// The shared properties: the shadow test and nearest hit agree with
    /// the crossings in every window, normals match finite differences,
    /// rays leaving do not re-hit, crossings alternate in and out; the box
    /// holds every hit; a sphere is a solid.
    #[test]
    fn properties_and_bounds() {
        let s = Sphere::new(DVec3::new(1.0, -2.0, 0.5), 1.5, 0);
        let rays = testing::rays_towards(s.centre, 2.0, 500, 5);
        assert!(testing::check_occludes_agrees(&s, &rays) > 100);
        assert!(testing::check_normals(&s, &rays) > 50);
        testing::check_no_rehit(&s, &rays);
        testing::check_alternation(&s, &rays);
        assert!(s.is_solid());
        let b = s.bounds();
        assert_eq!(
            b,
            Aabb::new(DVec3::new(-0.5, -3.5, -1.0), DVec3::new(2.5, -0.5, 2.0))
        );
        for r in &rays {
            if let Some(h) = s.intersect(r, 0.0, f64::INFINITY) {
                assert!(b.contains(h.point), "{:?} outside {b:?}", h.point);
                assert!(((h.point - s.centre).length() - 1.5).abs() < 1e-12);
            }
        }
    }

    /// u is the angle about +y from +z (towards +x) over 2π, in [0, 1);
    /// v is 1 − (angle from +y)/π: checked against that definition all
    /// round the sphere, and through the shape's own `uv`.
    #[test]
    fn uv_is_longitude_and_latitude() {
        let s = Sphere::new(DVec3::new(0.3, 0.1, -0.2), 2.0, 0);
        for i in 1..12 {
            for j in 0..16 {
                let theta = PI * i as f64 / 12.0;
                let phi = 2.0 * PI * (j as f64 + 0.25) / 16.0;
                let n = DVec3::new(
                    theta.sin() * phi.sin(),
                    theta.cos(),
                    theta.sin() * phi.cos(),
                );
                let want = DVec2::new(phi / (2.0 * PI), 1.0 - theta / PI);
                let uv = sphere_uv(n);
                assert!((uv - want).length() < 1e-12, "{uv:?} vs {want:?} at {n:?}");
                let o = s.centre + n * 5.0;
                let h = s.intersect(&Ray::new(o, -n), 0.0, 9.0).unwrap();
                assert!(
                    (s.uv(&h) - want).length() < 1e-9,
                    "{:?} vs {want:?}",
                    s.uv(&h)
                );
            }
        }
    }

    /// A hit's point is pulled onto the sphere (its distance from the
    /// centre is r up to a few roundings), and its error bound is a few
    /// roundings of the magnitudes involved: never negative, never a
    /// multiple of the sphere's size, near the origin and far from it.
    #[test]
    fn hit_points_are_on_the_sphere_with_a_rounding_sized_error() {
        for (c, r) in [
            (DVec3::new(0.1, -0.2, 0.3), 0.7),
            (DVec3::new(1e3, -2e3, 5e2), 3.0),
        ] {
            let s = Sphere::new(c, r, 0);
            let mut hits = 0;
            for ray in testing::rays_towards(c, r, 300, 9) {
                let Some(h) = s.intersect(&ray, 0.0, f64::INFINITY) else {
                    continue;
                };
                let mag = c.abs().max_element() + r;
                let e = h.p_error;
                assert!(e.min_element() >= 0.0, "{e:?}");
                assert!(
                    e.max_element() <= 16.0 * f64::EPSILON * mag,
                    "{e:?} vs {mag}"
                );
                let off = ((h.point - c).length() - r).abs();
                assert!(off <= 16.0 * f64::EPSILON * mag, "{off} off");
                assert!(
                    (h.normal - (h.point - c) / r).length() < 1e-9,
                    "{:?}",
                    h.normal
                );
                hits += 1;
            }
            assert!(hits > 100, "{hits}");
        }
    }

    /// Rays need not be unit length (a scaled transform passes longer or
    /// shorter ones): a direction k times as long meets the same points at
    /// t/k.
    #[test]
    fn direction_length_scales_t_only() {
        let s = Sphere::new(DVec3::new(1.0, -2.0, 0.5), 1.5, 0);
        for ray in testing::rays_towards(s.centre, 2.0, 200, 11) {
            let Some(h) = s.intersect(&ray, 0.0, f64::INFINITY) else {
                continue;
            };
            for k in [0.25, 2.5] {
                let long = Ray::new(ray.origin, ray.dir * k);
                let hk = s.intersect(&long, 0.0, f64::INFINITY).unwrap();
                assert!(
                    (hk.t * k - h.t).abs() < 1e-9 * h.t,
                    "{} vs {}",
                    hk.t * k,
                    h.t
                );
                assert!((hk.point - h.point).length() < 1e-9);
            }
        }
    }

    /// The window is open at both ends (`t_min < t < t_max`, as for every
    /// shape): a crossing exactly at either end is outside it. The ray
    /// down the z axis meets the unit sphere at exactly t = 4 and t = 6.
    #[test]
    fn a_crossing_exactly_at_a_window_end_is_outside() {
        let s = Sphere::new(DVec3::ZERO, 1.0, 0);
        let r = Ray::new(DVec3::new(0.0, 0.0, 5.0), -DVec3::Z);
        assert_eq!(s.roots(&r), Some((4.0, 6.0)));
        let t = |lo: f64, hi: f64| s.intersect(&r, lo, hi).map(|h| h.t);
        // From t = 4 on, the sphere is next met on leaving it, at 6.
        assert_eq!(t(4.0, 9.0), Some(6.0));
        assert!(s.occludes(&r, 4.0, 9.0));
        // Up to 4, or from 6 on: nothing; between the two: nothing.
        assert_eq!(t(0.0, 4.0), None);
        assert!(!s.occludes(&r, 0.0, 4.0));
        assert_eq!(t(6.0, 9.0), None);
        assert!(!s.occludes(&r, 6.0, 9.0));
        assert_eq!(t(4.0, 6.0), None);
        assert!(!s.occludes(&r, 4.0, 6.0));
        // Just past the ends, both are in.
        assert_eq!(t(0.0, 4.0 + 1e-9), Some(4.0));
        assert_eq!(t(6.0 - 1e-9, 9.0), Some(6.0));
        assert!(s.occludes(&r, 6.0 - 1e-9, 9.0));
    }

    /// The light route (`crossings_lite`, then `hit_of` for the one CSG
    /// keeps) gives the same crossings as `crossings`: the same t, facing
    /// in (negative) where the ray enters and out where it leaves, the
    /// same hit. Off the origin, so that p − c and p + c differ.
    #[test]
    fn crossings_lite_and_hit_of_agree_with_crossings() {
        let s = Sphere::new(DVec3::new(1.0, -2.0, 0.5), 1.5, 0);
        let mut met = 0;
        for r in testing::rays_towards(s.centre, 2.0, 300, 13) {
            let mut xs = Vec::new();
            s.crossings(&r, &mut xs);
            let mut lite = Vec::new();
            s.crossings_lite(&r, &mut lite);
            assert_eq!(xs.len(), lite.len());
            if xs.is_empty() {
                continue;
            }
            assert_eq!(xs.len(), 2);
            for (x, c) in xs.iter().zip(&lite) {
                assert_eq!(c.t, x.t);
                let h = s.hit_of(&r, c);
                assert_eq!((h.t, h.point, h.normal), (x.t, x.point, x.normal));
                assert_eq!(c.facing.signum(), x.normal.dot(r.dir).signum());
            }
            // The origin is outside: in first, out second.
            assert!(lite[0].facing < 0.0 && lite[1].facing > 0.0, "{lite:?}");
            met += 1;
        }
        assert!(met > 100, "{met}");
    }

    /// u is in [0, 1): a direction a hair west of +z (x = −1e−20) has
    /// u = 1 − 1.6e−21, which rounds to 1 and is held just below it.
    #[test]
    fn u_stays_below_one_at_the_seam() {
        let uv = sphere_uv(DVec3::new(-1e-20, 0.0, 1.0));
        assert!(uv.x < 1.0 && uv.x > 0.999, "{uv:?}");
        assert_eq!(sphere_uv(DVec3::Z).x, 0.0);
    }

    /// A sphere of radius 0 is its centre: a ray through the centre meets
    /// it there, and the hit's point is the centre with a finite bound
    /// (there is no direction to pull it along).
    #[test]
    fn a_point_sphere_is_met_at_its_centre() {
        let c = DVec3::new(0.5, -1.0, 2.0);
        let s = Sphere::new(c, 0.0, 0);
        let r = Ray::new(c + DVec3::new(0.0, 0.0, 4.0), -DVec3::Z);
        let mut xs = Vec::new();
        s.crossings(&r, &mut xs);
        assert_eq!(xs.len(), 2);
        for h in &xs {
            assert_eq!(h.t, 4.0);
            assert_eq!(h.point, c);
            assert!(h.p_error.is_finite() && h.p_error.min_element() >= 0.0);
        }
    }

    /// A line that touches the sphere (at distance r from the centre, here
    /// exactly) meets it at the touching point: a double root, whose hit
    /// lies on the sphere with the normal across the line.
    #[test]
    fn a_line_touching_the_sphere_meets_it_at_the_touching_point() {
        let s = Sphere::new(DVec3::ZERO, 1.0, 0);
        for side in [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y] {
            let r = Ray::new(side + DVec3::new(0.0, 0.0, 5.0), -DVec3::Z);
            assert_eq!(s.roots(&r), Some((5.0, 5.0)), "{side:?}");
            let h = s.intersect(&r, 0.0, 9.0).unwrap();
            assert_eq!(h.point, side);
            assert_eq!(h.normal, side);
        }
    }

    /// From a point on the sphere the line's crossings are that point
    /// (t = 0) and the far end of the chord, 2·|(c − o)·d| away for a unit
    /// d, on the sphere: the far root must not be lost in cancellation
    /// (b and √Δ are equal there; only their sum keeps the chord).
    #[test]
    fn a_chord_from_a_point_on_the_sphere_reaches_its_far_end() {
        let s = Sphere::new(DVec3::ZERO, 1.0, 0);
        let mut checked = 0;
        for o in [DVec3::X, DVec3::Y, DVec3::Z, -DVec3::Z] {
            for r in testing::rays_towards(DVec3::new(0.1, -0.2, 0.05), 0.5, 50, 17) {
                let ray = Ray::new(o, r.dir);
                let chord = 2.0 * (s.centre - o).dot(ray.dir);
                if chord <= 1e-3 {
                    continue;
                }
                let (t0, t1) = s.roots(&ray).unwrap();
                assert!(t0.abs() < 1e-12, "{t0} from {o:?} along {:?}", ray.dir);
                assert!((t1 - chord).abs() < 1e-12, "{t1} vs {chord}");
                let far = s.intersect(&ray, 1e-9, f64::INFINITY).unwrap();
                assert!(((far.point - s.centre).length() - 1.0).abs() < 1e-12);
                checked += 1;
            }
        }
        assert!(checked > 50, "{checked}");
    }
}
