//! Shapes: each file is one kind of surface, opening with its `.rt` syntax.
//!
//! Every shape works in its own space and answers two questions about a ray
//! `origin + t·dir` (where `dir` need not be unit length, see [`Ray`]):
//! the nearest hit in an interval, and every crossing of its surface along
//! the whole line (constructive solid geometry needs those). Placement in the
//! world is [`Transformed`]'s job, not the shape's.

mod cone;
pub mod csg;
mod cuboid;
mod cylinder;
mod disc;
pub mod mesh;
mod plane;
pub mod ply;
mod rectangle;
mod shared;
mod sphere;
mod torus;
mod transformed;
mod triangle;

pub use cone::Cone;
pub use csg::{Csg, CsgOp};
pub use cuboid::Cuboid;
pub use disc::Disc;
pub use mesh::{Mesh, MeshData};
pub use plane::Plane;
pub use rectangle::Rectangle;
pub use shared::Shared;
pub use sphere::Sphere;
pub use torus::Torus;
pub use transformed::Transformed;
pub use triangle::Triangle;

use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;

/// Where a ray meets a surface.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Hit {
    /// Ray parameter; the same in world and object space.
    pub t: f64,
    /// The outward normal of the surface at the hit (pointing out of the
    /// solid for closed shapes; the shape's own front side for open ones).
    /// Not necessarily unit length, and NOT turned towards the ray: the
    /// renderer does that. CSG relies on it to tell entering from leaving.
    pub normal: DVec3,
    /// Texture coordinates as listed in conventions.md, where they cost
    /// next to nothing (planes, discs, boxes, triangles, meshes, cylinder
    /// and cone caps). Shapes that need trigonometry for them (sphere,
    /// cone and cylinder sides, torus) leave them zero here and give them
    /// through [`Shape::uv`], which the renderer asks only for the hit it
    /// shades and only when its texture reads (u, v): CSG finds many
    /// crossings per ray and shades one.
    pub uv: DVec2,
    /// The hit point in the shape's own space (before any transform), for
    /// solid textures that must move with the object.
    pub local: DVec3,
    pub material: MaterialId,
    /// Which child the hit came from at each enclosing CSG operation, so
    /// that [`Shape::uv`] can ask the shape that made the hit (see
    /// [`Csg`]); 0 outside CSG.
    pub path: u64,
}

/// A crossing without its shading data, for constructive solid geometry,
/// which looks at every crossing along a line but shades at most one: the
/// full [`Hit`] is made only for that one, by [`Shape::hit_of`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    pub t: f64,
    /// normal·dir with the outward normal: negative entering, positive
    /// leaving (the same in every space an affine transform maps to).
    pub facing: f64,
    /// So nearly along the surface that the sign of `facing` is noise (the
    /// double root of a tangent ray).
    pub grazing: bool,
    /// The shape's own note of which crossing this is, for `hit_of`.
    pub key: u64,
}

impl Crossing {
    /// The crossing at `t` with outward normal `n` (any length) on `ray`.
    pub fn new(t: f64, n: DVec3, ray: &Ray, key: u64) -> Crossing {
        let facing = n.dot(ray.dir);
        Crossing {
            t,
            facing,
            grazing: facing * facing <= 1e-18 * n.length_squared() * ray.dir.length_squared(),
            key,
        }
    }
}

thread_local! {
    static LITE_TMP: std::cell::Cell<Vec<Hit>> = const { std::cell::Cell::new(Vec::new()) };
}

/// A surface the renderer can trace.
pub trait Shape: Send + Sync + std::fmt::Debug {
    /// The nearest hit with `t_min < t < t_max`.
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit>;

    /// Whether anything lies on the ray with `t_min < t < t_max`
    /// (shadow rays: no shading data needed).
    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.intersect(ray, t_min, t_max).is_some()
    }

    /// Every crossing of the surface along the whole line (any `t`, negative
    /// too), appended to `out` in increasing `t`. For a closed solid they
    /// alternate entering / leaving, which the sign of `normal · dir` tells.
    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>);

    /// [`Shape::crossings`] without shading data. The default makes the full
    /// hits and keeps each one's place in the list as its key; shapes that
    /// CSG meets often make their crossings directly.
    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        let mut hits = LITE_TMP.take();
        hits.clear();
        self.crossings(ray, &mut hits);
        out.extend(
            hits.iter()
                .enumerate()
                .map(|(k, h)| Crossing::new(h.t, h.normal, ray, k as u64)),
        );
        LITE_TMP.set(hits);
    }

    /// The full hit of a crossing that [`Shape::crossings_lite`] gave for
    /// the same ray. The default finds it again in the list of hits.
    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        let mut hits = Vec::new();
        self.crossings(ray, &mut hits);
        hits.get(c.key as usize).copied().unwrap_or(Hit {
            t: c.t,
            normal: ray.dir * c.facing.signum(),
            ..Hit::default()
        })
    }

    /// A box around the shape in its own space; `Aabb::INFINITE` when
    /// unbounded.
    fn bounds(&self) -> Aabb;

    /// Whether the shape encloses a volume (so CSG may use it).
    fn is_solid(&self) -> bool;

    /// Whether `p` lies inside the solid. CSG asks this only of an unbounded
    /// shape whose crossings a line has none of (a ray parallel to a plane),
    /// to learn whether the whole line is inside; a bounded shape never
    /// needs it, so the default says no.
    fn encloses(&self, _p: DVec3) -> bool {
        false
    }

    /// The texture coordinates of a hit this shape returned. The default is
    /// what the shape filled in as it went; shapes whose (u, v) need
    /// trigonometry compute them here instead, once per shaded hit.
    fn uv(&self, hit: &Hit) -> DVec2 {
        hit.uv
    }
}

/// Möller–Trumbore for a flat patch spanned by `e1` and `e2` from
/// `origin`: the line's (t, u, v) with the point at origin + u·e1 + v·e2,
/// when 0 ≤ u ≤ 1 and `accept(u, v)` (the patch's shape: a triangle or a
/// parallelogram). `None` for a line parallel to the patch or a degenerate
/// patch, whose determinant is zero for every line.
pub(crate) fn planar_hit(
    origin: DVec3,
    e1: DVec3,
    e2: DVec3,
    ray: &Ray,
    accept: impl Fn(f64, f64) -> bool,
) -> Option<(f64, f64, f64)> {
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = ray.origin - origin;
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv;
    if !accept(u, v) {
        return None;
    }
    let t = e2.dot(q) * inv;
    t.is_finite().then_some((t, u, v))
}

/// Solves a·t² + b·t + c = 0 (a ≠ 0) without cancellation: the root of the
/// larger magnitude comes from the q-form `q = -(b + sign(b)·√disc)/2`, the
/// other from `c / q`, so neither subtracts nearly equal numbers.
pub fn solve_quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 || a == 0.0 {
        return None;
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    if q == 0.0 {
        return Some((0.0, 0.0));
    }
    let (t0, t1) = (q / a, c / q);
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

#[cfg(test)]
pub(crate) mod testing {
    //! Property helpers every shape's tests share.
    use super::*;

    /// Rays from random points on a big sphere around `target`, aimed near it.
    pub fn rays_towards(target: DVec3, spread: f64, n: usize, seed: u64) -> Vec<Ray> {
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
        let mut rnd = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
        };
        (0..n)
            .map(|_| {
                let o = target + DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X) * 10.0;
                let aim = target + DVec3::new(rnd(), rnd(), rnd()) * spread;
                Ray::new(o, (aim - o).normalize())
            })
            .collect()
    }

    /// The nearest hit must be the first of the crossings in range, and a ray
    /// leaving the surface from the hit must not hit it again at once.
    pub fn check_consistency(shape: &dyn Shape, rays: &[Ray]) {
        for r in rays {
            let hit = shape.intersect(r, 1e-9, f64::INFINITY);
            let mut xs = Vec::new();
            shape.crossings(r, &mut xs);
            let first = xs.iter().find(|h| h.t > 1e-9);
            match (hit, first) {
                (Some(h), Some(f)) => assert!((h.t - f.t).abs() < 1e-6, "{h:?} vs {f:?}"),
                (None, None) => {}
                (h, f) => panic!("nearest {h:?} but crossings {f:?} for {r:?}"),
            }
            for w in xs.windows(2) {
                assert!(w[0].t <= w[1].t, "crossings out of order");
            }
        }
    }

    /// A ray leaving the surface from a hit, straight on or mirrored, must not
    /// meet the surface again at (nearly) the same point.
    pub fn check_no_rehit(shape: &dyn Shape, rays: &[Ray]) {
        for r in rays {
            let Some(h) = shape.intersect(r, 1e-9, f64::INFINITY) else {
                continue;
            };
            let p = r.at(h.t);
            let n = h.normal.normalize();
            let d = r.dir.normalize();
            for dir in [d, d - 2.0 * d.dot(n) * n] {
                let again = shape.intersect(&Ray::new(p, dir), 1e-9, f64::INFINITY);
                if let Some(a) = again {
                    assert!(a.t > 1e-6, "re-hit at t = {} from {p:?} along {dir:?}", a.t);
                }
            }
        }
    }

    /// The normal agrees with finite differences: hits of rays shifted a
    /// little sideways lie in the tangent plane (up to second order). Pairs
    /// that land on a different face (the normals disagree) are skipped.
    pub fn check_normals(shape: &dyn Shape, rays: &[Ray]) -> usize {
        let mut checked = 0;
        for r in rays {
            let Some(h) = shape.intersect(r, 1e-9, f64::INFINITY) else {
                continue;
            };
            let p = r.at(h.t);
            let n = h.normal.normalize();
            assert!(n.is_finite(), "normal {:?}", h.normal);
            let side = r.dir.any_orthonormal_pair();
            for off in [side.0, side.1] {
                let shifted = Ray::new(r.origin + off * 1e-5, r.dir);
                let Some(h2) = shape.intersect(&shifted, 1e-9, f64::INFINITY) else {
                    continue;
                };
                if h2.normal.normalize().dot(n) < 0.99 {
                    continue;
                }
                let q = shifted.at(h2.t);
                let gap = (q - p).dot(n).abs();
                assert!(
                    gap < 1e-3 * (q - p).length() + 1e-12,
                    "normal {n:?} at {p:?} vs {q:?}"
                );
                checked += 1;
            }
        }
        checked
    }

    /// Rays starting outside a solid's bounds cross it an even number of
    /// times, alternately entering (normal against the ray) and leaving.
    pub fn check_alternation(shape: &dyn Shape, rays: &[Ray]) {
        for r in rays {
            let mut xs = Vec::new();
            shape.crossings(r, &mut xs);
            assert!(xs.len().is_multiple_of(2), "odd crossings {xs:?}");
            for (i, h) in xs.iter().enumerate() {
                let entering = h.normal.dot(r.dir) < 0.0;
                assert_eq!(entering, i % 2 == 0, "crossing {i} of {xs:?}");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_is_stable_for_tiny_roots() {
        // Roots 1e-9 and 1e9: the naive formula loses the small one.
        let (a, b) = solve_quadratic(1.0, -(1e9 + 1e-9), 1.0).unwrap();
        assert!((a - 1e-9).abs() / 1e-9 < 1e-6);
        assert!((b - 1e9).abs() / 1e9 < 1e-12);
        assert!(solve_quadratic(1.0, 0.0, 1.0).is_none());
    }
}
