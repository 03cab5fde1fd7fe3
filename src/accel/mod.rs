//! Stage 3, ACCELERATE: the index the renderer asks for the nearest hit.
//!
//! Bounded objects go into a kd-tree ([`KdTree`], the same structure that
//! indexes the triangles of each mesh); unbounded ones (planes, some
//! implicit surfaces) are tested one by one beside it.

mod kdtree;

pub use kdtree::{KdTree, TreeStats};

use crate::geometry::Ray;
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
}

static MESH_TREES: [AtomicU64; 7] = [const { AtomicU64::new(0) }; 7];

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
    tree: KdTree,
    unbounded: Vec<Box<dyn Shape>>,
    pub stats: AccelStats,
}

impl World {
    pub fn build(objects: Vec<Box<dyn Shape>>) -> World {
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
        let tree = KdTree::build(&boxes);
        let stats = AccelStats {
            objects: bounded.len() + unbounded.len(),
            unbounded: unbounded.len(),
            nodes: tree.stats.nodes,
            build_seconds: start.elapsed().as_secs_f64(),
            tree: tree.stats,
            meshes: mesh_totals(),
        };
        World {
            bounded,
            tree,
            unbounded,
            stats,
        }
    }

    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let mut best = None;
        let mut t_best = t_max;
        for o in &self.unbounded {
            if let Some(h) = o.intersect(ray, t_min, t_best) {
                t_best = h.t;
                best = Some(h);
            }
        }
        let mut mailbox = Mailbox::default();
        self.tree.nearest(ray, t_min, t_best, |i, limit| {
            if mailbox.seen(i) {
                return None;
            }
            let h = self.bounded[i as usize].intersect(ray, t_min, limit)?;
            best = Some(h);
            Some(h.t)
        });
        best
    }

    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.unbounded.iter().any(|o| o.occludes(ray, t_min, t_max)) || {
            let mut mailbox = Mailbox::default();
            self.tree.any(ray, t_min, t_max, |i| {
                !mailbox.seen(i) && self.bounded[i as usize].occludes(ray, t_min, t_max)
            })
        }
    }
}
