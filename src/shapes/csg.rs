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
//! Shortcuts, each exact: a union whose children are pairwise clear of
//! each other (their boxes apart, or a bounded child's box in front of a
//! plane: solids standing on the floor) has no inner surfaces, so its
//! nearest hit is its children's nearest, and a shadow ray met by a
//! child that touches no other is blocked, with no sweep (where two
//! children touch, a ray may pass from one straight into the other,
//! crossing both at once, and the sweep merges those crossings: a
//! touching child crossed next to the nearest hit sends the ray there);
//! in other unions a child whose reach along the ray (its box, or an unbounded child's
//! first to last crossing) overlaps no other child's is asked for its
//! nearest hit directly (the floor under a few solids); an intersection
//! (after any child) or a difference (after its first child) stops as
//! soon as what that child encloses misses the window asked about, and
//! narrows the window for the children after it.
//!
//! One concept, kept whole: the sweep, its shortcuts and the hit they
//! hand back share the same bits and keys (`Flip`, `Scratch`, `LOST`);
//! split apart they would only pass those around (tests live beside).

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
    /// A union whose children are pairwise clear of each other
    /// ([`Shape::clear_of`]): no child's surface lies inside another, so
    /// the result's crossings are all the children's and its nearest hit
    /// is theirs, with no sweep.
    disjoint: bool,
    /// Per child of a `disjoint` union, the other children it may touch
    /// (not apart with a little room to spare), as bits.
    touch: Vec<u64>,
    /// Whether any two children may touch (`touch` not all zero), kept
    /// because every ray asks.
    touches: bool,
    /// The material the block gives its children (its own or inherited):
    /// hits wearing it have their solid-texture point in this block's
    /// space, see [`Csg::texture_space`].
    texture_space: Option<MaterialId>,
    /// Whether shading that material may read (u, v), which is then
    /// worked out before the point moves.
    texture_reads_uv: bool,
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

/// The widest union checked for pairwise clear children (the check is
/// quadratic, once per union).
const CLEAR_MAX: usize = 64;

/// Whether children `i` and `j` are clear of each other, `room` applied
/// to the box that is asked about: two bounded ones by their boxes, a
/// bounded one and an unbounded one by asking the unbounded one about
/// the other's box; two unbounded ones never are.
fn clear_pair(
    children: &[Box<dyn Shape>],
    bounds: &[Aabb],
    reach: &[Reach],
    (i, j): (usize, usize),
    room: impl Fn(&Aabb) -> Aabb,
) -> bool {
    match (reach[i], reach[j]) {
        (Reach::Nowhere, _) | (_, Reach::Nowhere) => true,
        (Reach::Bounded, Reach::Bounded) => room(&bounds[i]).apart(&bounds[j]),
        (Reach::Bounded, Reach::Unbounded) => children[j].clear_of(&room(&bounds[i])),
        (Reach::Unbounded, Reach::Bounded) => children[i].clear_of(&room(&bounds[j])),
        (Reach::Unbounded, Reach::Unbounded) => false,
    }
}

/// Whether every two children are clear of each other ([`clear_pair`]).
fn pairwise_clear(children: &[Box<dyn Shape>], bounds: &[Aabb], reach: &[Reach]) -> bool {
    let n = children.len();
    if n > CLEAR_MAX {
        return false;
    }
    (0..n).all(|i| (i + 1..n).all(|j| clear_pair(children, bounds, reach, (i, j), |b| *b)))
}

/// For children that are pairwise clear, which pairs may touch: those no
/// longer clear once one's box grows by a billionth of its size (and a
/// billionth), so that crossings within the sweep's tolerance of each
/// other are caught.
fn touching(children: &[Box<dyn Shape>], bounds: &[Aabb], reach: &[Reach]) -> Vec<u64> {
    let n = children.len();
    let grown = |b: &Aabb| b.padded(1e-9 * (1.0 + b.min.abs().max(b.max.abs()).max_element()));
    let mut touch = vec![0u64; n];
    for i in 0..n {
        for j in i + 1..n {
            if !clear_pair(children, bounds, reach, (i, j), grown) {
                touch[i] |= 1 << j;
                touch[j] |= 1 << i;
            }
        }
    }
    touch
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
        let reach: Vec<Reach> = child_bounds.iter().map(reach_of).collect();
        let extent = reach_of(&bounds);
        let disjoint = op == CsgOp::Union && pairwise_clear(&children, &child_bounds, &reach);
        let touch = if disjoint {
            touching(&children, &child_bounds, &reach)
        } else {
            Vec::new()
        };
        Csg {
            op,
            children,
            child_bounds,
            reach,
            bounds,
            extent,
            disjoint,
            touches: touch.iter().any(|&t| t != 0),
            touch,
            texture_space: None,
            texture_reads_uv: false,
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
    /// `reads_uv`: whether shading `material` may read (u, v) at all (a
    /// solid checker does not, and the sphere's or the cylinder's (u, v)
    /// costs an `atan2`).
    pub fn texture_space(mut self, material: MaterialId, reads_uv: bool) -> Self {
        self.texture_space = Some(material);
        self.texture_reads_uv = reads_uv;
        self
    }

    /// Moves a hit of child `i` that wears the block's material into the
    /// block's texture space (see [`Csg::texture_space`]).
    fn in_texture_space(&self, ray: &Ray, h: &mut Hit, i: usize) {
        if self.texture_space == Some(h.material) {
            if self.texture_reads_uv && h.path != LOST {
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
        // A difference's bounds are its first child's, which the caller
        // has already clipped over this same span.
        let clipped = i == 0 && self.op == CsgOp::Difference;
        if bounded
            && !clipped
            && self.child_bounds[i]
                .clip_with(ray, inv, span.0, span.1)
                .is_none()
        {
            return false;
        }
        let first = s.xs.len();
        self.children[i].crossings_lite(ray, &mut s.xs);
        // A bounded solid cannot contain the far end of a line; an unbounded
        // one (a plane) starts inside when its first crossing leaves. A
        // grazing crossing (a tangent ray's double root) flips the inside
        // flag rather than setting it. The first one's sign still says
        // which side the line starts on: an unbounded child's first
        // crossing is never half of a tangent pair (whose signs are noise),
        // but a plane's one crossing, exact in sign however nearly the
        // plane runs along the line, or a nested CSG's, which reports one
        // crossing per change of its inside-ness, chosen to agree with it.
        let mut inside = if bounded {
            false
        } else {
            match s.xs.get(first) {
                Some(c) => c.facing > 0.0,
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
    /// Every caller has met the result's bounds over `span` first
    /// ([`Csg::may_hit`]), so a difference's first child, whose box those
    /// bounds are, is not clipped again.
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
                    self.child_bounds[i].clip_with(ray, inv, t_min, t_max),
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
            Reach::Bounded => self.bounds.clip(ray, t_min, t_max).is_some(),
        }
    }
}

impl Csg {
    /// The result's first crossing within (t_min, t_max), as a full hit
    /// written into `hit` (left as it was when there is none). A lone
    /// child writes its hit there itself: a hit handed back in an `Option`
    /// is copied (160 bytes) at each level, and a union holding the floor
    /// is asked by every ray.
    fn nearest_into(&self, ray: &Ray, t_min: f64, t_max: f64, hit: &mut Hit) -> bool {
        if self.disjoint
            && let Some(found) = self.nearest_of_clear(ray, t_min, t_max, hit)
        {
            return found;
        }
        // The lone children's nearest hit, as the child gave it: made the
        // result's (texture space, path) only if nothing swept is nearer.
        let mut found_child = None;
        let swept = with_scratch(|s| {
            let (alone, rest) = self.union_split(ray, t_min, t_max, s);
            let mut t_best = t_max;
            for i in bits(alone) {
                if self.children[i].intersect_into(ray, t_min, t_best, hit) {
                    t_best = hit.t;
                    found_child = Some(i);
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
            *hit = self.hit_of(ray, &c);
            return true;
        }
        let Some(i) = found_child else {
            return false;
        };
        self.in_texture_space(ray, hit, i);
        self.tag(hit, i as u32);
        true
    }
}

impl Csg {
    /// [`Csg::nearest_into`] for a union of clear children: the nearest of
    /// the children's own hits, each child asked only when its box meets
    /// the ray before the nearest so far (as [`Csg::union_split`]'s lone
    /// children are). A child's crossing lies inside no other child (they
    /// share no interior), so it is the result's, unless a child touching
    /// it has a crossing at nearly the same `t`: a ray passing from one
    /// straight into the other through a face they share, or the point
    /// where a ball touches the floor, crosses both at once, and the sweep
    /// merges the two. Then `None` (the sweep decides), with `hit` put
    /// back as it was.
    fn nearest_of_clear(&self, ray: &Ray, t_min: f64, t_max: f64, hit: &mut Hit) -> Option<bool> {
        let inv = ray.dir.recip();
        // What to put back when the sweep must decide after all: saved
        // just before a child may first write into `hit` (160 bytes, so
        // not for every ray). A floor, or any unbounded child that finds
        // its root apart from its hit, gives only its root here (as in
        // the world's own search), and its hit is made at the end if it
        // still wins: a ray that meets only the floor copies nothing.
        let mut before: Option<Hit> = None;
        let mut deferred: Option<&dyn super::Roots> = None;
        let mut t_best = t_max;
        let mut winner = None;
        for (i, child) in self.children.iter().enumerate() {
            if !self.child_near(i, ray, inv, t_min, t_best) {
                continue;
            }
            if self.reach[i] == Reach::Unbounded
                && let Some(r) = child.roots()
            {
                if let Some(t) = r.root_within(ray, t_min, t_best) {
                    (t_best, winner, deferred) = (t, Some(i), Some(r));
                }
                continue;
            }
            if self.touches && before.is_none() {
                before = Some(*hit);
            }
            if child.intersect_into(ray, t_min, t_best, hit) {
                (t_best, winner, deferred) = (hit.t, Some(i), None);
            }
        }
        let Some(i) = winner else {
            return Some(false);
        };
        if self.touches {
            // Twice `same_t`'s reach on either side.
            let pad = 2e-9 * magnitude(t_best);
            let (lo, hi) = (t_best - pad, t_best + pad);
            for j in bits(self.touch[i]) {
                if self.child_near(j, ray, inv, lo, hi) && self.children[j].occludes(ray, lo, hi) {
                    // Untouched unless a child wrote into it.
                    if let Some(before) = before {
                        *hit = before;
                    }
                    return None;
                }
            }
        }
        if let Some(r) = deferred {
            r.hit_at_root(ray, t_best, hit);
        }
        self.in_texture_space(ray, hit, i);
        self.tag(hit, i as u32);
        Some(true)
    }

    /// Whether child `i` may have a crossing within (lo, hi): its box
    /// meets the ray there, or it is unbounded.
    #[inline(always)]
    fn child_near(&self, i: usize, ray: &Ray, inv: DVec3, lo: f64, hi: f64) -> bool {
        match self.reach[i] {
            Reach::Nowhere => false,
            Reach::Bounded => self.child_bounds[i].clip_with(ray, inv, lo, hi).is_some(),
            Reach::Unbounded => true,
        }
    }

    /// The children that block the segment (t_min, t_max), as bits, for
    /// a union's shadow test: the union is blocked only where one of them
    /// is.
    fn children_met(&self, ray: &Ray, t_min: f64, t_max: f64) -> u64 {
        let inv = ray.dir.recip();
        let mut m = 0u64;
        for i in 0..self.children.len() {
            // An unbounded child's box (all space, or a half-space) is
            // no cheaper to clip than the child (a plane) is to ask.
            if self.child_near(i, ray, inv, t_min, t_max)
                && self.children[i].occludes(ray, t_min, t_max)
            {
                m |= 1 << i;
            }
        }
        m
    }
}

impl Shape for Csg {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let mut hit = Hit::default();
        self.intersect_into(ray, t_min, t_max, &mut hit)
            .then_some(hit)
    }

    fn intersect_into(&self, ray: &Ray, t_min: f64, t_max: f64, hit: &mut Hit) -> bool {
        self.may_hit(ray, t_min, t_max) && self.nearest_into(ray, t_min, t_max, hit)
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        if !self.may_hit(ray, t_min, t_max) {
            return false;
        }
        // Every surface of the result is some child's surface, so when no
        // child has a crossing in range (the common shadow ray), neither
        // does the result: a union asks its children first and splits them
        // (which costs an unbounded child's crossings) only when one is hit.
        // An intersection or a difference narrows its sweep by its first
        // child at once, which does the same job.
        // A union wider than the mask's 64 bits skips the pre-test: the
        // sweep asks every child, the ones past the 64th included.
        let occluding = if self.op == CsgOp::Union && self.children.len() <= 64 {
            let m = self.children_met(ray, t_min, t_max);
            if m == 0 {
                return false;
            }
            // A child of clear ones that touches none: every crossing of
            // its is the result's.
            if self.disjoint && bits(m).any(|i| self.touch[i] == 0) {
                return true;
            }
            m
        } else {
            u64::MAX
        };
        with_scratch(|s| {
            let (alone, rest) = self.union_split(ray, t_min, t_max, s);
            // A lone child's surfaces are the result's.
            if alone & occluding != 0 {
                return true;
            }
            let mut hit = false;
            if rest & occluding != 0 {
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

    /// As [`Csg::uv`]: down the path to the child that made the hit,
    /// unless `local` was taken in this block's own space.
    fn normal_to_world(&self, hit: &Hit, v: DVec3) -> DVec3 {
        if self.texture_space == Some(hit.material) {
            return v;
        }
        let n = self.children.len() as u64;
        if hit.path == LOST || n == 0 {
            return v;
        }
        let inner = Hit {
            path: hit.path / n,
            ..*hit
        };
        self.children[(hit.path % n) as usize].normal_to_world(&inner, v)
    }
}

#[cfg(test)]
#[path = "csg_tests.rs"]
mod tests;
