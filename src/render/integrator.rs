//! The Whitted recursion of the course's 2017 and 2018 models: at each hit
//! it asks the material's parts (render/material/) what they reflect,
//! transmit and emit, asks the lights (render/light/) what arrives, and
//! casts the shadow, mirror, glossy and refracted rays.
//!
//! ```text
//! pixel = emitted
//!       + c ⊙ (k_a L_ambient·occlusion + Σ lights k_d E T (n·l)⁺ + k_d L_env·escaping)
//!       + Σ lights k_s c_s (r·v)⁺^e E T (n·l)⁺                        (Phong)
//!       + k_r c_r ⊙ L(mirror or glossy direction)
//!       + k_r f_out^s_r ⊙ L(reflected) + (k_t/η²) f_in^s_t ⊙ L(refracted)   (dielectric)
//! then, with the 2017 `reflect R`: (1 − R)·pixel + R·L(mirror direction)
//! ```
//! T is the shadow ray's transmittance: 1 or 0, or through glass the
//! filters^chord (no bending, no Fresnel loss: tinted shadows without
//! caustics, as POV-Ray does). Surfaces are two-sided: n is turned to face
//! the ray. Every secondary ray starts through [`Integrator::spawn`].

use super::light::{self, LightSample, area, environment};
use super::material::{dielectric, emissive, glossy, matte, mirror, phong};
use super::sampler::SampleStream;
use super::stats::RayCounts;
use crate::accel::{Blockers, Shaft, World};
use crate::geometry::Aabb;
use crate::geometry::rounding::SHADOW_EPSILON;
use crate::geometry::{
    DVec3, Ray, normalize_near_unit, offset_along_unit, offset_ray_origin, offset_towards,
    valid_reflection_normal,
};
use crate::scene::{AreaLight, Colour, LightKind, LightSurface, Material, Scene, pattern};
use crate::shapes::{Hit, Shape};

/// A shadow ray through glass stops being followed after this many
/// surfaces (it is then taken as blocked): bounded time for any scene.
const MAX_SHADOW_SURFACES: u32 = 32;

pub struct Integrator<'a> {
    scene: &'a Scene,
    world: &'a World,
    /// Whether any material is a dielectric (shadow rays then look for glass).
    has_glass: bool,
    /// The camera's view of the sky when nothing is hit.
    background: Colour,
    /// `render { bailout }`: rays whose weight falls below it are not cast.
    bailout: f64,
    /// Per area light, its own grid of points when it has one.
    grids: Vec<Option<area::Grid>>,
}

/// What one path carries: its random numbers, its ray counts, and its
/// weight: the share of the pixel its current ray carries (1 for a camera
/// ray; times the reflectivity or transmission at each bounce).
pub struct Path<'s> {
    pub stream: SampleStream,
    pub counts: &'s mut RayCounts,
    pub weight: f64,
}

impl<'a> Integrator<'a> {
    pub fn new(scene: &'a Scene, world: &'a World) -> Self {
        Integrator {
            scene,
            world,
            has_glass: scene.materials.iter().any(|m| m.refract.is_some()),
            background: scene.settings.background,
            bailout: scene.settings.bailout,
            grids: scene.area_lights.iter().map(area::Grid::new).collect(),
        }
    }

    /// Runs `cast` (which casts one secondary ray) with the path's weight
    /// multiplied by `share`, the part of this point's colour that ray
    /// brings; `None`, casting nothing, when that weight is below the
    /// bailout. POV-Ray's `adc_bailout`: a ray too faint to change the
    /// pixel much contributes black. The weight is a number, the largest
    /// channel's share, so a ray is kept while any channel still counts.
    /// With bailout 0 every ray is cast (a weight is never negative).
    fn weighted<T>(
        &self,
        path: &mut Path,
        share: f64,
        cast: impl FnOnce(&mut Path) -> T,
    ) -> Option<T> {
        let before = path.weight;
        let weight = before * share;
        if weight < self.bailout {
            path.counts.bailed += 1;
            return None;
        }
        path.weight = weight;
        let out = cast(path);
        path.weight = before;
        Some(out)
    }

    /// THE place a secondary ray leaves a surface: the hit point moved off
    /// the surface by its error bound, to the side of the geometric surface
    /// that `dir` goes to (`offset_ray_origin`, docs/architecture.md,
    /// "Rounding error and ray offsets"); refracted rays so start on the far side.
    #[inline(always)]
    fn spawn_origin(at: &Shading, dir: DVec3) -> DVec3 {
        offset_along_unit(at.p, at.p_err, at.ng_offset, dir)
    }

    /// A secondary ray from the shading point along unit `dir`. Inlined:
    /// `dir`, handed over in memory just after it was worked out, was read
    /// back before its stores had landed (a stalled forward on Intel).
    #[inline(always)]
    fn spawn(at: &Shading, dir: DVec3) -> Ray {
        Ray::new(Self::spawn_origin(at, dir), dir)
    }

    /// The objects traced against: the pixel renderer asks it for the
    /// few a pixel's beam meets.
    pub fn world(&self) -> &'a World {
        self.world
    }

    /// Colour seen along `ray` (unit direction), after `depth` bounces.
    pub fn trace(&self, ray: &Ray, depth: u32, path: &mut Path) -> Colour {
        if depth == 0 {
            path.counts.primary += 1;
        } else {
            path.counts.reflected += 1;
        }
        self.trace_far(ray, depth, path).0
    }

    /// A camera ray's first hit, written into `hit`: among the objects of
    /// its pixel's beam when `among` lists them
    /// ([`World::beam_candidates`]), else through the tree.
    pub fn first_hit(
        &self,
        ray: &Ray,
        among: Option<&Blockers>,
        hit: &mut Hit,
    ) -> Option<&'a dyn Shape> {
        match among {
            Some(c) => self.world.nearest_among(c, ray, 0.0, f64::INFINITY, hit),
            None => self.world.nearest_into(ray, 0.0, f64::INFINITY, hit),
        }
    }

    /// The colour a camera ray brings from the first hit
    /// [`Integrator::first_hit`] found (`None`: it met nothing), as
    /// [`Integrator::trace`] would give it. `lights` may hold, per light
    /// of the scene, the objects that may block a shadow ray from any of
    /// the pixel's first hits to it ([`Integrator::light_blockers`]).
    ///
    /// The colour goes to `take` from each arm: merged into one value
    /// first, it was copied 16 bytes at a time just after `shade_hit` had
    /// stored it 8 at a time (a stalled store-to-load forward a sample).
    #[inline(always)]
    pub fn shade_first(
        &self,
        ray: &Ray,
        found: Option<(&mut Hit, &dyn Shape)>,
        beamed: bool,
        lights: &[Option<Blockers>],
        path: &mut Path,
        take: impl FnOnce(Colour),
    ) {
        path.counts.primary += 1;
        path.counts.beamed += beamed as u64;
        match found {
            Some((hit, object)) => take(self.shade_hit(ray, hit, object, 0, path, lights).0),
            None => take(self.miss(ray.dir)),
        }
    }

    /// Per light of the scene, the objects that may block a shadow ray
    /// from a point of `points` to it (a pyramid from the light over the
    /// box, accel/shaft.rs), or `None` for that light's rays to go through
    /// the tree: a parallel light, a light inside or beside the box, or too
    /// many objects in the way.
    pub fn light_blockers(&self, points: &Aabb, out: &mut Vec<Option<Blockers>>) {
        out.clear();
        out.extend(self.scene.lights.iter().map(|l| {
            match l.kind {
                LightKind::Parallel { .. } => None,
                _ => self
                    .world
                    .blockers(&Shaft::towards_box(l.position, points)?),
            }
        }));
    }

    /// [`Integrator::trace`] and how far the ray went before its hit (∞ on
    /// a miss), for Beer absorption along it; the caller counts the ray.
    fn trace_far(&self, ray: &Ray, depth: u32, path: &mut Path) -> (Colour, f64) {
        let mut hit = Hit::default();
        let Some(object) = self.world.nearest_into(ray, 0.0, f64::INFINITY, &mut hit) else {
            return (self.miss(ray.dir), f64::INFINITY);
        };
        self.shade_hit(ray, &mut hit, object, depth, path, &[])
    }

    /// [`Integrator::trace_far`] from the hit on `object`; `lights` as in
    /// [`Integrator::shade_first`] (empty: every shadow ray through the
    /// tree).
    fn shade_hit(
        &self,
        ray: &Ray,
        hit: &mut Hit,
        object: &dyn Shape,
        depth: u32,
        path: &mut Path,
        lights: &[Option<Blockers>],
    ) -> (Colour, f64) {
        // Material patterns choose here; (u, v) is computed if read.
        let material = pattern::resolve(&self.scene.materials, hit, |h| object.uv(h));
        // The geometric normal decides the side; the shading normal is kept
        // in its hemisphere.
        let mut ng = normalize_near_unit(hit.geo_normal);
        let front = ng.dot(ray.dir) <= 0.0;
        if !front {
            ng = -ng;
        }
        // Most shapes have no shading normal of their own (the two normals
        // are one vector): then n is ng, as the general route would give.
        let mut n = if hit.normal == hit.geo_normal {
            ng
        } else {
            let n = hit.normal.normalize_or(ng);
            if n.dot(ng) < 0.0 { -n } else { n }
        };
        if let Some(bumps) = &material.normal {
            n = bumps.perturb_mapped(n, ng, hit.local, |g| object.normal_to_world(hit, g));
        }
        let (p, p_err) = (hit.point, hit.p_error);
        // What `offset_ray_origin` would make of ng, once for every ray
        // this point spawns.
        let ng_offset = normalize_near_unit(ng);
        let at = Shading {
            p,
            p_err,
            ng,
            ng_offset,
            n,
            d: ray.dir,
            // Along ng, which ng_offset (a positive multiple of it) faces.
            lifted: offset_towards(p, p_err, ng_offset),
            front,
        };
        let c = self.shade(material, hit, &at, depth, path, lights);
        (c, hit.t)
    }

    /// What a ray that hits nothing sees: the sky, or the background.
    fn miss(&self, dir: DVec3) -> Colour {
        match &self.scene.environment {
            Some(env) if env.visible && env.image.is_some() => env.radiance(dir),
            _ => self.background,
        }
    }

    /// Every part of `m` at one shading point.
    fn shade(
        &self,
        m: &Material,
        hit: &crate::shapes::Hit,
        at: &Shading,
        depth: u32,
        path: &mut Path,
        lights: &[Option<Blockers>],
    ) -> Colour {
        let deeper = depth < self.scene.settings.max_depth;
        let mut out = if matte::reflects(m) || m.phong.is_some() {
            self.local(m, hit, at, path, lights)
        } else {
            Colour::ZERO
        };
        if m.emits() {
            out += emissive::emitted(m, at.front);
        }
        if m.mirror != Colour::ZERO && deeper {
            let seen = self.weighted(path, m.mirror.max_element(), |path| {
                let dir = match m.glossy {
                    Some(e) => glossy::direction(at.d, at.n, e, path.stream.next2()),
                    None => at.mirror_dir(),
                };
                self.trace(&Self::spawn(at, dir), depth + 1, path)
            });
            out += m.mirror * seen.unwrap_or(Colour::ZERO);
        }
        if let Some(d) = &m.refract
            && deeper
        {
            out += self.dielectric(d, at, depth, path);
        }
        let r = m.reflect;
        if r <= 0.0 {
            return out;
        }
        let reflected = if deeper {
            self.weighted(path, r, |path| {
                self.trace(&Self::spawn(at, at.mirror_dir()), depth + 1, path)
            })
            .unwrap_or(Colour::ZERO)
        } else {
            Colour::ZERO
        };
        mirror::mix(out, reflected, r)
    }

    /// The matte and Phong parts: c ⊙ (light arriving) + highlights.
    fn local(
        &self,
        m: &Material,
        hit: &crate::shapes::Hit,
        at: &Shading,
        path: &mut Path,
        lights: &[Option<Blockers>],
    ) -> Colour {
        let mut ambient = self.scene.ambient;
        if let Some(o) = &self.scene.occlusion
            && ambient != Colour::ZERO
        {
            ambient *= environment::escaping(at.n, o.samples, &mut path.stream, o.min, |dir| {
                path.counts.shadow += 1;
                self.world
                    .occludes(&Ray::new(at.lifted, dir), 0.0, o.distance)
            });
        }
        let mut lit = Lit {
            light: matte::ambient(m, ambient),
            highlight: Colour::ZERO,
        };
        for (i, l) in self.scene.lights.iter().enumerate() {
            if let Some(s) = light::sample(l, at.lifted) {
                let mut blockers = lights.get(i).copied().flatten();
                self.add_light(m, at, s, path, blockers.as_mut(), &mut lit);
            }
        }
        for (l, grid) in self.scene.area_lights.iter().zip(&self.grids) {
            match (l.samples, grid) {
                (None, _) => {
                    let u = path.stream.next2();
                    let l = area::Prepared::new(l);
                    if let Some(s) = self.area_sample(&l, at.lifted, u, path.counts) {
                        self.add_light(m, at, s, path, None, &mut lit);
                    }
                }
                // Its own k × k grid of cell centres, averaged; the rays
                // are tested only against what may block them.
                (Some(_), Some(grid)) => {
                    let mut blockers = self.grid_blockers(l, at.lifted);
                    grid.each(l, at.lifted, |s| {
                        self.add_light(m, at, s, path, blockers.as_mut(), &mut lit)
                    });
                }
                // The same for a sphere light, whose points depend on
                // where it is seen from, and a light whose samples each
                // look for its surface first (`area_sample`).
                (Some(k), None) => {
                    let w = 1.0 / (k * k) as f64;
                    let mut blockers = self.grid_blockers(l, at.lifted);
                    let l = area::Prepared::new(l);
                    for j in 0..k {
                        for i in 0..k {
                            let u = area::cell_centre(i, j, k);
                            if let Some(mut s) = self.area_sample(&l, at.lifted, u, path.counts) {
                                s.radiance *= w;
                                self.add_light(m, at, s, path, blockers.as_mut(), &mut lit);
                            }
                        }
                    }
                }
            }
        }
        if let Some(env) = &self.scene.environment
            && m.diffuse > 0.0
        {
            let sky = environment::gather(env, at.n, &mut path.stream, |dir| {
                path.counts.shadow += 1;
                self.world
                    .occludes(&Ray::new(at.lifted, dir), 0.0, f64::INFINITY)
            });
            lit.light += sky * m.diffuse;
        }
        let local = m.texture.colour_at(hit) * lit.light;
        if m.phong.is_some() {
            local + lit.highlight
        } else {
            local
        }
    }

    /// One light sample's share at a shading point, if its shadow ray
    /// gets through. Always inlined: a sample handed over in memory was
    /// read back before its stores had landed (a stalled store-to-load
    /// forward on Intel cores, 8% of the `soft` benchmark's time).
    #[inline(always)]
    fn add_light(
        &self,
        m: &Material,
        at: &Shading,
        s: LightSample,
        path: &mut Path,
        blockers: Option<&mut Blockers>,
        lit: &mut Lit,
    ) {
        let cos = at.n.dot(s.dir);
        if cos <= 0.0 {
            return;
        }
        // An occluder counts up to the light less a sliver of the way
        // (the light may lie on a surface: an area light's sample).
        let reach = s.dist * (1.0 - SHADOW_EPSILON);
        let ray = Ray::new(at.lifted, s.dir);
        // Without glass a shadow ray is clear or not: a bool, not a
        // colour handed back through memory (read back too soon, it stalled
        // as the sample did).
        let e = if self.has_glass {
            let t = match blockers {
                Some(b) => self.transmittance_among(b, &ray, reach, path.counts),
                None => self.transmittance(&ray, reach, path.counts),
            };
            if t == Colour::ZERO {
                return;
            }
            s.radiance * t
        } else {
            let blocked = match blockers {
                Some(b) => self.blocked_among(b, &ray, reach, path.counts),
                None => self.blocked(&ray, reach, path.counts),
            };
            if blocked {
                return;
            }
            s.radiance
        };
        lit.light += matte::diffuse(m, e, cos);
        if let Some(ph) = &m.phong {
            lit.highlight += phong::highlight(ph, at.n, -at.d, s.dir, e);
        }
    }

    /// An area light's sample seen from `from`. A clipped light (inside
    /// CSG) keeps it only where a ray to the point meets an emitting
    /// surface there from its front: the solid may have cut that part of
    /// the surface away, or turned it to face inward. A light whose
    /// material pattern chooses its emission takes it from the material
    /// chosen where that ray meets the surface.
    #[inline(always)]
    fn area_sample(
        &self,
        l: &area::Prepared,
        from: DVec3,
        u: (f64, f64),
        counts: &mut RayCounts,
    ) -> Option<LightSample> {
        let mut s = l.sample(from, u)?;
        let l = l.light();
        if !l.clipped && !l.chosen {
            return Some(s);
        }
        counts.shadow += 1;
        let at = s.dist / area::SHORT_OF_SURFACE;
        let ray = Ray::new(from, s.dir);
        let (mut hit, object) = self
            .world
            .nearest(&ray, at * (1.0 - 1e-6), at * (1.0 + 1e-6))?;
        let m = pattern::resolve(&self.scene.materials, &mut hit, |h| object.uv(h));
        if !m.emits() || hit.geo_normal.dot(s.dir) >= 0.0 {
            return None;
        }
        if l.chosen {
            s.radiance *= m.emit;
        }
        Some(s)
    }

    /// Fresnel reflection plus refraction, with Beer absorption.
    fn dielectric(
        &self,
        d: &crate::scene::Dielectric,
        at: &Shading,
        depth: u32,
        path: &mut Path,
    ) -> Colour {
        let side = dielectric::Interface::new(d, at.front);
        let split = dielectric::split(at.d, at.n, side.eta);
        let reflect_dir = mirror::reflect(at.d, at.n);
        // The weights are POV-Ray's: F and 1 − F (absorption left out).
        let reflected = self.weighted(path, split.kr, |path| {
            path.counts.reflected += 1;
            self.trace_far(&Self::spawn(at, reflect_dir), depth + 1, path)
        });
        let mut out = match reflected {
            Some((lr, sr)) => split.kr * dielectric::absorb(&side.filter_here, sr) * lr,
            None => Colour::ZERO,
        };
        if let Some(t) = split.refracted
            && let Some((lt, st)) = self.weighted(path, 1.0 - split.kr, |path| {
                // The refracted ray leaves on the far side.
                path.counts.refracted += 1;
                self.trace_far(&Self::spawn(at, t), depth + 1, path)
            })
        {
            let kt = (1.0 - split.kr) / (side.eta * side.eta);
            out += kt * dielectric::absorb(&side.filter_there, st) * lt;
        }
        out
    }

    /// What of a light's colour gets through along `ray` up to `dist`:
    /// one for a clear path, zero when something opaque is in the way, and
    /// through glass each medium's filter to the length travelled in it.
    #[inline(always)]
    fn transmittance(&self, ray: &Ray, dist: f64, counts: &mut RayCounts) -> Colour {
        if !self.has_glass {
            return if self.blocked(ray, dist, counts) {
                Colour::ZERO
            } else {
                Colour::ONE
            };
        }
        counts.shadow += 1;
        let mut t = Colour::ONE;
        // The first stretch is `ray` itself, not a copy: it was stored a
        // coordinate at a time just before, and a copy read it back 16
        // bytes at a time (a stalled store-to-load forward at every shadow
        // ray of a scene with glass).
        let mut moved: Option<Ray> = None;
        let mut left = dist;
        let mut hit = crate::shapes::Hit::default();
        for _ in 0..MAX_SHADOW_SURFACES {
            let ray = moved.as_ref().unwrap_or(ray);
            if self.world.nearest_into(ray, 0.0, left, &mut hit).is_none() {
                return t;
            }
            // (u, v) as the shape gave it: shadow rays do not ask for more.
            let m = pattern::resolve(&self.scene.materials, &mut hit, |h| h.uv);
            let Some(glass) = &m.refract else {
                return Colour::ZERO;
            };
            // Leaving: the stretch before was inside; entering: outside.
            let leaving = hit.geo_normal.dot(ray.dir) > 0.0;
            let filter = if leaving {
                glass.filter
            } else {
                glass.outside_filter
            };
            t *= dielectric::absorb(&filter, hit.t);
            if t == Colour::ZERO {
                return t;
            }
            let (next, l) = Self::through(ray, &hit, left);
            (moved, left) = (Some(next), l);
        }
        Colour::ZERO
    }

    /// The objects that may block a ray from `from` to any point of the
    /// flat light `l` (accel/shaft.rs), or `None` when the rays should go
    /// through the tree: a sphere light, a light inside CSG (its samples
    /// cast rays of their own), a point in the light's plane, or too many
    /// objects in the way.
    fn grid_blockers(&self, l: &AreaLight, from: DVec3) -> Option<Blockers> {
        if l.clipped {
            return None;
        }
        let corners = match l.surface {
            LightSurface::Rectangle {
                corner,
                edge_u,
                edge_v,
            } => [
                corner,
                corner + edge_u,
                corner + edge_u + edge_v,
                corner + edge_v,
            ],
            // The parallelogram around the (possibly sheared) disc.
            LightSurface::Disc { centre, u, v, .. } => [
                centre - u - v,
                centre + u - v,
                centre + u + v,
                centre - u + v,
            ],
            LightSurface::Sphere { .. } => return None,
        };
        self.world.blockers(&Shaft::new(from, corners)?)
    }

    /// [`Integrator::transmittance`] for a ray inside the shaft `blockers`
    /// were found for: clear at once when nothing may block it.
    fn transmittance_among(
        &self,
        blockers: &mut Blockers,
        ray: &Ray,
        dist: f64,
        counts: &mut RayCounts,
    ) -> Colour {
        if blockers.is_empty() {
            counts.shadow += 1;
            counts.settled += 1;
            return Colour::ONE;
        }
        // Through glass a shadow ray goes on past what it meets, which the
        // shaft's list does not follow: the tree does.
        self.transmittance(ray, dist, counts)
    }

    /// Whether something (all of it opaque: no glass in the scene) blocks
    /// `ray` short of `dist`.
    fn blocked(&self, ray: &Ray, dist: f64, counts: &mut RayCounts) -> bool {
        counts.shadow += 1;
        self.world.occludes(ray, 0.0, dist)
    }

    /// [`Integrator::blocked`] for a ray inside the shaft `blockers` were
    /// found for: clear at once when nothing may block it.
    fn blocked_among(
        &self,
        blockers: &mut Blockers,
        ray: &Ray,
        dist: f64,
        counts: &mut RayCounts,
    ) -> bool {
        counts.shadow += 1;
        if blockers.is_empty() {
            counts.settled += 1;
            return false;
        }
        self.world.occludes_among(blockers, ray, 0.0, dist)
    }

    /// A shadow ray continued past the surface it met at `hit`: restarted
    /// on the far side by the hit's own error bound, as every secondary
    /// ray is ([`offset_ray_origin`]), with `left`, the length still to go,
    /// shortened by how far the new origin lies along the ray.
    fn through(ray: &Ray, hit: &crate::shapes::Hit, left: f64) -> (Ray, f64) {
        let origin = offset_ray_origin(hit.point, hit.p_error, hit.geo_normal, ray.dir);
        let gone = (origin - ray.origin).dot(ray.dir);
        (Ray::new(origin, ray.dir), left - gone)
    }
}

/// What the lights reaching one shading point add up to.
struct Lit {
    /// Ambient plus diffuse light, to be multiplied by the surface colour.
    light: Colour,
    /// Phong highlights, added on top.
    highlight: Colour,
}

/// One shading point.
struct Shading {
    p: DVec3,
    /// The bound on `p`'s rounding error, per coordinate.
    p_err: DVec3,
    /// Unit geometric normal facing the ray.
    ng: DVec3,
    /// `ng.normalize_or_zero()`: the normal the ray offsets use (the
    /// same to the bit as `offset_ray_origin` normalising `ng` itself).
    ng_offset: DVec3,
    /// Unit normal facing the ray.
    n: DVec3,
    /// The incoming ray's unit direction.
    d: DVec3,
    /// p moved off the surface on the ray's side (where shadow rays start).
    lifted: DVec3,
    /// Whether the ray met the outward side.
    front: bool,
}

impl Shading {
    /// The mirror direction, by the shading normal tilted (Cycles' rule)
    /// so that it never goes below the geometric surface.
    fn mirror_dir(&self) -> DVec3 {
        mirror::reflect(self.d, valid_reflection_normal(self.ng, -self.d, self.n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Light;
    use crate::shapes::Sphere;

    #[test]
    fn a_pixels_lights_list_what_lies_between_each_and_its_hits() {
        let scene = Scene {
            lights: vec![
                Light::point(DVec3::new(0.0, 10.0, 0.0), Colour::ONE),
                // (Its position, unused, above the hits as the first's.)
                Light {
                    position: DVec3::new(0.0, 20.0, 0.0),
                    colour: Colour::ONE,
                    kind: LightKind::Parallel {
                        direction: DVec3::Y,
                    },
                },
                // Among the hits: no pyramid from it holds them.
                Light::point(DVec3::new(0.1, 0.0, 0.0), Colour::ONE),
            ],
            ..Scene::default()
        };
        let ball = |x: f64, z: f64| Box::new(Sphere::new(DVec3::new(x, 5.0, z), 0.5, 0)) as _;
        // One ball between the light and the hits, two beside the way.
        let world = World::build(vec![ball(0.0, 0.0), ball(4.0, 0.0), ball(0.0, 3.0)]);
        let integrator = Integrator::new(&scene, &world);
        let hits = Aabb::new(DVec3::new(-0.2, 0.0, -0.2), DVec3::new(0.2, 0.0, 0.2));
        // Left over from an earlier pixel: replaced, not added to.
        let mut lists = vec![None; 5];
        integrator.light_blockers(&hits, &mut lists);
        assert_eq!(lists.len(), 3);
        assert!(lists[1].is_none(), "a parallel light's rays have no end");
        assert!(lists[2].is_none(), "a light among the hits");
        let mut between = lists[0].expect("a point light over the hits");
        assert_eq!(between.len(), 1);
        let up = |x: f64| {
            let from = DVec3::new(x, 0.0, 0.0);
            let d = DVec3::new(0.0, 10.0, 0.0) - from;
            (
                Ray::new(from, d.normalize()),
                d.length() * (1.0 - SHADOW_EPSILON),
            )
        };
        let (ray, reach) = up(0.0);
        assert!(world.occludes_among(&mut between, &ray, 0.0, reach));
        let (ray, reach) = up(0.2);
        assert_eq!(
            world.occludes_among(&mut between, &ray, 0.0, reach),
            world.occludes(&ray, 0.0, reach)
        );
    }
}
