//! A torus: a ring in the x-z plane around the y axis, centred at the
//! origin, of major radius R (centre of the tube) and minor radius r (the
//! tube).
//!
//! ```text
//! torus { major 2  minor 0.5  material gold  translate <0, 0.5, 0> }
//! ```
//! Surface: (x² + y² + z² + R² − r²)² − 4R²(x² + z²) = 0, negative inside.
//! Texture space: u = atan2(x, z)/2π around the y axis, v = the angle
//! around the tube (0 on the outer equator, 0.25 on top), both wrapped to
//! [0, 1).
//!
//! The ray is clipped to the box around the torus and re-parameterised
//! over that chord (t = mid + s·h, s in [−1, 1]), which keeps the quartic's
//! coefficients well scaled; its roots come from the implicit surfaces'
//! root finder.

use super::{Crossing, Hit, Shape};
use crate::geometry::rounding::gamma;
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::implicit::solve::{no_root_in_unit, roots_in};
use crate::scene::MaterialId;
use std::f64::consts::PI;

#[derive(Clone, Debug)]
pub struct Torus {
    pub major: f64,
    pub minor: f64,
    pub material: MaterialId,
    bounds: Aabb,
}

impl Torus {
    /// The builder checks that both radii are positive.
    pub fn new(major: f64, minor: f64, material: MaterialId) -> Self {
        let e = major.abs() + minor.abs();
        Torus {
            major,
            minor,
            material,
            bounds: Aabb::new(
                DVec3::new(-e, -minor.abs(), -e),
                DVec3::new(e, minor.abs(), e),
            ),
        }
    }

    fn roots(&self, ray: &Ray, lo: f64, hi: f64, mut visit: impl FnMut(f64) -> bool) {
        let Some((mid, h, o, d)) = self.chord(ray, lo, hi) else {
            return;
        };
        if self.chord_misses(o, d) {
            return;
        }
        let c = self.quartic(o, d);
        if no_root_in_unit(&c) {
            return;
        }
        roots_in(&c, -1.0, 1.0, 1e-13, |s| {
            let t = mid + s * h;
            t > lo && t < hi && !self.may_be_behind(o, d, &c, s, (t - lo) / h) && visit(t)
        });
    }

    /// Whether the root at chord parameter `s`, `ahead` (in units of s)
    /// past the window's start, may truly lie at or before that start: a
    /// secondary ray leaving the torus starts a few ulps off it, less than
    /// the rounding of the quartic's value there (its coefficients cancel
    /// terms of size (|o|² + R²)²), so the solver can find the very
    /// surface the ray leaves (pbrt's test of t's lower bound). The band
    /// is the rounding of the coefficients and of Horner's evaluation,
    /// over the slope, plus the solver's tolerance.
    fn may_be_behind(&self, o: DVec3, d: DVec3, c: &[f64; 5], s: f64, ahead: f64) -> bool {
        if ahead > 1e-6 {
            return false;
        }
        let (r2, rr2) = (self.major * self.major, self.minor * self.minor);
        let k = 4.0 * r2;
        let qa = d.dot(d);
        let qb = 2.0 * o.dot(d).abs();
        let qc = o.dot(o) + r2 + rr2;
        let mags = [
            qc * qc + k * (o.x * o.x + o.z * o.z),
            2.0 * qb * qc + 2.0 * k * (o.x * d.x).abs() + 2.0 * k * (o.z * d.z).abs(),
            qb * qb + 2.0 * qa * qc + k * (d.x * d.x + d.z * d.z),
            2.0 * qa * qb,
            qa * qa,
        ];
        let a = s.abs();
        let size = mags[0] + a * (mags[1] + a * (mags[2] + a * (mags[3] + a * mags[4])));
        let slope = c[1] + s * (2.0 * c[2] + s * (3.0 * c[3] + s * 4.0 * c[4]));
        ahead * slope.abs() <= gamma(16) * size + 1e-13 * slope.abs()
    }

    /// The ray clipped to the box, as (mid, h, o, d): the chord is
    /// o + s·d for s in [−1, 1], o = ray.at(mid), d = dir·h. Inlined:
    /// returned through memory, its vectors were stored a coordinate at a
    /// time and read back 16 bytes at a time (a stalled store-to-load
    /// forward at every ray that reaches the torus's box).
    #[inline(always)]
    fn chord(&self, ray: &Ray, lo: f64, hi: f64) -> Option<(f64, f64, DVec3, DVec3)> {
        let (a, b) = self.bounds.clip(ray, lo, hi)?;
        let (mid, h) = (0.5 * (a + b), 0.5 * (b - a));
        if h.is_nan() || h <= 0.0 {
            return None;
        }
        Some((mid, h, ray.at(mid), ray.dir * h))
    }

    /// The torus's equation along the chord o + s·d, as coefficients of
    /// s⁰..s⁴.
    fn quartic(&self, o: DVec3, d: DVec3) -> [f64; 5] {
        let (r2, rr2) = (self.major * self.major, self.minor * self.minor);
        let qa = d.dot(d);
        let qb = 2.0 * o.dot(d);
        let qc = o.dot(o) + r2 - rr2;
        let k = 4.0 * r2;
        [
            qc * qc - k * (o.x * o.x + o.z * o.z),
            2.0 * qb * qc - k * 2.0 * (o.x * d.x + o.z * d.z),
            qb * qb + 2.0 * qa * qc - k * (d.x * d.x + d.z * d.z),
            2.0 * qa * qb,
            qa * qa,
        ]
    }

    /// Whether the chord o + s·d, s in [−1, 1], surely misses the torus
    /// because it stays outside the cylinder ρ = R + r about the y axis
    /// (ρ² = x² + z²) or inside the hole ρ = R − r. The box lets through
    /// its corners and the hole, and these tests cost a tenth of the
    /// quartic's. ρ²(s) is a convex quadratic, least at its clamped vertex
    /// and greatest at an end. It is asked of the same o and d that the
    /// quartic is built from, whose magnitudes the box bounds, so a
    /// relative margin of 1e-9 keeps rounding from losing a grazing root.
    fn chord_misses(&self, o: DVec3, d: DVec3) -> bool {
        let (big, small) = (self.major.abs(), self.minor.abs());
        let rho2 = |s: f64| {
            let (x, z) = (o.x + s * d.x, o.z + s * d.z);
            x * x + z * z
        };
        let dxz = d.x * d.x + d.z * d.z;
        let vertex = if dxz > 0.0 {
            (-(o.x * d.x + o.z * d.z) / dxz).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let outer = big + small;
        if rho2(vertex) > outer * outer * (1.0 + 1e-9) {
            return true;
        }
        let inner = big - small;
        inner > 0.0 && rho2(-1.0).max(rho2(1.0)) < inner * inner * (1.0 - 1e-9)
    }

    /// The outward normal (the gradient's half) at a point of the torus.
    fn normal(&self, p: DVec3) -> DVec3 {
        let s = p.length_squared() + self.major * self.major - self.minor * self.minor;
        let k = 2.0 * self.major * self.major;
        DVec3::new(p.x * (s - k), p.y * s, p.z * (s - k))
    }

    /// The line's crossings (at most four), in increasing t.
    fn all_roots(&self, ray: &Ray) -> ([f64; 4], usize) {
        let mut ts = [0.0; 4];
        let mut n = 0;
        self.roots(ray, f64::NEG_INFINITY, f64::INFINITY, |t| {
            if n < 4 {
                ts[n] = t;
                n += 1;
            }
            false
        });
        (ts, n)
    }

    fn hit_at(&self, ray: &Ray, t: f64) -> Hit {
        let p = ray.at(t);
        let normal = self.normal(p);
        let (point, p_error) = self.reproject(p);
        Hit {
            t,
            normal,
            uv: DVec2::ZERO,
            local: p,
            point,
            p_error,
            geo_normal: normal,
            material: self.material,
            path: 0,
        }
    }
}

impl Torus {
    /// `p` put back on the torus: the nearest point of the tube's centre
    /// circle is R·(x, 0, z)/|(x, z)|, and the surface lies r from it
    /// along the line to `p`. A spindle torus (R < r) has an inner part
    /// too, the "lemon" inside the outer "apple", whose points lie r from
    /// the circle's point across the axis instead (and nearer than r to
    /// the near one): the circle's point is whichever of the two is
    /// nearer to r away. (For R ≥ r the far one is never nearer.) The
    /// root finder's tolerance in t no longer matters; the rounding of
    /// these few steps is γ₁₀ of the magnitudes.
    fn reproject(&self, p: DVec3) -> (DVec3, DVec3) {
        let (big, small) = (self.major.abs(), self.minor.abs());
        let rho = p.x.hypot(p.z);
        let near = if rho > 0.0 {
            DVec3::new(p.x, 0.0, p.z) * (big / rho)
        } else {
            DVec3::new(big, 0.0, 0.0)
        };
        let far = DVec3::new(-near.x, 0.0, -near.z);
        let ring = if ((p - far).length() - small).abs() < ((p - near).length() - small).abs() {
            far
        } else {
            near
        };
        let off = p - ring;
        let len = off.length();
        if len == 0.0 || !len.is_finite() {
            return (p, DVec3::splat(small));
        }
        let point = ring + off * (small / len);
        (
            point,
            gamma(10) * (point.abs() + ring.abs() + DVec3::splat(small)),
        )
    }
}

impl Shape for Torus {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let mut found = None;
        self.roots(ray, t_min, t_max, |t| {
            found = Some(t);
            true
        });
        found.map(|t| self.hit_at(ray, t))
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        let mut any = false;
        self.roots(ray, t_min, t_max, |_| {
            any = true;
            true
        });
        any
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        let (ts, n) = self.all_roots(ray);
        out.extend(ts[..n].iter().map(|&t| self.hit_at(ray, t)));
    }

    /// CSG sees up to four crossings per line and keeps at most one: the
    /// re-projected point and its error bound wait for `hit_of`.
    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        let (ts, n) = self.all_roots(ray);
        out.extend(
            ts[..n]
                .iter()
                .map(|&t| Crossing::new(t, self.normal(ray.at(t)), ray, 0)),
        );
    }

    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        self.hit_at(ray, c.t)
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn is_solid(&self) -> bool {
        true
    }

    fn uv(&self, hit: &Hit) -> DVec2 {
        let p = hit.local;
        let rho = (p.x * p.x + p.z * p.z).sqrt();
        let wrap = |a: f64| {
            let u = a / (2.0 * PI);
            if u < 0.0 {
                (u + 1.0).min(1.0 - f64::EPSILON)
            } else {
                u
            }
        };
        DVec2::new(wrap(p.x.atan2(p.z)), wrap(p.y.atan2(rho - self.major)))
    }
}

#[cfg(test)]
#[path = "torus_tests.rs"]
mod tests;
