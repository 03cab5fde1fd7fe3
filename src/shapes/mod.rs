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
mod rectangle;
mod shared;
mod sphere;
mod torus;
mod transformed;
mod triangle;

#[cfg(test)]
mod offset_tests;

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
    /// The hit point in the space of the hit (the world, once out of
    /// [`Transformed`]), as the shape computed it on its surface (often
    /// re-projected onto it, so better than `ray.at(t)`). Secondary rays
    /// start here, moved off by [`crate::geometry::offset_ray_origin`].
    /// A smooth mesh's point is lifted off its facet towards the incoming
    /// ray, onto the curved surface its vertex normals describe (Hanika's
    /// shadow-terminator fix), by at most the facet's sagitta: a ray that
    /// leaves into the far side (refraction) should start from the facet,
    /// `ray.at(t)`, instead (not yet needed: no shape is transparent).
    pub point: DVec3,
    /// A bound on `point`'s absolute error in each coordinate: the true
    /// surface point lies within ±`p_error` of it (pbrt-v4's pError).
    pub p_error: DVec3,
    /// The outward normal of the surface actually intersected (a mesh's
    /// face, not its interpolated normal), oriented as `normal` is and not
    /// necessarily unit length. It decides which side a ray is on and where
    /// secondary rays start; `normal` is for shading only.
    pub geo_normal: DVec3,
    pub material: MaterialId,
    /// Which child the hit came from at each enclosing CSG operation, so
    /// that [`Shape::uv`] can ask the shape that made the hit (see
    /// [`Csg`]); 0 outside CSG.
    pub path: u64,
}

impl Hit {
    /// The same hit seen from the other side (a CSG cutter's surface, an
    /// inward-wound mesh): both normals reversed.
    pub fn flipped(self) -> Hit {
        Hit {
            normal: -self.normal,
            geo_normal: -self.geo_normal,
            ..self
        }
    }

    /// [`Hit::flipped`] in place (no copy of the whole hit).
    pub fn flip(&mut self) {
        self.normal = -self.normal;
        self.geo_normal = -self.geo_normal;
    }
}

/// The error bound of `ray.at(t)` from rounding alone (t taken as exact):
/// γ₂ of the magnitudes the sum adds. Shapes that snap or re-project the
/// point onto their surface need only their own, smaller bound.
pub(crate) fn ray_point_error(ray: &Ray, t: f64) -> DVec3 {
    crate::geometry::rounding::gamma(2) * (ray.origin.abs() + (t * ray.dir).abs())
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

/// [`Shape::intersect_into`] for a shape that finds its root `t` first
/// and then builds the hit from it: `hit_at(t)` written into `hit`, or
/// false (and `hit` untouched) when there is no root.
#[inline(always)]
pub(crate) fn write_hit(t: Option<f64>, hit: &mut Hit, hit_at: impl FnOnce(f64) -> Hit) -> bool {
    let Some(t) = t else {
        return false;
    };
    *hit = hit_at(t);
    true
}

thread_local! {
    static LITE_TMP: std::cell::Cell<Vec<Hit>> = const { std::cell::Cell::new(Vec::new()) };
}

/// [`Roots::nearest_roots`] one ray after another, `root(ray, limit)`
/// being the shape's nearest root within (t_min, limit).
pub(crate) fn nearest_roots_each(
    rays: &[Ray],
    best: &mut [f64],
    won: &mut [bool],
    root: impl Fn(&Ray, f64) -> Option<f64>,
) {
    for ((ray, b), w) in rays.iter().zip(best).zip(won) {
        if let Some(t) = root(ray, *b) {
            *b = t;
            *w = true;
        }
    }
}

/// Shapes whose nearest root costs far less than their hit (a sphere's
/// or a plane's hit re-projects its point and bounds its error): a pixel's
/// camera rays are tested against such a shape together, and only the
/// rays it keeps in the end get its hit ([`crate::accel::World::first_hits`]).
pub trait Roots {
    /// For each ray, the root [`Shape::intersect_into`] would hit within
    /// (t_min, best[i]): written over best[i], with won[i] set. Nothing
    /// else changes.
    fn nearest_roots(&self, rays: &[Ray], t_min: f64, best: &mut [f64], won: &mut [bool]);

    /// The root [`Shape::intersect_into`] would hit within (t_min,
    /// t_max) for one ray (the world asks an unbounded shape so, and
    /// makes its hit only if nothing else comes nearer).
    fn root_within(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<f64> {
        let (mut best, mut won) = ([t_max], [false]);
        self.nearest_roots(std::slice::from_ref(ray), t_min, &mut best, &mut won);
        won[0].then_some(best[0])
    }

    /// The hit [`Shape::intersect_into`] makes at root `t` of `ray`,
    /// written into `hit` (handed back, its 160 bytes were copied).
    fn hit_at_root(&self, ray: &Ray, t: f64, hit: &mut Hit);
}

/// A surface the renderer can trace.
pub trait Shape: Send + Sync + std::fmt::Debug {
    /// The nearest hit with `t_min < t < t_max`.
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit>;

    /// [`Shape::intersect`] written into `hit` (left as it was on a miss).
    /// The world's nearest-hit query keeps one hit for the whole search:
    /// the commonest shapes build theirs there, and a transform passes it
    /// through, where a hit handed back in an `Option` is copied (160
    /// bytes) at every level it goes up.
    fn intersect_into(&self, ray: &Ray, t_min: f64, t_max: f64, hit: &mut Hit) -> bool {
        match self.intersect(ray, t_min, t_max) {
            Some(h) => {
                *hit = h;
                true
            }
            None => false,
        }
    }

    /// The shape's roots apart from its hits, when it has such a route
    /// ([`Roots`]): a pixel's many camera rays then meet it all at once.
    fn roots(&self) -> Option<&dyn Roots> {
        None
    }

    /// Whether the surface surely misses the convex hull of `points` (a
    /// shadow shaft, accel/shaft.rs): only unbounded shapes are asked, the
    /// others are culled by their boxes. `false` when unsure.
    fn misses_hull(&self, _points: &[DVec3]) -> bool {
        false
    }

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
            geo_normal: ray.dir * c.facing.signum(),
            point: ray.at(c.t),
            p_error: ray_point_error(ray, c.t),
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

    /// Whether no interior point of the solid lies inside the box `b`
    /// (touching its faces is allowed); false when unsure. A union whose
    /// children are pairwise clear of each other has no inner surfaces to
    /// remove (see [`super::csg`]). The default compares the bounds, which
    /// says nothing for an unbounded shape.
    fn clear_of(&self, b: &Aabb) -> bool {
        self.bounds().apart(b)
    }

    /// The texture coordinates of a hit this shape returned. The default is
    /// what the shape filled in as it went; shapes whose (u, v) need
    /// trigonometry compute them here instead, once per shaded hit.
    fn uv(&self, hit: &Hit) -> DVec2 {
        hit.uv
    }

    /// A normal (or a gradient) `v` given in the space of `hit.local`,
    /// mapped into the space of the hit as its own normal was: through the
    /// inverse transpose of every transform on the way out, not normalised.
    /// Normal patterns find their slope at `hit.local` and need it in the
    /// world. A shape that moves nothing returns `v` as it is.
    fn normal_to_world(&self, _hit: &Hit, v: DVec3) -> DVec3 {
        v
    }
}

/// A ray prepared for the watertight ray/triangle test of Woop, Benthin
/// and Wald ("Watertight Ray/Triangle Intersection", JCGT 2013): the
/// coordinates are permuted so that the ray's largest direction component
/// is z, then sheared so that the ray runs along +z from the origin. A
/// triangle's corners are moved the same way and the test is 2D: the
/// signs of three edge functions. An edge shared by two triangles gives
/// each exactly the negated value of the other's (the same products,
/// subtracted the other way round), so no ray slips between them, and a
/// ray through a vertex is caught by every triangle around it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShearedRay {
    origin: DVec3,
    /// Which of the six permutations (kx, ky, kz): kz the dominant axis,
    /// kx and ky in the order that keeps the winding.
    perm: u8,
    /// Shear d[kx]/d[kz], d[ky]/d[kz] and scale 1/d[kz].
    sx: f64,
    sy: f64,
    sz: f64,
}

/// The six permutations, indexed by `ShearedRay::perm`.
const PERMS: [[usize; 3]; 6] = [
    [1, 2, 0],
    [2, 1, 0],
    [2, 0, 1],
    [0, 2, 1],
    [0, 1, 2],
    [1, 0, 2],
];

impl ShearedRay {
    pub fn new(ray: &Ray) -> ShearedRay {
        let a = ray.dir.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        // Keep the winding: a mirrored permutation would flip every sign.
        let perm = 2 * kz + (ray.dir[kz] < 0.0) as usize;
        let [kx, ky, _] = PERMS[perm];
        let d = ray.dir;
        ShearedRay {
            origin: ray.origin,
            perm: perm as u8,
            sx: d[kx] / d[kz],
            sy: d[ky] / d[kz],
            sz: 1.0 / d[kz],
        }
    }

    /// The prepared ray's parts, for tests that must do this arithmetic
    /// several triangles at a time (the wide BVH's leaves): the origin,
    /// the permutation `[kx, ky, kz]` and the shear `sx`, `sy`, `sz`.
    pub fn parts(&self) -> (DVec3, [usize; 3], [f64; 3]) {
        (
            self.origin,
            PERMS[self.perm as usize],
            [self.sx, self.sy, self.sz],
        )
    }

    /// The line's crossing with triangle (v0, v1, v2), edges and corners
    /// included, at any t: `(t, [b0, b1, b2])` with the barycentric weights
    /// of the corners. `None` when the line misses, lies in the triangle's
    /// plane, or the triangle has no area.
    #[inline(always)]
    pub fn triangle(&self, v0: DVec3, v1: DVec3, v2: DVec3) -> Option<(f64, [f64; 3])> {
        // One branch per triangle, the same way for every triangle a ray
        // meets; each arm reads the coordinates at fixed places.
        match self.perm {
            0 => self.test::<1, 2, 0>(v0, v1, v2),
            1 => self.test::<2, 1, 0>(v0, v1, v2),
            2 => self.test::<2, 0, 1>(v0, v1, v2),
            3 => self.test::<0, 2, 1>(v0, v1, v2),
            4 => self.test::<0, 1, 2>(v0, v1, v2),
            _ => self.test::<1, 0, 2>(v0, v1, v2),
        }
    }

    #[inline(always)]
    fn test<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        v0: DVec3,
        v1: DVec3,
        v2: DVec3,
    ) -> Option<(f64, [f64; 3])> {
        let (a, b, c) = (v0 - self.origin, v1 - self.origin, v2 - self.origin);
        let (ax, ay) = (a[KX] - self.sx * a[KZ], a[KY] - self.sy * a[KZ]);
        let (bx, by) = (b[KX] - self.sx * b[KZ], b[KY] - self.sy * b[KZ]);
        let (cx, cy) = (c[KX] - self.sx * c[KZ], c[KY] - self.sy * c[KZ]);
        // Edge functions: u the weight of v0 (edge v1-v2), v of v1, w of v2.
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let t_scaled = u * (self.sz * a[KZ]) + v * (self.sz * b[KZ]) + w * (self.sz * c[KZ]);
        let inv = 1.0 / det;
        let t = t_scaled * inv;
        t.is_finite().then_some((t, [u * inv, v * inv, w * inv]))
    }
}

/// The point b0·v0 + b1·v1 + b2·v2 of a triangle, with the bound on its
/// error (pbrt-v4: γ₇ of the sum of the terms' magnitudes). It lies on the
/// triangle's plane up to that bound, whatever the error of the ray's t.
pub(crate) fn barycentric_point(v: [DVec3; 3], b: [f64; 3]) -> (DVec3, DVec3) {
    let terms = [v[0] * b[0], v[1] * b[1], v[2] * b[2]];
    let p = terms[0] + terms[1] + terms[2];
    let mag = terms[0].abs() + terms[1].abs() + terms[2].abs();
    (p, crate::geometry::rounding::gamma(7) * mag)
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

    /// A box's six faces as corner indices, wound outwards, corner `i`
    /// having bit 0, 1, 2 of `i` for its high x, y, z.
    pub const BOX_FACES: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];

    /// A shape that gives only what every shape must (`intersect`,
    /// `crossings`, `bounds`, `is_solid`), passed on to the shape `S`
    /// points to (borrowed or boxed): the trait's defaults answer the
    /// rest, and a borrowed shape can be placed under several transforms
    /// without being rebuilt.
    #[derive(Debug)]
    pub struct Bare<S>(pub S);

    impl<S> Shape for Bare<S>
    where
        S: std::ops::Deref + Send + Sync + std::fmt::Debug,
        S::Target: Shape,
    {
        fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
            self.0.intersect(ray, t_min, t_max)
        }
        fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
            self.0.crossings(ray, out)
        }
        fn bounds(&self) -> Aabb {
            self.0.bounds()
        }
        fn is_solid(&self) -> bool {
            self.0.is_solid()
        }
    }

    /// Numbers in [−1, 1), the same every run (a 64-bit LCG's top bits).
    pub fn numbers(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
        }
    }

    /// Rays from random points on a big sphere around `target`, aimed near it.
    pub fn rays_towards(target: DVec3, spread: f64, n: usize, seed: u64) -> Vec<Ray> {
        let mut rnd = numbers(seed);
        (0..n)
            .map(|_| {
                let o = target + DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X) * 10.0;
                let aim = target + DVec3::new(rnd(), rnd(), rnd()) * spread;
                Ray::new(o, (aim - o).normalize())
            })
            .collect()
    }

    /// A shape's [`Roots`] give what its `intersect_into` gives ray by ray,
    /// to the bit: the same roots kept against the same limits, and the
    /// same hit at each. Each ray is asked in a run of 4 and of 8 (the
    /// four-lane route), in each of the four lanes, and at the end of
    /// runs of 1, 5 and 7 (the scalar tail), with limits that are
    /// infinite, shrunk below some roots, or NaN, and from `t_min` 0 and
    /// below. Returns how many (ray, run) pairs were kept.
    pub fn check_roots_agree(shape: &dyn Shape, rays: &[Ray]) -> usize {
        let roots = shape.roots().expect("a shape with roots");
        let mut kept = 0;
        let mut rnd = numbers(0x7007);
        let runs = [1, 4, 5, 7, 8]
            .into_iter()
            .flat_map(|len| (0..rays.len()).map(move |start| (start, len)));
        for (start, len) in runs {
            let run = &rays[start..(start + len).min(rays.len())];
            for t_min in [0.0, -3.0] {
                let limits: Vec<f64> = run
                    .iter()
                    .map(|_| match (rnd() * 4.0) as i32 {
                        0 => f64::NAN,
                        1 => 1.0 + 20.0 * rnd().abs(),
                        _ => f64::INFINITY,
                    })
                    .collect();
                let mut best = limits.clone();
                // Some rays won already (by an earlier shape): they stay won.
                let won_before: Vec<bool> = (0..run.len()).map(|i| (start + i) % 3 == 0).collect();
                let mut won = won_before.clone();
                roots.nearest_roots(run, t_min, &mut best, &mut won);
                for (i, ray) in run.iter().enumerate() {
                    let mut want = Hit::default();
                    let hit = shape.intersect_into(ray, t_min, limits[i], &mut want);
                    assert_eq!(
                        won[i],
                        hit || won_before[i],
                        "ray {ray:?} from {t_min} below {}",
                        limits[i]
                    );
                    // One ray alone, as the world asks an unbounded shape.
                    let alone = roots.root_within(ray, t_min, limits[i]);
                    assert_eq!(alone.map(f64::to_bits), hit.then(|| want.t.to_bits()));
                    if hit {
                        assert_eq!(best[i].to_bits(), want.t.to_bits());
                        let mut got = Hit::default();
                        roots.hit_at_root(ray, best[i], &mut got);
                        assert_eq!(format!("{got:?}"), format!("{want:?}"));
                        kept += 1;
                    } else {
                        assert_eq!(best[i].to_bits(), limits[i].to_bits());
                    }
                }
            }
        }
        kept
    }

    /// Rays that test the edges of a root finder: from inside and on the
    /// surface of the unit sphere about `c`, through its centre, grazing
    /// it, pointing nowhere (a zero direction), not unit, and with NaN or
    /// infinite coordinates.
    pub fn awkward_rays(c: DVec3) -> Vec<Ray> {
        let mut rays = vec![
            Ray::new(c, DVec3::X),
            Ray::new(c + DVec3::Y, DVec3::Y),
            Ray::new(c + DVec3::Y, -DVec3::Y),
            Ray::new(c + DVec3::new(-5.0, 1.0, 0.0), DVec3::X),
            Ray::new(c + DVec3::new(-5.0, 0.0, 0.0), DVec3::ZERO),
            Ray::new(c + DVec3::new(-5.0, 0.0, 0.0), DVec3::new(3.0, 0.0, 0.0)),
            Ray::new(c + DVec3::new(0.0, 5.0, 0.0), DVec3::new(0.0, -1e-300, 0.0)),
            Ray::new(
                c + DVec3::new(-5.0, 0.0, 0.0),
                DVec3::new(f64::NAN, 0.0, 0.0),
            ),
            Ray::new(DVec3::new(f64::INFINITY, 0.0, 0.0), -DVec3::X),
            Ray::new(
                c + DVec3::new(0.0, 0.0, 2.0),
                DVec3::new(0.0, 0.0, f64::INFINITY),
            ),
            Ray::new(c - DVec3::Z * 3.0, DVec3::new(0.0, -0.0, 1.0)),
        ];
        rays.extend(rays_towards(c, 1.5, 400, 0x5eed));
        rays
    }

    /// Every nearest hit lies in the shape's box; returns how many rays hit.
    pub fn check_bounds_hold_hits(shape: &dyn Shape, rays: &[Ray]) -> usize {
        let b = shape.bounds();
        let mut hits = 0;
        for r in rays {
            if let Some(h) = shape.intersect(r, 0.0, f64::INFINITY) {
                assert!(b.contains(h.point), "{:?} outside {b:?}", h.point);
                hits += 1;
            }
        }
        hits
    }

    /// The nearest hit must be the first of the crossings in range, and a ray
    /// leaving the surface from the hit must not hit it again at once.
    pub fn check_consistency(shape: &dyn Shape, rays: &[Ray]) {
        for r in rays {
            let hit = shape.intersect(r, 1e-9, f64::INFINITY);
            // The in-place route gives the same hit, and leaves a miss's
            // hit alone.
            let mut into = Hit {
                t: -7.0,
                ..Hit::default()
            };
            let found = shape.intersect_into(r, 1e-9, f64::INFINITY, &mut into);
            match hit {
                Some(h) => assert!(found && into == h, "{into:?} vs {h:?} for {r:?}"),
                None => assert!(!found && into.t == -7.0, "{into:?} for {r:?}"),
            }
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

    /// The shadow-ray test and the nearest hit agree with the crossings
    /// (a separate route, through full hits) in every window: the whole
    /// ray, windows ending just before and just after the first hit, one
    /// starting past it, and ones starting behind the origin (CSG asks
    /// those). Shapes answer `occludes` without building a hit; this keeps
    /// the routes one test. Returns how many rays hit.
    pub fn check_occludes_agrees(shape: &dyn Shape, rays: &[Ray]) -> usize {
        let mut hits = 0;
        for r in rays {
            let mut xs = Vec::new();
            shape.crossings(r, &mut xs);
            let first = xs.iter().map(|h| h.t).find(|&t| t > 0.0);
            hits += first.is_some() as usize;
            let t = first.unwrap_or(1.0);
            for (lo, hi) in [
                (0.0, f64::INFINITY),
                (0.0, t * 0.999),
                (0.0, t * 1.001),
                (t * 1.001, f64::INFINITY),
                (-1e3, f64::INFINITY),
                (-1e3, t * 0.999),
            ] {
                let want = xs.iter().any(|h| h.t > lo && h.t < hi);
                assert_eq!(shape.occludes(r, lo, hi), want, "({lo}, {hi}) {r:?}");
                assert_eq!(
                    shape.intersect(r, lo, hi).is_some(),
                    want,
                    "({lo}, {hi}) {r:?}"
                );
            }
        }
        hits
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

    /// The fraction of an n×n grid of rays from `eye` (far away on +z),
    /// aimed at the points of the square [−half, half]² in the plane z = 0,
    /// that hit `shape`, times the square's area: the shape's silhouette
    /// area as seen from `eye` (nearly a parallel projection when far).
    pub fn silhouette_area(shape: &dyn Shape, eye: DVec3, half: f64, n: usize) -> f64 {
        let mut hits = 0;
        for j in 0..n {
            for i in 0..n {
                let x = -half + (i as f64 + 0.5) * 2.0 * half / n as f64;
                let y = -half + (j as f64 + 0.5) * 2.0 * half / n as f64;
                let ray = Ray::new(eye, (DVec3::new(x, y, 0.0) - eye).normalize());
                hits += shape.intersect(&ray, 0.0, f64::INFINITY).is_some() as usize;
            }
        }
        hits as f64 / (n * n) as f64 * (2.0 * half).powi(2)
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
mod tests;
