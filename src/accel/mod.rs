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
use crate::shapes::{Hit, Shape};
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
        for o in &self.unbounded {
            nearer(&**o, ray, t_min, &mut t_best, hit, &mut best);
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
                    best = Some(o);
                    Some(hit.t)
                });
            }
            // Each object is in one leaf: no mailbox.
            WorldIndex::Bvh(b) => b.walk(ray, t_min, t_best, |first, count, mut limit| {
                for &i in &b.items()[first..first + count] {
                    nearer(
                        &*self.bounded[i as usize],
                        ray,
                        t_min,
                        &mut limit,
                        hit,
                        &mut best,
                    );
                }
                limit
            }),
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
/// one, the limit shrinks to it and `o` is the nearest so far. Each
/// nearest-hit search over a list of objects steps through it so.
#[inline(always)]
fn nearer<'w>(
    o: &'w dyn Shape,
    ray: &Ray,
    t_min: f64,
    limit: &mut f64,
    hit: &mut Hit,
    best: &mut Option<&'w dyn Shape>,
) {
    if o.intersect_into(ray, t_min, *limit, hit) {
        *limit = hit.t;
        *best = Some(o);
    }
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
mod tests {
    use super::*;
    use crate::geometry::DVec3;
    use crate::shapes::{Plane, Sphere};

    #[test]
    fn world_agrees_with_a_linear_scan() {
        let _watchdog = crate::watchdog::start();
        let mut s = 0x9e3779b97f4a7c15u64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let spheres: Vec<Sphere> = (0..300)
            .map(|i| {
                let c = DVec3::new(rnd(), rnd(), rnd()) * 10.0;
                Sphere::new(c, 0.1 + rnd().abs(), i)
            })
            .collect();
        let mut objects: Vec<Box<dyn Shape>> = spheres
            .iter()
            .map(|s| Box::new(s.clone()) as Box<dyn Shape>)
            .collect();
        objects.push(Box::new(Plane::new(DVec3::Y, -9.0, 999)));
        let clone = |objects: &[Box<dyn Shape>]| -> Vec<Box<dyn Shape>> {
            (0..objects.len())
                .map(|i| match i {
                    300 => Box::new(Plane::new(DVec3::Y, -9.0, 999)) as Box<dyn Shape>,
                    _ => Box::new(spheres[i].clone()),
                })
                .collect()
        };
        let kd = World::build_with(clone(&objects), Accel::KdTree);
        assert_eq!(kd.stats.unbounded, 1);
        assert!(kd.stats.tree.leaves > 10, "{:?}", kd.stats.tree);
        let mut worlds = vec![kd];
        for simd in [bvh::Simd::Scalar, bvh::Simd::Avx2] {
            let mut w = World::build_with(clone(&objects), Accel::Bvh);
            assert!(w.stats.bvh.is_some_and(|b| b.nodes > 5 && b.items == 300));
            w.set_simd(simd);
            worlds.push(w);
        }
        let floor = Plane::new(DVec3::Y, -9.0, 999);
        for _ in 0..3000 {
            let o = DVec3::new(rnd(), rnd(), rnd()) * 15.0;
            let d = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X);
            let ray = Ray::new(o, d);
            let want = spheres
                .iter()
                .map(|s| s as &dyn Shape)
                .chain([&floor as &dyn Shape])
                .filter_map(|s| s.intersect(&ray, 1e-9, f64::INFINITY))
                .min_by(|a, b| a.t.total_cmp(&b.t));
            for world in &worlds {
                let got = world.intersect(&ray, 1e-9, f64::INFINITY);
                assert_eq!(
                    got.map(|h| (h.t, h.material)),
                    want.map(|h| (h.t, h.material))
                );
                // Shadow rays: blocked just past the nearest hit, free just before.
                let t = want.map_or(f64::INFINITY, |h| h.t);
                assert_eq!(world.occludes(&ray, 1e-9, t * 1.001), want.is_some());
                if want.is_some() {
                    assert!(!world.occludes(&ray, 1e-9, t * 0.999));
                }
            }
        }
    }

    #[test]
    fn shaft_blockers_decide_every_ray_as_the_tree_does() {
        let _watchdog = crate::watchdog::start();
        let mut s = 0x2545f4914f6cdd1du64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        // Small spheres in a 10-wide box above a floor; lights over them.
        let balls = random_balls(60, 0.1, 0.3, &mut rnd);
        // Both indexes find the blockers (each its own box query).
        for accel in [Accel::KdTree, Accel::Bvh] {
            let world = balls_over_a_floor(&balls, accel);
            blockers_decide_every_ray(&world, &mut rnd);
        }
    }

    #[test]
    fn a_pixels_rays_find_among_their_beams_objects_what_the_tree_finds() {
        let _watchdog = crate::watchdog::start();
        let mut rnd = beam::tests::rng(0x0bea_3c0d);
        // 20 balls (tested in a row for the beam) and 60 (found in the
        // tree), over a floor, seen through a lens from around them.
        for (count, accel) in [(20, Accel::KdTree), (60, Accel::KdTree), (60, Accel::Bvh)] {
            let balls = random_balls(count, 0.2, 0.6, &mut rnd);
            let world = balls_over_a_floor(&balls, accel);
            let (mut used, mut few, mut hits, mut misses) = (0, 0, 0, 0);
            for _ in 0..300 {
                let eye = DVec3::new(rnd() * 24.0 - 12.0, 1.0 + rnd() * 6.0, 14.0);
                let target = DVec3::new(rnd() * 8.0 - 4.0, rnd() * 12.0, rnd() * 8.0 - 4.0);
                let f = beam::tests::family(eye, target - eye, 0.3 * rnd(), 2.0 + 20.0 * rnd());
                let Some(among) = world.beam_candidates(&f) else {
                    continue;
                };
                used += 1;
                few += (among.len() <= 3) as u32;
                for _ in 0..24 {
                    let lens = (2.0 * rnd() - 1.0, 2.0 * rnd() - 1.0);
                    let ray = beam::tests::ray_of(&f, lens, (rnd(), rnd()));
                    let (mut a, mut b) = (Hit::default(), Hit::default());
                    let want = world.nearest_into(&ray, 0.0, f64::INFINITY, &mut a);
                    let got = world.nearest_among(&among, &ray, 0.0, f64::INFINITY, &mut b);
                    assert_eq!(want.is_some(), got.is_some());
                    if let (Some(w), Some(g)) = (want, got) {
                        assert!(std::ptr::addr_eq(w, g), "another object");
                        assert_eq!((a.t, a.point), (b.t, b.point));
                        hits += 1;
                    } else {
                        misses += 1;
                    }
                }
            }
            // Most beams hold a few objects, and rays hit and miss.
            assert!(used > 250 && few > 150, "{count}: {used} {few}");
            assert!(hits > 1000 && misses > 100, "{count}: {hits} {misses}");
        }
        // No bounded object: the unbounded ones alone. One: the tree, whose
        // walk is that one box test.
        let floor = || Box::new(Plane::new(DVec3::Y, 0.0, 0)) as Box<dyn Shape>;
        let f = beam::tests::family(DVec3::new(0.0, 2.0, 5.0), -DVec3::Z, 0.1, 5.0);
        assert_eq!(
            World::build(vec![floor()])
                .beam_candidates(&f)
                .map(|b| b.len()),
            Some(1)
        );
        let ball = Box::new(Sphere::new(DVec3::new(0.0, 1.0, 0.0), 1.0, 0));
        assert!(
            World::build(vec![floor(), ball])
                .beam_candidates(&f)
                .is_none()
        );
    }

    #[test]
    fn a_lights_blockers_over_a_pixels_hits_decide_its_shadow_rays() {
        let _watchdog = crate::watchdog::start();
        let mut rnd = beam::tests::rng(0x5ad0_77e5);
        let balls = random_balls(40, 0.2, 0.5, &mut rnd);
        for accel in [Accel::KdTree, Accel::Bvh] {
            let world = balls_over_a_floor(&balls, accel);
            let (mut used, mut blocked, mut clear) = (0, 0, 0);
            for _ in 0..300 {
                // A pixel's hits: a small box on or over the floor.
                let c = DVec3::new(rnd() * 10.0 - 5.0, rnd() * 3.0 - 0.5, rnd() * 10.0 - 5.0);
                let points = Aabb::new(c, c + DVec3::new(rnd(), rnd(), rnd()) * 0.3);
                let light = DVec3::new(rnd() * 10.0 - 5.0, 7.0, rnd() * 10.0 - 5.0);
                let Some(mut b) =
                    Shaft::towards_box(light, &points).and_then(|s| world.blockers(&s))
                else {
                    continue;
                };
                used += 1;
                for _ in 0..16 {
                    let p =
                        points.min + (points.max - points.min) * DVec3::new(rnd(), rnd(), rnd());
                    let d = light - p;
                    let (ray, reach) = (Ray::new(p, d.normalize()), d.length() * (1.0 - 1e-4));
                    let want = world.occludes(&ray, 0.0, reach);
                    assert_eq!(world.occludes_among(&mut b, &ray, 0.0, reach), want);
                    if want {
                        blocked += 1;
                    } else {
                        clear += 1;
                    }
                }
            }
            assert!(used > 250, "{used}");
            assert!(blocked > 300 && clear > 1000, "{blocked} {clear}");
        }
    }

    /// `n` balls (centre, radius) in a 10-wide, 4-high box: radii from
    /// `r0` to `r0 + dr`.
    fn random_balls(
        n: usize,
        r0: f64,
        dr: f64,
        rnd: &mut impl FnMut() -> f64,
    ) -> Vec<(DVec3, f64)> {
        (0..n)
            .map(|_| {
                let c = DVec3::new(rnd() * 10.0 - 5.0, rnd() * 4.0, rnd() * 10.0 - 5.0);
                (c, r0 + dr * rnd())
            })
            .collect()
    }

    /// Spheres (centre, radius) over the floor y = −0.5, indexed by `accel`.
    fn balls_over_a_floor(balls: &[(DVec3, f64)], accel: Accel) -> World {
        let mut objects: Vec<Box<dyn Shape>> = balls
            .iter()
            .enumerate()
            .map(|(i, &(c, r))| Box::new(Sphere::new(c, r, i as u32)) as Box<dyn Shape>)
            .collect();
        objects.push(Box::new(Plane::new(DVec3::Y, -0.5, 999)));
        World::build_with(objects, accel)
    }

    fn blockers_decide_every_ray(world: &World, rnd: &mut impl FnMut() -> f64) {
        let (mut used, mut empty, mut blocked, mut clear) = (0, 0, 0, 0);
        for _ in 0..400 {
            let apex = DVec3::new(rnd() * 10.0 - 5.0, rnd() * 4.0 - 0.4, rnd() * 10.0 - 5.0);
            let corner = DVec3::new(rnd() * 8.0 - 4.0, 6.0 + rnd(), rnd() * 8.0 - 4.0);
            let (eu, ev) = (
                DVec3::new(0.5 + rnd(), 0.1, 0.0),
                DVec3::new(0.0, 0.0, 0.5 + rnd()),
            );
            let corners = [corner, corner + eu, corner + eu + ev, corner + ev];
            let Some(shaft) = Shaft::new(apex, corners) else {
                continue;
            };
            let Some(mut b) = world.blockers(&shaft) else {
                continue;
            };
            used += 1;
            empty += b.is_empty() as u32;
            for _ in 0..16 {
                let y = corner + rnd() * eu + rnd() * ev;
                let dist = (y - apex).length() * (1.0 - 1e-4);
                let ray = Ray::new(apex, (y - apex).normalize());
                let want = world.occludes(&ray, 0.0, dist);
                assert_eq!(world.occludes_among(&mut b, &ray, 0.0, dist), want);
                if want {
                    blocked += 1;
                } else {
                    clear += 1;
                }
            }
        }
        // Every case was met: shafts with and without blockers, rays
        // blocked and clear.
        assert!(used > 200 && empty > 20 && empty < used, "{used} {empty}");
        assert!(blocked > 200 && clear > 200, "{blocked} {clear}");
    }

    #[test]
    fn a_floor_below_the_shaft_is_no_blocker_and_one_across_it_is() {
        let _watchdog = crate::watchdog::start();
        let corners = shaft::tests::light_square();
        let shaft = Shaft::new(DVec3::new(0.0, 1e-6, 0.0), corners).unwrap();
        let below = World::build(vec![Box::new(Plane::new(DVec3::Y, 0.0, 0))]);
        assert!(below.blockers(&shaft).unwrap().is_empty());
        let across = World::build(vec![Box::new(Plane::new(DVec3::Y, 3.0, 0))]);
        assert_eq!(across.blockers(&shaft).unwrap().len(), 1);
        // A tilted plane through the apex's side of the shaft.
        let tilted = World::build(vec![Box::new(Plane::new(
            DVec3::new(1.0, 0.2, 0.0),
            0.5,
            0,
        ))]);
        assert_eq!(tilted.blockers(&shaft).unwrap().len(), 1);
    }

    /// A ray through the boxes of a long row of balls, missing every
    /// ball: each index tests them all (the kd-tree's mailbox sees far
    /// more than it holds) and finds nothing; one a little lower hits the
    /// first ball.
    #[test]
    fn a_ray_past_a_long_row_tests_every_object_and_finds_nothing() {
        let _watchdog = crate::watchdog::start();
        for accel in [Accel::KdTree, Accel::Bvh] {
            let objects: Vec<Box<dyn Shape>> = (0..200)
                .map(|i| {
                    let c = DVec3::new(i as f64 * 1.25, 0.0, 0.0);
                    Box::new(Sphere::new(c, 0.5, i)) as Box<dyn Shape>
                })
                .collect();
            let world = World::build_with(objects, accel);
            // At 0.45 from the axis in y and z: inside every box, 0.64
            // from every centre.
            let past = Ray::new(DVec3::new(-2.0, 0.45, 0.45), DVec3::X);
            assert!(world.intersect(&past, 0.0, f64::INFINITY).is_none());
            assert!(!world.occludes(&past, 0.0, f64::INFINITY));
            let hit = Ray::new(DVec3::new(-2.0, 0.3, 0.0), DVec3::X);
            let h = world.intersect(&hit, 0.0, f64::INFINITY).unwrap();
            assert_eq!(h.material, 0);
            assert!((h.t - (2.0 - (0.25f64 - 0.09).sqrt())).abs() < 1e-12);
        }
    }

    #[test]
    fn accel_names_round_trip() {
        for (name, a) in Accel::NAMES
            .iter()
            .zip([Accel::Auto, Accel::KdTree, Accel::Bvh])
        {
            assert_eq!(Accel::from_name(name), Some(a));
            assert_eq!(a.name(), *name);
        }
        assert_eq!(Accel::from_name("kd-tree"), None);
        assert_eq!(Accel::from_name(""), None);
    }

    /// A plane across the shaft (unbounded, listed apart) and balls in it
    /// and beside it: the listed blockers decide every ray of the grid as
    /// the whole world does, the plane's rays and the balls' alike.
    #[test]
    fn unbounded_and_bounded_blockers_decide_the_rays() {
        let _watchdog = crate::watchdog::start();
        let corners = shaft::tests::light_square();
        let apex = DVec3::new(0.1, 0.0, -0.2);
        let shaft = Shaft::new(apex, corners).unwrap();
        for accel in [Accel::KdTree, Accel::Bvh] {
            // The plane tilted so that it blocks the rays to one side of
            // the light only; one ball inside the shaft, one beside it.
            let objects: Vec<Box<dyn Shape>> = vec![
                Box::new(Sphere::new(DVec3::new(5.0, 3.0, 0.0), 0.5, 0)),
                Box::new(Plane::new(DVec3::new(1.0, 0.3, 0.0).normalize(), 1.6, 1)),
                Box::new(Sphere::new(DVec3::new(-0.4, 4.0, 0.3), 0.3, 2)),
            ];
            let world = World::build_with(objects, accel);
            let mut b = world.blockers(&shaft).unwrap();
            assert_eq!(b.len(), 2, "{accel:?}");
            let (mut blocked, mut clear) = (0, 0);
            for i in 0..=20 {
                for j in 0..=20 {
                    let y = DVec3::new(-1.0 + 0.1 * i as f64, 6.0, -1.0 + 0.1 * j as f64);
                    let dist = (y - apex).length() * (1.0 - 1e-4);
                    let ray = Ray::new(apex, (y - apex) / (y - apex).length());
                    let want = world.occludes(&ray, 0.0, dist);
                    assert_eq!(world.occludes_among(&mut b, &ray, 0.0, dist), want);
                    if want {
                        blocked += 1;
                    } else {
                        clear += 1;
                    }
                }
            }
            assert!(blocked > 50 && clear > 50, "{blocked} {clear}");
        }
    }

    #[test]
    fn more_blockers_than_the_list_holds_send_the_rays_to_the_tree() {
        let _watchdog = crate::watchdog::start();
        let corners = shaft::tests::light_square();
        let shaft = Shaft::new(DVec3::ZERO, corners).unwrap();
        for n in [Blockers::MAX, Blockers::MAX + 1] {
            for accel in [Accel::KdTree, Accel::Bvh] {
                let objects: Vec<Box<dyn Shape>> = (0..n)
                    .map(|i| {
                        let c = DVec3::new(0.0, 1.0 + 0.5 * i as f64, 0.0);
                        Box::new(Sphere::new(c, 0.1, i as u32)) as Box<dyn Shape>
                    })
                    .collect();
                let world = World::build_with(objects, accel);
                let found = world.blockers(&shaft);
                // As many as the list holds are listed; one more, none.
                assert_eq!(found.map(|b| b.len()), (n == Blockers::MAX).then_some(n));
            }
        }
    }
}
