//! A wide bounding volume hierarchy (BVH8): eight children per node, their
//! boxes stored structure-of-arrays in `f32` and tested together (AVX2,
//! or one lane at a time where the CPU lacks it), walked front to back
//! with an explicit stack. It indexes a mesh's triangles ([`TriangleBvh`],
//! whose leaves hold the triangles themselves, tested four at a time) or
//! a scene's objects (through [`Bvh::walk`]); `render { accel bvh }` and
//! `--accel bvh` pick it over the kd-tree.
//!
//! Build ([`build`]): binned SAH into a binary tree, collapsed to eight
//! wide. Each item is in exactly one leaf (no references to repeat, no
//! mailbox). The box test ([`node`]) is conservative, so the `f64` item
//! tests decide every hit exactly as under the kd-tree.

mod build;
mod node;
#[cfg(test)]
mod node_tests;
#[cfg(test)]
pub(crate) mod tests;
pub mod triangles;

pub use build::BvhParams;

use crate::geometry::{Aabb, Ray};
use crate::shapes::ShearedRay;
use build::Binary;
use node::{BoxRay, LEAF, Node8, round_down, round_up};
use std::mem::MaybeUninit;
use triangles::{Block, LaneRay};

/// How the boxes and triangles are tested.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Simd {
    /// AVX2 and FMA (with BMI1 and POPCNT, which every AVX2 CPU has, for
    /// the child masks): eight boxes or four triangles per instruction.
    Avx2,
    /// One lane at a time, the same layout and results.
    Scalar,
}

impl Simd {
    /// The best this CPU runs, unless the environment variable
    /// `RAYTRACE_SIMD=scalar` asks for the scalar path (for comparisons).
    pub fn detect() -> Simd {
        static CHOSEN: std::sync::OnceLock<Simd> = std::sync::OnceLock::new();
        *CHOSEN.get_or_init(|| {
            let asked = std::env::var("RAYTRACE_SIMD").ok();
            Self::choose(asked.as_deref(), Self::avx2_available())
        })
    }

    /// The path for `RAYTRACE_SIMD`'s value (`asked`) on a CPU that has
    /// AVX2, FMA, BMI1 and POPCNT (`avx2`) or not: AVX2 where there is one, unless
    /// asked for `scalar`.
    fn choose(asked: Option<&str>, avx2: bool) -> Simd {
        let forced = asked == Some("scalar");
        if !forced && avx2 {
            Simd::Avx2
        } else {
            Simd::Scalar
        }
    }

    pub fn avx2_available() -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            is_x86_feature_detected!("avx2")
                && is_x86_feature_detected!("fma")
                && is_x86_feature_detected!("bmi1")
                && is_x86_feature_detected!("popcnt")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    }
}

/// Shape, size and build time of a wide BVH, for `--stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhStats {
    pub items: usize,
    /// Wide nodes.
    pub nodes: usize,
    pub leaves: usize,
    /// Leaf slots, padding included (a mesh pads leaves to whole blocks).
    pub slots: usize,
    /// Depth in wide nodes.
    pub depth: usize,
    pub bytes: usize,
    pub build_seconds: f64,
}

/// The wide tree over item boxes: nodes and the items in leaf order.
#[derive(Debug)]
pub struct Bvh {
    nodes: Vec<Node8>,
    /// Item numbers in leaf order; `u32::MAX` pads a leaf to whole groups.
    items: Vec<u32>,
    bounds: Aabb,
    simd: Simd,
    pub stats: BvhStats,
}

/// A stack entry: a child reference, its leaf size, where the ray enters it.
#[derive(Clone, Copy)]
struct Entry {
    child: u32,
    count: u32,
    near: f32,
}

/// Entries pushed at most: seven per wide level (the eighth is taken at
/// once) on a path of at most `MAX_BINARY_DEPTH` levels, and eight more.
const STACK: usize = 7 * build::MAX_BINARY_DEPTH + 8;

/// The traversal stack, left uninitialised: zeroing 6 KiB per ray would
/// cost more than the walk through a small mesh.
struct Stack {
    buf: [MaybeUninit<Entry>; STACK],
    len: usize,
}

impl Stack {
    #[inline(always)]
    fn new() -> Stack {
        Stack {
            buf: [const { MaybeUninit::uninit() }; STACK],
            len: 0,
        }
    }

    #[inline(always)]
    fn push(&mut self, e: Entry) {
        // The bound holds by construction (see `STACK`); indexing checks it.
        self.buf[self.len] = MaybeUninit::new(e);
        self.len += 1;
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<Entry> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: every slot below `len` was written by `push`.
        Some(unsafe { self.buf[self.len].assume_init() })
    }
}

impl Bvh {
    /// Builds over `boxes[i]` for item `i` (empty boxes are left out);
    /// leaves are padded to multiples of `params.group` slots.
    pub fn build(boxes: &[Aabb], params: BvhParams) -> Bvh {
        let start = std::time::Instant::now();
        let bounds = boxes
            .iter()
            .filter(|b| !b.is_empty())
            .fold(Aabb::EMPTY, |a, b| a.union(b));
        let mut bvh = Bvh {
            nodes: Vec::new(),
            items: Vec::new(),
            bounds,
            simd: Simd::detect(),
            stats: BvhStats::default(),
        };
        if let Some(root) = build::binary(boxes, params) {
            let depth = bvh.collapse(&root, params.group);
            bvh.stats.depth = depth;
        }
        bvh.nodes.shrink_to_fit();
        bvh.items.shrink_to_fit();
        bvh.stats.items = boxes.iter().filter(|b| !b.is_empty()).count();
        bvh.stats.nodes = bvh.nodes.len();
        bvh.stats.slots = bvh.items.len();
        bvh.stats.bytes = bvh.memory();
        bvh.stats.build_seconds = start.elapsed().as_secs_f64();
        bvh
    }

    /// Makes the wide node for binary node `b` (and those below it);
    /// returns the depth below it, in wide nodes.
    fn collapse(&mut self, b: &Binary, group: usize) -> usize {
        let at = self.nodes.len();
        self.nodes.push(Node8::empty());
        // Open the largest inner child until there are eight.
        let mut kids: Vec<&Binary> = match b {
            Binary::Leaf { .. } => vec![b],
            Binary::Inner { children, .. } => vec![&children[0], &children[1]],
        };
        while kids.len() < 8 {
            let open = kids
                .iter()
                .enumerate()
                .filter(|(_, k)| matches!(k, Binary::Inner { .. }))
                .max_by(|a, b| a.1.bounds().area().total_cmp(&b.1.bounds().area()))
                .map(|(i, _)| i);
            let Some(i) = open else { break };
            let Binary::Inner { children, .. } = kids[i] else {
                unreachable!()
            };
            kids[i] = &children[0];
            kids.insert(i + 1, &children[1]);
        }
        let mut depth = 0;
        for (k, kid) in kids.iter().enumerate() {
            let bb = kid.bounds();
            for a in 0..3 {
                self.nodes[at].lo[a][k] = round_down(bb.min[a]);
                self.nodes[at].hi[a][k] = round_up(bb.max[a]);
            }
            match kid {
                Binary::Leaf { items, .. } => {
                    let first = self.items.len();
                    self.items.extend_from_slice(items);
                    while !(self.items.len() - first).is_multiple_of(group) {
                        self.items.push(u32::MAX);
                    }
                    self.nodes[at].child[k] = LEAF | first as u32;
                    self.nodes[at].count[k] = (self.items.len() - first) as u32;
                    self.stats.leaves += 1;
                }
                Binary::Inner { .. } => {
                    let index = self.nodes.len() as u32;
                    depth = depth.max(self.collapse(kid, group));
                    self.nodes[at].child[k] = index;
                }
            }
        }
        depth + 1
    }

    /// The box around every item.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Calls `visit` on every item of every leaf whose box may meet `b`
    /// (an item may come more than once) until `visit` returns false;
    /// returns false then. Child boxes are stored rounded outwards, so no
    /// item whose box meets `b` is missed. The shadow shafts of area
    /// lights ask it (`World::blockers`).
    pub fn overlapping(&self, b: &Aabb, mut visit: impl FnMut(u32) -> bool) -> bool {
        if self.nodes.is_empty() {
            return true;
        }
        let (lo, hi) = (b.min.to_array(), b.max.to_array());
        let mut stack = [0u32; STACK];
        stack[0] = 0;
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let n = &self.nodes[stack[sp] as usize];
            for k in 0..8 {
                let meets =
                    (0..3).all(|a| n.lo[a][k] as f64 <= hi[a] && n.hi[a][k] as f64 >= lo[a]);
                if !meets {
                    continue;
                }
                let child = n.child[k];
                if child & LEAF == 0 {
                    stack[sp] = child;
                    sp += 1;
                    continue;
                }
                let first = (child & !LEAF) as usize;
                for &i in &self.items[first..first + n.count[k] as usize] {
                    if i != u32::MAX && !visit(i) {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// Bytes held by the nodes and the item list.
    pub fn memory(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<Node8>()
            + self.items.capacity() * std::mem::size_of::<u32>()
    }

    /// Item numbers in leaf order (`u32::MAX` for padding).
    pub fn items(&self) -> &[u32] {
        &self.items
    }

    /// Forces the scalar or the AVX2 path (tests compare them; AVX2 is
    /// refused, staying scalar, where the CPU lacks it).
    pub fn set_simd(&mut self, simd: Simd) {
        self.simd = if simd == Simd::Avx2 && !Simd::avx2_available() {
            Simd::Scalar
        } else {
            simd
        };
    }

    pub fn simd(&self) -> Simd {
        self.simd
    }

    /// Visits the leaves whose boxes the ray crosses within
    /// `[t_min, t_max]`, nearest box first: `leaf(first, count, best)`
    /// tests items `items()[first..first + count]` and returns the new
    /// limit (the nearest hit so far, or `best`); boxes entered beyond the
    /// limit are skipped. A limit of −∞ ends the walk (any-hit).
    #[inline]
    pub fn walk(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut leaf: impl FnMut(usize, usize, f64) -> f64,
    ) {
        let (origin, dir) = (ray.origin.to_array(), ray.dir.to_array());
        match self.simd {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `simd` is Avx2 only where the CPU has AVX2, FMA, BMI1 and
            // POPCNT.
            Simd::Avx2 => unsafe { self.walk_avx2(origin, dir, t_min, t_max, &mut leaf) },
            _ => self.walk_in::<false>(&BoxRay::new(origin, dir), t_min, t_max, &mut leaf),
        }
    }

    /// # Safety
    /// The CPU must support AVX2, FMA, BMI1 and POPCNT.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,popcnt")]
    unsafe fn walk_avx2(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        t_min: f64,
        t_max: f64,
        leaf: &mut impl FnMut(usize, usize, f64) -> f64,
    ) {
        // SAFETY: AVX2 implies AVX.
        let r = unsafe { node::box_ray_avx(origin, dir) };
        self.walk_in::<true>(&r, t_min, t_max, leaf)
    }

    #[inline(always)]
    fn walk_in<const AVX: bool>(
        &self,
        r: &BoxRay,
        t_min: f64,
        mut t_max: f64,
        leaf: &mut impl FnMut(usize, usize, f64) -> f64,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let lo = round_down(t_min);
        let mut hi = round_up(t_max);
        let mut stack = Stack::new();
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            let (mask, near) = if AVX {
                #[cfg(target_arch = "x86_64")]
                // SAFETY: AVX is true only inside `walk_avx2`.
                unsafe {
                    node::hits_avx2(n, r, lo, hi)
                }
                #[cfg(not(target_arch = "x86_64"))]
                node::hits_scalar(n, r, lo, hi)
            } else {
                node::hits_scalar(n, r, lo, hi)
            };
            push_sorted(&mut stack, n, mask, &near);
            // Pop until an inner node to open.
            loop {
                let Some(e) = stack.pop() else { return };
                if e.near > hi {
                    continue;
                }
                if e.child & LEAF == 0 {
                    node = e.child as usize;
                    break;
                }
                let best = leaf((e.child & !LEAF) as usize, e.count as usize, t_max);
                if best < t_max {
                    if best == f64::NEG_INFINITY {
                        return;
                    }
                    t_max = best;
                    hi = round_up(best);
                }
            }
        }
    }
}

/// Pushes the hit children far to near (so the nearest is popped first).
#[inline(always)]
fn push_sorted(stack: &mut Stack, n: &Node8, mask: u32, near: &[f32; 8]) {
    let hits = mask.count_ones();
    if hits == 0 {
        return;
    }
    let push = |stack: &mut Stack, k: usize| {
        stack.push(Entry {
            child: n.child[k],
            count: n.count[k],
            near: near[k],
        })
    };
    if hits == 1 {
        push(stack, mask.trailing_zeros() as usize);
        return;
    }
    if hits == 2 {
        // The sort below for two, without its loops: the nearer pushed
        // last; on a tie the higher slot last, as the sort leaves them.
        let a = mask.trailing_zeros() as usize;
        let b = (mask & (mask - 1)).trailing_zeros() as usize;
        let (far, near_one) = if near[a] < near[b] { (b, a) } else { (a, b) };
        push(stack, far);
        push(stack, near_one);
        return;
    }
    // Insertion sort, far first, of at most eight.
    let mut order = [0u8; 8];
    let mut len = 0;
    let mut m = mask;
    while m != 0 {
        let k = m.trailing_zeros() as usize;
        m &= m - 1;
        let mut j = len;
        while j > 0 && near[order[j - 1] as usize] < near[k] {
            order[j] = order[j - 1];
            j -= 1;
        }
        order[j] = k as u8;
        len += 1;
    }
    for &k in &order[..len] {
        push(stack, k as usize);
    }
}

/// The SAH costs for a mesh's triangles: a block of four triangles costs
/// about as much as a wide node's box test (measured on the bunny).
pub const TRIANGLES: BvhParams = BvhParams {
    group_cost: 1.0,
    group: 4,
    max_leaf: 8,
};

/// A mesh's triangles in a wide BVH, stored in its leaves four to a block.
#[derive(Debug)]
pub struct TriangleBvh {
    bvh: Bvh,
    blocks: Vec<Block>,
}

impl TriangleBvh {
    /// Builds over triangles given by their corners.
    pub fn build(corners: &[[crate::geometry::DVec3; 3]]) -> TriangleBvh {
        let start = std::time::Instant::now();
        let boxes: Vec<Aabb> = corners
            .iter()
            .map(|t| Aabb::new(t[0], t[1]).grow(t[2]))
            .collect();
        let mut bvh = Bvh::build(&boxes, TRIANGLES);
        drop(boxes);
        let blocks: Vec<Block> = bvh
            .items
            .chunks(4)
            .map(|ids| {
                Block::new(std::array::from_fn(|lane| {
                    ids.get(lane)
                        .filter(|&&i| i != u32::MAX)
                        .map(|&i| corners[i as usize])
                }))
            })
            .collect();
        bvh.stats.bytes += blocks.capacity() * std::mem::size_of::<Block>();
        bvh.stats.build_seconds = start.elapsed().as_secs_f64();
        TriangleBvh { bvh, blocks }
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    pub fn stats(&self) -> &BvhStats {
        &self.bvh.stats
    }

    /// Bytes held, the triangle blocks included.
    pub fn memory(&self) -> usize {
        self.bvh.memory() + self.blocks.capacity() * std::mem::size_of::<Block>()
    }

    pub fn set_simd(&mut self, simd: Simd) {
        self.bvh.set_simd(simd);
    }

    /// Runs the block test on the blocks of slots `first..first + count`,
    /// reporting each lane hit (`(slot, t)`, slots in order) to `found`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn leaf_hits(
        &self,
        r: &LaneRay,
        first: usize,
        count: usize,
        t_min: f64,
        t_max: f64,
        avx: bool,
        mut found: impl FnMut(usize, f64) -> bool,
    ) {
        for b in first / 4..(first + count) / 4 {
            let block = &self.blocks[b];
            let (mut mask, ts) = if avx {
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `avx` is true only inside `walk_avx2`'s callers
                // on a CPU with AVX2 (see `Bvh::set_simd`).
                unsafe {
                    triangles::hits_avx2(block, r, t_min, t_max)
                }
                #[cfg(not(target_arch = "x86_64"))]
                triangles::hits_scalar(block, r, t_min, t_max)
            } else {
                triangles::hits_scalar(block, r, t_min, t_max)
            };
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if found(4 * b + lane, ts[lane]) {
                    return;
                }
            }
        }
    }

    /// The nearest triangle the ray crosses at `t_min < t < t_max`:
    /// `(t, triangle)`, t exactly as [`ShearedRay::triangle`] gives it. Of
    /// several at the same t, the first met.
    pub(crate) fn nearest(
        &self,
        ray: &Ray,
        sheared: &ShearedRay,
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, u32)> {
        let r = LaneRay::new(*sheared);
        let avx = self.bvh.simd == Simd::Avx2;
        let mut best: Option<(f64, u32)> = None;
        self.bvh.walk(ray, t_min, t_max, |first, count, limit| {
            let mut limit = limit;
            self.leaf_hits(&r, first, count, t_min, limit, avx, |slot, t| {
                if t < limit {
                    limit = t;
                    best = Some((t, self.bvh.items[slot]));
                }
                false
            });
            limit
        });
        best
    }

    /// Whether any triangle crosses the ray at `t_min < t < t_max`.
    pub(crate) fn any(&self, ray: &Ray, sheared: &ShearedRay, t_min: f64, t_max: f64) -> bool {
        let r = LaneRay::new(*sheared);
        let avx = self.bvh.simd == Simd::Avx2;
        let mut hit = false;
        self.bvh.walk(ray, t_min, t_max, |first, count, limit| {
            self.leaf_hits(&r, first, count, t_min, t_max, avx, |_, _| {
                hit = true;
                true
            });
            if hit { f64::NEG_INFINITY } else { limit }
        });
        hit
    }

    /// Every triangle the whole line crosses, in no order: `(t, triangle)`.
    pub(crate) fn along_line(
        &self,
        ray: &Ray,
        sheared: &ShearedRay,
        mut visit: impl FnMut(f64, u32),
    ) {
        let r = LaneRay::new(*sheared);
        let avx = self.bvh.simd == Simd::Avx2;
        let (lo, hi) = (f64::NEG_INFINITY, f64::INFINITY);
        self.bvh.walk(ray, lo, hi, |first, count, limit| {
            self.leaf_hits(&r, first, count, lo, hi, avx, |slot, t| {
                visit(t, self.bvh.items[slot]);
                false
            });
            limit
        });
    }
}
