//! The implicit surface as a shape: the compiled equation plus a box.
//!
//! Inside a box, the ray is re-parameterised over the chord it cuts:
//! t = t_mid + s·h with s in [−1, 1], so the coefficients of s are those of
//! a polynomial about a point inside the box and of a step the box's size.
//! That keeps them well scaled whatever the distance to the camera, which is
//! what lets a degree-40 power cube come out without missed pixels.
//! Without a box (unbounded surfaces) the ray's own t is used, over an
//! interval that contains every root (the Cauchy bound).
//!
//! Normals are the polynomial's gradient, which points out of the solid
//! (the side where the polynomial is positive). Where the gradient vanishes
//! (singular points such as the heart's seam or a cone's apex), the normal
//! is deliberately the reversed ray direction, so the point is shaded as
//! facing the viewer instead of turning black or NaN.

use super::Equation;
use super::ray_poly::CAP;
use super::solve::{no_root_in_unit, roots_in};
use crate::geometry::rounding::gamma;
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;
use crate::shapes::{Hit, Shape};

#[derive(Debug)]
pub struct ImplicitSurface {
    equation: Equation,
    /// Finite when the surface is bounded (given or found).
    bounds: Aabb,
    material: MaterialId,
    /// Whether the box came from `bounded_by`, the automatic search, or
    /// neither (see [`ImplicitSurface::bound_note`]).
    source: BoundSource,
    /// Whether the nearest hit shows the faces of a given box where the box
    /// cuts the solid, as the crossings always do (see
    /// [`ImplicitSurface::solid_in_box`]).
    solid_in_box: bool,
    /// In a finite box, the rounding noise of the polynomial's value
    /// anywhere in it (see [`ImplicitSurface::root_error`]): the same for
    /// every hit, so worked out once here rather than per hit.
    box_noise: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundSource {
    Given,
    Automatic,
    Unbounded,
}

impl ImplicitSurface {
    /// With `bounded_by: None` a bound is searched for automatically; when
    /// none is found the surface is traced unbounded (correct, but every ray
    /// in the scene pays for it; see `bound_note`).
    pub fn new(equation: Equation, bounded_by: Option<Aabb>, material: MaterialId) -> Self {
        let (bounds, source) = match bounded_by {
            Some(b) => (b, BoundSource::Given),
            None => match equation.auto_bounds() {
                Some(b) => (b, BoundSource::Automatic),
                None => (Aabb::INFINITE, BoundSource::Unbounded),
            },
        };
        let box_noise = if bounds.is_finite() {
            let corner = bounds.min.abs().max(bounds.max.abs());
            noise(&equation, corner)
        } else {
            0.0
        };
        ImplicitSurface {
            equation,
            bounds,
            material,
            source,
            solid_in_box: false,
            box_noise,
        }
    }

    /// The surface as a solid in CSG: "equation < 0 inside the box", so
    /// that its nearest hit is the first of its crossings, box faces
    /// included where `bounded_by` cuts it (CSG asks a lone child of a union
    /// for its nearest hit). Alone, a bounded surface is the surface clipped
    /// to its box, open where the box cuts it.
    pub fn solid_in_box(mut self) -> Self {
        self.solid_in_box = true;
        self
    }

    /// Whether the nearest hit must come from the crossings: a given box
    /// may cut the solid, an automatic one only pads it.
    fn faces_may_show(&self) -> bool {
        self.solid_in_box && self.source == BoundSource::Given
    }

    /// The first crossing with `lo < t < hi`, box faces included.
    fn first_crossing(&self, ray: &Ray, lo: f64, hi: f64) -> Option<Hit> {
        let mut xs = Vec::new();
        self.crossings(ray, &mut xs);
        xs.into_iter().find(|h| h.t > lo && h.t < hi)
    }

    pub fn equation(&self) -> &Equation {
        &self.equation
    }

    pub fn bound_source(&self) -> BoundSource {
        self.source
    }

    /// A warning for the user when no bound was given or found.
    pub fn bound_note(&self) -> Option<String> {
        (self.source == BoundSource::Unbounded).then(|| {
            "no bounding box could be found for this implicit surface (it may be unbounded): \
             it is traced unbounded, which every ray pays for; add `bounded_by <min> <max>` \
             to clip it"
                .to_string()
        })
    }

    /// Visits the roots along the ray with t in [lo, hi], in increasing
    /// order, that lie on the written branch, until `visit` returns true.
    fn roots(&self, ray: &Ray, lo: f64, hi: f64, visit: impl FnMut(f64, DVec3) -> bool) {
        match self.equation.degree {
            0..=4 => self.roots_n::<5>(ray, lo, hi, visit),
            5..=6 => self.roots_n::<7>(ray, lo, hi, visit),
            7..=12 => self.roots_n::<13>(ray, lo, hi, visit),
            13..=20 => self.roots_n::<21>(ray, lo, hi, visit),
            _ => self.roots_n::<CAP>(ray, lo, hi, visit),
        }
    }

    fn roots_n<const N: usize>(
        &self,
        ray: &Ray,
        lo: f64,
        hi: f64,
        mut visit: impl FnMut(f64, DVec3) -> bool,
    ) {
        let mut c = [0.0; N];
        if self.bounds.is_finite() {
            let Some((a, b)) = self.bounds.clip(ray, lo, hi) else {
                return;
            };
            let (mid, h) = (0.5 * (a + b), 0.5 * (b - a));
            if h.is_nan() || h <= 0.0 {
                return;
            }
            let n = self.equation.value.along(ray.at(mid), ray.dir * h, &mut c);
            if no_root_in_unit(&c[..n]) {
                return;
            }
            roots_in(&c[..n], -1.0, 1.0, 1e-13, |s| {
                let t = mid + s * h;
                let p = ray.at(t);
                t > lo && t < hi && self.equation.on_written_branch(p) && visit(t, p)
            });
        } else {
            // Solved for the distance u = t·|dir| along the unit direction:
            // the precision asked, and Newton's stop a step below its
            // square root, are then those of space whatever the ray's
            // length (a moved surface's rays are not unit). Solved in t,
            // a thin torus's hits from rays 1024 long lay up to 20 times
            // their error bound off the surface.
            //
            // The polynomial is expanded about the point of the line
            // nearest the origin (distance `near` along it), not about
            // the ray's origin: its coefficients then have the magnitude
            // of the part of space the line passes through, and a ray from
            // 10⁵ away keeps the digits a surface near the origin needs
            // (expanded about the far origin, a tube 0.06 thick was hit
            // 0.04 off from 10³ away, and 20 off from 10⁵).
            let len = ray.dir.length();
            let dir = ray.dir / len;
            let near = -ray.origin.dot(dir);
            let n = self
                .equation
                .value
                .along(ray.origin + near * dir, dir, &mut c);
            let Some(bound) = cauchy_bound(&c[..n]) else {
                return;
            };
            let (a, b) = ((lo * len - near).max(-bound), (hi * len - near).min(bound));
            let eps = 1e-13 * (1.0 + a.abs().max(b.abs()).min(1e6));
            roots_in(&c[..n], a, b, eps, |u| {
                let t = (near + u) / len;
                let p = ray.at(t);
                t > lo && t < hi && self.equation.on_written_branch(p) && visit(t, p)
            });
        }
    }

    fn hit_at(&self, ray: &Ray, t: f64, p: DVec3) -> Hit {
        // One gradient serves both the normal and the error bound.
        let g = self.equation.gradient(p);
        let normal = self.normal_at(g, p, ray.dir);
        Hit {
            t,
            normal,
            uv: DVec2::ZERO,
            local: p,
            point: p,
            p_error: self.root_error(ray, t, g.length()),
            geo_normal: normal,
            material: self.material,
            path: 0,
        }
    }

    /// A bound on the error of a root's point `ray.at(t)`. The root finder
    /// stops within 1e-13 of the parameter it searched (s ∈ [−1, 1] over
    /// the chord through the box, so 1e-13 of the box's diagonal in space;
    /// on an unbounded surface, 1e-13·(1 + |t·dir|) in the distance along
    /// the ray, which it searches), plus the rounding of
    /// `ray.at(t)`. But the root is a root of the polynomial along the ray,
    /// whose coefficients carry rounding of about γ₄ₙ (n the degree) times
    /// the magnitude of the terms they sum ([`Equation::magnitude`] over
    /// the box): within that of zero the sign is noise, so a root may lie
    /// anywhere in a shell of thickness noise/|∇f| around the surface, and
    /// so may a secondary ray's. Where the gradient nearly vanishes (the
    /// heart's seam) that shell is thick; it is capped at 1e-6 of the
    /// box's diagonal. Unbounded, magnitude, noise and cap are those of 1 +
    /// the reach from the ray's origin to the point (not the point alone: a
    /// ray from afar through a cone's apex, |p| ≈ 0, has a root as far off
    /// as its scale's rounding allows), which bounds the terms about the
    /// line's point nearest the world's origin, where the polynomial is
    /// expanded. `slope` is |∇f| at the point.
    fn root_error(&self, ray: &Ray, t: f64, slope: f64) -> DVec3 {
        let (along, cap, noise) = if self.bounds.is_finite() {
            let diag = self.bounds.extent().length();
            (4e-13 * diag, 1e-6 * diag, self.box_noise)
        } else {
            // Unbounded: the rounding of the terms over the whole reach from
            // the ray's origin to the point, not only near p (a bound on the
            // terms about the line's point nearest the world's origin).
            let size = 1.0 + (ray.origin.abs() + (t * ray.dir).abs()).max_element();
            (
                4e-13 * (1.0 + (t * ray.dir).length()),
                1e-6 * size,
                noise(&self.equation, DVec3::splat(2.0 * size)),
            )
        };
        let shell = if slope > 0.0 { noise / slope } else { cap };
        let rounding = gamma(16) * (ray.origin.abs() + (t * ray.dir).abs());
        DVec3::splat(along + shell.min(cap)) + rounding
    }

    /// The hit on the face of the box where the line enters (or leaves) it
    /// at `t`, with the face's normal turned against the ray when entering.
    fn box_face_hit(&self, ray: &Ray, t: f64, entering: bool) -> Hit {
        let p = ray.at(t);
        let normal = box_face_normal(&self.bounds, p);
        let normal = if (normal.dot(ray.dir) < 0.0) == entering {
            normal
        } else {
            -normal
        };
        Hit {
            t,
            normal,
            geo_normal: normal,
            point: p,
            p_error: crate::shapes::ray_point_error(ray, t),
            uv: DVec2::ZERO,
            local: p,
            material: self.material,
            path: 0,
        }
    }

    /// Whether `p` lies inside the solid: where the written equation is
    /// negative (its roots on their principal branch; where it is undefined,
    /// outside). Without roots that is the polynomial's sign.
    fn inside(&self, p: DVec3) -> bool {
        match &self.equation.branch {
            None => self.equation.value(p) < 0.0,
            Some(tree) => super::expand::eval(tree, p).is_some_and(|d| d.v < 0.0),
        }
    }

    /// The outward normal at `p` from the gradient `g` there.
    fn normal_at(&self, mut g: DVec3, p: DVec3, dir: DVec3) -> DVec3 {
        if let Some(tree) = &self.equation.branch {
            // The eliminated polynomial may be negative outside: orient by the
            // written expression's own gradient where it exists.
            if let Some(d) = super::expand::eval(tree, p)
                && d.g.is_finite()
                && g.dot(d.g) < 0.0
            {
                g = -g;
            }
        }
        let scale = 1e-12 * (1.0 + p.abs().max_element()).powi(self.equation.degree as i32);
        if g.is_finite() && g.length() > scale {
            g
        } else {
            -dir
        }
    }
}

/// The rounding noise of the polynomial's value at points within `reach`
/// of the origin (per coordinate): γ₄ₙ (n the degree) times the magnitude
/// of the terms it sums.
fn noise(equation: &Equation, reach: DVec3) -> f64 {
    gamma(4 * equation.degree().max(1)) * equation.magnitude(reach)
}

/// The outward normal of the face of `b` nearest to `p` (a point on the
/// box's surface): the axis and side where p is closest to the box's wall,
/// measured against the box's size on that axis.
fn box_face_normal(b: &Aabb, p: DVec3) -> DVec3 {
    let size = b.extent().max(DVec3::splat(f64::MIN_POSITIVE));
    let mut best = (f64::INFINITY, DVec3::X);
    for axis in 0..3 {
        for (wall, sign) in [(b.min[axis], -1.0), (b.max[axis], 1.0)] {
            let gap = (p[axis] - wall).abs() / size[axis];
            if gap < best.0 {
                let mut n = DVec3::ZERO;
                n[axis] = sign;
                best = (gap, n);
            }
        }
    }
    best.1
}

/// Every real root of c has |t| ≤ 1 + max |c_k / c_n|; `None` for a
/// polynomial that is identically zero (a ray lying in the surface).
fn cauchy_bound(c: &[f64]) -> Option<f64> {
    let n = c.iter().rposition(|&k| k != 0.0)?;
    if n == 0 {
        return None;
    }
    let lead = c[n].abs();
    let m = c[..n].iter().fold(0.0f64, |m, k| m.max(k.abs() / lead));
    Some((1.0 + m).min(1e12))
}

impl Shape for ImplicitSurface {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        if self.faces_may_show() {
            return self.first_crossing(ray, t_min, t_max);
        }
        let mut found = None;
        self.roots(ray, t_min, t_max, |t, p| {
            found = Some((t, p));
            true
        });
        found.map(|(t, p)| self.hit_at(ray, t, p))
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        if self.faces_may_show() {
            return self.first_crossing(ray, t_min, t_max).is_some();
        }
        let mut any = false;
        self.roots(ray, t_min, t_max, |_, _| {
            any = true;
            true
        });
        any
    }

    /// For CSG the crossings must alternate, entering and leaving. A root
    /// alone does not say which it is: a grazing ray gives a double root
    /// (found once, twice or not at all) where the line only touches the
    /// surface, and at singular points the gradient says nothing. So the
    /// side of the surface is read off the equation's sign between roots:
    /// a root is a crossing where the side changes, and its normal is turned
    /// to agree (against the ray when entering).
    ///
    /// A bounded surface's solid is "equation < 0 inside the box": where the
    /// box cuts the solid (the line enters the box with the equation
    /// negative, or leaves it so), the box face is a crossing too, so that
    /// an implicit cylinder cut by its box is the capped `cylinder`.
    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        let mut ts: Vec<(f64, DVec3)> = Vec::new();
        self.roots(ray, f64::NEG_INFINITY, f64::INFINITY, |t, p| {
            ts.push((t, p));
            false
        });
        // The line's stretch through the box, for a bounded surface.
        let chord = if self.bounds.is_finite() {
            match self.bounds.clip(ray, f64::NEG_INFINITY, f64::INFINITY) {
                Some((a, b)) if a < b => Some((a, b)),
                _ => return,
            }
        } else {
            None
        };
        let far = |t: f64| self.inside(ray.at(t));
        let mut before = match (chord, ts.first()) {
            (Some((a, b)), first) => {
                let end = first.map_or(b, |&(t, _)| t);
                let cut = self.inside(ray.at(0.5 * (a + end)));
                if cut {
                    out.push(self.box_face_hit(ray, a, true));
                }
                cut
            }
            (None, Some(&(first, _))) => far(first - (1.0 + first.abs())),
            (None, None) => return,
        };
        for (k, &(t, p)) in ts.iter().enumerate() {
            let after = match (ts.get(k + 1), chord) {
                (Some(&(next, _)), _) => self.inside(ray.at(0.5 * (t + next))),
                (None, Some((_, b))) => self.inside(ray.at(0.5 * (t + b))),
                (None, None) => far(t + 1.0 + t.abs()),
            };
            if after != before {
                let mut h = self.hit_at(ray, t, p);
                if (h.normal.dot(ray.dir) < 0.0) != after {
                    h = h.flipped();
                }
                out.push(h);
            }
            before = after;
        }
        if let (Some((_, b)), true) = (chord, before) {
            out.push(self.box_face_hit(ray, b, false));
        }
    }

    fn encloses(&self, p: DVec3) -> bool {
        self.bounds.contains(p) && self.inside(p)
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn is_solid(&self) -> bool {
        true
    }
}
