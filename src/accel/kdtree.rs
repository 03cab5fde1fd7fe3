//! A kd-tree over anything with a bounding box: the triangles of a mesh or
//! the objects of a scene. The tree only knows item numbers and boxes; the
//! caller's closure intersects an item.
//!
//! Build: surface area heuristic (SAH) with a bonus for cutting off empty
//! space (pbrt's kd-tree rules: a split must beat the cost of a leaf, a few
//! bad refinements are tolerated, depth is capped at 8 + 1.3·log2 N). Big
//! nodes bin the items' boxes into 32 slabs per axis; small ones try every
//! box face. The two halves of big nodes are built in parallel (rayon).
//! Split positions are rounded to `f32` before the items are partitioned,
//! so the 8-byte nodes store exactly the plane that was used.
//!
//! Traversal: front to back with a small stack; the walk ends at a leaf
//! whose segment holds the nearest hit found so far, or at a segment that
//! starts beyond it. A ray parallel to a
//! split plane (zero direction component) goes only to the side its origin
//! is on, or to both when it lies in the plane.
//!
//! `build_clipped` makes "perfect splits": the caller clips an item to a
//! cell (a mesh clips the triangle itself), so an item straddling a plane
//! is binned with its true extent on each side, and dropped from a side it
//! only reaches with its box. The mesh uses that with SAH constants
//! measured on the bunny's rays (see `shapes::mesh::MESH_TREE`).

use crate::geometry::{Aabb, Ray};

/// Traversal steps (nodes visited), counted in test builds only so that
/// tests can measure a tree's quality without a cost in release.
#[cfg(test)]
pub(crate) mod counters {
    use std::cell::Cell;
    thread_local! {
        pub static STEPS: Cell<u64> = const { Cell::new(0) };
    }
    #[inline]
    pub fn step() {
        STEPS.with(|c| c.set(c.get() + 1));
    }
    pub fn take() -> u64 {
        STEPS.with(|c| c.replace(0))
    }
}

/// Interior: `a = above_child << 2 | axis`, `b = split as f32 bits`; the
/// child below the plane is the next node. Leaf: `a = count << 2 | 3`,
/// `b = offset` into the item list.
#[derive(Clone, Copy, Debug)]
struct Node {
    a: u32,
    b: u32,
}

impl Node {
    fn leaf(offset: usize, count: usize) -> Node {
        Node {
            a: ((count as u32) << 2) | 3,
            b: offset as u32,
        }
    }
    #[inline(always)]
    fn is_leaf(&self) -> bool {
        self.a & 3 == 3
    }
}

/// Shape and cost of a built tree, for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TreeStats {
    pub items: usize,
    pub nodes: usize,
    pub leaves: usize,
    pub empty_leaves: usize,
    /// Item references in all leaves (an item straddling a plane counts twice).
    pub references: usize,
    pub max_leaf: usize,
    pub max_depth: usize,
    pub build_seconds: f64,
    /// Bytes of the nodes and item lists ([`KdTree::memory`]).
    pub bytes: usize,
}

#[derive(Clone, Debug)]
pub struct KdTree {
    nodes: Vec<Node>,
    items: Vec<u32>,
    bounds: Aabb,
    pub stats: TreeStats,
}

/// Relative costs of one traversal step and one item test.
const TRAVERSAL_COST: f64 = 1.0;
const BINS: usize = 32;
/// Nodes with fewer items try every box face as a plane.
const EXACT_BELOW: usize = 12;
/// Nodes with more items build their two halves in parallel.
const PARALLEL_ABOVE: usize = 1024;

/// Tuning of the SAH build.
#[derive(Clone, Copy, Debug)]
pub struct BuildParams {
    /// Cost of one item test relative to one traversal step.
    pub item_cost: f64,
    /// Fraction of the cost saved when one side of a split is empty.
    pub empty_bonus: f64,
    /// Depth cap: `depth_base + 1.3·log2 N`.
    pub depth_base: f64,
}

/// The constants for a scene's objects (the world's tree; meshes have
/// their own, `MESH_TREE`). An item costs two steps: the costs matter
/// little within 1.5..4, and a deeper cap (11) doubled the nodes without
/// a faster render. No bonus for cutting off empty space: the textbook
/// half cut `glass_full`'s five objects into 11 leaves, 6 of them empty,
/// and a ray took ten steps through them; without it the tree is one leaf
/// per object (depth 3): `glass_full` 4%, `glass` 5%, `many` and
/// `bunny_grid` 5-6% faster (interleaved runs, session 19), `dof` and
/// `soft` (their rays go through beams and shafts) as fast.
impl Default for BuildParams {
    fn default() -> Self {
        BuildParams {
            item_cost: 2.0,
            empty_bonus: 0.0,
            depth_base: 8.0,
        }
    }
}
/// The traversal stack holds at most one entry per level.
const MAX_DEPTH: usize = 60;
const STACK: usize = MAX_DEPTH + 4;

/// A node's box prepared for SAH costs: per axis, the half area of the
/// faces across it (`cap`) and the half perimeter around it (`ring`).
struct Frame {
    min: [f64; 3],
    max: [f64; 3],
    cap: [f64; 3],
    ring: [f64; 3],
    inv_half_area: f64,
}

impl Frame {
    fn new(b: &Aabb) -> Frame {
        let e = b.extent().to_array();
        Frame {
            min: b.min.to_array(),
            max: b.max.to_array(),
            cap: [e[1] * e[2], e[2] * e[0], e[0] * e[1]],
            ring: [e[1] + e[2], e[2] + e[0], e[0] + e[1]],
            inv_half_area: 2.0 / b.area(),
        }
    }
}

/// A box as plain arrays: indexing glam's vectors by a run-time axis
/// costs a `match` per access, which the build does tens of millions of times.
/// In `f32`, rounded outwards: the planes are `f32` anyway, and the build
/// moves these boxes around in every node, so half the bytes is a faster build.
type Box6 = [[f32; 3]; 2];

#[inline]
fn round_down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x { f.next_down() } else { f }
}

#[inline]
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x { f.next_up() } else { f }
}

#[inline]
fn box6(b: &Aabb) -> Box6 {
    [
        b.min.to_array().map(round_down),
        b.max.to_array().map(round_up),
    ]
}

/// `clip(item, cell, axis, split)`: the boxes around the parts of the item
/// inside `cell` below and above the plane `split` on `axis`, `None` for a
/// side the item misses. They may be loose (a box too big costs only speed)
/// but must never cut off any of the item.
pub type Clip<'a> = &'a (dyn Fn(u32, &Aabb, usize, f64) -> [Option<Aabb>; 2] + Sync);

/// An item in a node under construction, with its box clipped to the node.
#[derive(Clone, Copy)]
struct Item {
    b: Box6,
    id: u32,
}

struct Builder<'a> {
    clip: Option<Clip<'a>>,
    nodes: Vec<Node>,
    items: Vec<u32>,
    stats: TreeStats,
    max_depth: usize,
    params: BuildParams,
}

impl KdTree {
    /// Builds the tree over `boxes[i]` for item `i`. Boxes must be finite
    /// (unbounded things stay outside the tree); empty boxes are left out.
    pub fn build(boxes: &[Aabb]) -> KdTree {
        Self::build_with(boxes, BuildParams::default())
    }

    pub fn build_with(boxes: &[Aabb], params: BuildParams) -> KdTree {
        Self::build_inner(boxes, None, params)
    }

    /// Builds with "perfect splits" (Wald & Havran 2006): an item that
    /// straddles a plane is clipped to each child's box, so the SAH sees the
    /// true extent of what is in a node and an item that only grazes a
    /// child's corner with its box is not referenced there at all.
    pub fn build_clipped(boxes: &[Aabb], clip: Clip, params: BuildParams) -> KdTree {
        Self::build_inner(boxes, Some(clip), params)
    }

    fn build_inner(boxes: &[Aabb], clip: Option<Clip>, params: BuildParams) -> KdTree {
        let start = std::time::Instant::now();
        let mut bounds = Aabb::EMPTY;
        let mut all = Vec::with_capacity(boxes.len());
        for (i, b) in boxes.iter().enumerate() {
            if !b.is_empty() && b.is_finite() {
                bounds = bounds.union(b);
                all.push(Item {
                    b: box6(b),
                    id: i as u32,
                });
            }
        }
        let n = all.len().max(1) as f64;
        let mut b = Builder {
            clip,
            // Room for what the bunny's tree needs (2.6 nodes and 3.5
            // references per triangle), so that the arrays are not copied
            // as they grow; pages never touched cost no memory.
            nodes: Vec::with_capacity(3 * all.len() + 1),
            items: Vec::with_capacity(4 * all.len()),
            stats: TreeStats {
                items: all.len(),
                ..TreeStats::default()
            },
            max_depth: ((params.depth_base + 1.3 * n.log2()).round() as usize).min(MAX_DEPTH),
            params,
        };
        b.node(bounds, all, 0, 0);
        // Returns the room never used (a remap for big arrays, no copy).
        b.nodes.shrink_to_fit();
        b.items.shrink_to_fit();
        let mut stats = b.stats;
        stats.nodes = b.nodes.len();
        stats.build_seconds = start.elapsed().as_secs_f64();
        stats.bytes = b.nodes.len() * std::mem::size_of::<Node>() + b.items.len() * 4;
        KdTree {
            nodes: b.nodes,
            items: b.items,
            bounds,
            stats,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Bytes held by the tree.
    pub fn memory(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.items.len() * 4
    }

    /// The nearest hit: `test(item, t_best)` intersects one item and returns
    /// its `t` if that lies in `(t_min, t_best)`. Returns the best `t`.
    #[inline]
    pub fn nearest(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut test: impl FnMut(u32, f64) -> Option<f64>,
    ) -> Option<f64> {
        let mut best = t_max;
        let mut found = false;
        self.walk(ray, t_min, t_max, |items| {
            for &i in items {
                if let Some(t) = test(i, best) {
                    best = t;
                    found = true;
                }
            }
            best
        });
        found.then_some(best)
    }

    /// Whether `test(item)` holds for any item the segment passes.
    #[inline]
    pub fn any(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut test: impl FnMut(u32) -> bool,
    ) -> bool {
        let mut hit = false;
        self.walk(ray, t_min, t_max, |items| {
            hit = items.iter().any(|&i| test(i));
            if hit { f64::NEG_INFINITY } else { t_max }
        });
        hit
    }

    /// Calls `visit` on every item in every leaf the whole line crosses
    /// (an item may come more than once).
    pub fn along_line(&self, ray: &Ray, mut visit: impl FnMut(u32)) {
        self.walk(ray, f64::NEG_INFINITY, f64::INFINITY, |items| {
            items.iter().for_each(|&i| visit(i));
            f64::INFINITY
        });
    }

    /// Calls `visit` on every item of every leaf whose cell may meet `b`
    /// (an item may come more than once) until `visit` returns false;
    /// returns false then. Each split plane is compared with a slack, so a
    /// box touching a plane visits both sides.
    pub fn overlapping(&self, b: &Aabb, mut visit: impl FnMut(u32) -> bool) -> bool {
        let t = &self.bounds;
        let apart = b.min.cmpgt(t.max).any() || b.max.cmplt(t.min).any();
        if self.items.is_empty() || apart {
            return true;
        }
        let (lo, hi) = (b.min.to_array(), b.max.to_array());
        let mut stack = [0u32; STACK];
        let mut sp = 0;
        let mut node = 0usize;
        loop {
            let n = self.nodes[node];
            if !n.is_leaf() {
                let axis = (n.a & 3) as usize;
                let split = f32::from_bits(n.b) as f64;
                let slack = SLACK * split.abs().max(lo[axis].abs()).max(hi[axis].abs());
                let below = lo[axis] <= split + slack;
                let above = hi[axis] >= split - slack;
                let (b_node, a_node) = (node + 1, (n.a >> 2) as usize);
                match (below, above) {
                    (true, true) => {
                        stack[sp] = a_node as u32;
                        sp += 1;
                        node = b_node;
                    }
                    (true, false) => node = b_node,
                    (false, true) => node = a_node,
                    // Only for a NaN box: nothing to visit.
                    (false, false) => return true,
                }
                continue;
            }
            let count = (n.a >> 2) as usize;
            let off = n.b as usize;
            for &i in &self.items[off..off + count] {
                if !visit(i) {
                    return false;
                }
            }
            if sp == 0 {
                return true;
            }
            sp -= 1;
            node = stack[sp] as usize;
        }
    }

    /// Visits the leaves along the segment front to back. `leaf(items)`
    /// returns the search limit after it (the nearest hit so far). The walk
    /// ends as soon as the limit lies within the leaf just visited, or
    /// before the next segment when that starts beyond it: every later
    /// leaf lies farther along the ray.
    #[inline]
    fn walk(&self, ray: &Ray, t_min: f64, t_max: f64, mut leaf: impl FnMut(&[u32]) -> f64) {
        if self.items.is_empty() {
            return;
        }
        let Some((mut lo, mut hi)) = self.bounds.clip(ray, t_min, t_max) else {
            return;
        };
        // Arrays, not glam vectors: indexing a DVec3 by a run-time axis is
        // a `match` per access on the hottest path of the renderer.
        let inv = ray.dir.recip().to_array();
        let origin = ray.origin.to_array();
        // The child below a plane comes first unless the ray goes down the
        // axis; by the sign bit, so that -0 goes with the negatives, as its
        // reciprocal -inf does.
        let toward_below = ray.dir.to_array().map(|d| !d.is_sign_negative());
        // A plane crossed within rounding of a segment's end is taken as
        // crossed inside it: both sides are visited. Without this a ray
        // aimed exactly at a vertex or edge lying on a split plane could be
        // sent to one side only and miss a flat mesh there (the plane's `t`
        // and the surface's `t` round differently). One slack per ray,
        // relative to the farthest `t` in the tree's box.
        let slack = SLACK * lo.abs().max(hi.abs());
        let nodes = self.nodes.as_slice();
        // Not zeroed per ray: every slot is written before it is read.
        let mut stack = [std::mem::MaybeUninit::<(u32, f64, f64)>::uninit(); STACK];
        let mut sp = 0;
        let mut node = 0usize;
        let mut limit = t_max;
        // Whether the ray lies in a split plane it met (NaN `tp`): both
        // sides then got the whole segment, so the stack is no longer in
        // front-to-back order and a hit on one side says nothing about the
        // other. The walk then ends only when the stack is empty, skipping
        // the entries that start beyond the limit.
        let mut in_plane = false;
        loop {
            debug_assert!(node < nodes.len());
            // SAFETY: the builder links only to nodes it pushed.
            let n = unsafe { *nodes.get_unchecked(node) };
            #[cfg(test)]
            counters::step();
            if !n.is_leaf() {
                let axis = (n.a & 3) as usize;
                let split = f32::from_bits(n.b) as f64;
                let (o, iv) = (origin[axis], inv[axis]);
                let below = node + 1;
                let above = (n.a >> 2) as usize;
                // A zero direction component needs no branch of its own:
                // its reciprocal is ±inf, so `tp` is ±inf and picks the
                // origin's side, or NaN for a ray in the plane, which fails
                // both tests below and visits both sides (see the push).
                let tp = (split - o) * iv;
                let (first, second) = if toward_below[axis] {
                    (below, above)
                } else {
                    (above, below)
                };
                if tp > hi + slack {
                    node = first;
                } else if tp < lo - slack {
                    node = second;
                } else {
                    // A NaN `tp` fails both comparisons: both sides then
                    // get the whole segment (as `f64::max` and `min`,
                    // which drop a NaN, would give, at several
                    // instructions each).
                    in_plane |= tp.is_nan();
                    let from = if tp > lo { tp } else { lo };
                    stack[sp].write((second as u32, from, hi));
                    sp += 1;
                    node = first;
                    hi = if tp < hi { tp } else { hi };
                }
                continue;
            }
            let count = (n.a >> 2) as usize;
            if count > 0 {
                let off = n.b as usize;
                debug_assert!(off + count <= self.items.len());
                // SAFETY: leaves point inside the item list they were built with.
                let items = unsafe { self.items.get_unchecked(off..off + count) };
                limit = leaf(items);
                if limit <= hi && (!in_plane || limit == f64::NEG_INFINITY) {
                    return;
                }
            }
            loop {
                if sp == 0 {
                    return;
                }
                sp -= 1;
                // SAFETY: slots below `sp` were written by a push.
                let (nn, l, h) = unsafe { stack[sp].assume_init() };
                if l > limit {
                    if in_plane {
                        continue;
                    }
                    return;
                }
                node = nn as usize;
                lo = l;
                hi = h;
                break;
            }
        }
    }
}

/// See the walk: relative slack on a split plane's crossing.
const SLACK: f64 = 1e-9;

impl Builder<'_> {
    fn leaf(&mut self, items: &[Item], depth: usize) {
        self.nodes.push(Node::leaf(self.items.len(), items.len()));
        self.items.extend(items.iter().map(|it| it.id));
        let s = &mut self.stats;
        s.leaves += 1;
        s.empty_leaves += items.is_empty() as usize;
        s.references += items.len();
        s.max_leaf = s.max_leaf.max(items.len());
        s.max_depth = s.max_depth.max(depth);
    }

    fn node(&mut self, bounds: Aabb, items: Vec<Item>, depth: usize, bad_refines: u32) {
        let n = items.len();
        if n <= 1 || depth >= self.max_depth {
            return self.leaf(&items, depth);
        }
        let BuildParams { item_cost, .. } = self.params;
        let leaf_cost = item_cost * n as f64;
        let area = bounds.area();
        if area.is_nan() || area <= 0.0 {
            return self.leaf(&items, depth);
        }
        let best = if n <= EXACT_BELOW {
            self.exact_split(&bounds, &items)
        } else {
            self.binned_split(&bounds, &items)
        };
        let Some((cost, axis, split)) = best else {
            return self.leaf(&items, depth);
        };
        let mut bad = bad_refines;
        if cost > leaf_cost {
            bad += 1;
        }
        if (cost > 4.0 * leaf_cost && n < 16) || bad >= 3 {
            return self.leaf(&items, depth);
        }
        let mut below_box = bounds;
        below_box.max[axis] = split;
        let mut above_box = bounds;
        above_box.min[axis] = split;
        // Counted first so that the lists are allocated at their size: they
        // hold boxes, and the build's peak memory is the lists along the
        // path being built.
        let sides = |it: &Item| {
            let (lo, hi) = (it.b[0][axis] as f64, it.b[1][axis] as f64);
            (lo < split, hi > split)
        };
        let (mut nb, mut na) = (0, 0);
        for it in &items {
            let (b, a) = sides(it);
            // A box flat in the plane itself goes to both sides.
            nb += (b || !a) as usize;
            na += (a || !b) as usize;
        }
        let mut below_items = Vec::with_capacity(nb);
        let mut above_items = Vec::with_capacity(na);
        for it in items {
            match sides(&it) {
                (true, true) => {
                    let (mut b, mut a) = (it, it);
                    // Exact: the plane is an `f32`.
                    b.b[1][axis] = split as f32;
                    a.b[0][axis] = split as f32;
                    let [cb, ca] = match self.clip {
                        Some(clip) => clip(it.id, &bounds, axis, split).map(|c| c.map(Some)),
                        None => [Some(None), Some(None)],
                    };
                    if let Some(c) = cb {
                        narrow(&mut b, c);
                        below_items.push(b);
                    }
                    if let Some(c) = ca {
                        narrow(&mut a, c);
                        above_items.push(a);
                    }
                }
                (true, false) => below_items.push(it),
                (false, true) => above_items.push(it),
                (false, false) => {
                    below_items.push(it);
                    above_items.push(it);
                }
            }
        }
        let at = self.nodes.len();
        self.nodes.push(Node { a: 0, b: 0 });
        if n >= PARALLEL_ABOVE {
            // Both halves at once on rayon's pool, each into its own
            // arrays, then appended with their indices moved.
            let (mut lo, mut hi) = (self.fork(below_items.len()), self.fork(above_items.len()));
            rayon::join(
                || lo.node(below_box, below_items, depth + 1, bad),
                || hi.node(above_box, above_items, depth + 1, bad),
            );
            self.append(lo);
            self.set_interior(at, axis, split);
            self.append(hi);
        } else {
            self.node(below_box, below_items, depth + 1, bad);
            self.set_interior(at, axis, split);
            self.node(above_box, above_items, depth + 1, bad);
        }
    }

    fn set_interior(&mut self, at: usize, axis: usize, split: f64) {
        let above = self.nodes.len() as u32;
        self.nodes[at] = Node {
            a: (above << 2) | axis as u32,
            b: (split as f32).to_bits(),
        };
    }

    /// A builder for a subtree over `n` items, sized as the root's.
    fn fork(&self, n: usize) -> Self {
        Builder {
            clip: self.clip,
            nodes: Vec::with_capacity(3 * n + 1),
            items: Vec::with_capacity(4 * n),
            stats: TreeStats::default(),
            max_depth: self.max_depth,
            params: self.params,
        }
    }

    /// Appends a subtree built by a fork, moving its node and item indices.
    fn append(&mut self, sub: Builder) {
        let (dn, di) = (self.nodes.len() as u32, self.items.len() as u32);
        self.nodes.extend(sub.nodes.iter().map(|n| {
            if n.is_leaf() {
                Node {
                    a: n.a,
                    b: n.b + di,
                }
            } else {
                Node {
                    a: (((n.a >> 2) + dn) << 2) | (n.a & 3),
                    b: n.b,
                }
            }
        }));
        self.items.extend_from_slice(&sub.items);
        let (s, o) = (&mut self.stats, &sub.stats);
        s.leaves += o.leaves;
        s.empty_leaves += o.empty_leaves;
        s.references += o.references;
        s.max_leaf = s.max_leaf.max(o.max_leaf);
        s.max_depth = s.max_depth.max(o.max_depth);
    }

    /// SAH cost of splitting the node at `split` on `axis`.
    #[inline]
    fn cost(&self, f: &Frame, axis: usize, split: f64, below: usize, above: usize) -> f64 {
        let area_b = f.cap[axis] + (split - f.min[axis]) * f.ring[axis];
        let area_a = f.cap[axis] + (f.max[axis] - split) * f.ring[axis];
        let bonus = if below == 0 || above == 0 {
            self.params.empty_bonus
        } else {
            0.0
        };
        TRAVERSAL_COST
            + self.params.item_cost
                * (1.0 - bonus)
                * (area_b * below as f64 + area_a * above as f64)
                * f.inv_half_area
    }

    /// The best plane among `BINS - 1` evenly spaced ones per axis, counting
    /// items by the bins their (clipped) boxes start and end in.
    fn binned_split(&self, bounds: &Aabb, items: &[Item]) -> Option<(f64, usize, f64)> {
        let n = items.len();
        let f = Frame::new(bounds);
        let ext = bounds.extent().to_array();
        let mut best: Option<(usize, f64)> = None;
        let mut best_sah = f64::INFINITY;
        let empty_scale = 1.0 - self.params.empty_bonus;
        // One pass over the items for all three axes.
        let mut lo_count = [[0u32; BINS]; 3];
        let mut hi_count = [[0u32; BINS]; 3];
        let bmin = bounds.min.to_array();
        let scale = ext.map(|e| BINS as f64 / e);
        // `max` then `min` clamp to the bins and turn NaN (a flat axis)
        // into 0, so the unchecked cast below always gets a bin number;
        // a checked `as usize` costs a dozen instructions per call here.
        let bin = |x: f64| -> usize {
            let c = x.max(0.0).min((BINS - 1) as f64);
            // SAFETY: `c` is finite and in 0..BINS.
            unsafe { c.to_int_unchecked::<u32>() as usize }
        };
        for it in items {
            let [lo, hi] = it.b.map(|c| c.map(f64::from));
            for axis in 0..3 {
                lo_count[axis][bin((lo[axis] - bmin[axis]) * scale[axis])] += 1;
                hi_count[axis][bin((hi[axis] - bmin[axis]) * scale[axis])] += 1;
            }
        }
        for axis in 0..3 {
            let w = ext[axis];
            if w.is_nan() || w <= 0.0 {
                continue;
            }
            // `cost` without its constant terms, so that the sweep (a tenth
            // of the whole build) is a few multiplications per plane: the
            // counts first, then the costs without a branch (vectorised),
            // then the first cheapest plane.
            let (cap, ring, lo, hi) = (f.cap[axis], f.ring[axis], f.min[axis], f.max[axis]);
            let (mut below, mut above) = ([0f64; BINS - 1], [0f64; BINS - 1]);
            let (mut nb, mut na) = (0u32, n as u32);
            for k in 0..BINS - 1 {
                nb += lo_count[axis][k];
                na -= hi_count[axis][k];
                below[k] = nb as f64;
                above[k] = na as f64;
            }
            let plane = |k: usize| bmin[axis] + w * (k + 1) as f64 * (1.0 / BINS as f64);
            let mut sah = [0f64; BINS - 1];
            for k in 0..BINS - 1 {
                let split = plane(k);
                let area_b = cap + (split - lo) * ring;
                let area_a = cap + (hi - split) * ring;
                let s = area_b * below[k] + area_a * above[k];
                let empty = below[k] == 0.0 || above[k] == 0.0;
                sah[k] = if empty { s * empty_scale } else { s };
            }
            for (k, &s) in sah.iter().enumerate() {
                if s < best_sah {
                    best_sah = s;
                    best = Some((axis, plane(k)));
                }
            }
        }
        let (axis, split) = best?;
        let cost = TRAVERSAL_COST + self.params.item_cost * best_sah * f.inv_half_area;
        let split = split as f32 as f64;
        (split > bounds.min[axis] && split < bounds.max[axis]).then_some((cost, axis, split))
    }

    /// The best plane among the items' own box faces (exact SAH), for small
    /// nodes where that is cheaper than binning and finds tight planes.
    fn exact_split(&self, bounds: &Aabb, items: &[Item]) -> Option<(f64, usize, f64)> {
        let n = items.len();
        let f = Frame::new(bounds);
        let mut best: Option<(f64, usize, f64)> = None;
        let mut mins = [0f64; EXACT_BELOW];
        let mut maxs = [0f64; EXACT_BELOW];
        for axis in 0..3 {
            let (bmin, bmax) = (f.min[axis], f.max[axis]);
            if bmax.is_nan() || bmax <= bmin {
                continue;
            }
            for (k, it) in items.iter().enumerate() {
                let b = &it.b;
                // Already `f32`, as the stored plane will be.
                mins[k] = b[0][axis] as f64;
                maxs[k] = b[1][axis] as f64;
            }
            let (mins, maxs) = (&mut mins[..n], &mut maxs[..n]);
            insertion_sort(mins);
            insertion_sort(maxs);
            // Sweep the candidate planes in order: below = #{min < s},
            // above = #{max > s}.
            let (mut i, mut j) = (0, 0);
            while i < n || j < n {
                let s = if j >= n || (i < n && mins[i] <= maxs[j]) {
                    mins[i]
                } else {
                    maxs[j]
                };
                while i < n && mins[i] < s {
                    i += 1;
                }
                while j < n && maxs[j] <= s {
                    j += 1;
                }
                if s > bmin && s < bmax {
                    let cost = self.cost(&f, axis, s, i, n - j);
                    if best.is_none_or(|(c, _, _)| cost < c) {
                        best = Some((cost, axis, s));
                    }
                }
                // Step past every min equal to s too.
                while i < n && mins[i] <= s {
                    i += 1;
                }
            }
        }
        best
    }
}

/// Narrows a straddling item's box (already cut at the plane) to the box
/// the caller's clipping found for its part on that side, if any.
#[inline]
fn narrow(it: &mut Item, clipped: Option<Aabb>) {
    let Some(c) = clipped else { return };
    let [cmin, cmax] = box6(&c);
    for k in 0..3 {
        // Comparisons rather than `max` and `min`: no NaN reaches here,
        // and their NaN handling doubled the cost of this loop.
        let (lo, hi) = (
            if cmin[k] > it.b[0][k] {
                cmin[k]
            } else {
                it.b[0][k]
            },
            if cmax[k] < it.b[1][k] {
                cmax[k]
            } else {
                it.b[1][k]
            },
        );
        // Both boxes hold all of the item in the cell, so they meet
        // unless the item only touches the cell within rounding: then
        // trust the clipped box.
        it.b[0][k] = if lo <= hi { lo } else { cmin[k] };
        it.b[1][k] = if lo <= hi { hi } else { cmax[k] };
    }
}

/// Sorts a dozen finite numbers: far cheaper than the general sort for
/// the tens of thousands of tiny nodes at the bottom of a tree.
#[inline]
fn insertion_sort(v: &mut [f64]) {
    for i in 1..v.len() {
        let x = v[i];
        let mut j = i;
        while j > 0 && v[j - 1] > x {
            v[j] = v[j - 1];
            j -= 1;
        }
        v[j] = x;
    }
}

#[cfg(test)]
#[path = "kdtree_tests.rs"]
mod tests;
