//! Constructive solid geometry: union, intersection and difference of solids.
//!
//! ```text
//! difference {
//!   intersection { box { min <-1,-1,-1> max <1,1,1> }  sphere { radius 1.4 } }
//!   cylinder { radius 0.5 height 3 }
//!   cylinder { radius 0.5 height 3  rotate x 90 }
//!   material brass
//! }
//! ```
//!
//! Everything goes through crossing lists. Each child reports every crossing
//! of its surface along the whole line; those become the child's
//! inside-intervals (as flips of an inside flag), the flips of all children
//! are swept in order of `t`, and wherever the combined inside-ness changes a
//! crossing of the result is reported. So a `Csg` is itself a solid with a
//! proper crossing list and nests to any depth.
//!
//! - `union` removes inner surfaces; `intersection` keeps what is inside
//!   every child; `difference` is the first child minus all the others.
//! - A surface cut by a later child of `difference` is that child's surface
//!   turned inside out: its normal is reversed and it keeps the cutter's
//!   material.
//! - A plane is a half-space (the solid side is behind its normal): it has
//!   one crossing, and the line starts inside when that crossing leaves.
//!
//! The sweep works on light crossings ([`Crossing`]: t, which way, and a
//! key), not full hits: the one hit a ray asks for is made at the end by
//! [`Shape::hit_of`], which follows the key down to the leaf. Each level
//! adds one mixed-radix digit (`key · n + child`) to the key, and the same
//! digit to [`Hit::path`], so that texture coordinates, computed only for
//! the hit that is shaded, are asked of the shape that made it.
//!
//! Shortcuts, each exact: a union's child whose reach along the ray (its
//! box, or an unbounded child's first to last crossing) overlaps no other
//! child's is asked for its nearest hit directly (the floor under a few
//! solids); an intersection (after any child) or a difference (after its
//! first child) stops as soon as what that child encloses misses the
//! window asked about, and narrows the window for the children after it.

use super::{Crossing, Hit, Shape};
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;
use std::cell::RefCell;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CsgOp {
    Union,
    Intersection,
    /// The first child minus all the others.
    Difference,
}

#[derive(Debug)]
pub struct Csg {
    op: CsgOp,
    children: Vec<Box<dyn Shape>>,
    /// Each child's bounds, to skip a child a line cannot touch.
    child_bounds: Vec<Aabb>,
    /// Per child, from its bounds: never hit, bounded (so every line starts
    /// outside it) or unbounded.
    reach: Vec<Reach>,
    bounds: Aabb,
    /// The same for the result's own bounds.
    extent: Reach,
    /// The material the block gives its children (its own or inherited):
    /// hits wearing it have their solid-texture point in this block's
    /// space, see [`Csg::texture_space`].
    texture_space: Option<MaterialId>,
}

/// One change of a child's inside flag along the line.
#[derive(Clone, Copy, Debug)]
struct Flip {
    t: f64,
    child: u32,
    inside: bool,
    /// Index of the child's crossing in [`Scratch::xs`]; a cutter's facing
    /// there is already reversed to face out of the result.
    at: u32,
}

/// Buffers reused between calls; a pool rather than one buffer because a
/// nested `Csg` needs its own while its parent's are in use.
#[derive(Default)]
struct Scratch {
    xs: Vec<Crossing>,
    flips: Vec<Flip>,
}

/// The indices of the set bits, lowest first.
fn bits(mut m: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (m != 0).then(|| {
            let i = m.trailing_zeros() as usize;
            m &= m - 1;
            i
        })
    })
}

thread_local! {
    static POOL: RefCell<Vec<Scratch>> = const { RefCell::new(Vec::new()) };
}

fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    let mut s = POOL.with(|p| p.borrow_mut().pop()).unwrap_or_default();
    let r = f(&mut s);
    POOL.with(|p| p.borrow_mut().push(s));
    r
}

/// The widest union whose children are checked pairwise for overlap.
const SPLIT_MAX: usize = 8;

/// The path of a hit nested deeper than [`Hit::path`] can record.
const LOST: u64 = u64::MAX;

/// |t|, but at least 1 (and 1 for a NaN): the scale of a relative
/// tolerance. `f64::max` says the same with more instructions (it takes
/// care over NaN and signed zeros), and this runs for every crossing.
#[inline(always)]
fn magnitude(t: f64) -> f64 {
    let m = t.abs();
    if m > 1.0 { m } else { 1.0 }
}

/// Crossings this close in `t` (relative) are one event: coincident faces
/// (A ∪ A, boxes sharing a face) must not open zero-width slivers.
fn same_t(a: f64, b: f64) -> bool {
    (b - a).abs() <= 1e-9 * magnitude(a)
}

/// [`Aabb::clip`] made of plain comparisons, which CSG runs several times
/// per ray. A NaN slab (a ray in the plane of a face) is ignored, so the
/// stretch can only come out wider, never lose a hit.
/// `inv` is `ray.dir.recip()`, worked out once for all the boxes.
fn clip(b: &Aabb, ray: &Ray, inv: DVec3, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
    let t0 = (b.min - ray.origin) * inv;
    let t1 = (b.max - ray.origin) * inv;
    let (mut lo, mut hi) = (t_min, t_max);
    slab(t0.x, t1.x, &mut lo, &mut hi);
    slab(t0.y, t1.y, &mut lo, &mut hi);
    slab(t0.z, t1.z, &mut lo, &mut hi);
    (lo <= hi).then_some((lo, hi))
}

/// Narrows (lo, hi) to one slab's stretch (a, c) in either order; a NaN
/// (0·∞: the ray runs in the plane of a face) leaves it as it is.
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

#[derive(Clone, Copy, Debug, PartialEq)]
enum Reach {
    Nowhere,
    Bounded,
    Unbounded,
}

/// How many children are inside, split as the operation needs.
#[derive(Clone, Copy, Default)]
struct Count {
    /// Children that add to the result (all but a difference's cutters).
    adding: usize,
    cutting: usize,
    first: bool,
}

impl Csg {
    /// Every child must be solid (`is_solid()`); the builder checks that.
    pub fn new(op: CsgOp, children: Vec<Box<dyn Shape>>) -> Self {
        let child_bounds: Vec<Aabb> = children.iter().map(|c| c.bounds()).collect();
        let mut it = child_bounds.iter();
        let bounds = match op {
            CsgOp::Union => child_bounds.iter().fold(Aabb::EMPTY, |a, b| a.union(b)),
            CsgOp::Intersection => it
                .next()
                .map(|first| it.fold(*first, |a, b| a.intersection(b)))
                .unwrap_or(Aabb::EMPTY),
            CsgOp::Difference => it.next().copied().unwrap_or(Aabb::EMPTY),
        };
        let bounds = if bounds.is_empty() {
            Aabb::EMPTY
        } else {
            bounds
        };
        let reach_of = |b: &Aabb| {
            if b.is_empty() {
                Reach::Nowhere
            } else if b.is_finite() {
                Reach::Bounded
            } else {
                Reach::Unbounded
            }
        };
        let reach = child_bounds.iter().map(reach_of).collect();
        let extent = reach_of(&bounds);
        Csg {
            op,
            children,
            child_bounds,
            reach,
            bounds,
            extent,
            texture_space: None,
        }
    }

    /// A texture given to a CSG block lives in the block's space (as in
    /// POV-Ray): a solid pattern runs on through the seams between
    /// children, whatever transforms place them. So every hit that wears
    /// `material` (the block's own or the one it passes on) gets
    /// [`Hit::local`] as the point in this block's space; a child that
    /// names another material keeps its own. The (u, v) of such a hit is
    /// worked out before its point moves (the child's shape reads its own
    /// point for it). Nested blocks that pass the same material on end up
    /// in the outermost one's space, as each level moves the point again.
    pub fn texture_space(mut self, material: MaterialId) -> Self {
        self.texture_space = Some(material);
        self
    }

    /// Moves a hit of child `i` that wears the block's material into the
    /// block's texture space (see [`Csg::texture_space`]).
    fn in_texture_space(&self, ray: &Ray, h: &mut Hit, i: usize) {
        if self.texture_space == Some(h.material) {
            if h.path != LOST {
                h.uv = self.children[i].uv(h);
            }
            h.local = ray.at(h.t);
        }
    }

    /// Whether a child contributes its inside (false) or cuts it away.
    fn is_cutter(&self, i: usize) -> bool {
        self.op == CsgOp::Difference && i > 0
    }

    fn combine(&self, c: Count) -> bool {
        match self.op {
            CsgOp::Union => c.adding > 0,
            CsgOp::Intersection => !self.children.is_empty() && c.adding == self.children.len(),
            CsgOp::Difference => c.first && c.cutting == 0,
        }
    }

    fn count(&self, c: &mut Count, i: usize, inside: bool) {
        let n = if self.is_cutter(i) {
            &mut c.cutting
        } else {
            &mut c.adding
        };
        if inside {
            *n += 1;
        } else {
            *n -= 1;
        }
        if i == 0 {
            c.first = inside;
        }
    }

    /// Appends child `i`'s flips along the line to the scratch buffers and
    /// returns its inside flag at t = −∞. A bounded child whose box misses
    /// the part of the line in `span` is outside all along that part, so it
    /// is left out (that is what makes a ray starting beside a big union
    /// cheap).
    fn child_flips(
        &self,
        i: usize,
        ray: &Ray,
        inv: DVec3,
        span: (f64, f64),
        s: &mut Scratch,
    ) -> bool {
        let bounded = match self.reach[i] {
            Reach::Nowhere => return false,
            Reach::Bounded => true,
            Reach::Unbounded => false,
        };
        if bounded && clip(&self.child_bounds[i], ray, inv, span.0, span.1).is_none() {
            return false;
        }
        let first = s.xs.len();
        self.children[i].crossings_lite(ray, &mut s.xs);
        // A bounded solid cannot contain the far end of a line; an unbounded
        // one (a plane) starts inside when its first crossing leaves. A
        // grazing crossing (a tangent ray's double root) flips the inside
        // flag rather than setting it.
        let mut inside = if bounded {
            false
        } else {
            match s.xs.get(first) {
                Some(c) if !c.grazing => c.facing > 0.0,
                Some(_) => false,
                None => self.children[i].encloses(ray.origin),
            }
        };
        let start = inside;
        let cutter = self.is_cutter(i);
        for k in first..s.xs.len() {
            let c = &mut s.xs[k];
            let now = if c.grazing { !inside } else { c.facing < 0.0 };
            // A repeated crossing (a mesh edge reported twice) changes nothing.
            if now == inside {
                continue;
            }
            inside = now;
            if cutter {
                c.facing = -c.facing;
            }
            s.flips.push(Flip {
                t: c.t,
                child: i as u32,
                inside: now,
                at: k as u32,
            });
        }
        start
    }

    /// Walks the result's crossings in increasing t, handing each to `emit`
    /// until it returns true (found what it wanted). Only the crossings
    /// within `span` are sure to be complete and right. Children whose bit
    /// is set in `skip` are left out (a union's children that the caller
    /// has shown to be outside all along `span`, or dealt with apart).
    fn sweep(
        &self,
        ray: &Ray,
        span: (f64, f64),
        skip: u64,
        s: &mut Scratch,
        mut emit: impl FnMut(Crossing) -> bool,
    ) {
        s.xs.clear();
        s.flips.clear();
        let mut count = Count::default();
        let mut span = span;
        let inv = ray.dir.recip();
        for i in 0..self.children.len() {
            if i < 64 && skip & (1 << i) != 0 {
                continue;
            }
            let before = s.flips.len();
            let start = self.child_flips(i, ray, inv, span, s);
            if start {
                self.count(&mut count, i, true);
            }
            // The result lies inside every child of an intersection and
            // inside the first child of a difference: outside the stretch
            // from where such a child is first inside to where it is last,
            // there is nothing to find (and later children whose boxes miss
            // what is left are left out). A child that is never inside
            // empties the result.
            if self.op == CsgOp::Intersection || (self.op == CsgOp::Difference && i == 0) {
                let mine = &s.flips[before..];
                let lo = match mine.first() {
                    _ if start => f64::NEG_INFINITY,
                    Some(f) => f.t,
                    None => return,
                };
                let hi = match mine.last() {
                    Some(f) if !f.inside => f.t,
                    Some(_) => f64::INFINITY,
                    None => f64::INFINITY,
                };
                // Widened like `same_t`, to keep crossings at the very ends.
                let pad = |t: f64| 1e-9 * magnitude(t);
                span = (span.0.max(lo - pad(lo)), span.1.min(hi + pad(hi)));
                if span.0 > span.1 {
                    return;
                }
            }
        }
        s.flips.sort_unstable_by(|a, b| a.t.total_cmp(&b.t));
        let mut state = self.combine(count);
        let mut k = 0;
        while k < s.flips.len() {
            // Apply every flip at (nearly) the same t, then compare.
            let t0 = s.flips[k].t;
            let begin = k;
            while k < s.flips.len() && same_t(t0, s.flips[k].t) {
                let f = s.flips[k];
                self.count(&mut count, f.child as usize, f.inside);
                k += 1;
            }
            let now = self.combine(count);
            if now == state {
                continue;
            }
            state = now;
            // Report the crossing whose (possibly reversed) normal agrees
            // with the change: against the ray when entering.
            let batch = &s.flips[begin..k];
            let agrees = |f: &&Flip| (s.xs[f.at as usize].facing < 0.0) == now;
            let f = batch.iter().find(agrees).unwrap_or(&batch[0]);
            let c = s.xs[f.at as usize];
            let key = c
                .key
                .checked_mul(self.children.len() as u64)
                .and_then(|k| k.checked_add(f.child as u64))
                .unwrap_or(LOST);
            if emit(Crossing { key, ..c }) {
                return;
            }
        }
    }

    /// A crossing nested too deep for its key to fit 64 bits is found again
    /// by its t among the children's own crossings: the same arithmetic gave
    /// the same t. Only (u, v) stays lost (its path did not fit either).
    fn find_lost(&self, ray: &Ray, c: &Crossing) -> Hit {
        let mut list = Vec::new();
        for (i, child) in self.children.iter().enumerate() {
            list.clear();
            child.crossings_lite(ray, &mut list);
            if let Some(inner) = list.iter().find(|x| x.t == c.t) {
                let mut h = child.hit_of(ray, inner);
                if self.is_cutter(i) {
                    h.flip();
                }
                h.path = LOST;
                self.in_texture_space(ray, &mut h, i);
                return h;
            }
        }
        Hit {
            t: c.t,
            normal: ray.dir * c.facing.signum(),
            geo_normal: ray.dir * c.facing.signum(),
            local: ray.at(c.t),
            point: ray.at(c.t),
            p_error: super::ray_point_error(ray, c.t),
            path: LOST,
            ..Hit::default()
        }
    }

    /// The hit as the result reports it: `child`'s digit added to its path.
    /// A path too deep for 64 bits becomes `LOST` (its (u, v) read as zero).
    /// In place, as [`Csg::in_texture_space`]: a hit is 160 bytes, and
    /// every copy on the way out of a query is a `memcpy`.
    fn tag(&self, h: &mut Hit, child: u32) {
        h.path = h
            .path
            .checked_mul(self.children.len() as u64)
            .and_then(|p| p.checked_add(child as u64))
            .unwrap_or(LOST);
    }

    /// Splits the children that matter within (t_min, t_max) into two bit
    /// sets: those whose reach along the ray (their box, or for an unbounded
    /// child the span between its first and last crossing) overlaps no other
    /// child's, and the rest. Within a union, a lone child's surfaces are the
    /// result's as they stand (nothing else is inside there), so it can be
    /// asked for its nearest hit directly; only the rest need the sweep.
    /// Other operations, and unions wider than [`SPLIT_MAX`] (where the
    /// pairwise test would cost more than it saves), get every child as
    /// "rest", with nothing alone.
    fn union_split(&self, ray: &Ray, t_min: f64, t_max: f64, s: &mut Scratch) -> (u64, u64) {
        let n = self.children.len();
        if self.op != CsgOp::Union || n > SPLIT_MAX {
            return (0, if n >= 64 { u64::MAX } else { (1 << n) - 1 });
        }
        let inv = ray.dir.recip();
        let mut lo = [0.0; SPLIT_MAX];
        let mut hi = [0.0; SPLIT_MAX];
        let mut live = 0u64;
        let mut unbounded = 0u64;
        let mut reach = |i: usize, span: Option<(f64, f64)>, live: &mut u64| {
            if let Some((a, b)) = span {
                // Widened like `same_t`, so that reaches that only touch
                // (a solid standing on the floor) count as overlapping.
                lo[i] = a - 1e-9 * magnitude(a);
                hi[i] = b + 1e-9 * magnitude(b);
                *live |= 1 << i;
            }
        };
        for i in 0..n {
            match self.reach[i] {
                Reach::Nowhere => {}
                Reach::Bounded => reach(
                    i,
                    clip(&self.child_bounds[i], ray, inv, t_min, t_max),
                    &mut live,
                ),
                Reach::Unbounded => unbounded |= 1 << i,
            }
        }
        // An unbounded child's reach costs its crossings: not needed when
        // nothing else is near (the floor seen away from everything else).
        if live == 0 && unbounded.count_ones() <= 1 {
            return (unbounded, 0);
        }
        for i in bits(unbounded) {
            reach(i, self.unbounded_reach(i, ray, t_min, t_max, s), &mut live);
        }
        if live.count_ones() <= 1 {
            return (live, 0);
        }
        let (mut alone, mut rest) = (0u64, 0u64);
        for i in bits(live) {
            if bits(live).all(|j| j == i || hi[j] < lo[i] || hi[i] < lo[j]) {
                alone |= 1 << i;
            } else {
                rest |= 1 << i;
            }
        }
        (alone, rest)
    }

    /// Where along (t_min, t_max) unbounded child `i` may be inside: from
    /// its first crossing, if that clearly enters, to its last, if that
    /// clearly leaves.
    fn unbounded_reach(
        &self,
        i: usize,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        s: &mut Scratch,
    ) -> Option<(f64, f64)> {
        s.xs.clear();
        self.children[i].crossings_lite(ray, &mut s.xs);
        let (a, b) = match (s.xs.first(), s.xs.last()) {
            (Some(first), Some(last)) => (
                if !first.grazing && first.facing < 0.0 {
                    first.t.max(t_min)
                } else {
                    t_min
                },
                if !last.grazing && last.facing > 0.0 {
                    last.t.min(t_max)
                } else {
                    t_max
                },
            ),
            _ if self.children[i].encloses(ray.origin) => (t_min, t_max),
            _ => return None,
        };
        (a <= b).then_some((a, b))
    }

    /// Whether the line can meet the result within (t_min, t_max) at all.
    fn may_hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        match self.extent {
            Reach::Nowhere => false,
            Reach::Unbounded => true,
            Reach::Bounded => clip(&self.bounds, ray, ray.dir.recip(), t_min, t_max).is_some(),
        }
    }
}

impl Csg {
    /// The result's first crossing within (t_min, t_max), as a full hit.
    fn nearest(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        // The lone children's nearest hit, as the child gave it: made the
        // result's (texture space, path) only if nothing swept is nearer.
        let mut found: Option<Hit> = None;
        let mut found_child = 0;
        let swept = with_scratch(|s| {
            let (alone, rest) = self.union_split(ray, t_min, t_max, s);
            let mut t_best = t_max;
            for i in bits(alone) {
                if let Some(h) = self.children[i].intersect(ray, t_min, t_best) {
                    t_best = h.t;
                    found = Some(h);
                    found_child = i;
                }
            }
            let mut swept = None;
            if rest != 0 {
                self.sweep(ray, (t_min, t_best), !rest, s, |c| {
                    if c.t >= t_best {
                        return true;
                    }
                    if c.t > t_min {
                        swept = Some(c);
                        return true;
                    }
                    false
                });
            }
            swept
        });
        // Anything the sweep found lies before t_best.
        if let Some(c) = swept {
            return Some(self.hit_of(ray, &c));
        }
        let mut h = found?;
        self.in_texture_space(ray, &mut h, found_child);
        self.tag(&mut h, found_child as u32);
        Some(h)
    }
}

impl Shape for Csg {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        if !self.may_hit(ray, t_min, t_max) {
            return None;
        }
        self.nearest(ray, t_min, t_max)
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        if !self.may_hit(ray, t_min, t_max) {
            return false;
        }
        with_scratch(|s| {
            let (alone, rest) = self.union_split(ray, t_min, t_max, s);
            if bits(alone).any(|i| self.children[i].occludes(ray, t_min, t_max)) {
                return true;
            }
            // Every surface of the result is some child's surface, so when no
            // child has a crossing in range (the common shadow ray), neither
            // does the result, and the sweep is not needed. (An intersection
            // or a difference narrows its sweep by its first child at once,
            // which does the same job.)
            let near = self.op != CsgOp::Union
                || bits(rest).any(|i| {
                    clip(&self.child_bounds[i], ray, ray.dir.recip(), t_min, t_max).is_some()
                        && self.children[i].occludes(ray, t_min, t_max)
                });
            let mut hit = false;
            if near {
                self.sweep(ray, (t_min, t_max), !rest, s, |c| {
                    hit = c.t > t_min && c.t < t_max;
                    hit || c.t >= t_max
                });
            }
            hit
        })
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        let mut lite = Vec::new();
        self.crossings_lite(ray, &mut lite);
        out.extend(lite.iter().map(|c| self.hit_of(ray, c)));
    }

    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        if !self.may_hit(ray, f64::NEG_INFINITY, f64::INFINITY) {
            return;
        }
        with_scratch(|s| {
            self.sweep(ray, (f64::NEG_INFINITY, f64::INFINITY), 0, s, |c| {
                out.push(c);
                false
            })
        });
    }

    /// The key is the child's key with the child's digit added (as in
    /// [`Hit::path`]); a cutter's surface comes back reversed.
    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        let n = self.children.len() as u64;
        if c.key == LOST || n == 0 {
            return self.find_lost(ray, c);
        }
        let i = (c.key % n) as usize;
        let inner = Crossing {
            key: c.key / n,
            ..*c
        };
        let mut h = self.children[i].hit_of(ray, &inner);
        if self.is_cutter(i) {
            h.flip();
        }
        self.in_texture_space(ray, &mut h, i);
        self.tag(&mut h, i as u32);
        h
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn is_solid(&self) -> bool {
        true
    }

    fn encloses(&self, p: DVec3) -> bool {
        let mut inside = self.children.iter().map(|c| c.encloses(p));
        match self.op {
            CsgOp::Union => inside.any(|x| x),
            CsgOp::Intersection => !self.children.is_empty() && inside.all(|x| x),
            CsgOp::Difference => inside.next() == Some(true) && !inside.any(|x| x),
        }
    }

    fn uv(&self, hit: &Hit) -> DVec2 {
        // Worked out already, before the point moved to this block's space.
        if self.texture_space == Some(hit.material) {
            return hit.uv;
        }
        let n = self.children.len() as u64;
        if hit.path == LOST || n == 0 {
            return DVec2::ZERO;
        }
        let inner = Hit {
            path: hit.path / n,
            ..*hit
        };
        self.children[(hit.path % n) as usize].uv(&inner)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Transform;
    use crate::shapes::{Cone, Cuboid, Plane, Sphere, Transformed, testing};

    fn sphere(c: DVec3, r: f64, m: u32) -> Box<dyn Shape> {
        Box::new(Sphere::new(c, r, m))
    }

    fn cube(lo: DVec3, hi: DVec3, m: u32) -> Box<dyn Shape> {
        Box::new(Cuboid::new(lo, hi, [m; 6]))
    }

    fn xs(s: &dyn Shape, r: &Ray) -> Vec<Hit> {
        let mut v = Vec::new();
        s.crossings(r, &mut v);
        v
    }

    /// Same crossings: same t and same outward normal direction.
    fn assert_same(a: &[Hit], b: &[Hit], r: &Ray) {
        assert_eq!(a.len(), b.len(), "{a:?}\nvs\n{b:?}\nfor {r:?}");
        for (x, y) in a.iter().zip(b) {
            assert!((x.t - y.t).abs() < 1e-9, "{x:?} vs {y:?}");
            assert!(x.normal.normalize().dot(y.normal.normalize()) > 1.0 - 1e-9);
        }
    }

    #[test]
    fn union_with_itself_is_itself() {
        let _watchdog = crate::watchdog::start();
        let a = || sphere(DVec3::new(0.2, 0.1, 0.0), 1.0, 1);
        let u = Csg::new(CsgOp::Union, vec![a(), a()]);
        let i = Csg::new(CsgOp::Intersection, vec![a(), a()]);
        for r in testing::rays_towards(DVec3::ZERO, 1.5, 300, 61) {
            let direct = xs(&*a(), &r);
            assert_same(&xs(&u, &r), &direct, &r);
            assert_same(&xs(&i, &r), &direct, &r);
        }
    }

    #[test]
    fn intersection_commutes() {
        let _watchdog = crate::watchdog::start();
        let ab = Csg::new(
            CsgOp::Intersection,
            vec![
                sphere(DVec3::ZERO, 1.2, 1),
                cube(-DVec3::ONE, DVec3::ONE, 2),
            ],
        );
        let ba = Csg::new(
            CsgOp::Intersection,
            vec![
                cube(-DVec3::ONE, DVec3::ONE, 2),
                sphere(DVec3::ZERO, 1.2, 1),
            ],
        );
        let mut seen = 0;
        for r in testing::rays_towards(DVec3::ZERO, 1.5, 500, 62) {
            let (x, y) = (xs(&ab, &r), xs(&ba, &r));
            assert_same(&x, &y, &r);
            for (h, k) in x.iter().zip(&y) {
                assert_eq!(h.material, k.material);
            }
            seen += x.len();
        }
        assert!(seen > 300);
    }

    #[test]
    fn sphere_minus_larger_concentric_sphere_is_empty() {
        let _watchdog = crate::watchdog::start();
        let d = Csg::new(
            CsgOp::Difference,
            vec![sphere(DVec3::ZERO, 1.0, 1), sphere(DVec3::ZERO, 1.5, 2)],
        );
        let mut rays = testing::rays_towards(DVec3::ZERO, 2.0, 300, 63);
        rays.push(Ray::new(DVec3::ZERO, DVec3::X));
        for r in rays {
            assert!(xs(&d, &r).is_empty());
            assert!(d.intersect(&r, 0.0, f64::INFINITY).is_none());
        }
    }

    #[test]
    fn difference_of_boxes_is_the_box_built_directly() {
        let _watchdog = crate::watchdog::start();
        let d = Csg::new(
            CsgOp::Difference,
            vec![
                cube(DVec3::ZERO, DVec3::splat(2.0), 1),
                cube(DVec3::new(1.0, -1.0, -1.0), DVec3::splat(3.0), 2),
            ],
        );
        let direct = Cuboid::new(DVec3::ZERO, DVec3::new(1.0, 2.0, 2.0), [1, 1, 1, 1, 1, 2]);
        assert_eq!(d.bounds(), Aabb::new(DVec3::ZERO, DVec3::splat(2.0)));
        let mut seen = 0;
        for r in testing::rays_towards(DVec3::new(0.5, 1.0, 1.0), 1.5, 500, 64) {
            let (x, y) = (xs(&d, &r), xs(&direct, &r));
            assert_same(&x, &y, &r);
            for (h, k) in x.iter().zip(&y) {
                // The cut face x = 1 shows the cutter's material.
                assert_eq!(h.material, k.material, "{h:?}");
            }
            let near = d.intersect(&r, 1e-9, f64::INFINITY);
            let want = direct.intersect(&r, 1e-9, f64::INFINITY);
            assert_eq!(near.map(|h| h.material), want.map(|h| h.material));
            seen += x.len();
        }
        assert!(seen > 300);
    }

    /// Inside-ness along a line from a crossing list, at parameter t.
    fn inside_by_crossings(list: &[Hit], r: &Ray, t: f64) -> bool {
        // The last crossing before t tells: entering means inside.
        list.iter()
            .rev()
            .find(|h| h.t < t)
            .is_some_and(|h| h.normal.dot(r.dir) < 0.0)
    }

    #[test]
    fn box_and_sphere_match_the_analytic_shape() {
        let _watchdog = crate::watchdog::start();
        let b = (DVec3::new(-1.0, -0.8, -1.0), DVec3::new(1.0, 0.8, 0.6));
        let (c, rad) = (DVec3::new(0.1, 0.0, 0.0), 1.2);
        let inside_box = |p: DVec3| p.cmpgt(b.0).all() && p.cmplt(b.1).all();
        let inside_ball = |p: DVec3| (p - c).length() < rad;
        let ops: [(CsgOp, &dyn Fn(DVec3) -> bool); 3] = [
            (CsgOp::Intersection, &|p| inside_box(p) && inside_ball(p)),
            (CsgOp::Union, &|p| inside_box(p) || inside_ball(p)),
            (CsgOp::Difference, &|p| inside_box(p) && !inside_ball(p)),
        ];
        for (op, inside) in ops {
            let s = Csg::new(op, vec![cube(b.0, b.1, 1), sphere(c, rad, 2)]);
            let rays = testing::rays_towards(DVec3::ZERO, 1.5, 300, 65);
            testing::check_consistency(&s, &rays);
            testing::check_alternation(&s, &rays);
            testing::check_no_rehit(&s, &rays);
            for r in &rays {
                let list = xs(&s, r);
                for k in 0..200 {
                    let t = 5.0 + (k as f64) * 0.05 + 0.0123;
                    let p = r.at(t);
                    // Skip samples within a hair of a surface.
                    if list.iter().any(|h| (h.t - t).abs() < 1e-6) {
                        continue;
                    }
                    assert_eq!(inside_by_crossings(&list, r, t), inside(p), "{op:?} {p:?}");
                }
            }
        }
    }

    #[test]
    fn nearest_hit_in_any_window_is_the_first_crossing_there() {
        let _watchdog = crate::watchdog::start();
        // intersect() leaves out children that miss its window; the answer
        // must still be the whole line's crossing list cut to the window.
        let shapes = [
            Csg::new(
                CsgOp::Union,
                vec![
                    sphere(DVec3::ZERO, 1.0, 1),
                    cube(DVec3::splat(0.5), DVec3::splat(2.0), 2),
                ],
            ),
            Csg::new(
                CsgOp::Difference,
                vec![
                    cube(-DVec3::ONE, DVec3::ONE, 1),
                    sphere(DVec3::splat(0.8), 0.9, 2),
                ],
            ),
            Csg::new(
                CsgOp::Intersection,
                vec![
                    sphere(DVec3::ZERO, 1.3, 1),
                    cube(-DVec3::ONE, DVec3::ONE, 2),
                ],
            ),
        ];
        for s in &shapes {
            for (k, r) in testing::rays_towards(DVec3::ZERO, 1.5, 300, 67)
                .iter()
                .enumerate()
            {
                let list = xs(s, r);
                let lo = 8.0 + (k % 7) as f64 * 0.4;
                let hi = lo + 0.3 + (k % 5) as f64 * 0.5;
                let want = list.iter().find(|h| h.t > lo && h.t < hi);
                let got = s.intersect(r, lo, hi);
                assert_eq!(got.map(|h| h.t), want.map(|h| h.t), "window {lo}..{hi}");
                assert_eq!(got.map(|h| h.material), want.map(|h| h.material));
                assert_eq!(s.occludes(r, lo, hi), want.is_some());
            }
        }
    }

    #[test]
    fn inside_a_union_only_the_outer_surface_shows() {
        let _watchdog = crate::watchdog::start();
        let u = Csg::new(
            CsgOp::Union,
            vec![
                sphere(DVec3::new(-0.5, 0.0, 0.0), 1.0, 1),
                sphere(DVec3::new(0.5, 0.0, 0.0), 1.0, 2),
            ],
        );
        let h = u
            .intersect(&Ray::new(DVec3::ZERO, DVec3::X), 1e-9, f64::INFINITY)
            .unwrap();
        assert!((h.t - 1.5).abs() < 1e-12 && h.material == 2 && h.normal.x > 0.0);
        let h = u
            .intersect(&Ray::new(DVec3::ZERO, -DVec3::X), 1e-9, f64::INFINITY)
            .unwrap();
        assert!((h.t - 1.5).abs() < 1e-12 && h.material == 1);
        // A shadow ray inside sees the same.
        assert!(!u.occludes(&Ray::new(DVec3::ZERO, DVec3::X), 1e-9, 1.4));
    }

    #[test]
    fn plane_is_a_half_space() {
        let _watchdog = crate::watchdog::start();
        let cut = || Box::new(Plane::new(DVec3::Y, 0.0, 3)) as Box<dyn Shape>;
        // Sphere minus everything below y = 0: the upper hemisphere.
        let top = Csg::new(CsgOp::Difference, vec![sphere(DVec3::ZERO, 1.0, 1), cut()]);
        let down = Ray::new(DVec3::new(0.3, 5.0, 0.0), -DVec3::Y);
        let h = top.intersect(&down, 0.0, f64::INFINITY).unwrap();
        assert!((h.t - (5.0 - 0.91f64.sqrt())).abs() < 1e-12 && h.material == 1);
        let up = Ray::new(DVec3::new(0.3, -5.0, 0.0), DVec3::Y);
        let h = top.intersect(&up, 0.0, f64::INFINITY).unwrap();
        // The cut face: the plane's material, its normal reversed (−y).
        assert!((h.t - 5.0).abs() < 1e-12 && h.material == 3 && h.normal.y < 0.0);
        assert_eq!(xs(&top, &up).len(), 2);
        // Sphere ∩ half-space: the lower hemisphere, and lines parallel to
        // the plane are inside or outside it as a whole.
        let low = Csg::new(
            CsgOp::Intersection,
            vec![cut(), sphere(DVec3::ZERO, 1.0, 1)],
        );
        let below = Ray::new(DVec3::new(-5.0, -0.5, 0.0), DVec3::X);
        let above = Ray::new(DVec3::new(-5.0, 0.5, 0.0), DVec3::X);
        assert!(
            (low.intersect(&below, 0.0, 99.0).unwrap().t - (5.0 - 0.75f64.sqrt())).abs() < 1e-12
        );
        assert!(low.intersect(&above, 0.0, 99.0).is_none());
        // A half-space minus a sphere is unbounded: a parallel line below
        // starts inside, leaves into the hole and comes back out of it.
        let holed = Csg::new(CsgOp::Difference, vec![cut(), sphere(DVec3::ZERO, 1.0, 1)]);
        assert!(!holed.bounds().is_finite());
        let list = xs(&holed, &below);
        assert_eq!(list.len(), 2, "{list:?}");
        assert!(list[0].normal.dot(below.dir) > 0.0 && list[1].normal.dot(below.dir) < 0.0);
        // Parallel lines that miss the hole are wholly inside or outside.
        assert!(xs(&holed, &Ray::new(DVec3::new(-5.0, -2.0, 0.0), DVec3::X)).is_empty());
        assert!(holed.encloses(DVec3::new(0.0, -2.0, 0.0)));
        assert!(!holed.encloses(DVec3::new(0.0, 2.0, 0.0)));
    }

    #[test]
    fn tangent_rays_do_not_fill_the_line() {
        let _watchdog = crate::watchdog::start();
        let u = Csg::new(
            CsgOp::Union,
            vec![
                sphere(DVec3::ZERO, 1.0, 1),
                sphere(DVec3::new(5.0, 1.0, 0.0), 0.5, 2),
            ],
        );
        // Grazes the first sphere at (0, 1, 0), then meets the second.
        let r = Ray::new(DVec3::new(-3.0, 1.0, 0.0), DVec3::X);
        let list = xs(&u, &r);
        assert!(list.len().is_multiple_of(2), "{list:?}");
        let h = u.intersect(&r, 3.5, f64::INFINITY).unwrap();
        assert!((h.t - 7.5).abs() < 1e-9 && h.material == 2);
        assert!(u.intersect(&r, 8.6, f64::INFINITY).is_none());
    }

    #[test]
    fn nested_and_transformed() {
        let _watchdog = crate::watchdog::start();
        // The lantern: (box ∩ sphere) minus three crossed cylinders, turned.
        let cyl = |t: Transform| -> Box<dyn Shape> {
            Box::new(Transformed::new(
                Box::new(Cone::cylinder(DVec3::ZERO, 0.5, 3.0, 2, Some([2, 2]))),
                t,
            ))
        };
        let body = Csg::new(
            CsgOp::Intersection,
            vec![
                cube(-DVec3::ONE, DVec3::ONE, 1),
                sphere(DVec3::ZERO, 1.4, 1),
            ],
        );
        let lantern = Csg::new(
            CsgOp::Difference,
            vec![
                Box::new(body),
                cyl(Transform::translate(DVec3::ZERO)),
                cyl(Transform::rotate(DVec3::X, 90.0).unwrap()),
                cyl(Transform::rotate(DVec3::Z, 90.0).unwrap()),
            ],
        );
        let turned = Transformed::new(
            Box::new(lantern),
            Transform::rotate(DVec3::Y, 30.0).unwrap(),
        );
        let rays = testing::rays_towards(DVec3::ZERO, 1.2, 500, 66);
        testing::check_consistency(&turned, &rays);
        testing::check_alternation(&turned, &rays);
        testing::check_no_rehit(&turned, &rays);
        // Straight down the y hole: nothing.
        let down = Ray::new(DVec3::new(0.0, 5.0, 0.0), -DVec3::Y);
        assert!(turned.intersect(&down, 0.0, 99.0).is_none());
        // Across at y = 0.7 (above the x hole): into the body, out into the y
        // hole through its wall, whose normal (reversed) leaves along the ray.
        let across = Ray::new(DVec3::new(-5.0, 0.7, 0.0), DVec3::X);
        let h = turned.intersect(&across, 0.0, 99.0).unwrap();
        assert_eq!(h.material, 1);
        let h = turned.intersect(&across, h.t + 1e-6, 99.0).unwrap();
        assert!(h.material == 2 && h.normal.dot(across.dir) > 0.0, "{h:?}");
        // A camera in the hollow centre sees the holes' walls, not the body.
        let h = turned
            .intersect(
                &Ray::new(DVec3::ZERO, DVec3::new(1.0, 1.0, 1.0)),
                1e-9,
                99.0,
            )
            .unwrap();
        assert_eq!(h.material, 2);
    }

    #[test]
    fn uv_is_asked_of_the_shape_that_was_hit() {
        let _watchdog = crate::watchdog::start();
        // A bitten ball in a union with a moved cylinder: each hit's (u, v)
        // must be what the leaf itself gives for that point.
        let ball = Sphere::new(DVec3::ZERO, 1.0, 1);
        let tube = Cone::cylinder(DVec3::ZERO, 0.4, 2.0, 3, Some([4, 4]));
        let moved = Transform::translate(DVec3::new(1.5, 0.0, 0.0));
        let bitten = Csg::new(
            CsgOp::Difference,
            vec![
                Box::new(ball.clone()),
                cube(DVec3::splat(0.2), DVec3::splat(2.0), 2),
            ],
        );
        let u = Transformed::new(
            Box::new(Csg::new(
                CsgOp::Union,
                vec![
                    Box::new(Transformed::new(Box::new(tube.clone()), moved)),
                    Box::new(bitten),
                ],
            )),
            Transform::rotate(DVec3::Y, 20.0).unwrap(),
        );
        let mut seen = [0; 5];
        for r in testing::rays_towards(DVec3::new(0.7, 0.0, 0.0), 1.5, 400, 68) {
            let Some(h) = u.intersect(&r, 1e-9, f64::INFINITY) else {
                continue;
            };
            let leaf = Hit { path: 0, ..h };
            let want = match h.material {
                1 => ball.uv(&leaf),
                3 | 4 => tube.uv(&leaf),
                _ => h.uv,
            };
            assert_eq!(u.uv(&h), want, "{h:?}");
            assert!(want.cmpge(DVec2::ZERO).all() && want.cmple(DVec2::ONE).all());
            seen[h.material as usize] += 1;
        }
        assert!(seen[1] > 20 && seen[2] > 5 && seen[3] > 20, "{seen:?}");
    }

    /// A nested unbounded intersection (a quarter-space: two planes) that a
    /// line runs inside of without crossing it: the parent learns from
    /// `encloses` that the whole line is inside, so a ball minus the
    /// quarter-space shows nothing along a line within the quarter, and
    /// the ball along one outside it.
    #[test]
    fn a_nested_unbounded_intersection_encloses_the_lines_inside_it() {
        let _watchdog = crate::watchdog::start();
        let quarter = || {
            Box::new(Csg::new(
                CsgOp::Intersection,
                vec![
                    Box::new(Plane::new(DVec3::Y, 0.0, 2)) as Box<dyn Shape>,
                    Box::new(Plane::new(DVec3::X, 0.0, 2)),
                ],
            )) as Box<dyn Shape>
        };
        assert!(quarter().encloses(DVec3::new(-1.0, -1.0, 7.0)));
        assert!(!quarter().encloses(DVec3::new(1.0, -1.0, 7.0)));
        let ball_minus = Csg::new(
            CsgOp::Difference,
            vec![sphere(DVec3::ZERO, 5.0, 1), quarter()],
        );
        let ball_and = Csg::new(
            CsgOp::Intersection,
            vec![sphere(DVec3::ZERO, 5.0, 1), quarter()],
        );
        // Along z, parallel to both planes.
        let inside = Ray::new(DVec3::new(-1.0, -1.0, 20.0), -DVec3::Z);
        let outside = Ray::new(DVec3::new(1.0, -1.0, 20.0), -DVec3::Z);
        assert!(ball_minus.intersect(&inside, 0.0, f64::INFINITY).is_none());
        assert!(ball_minus.intersect(&outside, 0.0, f64::INFINITY).is_some());
        let h = ball_and
            .intersect(&inside, 0.0, f64::INFINITY)
            .expect("the ball's quarter");
        assert!((h.t - (20.0 - 23f64.sqrt())).abs() < 1e-9, "{h:?}");
        assert!(ball_and.intersect(&outside, 0.0, f64::INFINITY).is_none());
        assert_eq!(xs(&ball_and, &inside).len(), 2);
        assert!(xs(&ball_minus, &inside).is_empty());
    }

    #[test]
    fn nesting_too_deep_for_the_key_keeps_the_material() {
        let _watchdog = crate::watchdog::start();
        // 70 unions of three children nest 3^70 > 2^64 keys deep: the key
        // overflows, and the hit must still be the right surface. The other
        // spheres lie further along the ray, so that every union sweeps.
        let mut s: Box<dyn Shape> = sphere(DVec3::ZERO, 1.0, 9);
        for k in 0..70 {
            let far = |m| sphere(DVec3::new(0.0, 0.0, -3.0 - k as f64), 0.5, m);
            s = Box::new(Csg::new(CsgOp::Union, vec![far(1), s, far(2)]));
        }
        let r = Ray::new(DVec3::new(0.3, 0.2, 5.0), DVec3::new(0.0, 0.0, -1.0));
        let h = s.intersect(&r, 1e-9, f64::INFINITY).expect("the sphere");
        assert_eq!(h.material, 9);
        let want = 5.0 - (1.0f64 - 0.09 - 0.04).sqrt();
        assert!((h.t - want).abs() < 1e-12, "{}", h.t);
        let p = r.at(h.t);
        assert!((h.normal.normalize() - p).length() < 1e-9, "{:?}", h.normal);
        // Its path did not fit: marked lost, so (u, v) reads as zero rather
        // than being asked of whichever child a wrapped path would name.
        assert_eq!(h.path, LOST);
    }

    /// A lost crossing found again on a cutter of a difference is the
    /// cutter's surface turned inside out, as when the key fits.
    #[test]
    fn a_lost_crossing_on_a_cutter_faces_out_of_the_result() {
        let _watchdog = crate::watchdog::start();
        let d = Csg::new(
            CsgOp::Difference,
            vec![
                sphere(DVec3::ZERO, 2.0, 1),
                sphere(DVec3::new(0.0, 0.0, 2.0), 1.0, 2),
            ],
        );
        let r = Ray::new(DVec3::new(0.0, 0.0, 9.0), -DVec3::Z);
        // Entering the result at z = 1, on the cutter (its back face).
        let found = xs(&d, &r);
        let first = found.first().expect("a crossing");
        assert!((first.t - 8.0).abs() < 1e-12 && first.material == 2);
        let c = Crossing::new(first.t, first.normal, &r, LOST);
        let h = d.hit_of(&r, &c);
        assert_eq!((h.t, h.material, h.path), (first.t, 2, LOST));
        assert!(h.normal.dot(r.dir) < 0.0, "entering: {h:?}");
    }

    /// A union whose unbounded child (a half-space) holds the whole line
    /// without crossing it: everything along the line is inside the union,
    /// so the other children's surfaces there are inner ones, not seen.
    #[test]
    fn a_line_inside_an_unbounded_child_of_a_union_sees_no_inner_surfaces() {
        let _watchdog = crate::watchdog::start();
        let u = Csg::new(
            CsgOp::Union,
            vec![
                Box::new(Plane::new(DVec3::Y, 0.0, 1)) as Box<dyn Shape>,
                sphere(DVec3::ZERO, 1.0, 2),
            ],
        );
        let below = Ray::new(DVec3::new(0.0, -0.5, 9.0), -DVec3::Z);
        assert!(u.intersect(&below, 0.0, f64::INFINITY).is_none());
        assert!(!u.occludes(&below, 0.0, f64::INFINITY));
        let above = Ray::new(DVec3::new(0.0, 0.5, 9.0), -DVec3::Z);
        let h = u.intersect(&above, 0.0, f64::INFINITY).expect("the sphere");
        assert_eq!(h.material, 2);
    }

    /// The last resort of a lost crossing: no child has a crossing at its t
    /// (it cannot be found again), so the hit is made from the crossing
    /// alone: its t, a normal that says entering or leaving as `facing`
    /// did, the point for solid textures, and the path marked lost.
    #[test]
    fn a_lost_crossing_no_child_has_is_still_a_consistent_hit() {
        let _watchdog = crate::watchdog::start();
        let u = Csg::new(CsgOp::Union, vec![sphere(DVec3::ZERO, 1.0, 4)]);
        let r = Ray::new(DVec3::new(0.0, 0.0, 9.0), DVec3::new(0.0, 0.0, -2.0));
        for facing in [-1.0, 1.0] {
            let c = Crossing {
                t: 2.5,
                facing,
                grazing: false,
                key: LOST,
            };
            let h = u.hit_of(&r, &c);
            assert_eq!(h.t, 2.5);
            assert_eq!(h.local, r.at(2.5));
            assert_eq!(h.path, LOST);
            assert_eq!(h.normal.dot(r.dir).signum(), facing, "{h:?}");
            assert_eq!(u.uv(&h), DVec2::ZERO);
        }
    }

    #[test]
    fn lite_crossings_rebuild_the_same_hits() {
        let _watchdog = crate::watchdog::start();
        // Each shape's crossings_lite, made into hits by hit_of, must be its
        // crossings exactly; the torus uses the trait's default bodies.
        use crate::shapes::Torus;
        let turned = |s: Box<dyn Shape>| -> Box<dyn Shape> {
            Box::new(Transformed::new(
                s,
                Transform::rotate(DVec3::new(1.0, 2.0, 0.5), 35.0).unwrap(),
            ))
        };
        let shapes: Vec<Box<dyn Shape>> = vec![
            sphere(DVec3::new(0.1, 0.0, 0.2), 1.0, 1),
            cube(-DVec3::ONE, DVec3::new(1.0, 0.5, 1.2), 2),
            Box::new(Cone::cylinder(DVec3::ZERO, 0.8, 1.5, 3, Some([4, 5]))),
            Box::new(Plane::new(DVec3::new(0.2, 1.0, 0.0), 0.1, 6)),
            Box::new(Torus::new(1.0, 0.3, 7)),
            turned(Box::new(Cone::cylinder(
                DVec3::ZERO,
                0.8,
                1.5,
                3,
                Some([4, 5]),
            ))),
            Box::new(Csg::new(
                CsgOp::Difference,
                vec![
                    turned(cube(-DVec3::ONE, DVec3::ONE, 1)),
                    sphere(DVec3::splat(0.6), 0.8, 2),
                    Box::new(Torus::new(0.9, 0.2, 3)),
                ],
            )),
        ];
        let mut seen = 0;
        for s in &shapes {
            for r in testing::rays_towards(DVec3::ZERO, 1.2, 200, 69) {
                let mut lite = Vec::new();
                s.crossings_lite(&r, &mut lite);
                let full = xs(&**s, &r);
                assert_eq!(lite.len(), full.len(), "{s:?} {r:?}");
                for (c, h) in lite.iter().zip(&full) {
                    assert_eq!(s.hit_of(&r, c), *h);
                    assert_eq!(c.facing < 0.0, h.normal.dot(r.dir) < 0.0);
                }
                seen += full.len();
            }
        }
        assert!(seen > 1000, "{seen}");
    }

    #[test]
    fn union_of_apart_children_agrees_with_the_sweep() {
        let _watchdog = crate::watchdog::start();
        // Children whose reaches along a ray do not overlap are asked for
        // their nearest hit directly; that must be what the full crossing
        // list says, in any window, floor included.
        let floor = || Box::new(Plane::new(DVec3::Y, 0.0, 3)) as Box<dyn Shape>;
        let u = Csg::new(
            CsgOp::Union,
            vec![
                sphere(DVec3::new(-1.5, 1.0, 0.0), 1.0, 1),
                cube(DVec3::new(0.5, 0.0, -0.5), DVec3::new(1.5, 2.0, 0.5), 2),
                floor(),
                sphere(DVec3::new(1.0, 1.5, 0.0), 0.7, 4),
            ],
        );
        let mut hits = 0;
        for (k, r) in testing::rays_towards(DVec3::new(0.0, 1.0, 0.0), 2.5, 600, 70)
            .iter()
            .enumerate()
        {
            let list = xs(&u, r);
            let lo = if k % 3 == 0 {
                1e-9
            } else {
                7.0 + (k % 7) as f64 * 0.5
            };
            let hi = if k % 2 == 0 {
                f64::INFINITY
            } else {
                lo + 1.0 + (k % 5) as f64
            };
            let want = list.iter().find(|h| h.t > lo && h.t < hi);
            let got = u.intersect(r, lo, hi);
            assert_eq!(got.map(|h| h.t), want.map(|h| h.t), "window {lo}..{hi}");
            assert_eq!(got.map(|h| h.material), want.map(|h| h.material));
            assert_eq!(got.map(|h| h.path), want.map(|h| h.path));
            assert_eq!(u.occludes(r, lo, hi), want.is_some());
            hits += got.is_some() as usize;
        }
        assert!(hits > 300, "{hits}");
    }

    #[test]
    fn quick_clip_agrees_with_aabb_clip() {
        let _watchdog = crate::watchdog::start();
        let b = Aabb::new(DVec3::new(-1.0, 0.0, -0.5), DVec3::new(1.0, 2.0, 0.5));
        let mut rays = testing::rays_towards(DVec3::new(0.0, 1.0, 0.0), 2.0, 500, 71);
        // Axis-parallel, one of them in the plane of a face.
        rays.push(Ray::new(DVec3::new(0.0, 1.0, -5.0), DVec3::Z));
        rays.push(Ray::new(DVec3::new(1.0, 1.0, -5.0), DVec3::Z));
        rays.push(Ray::new(DVec3::new(3.0, 1.0, -5.0), DVec3::Z));
        let mut hits = 0;
        for r in &rays {
            for (lo, hi) in [(0.0, f64::INFINITY), (9.0, 10.0), (f64::NEG_INFINITY, 9.5)] {
                let (a, b2) = (clip(&b, r, r.dir.recip(), lo, hi), b.clip(r, lo, hi));
                if r.dir.cmpne(DVec3::ZERO).all() {
                    assert_eq!(a, b2, "{r:?} {lo}..{hi}");
                } else if let Some((x, y)) = b2 {
                    // Along a face's plane: at least Aabb::clip's stretch.
                    let (p, q) = a.unwrap();
                    assert!(p <= x && q >= y, "{r:?} {lo}..{hi}");
                }
                hits += a.is_some() as usize;
            }
        }
        // The line in the plane x = 1 (of the face) still meets the box.
        let along = Ray::new(DVec3::new(1.0, 1.0, -5.0), DVec3::Z);
        assert_eq!(
            clip(&b, &along, along.dir.recip(), 0.0, 99.0),
            Some((4.5, 5.5))
        );
        assert!(hits > 300, "{hits}");
    }

    /// Renders `objects` with a camera and a light at `eye`, looking along +x.
    fn render(objects: Vec<Box<dyn Shape>>, eye: DVec3) -> crate::render::Film {
        use crate::scene::{Camera, Light, Material, Projection, RenderSettings, Scene, Texture};
        let solid = |r, g, b| Material::matte(Texture::Solid(DVec3::new(r, g, b)), 0.0);
        let scene = Scene {
            camera: Camera {
                position: eye,
                look_at: eye + DVec3::X,
                up: DVec3::Y,
                projection: Projection::Fov(60.0),
                lens: None,
            },
            settings: RenderSettings {
                width: 24,
                height: 16,
                ..RenderSettings::default()
            },
            ambient: DVec3::splat(0.1),
            lights: vec![Light::point(eye, DVec3::ONE)],
            materials: vec![
                Material::default(),
                solid(1.0, 0.0, 0.0),
                solid(0.0, 1.0, 0.0),
            ],
            ..Scene::default()
        };
        let world = crate::accel::World::build(objects);
        let opts = crate::render::RenderOptions { progress: None };
        crate::render::render(&scene, &world, &opts).unwrap().0
    }

    #[test]
    fn rendered_from_inside_a_union_and_a_group() {
        let _watchdog = crate::watchdog::start();
        let two = || {
            vec![
                sphere(DVec3::new(-0.5, 0.0, 0.0), 1.0, 1),
                sphere(DVec3::new(0.5, 0.0, 0.0), 1.0, 2),
            ]
        };
        // Union: every pixel sees the far, green wall, lit by the light
        // inside (no inner surface casts a shadow).
        let union = render(vec![Box::new(Csg::new(CsgOp::Union, two()))], DVec3::ZERO);
        for p in &union.pixels {
            assert!(p[0] == 0.0 && p[1] > 0.5 && p[2] == 0.0, "{p:?}");
        }
        // A group of the same two spheres shows the red sphere's inside.
        let group = render(two(), DVec3::ZERO);
        let centre = group.get(12, 8);
        assert!(centre[0] > 0.5 && centre[1] == 0.0, "{centre:?}");
    }

    #[test]
    fn rendered_union_with_itself_is_the_shape() {
        let _watchdog = crate::watchdog::start();
        let lens = || -> Box<dyn Shape> {
            Box::new(Csg::new(
                CsgOp::Intersection,
                vec![
                    sphere(DVec3::new(0.0, 0.0, 0.6), 1.0, 1),
                    sphere(DVec3::new(0.0, 0.0, -0.6), 1.0, 2),
                ],
            ))
        };
        let eye = DVec3::new(-4.0, 0.3, 0.2);
        let alone = render(vec![lens()], eye);
        let doubled = render(
            vec![Box::new(Csg::new(CsgOp::Union, vec![lens(), lens()]))],
            eye,
        );
        assert_eq!(alone.pixels, doubled.pixels);
        // The lens is seen edge-on: both colours, and background around it.
        assert!(alone.pixels.iter().any(|p| p[0] > 0.0));
        assert!(alone.pixels.iter().any(|p| p[1] > 0.0));
        assert!(alone.pixels.contains(&[0.0; 3]));
    }
}
