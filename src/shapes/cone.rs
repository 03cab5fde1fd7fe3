//! A cone or frustum along y, open (a lampshade) or solid (capped by discs).
//! The cylinder is the frustum with equal radii and shares this code.
//!
//! ```text
//! cone { centre <0, 1, 0>  radius 1  height 2  material red }             // point at y = 2
//! cone { radius 1  top_radius 0.5  height 1  top glass  bottom wood }     // capped frustum
//! cone { radius 1  top_radius 0.5  height 1  open  material paper }       // no caps
//! ```
//! Base radius `radius` at centre.y − height/2, `top_radius` at centre.y +
//! height/2. Texture space: side u = atan2(x − c.x, z − c.z)/2π wrapped to
//! [0, 1), v = (y − c.y)/h + 0.5; each cap like a disc in its x-z plane,
//! u = (x − c.x + r)/2r, v = (z − c.z + r)/2r with r that cap's radius.

use super::{Crossing, Hit, Shape, ray_point_error, solve_quadratic};
use crate::geometry::rounding::gamma;
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;
use std::f64::consts::PI;

#[derive(Clone, Debug)]
pub struct Cone {
    frustum: Frustum,
}

impl Cone {
    /// Base radius `radius` at centre.y − height/2, `top_radius` at centre.y + height/2.
    pub fn new(
        centre: DVec3,
        radius: f64,
        top_radius: f64,
        height: f64,
        side: MaterialId,
        caps: Option<[MaterialId; 2]>,
    ) -> Self {
        Cone {
            frustum: Frustum::new(centre, radius, top_radius, height, side, caps),
        }
    }
}

impl Shape for Cone {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        self.frustum.intersect(ray, t_min, t_max)
    }
    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        self.frustum.crossings(ray, out)
    }
    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.frustum.occludes(ray, t_min, t_max)
    }
    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        self.frustum.crossings_lite(ray, out)
    }
    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        self.frustum.hit_of(ray, c)
    }
    fn bounds(&self) -> Aabb {
        self.frustum.bounds()
    }
    fn is_solid(&self) -> bool {
        self.frustum.caps.is_some()
    }
    fn uv(&self, hit: &Hit) -> DVec2 {
        self.frustum.uv(hit)
    }
}

/// A cap's (u, v): the disc's, in the x-z plane (`q` relative to the centre).
fn cap_uv(q: DVec3, r: f64) -> DVec2 {
    DVec2::new((q.x + r) / (2.0 * r), (q.z + r) / (2.0 * r))
}

/// Which part of the frustum a crossing is on. Four bytes, not one: a
/// crossing's copy read its tag as four bytes where one had been stored,
/// and such a load cannot take its bytes from the store in flight (it
/// waits until the store reaches the cache): a tenth of `Frustum::sorted`
/// in the `csg` benchmark.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(u32)]
enum Surface {
    Side = 0,
    Top = 1,
    Bottom = 2,
}

/// The surface x² + z² = r(y)² (relative to the centre) between two
/// horizontal planes, where r runs linearly from `r0` at the bottom to `r1`
/// at the top; with caps it is a convex solid.
#[derive(Clone, Debug)]
pub(super) struct Frustum {
    centre: DVec3,
    r0: f64,
    r1: f64,
    height: f64,
    y0: f64,
    y1: f64,
    /// dr/dy.
    slope: f64,
    side: MaterialId,
    /// `[top, bottom]`.
    pub(super) caps: Option<[MaterialId; 2]>,
    /// False for degenerate input (no height, no radius, NaN): such a shape
    /// is simply never hit.
    valid: bool,
}

/// Relative slack on the rim tests, so a ray through the very edge of a cap
/// is not lost between the side's y-range test and the cap's radius test.
const RIM: f64 = 1e-9;

impl Frustum {
    pub(super) fn new(
        centre: DVec3,
        r0: f64,
        r1: f64,
        height: f64,
        side: MaterialId,
        caps: Option<[MaterialId; 2]>,
    ) -> Self {
        let valid = centre.is_finite()
            && r0.is_finite()
            && r1.is_finite()
            && height.is_finite()
            && r0 >= 0.0
            && r1 >= 0.0
            && r0.max(r1) > 0.0
            && height > 0.0;
        Frustum {
            centre,
            r0,
            r1,
            height,
            y0: centre.y - height / 2.0,
            y1: centre.y + height / 2.0,
            slope: if valid { (r1 - r0) / height } else { 0.0 },
            side,
            caps,
            valid,
        }
    }

    /// Candidate crossings along the whole line, unsorted: up to two on the
    /// side, one per cap.
    fn candidates(&self, ray: &Ray, out: &mut [(f64, Surface); 4]) -> usize {
        let mut n = 0;
        if !self.valid {
            return 0;
        }
        // Re-centred: the line's origin is moved to its closest point to the
        // centre (t = t_c), so that the quadratic's coefficients are of the
        // cone's own size even when the ray starts far away (the raw ones
        // lose the radius from 1e8). The roots are shifted back by t_c.
        let d = ray.dir;
        let dd = d.length_squared();
        let f = ray.origin - self.centre;
        let t_c = if dd > 0.0 { -f.dot(d) / dd } else { 0.0 };
        let o = f + t_c * d;
        let (y0, y1) = (self.y0 - self.centre.y, self.y1 - self.centre.y);
        let slack = RIM * self.height;
        // Radius where the ray's origin height meets the (extended) surface.
        let r_o = self.r0 + self.slope * (o.y - y0);
        let k = self.slope;
        let a = d.x * d.x + d.z * d.z - k * k * d.y * d.y;
        let b = 2.0 * (o.x * d.x + o.z * d.z - k * r_o * d.y);
        let c = o.x * o.x + o.z * o.z - r_o * r_o;
        let mut side = |s: f64| {
            let y = o.y + s * d.y;
            let t = t_c + s;
            if t.is_finite() && y >= y0 - slack && y <= y1 + slack {
                out[n] = (t, Surface::Side);
                n += 1;
            }
        };
        if a != 0.0 {
            if let Some((s0, s1)) = solve_quadratic(a, b, c) {
                side(s0);
                side(s1);
            }
        } else if b != 0.0 {
            // Parallel to the axis (cylinder) or to a generator (cone): one root.
            side(-c / b);
        }
        let o = ray.origin - self.centre;
        if self.caps.is_some() && d.y != 0.0 {
            for (y, r, s) in [(y1, self.r1, Surface::Top), (y0, self.r0, Surface::Bottom)] {
                let t = (y - o.y) / d.y;
                let (x, z) = (o.x + t * d.x, o.z + t * d.z);
                if r > 0.0 && x * x + z * z <= r * r * (1.0 + RIM) {
                    out[n] = (t, s);
                    n += 1;
                }
            }
        }
        n
    }

    /// The side's outward normal at `p`, unit length.
    fn side_normal(&self, p: DVec3) -> DVec3 {
        let q = p - self.centre;
        let r = self.r0 + self.slope * (p.y - self.y0);
        let n = DVec3::new(q.x, -r * self.slope, q.z);
        // Only the apex has no normal; there the axis is the best guess.
        let apex = if self.r0 > self.r1 {
            DVec3::Y
        } else {
            -DVec3::Y
        };
        n.try_normalize().unwrap_or(apex)
    }

    fn crossing(&self, ray: &Ray, t: f64, s: Surface) -> Crossing {
        let normal = match s {
            // Only the direction matters here, so no need to normalise
            // (except at the apex, which has no normal of its own).
            Surface::Side => {
                let p = ray.at(t);
                let q = p - self.centre;
                let r = self.r0 + self.slope * (p.y - self.y0);
                let n = DVec3::new(q.x, -r * self.slope, q.z);
                if n == DVec3::ZERO {
                    self.side_normal(p)
                } else {
                    n
                }
            }
            Surface::Top => DVec3::Y,
            Surface::Bottom => -DVec3::Y,
        };
        Crossing::new(t, normal, ray, s as u64)
    }

    pub(super) fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        let (c, n) = self.sorted(ray);
        c[..n].iter().any(|x| x.0 > t_min && x.0 < t_max)
    }

    pub(super) fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        let (c, n) = self.sorted(ray);
        out.extend(c[..n].iter().map(|&(t, s)| self.crossing(ray, t, s)));
    }

    pub(super) fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        let s = match c.key {
            1 => Surface::Top,
            2 => Surface::Bottom,
            _ => Surface::Side,
        };
        self.hit_at(ray, c.t, s)
    }

    fn hit_at(&self, ray: &Ray, t: f64, s: Surface) -> Hit {
        let p = ray.at(t);
        let q = p - self.centre;
        let (normal, uv, material) = match s {
            // The side's (u, v) needs atan2: left to `uv`.
            Surface::Side => (self.side_normal(p), DVec2::ZERO, self.side),
            Surface::Top | Surface::Bottom => {
                let caps = self.caps.unwrap_or([self.side; 2]);
                let (r, n, m) = if s == Surface::Top {
                    (self.r1, DVec3::Y, caps[0])
                } else {
                    (self.r0, -DVec3::Y, caps[1])
                };
                (n, cap_uv(q, r), m)
            }
        };
        let (point, p_error) = self.reproject(ray, t, s);
        Hit {
            t,
            normal,
            uv,
            local: p,
            point,
            p_error,
            geo_normal: normal,
            material,
            path: 0,
        }
    }

    /// The hit point put back on its surface, with its error bound. A cap's
    /// point is snapped to the cap's plane (exact in y). A side point keeps
    /// its height and has its distance from the axis set to r(y), so the
    /// error of `t` (large for a grazing ray) no longer matters: what is
    /// left is the rounding of r(y) and of the rescaling, a few γ of the
    /// magnitudes involved.
    fn reproject(&self, ray: &Ray, t: f64, s: Surface) -> (DVec3, DVec3) {
        let p = ray.at(t);
        match s {
            Surface::Top | Surface::Bottom => {
                let y = if s == Surface::Top { self.y1 } else { self.y0 };
                let mut err = ray_point_error(ray, t);
                err.y = 0.0;
                (DVec3::new(p.x, y, p.z), err)
            }
            Surface::Side => {
                let q = p - self.centre;
                let rho = q.x.hypot(q.z);
                let r = self.r0 + self.slope * (p.y - self.y0);
                if rho == 0.0 || !r.is_finite() || r < 0.0 {
                    return (
                        p,
                        ray_point_error(ray, t) + DVec3::splat(gamma(8) * self.r0.max(self.r1)),
                    );
                }
                let k = r / rho;
                let q = DVec3::new(q.x * k, q.y, q.z * k);
                let point = self.centre + q;
                // r(y): γ₄ of its terms; the scale and the centre's sum a few more.
                let r_err = gamma(4) * (self.r0.abs() + (self.slope * (p.y - self.y0)).abs());
                let radial = gamma(6) * q.abs() + DVec3::new(r_err, 0.0, r_err);
                (point, radial + gamma(1) * point.abs())
            }
        }
    }

    /// Texture coordinates of a hit this frustum returned: a point on a cap's
    /// plane strictly inside its rim is a cap hit, anything else the side
    /// (a ray along a cap's plane meets the side at the rim).
    pub(super) fn uv(&self, hit: &Hit) -> DVec2 {
        let q = hit.local - self.centre;
        if self.caps.is_some() {
            let slack = RIM * self.height;
            let rho2 = q.x * q.x + q.z * q.z;
            for (y, r) in [(self.y1, self.r1), (self.y0, self.r0)] {
                if (hit.local.y - y).abs() <= slack && rho2 < r * r * (1.0 - RIM) {
                    return cap_uv(q, r);
                }
            }
        }
        let mut u = q.x.atan2(q.z) / (2.0 * PI);
        if u < 0.0 {
            u += 1.0;
        }
        DVec2::new(u.min(1.0 - f64::EPSILON), q.y / self.height + 0.5)
    }

    /// The crossings in increasing t: for a solid only the first and the last
    /// candidate (the shape is convex, so anything between is a duplicate at a
    /// rim), for a tube all of them. Inlined: returned through memory, its
    /// crossings were stored in parts and read back 16 bytes at a time (a
    /// stalled store-to-load forward, a quarter of `crossings_lite`).
    #[inline(always)]
    fn sorted(&self, ray: &Ray) -> ([(f64, Surface); 4], usize) {
        let mut c = [(0.0, Surface::Side); 4];
        let n = self.candidates(ray, &mut c);
        if self.caps.is_some() {
            if n < 2 {
                return (c, 0);
            }
            let (mut lo, mut hi) = (c[0], c[0]);
            for &x in &c[1..n] {
                if x.0 < lo.0 {
                    lo = x;
                }
                if x.0 > hi.0 {
                    hi = x;
                }
            }
            return ([lo, hi, lo, hi], 2);
        }
        // A tube has at most the two side roots, already in order.
        (c, n)
    }

    pub(super) fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let (c, n) = self.sorted(ray);
        c[..n]
            .iter()
            .find(|x| x.0 > t_min && x.0 < t_max)
            .map(|&(t, s)| self.hit_at(ray, t, s))
    }

    pub(super) fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        let (c, n) = self.sorted(ray);
        out.extend(c[..n].iter().map(|&(t, s)| self.hit_at(ray, t, s)));
    }

    pub(super) fn bounds(&self) -> Aabb {
        if !self.valid {
            return Aabb::EMPTY;
        }
        let r = self.r0.max(self.r1);
        let e = DVec3::new(r, self.height / 2.0, r);
        Aabb::new(self.centre - e, self.centre + e)
    }
}

#[cfg(test)]
#[path = "cone_tests.rs"]
mod tests;
