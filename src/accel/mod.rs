//! Stage 3, ACCELERATE: the index the renderer asks for the nearest hit.
//!
//! Bounded objects go into a wide BVH ([`bvh::Bvh`]) or a kd-tree
//! ([`KdTree`]), whichever [`Accel`] names: the same structure indexes the
//! triangles of each mesh. Unbounded ones (planes, some implicit surfaces)
//! are tested one by one beside it.

pub mod beam;
pub mod bvh;
mod kdtree;
mod shaft;

#[cfg(test)]
pub(crate) use kdtree::counters;
pub use kdtree::{BuildParams, Clip, KdTree, TreeStats};
pub use shaft::Shaft;

/// Which structure indexes a mesh's triangles and the scene's objects:
/// `render { accel auto|kdtree|bvh }`, `--accel`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Accel {
    /// The BVH for meshes and the kd-tree for the scene's objects: what
    /// measured fastest on every benchmark (the wide BVH pays on tens of
    /// thousands of triangles; over a few dozen objects of different
    /// kinds, the kd-tree's tighter clipped cells cut 20-30% off dof and
    /// glass; on `many` they tie).
    #[default]
    Auto,
    /// The SAH kd-tree with clipped ("perfect") splits.
    KdTree,
    /// The wide BVH (eight children a node, SIMD box tests).
    Bvh,
}

impl Accel {
    pub const NAMES: [&'static str; 3] = ["auto", "kdtree", "bvh"];

    pub fn from_name(name: &str) -> Option<Accel> {
        match name {
            "auto" => Some(Accel::Auto),
            "kdtree" => Some(Accel::KdTree),
            "bvh" => Some(Accel::Bvh),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Accel::Auto => "auto",
            Accel::KdTree => "kdtree",
            Accel::Bvh => "bvh",
        }
    }
}

use crate::geometry::{Aabb, Ray};
use crate::shapes::{Hit, Roots, Shape};
use std::sync::atomic::{AtomicU64, Ordering};

/// Counts for `--stats`.
#[derive(Clone, Debug, Default)]
pub struct AccelStats {
    pub objects: usize,
    pub unbounded: usize,
    /// Nodes of the scene-level tree.
    pub nodes: usize,
    pub build_seconds: f64,
    /// The scene-level tree in full.
    pub tree: TreeStats,
    /// Every mesh tree built so far in this process (meshes are built while
    /// the scene is, before the world; instances share one tree).
    pub meshes: MeshTreeTotals,
    /// Every mesh BVH built so far in this process.
    pub mesh_bvhs: MeshBvhTotals,
    /// The scene-level BVH, when `accel bvh` chose it.
    pub bvh: Option<bvh::BvhStats>,
    pub memory: AccelMemory,
}

/// Bytes held by the acceleration structures, for `--stats`: each kind
/// of index adds its own field here.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AccelMemory {
    /// The scene-level kd-tree (nodes and item lists).
    pub scene_tree: usize,
    /// The meshes' own kd-trees (instances share one).
    pub mesh_trees: usize,
    /// The scene-level BVH, when `accel bvh` chose it.
    pub scene_bvh: usize,
    /// The meshes' own BVHs.
    pub mesh_bvhs: usize,
}

impl AccelMemory {
    pub fn total(&self) -> usize {
        self.scene_tree + self.mesh_trees + self.scene_bvh + self.mesh_bvhs
    }
}

/// Sums over the kd-trees of the meshes loaded.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshTreeTotals {
    pub trees: u64,
    pub triangles: u64,
    pub nodes: u64,
    pub leaves: u64,
    pub references: u64,
    pub max_depth: u64,
    pub build_seconds: f64,
    pub bytes: u64,
}

static MESH_TREES: [AtomicU64; 8] = [const { AtomicU64::new(0) }; 8];

/// Called by each mesh once its tree is built.
pub(crate) fn record_mesh_tree(s: &TreeStats) {
    let m = &MESH_TREES;
    m[0].fetch_add(1, Ordering::Relaxed);
    m[1].fetch_add(s.items as u64, Ordering::Relaxed);
    m[2].fetch_add(s.nodes as u64, Ordering::Relaxed);
    m[3].fetch_add(s.leaves as u64, Ordering::Relaxed);
    m[4].fetch_add(s.references as u64, Ordering::Relaxed);
    m[5].fetch_max(s.max_depth as u64, Ordering::Relaxed);
    m[6].fetch_add((s.build_seconds * 1e9) as u64, Ordering::Relaxed);
    m[7].fetch_add(s.bytes as u64, Ordering::Relaxed);
}

/// Sums over the wide BVHs of the meshes loaded.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshBvhTotals {
    pub trees: u64,
    pub triangles: u64,
    pub nodes: u64,
    pub leaves: u64,
    pub bytes: u64,
    pub max_depth: u64,
    pub build_seconds: f64,
}

static MESH_BVHS: [AtomicU64; 7] = [const { AtomicU64::new(0) }; 7];

/// Called by each mesh once its BVH is built.
pub(crate) fn record_mesh_bvh(s: &bvh::BvhStats) {
    let m = &MESH_BVHS;
    m[0].fetch_add(1, Ordering::Relaxed);
    m[1].fetch_add(s.items as u64, Ordering::Relaxed);
    m[2].fetch_add(s.nodes as u64, Ordering::Relaxed);
    m[3].fetch_add(s.leaves as u64, Ordering::Relaxed);
    m[4].fetch_add(s.bytes as u64, Ordering::Relaxed);
    m[5].fetch_max(s.depth as u64, Ordering::Relaxed);
    m[6].fetch_add((s.build_seconds * 1e9) as u64, Ordering::Relaxed);
}

fn mesh_bvh_totals() -> MeshBvhTotals {
    let v: Vec<u64> = MESH_BVHS
        .iter()
        .map(|a| a.load(Ordering::Relaxed))
        .collect();
    MeshBvhTotals {
        trees: v[0],
        triangles: v[1],
        nodes: v[2],
        leaves: v[3],
        bytes: v[4],
        max_depth: v[5],
        build_seconds: v[6] as f64 * 1e-9,
    }
}

fn mesh_totals() -> MeshTreeTotals {
    let v: Vec<u64> = MESH_TREES
        .iter()
        .map(|a| a.load(Ordering::Relaxed))
        .collect();
    MeshTreeTotals {
        trees: v[0],
        triangles: v[1],
        nodes: v[2],
        leaves: v[3],
        references: v[4],
        max_depth: v[5],
        build_seconds: v[6] as f64 * 1e-9,
        bytes: v[7],
    }
}

/// The last few objects a ray was tested against. An object spanning
/// several leaves would otherwise be intersected once per leaf, and an
/// object (a placed mesh) can cost thousands of instructions. Skipping a
/// repeat is exact: the search limit only shrinks, so a second test could
/// not find anything the first did not.
struct Mailbox {
    ids: [u32; 8],
    next: usize,
}

impl Default for Mailbox {
    fn default() -> Self {
        Mailbox {
            ids: [u32::MAX; 8],
            next: 0,
        }
    }
}

impl Mailbox {
    #[inline]
    fn seen(&mut self, id: u32) -> bool {
        if self.ids.contains(&id) {
            return true;
        }
        self.ids[self.next % 8] = id;
        self.next += 1;
        false
    }
}

/// The scene's objects, indexed for ray queries.
#[derive(Debug)]
pub struct World {
    bounded: Vec<Box<dyn Shape>>,
    /// Each bounded object's box when there are at most [`BEAM_SCAN`]
    /// (a pixel's beam tests them in a row; kept for more, they would
    /// cost `many` 6 MB), and the box around them all (empty when there
    /// are none).
    boxes: Vec<Aabb>,
    bounded_box: Aabb,
    index: WorldIndex,
    unbounded: Vec<Box<dyn Shape>>,
    pub stats: AccelStats,
}

#[derive(Debug)]
enum WorldIndex {
    Kd(KdTree),
    Bvh(bvh::Bvh),
}

/// The SAH costs for scene objects: testing one costs several box tests
/// (a sphere a few, a placed mesh a whole walk of its own), so leaves end
/// up holding one or two.
const OBJECTS: bvh::BvhParams = bvh::BvhParams {
    group_cost: 4.0,
    group: 1,
    max_leaf: 4,
};

impl World {
    /// The objects indexed by the default structure.
    pub fn build(objects: Vec<Box<dyn Shape>>) -> World {
        Self::build_with(objects, Accel::default())
    }

    pub fn build_with(objects: Vec<Box<dyn Shape>>, accel: Accel) -> World {
        let start = std::time::Instant::now();
        let (mut bounded, mut unbounded) = (Vec::new(), Vec::new());
        for o in objects {
            if o.bounds().is_finite() {
                bounded.push(o);
            } else {
                unbounded.push(o);
            }
        }
        let boxes: Vec<_> = bounded.iter().map(|o| o.bounds()).collect();
        let bounded_box = boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(b));
        let (index, nodes, tree, bvh, tree_bytes) = match accel {
            // Auto: the kd-tree over the scene's objects.
            Accel::KdTree | Accel::Auto => {
                let t = KdTree::build(&boxes);
                let (n, s, bytes) = (t.stats.nodes, t.stats, t.memory());
                (WorldIndex::Kd(t), n, s, None, bytes)
            }
            Accel::Bvh => {
                let b = bvh::Bvh::build(&boxes, OBJECTS);
                let (n, s) = (b.stats.nodes, b.stats);
                (WorldIndex::Bvh(b), n, TreeStats::default(), Some(s), 0)
            }
        };
        let (meshes, mesh_bvhs) = (mesh_totals(), mesh_bvh_totals());
        let stats = AccelStats {
            objects: bounded.len() + unbounded.len(),
            unbounded: unbounded.len(),
            nodes,
            build_seconds: start.elapsed().as_secs_f64(),
            tree,
            meshes,
            mesh_bvhs,
            bvh,
            memory: AccelMemory {
                scene_tree: tree_bytes,
                mesh_trees: meshes.bytes as usize,
                scene_bvh: bvh.map_or(0, |b| b.bytes),
                mesh_bvhs: mesh_bvhs.bytes as usize,
            },
        };
        let boxes = if boxes.len() > BEAM_SCAN {
            Vec::new()
        } else {
            boxes
        };
        World {
            bounded,
            boxes,
            bounded_box,
            index,
            unbounded,
            stats,
        }
    }

    /// Forces the BVH's scalar or AVX2 path (tests run both).
    #[cfg(test)]
    pub(crate) fn set_simd(&mut self, simd: bvh::Simd) {
        if let WorldIndex::Bvh(b) = &mut self.index {
            b.set_simd(simd);
        }
    }

    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        self.nearest(ray, t_min, t_max).map(|(h, _)| h)
    }

    /// The nearest hit and the object that made it (which gives the hit's
    /// texture coordinates, see [`Shape::uv`]).
    pub fn nearest(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(Hit, &dyn Shape)> {
        let mut hit = Hit::default();
        let object = self.nearest_into(ray, t_min, t_max, &mut hit)?;
        Some((hit, object))
    }

    /// [`World::nearest`] written into `hit` (left as it was on a miss),
    /// returning the object. The renderer's route: a hit is 160 bytes,
    /// and handing it back inside an `Option` with its object copied it
    /// twice more per ray (a twentieth of a glass render).
    pub fn nearest_into(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        hit: &mut Hit,
    ) -> Option<&dyn Shape> {
        let mut best: Option<&dyn Shape> = None;
        let mut t_best = t_max;
        // An unbounded shape that finds its root apart from its hit (the
        // floor) gives only its root here, and its hit is made at the end
        // if nothing in the tree comes nearer: a floor seen behind a ball
        // no longer builds a hit the ball then overwrites.
        let mut deferred: Option<&dyn Roots> = None;
        for o in &self.unbounded {
            match o.roots() {
                Some(r) => {
                    if let Some(t) = r.root_within(ray, t_min, t_best) {
                        (t_best, best, deferred) = (t, Some(&**o), Some(r));
                    }
                }
                None => {
                    if nearer(&**o, ray, t_min, &mut t_best, hit, &mut best) {
                        deferred = None;
                    }
                }
            }
        }
        match &self.index {
            WorldIndex::Kd(tree) => {
                let mut mailbox = Mailbox::default();
                tree.nearest(ray, t_min, t_best, |i, limit| {
                    if mailbox.seen(i) {
                        return None;
                    }
                    let o = &*self.bounded[i as usize];
                    if !o.intersect_into(ray, t_min, limit, hit) {
                        return None;
                    }
                    (best, deferred) = (Some(o), None);
                    Some(hit.t)
                });
            }
            // Each object is in one leaf: no mailbox.
            WorldIndex::Bvh(b) => b.walk(ray, t_min, t_best, |first, count, mut limit| {
                for &i in &b.items()[first..first + count] {
                    let o = &*self.bounded[i as usize];
                    if nearer(o, ray, t_min, &mut limit, hit, &mut best) {
                        deferred = None;
                    }
                }
                limit
            }),
        }
        // Still deferred: nothing came nearer, and t_best is its root.
        if let Some(r) = deferred {
            r.hit_at_root(ray, t_best, hit);
        }
        best
    }

    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.unbounded.iter().any(|o| o.occludes(ray, t_min, t_max))
            || match &self.index {
                WorldIndex::Kd(tree) => {
                    let mut mailbox = Mailbox::default();
                    tree.any(ray, t_min, t_max, |i| {
                        !mailbox.seen(i) && self.bounded[i as usize].occludes(ray, t_min, t_max)
                    })
                }
                WorldIndex::Bvh(b) => {
                    let mut hit = false;
                    b.walk(ray, t_min, t_max, |first, count, limit| {
                        hit = b.items()[first..first + count]
                            .iter()
                            .any(|&i| self.bounded[i as usize].occludes(ray, t_min, t_max));
                        if hit { f64::NEG_INFINITY } else { limit }
                    });
                    hit
                }
            }
    }
}

/// Tests `o` for a hit in (`t_min`, `*limit`), written into `hit`; on
/// one, the limit shrinks to it, `o` is the nearest so far, and true is
/// returned. Each nearest-hit search over a list of objects steps
/// through it so.
#[inline(always)]
fn nearer<'w>(
    o: &'w dyn Shape,
    ray: &Ray,
    t_min: f64,
    limit: &mut f64,
    hit: &mut Hit,
    best: &mut Option<&'w dyn Shape>,
) -> bool {
    let won = o.intersect_into(ray, t_min, *limit, hit);
    if won {
        *limit = hit.t;
        *best = Some(o);
    }
    won
}

/// [`World::first_hits`]' buffers, kept by the caller from pixel to pixel.
#[derive(Debug, Default)]
pub struct FirstHits {
    best: Vec<f64>,
    won: Vec<bool>,
    by: Vec<Option<usize>>,
}

/// The objects of a [`World`] that may block the rays inside one
/// [`Shaft`] (at most [`Blockers::MAX`]): the rays are tested against
/// these alone, and not at all when there are none. The same short list
/// holds the objects a pixel's camera rays may hit
/// ([`World::beam_candidates`]). An object that blocks
/// a ray moves to the front, so the next ray of the grid tries it first
/// (neighbouring rays are mostly blocked by the same object).
#[derive(Clone, Copy, Debug, Default)]
pub struct Blockers {
    /// Indices into `bounded`, or into `unbounded` with [`UNBOUNDED`] set.
    ids: [u32; Blockers::MAX],
    len: usize,
}

/// Up to this many bounded objects, a beam's are found by testing each
/// box rather than by walking the tree.
const BEAM_SCAN: usize = 32;

/// Marks an index into `World::unbounded` in [`Blockers`].
const UNBOUNDED: u32 = 1 << 31;

impl Blockers {
    /// More than this many and the rays go through the tree as usual:
    /// testing each ray against a long list costs more than the walk.
    pub const MAX: usize = 8;

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn len(&self) -> usize {
        self.len
    }

    /// Adds `id` unless present; false when the list is full.
    fn push(&mut self, id: u32) -> bool {
        if self.ids[..self.len].contains(&id) {
            return true;
        }
        if self.len == Self::MAX {
            return false;
        }
        self.ids[self.len] = id;
        self.len += 1;
        true
    }
}

impl World {
    /// The objects that may block a ray inside `shaft`, or `None` when
    /// there are more than [`Blockers::MAX`].
    pub fn blockers(&self, shaft: &Shaft) -> Option<Blockers> {
        let mut b = Blockers::default();
        let corners = shaft.vertices();
        for (i, o) in self.unbounded.iter().enumerate() {
            if !o.misses_hull(&corners) && !b.push(i as u32 | UNBOUNDED) {
                return None;
            }
        }
        let keep = |i: u32| !shaft.may_meet(&self.bounded[i as usize].bounds()) || b.push(i);
        let all = match &self.index {
            WorldIndex::Kd(t) => t.overlapping(&shaft.bounds(), keep),
            WorldIndex::Bvh(t) => t.overlapping(&shaft.bounds(), keep),
        };
        all.then_some(b)
    }

    /// [`World::occludes`] for a ray inside the shaft `blockers` were found
    /// for.
    pub fn occludes_among(
        &self,
        blockers: &mut Blockers,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
    ) -> bool {
        for k in 0..blockers.len {
            let o = self.object(blockers.ids[k]);
            if o.occludes(ray, t_min, t_max) {
                blockers.ids[..=k].rotate_right(1);
                return true;
            }
        }
        false
    }

    /// The objects any of the `rays` of one pixel may hit: every
    /// unbounded one and the bounded ones whose boxes meet their beam
    /// (accel/beam.rs). `None` when there are more than [`Blockers::MAX`],
    /// or only one bounded object (whose box the tree tests at once), or
    /// the rays make no beam: they go through the tree then.
    pub fn beam_candidates(&self, rays: &beam::RayFamily) -> Option<Blockers> {
        let mut b = Blockers::default();
        for i in 0..self.unbounded.len() {
            if !b.push(i as u32 | UNBOUNDED) {
                return None;
            }
        }
        match self.bounded.len() {
            0 => return Some(b),
            // The tree's walk is one box test: nothing to save.
            1 => return None,
            _ => {}
        }
        let beam = beam::Beam::new(rays, &self.bounded_box)?;
        // A few objects are quicker tested in a row than found in the tree.
        let all = if self.boxes.len() == self.bounded.len() {
            self.boxes
                .iter()
                .enumerate()
                .all(|(i, o)| !beam.may_meet(o) || b.push(i as u32))
        } else {
            let keep = |i: u32| !beam.may_meet(&self.bounded[i as usize].bounds()) || b.push(i);
            match &self.index {
                WorldIndex::Kd(t) => t.overlapping(&beam.bounds(), keep),
                WorldIndex::Bvh(t) => t.overlapping(&beam.bounds(), keep),
            }
        };
        all.then_some(b)
    }

    /// [`World::nearest_into`] for a ray inside the beam `candidates` were
    /// found for: each candidate tested in turn, none skipped.
    pub fn nearest_among(
        &self,
        candidates: &Blockers,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        hit: &mut Hit,
    ) -> Option<&dyn Shape> {
        let mut best: Option<&dyn Shape> = None;
        let mut t_best = t_max;
        for &id in &candidates.ids[..candidates.len] {
            nearer(self.object(id), ray, t_min, &mut t_best, hit, &mut best);
        }
        best
    }

    /// [`World::nearest_among`] for every ray of a pixel's beam, the same
    /// hits (`hits[i]`, and the object hit in `objects[i]`): each
    /// candidate meets all the rays in turn, not each ray all the
    /// candidates, so a shape with roots apart from its hits
    /// ([`Shape::roots`]) is one call for the lot, and makes its hit only
    /// for the rays it keeps in the end (a floor met behind a sphere no
    /// longer builds its hit first).
    pub fn first_hits<'w>(
        &'w self,
        candidates: &Blockers,
        rays: &[Ray],
        hits: &mut [Hit],
        objects: &mut Vec<Option<&'w dyn Shape>>,
        s: &mut FirstHits,
    ) {
        let n = rays.len();
        debug_assert!(hits.len() == n);
        s.best.clear();
        s.best.resize(n, f64::INFINITY);
        // Per ray, which candidate holds its nearest hit so far. A hit
        // from a shape without roots is written as it is found; one with
        // roots waits for the end.
        s.by.clear();
        s.by.resize(n, None);
        for (k, &id) in candidates.ids[..candidates.len].iter().enumerate() {
            let o = self.object(id);
            match o.roots() {
                Some(r) => {
                    s.won.clear();
                    s.won.resize(n, false);
                    r.nearest_roots(rays, 0.0, &mut s.best, &mut s.won);
                    for (by, _) in s.by.iter_mut().zip(&s.won).filter(|(_, w)| **w) {
                        *by = Some(k);
                    }
                }
                None => {
                    for (i, (ray, hit)) in rays.iter().zip(hits.iter_mut()).enumerate() {
                        if o.intersect_into(ray, 0.0, s.best[i], hit) {
                            s.best[i] = hit.t;
                            s.by[i] = Some(k);
                        }
                    }
                }
            }
        }
        objects.clear();
        for (i, (ray, hit)) in rays.iter().zip(hits.iter_mut()).enumerate() {
            let object = s.by[i].map(|k| self.object(candidates.ids[k]));
            if let Some(r) = object.and_then(|o| o.roots()) {
                r.hit_at_root(ray, s.best[i], hit);
            }
            objects.push(object);
        }
    }

    /// The object a [`Blockers`] id names.
    fn object(&self, id: u32) -> &dyn Shape {
        if id & UNBOUNDED != 0 {
            &*self.unbounded[(id & !UNBOUNDED) as usize]
        } else {
            &*self.bounded[id as usize]
        }
    }
}

#[cfg(test)]
#[path = "world_tests.rs"]
mod tests;
