//! A kd-tree over anything with a bounding box: the triangles of a mesh or
//! the objects of a scene. The tree only knows item numbers and boxes; the
//! caller's closure intersects an item.
//!
//! Build: binned surface area heuristic (SAH) on the items' boxes clipped to
//! the node, with a bonus for cutting off empty space (pbrt's kd-tree
//! rules: a split must beat the cost of a leaf, a few bad refinements are
//! tolerated, depth is capped at 8 + 1.3·log2 N). Split positions are
//! rounded to `f32` before the items are partitioned, so the 8-byte nodes
//! store exactly the plane that was used.
//!
//! Traversal: front to back with a small stack; a segment whose start lies
//! beyond the nearest hit found so far ends the walk. A ray parallel to a
//! split plane (zero direction component) goes only to the side its origin
//! is on, or to both when it lies in the plane.

use crate::geometry::{Aabb, Ray};

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
const ITEM_COST: f64 = 2.0;
/// Fraction of the cost saved when one side of a split is empty.
const EMPTY_BONUS: f64 = 0.5;
const BINS: usize = 32;
/// The traversal stack holds at most one entry per level.
const MAX_DEPTH: usize = 60;
const STACK: usize = MAX_DEPTH + 4;

struct Builder<'a> {
    boxes: &'a [Aabb],
    nodes: Vec<Node>,
    items: Vec<u32>,
    stats: TreeStats,
    max_depth: usize,
}

impl KdTree {
    /// Builds the tree over `boxes[i]` for item `i`. Boxes must be finite
    /// (unbounded things stay outside the tree); empty boxes are left out.
    pub fn build(boxes: &[Aabb]) -> KdTree {
        let start = std::time::Instant::now();
        let mut bounds = Aabb::EMPTY;
        let mut all = Vec::with_capacity(boxes.len());
        for (i, b) in boxes.iter().enumerate() {
            if !b.is_empty() && b.is_finite() {
                bounds = bounds.union(b);
                all.push(i as u32);
            }
        }
        let n = all.len().max(1) as f64;
        let mut b = Builder {
            boxes,
            nodes: Vec::with_capacity(2 * all.len() + 1),
            items: Vec::with_capacity(2 * all.len()),
            stats: TreeStats {
                items: all.len(),
                ..TreeStats::default()
            },
            max_depth: ((8.0 + 1.3 * n.log2()).round() as usize).min(MAX_DEPTH),
        };
        b.node(bounds, all, 0, 0);
        let mut stats = b.stats;
        stats.nodes = b.nodes.len();
        stats.build_seconds = start.elapsed().as_secs_f64();
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
        self.walk(ray, t_min, t_max, |items, seg_min| {
            if seg_min > best {
                return true;
            }
            for &i in items {
                if let Some(t) = test(i, best) {
                    best = t;
                    found = true;
                }
            }
            false
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
        self.walk(ray, t_min, t_max, |items, _| {
            hit = items.iter().any(|&i| test(i));
            hit
        });
        hit
    }

    /// Calls `visit` on every item in every leaf the whole line crosses
    /// (an item may come more than once).
    pub fn along_line(&self, ray: &Ray, mut visit: impl FnMut(u32)) {
        self.walk(ray, f64::NEG_INFINITY, f64::INFINITY, |items, _| {
            items.iter().for_each(|&i| visit(i));
            false
        });
    }

    /// Visits the leaves along the segment front to back; `leaf(items,
    /// segment_start)` returns true to stop.
    #[inline]
    fn walk(&self, ray: &Ray, t_min: f64, t_max: f64, mut leaf: impl FnMut(&[u32], f64) -> bool) {
        if self.items.is_empty() {
            return;
        }
        let Some((mut lo, mut hi)) = self.bounds.clip(ray, t_min, t_max) else {
            return;
        };
        let inv = ray.dir.recip();
        let mut stack = [(0u32, 0f64, 0f64); STACK];
        let mut sp = 0;
        let mut node = 0usize;
        loop {
            let n = self.nodes[node];
            if !n.is_leaf() {
                let axis = (n.a & 3) as usize;
                let split = f32::from_bits(n.b) as f64;
                let (o, d) = (ray.origin[axis], ray.dir[axis]);
                let below = node + 1;
                let above = (n.a >> 2) as usize;
                if d == 0.0 {
                    if o < split {
                        node = below;
                    } else if o > split {
                        node = above;
                    } else {
                        stack[sp] = (above as u32, lo, hi);
                        sp += 1;
                        node = below;
                    }
                    continue;
                }
                let tp = (split - o) * inv[axis];
                let (first, second) = if d > 0.0 {
                    (below, above)
                } else {
                    (above, below)
                };
                if tp > hi {
                    node = first;
                } else if tp < lo {
                    node = second;
                } else {
                    stack[sp] = (second as u32, tp, hi);
                    sp += 1;
                    node = first;
                    hi = tp;
                }
                continue;
            }
            let count = (n.a >> 2) as usize;
            if count > 0 {
                let off = n.b as usize;
                if leaf(&self.items[off..off + count], lo) {
                    return;
                }
            }
            if sp == 0 {
                return;
            }
            sp -= 1;
            let (nn, l, h) = stack[sp];
            node = nn as usize;
            lo = l;
            hi = h;
        }
    }
}

impl Builder<'_> {
    fn leaf(&mut self, items: &[u32], depth: usize) {
        self.nodes.push(Node::leaf(self.items.len(), items.len()));
        self.items.extend_from_slice(items);
        let s = &mut self.stats;
        s.leaves += 1;
        s.empty_leaves += items.is_empty() as usize;
        s.references += items.len();
        s.max_leaf = s.max_leaf.max(items.len());
        s.max_depth = s.max_depth.max(depth);
    }

    fn node(&mut self, bounds: Aabb, items: Vec<u32>, depth: usize, bad_refines: u32) {
        let n = items.len();
        if n <= 1 || depth >= self.max_depth {
            return self.leaf(&items, depth);
        }
        let leaf_cost = ITEM_COST * n as f64;
        let area = bounds.area();
        let ext = bounds.extent();
        if area.is_nan() || area <= 0.0 {
            return self.leaf(&items, depth);
        }
        // (cost, axis, split)
        let mut best: Option<(f64, usize, f64)> = None;
        let mut lo_count = [0u32; BINS];
        let mut hi_count = [0u32; BINS];
        for axis in 0..3 {
            let (bmin, w) = (bounds.min[axis], ext[axis]);
            if w.is_nan() || w <= 0.0 {
                continue;
            }
            let scale = BINS as f64 / w;
            lo_count.fill(0);
            hi_count.fill(0);
            for &i in &items {
                let b = &self.boxes[i as usize];
                let lo = ((b.min[axis].max(bmin) - bmin) * scale) as usize;
                let hi = ((b.max[axis].min(bmin + w) - bmin) * scale) as usize;
                lo_count[lo.min(BINS - 1)] += 1;
                hi_count[hi.min(BINS - 1)] += 1;
            }
            // Plane k lies between bins k-1 and k: items whose min bin is
            // below k go below, items whose max bin is k or above go above.
            let mut below = 0u32;
            let mut above = n as u32;
            let (o1, o2) = ((axis + 1) % 3, (axis + 2) % 3);
            let cap = ext[o1] * ext[o2];
            let ring = ext[o1] + ext[o2];
            for k in 1..BINS {
                below += lo_count[k - 1];
                above -= hi_count[k - 1];
                let split = (bmin + w * k as f64 / BINS as f64) as f32 as f64;
                if !(split > bmin && split < bmin + w) {
                    continue;
                }
                let (db, da) = (split - bmin, bmin + w - split);
                let area_b = 2.0 * (cap + db * ring);
                let area_a = 2.0 * (cap + da * ring);
                let bonus = if below == 0 || above == 0 {
                    EMPTY_BONUS
                } else {
                    0.0
                };
                let cost = TRAVERSAL_COST
                    + ITEM_COST * (1.0 - bonus) * (area_b * below as f64 + area_a * above as f64)
                        / area;
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, axis, split));
                }
            }
        }
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
        let mut below_items = Vec::with_capacity(n);
        let mut above_items = Vec::with_capacity(n);
        for &i in &items {
            let b = &self.boxes[i as usize];
            let (lo, hi) = (b.min[axis], b.max[axis]);
            let (goes_below, goes_above) = (lo < split, hi > split);
            if goes_below || !goes_above {
                below_items.push(i);
            }
            if goes_above || !goes_below {
                above_items.push(i);
            }
        }
        drop(items);
        let mut below_box = bounds;
        below_box.max[axis] = split;
        let mut above_box = bounds;
        above_box.min[axis] = split;
        let at = self.nodes.len();
        self.nodes.push(Node { a: 0, b: 0 });
        self.node(below_box, below_items, depth + 1, bad);
        let above = self.nodes.len() as u32;
        self.nodes[at] = Node {
            a: (above << 2) | axis as u32,
            b: (split as f32).to_bits(),
        };
        self.node(above_box, above_items, depth + 1, bad);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DVec3;

    fn unit_boxes(centres: &[DVec3]) -> Vec<Aabb> {
        centres
            .iter()
            .map(|&c| Aabb::new(c - DVec3::splat(0.5), c + DVec3::splat(0.5)))
            .collect()
    }

    #[test]
    fn empty_tree_finds_nothing() {
        let t = KdTree::build(&[]);
        let r = Ray::new(DVec3::ZERO, DVec3::X);
        assert!(
            t.nearest(&r, 0.0, f64::INFINITY, |_, _| Some(1.0))
                .is_none()
        );
        assert!(!t.any(&r, 0.0, f64::INFINITY, |_| true));
    }

    #[test]
    fn splits_a_row_of_boxes_and_walks_front_to_back() {
        let centres: Vec<DVec3> = (0..100)
            .map(|i| DVec3::new(i as f64 * 3.0, 0.0, 0.0))
            .collect();
        let boxes = unit_boxes(&centres);
        let t = KdTree::build(&boxes);
        assert!(t.stats.leaves > 10, "{:?}", t.stats);
        // Along +x the first box met is item 0; along -x from the far end, item 99.
        let mut order = Vec::new();
        t.along_line(&Ray::new(DVec3::new(-5.0, 0.0, 0.0), DVec3::X), |i| {
            order.push(i)
        });
        order.dedup();
        assert_eq!(order.first(), Some(&0));
        let mut seen = Vec::new();
        let hit = t.nearest(
            &Ray::new(DVec3::new(400.0, 0.0, 0.0), -DVec3::X),
            0.0,
            f64::INFINITY,
            |i, best| {
                seen.push(i);
                let tt = 400.0 - (centres[i as usize].x + 0.5);
                (tt < best).then_some(tt)
            },
        );
        assert_eq!(hit, Some(400.0 - 297.5));
        assert!(
            seen.len() < 10,
            "early exit failed: {} items tested",
            seen.len()
        );
    }

    #[test]
    fn rays_in_a_split_plane_see_both_sides() {
        // Two boxes meeting at x = 0; a ray lying in that plane along y.
        let boxes = vec![
            Aabb::new(DVec3::new(-1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 1.0)),
            Aabb::new(DVec3::new(0.0, 5.0, 0.0), DVec3::new(1.0, 6.0, 1.0)),
        ];
        let t = KdTree::build(&boxes);
        let mut seen = Vec::new();
        t.along_line(&Ray::new(DVec3::new(0.0, -3.0, 0.5), DVec3::Y), |i| {
            seen.push(i)
        });
        seen.sort();
        seen.dedup();
        assert_eq!(seen, vec![0, 1]);
    }
}
